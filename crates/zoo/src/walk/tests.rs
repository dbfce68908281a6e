//! Checks of the random walk against exact and published references.
//!
//! Statistical tests use fixed seeds, so each either always passes or always fails; the stated
//! tolerances are what a fresh seed would pass with high probability. Two tolerance rules:
//! - fast (default suite, 10⁵ photons): |MC − ref| ≤ max(4 σ, 2 % · ref);
//! - full (`--ignored`, 10⁷ photons): |MC − ref| ≤ 3 σ and ≤ 0.5 % · ref.

use super::*;
use crate::fresnel;
use crate::quadrature::adaptive;
use harmonics::{harmonics, unreduced_albedo, HarmonicsConfig, WalkHarmonics, HARMONICS};
use std::f64::consts::{PI, TAU};

/// Photons of the fast checks.
pub(super) const FAST_PHOTONS: u64 = 100_000;
/// Photons of the full checks.
const FULL_PHOTONS: u64 = 10_000_000;

/// Reference total diffuse reflectances of a half-space, g = 0, copied from
/// `shared/reference/semi-infinite-reflectance.csv`: (albedo, η, θ in degrees, R_diffuse,
/// R_specular). η = 1 rows are `exact_H_function` (Chandrasekhar's H-function, to ~1e-9);
/// η > 1 rows are `adding_doubling_iadpython` (Prahl's adding–doubling, iadpython 0.5.3,
/// accurate to ~3e-5), per unit *incident* power with the specular reflection removed, so
/// they are divided by the entry transmittance 1 − R_specular before comparing.
const H_FUNCTION_05_0: (f64, f64, f64, f64, f64) = (0.5, 1.0, 0.0, 0.115226, 0.0);
const H_FUNCTION_09_60: (f64, f64, f64, f64, f64) = (0.9, 1.0, 60.0, 0.507939, 0.0);
const H_FUNCTION_099_85: (f64, f64, f64, f64, f64) = (0.99, 1.0, 85.0, 0.879945, 0.0);
const H_FUNCTION_08_85: (f64, f64, f64, f64, f64) = (0.8, 1.0, 85.0, 0.496767, 0.0);
const H_FUNCTION_099_0: (f64, f64, f64, f64, f64) = (0.99, 1.0, 0.0, 0.752721, 0.0);
const ADDING_DOUBLING_09_13: (f64, f64, f64, f64, f64) = (0.9, 1.3, 0.0, 0.28579, 0.0170132);
const ADDING_DOUBLING_05_14: (f64, f64, f64, f64, f64) = (0.5, 1.4, 0.0, 0.0523035, 0.0277778);
const ADDING_DOUBLING_095_15: (f64, f64, f64, f64, f64) = (0.95, 1.5, 0.0, 0.321126, 0.04);

/// van de Hulst's slab as quoted by MCML (Wang, Jacques, Zheng 1995, Table 2): η = 1,
/// a = 0.9, g = 0.75, τ = 2, normal incidence. T_t includes unscattered transmission.
const VAN_DE_HULST_RD: f64 = 0.09739;
const VAN_DE_HULST_TT: f64 = 0.66096;

fn half_space(albedo: f64, g: f64, eta: f64, theta_deg: f64, photons: u64, seed: u64) -> Config {
    Config {
        photons,
        seed,
        ..Config::new(albedo, g, eta, theta_deg.to_radians())
    }
}

fn van_de_hulst(photons: u64, seed: u64) -> Config {
    Config {
        geometry: Geometry::Slab { thickness: 2.0 },
        ..half_space(0.9, 0.75, 1.0, 0.0, photons, seed)
    }
}

fn must_run(config: &Config) -> WalkResult {
    match run(config) {
        Ok(r) => r,
        Err(e) => panic!("run failed: {e}"),
    }
}

/// Reference per unit power entering.
fn entering(row: (f64, f64, f64, f64, f64)) -> f64 {
    row.3 / (1.0 - row.4)
}

fn assert_fast(what: &str, e: Estimate, reference: f64) {
    let tol = (4.0 * e.stderr).max(0.02 * reference.abs());
    let dev = (e.value - reference).abs();
    println!(
        "{what}: MC {:.6} ± {:.2e}, ref {reference:.6}, dev {:.2} σ",
        e.value,
        e.stderr,
        dev / e.stderr
    );
    assert!(
        dev <= tol,
        "{what}: {} ± {} vs {reference}",
        e.value,
        e.stderr
    );
}

fn assert_full(what: &str, e: Estimate, reference: f64) {
    let dev = (e.value - reference).abs();
    println!(
        "{what}: MC {:.6} ± {:.2e}, ref {reference:.6}, dev {:.2} σ, {:.3} %",
        e.value,
        e.stderr,
        dev / e.stderr,
        100.0 * dev / reference
    );
    assert!(dev <= 3.0 * e.stderr, "{what}: more than 3 σ off");
    assert!(dev <= 0.005 * reference, "{what}: more than 0.5 % off");
}

