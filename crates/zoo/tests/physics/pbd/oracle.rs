//! An independent evaluation of photon beam diffusion, to hold `Pbd`'s reference rule to.
//!
//! It shares no code with the library: its own Fresnel moments, its own diffusion and boundary
//! constants, the integrand written directly in the beam parameter t (the library integrates in
//! u, t = t* + h sinh u), its own exponent scale (golden-section search; any scale near the
//! minimum serves), its own breakpoints, and its own quadrature: tanh-sinh (double exponential)
//! on every panel, refined until two levels agree, against the library's Gauss–Kronrod.
//!
//! Panels: the beam is cut at t = 0, at the closest approach t* and t* ± h·2ᵏ (the 1/d_r² peak of
//! width h; the integrand is written in x = t − t* so that it resolves any h), at r·2ᵏ (the scale
//! of the ln(1/r) growth near the entry point), and on both sides of
//! the exponent's minimum every few nats out to 150 nats above it. Beyond that the integrand is
//! below e⁻¹⁵⁰ times its algebraic factors, which no point of the checked domain brings near
//! 10⁻³⁰ of the integral.
//!
//! Its own accuracy: the dipole difference is taken directly (e^{−σd_r}/d_r − e^{−σd_v}/d_v), which
//! over the checked domain (r ≤ 300) loses at most five of sixteen digits; every panel converges to
//! 10⁻¹⁴ of the whole. So the oracle is good to about 10⁻¹¹ relative, three digits below the
//! floor it checks.

use std::f64::consts::{FRAC_PI_2, PI};

