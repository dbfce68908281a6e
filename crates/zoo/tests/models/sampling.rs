//! Every sampler of the zoo against its own pdf: a χ² test over (r, φ) cells with a fixed seed
//! (false-failure rate 1e-6, Wilson–Hilferty critical value), and `sample`'s density equal to
//! `pdf` at the drawn point.

use bssrdf_testkit::models::model;
use bssrdf_testkit::stats::chi2_critical_1e6;
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::models::burley::{Burley, BurleyFit, BurleyOptions, SurfaceAlbedo};
use bssrdf_zoo::models::mc::McModel;
use bssrdf_zoo::models::{Model, ModelKind, Params};
use bssrdf_zoo::quadrature::adaptive;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use std::f64::consts::PI;

/// Draws per test.
const DRAWS: usize = 100_000;

/// P(cell) = ∫∫ pdf r dr dφ by nested adaptive quadrature.
fn cell_probability(m: &dyn Model, theta: f64, r: (f64, f64), phi: (f64, f64)) -> f64 {
    adaptive(
        |p| adaptive(|x| m.pdf(theta, x, p) * x, &[r.0, r.1], 1e-9, 1e-300, 200).value,
        &[phi.0, phi.1],
        1e-8,
        1e-300,
        100,
    )
    .value
}

/// χ² of `DRAWS` samples over the cells r_edges × phi_edges (plus one cell for r beyond the
/// last edge, whose probability is the complement), pooling cells expected below 5.
fn chi_square(m: &dyn Model, theta: f64, r_edges: &[f64], phi_edges: &[f64], seed: u64) {
    let (n_r, n_phi) = (r_edges.len() - 1, phi_edges.len() - 1);
    let mut observed = vec![0usize; n_r * n_phi + 1];
    let mut rng = SplitMix64::seed_from_u64(seed);
    let mut failed = 0;
    for _ in 0..DRAWS {
        let u = [rng.next_f64(), rng.next_f64()];
        let Some(s) = m.sample(theta, u) else {
            failed += 1;
            continue;
        };
        let pdf = m.pdf(theta, s.r, s.phi);
        assert!(
            (s.pdf - pdf).abs() <= 1e-6 * pdf,
            "{}: sample density {} vs pdf {pdf} at r {} phi {}",
            m.kind(),
            s.pdf,
            s.r,
            s.phi
        );
        assert!((-PI..=PI).contains(&s.phi) && s.r >= 0.0);
        let i = r_edges.partition_point(|&e| e <= s.r);
        let j = phi_edges.partition_point(|&e| e <= s.phi).clamp(1, n_phi) - 1;
        let cell = if i == 0 || i > n_r {
            n_r * n_phi
        } else {
            (i - 1) * n_phi + j
        };
        observed[cell] += 1;
    }
    assert!(
        failed <= DRAWS / 10_000,
        "{}: {failed} failed draws",
        m.kind()
    );
    let n = (DRAWS - failed) as f64;
    let mut expected: Vec<f64> = (0..n_r * n_phi)
        .map(|c| {
            let (i, j) = (c / n_phi, c % n_phi);
            n * cell_probability(
                m,
                theta,
                (r_edges[i], r_edges[i + 1]),
                (phi_edges[j], phi_edges[j + 1]),
            )
        })
        .collect();
    let inside: f64 = expected.iter().sum();
    expected.push((n - inside).max(0.0));
    let (mut chi2, mut cells) = (0.0, 0usize);
    let (mut pooled_o, mut pooled_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(&expected) {
        if e < 5.0 {
            pooled_o += o as f64;
            pooled_e += e;
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            cells += 1;
        }
    }
    if pooled_e >= 5.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e;
        cells += 1;
    } else {
        assert!(
            pooled_o <= 10.0 + 3.0 * pooled_e,
            "{}: pooled {pooled_o} vs {pooled_e}",
            m.kind()
        );
    }
    let critical = chi2_critical_1e6(cells - 1);
    assert!(
        chi2 < critical,
        "{}: chi2 = {chi2:.1} over {cells} cells, critical {critical:.1}",
        m.kind()
    );
}

