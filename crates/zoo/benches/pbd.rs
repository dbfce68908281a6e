//! One photon-beam-diffusion evaluation with each quadrature (the reference, the fast rule and the
//! two-lobe bake's node rule), at representative points (normal
//! incidence, oblique, grazing, a beam just under the exit point at η ≈ 1, small r), against a
//! fixed arithmetic baseline in the same run. Run: `cargo bench -p bssrdf-zoo --bench pbd`; docs/performance.md gives
//! each evaluation as a ratio to `baseline/exp_sqrt_64`.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use criterion::{black_box, criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let deg = f64::to_radians;
    let points = [
        ("theta0_r1", 0.9, 1.33, 0.0, 1.0, 0.0),
        ("theta60_r0.1", 0.9, 1.33, deg(60.0), 0.1, 0.3),
        ("theta89_r1", 0.9, 1.33, deg(89.0), 1.0, 0.0),
        ("eta1.0001_theta90_r19", 0.96, 1.0001, deg(90.0), 18.8, 0.0),
        ("theta60_r1e-9", 0.5, 1.33, deg(60.0), 1e-9, 2.0),
    ];
    let mut group = c.benchmark_group("pbd_eval");
    // The baseline: 64 exponentials and square roots, about one panel's worth of integrand work.
    group.bench_function("baseline/exp_sqrt_64", |b| {
        b.iter(|| {
            (0..64)
                .map(|i| {
                    let x = black_box(0.1) + f64::from(i) * 0.01;
                    (-x).exp() * x.sqrt()
                })
                .sum::<f64>()
        })
    });
    for (name, rho, eta, theta, r, phi) in points {
        let pbd = Pbd::new(rho, Boundary::new(eta, Moments::Exact).unwrap()).unwrap();
        for (rule_name, rule) in [("reference", Rule::Reference), ("fast", Rule::Fast)] {
            group.bench_function(format!("{rule_name}/{name}"), |b| {
                b.iter(|| pbd.eval(black_box(theta), black_box(r), black_box(phi), rule))
            });
        }
        // The rule two-lobe bakes fit their nodes through (`Pbd::eval_node`)
        group.bench_function(format!("node/{name}"), |b| {
            b.iter(|| pbd.eval_node(black_box(theta), black_box(r), black_box(phi)))
        });
    }
    group.finish();
    c.bench_function("boundary_exact_moments", |b| {
        b.iter(|| Boundary::new(black_box(1.33), Moments::Exact))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
