//! The diffuse reflectance A(ρ′, θ) = (1 − F_r(θ)) ρ_eff(ρ′, θ) of a table and its inverse
//! (`TableRef::rho_prime_for_reflectance`): the definition held to independent computations,
//! the round trip A → ρ′ → A over random points weighted toward the stiff corners, monotonicity
//! over fine grids, and every refusal.
//!
//! Run with `--nocapture` to see the measured errors.

use bssrdf_runtime::float::{next_down, next_up};
use bssrdf_zoo::fresnel::{entry_transmittance, Moments};
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::Pbd;
use bssrdf_zoo::quadrature::GaussLegendre;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{bake, AngularTable, Grid, GridPreset, ReflectanceError, TableRef};
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::OnceLock;

use super::subset::{full, ETA};

/// The η of the tables the round trip runs on: below 1 (light enters only below the critical
/// angle), at and just above index match (two lobes), the default, and the ends of the domain.
const ETAS: [f64; 8] = [0.75, 0.9, 1.0, 1.0001, 1.1, 1.33, 1.5, 2.5];

/// Coarse tables at every η of [`ETAS`], baked once for the file.
fn tables() -> &'static [(f64, AngularTable)] {
    static TABLES: OnceLock<Vec<(f64, AngularTable)>> = OnceLock::new();
    TABLES.get_or_init(|| {
        ETAS.iter()
            .map(|&eta| {
                let grid = Grid::preset(GridPreset::Coarse);
                (eta, bake(eta, Moments::Exact, &grid, false).unwrap().0)
            })
            .collect()
    })
}

/// ∫∫ S r dr dφ of the table's `eval` over the exit plane: Gauss–Legendre on each radius
/// interval, the trapezoid rule in φ (exact to rounding for a smooth periodic profile).
fn plane_integral(view: &TableRef, rho: f64, theta: f64) -> f64 {
    let rule = GaussLegendre::new(12);
    let nodes = view.axes().r().as_slice();
    let n_phi = 512;
    let ring = |r: f64| {
        let sum: f64 = (0..n_phi)
            .map(|k| {
                let phi = -PI + TAU * (k as f64 + 0.5) / n_phi as f64;
                view.eval(rho, theta, r, phi).unwrap()
            })
            .sum();
        r * sum * TAU / n_phi as f64
    };
    nodes
        .windows(2)
        .map(|w| rule.integrate(w[0], w[1], ring))
        .sum()
}

/// The definition, checked by parts against computations that share nothing with the lookup:
/// ρ_eff (the last radial-CDF node) against the plane integral of `eval` and against PBD's own
/// ρ_eff (its integral over the plane taken first); T against the Fresnel equations is in
/// `fresnel`'s unit tests. Then A = T ρ_eff.
#[test]
fn the_diffuse_reflectance_is_the_entry_transmittance_times_the_power_leaving() {
    let view = full().view();
    let boundary = Boundary::new(ETA, Moments::Exact).unwrap();
    let (mut worst_plane, mut worst_pbd) = (0.0f64, 0.0f64);
    for rho in [0.3, 0.7, 0.9, 0.99] {
        for theta_deg in [0.0, 30.0, 60.0, 85.0] {
            let theta = f64::to_radians(theta_deg);
            let rho_eff = view.effective_albedo(rho, theta).unwrap();
            let a = view.diffuse_reflectance(rho, theta).unwrap();
            assert_eq!(a, entry_transmittance(theta, ETA) * rho_eff);
            // The radial CDF integrates the plain spline of E along r; eval interpolates
            // exp(spline of ln E): the two differ by the table's own interpolation.
            let plane = plane_integral(&view, rho, theta);
            let rel = (plane / rho_eff - 1.0).abs();
            assert!(
                rel < 2e-3,
                "rho {rho}, theta {theta_deg}: {plane} vs {rho_eff}"
            );
            worst_plane = worst_plane.max(rel);
            // PBD to infinity: the table misses the tail beyond its last radius, 273 mean free
            // paths on the coarse grid, which matters only where nothing is absorbed.
            let pbd = Pbd::new(rho, boundary).unwrap().effective_albedo(theta);
            let rel = (rho_eff / pbd - 1.0).abs();
            assert!(
                rel < 2e-3,
                "rho {rho}, theta {theta_deg}: {rho_eff} vs PBD {pbd}"
            );
            worst_pbd = worst_pbd.max(rel);
        }
    }
    eprintln!(
        "rho_eff: plane integral of eval within {worst_plane:.2e}, PBD's within {worst_pbd:.2e}"
    );
    // At ρ′ = 1 the tail beyond the last radius is 1 %.
    let pbd = Pbd::new(1.0, boundary).unwrap().effective_albedo(0.0);
    let table = view.effective_albedo(1.0, 0.0).unwrap();
    assert!((0.98..1.0).contains(&(table / pbd)), "{table} vs PBD {pbd}");
    // At normal incidence T = 1 − ((η − 1)/(η + 1))², so A_max = 0.97994 ρ_eff(1, 0).
    let t0 = 1.0 - ((ETA - 1.0) / (ETA + 1.0)).powi(2);
    let [min, max] = view.reflectance_range(0.0).unwrap();
    assert_eq!(min, 0.0);
    assert!((max - t0 * table).abs() < 1e-15, "{max} vs {}", t0 * table);
}

