//! Properties of every registered model: finite and non-negative over the extreme grid (or a
//! documented +∞), even in φ, zero where no light enters, scaling with σ′t in world units,
//! totals against the plane integral of `eval`, and constructor rejections naming the value.

use bssrdf_testkit::models::{documented_infinity, model, options, table_for};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Medium;
use bssrdf_zoo::models::burley::{BurleyFit, BurleyOptions, SurfaceAlbedo};
use bssrdf_zoo::models::dirpole::{Dirpole, DirpoleOptions};
use bssrdf_zoo::models::table::{Mode, TableModel, TableSource};
use bssrdf_zoo::models::{build, integrate_total, Model, ModelKind, Options, Params, World};
use bssrdf_zoo::table::{bake, Grid};
use std::f64::consts::PI;
use std::sync::Arc;

const RHOS: [f64; 5] = [0.0, 1e-9, 0.5, 1.0 - 1e-9, 1.0];
/// Both ends of the η domain, index matching and just above it.
const ETAS: [f64; 5] = [0.75, 1.0, 1.0001, 1.33, 2.5];
/// r = 0, the smallest subnormal and others below the smallest normal, up to 10⁴ mfp.
const R: [f64; 9] = [0.0, 5e-324, 1e-310, 1e-100, 1e-12, 1.0, 300.0, 1e4, 1e300];
const PHIS: [f64; 4] = [0.0, PI, -PI, 1e-300];

fn thetas() -> [f64; 4] {
    [0.0, 1e-300, 89.99f64.to_radians(), 0.5 * PI]
}

fn no_light_enters(eta: f64, theta: f64) -> bool {
    theta.sin() > eta
}

fn check_extremes(kind: ModelKind) {
    for eta in ETAS {
        for rho in RHOS {
            for theta in thetas() {
                // Only the walk depends on θ at construction.
                let built = model(kind, rho, eta, theta, 32);
                let m = match built {
                    Ok(m) => m,
                    Err(e) => {
                        // The walk cannot normalise by entering power when none enters.
                        assert!(
                            kind == ModelKind::MonteCarlo && no_light_enters(eta, theta),
                            "{kind} rho {rho} eta {eta} theta {theta}: {e}"
                        );
                        assert!(e.to_string().contains("theta"), "{e}");
                        continue;
                    }
                };
                for r in R {
                    for phi in PHIS {
                        let v = m.eval(theta, r, phi);
                        let at =
                            format!("{kind} rho {rho} eta {eta} theta {theta} r {r} phi {phi}");
                        assert!(v >= 0.0, "{at}: {v}");
                        if !documented_infinity(kind, eta, theta, r, phi) {
                            assert!(v.is_finite(), "{at}: {v}");
                        }
                        if no_light_enters(eta, theta) {
                            assert_eq!(v, 0.0, "{at}");
                        }
                        let mirrored = m.eval(theta, r, -phi);
                        assert!(
                            v == mirrored || (v - mirrored).abs() <= 1e-12 * v.abs(),
                            "{at}: {v} vs {mirrored} at -phi"
                        );
                    }
                    // A generic azimuth too: evenness away from the special angles.
                    let (a, b) = (m.eval(theta, r, 0.7), m.eval(theta, r, -0.7));
                    assert!(
                        a == b || (a - b).abs() <= 1e-12 * a.abs(),
                        "{kind}: {a} vs {b}"
                    );
                }
                if rho == 0.0 {
                    // Nothing scatters: nothing leaves (the directional dipole's documented 0).
                    assert_eq!(m.eval(theta, 1.0, 0.3), 0.0, "{kind} eta {eta}");
                }
            }
        }
    }
}

#[test]
fn dipole_is_finite_non_negative_and_even_over_the_extreme_grid() {
    check_extremes(ModelKind::Dipole);
}

#[test]
fn dirpole_is_finite_non_negative_and_even_over_the_extreme_grid() {
    check_extremes(ModelKind::Dirpole);
}

#[test]
fn burley_is_finite_non_negative_and_even_over_the_extreme_grid() {
    check_extremes(ModelKind::Burley);
}

