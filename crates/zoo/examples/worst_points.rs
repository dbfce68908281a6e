//! The largest errors a renderer meets: points drawn by a table's own sampler, as
//! `bssrdf validate` draws them, against photon beam diffusion, with the worst point of each
//! case. `validate` gives the mean; this finds the rare points far off (a spike of the
//! two-lobe rebuild at φ = 0 is a few thousandths of a degree wide).
//!
//! Run: `cargo run --release -p bssrdf-zoo --example worst_points -- [ETA [POINTS [SEED]]]`
//! (defaults 1.05, 50000, 7).
//!
//! Bakes the default table for ETA (`bssrdf bake --eta ETA`) and, for ρ′ ∈ {0.3, 0.5, 0.9,
//! 0.99} and θ ∈ {30°, 60°, 75°, 89°} (below η = 1 the angles at or above the critical angle
//! less 0.3° are replaced by that angle), draws POINTS points (r, φ) with the table's sampler
//! and prints the mean and largest relative error against PBD's fast rule, where the largest
//! is, and how many points are more than 4 % off.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{bake_lobes, GridPreset, Lobes};
use rayon::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: f64| -> f64 {
        args.get(i).map_or(default, |s| {
            s.parse()
                .unwrap_or_else(|_| panic!("argument {}: {s} is not a number", i + 1))
        })
    };
    let (eta, points, seed) = (arg(0, 1.05), arg(1, 50_000.0) as usize, arg(2, 7.0) as u64);
    let lobes = Lobes::for_eta(eta);
    let grid = GridPreset::Default.grid(eta, lobes);
    let (table, _) = bake_lobes(eta, Moments::Exact, &grid, true, lobes).expect("bake");
    let view = table.view();
    let boundary = Boundary::new(eta, Moments::Exact).expect("η");
    let last = if eta < 1.0 {
        eta.asin().to_degrees() - 0.3
    } else {
        89.0
    };
    println!("eta {eta}, default grid, {points} points per case, seed {seed}");
    println!("  rho  theta   mean %    max %        r   phi deg  > 4 %");
    for rho in [0.3, 0.5, 0.9, 0.99] {
        let pbd = Pbd::new(rho, boundary).expect("ρ′");
        let mut thetas: Vec<f64> = [30.0, 60.0, 75.0, 89.0].map(|t: f64| t.min(last)).to_vec();
        thetas.dedup();
        for theta_deg in thetas {
            let theta = theta_deg.to_radians();
            let mut rng = SplitMix64::seed_from_u64(seed);
            let draws: Vec<[f64; 2]> = (0..points)
                .map(|_| [rng.next_f64(), rng.next_f64()])
                .collect();
            let errors: Vec<[f64; 3]> = draws
                .par_iter()
                .filter_map(|&[u, v]| {
                    let s = view.sample(rho, theta, u, v)?;
                    let truth = pbd.eval(theta, s.r, s.phi, Rule::Fast);
                    let value = view.eval(rho, theta, s.r, s.phi).unwrap_or(0.0);
                    (truth > 0.0).then(|| [(value / truth - 1.0).abs(), s.r, s.phi])
                })
                .collect();
            let n = errors.len().max(1) as f64;
            let mean = errors.iter().map(|e| e[0]).sum::<f64>() / n;
            let worst = errors
                .iter()
                .copied()
                .fold([0.0; 3], |w, e| if e[0] > w[0] { e } else { w });
            let above = errors.iter().filter(|e| e[0] > 0.04).count();
            println!(
                "{rho:5} {theta_deg:6.2} {:8.4} {:8.2} {:8.3} {:9.3} {above:6}",
                100.0 * mean,
                100.0 * worst[0],
                worst[1],
                worst[2].to_degrees()
            );
        }
    }
}
