//! The directional dipole (Frisvad, Hachisuka, Kjeldsen 2014, "Directional dipole model for
//! subsurface scattering", ACM TOG 34(1); formulas as in Frisvad's 2016 slides and the authors'
//! sample code), on a flat surface, with the finite limits the sample code lacks.
//!
//! | parameter | unit | valid range |
//! |---|---|---|
//! | ρ′ reduced albedo (the paper's α′) | – | [0, 1]; ρ′ = 0 gives 0 (see below) |
//! | η relative index, inside over outside | – | [0.75, 2.5] |
//! | g | – | (−1, 1); used only by the back-lit branch (unreduced σt) |
//! | Fresnel moments | – | the model's, or the authors' fits ([`DirpoleOptions`]) |
//! | θ incidence before refraction | rad | [0, π/2]; no light enters beyond asin η → 0 |
//! | r, φ exit point | reduced mfp, rad (0 forward) | r ≥ 0 |
//! | result R(r, φ; θ) | per reduced mfp², per unit power entering | ≥ 0 (clamped) |
//!
//! # The model, reduced units (σ′t = 1)
//! D = 1/(3σ′t) = 1/3 (classical), σtr = √(σa/D) = √(3(1 − ρ′)), extrapolation distance
//! d_e = 2.131 D/√ρ′ (the TOG paper; the 2014 tech report's 2.121 D/ρ′ is not used), reflection
//! parameter A = (1 − C_E)/(2C_φ) = (1 + 3F₂)/(1 − 2F₁), C_φ = (1 − 2F₁)/4, C_E = (1 − 3F₂)/2 from
//! the model's Fresnel [`crate::fresnel::Moments`], or ([`DirpoleFresnel::AuthorsFits`]) the
//! double-precision d'Eon–Irving fits with the branches of the authors' code, which reproduce it.
//! With w_r the refracted direction, x = x_o − x_i, r = |x|, the ray-source monopole
//!
//! S′(X, w, R) = e^{−σtr R}/R³ { C_φ(η)[R²/D + 3(1 + σtr R)(X·w)]
//!               − C_E(η)[3D(1 + σtr R)(w·n_o) − ((1 + σtr R) + 3D(3(1 + σtr R) + (σtr R)²)(X·w)/R²)(X·n_o)] }
//!
//! is taken at the real source (X = x, w = w_r, R = d_r) and at the image
//! (X = x_o − x_v, w = w_v, R = d_v), with the modified tangent plane's normal n_i* (the unit
//! component of n_i orthogonal to x), x_v = x_i + 2A d_e n_i*, w_v = w_r − 2(w_r·n_i*)n_i*,
//! μ₀ = −n_o·w_r, cos β = −√((r² − (x·w_r)²)/(r² + d_e²)), and
//! d_r² = r² + Dμ₀(Dμ₀ − 2d_e cos β) if μ₀ > 0, else r² + 1/(3σt)² (unreduced σt, the one place
//! g enters). The authors' S_d = max(0, S′_real − S′_image) / (4C_φ(1/η) · 4π²).
//!
//! **From S_d to R.** The exit is diffuse, S = T₁₂ S_d T₂₁; per unit power entering, the power
//! leaving per unit area is S_d ∫ T₂₁ cos θ_o dω_o = S_d · π(1 − 2F₁(1/η)) = S_d · 4πC_φ(1/η),
//! which cancels the normalisation exactly when both use the same moments:
//! R = max(0, S′_real − S′_image)/(4π), independent of C_φ(1/η).
//!
//! # Limits the sample code gets wrong (derived)
//! - **x_o = x_i.** n_i* = x̂ × (n_i × x̂)/|n_i × x̂| is 0/0 (NaN in the code). Every other factor
//!   is finite at x = 0: cos β = 0, so d_r = Dμ₀ > 0 (or 1/(3σt) back-lit), d_v = 2A d_e, and the
//!   X-dependent terms vanish. For x_o in the tangent plane n_i* = n_i for every r > 0, so the
//!   r → 0 limit is the formula with n_i* = n_i (the slides' convention) and cos β = 0: R is
//!   continuous at r = 0 on a flat surface (tested).
//! - **x_o − x_i ∥ n_i** (straight through a slab; not reachable on a flat surface). n_i* is the
//!   unit transverse offset in the limit, so the value depends on the direction of approach and
//!   there is no limit in general; S_d stays bounded. We approach perpendicular to the plane of
//!   incidence, n_i* = unit(n_i × w_r) (any unit vector ⊥ n_i at normal incidence, where all
//!   approaches agree by rotational symmetry); when n_o lies in the plane of incidence this is
//!   the two-sided limit along that line.
//! - The square root in cos β is clamped at 0 against rounding.
//!
//! # Where it breaks down
//! - It is the difference of two monopoles and goes negative (clamped to 0 as the authors do)
//!   for oblique incidence at η ≈ 1 behind the entry point (φ = 180°, r ~ 0.1–10).
//! - It has no albedo factor: as ρ′ → 0 it does not vanish near the source (d_e → ∞ removes the
//!   image, but the real source at r = 0 keeps a finite value). At exactly ρ′ = 0 we return the
//!   physical 0 (d_e is infinite there). Not reciprocal.
//! - It does not conserve energy: ∫∫ R dA at θ = 0 is 1.09 at ρ′ = 0.99 and 1.34 at ρ′ = 1 for
//!   η = 1 (1.23 at ρ′ = 1, η = 1.33; both Fresnel fits agree to 1e-3), against at most 1. Against
//!   the walk's multiple scattering it is high everywhere (`models.md`, the comparison): ×2 at
//!   ρ′ = 0.9, ×1.5 at 0.99, ×8 at 0.5.
//! - Grazing incidence at η ≈ 1: the refracted ray runs along the surface, μ₀ → 0 and d_r → r,
//!   so R grows like 1/r towards the source in the forward direction; at θ = 90°, η = 1 exactly
//!   μ₀ = 0 and the back-lit branch applies.
//! - The reduced-intensity term S_δE of the paper never reaches an exit point on the same flat
//!   surface and is not modelled.

