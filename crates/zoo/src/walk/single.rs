//! Single scattering of the half-space, exactly, by quadrature along the refracted beam: the
//! part a `total` walk table adds to the walk's multiple scattering, without the walk's noise.
//!
//! | parameter | unit | range |
//! |---|---|---|
//! | `g` | – | Henyey–Greenstein asymmetry, (−1, 1) |
//! | `eta` | – | η = n_inside/n_outside in [0.75, 2.5] |
//! | `theta` | radians | [0, π/2]; at most asin η when η < 1 |
//! | r | mean free paths (σt = 1, unreduced) | > 0 |
//! | φ | radians | any; 0 forward |
//!
//! Values are per unit power entering and per unit albedo: multiply by the albedo a (the walk's
//! conventions, [`super`]). In reduced units, a row of reduced albedo ρ′ has a = ρ′/(1 − g + gρ′)
//! and σ′t/σt = k = 1 − g a; its exitance per unit reduced area at reduced radius r′ is
//! a · S₁(r′/k, φ)/k² ([`SingleScattering::reduced`]).
//!
//! # The integral
//! The beam enters at the origin and runs along ω₀ = (sin θ′, 0, −cos θ′), θ′ by Snell. It
//! first scatters at distance s with density e^{−s}; a direction ω drawn from the phase function
//! p(ω₀·ω) reaches the surface point x = (r cos φ, r sin φ, 0) at distance d after surviving
//! e^{−d}, and leaves with the Fresnel transmittance T(μ) at its cosine μ to the normal (no
//! light leaves below the critical cosine μc = √(1 − 1/η²) when η > 1). A solid angle dω
//! meets the surface in the area d²dω/μ, so per unit area
//!
//!   S₁(r, φ) = ∫₀^∞ e^{−s−d} p((b − s)/d) T(μ) μ/d² ds,   μ = s cos θ′/d,
//!
//! with b = r sin θ′ cos φ (the point of the beam nearest x is at s = b), h² = r² − b² and
//! d² = (s − b)² + h² (ω₀·(x − sω₀) = b − s). This is the walk's single-scattering order
//! ([`super::Component::Single`]): exits after exactly one vertex.
//!
//! # Quadrature
//! - **Along the beam**, s = b + h sinh u: ds = d du, and the peak of width h at s = b, as
//!   narrow as r cos θ′ at φ = 0 near grazing refraction, becomes a bump of width ~1 in u; the
//!   integrand is e^{−s−d} p T s cos θ′/d² in u. Where η > 1 only the s with μ > μc
//!   contribute: μ² > μc² is the quadratic (cos²θ′ − μc²) s² + 2μc² b s − μc² r² > 0, solved for
//!   the interval(s) it holds on. Each interval by adaptive Gauss–Kronrod to 10⁻⁹ relative, up
//!   to s = r + |b| + 45 (what lies beyond is below e⁻⁴⁵ of the integrand at s = 0's scale).
//! - **Over φ**, μₙ = 2∫₀^π S₁ cos nφ dφ ([`SingleScattering::harmonics`]) by 8-point
//!   Gauss–Legendre on panels whose widths double from w = cos θ′/2 (the forward peak's width
//!   in φ) up to π: within 10⁻⁶ of μ₀ against adaptive quadrature, and integrated over the
//!   surface within 2·10⁻⁶ of the reflectance by the angular formula (`single_tests.rs`).
//!
//! # Where it breaks down
//! - **r → 0**: S₁ grows like 1/r (sources at s ≪ 1 see x at distance ~r), so r·μ₀ tends to a
//!   constant; a table's node at r = 0 holds none of it.
//! - **A beam in the surface** (cos θ′ = 0: η = 1 at 90°, or the critical angle below η = 1):
//!   every exit leaves at the vertex, on φ = 0, a ridge of energy e^{−r}·K per unit r
//!   ([`surface_ridge_weight`]); [`SingleScattering::eval`] is then 0 off it.
//! - The quadrature knows nothing of exit directions: S₁ is integrated over them, as the walk
//!   scores it.

use super::hg_phase;
use crate::error::Result;
use crate::fresnel;
use crate::quadrature::{adaptive, GaussLegendre};
use std::f64::consts::PI;

/// Relative tolerance of the integral along the beam.
const REL_TOL: f64 = 1e-9;

/// Most Gauss–Kronrod panels per interval along the beam.
const MAX_PANELS: usize = 200;

/// Mean free paths beyond r + |b| at which the integral along the beam stops.
const TAIL: f64 = 45.0;

/// Gauss–Legendre points per panel in φ.
const PHI_POINTS: usize = 8;

