//! Tests of the three-anchor GWC fit: exactness on GWC and non-GWC profiles, the report's
//! misprinted β, every degenerate branch, and robustness on extreme inputs.

use bssrdf_zoo::rng::{RngCore, SeedableRng, UnitF64};
use std::f64::consts::{PI, TAU};

use bssrdf_testkit::gwc::{SplitMix64, UniformRange};
use bssrdf_zoo::gwc::{
    fit_anchors, fit_three_anchors, FitBranch, Gwc, GwcFit, ANCHOR_COS, C_MAX_FIT,
};
use bssrdf_zoo::Error;

/// Relative tolerance at anchors the fit must pass through.
const ANCHOR_TOL: f64 = 1e-12;

/// The anchor angles φ_i = arccos(ANCHOR_COS[i]).
fn anchor_phis() -> [f64; 3] {
    ANCHOR_COS.map(f64::acos)
}

/// Samples of `f` at the anchors.
fn at_anchors(f: impl Fn(f64) -> f64) -> [f64; 3] {
    anchor_phis().map(f)
}

fn fit(f: [f64; 3]) -> GwcFit {
    fit_three_anchors(f[0], f[1], f[2]).unwrap()
}

/// Relative error of the fitted profile at anchor i (absolute where the sample is 0).
fn anchor_error(g: &Gwc, f: [f64; 3], i: usize) -> f64 {
    let got = g.eval(anchor_phis()[i]);
    (got - f[i]).abs() / f[i].max(f64::MIN_POSITIVE)
}

fn assert_anchors(g: &Gwc, f: [f64; 3], which: &[usize]) {
    for &i in which {
        let err = anchor_error(g, f, i);
        assert!(
            err <= ANCHOR_TOL,
            "anchor {} of {f:?}: {err:e}, {g:?}",
            i + 1
        );
    }
}

/// The anchors a fit reproduces, by branch (module docs of `gwc`): all for exact fits, the
/// peak anchor p (the larger of 1 and 3) and 2 for `AlphaClamped`, 1 and 3 for `PeakClamped`,
/// p alone otherwise.
fn kept_anchors(fit: &GwcFit, f: [f64; 3]) -> Vec<usize> {
    let peak = if f[0] >= f[2] { 0 } else { 2 };
    match fit.branch {
        FitBranch::Exact | FitBranch::Uniform | FitBranch::Zero => vec![0, 1, 2],
        FitBranch::AlphaClamped => vec![peak, 1],
        FitBranch::PeakClamped => vec![0, 2],
        FitBranch::PeakAndAlphaClamped | FitBranch::NonMonotone => vec![peak],
    }
}

/// The fit's invariants: admissible parameters, nothing NaN anywhere.
fn assert_admissible(fit: &GwcFit) {
    let g = fit.gwc;
    assert!(
        g.alpha() >= 0.0 && g.beta() >= 0.0 && g.c().abs() <= C_MAX_FIT,
        "{fit:?}"
    );
    assert!(g.alpha().is_finite() && g.beta().is_finite());
    for phi in [-PI, -1.0, 0.0, 0.3, PI] {
        assert!(g.eval(phi) >= 0.0 && g.pdf(phi).is_finite() && g.cdf(phi).is_finite());
    }
    assert!(g.sample(0.37).abs() <= PI);
}

#[test]
fn fit_recovers_random_gwc_profiles() {
    let mut rng = SplitMix64::seed_from_u64(11);
    let mut exact = 0;
    for _ in 0..20_000 {
        let alpha = if rng.next_f64() < 0.25 {
            0.0
        } else {
            10f64.powf(rng.range(-3.0, 1.0))
        };
        let beta = 10f64.powf(rng.range(-2.0, 2.0));
        let c = rng.range(0.0, 0.99);
        let truth = Gwc::new(alpha, beta, c).unwrap();
        let f = at_anchors(|p| truth.eval(p));
        let fitted = fit(f);
        assert_admissible(&fitted);
        assert_anchors(&fitted.gwc, f, &[0, 1, 2]);
        // α = 0 sits on the boundary of the admissible set: rounding may clamp it
        let expected = [FitBranch::Exact, FitBranch::AlphaClamped];
        assert!(
            alpha == 0.0 || fitted.branch == FitBranch::Exact,
            "{fitted:?}"
        );
        assert!(expected.contains(&fitted.branch));
        // Parameters, where the anchors determine them well (a visible lobe)
        let lobe = beta / truth.integral();
        if fitted.branch == FitBranch::Exact && c > 0.05 && lobe > 1e-2 {
            let g = fitted.gwc;
            assert!((g.c() - c).abs() < 1e-9, "{g:?} vs {truth:?}");
            assert!((g.beta() - beta).abs() < 1e-9 * beta, "{g:?} vs {truth:?}");
            assert!((g.integral() - truth.integral()).abs() < 1e-9 * truth.integral());
            exact += 1;
        }
    }
    assert!(exact > 10_000);
}

