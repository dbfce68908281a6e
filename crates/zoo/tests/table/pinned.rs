//! Lookup outputs pinned at points of the coarse table (η = 1.33): faster lookup code must return
//! the same numbers. Evaluation and densities agree to f32-level rounding (the table stores f32
//! and blends it in f32); samples agree to the tolerance of their Newton solves.
//!
//! When a change to the bake or the lookups moves these values on purpose, recompute them and
//! say in the commit message which moved, by how much, and in which direction against the
//! reference PBD quadrature (`git log -p` on this file has every such step so far).

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{bake, AngularTable, Grid, GridPreset};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Relative tolerance on values and densities (f32 rounding of blended table values).
const VALUE_TOL: f64 = 1e-6;
/// Tolerance on sampled r (relative) and φ (radians): the solvers stop at 1e-12 in the segment
/// parameter and 1e-13 in u.
const SAMPLE_TOL: f64 = 1e-9;

fn coarse() -> &'static AngularTable {
    static TABLE: OnceLock<AngularTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        bake(
            1.33,
            Moments::Exact,
            &Grid::preset(GridPreset::Coarse),
            true,
        )
        .unwrap()
        .0
    })
}

fn close(got: f64, want: f64, tol: f64) -> bool {
    (got - want).abs() <= tol * want.abs()
}

/// (ρ′, θ, r, φ) → (eval, pdf, eval_perpendicular(ρ′, r)). Covers θ = 0, grazing θ, the first
/// radius interval (r₁ = 0.00337) and r = 0, the log-interpolated middle, underflowing tails
/// (0 and 1.4e-37), φ = π and a φ outside [−π, π].
const EVAL: [([f64; 4], f64, f64, f64); 11] = [
    (
        [0.95, 0.2, 20.0, 0.1],
        2.0071361687732495e-7,
        3.468106647631024e-7,
        1.840584084409079e-7,
    ),
    (
        [0.45, 1.3, 0.0041, -3.0],
        0.048152252202861553,
        1.742124512501232,
        0.08491134463576205,
    ),
    (
        [0.5, 0.0, 0.3, 0.0],
        0.011370394430231866,
        0.3729828537909979,
        0.011370394430231866,
    ),
    (
        [0.9, 0.7, 0.001, 0.4],
        0.5095399209292527,
        1.690525894692001,
        0.47584244498368905,
    ),
    (
        [0.99, 1.2, 2.5, -2.0],
        0.00478282088693954,
        0.007675032544153071,
        0.005875061695031078,
    ),
    ([0.3, 1.5, 40.0, 3.0], 0.0, 0.0, 0.0),
    (
        [0.999, 0.3, 0.05, PI],
        0.1717896887039719,
        0.20771659629736156,
        0.1989444275866481,
    ),
    (
        [0.7, 0.9, 150.0, 1.0],
        1.1788812499525473e-37,
        0.0,
        8.841293464553079e-38,
    ),
    (
        [0.62, 0.45, 0.0, 0.2],
        0.9951977333638535,
        0.0,
        1.0220776995128131,
    ),
    (
        [0.8, 1.0, 7.3, -0.7],
        1.7897734526333754e-5,
        0.0001285633588951047,
        1.1094925804060777e-5,
    ),
    (
        [0.15, 1.45, 0.012, 5.0],
        0.005258885849300546,
        2.0615287018145505,
        0.00680300492962874,
    ),
];

/// (ρ′, θ, u_r, u_φ) → ([r, φ, pdf] of sample, [r, pdf] of sample_perpendicular).
const SAMPLE: [([f64; 4], [f64; 3], [f64; 2]); 8] = [
    (
        [0.5, 0.0, 0.5, 0.5],
        [0.8336776046487868, 0.0, 0.09362189280418784],
        [0.8336776046487868, 0.09362189280418784],
    ),
    (
        [0.9, 0.7, 0.01, 0.99],
        [0.06938774425863489, 3.0523175121503527, 0.3684895548462156],
        [0.06576956483154968, 0.5760909073659416],
    ),
    (
        [0.99, 1.2, 0.999, 0.2],
        [
            27.479547965861713,
            -1.664981897150138,
            1.1937691119609385e-6,
        ],
        [28.051509453247178, 1.1969341221475716e-6],
    ),
    (
        [0.3, 1.5, 0.3, 0.7],
        [0.49633084114067066, 0.5461120060700828, 0.3902479086597404],
        [0.4328332522546523, 0.2669327164142876],
    ),
    (
        [0.999, 0.3, 0.75, 0.05],
        [
            7.2919331986323055,
            -2.800138174862544,
            0.0008098800422468029,
        ],
        [7.329248805802321, 0.0008686760185113894],
    ),
    (
        [0.7, 0.9, 1e-5, 0.5],
        [0.0011904465125142274, 0.0, 2.919517725530223],
        [0.0010641571118772133, 2.821615024336582],
    ),
    (
        [0.8, 1.0, 0.62, 0.999999],
        [1.5802492191612023, 3.1415813807016777, 0.01523020893644987],
        [1.5398264339940877, 0.02817917217178161],
    ),
    (
        [0.15, 1.45, 0.9, 0.31],
        [
            2.2045174896902298,
            -0.4769933303975884,
            0.016978982578232826,
        ],
        [2.0479441838735504, 0.009376024979682335],
    ),
];

