//! Tests of the minimax refinement of a GWC fit (`gwc::refine_minimax`): it levels the error
//! on photon beam diffusion as designed, recovers GWC profiles, is never worse than its start
//! at the samples, and falls back cleanly, without NaN, on degenerate inputs.

use bssrdf_zoo::rng::{RngCore, SeedableRng};
use std::f64::consts::PI;

use bssrdf_testkit::gwc::{SplitMix64, UniformRange};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::gwc::{
    fit_three_anchors, floor_bound, refine_minimax, FitBranch, Gwc, MinimaxFit, ANCHOR_COS,
    C_MAX_FIT, MINIMAX_MAX_SAMPLES,
};
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::Error;

/// The seven azimuths the bake refines over: the anchors and 0, 38°, 96°, π.
fn seven_azimuths() -> [f64; 7] {
    let a = ANCHOR_COS.map(f64::acos);
    let deg = PI / 180.0;
    [0.0, a[0], 38.0 * deg, a[1], 96.0 * deg, a[2], PI]
}

fn three_anchor_fit(f: impl Fn(f64) -> f64) -> Gwc {
    let s = ANCHOR_COS.map(|x| f(x.acos()));
    fit_three_anchors(s[0], s[1], s[2]).unwrap().gwc
}

fn rel_errors(g: &Gwc, phi: &[f64], f: &[f64]) -> Vec<f64> {
    phi.iter()
        .zip(f)
        .map(|(&p, &v)| g.eval(p) / v - 1.0)
        .collect()
}

/// Largest relative error of `g` against `f` on 721 azimuths over [0, π].
fn dense_max_error(g: &Gwc, f: impl Fn(f64) -> f64) -> f64 {
    (0..=720)
        .map(|i| PI * i as f64 / 720.0)
        .map(|p| (g.eval(p) / f(p) - 1.0).abs())
        .fold(0.0, f64::max)
}

/// The result's invariants: admissible (a floor no lower than −β·min pdf_WC, so ≥ 0 at every
/// φ), finite, the reported error recomputed, never worse than the start and strictly better
/// when refined.
fn assert_sound(m: &MinimaxFit, start: &Gwc, phi: &[f64], f: &[f64]) {
    let g = m.gwc;
    assert!(
        g.alpha() >= floor_bound(g.beta(), g.c()) && g.beta() >= 0.0 && g.c().abs() <= C_MAX_FIT,
        "{m:?}"
    );
    assert!(g.eval(0.0) >= 0.0 && g.eval(PI) >= 0.0, "{m:?}");
    assert!(g.alpha().is_finite() && g.beta().is_finite() && g.integral().is_finite());
    assert!(!m.max_rel_error.is_nan() && !m.start_max_rel_error.is_nan());
    assert!(m.max_rel_error <= m.start_max_rel_error, "{m:?}");
    if m.refined {
        assert!(m.max_rel_error < m.start_max_rel_error, "{m:?}");
        let worst = rel_errors(&g, phi, f)
            .iter()
            .fold(0.0f64, |a, e| a.max(e.abs()));
        assert_eq!(worst, m.max_rel_error);
    } else {
        assert_eq!(m.gwc, *start);
    }
}

#[test]
fn levels_the_error_of_pbd_at_grazing_incidence() {
    // (ρ′, θ, r) = (0.99, 89°, 1.4): where the three-anchor fit is worst at (0.99, 89°)
    // (1.13 % at φ ≈ 39°); the best GWC over all φ reaches 0.998 % there (dense minimax).
    let boundary = Boundary::new(1.33, Moments::Exact).unwrap();
    let pbd = Pbd::new(0.99, boundary).unwrap();
    let f = |phi: f64| pbd.eval(89f64.to_radians(), 1.4, phi, Rule::Fast);
    let start = three_anchor_fit(f);
    let phi = seven_azimuths();
    let samples = phi.map(f);
    let m = refine_minimax(&start, &phi, &samples).unwrap();
    assert_sound(&m, &start, &phi, &samples);
    assert!(m.refined);

    // Levelled on the four extremes 0, 38°, 96°, π with alternating signs; the anchors lie
    // inside the band
    let e = rel_errors(&m.gwc, &phi, &samples);
    let level = m.max_rel_error;
    for (k, &i) in [0, 2, 4, 6].iter().enumerate() {
        let sign = if k % 2 == 0 { -1.0 } else { 1.0 };
        assert!((e[i] - sign * level).abs() < 1e-6 * level, "{e:?}");
    }
    for i in [1, 3, 5] {
        assert!(e[i].abs() < level);
    }

    // Over all φ: the three-anchor fit exceeds 1 %, the refinement stays below it
    let (before, after) = (dense_max_error(&start, f), dense_max_error(&m.gwc, f));
    assert!(before > 0.0113, "{before}");
    assert!(after < 0.00999, "{after}");
}

