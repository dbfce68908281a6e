//! Photon beam diffusion (PBD), multiple scattering, at any angle of incidence.
//!
//! Sources: Habel, Christensen, Jarosz 2013, "Photon beam diffusion"; Ferrier 2016, appendix A
//! (table 4); pbrt-v3 §15.5 for the perpendicular special case.
//!
//! | parameter | unit | valid range |
//! |---|---|---|
//! | ρ′ reduced albedo | – | [0, 1] |
//! | η relative index ([`Boundary`]) | – | [0.75, 2.5] |
//! | θ incidence before refraction | rad | [0, π/2]; outside → 0 |
//! | r exit distance | reduced mean free paths (σ′t = 1) | ≥ 0, finite |
//! | φ exit azimuth, 0 = forward | rad | any finite (2π-periodic); non-finite → 0 |
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
//! e^{−σtr d_r}/d_r · ((1 − e^{−σtr δ}) + e^{−σtr δ} δ/d_v), with δ = d_v − d_r = 4z_b(z_r+z_b)/(d_v+d_r):
//! two non-negative terms, so it keeps full relative precision where the two monopoles nearly
//! cancel (large r, σtr → 0).
//! The integral runs from the beam's entry (or from where t + σtr d_r has fallen to m + 46, if it
//! starts above) to where it rises to m + 46 again (a neglected tail below e⁻⁴⁶ ≈ 10⁻²⁰).
//! - [`Rule::Reference`]: adaptive Gauss–Kronrod in u to 10⁻¹⁰ relative (error estimate
//!   returned). Held to 10⁻⁸ (measured: 9e-12 at most) by an independent quadrature over
//!   50,000 random points of the domain (`crates/zoo/tests/physics/pbd/mod.rs`).
//! - [`Rule::Fast`]: a fixed composite 8-point Gauss–Legendre rule in u for baking and the
//!   bake's check: within 1.6e-7 of the reference on every bake grid and 5.9e-8 over the domain
//!   (`examples/quadrature_error.rs`).
//! - The node rule ([`Pbd::eval_node`], [`Pbd::eval_surface_beam_node`]): the fast rule's panels
//!   with 6 points, for the azimuths two-lobe bakes fit through and the surface-beam nodes'
//!   harmonics: within 1.2e-5 of the reference there.
//!
//! A panel's points are evaluated in passes (`Pbd::panel`), the same operations in the same
//! order as point by point. Below r = 10⁻¹² every rule uses the small-r expansion S(r) = S(10⁻¹²) + k ln(10⁻¹²/r), with
//! k = ρ′² C_E cos θ′/π ([`Pbd::log_slope`]); its error is O(r ln r) relative.
//!
//! # Where it breaks down (documented limits, never NaN)
//! - r = 0 with ρ′ > 0: S diverges like (ρ′² C_E cos θ′/π)·ln(1/r); the value returned is +∞
//!   (every r > 0, down to the smallest subnormal, has a finite value).
//! - A refracted beam running exactly along the surface (θ = 90° with η = 1, or sin θ = η < 1)
//!   passes through the exit points at φ = 0: S is +∞ there (a non-integrable 1/|t − r| along
//!   the beam) and finite for every φ ≠ 0.
//! - η < 1 beyond the critical angle (sin θ > η): no light enters; S = 0.
//! - Very far out (r ≳ 600 mfp at low albedo) S leaves f64's normal range: [`Pbd::eval`] is
//!   within 10⁻⁸ relative down to 2.2e-308 and within one subnormal step below, then 0;
//!   [`Pbd::ln_eval`] gives ln S there, to r·10⁻¹⁶ (the rounding of the beam's exponent, of
//!   order r): 10⁻⁸ up to r = 10⁸. Beyond r = 10⁸, where S < 10⁻²⁴, both return 0 (ln: −∞).

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

/// The quadrature an evaluation takes: a [`Rule`], or the bake's node rule
/// ([`Pbd::eval_node`]).
#[derive(Debug, Clone, Copy)]
enum Quadrature {
    Reference,
    Fast,
    Node,
}

impl From<Rule> for Quadrature {
    fn from(rule: Rule) -> Self {
        match rule {
            Rule::Reference => Quadrature::Reference,
            Rule::Fast => Quadrature::Fast,
        }
    }
}

