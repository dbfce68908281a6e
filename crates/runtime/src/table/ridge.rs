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
//! In reduced units (σ′t = 1), with s = sin θ′, c = cos θ′ and the table's C_E:
//!
//! ```text
//! R(r, φ; ρ′, θ) = w(c) · m(r) · pdf_WC(φ; κ),   κ = exp(−max(c, 10⁻⁵)),
//! m(r) = ρ′² C_E s · e^{−rs} (1 − e^{−2rs}) / (2r)        (m(0) = ρ′² C_E s²),
//! w(c) = 1 for c ≤ 0.1, 0 for c ≥ 0.3, x²(3 − 2x) between, x = (0.3 − c)/0.2,
//! ```
//!
//! and R = 0 where no light enters and beyond the table's last radius r_max, as every lookup
//! is. m is the flux term of the sources at depth t·c along the beam, attenuated as e^{−t},
//! each seen from the exit point above it; over the plane it carries ρ′² C_E/3 at every θ
//! (∫ m r dr = ρ′² C_E s/2 · (1/s − 1/(3s))), of which the radii up to r_max hold the share
//! F(r_max), F(r) = ε²(3 − ε)/2 with ε = 1 − e^{−rs}. The radial density of R, r·m(r) over its
//! energy, is (3s/2)(e^{−rs} − e^{−3rs})/F(r_max), inverted in closed form in ε (a cubic).

use crate::gwc::{inv_cdf_wc, pdf_wc};
use std::f64::consts::FRAC_PI_2;

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

/// Whether the ridge has weight at some incidence θ ∈ [0°, 90°] for this η: below η ≈ 1.048,
/// where cos θ′ at grazing (or at the critical angle, η < 1) falls below [`ZERO_WEIGHT_COS`].
pub fn reaches(eta: f64) -> bool {
    match crate::fresnel::refracted_cos(FRAC_PI_2, eta) {
        Some(cos_t) => cos_t < ZERO_WEIGHT_COS,
        None => eta > 0.0,
    }
}

/// The ridge at one (ρ′, θ) of a table: R(r, φ) = scale · m̂(r) · pdf_WC(φ; κ) with
/// m̂ = s e^{−rs}(1 − e^{−2rs})/(2r), scale = w ρ′² C_E, on r ∈ [0, r_max].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ridge {
    scale: f64,
    s: f64,
    kappa: f64,
    r_max: f64,
    /// F(r_max): the share of the ridge's energy up to r_max.
    share: f64,
}

impl Ridge {
    /// The ridge at (ρ′, θ) of a table of index `eta`, constant `c_e` and last radius `r_max`;
    /// `None` where it has no weight or no energy (w = 0, ρ′ = 0, no light enters, θ outside
    /// [0, π/2], r_max not positive).
    pub fn at(eta: f64, c_e: f64, rho: f64, theta: f64, r_max: f64) -> Option<Self> {
        let cos_t = crate::fresnel::refracted_cos(theta, eta)?;
        let scale = weight(cos_t) * rho * rho * c_e;
        let s = (1.0 - cos_t * cos_t).sqrt();
        let share = energy_share(r_max * s);
        (scale > 0.0 && s > 0.0 && r_max > 0.0 && share > 0.0).then_some(Self {
            scale,
            s,
            kappa: (-cos_t.max(MIN_WIDTH_COS)).exp(),
            r_max,
            share,
        })
    }

    /// Its energy up to r_max: ∫∫ R r dr dφ = w ρ′² C_E F(r_max)/3.
    pub fn energy(&self) -> f64 {
        self.scale * self.share / 3.0
    }

    /// Its mean over φ, (1/2π) ∫ R dφ = w ρ′² C_E m̂(r)/(2π), per unit area; 0 outside
    /// [0, r_max].
    pub fn mean(&self, r: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        self.scale * self.radial(r) / std::f64::consts::TAU
    }

    /// R(r, φ) per unit area; 0 outside [0, r_max] or for φ outside [−π, π] (wrapped by the
    /// caller) or NaN.
    pub fn eval(&self, r: f64, phi: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        self.scale * self.radial(r) * pdf_wc(phi, self.kappa)
    }

    /// m̂(r) = s e^{−rs}(1 − e^{−2rs})/(2r), s² at r = 0.
    fn radial(&self, r: f64) -> f64 {
        let q = 2.0 * r * self.s;
        let front = if q == 0.0 { 1.0 } else { -(-q).exp_m1() / q };
        self.s * self.s * (-r * self.s).exp() * front
    }

    /// Density per unit r of [`Ridge::sample_radius`], (3s/2)(e^{−rs} − e^{−3rs})/F(r_max)
    /// on [0, r_max], 0 elsewhere.
    pub fn pdf_radius(&self, r: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        let x = (-r * self.s).exp();
        // e^{−rs} − e^{−3rs} = x(1 − x²), with 1 − x² = −expm1(−2rs) kept exact near 0
        1.5 * self.s * x * -(-2.0 * r * self.s).exp_m1() / self.share
    }

    /// The r ∈ [0, r_max] whose share of the ridge's energy up to r_max is u ∈ [0, 1] (u
    /// clamped into it): F(r) = u F(r_max), solved in ε = 1 − e^{−rs} ([`solve_share`]).
    pub fn sample_radius(&self, u: f64) -> f64 {
        let target = u.clamp(0.0, 1.0) * self.share;
        let eps = solve_share(target);
        (-(-eps).ln_1p() / self.s).min(self.r_max)
    }