#[test]
fn recovers_a_gwc_from_a_wrong_start() {
    let mut rng = SplitMix64::seed_from_u64(3);
    let phi = seven_azimuths();
    for _ in 0..200 {
        let truth = Gwc::new(
            rng.range(0.0, 0.5),
            rng.range(0.1, 5.0),
            rng.range(-0.9, 0.9),
        )
        .unwrap();
        let samples = phi.map(|p| truth.eval(p));
        // A start off in every parameter, c by up to 0.03
        let start = Gwc::new(
            1.1 * truth.alpha(),
            0.9 * truth.beta(),
            (truth.c() + rng.range(-0.03, 0.03)).clamp(-C_MAX_FIT, C_MAX_FIT),
        )
        .unwrap();
        let m = refine_minimax(&start, &phi, &samples).unwrap();
        assert_sound(&m, &start, &phi, &samples);
        assert!(m.refined && m.max_rel_error < 1e-7, "{truth:?}: {m:?}");
        assert!((m.gwc.c() - truth.c()).abs() < 1e-6, "{truth:?}: {m:?}");
    }
}

#[test]
fn an_exact_start_is_kept() {
    // The three-anchor fit of a GWC passes through every sample already: nothing to lower
    let truth = Gwc::new(0.05, 1.3, 0.4).unwrap();
    let start = three_anchor_fit(|p| truth.eval(p));
    let phi = seven_azimuths();
    let samples = phi.map(|p| truth.eval(p));
    let m = refine_minimax(&start, &phi, &samples).unwrap();
    assert_sound(&m, &start, &phi, &samples);
    assert!(m.max_rel_error < 1e-12, "{m:?}");
}

#[test]
fn never_worse_than_the_start_at_its_samples() {
    let mut rng = SplitMix64::seed_from_u64(17);
    let mut refined = 0;
    for case in 0..2_000 {
        // Smooth non-GWC profiles: a GWC times a low-order cosine series, von Mises, or
        // arbitrary positive values (not even monotone)
        let kind = case % 3;
        let g = Gwc::new(
            rng.range(0.0, 0.3),
            rng.range(0.0, 3.0),
            rng.range(-0.95, 0.95),
        )
        .unwrap();
        let (a2, a3, kappa) = (
            rng.range(-0.1, 0.1),
            rng.range(-0.05, 0.05),
            rng.range(-4.0, 4.0),
        );
        let n = 4 + (rng.next_u64() % (MINIMAX_MAX_SAMPLES as u64 - 3)) as usize;
        let mut phi: Vec<f64> = (0..n).map(|_| rng.range(0.0, PI)).collect();
        phi.sort_by(f64::total_cmp);
        phi.dedup();
        let random: Vec<f64> = (0..phi.len()).map(|_| rng.range(0.01, 1.0)).collect();
        let f = |i: usize, p: f64| match kind {
            0 => g.eval(p) * (1.0 + a2 * (2.0 * p).cos() + a3 * (3.0 * p).cos()) + 1e-3,
            1 => (kappa * p.cos()).exp(),
            _ => random[i],
        };
        let samples: Vec<f64> = phi.iter().enumerate().map(|(i, &p)| f(i, p)).collect();
        let start = match kind {
            0 => three_anchor_fit(|p| f(0, p)),
            1 => three_anchor_fit(|p| f(0, p)),
            _ => Gwc::new(
                rng.range(0.0, 0.5),
                rng.range(0.0, 2.0),
                rng.range(-0.9, 0.9),
            )
            .unwrap(),
        };
        let m = refine_minimax(&start, &phi, &samples).unwrap();
        assert_sound(&m, &start, &phi, &samples);
        refined += usize::from(m.refined);
    }
    // Most starts are improved upon
    assert!(refined > 1_500, "{refined}");
}

