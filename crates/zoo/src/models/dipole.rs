//! The standard dipole (Jensen, Marschner, Levoy, Hanrahan 2001, "A practical model for
//! subsurface light transport", eqs. 4–5 and §2.4), with an exact sampler.
//!
//! | parameter | unit | valid range |
//! |---|---|---|
//! | ρ′ reduced albedo | – | [0, 1] |
//! | η relative index, inside over outside | – | [0.75, 2.5] |
//! | θ incidence before refraction | rad | [0, π/2]; no light enters beyond asin η when η < 1 → 0 |
//! | r exit distance | reduced mean free paths | ≥ 0 |
//! | result R(r) | per reduced mfp², per unit power entering | ≥ 0 |
//!
//! # The model, in reduced units (σ′t = 1)
//! Jensen's constants, not the Grosjean D of the rest of the crate: D = 1/(3σ′t) = 1/3,
//! σtr = √(3σaσ′t) = √(3(1 − ρ′)), a real source at depth z_r = 1/σ′t = 1 and a negative image
//! at height z_v = z_r + 4AD above it. Per unit power entering,
//!
//! R_d(r) = ρ′/(4π) [ z_r(1 + σtr d_r)e^{−σtr d_r}/d_r³ + z_v(1 + σtr d_v)e^{−σtr d_v}/d_v³ ],
//! d_r² = r² + z_r², d_v² = r² + z_v².
//!
//! Both terms are non-negative (z_v > 0 for every A > 0), so R_d never goes negative and needs
//! no clamp. It does not depend on θ or φ: the model knows only that light entered.
//!
//! **Boundary** ([`DipoleBoundary`]): by default Jensen's A = (1 + F_dr)/(1 − F_dr) with the
//! Egan–Hilgeman fit F_dr(η) = −1.440/η² + 0.710/η + 0.668 + 0.0636η. That fit is for η ≥ 1 (it
//! goes negative just below 1, and below η ≈ 0.54 would make A negative); for η < 1 the
//! internal diffuse reflectance 2F₁(η) of the chosen [`crate::fresnel::Moments`] is used instead (a jump of
//! 0.0016 in F_dr at η = 1). [`DipoleBoundary::Moments`] takes A = (1 + 3F₂)/(1 − 2F₁), the
//! constant of the rest of the crate.
//!
//! **From S_d to R.** Jensen's BSSRDF is S_d = (1/π) F_t(η, ω_i) R_d F_t(η, ω_o). Per unit power
//! entering (F_t(ω_i) dropped) the power leaving per unit area is S_d integrated against
//! F_t(ω_o) cos θ_o over the outgoing hemisphere:
//! R(r) = R_d(r) · (1/π)∫ F_t cos dω = R_d(r) · (1 − 2F₁(1/η)), where F₁(1/η) is the first
//! moment of the *external* reflectance (the Fresnel transmittance seen from outside; by
//! reciprocity the same as leaving at θ_o). The factor is 0.934 at η = 1.33 with exact moments.
//!
//! Totals (closed form, ∫ e^{−σd}(1 + σd)/d² dd = −e^{−σd}/d):
//! ∫∫ R_d dA = (ρ′/2)(e^{−σtr z_r} + e^{−σtr z_v}) (Jensen's eq. for the diffuse albedo).
//!
//! # Sampling (exact)
//! Each term is a distribution over the plane: the real term's radial CDF, in d, is
//! 1 − z e^{−σtr(d − z)}/d. A term is chosen with probability proportional to its energy
//! e^{−σtr z}, then d solves ln(d/z) + σtr(d − z) = −ln(1 − u) (safeguarded Newton on d − z),
//! r = √(d² − z²), φ uniform. The density is R_d/∫∫R_d: `sample` and `pdf` agree exactly.
//!
//! # Where it breaks down
//! Known to be inaccurate near the source (r ≲ 1 mfp) where it ignores the depth distribution
//! of first scattering and single scattering, and at low albedo; θ-independent by construction.
//! At ρ′ = 0 it is 0 everywhere; at ρ′ = 1 the profile falls off as a power law (σtr = 0).

use super::{entering, Model, ModelKind, Params, Sample};
use crate::walk::Component;
use std::f64::consts::PI;

/// Which boundary constant A the dipole uses.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum DipoleBoundary {
    /// Jensen et al.: A = (1 + F_dr)/(1 − F_dr) with the Egan–Hilgeman fit of F_dr (η ≥ 1).
    #[default]
    JensenFit,
    /// A = (1 + 3F₂)/(1 − 2F₁) from the model's Fresnel moments.
    Moments,
}

