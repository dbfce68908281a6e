//! The artist's parameters (`scene::artist`): reflectance and mean free path to coefficients
//! through the table's diffuse reflectance (1 − F_r) ρ_eff at θ = 0.

use bssrdf_zoo::bake::Baker;
use bssrdf_zoo::fresnel::{entry_transmittance, Moments};
use bssrdf_zoo::scene::artist::{coefficients, ReflectanceCurve};
use bssrdf_zoo::table::{bake_lobes, GridPreset, Lobes};

use super::subset::{full, grid, ETA};

/// The curve baked on its own equals the full table's θ = 0 column, and a reflectance inverts
/// to the ρ′ whose diffuse reflectance (1 − F_r(0)) ρ_eff(ρ′, 0) on the table is that
/// reflectance.
#[test]
fn reflectance_inverts_through_the_tables_diffuse_reflectance() {
    let full = full();
    let curve = ReflectanceCurve::from_table(full).unwrap();
    assert_eq!(
        ReflectanceCurve::bake(ETA, Moments::Exact, &grid(), Lobes::for_eta(ETA)).unwrap(),
        curve
    );
    let v = full.view();
    let t0 = entry_transmittance(0.0, ETA);
    for reflectance in [0.0, 0.05, 0.3, 0.5, 0.8, 0.9, 0.93] {
        let inv = curve.invert(reflectance, 0).unwrap();
        assert!(!inv.clamped);
        let back = v.diffuse_reflectance(inv.rho_prime, 0.0).unwrap();
        assert!((back - reflectance).abs() < 1e-7, "{reflectance}: {back}");
        let rho_eff = v.effective_albedo(inv.rho_prime, 0.0).unwrap();
        assert!(
            (t0 * rho_eff - reflectance).abs() < 1e-7,
            "{reflectance}: {rho_eff}"
        );
    }
    // Above the largest, T₀ ρ_eff(1, 0) ≈ 0.9315 on this grid: clamped to ρ′ = 1.
    assert_eq!(curve.max(), v.reflectance_range(0.0).unwrap()[1]);
    assert_eq!(curve.max(), t0 * v.effective_albedo(1.0, 0.0).unwrap());
    let top = curve.invert(0.95, 0).unwrap();
    assert!(top.clamped && top.rho_prime == 1.0);
    // mfp = 1/σt and the reduced albedo survive the conversion, with g.
    let d = curve
        .diffuse([0.5, 0.8, 0.3], [1.0, 2.0, 0.5], [0.0, 0.5, -0.3])
        .unwrap();
    for c in 0..3 {
        let (s, a) = (d.sigma_s[c], d.sigma_a[c]);
        let g = [0.0, 0.5, -0.3][c];
        assert!((s + a - 1.0 / [1.0, 2.0, 0.5][c]).abs() < 1e-12);
        let rho = s * (1.0 - g) / (s * (1.0 - g) + a);
        assert!((rho - d.inverted[c].rho_prime).abs() < 1e-12);
        let (s2, a2) = coefficients(d.inverted[c].rho_prime, [1.0, 2.0, 0.5][c], g);
        assert_eq!((s, a), (s2, a2));
    }
}

/// A bake's curve is the θ = 0 column of the very table it bakes at η, radii and lobes
/// included: at η = 1.2 a table has two lobes and the preset's two-lobe radii, and the
/// reflectance a scene's material inverts to is read back from its file's table exactly.
#[test]
fn a_bakes_curve_is_the_column_of_the_table_it_bakes() {
    let eta = 1.2;
    let baker = Baker::new(GridPreset::Coarse);
    assert_eq!(baker.lobes_at(eta), Lobes::Two);
    let curve = baker.curve(eta).unwrap();
    let (table, _) = bake_lobes(
        eta,
        Moments::Exact,
        &baker.grid_at(eta),
        false,
        baker.lobes_at(eta),
    )
    .unwrap();
    assert_eq!(ReflectanceCurve::from_table(&table).unwrap(), curve);
    let (view, own) = (table.view(), curve.view());
    for &rho in table.axes().rho().as_slice() {
        let a = view.diffuse_reflectance(rho, 0.0).unwrap();
        assert_eq!(
            a.to_bits(),
            own.diffuse_reflectance(rho, 0.0).unwrap().to_bits()
        );
    }
    let inv = curve.invert(0.6, 0).unwrap();
    let back = view.diffuse_reflectance(inv.rho_prime, 0.0).unwrap();
    assert!((back - 0.6).abs() < 1e-7, "{back}");
}