/// Harmonics of [`SingleScattering::harmonics`]: μ₀ … μ₄, as the walk's.
pub const SINGLE_HARMONICS: usize = 5;

/// Exact single scattering at one incidence (module docs).
#[derive(Debug, Clone)]
pub struct SingleScattering {
    g: f64,
    /// Relative index of the exit, outside over inside: 1/η.
    exit_eta: f64,
    sin_t: f64,
    cos_t: f64,
    /// Critical cosine inside (0 for η ≤ 1).
    mu_c: f64,
    rule: GaussLegendre,
}

impl SingleScattering {
    /// The single scattering of a beam at incidence `theta` (radians, before refraction) into
    /// a half-space of relative index `eta` and Henyey–Greenstein asymmetry `g`; an error
    /// naming the first parameter outside its range (module docs).
    pub fn new(g: f64, eta: f64, theta: f64) -> Result<Self> {
        super::validate_beam(g, eta, theta)?;
        // At or beyond the critical angle of an η < 1 the beam runs in the surface
        let cos_t = fresnel::refracted_cos(theta, eta).unwrap_or(0.0);
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let mu_c = if eta > 1.0 {
            ((eta - 1.0) * (eta + 1.0)).sqrt() / eta
        } else {
            0.0
        };
        Ok(Self {
            g,
            exit_eta: 1.0 / eta,
            sin_t,
            cos_t,
            mu_c,
            rule: GaussLegendre::new(PHI_POINTS),
        })
    }

    /// cos θ′ of the refracted beam.
    pub fn refracted_cos(&self) -> f64 {
        self.cos_t
    }

    /// S₁(r, φ) per unit area per unit power entering and per unit albedo (module docs), r in
    /// mean free paths; 0 for r ≤ 0, NaN or infinite inputs, and off the ridge of a beam in
    /// the surface.
    pub fn eval(&self, r: f64, phi: f64) -> f64 {
        if !(r > 0.0 && r.is_finite() && phi.is_finite()) || self.cos_t <= 0.0 {
            return 0.0;
        }
        let b = r * self.sin_t * phi.cos();
        // h² = r² − b² = r²(sin²φ + cos²θ′ cos²φ), without the cancellation
        let (sp, cp) = phi.sin_cos();
        let h = r * (sp * sp + self.cos_t * self.cos_t * cp * cp).sqrt();
        if h <= 0.0 {
            return 0.0;
        }
        let s_max = r + b.abs() + TAIL;
        let to_u = |s: f64| ((s - b) / h).asinh();
        let integrand = |u: f64| {
            let s = b + h * u.sinh();
            let d = h * u.cosh();
            if s <= 0.0 {
                return 0.0;
            }
            let mu = s * self.cos_t / d;
            let t = fresnel::transmittance(mu, self.exit_eta);
            let cos_scatter = ((b - s) / d).clamp(-1.0, 1.0);
            (-s - d).exp() * hg_phase(self.g, cos_scatter) * t * s * self.cos_t / (d * d)
        };
        let mut sum = 0.0;
        for (lo, hi) in self.exits(r, b, s_max) {
            let (u0, u1) = (to_u(lo), to_u(hi));
            // The peak at u = 0 (s = b) as a panel edge where it lies inside
            let breaks: Vec<f64> = if u0 < 0.0 && u1 > 0.0 {
                vec![u0, 0.0, u1]
            } else {
                vec![u0, u1]
            };
            sum += adaptive(integrand, &breaks, REL_TOL, 0.0, MAX_PANELS).value;
        }
        sum.max(0.0)
    }

    /// The intervals of s in [0, s_max] from which light can leave for (r, b): all of it for
    /// η ≤ 1, else where μ > μc (module docs).
    fn exits(&self, r: f64, b: f64, s_max: f64) -> Vec<(f64, f64)> {
        if self.mu_c <= 0.0 {
            return vec![(0.0, s_max)];
        }
        let m2 = self.mu_c * self.mu_c;
        // q(s) = A s² + 2 μc² b s − μc² r², q(0) < 0
        let a = (self.cos_t - self.mu_c) * (self.cos_t + self.mu_c);
        let (lin, c) = (2.0 * m2 * b, -m2 * r * r);
        let clip = |lo: f64, hi: f64| {
            let (lo, hi) = (lo.max(0.0), hi.min(s_max));
            (lo < hi).then_some((lo, hi))
        };
        let scale = m2.max(a.abs());
        if a.abs() <= 1e-12 * scale {
            // Linear: 2 μc² b s > μc² r²
            return if b > 0.0 {
                clip(r * r / (2.0 * b), s_max).into_iter().collect()
            } else {
                Vec::new()
            };
        }
        let disc = lin * lin - 4.0 * a * c;
        if disc < 0.0 {
            // q keeps the sign of A < 0 (q(0) < 0): no exit
            return Vec::new();
        }
        // The roots without cancellation: q₁ = −(lin + sign(lin)√disc)/2, roots q₁/A and c/q₁
        let root = disc.sqrt();
        let q1 = -0.5 * (lin + if lin >= 0.0 { root } else { -root });
        let (x1, x2) = if q1 == 0.0 {
            (0.0, 0.0)
        } else {
            let (p, q) = (q1 / a, c / q1);
            (p.min(q), p.max(q))
        };
        if a > 0.0 {
            // q > 0 beyond the larger root (the roots have opposite signs)
            clip(x2, s_max).into_iter().collect()
        } else {
            // q > 0 between the roots
            clip(x1, x2).into_iter().collect()
        }
    }

