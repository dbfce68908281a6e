//! Tests of the General Wrapped Cauchy model: the wrapped Cauchy triad, the GWC profile's
//! evaluation, density, distribution and sampler.

use bssrdf_zoo::rng::{SeedableRng, UnitF64};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use bssrdf_testkit::gwc::{chi_square, integrate, SplitMix64, UniformRange};
use bssrdf_testkit::stats::chi2_critical_1e6;
use bssrdf_zoo::gwc::{cdf_wc, floor_bound, inv_cdf_wc, lobe_cap, pdf_wc, Gwc, C_LIMIT};
use bssrdf_zoo::Error;

/// Quadrature tolerance, and the tolerance quadrature results are held to.
const QUAD_TOL: f64 = 1e-11;
const QUAD_CHECK: f64 = 1e-9;
/// cdf(sample(u)) = u round trip.
const ROUND_TRIP_TOL: f64 = 1e-10;

/// Concentrations covering uniform, both peak directions and near-degenerate lobes.
const CS: [f64; 9] = [0.0, 0.3, -0.3, 0.7, -0.7, 0.95, 0.999, -0.999, 1e-6];

/// (α, β, c) sets for the profile tests: typical, α = 0, uniform (β = 0), very peaked,
/// backward, large α/β, tiny values, signed floors (α < 0) forward, backward and within 4e-6
/// of the bound −β(1 − |c|)/(2π(1 + |c|)) = −0.0856983 at c = 0.3, where f(π) is nearly 0.
const PARAMS: [(f64, f64, f64); 12] = [
    (0.1, 1.0, 0.5),
    (0.0, 1.0, 0.8),
    (1.0, 0.0, 0.0),
    (0.0, 1.0, 0.999),
    (1e-3, 1.0, 0.999),
    (0.05, 2.0, -0.8),
    (1e6, 1e-3, 0.9),
    (1e-3, 1e6, 0.3),
    (1e-300, 3e-300, 0.6),
    (-0.05, 1.0, 0.5),
    (-0.01, 1.0, -0.8),
    (-0.085698, 1.0, 0.3),
];

fn profiles() -> Vec<Gwc> {
    PARAMS
        .iter()
        .map(|&(a, b, c)| Gwc::new(a, b, c).unwrap())
        .collect()
}

/// The report's cdf_WC with tan(φ/2) (Ferrier 2016, §4.2), valid inside (−π, π).
fn paper_cdf_wc(phi: f64, c: f64) -> f64 {
    0.5 + ((1.0 + c) / (1.0 - c) * (0.5 * phi).tan()).atan() / PI
}

#[test]
fn wc_reference_values() {
    for c in CS {
        // Peak and trough: (1/2π)(1 ± c)/(1 ∓ c)
        let peak = (1.0 + c) / (TAU * (1.0 - c));
        let trough = (1.0 - c) / (TAU * (1.0 + c));
        assert!((pdf_wc(0.0, c) - peak).abs() <= 1e-14 * peak, "c = {c}");
        assert!((pdf_wc(PI, c) - trough).abs() <= 1e-12 * trough, "c = {c}");
        assert_eq!(cdf_wc(0.0, c), 0.5);
        assert_eq!(inv_cdf_wc(0.5, c), 0.0);
    }
    // c = 0 is uniform
    for phi in [-3.0, -1.0, 0.25, 2.0] {
        assert!((pdf_wc(phi, 0.0) - 1.0 / TAU).abs() < 1e-16);
        assert!((cdf_wc(phi, 0.0) - (phi + PI) / TAU).abs() < 1e-15);
    }
    // cdf_WC(π/2; 1/2) = 1/2 + arctan(3)/π
    assert!((cdf_wc(FRAC_PI_2, 0.5) - (0.5 + 3f64.atan() / PI)).abs() < 1e-15);
}

#[test]
fn wc_cdf_agrees_with_the_papers_tan_form_inside_the_domain() {
    let mut rng = SplitMix64::seed_from_u64(1);
    for _ in 0..10_000 {
        let c = rng.range(-0.99, 0.99);
        let phi = rng.range(-3.0, 3.0);
        let (ours, paper) = (cdf_wc(phi, c), paper_cdf_wc(phi, c));
        assert!((ours - paper).abs() < 1e-13, "phi = {phi}, c = {c}");
    }
}

