//! Error against run time of the two PBD quadratures, over the bake grid's stiff corners.
//!
//! Run: `cargo run --release --example quadrature_error`
//!
//! For η ∈ {1, 1.33, 2.5}, every 7th albedo node of the default table (plus ρ′ = 1), θ every
//! 10° to 90° (and 89.99°), every 3rd radius node, and the three anchor azimuths of the table
//! fit, it prints the fast rule's mean, 99th-percentile and max relative error against the
//! reference quadrature, and the mean time of one evaluation with each.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use std::time::Instant;

fn main() {
    let mut errors = Vec::new();
    let mut points = Vec::new();
    for eta in [1.0, 1.33, 2.5] {
        let boundary = Boundary::new(eta, Moments::Exact).expect("valid eta");
        for i in (0..100).step_by(7).chain([99]) {
            let rho = (1.0 - (-8.0 * i as f64 / 99.0).exp()) / (1.0 - (-8.0f64).exp());
            let pbd = Pbd::new(rho.min(1.0), boundary).expect("valid rho");
            for theta_deg in [
                0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 89.99, 90.0,
            ] {
                for j in (1..64).step_by(3) {
                    for cos_phi in [0.9530f64, 0.4050, -0.7527] {
                        points.push((
                            pbd,
                            f64::to_radians(theta_deg),
                            0.0025 * 1.2f64.powi(j),
                            cos_phi.acos(),
                        ));
                    }
                }
            }
        }
    }
    let time = |rule: Rule| {
        let start = Instant::now();
        let values: Vec<f64> = points
            .iter()
            .map(|(p, t, r, phi)| p.eval(*t, *r, *phi, rule))
            .collect();
        (values, start.elapsed().as_secs_f64() / points.len() as f64)
    };
    let (reference, t_reference) = time(Rule::Reference);
    let (fast, t_fast) = time(Rule::Fast);
    for (f, r) in fast.iter().zip(&reference) {
        if *r > 0.0 && r.is_finite() {
            errors.push((f / r - 1.0).abs());
        }
    }
    errors.sort_by(f64::total_cmp);
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let p99 = errors[errors.len() * 99 / 100];
    let max = errors[errors.len() - 1];
    println!("points: {}", errors.len());
    println!("rule       time/eval   mean rel. error   p99         max");
    println!(
        "reference  {:7.2} µs   (tolerance 1e-10)",
        t_reference * 1e6
    );
    println!(
        "fast       {:7.2} µs   {mean:.2e}          {p99:.2e}    {max:.2e}",
        t_fast * 1e6
    );
}
