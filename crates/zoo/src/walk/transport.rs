//! The path of one photon packet: free flights, scattering vertices, boundary events.
//!
//! Coordinates: entry point at the origin, outward normal +z, medium at −τ < z < 0 (τ = ∞ for
//! the half-space); distances in mean free paths (σt = 1). The refracted beam travels in the
//! x–z plane toward +x, so φ = atan2(y, x) = 0 is forward.
//!
//! One flight, from a point p in direction ω with weight w (see the module docs of
//! [`crate::walk`] for why this is unbiased):
//! 1. *Exit estimate.* If the ray p + tω meets a boundary at distance
//!    d ≤ [`EXPECTED_SCORE_DISTANCE`], score w · e^{−d} · T(|ω_z|) at the point where it meets
//!    it, for the current scattering order.
//! 2. *Flight.* Draw s, exponential with mean 1. If s < d: a scattering vertex at p + sω,
//!    w ← a·w, new direction from Henyey–Greenstein. Otherwise the packet reaches the boundary:
//!    its transmitted part w · T leaves (scored in step 1 when d ≤ [`EXPECTED_SCORE_DISTANCE`],
//!    here otherwise) and, with probability R = 1 − T, the packet continues with ω_z ← −ω_z;
//!    otherwise it stops. The unscattered beam continues with w ← R·w instead.
//! 3. *Roulette.* Below [`ROULETTE_WEIGHT`], survive with probability [`ROULETTE_SURVIVAL`] and
//!    divide the weight by it (MCML's constants), otherwise stop.

use super::exits::Sink;
use super::rng::{UnitF64, Xoshiro256PlusPlus};
use super::tally::{Order, Surface};
use crate::fresnel;
use rand_distr::{Distribution, Exp1};

/// Weight below which Russian roulette is played (Wang, Jacques, Zheng 1995, `WEIGHT`).
pub const ROULETTE_WEIGHT: f64 = 1e-4;
/// Survival probability of the roulette (MCML's `CHANCE`).
pub const ROULETTE_SURVIVAL: f64 = 0.1;
/// Flights that start at most this far from the boundary they head for (mean free paths)
/// score their expected transmitted part; farther ones reach it with probability below
/// e⁻⁶ ≈ 0.25 % and score only when they do (the walk's module docs, "Estimator").
pub const EXPECTED_SCORE_DISTANCE: f64 = 6.0;
/// A photon is stopped after this many scattering vertices and its weight is reported as
/// truncated. Only reached for albedo ≈ 1, where path lengths in a half-space have an
/// infinite mean (their tail falls like n^{−1/2}).
pub const MAX_VERTICES: u32 = 1_000_000;

/// The medium and beam, in the form the inner loop wants.
#[derive(Debug, Clone)]
pub(crate) struct Medium {
    /// Single-scattering albedo a = σs/σt.
    albedo: f64,
    /// Henyey–Greenstein asymmetry g.
    g: f64,
    /// Relative index seen from inside, n_outside/n_inside = 1/η.
    eta_out_over_in: f64,
    /// Optical thickness τ of a slab; `None` for the half-space.
    thickness: Option<f64>,
    /// Refracted beam direction (sin θt, 0, −cos θt).
    entry: [f64; 3],
}

impl Medium {
    /// The medium of a validated configuration: θ is below the critical angle when η < 1.
    pub(crate) fn new(albedo: f64, g: f64, eta: f64, theta: f64, thickness: Option<f64>) -> Self {
        // Snell at entry: sin θt = sin θ / η.
        let sin_t = (theta.sin() / eta).clamp(0.0, 1.0);
        let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
        Self {
            albedo,
            g,
            eta_out_over_in: 1.0 / eta,
            thickness,
            entry: [sin_t, 0.0, -cos_t],
        }
    }

    /// Refracted beam direction inside the medium.
    #[cfg(test)]
    pub(crate) fn entry_direction(&self) -> [f64; 3] {
        self.entry
    }

    /// Distance from height z along a direction with z-component `uz` to the boundary it is
    /// heading for, and which boundary; `None` when it never meets one.
    fn boundary(&self, z: f64, uz: f64) -> Option<(f64, Surface)> {
        if uz > 0.0 {
            Some(((-z / uz).max(0.0), Surface::Top))
        } else if uz < 0.0 {
            let tau = self.thickness?;
            Some((((z + tau) / -uz).max(0.0), Surface::Bottom))
        } else {
            None
        }
    }

