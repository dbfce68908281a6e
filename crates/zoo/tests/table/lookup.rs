//! The angular table model: bake determinism, what the bake stores, sampling against pdf
//! (chi-square), normalisation, the report's accuracy protocol and its figure 9 (fast forms),
//! stability at the extremes, world units.

use bssrdf_testkit::stats::chi2_critical_1e6;
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::gwc::{fit_three_anchors, FitBranch, Gwc, ANCHOR_COS};
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::quadrature::{adaptive, GaussLegendre};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{
    bake, node_cell, validate, AngularTable, Grid, GridPreset, World, ONE_LOBE_ABOVE_COS,
    REPORT_TABLE_2,
};
use std::f64::consts::{PI, TAU};
use std::sync::OnceLock;

/// The default grid at η = 1.33, baked once for the whole file.
pub(crate) fn default_table() -> &'static AngularTable {
    static TABLE: OnceLock<AngularTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        bake(
            1.33,
            Moments::Exact,
            &Grid::preset(GridPreset::Default),
            true,
        )
        .unwrap()
        .0
    })
}

/// The default grid at η = 1.2, where tables have two lobes (`table::Lobes::for_eta`), baked
/// once for the whole file.
pub(crate) fn two_lobe_table() -> &'static AngularTable {
    static TABLE: OnceLock<AngularTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        let table = bake(
            1.2,
            Moments::Exact,
            &Grid::preset(GridPreset::Default),
            true,
        )
        .unwrap()
        .0;
        assert!(table.harmonics().is_some());
        table
    })
}

/// Both kinds of table: one lobe (η = 1.33) and two (η = 1.2).
fn both_tables() -> [&'static AngularTable; 2] {
    [default_table(), two_lobe_table()]
}

/// The crate's pinned random stream, under the name these tests use.
struct Rng(SplitMix64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0.next_f64()
    }
}

#[test]
fn bake_is_bit_identical_on_any_thread_count() {
    let grid = Grid::preset(GridPreset::Coarse);
    // One lobe at η = 1.33, two at 1.2 (each row's two-lobe fits start from its previous
    // radius, inside one task)
    for eta in [1.33, 1.2] {
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| bake(eta, Moments::Exact, &grid, true).unwrap().0)
        };
        let (one, two) = (run(1), run(2));
        let bits = |t: &AngularTable| -> Vec<u32> {
            t.params()
                .iter()
                .chain(t.radial_cdf())
                .chain(t.harmonics().unwrap_or(&[]))
                .map(|v| v.to_bits())
                .collect()
        };
        assert_eq!(bits(&one), bits(&two));
        assert_eq!(one, two);
    }
}

#[test]
fn default_table_is_at_most_one_mebibyte() {
    let t = default_table();
    assert_eq!(t.axes().dims(), (100, 10, 64));
    // (E, E_β, c) + radial CDF per node, plus the 100 × 10 θ CDF.
    assert_eq!(t.size_bytes(), 100 * 10 * 64 * 4 * 4 + 100 * 10 * 4);
    assert!(t.size_bytes() <= 1 << 20);
}

/// Expected fraction of samples per (r, φ) bin from the pdf, by Gauss–Legendre in each bin.
fn expected_fractions(
    table: &AngularTable,
    rho: f64,
    theta: f64,
    r_edges: &[f64],
    n_phi: usize,
) -> Vec<f64> {
    let view = table.view();
    let gl_r = GaussLegendre::new(12);
    let mut out = Vec::new();
    for w in r_edges.windows(2) {
        for j in 0..n_phi {
            let (p0, p1) = (
                -PI + 2.0 * PI * j as f64 / n_phi as f64,
                -PI + 2.0 * PI * (j + 1) as f64 / n_phi as f64,
            );
            // (adaptive in φ: a lobe as sharp as the lookups allow, κ = 0.999, is 10⁻³ rad wide)
            out.push(gl_r.integrate(w[0], w[1], |r| {
                r * adaptive(
                    |phi| view.pdf(rho, theta, r, phi),
                    &[p0, p1],
                    1e-10,
                    0.0,
                    400,
                )
                .value
            }));
        }
    }
    out
}

#[test]
fn samples_follow_the_pdf_chi_square() {
    for table in both_tables() {
        samples_follow_the_pdf(table);
    }
}

fn samples_follow_the_pdf(table: &AngularTable) {
    let cases = [
        (0.5, 0.0),
        (0.9, 60.0),
        (0.999, 89.0),
        (0.999, 0.0),
        (0.3, 89.0),
        (0.99, 35.0),
    ];
    samples_follow_the_pdf_at(table, &cases);
}

/// Chi-square of 200,000 draws of `sample` at each (ρ′, θ in degrees) of `cases` against the
/// bins' probabilities under `pdf` (every radius node an edge, 12 φ bins), which must add to 1.
pub(crate) fn samples_follow_the_pdf_at(table: &AngularTable, cases: &[(f64, f64)]) {
    let view = table.view();
    let r_nodes = table.axes().r().as_slice();
    // Bin edges: every radius node (bins follow the spline segments), 12 φ bins.
    let n_phi = 12;
    for (case, &(rho, theta_deg)) in cases.iter().enumerate() {
        let theta = f64::to_radians(theta_deg);
        let expected = expected_fractions(table, rho, theta, r_nodes, n_phi);
        let total: f64 = expected.iter().sum();
        // ∫∫ pdf dA = 1 within the quadrature error of the bins.
        assert!(
            (total - 1.0).abs() < 1e-5,
            "{rho} {theta_deg}: ∫pdf = {total}"
        );
        let n = 200_000;
        let mut counts = vec![0usize; expected.len()];
        let mut rng = Rng(SplitMix64::seed_from_u64(0xC0FFEE + case as u64));
        for _ in 0..n {
            let s = view
                .sample(rho, theta, rng.next(), rng.next())
                .expect("energy is stored here");
            assert!((view.pdf(rho, theta, s.r, s.phi) / s.pdf - 1.0).abs() < 1e-9);
            let k = r_nodes
                .partition_point(|&x| x <= s.r)
                .clamp(1, r_nodes.len() - 1)
                - 1;
            let j = (((s.phi + PI) / (2.0 * PI)) * n_phi as f64)
                .floor()
                .clamp(0.0, n_phi as f64 - 1.0) as usize;
            counts[k * n_phi + j] += 1;
        }
        let (chi2, dof) = pooled_chi_square(&expected, &counts, n);
        let crit = chi2_critical_1e6(dof - 1);
        assert!(
            chi2 < crit,
            "η {} {rho} {theta_deg}: chi2 {chi2:.1} > {crit:.1} (dof {dof})",
            table.eta()
        );
    }
}

