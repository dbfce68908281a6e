//! The angular table baked from the walk (`table::bake_walk`): its lookups hold to the rules of
//! every table, its sampler follows its pdf, the bake is deterministic on any thread count, and
//! its reflectance is an independent walk's.

use std::sync::OnceLock;

use bssrdf_testkit::lookups::{check_view, inputs};
use bssrdf_zoo::rng::{RngCore, SeedableRng, SplitMix64};
use bssrdf_zoo::table::{bake_walk, AngularTable, Grid, GridPreset, Lobes, WalkBake};
use bssrdf_zoo::walk::{self, Config};

use crate::lookup::samples_follow_the_pdf_at;

/// Photons per θ node of the bake of these tests.
const PHOTONS: u64 = 50_000;

/// A small walk bake at η = 1.33, g = 0: the default albedo rows below 0.99, and 0.99 (one group of
/// rows: one walk per θ node), five angles to grazing, the default two-lobe radii.
fn config(photons: u64) -> WalkBake {
    let default = GridPreset::Default.grid(1.33, Lobes::Two);
    WalkBake {
        eta: 1.33,
        g: 0.0,
        grid: Grid {
            rho: (default.rho.into_iter().filter(|&p| p < 0.99))
                .chain([0.99])
                .collect(),
            theta: [0.0, 30.0, 60.0, 80.0, 90.0f64]
                .map(f64::to_radians)
                .to_vec(),
            r: default.r,
        },
        photons,
        seed: 3,
        theta_sampling: true,
    }
}

fn table() -> &'static AngularTable {
    static TABLE: OnceLock<AngularTable> = OnceLock::new();
    TABLE.get_or_init(|| bake_walk(&config(PHOTONS), &|_| {}).unwrap().0)
}

#[test]
fn walk_table_reflectance_is_an_independent_walks() {
    // ρ_eff of the table (its radial CDF's end) against the multiple-scattering reflectance of
    // `walk::run` (another seed, 10⁵ photons, its own tally). The bake's estimate has about the
    // variance of a walk of its photons, σ² ≈ σ_run² · 10⁵/PHOTONS; beyond 4 combined σ, 0.5 %
    // for the spline's integral and the residual of PBD's correction of the kernel averages
    // (within 0.7 % at 2·10⁵ photons, measured; without the correction the table is 2–2.8 %
    // high).
    let view = table().view();
    let cases = [
        (0.5, 0.0),
        (0.9, 60.0),
        (0.99, 30.0),
        (0.8, 90.0),
        (0.2, 80.0),
        (0.95, 45.0),
    ];
    for (rho, theta_deg) in cases {
        let theta = f64::to_radians(theta_deg);
        let table = view.effective_albedo(rho, theta).unwrap();
        let run = walk::run(&Config {
            photons: 100_000,
            seed: 17,
            ..Config::new(rho, 0.0, 1.33, theta)
        })
        .unwrap();
        let r = run.multiple_reflectance();
        let sigma = r.stderr * (1.0 + 100_000.0 / PHOTONS as f64).sqrt();
        let bound = 4.0 * sigma + 0.005 * r.value;
        assert!(
            (table - r.value).abs() <= bound,
            "{rho} {theta_deg}°: table {table}, walk {} ± {}",
            r.value,
            r.stderr
        );
    }
}

#[test]
fn walk_table_samples_follow_its_pdf() {
    samples_follow_the_pdf_at(
        table(),
        &[(0.5, 0.0), (0.9, 60.0), (0.99, 89.0), (0.3, 75.0)],
    );
}

#[test]
fn walk_table_lookups_at_arbitrary_inputs_are_valid() {
    let view = table().view();
    let mut rng = SplitMix64::seed_from_u64(29);
    let (rounds, mut drawn) = (4000, 0);
    for _ in 0..rounds {
        let selectors = [0; 9].map(|_| rng.next_u64() as u8);
        let bits = [0; 9].map(|_| rng.next_u64());
        drawn += check_view(&view, &inputs(&view, selectors, bits));
    }
    assert!(drawn > rounds / 4, "{drawn} draws in {rounds} rounds");
}

#[test]
fn walk_bake_is_bit_identical_on_any_thread_count() {
    let mut config = config(bssrdf_zoo::table::MIN_HARMONICS_PHOTONS + 5);
    config.grid.theta = vec![0.0, 1.0];
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| bake_walk(&config, &|_| {}).unwrap().0)
    };
    assert_eq!(run(1), run(2));
}
