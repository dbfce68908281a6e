//! Random points of PBD's documented domain, shared by the oracle test and
//! `examples/quadrature_error.rs`.

use bssrdf_zoo::rng::SplitMix64;
use std::f64::consts::PI;

/// One point of PBD's documented domain, drawn with the stiff corners weighted up:
/// (ρ′, η, θ, r, φ).
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
    let r = 10f64.powf(-6.0 + (300f64.log10() + 6.0) * u());
    let phi = match (u() * 4.0) as u32 {
        0 => 0.02 * (u() - 0.5),
        _ => 2.0 * PI * u(),
    };
    (rho.clamp(1e-9, 1.0 - 1e-9), eta, theta, r, phi)
}
