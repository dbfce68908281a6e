//! The diffuse reflectance A of a table and its inverse: the reduced albedo ρ′ that gives the
//! reflectance an artist asks for.
//!
//! # The quantity
//!
//! For a collimated beam arriving at incidence θ (before refraction) on the smooth boundary of a
//! half-space of relative index η,
//!
//! A(ρ′, θ) = T(θ) ρ_eff(ρ′, θ), T(θ) = 1 − F_r(cos θ; η),
//!
//! is the power that leaves the surface after multiple scattering, anywhere and in any
//! direction, per unit power arriving:
//!
//! - ρ_eff(ρ′, θ) = ∫ E dr ([`TableRef::effective_albedo`]) is the table's multiply scattered
//!   power leaving per unit power **entering**. The exit Fresnel transmission is already in it:
//!   PBD's exitance is C_φ φ + C_E E·n, and C_φ = (1 − 2F₁)/4 = ½∫₀¹ (1 − F_r(μ)) μ dμ,
//!   C_E = (1 − 3F₂)/2 are the hemispherical moments of the internal boundary's transmittance
//!   (`medium`, docs/physics.md): the diffuse radiance's flux through the boundary after its
//!   internal reflection.
//! - T(θ) ([`crate::fresnel::entry_transmittance`]) is the share of the arriving power that
//!   enters. What the boundary reflects at once, F_r(θ), is the renderer's specular lobe, not
//!   part of A. T is 0 at grazing incidence and, for η < 1, beyond the critical angle asin η.
//! - Single scattering is not in PBD, so not in A (pbrt's ρ_eff adds it: 1.019 at ρ′ = 1,
//!   η = 1.33, against PBD's 0.9613, docs/physics.md); nor is the power the table leaves
//!   beyond its last radius (1.1 % of PBD's at ρ′ = 1, η = 1.33 on the default grid,
//!   docs/scenes.md).
//!
//! A is what a renderer shows as the subsurface colour of a material lit at θ: the
//! directional-hemispherical reflectance of the BSSRDF (pbrt's `SubsurfaceFromDiffuse` inverts
//! ρ_eff alone, so its rendered colour is T(0) times the value asked for, 2 % less at η = 1.33).
//!
//! # The inverse
//!
//! [`TableRef::rho_prime_for_reflectance`] solves A(ρ′, θ) = A on the table's own curve: the
//! same ρ_eff lookup, the same T, so that `diffuse_reflectance` at the ρ′ found gives A back to
//! the curve's own resolution (its rows blend with f32 weights: steps of about 1e-7 of A).
//! The values A takes are [A(ρ′₀, θ), A(ρ′ₙ, θ)], ρ′₀ and ρ′ₙ the first and last albedo rows
//! (0 and 1 for a full table, some rows of it for a scene bake); outside, and for NaN, the
//! inverse is an error naming the value and that range: a table is never extrapolated.
//!
//! The solver is bisection with a fixed sequence of probes: first over the albedo nodes, then
//! over the f64 values between the two nodes that bracket A, halving the distance between their
//! order keys (the bit patterns, arranged so that integer order is the numbers' order), so that
//! it ends on two neighbouring f64 after at most 64 steps whatever the scale of ρ′ (A = 1e-30
//! needs ρ′ ≈ 1e-15, which halving the interval itself would take about 100 steps to resolve
//! to its last bit). Each step keeps A(lo) ≤ A < A(hi); the end takes whichever of the two
//! neighbours is closer in A. Every probe depends only on the outcomes of the comparisons
//! before it, so for A₁ < A₂ the two searches agree until the first probe p they judge
//! differently, after which the first stays ≤ p and the second ≥ p: the inverse is monotone in
//! A by construction, even where f32 rounding makes the curve step down (by about 1e-7 of A).
//! It costs about 70 lookups of ρ_eff.

use super::TableRef;
use crate::error::number;
use crate::fresnel::entry_transmittance;

/// Why no reduced albedo could be found for a diffuse reflectance.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReflectanceError {
    /// θ is NaN or outside the table's θ axis.
    #[error(
        "theta = {} rad ({} deg) is outside the table's incidence axis, [{}, {}] rad",
        number(*theta),
        number(theta.to_degrees()),
        number(*min),
        number(*max)
    )]
    Theta {
        /// θ asked for, radians.
        theta: f64,
        /// Smallest θ the table takes, radians ([`TableRef::theta_domain`]).
        min: f64,
        /// Largest θ the table takes, radians.
        max: f64,
    },
    /// Nothing is reflected diffusely at θ, whatever ρ′: grazing incidence, or beyond the
    /// critical angle of an η < 1.
    #[error(
        "no light enters at theta = {} rad ({} deg) with eta = {} (grazing incidence, or beyond the critical angle of an eta below 1): every rho' gives a diffuse reflectance of 0",
        number(*theta),
        number(theta.to_degrees()),
        number(*eta)
    )]
    NoLight {
        /// θ asked for, radians.
        theta: f64,
        /// η of the table.
        eta: f64,
    },
    /// The reflectance is NaN or outside the range the table reaches at θ.
    #[error(
        "reflectance {} is outside [{}, {}], the diffuse reflectance (1 - F_r) rho_eff this table reaches at theta = {} deg (multiple scattering only; rho' from {} to {})",
        number(*reflectance),
        number(*min),
        number(*max),
        number(theta.to_degrees()),
        number(*rho_min),
        number(*rho_max)
    )]
    OutOfRange {
        /// The reflectance asked for.
        reflectance: f64,
        /// A at the first albedo row.
        min: f64,
        /// A at the last albedo row.
        max: f64,
        /// θ, radians.
        theta: f64,
        /// The first albedo row's ρ′.
        rho_min: f64,
        /// The last albedo row's ρ′.
        rho_max: f64,
    },
}

