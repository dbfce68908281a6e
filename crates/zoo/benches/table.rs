//! The angular table: bake of the default grid, evaluate, sample, pdf and the path-tracing draw,
//! with the perpendicular model (pbrt's assumption: θ = 0 slice, uniform φ) measured in the same
//! run as the baseline, and the Catmull-Rom weights on each of the table's three axes (an
//! evaluation computes one set per axis), the same lookups on a two-lobe table (η = 1.2), and on
//! the η = 1 table with and without its ridge (`-- ridge`).
//! Run: `cargo bench -p bssrdf-zoo --bench table`, or `cargo bench -p bssrdf-zoo --bench table -- axes` for the weights
//! alone.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{bake, bake_lobes, Grid, GridPreset, Lobes, RidgeKind, TableRef};
use criterion::measurement::WallTime;
use criterion::{black_box, criterion_group, criterion_main, BenchmarkGroup, Criterion};

#[path = "support/lookup_points.rs"]
mod lookup_points;
use lookup_points::lookup_points;

/// The index after `i` in 0..n, cycling: a compare, not a `%` (a 64-bit division, tens of
/// cycles, that a timed closure would carry along with the lookup).
fn advance(i: &mut usize, n: usize) -> usize {
    *i = if *i + 1 < n { *i + 1 } else { 0 };
    *i
}

fn bench(c: &mut Criterion) {
    let grid = Grid::preset(GridPreset::Default);
    let mut group = c.benchmark_group("bake");
    group.sample_size(10);
    group.bench_function("default_grid_eta1.33", |b| {
        b.iter(|| bake(1.33, Moments::Exact, black_box(&grid), true).unwrap())
    });
    group.bench_function("default_grid_eta1.2_two_lobes", |b| {
        b.iter(|| bake(1.2, Moments::Exact, black_box(&grid), true).unwrap())
    });
    group.finish();

    let (table, _) = bake(1.33, Moments::Exact, &grid, true).unwrap();
    let view = table.view();
    let mut rng = SplitMix64::seed_from_u64(1);
    let points = lookup_points(&view, &mut rng);
    let uniforms: Vec<[f64; 4]> = (0..4096)
        .map(|_| {
            [
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
            ]
        })
        .collect();

    // The weights at the lookups' own (ρ′, θ, r), on the axes as baked (f32-rounded nodes)
    let axes = table.axes();
    let mut group = c.benchmark_group("axes");
    for (name, nodes, k) in [
        ("rho", axes.rho(), 0),
        ("theta", axes.theta(), 1),
        ("r", axes.r(), 2),
    ] {
        let xs: Vec<f64> = points.iter().map(|p| p[k]).collect();
        let mut i = 0usize;
        group.bench_function(format!("weights_{name}"), |b| {
            b.iter(|| nodes.weights(black_box(xs[advance(&mut i, xs.len())])))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("lookup");
    let mut i = 0usize;
    let mut next = |n: usize| advance(&mut i, n);
    group.bench_function("harness", |b| {
        // What the eval closure does besides eval: the time the figures below include
        b.iter(|| {
            let [rho, theta, r, phi] = points[next(points.len())];
            black_box(rho) + black_box(theta) + black_box(r) + black_box(phi)
        })
    });
    lookups(&mut group, &view, &points, &uniforms);
    group.bench_function("pdf", |b| {
        b.iter(|| {
            let [rho, theta, r, phi] = points[next(points.len())];
            view.pdf(
                black_box(rho),
                black_box(theta),
                black_box(r),
                black_box(phi),
            )
        })
    });
    group.bench_function("sample_path", |b| {
        b.iter(|| {
            let [rho, _, _, _] = points[next(points.len())];
            view.sample_path(black_box(rho), uniforms[next(uniforms.len())])
        })
    });
    group.finish();

    // A two-lobe table (η = 1.2, `table::Lobes`), with its own perpendicular baseline
    let (two, _) = bake(1.2, Moments::Exact, &grid, true).unwrap();
    let view = two.view();
    let mut group = c.benchmark_group("two_lobes");
    lookups(&mut group, &view, &points, &uniforms);
    group.finish();

    // The η = 1 table, whose lookups add the analytic ridge (`table::ridge`), and the same
    // arrays read without it: the ridge's cost as the ratio of the two groups
    let grid_1 = GridPreset::Default.grid(1.0, Lobes::for_eta(1.0));
    let (ridged, _) = bake_lobes(1.0, Moments::Exact, &grid_1, true, Lobes::Two).unwrap();
    assert!(ridged.ridge().is_some());
    for (name, view) in [
        ("ridge", ridged.view()),
        (
            "ridge_off_baseline",
            ridged.view().with_ridge(RidgeKind::None),
        ),
    ] {
        let mut group = c.benchmark_group(name);
        lookups(&mut group, &view, &points, &uniforms);
        group.finish();
    }
}

/// `eval`, `sample` and their perpendicular baselines (the ratios the docs report) of `view`
/// over the lookups' points, into `group`.
fn lookups(
    group: &mut BenchmarkGroup<'_, WallTime>,
    view: &TableRef<'_>,
    points: &[[f64; 4]],
    uniforms: &[[f64; 4]],
) {
    let mut i = 0usize;
    let mut next = |n: usize| advance(&mut i, n);
    group.bench_function("eval", |b| {
        b.iter(|| {
            let [rho, theta, r, phi] = points[next(points.len())];
            view.eval(
                black_box(rho),
                black_box(theta),
                black_box(r),
                black_box(phi),
            )
        })
    });
    group.bench_function("eval_perpendicular_baseline", |b| {
        b.iter(|| {
            let [rho, _, r, _] = points[next(points.len())];
            view.eval_perpendicular(black_box(rho), black_box(r))
        })
    });
    group.bench_function("sample", |b| {
        b.iter(|| {
            let [rho, theta, _, _] = points[next(points.len())];
            let u = uniforms[next(uniforms.len())];
            view.sample(black_box(rho), black_box(theta), u[0], u[1])
        })
    });
    group.bench_function("sample_perpendicular_baseline", |b| {
        b.iter(|| {
            let [rho, _, _, _] = points[next(points.len())];
            let u = uniforms[next(uniforms.len())];
            view.sample_perpendicular(black_box(rho), u[0], u[1])
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
