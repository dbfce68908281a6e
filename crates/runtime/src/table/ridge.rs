//! The analytic ridge of grazing incidence near index matching (format-spec.md §10, "The
//! ridge").
//!
//! When the refracted beam runs just under the surface (cos θ′ small: η near 1 at grazing θ,
//! or η < 1 near the critical angle), the sources of photon beam diffusion lie at depth
//! t·cos θ′ under the exit points they pass, and their near field puts a forward ridge on
//! φ = 0 whose width is about cos θ′. Its width changes faster over θ than the θ nodes can
//! follow: blending two nodes' profiles gives a mixture of two ridges, not one of the width
//! between. A table that says so (its record's `ridge`) stores at its nodes S less the ridge
//! R below, and every lookup adds R back at its own θ, with its own width.
//!
//! In reduced units (σ′t = 1), with s = sin θ′, c = cos θ′, the table's C_E and the diffusion
//! coefficient of ρ′, σtr = √(3(1 − ρ′)/(2 − ρ′)):
//!
//! ```text
//! R(r, φ; ρ′, θ) = w(c) · m(r) · pdf_WC(φ; κ),   κ = exp(−max(c, 10⁻⁵)),
//! m(r) = ρ′² C_E s · e^{−r(s + k)} (1 − e^{−2rs}) / (2r),   k = σtr c/s   (m(0) = ρ′² C_E s²),
//! w(c) = 1 for c ≤ 0.1, 0 for c ≥ 0.3, x²(3 − 2x) between, x = (0.3 − c)/0.2,
//! ```
//!
//! and R = 0 where no light enters and beyond the table's last radius r_max, as every lookup
//! is. m is the flux term of the beam's sources, attenuated along the beam as e^{−t}, each
//! seen from the exit point above it at t = r/s: a line density ρ′² C_E (1 − e^{−2rs}) e^{−rs}/2
//! along φ = 0 in the limit c → 0 (`Pbd::surface_ridge`), spread over φ as a wrapped Cauchy
//! lobe of width c, and attenuated by diffusion over the source's depth h = r c/s as e^{−σtr h}
//! (which keeps it nearer S off the ridge at low albedo, where S decays as e^{−σtr r}; it can
//! still reach past S there, far out, and a bake then keeps a floor of S at the node). Over the
//! plane it carries w ρ′² C_E (s/2)·G(r_max), G(r) = ∫₀^r (e^{−ax} − e^{−bx}) dx with a = s + k,
//! b = 3s + k (ρ′² C_E/3 for k = 0, r_max = ∞). The radial density of R, r·m(r) over its
//! energy, is (e^{−ar} − e^{−br})/G(r_max), inverted by a safeguarded Newton iteration.

use crate::gwc::{inv_cdf_wc, pdf_wc};
use std::f64::consts::{FRAC_PI_2, TAU};

/// cos θ′ up to which the ridge has its full weight.
pub const FULL_WEIGHT_COS: f64 = 0.1;
/// cos θ′ from which the ridge has weight 0.
pub const ZERO_WEIGHT_COS: f64 = 0.3;
/// The least cos θ′ the width takes: at θ′ = 90° the ridge would be a line.
pub const MIN_WIDTH_COS: f64 = 1e-5;

/// The ridge's weight w at cos θ′ = `cos_t`: 1 up to [`FULL_WEIGHT_COS`], 0 from
/// [`ZERO_WEIGHT_COS`], the smooth step x²(3 − 2x) between.
pub fn weight(cos_t: f64) -> f64 {
    if cos_t <= FULL_WEIGHT_COS {
        1.0
    } else if cos_t >= ZERO_WEIGHT_COS {
        0.0
    } else {
        let x = (ZERO_WEIGHT_COS - cos_t) / (ZERO_WEIGHT_COS - FULL_WEIGHT_COS);
        x * x * (3.0 - 2.0 * x)
    }
}

/// Whether the ridge has weight at some incidence θ ∈ [0°, 90°] for this η: below η = 1/√0.91 ≈ 1.0483,
/// where cos θ′ at grazing (or at the critical angle, η < 1) falls below [`ZERO_WEIGHT_COS`].
pub fn reaches(eta: f64) -> bool {
    match crate::fresnel::refracted_cos(FRAC_PI_2, eta) {
        Some(cos_t) => cos_t < ZERO_WEIGHT_COS,
        None => eta > 0.0,
    }
}

