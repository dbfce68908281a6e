//! Random points of PBD's documented domain, shared by the oracle test and
//! `examples/quadrature_error.rs`.

use bssrdf_zoo::rng::{SplitMix64, UnitF64};
use std::f64::consts::PI;

/// One point of PBD's documented domain, drawn with the stiff corners weighted up:
/// (ρ′, η, θ, r, φ).
///
/// - η: 10 % exactly 1 or 1 ± 1e-4, 30 % uniform over [0.95, 1.2], the rest over [0.75, 2.5];
/// - ρ′: a third log-uniform over [1e-9, 1], a third with 1 − ρ′ log-uniform over [1e-9, 1],
///   a third uniform;
/// - θ: 5 % exactly 90°, 45 % uniform over [80°, 90°], the rest over [0°, 90°];
/// - r: 10 % log-uniform over [1e-100, 1e-6] (the small-r expansion below 1e-12), the rest
///   log-uniform over [1e-6, 300] reduced mean free paths;
/// - φ: an eighth within ±0.57° of forward, an eighth with |φ| log-uniform over
///   [1e-140, 1e-2] rad (a beam grazing the exit point at θ = 90°, η = 1), the rest uniform.
pub fn domain_point(rng: &mut SplitMix64) -> (f64, f64, f64, f64, f64) {
    let mut u = || rng.next_f64();
    let eta = match (u() * 10.0) as u32 {
        0 => [1.0, 1.0 + 1e-4, 1.0 - 1e-4][(u() * 3.0) as usize % 3],
        1..=3 => 0.95 + 0.25 * u(),
        _ => 0.75 + 1.75 * u(),
    };
    let rho = match (u() * 3.0) as u32 {
        0 => 10f64.powf(-9.0 + 9.0 * u()),
        1 => 1.0 - 10f64.powf(-9.0 + 9.0 * u()),
        _ => u(),
    };
    let theta = match (u() * 20.0) as u32 {
        0 => 0.5 * PI,
        1..=9 => (80.0 + 10.0 * u()).to_radians(),
        _ => 0.5 * PI * u(),
    };
    let r = match (u() * 10.0) as u32 {
        // The small-r expansion below 1e-12, and the quadrature just above it.
        0 => 10f64.powf(-100.0 + 94.0 * u()),
        _ => 10f64.powf(-6.0 + (300f64.log10() + 6.0) * u()),
    };
    let phi = match (u() * 8.0) as u32 {
        0 => 0.02 * (u() - 0.5),
        1 => 10f64.powf(-140.0 + 138.0 * u()) * if u() < 0.5 { -1.0 } else { 1.0 },
        _ => 2.0 * PI * u(),
    };
    (rho.clamp(1e-9, 1.0 - 1e-9), eta, theta, r, phi)
}
