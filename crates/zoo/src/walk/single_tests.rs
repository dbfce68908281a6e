//! Checks of the exact single scattering (single.rs) against references that share none of its
//! code: the depth integral at normal incidence and the angular formula of the reflectance
//! (tests.rs), adaptive quadrature over φ, and the walk's own single-scattering score.

use super::harmonics::unreduced_albedo;
use super::single::{surface_ridge_weight, SingleScattering, SINGLE_HARMONICS};
use super::tests::{
    harmonics_radii, kernel_average, single_scattering_exitance, single_scattering_reflectance,
    walk_harmonics, FAST_PHOTONS,
};
use super::Component;
use crate::quadrature::adaptive;
use std::f64::consts::{PI, TAU};

fn single(g: f64, eta: f64, theta_deg: f64) -> SingleScattering {
    SingleScattering::new(g, eta, theta_deg.to_radians()).unwrap()
}

#[test]
fn normal_incidence_matches_the_depth_integral() {
    // E₁(r) = ∫ e^{−z} p T e^{−d} μ/d² dz over the depth z (tests.rs), isotropic in φ; that
    // quadrature stops at an absolute 10⁻¹⁵, which bounds the comparison far out
    for (g, eta) in [(0.0, 1.0), (0.5, 1.4), (-0.3, 0.8), (0.9, 1.33)] {
        let s = single(g, eta, 0.0);
        for r in [0.003, 0.05, 0.7, 3.0, 12.0] {
            let exact = single_scattering_exitance(1.0, g, eta, r);
            let m = s.harmonics(r);
            let value = m[0] / TAU;
            let tol = (1e-7 * exact).max(1e-15);
            assert!(
                (value - exact).abs() <= tol,
                "g {g}, eta {eta}, r {r}: {value} vs {exact}"
            );
            assert!(m[1..].iter().all(|&x| x == 0.0));
            assert!((s.eval(r, 1.0) - exact).abs() <= tol);
        }
    }
}

/// ∫ r μ₀(r) dr over (0, ∞), as ∫ r² μ₀ d(ln r) from r = 10⁻⁷ (r·μ₀ is bounded as r → 0: what
/// lies below is < 10⁻⁶ of the total) to 80 mean free paths.
fn reflectance_of(s: &SingleScattering) -> f64 {
    let f = |u: f64| {
        let r = u.exp();
        r * r * s.harmonics(r)[0]
    };
    let breaks: Vec<f64> = [1e-7, 1e-3, 0.1, 1.0, 5.0, 20.0, 80.0]
        .iter()
        .map(|x: &f64| x.ln())
        .collect();
    adaptive(f, &breaks, 1e-8, 0.0, 400).value
}

#[test]
fn integrated_over_the_surface_it_is_the_angular_reflectance() {
    // R₁ = a ∫ p T μ/(μ + μ₀) dω over exit directions (tests.rs): no integral along the beam
    // and no surface point, so nothing in common with single.rs but the HG and Fresnel
    // formulas. Oblique, anisotropic, mismatched both ways, and grazing at index matching.
    for (g, eta, theta_deg) in [
        (0.5, 1.3, 60.0),
        (-0.3, 0.8, 30.0),
        (0.0, 1.33, 89.0),
        (0.9, 1.33, 80.0),
        (0.0, 1.0, 89.0),
        (0.9, 1.0, 60.0),
    ] {
        let s = single(g, eta, theta_deg);
        let surface = reflectance_of(&s);
        let angular = single_scattering_reflectance(1.0, g, eta, theta_deg.to_radians());
        println!("g {g}, eta {eta}, {theta_deg}°: {surface:.9} vs {angular:.9}");
        assert!(
            (surface - angular).abs() <= 2e-5 * angular,
            "g {g}, eta {eta}, {theta_deg}°: {surface} vs {angular}"
        );
    }
}