use super::{entering, integrate_total, Model, ModelKind, Params};
use crate::fresnel::{deon_irving_moment1, deon_irving_moment2};
use crate::walk::Component;
use std::f64::consts::PI;

/// Extrapolation-distance constant of the TOG paper, d_e = 2.131 D/√α′.
pub const D_E_FACTOR: f64 = 2.131;

type V3 = [f64; 3];

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add_scaled(a: V3, s: f64, b: V3) -> V3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}

/// Which Fresnel moments give C_φ, C_E and A.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum DirpoleFresnel {
    /// The moments of the model's [`Params`] (exact by default), like every other model.
    #[default]
    Params,
    /// The authors' sample code: d'Eon & Irving's fits in double precision, the first moment on
    /// its η < 1 branch at η = 1 ([`crate::fresnel::deon_irving_moment1`]).
    AuthorsFits,
}

/// Options of the directional dipole.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct DirpoleOptions {
    /// Fresnel moments.
    pub fresnel: DirpoleFresnel,
}

/// Points and directions of one evaluation, in reduced units (lengths times σ′t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Entry point.
    pub x_i: [f64; 3],
    /// Unit outward normal at the entry point.
    pub n_i: [f64; 3],
    /// Unit direction toward the light at the entry point.
    pub w_i: [f64; 3],
    /// Exit point.
    pub x_o: [f64; 3],
    /// Unit outward normal at the exit point.
    pub n_o: [f64; 3],
}

/// The directional dipole for one medium, in reduced units.
#[derive(Debug, Clone, PartialEq)]
pub struct Dirpole {
    params: Params,
    d: f64,
    sigma_tr: f64,
    d_e: f64,
    a: f64,
    c_phi: f64,
    c_e: f64,
    /// C_φ(1/η), for S_d's normalisation.
    c_phi_inverse: f64,
    /// Unreduced σt in reduced units, for the back-lit branch.
    sigma_t: f64,
}

