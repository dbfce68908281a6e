//! Every lookup of a table at arbitrary inputs — NaN, ±∞, subnormals, ±0, huge, out of range,
//! random numbers anywhere in f64 — on the tables of `bssrdf_testkit::lookups::tables` (the default grid,
//! scene subsets, no θ sampling, the ends of the η domain, pbrt's moments, a short radius
//! axis): no panic, no NaN or negative value or density, and each draw either `None` or a
//! valid point whose density is `pdf`'s. The fuzz target `fuzz/fuzz_targets/lookups.rs` holds
//! the same rules (same code) over many more inputs.

use std::sync::OnceLock;

use bssrdf_zoo::rng::{RngCore, SeedableRng, SplitMix64};
use bssrdf_zoo::table::AngularTable;
use proptest::prelude::*;

use crate::lookup::default_table;
use bssrdf_testkit::lookups::{check_view, inputs, tables};

fn fixtures() -> &'static [(&'static str, AngularTable)] {
    static TABLES: OnceLock<Vec<(&'static str, AngularTable)>> = OnceLock::new();
    TABLES.get_or_init(|| tables(default_table().clone()))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn table_lookups_at_arbitrary_inputs_are_valid(
        t in 0..8usize,
        selectors in any::<[u8; 9]>(),
        bits in any::<[u64; 9]>(),
    ) {
        let (_, table) = &fixtures()[t % fixtures().len()];
        let view = table.view();
        check_view(&view, &inputs(&view, selectors, bits));
    }
}

/// The same rules over a fixed stream of inputs, counting the draws: most inputs lie inside
/// the tables, so most rounds must draw points (the rules are not met by drawing nothing).
#[test]
fn most_arbitrary_inputs_draw_valid_points() {
    let mut rng = SplitMix64::seed_from_u64(23);
    for (name, table) in fixtures() {
        let view = table.view();
        let (rounds, mut drawn) = (4000, 0);
        for _ in 0..rounds {
            let selectors = [0; 9].map(|_| rng.next_u64() as u8);
            let bits = [0; 9].map(|_| rng.next_u64());
            drawn += check_view(&view, &inputs(&view, selectors, bits));
        }
        // Three draws a round; each number is in its domain with probability 5/8 or more.
        assert!(
            drawn > rounds / 4,
            "{name}: {drawn} draws in {rounds} rounds"
        );
    }
}

/// Regression: ρ_eff was negative where the θ spline undershoots, between the lit node at 30°
/// and the unlit ones at 60° and 90° of an η = 0.75 table (no light enters beyond 48.6°):
/// −0.022 at ρ′ = 1, θ = 70°; and −5e-48 on the default grid at ρ′ = 2e-24, θ = 83.5°, where
/// the f32 weights (ρ′/ρ′ᵢ)² round.
#[test]
fn effective_albedo_is_never_negative() {
    let find = |name: &str| &fixtures().iter().find(|(n, _)| *n == name).unwrap().1;
    let (below, full) = (find("eta 0.75").view(), find("full").view());
    for theta_deg in [50.0, 60.0, 70.0, 80.0, 90.0] {
        let a = below.effective_albedo(1.0, f64::to_radians(theta_deg));
        assert!(a.is_some_and(|a| a >= 0.0), "{theta_deg}: {a:?}");
    }
    let a = full.effective_albedo(2.042615324830291e-24, f64::to_radians(83.5));
    assert!(a.is_some_and(|a| a >= 0.0), "{a:?}");
}

/// Regression: a NaN random number for a uniform azimuth (φ of the perpendicular model, φ′ of
/// the path draw) gave a NaN azimuth, then φ = −π (read as 0): a broken random stream drew a
/// plausible point. It now draws nothing.
#[test]
fn a_nan_random_number_draws_nothing() {
    let view = fixtures()[0].1.view();
    assert!(view.sample_path(0.5, [0.3, 0.4, 0.5, 0.6]).is_some());
    assert!(view.sample_path(0.5, [0.3, 0.4, 0.5, f64::NAN]).is_none());
    assert!(view.sample_perpendicular(0.5, 0.4, 0.6).is_some());
    assert!(view.sample_perpendicular(0.5, 0.4, f64::NAN).is_none());
}

/// Every uniform of a draw is in [0, 1), as the C header and Python say: a finite azimuthal
/// uniform outside was clamped (u_φ = 7 or 1e300 drew φ = π) and the path draw's u[0] = 1 drew
/// θ = 90°, where Python refused both. A draw from the largest uniform below 1 works.
#[test]
fn a_uniform_outside_0_1_draws_nothing() {
    let view = fixtures()[0].1.view();
    let below_one = 1.0 - f64::EPSILON / 2.0;
    assert!(view.sample(0.5, 0.3, 0.4, below_one).is_some());
    assert!(view
        .sample_path(0.5, [below_one, 0.4, below_one, below_one])
        .is_some());
    for u in [
        1.0,
        7.0,
        1e300,
        -3.0,
        -f64::MIN_POSITIVE,
        f64::INFINITY,
        f64::NAN,
    ] {
        assert!(view.sample(0.5, 0.3, 0.4, u).is_none(), "u_phi {u}");
        assert!(
            view.sample_perpendicular(0.5, 0.4, u).is_none(),
            "u_phi {u}"
        );
        for k in 0..4 {
            let mut uniforms = [0.3, 0.4, 0.5, 0.6];
            uniforms[k] = u;
            assert!(view.sample_path(0.5, uniforms).is_none(), "u[{k}] {u}");
        }
    }
}

/// Below η = 1 the θ axis ends at the critical angle rounded to f32, a little above asin η:
/// a path draw whose θ uniform was within about 10⁻⁷ of 1 fell between the two and drew
/// nothing (3.7·10⁻⁸ of uniforms at η = 0.75, found from outside). It draws the critical
/// angle now, with its density.
#[test]
fn a_path_draw_at_the_end_of_the_theta_uniform_is_lit_below_eta_1() {
    use bssrdf_zoo::table::{bake, GridPreset, Lobes};
    let grid = GridPreset::Coarse.grid(0.75, Lobes::One);
    let (table, _) = bake(0.75, bssrdf_zoo::fresnel::Moments::Exact, &grid, true).unwrap();
    let view = table.view();
    let last = f64::from(1.0f32 - f32::EPSILON / 2.0);
    for u0 in [0.999_999_97, 1.0 - 1e-12, 1.0 - f64::EPSILON / 2.0, last] {
        let p = view.sample_path(0.5, [u0, 0.3, 0.4, 0.5]);
        let p = p.unwrap_or_else(|| panic!("u0 = {u0}: no draw"));
        assert!(p.theta <= 0.75f64.asin() + 1e-15, "u0 = {u0}: {}", p.theta);
        assert_eq!(p.pdf_theta, view.pdf_theta(0.5, p.theta), "u0 = {u0}");
        assert!(p.pdf_theta > 0.0 && p.pdf > 0.0, "u0 = {u0}");
    }
}
