//! The report's accuracy protocol (`bssrdf validate`'s: points drawn by the table's own
//! sampler, mean relative error against the reference quadrature) over any incidences and
//! albedos, on the table `bssrdf bake --eta ETA` writes (the same grid and lobes), baked here.
//!
//! Run: `cargo run --release -p bssrdf-zoo --example protocol_sweep -- ETA [THETAS [RHOS]]`,
//! THETAS in degrees and RHOS as comma lists (default 5,15,25,35,45,55,60,75,89 and
//! 0.1,0.5,0.9,0.99); `N=…` points per case (default 20,000), seed 7 as `validate`'s.
//! Prints the bake's time and the mean error of each (θ, ρ′) in per cent.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{bake, validate, GridPreset, Lobes};
use std::time::Instant;

fn list(arg: Option<&String>, default: &str) -> Vec<f64> {
    arg.map_or(default, String::as_str)
        .split(',')
        .map(|x| x.trim().parse().expect("a comma list of numbers"))
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let eta: f64 = args
        .get(1)
        .and_then(|e| e.parse().ok())
        .expect("usage: protocol_sweep ETA [THETAS [RHOS]]");
    let thetas = list(args.get(2), "5,15,25,35,45,55,60,75,89");
    let rhos = list(args.get(3), "0.1,0.5,0.9,0.99");
    let samples: usize = std::env::var("N").map_or(20_000, |n| n.parse().expect("N: a count"));
    let grid = GridPreset::Default.grid(eta, Lobes::for_eta(eta));
    let start = Instant::now();
    let (table, _) = bake(eta, Moments::Exact, &grid, true).expect("a valid η");
    println!("η = {eta}: bake {:.2} s", start.elapsed().as_secs_f64());
    print!("{:>7}", "θ \\ ρ′");
    for rho in &rhos {
        print!(" {rho:>8}");
    }
    println!();
    for &theta in &thetas {
        let cases: Vec<(f64, f64)> = rhos.iter().map(|&rho| (rho, theta)).collect();
        let rows = validate(&table.view(), Moments::Exact, &cases, samples, 7)
            .expect("cases in the domain");
        print!("{theta:>7}");
        for row in rows {
            print!(" {:>7.3}%", 100.0 * row.mean_rel_error);
        }
        println!();
    }
}
