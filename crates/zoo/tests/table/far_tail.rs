//! No silent zeros (issue 17): wherever photon beam diffusion is at least 10⁻¹² of its profile's
//! peak for that (ρ′, θ), the table is within 10 % of it and never 0, at every ρ′ in (0, 1] and
//! θ in [0, 90°]. Truth is PBD's reference quadrature, which shares no code with the table's
//! lookups; the points lean towards both ends of the albedo axis and large r, where the tails
//! are hardest (as `examples/tail_error`, which prints the errors decade by decade).

use crate::lookup::default_table;
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{bake, AngularTable, Grid, GridPreset, CHECK_BOUNDS, PEAK_FRACTION};
use rayon::prelude::*;
use std::f64::consts::PI;

/// The bound: within 10 % where PBD is at least 10⁻¹² of the peak (PBD at (r₁, φ = 0)).
const PEAK: f64 = 1e-12;
const BOUND: f64 = 0.10;

/// The worst of the points that count, and how many did.
#[derive(Debug)]
struct Tail {
    counted: usize,
    zeros: usize,
    worst: f64,
    at: [f64; 5],
}

/// `n` points (seed `seed`) on `table`: ρ′ log-uniform over [10⁻⁹, 10⁻³] for an eighth,
/// over [10⁻³, 1] for three eighths, 1 − ρ′ log-uniform over [10⁻⁷, 1] for a quarter and ρ′
/// uniform for the rest; θ uniform over [0, 90°], φ over [0, π]; r log-uniform over the axis
/// for a third, else uniform over [1, min(r_max, 35/√(3(1 − ρ′)))] (PBD near 10⁻¹³ of its peak).
fn far_tail(table: &AngularTable, n: usize, seed: u64) -> Tail {
    let view = table.view();
    let boundary = Boundary::new(table.eta(), Moments::Exact).unwrap();
    let r_nodes = table.axes().r().as_slice();
    let (r1, r_max) = (r_nodes[1], r_nodes[r_nodes.len() - 1]);
    let mut rng = SplitMix64::seed_from_u64(seed);
    let draws: Vec<[f64; 4]> = (0..n)
        .map(|_| std::array::from_fn(|_| rng.next_f64()))
        .collect();
    let results: Vec<Option<(f64, bool, [f64; 5])>> = draws
        .par_iter()
        .enumerate()
        .map(|(k, u)| {
            let rho = match k % 8 {
                0 => 1e-9 * 1e6f64.powf(u[0]),
                1..=3 => 1e-3 * 1e3f64.powf(u[0]),
                4 | 5 => 1.0 - 1e-7 * 1e7f64.powf(u[0]),
                _ => u[0],
            }
            .clamp(0.0, 1.0);
            let (theta, phi) = (0.5 * PI * u[1], PI * u[2]);
            let r = if k % 3 == 0 {
                r1 * (r_max / r1).powf(u[3])
            } else {
                let far = 35.0 / (3.0 * (1.0 - rho)).sqrt();
                1.0 + (far.min(r_max) - 1.0) * u[3]
            };
            let pbd = Pbd::new(rho, boundary).unwrap();
            let truth = pbd.eval(theta, r, phi, Rule::Reference);
            let peak = pbd.eval(theta, r1, 0.0, Rule::Reference);
            if !(truth > 0.0 && truth >= PEAK * peak) {
                return None;
            }
            let value = view.eval(rho, theta, r, phi).unwrap();
            let error = (value / truth - 1.0).abs();
            let error = if error.is_nan() { f64::INFINITY } else { error };
            Some((
                error,
                value == 0.0,
                [rho, theta.to_degrees(), r, phi, truth / peak],
            ))
        })
        .collect();
    let mut tail = Tail {
        counted: 0,
        zeros: 0,
        worst: 0.0,
        at: [0.0; 5],
    };
    for (error, zero, at) in results.into_iter().flatten() {
        tail.counted += 1;
        tail.zeros += usize::from(zero);
        if error > tail.worst {
            (tail.worst, tail.at) = (error, at);
        }
    }
    tail
}

// The bake's check holds the default and fine grids to the bound
const _: () = assert!(PEAK_FRACTION <= PEAK && CHECK_BOUNDS.peak_fraction <= PEAK);
const _: () = assert!(CHECK_BOUNDS.coverage_rel_error <= BOUND);

// Before the spline of E/(ρ′² f) at the ends of the albedo axis (`table::albedo`, "The ends of
// the axis") these points found the table 100 % off (exactly 0) at ρ′ < 0.02, r ≈ 16–18; on
// 20,000 such points (`examples/tail_error`) it was also 21 % off at ρ′ → 1, r ≈ 240. Now 1.7 %
// at most here, 2.5 % on those (5.6 % at η = 1.2), largest near grazing incidence.

#[test]
fn far_tails_of_the_default_table_are_within_ten_per_cent_and_never_zero() {
    let tail = far_tail(default_table(), 3000, 17);
    assert!(tail.counted > 2000, "{tail:?}");
    assert_eq!(tail.zeros, 0, "{tail:?}");
    assert!(tail.worst <= BOUND, "{tail:?}");
}

#[test]
#[ignore = "bakes 20 tables and evaluates PBD's reference at 20,000 points on each: about a minute"]
fn far_tails_are_within_ten_per_cent_at_every_eta_from_1_2_on_the_default_and_fine_grids() {
    for preset in [GridPreset::Default, GridPreset::Fine] {
        for eta in [1.2, 1.25, 1.3, 1.33, 1.4, 1.5, 1.75, 2.0, 2.25, 2.5] {
            let (table, _) = bake(eta, Moments::Exact, &Grid::preset(preset), false).unwrap();
            let tail = far_tail(&table, 20_000, 3);
            assert_eq!(tail.zeros, 0, "{preset:?} {eta}: {tail:?}");
            assert!(tail.worst <= BOUND, "{preset:?} {eta}: {tail:?}");
        }
    }
}
