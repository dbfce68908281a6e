//! Photon beam diffusion (PBD), multiple scattering, at any angle of incidence.
//!
//! Sources: Habel, Christensen, Jarosz 2013, "Photon beam diffusion"; Ferrier 2016, appendix A
//! (table 4); pbrt-v3 §15.5 for the perpendicular special case.
//!
//! | parameter | unit | valid range |
//! |---|---|---|
//! | ρ′ reduced albedo | – | [0, 1] |
//! | θ incidence before refraction | rad | [0, π/2]; outside → 0 |
//! | r exit distance | reduced mean free paths (σ′t = 1) | ≥ 0 |
//! | φ exit azimuth, 0 = forward | rad | any (2π-periodic) |
//! | result S_p^MS | per reduced mfp² (per unit area per unit power entering) | ≥ 0 |
//!
//! # The model
//! The refracted beam enters at the origin with direction (sin θ′, 0, −cos θ′), sin θ′ = sin θ/η.
//! A dipole source at distance t along it sits at depth z_r = t cos θ′; its mirror image lies
//! z_r + 2z_b above the surface (z_b = 2AD, [`crate::medium`]). For the exit point
//! x = (r cos φ, r sin φ, 0):
//!
//! S(r, φ; θ) = ρ′² ∫₀^∞ e^{−t} κ(t) [ C_φ/(4πD) (e^{−σtr d_r}/d_r − e^{−σtr d_v}/d_v)
//!              + C_E/(4π) ( z_r(1+σtr d_r)e^{−σtr d_r}/d_r³ + z_v(1+σtr d_v)e^{−σtr d_v}/d_v³ ) ] dt
//!
//! with z_v = z_r + 2z_b, d_r² = λ² + z_r², d_v² = λ² + z_v², λ² = r² + t² sin²θ′ − 2rt sin θ′ cos φ,
//! κ(t) = 1 − e^{−2(d_r + t)} (pbrt's correction at θ = 0). One ρ′ is the source density
//! Q(t) = ρ′σ′t e^{−σ′t t}, the other the albedo factor of each dipole term.
//! Ferrier prints the image-source factor as (z_r + 2z_b) with his z_b = −2AD < 0; with that
//! sign the image term would shrink, so the printed sign is a typo: the factor is the image
//! height above the surface, z_r + 4AD.
//!
//! # Evaluating the integral over the beam
//! d_r is the distance from the beam point to x: d_r² = (t − t*)² + h² with
//! t* = r sin θ′ cos φ (closest approach) and h² = r²(sin²φ + cos²θ′ cos²φ). Substituting
//! t = t* + h sinh u gives dt = d_r du: the 1/d_r and z_r/d_r³ peaks (sharp when the beam runs
//! just under the exit point at grazing incidence, and the log singularity as r → 0) become
//! smooth bumps of unit width in u. The exponentials are scaled by e^{m}, m = min_t (t + σtr d_r)
//! in closed form, so nothing underflows before the end; the dipole difference is computed as
//! e^{−σtr d_r}/d_r · (−expm1(−σtr δ) + e^{−σtr δ} δ/d_v), with δ = d_v − d_r = 4z_b(z_r+z_b)/(d_v+d_r):
//! two non-negative terms, so it keeps full relative precision where the two monopoles nearly
//! cancel (large r, σtr → 0).
//! The integral is cut where t + σtr d_r exceeds m + 46 (a neglected tail below e⁻⁴⁶ ≈ 10⁻²⁰).
//! - [`Rule::Reference`]: adaptive Gauss–Kronrod in u to 10⁻¹⁰ relative (error estimate returned).
//! - [`Rule::Fast`]: a fixed composite Gauss–Legendre rule in u for baking (error in the README).
//!
//! # Where it breaks down (documented limits, never NaN)
//! - r = 0 with ρ′ > 0: S diverges like (C_E ρ′²/π)·ln(1/r); the value returned is +∞.
//! - A refracted beam running exactly along the surface (θ = 90° with η = 1, or sin θ = η < 1)
//!   passes through the exit points at φ = 0: S is +∞ there (a non-integrable 1/|t − r| along
//!   the beam) and finite for every φ ≠ 0.
//! - η < 1 beyond the critical angle (sin θ > η): no light enters; S = 0.
//! - Very far out (r ≳ 600 mfp at low albedo) S underflows f64 and is returned as 0;
//!   [`Pbd::ln_eval`] gives ln S with full relative accuracy there.

