//! Error against run time of PBD's quadratures: the fast and node rules against the reference, on
//! the points every bake evaluates and over the whole documented domain.
//!
//! Run: `cargo run --release -p bssrdf-zoo --example quadrature_error [STRIDE [NODE_STRIDE]]`
//!
//! - **Bake grid**: every STRIDE-th point (default 7) of what a bake evaluates, for each grid
//!   preset (coarse, default, fine) at η ∈ {0.75, 0.9, 1, 1.0001, 1.05, 1.1, 1.2, 1.33, 1.5, 2,
//!   2.5}: every (ρ′, θ, r > 0) node at the three anchor azimuths of the fit and the four of
//!   its refinement, and the θ = 10⁻³ rad limit of the θ = 0 nodes. STRIDE = 1 is every point
//!   (several minutes).
//! - **Two-lobe nodes**: every NODE_STRIDE-th point (default 13) that a two-lobe bake fits
//!   its lobes through, for each preset's grid below η = 1.33 (η ∈ {0.75, 0.9, 0.99, 1,
//!   1.0001, 1.001, 1.01, 1.05, 1.1, 1.2, 1.3}, the grazing nodes below 1.05): every (ρ′, θ > 0,
//!   r > 0) node at the azimuths of `table::two_lobe_azimuths`, by the node rule
//!   (`Pbd::eval_node`) and, for comparison, the fast rule.
//! - **Domain**: 20,000 random points of the documented domain with the stiff corners weighted
//!   up (the distribution of the reference rule's oracle test, `crates/zoo/tests/physics/pbd/domain.rs`).
//!
//! For each it prints the number of points, the fast rule's mean, 99th-percentile and largest
//! relative error (and where the largest is), and the mean time of one evaluation with each rule.

#[path = "../tests/physics/pbd/domain.rs"]
mod domain;

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64};
use bssrdf_zoo::table::{two_lobe_azimuths, Grid, GridPreset, Lobes, REFINE_PHI_DEG};
use std::time::Instant;

/// (ρ′, η, θ, r, φ).
type Point = (f64, f64, f64, f64, f64);

const ETAS: [f64; 11] = [0.75, 0.9, 1.0, 1.0001, 1.05, 1.1, 1.2, 1.33, 1.5, 2.0, 2.5];
const ANCHOR_COS: [f64; 3] = [0.9530, 0.4050, -0.7527];

fn bake_points(stride: usize) -> Vec<Point> {
    let mut phis: Vec<f64> = ANCHOR_COS.iter().map(|c| c.acos()).collect();
    phis.extend(REFINE_PHI_DEG.map(f64::to_radians));
    let mut all = Vec::new();
    for preset in [GridPreset::Coarse, GridPreset::Default, GridPreset::Fine] {
        let grid = Grid::preset(preset);
        for &eta in &ETAS {
            for &rho in &grid.rho {
                for &theta in &grid.theta {
                    let theta = if theta == 0.0 { 1e-3 } else { theta };
                    for &r in grid.r.iter().filter(|&&r| r > 0.0) {
                        for &phi in &phis {
                            all.push((rho, eta, theta, r, phi));
                        }
                    }
                }
            }
        }
    }
    all.into_iter().step_by(stride.max(1)).collect()
}

const TWO_LOBE_ETAS: [f64; 11] = [
    0.75, 0.9, 0.99, 1.0, 1.0001, 1.001, 1.01, 1.05, 1.1, 1.2, 1.3,
];

fn two_lobe_points(stride: usize) -> Vec<Point> {
    let mut all = Vec::new();
    for preset in [GridPreset::Coarse, GridPreset::Default, GridPreset::Fine] {
        for &eta in &TWO_LOBE_ETAS {
            let grid = preset.grid(eta, Lobes::Two);
            for &rho in &grid.rho {
                for &theta in grid.theta.iter().filter(|&&t| t > 0.0) {
                    for &r in grid.r.iter().filter(|&&r| r > 0.0) {
                        for phi in two_lobe_azimuths() {
                            all.push((rho, eta, theta, r, phi));
                        }
                    }
                }
            }
        }
    }
    all.into_iter().step_by(stride.max(1)).collect()
}