/// Chi-square of `counts` of `n` draws against the bins' probabilities `expected`, the bins
/// expecting fewer than 20 draws pooled into one: (statistic, number of terms).
pub(crate) fn pooled_chi_square(expected: &[f64], counts: &[usize], n: usize) -> (f64, usize) {
    let (mut chi2, mut dof, mut pooled_e, mut pooled_o) = (0.0, 0usize, 0.0, 0.0);
    for (e, &o) in expected.iter().zip(counts) {
        let e = e * n as f64;
        if e < 20.0 {
            pooled_e += e;
            pooled_o += o as f64;
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            dof += 1;
        }
    }
    if pooled_e > 0.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e.max(1.0);
        dof += 1;
    }
    (chi2, dof)
}

/// Mean relative error of the table against the reference quadrature over points drawn with
/// `sample` (the report's table 2 protocol, `table::validate`), for every case of the report.
fn protocol(samples: usize) -> Vec<bssrdf_zoo::table::ValidationRow> {
    let cases: Vec<(f64, f64)> = REPORT_TABLE_2.iter().map(|c| (c.0, c.1)).collect();
    validate(&default_table().view(), Moments::Exact, &cases, samples, 7).unwrap()
}

/// PBD at η = 1.33, as the tables of this file are baked.
fn pbd(rho: f64) -> Pbd {
    Pbd::new(rho, Boundary::new(1.33, Moments::Exact).unwrap()).unwrap()
}

/// The profile the bake stores at (ρ′, θ, r), computed at that exact point (no table).
fn node_profile(pbd: &Pbd, theta: f64, r: f64) -> Gwc {
    let [e, e_beta, c] = node_cell(pbd, theta, r).unwrap().cell;
    Gwc::from_table(e, e_beta / r, c, r)
}

/// Largest relative error against the reference quadrature of the profiles the bake stores,
/// each computed at its point's own (θ, r), over `n` points drawn with the default table's
/// sampler at (ρ′, θ) as `validate` draws them: the table's accuracy without its
/// interpolation.
fn node_profile_max_error(rho: f64, theta_deg: f64, n: usize, seed: u64) -> f64 {
    let (view, pbd, theta) = (default_table().view(), pbd(rho), theta_deg.to_radians());
    let mut rng = SplitMix64::seed_from_u64(seed);
    (0..n)
        .filter_map(|_| view.sample(rho, theta, rng.next_f64(), rng.next_f64()))
        .map(|s| {
            let reference = pbd.eval(theta, s.r, s.phi, Rule::Reference);
            (node_profile(&pbd, theta, s.r).eval(s.phi) / reference - 1.0).abs()
        })
        .fold(0.0, f64::max)
}

// Ferrier's figure 9: at η = 1.33 and g = 0, for ρ′ = 0.5 and 0.99, every one of 100 000
// points drawn with the table's sampler is within 1 % of the reference, "even for grazing
// angles". The table holds it in every case of the protocol (ρ′ = 0.9 too). The tightest is
// (0.99, 89°), near r = 1.4 at φ = 0 and π, where the best GWC profile itself is 0.998 % off
// PBD at four azimuths (dense minimax, `gwc_minimax::levels_the_error_of_pbd_at_grazing_
// incidence`): interpolation has 0.002 % left there. With the central difference at 80° the θ
// spline took 0.0004 % of it and one or two points in 10⁵ reached 1.0000–1.0002 % (seeds 7, 1,
// 2024); the even quartic's slope there (`catmull_rom` module docs) leaves 0.9998 % on a dense
// scan and none. (Before the first two radius intervals took their own model and the
// refinement its signed floors, up to 4 points in 10⁵ exceeded 1 %, up to 1.44 %, docs/accuracy.md
// "Accuracy".)

/// Figure 9's bound on every point's relative error.
const FIGURE_9_MAX: f64 = 0.01;

/// The table's largest relative error against the reference quadrature at (ρ′, θ) over
/// `n_r` radii evenly spread over `r_range` × `n_phi` azimuths evenly over [0, π]: the
/// deterministic form of figure 9 around its worst point.
fn dense_max_error(rho: f64, theta_deg: f64, r_range: (f64, f64), n_r: usize, n_phi: usize) -> f64 {
    let (view, pbd, theta) = (default_table().view(), pbd(rho), theta_deg.to_radians());
    let mut worst: f64 = 0.0;
    for i in 0..n_r {
        let r = r_range.0 + (r_range.1 - r_range.0) * i as f64 / (n_r - 1) as f64;
        for j in 0..n_phi {
            let phi = PI * j as f64 / (n_phi - 1) as f64;
            let reference = pbd.eval(theta, r, phi, Rule::Reference);
            worst = worst.max((view.eval(rho, theta, r, phi).unwrap() / reference - 1.0).abs());
        }
    }
    worst
}

#[test]
fn accuracy_protocol_fast_form() {
    // 2 000 points per case (the full 100 000 are in the ignored test below and in
    // `bssrdf validate`); a mean over 2 000 points is within ~10 % of the full one, so the
    // bound here is the report's figure with that margin.
    for row in protocol(2_000) {
        let report = row.report_mean_rel_error.unwrap();
        assert!(row.mean_rel_error < 1.15 * report, "{row:?}");
        assert!(row.max_rel_error < FIGURE_9_MAX, "{row:?}");
    }
    // Figure 9 at 89°, for the profiles the bake stores (no θ interpolation)
    let worst = node_profile_max_error(0.99, 89.0, 3_000, 7);
    assert!(worst < FIGURE_9_MAX, "{worst}");
    // and for the table, around its worst point, r = 1.436 at φ = 0 and π (the full scan is in
    // the ignored test): 0.99982 %, where the central difference at 80° gave 1.00015 %
    let worst = dense_max_error(0.99, 89.0, (1.376, 1.496), 7, 91);
    assert!(worst < FIGURE_9_MAX, "{worst}");
}