/// Reflectances to invert in [0, A_max] at one (θ, table): a quarter spread evenly, a quarter
/// near 0 (down to 1e-40 of A_max), a quarter near A_max (down to 1e-13 below it), the rest
/// the ends themselves and the values at the albedo nodes.
fn reflectance_draw(rng: &mut SplitMix64, view: &TableRef, theta: f64, max: f64) -> f64 {
    let u = rng.next_f64();
    let v = rng.next_f64();
    match (4.0 * u) as u32 {
        0 => max * v,
        1 => max * 10f64.powf(-40.0 * v),
        2 => max * (1.0 - 10f64.powf(-13.0 * v)),
        _ => {
            let nodes = view.axes().rho().as_slice();
            match (v * (nodes.len() + 2) as f64) as usize {
                0 => 0.0,
                1 => max,
                k => view.diffuse_reflectance(nodes[k - 2], theta).unwrap(),
            }
        }
    }
}

/// An incidence in radians: a third spread over [0°, 90°], a third toward 90° (down to 1e-10
/// rad), for η < 1 a sixth toward the critical angle from below, the rest at 0.
fn theta_draw(rng: &mut SplitMix64, eta: f64) -> f64 {
    let (u, v) = (rng.next_f64(), rng.next_f64());
    let critical = if eta < 1.0 { eta.asin() } else { FRAC_PI_2 };
    match (6.0 * u) as u32 {
        0 | 1 => critical * v,
        2 | 3 => FRAC_PI_2 - 10f64.powf(-1.0 - 9.0 * v),
        4 if eta < 1.0 => critical * (1.0 - 10f64.powf(-1.0 - 9.0 * v)),
        _ => 0.0,
    }
}