#[test]
fn wc_negative_c_is_the_mirrored_lobe() {
    for c in [0.3, 0.9, 0.999] {
        for phi in [0.0, 0.4, 1.5, 2.9, PI] {
            let mirrored = pdf_wc(PI - phi, c);
            for p in [phi, -phi] {
                assert!((pdf_wc(p, -c) - mirrored).abs() <= 1e-12 * mirrored);
            }
        }
    }
}

#[test]
fn wc_pdf_integrates_to_its_cdf() {
    for c in CS {
        let pdf = |p: f64| pdf_wc(p, c);
        let total = integrate(&pdf, -PI, PI, QUAD_TOL);
        assert!((total - 1.0).abs() < QUAD_CHECK, "c = {c}: {total}");
        for phi in [-2.5, -0.3, 0.0, 0.01, 1.0, 3.0] {
            let partial = integrate(&pdf, -PI, phi, QUAD_TOL);
            assert!(
                (partial - cdf_wc(phi, c)).abs() < QUAD_CHECK,
                "c = {c}, φ = {phi}"
            );
        }
    }
}

#[test]
fn wc_cdf_is_exact_and_continuous_at_plus_minus_pi() {
    for c in CS.into_iter().chain([-0.999_999, 0.999_999]) {
        assert_eq!(cdf_wc(PI, c), 1.0);
        assert_eq!(cdf_wc(-PI, c), 0.0);
        // One-sided: the tail beyond π − δ is δ·pdf(π)(1 + O(δ²/(1 − |c|)²)). δ is taken as the
        // exact float distance to PI, which the cdf treats as π.
        let edge = pdf_wc(PI, c);
        for delta in [1e-9, 1e-12, 1e-15] {
            let phi = PI - delta;
            let d = PI - phi;
            let upper = 1.0 - cdf_wc(phi, c);
            let lower = cdf_wc(-phi, c);
            for tail in [upper, lower] {
                // 1e-5 relative covers the curvature; 3e-16 the rounding of 1 − cdf near 1
                assert!(
                    (tail - d * edge).abs() <= 1e-5 * d * edge + 3e-16,
                    "c = {c}"
                );
            }
        }
    }
    // Outside the domain and NaN
    assert_eq!(cdf_wc(4.0, 0.5), 1.0);
    assert_eq!(cdf_wc(-4.0, 0.5), 0.0);
    assert_eq!(cdf_wc(f64::NAN, 0.5), 0.0);
    assert_eq!(pdf_wc(3.2, 0.5), 0.0);
    assert_eq!(pdf_wc(f64::NAN, 0.5), 0.0);
}

#[test]
fn wc_inverse_cdf_round_trip() {
    let mut rng = SplitMix64::seed_from_u64(2);
    let edge_u = [0.0, 1e-300, 1e-16, 0.25, 0.5, 0.75, 1.0 - 1e-16, 1.0];
    for c in CS {
        assert_eq!(inv_cdf_wc(0.0, c), -PI);
        assert_eq!(inv_cdf_wc(1.0, c), PI);
        let us = edge_u.into_iter().chain((0..2000).map(|_| rng.next_f64()));
        for u in us {
            let phi = inv_cdf_wc(u, c);
            assert!(phi.abs() <= PI);
            // φ is rounded to ~4e-16 near ±π, where pdf_WC(π; −0.999) ≈ 318
            assert!((cdf_wc(phi, c) - u).abs() < 1e-12, "c = {c}, u = {u}");
        }
    }
}

#[test]
fn wc_clamps_c_and_u() {
    for c in [1.0, -1.0, 2.0, f64::NAN, f64::INFINITY] {
        for phi in [-PI, -1.0, 0.0, 2.0, PI] {
            assert!(pdf_wc(phi, c).is_finite() && cdf_wc(phi, c).is_finite());
        }
        assert!(inv_cdf_wc(0.3, c).is_finite());
    }
    assert_eq!(pdf_wc(1.0, 5.0), pdf_wc(1.0, C_LIMIT));
    assert_eq!(pdf_wc(1.0, f64::NAN), pdf_wc(1.0, 0.0));
    assert_eq!(inv_cdf_wc(-1.0, 0.5), -PI);
    assert_eq!(inv_cdf_wc(2.0, 0.5), PI);
    assert_eq!(inv_cdf_wc(f64::NAN, 0.5), -PI);
}