/// Relative tolerance of the reference quadrature.
pub const REFERENCE_REL_TOL: f64 = 1e-10;
/// Below this radius (reduced mfp) S is its small-r expansion, S(R_SMALL) + k·ln(R_SMALL/r)
/// ([`Pbd::log_slope`]): its relative error is O(r ln r), below 1e-11 here (tested against the
/// quadrature and the independent oracle), while the quadrature's panels in u would have to
/// span ln(1/r) ≈ 745 at the smallest subnormal.
const R_SMALL: f64 = 1e-12;
/// Smallest distance h from the beam to the exit point that the substitution t = t* + h sinh u
/// is used with; closer, a closed-form log term takes the rest ([`Pbd::setup`]).
const H_FLOOR: f64 = 1e-280;
/// Beyond this radius (reduced mfp) S is 0: it falls at least like r⁻³ (the power-law tail at
/// ρ′ = 1), below 1e-24, while the beam's exponent t + σtr d_r, of order r, carries an absolute
/// rounding error of r·1e-16 that reaches 1e-8 there.
const R_LARGE: f64 = 1e8;
/// Nats beyond the smallest exponent at which the beam integral is cut.
const TAIL_NATS: f64 = 46.0;
/// Levels of f − m (nats above the exponent's minimum) at which panels are cut; the last is
/// where the integral ends.
const LEVELS: [f64; 5] = [3.0, 6.0, 12.0, 24.0, TAIL_NATS];
/// Widest panel in u (see [`Pbd::breaks`]).
const MAX_PANEL_U: f64 = 2.5;
/// Most edges before the wide panels are split: the level edges on both sides, the minimum and
/// the five around the closest approach.
const MERGED_EDGES: usize = 2 * LEVELS.len() + 6;
/// Most panel edges [`Pbd::breaks`] returns: room for the merged edges split in up to four each,
/// and for the doubling splits of a few wide panels (a beam 10⁻²⁸⁰ from the exit point needs
/// about 40).
const MAX_EDGES: usize = 160;
/// Points per panel of the fast rule: 8, within 1.6e-7 of the reference over every bake
/// grid. With 7 it is 11 % faster but 1.26e-6 off at one point of the 25.9 million (η =
/// 1.0001, θ = 90°, φ = 0: the beam just under the exit point), over the documented 1e-6; with
/// 6, 22 % faster and 3e-6 off (`examples/quadrature_error.rs`; docs/physics.md).
pub const FAST_POINTS_PER_PANEL: usize = 8;

/// Points per panel of [`Pbd::eval_node`]: 6, the fast rule's panels with 22 % fewer points,
/// within 1.2·10⁻⁵ of the reference on every point a two-lobe bake fits through
/// (`examples/quadrature_error.rs`).
pub const NODE_POINTS_PER_PANEL: usize = 6;

/// The fast rule in words, for a baked file's provenance.
pub fn fast_rule_description() -> String {
    let levels: Vec<String> = LEVELS.iter().map(|l| l.to_string()).collect();
    format!(
        "composite {FAST_POINTS_PER_PANEL}-point Gauss-Legendre in u, t = t* + h sinh u, panels \
         at the closest approach and at {} nats of the exponent",
        levels.join(", ")
    )
}

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

/// One quadrature point on the beam ([`Pbd::point`]): distance t along it, the distances
/// d_r and d_v of its real and image sources from the exit point, their heights z_r and z_v,
/// and δ = d_v − d_r.
#[derive(Debug, Clone, Copy, Default)]
struct Point {
    t: f64,
    d_r: f64,
    z_r: f64,
    z_v: f64,
    d_v: f64,
    delta: f64,
}

/// Most points per panel that [`Pbd::panel`] takes in passes (the fast rule's 8).
const MAX_PANEL_POINTS: usize = 8;

enum Setup {
    Value(f64),
    /// The integral over the beam, plus a term of the closed form at a beam grazing the exit
    /// point (see [`Pbd::setup`]).
    Integrate(Beam, f64),
}

/// What one evaluation found: S = scaled·e^{ln_scale}.
struct Evaluated {
    /// The integral scaled by e^{m}, with the small-r expansion's k·ln(R_SMALL/r) or a grazing
    /// beam's A·ln(floor/h) scaled likewise (or the exact value where no integral was needed).
    scaled: f64,
    /// −m: the exponent scale (0 for an exact value).
    ln_scale: f64,
    /// The reference rule's error estimate of `scaled` (0 for the fast rule).
    error: f64,
    converged: bool,
}

impl Evaluated {
    fn exact(value: f64) -> Self {
        Self {
            scaled: value,
            ln_scale: 0.0,
            error: 0.0,
            converged: true,
        }
    }

    fn value(&self) -> f64 {
        if self.ln_scale > -700.0 {
            self.scaled * self.ln_scale.exp()
        } else {
            // e^{ln_scale} alone would be subnormal or 0 while the product is not.
            self.ln_value().exp()
        }
    }