fn check_row(row: (f64, f64, f64, f64, f64), photons: u64, full: bool) {
    let (albedo, eta, theta, ..) = row;
    let r = must_run(&half_space(albedo, 0.0, eta, theta, photons, 2024));
    let what = format!("a = {albedo}, eta = {eta}, theta = {theta}°");
    if full {
        assert_full(&what, r.total_reflectance(), entering(row));
    } else {
        assert_fast(&what, r.total_reflectance(), entering(row));
    }
    // Parts add up and the half-space has no unscattered exit.
    let parts = r.single_reflectance().value + r.multiple_reflectance().value;
    assert!((parts - r.total_reflectance().value).abs() <= 1e-12);
    assert_eq!(r.reflectance(Component::Unscattered).value, 0.0);
    assert!(r.total_transmittance().is_none());
}

/// Refracted direction cosine μ0 = cos θt of the beam inside.
pub(super) fn mu0(eta: f64, theta: f64) -> f64 {
    let s = theta.sin() / eta;
    (1.0 - s * s).sqrt()
}

/// Critical cosine inside, below which exits are totally reflected (0 for η ≤ 1).
pub(super) fn mu_critical(eta: f64) -> f64 {
    if eta > 1.0 {
        (1.0 - 1.0 / (eta * eta)).sqrt()
    } else {
        0.0
    }
}

/// Exact single-scattering reflectance of a half-space per unit power entering:
/// R₁ = a ∫_{up} p(ω₀·ω) T(μ) μ/(μ + μ₀) dω, from the vertex density e^{−z/μ₀}/μ₀ per unit
/// depth and the escape probability e^{−z/μ} T(μ) (integrated over depth z). φ by the
/// trapezoid rule (spectrally accurate for a periodic integrand), μ adaptively, split at the
/// critical cosine.
pub(super) fn single_scattering_reflectance(albedo: f64, g: f64, eta: f64, theta: f64) -> f64 {
    let m0 = mu0(eta, theta);
    let s0 = (1.0 - m0 * m0).sqrt();
    let n_phi = 512;
    let inner = |mu: f64| {
        let s = (1.0 - mu * mu).max(0.0).sqrt();
        let t = fresnel::transmittance(mu, 1.0 / eta);
        let mut sum = 0.0;
        for k in 0..n_phi {
            let phi = TAU * k as f64 / n_phi as f64;
            let cos_scatter = s0 * s * phi.cos() - m0 * mu;
            sum += super::hg_phase(g, cos_scatter);
        }
        albedo * t * mu / (mu + m0) * sum * TAU / n_phi as f64
    };
    let mc = mu_critical(eta);
    let breaks: Vec<f64> = if mc > 0.0 {
        vec![0.0, mc, 1.0]
    } else {
        vec![0.0, 1.0]
    };
    adaptive(inner, &breaks, 1e-10, 1e-13, 500).value
}

/// Exact single-scattering exitance at distance r under normal incidence, per unit area per
/// unit power entering: E₁(r) = a ∫₀^∞ e^{−z} p(−μ) T(μ) e^{−d} μ/d² dz, d = √(r² + z²),
/// μ = z/d (dω = μ dA/d²).
pub(super) fn single_scattering_exitance(albedo: f64, g: f64, eta: f64, r: f64) -> f64 {
    let f = |z: f64| {
        let d = (r * r + z * z).sqrt();
        let mu = z / d;
        let t = fresnel::transmittance(mu, 1.0 / eta);
        albedo * (-z - d).exp() * super::hg_phase(g, -mu) * t * mu / (d * d)
    };
    let mc = mu_critical(eta);
    // Below z_c = r μc/√(1 − μc²) the exit is totally reflected.
    let zc = r * mc / (1.0 - mc * mc).sqrt();
    adaptive(f, &[zc, zc + 1.0, zc + 60.0], 1e-10, 1e-15, 2000).value
}

#[test]
fn half_space_eta_one_matches_h_function_fast() {
    for row in [H_FUNCTION_05_0, H_FUNCTION_09_60, H_FUNCTION_08_85] {
        check_row(row, FAST_PHOTONS, false);
    }
}

#[test]
fn half_space_eta_above_one_matches_adding_doubling_fast() {
    check_row(ADDING_DOUBLING_09_13, FAST_PHOTONS, false);
}

#[test]
fn single_scattering_quadrature_has_the_isotropic_closed_form() {
    // η = 1, g = 0, θ = 0: R₁ = (a/2)(1 − ln 2).
    let q = single_scattering_reflectance(0.7, 0.0, 1.0, 0.0);
    let exact = 0.35 * (1.0 - 2f64.ln());
    assert!((q - exact).abs() < 1e-9, "{q} vs {exact}");
    // And μ₀ = cos 60°: (a/2)[1 − μ₀ ln((1 + μ₀)/μ₀)].
    let q = single_scattering_reflectance(0.7, 0.0, 1.0, PI / 3.0);
    let exact = 0.35 * (1.0 - 0.5 * 3f64.ln());
    assert!((q - exact).abs() < 1e-9, "{q} vs {exact}");
}

#[test]
fn single_scattering_matches_quadrature_fast() {
    // Oblique, anisotropic, mismatched: every ingredient of the single-scattering path.
    for (albedo, g, eta, theta_deg) in [(0.8, 0.5, 1.3, 60.0), (0.95, -0.3, 0.8, 30.0)] {
        let r = must_run(&half_space(albedo, g, eta, theta_deg, FAST_PHOTONS, 7));
        let q = single_scattering_reflectance(albedo, g, eta, theta_deg.to_radians());
        let what = format!("single scattering a = {albedo}, g = {g}, eta = {eta}, {theta_deg}°");
        assert_fast(&what, r.single_reflectance(), q);
    }
}