#[test]
fn the_panels_in_phi_agree_with_adaptive_quadrature() {
    // μ₀ and μ₂ by the harmonics' Gauss–Legendre panels against adaptive Gauss–Kronrod over φ,
    // where the forward peak is narrowest (η = 1 at 89°: cos θ′ = 0.017) and at η = 1.33
    for (g, eta, theta_deg) in [(0.0, 1.0, 89.0), (0.9, 1.0, 87.5), (0.0, 1.33, 60.0)] {
        let s = single(g, eta, theta_deg);
        let c = s.refracted_cos();
        for r in [0.003, 0.1, 1.0, 6.0] {
            let m = s.harmonics(r);
            for n in [0, 2] {
                let f = |phi: f64| 2.0 * s.eval(r, phi) * (n as f64 * phi).cos();
                let breaks: Vec<f64> = [0.0, c, 10.0 * c]
                    .into_iter()
                    .filter(|&x| x < PI)
                    .chain([PI])
                    .collect();
                let exact = adaptive(f, &breaks, 1e-10, 0.0, 400).value;
                assert!(
                    (m[n] - exact).abs() <= 1e-6 * m[0],
                    "eta {eta} {theta_deg}°, r {r}, n {n}: {} vs {exact}",
                    m[n]
                );
            }
        }
    }
}

#[test]
fn oblique_harmonics_match_the_walks_single_scattering() {
    // The walk's harmonics score single scattering apart (harmonics.rs), at each row's reduced
    // units: kernel averages of a·μₙ(r′/k)/k² against them, three rows from one walk at 50°,
    // g = 0.5, η = 1.4
    let (g, eta, theta_deg) = (0.5, 1.4, 50.0);
    let rho = [0.3, 0.95, 0.7];
    let h = walk_harmonics(&rho, g, theta_deg, FAST_PHOTONS, 9);
    let r = harmonics_radii();
    let s = single(g, eta, theta_deg);
    let (mut chi2, mut count) = (0.0, 0);
    for (row, &rho) in rho.iter().enumerate() {
        let a = unreduced_albedo(rho, g);
        for node in (1..r.len()).filter(|&i| r[i] < 2.0) {
            let mean = h.mean(Component::Single, row, node).unwrap();
            let se = h.stderr(Component::Single, row, node).unwrap();
            for n in 0..SINGLE_HARMONICS {
                let exact = kernel_average(&r, node, |x| s.reduced_harmonics(a, x)[n]);
                let z = (mean[n] - exact) / se[n];
                assert!(
                    z.abs() < 4.5,
                    "rho {rho}, r {}, n {n}: walk {} ± {}, exact {exact}",
                    r[node],
                    mean[n],
                    se[n]
                );
                chi2 += z * z;
                count += 1;
            }
        }
    }
    // Batch means with 31 degrees of freedom: z² averages 31/29 ≈ 1.07
    assert!(chi2 < 1.5 * count as f64, "chi2 = {chi2} over {count}");
}

#[test]
fn a_beam_in_the_surface_leaves_the_limit_of_grazing_refraction() {
    // The ridge's energy per unit r, e^{−r} K, is the limit of r μ₀(r) as cos θ′ → 0: at
    // η = 1 and θ = 90° − 10⁻⁶ rad (cos θ′ = 10⁻⁶). A vertex at depth δ = r cos θ′ loses about
    // δ ln(1/δ) of it on the way out (4·10⁻⁵ at r = 3)
    for g in [0.0, 0.6] {
        let k = surface_ridge_weight(g, 1.0);
        let s = SingleScattering::new(g, 1.0, 0.5 * PI - 1e-6).unwrap();
        for r in [0.3, 1.0, 3.0] {
            let e = r * s.harmonics(r)[0];
            let limit = (-r).exp() * k;
            assert!(
                (e - limit).abs() <= 2e-4 * limit,
                "g {g}, r {r}: {e} vs {limit}"
            );
        }
    }
    // And off the ridge a beam exactly in the surface leaves nothing
    let s = SingleScattering::new(0.0, 1.0, 0.5 * PI).unwrap();
    assert_eq!(s.refracted_cos(), 0.0);
    assert_eq!(s.eval(1.0, 0.3), 0.0);
}

#[test]
fn it_refuses_what_it_cannot_integrate_and_stays_finite() {
    assert!(SingleScattering::new(1.0, 1.33, 0.3).is_err());
    assert!(SingleScattering::new(0.0, 3.0, 0.3).is_err());
    assert!(SingleScattering::new(0.0, 0.8, 1.2).is_err());
    assert!(SingleScattering::new(f64::NAN, 1.33, 0.3).is_err());
    let s = single(0.9, 1.33, 89.0);
    for (r, phi) in [
        (0.0, 0.0),
        (-1.0, 0.0),
        (f64::NAN, 0.0),
        (1.0, f64::INFINITY),
        (1e-300, 0.0),
        (1e300, 1.0),
        (500.0, 0.0),
    ] {
        let v = s.eval(r, phi);
        assert!(v.is_finite() && v >= 0.0, "({r}, {phi}): {v}");
    }
}