#[test]
fn fit_recovers_backward_peaked_and_uniform_profiles() {
    for (alpha, beta, c) in [(0.2, 1.0, -0.6), (0.0, 1.0, -0.9), (0.5, 2.0, -0.2)] {
        let truth = Gwc::new(alpha, beta, c).unwrap();
        let f = at_anchors(|p| truth.eval(p));
        let fitted = fit(f);
        assert_anchors(&fitted.gwc, f, &[0, 1, 2]);
        assert!((fitted.gwc.c() - c).abs() < 1e-9, "{fitted:?}");
        assert!(fitted.gwc.c() < 0.0);
    }
    // c = 0 is flat: the constant goes to α
    let truth = Gwc::new(0.3, 2.0, 0.0).unwrap();
    let fitted = fit(at_anchors(|p| truth.eval(p)));
    assert_eq!(fitted.branch, FitBranch::Uniform);
    assert!((fitted.gwc.integral() - truth.integral()).abs() < 1e-15);
}

#[test]
fn fit_passes_anchors_of_smooth_non_gwc_profiles() {
    // Shapes unlike a GWC for which the exact branch is admissible
    let profiles: Vec<Box<dyn Fn(f64) -> f64>> = vec![
        Box::new(|p: f64| (1.2 - p.cos()).powf(-0.5)),
        Box::new(|p: f64| (4.0 - p.cos()).powf(-0.5)),
        Box::new(|p: f64| 3.0 + (0.5 * p.cos()).exp()),
        Box::new(|p: f64| 3.0 + (3.0 * p.cos()).exp()),
        Box::new(|p: f64| 2.0 + (2.0 * p.cos()).exp()),
        Box::new(|p: f64| 1e-7 * (1.0 + 0.5 * (0.5 * p).cos().powi(6))),
    ];
    for profile in profiles {
        let f = at_anchors(profile);
        let fitted = fit(f);
        assert_eq!(fitted.branch, FitBranch::Exact, "{f:?}");
        assert_anchors(&fitted.gwc, f, &[0, 1, 2]);
    }
}

#[test]
fn general_anchors_fit_and_validation() {
    let truth = Gwc::new(0.1, 1.0, 0.7).unwrap();
    let cos_phi = [1.0, 0.0, -1.0];
    let f = cos_phi.map(|x: f64| truth.eval(x.acos()));
    let fitted = fit_anchors(cos_phi, f).unwrap();
    assert_eq!(fitted.branch, FitBranch::Exact);
    assert!((fitted.gwc.c() - 0.7).abs() < 1e-12 && (fitted.gwc.alpha() - 0.1).abs() < 1e-12);

    for bad in [
        [0.9, 0.95, -0.5],
        [0.9, -0.5, -0.5],
        [0.0, -0.2, -0.5],
        [0.9, 0.5, 0.1],
        [1.1, 0.5, -0.5],
        [0.9, f64::NAN, -0.5],
    ] {
        let err = fit_anchors(bad, [1.0, 0.5, 0.2]).unwrap_err();
        assert!(
            matches!(err, Error::OutOfRange { .. } | Error::NotFinite { .. }),
            "{bad:?}: {err}"
        );
    }
}

/// The report's closed form (§3.3) as printed, returning (α, β, c).
fn paper_fit(f: [f64; 3], beta_bracket_anchor: usize) -> (f64, f64, f64) {
    let [x1, x2, x3] = ANCHOR_COS;
    let k = (x1 - x2) / (x2 - x3);
    let big_k = (f[0] - f[1]) / (f[1] - f[2]);
    let a = (big_k * x1 - k * x3) / (big_k - k);
    let b = (a * a - 1.0).sqrt();
    let c = a - b;
    let xj = ANCHOR_COS[beta_bracket_anchor];
    let beta = TAU * (f[0] - f[1]) / b / (1.0 / (a - x1) - 1.0 / (a - xj));
    let alpha = f[0] - beta * b / (TAU * (a - x1));
    (alpha, beta, c)
}