#[test]
fn single_scattering_bins_match_quadrature() {
    // Ring averages of the binned single-scattering exitance against ∫ E₁(r) 2πr dr / area.
    let (albedo, g, eta) = (0.8, 0.3, 1.4);
    let bins = Bins::new(0.05, 5.0, 10, 8).unwrap();
    let config = Config {
        bins: bins.clone(),
        ..half_space(albedo, g, eta, 0.0, FAST_PHOTONS, 11)
    };
    let r = must_run(&config);
    let b = r.bins();
    let mut chi2 = 0.0;
    let rings = b.layout().radial_count();
    for i in 0..rings {
        let (lo, hi) = (b.r_edges()[i], b.r_edges()[i + 1]);
        let (mut power, mut var, mut area) = (0.0, 0.0, 0.0);
        for j in 0..b.layout().phi_count() {
            let a = b.area(i, j).unwrap();
            power += b.value(Component::Single, i, j).unwrap() * a;
            var += (b.stderr(Component::Single, i, j).unwrap() * a).powi(2);
            area += a;
        }
        let mc = power / area;
        // Conservative: a photon scores single scattering in at most one bin, so the φ bins of
        // a ring are negatively correlated and the summed variances overestimate.
        let se = var.sqrt() / area;
        let exact = adaptive(
            |rr| single_scattering_exitance(albedo, g, eta, rr) * TAU * rr,
            &[lo, hi],
            1e-8,
            1e-14,
            200,
        )
        .value
            / area;
        let z = (mc - exact) / se;
        println!("ring [{lo:.4}, {hi:.4}): MC {mc:.5e} ± {se:.1e}, exact {exact:.5e}, {z:.2} σ");
        assert!(z.abs() < 4.5, "ring {i}");
        chi2 += z * z;
    }
    assert!(
        chi2 < 2.0 * rings as f64 + 10.0,
        "chi2 = {chi2} over {rings} rings"
    );
}

#[test]
fn exitance_is_even_in_phi() {
    // Mirror bins j and n − 1 − j about the plane of incidence, at oblique incidence.
    let bins = Bins::new(0.1, 10.0, 8, 12).unwrap();
    let config = Config {
        bins,
        ..half_space(0.9, 0.6, 1.3, 50.0, FAST_PHOTONS, 3)
    };
    let r = must_run(&config);
    let b = r.bins();
    let (nr, np) = (b.layout().radial_count(), b.layout().phi_count());
    let (mut chi2, mut dof) = (0.0, 0);
    for c in [Component::Single, Component::Multiple, Component::Total] {
        for i in 0..nr {
            for j in 0..np / 2 {
                let m = np - 1 - j;
                let (va, vb) = (b.value(c, i, j).unwrap(), b.value(c, i, m).unwrap());
                let (sa, sb) = (b.stderr(c, i, j).unwrap(), b.stderr(c, i, m).unwrap());
                let s = (sa * sa + sb * sb).sqrt();
                if s > 0.0 {
                    let z = (va - vb) / s;
                    assert!(z.abs() < 5.0, "{c:?} bin ({i}, {j}): {va} vs {vb}, z = {z}");
                    chi2 += z * z;
                    dof += 1;
                }
            }
        }
    }
    println!("evenness: chi2 = {chi2:.1} over {dof} pairs");
    assert!(dof > 50);
    // χ² with `dof` degrees of freedom: mean dof, sd √(2 dof); allow 5 sd.
    let d = dof as f64;
    assert!(
        chi2 < d + 5.0 * (2.0 * d).sqrt(),
        "chi2 = {chi2} over {dof}"
    );
}

#[test]
fn phi_zero_is_forward() {
    // A forward-peaked phase function at 60°: single scattering exits mostly ahead of the
    // beam, at φ = 0 (x > 0).
    let bins = Bins::new(0.1, 10.0, 6, 2).unwrap();
    let config = Config {
        bins,
        ..half_space(0.9, 0.8, 1.0, 60.0, 20_000, 5)
    };
    let r = must_run(&config);
    let b = r.bins();
    // Two φ bins: [−π, 0) and [0, π) are the two sides of the plane of incidence, equal.
    let bins4 = Bins::new(0.1, 10.0, 6, 4).unwrap();
    let r4 = must_run(&Config {
        bins: bins4,
        ..config.clone()
    });
    let b4 = r4.bins();
    let (mut forward, mut backward) = (0.0, 0.0);
    for i in 0..b4.layout().radial_count() {
        // Bins 1 and 2 are [−π/2, 0) and [0, π/2): forward; 0 and 3 backward.
        forward +=
            b4.value(Component::Single, i, 1).unwrap() + b4.value(Component::Single, i, 2).unwrap();
        backward +=
            b4.value(Component::Single, i, 0).unwrap() + b4.value(Component::Single, i, 3).unwrap();
    }
    assert!(
        forward > 3.0 * backward,
        "forward {forward}, backward {backward}"
    );
    assert!(b.value(Component::Total, 2, 0).unwrap() > 0.0);
}

