//! How far the table's far tail is from photon beam diffusion, decade by decade below the
//! profile's peak: the figures behind the "no silent zeros" bound of the bake's check
//! (`table::check`, docs/accuracy.md).
//!
//! Run: `cargo run --release -p bssrdf-zoo --example tail_error -- [ETA [GRID [POINTS [SEED]]]]` (defaults
//! 1.33, default, 20000, 1; GRID coarse, default or fine).
//!
//! Bakes the table `bssrdf bake --eta ETA --grid GRID` makes and draws POINTS points weighted towards the ends of the albedo axis and
//! large r: ρ′ log-uniform over [10⁻³, 1] for half of them, 1 − ρ′ log-uniform over [10⁻⁷, 1]
//! for a quarter and ρ′ uniform for the rest; θ uniform over the angles at which light enters;
//! φ uniform over [0, π]; r log-uniform over [r₁, r_max] of the axis for a third, uniform over
//! [1, min(r_max, 35/σ_tr)] for the rest (PBD falls to about 10⁻¹³ of its peak at 35/σ_tr).
//! Truth is PBD's fast rule, the peak PBD at (r₁, φ = 0). Prints, per ρ′ band and per decade of
//! truth/peak, the points, their mean and largest relative error, how many are more than 10 %
//! off and how many the table gives as exactly 0; the same over every point at or above 10⁻¹²
//! of the peak; the worst of those per ρ′ band; and PBD at the last radius node over its peak
//! for ρ′ from 0.9 to 1 (beyond that node the table is 0).

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{bake_lobes, GridPreset, Lobes};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::io::Write as _;

/// Band edges of ρ′ for the summary.
const RHO_EDGES: [f64; 10] = [
    0.0,
    0.02,
    0.05,
    0.078,
    0.1,
    0.3,
    0.7,
    0.99,
    0.9999,
    1.0 + 1e-9,
];
/// Decades of truth/peak for the summary (lower edges).
const DECADES: [f64; 8] = [1e-4, 1e-6, 1e-7, 1e-8, 1e-10, 1e-11, 1e-12, 0.0];
/// Worst points printed per ρ′ band.
const WORST_PER_BAND: usize = 4;

/// A band edge as printed (the last, a hair above 1 so that the band holds ρ′ = 1, as 1).
fn edge(x: f64) -> String {
    format!("{}", x.min(1.0))
}

struct Point {
    rho: f64,
    theta_deg: f64,
    r: f64,
    phi_deg: f64,
    fraction: f64,
    rel: f64,
    zero: bool,
}

