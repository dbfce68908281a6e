//! Helpers shared by the Catmull-Rom integration tests: tolerances, a seeded RNG, test node
//! sets and profiles, quadrature and the chi-square test of a sampler against its pdf.

use crate::stats::chi2_critical_1e6;
use bssrdf_zoo::catmull_rom::Nodes;

/// Agreement expected from exact arithmetic carried out in f64 (a few ulps, accumulated).
pub const EXACT: f64 = 1e-13;
/// Agreement expected from the Newton–bisection solves (T_TOLERANCE = 1e-12 in t, plus slack).
pub const SOLVED: f64 = 1e-10;
/// Samples per chi-square test.
pub const CHI_SQUARE_SAMPLES: usize = 1_000_000;

/// The crate's own generator (SplitMix64), seeded per test.
pub use bssrdf_zoo::rng::SplitMix64;
use bssrdf_zoo::rng::{SeedableRng, UnitF64};

/// pbrt's radius grid: r₀ = 0, r₁ = 0.0025, rᵢ = 1.2·r_{i−1}, 64 nodes up to 202.85.
pub fn geometric_radii() -> Vec<f64> {
    let mut r = vec![0.0, 0.0025];
    while r.len() < 64 {
        let last = r[r.len() - 1];
        r.push(last * 1.2);
    }
    r
}

/// An exponential-like radial profile, 2πr·(e^{−r} + e^{−r/4}/4) (zero at r = 0).
pub fn radial_profile(r: f64) -> f64 {
    2.0 * std::f64::consts::PI * r * ((-r).exp() + 0.25 * (-r / 4.0).exp())
}

/// Non-uniform nodes on [0, 2] (spacing varies by about 10×).
pub fn uneven_nodes() -> Vec<f64> {
    (0..=20)
        .map(|i| 2.0 * (i as f64 / 20.0).powf(1.7))
        .collect()
}

/// The running integral of the spline through `values` ([`Nodes::integrate`]).
pub fn integrated(nodes: &Nodes, values: &[f64]) -> Vec<f64> {
    let mut cumulative = vec![0.0; values.len()];
    nodes
        .integrate(|i| values[i], &mut cumulative)
        .expect("lengths match");
    cumulative
}

/// Composite Simpson's rule with `panels` (even) panels; exact for cubics.
pub fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let h = (b - a) / panels as f64;
    let inner: f64 = (1..panels)
        .map(|k| f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    (f(a) + inner + f(b)) * h / 3.0
}

/// Draws `CHI_SQUARE_SAMPLES` samples and compares their histogram with the integral of `pdf`
/// over each bin, each spline segment split into `split` bins, pooling neighbours until every
/// expected count is ≥ 5. Asserts that ∫pdf = 1 within 10⁻⁶ (the documented mismatch where a
/// signed CDF decreases in the tail is 2·10⁻⁷ here, far below what 10⁶ samples resolve), that
/// no draw failed, and that the statistic is below the p = 10⁻⁶ critical value.
pub fn chi_square(
    nodes: &[f64],
    seed: u64,
    split: usize,
    sample: impl Fn(f64) -> Option<f64>,
    pdf: impl Fn(f64) -> f64,
) {
    let edges: Vec<f64> = nodes
        .windows(2)
        .flat_map(|w| (0..split).map(move |k| w[0] + (w[1] - w[0]) * k as f64 / split as f64))
        .chain(nodes.last().copied())
        .collect();
    let probabilities: Vec<f64> = edges
        .windows(2)
        .map(|w| simpson(&pdf, w[0], w[1], 32))
        .collect();
    let normalization: f64 = probabilities.iter().sum();
    assert!((normalization - 1.0).abs() < 1e-6, "∫pdf = {normalization}");

    let mut counts = vec![0u64; probabilities.len()];
    let mut rng = SplitMix64::seed_from_u64(seed);
    for _ in 0..CHI_SQUARE_SAMPLES {
        let u = rng.next_f64();
        let x = sample(u).unwrap_or_else(|| panic!("sampling failed at u = {u}"));
        let bin = edges.partition_point(|&e| e <= x).clamp(1, counts.len()) - 1;
        counts[bin] += 1;
    }

    let n = CHI_SQUARE_SAMPLES as f64;
    let (mut statistic, mut cells) = (0.0, 0usize);
    let (mut observed, mut expected) = (0.0, 0.0);
    for (k, (&count, &p)) in counts.iter().zip(&probabilities).enumerate() {
        observed += count as f64;
        expected += p * n;
        let rest: f64 = probabilities[k + 1..].iter().sum::<f64>() * n;
        if (expected >= 5.0 && rest >= 5.0) || k + 1 == counts.len() {
            statistic += (observed - expected).powi(2) / expected;
            cells += 1;
            (observed, expected) = (0.0, 0.0);
        }
    }
    let dof = cells - 1;
    let critical = chi2_critical_1e6(dof);
    assert!(cells > 20, "only {cells} cells");
    assert!(
        statistic < critical,
        "chi-square {statistic} ≥ {critical} with {dof} degrees of freedom"
    );
}