use crate::error::Result;
use crate::fresnel::Moments;
use crate::medium::{Boundary, Medium, ReducedDiffusion};
use crate::quadrature::{adaptive, GaussLegendre};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Which quadrature evaluates the integral over the beam.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Rule {
    /// Adaptive Gauss–Kronrod to 10⁻¹⁰ relative: the reference.
    #[default]
    Reference,
    /// Fixed composite Gauss–Legendre rule, for baking.
    Fast,
}

/// Relative tolerance of the reference quadrature.
pub const REFERENCE_REL_TOL: f64 = 1e-10;
/// Nats beyond the smallest exponent at which the beam integral is cut.
const TAIL_NATS: f64 = 46.0;
/// Levels of f − m (nats above the exponent's minimum) at which panels are cut; the last is
/// where the integral ends.
const LEVELS: [f64; 5] = [3.0, 6.0, 12.0, 24.0, TAIL_NATS];
/// Widest panel in u (see [`Pbd::breaks`]).
const MAX_PANEL_U: f64 = 2.5;
/// Most panel edges [`Pbd::breaks`] returns.
const MAX_EDGES: usize = 40;
/// Points per panel of the fast rule.
pub const FAST_POINTS_PER_PANEL: usize = 8;

/// PBD multiple scattering for one reduced albedo and one boundary, in reduced units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pbd {
    diffusion: ReducedDiffusion,
    boundary: Boundary,
    z_b: f64,
}

/// Geometry of one evaluation, after refraction.
#[derive(Debug, Clone, Copy)]
struct Beam {
    cos_t: f64,
    t_star: f64,
    h: f64,
    /// Exponent scale m = min_t (t + σtr d_r), reached at t = t_min.
    m: f64,
    t_min: f64,
}

enum Setup {
    Value(f64),
    Integrate(Beam),
}

impl Pbd {
    /// PBD for reduced albedo ρ′ ∈ [0, 1] and the given boundary.
    pub fn new(rho_prime: f64, boundary: Boundary) -> Result<Self> {
        let diffusion = ReducedDiffusion::new(rho_prime)?;
        let z_b = 2.0 * boundary.a() * diffusion.d;
        Ok(Self {
            diffusion,
            boundary,
            z_b,
        })
    }

    /// PBD for a medium (its ρ′ and η), in the medium's reduced units.
    pub fn for_medium(medium: &Medium, moments: Moments) -> Self {
        let boundary = medium.boundary(moments);
        // ρ′ of a validated medium is always in [0, 1].
        let diffusion =
            ReducedDiffusion::new(medium.rho_prime().clamp(0.0, 1.0)).unwrap_or(ReducedDiffusion {
                rho_prime: 0.0,
                d: 2.0 / 3.0,
                sigma_tr: 1.5f64.sqrt(),
            });
        Self {
            diffusion,
            boundary,
            z_b: 2.0 * boundary.a() * diffusion.d,
        }
    }

    /// Reduced albedo ρ′.
    pub fn rho_prime(&self) -> f64 {
        self.diffusion.rho_prime
    }

    /// The boundary constants.
    pub fn boundary(&self) -> &Boundary {
        &self.boundary
    }

    /// S_p^MS(r, φ; θ) in reduced units (see the module docs for ranges and limits).
    pub fn eval(&self, theta: f64, r: f64, phi: f64, rule: Rule) -> f64 {
        match self.setup(theta, r, phi) {
            Setup::Value(v) => v,
            Setup::Integrate(beam) => {
                let scaled = match rule {
                    Rule::Reference => self.reference(&beam).value,
                    Rule::Fast => self.fast(&beam),
                };
                scaled * (-beam.m).exp()
            }
        }
    }

    /// ln S_p^MS, accurate where S itself underflows (−∞ where S = 0).
    pub fn ln_eval(&self, theta: f64, r: f64, phi: f64, rule: Rule) -> f64 {
        match self.setup(theta, r, phi) {
            Setup::Value(v) => v.ln(),
            Setup::Integrate(beam) => {
                let scaled = match rule {
                    Rule::Reference => self.reference(&beam).value,
                    Rule::Fast => self.fast(&beam),
                };
                scaled.ln() - beam.m
            }
        }
    }