#[test]
fn new_rejects_invalid_parameters() {
    let not_finite = |name| Error::NotFinite {
        name,
        value: f64::NAN,
    };
    // NaN != NaN, so compare the variant and name through the message
    let message = |r: Result<Gwc, Error>| r.unwrap_err().to_string();
    assert_eq!(
        message(Gwc::new(f64::NAN, 1.0, 0.5)),
        not_finite("alpha").to_string()
    );
    assert_eq!(
        Gwc::new(1.0, -2.0, 0.5),
        Err(Error::Negative {
            name: "beta",
            value: -2.0
        })
    );
    assert!(matches!(
        Gwc::new(1.0, f64::INFINITY, 0.5),
        Err(Error::NotFinite { name: "beta", .. })
    ));
    for c in [1.0, -1.0, 1.5] {
        assert!(matches!(
            Gwc::new(1.0, 1.0, c),
            Err(Error::OutOfRange { name: "c", .. })
        ));
    }
    assert!(matches!(
        Gwc::new(1.0, 1.0, f64::NAN),
        Err(Error::NotFinite { name: "c", .. })
    ));
    // A floor below −β(1 − |c|)/(2π(1 + |c|)) would make the profile negative opposite the lobe
    // (−0.0531 for β = 1, c = ±0.5; 0 without a lobe)
    for (alpha, beta, c) in [(-0.054, 1.0, 0.5), (-0.054, 1.0, -0.5), (-1e-3, 0.0, 0.0)] {
        assert!(
            matches!(
                Gwc::new(alpha, beta, c),
                Err(Error::OutOfRange { name: "alpha", .. })
            ),
            "{alpha} {beta} {c}"
        );
    }
    let bound = floor_bound(1.0, 0.5);
    assert!((bound + 0.5 / (TAU * 1.5)).abs() < 1e-16);
    let at_bound = Gwc::new(bound, 1.0, 0.5).unwrap();
    assert!(at_bound.eval(PI) >= 0.0 && at_bound.eval(PI) < 1e-16);
    assert!(at_bound.pdf(PI) >= 0.0 && at_bound.pdf(PI) < 1e-16);
    assert!(matches!(
        Gwc::new(1e308, 1.0, 0.0),
        Err(Error::NotFinite {
            name: "2*pi*alpha + beta",
            ..
        })
    ));
    // The zero profile and the extremes of c are valid
    for c in [C_LIMIT, -C_LIMIT, 0.0] {
        assert!(Gwc::new(0.0, 0.0, c).is_ok());
    }
}