#[test]
fn bins_sum_to_the_binned_reflectance() {
    let bins = Bins::new(0.02, 3.0, 12, 10).unwrap();
    let config = Config {
        bins,
        ..half_space(0.95, 0.4, 1.2, 45.0, 20_000, 9)
    };
    let r = must_run(&config);
    let b = r.bins();
    let mut sums = [0.0; 4];
    for i in 0..b.layout().radial_count() {
        for j in 0..b.layout().phi_count() {
            let a = b.area(i, j).unwrap();
            for (k, c) in Component::ALL.into_iter().enumerate() {
                sums[k] += b.value(c, i, j).unwrap() * a;
            }
        }
    }
    let binned = r.binned_reflectance().value;
    assert!(
        (sums[3] - binned).abs() <= 1e-12 * binned,
        "{} vs {binned}",
        sums[3]
    );
    assert!((sums[0] + sums[1] + sums[2] - sums[3]).abs() <= 1e-12 * binned);
    // The disc of radius 3 holds most but not all of the reflectance.
    let total = r.total_reflectance().value;
    assert!(
        binned < total && binned > 0.5 * total,
        "{binned} of {total}"
    );
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let config = Config {
        bins: Bins::new(0.05, 8.0, 10, 6).unwrap(),
        ..half_space(0.9, 0.5, 1.3, 40.0, 5 * BLOCK + 123, 42)
    };
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(|| must_run(&config));
    let two = pool(2).install(|| must_run(&config));
    let bits = |r: &WalkResult| {
        let mut v: Vec<u64> = Vec::new();
        for c in Component::ALL {
            v.push(r.reflectance(c).value.to_bits());
            v.push(r.reflectance(c).stderr.to_bits());
        }
        v.push(r.binned_reflectance().value.to_bits());
        let b = r.bins();
        for i in 0..b.layout().radial_count() {
            for j in 0..b.layout().phi_count() {
                for c in Component::ALL {
                    v.push(b.value(c, i, j).unwrap().to_bits());
                    v.push(b.stderr(c, i, j).unwrap().to_bits());
                }
            }
        }
        v
    };
    assert_eq!(one.scattering_events(), two.scattering_events());
    assert_eq!(bits(&one), bits(&two));
    // And a different seed gives a different (but statistically equal) answer.
    let other = must_run(&Config {
        seed: 43,
        ..config.clone()
    });
    assert_ne!(bits(&one), bits(&other));
}

#[test]
fn the_spread_per_photon_of_issue_22s_case_stays_that_of_the_split_walk() {
    // Half-space, albedo 0.9, η = 1.33, normal incidence: the standard deviation per photon of
    // the total reflectance, √N · σ, was 0.269 (g = 0) and 0.1165 (g = 0.9) with the reflected
    // part split by weight at every boundary and every flight scored in expectation (10⁶
    // photons, seed 1); the walk's roulette and far-flight scores make it 0.2725 and 0.1168.
    // At 10⁵ photons seeds 1–4 give 0.2719–0.2736 and 0.1142–0.1173: a bound 5 % above the
    // split walk's fails on a real loss of efficiency per photon, not on noise.
    for (g, split) in [(0.0, 0.269), (0.9, 0.1165)] {
        let r = must_run(&half_space(0.9, g, 1.33, 0.0, FAST_PHOTONS, 1));
        let spread = r.total_reflectance().stderr * (FAST_PHOTONS as f64).sqrt();
        println!("g = {g}: spread per photon {spread:.4} (split walk {split})");
        assert!(spread <= 1.05 * split, "g = {g}: {spread} against {split}");
    }
}

#[test]
fn van_de_hulst_slab_fast() {
    let r = must_run(&van_de_hulst(FAST_PHOTONS, 1));
    assert_fast("van de Hulst R_d", r.total_reflectance(), VAN_DE_HULST_RD);
    let t = r.total_transmittance().unwrap();
    assert_fast("van de Hulst T_t", t, VAN_DE_HULST_TT);
    // Unscattered transmission e^{−2} is scored exactly by every photon.
    let t0 = r.transmittance(Component::Unscattered).unwrap();
    assert!((t0.value - (-2f64).exp()).abs() < 1e-12 && t0.stderr < 1e-12);
}

#[test]
fn unscattered_slab_matches_the_fresnel_series() {
    // a = 0: only the beam bouncing between the faces leaves. With μ = cos θt, internal
    // Fresnel R and T, and t = e^{−τ/μ}: T₀ = t T/(1 − R²t²), R₀ = t² R T/(1 − R²t²).
    let (eta, theta, tau) = (1.5, 60f64.to_radians(), 0.5);
    let config = Config {
        geometry: Geometry::Slab { thickness: tau },
        ..half_space(0.0, 0.0, eta, theta.to_degrees(), 20_000, 2)
    };
    let r = must_run(&config);
    let mu = mu0(eta, theta);
    let (rf, tf) = (
        fresnel::reflectance(mu, 1.0 / eta),
        fresnel::transmittance(mu, 1.0 / eta),
    );
    let t = (-tau / mu).exp();
    let t0 = t * tf / (1.0 - rf * rf * t * t);
    let r0 = t * t * rf * tf / (1.0 - rf * rf * t * t);
    let got_t = r.transmittance(Component::Unscattered).unwrap();
    let got_r = r.reflectance(Component::Unscattered);
    println!("T0 {got_t:?} vs {t0}, R0 {got_r:?} vs {r0}");
    assert!((got_t.value - t0).abs() <= 4.0 * got_t.stderr + 1e-12);
    assert!((got_r.value - r0).abs() <= 4.0 * got_r.stderr + 1e-12);
    assert_eq!(r.scattering_events(), r.scattering_events());
    assert_eq!(r.single_reflectance().value, 0.0);
    assert_eq!(r.multiple_reflectance().value, 0.0);
}

