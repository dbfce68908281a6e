//! The two rules by which lookups of a two-lobe table rebuild its lobes (format-spec.md §10
//! step 4, required feature bit 4): with merged roots (`Rebuild::MergedRoots`, format 1.4, what
//! the bake writes) and without (`Rebuild::Roots`, how files without bit 4 are read), on the
//! same table, against PBD.
//!
//! Run: `cargo run --release -p bssrdf-zoo --example rebuild_rules -- [ETA [POINTS [SEED]]]`
//! (defaults 1.05, 200000, 3).
//!
//! Bakes the default table for ETA and reads it by both rules:
//! - at every node (each at 65 azimuths in [0, π]): how many nodes the rules read differently
//!   (by more than 10⁻⁶ relative at some azimuth), and over those the mean of each rule's
//!   largest error against PBD's fast rule, and at how many the merged roots are further off;
//! - at POINTS points between the nodes, drawn as `tail_error` draws them (ρ′ log-uniform over
//!   [10⁻³, 1] for half, uniform for the rest; θ uniform where light enters; r log-uniform over
//!   the axis for a third, uniform over [1, min(r_max, 35/σ_tr)] for the rest; φ uniform over
//!   [0, π]), where PBD is at least 10⁻¹² of its peak: per rule the mean and largest error and
//!   how many points are above 10 %.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::gwc::Rebuild;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{bake_lobes, GridPreset, Lobes, TableRef};
use rayon::prelude::*;
use std::f64::consts::PI;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: f64| -> f64 {
        args.get(i).map_or(default, |s| {
            s.parse()
                .unwrap_or_else(|_| panic!("argument {}: {s} is not a number", i + 1))
        })
    };
    let (eta, points, seed) = (arg(0, 1.05), arg(1, 200_000.0) as usize, arg(2, 3.0) as u64);
    let grid = GridPreset::Default.grid(eta, Lobes::Two);
    let (table, _) = bake_lobes(eta, Moments::Exact, &grid, true, Lobes::Two).expect("bake");
    let boundary = Boundary::new(eta, Moments::Exact).expect("η");
    let merged = table.view();
    let roots = merged.with_rebuild(Rebuild::Roots);
    println!("eta {eta}, default grid, two lobes");
    nodes(&merged, &roots, boundary);
    between(&merged, &roots, boundary, points, seed);
}

/// The nodes the two rules read differently, and their errors there.
fn nodes(merged: &TableRef, roots: &TableRef, boundary: Boundary) {
    let axes = merged.axes();
    let (rho, theta, r) = (
        axes.rho().as_slice(),
        axes.theta().as_slice(),
        axes.r().as_slice(),
    );
    let cells: Vec<(f64, f64, f64)> = rho
        .iter()
        .flat_map(|&p| {
            theta
                .iter()
                .flat_map(move |&t| r.iter().map(move |&k| (p, t, k)))
        })
        .filter(|&(p, _, k)| p > 0.0 && k > 0.0)
        .collect();
    let phis: Vec<f64> = (0..=64).map(|k| PI * f64::from(k) / 64.0).collect();
    let differ: Vec<[f64; 2]> = cells
        .par_iter()
        .filter_map(|&(p, t, k)| {
            let read = |v: &TableRef| -> Vec<f64> {
                phis.iter()
                    .map(|&phi| v.eval(p, t, k, phi).unwrap_or(0.0))
                    .collect()
            };
            let (a, b) = (read(merged), read(roots));
            let differs = a
                .iter()
                .zip(&b)
                .any(|(x, y)| (x - y).abs() > 1e-6 * y.abs());
            if !differs {
                return None;
            }
            let pbd = Pbd::new(p, boundary).ok()?;
            let truth: Vec<f64> = phis
                .iter()
                .map(|&phi| pbd.eval(t, k, phi, Rule::Fast))
                .collect();
            let worst = |v: &[f64]| {
                v.iter()
                    .zip(&truth)
                    .filter(|(_, &y)| y > 0.0)
                    .map(|(x, y)| (x / y - 1.0).abs())
                    .fold(0.0, f64::max)
            };
            Some([worst(&a), worst(&b)])
        })
        .collect();
    let n = differ.len().max(1) as f64;
    let mean = |i: usize| 100.0 * differ.iter().map(|e| e[i]).sum::<f64>() / n;
    let further = differ.iter().filter(|e| e[0] > e[1]).count();
    println!(
        "nodes: {} of {} read differently; largest error over phi there, mean: merged roots {:.4} %, roots {:.4} %; merged further off at {further}",
        differ.len(),
        cells.len(),
        mean(0),
        mean(1)
    );
}

/// Both rules' errors at points between the nodes.
fn between(merged: &TableRef, roots: &TableRef, boundary: Boundary, points: usize, seed: u64) {
    let axes = merged.axes();
    let (r_first, r_last) = (axes.r().as_slice()[1], *axes.r().as_slice().last().unwrap());
    let theta_max = if boundary.eta() < 1.0 {
        boundary.eta().asin()
    } else {
        PI / 2.0
    };
    let mut rng = SplitMix64::seed_from_u64(seed);
    let draws: Vec<[f64; 4]> = (0..points)
        .map(|_| std::array::from_fn(|_| rng.next_f64()))
        .collect();
    let errors: Vec<[f64; 2]> = draws
        .par_iter()
        .filter_map(|&[a, b, c, d]| {
            let rho = if a < 0.5 {
                (1e-3f64.ln() * (1.0 - 2.0 * a)).exp()
            } else {
                2.0 * (a - 0.5)
            }
            .clamp(1e-3, 1.0);
            let theta = b * theta_max * (1.0 - 1e-9);
            let far = (35.0 / (3.0 * (1.0 - rho)).sqrt()).min(r_last);
            let r = if c < 1.0 / 3.0 {
                (r_first.ln() + 3.0 * c * (r_last / r_first).ln()).exp()
            } else {
                1.0 + 1.5 * (c - 1.0 / 3.0) * (far - 1.0)
            };
            let phi = PI * d;
            let pbd = Pbd::new(rho, boundary).ok()?;
            let truth = pbd.eval(theta, r, phi, Rule::Fast);
            let peak = pbd.eval(theta, r_first, 0.0, Rule::Fast);
            if !(truth > 0.0 && truth >= 1e-12 * peak) {
                return None;
            }
            let error =
                |v: &TableRef| (v.eval(rho, theta, r, phi).unwrap_or(0.0) / truth - 1.0).abs();
            Some([error(merged), error(roots)])
        })
        .collect();
    let n = errors.len().max(1) as f64;
    for (i, name) in ["merged roots", "roots"].iter().enumerate() {
        let mean = 100.0 * errors.iter().map(|e| e[i]).sum::<f64>() / n;
        let worst = 100.0 * errors.iter().map(|e| e[i]).fold(0.0, f64::max);
        let above = errors.iter().filter(|e| e[i] > 0.1).count();
        println!(
            "{} points between nodes, {name}: mean {mean:.3} %, largest {worst:.2} %, {above} above 10 %",
            errors.len()
        );
    }
}