#[test]
fn from_table_recovers_consistent_cells_and_clamps_inconsistent_ones() {
    let r = 0.7;
    let g = Gwc::new(0.2, 1.5, 0.6).unwrap();
    let [e, beta, c] = g.table_cell(r);
    let back = Gwc::from_table(e, beta, c, r);
    assert!((back.alpha() - 0.2).abs() < 1e-15 && back.beta() == 1.5 && back.c() == 0.6);

    // β > E/r: a signed floor α = (E/r − β)/2π < 0, kept while the profile stays ≥ 0, that is
    // up to β = E/r·(1 + |c|)/(2|c|) = 3 here; beyond, β = 3 and f(π) = 0; energy kept
    let signed = Gwc::from_table(1.0, 2.5, 0.5, 0.5);
    assert_eq!((signed.beta(), signed.integral()), (2.5, 2.0));
    assert!((signed.alpha() + 0.5 / TAU).abs() < 1e-16);
    let over = Gwc::from_table(1.0, 4.0, 0.5, 0.5);
    assert_eq!((over.beta(), over.integral()), (3.0, 2.0));
    assert!(over.eval(PI) < 1e-16);
    assert_eq!(lobe_cap(2.0, 0.5), 3.0);
    // At c = 0 the split is immaterial (a uniform lobe): α ≥ 0 is kept
    assert_eq!(Gwc::from_table(1.0, 4.0, 0.0, 0.5).beta(), 2.0);
    // β < 0: β = 0, all energy in α
    let under = Gwc::from_table(1.0, -0.1, 0.5, 0.5);
    assert_eq!((under.beta(), under.integral()), (0.0, 2.0));
    // E < 0: the zero profile, sampled uniformly
    let zero = Gwc::from_table(-1e-9, 0.3, 0.5, 0.5);
    assert_eq!((zero.alpha(), zero.beta(), zero.eval(0.0)), (0.0, 0.0, 0.0));
    assert_eq!(zero.pdf(1.0), 1.0 / TAU);
    // c outside (−1, 1) or NaN
    assert_eq!(Gwc::from_table(1.0, 1.0, 1.2, 1.0).c(), C_LIMIT);
    assert_eq!(Gwc::from_table(1.0, 1.0, -3.0, 1.0).c(), -C_LIMIT);
    assert_eq!(Gwc::from_table(1.0, 1.0, f64::NAN, 1.0).c(), 0.0);
    // r = 0 row and non-finite E: α = 0, lobe alone
    let origin = Gwc::from_table(0.0, 0.4, 0.5, 0.0);
    assert_eq!((origin.alpha(), origin.beta()), (0.0, 0.4));
    assert_eq!(Gwc::from_table(f64::NAN, 0.4, 0.5, 1.0).alpha(), 0.0);
    assert_eq!(Gwc::from_table(1.0, f64::NAN, 0.5, 1.0).beta(), 0.0);

    // Whatever the cell, nothing is NaN
    let weird = [
        0.0,
        -1.0,
        1e-310,
        1e300,
        f64::NAN,
        f64::INFINITY,
        -f64::INFINITY,
    ];
    for e in weird {
        for b in weird {
            for c in [0.5, 1.0, -2.0, f64::NAN] {
                for r in [0.0, 1e-300, 1.0, -1.0, f64::NAN] {
                    let g = Gwc::from_table(e, b, c, r);
                    for phi in [-PI, -0.1, 0.0, 2.0, PI] {
                        assert!(!g.eval(phi).is_nan() && g.pdf(phi).is_finite());
                        assert!(g.cdf(phi).is_finite());
                    }
                    assert!(g.sample(0.3).abs() <= PI);
                }
            }
        }
    }
}

#[test]
fn pdf_integrates_to_one_and_eval_to_the_integral() {
    for g in profiles() {
        let total = integrate(&|p| g.pdf(p), -PI, PI, QUAD_TOL);
        assert!((total - 1.0).abs() < QUAD_CHECK, "{g:?}: {total}");
        let scale = g.integral();
        let energy = integrate(&|p| g.eval(p) / scale, -PI, PI, QUAD_TOL);
        assert!((energy - 1.0).abs() < QUAD_CHECK, "{g:?}: {energy}");
    }
}

#[test]
fn cdf_is_zero_one_monotone_and_integrates_the_pdf() {
    for g in profiles() {
        assert_eq!((g.cdf(-PI), g.cdf(PI)), (0.0, 1.0));
        let mut previous = 0.0;
        for i in 0..=20_000 {
            let phi = -PI + TAU * i as f64 / 20_000.0;
            let p = g.cdf(phi.min(PI));
            assert!(p >= previous, "{g:?} at φ = {phi}");
            previous = p;
        }
        for phi in [-3.0, -1.0, -1e-3, 0.0, 1e-3, 0.5, 2.5] {
            let partial = integrate(&|p| g.pdf(p), -PI, phi, QUAD_TOL);
            assert!(
                (partial - g.cdf(phi)).abs() < QUAD_CHECK,
                "{g:?} at φ = {phi}"
            );
        }
    }
}

#[test]
fn profile_is_even_and_zero_outside_the_domain() {
    let mut rng = SplitMix64::seed_from_u64(3);
    for g in profiles() {
        for _ in 0..1000 {
            let phi = rng.range(0.0, PI);
            assert_eq!(g.eval(phi), g.eval(-phi));
            assert_eq!(g.pdf(phi), g.pdf(-phi));
            assert!((g.cdf(phi) + g.cdf(-phi) - 1.0).abs() < 1e-15);
        }
        for phi in [3.2, -3.2, f64::INFINITY, f64::NAN] {
            assert_eq!((g.eval(phi), g.pdf(phi)), (0.0, 0.0));
        }
    }
}