#[test]
fn paper_printed_beta_misses_the_anchors() {
    let truth = Gwc::new(0.2, 1.0, 0.6).unwrap();
    let f = at_anchors(|p| truth.eval(p));
    let anchor_errors = |(alpha, beta, c): (f64, f64, f64)| {
        let g = Gwc::new(alpha, beta, c).unwrap();
        [0, 1, 2].map(|i| anchor_error(&g, f, i))
    };
    // Printed: [1/(a − cos φ1) − 1/(a − cos φ3)]⁻¹ next to f1 − f2. α is fitted through anchor
    // 1, so that one passes, but β is off by the factor (x1 − x2)(a − x3)/((x1 − x3)(a − x2))
    let printed = paper_fit(f, 2);
    let errors = anchor_errors(printed);
    assert!(errors[0] <= ANCHOR_TOL);
    assert!(errors[1] > 1e-2 && errors[2] > 1e-2, "{errors:?}");
    assert!((printed.1 - 1.0).abs() > 0.1);
    // Corrected: the bracket pairs f1 − f2 with anchors 1 and 2
    let corrected = paper_fit(f, 1);
    assert!(anchor_errors(corrected).iter().all(|&e| e <= ANCHOR_TOL));
    assert!((corrected.1 - 1.0).abs() < 1e-12 && (corrected.2 - 0.6).abs() < 1e-12);
}

#[test]
fn paper_flat_choice_misses_anchors_when_only_f2_equals_f3() {
    // Report: f2 = f3 ⇒ c = 0, β = 2π·f1, α = 0, which is the constant f1
    let f = [1.0, 0.3, 0.3];
    let paper = Gwc::new(0.0, TAU * f[0], 0.0).unwrap();
    assert!(anchor_error(&paper, f, 0) <= ANCHOR_TOL);
    assert!(anchor_error(&paper, f, 1) > 1.0 && anchor_error(&paper, f, 2) > 1.0);
    // Ours keeps anchors 1 and 3 and comes within 6 % of (f1 − f3) at anchor 2
    let ours = fit(f);
    assert_eq!(ours.branch, FitBranch::PeakClamped);
    assert_eq!(ours.gwc.c(), C_MAX_FIT);
    assert_anchors(&ours.gwc, f, &[0, 2]);
    let miss = ours.gwc.eval(anchor_phis()[1]) - f[1];
    assert!(miss > 0.0 && miss < 0.06 * (f[0] - f[2]), "{miss}");
}

#[test]
fn degenerate_zero_and_flat() {
    for f in [[0.0; 3], [0.0, -0.0, 0.0]] {
        let zero = fit(f);
        assert_eq!(zero.branch, FitBranch::Zero);
        let g = zero.gwc;
        assert_eq!(
            (g.alpha(), g.beta(), g.c(), g.eval(0.3)),
            (0.0, 0.0, 0.0, 0.0)
        );
        assert_eq!(g.pdf(0.3), 1.0 / TAU);
    }
    for v in [2.5, 1e-310, 1e300] {
        let flat = fit([v; 3]);
        assert_eq!(flat.branch, FitBranch::Uniform);
        let g = flat.gwc;
        assert_eq!((g.alpha(), g.beta(), g.c()), (v, 0.0, 0.0));
        assert_eq!(g.eval(1.0), v);
    }
}

#[test]
fn degenerate_alpha_clamped() {
    // Cosine limit K = k (w → 0: β → ∞, α → −∞), von Mises, and a far tail at 0
    let cosine = at_anchors(|p| 2.0 + p.cos());
    let von_mises = at_anchors(|p| p.cos().exp());
    for f in [cosine, von_mises, [1.0, 0.5, 0.0]] {
        let fitted = fit(f);
        assert_eq!(fitted.branch, FitBranch::AlphaClamped, "{f:?}");
        assert_admissible(&fitted);
        assert_eq!(fitted.gwc.alpha(), 0.0);
        assert!(fitted.gwc.c() > 0.0);
        assert_anchors(&fitted.gwc, f, &[0, 1]);
        // The far anchor is overestimated, never underestimated
        assert!(fitted.gwc.eval(anchor_phis()[2]) > f[2]);
    }
    // Flat front f1 = f2 > f3: the constant f1, stored in β
    let flat_front = fit([1.0, 1.0, 0.4]);
    assert_eq!(flat_front.branch, FitBranch::AlphaClamped);
    let g = flat_front.gwc;
    assert_eq!((g.alpha(), g.c()), (0.0, 0.0));
    assert!((g.beta() - TAU).abs() < 1e-15);
}