#[test]
fn conservative_slab_conserves_energy() {
    // a = 1: everything that enters leaves through one face or the other.
    let config = Config {
        geometry: Geometry::Slab { thickness: 1.0 },
        ..half_space(1.0, 0.5, 1.3, 30.0, 20_000, 8)
    };
    let r = must_run(&config);
    let (rt, tt) = (r.total_reflectance(), r.total_transmittance().unwrap());
    let sum = rt.value + tt.value + r.truncated_weight().value;
    println!("R + T = {sum} (R {rt:?}, T {tt:?})");
    assert!((sum - 1.0).abs() <= 4.0 * (rt.stderr + tt.stderr));
}

#[test]
fn albedo_zero_half_space_reflects_nothing() {
    let r = must_run(&half_space(0.0, 0.0, 1.3, 0.3, 1000, 1));
    assert_eq!(r.total_reflectance().value, 0.0);
    assert_eq!(r.scattering_events(), 1000);
}

#[test]
fn grazing_and_extreme_parameters_stay_finite() {
    for (albedo, g, eta, theta) in [
        (0.9, 0.0, 1.0, FRAC_PI_2),
        (0.9, 0.99, 1.0, FRAC_PI_2),
        (0.5, -0.99, 0.75, 0.75f64.asin()),
        (1.0, 0.0, 1.0, 0.0),
        (0.99, 0.0, 2.5, 1.0),
    ] {
        let config = Config {
            photons: 2000,
            ..Config::new(albedo, g, eta, theta)
        };
        let r = must_run(&config);
        let t = r.total_reflectance();
        assert!(t.value.is_finite() && t.stderr.is_finite(), "{config:?}");
        assert!((0.0..=1.0 + 5.0 * t.stderr).contains(&t.value), "{t:?}");
    }
}

#[test]
fn invalid_configs_are_rejected() {
    let ok = || half_space(0.5, 0.0, 1.3, 10.0, 100, 0);
    let eta_out_of_range = |value| Error::OutOfRange {
        name: "eta",
        value,
        min: crate::medium::ETA_MIN,
        max: crate::medium::ETA_MAX,
    };
    let cases: Vec<(Config, Error)> = vec![
        (
            Config {
                albedo: f64::NAN,
                ..ok()
            },
            Error::NotFinite {
                name: "albedo",
                value: f64::NAN,
            },
        ),
        (
            Config {
                albedo: 1.5,
                ..ok()
            },
            Error::OutOfRange {
                name: "albedo",
                value: 1.5,
                min: 0.0,
                max: 1.0,
            },
        ),
        (
            Config {
                albedo: -0.1,
                ..ok()
            },
            Error::OutOfRange {
                name: "albedo",
                value: -0.1,
                min: 0.0,
                max: 1.0,
            },
        ),
        (Config { g: 1.0, ..ok() }, Error::AsymmetryOutOfRange(1.0)),
        (Config { g: -1.0, ..ok() }, Error::AsymmetryOutOfRange(-1.0)),
        (
            Config {
                g: f64::INFINITY,
                ..ok()
            },
            Error::NotFinite {
                name: "g",
                value: f64::INFINITY,
            },
        ),
        (Config { eta: 0.0, ..ok() }, eta_out_of_range(0.0)),
        (Config { eta: -1.3, ..ok() }, eta_out_of_range(-1.3)),
        (Config { eta: 2.6, ..ok() }, eta_out_of_range(2.6)),
        (
            Config {
                eta: f64::NAN,
                ..ok()
            },
            Error::NotFinite {
                name: "eta",
                value: f64::NAN,
            },
        ),
        (
            Config {
                theta: -0.1,
                ..ok()
            },
            Error::OutOfRange {
                name: "theta",
                value: -0.1,
                min: 0.0,
                max: FRAC_PI_2,
            },
        ),
        (
            Config { theta: 2.0, ..ok() },
            Error::OutOfRange {
                name: "theta",
                value: 2.0,
                min: 0.0,
                max: FRAC_PI_2,
            },
        ),
        (
            Config {
                eta: 0.75,
                theta: 1.0,
                ..ok()
            },
            Error::OutOfRange {
                name: "theta",
                value: 1.0,
                min: 0.0,
                max: 0.75f64.asin(),
            },
        ),
        (
            Config { photons: 0, ..ok() },
            Error::CountOutOfRange {
                name: "photons",
                value: 0,
                min: 2,
                max: u64::MAX,
            },
        ),
        (
            Config { photons: 1, ..ok() },
            Error::CountOutOfRange {
                name: "photons",
                value: 1,
                min: 2,
                max: u64::MAX,
            },
        ),
        (
            Config {
                geometry: Geometry::Slab { thickness: 0.0 },
                ..ok()
            },
            Error::NotPositive {
                name: "thickness",
                value: 0.0,
            },
        ),
        (
            Config {
                geometry: Geometry::Slab {
                    thickness: f64::NAN,
                },
                ..ok()
            },
            Error::NotFinite {
                name: "thickness",
                value: f64::NAN,
            },
        ),
    ];
    for (config, expected) in cases {
        match run(&config) {
            Ok(_) => panic!("accepted {config:?}"),
            // NaN ≠ NaN: compare the messages, which name the value.
            Err(e) => assert_eq!(e.to_string(), expected.to_string()),
        }
    }
    assert!(run(&ok()).is_ok());
}

