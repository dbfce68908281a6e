//! A tight loop of table lookups, for A/B timing of lookup code (criterion in `crates/zoo/benches/table.rs`
//! gives the figures docs/performance.md reports; this loop is quicker to run many times in alternation,
//! and its binary can be copied aside and run against another build's).
//!
//! Run: `N=4000000 cargo run --release -p bssrdf-zoo --example lookup_loop -- eval|sample|pdf`. Bakes the default
//! table at η = 1.33, draws 4,096 points (ρ′ ∈ [0.05, 1), θ ∈ [0, 1.5) rad, (r, φ) from the
//! table's own sampler) and times N calls of `eval`, `sample` or `pdf` over them; prints ns per call
//! and a checksum. To compare two builds, copy `target/release/examples/lookup_loop` aside
//! after each build and run the copies in alternation, keeping each one's minimum.
//! `RHO=LO,HI` draws ρ′ uniformly in [LO, HI) instead, to time one part of the albedo axis
//! (the ends take their own path, `table::albedo`, "The ends of the axis"). `ETA=1.2` bakes at
//! that η instead (below 1.33 a two-lobe table, `table::Lobes`). `REPEAT=1` times the first
//! point over and over (the random numbers of the draws still change): every cache warm and
//! every branch predicted, what is left is the lookup's own arithmetic.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{bake, Grid, GridPreset};
use std::hint::black_box;

#[path = "../benches/support/lookup_points.rs"]
mod lookup_points;
use lookup_points::lookup_points;

fn main() {
    let what = std::env::args().nth(1).unwrap_or("sample".into());
    if !["eval", "sample", "pdf"].contains(&what.as_str()) {
        eprintln!("lookup_loop: the mode is eval, sample or pdf, not {what:?}");
        std::process::exit(2);
    }
    let eta = std::env::var("ETA").map_or(1.33, |v| v.parse().expect("ETA=number"));
    let (table, _) = bake(
        eta,
        Moments::Exact,
        &Grid::preset(GridPreset::Default),
        true,
    )
    .expect("the default grid bakes");
    let view = table.view();
    let mut rng = SplitMix64::seed_from_u64(1);
    let points = match std::env::var("RHO") {
        Ok(range) => {
            let (lo, hi) = range
                .split_once(',')
                .and_then(|(lo, hi)| Some((lo.parse::<f64>().ok()?, hi.parse::<f64>().ok()?)))
                .expect("RHO=LO,HI, two numbers");
            (0..4096)
                .map(|_| loop {
                    let (rho, theta) = (lo + (hi - lo) * rng.next_f64(), 1.5 * rng.next_f64());
                    if let Some(s) = view.sample(rho, theta, rng.next_f64(), rng.next_f64()) {
                        break [rho, theta, s.r, s.phi];
                    }
                })
                .collect()
        }
        Err(_) => lookup_points(&view, &mut rng),
    };
    let points = if std::env::var("REPEAT").is_ok_and(|v| v == "1") {
        vec![points[0]; points.len()]
    } else {
        points
    };
    let us: Vec<[f64; 2]> = (0..4096)
        .map(|_| [rng.next_f64(), rng.next_f64()])
        .collect();
    let n: usize = std::env::var("N")
        .map(|v| v.parse().expect("N, a number of calls"))
        .unwrap_or(20_000_000);
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    for i in 0..n {
        let [rho, theta, r, phi] = points[i % 4096];
        let u = us[(i * 7) % 4096];
        acc += match what.as_str() {
            "eval" => view
                .eval(
                    black_box(rho),
                    black_box(theta),
                    black_box(r),
                    black_box(phi),
                )
                .unwrap_or(0.0),
            "pdf" => view.pdf(
                black_box(rho),
                black_box(theta),
                black_box(r),
                black_box(phi),
            ),
            _ => view
                .sample(black_box(rho), black_box(theta), u[0], u[1])
                .map_or(0.0, |s| s.r),
        };
    }
    println!(
        "{what}: {:.1} ns/call ({acc})",
        t.elapsed().as_nanos() as f64 / n as f64
    );
}