#[test]
fn degenerate_peak_clamped_when_no_real_c() {
    // K = 0.94/0.01 = 94 > k·(1 − x3)/(1 − x1) ≈ 17.65: the report's a < 1, b = NaN
    let f = [1.0, 0.06, 0.05];
    assert!(paper_fit(f, 1).2.is_nan());
    let fitted = fit(f);
    assert_eq!(fitted.branch, FitBranch::PeakClamped);
    assert_eq!(fitted.gwc.c(), C_MAX_FIT);
    assert_admissible(&fitted);
    assert_anchors(&fitted.gwc, f, &[0, 2]);
    // Mirrored for a backward profile
    let back = fit([0.2, 0.21, 1.0]);
    assert_eq!(back.branch, FitBranch::PeakClamped);
    assert_eq!(back.gwc.c(), -C_MAX_FIT);
    assert_anchors(&back.gwc, [0.2, 0.21, 1.0], &[0, 2]);
}

#[test]
fn degenerate_peak_and_alpha_clamped_beyond_gwc_contrast() {
    // f1/f2 > 12.65 (even the α = 0 profile through anchors 1 and 2 needs c > C_MAX_FIT), or
    // f1/f3 > 37.2 with anchor 2 no help; subnormal samples alike
    for f in [[1.0, 0.05, 0.0], [1.0, 0.02, 0.01], [1e-310, 5e-312, 0.0]] {
        let fitted = fit(f);
        assert_eq!(fitted.branch, FitBranch::PeakAndAlphaClamped, "{f:?}");
        assert_admissible(&fitted);
        assert_eq!((fitted.gwc.alpha(), fitted.gwc.c()), (0.0, C_MAX_FIT));
        let tol = if f[0] < 1e-300 { 1e-4 } else { ANCHOR_TOL };
        assert!(anchor_error(&fitted.gwc, f, 0) < tol);
    }
    for f in [[0.0, 0.3, 2.0], [0.0, 0.05, 1.0]] {
        let back = fit(f);
        assert_eq!(back.branch, FitBranch::PeakAndAlphaClamped);
        assert_eq!(back.gwc.c(), -C_MAX_FIT);
        assert_anchors(&back.gwc, f, &[2]);
    }
}

#[test]
fn degenerate_backward_profiles() {
    // Monotone rising towards φ = π: c < 0 in every branch, anchors kept as documented
    let truth = Gwc::new(0.2, 1.0, -0.6).unwrap();
    let mut branches = Vec::new();
    for f in [
        at_anchors(|p| truth.eval(p)),
        [0.3, 0.5, 1.0],
        [0.5, 0.5, 1.0],
        [0.9, 0.95, 1.0],
        [0.2, 0.21, 1.0],
        [0.0, 0.1, 1.0],
    ] {
        let fitted = fit(f);
        assert_admissible(&fitted);
        assert!(fitted.gwc.c() < 0.0, "{fitted:?}");
        assert_anchors(&fitted.gwc, f, &kept_anchors(&fitted, f));
        branches.push(fitted.branch);
    }
    use FitBranch::*;
    let expected = [
        Exact,
        AlphaClamped,
        PeakClamped,
        AlphaClamped,
        PeakClamped,
        PeakAndAlphaClamped,
    ];
    assert_eq!(branches, expected);
}

#[test]
fn degenerate_non_monotone() {
    // f2 above both ends: the constant f_p; below both ends: c = C_MAX_FIT through 1 and 3
    let above = fit([1.0, 2.0, 0.5]);
    assert_eq!(above.branch, FitBranch::NonMonotone);
    assert_admissible(&above);
    assert_eq!((above.gwc.alpha(), above.gwc.c()), (0.0, 0.0));
    assert_anchors(&above.gwc, [1.0, 2.0, 0.5], &[0]);
    let below = fit([1.0, 0.1, 0.5]);
    assert_eq!(below.branch, FitBranch::NonMonotone);
    assert_eq!(below.gwc.c(), C_MAX_FIT);
    assert_anchors(&below.gwc, [1.0, 0.1, 0.5], &[0, 2]);
    // f1 = f3: a constant is all that is left
    let constants = [
        ([1.0, 0.2, 1.0], 1.0),
        ([0.0, 1.0, 0.0], 0.0),
        ([5e-324, 1e10, 0.0], 5e-324),
    ];
    for (f, constant) in constants {
        let fitted = fit(f);
        assert_eq!(fitted.branch, FitBranch::NonMonotone, "{f:?}");
        let g = fitted.gwc;
        assert_eq!((g.alpha(), g.beta(), g.c()), (constant, 0.0, 0.0));
    }
}