    /// Its harmonics ∫ R cos nφ dφ over [−π, π] at r, n = 0 … N − 1: w ρ′² C_E m̂(r) κⁿ (the
    /// wrapped Cauchy density's are κⁿ); 0 outside [0, r_max].
    pub fn harmonics<const N: usize>(&self, r: f64) -> [f64; N] {
        let mass = std::f64::consts::TAU * self.mean(r);
        std::array::from_fn(|n| mass * self.kappa.powi(n as i32))
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

/// F at r·s = `rs`: ε²(3 − ε)/2 with ε = 1 − e^{−rs}, the share of the ridge's energy within
/// r (1 for rs = ∞).
pub fn energy_share(rs: f64) -> f64 {
    let eps = -(-rs).exp_m1();
    0.5 * eps * eps * (3.0 - eps)
}

/// The ε ∈ [0, 1] with ε²(3 − ε)/2 = `target` ∈ [0, 1]: the cubic's root in [0, 1] by its
/// trigonometric form (1 − ε = 2 cos((2π − acos(target − 1))/3)), polished by Newton's method
/// on ε itself, which the trigonometric form loses to cancellation where ε is small.
pub fn solve_share(target: f64) -> f64 {
    let target = target.clamp(0.0, 1.0);
    if target == 0.0 {
        return 0.0;
    }
    let x = 2.0 * ((std::f64::consts::TAU - (target - 1.0).acos()) / 3.0).cos();
    // For small targets ε ≈ √(2 target/3) is the better start
    let mut eps = if target < 1e-4 {
        (2.0 * target / 3.0).sqrt()
    } else {
        (1.0 - x).clamp(0.0, 1.0)
    };
    for _ in 0..4 {
        let f = 0.5 * eps * eps * (3.0 - eps) - target;
        let df = 1.5 * eps * (2.0 - eps);
        if df <= 0.0 {
            break;
        }
        let next = (eps - f / df).clamp(0.0, 1.0);
        if next == eps {
            break;
        }
        eps = next;
    }
    eps
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    /// Gauss–Legendre-free check: composite Simpson on a fine grid.
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
    }

    #[test]
    fn its_energy_is_the_integral_of_its_values() {
        // ∫₀^{r_max} ∫ R r dφ dr by Simpson over r and φ against w ρ′² C_E F(r_max)/3
        for (eta, theta_deg, r_max) in [(1.0, 89.0, 50.0), (1.0, 80.0, 3.0), (0.9, 60.0, 20.0)] {
            let ridge = Ridge::at(eta, 0.37, 0.8, f64::to_radians(theta_deg), r_max).unwrap();
            // φ on a grid that resolves the narrowest width (κ up to e^{−0.0175})
            let over_phi = |r: f64| {
                let n = 20_000;
                simpson(|p| ridge.eval(r, p), -PI, PI, n)
            };
            let radial = |r: f64| r * over_phi(r);
            // r in pieces: the density changes over 1/s
            let total: f64 = (0..40)
                .map(|k| {
                    let (a, b) = (r_max * k as f64 / 40.0, r_max * (k + 1) as f64 / 40.0);
                    simpson(radial, a, b, 40)
                })
                .sum();
            let want = ridge.energy();
            assert!((total / want - 1.0).abs() < 1e-6, "{total} vs {want}");
            // and the mean over φ is R's
            for r in [0.0, 0.01, 1.0, r_max] {
                let mean = over_phi(r) / TAU;
                assert!((mean - ridge.mean(r)).abs() <= 1e-7 * ridge.mean(r) + 1e-300);
            }
        }
    }

    #[test]
    fn the_radial_sampler_inverts_its_distribution() {
        let ridge = Ridge::at(1.0, 0.37, 0.9, 88f64.to_radians(), 30.0).unwrap();
        let cdf = |r: f64| simpson(|x| ridge.pdf_radius(x), 0.0, r, 4000);
        assert!((cdf(30.0) - 1.0).abs() < 1e-9);
        for u in [1e-12, 1e-6, 0.01, 0.3, 0.5, 0.9, 0.999999, 1.0] {
            let r = ridge.sample_radius(u);
            assert!((0.0..=30.0).contains(&r));
            let got = energy_share(r * ridge.s) / ridge.share;
            assert!((got - u).abs() <= 1e-12 * u.max(1e-3), "u {u}: {got}");
        }
        assert_eq!(ridge.sample_radius(0.0), 0.0);
        assert!((cdf(ridge.sample_radius(0.37)) - 0.37).abs() < 1e-8);
    }

    #[test]
    fn the_cubic_is_solved_to_rounding_everywhere() {
        for k in 0..=2000 {
            let target = if k < 1000 {
                10f64.powf(-16.0 + 16.0 * k as f64 / 1000.0)
            } else {
                (k - 1000) as f64 / 1000.0
            };
            let eps = solve_share(target);
            let back = 0.5 * eps * eps * (3.0 - eps);
            assert!(
                (back - target).abs() <= 4.0 * f64::EPSILON * target.max(1e-300),
                "{target}: {back}"
            );
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
