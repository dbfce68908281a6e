//! Tables with the analytic ridge (`table::ridge`, format-spec.md §10 "The ridge"): which bakes
//! take it, what it buys against PBD at η = 1, and that every lookup stays an exact pair with
//! its density (chi-square of draws, densities integrating to 1, θ draws, the inverse).

use crate::below_critical::{default_at, path_draws_of_theta_follow_pdf_theta};
use crate::lookup::pooled_chi_square;
use bssrdf_testkit::stats::chi2_critical_1e6;
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::quadrature::GaussLegendre;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{
    bake_lobes, check, AngularTable, GridPreset, Lobes, RidgeKind, CHECK_BOUNDS,
};
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;

/// The table `bssrdf bake --eta 1` makes, with θ sampling, baked once for the file.
pub(crate) fn ridge_table() -> &'static AngularTable {
    static TABLE: OnceLock<AngularTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        let table = default_at(1.0, true);
        assert_eq!(table.ridge(), RidgeKind::NEWEST);
        table
    })
}

#[test]
fn two_lobe_bakes_below_eta_1_048_take_the_ridge() {
    for eta in [0.9, 1.0, 1.04] {
        assert_eq!(default_at(eta, false).ridge(), RidgeKind::NEWEST, "{eta}");
    }
    for eta in [1.05, 1.33] {
        assert_eq!(default_at(eta, false).ridge(), RidgeKind::None, "{eta}");
    }
    // One lobe keeps S at the nodes
    let grid = GridPreset::Coarse.grid(1.0, Lobes::One);
    let (one, _) = bake_lobes(1.0, Moments::Exact, &grid, false, Lobes::One).unwrap();
    assert_eq!(one.ridge(), RidgeKind::None);
}

#[test]
fn no_node_is_lost_where_the_ridge_reaches_past_pbd() {
    // Far off the ridge at low albedo R can exceed S; a fit through S − R ≤ 0 failed and the
    // node held 0 (ρ′ = 0.078, θ = 85–89°, r = 15.9 at η = 1), so lookups near it gave R alone,
    // 0.16–0.51 times PBD. Every node where PBD holds energy holds energy.
    let table = ridge_table();
    let view = table.view();
    let boundary = Boundary::new(1.0, Moments::Exact).unwrap();
    let (n_rho, n_theta, n_r) = view.axes().dims();
    let [rho_axis, theta_axis, r_axis] = [
        view.axes().rho().as_slice(),
        view.axes().theta().as_slice(),
        view.axes().r().as_slice(),
    ];
    for i in (1..n_rho).filter(|&i| rho_axis[i] < 0.3) {
        let pbd = Pbd::new(rho_axis[i], boundary).unwrap();
        for j in
            (0..n_theta).filter(|&j| theta_axis[j] > 80f64.to_radians() && theta_axis[j] < 1.57)
        {
            for (k, &r) in r_axis.iter().enumerate().skip(1) {
                let e = table.params()[((i * n_theta + j) * n_r + k) * 3];
                let truth = pbd.eval(theta_axis[j], r, PI, Rule::Fast);
                if truth > 1e-30 {
                    assert!(
                        e > 0.0,
                        "rho {} theta {} r {}",
                        rho_axis[i],
                        theta_axis[j].to_degrees(),
                        r
                    );
                }
            }
        }
    }
    // and the lookups there follow PBD as the table did before the ridge (0.68 of it at
    // (0.05, 89°, r = 10, φ = π), PBD 10⁻¹¹ there: the far tail below the first albedo node)
    for (rho, theta_deg) in [(0.05, 89.0), (0.1, 86.0)] {
        let pbd = Pbd::new(rho, boundary).unwrap();
        for phi in [0.5, PI] {
            let theta = f64::to_radians(theta_deg);
            let ratio = view.eval(rho, theta, 10.0, phi).unwrap()
                / pbd.eval(theta, 10.0, phi, Rule::Reference);
            assert!(
                (0.6..1.5).contains(&ratio),
                "{rho} {theta_deg} {phi}: {ratio}"
            );
        }
    }
}

#[test]
fn at_eta_1_the_regions_near_grazing_follow_pbd_within_a_few_per_cent() {
    // The bake's check (PBD's reference quadrature at points spread over each region): from
    // 85° to 90° the region means were 8.4–13.6 % with the ridge in the nodes, 1.8–2.7 % with
    // its flux part added at lookup, 0.5–1.36 % with its fluence part too, and 0.37–0.81 % with
    // the θ node at 89.4° (docs/accuracy.md): every region within the 1 % bound, no silent zero
    let result = check(&ridge_table().view(), Moments::Exact, CHECK_BOUNDS).unwrap();
    for r in &result.regions {
        assert_eq!(r.silent_zeros, 0, "{r:?}");
        assert!(r.mean_rel_error <= CHECK_BOUNDS.mean_rel_error, "{r:?}");
    }
}

