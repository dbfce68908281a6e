//! The bake's own check (`table::check`): a good table passes, a table that is a few per cent
//! off everywhere fails in every region, and beyond the critical angle every lookup is 0.

use crate::lookup::default_table;
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{
    bake, check, AngularTable, Grid, GridPreset, Lobes, CHECK_BOUNDS, CHECK_COARSE_BOUNDS,
    PARAMS_PER_NODE,
};

fn coarse(eta: f64) -> AngularTable {
    bake(eta, Moments::Exact, &Grid::preset(GridPreset::Coarse), true)
        .unwrap()
        .0
}

#[test]
fn a_good_table_passes_in_every_region_and_is_deterministic() {
    let table = coarse(1.33);
    let result = check(&table.view(), Moments::Exact, CHECK_COARSE_BOUNDS).unwrap();
    // 6 albedo bands x 5 incidence bands, every one with points
    assert_eq!(result.regions.len(), 30);
    for r in &result.regions {
        assert!(r.points > 300, "{r:?}");
        assert!(r.coverage_points > 50, "{r:?}");
        assert!(
            r.mean_rel_error <= CHECK_COARSE_BOUNDS.mean_rel_error,
            "{r:?}"
        );
        assert_eq!(r.silent_zeros, 0, "{r:?}");
    }
    assert!(result.passes());
    let again = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| check(&table.view(), Moments::Exact, CHECK_COARSE_BOUNDS).unwrap());
    assert_eq!(again, result);
}

#[test]
fn the_default_table_passes_with_its_spread_points_down_to_1e_12_of_the_peak() {
    // The default and fine grids' bound reaches 10⁻¹² of the peak (issue 17): before the
    // spline of E/(ρ′² f) at the ends of the albedo axis, this table failed it below
    // ρ′ = 0.1 (tails up to 25 % off at r ≈ 15–18, exact zeros at ρ′ < 0.02)
    assert_eq!(CHECK_BOUNDS.peak_fraction, 1e-12);
    let result = check(&default_table().view(), Moments::Exact, CHECK_BOUNDS).unwrap();
    assert_eq!(result.regions.len(), 30);
    for r in &result.regions {
        assert!(r.coverage_points > 100, "{r:?}");
        assert_eq!(r.silent_zeros, 0, "{r:?}");
        assert!(r.passes(&CHECK_BOUNDS), "{r:?}");
    }
}

fn default_bake(eta: f64) -> AngularTable {
    let grid = GridPreset::Default.grid(eta, Lobes::for_eta(eta));
    bake(eta, Moments::Exact, &grid, false).unwrap().0
}

/// The tail points see what r log-uniform over the whole axis crossed in too few points: the
/// default table at η = 1.01 is 10–80 % off PBD at ρ′ < 0.1, θ ≥ 75° and r ≈ 13–20, where PBD
/// is 10⁻¹²–10⁻⁹ of its peak (`examples/tail_error`), and up to 16 % at ρ′ 0.1–0.7, 75–85°,
/// where the analytic ridge's lobe reaches past S off the ridge (`table::ridge`); its check
/// fails there, and only there, on coverage points, its weighted means within the bound.
#[test]
fn the_far_tail_near_grazing_at_eta_1_01_fails_the_check() {
    let result = check(&default_bake(1.01).view(), Moments::Exact, CHECK_BOUNDS).unwrap();
    let failed: Vec<_> = result.failures().collect();
    assert!(!failed.is_empty());
    for r in failed {
        assert!(r.rho[1] as f32 <= 0.7, "{r:?}");
        assert!(r.theta_deg[0] >= 75.0, "{r:?}");
        assert!(
            r.coverage_max_rel_error > CHECK_BOUNDS.coverage_rel_error,
            "{r:?}"
        );
        assert!(r.mean_rel_error < CHECK_BOUNDS.mean_rel_error, "{r:?}");
    }
}