    /// The azimuthal harmonics μₙ(r) = ∫ S₁(r, φ) cos nφ dφ over [−π, π], n = 0 … 4, per unit
    /// power entering and per unit albedo (module docs: Gauss–Legendre panels in φ).
    pub fn harmonics(&self, r: f64) -> [f64; SINGLE_HARMONICS] {
        let mut m = [0.0; SINGLE_HARMONICS];
        if self.sin_t == 0.0 {
            // Normal incidence: isotropic
            m[0] = 2.0 * PI * self.eval(r, 0.0);
            return m;
        }
        let mut a = 0.0;
        let mut width = (0.5 * self.cos_t).clamp(1e-9, 0.5);
        while a < PI {
            let b = (a + width).min(PI);
            let (half, mid) = (0.5 * (b - a), 0.5 * (a + b));
            for (x, w) in self.rule.nodes().iter().zip(self.rule.weights()) {
                let phi = mid + half * x;
                // Twice the integral over [0, π] of an even profile
                let s = 2.0 * w * half * self.eval(r, phi);
                for (n, mn) in m.iter_mut().enumerate() {
                    *mn += s * (n as f64 * phi).cos();
                }
            }
            a = b;
            width *= 2.0;
        }
        m
    }

    /// [`SingleScattering::eval`] of a row in reduced units: a · S₁(r′/k, φ)/k², per unit
    /// reduced area, for unreduced albedo `albedo` and k = 1 − g·albedo (module docs).
    pub fn reduced(&self, albedo: f64, r_reduced: f64, phi: f64) -> f64 {
        let k = 1.0 - self.g * albedo;
        albedo * self.eval(r_reduced / k, phi) / (k * k)
    }

    /// [`SingleScattering::harmonics`] of a row in reduced units (as
    /// [`SingleScattering::reduced`]).
    pub fn reduced_harmonics(&self, albedo: f64, r_reduced: f64) -> [f64; SINGLE_HARMONICS] {
        let k = 1.0 - self.g * albedo;
        self.harmonics(r_reduced / k).map(|m| albedo * m / (k * k))
    }
}

/// K of a beam in the surface (cos θ′ = 0): the share of the power scattered at a vertex on the
/// surface that leaves at once, K = ∫ p(ω₀·ω) T(μ) dω over the upper hemisphere with ω₀
/// horizontal (ω₀·ω = √(1 − μ²) cos φ). Per unit power entering, single scattering then leaves
/// a ridge on φ = 0 of energy a·e^{−r}·K per unit r (module docs). By adaptive quadrature in μ
/// of adaptive quadrature in φ (the phase function's peak at φ = 0 as a panel edge).
pub fn surface_ridge_weight(g: f64, eta: f64) -> f64 {
    let exit_eta = 1.0 / eta;
    let peak = (1.0 - g.abs()).clamp(1e-3, 1.0);
    let inner = |mu: f64| {
        let sin = (1.0 - mu * mu).max(0.0).sqrt();
        let f = |phi: f64| hg_phase(g, (sin * phi.cos()).clamp(-1.0, 1.0));
        // Twice the integral over [0, π]
        2.0 * fresnel::transmittance(mu, exit_eta)
            * adaptive(f, &[0.0, peak, PI], 1e-10, 0.0, MAX_PANELS).value
    };
    let mu_c = if eta > 1.0 {
        ((eta - 1.0) * (eta + 1.0)).sqrt() / eta
    } else {
        0.0
    };
    let breaks: Vec<f64> = if mu_c > 0.0 {
        vec![mu_c, 1.0]
    } else {
        vec![0.0, peak.min(0.5), 1.0]
    };
    adaptive(inner, &breaks, 1e-10, 0.0, MAX_PANELS).value
}