    /// Traces one photon packet of unit weight entering at the origin, scoring into `tally`
    /// (the binned tally of a run, or the exit callback of [`super::ExitWalk`]).
    pub(crate) fn trace(&self, rng: &mut Xoshiro256PlusPlus, tally: &mut impl Sink) {
        let mut p = [0.0_f64; 3];
        let mut u = self.entry;
        let mut w = 1.0_f64;
        let mut vertices: u32 = 0;
        loop {
            // Score the expected transmitted part of a flight that may well reach the boundary,
            // where it would leave; a farther one is scored only if it gets there.
            let hit = self.boundary(p[2], u[2]);
            let expected = matches!(hit, Some((d, _)) if d <= EXPECTED_SCORE_DISTANCE);
            let mut reflectance = 1.0;
            if let (true, Some((d, surface))) = (expected, hit) {
                reflectance = fresnel::reflectance(u[2].abs(), self.eta_out_over_in);
                let escape = w * (1.0 - reflectance) * (-d).exp();
                if escape > 0.0 {
                    let order = Order::from_vertices(vertices);
                    tally.exit(surface, p[0] + d * u[0], p[1] + d * u[1], escape, order);
                }
            }

            // Sample the free flight s, exponential with mean 1 (σt = 1).
            let s: f64 = Exp1.sample(rng);
            match hit {
                Some((d, surface)) if s >= d => {
                    // Reach the boundary: the transmitted part leaves (scored now unless it
                    // was scored in expectation), the reflected part continues as a whole with
                    // probability R; the unscattered beam is split instead.
                    if !expected {
                        reflectance = fresnel::reflectance(u[2].abs(), self.eta_out_over_in);
                        if reflectance < 1.0 {
                            let order = Order::from_vertices(vertices);
                            let (x, y) = (p[0] + d * u[0], p[1] + d * u[1]);
                            tally.exit(surface, x, y, w * (1.0 - reflectance), order);
                        }
                    }
                    if vertices == 0 {
                        w *= reflectance;
                    } else if reflectance < 1.0 && rng.next_f64() >= reflectance {
                        return;
                    }
                    p[0] += d * u[0];
                    p[1] += d * u[1];
                    p[2] = match surface {
                        Surface::Top => 0.0,
                        Surface::Bottom => -self.thickness.unwrap_or(0.0),
                    };
                    u[2] = -u[2];
                }
                _ => {
                    // Scatter at p + sω: absorb by weight, turn by the phase function.
                    for k in 0..3 {
                        p[k] += s * u[k];
                    }
                    vertices += 1;
                    tally.vertex();
                    w *= self.albedo;
                    if vertices >= MAX_VERTICES {
                        tally.truncate(w);
                        return;
                    }
                    let cos_theta = sample_hg_cos(self.g, rng.next_f64());
                    let (cos_phi, sin_phi) = sample_unit_circle(rng);
                    u = turn(u, cos_theta, cos_phi, sin_phi);
                }
            }

            // Stop empty packets; play roulette with light ones.
            if w <= 0.0 || w.is_nan() {
                return;
            }
            if w < ROULETTE_WEIGHT {
                if rng.next_f64() < ROULETTE_SURVIVAL {
                    w /= ROULETTE_SURVIVAL;
                } else {
                    return;
                }
            }
        }
    }
}

/// Henyey–Greenstein phase function p(cos Θ) = (1 − g²) / (4π (1 + g² − 2g cos Θ)^{3/2}), per
/// steradian.
pub fn hg_phase(g: f64, cos_theta: f64) -> f64 {
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * denom * denom.sqrt())
}

/// Samples cos Θ from Henyey–Greenstein by inverting its CDF for ξ ∈ [0, 1].
///
/// The textbook inverse, cos Θ = [1 + g² − ((1 − g²)/(1 − g + 2gξ))²] / 2g, cancels
/// catastrophically as g → 0. With v = 2ξ − 1 and D = 1 + g v it expands to
/// cos Θ = [v + g(v² + 3)/2 + g²v + g³(v² − 1)/2] / D², exact for every g ∈ (−1, 1) including 0,
/// and ±1 at ξ = 0, 1.
pub fn sample_hg_cos(g: f64, xi: f64) -> f64 {
    let v = 2.0 * xi - 1.0;
    let d = 1.0 + g * v;
    let num = v + g * (0.5 * (v * v + 3.0) + g * (v + 0.5 * g * (v * v - 1.0)));
    (num / (d * d)).clamp(-1.0, 1.0)
}

/// A uniformly distributed point (cos φ, sin φ) on the unit circle, without trigonometry.
///
/// Draws (x, y) uniformly in the unit disc by rejection from the square (acceptance π/4), then
/// doubles its angle: (x² − y², 2xy)/(x² + y²). The angle of a uniform point of the disc is
/// uniform, so is twice that angle modulo 2π.
pub(crate) fn sample_unit_circle(rng: &mut Xoshiro256PlusPlus) -> (f64, f64) {
    loop {
        let x = 2.0 * rng.next_f64() - 1.0;
        let y = 2.0 * rng.next_f64() - 1.0;
        let r2 = x * x + y * y;
        // Reject the corners and a tiny disc about 0, where the angle is ill-conditioned.
        if r2 <= 1.0 && r2 > 1e-12 {
            return ((x * x - y * y) / r2, 2.0 * x * y / r2);
        }
    }
}