/// A → ρ′ → A over 12,000 random (A, θ, η), weighted toward the stiff corners. The solver's
/// own promise, exactly: the answer and one of its neighbouring f64 bracket A on the table's
/// curve, and the answer is the closer of the two. What that gives: A back to 1e-6
/// absolutely everywhere, and to 1e-6 of itself down to A = 1e-30. (The curve steps by the f32
/// rounding of the rows' weights, about 1e-7 of A, up to 6e-7 below the first albedo node
/// above 0, where the folded weights reach ±4; below A ≈ 1e-30 the ρ′²-scaled weights leave
/// f32's range and the curve steps up from 0.)
#[test]
fn reflectance_round_trips_through_the_reduced_albedo() {
    let mut rng = SplitMix64::seed_from_u64(20);
    let (mut worst_rel, mut worst_abs, mut points, mut no_light) = (0.0f64, 0.0f64, 0, 0);
    for (eta, table) in tables() {
        let view = table.view();
        let nodes = view.axes().rho().as_slice();
        for _ in 0..1500 {
            let theta = theta_draw(&mut rng, *eta);
            let [min, max] = view.reflectance_range(theta).unwrap();
            assert_eq!(min, 0.0);
            if max == 0.0 {
                // θ = 90° exactly, or at or beyond the critical angle: no light enters
                assert!(matches!(
                    view.rho_prime_for_reflectance(0.0, theta),
                    Err(ReflectanceError::NoLight { .. })
                ));
                no_light += 1;
                continue;
            }
            let a = reflectance_draw(&mut rng, &view, theta, max);
            let rho = view.rho_prime_for_reflectance(a, theta).unwrap();
            let curve = |x: f64| view.diffuse_reflectance(x, theta).unwrap();
            let back = curve(rho);
            let at = format!(
                "eta {eta}, theta {theta}, A {a:e} of max {max:e}: rho' {rho:e} gives {back:e}"
            );
            if rho != nodes[0] && rho != nodes[nodes.len() - 1] {
                let (down, up) = (next_down(rho), next_up(rho));
                let bracketed = if back <= a {
                    a < curve(up) && a - back <= curve(up) - a
                } else {
                    curve(down) <= a && back - a < a - curve(down)
                };
                assert!(bracketed, "{at}");
            } else if rho == nodes[nodes.len() - 1] && a < max {
                // The last row, nearer to A than its neighbour below (the ridge's energy,
                // table::ridge, has a square-root slope at ρ′ = 1)
                let down = curve(next_down(rho));
                assert!(down <= a && back - a <= a - down, "{at}");
            } else {
                assert!(a == 0.0 || a == max || back == a, "{at}");
            }
            let abs = (back - a).abs();
            assert!(abs <= 1e-6, "{at}");
            worst_abs = worst_abs.max(abs);
            if a >= 1e-30 {
                let rel = abs / a;
                assert!(rel <= 1e-6, "{at}: {rel:e}");
                worst_rel = worst_rel.max(rel);
            }
            points += 1;
        }
    }
    assert!(points > 10_000, "{points}");
    assert!(no_light > 0, "grazing and critical incidence were drawn");
    eprintln!(
        "round trip over {points} points ({no_light} more without light): max |error| {worst_abs:.2e}, max relative {worst_rel:.2e} for A >= 1e-30"
    );
}

/// ρ′(A) does not decrease over 20,001 evenly spaced A in [0, A_max(θ)] plus the 2,000 nearest
/// each end, at every η and at θ from 0 to just below 90° (and to just below the critical
/// angle); it starts at the first albedo node and ends at the last.
#[test]
fn the_inverse_is_monotone_over_fine_grids_of_reflectance() {
    for (eta, table) in tables() {
        let view = table.view();
        let nodes = view.axes().rho().as_slice();
        let critical = if *eta < 1.0 { eta.asin() } else { FRAC_PI_2 };
        let thetas = [0.0, 0.5, 1.2, critical - 1e-3, critical - 1e-7];
        for theta in thetas.into_iter().filter(|&t| t < critical) {
            let [_, max] = view.reflectance_range(theta).unwrap();
            // (max·k/n can round to either side of max: the end is added as itself)
            let mut grid: Vec<f64> = (0..20_000).map(|k| max * f64::from(k) / 20_000.0).collect();
            grid.push(max);
            grid.extend((1..=1000).map(|k| max * 1e-12 * f64::from(k)));
            grid.extend((1..=1000).map(|k| max * (1.0 - 1e-12 * f64::from(k))));
            grid.sort_by(f64::total_cmp);
            let rho: Vec<f64> = grid
                .iter()
                .map(|&a| view.rho_prime_for_reflectance(a, theta).unwrap())
                .collect();
            let at = format!("eta {eta}, theta {theta}");
            assert!(rho.windows(2).all(|w| w[0] <= w[1]), "{at}");
            assert_eq!(rho[0], nodes[0], "{at}");
            assert_eq!(rho[rho.len() - 1], nodes[nodes.len() - 1], "{at}");
            // The table's own curve increases along ρ′ at these θ.
            let at_nodes: Vec<f64> = nodes
                .iter()
                .map(|&r| view.diffuse_reflectance(r, theta).unwrap())
                .collect();
            assert!(
                at_nodes.windows(2).all(|w| w[0] < w[1]),
                "{at}: {at_nodes:?}"
            );
        }
    }
}