    fn ln_value(&self) -> f64 {
        self.scaled.ln() + self.ln_scale
    }
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
        self.evaluate(theta, r, phi, rule.into()).value()
    }

    /// [`Pbd::eval`] by the node rule: the fast rule's panels with [`NODE_POINTS_PER_PANEL`]
    /// points each, for the azimuths a two-lobe bake fits through (its fit misses PBD by
    /// 10⁻⁵–10⁻³ there, this rule by at most 1.2·10⁻⁵; docs/physics.md).
    pub fn eval_node(&self, theta: f64, r: f64, phi: f64) -> f64 {
        self.evaluate(theta, r, phi, Quadrature::Node).value()
    }

    /// S with the refracted beam running in the surface (θ′ = 90°: η = 1 at θ = 90°, or the
    /// critical angle asin η below η = 1), in reduced units: finite at every φ ≠ 0, +∞ at
    /// φ = 0 (the module docs). This is the limit θ′ → 90° of S at every φ ≠ 0, but not of
    /// the profile's energy: the limit also holds [`Pbd::surface_ridge`] on the line φ = 0.
    pub fn eval_surface_beam(&self, r: f64, phi: f64, rule: Rule) -> f64 {
        self.evaluate_refracted(Some((1.0, 0.0)), r, phi, rule.into())
            .value()
    }

    /// [`Pbd::eval_surface_beam`] by the node rule ([`Pbd::eval_node`]): for the harmonics of
    /// a bake's surface-beam nodes, which integrate it over φ to 10⁻⁴ of μ₀.
    pub fn eval_surface_beam_node(&self, r: f64, phi: f64) -> f64 {
        self.evaluate_refracted(Some((1.0, 0.0)), r, phi, Quadrature::Node)
            .value()
    }

    /// The ridge of the limit θ′ → 90°: its mass per radian of φ at radius r (reduced units),
    /// all of it on the line φ = 0, a(r) = ρ′² C_E κ e^{−r}/(2r) with κ = 1 − e^{−2r}.
    ///
    /// As the beam nears the surface (z_r = t cos θ′ → 0), the real source's flux term
    /// C_E/(4π)·κ z_r (1 + σtr d_r) e^{−σtr d_r}/d_r³ of each beam point t concentrates on the
    /// exit point straight above it, where it integrates over the plane to C_E κ(t, 0)/2
    /// (∫ z/d³ dA = 2π): weighted by the beam's ρ′² e^{−t} and with t = r (sin θ′ = 1), a line
    /// density ρ′² C_E κ e^{−r}/2 along φ = 0, which S at θ′ = 90° exactly (z_r = 0) does not
    /// hold. Over r it adds ρ′² C_E/3 to ρ_eff, the step between [`Pbd::effective_albedo`] at
    /// grazing and the integral of [`Pbd::eval_surface_beam`] (tested).
    pub fn surface_ridge(&self, r: f64) -> f64 {
        if r.is_nan() || r <= 0.0 || r.is_infinite() {
            return 0.0;
        }
        let rho = self.diffusion.rho_prime;
        rho * rho * self.boundary.c_e() * -(-2.0 * r).exp_m1() * (-r).exp() / (2.0 * r)
    }

    /// The coefficient a of ln(1/φ) in [`Pbd::eval_surface_beam`] as φ → 0 at radius r > 0
    /// (reduced units): S = a·ln(1/φ) + O(1), a = 2ρ′² C_φ κ e^{−r}/(4πD), κ = 1 − e^{−2r}. The
    /// fluence's 1/d_r at the beam point under the exit point, t* = r cos φ → r, integrates to
    /// 2 ln(1/h) with h = r sin φ times the rest of the integrand there; the flux terms stay
    /// finite (z_r = 0). 0 for r ≤ 0 or not finite.
    pub fn surface_log_coefficient(&self, r: f64) -> f64 {
        if !(r > 0.0 && r.is_finite()) {
            return 0.0;
        }
        self.log_amplitude(r) * (-r).exp()
    }

    /// 2ρ′² C_φ κ(t)/(4πD), κ(t) = 1 − e^{−2t}: the coefficient of ln(1/h) that the fluence's
    /// 1/d_r gives a beam passing at distance h → 0 under the exit point at t, less the beam's
    /// attenuation e^{−t} ([`Pbd::surface_log_coefficient`], and the closed-form term of a beam
    /// grazing the exit point in `setup`).
    fn log_amplitude(&self, t: f64) -> f64 {
        let ReducedDiffusion { rho_prime, d, .. } = self.diffusion;
        2.0 * rho_prime * rho_prime * self.boundary.c_phi() / (4.0 * PI * d) * -(-2.0 * t).exp_m1()
    }

    /// σtr, per reduced mean free path: the rate at which S falls far from the sources.
    pub fn sigma_tr(&self) -> f64 {
        self.diffusion.sigma_tr
    }

    /// ln S_p^MS, accurate where S itself underflows (−∞ where S = 0).
    pub fn ln_eval(&self, theta: f64, r: f64, phi: f64, rule: Rule) -> f64 {
        self.evaluate(theta, r, phi, rule.into()).ln_value()
    }

    /// The reference value with the quadrature's own error estimate (relative), for tests
    /// and the CLI. Returns (value, estimated relative error, converged).
    pub fn eval_reference_with_error(&self, theta: f64, r: f64, phi: f64) -> (f64, f64, bool) {
        let e = self.evaluate(theta, r, phi, Quadrature::Reference);
        let value = e.value();
        let rel = if value > 0.0 {
            e.error * (e.ln_scale - value.ln()).exp()
        } else {
            0.0
        };
        (value, rel, e.converged)
    }

    /// The slope k = ρ′² C_E cos θ′/π of S against ln(1/r) as r → 0: near the entry point the
    /// beam's flux term, z_r/d_r³ with κ ≈ 2(d_r + t) ≈ 4t, integrates k/t from t ~ r outward;
    /// the other terms stay finite. 0 where no light enters.
    pub fn log_slope(&self, theta: f64) -> f64 {
        self.log_slope_refracted(self.refract(theta))
    }

    /// [`Pbd::log_slope`] of the refracted beam (sin θ′, cos θ′); 0 for `None`.
    fn log_slope_refracted(&self, refracted: Option<(f64, f64)>) -> f64 {
        let Some((_, cos_t)) = refracted else {
            return 0.0;
        };
        let rho = self.diffusion.rho_prime;
        rho * rho * self.boundary.c_e() * cos_t / PI
    }

    /// (sin θ′, cos θ′) of the refracted beam; `None` where no light enters
    /// ([`crate::fresnel::refracted_cos`]).
    fn refract(&self, theta: f64) -> Option<(f64, f64)> {
        let eta = self.boundary.eta();
        let cos_t = crate::fresnel::refracted_cos(theta, eta)?;
        Some(((theta.sin() / eta).min(1.0), cos_t))
    }

    fn evaluate(&self, theta: f64, r: f64, phi: f64, rule: Quadrature) -> Evaluated {
        self.evaluate_refracted(self.refract(theta), r, phi, rule)
    }

    /// [`Pbd::evaluate`] of the refracted beam (sin θ′, cos θ′); `None` where no light enters.
    fn evaluate_refracted(
        &self,
        refracted: Option<(f64, f64)>,
        r: f64,
        phi: f64,
        rule: Quadrature,
    ) -> Evaluated {
        if r > 0.0 && r < R_SMALL {
            // The small-r expansion: S(r) = S(R_SMALL) + k·ln(R_SMALL/r), with ln r taken
            // apart so that R_SMALL/r cannot overflow at subnormal r.
            let mut at = self.evaluate_refracted(refracted, R_SMALL, phi, rule);
            at.scaled += self.log_slope_refracted(refracted)
                * (R_SMALL.ln() - r.ln())
                * (-at.ln_scale).exp();
            return at;
        }
        match self.setup(refracted, r, phi) {
            Setup::Value(v) => Evaluated::exact(v),
            Setup::Integrate(beam, log_scaled) => {
                let (scaled, error, converged) = match rule {
                    Quadrature::Reference => {
                        let est = self.reference(&beam);
                        (est.value, est.error, est.converged)
                    }
                    Quadrature::Fast => (self.fast(&beam), 0.0, true),
                    Quadrature::Node => (self.node(&beam), 0.0, true),
                };
                Evaluated {
                    scaled: scaled + log_scaled,
                    ln_scale: -beam.m,
                    error,
                    converged,
                }
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
        let Some((_, cos_t)) = self.refract(theta) else {
            return 0.0;
        };
        if self.diffusion.rho_prime == 0.0 {
            return 0.0;
        }
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

    fn setup(&self, refracted: Option<(f64, f64)>, r: f64, phi: f64) -> Setup {
        if !r.is_finite() || r < 0.0 || !phi.is_finite() || r > R_LARGE {
            // Beyond R_LARGE, S < 1e-24 and its exponent is no longer resolved: 0.
            return Setup::Value(0.0);
        }
        // Where no light enters, or with ρ′ = 0 where nothing scatters, S = 0.
        let Some((sin_t, cos_t)) = refracted else {
            return Setup::Value(0.0);
        };
        if self.diffusion.rho_prime == 0.0 {
            return Setup::Value(0.0);
        }
        if r == 0.0 {
            return Setup::Value(f64::INFINITY);
        }
        let (sin_phi, cos_phi) = phi.sin_cos();
        let t_star = r * sin_t * cos_phi;
        // h = r·√(sin²φ + cos²θ′cos²φ), as a product so that it underflows only with h itself.
        let h_over_r = sin_phi.hypot(cos_t * cos_phi);
        let mut h = r * h_over_r;
        // Closer than this the beam is taken at this distance plus a closed-form log term
        // (relative to r too, so that |u| stays below ~670 over the beam).
        let floor = H_FLOOR.max(r * 1e-290);
        // ln(floor/h) where the beam passes closer than the floor, else 0.
        let mut log_ratio = 0.0;
        if h < floor {
            if h_over_r == 0.0 {
                // The beam runs along the surface through the exit point.
                return Setup::Value(f64::INFINITY);
            }
            // Only a beam along the surface (cos θ′ = 0: η = 1 and θ within 1e-8 of 90°, or
            // sin θ = η < 1) at φ within ~1e-268 of 0 comes this close, so t* = r > 0.
            log_ratio = floor.ln() - r.ln() - h_over_r.ln();
            h = floor;
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
        // The grazing beam's only singular term is the fluence's 1/d_r at t*, which
        // integrates to 2 ln(1/h) times the rest of the integrand there; so
        // S(h) = S(floor) + A ln(floor/h), with A = 2ρ′² C_φ κ(t*) e^{−t*}/(4πD) and
        // κ(t*) = 1 − e^{−2t*} (d_r = 0); scaled by e^{m} as the integral is (m ≤ t* + σtr h).
        let log_scaled = if log_ratio > 0.0 {
            self.log_amplitude(t_star) * (m - t_star).exp() * log_ratio
        } else {
            0.0
        };
        Setup::Integrate(
            Beam {
                cos_t,
                t_star,
                h,
                m,
                t_min,
            },
            log_scaled,
        )
    }

    /// The integrand in u (dt = d_r du), scaled by e^{m}.
    #[inline]
    fn integrand(&self, beam: &Beam, u: f64) -> f64 {
        let point = self.point(beam, u, u.abs().exp());
        let [e_r, kappa, lost] = self.point_exponentials(beam, &point);
        self.point_value(&point, e_r, kappa, lost)
    }

    /// The integrand's beam point at u, from e^{|u|} (`exp_abs_u`).
    #[inline(always)]
    fn point(&self, beam: &Beam, u: f64, exp_abs_u: f64) -> Point {
        let z_b = self.z_b;
        let (sinh_u, cosh_u) = sinh_cosh(u, exp_abs_u);
        let t = (beam.t_star + beam.h * sinh_u).max(0.0);
        let d_r = beam.h * cosh_u;
        let z_r = t * beam.cos_t;
        let z_v = z_r + 2.0 * z_b;
        let dv2_minus_dr2 = 4.0 * z_b * (z_r + z_b);
        let d_v = (d_r * d_r + dv2_minus_dr2).sqrt();
        let delta = dv2_minus_dr2 / (d_v + d_r);
        Point {
            t,
            d_r,
            z_r,
            z_v,
            d_v,
            delta,
        }
    }

    /// The point's three exponentials: e^{m − t − σtr d_r} and, for the value,
    /// κ = 1 − e^{−2(d_r + t)} (exactly 1 in f64 once the exponent passes 40) and
    /// 1 − e^{−σtr δ}.
    #[inline(always)]
    fn point_exponentials(&self, beam: &Beam, p: &Point) -> [f64; 3] {
        let sigma_tr = self.diffusion.sigma_tr;
        let e_r = (beam.m - p.t - sigma_tr * p.d_r).exp();
        let kappa = if p.d_r + p.t > 20.0 {
            1.0
        } else {
            one_minus_exp_neg(2.0 * (p.d_r + p.t))
        };
        [e_r, kappa, one_minus_exp_neg(sigma_tr * p.delta)]
    }

    /// The integrand at the point, from its exponentials ([`Pbd::point_exponentials`]).
    #[inline(always)]
    fn point_value(&self, p: &Point, e_r: f64, kappa: f64, lost: f64) -> f64 {
        let ReducedDiffusion {
            rho_prime,
            d,
            sigma_tr,
        } = self.diffusion;
        if e_r == 0.0 {
            return 0.0;
        }
        let Point {
            d_r,
            z_r,
            z_v,
            d_v,
            delta,
            ..
        } = *p;
        // d_r·(e^{−σ d_r}/d_r − e^{−σ d_v}/d_v) = e^{−σ d_r}·(1 − (d_r/d_v)e^{−σδ}), and
        // 1 − (d_r/d_v)e^{−σδ} = (1 − e^{−σδ}) + e^{−σδ}·δ/d_v: two non-negative terms.
        let image_ratio = 1.0 - lost;
        let fluence = self.boundary.c_phi() / (4.0 * PI * d) * (lost + image_ratio * delta / d_v);
        // z_r/d_r ≤ 1 first: d_r² underflows where the beam passes within 1e-154.
        let flux_real = (z_r / d_r) * (1.0 + sigma_tr * d_r) / d_r;
        // (d_r/d_v)/d_v² rather than d_r/d_v³, which overflows from d_v ≈ 6e102.
        let flux_virtual = z_v * (1.0 + sigma_tr * d_v) * image_ratio * (d_r / d_v) / (d_v * d_v);
        let flux = self.boundary.c_e() / (4.0 * PI) * (flux_real + flux_virtual);
        rho_prime * rho_prime * kappa * e_r * (fluence + flux)
    }

    /// Panel edges in u. The integrand is e^{−(f(t) − m)} times algebraic factors, with
    /// f(t) = t + σtr d_r(t) convex in t. Edges go
    /// - where f − m reaches each of [`LEVELS`] on both sides of its minimum
    ///   ([`level_crossings`] on the monotone branches); the integral starts at t = 0, or where
    ///   f − m falls to the last level if it starts above, and ends where it rises to it;
    /// - at the closest approach t* (u = 0), where the algebraic factors peak, and at u = ±2, ±5
    ///   around it;
    /// - and every panel wider than [`MAX_PANEL_U`] is split ([`split_panel`]): the algebraic
    ///   factors vary like e^{±u} away from the peak, which one 8-point panel integrates to
    ///   1e-11 over that width (small r, or a beam just under the surface, spread them over
    ///   tens to hundreds of units of u).
    fn breaks(&self, beam: &Beam) -> ([f64; MAX_EDGES], usize) {
        let sigma_tr = self.diffusion.sigma_tr;
        let f = |t: f64| {
            let dt = t - beam.t_star;
            t + sigma_tr * (dt * dt + beam.h * beam.h).sqrt() - beam.m
        };
        let t_min = beam.t_min;
        // Edges in t, increasing: left branch (decreasing on [0, t_min]) from the far level
        // inward, the minimum, the right branch outward.
        // Left: each level from the previous one outward, down to t = 0 (the last level's
        // edge is the integral's start, 0 where f starts below it).
        let mut left = [0.0f64; LEVELS.len()];
        let mut n_left = 0;
        let f_entry = f(0.0);
        let crossings = LEVELS.map(|level| level_crossings(sigma_tr, beam, level));
        for (level, &(falling, _)) in LEVELS.iter().zip(&crossings) {
            if t_min > 0.0 && f_entry > *level {
                left[n_left] = falling;
                n_left += 1;
            }
        }
        if n_left < LEVELS.len() {
            left[n_left] = 0.0;
            n_left += 1;
        }
        let mut ts = [0.0f64; 2 * LEVELS.len() + 1];
        let mut k = 0;
        for &t in left[..n_left].iter().rev() {
            ts[k] = t;
            k += 1;
        }
        ts[k] = t_min;
        k += 1;
        // Right, likewise outward.
        for &(_, rising) in &crossings {
            ts[k] = rising;
            k += 1;
        }
        let to_u = |t: f64| ((t - beam.t_star) / beam.h).asinh();
        let (u_first, u_last) = (to_u(ts[0]), to_u(ts[k - 1]));
        // Merge the level edges with the ones around the closest approach.
        let mut merged = [0.0f64; MERGED_EDGES];
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
        let mut len = 1;
        for &b in &merged[1..n] {
            let a = out[len - 1];
            if b <= a {
                continue;
            }
            len = split_panel(a, b, &mut out, len);
        }
        if len < 2 {
            out[1] = out[0];
            len = 2;
        }
        (out, len)
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
        self.composite(
            beam,
            RULE.get_or_init(|| GaussLegendre::new(FAST_POINTS_PER_PANEL)),
        )
    }

    fn node(&self, beam: &Beam) -> f64 {
        static RULE: OnceLock<GaussLegendre> = OnceLock::new();
        self.composite(
            beam,
            RULE.get_or_init(|| GaussLegendre::new(NODE_POINTS_PER_PANEL)),
        )
    }

    /// `rule` on each panel of [`Pbd::breaks`].
    fn composite(&self, beam: &Beam, rule: &GaussLegendre) -> f64 {
        let (breaks, n) = self.breaks(beam);
        breaks[..n]
            .windows(2)
            .map(|w| self.panel(beam, rule, w[0], w[1]))
            .sum()
    }

    /// `rule.integrate(a, b, |u| self.integrand(beam, u))` bit for bit (the same operations on
    /// each point, summed in the same order), for rules of at most [`MAX_PANEL_POINTS`] points,
    /// in passes over the panel's points: their exponentials of |u|, their geometry, their
    /// three exponentials each, their values. Each point is a chain of dependent operations
    /// through two exponentials; point by point, little more than one chain is in flight at a
    /// time, in passes the points' chains overlap.
    fn panel(&self, beam: &Beam, rule: &GaussLegendre, a: f64, b: f64) -> f64 {
        let (x, w) = (rule.nodes(), rule.weights());
        let n = x.len();
        if n > MAX_PANEL_POINTS {
            return rule.integrate(a, b, |u| self.integrand(beam, u));
        }
        let half = 0.5 * (b - a);
        let mid = 0.5 * (a + b);
        let mut u = [0.0; MAX_PANEL_POINTS];
        let mut exp_abs_u = [0.0; MAX_PANEL_POINTS];
        for k in 0..n {
            u[k] = mid + half * x[k];
            exp_abs_u[k] = u[k].abs().exp();
        }
        let points: [Point; MAX_PANEL_POINTS] = std::array::from_fn(|k| {
            if k < n {
                self.point(beam, u[k], exp_abs_u[k])
            } else {
                Point::default()
            }
        });
        let mut exponentials = [[0.0; 3]; MAX_PANEL_POINTS];
        for k in 0..n {
            exponentials[k] = self.point_exponentials(beam, &points[k]);
        }
        let mut sum = 0.0;
        for k in 0..n {
            let [e_r, kappa, lost] = exponentials[k];
            sum += w[k] * self.point_value(&points[k], e_r, kappa, lost);
        }
        sum * half
    }
}

/// Pushes the edges of [a, b] after a into `out` from index `m` and returns the new length:
/// equal pieces at most [`MAX_PANEL_U`] wide up to four of them; a wider panel gets pieces
/// [`MAX_PANEL_U`] wide at both ends, doubling toward the middle. Away from the peak
/// and from the level edges (where t − t* is between ~100h and ~1) the integrand is a constant
/// plus terms like e^{−|u − u_end|}, which each end's panels resolve and the doubling ones
/// follow at no cost: a beam 10⁻²⁰⁰ from the exit point spreads that stretch over 460 units
/// of u, 15 panels instead of 184.
fn split_panel(a: f64, b: f64, out: &mut [f64; MAX_EDGES], mut m: usize) -> usize {
    let width = b - a;
    if width <= 4.0 * MAX_PANEL_U {
        // Up to four equal pieces.
        let pieces = (width / MAX_PANEL_U).ceil().max(1.0);
        for i in 1..pieces as usize {
            out[m] = a + width * i as f64 / pieces;
            m += 1;
        }
        out[m] = b;
        return m + 1;
    }
    let offset = |k: usize| MAX_PANEL_U * f64::from(1u32 << k);
    // Offsets below half the width (at least 2.5 and 5), leaving room for the edges still to
    // come (each merged edge may bring four).
    let room = MAX_EDGES.saturating_sub(4 * MERGED_EDGES + m) / 2;
    let count = (0..room.min(20))
        .take_while(|&k| offset(k) < 0.5 * width)
        .count();
    for k in 0..count {
        out[m] = a + offset(k);
        m += 1;
    }
    for k in (0..count).rev() {
        out[m] = b - offset(k);
        m += 1;
    }
    out[m] = b;
    m + 1
}

/// (sinh u, cosh u) from one exponential, e = e^{|u|}. sinh u = (eᵘ − e⁻ᵘ)/2 is within 4ε·cosh u (tested):
/// absolute, not relative, near u = 0, which is all the beam needs (t = t* + h sinh u is then
/// exact to about h·10⁻¹⁵, and the Gauss nodes nearest u = 0, an edge of every panel that
/// reaches it, are 0.02 of a panel's width away). `exp` rather than `exp_m1`: half the
/// latency, at the head of every point's chain of dependent operations.
#[inline]
fn sinh_cosh(u: f64, e: f64) -> (f64, f64) {
    let inverse = 1.0 / e;
    let sinh = 0.5 * (e - inverse);
    let cosh = 0.5 * (e + inverse);
    (sinh.copysign(u), cosh)
}

/// 1 − e⁻ˣ for x ≥ 0, within 3·10⁻¹³ relative: by `exp` where x > 10⁻³ (the subtraction
/// loses at most 10 bits there, far below the reference rule's 10⁻¹⁰), by `exp_m1` below.
/// `exp` has half the latency of `exp_m1`.
#[inline]
fn one_minus_exp_neg(x: f64) -> f64 {
    if x > 1e-3 {
        1.0 - (-x).exp()
    } else {
        -(-x).exp_m1()
    }
}

/// Where f(t) = t + σ·√((t − t*)² + h²) − m, σ = `sigma` and (t*, h, m) of `beam`, equals
/// `level` > 0, on its falling and on its rising branch: (falling, rising) in t. f is convex, 0
/// at its least point t_min ≥ 0; it falls to it from t = 0 only where σ > 1 (the falling value
/// is meaningful where f(0) > `level`).
///
/// With d = t − t* and K = level + m − t*, f = level is σ√(d² + h²) = K − d, which squared is
/// (σ² − 1)d² + 2Kd + σ²h² − K² = 0 with roots d = (−K ± σ√(K² − (σ² − 1)h²))/(σ² − 1); the one
/// with + is on the rising branch for every σ (the other root then gives K − d < 0 for σ < 1),
/// the one with − on the falling branch for σ > 1. As σ → 1 the rising one is written
/// (K² − σ²h²)/(K + σ√(…)), without cancellation where K ≥ 0 (K < 0 only for σ < 1, where the
/// first form has none). K² − (σ² − 1)h² ≥ 0: for σ > 1, m ≥ t* + h√(σ² − 1) (the least value
/// of t + σ√(d² + h²) over all t), so K ≥ level + h√(σ² − 1).
fn level_crossings(sigma: f64, beam: &Beam, level: f64) -> (f64, f64) {
    let (t_star, h) = (beam.t_star, beam.h);
    let k = level + beam.m - t_star;
    let a = (sigma - 1.0) * (sigma + 1.0);
    let root = sigma * (k * k - a * h * h).max(0.0).sqrt();
    let rising = if k >= 0.0 {
        (k - sigma * h) * (k + sigma * h) / (k + root)
    } else {
        (root - k) / a
    };
    let falling = -(k + root) / a;
    (t_star + falling, t_star + rising)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{SeedableRng, SplitMix64, UnitF64};

    /// A panel in passes ([`Pbd::panel`]) is the rule applied point by point to the integrand,
    /// bit for bit: every panel of 3,000 random evaluations (η, ρ′, θ, r, φ over the domain,
    /// beams grazing the exit point included), with the fast rule's 8 points and the node
    /// rule's 6.
    #[test]
    fn a_panel_in_passes_is_the_rule_point_by_point() {
        let mut rng = SplitMix64::seed_from_u64(21);
        let rules = [
            GaussLegendre::new(FAST_POINTS_PER_PANEL),
            GaussLegendre::new(NODE_POINTS_PER_PANEL),
        ];
        let mut panels = 0;
        for case in 0..3000 {
            let eta = 0.75 + 1.75 * rng.next_f64();
            let rho = 1.0 - 10f64.powf(-6.0 * rng.next_f64());
            let pbd = Pbd::new(rho, Boundary::new(eta, Moments::Exact).unwrap()).unwrap();
            let theta = 0.5 * PI * rng.next_f64().sqrt();
            let r = 10f64.powf(6.0 * rng.next_f64() - 4.0);
            let phi = if case % 5 == 0 {
                0.0
            } else {
                PI * rng.next_f64()
            };
            let Setup::Integrate(beam, _) = pbd.setup(pbd.refract(theta), r, phi) else {
                continue;
            };
            let (breaks, n) = pbd.breaks(&beam);
            for w in breaks[..n].windows(2) {
                for rule in &rules {
                    let passes = pbd.panel(&beam, rule, w[0], w[1]);
                    let by_point = rule.integrate(w[0], w[1], |u| pbd.integrand(&beam, u));
                    assert_eq!(passes.to_bits(), by_point.to_bits(), "case {case}");
                    panels += 1;
                }
            }
        }
        assert!(panels > 20_000, "{panels} panels");
    }

    /// The two exponential leaves of the integrand against std's functions, over their whole
    /// range: 1 − e⁻ˣ within 3·10⁻¹³ relative, sinh u within 4ε·cosh u (absolute near 0, a
    /// few ulps relative beyond 1), cosh u within 4 ulps.
    #[test]
    fn one_minus_exp_neg_and_sinh_cosh_hold_their_bounds() {
        let mut rng = SplitMix64::seed_from_u64(11);
        for k in 0..200_000 {
            let x = if k == 0 {
                0.0
            } else {
                10f64.powf(-300.0 + 303.0 * rng.next_f64())
            };
            let (got, want) = (one_minus_exp_neg(x), -(-x).exp_m1());
            assert!(
                got == want || (got / want - 1.0).abs() <= 3e-13,
                "x = {x}: {got} {want}"
            );
            let u = (2.0 * rng.next_f64() - 1.0) * 10f64.powf(-8.0 + 10.8 * rng.next_f64());
            let (sinh, cosh) = sinh_cosh(u, u.abs().exp());
            assert!(
                (sinh - u.sinh()).abs() <= 4.0 * f64::EPSILON * u.cosh(),
                "sinh {u}"
            );
            assert!(
                (cosh / u.cosh() - 1.0).abs() <= 4.0 * f64::EPSILON,
                "cosh {u}"
            );
        }
    }

    /// [`level_crossings`] against f itself, on beams of random media, incidences and exit
    /// points (r log-uniform over 10⁻⁶ … 10⁸, φ log-uniform down to 10⁻⁸ so that beams pass
    /// close, ρ′ near 0.5 where σtr = 1 for a quarter): each edge lies on its branch and f
    /// there is the level to 10⁻⁹ of f's scale.
    #[test]
    fn level_crossings_are_on_their_level_and_branch() {
        let mut rng = SplitMix64::seed_from_u64(9);
        let mut checked = 0;
        for _ in 0..20_000 {
            let rho = if rng.next_f64() < 0.25 {
                0.5 + 1e-3 * (rng.next_f64() - 0.5)
            } else {
                rng.next_f64()
            };
            let eta = 0.8 + 1.7 * rng.next_f64();
            let theta = 0.5 * PI * rng.next_f64();
            let r = 10f64.powf(-6.0 + 14.0 * rng.next_f64());
            let phi = 10f64.powf(-8.0 + 8.5 * rng.next_f64()).min(PI);
            let Ok(pbd) = Pbd::new(rho, Boundary::new(eta, Moments::Exact).unwrap()) else {
                continue;
            };
            let Setup::Integrate(beam, _) = pbd.setup(pbd.refract(theta), r, phi) else {
                continue;
            };
            let sigma = pbd.diffusion.sigma_tr;
            let f = |t: f64| {
                let d = t - beam.t_star;
                t + sigma * (d * d + beam.h * beam.h).sqrt() - beam.m
            };
            for level in LEVELS {
                let (falling, rising) = level_crossings(sigma, &beam, level);
                let scale = level + beam.m + rising.abs();
                assert!(rising >= beam.t_min, "{beam:?} {level}: {rising}");
                assert!(
                    (f(rising) - level).abs() <= 1e-9 * scale,
                    "{beam:?} {level}"
                );
                if beam.t_min > 0.0 && f(0.0) > level {
                    assert!((0.0..=beam.t_min).contains(&falling), "{beam:?}: {falling}");
                    let scale = level + beam.m + falling.abs();
                    assert!(
                        (f(falling) - level).abs() <= 1e-9 * scale,
                        "{beam:?} {level}"
                    );
                }
                checked += 1;
            }
        }
        assert!(checked > 50_000, "{checked}");
    }
}