/// Direction at polar angle acos(cos_theta) and azimuth φ (given by its cosine and sine)
/// about the unit vector `u`.
///
/// The frame about u is the branchless orthonormal basis of Duff et al. 2017 ("Building an
/// orthonormal basis, revisited"). The result is renormalised when rounding has moved its
/// length away from 1 by more than 10⁻¹², so errors do not accumulate over long walks.
pub fn turn(u: [f64; 3], cos_theta: f64, cos_phi: f64, sin_phi: f64) -> [f64; 3] {
    let [ux, uy, uz] = u;
    let sign = 1.0_f64.copysign(uz);
    let a = -1.0 / (sign + uz);
    let b = ux * uy * a;
    let t1 = [1.0 + sign * ux * ux * a, sign * b, -sign * ux];
    let t2 = [b, sign + uy * uy * a, -uy];
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (c1, c2) = (sin_theta * cos_phi, sin_theta * sin_phi);
    let v = [
        c1 * t1[0] + c2 * t2[0] + cos_theta * ux,
        c1 * t1[1] + c2 * t2[1] + cos_theta * uy,
        c1 * t1[2] + c2 * t2[2] + cos_theta * uz,
    ];
    let n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (n2 - 1.0).abs() <= 1e-12 {
        return v;
    }
    if n2 > 0.0 && n2.is_finite() {
        let inv = 1.0 / n2.sqrt();
        [v[0] * inv, v[1] * inv, v[2] * inv]
    } else {
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walk::rng::photon_stream;

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    #[test]
    fn hg_inverse_hits_the_ends_and_is_monotone() {
        for g in [-0.9, -0.3, 0.0, 1e-9, 0.5, 0.99] {
            assert!((sample_hg_cos(g, 0.0) + 1.0).abs() < 1e-12, "g = {g}");
            assert!((sample_hg_cos(g, 1.0) - 1.0).abs() < 1e-12, "g = {g}");
            let mut last = -1.0;
            for i in 1..=1000 {
                let c = sample_hg_cos(g, i as f64 / 1000.0);
                assert!(c >= last - 1e-15, "g = {g}, i = {i}");
                last = c;
            }
        }
    }

    #[test]
    fn hg_inverse_is_the_cdf_inverse() {
        // CDF of cos Θ: F(μ) = (1 − g²)/(2g) · [1/√(1 + g² − 2gμ) − 1/(1 + g)].
        for g in [-0.7, 0.2, 0.85] {
            for i in 0..=20 {
                let xi = i as f64 / 20.0;
                let mu = sample_hg_cos(g, xi);
                let cdf = (1.0 - g * g) / (2.0 * g)
                    * (1.0 / (1.0 + g * g - 2.0 * g * mu).sqrt() - 1.0 / (1.0 + g));
                assert!((cdf - xi).abs() < 1e-12, "g = {g}, xi = {xi}: {cdf}");
            }
        }
    }

    #[test]
    fn hg_phase_is_normalised() {
        // 2π ∫ p dμ over [−1, 1] by Gauss–Legendre.
        let rule = crate::quadrature::GaussLegendre::new(200);
        for g in [-0.5, 0.0, 0.75] {
            let total = std::f64::consts::TAU * rule.integrate(-1.0, 1.0, |mu| hg_phase(g, mu));
            assert!((total - 1.0).abs() < 1e-10, "g = {g}: {total}");
        }
    }

    #[test]
    fn turn_keeps_unit_length_and_the_requested_angle() {
        let dirs = [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [0.6, 0.0, -0.8],
            [0.48, 0.6, 0.64],
            [1.0, 0.0, 0.0],
        ];
        for u in dirs {
            for (c, phi) in [(0.3, 0.1f64), (-0.9, 2.0), (1.0, 4.0), (-1.0, 5.5)] {
                let v = turn(u, c, phi.cos(), phi.sin());
                assert!((dot(v, v) - 1.0).abs() < 1e-14);
                assert!((dot(u, v) - c).abs() < 1e-12, "u = {u:?}, c = {c}");
            }
        }
    }

    #[test]
    fn unit_circle_samples_are_unit_and_uniform() {
        // Quadrant counts of 40000 angles: each 10000 ± 87 (binomial sd); allow 5 sd.
        let mut rng = photon_stream(1, 2);
        let mut quadrants = [0u32; 4];
        let mut mean = (0.0, 0.0);
        for _ in 0..40_000 {
            let (c, s) = sample_unit_circle(&mut rng);
            assert!((c * c + s * s - 1.0).abs() < 1e-14);
            quadrants[usize::from(c < 0.0) * 2 + usize::from(s < 0.0)] += 1;
            mean.0 += c / 40_000.0;
            mean.1 += s / 40_000.0;
        }
        for q in quadrants {
            assert!((q as f64 - 10_000.0).abs() < 5.0 * 87.0, "{quadrants:?}");
        }
        // E[cos φ] = E[sin φ] = 0 with sd √(1/2/40000) ≈ 0.0035.
        assert!(mean.0.abs() < 0.018 && mean.1.abs() < 0.018, "{mean:?}");
    }

    #[test]
    fn entry_direction_follows_snell() {
        let m = Medium::new(0.5, 0.0, 1.5, 60f64.to_radians(), None);
        let [x, y, z] = m.entry_direction();
        assert!((x - 60f64.to_radians().sin() / 1.5).abs() < 1e-15);
        assert_eq!(y, 0.0);
        assert!(z < 0.0 && (x * x + z * z - 1.0).abs() < 1e-15);
    }
}
