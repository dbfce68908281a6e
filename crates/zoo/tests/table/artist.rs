//! The artist's parameters (`scene::artist`): reflectance and mean free path to coefficients
//! through the table's effective albedo at θ = 0.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::scene::artist::{coefficients, EffectiveAlbedo};

use super::subset::{full, grid, ETA};

/// The artist's parameters: the curve baked on its own equals the full table's θ = 0 column,
/// and a reflectance inverts to the ρ′ whose table ρ_eff(ρ′, θ = 0) is that reflectance.
#[test]
fn reflectance_inverts_through_the_tables_effective_albedo() {
    let full = full();
    let curve = EffectiveAlbedo::from_table(full).unwrap();
    assert_eq!(
        EffectiveAlbedo::bake(ETA, Moments::Exact, &grid()).unwrap(),
        curve
    );
    let v = full.view();
    for reflectance in [0.0, 0.05, 0.3, 0.5, 0.8, 0.9, 0.95] {
        let inv = curve.invert(reflectance, 0).unwrap();
        assert!(!inv.clamped);
        let back = v.effective_albedo(inv.rho_prime, 0.0).unwrap();
        // The lookup blends rows with f32 weights: agreement to ~1e-8.
        assert!((back - reflectance).abs() < 1e-7, "{reflectance}: {back}");
    }
    // Above the largest ρ_eff (≈ 0.951 on this grid): clamped to ρ′ = 1.
    assert!((curve.max() - v.effective_albedo(1.0, 0.0).unwrap()).abs() < 1e-7);
    let top = curve.invert(0.99, 0).unwrap();
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