#[test]
fn csv_has_one_row_per_bin() {
    let bins = Bins::new(0.1, 2.0, 3, 4).unwrap();
    let r = must_run(&Config {
        bins,
        ..half_space(0.8, 0.0, 1.0, 0.0, 2000, 1)
    });
    let mut out = Vec::new();
    r.to_csv(&mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "r_lo,r_hi,phi_lo_deg,phi_hi_deg,single,single_stderr,multiple,multiple_stderr,total,total_stderr"
    );
    assert_eq!(lines.len(), 1 + 4 * 4);
    let first: Vec<f64> = lines[1].split(',').map(|s| s.parse().unwrap()).collect();
    assert_eq!(first.len(), 10);
    assert_eq!(
        (first[0], first[1], first[2], first[3]),
        (0.0, 0.1, -180.0, -90.0)
    );
    assert_eq!(first[8], r.bins().value(Component::Total, 0, 0).unwrap());
}

#[test]
fn json_summary_has_the_documented_keys() {
    let r = must_run(&half_space(0.8, 0.0, 1.0, 0.0, 2000, 77));
    let v = serde_json::to_value(&r).unwrap();
    for key in [
        "total_reflectance",
        "total_reflectance_stderr",
        "single_reflectance",
        "single_reflectance_stderr",
        "multiple_reflectance",
        "multiple_reflectance_stderr",
        "photons",
        "seed",
        "scattering_events",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["photons"], 2000);
    assert_eq!(v["seed"], 77);
    assert_eq!(v["scattering_events"], r.scattering_events());
    assert_eq!(v["total_reflectance"], r.total_reflectance().value);
    assert!(v.get("total_transmittance").is_none());
}

#[test]
#[ignore = "10^7 photons per row; run with cargo test --release -- --ignored walk"]
fn full_half_space_matches_references() {
    for row in [
        H_FUNCTION_05_0,
        H_FUNCTION_09_60,
        H_FUNCTION_08_85,
        H_FUNCTION_099_85,
        H_FUNCTION_099_0,
        ADDING_DOUBLING_09_13,
        ADDING_DOUBLING_05_14,
        ADDING_DOUBLING_095_15,
    ] {
        check_row(row, FULL_PHOTONS, true);
    }
}

#[test]
#[ignore = "10^7 photons; run with cargo test --release -- --ignored walk"]
fn full_van_de_hulst_slab() {
    let r = must_run(&van_de_hulst(FULL_PHOTONS, 1));
    // The published figures have 4–5 significant digits; iadpython gives 0.097395 and
    // 0.660958 (notes-models.md §4.2), within their rounding.
    assert_full("van de Hulst R_d", r.total_reflectance(), VAN_DE_HULST_RD);
    assert_full(
        "van de Hulst T_t",
        r.total_transmittance().unwrap(),
        VAN_DE_HULST_TT,
    );
}

#[test]
#[ignore = "10^7 photons per case; run with cargo test --release -- --ignored walk"]
fn full_single_scattering_matches_quadrature() {
    for (albedo, g, eta, theta_deg) in [(0.8, 0.5, 1.3, 60.0), (0.95, -0.3, 0.8, 30.0)] {
        let r = must_run(&half_space(albedo, g, eta, theta_deg, FULL_PHOTONS, 13));
        let q = single_scattering_reflectance(albedo, g, eta, theta_deg.to_radians());
        let what = format!("single scattering a = {albedo}, g = {g}, eta = {eta}, {theta_deg}°");
        assert_full(&what, r.single_reflectance(), q);
    }
}

// --- The harmonics of many albedos from one walk (harmonics.rs) ---

/// Radii of the harmonics checks: a geometric axis from 0 with ratio 1.33 up to ~25 mfp.
pub(super) fn harmonics_radii() -> Vec<f64> {
    std::iter::once(0.0)
        .chain((0..24).map(|i| 0.03 * 1.33f64.powi(i)))
        .collect()
}

pub(super) fn walk_harmonics(
    rho: &[f64],
    g: f64,
    theta_deg: f64,
    photons: u64,
    seed: u64,
) -> WalkHarmonics {
    let config = HarmonicsConfig {
        rho: rho.to_vec(),
        g,
        eta: 1.4,
        theta: theta_deg.to_radians(),
        r: harmonics_radii(),
        photons,
        seed,
    };
    harmonics(&config, &|_| {}).unwrap()
}

/// The hat kernel of node i of `r` (r[i − 1] > 0 or i = 1 with r[0] = 0) over ln r, as
/// harmonics.rs documents it, written out here: its weight at ln-radius u per unit ln r,
/// normalised to integrate to 1.
fn hat(r: &[f64], i: usize, u: f64) -> f64 {
    let c = r[i].ln();
    let right = if i + 1 < r.len() {
        r[i + 1].ln() - c
    } else {
        c - r[i - 1].ln()
    };
    let left = if r[i - 1] > 0.0 {
        c - r[i - 1].ln()
    } else {
        right
    };
    let h = if u < c {
        1.0 - (c - u) / left
    } else {
        1.0 - (u - c) / right
    };
    h.max(0.0) / (0.5 * (left + right))
}