#[test]
fn pbd_is_finite_non_negative_and_even_over_the_extreme_grid() {
    check_extremes(ModelKind::Pbd);
    check_extremes(ModelKind::PbdFast);
}

#[test]
fn tables_are_finite_non_negative_and_even_over_the_extreme_grid() {
    check_extremes(ModelKind::Table);
    check_extremes(ModelKind::Perpendicular);
}

#[test]
fn monte_carlo_is_finite_non_negative_and_even_over_the_extreme_grid() {
    check_extremes(ModelKind::MonteCarlo);
}

#[test]
fn world_units_scale_with_the_reduced_extinction() {
    // σ′t = 1 and σ′t = 4 (a power of two: r/4 and ρ′ = 3/4 are exact, so even the walk and the
    // bin lookups see identical reduced inputs). R_world(r/k; kσ′t) = k² R_world(r; σ′t).
    let k = 4.0;
    let theta = 0.9;
    let base = Medium::new(0.75, 0.25, 0.0, 1.33).unwrap();
    let scaled = Medium::new(0.75 * k, 0.25 * k, 0.0, 1.33).unwrap();
    let opts = options(1.33, theta, 2000);
    for kind in ModelKind::ALL {
        let w1 = World::for_medium(kind, &base, Moments::Exact, &opts).unwrap();
        let w2 = World::for_medium(kind, &scaled, Moments::Exact, &opts).unwrap();
        for (r, phi) in [(0.037, 0.2), (0.61, 2.9), (3.3, -1.1)] {
            let (a, b) = (w1.eval(theta, r, phi), w2.eval(theta, r / k, phi));
            assert!(a > 0.0, "{kind} r {r}");
            assert!(
                (b - k * k * a).abs() <= 1e-12 * b,
                "{kind} r {r}: {b} vs {}",
                k * k * a
            );
            let (p1, p2) = (w1.pdf(theta, r, phi), w2.pdf(theta, r / k, phi));
            assert!((p2 - k * k * p1).abs() <= 1e-12 * p2.abs(), "{kind} pdf");
        }
        if let (Some(s1), Some(s2)) = (w1.sample(theta, [0.3, 0.6]), w2.sample(theta, [0.3, 0.6])) {
            assert!((s1.r - k * s2.r).abs() <= 1e-12 * s1.r, "{kind} sample r");
            assert!(
                (s2.pdf - k * k * s1.pdf).abs() <= 1e-12 * s2.pdf,
                "{kind} sample pdf"
            );
        }
        assert_eq!(
            w1.effective_albedo(theta),
            w2.effective_albedo(theta),
            "{kind}"
        );
    }
}

#[test]
fn effective_albedo_is_the_plane_integral_of_eval() {
    // Independent computations of the total (closed forms, PBD's swapped integration order,
    // the table's radial CDF) against nested quadrature of `eval`.
    let (rho, eta, theta) = (0.8, 1.33, 1.0);
    for (kind, tol) in [
        (ModelKind::Dipole, 1e-6),
        (ModelKind::Burley, 1e-6),
        (ModelKind::Pbd, 1e-5),
        (ModelKind::PbdFast, 1e-5),
        // The table's total is the plain spline's; evaluation refines the spline in ln E and on
        // the first interval (table module docs): they differ by the interpolation error.
        (ModelKind::Table, 2e-2),
        (ModelKind::Perpendicular, 2e-2),
    ] {
        let m = model(kind, rho, eta, theta, 2000).unwrap();
        let total = m.effective_albedo(theta).unwrap();
        let integral = integrate_total(&*m, theta);
        assert!(
            (total - integral).abs() < tol * total,
            "{kind}: {total} vs {integral}"
        );
    }
}