impl Dirpole {
    /// The directional dipole for validated parameters.
    pub fn new(params: Params, options: DirpoleOptions) -> Self {
        let moments = |eta: f64| match options.fresnel {
            DirpoleFresnel::Params => params.moments().evaluate(eta),
            DirpoleFresnel::AuthorsFits => (deon_irving_moment1(eta), deon_irving_moment2(eta)),
        };
        let (f1, f2) = moments(params.eta());
        let (f1_inverse, _) = moments(1.0 / params.eta());
        let rho = params.rho_prime();
        let d = 1.0 / 3.0;
        Self {
            params,
            d,
            sigma_tr: ((1.0 - rho) / d).sqrt(),
            d_e: D_E_FACTOR * d / rho.sqrt(),
            a: (1.0 + 3.0 * f2) / (1.0 - 2.0 * f1),
            c_phi: 0.25 * (1.0 - 2.0 * f1),
            c_e: 0.5 * (1.0 - 3.0 * f2),
            c_phi_inverse: 0.25 * (1.0 - 2.0 * f1_inverse),
            sigma_t: params.sigma_t_over_reduced(),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The authors' S_d (clamped at 0, without the Fresnel transmittances), per reduced mfp².
    pub fn s_d(&self, geometry: &Geometry) -> f64 {
        self.s_d_signed(geometry).max(0.0)
    }

    /// S_d before the clamp (negative where the image outweighs the real source).
    pub fn s_d_signed(&self, geometry: &Geometry) -> f64 {
        self.difference(geometry) / (4.0 * self.c_phi_inverse * 4.0 * PI * PI)
    }

    /// S′_real − S′_image; 0 where no light enters or ρ′ = 0.
    fn difference(&self, g: &Geometry) -> f64 {
        if self.params.rho_prime() <= 0.0 || !self.d_e.is_finite() {
            return 0.0;
        }
        let eta = self.params.eta();
        let n_i = g.n_i;
        let cos_i = dot(g.w_i, n_i);
        let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
        if cos_i.is_nan() || cos_i < 0.0 || sin2_t > 1.0 {
            return 0.0;
        }
        // Refracted direction, into the medium.
        let w_r = add_scaled(
            scale(1.0 / eta, add_scaled(scale(cos_i, n_i), -1.0, g.w_i)),
            -(1.0 - sin2_t).sqrt(),
            n_i,
        );
        let mut x = sub(g.x_o, g.x_i);
        let mut r = norm(x);
        if r.is_nan() {
            return 0.0;
        }
        if r < 1e-150 {
            // Below this r² underflows; the limit x → 0 is continuous (module docs).
            x = [0.0; 3];
            r = 0.0;
        }
        let (d, d_e) = (self.d, self.d_e);
        let x_dot_w = dot(x, w_r);
        let mu_0 = -dot(g.n_o, w_r);
        let d_r = if mu_0 > 0.0 {
            let cos_beta = -((r * r - x_dot_w * x_dot_w).max(0.0) / (r * r + d_e * d_e)).sqrt();
            (r * r + d * mu_0 * (d * mu_0 - 2.0 * d_e * cos_beta)).sqrt()
        } else {
            let back = 1.0 / (3.0 * self.sigma_t);
            (r * r + back * back).sqrt()
        };
        let n_star = self.modified_normal(n_i, x, r, w_r);
        let x_v = add_scaled(g.x_i, 2.0 * self.a * d_e, n_star);
        let w_v = add_scaled(w_r, -2.0 * dot(w_r, n_star), n_star);
        let x_ov = sub(g.x_o, x_v);
        let d_v = norm(x_ov);
        self.monopole(x, w_r, d_r, g.n_o) - self.monopole(x_ov, w_v, d_v, g.n_o)
    }

    /// n_i*: the unit component of n_i orthogonal to x, with the limits of the module docs.
    fn modified_normal(&self, n_i: V3, x: V3, r: f64, w_r: V3) -> V3 {
        if r == 0.0 {
            return n_i;
        }
        let c = cross(n_i, x);
        let c_norm = norm(c);
        if c_norm > 1e-12 * r {
            let n_star = cross(scale(1.0 / r, x), scale(1.0 / c_norm, c));
            return n_star;
        }
        // x ∥ n_i: approach perpendicular to the plane of incidence.
        let p = cross(n_i, w_r);
        let p_norm = norm(p);
        if p_norm > 1e-12 {
            return scale(1.0 / p_norm, p);
        }
        // Normal incidence: any unit vector orthogonal to n_i.
        let helper = if n_i[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let q = cross(n_i, helper);
        scale(1.0 / norm(q), q)
    }

    /// S′(X, w, R) without the 1/(4C_φ(1/η)·4π²) normalisation.
    fn monopole(&self, x: V3, w: V3, r: f64, n_o: V3) -> f64 {
        let (d, s) = (self.d, self.sigma_tr);
        let sr = s * r;
        let one = 1.0 + sr;
        let x_dot_w = dot(x, w);
        let x_dot_n = dot(x, n_o);
        let fluence = self.c_phi * (r * r / d + 3.0 * one * x_dot_w);
        let flux = self.c_e
            * (3.0 * d * one * dot(w, n_o)
                - (one + 3.0 * d * (3.0 * one + sr * sr) * x_dot_w / (r * r)) * x_dot_n);
        let value = (-sr).exp() / (r * r * r) * (fluence - flux);
        if value.is_finite() {
            value
        } else {
            0.0
        }
    }

    /// The flat-surface geometry of an evaluation: entry at the origin, normal +z, the refracted
    /// beam travelling toward +x (so φ = 0 is forward).
    pub fn flat_geometry(theta: f64, r: f64, phi: f64) -> Geometry {
        let (sin_phi, cos_phi) = phi.sin_cos();
        Geometry {
            x_i: [0.0; 3],
            n_i: [0.0, 0.0, 1.0],
            w_i: [-theta.sin(), 0.0, theta.cos()],
            x_o: [r * cos_phi, r * sin_phi, 0.0],
            n_o: [0.0, 0.0, 1.0],
        }
    }
}

impl Model for Dirpole {
    fn kind(&self) -> ModelKind {
        ModelKind::Dirpole
    }

    fn component(&self) -> Component {
        Component::Multiple
    }

    fn eval(&self, theta: f64, r: f64, phi: f64) -> f64 {
        if entering(theta, self.params.eta()).is_none()
            || r.is_nan()
            || r < 0.0
            || r.is_infinite()
            || !phi.is_finite()
        {
            return 0.0;
        }
        let geometry = Self::flat_geometry(theta, r, phi);
        (self.difference(&geometry) / (4.0 * PI)).max(0.0)
    }

    fn effective_albedo(&self, theta: f64) -> Option<f64> {
        Some(integrate_total(self, theta))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fresnel::Moments;

    #[test]
    fn value_at_the_entry_point_is_the_limit_of_nearby_values() {
        for (rho, eta, theta) in [(0.5, 1.3, 1.2), (0.99, 1.0, 0.3), (0.9, 2.5, 0.0)] {
            let m = Dirpole::new(
                Params::new(rho, eta, Moments::Exact).unwrap(),
                DirpoleOptions::default(),
            );
            let at_zero = m.eval(theta, 0.0, 0.0);
            assert!(at_zero.is_finite() && at_zero > 0.0);
            for phi in [0.0, 1.0, PI] {
                let near = m.eval(theta, 1e-9, phi);
                assert!(
                    (near - at_zero).abs() < 1e-6 * at_zero,
                    "{near} vs {at_zero}"
                );
            }
        }
    }

    #[test]
    fn normal_through_a_slab_is_finite_and_matches_a_perpendicular_approach() {
        let m = Dirpole::new(
            Params::new(0.9, 1.3, Moments::Exact).unwrap(),
            DirpoleOptions::default(),
        );
        let theta: f64 = 0.7;
        let w_i = [-theta.sin(), 0.0, theta.cos()];
        let at = |offset: [f64; 3]| {
            m.s_d(&Geometry {
                x_i: [0.0; 3],
                n_i: [0.0, 0.0, 1.0],
                w_i,
                x_o: offset,
                n_o: [0.0, 0.0, -1.0],
            })
        };
        let on_axis = at([0.0, 0.0, -2.0]);
        assert!(on_axis.is_finite() && on_axis > 0.0);
        for side in [1e-7, -1e-7] {
            let near = at([0.0, side, -2.0]);
            assert!(
                (near - on_axis).abs() < 1e-5 * on_axis,
                "{near} vs {on_axis}"
            );
        }
    }
}