/// (ρ′, u) → [θ, r, φ, φ′, pdf_θ, pdf] of sample_path.
const PATH: [(f64, [f64; 4], [f64; 6]); 3] = [
    (
        0.5,
        [0.1, 0.2, 0.3, 0.4],
        [
            0.17079849835098215,
            0.33581505872243056,
            -1.1398306644381864,
            -0.6283185307179586,
            0.5868761662791467,
            0.032240119408535335,
        ],
    ),
    (
        0.95,
        [0.8, 0.6, 0.9, 0.1],
        [
            1.2699094812732914,
            2.2744002600823436,
            2.146664657885819,
            -2.5132741228718345,
            0.6603995337744356,
            0.00094333566483047,
        ],
    ),
    (
        0.25,
        [0.55, 0.05, 0.45, 0.95],
        [
            0.9119178850689728,
            0.11476382314911589,
            -0.17520494811921475,
            2.827433388230814,
            0.6463431320770402,
            0.1615951595181257,
        ],
    ),
];

#[test]
fn eval_and_pdf_match_the_pinned_values() {
    let view = coarse().view();
    for ([rho, theta, r, phi], eval, pdf, perpendicular) in EVAL {
        let got = view.eval(rho, theta, r, phi).unwrap();
        assert!(
            close(got, eval, VALUE_TOL),
            "eval{:?}: {got:e} vs {eval:e}",
            (rho, theta, r, phi)
        );
        let got = view.pdf(rho, theta, r, phi);
        assert!(
            close(got, pdf, VALUE_TOL),
            "pdf{:?}: {got:e} vs {pdf:e}",
            (rho, theta, r, phi)
        );
        let got = view.eval_perpendicular(rho, r).unwrap();
        assert!(
            close(got, perpendicular, VALUE_TOL),
            "eval_perpendicular({rho}, {r}): {got:e} vs {perpendicular:e}"
        );
    }
}

#[test]
fn samples_match_the_pinned_values() {
    let view = coarse().view();
    for ([rho, theta, u_r, u_phi], [r, phi, pdf], [r_perp, pdf_perp]) in SAMPLE {
        let s = view.sample(rho, theta, u_r, u_phi).unwrap();
        let at = (rho, theta, u_r, u_phi);
        assert!(close(s.r, r, SAMPLE_TOL), "r{at:?}: {} vs {r}", s.r);
        assert!(
            (s.phi - phi).abs() <= SAMPLE_TOL,
            "phi{at:?}: {} vs {phi}",
            s.phi
        );
        assert!(
            close(s.pdf, pdf, VALUE_TOL),
            "pdf{at:?}: {} vs {pdf}",
            s.pdf
        );
        let p = view.sample_perpendicular(rho, u_r, u_phi).unwrap();
        assert!(
            close(p.r, r_perp, SAMPLE_TOL),
            "perpendicular r{at:?}: {} vs {r_perp}",
            p.r
        );
        assert!(close(p.pdf, pdf_perp, VALUE_TOL), "perpendicular pdf{at:?}");
    }
}

#[test]
fn path_samples_match_the_pinned_values() {
    let view = coarse().view();
    for (rho, u, [theta, r, phi, phi_prime, pdf_theta, pdf]) in PATH {
        let s = view.sample_path(rho, u).unwrap();
        let at = (rho, u);
        assert!(
            close(s.theta, theta, SAMPLE_TOL),
            "theta{at:?}: {} vs {theta}",
            s.theta
        );
        assert!(close(s.r, r, SAMPLE_TOL), "r{at:?}: {} vs {r}", s.r);
        assert!(
            (s.phi - phi).abs() <= SAMPLE_TOL,
            "phi{at:?}: {} vs {phi}",
            s.phi
        );
        assert_eq!(s.phi_prime, phi_prime, "phi'{at:?}");
        assert!(close(s.pdf_theta, pdf_theta, VALUE_TOL), "pdf_theta{at:?}");
        assert!(
            close(s.pdf, pdf, VALUE_TOL),
            "pdf{at:?}: {} vs {pdf}",
            s.pdf
        );
    }
}