/// The average of f over the hat kernel of node i ([`hat`]), by Gauss–Legendre over ln r on
/// each side of the node (the hat's kink).
pub(super) fn kernel_average(r: &[f64], i: usize, f: impl Fn(f64) -> f64) -> f64 {
    // Below a node whose neighbour is 0 the hat is as wide as above it
    let below = if r[i - 1] > 0.0 {
        r[i - 1]
    } else {
        r[i] * r[i] / r[i + 1]
    };
    let (lo, c, hi) = (below.ln(), r[i].ln(), r[i + 1].ln());
    let rule = crate::quadrature::GaussLegendre::new(24);
    let g = |u: f64| hat(r, i, u) * f(u.exp());
    rule.integrate(lo, c, g) + rule.integrate(c, hi, g)
}

#[test]
fn harmonics_single_scattering_matches_quadrature_in_every_row() {
    // At normal incidence single scattering is isotropic in φ: μ₀(r′) = 2π E₁(r′/s)/s² in a
    // row's reduced units (s = 1 − g a), μₙ = 0 for n ≥ 1. Rows of three albedos from one walk
    // at the largest; each against the exact exitance E₁ by quadrature, kernel-averaged.
    let (g, eta) = (0.5, 1.4);
    let rho = [0.3, 0.95, 0.7];
    let h = walk_harmonics(&rho, g, 0.0, FAST_PHOTONS, 5);
    let r = harmonics_radii();
    let (mut chi2, mut count) = (0.0, 0);
    for (row, &rho) in rho.iter().enumerate() {
        let a = unreduced_albedo(rho, g);
        let s = 1.0 - g * a;
        // Up to 2 reduced mfp: farther out single-scattering exits are rare and the batch
        // means far from normal
        for node in (1..r.len()).filter(|&i| r[i] < 2.0) {
            let mean = h.mean(Component::Single, row, node).unwrap();
            let se = h.stderr(Component::Single, row, node).unwrap();
            let exact = kernel_average(&r, node, |x| {
                TAU * single_scattering_exitance(a, g, eta, x / s) / (s * s)
            });
            for n in 0..HARMONICS {
                let expected = if n == 0 { exact } else { 0.0 };
                let z = (mean[n] - expected) / se[n];
                assert!(
                    z.abs() < 4.5,
                    "rho {rho}, r {}, n {n}: {} vs {expected} ± {}",
                    r[node],
                    mean[n],
                    se[n]
                );
                chi2 += z * z;
                count += 1;
            }
        }
    }
    // Batch means with 31 degrees of freedom: z² averages 31/29 ≈ 1.07
    assert!(chi2 < 1.5 * count as f64, "chi2 = {chi2} over {count}");
}

#[test]
fn harmonics_one_row_is_the_sum_over_its_walks_exits() {
    // One row walks at its own albedo: its estimates are the exits of `ExitWalk` with the same
    // streams, summed through the kernel written out in `kernel_average`'s terms.
    let (rho, g, eta, theta) = (0.8, 0.3, 1.4, 50f64.to_radians());
    let photons = harmonics::MIN_HARMONICS_PHOTONS + 100;
    let h = walk_harmonics(&[rho], g, 50.0, photons, 3);
    let r = harmonics_radii();
    let a = unreduced_albedo(rho, g);
    let s = 1.0 - g * a;
    let exits = ExitWalk::new(a, g, eta).unwrap();
    let mut sums = vec![[0.0; HARMONICS]; r.len()];
    for index in 0..photons {
        let mut rng = rng::photon_stream(3, index);
        exits.trace(theta, &mut rng, |e| {
            if e.component != Component::Multiple {
                return;
            }
            let x = e.x.hypot(e.y) * s;
            let phi = e.y.atan2(e.x);
            for (i, sum) in sums.iter_mut().enumerate().skip(1) {
                let k = e.weight * hat(&r, i, x.ln()) / (x * x);
                if k > 0.0 {
                    for (n, v) in sum.iter_mut().enumerate() {
                        *v += k * (n as f64 * phi).cos();
                    }
                }
            }
        });
    }
    for (i, sum) in sums.iter().enumerate() {
        let mean = h.mean(Component::Multiple, 0, i).unwrap();
        for n in 0..HARMONICS {
            let expected = sum[n] / photons as f64;
            let scale = sum[0].abs() / photons as f64 + 1e-300;
            assert!(
                (mean[n] - expected).abs() <= 1e-9 * scale,
                "r {}, n {n}: {} vs {expected}",
                r[i],
                mean[n]
            );
        }
    }
    assert_eq!(h.mean(Component::Multiple, 0, 0).unwrap(), [0.0; HARMONICS]);
}

