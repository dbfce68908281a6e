//! One photon-beam-diffusion evaluation with each quadrature, at a few representative points
//! (normal incidence, oblique, grazing). Run: `cargo bench --bench pbd`.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use criterion::{black_box, criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let boundary = Boundary::new(1.33, Moments::Exact).unwrap();
    let pbd = Pbd::new(0.9, boundary).unwrap();
    let points = [
        ("theta0_r1", 0.0f64, 1.0, 0.0),
        ("theta60_r0.1", 60f64.to_radians(), 0.1, 0.3),
        ("theta89_r1", 89f64.to_radians(), 1.0, 0.0),
    ];
    let mut group = c.benchmark_group("pbd_eval");
    for (name, theta, r, phi) in points {
        for (rule_name, rule) in [("reference", Rule::Reference), ("fast", Rule::Fast)] {
            group.bench_function(format!("{rule_name}/{name}"), |b| {
                b.iter(|| pbd.eval(black_box(theta), black_box(r), black_box(phi), rule))
            });
        }
    }
    group.finish();
    c.bench_function("boundary_exact_moments", |b| {
        b.iter(|| Boundary::new(black_box(1.33), Moments::Exact))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