/// The ridge at one (ρ′, θ) of a table: R(r, φ) = scale · m̂(r) · pdf_WC(φ; κ) with
/// m̂ = s e^{−r(s+k)}(1 − e^{−2rs})/(2r), scale = w ρ′² C_E, on r ∈ [0, r_max].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ridge {
    scale: f64,
    s: f64,
    /// The attenuation σtr c/s over the source's depth, per unit r.
    k: f64,
    kappa: f64,
    r_max: f64,
    /// G(r_max): the radial integral up to r_max (`radial_integral`).
    total: f64,
}

impl Ridge {
    /// The ridge at (ρ′, θ) of a table of index `eta`, constant `c_e` and last radius `r_max`;
    /// `None` where it has no weight or no energy (w = 0, ρ′ = 0, no light enters, θ outside
    /// [0, π/2], r_max not positive).
    pub fn at(eta: f64, c_e: f64, rho: f64, theta: f64, r_max: f64) -> Option<Self> {
        Self::with_cos(c_e, rho, crate::fresnel::refracted_cos(theta, eta)?, r_max)
    }

    /// The ridge at cos θ′ = `cos_t` ∈ [0, 1] ([`Ridge::at`] of the θ refracted to it). θ nodes
    /// beyond the critical angle of an η < 1 hold the limit θ′ → 90° of the profile, so their
    /// ridge is this at cos θ′ = 0.
    pub fn with_cos(c_e: f64, rho: f64, cos_t: f64, r_max: f64) -> Option<Self> {
        let scale = weight(cos_t) * rho * rho * c_e;
        let s = (1.0 - cos_t * cos_t).sqrt();
        if !(scale > 0.0 && s > 0.0 && r_max > 0.0) {
            return None;
        }
        let sigma_tr = (3.0 * (1.0 - rho) / (2.0 - rho)).max(0.0).sqrt();
        let k = sigma_tr * cos_t / s;
        let total = radial_integral(s + k, 3.0 * s + k, r_max);
        (total > 0.0).then_some(Self {
            scale,
            s,
            k,
            kappa: (-cos_t.max(MIN_WIDTH_COS)).exp(),
            r_max,
            total,
        })
    }

    /// Its energy up to r_max: ∫∫ R r dr dφ = w ρ′² C_E (s/2) G(r_max).
    pub fn energy(&self) -> f64 {
        self.scale * 0.5 * self.s * self.total
    }

    /// Its mean over φ, (1/2π) ∫ R dφ = w ρ′² C_E m̂(r)/(2π), per unit area; 0 outside
    /// [0, r_max].
    pub fn mean(&self, r: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        self.scale * self.radial(r) / TAU
    }

    /// R(r, φ) per unit area; 0 outside [0, r_max] or for φ outside [−π, π] (wrapped by the
    /// caller) or NaN.
    pub fn eval(&self, r: f64, phi: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        self.scale * self.radial(r) * pdf_wc(phi, self.kappa)
    }

    /// Its harmonics ∫ R cos nφ dφ over [−π, π] at r, n = 0 … N − 1: w ρ′² C_E m̂(r) κⁿ (the
    /// wrapped Cauchy density's are κⁿ); 0 outside [0, r_max].
    pub fn harmonics<const N: usize>(&self, r: f64) -> [f64; N] {
        let mass = TAU * self.mean(r);
        std::array::from_fn(|n| mass * self.kappa.powi(n as i32))
    }

    /// m̂(r) = s e^{−r(s+k)}(1 − e^{−2rs})/(2r), s² at r = 0.
    fn radial(&self, r: f64) -> f64 {
        let q = 2.0 * r * self.s;
        let front = if q == 0.0 { 1.0 } else { -(-q).exp_m1() / q };
        self.s * self.s * (-r * (self.s + self.k)).exp() * front
    }

    /// Density per unit r of [`Ridge::sample_radius`], (e^{−ar} − e^{−br})/G(r_max) on
    /// [0, r_max], 0 elsewhere.
    pub fn pdf_radius(&self, r: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        // e^{−ar} − e^{−br} = e^{−ar}(1 − e^{−2sr}), exact near 0
        (-r * (self.s + self.k)).exp() * -(-2.0 * r * self.s).exp_m1() / self.total
    }

