//! How well can an angular model follow PBD's azimuthal profile at one (η, ρ′, θ)? The best fit
//! of each family, one wrapped Cauchy lobe over a floor (what tables store) and two lobes over
//! a floor, at eight radii.
//!
//! Run: `cargo run --release -p bssrdf-zoo --example angular_families -- ETA RHO THETA_DEG`
//!
//! At each r, PBD (reference rule) at 721 azimuths in [0, π]; for every concentration c (two
//! for two lobes) on a grid uniform in ln(1 − c) from 0 to 0.9999, the floor and lobe masses by
//! least squares on the relative error weighted by the profile (the weight of a renderer's
//! points, which the table's sampler draws in proportion to it). It prints the best fit's
//! weighted mean and largest relative error, and its concentrations. The fits may have negative
//! floors; a fit whose profile dips below 0 anywhere is discarded.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use std::f64::consts::PI;

/// The wrapped Cauchy density.
fn wrapped_cauchy(phi: f64, c: f64) -> f64 {
    (1.0 - c * c) / (2.0 * PI * (1.0 + c * c - 2.0 * c * phi.cos()))
}

/// The fit of `basis` columns to `f`, least squares on the relative error with weights `w`:
/// (weighted mean, largest) relative error, `None` if singular or negative somewhere.
fn fit(basis: &[Vec<f64>], f: &[f64], w: &[f64]) -> Option<(f64, f64)> {
    let m = basis.len();
    // Normal equations [A | b], solved by Gauss-Jordan elimination with partial pivoting
    let mut a = vec![vec![0.0; m + 1]; m];
    for k in 0..f.len() {
        let wk = w[k] / (f[k] * f[k]);
        for i in 0..m {
            for j in 0..m {
                a[i][j] += wk * basis[i][k] * basis[j][k];
            }
            a[i][m] += wk * basis[i][k] * f[k];
        }
    }
    for i in 0..m {
        let pivot = (i..m).max_by(|&x, &y| a[x][i].abs().total_cmp(&a[y][i].abs()))?;
        a.swap(i, pivot);
        let p = a[i][i];
        if p.abs() < 1e-300 {
            return None;
        }
        for v in &mut a[i][i..=m] {
            *v /= p;
        }
        let pivot_row = a[i].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != i {
                let factor = row[i];
                for (x, y) in row[i..=m].iter_mut().zip(&pivot_row[i..=m]) {
                    *x -= factor * y;
                }
            }
        }
    }
    let (mut sum, mut weight, mut max) = (0.0, 0.0, 0.0f64);
    for k in 0..f.len() {
        let v: f64 = (0..m).map(|i| a[i][m] * basis[i][k]).sum();
        if v < 0.0 {
            return None;
        }
        let e = (v / f[k] - 1.0).abs();
        sum += w[k] * e;
        weight += w[k];
        max = max.max(e);
    }
    Some((sum / weight, max))
}

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("ETA RHO THETA_DEG, three numbers"))
        .collect();
    let [eta, rho, theta_deg] = args[..] else {
        eprintln!("usage: angular_families ETA RHO THETA_DEG");
        std::process::exit(2);
    };
    let pbd = Pbd::new(
        rho,
        Boundary::new(eta, Moments::Exact).expect("eta in [0.75, 2.5]"),
    )
    .expect("rho in [0, 1]");
    let theta = theta_deg.to_radians();
    let n = 721;
    let phis: Vec<f64> = (0..n).map(|i| PI * i as f64 / (n - 1) as f64).collect();
    let cs: Vec<f64> = (0..=310)
        .map(|i| (1.0 - (-(i as f64) * 0.03).exp()).min(0.9999))
        .collect();
    let lobes: Vec<Vec<f64>> = cs
        .iter()
        .map(|&c| phis.iter().map(|&p| wrapped_cauchy(p, c)).collect())
        .collect();
    let floor = vec![1.0; n];
    println!("eta {eta}, rho' {rho}, theta {theta_deg} deg: best fits, relative error (mean weighted by the profile / largest)");
    for r in [0.01, 0.05, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0] {
        let f: Vec<f64> = phis
            .iter()
            .map(|&p| pbd.eval(theta, r, p, Rule::Reference))
            .collect();
        let mut one = (f64::INFINITY, f64::INFINITY, 0.0);
        for (i, lobe) in lobes.iter().enumerate() {
            if let Some((mean, max)) = fit(&[floor.clone(), lobe.clone()], &f, &f) {
                if mean < one.0 {
                    one = (mean, max, cs[i]);
                }
            }
        }
        let mut two = (f64::INFINITY, f64::INFINITY, 0.0, 0.0);
        for i in 0..lobes.len() {
            for j in 0..i {
                let basis = [floor.clone(), lobes[i].clone(), lobes[j].clone()];
                if let Some((mean, max)) = fit(&basis, &f, &f) {
                    if mean < two.0 {
                        two = (mean, max, cs[i], cs[j]);
                    }
                }
            }
        }
        println!(
            "r {r:5}: one lobe {:7.3} % / {:7.3} % (c {:.4}) | two lobes {:7.3} % / {:7.3} % (c {:.4}, {:.4})",
            100.0 * one.0,
            100.0 * one.1,
            one.2,
            100.0 * two.0,
            100.0 * two.1,
            two.2,
            two.3
        );
    }
}
