//! Random-walk throughput: scattering events per second on one core.
//!
//! `cargo bench -p bssrdf-zoo --bench walk`. Each case runs on a one-thread rayon pool; criterion's
//! throughput line ("thrpt", elements/s) is scattering events per second per core. The event
//! count of a case is fixed by its seed, so it is measured once and set as the throughput.

use bssrdf_zoo::walk::{run, Bins, Config, Geometry};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};

fn cases() -> Vec<(&'static str, Config)> {
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

fn bench_walk(c: &mut Criterion) {
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("cannot build a one-thread pool: {e}");
            return;
        }
    };
    let mut group = c.benchmark_group("walk events per core");
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(10));
    for (name, config) in cases() {
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

criterion_group!(benches, bench_walk);
criterion_main!(benches);