#[test]
fn profiles_flatter_than_a_lobe_refine_to_a_signed_floor() {
    // von Mises e^(cos φ/2) needs α < 0: the three-anchor fit clamps α = 0 through anchors 1
    // and 2 (25 % off at φ = π); the refinement takes a signed floor (a lobe less a constant,
    // still ≥ 0), 0.77 % off at the samples, and levels the error on at least three of them
    let f = |p: f64| (0.5 * p.cos()).exp();
    let s = ANCHOR_COS.map(|x| f(x.acos()));
    let fit = fit_three_anchors(s[0], s[1], s[2]).unwrap();
    assert_eq!(fit.branch, FitBranch::AlphaClamped);
    let phi = seven_azimuths();
    let samples = phi.map(f);
    let m = refine_minimax(&fit.gwc, &phi, &samples).unwrap();
    assert_sound(&m, &fit.gwc, &phi, &samples);
    assert!(m.refined && m.gwc.alpha() < 0.0, "{m:?}");
    assert!(m.max_rel_error < 0.01, "{m:?}");
    let dense = dense_max_error(&m.gwc, f);
    assert!(dense < 0.012, "{dense}");
    let at_level = rel_errors(&m.gwc, &phi, &samples)
        .iter()
        .filter(|e| (e.abs() - m.max_rel_error).abs() < 1e-6 * m.max_rel_error)
        .count();
    assert!(at_level >= 3, "{m:?}");
}

#[test]
fn backward_peaked_profiles_refine_to_a_backward_lobe() {
    // The mirror image of the grazing PBD case: the refinement of the mirrored samples is the
    // mirrored refinement
    let boundary = Boundary::new(1.33, Moments::Exact).unwrap();
    let pbd = Pbd::new(0.9, boundary).unwrap();
    let forward = |p: f64| pbd.eval(80f64.to_radians(), 0.02, p, Rule::Fast);
    let backward = |p: f64| forward(PI - p);
    let phi = seven_azimuths();
    let mirrored: Vec<f64> = phi.iter().rev().map(|p| PI - p).collect();
    let fwd = refine_minimax(&three_anchor_fit(forward), &phi, &phi.map(forward)).unwrap();
    let samples: Vec<f64> = mirrored.iter().map(|&p| backward(p)).collect();
    let s = three_anchor_fit(forward);
    let start = Gwc::new(s.alpha(), s.beta(), -s.c()).unwrap();
    let bwd = refine_minimax(&start, &mirrored, &samples).unwrap();
    assert_sound(&bwd, &start, &mirrored, &samples);
    assert!(fwd.refined && bwd.refined);
    assert!((bwd.gwc.c() + fwd.gwc.c()).abs() < 1e-6, "{fwd:?} {bwd:?}");
    assert!((bwd.max_rel_error - fwd.max_rel_error).abs() < 1e-6 * fwd.max_rel_error);
}