/// ln S_p^MS(r, φ; θ) in reduced units for reduced albedo ρ′ and relative index η (−∞ where S = 0).
pub fn ln_pbd(rho: f64, eta: f64, theta: f64, r: f64, phi: f64) -> f64 {
    // cos θ′ from cos θ: 1 − sin²θ′ rounds to 0 within 1e-8 of grazing at η = 1.
    // The f64 nearest π/2 is 90° exactly.
    let cos_i = if theta == FRAC_PI_2 { 0.0 } else { theta.cos() };
    let cos_t2 = (eta * eta - 1.0 + cos_i * cos_i) / (eta * eta);
    if cos_t2 < 0.0 || rho == 0.0 {
        return f64::NEG_INFINITY;
    }
    let (sin_t, cos_t) = (theta.sin() / eta, cos_t2.sqrt());
    let (f1, f2) = (fresnel_moment(1, eta), fresnel_moment(2, eta));
    let d = (2.0 - rho) / 3.0;
    let sigma = ((1.0 - rho) / d).sqrt();
    let z_b = 2.0 * d * (1.0 + 3.0 * f2) / (1.0 - 2.0 * f1);
    let c_phi = 0.25 * (1.0 - 2.0 * f1);
    let c_e = 0.5 * (1.0 - 3.0 * f2);
    let (sin_phi, cos_phi) = phi.sin_cos();
    // The beam is parametrised by x = t − t*, the distance past its closest approach to the
    // exit point, so that distances near that point never come from a difference of nearby
    // t. With t = t* + x, the exit point's offset in the surface plane from the source's foot
    // is (x sin θ′ − r cos φ cos²θ′, r sin φ): t* sin θ′ − r cos φ = −r cos φ cos²θ′.
    let t_star = r * sin_t * cos_phi;
    let (along, across) = (r * cos_phi * cos_t * cos_t, r * sin_phi);
    let distance = |x: f64, z: f64| (x * sin_t - along).hypot(across).hypot(z);
    let d_r = |x: f64| distance(x, (t_star + x) * cos_t);
    let exponent = |x: f64| t_star + x + sigma * d_r(x);
    // Scale: near the minimum of the convex exponent, at t ∈ [0, σr] since exponent ≥ t.
    let x_min = golden_section_min(exponent, -t_star, sigma * r - t_star);
    let m = exponent(x_min);
    let integrand = |x: f64| {
        let t = t_star + x;
        let z_r = t * cos_t;
        let z_v = z_r + 2.0 * z_b;
        let dr = distance(x, z_r);
        let dv = distance(x, z_v);
        let er = (m - t - sigma * dr).exp();
        let ev = (m - t - sigma * dv).exp();
        let fluence = c_phi / (4.0 * PI * d) * (er / dr - ev / dv);
        let flux = c_e / (4.0 * PI)
            * ((z_r / dr) * (1.0 + sigma * dr) * er / dr / dr
                + (z_v / dv) * (1.0 + sigma * dv) * ev / dv / dv);
        let kappa = -(-2.0 * (dr + t)).exp_m1();
        rho * rho * kappa * (fluence + flux)
    };

    // Breakpoints in x.
    let h = r * sin_phi.hypot(cos_t * cos_phi);
    let level = |nats: f64, lo: f64, hi: f64, rising: bool| {
        // Bisection for exponent − m = nats on a monotone branch.
        let (mut lo, mut hi) = (lo, hi);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if (exponent(mid) - m < nats) == rising {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    const LEVELS: [f64; 12] = [
        0.25, 1.0, 2.5, 5.0, 10.0, 20.0, 35.0, 50.0, 70.0, 95.0, 120.0, 150.0,
    ];
    // exponent ≥ t, so exponent − m ≥ 150 at t = t_min + m + 150.
    let x_start = -t_star;
    let x_end = level(150.0, x_min, x_min + m + 150.0, true);
    let mut edges = vec![x_start, x_min, x_end];
    for nats in LEVELS {
        if exponent(x_start) - m > nats {
            edges.push(level(nats, x_start, x_min, false));
        }
        edges.push(level(nats, x_min, x_end, true));
    }
    let mut step = 1.0 / 16.0;
    while r * step <= x_end - x_start || h * step <= x_end - x_start {
        edges.extend([x_start + r * step, 0.0, -h * step, h * step]);
        step *= 2.0;
    }
    edges.retain(|&x| (x_start..=x_end).contains(&x));
    edges.sort_by(f64::total_cmp);
    edges.dedup();

    // A coarse pass gives the scale of the whole; then every panel to 1e-14 of it.
    let coarse: f64 = edges
        .windows(2)
        .map(|w| tanh_sinh(&integrand, w[0], w[1], 0.0, 3))
        .sum();
    let tol = 1e-14 * coarse.abs();
    let total: f64 = edges
        .windows(2)
        .map(|w| tanh_sinh(&integrand, w[0], w[1], tol, 12))
        .sum();
    total.ln() - m
}

/// F_n(η) = ∫₀¹ R(μ) μⁿ dμ, R the unpolarised Fresnel reflectance seen from inside a medium of
/// relative index η (light going from index η to index 1).
pub fn fresnel_moment(n: i32, eta: f64) -> f64 {
    let reflectance = |mu: f64| {
        let sin_out2 = eta * eta * (1.0 - mu * mu);
        if sin_out2 >= 1.0 {
            return 1.0;
        }
        let cos_out = (1.0 - sin_out2).sqrt();
        let r_s = (eta * mu - cos_out) / (eta * mu + cos_out);
        let r_p = (mu - eta * cos_out) / (mu + eta * cos_out);
        0.5 * (r_s * r_s + r_p * r_p)
    };
    let f = |mu: f64| reflectance(mu) * mu.powi(n);
    if eta > 1.0 {
        // Total internal reflection below the critical cosine; a square-root kink there, which
        // tanh-sinh takes as an endpoint.
        let mu_c = (1.0 - 1.0 / (eta * eta)).sqrt();
        mu_c.powi(n + 1) / (n as f64 + 1.0) + tanh_sinh(&f, mu_c, 1.0, 1e-16, 12)
    } else {
        tanh_sinh(&f, 0.0, 1.0, 1e-16, 12)
    }
}

/// ∫ₐᵇ f by the tanh-sinh rule, halving the step until two levels differ by at most `abs_tol`
/// (or `max_level` is reached). Nodes near an end are placed by their distance to that end, so
/// they do not round onto it.
fn tanh_sinh(f: &impl Fn(f64) -> f64, a: f64, b: f64, abs_tol: f64, max_level: u32) -> f64 {
    if b <= a {
        return 0.0;
    }
    let half = 0.5 * (b - a);
    // s = jh up to 3.2: past that the weights are below 1e-30 of the centre's.
    const S_MAX: f64 = 3.2;
    let term = |s: f64| {
        let q = FRAC_PI_2 * s.sinh();
        // 1 − tanh q = 2/(1 + e^{2q}); weight (π/2) cosh s / cosh² q.
        let gap = 2.0 / (1.0 + (2.0 * q).exp());
        let weight = FRAC_PI_2 * s.cosh() / q.cosh().powi(2);
        if weight == 0.0 {
            return 0.0;
        }
        let (left, right) = (a + half * gap, b - half * gap);
        weight * (f(left) + f(right))
    };
    let mut step = 1.0;
    let mut sum = FRAC_PI_2 * f(0.5 * (a + b));
    let mut j = 1.0;
    while j * step <= S_MAX {
        sum += term(j * step);
        j += 1.0;
    }
    let mut estimate = half * step * sum;
    for _ in 0..max_level {
        step *= 0.5;
        let mut j = 1.0;
        while j * step <= S_MAX {
            sum += term(j * step);
            j += 2.0;
        }
        let next = half * step * sum;
        let converged = (next - estimate).abs() <= abs_tol.max(1e-15 * next.abs());
        estimate = next;
        if converged {
            break;
        }
    }
    estimate
}

/// The minimiser of a convex function on [lo, hi] by golden-section search.
fn golden_section_min(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let inv_phi = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let x1 = hi - inv_phi * (hi - lo);
        let x2 = lo + inv_phi * (hi - lo);
        if f(x1) <= f(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    0.5 * (lo + hi)
}