    /// The r ∈ [0, r_max] whose share of the ridge's energy up to r_max is u ∈ [0, 1] (u
    /// clamped into it): G(r) = u G(r_max), by Newton's method kept inside a shrinking
    /// bracket (G increases; its slope e^{−ar} − e^{−br} is 0 only at r = 0).
    pub fn sample_radius(&self, u: f64) -> f64 {
        let (a, b) = (self.s + self.k, 3.0 * self.s + self.k);
        let target = u.clamp(0.0, 1.0) * self.total;
        if target <= 0.0 {
            return 0.0;
        }
        if target >= self.total {
            return self.r_max;
        }
        let (mut lo, mut hi) = (0.0, self.r_max);
        // Near 0, G ≈ s r²
        let mut r = (target / self.s).sqrt().min(0.5 * self.r_max);
        for _ in 0..200 {
            let f = radial_integral(a, b, r) - target;
            if f == 0.0 {
                return r;
            }
            if f > 0.0 {
                hi = r;
            } else {
                lo = r;
            }
            let slope = (-a * r).exp() * -(-2.0 * self.s * r).exp_m1();
            let newton = r - f / slope;
            let next = if slope > 0.0 && (lo..=hi).contains(&newton) {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (next - r).abs() <= 4.0 * f64::EPSILON * r || hi - lo <= f64::EPSILON * hi {
                return next;
            }
            r = next;
        }
        r
    }

    /// The ridge's density in φ, pdf_WC(φ; κ).
    pub fn pdf_phi(&self, phi: f64) -> f64 {
        pdf_wc(phi, self.kappa)
    }

    /// The φ whose wrapped Cauchy CDF is u.
    pub fn sample_phi(&self, u: f64) -> f64 {
        inv_cdf_wc(u, self.kappa)
    }
}

/// G(r) = ∫₀^r (e^{−ax} − e^{−bx}) dx for 0 < a < b: (1 − e^{−ar})/a − (1 − e^{−br})/b, by its
/// Taylor series where br is small (the two terms cancel to (b − a) r²/2 there).
fn radial_integral(a: f64, b: f64, r: f64) -> f64 {
    if b * r < 1e-3 {
        // Σ_{n≥2} (−1)ⁿ rⁿ (bⁿ⁻¹ − aⁿ⁻¹)/n!, four terms: the fifth is below 1e-15 of the first
        let (a2, b2) = (a * a, b * b);
        let (a3, b3) = (a2 * a, b2 * b);
        let (a4, b4) = (a3 * a, b3 * b);
        let r2 = r * r;
        return r2
            * ((b - a) / 2.0 - r * (b2 - a2) / 6.0 + r2 * (b3 - a3) / 24.0
                - r2 * r * (b4 - a4) / 120.0);
    }
    -(-a * r).exp_m1() / a + (-b * r).exp_m1() / b
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Composite Simpson on n (even) intervals.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut sum = f(a) + f(b);
        for k in 1..n {
            sum += f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        sum * h / 3.0
    }

    #[test]
    fn the_weight_is_one_then_a_smooth_step_then_zero() {
        assert_eq!(weight(0.0), 1.0);
        assert_eq!(weight(0.1), 1.0);
        assert_eq!(weight(0.3), 0.0);
        assert_eq!(weight(0.9), 0.0);
        assert!((weight(0.2) - 0.5).abs() < 1e-15);
        let mut last = 1.0;
        for k in 0..=200 {
            let w = weight(0.1 + 0.2 * k as f64 / 200.0);
            assert!(w <= last && (0.0..=1.0).contains(&w));
            last = w;
        }
        assert!(reaches(1.0) && reaches(0.8) && reaches(1.04));
        assert!(!reaches(1.05) && !reaches(1.33));
        // the edge: cos θ′ at 90° is 0.3 at η = 1/√0.91
        assert!(reaches(1.0482) && !reaches(1.0484));
    }

    #[test]
    fn without_attenuation_it_carries_a_third_of_rho_squared_c_e() {
        // ρ′ = 1: σtr = 0, k = 0, and over the whole plane ρ′² C_E/3
        let ridge = Ridge::at(1.0, 0.37, 1.0, 85f64.to_radians(), 1e4).unwrap();
        assert_eq!(ridge.k, 0.0);
        assert!((ridge.energy() / (0.37 / 3.0) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn its_energy_is_the_integral_of_its_values() {
        // ∫₀^{r_max} ∫ R r dφ dr by Simpson over r and φ against its energy, and the mean
        // over φ against R's
        for (eta, rho, theta_deg, r_max) in [
            (1.0, 0.8, 89.0, 50.0),
            (1.0, 0.3, 80.0, 3.0),
            (0.9, 0.95, 60.0, 20.0),
        ] {
            let ridge = Ridge::at(eta, 0.37, rho, f64::to_radians(theta_deg), r_max).unwrap();
            // φ on a grid that resolves the narrowest width (κ up to e^{−0.0175})
            let over_phi = |r: f64| simpson(|p| ridge.eval(r, p), -PI, PI, 20_000);
            let radial = |r: f64| r * over_phi(r);
            let total: f64 = (0..40)
                .map(|k| {
                    let (a, b) = (r_max * k as f64 / 40.0, r_max * (k + 1) as f64 / 40.0);
                    simpson(radial, a, b, 40)
                })
                .sum();
            let want = ridge.energy();
            assert!((total / want - 1.0).abs() < 1e-6, "{total} vs {want}");
            for r in [0.0, 0.01, 1.0, r_max] {
                let mean = over_phi(r) / TAU;
                assert!((mean - ridge.mean(r)).abs() <= 1e-7 * ridge.mean(r) + 1e-300);
            }
        }
    }

    #[test]
    fn the_radial_sampler_inverts_its_distribution() {
        for (rho, theta_deg) in [(0.9, 88.0), (0.05, 75.0), (1.0, 89.9)] {
            let ridge = Ridge::at(1.0, 0.37, rho, f64::to_radians(theta_deg), 30.0).unwrap();
            let (a, b) = (ridge.s + ridge.k, 3.0 * ridge.s + ridge.k);
            let cdf = |r: f64| simpson(|x| ridge.pdf_radius(x), 0.0, r, 20_000);
            assert!(
                (cdf(30.0) - 1.0).abs() < 1e-9,
                "{rho} {theta_deg}: {}",
                cdf(30.0)
            );
            for u in [
                1e-300, 1e-200, 1e-15, 1e-12, 1e-6, 0.01, 0.3, 0.5, 0.9, 0.999999, 1.0,
            ] {
                let r = ridge.sample_radius(u);
                assert!((0.0..=30.0).contains(&r));
                let got = radial_integral(a, b, r) / ridge.total;
                assert!(
                    (got - u).abs() <= 1e-12 * u.max(1e-3) && (got - u).abs() <= 1e-9 * u,
                    "u {u}: {got}"
                );
            }
            assert_eq!(ridge.sample_radius(0.0), 0.0);
            // the least uniform draws within rounding of 0 (its target underflows or nearly)
            assert!(ridge.sample_radius(5e-324) < 1e-150);
            assert!((cdf(ridge.sample_radius(0.37)) - 0.37).abs() < 1e-8);
        }
    }

    #[test]
    fn the_radial_integral_is_continuous_where_it_switches_to_its_series() {
        for (a, b) in [(1.0, 3.0), (1.7, 3.7), (0.02, 0.06)] {
            let r = 1e-3 / b;
            let below = radial_integral(a, b, r * (1.0 - 1e-12));
            let above = radial_integral(a, b, r * (1.0 + 1e-12));
            assert!(
                (above / below - 1.0).abs() < 1e-9,
                "{a} {b}: {below} {above}"
            );
            // and the series against the closed form in f64 where both are accurate
            let r = 0.9e-3 / b;
            let closed = -(-a * r).exp_m1() / a + (-b * r).exp_m1() / b;
            assert!((radial_integral(a, b, r) / closed - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn no_ridge_where_it_has_no_weight_or_no_light_enters() {
        assert!(Ridge::at(1.33, 0.4, 0.9, 89f64.to_radians(), 50.0).is_none());
        assert!(Ridge::at(1.0, 0.4, 0.9, 0.0, 50.0).is_none());
        assert!(Ridge::at(1.0, 0.4, 0.0, 89f64.to_radians(), 50.0).is_none());
        assert!(Ridge::at(0.9, 0.4, 0.9, 70f64.to_radians(), 50.0).is_none());
        assert!(Ridge::at(1.0, 0.4, 0.9, 89f64.to_radians(), 50.0).is_some());
        // At θ′ = 90° the width stops at 10⁻⁵: finite everywhere
        let at_90 = Ridge::at(1.0, 0.4, 0.9, FRAC_PI_2, 50.0).unwrap();
        assert!(at_90.eval(1.0, 0.0).is_finite() && at_90.eval(0.0, 0.0) > 0.0);
    }
}