#[test]
fn degenerate_inputs_keep_the_start_without_nan() {
    let start = Gwc::new(0.1, 1.0, 0.3).unwrap();
    let phi = seven_azimuths();
    let smooth = phi.map(|p| 0.2 + (p.cos()).exp());
    let keep = |phi: &[f64], f: &[f64]| {
        let m = refine_minimax(&start, phi, f).unwrap();
        assert_sound(&m, &start, phi, f);
        assert!(!m.refined, "{phi:?} {f:?}: {m:?}");
        m
    };
    // Fewer than four samples: three parameters interpolate them
    keep(&phi[..3], &smooth[..3]);
    keep(&phi[..1], &smooth[..1]);
    // A sample that underflowed to 0: relative error undefined there (and infinite for the
    // start, which is positive)
    let mut with_zero = smooth;
    with_zero[6] = 0.0;
    assert_eq!(keep(&phi, &with_zero).max_rel_error, f64::INFINITY);
    let zeros = [0.0; 7];
    keep(&phi, &zeros);
    // The zero profile as a start against zero samples: error 0
    let zero = Gwc::new(0.0, 0.0, 0.0).unwrap();
    let m = refine_minimax(&zero, &phi, &zeros).unwrap();
    assert!(!m.refined && m.max_rel_error == 0.0);
    // A flat profile and a flat start: already exact
    let flat = Gwc::new(0.7, 0.0, 0.0).unwrap();
    let m = refine_minimax(&flat, &phi, &[0.7; 7]).unwrap();
    assert!(!m.refined && m.max_rel_error == 0.0);
}

#[test]
fn refinement_is_scale_invariant_from_subnormal_to_huge() {
    let f = |p: f64| 0.05 + (1.5 * p.cos()).exp();
    let phi = seven_azimuths();
    let base = phi.map(f);
    let start = three_anchor_fit(f);
    let reference = refine_minimax(&start, &phi, &base).unwrap();
    assert!(reference.refined);
    for scale in [1e-300, 1e-30, 1e30, 1e300] {
        let samples = base.map(|v| v * scale);
        let scaled_start =
            Gwc::new(start.alpha() * scale, start.beta() * scale, start.c()).unwrap();
        let m = refine_minimax(&scaled_start, &phi, &samples).unwrap();
        assert_sound(&m, &scaled_start, &phi, &samples);
        assert!(m.refined, "{scale}");
        assert!(
            (m.gwc.c() - reference.gwc.c()).abs() < 1e-7,
            "{scale}: {m:?}"
        );
        assert!(
            (m.max_rel_error - reference.max_rel_error).abs() < 1e-9,
            "{scale}"
        );
    }
    // Subnormal samples carry few bits: still admissible, still never worse than the start
    let samples = base.map(|v| v * 1e-315);
    let tiny_start = Gwc::new(start.alpha() * 1e-315, start.beta() * 1e-315, start.c()).unwrap();
    let m = refine_minimax(&tiny_start, &phi, &samples).unwrap();
    assert_sound(&m, &tiny_start, &phi, &samples);
}

#[test]
fn invalid_inputs_are_errors_naming_them() {
    let start = Gwc::new(0.1, 1.0, 0.3).unwrap();
    let phi = seven_azimuths();
    let f = [1.0; 7];
    let err = |phi: &[f64], f: &[f64]| refine_minimax(&start, phi, f).unwrap_err();
    assert!(matches!(err(&[], &[]), Error::CountOutOfRange { .. }));
    let many = [0.5; MINIMAX_MAX_SAMPLES + 1];
    assert!(matches!(err(&many, &many), Error::CountOutOfRange { .. }));
    assert!(matches!(err(&phi, &f[..6]), Error::Mismatch { .. }));
    for bad in [f64::NAN, f64::INFINITY, -1.0] {
        let mut g = f;
        g[3] = bad;
        let e = err(&phi, &g);
        assert!(
            matches!(
                e,
                Error::NotFinite { name: "f", .. } | Error::Negative { name: "f", .. }
            ),
            "{e:?}"
        );
    }
    for bad in [-0.1, PI + 1e-9, f64::NAN] {
        let mut p = phi;
        p[0] = bad;
        let e = err(&p, &f);
        assert!(
            matches!(
                e,
                Error::OutOfRange { name: "phi", .. } | Error::NotFinite { name: "phi", .. }
            ),
            "{e:?}"
        );
    }
    let mut repeated = phi;
    repeated[2] = repeated[1];
    assert!(matches!(
        err(&repeated, &f),
        Error::EdgesNotIncreasing { .. }
    ));
    let mut reversed = phi;
    reversed.reverse();
    assert!(matches!(
        err(&reversed, &f),
        Error::EdgesNotIncreasing { .. }
    ));
}