/// 20 geometric radial cells from 1e-3 to 30 mfp (and [0, 1e-3)), 8 azimuthal cells.
fn default_cells() -> (Vec<f64>, Vec<f64>) {
    let mut r = vec![0.0];
    r.extend((0..=20).map(|k| 1e-3 * (3e4f64).powf(k as f64 / 20.0)));
    let phi = (0..=8).map(|k| -PI + 2.0 * PI * k as f64 / 8.0).collect();
    (r, phi)
}

#[test]
fn dipole_sampler_matches_its_pdf() {
    let (r, phi) = default_cells();
    for (rho, eta) in [(0.3, 1.33), (0.99, 1.0), (1.0, 2.5)] {
        let m = model(ModelKind::Dipole, rho, eta, 0.0, 1).unwrap();
        chi_square(&*m, 0.4, &r, &phi, 11);
    }
}

#[test]
fn burley_samplers_match_their_pdfs() {
    let (r, phi) = default_cells();
    let params = Params::new(0.7, 1.33, Moments::Exact).unwrap();
    for fit in [
        BurleyFit::Searchlight,
        BurleyFit::DiffuseTransmission,
        BurleyFit::DiffuseMeanFreePath,
    ] {
        for albedo in [SurfaceAlbedo::Pbd, SurfaceAlbedo::Given(0.95)] {
            let m = Burley::new(params, BurleyOptions { fit, albedo }).unwrap();
            chi_square(&m, 0.0, &r, &phi, 12);
        }
    }
}

#[test]
fn table_sampler_matches_its_pdf() {
    let (r, phi) = default_cells();
    let m = model(ModelKind::Table, 0.8, 1.33, 0.0, 1).unwrap();
    chi_square(&*m, 1.05, &r, &phi, 13);
}

#[test]
fn perpendicular_sampler_matches_its_pdf() {
    let (r, phi) = default_cells();
    let m = model(ModelKind::Perpendicular, 0.8, 1.33, 0.0, 1).unwrap();
    chi_square(&*m, 1.05, &r, &phi, 14);
}

#[test]
fn monte_carlo_sampler_matches_its_pdf() {
    // Cells on the model's own bins, where its pdf is constant.
    let theta = 0.6;
    let m = model(ModelKind::MonteCarlo, 0.8, 1.33, theta, 20_000).unwrap();
    let mc = McModel::run(
        &Params::new(0.8, 1.33, Moments::Exact).unwrap(),
        &bssrdf_testkit::models::options(1.33, theta, 20_000).mc,
    )
    .unwrap();
    let r = mc.r_edges().to_vec();
    let phi: Vec<f64> = (0..=mc.phi_count())
        .map(|k| -PI + 2.0 * PI * k as f64 / mc.phi_count() as f64)
        .collect();
    chi_square(&*m, theta, &r, &phi, 15);
}

#[test]
fn monte_carlo_draws_on_bin_edges_carry_their_bins_density() {
    // The φ uniform picks a point in the drawn bin; at u = 0 it is the bin's lower edge, which
    // `pdf` (folding φ onto [0, π]) read in the neighbouring bin on the φ < 0 side: the draw
    // had one bin's density and reported another's. Every φ of the same radial uniform is in
    // the same bin, so the densities must agree.
    let theta = 0.6;
    let m = model(ModelKind::MonteCarlo, 0.8, 1.33, theta, 20_000).unwrap();
    let mut differed = 0;
    for k in 0..2000 {
        let u0 = (k as f64 + 0.5) / 2000.0;
        let middle = m.sample(theta, [u0, 0.5]);
        for u1 in [0.0, 1.0 - f64::EPSILON / 2.0] {
            let edge = m.sample(theta, [u0, u1]);
            match (middle, edge) {
                (Some(a), Some(b)) => {
                    if a.pdf != b.pdf {
                        differed += 1;
                    }
                }
                (a, b) => assert_eq!(a.is_some(), b.is_some(), "{u0} {u1}"),
            }
        }
    }
    assert_eq!(differed, 0);
}
