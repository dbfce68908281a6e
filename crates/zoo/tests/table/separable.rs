//! The lookups for separable renderers (`TableRef::sample_radius`, `pdf_radius`,
//! `angular_factor`, and the same on `MediumRef`): the radial draw is `sample`'s, its density
//! the radial factor of `pdf`, the angular factor averages to 1 over φ and times S̄ gives eval,
//! and the separable estimator ρ_eff·F, with r from `sample_radius` and φ uniform, has mean
//! ρ_eff(θ) (runtime `table::lookup::separable`, docs/embedding.md "Separable renderers").

use crate::lookup::{default_table, two_lobe_table};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{AngularTable, TableRef};
use std::f64::consts::{PI, TAU};

/// Both kinds of table: one lobe (η = 1.33) and two (η = 1.2).
fn tables() -> [(&'static str, TableRef<'static>); 2] {
    let view = |t: &'static AngularTable| t.view();
    [
        ("one lobe", view(default_table())),
        ("two lobes", view(two_lobe_table())),
    ]
}

/// (1/2π) ∫ f dφ over [−π, π) by the trapezoid rule on `n` points: exact to rounding for a
/// periodic f resolved by the points (the sharpest lobes, c ≈ 0.95, need a few hundred).
fn mean_over_phi(n: usize, f: impl Fn(f64) -> f64) -> f64 {
    (0..n)
        .map(|k| f(-PI + TAU * k as f64 / n as f64))
        .sum::<f64>()
        / n as f64
}

/// Random lookups inside the tables: ρ′ in [0.05, 1], θ in [0, 89.9°], and a uniform.
fn points(seed: u64, n: usize) -> Vec<(f64, f64, f64)> {
    let mut rng = SplitMix64::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let rho = 0.05 + 0.95 * rng.next_f64();
            let theta = 89.9f64.to_radians() * rng.next_f64();
            (rho, theta, rng.next_f64())
        })
        .collect()
}

#[test]
fn the_radial_draw_is_samples_and_pdf_radius_its_density() {
    for (name, view) in tables() {
        for (rho, theta, u) in points(7, 300) {
            let Some(d) = view.sample_radius(rho, theta, u) else {
                assert!(
                    view.sample(rho, theta, u, 0.5).is_none(),
                    "{name} {rho} {theta}"
                );
                continue;
            };
            let s = view.sample(rho, theta, u, 0.5).unwrap();
            assert_eq!(d.r.to_bits(), s.r.to_bits(), "{name} {rho} {theta} {u}");
            let pdf = view.pdf_radius(rho, theta, d.r);
            assert!(
                (d.pdf / pdf - 1.0).abs() < 1e-9,
                "{name}: {} vs {pdf}",
                d.pdf
            );
            // The radial factor of pdf: ∫ pdf(r, φ) r dφ = pdf_radius
            let marginal = TAU * d.r * mean_over_phi(4096, |phi| view.pdf(rho, theta, d.r, phi));
            // (the two-lobe profile's density integrates to 1 within ~1e-6 on these points)
            assert!(
                (marginal / pdf - 1.0).abs() < 1e-5,
                "{name}: {marginal} vs {pdf}"
            );
        }
        assert_eq!(view.pdf_radius(0.5, 0.3, -1.0), 0.0);
        assert_eq!(view.pdf_radius(0.5, 0.3, f64::NAN), 0.0);
        assert_eq!(view.pdf_radius(0.5, 0.3, 1e9), 0.0);
    }
}

#[test]
fn the_angular_factor_averages_to_one_and_times_s_bar_gives_eval() {
    for (name, view) in tables() {
        for (rho, theta, u) in points(11, 300) {
            // Radii where the table holds energy, from the radial sampler
            let Some(d) = view.sample_radius(rho, theta, u) else {
                continue;
            };
            let f = |phi: f64| view.angular_factor(rho, theta, d.r, phi).unwrap();
            let mean = mean_over_phi(4096, f);
            assert!(
                (mean - 1.0).abs() < 1e-6,
                "{name} {rho} {theta} r {}: {mean}",
                d.r
            );
            // eval/F is S̄, the same at every φ
            let s_bar = |phi: f64| view.eval(rho, theta, d.r, phi).unwrap() / f(phi);
            let s0 = s_bar(0.0);
            for phi in [0.5, 1.5, -2.5, 3.0, 7.0] {
                if f(phi) > 1e-6 {
                    assert!((s_bar(phi) / s0 - 1.0).abs() < 1e-12, "{name} {phi}");
                }
            }
        }
        assert_eq!(view.angular_factor(0.5, 0.3, -1.0, 0.0), Some(0.0));
        assert_eq!(view.angular_factor(0.5, 0.3, 1.0, f64::NAN), Some(0.0));
        assert_eq!(view.angular_factor(0.5, 2.0, 1.0, 0.0), None);
    }
}