    /// The reference value with the quadrature's own error estimate (relative), for tests
    /// and the CLI. Returns (value, estimated relative error, converged).
    pub fn eval_reference_with_error(&self, theta: f64, r: f64, phi: f64) -> (f64, f64, bool) {
        match self.setup(theta, r, phi) {
            Setup::Value(v) => (v, 0.0, true),
            Setup::Integrate(beam) => {
                let est = self.reference(&beam);
                let rel = if est.value > 0.0 {
                    est.error / est.value
                } else {
                    0.0
                };
                (est.value * (-beam.m).exp(), rel, est.converged)
            }
        }
    }

    /// Effective albedo ρ_eff(θ) = ∫∫ S_p^MS(r, φ; θ) r dr dφ, the multiply scattered power
    /// leaving per unit power entering (0 where no light enters).
    ///
    /// Computed independently of [`Pbd::eval`]: the plane is translation invariant, so the
    /// order of integration can be swapped. A source at depth z = t cos θ′ contributes
    /// 2π ∫_z^∞ κ(t, d) E_dipole(d) d dd over the plane (d the distance to the exit point), and
    /// ρ_eff = ρ′² ∫ e^{−t} (that) dt. Only the depth of the sources depends on θ. Both integrals
    /// are adaptive (relative tolerance 1e-9); the radial one is mapped onto [0, 1) so the
    /// power-law tail at ρ′ = 1 is integrated to infinity.
    pub fn effective_albedo(&self, theta: f64) -> f64 {
        if !(0.0..=0.5 * PI).contains(&theta) {
            return 0.0;
        }
        let sin_t = theta.sin() / self.boundary.eta();
        if sin_t > 1.0 || self.diffusion.rho_prime == 0.0 {
            return 0.0;
        }
        let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
        let ReducedDiffusion {
            rho_prime,
            d,
            sigma_tr,
        } = self.diffusion;
        let z_b = self.z_b;
        let (c_phi, c_e) = (self.boundary.c_phi(), self.boundary.c_e());
        let plane = |t: f64| {
            let z = t * cos_t;
            let z_v = z + 2.0 * z_b;
            let dv2_minus_d2 = 4.0 * z_b * (z + z_b);
            let radial = |y: f64| {
                // d = z + y/(1 − y), dd = dy/(1 − y)².
                let one_minus = 1.0 - y;
                let dist = z + y / one_minus;
                let jac = 1.0 / (one_minus * one_minus);
                if dist == 0.0 {
                    return 0.0;
                }
                let d_v = (dist * dist + dv2_minus_d2).sqrt();
                let delta = dv2_minus_d2 / (d_v + dist);
                let e_r = (-sigma_tr * dist).exp();
                let kappa = -(-2.0 * (dist + t)).exp_m1();
                // d·(e^{−σd}/d − e^{−σ d_v}/d_v) = e^{−σd}(1 − (d/d_v)e^{−σδ}).
                let fluence = c_phi / (4.0 * PI * d)
                    * e_r
                    * -(-(sigma_tr * delta + (delta / dist).ln_1p())).exp_m1();
                let flux = c_e / (4.0 * PI)
                    * e_r
                    * (z * (1.0 + sigma_tr * dist) / (dist * dist)
                        + z_v * (1.0 + sigma_tr * d_v) * (-sigma_tr * delta).exp() * dist
                            / (d_v * d_v * d_v));
                2.0 * PI * kappa * (fluence + flux) * jac
            };
            adaptive(radial, &[0.0, 0.5, 0.9, 0.99, 1.0], 1e-10, 1e-300, 2000).value
        };
        let outer = adaptive(
            |t| (-t).exp() * plane(t),
            &[0.0, 0.05, 1.0, 4.0, 12.0, TAIL_NATS],
            1e-9,
            1e-300,
            2000,
        );
        rho_prime * rho_prime * outer.value
    }

