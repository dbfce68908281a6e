//! One evaluation of every model of the zoo through the `Model` trait (dynamic dispatch, as the
//! comparison and a renderer would call it), at ρ′ = 0.9, η = 1.33, θ = 60°, r = 1 mfp,
//! φ = 0.5 rad; and one draw of each sampler. Run: `cargo bench -p bssrdf-zoo --bench models`.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::models::mc::McOptions;
use bssrdf_zoo::models::table::TableSource;
use bssrdf_zoo::models::{build, ModelKind, Options, Params};
use bssrdf_zoo::table::{bake, Grid, GridPreset};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    let (eta, rho, theta, r, phi) = (1.33, 0.9, 60f64.to_radians(), 1.0, 0.5);
    let params = Params::new(rho, eta, Moments::Exact).unwrap();
    let (table, _) = bake(
        eta,
        Moments::Exact,
        &Grid::preset(GridPreset::Default),
        false,
    )
    .unwrap();
    let options = Options {
        table: TableSource::Shared(Arc::new(table)),
        mc: McOptions {
            theta,
            photons: 100_000,
            ..McOptions::default()
        },
        ..Options::default()
    };
    let models: Vec<_> = ModelKind::ALL
        .iter()
        .map(|&k| build(k, &params, &options).unwrap())
        .collect();

    let mut group = c.benchmark_group("model_eval");
    for m in &models {
        group.bench_function(m.kind().name(), |b| {
            b.iter(|| m.eval(black_box(theta), black_box(r), black_box(phi)))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("model_sample");
    for m in models
        .iter()
        .filter(|m| m.sample(theta, [0.3, 0.6]).is_some())
    {
        group.bench_function(m.kind().name(), |b| {
            b.iter(|| m.sample(black_box(theta), black_box([0.3, 0.6])))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