impl TableRef<'_> {
    /// The diffuse reflectance A(ρ′, θ) = T(θ) ρ_eff(ρ′, θ) for light arriving at incidence θ
    /// (radians, before refraction): multiply scattered power leaving per unit power arriving,
    /// the entry Fresnel transmittance T = 1 − F_r(cos θ; η) included (module docs). `None`
    /// where [`TableRef::effective_albedo`] is (ρ′ or θ outside the axes).
    pub fn diffuse_reflectance(&self, rho: f64, theta: f64) -> Option<f64> {
        let rho_eff = self.effective_albedo(rho, theta)?;
        Some(entry_transmittance(theta, self.eta) * rho_eff)
    }

    /// [A(ρ′₀, θ), A(ρ′ₙ, θ)], the diffuse reflectance at the first and the last albedo row:
    /// the values [`TableRef::rho_prime_for_reflectance`] accepts at θ ([0, 0] where no light
    /// enters). An error for θ outside the table's θ axis or NaN.
    pub fn reflectance_range(&self, theta: f64) -> Result<[f64; 2], ReflectanceError> {
        let nodes = self.axes.rho().as_slice();
        let (first, last) = (nodes[0], nodes[nodes.len() - 1]);
        let at = |rho| self.diffuse_reflectance(rho, theta);
        match (at(first), at(last)) {
            (Some(min), Some(max)) => Ok([min, max]),
            _ => {
                let [min, max] = self.theta_domain();
                Err(ReflectanceError::Theta { theta, min, max })
            }
        }
    }

    /// The reduced albedo ρ′ whose diffuse reflectance at incidence θ (radians) is
    /// `reflectance`: A(ρ′, θ) = `reflectance` on this table's curve, to its resolution (module
    /// docs: bisection to neighbouring f64, monotone in the reflectance by construction).
    ///
    /// Errors: θ outside the θ axis or NaN; no light entering at θ (grazing incidence, beyond
    /// the critical angle); a reflectance outside [`TableRef::reflectance_range`] or NaN, named
    /// with that range. Allocates nothing (on success).
    pub fn rho_prime_for_reflectance(
        &self,
        reflectance: f64,
        theta: f64,
    ) -> Result<f64, ReflectanceError> {
        let [min, max] = self.reflectance_range(theta)?;
        let nodes = self.axes.rho().as_slice();
        let n = nodes.len();
        if max <= 0.0 {
            return Err(ReflectanceError::NoLight {
                theta,
                eta: self.eta,
            });
        }
        if !(min..=max).contains(&reflectance) {
            return Err(ReflectanceError::OutOfRange {
                reflectance,
                min,
                max,
                theta,
                rho_min: nodes[0],
                rho_max: nodes[n - 1],
            });
        }
        if reflectance <= min {
            return Ok(nodes[0]);
        }
        if reflectance >= max {
            return Ok(nodes[n - 1]);
        }
        // Inside the axes (ρ′ between two nodes, θ checked above): always Some.
        let a = |rho: f64| self.diffuse_reflectance(rho, theta).unwrap_or(0.0);
        // The nodes that bracket the reflectance: A(lo) ≤ reflectance < A(hi)
        let (mut lo, mut hi) = (0, n - 1);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if a(nodes[mid]) <= reflectance {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        // Then the f64 between them, by their order keys
        let (mut lo, mut hi) = (order_key(nodes[lo]), order_key(nodes[hi]));
        let (mut a_lo, mut a_hi) = (a(from_order_key(lo)), a(from_order_key(hi)));
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            let a_mid = a(from_order_key(mid));
            if a_mid <= reflectance {
                (lo, a_lo) = (mid, a_mid);
            } else {
                (hi, a_hi) = (mid, a_mid);
            }
        }
        let closer = if reflectance - a_lo <= a_hi - reflectance {
            lo
        } else {
            hi
        };
        Ok(from_order_key(closer))
    }
}

const SIGN: u64 = 1 << 63;

/// A key whose order as an integer is the order of the (non-NaN) f64 `x`: the bits with the
/// sign flipped for x ≥ 0, all bits flipped for x < 0 (−0 just below +0). Neighbouring keys
/// are neighbouring f64.
fn order_key(x: f64) -> u64 {
    let bits = x.to_bits();
    if bits & SIGN == 0 {
        bits | SIGN
    } else {
        !bits
    }
}

/// The f64 of an [`order_key`].
fn from_order_key(key: u64) -> f64 {
    if key & SIGN != 0 {
        f64::from_bits(key & !SIGN)
    } else {
        f64::from_bits(!key)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_keys_sort_as_the_numbers_and_step_to_the_neighbours() {
        let xs = [-1.0, -1e-300, -0.0, 0.0, 5e-324, 1e-300, 0.5, 1.0];
        for w in xs.windows(2) {
            assert!(order_key(w[0]) < order_key(w[1]), "{w:?}");
        }
        for x in xs {
            assert_eq!(from_order_key(order_key(x)).to_bits(), x.to_bits());
        }
        assert_eq!(order_key(0.0) - order_key(-0.0), 1);
        assert_eq!(
            from_order_key(order_key(0.5) + 1),
            crate::float::next_up(0.5)
        );
    }
}