#[test]
fn harmonics_rows_agree_with_walks_at_their_own_albedo() {
    // Reweighting one walk at the largest albedo against a walk at each row's own albedo
    // (different roulette, different seed): the multiple-scattering harmonics agree within
    // their standard errors at every node up to 10 mfp.
    let (g, theta_deg) = (0.5, 60.0);
    let rho = [0.4, 0.9, 0.99];
    let together = walk_harmonics(&rho, g, theta_deg, FAST_PHOTONS, 21);
    let r = harmonics_radii();
    let (mut chi2, mut count) = (0.0, 0);
    for (row, &one) in rho.iter().enumerate() {
        let alone = walk_harmonics(&[one], g, theta_deg, FAST_PHOTONS, 22);
        for node in (1..r.len()).filter(|&i| r[i] < 10.0) {
            let (m1, s1) = (
                together.mean(Component::Multiple, row, node).unwrap(),
                together.stderr(Component::Multiple, row, node).unwrap(),
            );
            let (m2, s2) = (
                alone.mean(Component::Multiple, 0, node).unwrap(),
                alone.stderr(Component::Multiple, 0, node).unwrap(),
            );
            for n in 0..HARMONICS {
                let z = (m1[n] - m2[n]) / s1[n].hypot(s2[n]);
                assert!(
                    z.abs() < 4.5,
                    "rho {one}, r {}, n {n}: {} ± {} vs {} ± {}",
                    r[node],
                    m1[n],
                    s1[n],
                    m2[n],
                    s2[n]
                );
                chi2 += z * z;
                count += 1;
            }
        }
    }
    assert!(chi2 < 1.5 * count as f64, "chi2 = {chi2} over {count}");
}

#[test]
fn harmonics_do_not_depend_on_the_thread_count() {
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| walk_harmonics(&[0.5, 0.9], 0.2, 30.0, 17 * BLOCK + 7, 4))
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn harmonics_refuse_what_they_cannot_walk() {
    let good = HarmonicsConfig {
        rho: vec![0.5],
        g: 0.0,
        eta: 1.33,
        theta: 0.3,
        r: vec![0.0, 1.0, 2.0],
        photons: harmonics::MIN_HARMONICS_PHOTONS,
        seed: 0,
    };
    assert!(good.validate().is_ok());
    let bad = |f: &dyn Fn(&mut HarmonicsConfig), says: &str| {
        let mut c = good.clone();
        f(&mut c);
        let message = c.validate().unwrap_err().to_string();
        assert!(message.contains(says), "{message}");
    };
    bad(&|c| c.rho.clear(), "rho rows = 0");
    bad(&|c| c.rho.push(1.5), "rho = 1.5");
    bad(&|c| c.g = 1.0, "g = 1");
    bad(&|c| c.eta = 3.0, "eta = 3");
    bad(&|c| (c.eta, c.theta) = (0.8, 1.2), "theta = 1.2");
    bad(
        &|c| c.r = vec![0.0, 2.0, 1.0],
        "r node = 2 must be below the next r node = 1",
    );
    bad(&|c| c.r = vec![-1.0, 2.0], "first r node = -1");
    bad(&|c| c.photons = 16 * BLOCK - 1, "photons = 16383");
    // At the critical angle itself, whose sine rounds one ulp above η for η = 0.8426
    let eta = 0.8426f64;
    assert!(eta.asin().sin() > eta);
    let critical = HarmonicsConfig {
        eta,
        theta: eta.asin(),
        ..good.clone()
    };
    assert!(critical.validate().is_ok());
    let h = harmonics(&good, &|_| {}).unwrap();
    assert!(h.mean(Component::Total, 0, 1).is_none());
    assert!(h.mean(Component::Multiple, 1, 1).is_none());
    assert!(h.mean(Component::Multiple, 0, 3).is_none());
}

/// At a tiny albedo every score carries the albedo and its square fell below f64's range
/// (albedo below about 1e-157): the standard errors came out 0, as if exact. The scores are
/// squared after scaling by a power of two; the same walk at albedo 1e-100 and 1e-200 scores
/// the same photons times the albedo (roulette ends each after its first vertex), so their relative
/// standard errors agree, and the bins' too.
#[test]
fn standard_errors_survive_a_tiny_albedo() {
    let relative = |albedo: f64| {
        let r = must_run(&half_space(albedo, 0.0, 1.33, 30.0, 2000, 5));
        let total = r.total_reflectance();
        assert!(total.value > 0.0, "albedo {albedo}: {total:?}");
        let bins = r.bins();
        let (_, b) = (0..bins.layout().radial_count())
            .flat_map(|i| (0..bins.layout().phi_count()).map(move |j| (i, j)))
            .filter_map(|(i, j)| {
                let v = bins.value(Component::Total, i, j)?;
                let s = bins.stderr(Component::Total, i, j)?;
                (v > 0.0).then_some((v, s / v))
            })
            .fold(
                (0.0, f64::INFINITY),
                |(v0, s0), (v, s)| if v > v0 { (v, s) } else { (v0, s0) },
            );
        (total.stderr / total.value, b)
    };
    let (reference, reference_bin) = relative(1e-100);
    for albedo in [1e-160, 1e-200, 1e-250] {
        let (rel, bin) = relative(albedo);
        assert!(rel > 0.0 && bin > 0.0, "albedo {albedo}: {rel} {bin}");
        assert!(
            (rel / reference - 1.0).abs() < 1e-3,
            "albedo {albedo}: {rel} against {reference}"
        );
        assert!(
            (bin / reference_bin - 1.0).abs() < 1e-3,
            "albedo {albedo}: {bin} against {reference_bin}"
        );
    }
}