/// Draws per case of the unbiasedness test.
const DRAWS: usize = 200_000;
/// Standard errors allowed: |Z| > 4 has probability 6.3e-5 per case for a normal mean (the
/// mean of 2·10⁵ draws of a bounded weight is normal to far better than that), 1.5e-3 over
/// the 24 cases; the seed is fixed, so the test is deterministic.
const Z: f64 = 4.0;
/// Allowance for the full-table-value estimator: its mean is ∫ E_eval dr, which differs from
/// ρ_eff by the gap between evaluation's log-energy interpolation and the samplers' spline
/// (5.5e-5 of ρ_eff at θ = 0 on both tables, where the estimator's spread is smallest).
const EVAL_GAP: f64 = 5e-4;
/// The same below the first nonzero albedo node, where evaluation weighs the rows per radius
/// node (`albedo_ends`) and the samplers blend them: about 1 % apart there.
const EVAL_GAP_LOW_ALBEDO: f64 = 2e-2;

/// Mean and standard error of `n` weights.
fn mean_and_error(w: &[f64]) -> (f64, f64) {
    let n = w.len() as f64;
    let mean = w.iter().sum::<f64>() / n;
    let var = w.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn the_separable_estimator_has_mean_rho_eff_at_every_incidence() {
    for (name, view) in tables() {
        for (case, &(rho, theta_deg)) in [
            (0.2, 0.0),
            (0.6, 30.0),
            (0.9, 60.0),
            (0.99, 80.0),
            (0.5, 85.0),
            (0.8, 88.0),
            (0.95, 89.0),
            (0.7, 89.5),
            (0.999, 45.0),
            (0.4, 89.9),
            (0.001, 80.0),
            (0.01, 89.0),
        ]
        .iter()
        .enumerate()
        {
            let theta = f64::to_radians(theta_deg);
            let gap = if rho < view.axes().rho().as_slice()[1] {
                EVAL_GAP_LOW_ALBEDO
            } else {
                EVAL_GAP
            };
            let rho_eff = view.effective_albedo(rho, theta).unwrap();
            let mut rng = SplitMix64::seed_from_u64(100 + case as u64);
            let (mut separable, mut full) = (Vec::new(), Vec::new());
            for _ in 0..DRAWS {
                let (u_r, u_phi) = (rng.next_f64(), rng.next_f64());
                let Some(d) = view.sample_radius(rho, theta, u_r) else {
                    separable.push(0.0);
                    full.push(0.0);
                    continue;
                };
                // φ uniform: the point's density per unit area is pdf_r/(2πr)
                let phi = TAU * u_phi - PI;
                let f = view.angular_factor(rho, theta, d.r, phi).unwrap();
                separable.push(rho_eff * f);
                let s = view.eval(rho, theta, d.r, phi).unwrap();
                full.push(s * TAU * d.r / d.pdf);
            }
            let (mean, error) = mean_and_error(&separable);
            eprintln!(
                "{name} rho' {rho} theta {theta_deg}: rho_eff {rho_eff:.6e}, separable {mean:.6e} \
                 ± {error:.1e} ({:+.2e} relative)",
                mean / rho_eff - 1.0
            );
            // (at θ = 0 the factor is 1 and the weights all ρ_eff: the error is the sum's
            // rounding, up to n·ε of it)
            let rounding = DRAWS as f64 * f64::EPSILON * rho_eff;
            assert!(
                (mean - rho_eff).abs() <= Z * error + rounding,
                "{name} {rho} {theta_deg}"
            );
            let (mean, error) = mean_and_error(&full);
            eprintln!(
                "    full table value {mean:.6e} ± {error:.1e} ({:+.2e} relative)",
                mean / rho_eff - 1.0
            );
            assert!(
                (mean - rho_eff).abs() <= Z * error + gap * rho_eff,
                "{name} {rho} {theta_deg}"
            );
        }
    }
}

#[test]
fn world_units_scale_the_radial_draw_and_keep_the_factor() {
    let view = default_table().view();
    let medium = view.medium(0.9, 2.5).unwrap();
    let (theta, u) = (0.7, 0.4);
    let reduced = view.sample_radius(0.9, theta, u).unwrap();
    let d = medium.sample_radius(theta, u).unwrap();
    assert!((d.r * 2.5 / reduced.r - 1.0).abs() < 1e-15);
    assert!((d.pdf / (2.5 * reduced.pdf) - 1.0).abs() < 1e-12);
    assert!((medium.pdf_radius(theta, d.r) / d.pdf - 1.0).abs() < 1e-9);
    let f = medium.angular_factor(theta, d.r, 0.3).unwrap();
    assert_eq!(f, view.angular_factor(0.9, theta, 2.5 * d.r, 0.3).unwrap());
    // eval in mm⁻² is S̄ in mm⁻² times the factor: S̄ = ρ_eff-free, so the weight of the
    // separable step is unit-free
    let s = medium.eval(theta, d.r, 0.3).unwrap();
    let s_reduced = view.eval(0.9, theta, 2.5 * d.r, 0.3).unwrap();
    assert!((s / (6.25 * s_reduced) - 1.0).abs() < 1e-14);
}