    fn setup(&self, theta: f64, r: f64, phi: f64) -> Setup {
        let rho = self.diffusion.rho_prime;
        if !(0.0..=0.5 * PI).contains(&theta) || !r.is_finite() || r < 0.0 || !phi.is_finite() {
            return Setup::Value(0.0);
        }
        let sin_t = theta.sin() / self.boundary.eta();
        if sin_t > 1.0 || rho == 0.0 {
            // Beyond the critical angle nothing enters; with ρ′ = 0 nothing scatters.
            return Setup::Value(0.0);
        }
        let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
        if r == 0.0 {
            return Setup::Value(f64::INFINITY);
        }
        let (sin_phi, cos_phi) = phi.sin_cos();
        let t_star = r * sin_t * cos_phi;
        let h2 = r * r * (sin_phi * sin_phi + cos_t * cos_t * cos_phi * cos_phi);
        let mut h = h2.sqrt();
        if h == 0.0 {
            if t_star > 0.0 {
                // The beam runs along the surface through the exit point.
                return Setup::Value(f64::INFINITY);
            }
            // The beam runs away from the exit point: no singularity on t ≥ 0. A tiny h keeps
            // the substitution valid while changing d_r by a relative 1e-200 at most.
            h = r * 1e-100;
        }
        let sigma_tr = self.diffusion.sigma_tr;
        // m = min over t ≥ 0 of t + σtr·d_r(t).
        let (mut m, mut t_min) = (sigma_tr * r, 0.0);
        if sigma_tr > 1.0 {
            let s = (sigma_tr * sigma_tr - 1.0).sqrt();
            if t_star - h / s >= 0.0 {
                t_min = t_star - h / s;
                m = t_star + h * s;
            }
        }
        Setup::Integrate(Beam {
            cos_t,
            t_star,
            h,
            m,
            t_min,
        })
    }

    /// The integrand in u (dt = d_r du), scaled by e^{m}.
    #[inline]
    fn integrand(&self, beam: &Beam, u: f64) -> f64 {
        let ReducedDiffusion {
            rho_prime,
            d,
            sigma_tr,
        } = self.diffusion;
        let z_b = self.z_b;
        let (sinh_u, cosh_u) = sinh_cosh(u);
        let t = (beam.t_star + beam.h * sinh_u).max(0.0);
        let d_r = beam.h * cosh_u;
        let z_r = t * beam.cos_t;
        let z_v = z_r + 2.0 * z_b;
        let dv2_minus_dr2 = 4.0 * z_b * (z_r + z_b);
        let d_v = (d_r * d_r + dv2_minus_dr2).sqrt();
        let delta = dv2_minus_dr2 / (d_v + d_r);
        let e_r = (beam.m - t - sigma_tr * d_r).exp();
        if e_r == 0.0 {
            return 0.0;
        }
        let kappa = -(-2.0 * (d_r + t)).exp_m1();
        // d_r·(e^{−σ d_r}/d_r − e^{−σ d_v}/d_v) = e^{−σ d_r}·(1 − (d_r/d_v)e^{−σδ}), and
        // 1 − (d_r/d_v)e^{−σδ} = −expm1(−σδ) + e^{−σδ}·δ/d_v: two non-negative terms.
        let em = (-sigma_tr * delta).exp_m1();
        let image_ratio = 1.0 + em;
        let fluence = self.boundary.c_phi() / (4.0 * PI * d) * (-em + image_ratio * delta / d_v);
        let flux_real = z_r * (1.0 + sigma_tr * d_r) / (d_r * d_r);
        let flux_virtual = z_v * (1.0 + sigma_tr * d_v) * image_ratio * d_r / (d_v * d_v * d_v);
        let flux = self.boundary.c_e() / (4.0 * PI) * (flux_real + flux_virtual);
        rho_prime * rho_prime * kappa * e_r * (fluence + flux)
    }

