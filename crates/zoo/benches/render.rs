//! Render throughput: photons per second on one core.
//!
//! `cargo bench -p bssrdf-zoo --bench render`. Each case traces a fixed number of photons of Ferrier's
//! figure 10 material at θ = 60° into a 256 × 256 picture on a one-thread rayon pool, the table
//! already baked (the bake is timed by `cargo bench -p bssrdf-zoo --bench table -- bake`). Criterion's
//! throughput line ("thrpt", elements/s) is photons per second per core; for `mc` a photon is
//! traced once in each of the three channels.

use bssrdf_zoo::models::ModelKind;
use bssrdf_zoo::render::{figure_10_material, Config, Renderer};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};

fn bench_render(c: &mut Criterion) {
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("cannot build a one-thread pool: {e}");
            return;
        }
    };
    let material = figure_10_material();
    let mut group = c.benchmark_group("render photons per core");
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(10));
    for (model, photons) in [
        (ModelKind::Table, 32_768),
        (ModelKind::Perpendicular, 32_768),
        (ModelKind::Pbd, 4_096),
        (ModelKind::MonteCarlo, 1_024),
    ] {
        let config = Config {
            photons,
            ..Config::new(model, 60f64.to_radians())
        };
        let renderer = match Renderer::new(&config, &material) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{}: {e}", model.name());
                continue;
            }
        };
        group.throughput(Throughput::Elements(photons));
        group.bench_function(model.name(), |b| {
            b.iter(|| pool.install(|| black_box(renderer.run(&|_| ())).stats.photons))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_render);
criterion_main!(benches);