/// At η = 1.05 and 1.1 the same far tails failed the check (25 % and 13 % off at ρ′ < 0.1,
/// θ 75–85°) while lookups read the one lobe of μ₁, μ₂ where the harmonics they blend have
/// merged Prony roots; rebuilt as the limit of a signed pair (`gwc::MERGED_DEPARTURE`), they
/// pass.
#[test]
fn the_far_tails_near_grazing_at_eta_1_05_and_1_1_pass_the_check() {
    for eta in [1.05, 1.1] {
        let result = check(&default_bake(eta).view(), Moments::Exact, CHECK_BOUNDS).unwrap();
        let failed: Vec<_> = result.failures().collect();
        assert!(failed.is_empty(), "eta {eta}: {failed:?}");
    }
}

#[test]
fn a_table_two_per_cent_off_fails_everywhere() {
    let table = coarse(1.33);
    // E and E_beta scaled by 1.02: the same shapes, 2 % more energy at every node
    let mut params = table.params().to_vec();
    for node in params.chunks_exact_mut(PARAMS_PER_NODE) {
        node[0] *= 1.02;
        node[1] *= 1.02;
    }
    let off = AngularTable::from_parts(
        table.eta(),
        table.moments(),
        table.axes().clone(),
        params,
        table.radial_cdf().to_vec(),
        table.theta_cdf().map(<[f32]>::to_vec),
    )
    .unwrap();
    let result = check(&off.view(), Moments::Exact, CHECK_BOUNDS).unwrap();
    assert!(!result.passes());
    for r in &result.regions {
        assert!((r.mean_rel_error - 0.02).abs() < 0.01, "{r:?}");
    }
    assert_eq!(result.failures().count(), result.regions.len());
}

#[test]
fn below_index_one_the_check_stays_below_the_critical_angle_and_lookups_beyond_are_zero() {
    let eta = 0.75f64;
    let table = coarse(eta);
    let result = check(&table.view(), Moments::Exact, CHECK_COARSE_BOUNDS).unwrap();
    let critical = eta.asin().to_degrees();
    for r in &result.regions {
        assert!(r.theta_deg[1] < critical, "{r:?}");
    }
    // No bands 60-75 and beyond: 2 incidence bands (0-30, 30-60 cut at 48.6) x 6 albedo bands
    assert_eq!(result.regions.len(), 12);
    let view = table.view();
    let beyond = (critical + 1.0).to_radians();
    for rho in [0.3, 0.9] {
        for r in [0.01, 1.0, 10.0] {
            for phi in [0.0, 1.0, 3.0] {
                assert_eq!(view.eval(rho, beyond, r, phi), Some(0.0));
                assert_eq!(view.pdf(rho, beyond, r, phi), 0.0);
            }
        }
        assert!(view.sample(rho, beyond, 0.5, 0.5).is_none());
        assert_eq!(view.effective_albedo(rho, beyond), Some(0.0));
        assert!(view.effective_albedo(rho, 0.3).unwrap() > 0.0);
    }
}

#[test]
fn two_lobe_tables_pass_where_one_lobe_fails() {
    // η = 1.2 on the default grid: one lobe is above the report's figures at grazing incidence
    // and fails the check (up to 1.5 % mean in a region); two lobes pass in every region.
    let two = crate::lookup::two_lobe_table();
    let result = check(&two.view(), Moments::Exact, CHECK_BOUNDS).unwrap();
    assert!(result.passes(), "{result:?}");
    let worst = result
        .regions
        .iter()
        .map(|r| r.mean_rel_error)
        .fold(0.0, f64::max);
    assert!(worst < 0.005, "worst region mean {worst}");
    let (one, _) = bssrdf_zoo::table::bake_lobes(
        1.2,
        Moments::Exact,
        &Grid::preset(GridPreset::Default),
        true,
        bssrdf_zoo::table::Lobes::One,
    )
    .unwrap();
    assert!(one.harmonics().is_none());
    // Above ρ′ = 0.3 at 75–90° (below, the low-albedo tails dominate either table's error)
    let grazing = |t: &AngularTable| {
        let r = check(&t.view(), Moments::Exact, CHECK_BOUNDS).unwrap();
        r.regions
            .iter()
            .filter(|r| r.theta_deg[0] >= 75.0 && r.rho[0] >= 0.3)
            .map(|r| r.mean_rel_error)
            .fold(0.0, f64::max)
    };
    let (two, one) = (grazing(two), grazing(&one));
    assert!(two * 5.0 < one, "two lobes {two}, one {one}");
}