/// Options of the standard dipole.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct DipoleOptions {
    /// Boundary constant.
    pub boundary: DipoleBoundary,
}

/// Egan & Hilgeman's fit of the internal diffuse Fresnel reflectance, as used by Jensen et al.
pub fn jensen_fdr(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

/// The standard dipole for one medium, in reduced units.
#[derive(Debug, Clone, PartialEq)]
pub struct Dipole {
    params: Params,
    sigma_tr: f64,
    z_r: f64,
    z_v: f64,
    /// 1 − 2F₁(1/η): the hemispherical exit transmittance factor.
    exit: f64,
    /// e^{−σtr z_r} and e^{−σtr z_v}: the energies of the two terms (times ρ′/2).
    weight_r: f64,
    weight_v: f64,
}

impl Dipole {
    /// The dipole for validated parameters.
    pub fn new(params: Params, options: DipoleOptions) -> Self {
        let eta = params.eta();
        let (f1, f2) = params.moments().evaluate(eta);
        let a = match options.boundary {
            DipoleBoundary::JensenFit => {
                let fdr = if eta >= 1.0 {
                    jensen_fdr(eta)
                } else {
                    2.0 * f1
                };
                (1.0 + fdr) / (1.0 - fdr)
            }
            DipoleBoundary::Moments => (1.0 + 3.0 * f2) / (1.0 - 2.0 * f1),
        };
        let (f1_external, _) = params.moments().evaluate(1.0 / eta);
        let rho = params.rho_prime();
        let sigma_tr = (3.0 * (1.0 - rho)).sqrt();
        let d = 1.0 / 3.0;
        let z_r = 1.0;
        let z_v = z_r + 4.0 * a * d;
        Self {
            params,
            sigma_tr,
            z_r,
            z_v,
            exit: 1.0 - 2.0 * f1_external,
            weight_r: (-sigma_tr * z_r).exp(),
            weight_v: (-sigma_tr * z_v).exp(),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Height of the image source above the real one, z_v (reduced mfp).
    pub fn z_v(&self) -> f64 {
        self.z_v
    }

    /// The exit factor 1 − 2F₁(1/η) turning Jensen's R_d into exitance.
    pub fn exit_factor(&self) -> f64 {
        self.exit
    }

    /// Jensen's R_d(r) (before the exit factor), per reduced mfp².
    pub fn r_d(&self, r: f64) -> f64 {
        if r.is_nan() || r < 0.0 || r.is_infinite() {
            return 0.0;
        }
        let s = self.sigma_tr;
        let term = |z: f64| {
            let d = r.hypot(z);
            let decay = (-s * d).exp();
            // Far out e^{−σtr d} reaches 0 while σtr d overflows to ∞ (r near f64::MAX): 0·∞
            if decay == 0.0 {
                return 0.0;
            }
            z * (1.0 + s * d) * decay / (d * d * d)
        };
        self.params.rho_prime() / (4.0 * PI) * (term(self.z_r) + term(self.z_v))
    }

    /// ∫∫ R_d dA = (ρ′/2)(e^{−σtr z_r} + e^{−σtr z_v}).
    pub fn r_d_total(&self) -> f64 {
        0.5 * self.params.rho_prime() * (self.weight_r + self.weight_v)
    }

    /// Distance d ≥ z from a source at depth z with P(distance ≤ d) = u, for one dipole term.
    fn invert_term(&self, z: f64, u: f64) -> Option<f64> {
        let ln_tail = (-u).ln_1p(); // ln(1 − u) ≤ 0
        if !ln_tail.is_finite() {
            return None;
        }
        let s = self.sigma_tr;
        // f(δ) = ln(1 + δ/z) + σδ + ln(1 − u), increasing in δ = d − z ≥ 0.
        let f = |delta: f64| (delta / z).ln_1p() + s * delta + ln_tail;
        let by_power = z * (1.0 / (1.0 - u) - 1.0);
        let by_exponential = if s > 0.0 { -ln_tail / s } else { f64::INFINITY };
        let (mut lo, mut hi) = (0.0, by_power.min(by_exponential));
        if !hi.is_finite() {
            return None;
        }
        let mut delta = hi;
        for _ in 0..100 {
            let value = f(delta);
            if value > 0.0 {
                hi = delta;
            } else {
                lo = delta;
            }
            let slope = 1.0 / (z + delta) + s;
            let mut next = delta - value / slope;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - delta).abs() <= 1e-15 * next.max(f64::MIN_POSITIVE) || hi - lo <= 0.0 {
                delta = next;
                break;
            }
            delta = next;
        }
        Some(delta)
    }
}

impl Model for Dipole {
    fn kind(&self) -> ModelKind {
        ModelKind::Dipole
    }

    fn component(&self) -> Component {
        Component::Multiple
    }

    fn eval(&self, theta: f64, r: f64, _phi: f64) -> f64 {
        if entering(theta, self.params.eta()).is_none() {
            return 0.0;
        }
        self.exit * self.r_d(r)
    }

    fn effective_albedo(&self, theta: f64) -> Option<f64> {
        Some(match entering(theta, self.params.eta()) {
            Some(_) => self.exit * self.r_d_total(),
            None => 0.0,
        })
    }

    fn sample(&self, theta: f64, u: [f64; 2]) -> Option<Sample> {
        entering(theta, self.params.eta())?;
        let total = self.weight_r + self.weight_v;
        if self.params.rho_prime() <= 0.0 || total.is_nan() || total <= 0.0 {
            return None;
        }
        let p_real = self.weight_r / total;
        let (z, u_r) = if u[0] < p_real {
            (self.z_r, u[0] / p_real)
        } else {
            (self.z_v, ((u[0] - p_real) / (1.0 - p_real)).min(1.0))
        };
        let delta = self.invert_term(z, u_r)?;
        let r = (delta * (delta + 2.0 * z)).sqrt();
        let phi = crate::gwc::uniform_azimuth(u[1]);
        let pdf = self.pdf(theta, r, phi);
        (pdf.is_finite() && pdf > 0.0).then_some(Sample { r, phi, pdf })
    }

    fn pdf(&self, theta: f64, r: f64, _phi: f64) -> f64 {
        let total = self.r_d_total();
        if entering(theta, self.params.eta()).is_none() || total.is_nan() || total <= 0.0 {
            return 0.0;
        }
        self.r_d(r) / total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fresnel::Moments;

    fn dipole(rho: f64, eta: f64) -> Dipole {
        Dipole::new(
            Params::new(rho, eta, Moments::Exact).unwrap(),
            DipoleOptions::default(),
        )
    }

    #[test]
    fn total_matches_jensens_closed_form_albedo() {
        // Jensen et al. 2001: R_d = (α′/2)(1 + e^{−(4/3)A√(3(1−α′))}) e^{−√(3(1−α′))}.
        for (rho, eta) in [(0.5, 1.3), (0.9, 1.0), (0.99, 1.5)] {
            let d = dipole(rho, eta);
            let fdr = jensen_fdr(eta);
            let a = (1.0 + fdr) / (1.0 - fdr);
            let s = (3.0 * (1.0 - rho)).sqrt();
            let want = 0.5 * rho * (1.0 + (-4.0 / 3.0 * a * s).exp()) * (-s).exp();
            assert!((d.r_d_total() - want).abs() < 1e-14 * want);
            // And the plane integral of R_d agrees with it.
            let plane = crate::quadrature::adaptive(
                |y: f64| {
                    let r = y / (1.0 - y);
                    std::f64::consts::TAU * r * d.r_d(r) / ((1.0 - y) * (1.0 - y))
                },
                &[0.0, 0.5, 0.9, 0.99, 1.0],
                1e-11,
                1e-300,
                2000,
            );
            assert!((plane.value - want).abs() < 1e-9 * want, "{}", plane.value);
        }
    }

    #[test]
    fn sampled_distances_invert_the_term_cdf() {
        let d = dipole(0.8, 1.33);
        for z in [d.z_r, d.z_v] {
            for u in [1e-12, 1e-3, 0.3, 0.9, 1.0 - 1e-12] {
                let delta = d.invert_term(z, u).unwrap();
                let dist = z + delta;
                let cdf = 1.0 - z * (-d.sigma_tr * delta).exp() / dist;
                assert!(
                    (cdf - u).abs() < 1e-12 * u.max(1e-3),
                    "z {z} u {u} cdf {cdf}"
                );
            }
        }
        assert!(d.invert_term(1.0, 1.0).is_none());
    }

    #[test]
    fn exit_factor_is_one_minus_the_external_diffuse_reflectance() {
        let d = dipole(0.5, 1.33);
        let f1 = crate::fresnel::moment(1, 1.0 / 1.33);
        assert!((d.exit_factor() - (1.0 - 2.0 * f1)).abs() < 1e-15);
        assert!((d.exit_factor() - 0.934).abs() < 2e-3);
        assert!((dipole(0.5, 1.0).exit_factor() - 1.0).abs() < 1e-15);
    }
}