#[test]
fn sample_round_trips_through_cdf() {
    let mut rng = SplitMix64::seed_from_u64(4);
    let extreme = [
        (1e-6, 1.0, 1.0 - 1e-9),
        (0.3, 1.0, -0.9999),
        (1e-12, 1.0, 0.5),
        (-0.000_799_7, 1.0, 0.99),
    ];
    let gs = profiles()
        .into_iter()
        .chain(extreme.map(|(a, b, c)| Gwc::new(a, b, c).unwrap()));
    for g in gs {
        assert_eq!((g.sample(0.0), g.sample(1.0)), (-PI, PI));
        let us = [1e-300, 1e-12, 0.5, 1.0 - 1e-12].into_iter();
        for u in us.chain((0..5000).map(|_| rng.next_f64())) {
            let phi = g.sample(u);
            assert!(phi.abs() <= PI);
            assert!((g.cdf(phi) - u).abs() < ROUND_TRIP_TOL, "{g:?}, u = {u}");
        }
        // Out-of-range and NaN u are clamped
        assert_eq!(g.sample(-0.5), g.sample(0.0));
        assert_eq!(g.sample(f64::NAN), g.sample(0.0));
        assert_eq!(g.sample(7.0), g.sample(1.0));
    }
}

#[test]
fn sample_agrees_with_bisection_on_the_papers_cdf() {
    // Reference: 200 bisection steps on the report's tan-form cdf, independent of the sampler
    let g = Gwc::new(0.1, 1.0, 0.7).unwrap();
    let lambda = TAU * 0.1 / (TAU * 0.1 + 1.0);
    let cdf = |p: f64| lambda * (p + PI) / TAU + (1.0 - lambda) * paper_cdf_wc(p, 0.7);
    for u in [0.01, 0.2, 0.5, 0.77, 0.999] {
        let (mut lo, mut hi) = (-PI + 1e-15, PI - 1e-15);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if cdf(mid) < u {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        assert!((g.sample(u) - lo).abs() < 1e-12, "u = {u}");
    }
}

#[test]
fn sample_matches_pdf_chi_square() {
    // Fixed seed. Threshold: Wilson–Hilferty χ² critical value at p = 1e-6, so each case would
    // fail by chance with probability 1e-6 (10 cases: 1e-5 overall). The last three have signed
    // floors (λ < 0), the last one touching 0 opposite its lobe.
    let cases = [
        (0.1, 1.0, 0.5),
        (0.0, 1.0, 0.999),
        (1e-3, 1.0, 0.999),
        (1.0, 0.0, 0.0),
        (0.0, 1.0, 0.0),
        (0.02, 1.0, -0.8),
        (0.05, 1.0, 0.9),
        (-0.05, 1.0, 0.5),
        (-0.015, 1.0, -0.8),
        (-0.085698, 1.0, 0.3),
    ];
    let mut rng = SplitMix64::seed_from_u64(0x5eed);
    for (a, b, c) in cases {
        let g = Gwc::new(a, b, c).unwrap();
        let (chi2, dof) = chi_square(g.c(), &|p| g.pdf(p), &mut || g.sample(rng.next_f64()));
        let critical = chi2_critical_1e6(dof);
        assert!(
            chi2 < critical,
            "(α, β, c) = {:?}: χ² = {chi2} ≥ {critical}",
            (a, b, c)
        );
    }
}

#[test]
fn chi_square_detects_a_slightly_wrong_sampler() {
    // The test above has power: sampling c = 0.53 or α 50 % too large against c = 0.5 fails
    let mut rng = SplitMix64::seed_from_u64(7);
    let g = Gwc::new(0.1, 1.0, 0.5).unwrap();
    for wrong in [Gwc::new(0.1, 1.0, 0.53), Gwc::new(0.15, 1.0, 0.5)] {
        let wrong = wrong.unwrap();
        let (chi2, dof) = chi_square(g.c(), &|p| g.pdf(p), &mut || wrong.sample(rng.next_f64()));
        assert!(chi2 > chi2_critical_1e6(dof), "χ² = {chi2}");
    }
}
