//! The light: a narrow cone of directions about incidence θ, all hitting the surface at the
//! origin, and the Fresnel split at entry.
//!
//! | parameter | unit | range |
//! |---|---|---|
//! | θ, the cone's axis from the normal | radians | [0, π/2), with θ + δ < π/2 |
//! | δ, the cone's half-angle | radians | [0, π/2); 0 is a collimated beam |
//! | η, relative index of the medium | – | > 0 |
//!
//! Directions are uniform in solid angle inside the cone. The axis travels toward +x and down,
//! d₀ = (sin θ, 0, −cos θ). A photon's own incidence θᵢ and the azimuth ψ of its own plane of
//! incidence follow from its direction d: cos θᵢ = −d_z, ψ = atan2(d_y, d_x). The models place
//! exit points at (r, φ) relative to that plane, so the point in the image is
//! r (cos(ψ + φ), sin(ψ + φ)).
//!
//! Per unit incident power, the part R(θᵢ) (Fresnel, unpolarised, the same in every channel as η
//! is) is reflected specularly and leaves: it is reported, never imaged. T(θᵢ) = 1 − R(θᵢ)
//! enters and is the photon's weight. Splitting by weight rather than choosing reflection with
//! probability R costs nothing and removes that choice's variance.

use crate::fresnel;
use crate::walk::rng::{UnitF64, Xoshiro256PlusPlus};
use std::f64::consts::TAU;

/// The cone of incident light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Source {
    /// The axis d₀ = (sin θ, 0, −cos θ) and two unit vectors normal to it, (cos θ, 0, sin θ)
    /// and (0, 1, 0).
    axis: [f64; 3],
    across: [f64; 3],
    cos_cone: f64,
    eta: f64,
}

/// One photon's incidence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Incidence {
    /// θᵢ, radians from the normal, before refraction.
    pub theta: f64,
    /// cos ψ, sin ψ of the photon's plane of incidence (ψ = 0 for the axis).
    pub cos_psi: f64,
    pub sin_psi: f64,
    /// Fresnel reflectance R(θᵢ) at entry: this part leaves specularly.
    pub reflected: f64,
}

impl Incidence {
    /// Power entering per unit incident power, T = 1 − R.
    pub fn transmitted(&self) -> f64 {
        1.0 - self.reflected
    }

    /// The image point of an exit at distance r (mm) and azimuth φ from the photon's plane of
    /// incidence.
    pub fn place(&self, r: f64, phi: f64) -> (f64, f64) {
        let (s, c) = phi.sin_cos();
        (
            r * (c * self.cos_psi - s * self.sin_psi),
            r * (s * self.cos_psi + c * self.sin_psi),
        )
    }

    /// The image point of an exit at (x, y) in the photon's own frame (x forward).
    pub fn rotate(&self, x: f64, y: f64) -> (f64, f64) {
        (
            x * self.cos_psi - y * self.sin_psi,
            x * self.sin_psi + y * self.cos_psi,
        )
    }
}

impl Source {
    /// A cone about incidence `theta` of half-angle `cone` (radians, validated by the caller)
    /// onto a medium of relative index `eta`.
    pub fn new(theta: f64, cone: f64, eta: f64) -> Self {
        let (sin_t, cos_t) = theta.sin_cos();
        Self {
            axis: [sin_t, 0.0, -cos_t],
            across: [cos_t, 0.0, sin_t],
            cos_cone: cone.cos(),
            eta,
        }
    }

    /// Draws one photon's direction (two uniforms) and its Fresnel split.
    pub fn sample(&self, rng: &mut Xoshiro256PlusPlus) -> Incidence {
        // Uniform in solid angle: cos α uniform in [cos δ, 1].
        let cos_alpha = 1.0 - rng.next_f64() * (1.0 - self.cos_cone);
        let (sin_beta, cos_beta) = (TAU * rng.next_f64()).sin_cos();
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let (a, b) = (sin_alpha * cos_beta, sin_alpha * sin_beta);
        let d = [
            cos_alpha * self.axis[0] + a * self.across[0],
            b,
            cos_alpha * self.axis[2] + a * self.across[2],
        ];
        let cos_i = (-d[2]).clamp(0.0, 1.0);
        let horizontal = d[0].hypot(d[1]);
        let (cos_psi, sin_psi) = if horizontal > 0.0 {
            (d[0] / horizontal, d[1] / horizontal)
        } else {
            (1.0, 0.0)
        };
        Incidence {
            theta: cos_i.acos(),
            cos_psi,
            sin_psi,
            reflected: fresnel::reflectance(cos_i, self.eta),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walk::rng::photon_stream;

    #[test]
    fn a_collimated_beam_keeps_its_angle_and_plane() {
        let s = Source::new(60f64.to_radians(), 0.0, 1.33);
        let mut rng = photon_stream(3, 4);
        let i = s.sample(&mut rng);
        assert!((i.theta - 60f64.to_radians()).abs() < 1e-12);
        assert_eq!((i.cos_psi, i.sin_psi), (1.0, 0.0));
        let r = fresnel::reflectance(0.5, 1.33);
        assert!((i.reflected - r).abs() < 1e-12);
        assert!((i.transmitted() + i.reflected - 1.0).abs() < 1e-15);
    }

    #[test]
    fn cone_directions_stay_inside_the_cone() {
        let (theta, cone) = (30f64.to_radians(), 2f64.to_radians());
        let s = Source::new(theta, cone, 1.33);
        let mut rng = photon_stream(5, 6);
        let mut mean_psi = 0.0;
        for _ in 0..2000 {
            let i = s.sample(&mut rng);
            assert!((i.theta - theta).abs() <= cone + 1e-12);
            // The plane of incidence turns by at most asin(sin δ / sin θ).
            let psi = i.sin_psi.atan2(i.cos_psi);
            assert!(psi.abs() <= (cone.sin() / theta.sin()).asin() + 1e-12);
            mean_psi += psi / 2000.0;
        }
        assert!(mean_psi.abs() < 0.005, "{mean_psi}");
    }

    #[test]
    fn placing_turns_by_the_plane_of_incidence() {
        let i = Incidence {
            theta: 0.3,
            cos_psi: 0.0,
            sin_psi: 1.0,
            reflected: 0.0,
        };
        let (x, y) = i.place(2.0, 0.0);
        assert!(x.abs() < 1e-15 && (y - 2.0).abs() < 1e-15);
        let (x, y) = i.rotate(1.0, 0.0);
        assert!(x.abs() < 1e-15 && (y - 1.0).abs() < 1e-15);
    }
}
