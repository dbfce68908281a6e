//! Lookup outputs pinned at points of the coarse table (η = 1.33), as computed at commit c3470ca,
//! before the lookup speed work: faster code must return the same numbers. Evaluation and
//! densities agree to f32-level rounding (the table stores f32 and blends it in f32); samples
//! agree to the tolerance of their Newton solves.

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
        2.0087338591188028e-7,
        3.4686793201633656e-7,
        1.8405955329234584e-7,
    ),
    (
        [0.45, 1.3, 0.0041, -3.0],
        0.04804649325228068,
        1.7301202890077614,
        0.08534226680409694,
    ),
    (
        [0.5, 0.0, 0.3, 0.0],
        0.01136585984252592,
        0.37293287804272235,
        0.01136585984252592,
    ),
    (
        [0.9, 0.7, 0.001, 0.4],
        0.508543897193107,
        1.6849781536409592,
        0.47669147497885195,
    ),
    (
        [0.99, 1.2, 2.5, -2.0],
        0.004780929499273762,
        0.007670522573080045,
        0.005875060416934398,
    ),
    ([0.3, 1.5, 40.0, 3.0], 0.0, 0.0, 0.0),
    (
        [0.999, 0.3, 0.05, PI],
        0.17179239933166582,
        0.20771951563138652,
        0.19894437861326247,
    ),
    (
        [0.7, 0.9, 150.0, 1.0],
        1.4481256098924307e-37,
        0.0,
        1.087716529874866e-37,
    ),
    (
        [0.62, 0.45, 0.0, 0.2],
        0.994804429933394,
        0.0,
        1.022683858173491,
    ),
    (
        [0.8, 1.0, 7.3, -0.7],
        1.7896446976222117e-5,
        0.00012854125685026954,
        1.1092696319693974e-5,
    ),
    (
        [0.15, 1.45, 0.012, 5.0],
        0.005300076827377165,
        2.071893567535981,
        0.006807640979326277,
    ),
];

/// (ρ′, θ, u_r, u_φ) → ([r, φ, pdf_area] of sample, [r, pdf_area] of sample_perpendicular).
const SAMPLE: [([f64; 4], [f64; 3], [f64; 2]); 8] = [
    (
        [0.5, 0.0, 0.5, 0.5],
        [0.8337980557249496, 0.0, 0.0935923323217691],
        [0.8337980557249496, 0.09359233232176911],
    ),
    (
        [0.9, 0.7, 0.01, 0.99],
        [0.06938755157307668, 3.052339410428271, 0.36858206173018254],
        [0.06576924312705112, 0.5760965766288209],
    ),
    (
        [0.99, 1.2, 0.999, 0.2],
        [
            27.477504250627483,
            -1.6649894009830914,
            1.193743336143496e-6,
        ],
        [28.051514054033486, 1.1969331545345808e-6],
    ),
    (
        [0.3, 1.5, 0.3, 0.7],
        [0.49659242281907146, 0.5483395361097926, 0.3881823905633047],
        [0.4331315788445702, 0.2665516813847352],
    ),
    (
        [0.999, 0.3, 0.75, 0.05],
        [
            7.291931930516197,
            -2.8001440457755495,
            0.0008098937977281396,
        ],
        [7.329248994071933, 0.0008686759622137413],
    ),
    (
        [0.7, 0.9, 1e-5, 0.5],
        [0.0011904761730739354, 0.0, 2.907924898081979],
        [0.0010641656303242055, 2.821569864705269],
    ),
    (
        [0.8, 1.0, 0.62, 0.999999],
        [1.5802469630017506, 3.1415813841728535, 0.015235237465603724],
        [1.5398135765678058, 0.028180145698761348],
    ),
    (
        [0.15, 1.45, 0.9, 0.31],
        [
            2.203779796632425,
            -0.47195781737587833,
            0.017168531916031984,
        ],
        [2.047562199612881, 0.00937950766953901],
    ),
];

/// (ρ′, u) → [θ, r, φ, φ′, pdf_θ, pdf] of sample_path.
const PATH: [(f64, [f64; 4], [f64; 6]); 3] = [
    (
        0.5,
        [0.1, 0.2, 0.3, 0.4],
        [
            0.17078054756890618,
            0.33591336914733766,
            -1.1388532235629543,
            -0.6283185307179586,
            0.5870044689292494,
            0.03224501738398956,
        ],
    ),
    (
        0.95,
        [0.8, 0.6, 0.9, 0.1],
        [
            1.2697922595566407,
            2.2742553160741323,
            2.145724537480849,
            -2.5132741228718345,
            0.6606195244807008,
            0.0009433180408750931,
        ],
    ),
    (
        0.25,
        [0.55, 0.05, 0.45, 0.95],
        [
            0.9121299963863122,
            0.1150353092008971,
            -0.17309838717225348,
            2.827433388230814,
            0.6475123003743923,
            0.16300345369684122,
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
    for ([rho, theta, u_r, u_phi], [r, phi, pdf_area], [r_perp, pdf_perp]) in SAMPLE {
        let s = view.sample(rho, theta, u_r, u_phi).unwrap();
        let at = (rho, theta, u_r, u_phi);
        assert!(close(s.r, r, SAMPLE_TOL), "r{at:?}: {} vs {r}", s.r);
        assert!(
            (s.phi - phi).abs() <= SAMPLE_TOL,
            "phi{at:?}: {} vs {phi}",
            s.phi
        );
        assert!(
            close(s.pdf_area, pdf_area, VALUE_TOL),
            "pdf{at:?}: {} vs {pdf_area}",
            s.pdf_area
        );
        let p = view.sample_perpendicular(rho, u_r, u_phi).unwrap();
        assert!(
            close(p.r, r_perp, SAMPLE_TOL),
            "perpendicular r{at:?}: {} vs {r_perp}",
            p.r
        );
        assert!(
            close(p.pdf_area, pdf_perp, VALUE_TOL),
            "perpendicular pdf{at:?}"
        );
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