/// Bin edges in φ ∈ [−π, π]: geometric towards 0, where the ridge is as narrow as cos θ′.
fn phi_edges() -> Vec<f64> {
    let mut positive = vec![0.0];
    let mut x = 1e-6;
    while x < 2.0 {
        positive.push(x);
        x *= 2.0;
    }
    positive.push(PI);
    let mut edges: Vec<f64> = positive.iter().rev().map(|&p| -p).collect();
    edges.extend(&positive[1..]);
    edges
}

/// ∫∫ over the bin of pdf r dr dφ: Gauss–Legendre in each, the φ bins split at the ridge's
/// scale (the narrowest bins are 10⁻⁶ wide, the ridge's width at 90°).
fn bin_mass(
    view: &bssrdf_zoo::table::TableRef<'_>,
    rho: f64,
    theta: f64,
    r: [f64; 2],
    phi: [f64; 2],
) -> f64 {
    let gl = GaussLegendre::new(12);
    gl.integrate(r[0], r[1], |x| {
        x * gl.integrate(phi[0], phi[1], |p| view.pdf(rho, theta, x, p))
    })
}

#[test]
fn draws_follow_the_density_of_table_and_ridge() {
    let view = ridge_table().view();
    let r_nodes = view.axes().r().as_slice();
    let phi = phi_edges();
    for (case, &(rho, theta_deg)) in [(0.5, 89.0), (0.9, 86.2), (0.99, 80.0), (0.3, 89.95)]
        .iter()
        .enumerate()
    {
        let theta = f64::to_radians(theta_deg);
        let mut expected = Vec::new();
        for r in r_nodes.windows(2) {
            for p in phi.windows(2) {
                expected.push(bin_mass(&view, rho, theta, [r[0], r[1]], [p[0], p[1]]));
            }
        }
        let total: f64 = expected.iter().sum();
        assert!(
            (total - 1.0).abs() < 1e-4,
            "{rho} {theta_deg}: ∫pdf = {total}"
        );
        let n = 200_000;
        let mut counts = vec![0usize; expected.len()];
        let mut rng = SplitMix64::seed_from_u64(0x51D6E + case as u64);
        let mut from_ridge = 0;
        for _ in 0..n {
            let (u_r, u_phi) = (rng.next_f64(), rng.next_f64());
            let s = view.sample(rho, theta, u_r, u_phi).expect("energy here");
            let pdf = view.pdf(rho, theta, s.r, s.phi);
            assert!((pdf / s.pdf - 1.0).abs() < 1e-9, "{s:?} {pdf}");
            // A draw through the nodes' part has its uniforms back from the inverse
            match view.invert(rho, theta, s.r, s.phi) {
                Some((back_r, back_phi))
                    if (back_r - u_r).abs() < 1e-6 && (back_phi - u_phi).abs() < 1e-6 => {}
                _ => from_ridge += 1,
            }
            let k = r_nodes
                .partition_point(|&x| x <= s.r)
                .clamp(1, r_nodes.len() - 1)
                - 1;
            let j = phi.partition_point(|&x| x <= s.phi).clamp(1, phi.len() - 1) - 1;
            counts[k * (phi.len() - 1) + j] += 1;
        }
        // The ridge's share of the draws is its share of the energy
        let ridge_share = {
            let all = view.effective_albedo(rho, theta).unwrap();
            let bare = view
                .with_ridge(RidgeKind::None)
                .effective_albedo(rho, theta)
                .unwrap();
            1.0 - bare / all
        };
        let share = from_ridge as f64 / n as f64;
        let sigma = (ridge_share * (1.0 - ridge_share) / n as f64).sqrt();
        assert!(
            (share - ridge_share).abs() < 5.0 * sigma + 1e-4,
            "{share} vs {ridge_share}"
        );
        let (chi2, dof) = pooled_chi_square(&expected, &counts, n);
        let crit = chi2_critical_1e6(dof - 1);
        assert!(
            chi2 < crit,
            "{rho} {theta_deg}: chi2 {chi2:.1} > {crit:.1} (dof {dof})"
        );
    }
}

