//! Where in r the default table departs from photon beam diffusion, and how often the table's
//! own sampler lands there: the deterministic form of Ferrier's figure 9.
//!
//! Run: `cargo run --release -p bssrdf-zoo --example error_map [THETAS [RHOS]]`, THETAS and RHOS comma lists
//! (degrees; default 0,60,89 and 0.5,0.9,0.99, the cases of the report's table 2).
//!
//! Bakes the default table at η = 1.33 and, for each (ρ′, θ) and each radius interval (the
//! first, [0, r₁], on a log scale down to 10⁻⁴ r₁), compares the table with the reference
//! quadrature on 8 radii × 64 azimuths in [0, π]. Each point carries the probability the
//! table's sampler gives its cell (pdf × r dr dφ, both halves of φ). Prints, per case, the
//! expected number of points above 1 % error among 10⁵ drawn (figure 9 wants none) and the
//! mean error under the sampler (the deterministic form of table 2's figure), then the
//! intervals whose worst error exceeds 0.5 % or that hold such points: worst error, where, the
//! sampler-weighted mean error and the expected count there. Far tails where the energy
//! underflows f32 show 100 % (the table holds 0) and carry no probability.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::table::{bake, Grid, GridPreset, TableRef};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Sub-radii per interval and azimuths over [0, π].
const SUB: usize = 8;
const N_PHI: usize = 64;

/// One radius interval's summary.
struct Interval {
    index: usize,
    worst: f64,
    worst_r: f64,
    worst_phi_deg: f64,
    mean: f64,
    /// The sampler's probability of the interval.
    mass: f64,
    mass_above_1pct: f64,
}

fn list(arg: Option<String>, default: &[f64]) -> Vec<f64> {
    match arg {
        Some(s) => s
            .split(',')
            .map(|t| t.trim().parse().expect("a comma list of numbers"))
            .collect(),
        None => default.to_vec(),
    }
}

/// The radius and its width for sub-radius k of interval [a, b] (the first on a log scale).
fn sub_radius(first: bool, a: f64, b: f64, k: usize) -> (f64, f64) {
    let t = |j: f64| j / SUB as f64;
    if first {
        let lo = (1e-4f64).ln();
        let at = |j: f64| b * (lo * (1.0 - t(j))).exp();
        (at(k as f64 + 0.5), at(k as f64 + 1.0) - at(k as f64))
    } else {
        let h = (b - a) / SUB as f64;
        (a + (k as f64 + 0.5) * h, h)
    }
}

fn interval(
    view: &TableRef<'_>,
    pbd: &Pbd,
    rho: f64,
    theta: f64,
    r_nodes: &[f64],
    i: usize,
) -> Interval {
    let (mut worst, mut worst_r, mut worst_phi) = (0.0f64, 0.0, 0.0);
    let (mut mass, mut weighted, mut above) = (0.0, 0.0, 0.0);
    let dphi = PI / N_PHI as f64;
    for k in 0..SUB {
        let (r, dr) = sub_radius(i == 0, r_nodes[i], r_nodes[i + 1], k);
        for j in 0..N_PHI {
            let phi = (j as f64 + 0.5) * dphi;
            let reference = pbd.eval(theta, r, phi, Rule::Reference);
            if reference.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            let table = view.eval(rho, theta, r, phi).unwrap_or(0.0);
            let e = (table / reference - 1.0).abs();
            let m = 2.0 * view.pdf(rho, theta, r, phi) * r * dr * dphi;
            mass += m;
            weighted += m * e;
            if e > 0.01 {
                above += m;
            }
            if e > worst {
                (worst, worst_r, worst_phi) = (e, r, phi.to_degrees());
            }
        }
    }
    Interval {
        index: i,
        worst,
        worst_r,
        worst_phi_deg: worst_phi,
        mean: if mass > 0.0 { weighted / mass } else { 0.0 },
        mass,
        mass_above_1pct: above,
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let thetas = list(args.next(), &[0.0, 60.0, 89.0]);
    let rhos = list(args.next(), &[0.5, 0.9, 0.99]);
    let grid = Grid::preset(GridPreset::Default);
    let (table, _) = bake(1.33, Moments::Exact, &grid, true).expect("the default grid bakes");
    let view = table.view();
    let boundary = Boundary::new(1.33, Moments::Exact).expect("η = 1.33 is valid");
    for &rho in &rhos {
        for &theta_deg in &thetas {
            let pbd = Pbd::new(rho, boundary).expect("ρ′ in [0, 1]");
            let theta = theta_deg.to_radians();
            let rows: Vec<Interval> = (0..grid.r.len() - 1)
                .into_par_iter()
                .map(|i| interval(&view, &pbd, rho, theta, &grid.r, i))
                .collect();
            let expected: f64 = rows.iter().map(|row| row.mass_above_1pct).sum::<f64>() * 1e5;
            let mass: f64 = rows.iter().map(|row| row.mass).sum();
            let mean = rows.iter().map(|row| row.mean * row.mass).sum::<f64>() / mass;
            println!(
                "rho {rho} theta {theta_deg}: expected points above 1 % per 1e5 = {expected:.2}, \
                 mean error {:.3} %",
                mean * 100.0
            );
            for row in rows
                .iter()
                .filter(|row| row.worst > 0.005 || row.mass_above_1pct * 1e5 > 0.01)
            {
                println!(
                    "  interval {:2} r {:9.5} phi {:6.1}: worst {:.3} %, mean {:.3} %, above 1 % per 1e5 {:.3}",
                    row.index,
                    row.worst_r,
                    row.worst_phi_deg,
                    row.worst * 100.0,
                    row.mean * 100.0,
                    row.mass_above_1pct * 1e5
                );
            }
        }
    }
}