#[test]
fn directional_dipole_negative_lobe_is_clamped_to_zero() {
    // notes-models §1.4 item 4: η = 1, θ = 85°, backward (φ = 180°), r = 0.1, α′ = 0.5.
    let m = Dirpole::new(
        Params::new(0.5, 1.0, Moments::Exact).unwrap(),
        DirpoleOptions::default(),
    );
    let theta = 85f64.to_radians();
    let geometry = Dirpole::flat_geometry(theta, 0.1, PI);
    assert!(m.s_d_signed(&geometry) < 0.0);
    assert_eq!(m.eval(theta, 0.1, PI), 0.0);
    assert!(m.eval(theta, 0.1, 0.0) > 0.0);
}

#[test]
fn constructors_reject_bad_values_and_name_them() {
    let p = Params::new(0.5, 1.33, Moments::Exact).unwrap();
    let err = |r: bssrdf_zoo::Result<Box<dyn Model>>| r.err().expect("rejected").to_string();

    let mut o = options(1.33, 0.0, 100);
    o.burley = BurleyOptions {
        fit: BurleyFit::Searchlight,
        albedo: SurfaceAlbedo::Given(1.5),
    };
    assert!(err(build(ModelKind::Burley, &p, &o)).contains("surface albedo A = 1.5"));

    o.burley = BurleyOptions {
        fit: BurleyFit::DiffuseMeanFreePath,
        albedo: SurfaceAlbedo::Pbd,
    };
    let white = Params::new(1.0, 1.33, Moments::Exact).unwrap();
    assert!(err(build(ModelKind::Burley, &white, &o)).contains("sigma_tr"));

    let o = options(1.0, 0.0, 100); // a table baked for η = 1
    let e = err(build(ModelKind::Table, &p, &o));
    assert!(e.contains("table eta") && e.contains("1.33"), "{e}");

    let narrow = Grid {
        rho: vec![0.6, 0.7, 0.8, 0.9],
        ..bssrdf_testkit::models::small_grid()
    };
    let (t, _) = bake(1.33, Moments::Exact, &narrow, false).unwrap();
    let shared = TableSource::Shared(Arc::new(t));
    let e = TableModel::new(&p, &shared, Mode::Angular)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rho'") && e.contains("0.5"), "{e}");

    let o = options(0.75, 1.2, 100); // sin 1.2 > 0.75: no light enters
    let low = Params::new(0.5, 0.75, Moments::Exact).unwrap();
    assert!(err(build(ModelKind::MonteCarlo, &low, &o)).contains("theta"));

    assert!(build(ModelKind::Dipole, &p, &Options::default()).is_ok());
}

#[test]
fn the_shared_table_is_the_one_in_use() {
    let p = Params::new(0.5, 2.5, Moments::Exact).unwrap();
    let table = table_for(2.5);
    let m = TableModel::new(&p, &TableSource::Shared(Arc::clone(&table)), Mode::Angular).unwrap();
    assert!(Arc::ptr_eq(m.table(), &table));
}

#[test]
fn every_model_refuses_eta_and_extinction_outside_the_domain() {
    // Every model is built from Params, which enforces η ∈ [0.75, 2.5] (as do Medium, Boundary
    // and the walk); the message names the value and the range.
    for eta in [1e6, 100.0, 2.51, 0.74, 0.0, -1.33] {
        let err = Params::new(0.5, eta, Moments::Exact)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!("eta = {}", bssrdf_zoo::error::number(eta)))
                && err.contains("[0.75, 2.5]"),
            "{err}"
        );
        let err = Medium::new(1.0, 1.0, 0.0, eta).unwrap_err().to_string();
        assert!(err.contains("[0.75, 2.5]"), "{err}");
    }
    for eta in [f64::NAN, f64::INFINITY] {
        assert!(Params::new(0.5, eta, Moments::Exact).is_err());
    }
    // σ′t = 1e308 + 1e308 overflows to ∞ (it stored ρ′ = 0 and σ′t = ∞); far below any medium,
    // σ′t² of the world-unit conversion would underflow.
    for (s, a) in [(1e308, 1e308), (1e13, 0.0), (0.0, 1e-10)] {
        let err = Medium::new(s, a, 0.0, 1.33).unwrap_err().to_string();
        assert!(
            err.contains("sigma_t'") && err.contains("[1e-9, 1e12]"),
            "{err}"
        );
    }
}