#[test]
fn the_effective_albedo_is_the_integral_of_the_value() {
    // ∫∫ eval r dr dφ over the radius nodes' segments and the φ bins: the nodes' part differs
    // by evaluation's log-energy interpolation (~1e-4 of it), the ridge's not at all
    let view = ridge_table().view();
    let phi = phi_edges();
    let gl = GaussLegendre::new(12);
    for (rho, theta_deg) in [(0.5, 89.0), (0.95, 87.0), (0.2, 83.0), (0.9, 90.0)] {
        let theta = f64::to_radians(theta_deg).min(FRAC_PI_2);
        let r_nodes = view.axes().r().as_slice();
        let integral: f64 = r_nodes
            .windows(2)
            .map(|r| {
                gl.integrate(r[0], r[1], |x| {
                    x * phi
                        .windows(2)
                        .map(|p| gl.integrate(p[0], p[1], |q| view.eval(rho, theta, x, q).unwrap()))
                        .sum::<f64>()
                })
            })
            .sum();
        let rho_eff = view.effective_albedo(rho, theta).unwrap();
        assert!(
            (integral / rho_eff - 1.0).abs() < 2e-3,
            "{rho} {theta_deg}: {integral} vs {rho_eff}"
        );
        // and the ridge adds to the nodes' part
        assert!(
            rho_eff
                > view
                    .with_ridge(RidgeKind::None)
                    .effective_albedo(rho, theta)
                    .unwrap()
        );
    }
}

#[test]
fn path_draws_of_theta_follow_pdf_theta_with_the_ridge() {
    path_draws_of_theta_follow_pdf_theta(&ridge_table().view(), FRAC_PI_2);
}

/// ∫ f dφ over [−π, π] on the bins of [`phi_edges`], Gauss–Legendre in each.
fn over_phi(f: impl Fn(f64) -> f64) -> f64 {
    let gl = GaussLegendre::new(12);
    phi_edges()
        .windows(2)
        .map(|p| gl.integrate(p[0], p[1], &f))
        .sum()
}

#[test]
fn the_separable_lookups_see_the_ridge() {
    // The radial draw is sample's, its density the radial factor of pdf; the angular factor
    // averages to 1 over φ and times S̄ gives eval; the separable estimator ρ_eff·F with r
    // from sample_radius and φ uniform has mean ρ_eff (as for tables without, separable.rs)
    let view = ridge_table().view();
    let mut rng = SplitMix64::seed_from_u64(29);
    for _ in 0..60 {
        let rho = 0.05 + 0.95 * rng.next_f64();
        let theta = f64::to_radians(75.0 + 15.0 * rng.next_f64());
        let u = rng.next_f64();
        let d = view.sample_radius(rho, theta, u).unwrap();
        let s = view.sample(rho, theta, u, 0.5).unwrap();
        assert_eq!(d.r.to_bits(), s.r.to_bits(), "{rho} {theta} {u}");
        let pdf = view.pdf_radius(rho, theta, d.r);
        assert!((d.pdf / pdf - 1.0).abs() < 1e-9, "{} vs {pdf}", d.pdf);
        let marginal = d.r * over_phi(|phi| view.pdf(rho, theta, d.r, phi));
        assert!((marginal / pdf - 1.0).abs() < 1e-5, "{marginal} vs {pdf}");
        let f = |phi: f64| view.angular_factor(rho, theta, d.r, phi).unwrap();
        let mean = over_phi(f) / (2.0 * PI);
        assert!((mean - 1.0).abs() < 1e-5, "{rho} {theta} r {}: {mean}", d.r);
        let s_bar = |phi: f64| view.eval(rho, theta, d.r, phi).unwrap() / f(phi);
        for phi in [0.0, 1e-4, 0.5, -2.5] {
            assert!((s_bar(phi) / s_bar(1.0) - 1.0).abs() < 1e-12);
        }
    }
    for (case, &(rho, theta_deg)) in [(0.5, 89.0), (0.95, 86.0), (0.2, 80.0)].iter().enumerate() {
        let theta = f64::to_radians(theta_deg);
        let rho_eff = view.effective_albedo(rho, theta).unwrap();
        let mut rng = SplitMix64::seed_from_u64(300 + case as u64);
        let n = 200_000;
        let weights: Vec<f64> = (0..n)
            .map(|_| {
                let (u_r, u_phi) = (rng.next_f64(), rng.next_f64());
                let d = view.sample_radius(rho, theta, u_r).unwrap();
                rho_eff
                    * view
                        .angular_factor(rho, theta, d.r, 2.0 * PI * u_phi - PI)
                        .unwrap()
            })
            .collect();
        let mean = weights.iter().sum::<f64>() / n as f64;
        let var = weights.iter().map(|w| (w - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let error = (var / n as f64).sqrt();
        assert!(
            (mean - rho_eff).abs() <= 4.0 * error,
            "{rho} {theta_deg}: {mean} vs {rho_eff} ± {error}"
        );
    }
}