fn domain_points(n: usize) -> Vec<Point> {
    let mut rng = SplitMix64::seed_from_u64(11);
    (0..n).map(|_| domain::domain_point(&mut rng)).collect()
}

/// The rules compared with the reference.
#[derive(Clone, Copy)]
enum Rules {
    /// The fast rule.
    Fast,
    /// The node rule, and the fast rule beside it.
    NodeAndFast,
}

fn report(name: &str, points: &[Point], rules: Rules) {
    let pbds: Vec<Pbd> = points
        .iter()
        .map(|&(rho, eta, ..)| {
            Pbd::new(
                rho,
                Boundary::new(eta, Moments::Exact).expect("eta in domain"),
            )
            .expect("rho in domain")
        })
        .collect();
    let time = |eval: &dyn Fn(&Pbd, f64, f64, f64) -> f64| {
        let start = Instant::now();
        let values: Vec<f64> = points
            .iter()
            .zip(&pbds)
            .map(|(&(_, _, theta, r, phi), p)| eval(p, theta, r, phi))
            .collect();
        (values, start.elapsed().as_secs_f64() / points.len() as f64)
    };
    let (reference, t_reference) = time(&|p, theta, r, phi| p.eval(theta, r, phi, Rule::Reference));
    let (fast, t_fast) = time(&|p, theta, r, phi| p.eval(theta, r, phi, Rule::Fast));
    let n = reference
        .iter()
        .filter(|r| **r > 0.0 && r.is_finite())
        .count();
    println!("{name}: {n} points with S > 0");
    println!("  reference {:6.2} µs/eval", t_reference * 1e6);
    errors("fast rule", &fast, t_fast, &reference, t_reference, points);
    if let Rules::NodeAndFast = rules {
        let (node, t_node) = time(&|p, theta, r, phi| p.eval_node(theta, r, phi));
        errors("node rule", &node, t_node, &reference, t_reference, points);
    }
}

/// The relative errors of `values` against `reference` (where it is positive and finite),
/// with the time per evaluation against the reference's.
fn errors(
    rule: &str,
    values: &[f64],
    t_rule: f64,
    reference: &[f64],
    t_reference: f64,
    points: &[Point],
) {
    let mut errors: Vec<(f64, Point)> = values
        .iter()
        .zip(reference)
        .zip(points)
        .filter(|((_, r), _)| **r > 0.0 && r.is_finite())
        .map(|((f, r), p)| ((f / r - 1.0).abs(), *p))
        .collect();
    errors.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = errors.len();
    let mean = errors.iter().map(|e| e.0).sum::<f64>() / n as f64;
    let (max, (rho, eta, theta, r, phi)) = errors[n - 1];
    println!(
        "  {rule}: {:6.2} µs/eval ({:.2}× faster than the reference)",
        t_rule * 1e6,
        t_reference / t_rule
    );
    println!(
        "    mean {mean:.2e}, p99 {:.2e}, p99.99 {:.2e}, max {max:.2e} at ρ′ {rho}, η {eta}, θ {:.4}°, r {r:.4e}, φ {:.3}°",
        errors[n * 99 / 100].0,
        errors[n * 9999 / 10000].0,
        theta.to_degrees(),
        phi.to_degrees()
    );
}

fn main() {
    let arg = |i: usize, default: usize| {
        std::env::args().nth(i).map_or(default, |s| {
            s.parse()
                .expect("STRIDE and NODE_STRIDE are positive whole numbers")
        })
    };
    let (stride, node_stride) = (arg(1, 7), arg(2, 13));
    report(
        &format!("bake grid (every {stride}th point)"),
        &bake_points(stride),
        Rules::Fast,
    );
    report(
        &format!("two-lobe nodes (every {node_stride}th point)"),
        &two_lobe_points(node_stride),
        Rules::NodeAndFast,
    );
    report("domain", &domain_points(20_000), Rules::Fast);
}
