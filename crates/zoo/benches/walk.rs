//! Random-walk throughput on one core: photons per second on the case of issue 22 (a
//! half-space, albedo 0.9, η = 1.33, normal incidence, g = 0 and g = 0.9, the case MCML 1.2.2
//! was timed on), and scattering events per second on three more.
//!
//! `cargo bench -p bssrdf-zoo --bench walk`. Each case runs on a one-thread rayon pool;
//! criterion's throughput line ("thrpt", elements/s) is photons per second in the first group
//! and scattering events per second in the second. The event count of a case is fixed by its
//! seed, so it is measured once and set as the throughput.
//!
//! After criterion, a gate: each g of the issue's case runs [`GATE_PHOTONS`] photons
//! [`GATE_RUNS`] times, the two g alternating, and the fastest run of each counts (on a shared
//! machine the fastest run is the one the least disturbed). It prints photons per second and
//! variance × time, the squared standard error of the total diffuse reflectance times the
//! run's seconds (independent of the photon count: the smaller, the more efficient), and holds
//! the rate to its floor ([`FLOORS`]): under `cargo bench` the benchmark fails, naming the
//! figure, when a rate is below it.

use bssrdf_zoo::walk::{run, Bins, Config, Geometry};
use criterion::{black_box, Criterion, Throughput};
use std::time::Instant;

/// Photons of one gate run.
const GATE_PHOTONS: u64 = 100_000;
/// Gate runs per g; the fastest counts.
const GATE_RUNS: usize = 7;
/// The floors of the gate, photons per second on one core: MCML 1.2.2's rates on the same case
/// as issue 22 measured them (412k at g = 0, 214k at g = 0.9).
const FLOORS: [(f64, f64); 2] = [(0.0, 412_000.0), (0.9, 214_000.0)];

/// The issue's case: half-space, albedo 0.9, η = 1.33, θ = 0, seed 1.
fn issue_case(g: f64, photons: u64) -> Config {
    Config {
        photons,
        seed: 1,
        ..Config::new(0.9, g, 1.33, 0.0)
    }
}

fn event_cases() -> Vec<(&'static str, Config)> {
    let base = |albedo, g, eta, theta_deg: f64| Config {
        photons: 20_000,
        seed: 1,
        bins: Bins::default(),
        ..Config::new(albedo, g, eta, theta_deg.to_radians())
    };
    vec![
        (
            "half-space a=0.9 g=0.5 eta=1.3 theta=30",
            base(0.9, 0.5, 1.3, 30.0),
        ),
        (
            "half-space a=0.99 g=0 eta=1 theta=0",
            base(0.99, 0.0, 1.0, 0.0),
        ),
        (
            "slab tau=2 a=0.9 g=0.75 eta=1 theta=0",
            Config {
                geometry: Geometry::Slab { thickness: 2.0 },
                ..base(0.9, 0.75, 1.0, 0.0)
            },
        ),
    ]
}

fn bench_walk(c: &mut Criterion, pool: &rayon::ThreadPool) {
    let mut group = c.benchmark_group("walk photons per core");
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(10));
    for (g, _) in FLOORS {
        let config = issue_case(g, 20_000);
        group.throughput(Throughput::Elements(config.photons));
        group.bench_function(format!("half-space a=0.9 g={g} eta=1.33 theta=0"), |b| {
            b.iter(|| {
                pool.install(|| run(black_box(&config)))
                    .map(|r| r.photons())
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("walk events per core");
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(10));
    for (name, config) in event_cases() {
        let events = match pool.install(|| run(&config)) {
            Ok(r) => r.scattering_events(),
            Err(e) => {
                eprintln!("{name}: {e}");
                continue;
            }
        };
        group.throughput(Throughput::Elements(events));
        group.bench_function(name, |b| {
            b.iter(|| {
                pool.install(|| run(black_box(&config)))
                    .map(|r| r.scattering_events())
            })
        });
    }
    group.finish();
}

/// The gate: each g's fastest of [`GATE_RUNS`] runs, printed with its verdict; the verdicts
/// of the rates below their floors are returned.
fn gate(pool: &rayon::ThreadPool) -> Vec<String> {
    let mut best = [f64::INFINITY; FLOORS.len()];
    let mut variance = [f64::NAN; FLOORS.len()];
    for _ in 0..GATE_RUNS {
        for (k, (g, _)) in FLOORS.into_iter().enumerate() {
            let config = issue_case(g, GATE_PHOTONS);
            let start = Instant::now();
            let result = pool
                .install(|| run(&config))
                .expect("the issue's case is valid");
            best[k] = best[k].min(start.elapsed().as_secs_f64());
            variance[k] = result.total_reflectance().stderr.powi(2);
        }
    }
    let mut below = Vec::new();
    for (k, (g, floor)) in FLOORS.into_iter().enumerate() {
        let rate = GATE_PHOTONS as f64 / best[k];
        let figures = format!(
            "g = {g}: {rate:.0} photons/s, variance x time {:.3e} s",
            variance[k] * best[k]
        );
        let verdict = if rate < floor {
            below.push(format!(
                "walk {figures}, below the floor of {floor} photons/s"
            ));
            "BELOW"
        } else {
            "above"
        };
        println!("walk gate {figures}; {verdict} the floor of {floor} photons/s (MCML 1.2.2)");
    }
    below
}

fn main() {
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => panic!("cannot build a one-thread pool: {e}"),
    };
    let mut criterion = Criterion::default().configure_from_args();
    bench_walk(&mut criterion, &pool);
    let below = gate(&pool);
    criterion.final_summary();
    // The floors are a gate under `cargo bench` (`cargo test --benches` runs this once, as a
    // smoke test, on whatever load the machine has).
    if std::env::args().any(|a| a == "--bench") {
        assert!(
            below.is_empty(),
            "walk floors missed:\n{}",
            below.join("\n")
        );
    }
}