fn main() {
    let mut args = std::env::args().skip(1);
    let eta: f64 = args.next().map_or(1.33, |s| s.parse().expect("ETA"));
    let preset = match args.next().as_deref() {
        None | Some("default") => GridPreset::Default,
        Some("coarse") => GridPreset::Coarse,
        Some("fine") => GridPreset::Fine,
        Some(other) => panic!("GRID is coarse, default or fine, not {other}"),
    };
    let n: usize = args.next().map_or(20_000, |s| s.parse().expect("POINTS"));
    let seed: u64 = args.next().map_or(1, |s| s.parse().expect("SEED"));

    // The grid `bssrdf bake --grid GRID` takes at this η (its θ nodes and radii)
    let lobes = Lobes::for_eta(eta);
    let grid = preset.grid(eta, lobes);
    let (table, _) = bake_lobes(eta, Moments::Exact, &grid, false, lobes).expect("bake");
    let view = table.view();
    let boundary = Boundary::new(eta, Moments::Exact).expect("eta");
    let r_nodes = table.axes().r().as_slice();
    let (r1, r_max) = (r_nodes[1], r_nodes[r_nodes.len() - 1]);
    let theta_max = if eta < 1.0 {
        eta.asin().to_degrees() * (1.0 - 1e-6)
    } else {
        90.0
    };

    let mut rng = SplitMix64::seed_from_u64(seed);
    let draws: Vec<[f64; 4]> = (0..n)
        .map(|_| std::array::from_fn(|_| rng.next_f64()))
        .collect();
    let points: Vec<Point> = draws
        .par_iter()
        .enumerate()
        .filter_map(|(k, u)| {
            let rho = match k % 4 {
                0 | 1 => 1e-3 * (1e3f64).powf(u[0]),
                2 => u[0],
                _ => 1.0 - 1e-7 * (1e7f64).powf(u[0]),
            }
            .clamp(0.0, 1.0);
            let theta_deg = theta_max * u[1];
            let theta = theta_deg.to_radians();
            let phi = PI * u[2];
            // (σ_tr ≈ √(3(1 − ρ′)): PBD is about 10⁻¹³ of its peak at r = 35/σ_tr)
            let sigma_tr = (3.0 * (1.0 - rho)).sqrt();
            let r = if k % 3 == 0 {
                r1 * (r_max / r1).powf(u[3])
            } else {
                1.0 + ((35.0 / sigma_tr).min(r_max) - 1.0) * u[3]
            };
            let pbd = Pbd::new(rho, boundary).ok()?;
            let truth = pbd.eval(theta, r, phi, Rule::Fast);
            let peak = pbd.eval(theta, r1, 0.0, Rule::Fast);
            if !(truth > 0.0 && peak > 0.0) {
                return None;
            }
            let value = view.eval(rho, theta, r, phi)?;
            let rel = (value / truth - 1.0).abs();
            Some(Point {
                rho,
                theta_deg,
                r,
                phi_deg: phi.to_degrees(),
                fraction: truth / peak,
                rel: if rel.is_nan() { f64::INFINITY } else { rel },
                zero: value == 0.0,
            })
        })
        .collect();

    // Printed at the end in one write, which a closed pipe may refuse
    let mut lines: Vec<String> = Vec::new();
    lines.push(format!(
        "eta {eta}, {preset:?} grid, {} points, seed {seed}",
        points.len()
    ));
    lines.push(
        "rho band        | truth/peak  | points | mean rel err | max rel err | > 10 % | zeros"
            .to_string(),
    );
    for band in RHO_EDGES.windows(2) {
        let mut upper = f64::INFINITY;
        for &lower in &DECADES {
            let chosen: Vec<&Point> = points
                .iter()
                .filter(|p| p.rho >= band[0] && p.rho < band[1])
                .filter(|p| p.fraction >= lower && p.fraction < upper)
                .collect();
            if !chosen.is_empty() {
                let max = chosen.iter().map(|p| p.rel).fold(0.0, f64::max);
                let mean = chosen.iter().map(|p| p.rel).sum::<f64>() / chosen.len() as f64;
                let above = chosen.iter().filter(|p| p.rel > 0.1).count();
                let zeros = chosen.iter().filter(|p| p.zero).count();
                lines.push(format!(
                    "[{:<6}, {:<6}) | >= {lower:7.0e} | {:6} | {:10.3} % | {:9.3} % | {above:6} | {zeros}",
                    edge(band[0]),
                    edge(band[1]),
                    chosen.len(),
                    100.0 * mean,
                    100.0 * max,
                ));
            }
            upper = lower;
        }
    }

    let counted: Vec<&Point> = points.iter().filter(|p| p.fraction >= 1e-12).collect();
    let max = counted.iter().map(|p| p.rel).fold(0.0, f64::max);
    lines.push(format!("at or above 1e-12 of the peak: {} points, mean {:.3} %, max {:.3} %, {} above 10 %, {} zeros",
        counted.len(),
        100.0 * counted.iter().map(|p| p.rel).sum::<f64>() / counted.len().max(1) as f64,
        100.0 * max,
        counted.iter().filter(|p| p.rel > 0.1).count(),
        counted.iter().filter(|p| p.zero).count()
    ));
    lines.push("worst points at or above 1e-12 of the peak, per rho band:".to_string());
    lines.push("   rho   theta      r     phi   truth/peak   rel err  zero".to_string());
    for band in RHO_EDGES.windows(2) {
        let mut worst: Vec<&Point> = points
            .iter()
            .filter(|p| p.fraction >= 1e-12 && p.rho >= band[0] && p.rho < band[1])
            .collect();
        worst.sort_by(|a, b| b.rel.total_cmp(&a.rel));
        for p in worst.iter().take(WORST_PER_BAND) {
            lines.push(format!(
                "{:.4} {:6.2} {:7.3} {:6.1} {:11.3e} {:8.3} % {}",
                p.rho,
                p.theta_deg,
                p.r,
                p.phi_deg,
                p.fraction,
                100.0 * p.rel,
                p.zero
            ));
        }
    }

    // Where the axis ends: PBD there against the peak (beyond r_max the table is 0)
    let mut end: Vec<(f64, f64, f64)> = Vec::new();
    for rho in [0.9, 0.99, 0.999, 1.0] {
        let pbd = Pbd::new(rho, boundary).expect("rho");
        for theta_deg in [0.0, 60.0, 89.0f64.min(theta_max)] {
            let theta = theta_deg.to_radians();
            let peak = pbd.eval(theta, r1, 0.0, Rule::Fast);
            let at_end = pbd.eval(theta, r_max, 0.0, Rule::Fast);
            end.push((rho, theta_deg, at_end / peak));
        }
    }
    lines.push(format!(
        "PBD at the last radius node ({r_max:.1}), phi = 0, over the peak:"
    ));
    for (rho, theta_deg, f) in end {
        lines.push(format!("  rho {rho} theta {theta_deg:.0}: {f:.3e}"));
    }
    lines.push(String::new());
    std::io::stdout()
        .write_all(lines.join("\n").as_bytes())
        .ok();
}