    /// Panel edges in u. The integrand is e^{−(f(t) − m)} times algebraic factors, with
    /// f(t) = t + σtr d_r(t) convex in t. Edges go
    /// - where f − m reaches each of [`LEVELS`] on both sides of its minimum (bisection on the
    ///   monotone branches); the integral starts at t = 0, or where f − m falls to the last
    ///   level if it starts above, and ends where it rises to it;
    /// - at the closest approach t* (u = 0), where the algebraic factors peak, and at u = ±2, ±5
    ///   around it;
    /// - and every panel wider than [`MAX_PANEL_U`] is split evenly: the algebraic factors vary
    ///   like e^{±u} away from the peak, which one 8-point panel integrates to 1e-11 over that
    ///   width (small r, or a beam just under the surface, spread them over tens of units of u).
    fn breaks(&self, beam: &Beam) -> ([f64; MAX_EDGES], usize) {
        let sigma_tr = self.diffusion.sigma_tr;
        let f = |t: f64| {
            let dt = t - beam.t_star;
            t + sigma_tr * (dt * dt + beam.h * beam.h).sqrt() - beam.m
        };
        let t_min = beam.t_min;
        // Edges in t, increasing: left branch (decreasing on [0, t_min]) from the far level
        // inward, the minimum, the right branch outward.
        let mut ts = [0.0f64; 2 * LEVELS.len() + 1];
        let mut k = 0;
        let f_entry = f(0.0);
        if t_min > 0.0 && f_entry > TAIL_NATS {
            ts[k] = bisect(|t| f(t) > TAIL_NATS, 0.0, t_min);
        }
        k += 1;
        for &level in LEVELS.iter().rev().skip(1) {
            if t_min > 0.0 && f_entry > level {
                ts[k] = bisect(|t| f(t) > level, 0.0, t_min);
                k += 1;
            }
        }
        ts[k] = t_min;
        k += 1;
        // f(t) ≥ t − m, so f(t_min + m + level) ≥ level.
        for level in LEVELS {
            ts[k] = bisect(|t| f(t) < level, t_min, t_min + beam.m + level);
            k += 1;
        }
        let to_u = |t: f64| ((t - beam.t_star) / beam.h).asinh();
        let (u_first, u_last) = (to_u(ts[0]), to_u(ts[k - 1]));
        // Merge the level edges with the ones around the closest approach.
        let mut merged = [0.0f64; 2 * LEVELS.len() + 6];
        let mut n = 0;
        let mut star = [-5.0, -2.0, 0.0, 2.0, 5.0]
            .into_iter()
            .filter(|&u| u > u_first && u < u_last)
            .peekable();
        for u in ts[..k].iter().map(|&t| to_u(t)) {
            while let Some(us) = star.next_if(|&us| us < u) {
                merged[n] = us;
                n += 1;
            }
            merged[n] = u;
            n += 1;
        }
        // Split wide panels, dropping repeated edges.
        let mut out = [0.0; MAX_EDGES];
        out[0] = merged[0];
        let mut m = 1;
        for (j, &b) in merged[1..n].iter().enumerate() {
            let a = out[m - 1];
            if b <= a {
                continue;
            }
            // Room for this panel's edges with one slot kept for each edge still to come
            // (at least 1: MAX_EDGES exceeds the merged edges).
            let room = MAX_EDGES - m - (n - 2 - j);
            let pieces = (((b - a) / MAX_PANEL_U).ceil() as usize).clamp(1, room);
            for i in 1..pieces {
                out[m] = a + (b - a) * i as f64 / pieces as f64;
                m += 1;
            }
            out[m] = b;
            m += 1;
        }
        if m < 2 {
            out[1] = out[0];
            m = 2;
        }
        (out, m)
    }

    fn reference(&self, beam: &Beam) -> crate::quadrature::Estimate {
        let (breaks, n) = self.breaks(beam);
        adaptive(
            |u| self.integrand(beam, u),
            &breaks[..n],
            REFERENCE_REL_TOL,
            1e-300,
            4000,
        )
    }

    fn fast(&self, beam: &Beam) -> f64 {
        static RULE: OnceLock<GaussLegendre> = OnceLock::new();
        let rule = RULE.get_or_init(|| GaussLegendre::new(FAST_POINTS_PER_PANEL));
        let (breaks, n) = self.breaks(beam);
        breaks[..n]
            .windows(2)
            .map(|w| rule.integrate(w[0], w[1], |u| self.integrand(beam, u)))
            .sum()
    }
}

/// (sinh u, cosh u) from one exponential; sinh by expm1 keeps its relative accuracy near 0.
#[inline]
fn sinh_cosh(u: f64) -> (f64, f64) {
    let em1 = u.abs().exp_m1();
    let e = em1 + 1.0;
    let sinh = 0.5 * em1 * (1.0 + 1.0 / e);
    let cosh = 0.5 * (e + 1.0 / e);
    (sinh.copysign(u), cosh)
}

/// The point where `below` switches from true to false in [lo, hi], to 2⁻¹⁶ of the bracket
/// (panel edges need not be exact: any edge gives a valid rule).
fn bisect(below: impl Fn(f64) -> bool, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..16 {
        let mid = 0.5 * (lo + hi);
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// S_p^MS in world units: r in mm, result in mm⁻² (S scales as σ′t²: S(r; σ′t) = σ′t² S(σ′t r; 1)).
pub fn eval_world(
    medium: &Medium,
    moments: Moments,
    theta: f64,
    r_mm: f64,
    phi: f64,
    rule: Rule,
) -> f64 {
    let st = medium.sigma_t_prime();
    st * st * Pbd::for_medium(medium, moments).eval(theta, st * r_mm, phi, rule)
}
