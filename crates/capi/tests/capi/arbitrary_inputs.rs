//! The C interface and the Rust handles at arbitrary inputs — ρ′ and σ′t of a medium, θ, r, φ
//! and the random numbers anywhere in f64 — on the tables of `bssrdf_testkit::lookups::tables` (a coarse
//! grid, scene subsets, no θ sampling, the ends of the η domain, pbrt's moments, a short radius
//! axis), in one mapped file: a medium is refused or its handle's lookups are valid (no NaN or
//! negative value or density, draws valid with the density `pdf` gives), and the C interface
//! returns the Rust handle's statuses and values bit for bit. The fuzz target
//! `fuzz/fuzz_targets/lookups.rs` holds the same rules on the default grid.
#![allow(unsafe_code)]

use std::sync::OnceLock;

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{bake, reduced_to_mm, Grid, GridPreset};
use proptest::prelude::*;

use bssrdf_testkit::lookups::{
    check_capi, check_channel, density_matches, inputs, open_tables, Opened,
};

fn opened() -> &'static Opened {
    static OPENED: OnceLock<Opened> = OnceLock::new();
    OPENED.get_or_init(|| {
        let coarse = Grid::preset(GridPreset::Coarse);
        open_tables(bake(1.33, Moments::Exact, &coarse, true).unwrap().0)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    #[cfg_attr(miri, ignore = "a coarse bake and 2000 cases: hours under Miri")]
    fn c_and_rust_handles_at_arbitrary_inputs_are_valid_and_equal(
        t in 0..8usize,
        selectors in any::<[u8; 9]>(),
        bits in any::<[u64; 9]>(),
    ) {
        let opened = opened();
        let t = t % opened.rust.table_count();
        let table = opened.rust.table(t).unwrap();
        let x = inputs(&table.view(), selectors, bits);
        let rust = check_channel(&table, &x);
        // SAFETY: the open C handle of the file `opened.rust` maps.
        unsafe { check_capi(opened.c, t, rust.as_ref(), &x) };
    }
}

/// Regression: a draw with u_r = 1 lands on the last radius node; its distance in mm, r/σ′t
/// rounded up, converted back by σ′t·r_mm, passed the node by an ulp, where `pdf` is 0.
/// Distances in mm now round so that σ′t·r_mm never passes the reduced distance.
#[test]
#[cfg_attr(miri, ignore = "a coarse bake: minutes under Miri")]
fn a_draw_at_the_last_radius_node_keeps_its_density() {
    let table = opened().rust.table(0).unwrap();
    let r_max = *table.view().axes().r().as_slice().last().unwrap();
    let mut rounded_up = 0;
    for k in 0..2000 {
        let sigma_t = 0.5 + 0.137 * k as f64;
        rounded_up += usize::from(sigma_t * (r_max / sigma_t) > r_max);
        assert!(sigma_t * reduced_to_mm(r_max, sigma_t) <= r_max);
        let channel = table.medium(1.0, sigma_t).unwrap();
        let s = channel.sample(0.9, 1.0, 0.5).unwrap();
        let pdf = |r, phi| channel.pdf(0.9, r, phi);
        assert!(
            density_matches(s.pdf, pdf, s.r, s.phi, sigma_t * sigma_t),
            "{sigma_t}: {s:?} {}",
            pdf(s.r, s.phi)
        );
    }
    assert!(rounded_up > 0, "no sigma_t rounds the node up");
}

/// Regression, found by the `lookups` fuzz target: a path draw with u = 1 − 2⁻⁵³ for r lands
/// on a radius node far in the tail, where the radial density jumps by orders of
/// magnitude (the stored CDF's rounding); r in mm converted back landed on the node's other
/// side, and `pdf` there was 3·10⁷ times the draw's density. Where σ′t·r_mm does not give back
/// the drawn distance, the handles now return the density at the returned point. (The fuzzer's
/// u for θ was 1 − 2⁻⁵³ too, which on this η = 0.75 table draws θ next to the critical angle,
/// the last θ with light: the θ CDF takes nothing beyond it. θ's u is 0.9 here.)
#[test]
#[cfg_attr(miri, ignore = "a coarse bake: minutes under Miri")]
fn a_path_draw_on_a_radius_node_has_the_density_pdf_gives_there() {
    let table = opened().rust.table(4).unwrap();
    let almost_one = 1.0 - f64::EPSILON / 2.0;
    let sigma_t = 0.004930462918966473;
    let channel = table.medium(0.9992833137512208, sigma_t).unwrap();
    if let Some(last) = channel.sample_path([almost_one, almost_one, 0.1, 0.2]) {
        assert!(
            last.theta <= 0.75f64.asin() && last.pdf_theta > 0.0,
            "{last:?}"
        );
    }
    let u = [0.9, almost_one, 0.12846195697784424, 0.28879880207740494];
    let p = channel.sample_path(u).unwrap();
    let given = |r, phi| channel.pdf(p.theta, r, phi);
    let drawn = p.pdf / p.pdf_theta * std::f64::consts::TAU;
    assert!(
        density_matches(drawn, given, p.r, p.phi, sigma_t * sigma_t),
        "{p:?}: {drawn} against {}",
        given(p.r, p.phi)
    );
}

/// Regression, found by the `lookups` target: the density at a draw near φ = π, where a signed
/// floor's profile nears 0, became 0 an ulp of r away, where σ′t·r_mm lands when it does not
/// give back the drawn distance; so the handles return `pdf` at the returned point whenever
/// the conversion is inexact, not only on radius nodes.
#[test]
#[cfg_attr(miri, ignore = "a coarse bake: minutes under Miri")]
fn a_draw_where_the_profile_nears_zero_has_the_density_pdf_gives_there() {
    let table = opened().rust.table(7).unwrap();
    let sigma_t = 0.001;
    let channel = table.medium(0.8890624765766031, sigma_t).unwrap();
    let theta = 1.566243862943679;
    if let Some(s) = channel.sample(theta, 0.7304033041136804, 1.2212453270876722e-15) {
        let pdf = |r, phi| channel.pdf(theta, r, phi);
        assert!(
            density_matches(s.pdf, pdf, s.r, s.phi, sigma_t * sigma_t),
            "{s:?}: pdf {}",
            pdf(s.r, s.phi)
        );
    }
}