/// Every value outside the domain is refused, naming it and the range.
#[test]
fn values_outside_the_domain_are_refused_by_name() {
    let view = full().view();
    let [_, max] = view.reflectance_range(0.0).unwrap();
    for a in [
        -1e-300,
        -0.5,
        max * (1.0 + 1e-15),
        0.99,
        1.0,
        2.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        let err = view.rho_prime_for_reflectance(a, 0.0).unwrap_err();
        match err {
            ReflectanceError::OutOfRange {
                reflectance,
                min,
                max: m,
                ..
            } => {
                assert_eq!(reflectance.to_bits(), a.to_bits());
                assert_eq!((min, m), (0.0, max));
            }
            other => panic!("{a}: {other:?}"),
        }
    }
    let message = view
        .rho_prime_for_reflectance(0.99, 0.0)
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with("reflectance 0.99 is outside [0, 0.93")
            && message.contains("at theta = 0 deg")
            && message.contains("rho' from 0 to 1"),
        "{message}"
    );
    // θ outside [0, 90°] or NaN
    for theta in [-1e-9, FRAC_PI_2 + 1e-3, 4.0, f64::NAN, f64::INFINITY] {
        let err = view.rho_prime_for_reflectance(0.5, theta).unwrap_err();
        assert!(
            matches!(err, ReflectanceError::Theta { .. }),
            "{theta}: {err:?}"
        );
        assert!(view.reflectance_range(theta).is_err());
        assert!(view.diffuse_reflectance(0.5, theta).is_none());
    }
    let message = view
        .rho_prime_for_reflectance(0.5, 4.0)
        .unwrap_err()
        .to_string();
    assert!(message.starts_with("theta = 4 rad (229.1"), "{message}");
    // The angles the lookups take (`TableRef::theta_domain`): the f32 node, rounding included
    assert!(message.contains("[0, 1.5707964641330463] rad"), "{message}");
    // No light at grazing incidence, nor beyond the critical angle of η < 1: even A = 0.
    let below = &tables()[0];
    assert_eq!(below.0, 0.75);
    for (view, theta) in [
        (view, FRAC_PI_2),
        (below.1.view(), 0.9),
        (below.1.view(), 0.75f64.asin() + 1e-9),
    ] {
        assert_eq!(view.reflectance_range(theta).unwrap(), [0.0, 0.0]);
        for a in [0.0, 0.1] {
            let err = view.rho_prime_for_reflectance(a, theta).unwrap_err();
            assert!(
                matches!(err, ReflectanceError::NoLight { .. }),
                "{theta}: {err:?}"
            );
            assert!(err.to_string().contains("no light enters"), "{err}");
        }
    }
}

/// A scene's subset of albedo rows reaches only the reflectances of its rows: below them (and
/// above) is an error naming that range; inside, the round trip holds as on the full table.
#[test]
fn a_subset_of_albedo_rows_inverts_only_inside_its_range() {
    let sub = full().subset_rows(20..30).unwrap();
    let view = sub.view();
    let nodes = view.axes().rho().as_slice();
    for theta in [0.0, 1.0] {
        let [min, max] = view.reflectance_range(theta).unwrap();
        assert_eq!(min, view.diffuse_reflectance(nodes[0], theta).unwrap());
        assert!(min > 0.0 && max > min);
        let err = view
            .rho_prime_for_reflectance(0.5 * min, theta)
            .unwrap_err();
        assert!(
            matches!(err, ReflectanceError::OutOfRange { rho_min, .. } if rho_min == nodes[0]),
            "{err:?}"
        );
        assert!(view.rho_prime_for_reflectance(max * 1.001, theta).is_err());
        for k in 0..=100 {
            let a = min + (max - min) * f64::from(k) / 100.0;
            let rho = view.rho_prime_for_reflectance(a, theta).unwrap();
            let back = view.diffuse_reflectance(rho, theta).unwrap();
            assert!((back - a).abs() <= 1e-7 * a, "{a} {rho} {back}");
            // The full table agrees two rows inside either end, where a subset's lookups are
            // bit-identical to it (the rows a scene declares).
            if (nodes[2]..=nodes[nodes.len() - 3]).contains(&rho) {
                let full_back = full().view().diffuse_reflectance(rho, theta).unwrap();
                assert_eq!(back.to_bits(), full_back.to_bits());
            }
        }
    }
}