#[test]
fn invalid_samples_are_errors() {
    for (f, name) in [
        ([f64::NAN, 1.0, 1.0], "f1"),
        ([1.0, f64::INFINITY, 1.0], "f2"),
        ([1.0, 1.0, f64::NEG_INFINITY], "f3"),
    ] {
        let err = fit_three_anchors(f[0], f[1], f[2]).unwrap_err();
        assert!(
            matches!(err, Error::NotFinite { name: n, .. } if n == name),
            "{err}"
        );
    }
    assert_eq!(
        fit_three_anchors(1.0, -1e-30, 0.5),
        Err(Error::Negative {
            name: "f2",
            value: -1e-30
        })
    );
    // α or β overflowing f64 is reported, not returned as infinity
    assert!(fit_three_anchors(f64::MAX, f64::MAX / 2.0, f64::MAX / 4.0).is_err());
}

#[test]
fn fit_is_scale_invariant_from_subnormal_to_huge() {
    let truth = Gwc::new(0.1, 1.0, 0.6).unwrap();
    let base = at_anchors(|p| truth.eval(p));
    let reference = fit(base);
    assert_eq!(reference.branch, FitBranch::Exact);
    for scale in [1e-300, 1e-150, 1e150, 1e300] {
        let scaled = fit(base.map(|v| v * scale));
        assert_eq!(scaled.branch, reference.branch);
        let (g, r) = (scaled.gwc, reference.gwc);
        assert!((g.c() - r.c()).abs() < 1e-14);
        assert!((g.alpha() / scale - r.alpha()).abs() < 1e-13 * r.alpha());
        assert!((g.beta() / scale - r.beta()).abs() < 1e-13 * r.beta());
    }
    // Subnormal samples carry few bits, but the fit stays admissible and close
    let tiny = fit(base.map(|v| v * 1e-315));
    assert_admissible(&tiny);
    assert!((tiny.gwc.c() - reference.gwc.c()).abs() < 1e-3);
}

#[test]
fn fit_changes_continuously_across_branches() {
    // Sweep f2 from above f1 to below f3: NonMonotone → AlphaClamped → Exact → PeakClamped →
    // NonMonotone, with no jump in the fitted values at the anchors
    let (f1, f3) = (1.0, 0.1);
    let mut previous: Option<[f64; 3]> = None;
    let mut branches = Vec::new();
    for i in 0..=4000 {
        let f2 = 1.05 - 1.0 * i as f64 / 4000.0;
        let fitted = fit([f1, f2, f3]);
        if branches.last() != Some(&fitted.branch) {
            branches.push(fitted.branch);
        }
        let values = anchor_phis().map(|p| fitted.gwc.eval(p));
        if let Some(prev) = previous {
            for (v, p) in values.iter().zip(prev) {
                assert!(
                    (v - p).abs() < 1e-3,
                    "jump at f2 = {f2}: {values:?} vs {prev:?}"
                );
            }
        }
        previous = Some(values);
    }
    use FitBranch::*;
    let expected = [NonMonotone, AlphaClamped, Exact, PeakClamped, NonMonotone];
    assert_eq!(branches, expected);
}

#[test]
fn fit_never_returns_nan_on_extreme_triples() {
    let specials = [
        0.0,
        5e-324,
        1e-310,
        1e-300,
        1e-10,
        0.3,
        0.5,
        1.0,
        1.0 + 1e-15,
        1e10,
        1e300,
    ];
    let mut checked = 0;
    for &a in &specials {
        for &b in &specials {
            for &c in &specials {
                let fitted = fit([a, b, c]);
                assert_admissible(&fitted);
                checked += 1;
            }
        }
    }
    // Random triples over 600 orders of magnitude, with ties
    let mut rng = SplitMix64::seed_from_u64(12);
    for _ in 0..100_000 {
        let mut f = [0.0; 3];
        for v in f.iter_mut() {
            *v = match rng.next_u64() % 4 {
                0 => 0.0,
                1 => 10f64.powf(rng.range(-300.0, 300.0)),
                _ => rng.next_f64(),
            };
        }
        if rng.next_u64() % 8 == 0 {
            f[1] = f[2];
        }
        let fitted = fit(f);
        assert_admissible(&fitted);
        // Every branch keeps its documented anchors (to full precision while no sample is
        // subnormal relative to the largest, which the fit divides by)
        let max = f[0].max(f[1]).max(f[2]);
        if f.iter().all(|&v| v == 0.0 || v > 1e-300 * max) {
            assert_anchors(&fitted.gwc, f, &kept_anchors(&fitted, f));
        }
        checked += 1;
    }
    assert!(checked > 100_000);
}