#[test]
#[ignore = "full protocol and figure 9: 950 000 reference evaluations, 200 000 node fits, about 20 s in release"]
fn accuracy_protocol_full() {
    for row in protocol(100_000) {
        println!("{row:?}");
        assert!(
            row.mean_rel_error <= row.report_mean_rel_error.unwrap(),
            "{row:?}"
        );
        assert!(row.max_rel_error < FIGURE_9_MAX, "{row:?}");
        assert_eq!(row.fraction_above_1pct, 0.0, "{row:?}");
    }
    for rho in [0.9, 0.99] {
        let worst = node_profile_max_error(rho, 89.0, 100_000, 7);
        println!("node profiles at ({rho}, 89°): largest error {worst}");
        assert!(worst < FIGURE_9_MAX, "{rho}: {worst}");
    }
    // The table at (0.99, 89°) on r ∈ [1.1, 1.82] × 721 azimuths: 0.99982 %, 0.0018 percentage
    // points above the GWC family's limit there and 0.0002 below 1 %
    let worst = dense_max_error(0.99, 89.0, (1.1, 1.82), 61, 721);
    println!("table at (0.99, 89°), dense scan: largest error {worst}");
    assert!(worst < FIGURE_9_MAX, "{worst}");
}

#[test]
fn bake_refines_where_the_three_anchor_fit_is_weak() {
    let pbd = pbd(0.99);
    let deg = PI / 180.0;
    // Grazing incidence: refined, and better than the three-anchor fit over all φ
    let (theta, r) = (89.0 * deg, 1.4);
    let node = node_cell(&pbd, theta, r).unwrap();
    assert!(node.refined && node.branch == FitBranch::Exact, "{node:?}");
    let f = |phi: f64| pbd.eval(theta, r, phi, Rule::Fast);
    let s = ANCHOR_COS.map(|x| f(x.acos()));
    let fit = fit_three_anchors(s[0], s[1], s[2]).unwrap().gwc;
    let dense_max = |g: &Gwc| {
        (0..=360)
            .map(|i| PI * i as f64 / 360.0)
            .map(|p| (g.eval(p) / f(p) - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let (stored, three) = (dense_max(&node_profile(&pbd, theta, r)), dense_max(&fit));
    assert!(stored < 0.01 && three > 0.011, "{stored} {three}");
    // Below 45°, an exact fit is stored as it is
    let node = node_cell(&pbd, 30.0 * deg, 1.4).unwrap();
    assert!(!node.refined && node.branch == FitBranch::Exact, "{node:?}");
    // ... but not where the fit clamped α (far out, here at ρ′ = 0.5)
    let node = node_cell(&self::pbd(0.5), 30.0 * deg, 20.0).unwrap();
    assert!(
        node.refined && node.branch == FitBranch::AlphaClamped,
        "{node:?}"
    );
    // θ = 0 and r = 0 keep their own rules
    assert!(!node_cell(&pbd, 0.0, 1.4).unwrap().refined);
    let zero = node_cell(&pbd, theta, 0.0).unwrap();
    assert!(!zero.refined && zero.branch == FitBranch::Zero && zero.cell == [0.0; 3]);
    // Arguments outside the grid's range are errors
    assert!(node_cell(&pbd, -0.1, 1.0).is_err() && node_cell(&pbd, 1.6, 1.0).is_err());
    assert!(node_cell(&pbd, 0.5, -1.0).is_err() && node_cell(&pbd, 0.5, f64::NAN).is_err());
}

/// The θ and r counts of a table and its three axes' nodes (ρ′, θ, r), for reading its rows.
fn axes_of(table: &AngularTable) -> (usize, usize, [&[f64]; 3]) {
    let axes = table.axes();
    let (_, n_theta, n_r) = axes.dims();
    let nodes = [axes.rho(), axes.theta(), axes.r()].map(|a| a.as_slice());
    (n_theta, n_r, nodes)
}

#[test]
fn stored_nodes_are_the_node_cells_and_r0_extends_c() {
    // Every stored cell is `node_cell` rounded to f32, except c at r₀ = 0: the line through
    // (r₁, c₁) and (r₂, c₂) extended to 0 (0 at θ = 0)
    let table = default_table();
    let (n_theta, n_r, [rho_axis, theta_axis, r]) = axes_of(table);
    for (i, j) in [(10, 0), (57, 9), (80, 5), (99, 3)] {
        let pbd = pbd(rho_axis[i]);
        let row = &table.params()[(i * n_theta + j) * n_r * 3..][..n_r * 3];
        for k in [1, 2, 20, 40, 63] {
            let cell = node_cell(&pbd, theta_axis[j], r[k]).unwrap().cell;
            let stored = &row[3 * k..3 * k + 3];
            for (s, c) in stored.iter().zip(cell) {
                assert!(
                    *s == c as f32 || (s.abs() < f32::MIN_POSITIVE && c.abs() < 1e-37),
                    "{i} {j} {k}"
                );
            }
        }
        let c = |k: usize| f64::from(row[3 * k + 2]);
        let extended = c(1) - (c(2) - c(1)) / (r[2] - r[1]) * r[1];
        assert_eq!(row[..2], [0.0, 0.0]);
        assert_eq!(row[2], extended as f32, "{i} {j}");
        if j == 0 {
            assert_eq!(row[2], 0.0);
        }
    }
}

#[test]
fn two_lobe_tables_take_one_lobe_near_normal_incidence() {
    // At η = 1.2 the nodes 10°, 20° and 30° have cos θ′ > ONE_LOBE_ABOVE_COS: each stores the
    // one-lobe node (`node_cell` rounded to f32) with that lobe's r·μ₃ = E_β c³, r·μ₄ = E_β c⁴,
    // and a lookup there is that lobe over its floor; 40° keeps two lobes
    let table = two_lobe_table();
    let view = table.view();
    let (n_theta, n_r, [rho_axis, theta_axis, r]) = axes_of(table);
    let harmonics = table.harmonics().unwrap();
    let cos_refracted = |theta: f64| (1.0 - (theta.sin() / 1.2).powi(2)).sqrt();
    let boundary = Boundary::new(1.2, Moments::Exact).unwrap();
    let mut two_lobe_nodes = 0;
    for i in [5, 40, 90] {
        let pbd = Pbd::new(rho_axis[i], boundary).unwrap();
        for (j, &theta) in theta_axis.iter().enumerate().take(5).skip(1) {
            let node = (i * n_theta + j) * n_r;
            for k in [1, 20, 40, 63] {
                let stored = &table.params()[3 * (node + k)..][..3];
                let second = &harmonics[2 * (node + k)..][..2];
                if cos_refracted(theta) <= ONE_LOBE_ABOVE_COS {
                    if stored[0] > 0.0 {
                        two_lobe_nodes += 1;
                        assert_ne!(second[0], stored[1] * stored[2].powi(3), "{i} {j} {k}");
                    }
                    continue;
                }
                let [e, e_beta, c] = node_cell(&pbd, theta, r[k]).unwrap().cell;
                // (the bake stores f32 subnormals as 0)
                let want = [e, e_beta, c, e_beta * c.powi(3), e_beta * c.powi(4)];
                for (s, w) in stored.iter().chain(second).zip(want) {
                    let same = *s == w as f32 || (*s == 0.0 && w.abs() < 1e-37);
                    assert!(same, "{i} {j} {k}: {stored:?} {second:?} against {want:?}");
                }
                let [e, e_beta, c] = [0, 1, 2].map(|n| f64::from(stored[n]));
                for phi in [0.0, 0.3, 1.0, 2.0, PI] {
                    let lobe = (e - e_beta) / (2.0 * PI) + e_beta * bssrdf_zoo::gwc::pdf_wc(phi, c);
                    let want = lobe / r[k];
                    let got = view.eval(rho_axis[i], theta, r[k], phi).unwrap();
                    let close = got == want || (got / want - 1.0).abs() < 1e-5;
                    assert!(close, "{i} {j} {k} {phi}: {got} {want}");
                }
            }
        }
    }
    assert!(two_lobe_nodes >= 9, "the 40° node has two lobes");
}

#[test]
fn stable_at_the_extremes() {
    for eta in [0.75, 1.0, 1.0001, 2.5] {
        let (table, _) =
            bake(eta, Moments::Exact, &Grid::preset(GridPreset::Coarse), true).unwrap();
        let view = table.view();
        let r_max = *table.axes().r().as_slice().last().unwrap();
        for rho in [0.0, 1e-9, 1.0 - 1e-9, 1.0] {
            for theta in [0.0, f64::to_radians(89.99), PI / 2.0] {
                for r in [0.0, 1e-12, r_max, 1e4] {
                    for phi in [0.0, PI, -PI] {
                        let v = view.eval(rho, theta, r, phi).expect("inside the axes");
                        assert!(
                            v.is_finite() && v >= 0.0,
                            "eta {eta} rho {rho} theta {theta} r {r}: {v}"
                        );
                        let p = view.pdf(rho, theta, r, phi);
                        assert!(p.is_finite() && p >= 0.0);
                    }
                }
                for u in [0.0, 0.3, 0.999_999, 1.0] {
                    if let Some(s) = view.sample(rho, theta, u, 1.0 - u) {
                        assert!(
                            s.r > 0.0 && s.r <= r_max && s.phi.abs() <= PI,
                            "{eta} {rho} {theta}: {s:?}"
                        );
                        assert!(s.pdf.is_finite() && s.pdf > 0.0);
                    }
                }
                if let Some(p) = view.sample_path(rho, [0.5, 0.5, 0.5, 0.5]) {
                    assert!(p.pdf.is_finite() && p.pdf > 0.0 && p.theta <= PI / 2.0);
                }
            }
        }
        // Outside the axes: no value, never an extrapolation.
        assert!(view.eval(1.5, 0.0, 1.0, 0.0).is_none());
        assert!(view.sample(0.5, 2.0, 0.5, 0.5).is_none());
    }
}

#[test]
fn short_radius_axes_from_zero_stay_finite() {
    // The first two radius intervals use nodes 1 and 2; an axis of 2 or 3 nodes has fewer
    // (the format allows any number of radii from 2 up)
    for r_axis in [
        vec![0.0, 0.01],
        vec![0.0, 0.01, 0.02],
        vec![0.0, 0.01, 0.02, 0.05],
    ] {
        let grid = Grid {
            rho: vec![0.3, 0.9],
            theta: vec![0.0, 1.2],
            r: r_axis.clone(),
        };
        let (table, _) = bake(1.33, Moments::Exact, &grid, true).unwrap();
        let view = table.view();
        let r_max = *r_axis.last().unwrap();
        // (The axes are stored as f32: 0.3 and 0.9 round outwards, so look inside them.)
        for rho in [0.31, 0.5, 0.89] {
            for theta in [0.0, 0.7, 1.19] {
                for r in [0.0, 1e-9, 0.003, 0.01, 0.015, r_max] {
                    for phi in [0.0, 2.0, PI] {
                        let v = view.eval(rho, theta, r, phi).unwrap();
                        let p = view.pdf(rho, theta, r, phi);
                        assert!(
                            v.is_finite() && v >= 0.0,
                            "{r_axis:?} {rho} {theta} {r}: {v}"
                        );
                        assert!(
                            p.is_finite() && p >= 0.0,
                            "{r_axis:?} {rho} {theta} {r}: {p}"
                        );
                    }
                }
                if let Some(s) = view.sample(rho, theta, 0.4, 0.6) {
                    assert!(s.r > 0.0 && s.r <= r_max && s.pdf.is_finite(), "{s:?}");
                }
            }
        }
    }
}

// PBD's energies carry ρ′², so the lookups spline E/ρ′² along ρ′ and multiply back, with the
// node at ρ′ = 0 (E = 0) handing its weight to the cubic through nodes 1–4 (`table::albedo`).
// Below the default axis' first nodes (ρ′₁ = 0.0777, ρ′₂ = 0.149) the plain spline of E was far
// off: on the points below, 230 %, 22 % and 0.36 % at θ = 0 for ρ′ = 0.02, 0.05, 0.1, and 576 %,
// 64 % and 10 % at 60°; ρ_eff 3.2 times PBD's at 0.02. Now 0.14 %, 0.023 % and 0.031 % at 0°,
// 3.3 %, 2.6 % and 2.3 % at 60°, where the profiles the bake stores at those exact points are
// already 2.6 %, 2.5 % and 2.2 % off (the GWC shape at φ = π and r ≈ 2); ρ_eff within 0.07 %.

#[test]
fn low_albedo_follows_pbd_between_the_first_albedo_nodes() {
    let view = default_table().view();
    for rho in [0.02, 0.05, 0.1] {
        let pbd = pbd(rho);
        for (theta_deg, bound) in [(0.0, 0.0025), (60.0, 0.04)] {
            let theta = f64::to_radians(theta_deg);
            for r in [0.003, 0.01, 0.05, 0.2, 0.5, 1.0, 2.0, 4.0] {
                for phi in [0.0, 1.0, 2.0, PI] {
                    let got = view.eval(rho, theta, r, phi).unwrap();
                    let want = pbd.eval(theta, r, phi, Rule::Reference);
                    assert!(
                        (got / want - 1.0).abs() < bound,
                        "({rho}, {theta_deg}°, {r}, {phi}): {got:e} vs {want:e}"
                    );
                }
            }
            let got = view.effective_albedo(rho, theta).unwrap();
            let want = pbd.effective_albedo(theta);
            assert!(
                (got / want - 1.0).abs() < 1e-3,
                "{rho} {theta_deg}°: {got} vs {want}"
            );
        }
    }
}

#[test]
fn lookups_at_an_albedo_node_read_that_row_alone() {
    // At ρ′ᵢ the weights along ρ′ are 1 and 0 (1 ± 2⁻⁵² before the f32 row weights): every
    // lookup equals, bit for bit, the same lookup on a table holding rows i and i + 1 only, and
    // ρ_eff is the stored one. Nodes 1 and 2 lie in the segments that fold node 0's weight.
    let table = default_table();
    let (view, (_, n_theta, n_r)) = (table.view(), table.axes().dims());
    let axis = table.axes().rho().as_slice();
    let bits = |v: Option<f64>| v.map(f64::to_bits);
    let mut rng = Rng(SplitMix64::seed_from_u64(5));
    for i in [1, 2, 3, 40, 98] {
        let alone = table.subset_rows(i..i + 2).unwrap();
        let (one, rho) = (alone.view(), axis[i]);
        for j in 0..n_theta {
            let theta = table.axes().theta().as_slice()[j];
            let stored = table.radial_cdf()[(i * n_theta + j) * n_r + n_r - 1];
            assert_eq!(view.effective_albedo(rho, theta), Some(f64::from(stored)));
        }
        for _ in 0..200 {
            let (theta, r, phi) = (1.5 * rng.next(), 20.0 * rng.next().powi(3), PI * rng.next());
            let at = format!("({i}, {theta}, {r}, {phi})");
            assert_eq!(
                bits(view.eval(rho, theta, r, phi)),
                bits(one.eval(rho, theta, r, phi)),
                "{at}"
            );
            let pdf = |v: &bssrdf_zoo::table::TableRef| v.pdf(rho, theta, r, phi).to_bits();
            assert_eq!(pdf(&view), pdf(&one), "{at}");
            let (u, v) = (rng.next(), rng.next());
            assert_eq!(
                view.sample(rho, theta, u, v),
                one.sample(rho, theta, u, v),
                "{at}"
            );
        }
    }
}

#[test]
fn perpendicular_model_is_the_normal_incidence_slice_with_uniform_phi() {
    let view = default_table().view();
    for (rho, r) in [(0.5, 0.3), (0.99, 4.0)] {
        let want = view.eval(rho, 0.0, r, 0.0).unwrap();
        let got = view.eval_perpendicular(rho, r).unwrap();
        assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
        let mut rng = Rng(SplitMix64::seed_from_u64(3));
        for _ in 0..100 {
            let s = view
                .sample_perpendicular(rho, rng.next(), rng.next())
                .unwrap();
            // Uniform φ: the perpendicular density is the θ = 0 table's density.
            let p0 = view.pdf(rho, 0.0, s.r, 0.0);
            assert!((s.pdf / p0 - 1.0).abs() < 1e-9);
        }
    }
}

#[test]
fn path_tracing_theta_samples_follow_their_pdf() {
    let view = default_table().view();
    let rho = 0.9;
    let n = 100_000;
    let n_bins = 18;
    let mut counts = vec![0usize; n_bins];
    let mut rng = Rng(SplitMix64::seed_from_u64(11));
    for _ in 0..n {
        let s = view
            .sample_path(rho, [rng.next(), rng.next(), rng.next(), rng.next()])
            .unwrap();
        // The joint pdf is the product of its parts.
        let want = view.pdf_theta(rho, s.theta) * view.pdf(rho, s.theta, s.r, s.phi) / (2.0 * PI);
        assert!((s.pdf / want - 1.0).abs() < 1e-9);
        counts[((s.theta / (PI / 2.0)) * n_bins as f64).min(n_bins as f64 - 1.0) as usize] += 1;
    }
    let gl = GaussLegendre::new(16);
    let mut chi2 = 0.0;
    for (k, &o) in counts.iter().enumerate() {
        let (a, b) = (
            k as f64 * PI / 2.0 / n_bins as f64,
            (k + 1) as f64 * PI / 2.0 / n_bins as f64,
        );
        let e = n as f64 * gl.integrate(a, b, |t| view.pdf_theta(rho, t));
        chi2 += (o as f64 - e).powi(2) / e;
    }
    assert!(chi2 < chi2_critical_1e6(n_bins - 1), "chi2 {chi2}");
}

#[test]
fn world_units_scale_r_by_one_over_sigma_t_and_s_by_sigma_t_squared() {
    let view = default_table().view();
    let world = World::new(view, 2.5).unwrap();
    let (rho, theta, r_mm, phi) = (0.9, 0.7, 0.4, 0.3);
    let want = 2.5 * 2.5 * view.eval(rho, theta, 2.5 * r_mm, phi).unwrap();
    assert!((world.eval(rho, theta, r_mm, phi).unwrap() / want - 1.0).abs() < 1e-14);
    let s = world.sample(rho, theta, 0.4, 0.6).unwrap();
    assert!((world.pdf(rho, theta, s.r, s.phi) / s.pdf - 1.0).abs() < 1e-9);
    for st in [0.0, 1e-10, 1.1e12, 1e300] {
        assert!(World::new(view, st).is_err(), "{st}");
    }
}

#[test]
fn round_trip_through_a_library_file_is_bit_exact_both_ways() {
    for eta in [1.33, 1.2] {
        round_trip_at(eta);
    }
}

fn round_trip_at(eta: f64) {
    use bssrdf_zoo::format::{Compression, Library, LibraryBuilder, Verify};
    use bssrdf_zoo::table::FileTable;
    let (table, _) = bake(eta, Moments::Exact, &Grid::preset(GridPreset::Coarse), true).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.bssrdf");
    let mut builder = LibraryBuilder::new();
    builder.add_table(table.to_table_data()).unwrap();
    builder.write_atomic(&path, Compression::None).unwrap();
    for library in [
        Library::open_mmap(&path, Verify::Full).unwrap(),
        Library::read(&path, Verify::Full).unwrap(),
    ] {
        let file_table = FileTable::new(library.table(0).unwrap()).unwrap();
        let back = file_table.to_owned_table().unwrap();
        assert_eq!(back, table);
        // Lookups through the file give the same bits as through memory.
        let (a, b) = (file_table.view().unwrap(), table.view());
        for (rho, theta, r, phi) in [
            (0.5, 0.3, 0.7, 0.2),
            (0.99, 1.5, 20.0, -2.0),
            (0.1, 0.0, 0.001, 0.0),
        ] {
            assert_eq!(
                a.eval(rho, theta, r, phi).unwrap().to_bits(),
                b.eval(rho, theta, r, phi).unwrap().to_bits()
            );
            assert_eq!(
                a.pdf(rho, theta, r, phi).to_bits(),
                b.pdf(rho, theta, r, phi).to_bits()
            );
        }
    }
}

/// A NaN uniform, or any uniform outside [0, 1), draws nothing (a broken random stream gives
/// no plausible point), for one and two lobes, every sampler.
#[test]
fn a_nan_uniform_draws_nothing() {
    let nan = f64::NAN;
    for table in both_tables() {
        let view = table.view();
        let (rho, theta) = (0.9, 1.0);
        assert!(view.sample(rho, theta, 0.5, 0.5).is_some());
        for (u_r, u_phi) in [(nan, 0.5), (0.5, nan), (1.0, 0.5), (-0.5, 0.5), (2.0, 0.5)] {
            assert!(
                view.sample(rho, theta, u_r, u_phi).is_none(),
                "{u_r} {u_phi}"
            );
            assert!(
                view.sample_perpendicular(rho, u_r, u_phi).is_none(),
                "{u_r} {u_phi}"
            );
        }
        assert!(view.sample_radius(rho, theta, nan).is_none());
        for k in 0..4 {
            let mut u = [0.5; 4];
            assert!(view.sample_path(rho, u).is_some());
            u[k] = nan;
            assert!(view.sample_path(rho, u).is_none(), "{u:?}");
        }
        // A finite azimuthal uniform outside [0, 1) is a broken stream too (it was clamped)
        for u_phi in [1.0, 1.5, -0.5] {
            assert!(view.sample(rho, theta, 0.5, u_phi).is_none(), "{u_phi}");
        }
    }
}

#[test]
fn invert_undoes_sample() {
    for table in both_tables() {
        invert_undoes_sample_of(table);
    }
}

fn invert_undoes_sample_of(table: &AngularTable) {
    let view = table.view();
    let mut rng = Rng(SplitMix64::seed_from_u64(21));
    for (rho, theta_deg) in [(0.5, 0.0), (0.9, 60.0), (0.999, 89.0)] {
        let theta = f64::to_radians(theta_deg);
        for _ in 0..2000 {
            let (u_r, u_phi) = (rng.next(), rng.next());
            let s = view.sample(rho, theta, u_r, u_phi).unwrap();
            let (back_r, back_phi) = view.invert(rho, theta, s.r, s.phi).unwrap();
            assert!(
                (back_r - u_r).abs() < 1e-9,
                "{rho} {theta_deg}: u_r {u_r} -> {back_r}"
            );
            assert!(
                (back_phi - u_phi).abs() < 1e-9,
                "{rho} {theta_deg}: u_phi {u_phi} -> {back_phi}"
            );
        }
    }
    assert!(view.invert(1.5, 0.0, 1.0, 0.0).is_none());
}

#[test]
fn steep_tails_interpolate_ln_e_even_where_the_plain_spline_undershoots() {
    // Coarse grid, ρ′ = 0.95, θ = 0.2, r = 30: the four node energies are positive but the plain
    // spline of E dips below zero there; the table used to return 0 (PBD: about 2e-9).
    let (table, _) = bake(
        1.33,
        Moments::Exact,
        &Grid::preset(GridPreset::Coarse),
        false,
    )
    .unwrap();
    let pbd = bssrdf_zoo::pbd::Pbd::new(
        0.95,
        bssrdf_zoo::medium::Boundary::new(1.33, Moments::Exact).unwrap(),
    )
    .unwrap();
    let got = table.view().eval(0.95, 0.2, 30.0, 0.0).unwrap();
    let want = pbd.eval(0.2, 30.0, 0.0, bssrdf_zoo::pbd::Rule::Reference);
    assert!(
        got > 0.0 && (got / want - 1.0).abs() < 0.1,
        "{got} vs {want}"
    );
}

/// The θ axis ends with slope 0 at 90°, where PBD's slope is 0 (it depends on θ through sin θ
/// only): approaching the last node, lookups level off. Their difference quotient over the
/// last ε falls in proportion to ε (to 1/16 of the chord's slope over 80°–90° at ε = 0.01 and
/// 1/160 at ε = 0.001 here), while with the chord rule it would stay near the chord's slope.
#[test]
fn lookups_approach_grazing_incidence_with_zero_slope() {
    let view = default_table().view();
    let theta = view.axes().theta().as_slice();
    let n = theta.len();
    let (last, before) = (theta[n - 1], theta[n - 2]);
    let width = last - before;
    for (rho, r, phi) in [
        (0.5, 0.3, 0.0),
        (0.9, 1.0, 1.0),
        (0.99, 3.0, PI),
        (0.7, 0.01, -0.5),
        (0.2, 8.0, 0.3),
    ] {
        type Lookup<'a> = Box<dyn Fn(f64) -> f64 + 'a>;
        let lookups: [(&str, Lookup); 4] = [
            ("eval", Box::new(|t| view.eval(rho, t, r, phi).unwrap())),
            ("pdf", Box::new(|t| view.pdf(rho, t, r, phi))),
            (
                "ρ_eff",
                Box::new(|t| view.effective_albedo(rho, t).unwrap()),
            ),
            ("pdf_θ", Box::new(|t| view.pdf_theta(rho, t))),
        ];
        for (name, f) in lookups {
            let chord = (f(last) - f(before)) / width;
            // The table blends f32 values: differences carry noise of about 1e-7 relative
            let noise = 1e-7 * f(last).abs();
            for (eps, share) in [(1e-2, 0.1), (1e-3, 0.015)] {
                let quotient = (f(last) - f(last - eps)) / eps;
                assert!(
                    quotient.abs() <= share * chord.abs() + noise / eps,
                    "{name}({rho}, θ, {r}, {phi}) over the last {eps} rad: {quotient:e}, \
                     chord {chord:e}"
                );
            }
        }
    }
}

/// Every table's θ axis, baked, read back or cut to albedo rows, has slope 0 at its last node
/// exactly when that is π/2 (as f32, or within 10⁻⁶ rad); the other axes keep chord slopes.
/// The stored θ CDF integrates that spline.
#[test]
fn theta_axis_ends_flat_exactly_at_grazing_incidence() {
    use bssrdf_zoo::catmull_rom::End;
    use bssrdf_zoo::table::Axes;
    let table = default_table();
    let axes = table.axes();
    assert_eq!(axes.theta().end(), End::Even);
    assert_eq!(axes.rho().end(), End::Chord);
    assert_eq!(axes.r().end(), End::Chord);
    assert_eq!(
        *axes.theta().as_slice().last().unwrap(),
        f64::from(PI as f32 / 2.0)
    );
    let subset = table.subset_rows(3..7).unwrap();
    assert_eq!(subset.axes().theta().end(), End::Even);
    let end_of = |last: f64| {
        let axes = Axes::new(vec![0.0, 1.0], vec![0.0, 0.5, last], vec![0.0, 1.0]).unwrap();
        axes.theta().end()
    };
    assert_eq!(end_of(PI / 2.0), End::Even);
    assert_eq!(end_of(PI / 2.0 + 9e-7), End::Even);
    assert_eq!(end_of(PI / 2.0 - 9e-7), End::Even);
    assert_eq!(end_of(PI / 2.0 + 2e-6), End::Chord);
    assert_eq!(end_of(PI / 2.0 - 2e-6), End::Chord);
    assert_eq!(end_of(80f64.to_radians()), End::Chord);

    // The θ CDF of each albedo row is the integral of the even-end spline through ρ_eff: the
    // chord rule's up to 70°, where the two splines part (Simpson's rule is exact on each
    // cubic segment)
    let (n_rho, n_theta, n_r) = axes.dims();
    let theta_cdf = table.theta_cdf().unwrap();
    let chord_axis = bssrdf_zoo::catmull_rom::Nodes::new(axes.theta().as_slice().to_vec()).unwrap();
    let theta = axes.theta().as_slice();
    let mut even = vec![0.0; n_theta];
    let mut chord = vec![0.0; n_theta];
    for i in (0..n_rho).step_by(7) {
        let rho_eff = |j: usize| f64::from(table.radial_cdf()[(i * n_theta + j) * n_r + n_r - 1]);
        let total = axes.theta().integrate_positive(rho_eff, &mut even).unwrap();
        chord_axis.integrate_positive(rho_eff, &mut chord).unwrap();
        let stored = &theta_cdf[i * n_theta..(i + 1) * n_theta];
        for (j, (&s, &c)) in stored.iter().zip(&even).enumerate() {
            assert_eq!(s, c as f32, "row {i}, node {j}");
        }
        assert_eq!(even[..n_theta - 2], chord[..n_theta - 2], "row {i}");
        let spline = |x: f64| axes.theta().evaluate(rho_eff, x).unwrap();
        let simpson: f64 = theta
            .windows(2)
            .map(|w| bssrdf_testkit::splines::simpson(spline, w[0], w[1], 2))
            .sum();
        assert!((total - simpson).abs() <= 1e-12 * total, "row {i}");
    }
}

/// The largest relative change of `eval` and `pdf` from each interior θ node and albedo node
/// of `table` to 10⁻¹² either side of it (values below 10⁻⁹ of the point's φ = 0 value left
/// out), over a grid of (ρ′, r, φ).
pub(crate) fn largest_jump_at_nodes(table: &AngularTable) -> f64 {
    let view = table.view();
    let rel = |a: f64, b: f64| {
        if a == b {
            0.0
        } else {
            (a - b).abs() / a.abs().max(b.abs())
        }
    };
    let axes = view.axes();
    let thetas: Vec<f64> = axes.theta().as_slice().to_vec();
    let rhos: Vec<f64> = axes.rho().as_slice().to_vec();
    let enters = |t: f64| view.eta() >= 1.0 || t.sin() < view.eta() - 1e-6;
    let mut worst: f64 = 0.0;
    let mut check = |rho: f64, theta: f64, moved: [f64; 2]| {
        for r in [0.01, 0.3, 3.0] {
            let peak = view.eval(rho, theta, r, 0.0).unwrap_or(0.0);
            for phi in [0.0, 0.7, 3.0] {
                let (Some(a), pa) = (view.eval(rho, theta, r, phi), view.pdf(rho, theta, r, phi))
                else {
                    continue;
                };
                if a <= 1e-9 * peak {
                    continue;
                }
                let [rho_b, theta_b] = moved;
                if let Some(b) = view.eval(rho_b, theta_b, r, phi) {
                    worst = worst.max(rel(a, b));
                    worst = worst.max(rel(pa, view.pdf(rho_b, theta_b, r, phi)));
                }
            }
        }
    };
    for &rho in rhos.iter().skip(1).step_by(5) {
        for &theta in &thetas[1..thetas.len() - 1] {
            if !enters(theta) {
                continue;
            }
            for t in [theta * (1.0 + 1e-12), theta * (1.0 - 1e-12)] {
                check(rho, theta, [rho, t]);
            }
        }
    }
    for &rho in &rhos[1..rhos.len() - 1] {
        for theta in [0.3, 1.0, 1.5] {
            if !enters(theta) {
                continue;
            }
            for p in [rho * (1.0 + 1e-12), rho * (1.0 - 1e-12)] {
                check(rho, theta, [p, theta]);
            }
        }
    }
    worst
}

#[test]
fn two_lobe_lookups_are_continuous_across_the_nodes() {
    // The cap of the rebuild (its sharpest lobe) once took the sharpness of every row of nonzero
    // weight, and jumped where a row's weight left 0: 0.9 % one ulp off a θ node of the η = 1
    // table, 4.3 % on a walk table (337 % at one far point); ramped in with the weight it is
    // continuous. A relative change of 10⁻¹² in a coordinate moves a value by about that times
    // its logarithmic slope: 10⁻⁶ leaves room for the steepest (the far tail, the forward peak).
    for (name, table) in [
        ("two lobes, eta 1.2", two_lobe_table()),
        (
            "two lobes and the ridge, eta 1",
            crate::ridge::ridge_table(),
        ),
    ] {
        let jump = largest_jump_at_nodes(table);
        assert!(jump < 1e-6, "{name}: {jump:e}");
        // Across radius nodes the window of four nodes moves on: the node it drops has weight
        // 0 there, but its sharpest lobe capped the rebuild in full (12 % at η = 0.99, 13 % at
        // η = 1 on the default grids, one ulp off a node, found from outside)
        let jump = largest_jump_at_radius_nodes(table);
        assert!(jump < 1e-6, "{name}, radius nodes: {jump:e}");
    }
}

/// The largest relative change of eval, or of the pdf over its value at φ = 0, between a radius
/// node and 10⁻¹² of it either side, over albedos, incidences and azimuths, where the value is
/// above 10⁻⁶ of the forward one at the second radius node.
fn largest_jump_at_radius_nodes(table: &AngularTable) -> f64 {
    let view = table.view();
    let enters = |t: f64| view.eta() >= 1.0 || t.sin() < view.eta() - 1e-6;
    let r_nodes: Vec<f64> = view.axes().r().as_slice().to_vec();
    let mut worst: f64 = 0.0;
    for rho in [0.1, 0.3, 0.5, 0.7, 0.9, 0.99] {
        for theta in [0.3, 1.0, 1.3, 1.5, 1.55, 1.57] {
            if !enters(theta) {
                continue;
            }
            // (Beyond the last node the table is 0)
            let inner = &r_nodes[..r_nodes.len() - 1];
            // (Far in the tail the two parts of a ridge table mix by radial densities that
            // jump at nodes by the f32 rounding of their CDFs: the points where the value is
            // above 10⁻⁶ of the profile near the entry point)
            let peak = view.eval(rho, theta, r_nodes[2], 0.0).unwrap_or(0.0);
            for &r in inner.iter().skip(2).filter(|&&r| r < 30.0) {
                for phi in [0.0, 0.01, 0.05, 0.3, 1.5, 3.0] {
                    // (The angular density at r: the radial one jumps at nodes by the f32
                    // rounding of the stored CDF, reliability.md. A ridge table's density mixes
                    // its two parts by their radial densities, so its shape in φ jumps with
                    // them: eval alone there.)
                    let at = |r: f64| {
                        let v = view.eval(rho, theta, r, phi).unwrap_or(0.0);
                        let pdf = view.pdf(rho, theta, r, phi) / view.pdf(rho, theta, r, 0.0);
                        [
                            v,
                            if view.ridge() == bssrdf_zoo::table::RidgeKind::None {
                                pdf
                            } else {
                                0.0
                            },
                        ]
                    };
                    let here = at(r);
                    if here[0] <= 1e-6 * peak {
                        continue;
                    }
                    for moved in [r * (1.0 - 1e-12), r * (1.0 + 1e-12)] {
                        for (a, b) in here.into_iter().zip(at(moved)) {
                            if a != b {
                                worst = worst.max((a - b).abs() / a.abs().max(b.abs()));
                            }
                        }
                    }
                }
            }
        }
    }
    worst
}

#[test]
fn far_azimuths_are_reduced_alike_on_both_sides() {
    // φ beyond [−π, π] is reduced modulo 2π: the value at −φ is the value at φ bit for bit at
    // every φ (it was 1.3 % off at 10¹⁵ rad and 41 % at 10¹⁶), and φ + 2πk is φ to within
    // k·2.4·10⁻¹⁶ rad (the f64 2π's shortfall) as far as the profile's slope shows it.
    let view = two_lobe_table().view();
    let mut rng = SplitMix64::seed_from_u64(41);
    for _ in 0..2000 {
        let (rho, theta, r) = (
            rng.next_f64(),
            1.5 * rng.next_f64(),
            0.05 + 5.0 * rng.next_f64(),
        );
        let phi = 10f64.powf(20.0 * rng.next_f64());
        let [a, b] = [phi, -phi].map(|p| view.eval(rho, theta, r, p).unwrap());
        assert_eq!(a.to_bits(), b.to_bits(), "{rho} {theta} {r} {phi}");
        let near = PI * (2.0 * rng.next_f64() - 1.0);
        let k = (rng.next_f64() * 1e6).floor();
        let far = view.eval(rho, theta, r, near + TAU * k).unwrap();
        let here = view.eval(rho, theta, r, near).unwrap();
        assert!(
            (far - here).abs() <= 1e-6 * here,
            "{rho} {theta} {r} {near} {k}: {far} vs {here}"
        );
    }
}

#[test]
fn albedos_near_zero_keep_the_law_of_the_smallest() {
    // Every energy is ρ′² g(ρ′) with g smooth at 0: below TINY_ALBEDO (10⁻⁸) the lookups read the
    // table there and scale by (ρ′/10⁻⁸)². ρ_eff/ρ′² and eval/ρ′² at ρ′ from 10⁻⁷ down to 10⁻³⁰⁰
    // within 10⁻⁶ of their values at 10⁻⁷ (f32 weights underflowed from about 10⁻²⁰: ρ_eff
    // 62 % low at 10⁻²³, 8.8 times high at 10⁻²⁴, 0 below), and every draw has its pdf.
    use bssrdf_zoo::table::TINY_ALBEDO;
    for table in [
        default_table(),
        two_lobe_table(),
        crate::ridge::ridge_table(),
    ] {
        let view = table.view();
        for theta in [0.0, 1.0, 1.5] {
            let reference = 1e-7;
            let law = |rho: f64| view.effective_albedo(rho, theta).unwrap() / (rho * rho);
            let value = |rho: f64| view.eval(rho, theta, 0.7, 0.4).unwrap() / (rho * rho);
            let (g, v) = (law(reference), value(reference));
            for rho in [
                TINY_ALBEDO * (1.0 + 1e-12),
                TINY_ALBEDO,
                0.99e-8,
                1e-12,
                1e-23,
                1e-24,
                1e-30,
                1e-150,
            ] {
                assert!(
                    (law(rho) / g - 1.0).abs() < 1e-6,
                    "{rho} {theta}: {} vs {g}",
                    law(rho)
                );
                assert!(
                    (value(rho) / v - 1.0).abs() < 1e-6,
                    "{rho} {theta}: {} vs {v}",
                    value(rho)
                );
                let s = view.sample(rho, theta, 0.37, 0.61).unwrap();
                assert!((view.pdf(rho, theta, s.r, s.phi) / s.pdf - 1.0).abs() < 1e-9);
            }
            // Beyond f64 (ρ′² below 10⁻³²⁴) the energies are 0, the densities still those of 10⁻⁸
            assert_eq!(view.effective_albedo(1e-300, theta), Some(0.0));
            assert!(view.sample(1e-300, theta, 0.37, 0.61).is_some());
        }
    }
}
