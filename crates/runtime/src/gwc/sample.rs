//! Sampling a GWC profile: φ from u by inverting cdf(φ) = λ(φ + π)/2π + (1 − λ)·cdf_WC(φ; c)
//! (Ferrier 2016, §4.2), with the density at the sample.
//!
//! The report inverts in φ by Newton steps from cdf_WC⁻¹(u), the λ = 0 answer. Here the
//! unknown is, where it can be, w = cdf_WC(φ) instead: cdf(φ) = u reads
//! H(w) = λ(φ(w) + π)/2π + (1 − λ)·w − u = 0 with φ(w) = cdf_WC⁻¹(w), nearly linear for the small
//! λ the tables hold (mostly below 0.2). Each iterate costs one inverse (two sines and an
//! atan2), which also gives pdf_WC and its derivatives there ([`LobePoint`]); Halley steps
//! use them, and once a step is short, φ and pdf_WC at its end follow from second-order Taylor
//! series instead of another inverse: about one inverse after the start instead of the two to
//! three cdf evaluations of Newton in φ. Where H′ = λ/(2π pdf_WC) + 1 − λ would vary by more
//! than a factor 2 over the lobe (large λ, peaked lobes, where H(w) is nearly a step), and for
//! |c| > [`C_MAX_FIT`], which no table stores, the solve stays in φ.
//!
//! Both solves keep a bisection bracket, stop when the residual is at most [`SAMPLE_U_TOL`] or
//! the bracket is down to adjacent floats, and take at most 100 iterations.

use std::f64::consts::{PI, TAU};

use super::trig::{atan2_quadrant, sin_quarter};
use super::{clamp_c, Gwc, C_MAX_FIT, SAMPLE_U_TOL};

/// Iteration cap of the Newton–bisection in [`Gwc::sample`].
const SAMPLE_MAX_ITER: usize = 100;

/// Longest step in w = cdf_WC(φ) that [`Gwc::sample`] ends with second-order Taylor series of
/// φ(w) and pdf_WC(φ) instead of another inverse.
const TAYLOR_STEP: f64 = 1e-6;

/// Largest relative change of pdf_WC over that step.
const TAYLOR_DENSITY: f64 = 1e-5;

/// 1/2π.
const INV_TAU: f64 = 1.0 / TAU;

/// A random number as the azimuth samplers read it: clamped into [0, 1], NaN → 0, so that
/// every f64 gives an azimuth.
pub fn unit_interval(u: f64) -> f64 {
    if u.is_nan() {
        0.0
    } else {
        u.clamp(0.0, 1.0)
    }
}

/// The azimuth φ = 2πu − π ∈ [−π, π] of a uniform draw, u read by [`unit_interval`].
pub fn uniform_azimuth(u: f64) -> f64 {
    (TAU * unit_interval(u) - PI).clamp(-PI, PI)
}

/// The wrapped Cauchy lobe at φ = cdf_WC⁻¹(w): φ, the density and its logarithmic derivatives,
/// all from the two sines of the inverse.
#[derive(Debug, Clone, Copy)]
pub(super) struct LobePoint {
    pub(super) phi: f64,
    /// pdf_WC(φ), rad⁻¹.
    pub(super) pdf: f64,
    /// p′/p = −2c·sin φ/D, with p = pdf_WC and D = 1 + c² − 2c·cos φ.
    dlog: f64,
    /// p″/p = −2c·cos φ/D + 8c²·sin²φ/D².
    d2: f64,
}

impl LobePoint {
    /// The lobe at cdf_WC⁻¹(w; c); w is clamped into [0, 1] (NaN → 0) and c as in
    /// [`super::pdf_wc`].
    ///
    /// With ψ = 2π(w − 1/2), tan(φ/2) = ((1 − c)/(1 + c))·tan(ψ/2) is a Möbius map of the
    /// circle, and 1 + c² − 2c·cos φ = (1 − c²)²/(1 + c² + 2c·cos ψ), so
    /// pdf_WC(φ) = (1 + c² + 2c·cos ψ)/(2π(1 − c²)). With m = |w − 1/2| and t = 1/2 − m as
    /// below, cos(ψ/2) = sin(πt) and sin(ψ/2) = ±sin(πm): 1 + c² + 2c·cos ψ
    /// = (1 − c)² + 4c·sin²(πt) = (1 + c)² − 4c·sin²(πm), each free of cancellation for one
    /// sign of c. sin φ and cos φ follow from tan h, h = |φ|/2.
    pub(super) fn at(w: f64, c: f64) -> Self {
        let w = unit_interval(w);
        let c = clamp_c(c);
        // Tail mass t beyond |φ| and its complement m = 1/2 − t, both without cancellation
        let (t, m, sign) = if w >= 0.5 {
            (1.0 - w, w - 0.5, 1.0)
        } else {
            (w, 0.5 - w, -1.0)
        };
        let (sin_m, sin_t) = (sin_quarter(PI * m), sin_quarter(PI * t));
        // Solve π·t = atan2((1−c)·cos h, (1+c)·sin h) for h: tan h = y/x
        let (y, x) = ((1.0 - c) * sin_m, (1.0 + c) * sin_t);
        let h = atan2_quadrant(y, x);
        let num = if c >= 0.0 {
            (1.0 - c) * (1.0 - c) + 4.0 * c * sin_t * sin_t
        } else {
            (1.0 + c) * (1.0 + c) - 4.0 * c * sin_m * sin_m
        };
        let one_minus_c2 = (1.0 - c) * (1.0 + c);
        // Two divisions where four would do: 1/(x² + y²), and 1/D = num/(1 − c²)²
        let inv_r2 = 1.0 / (x * x + y * y);
        let (sin_phi, cos_phi) = (sign * 2.0 * x * y * inv_r2, (x - y) * (x + y) * inv_r2);
        let inv_d = num / (one_minus_c2 * one_minus_c2);
        let dlog = -2.0 * c * sin_phi * inv_d;
        Self {
            phi: sign * (2.0 * h).min(PI),
            pdf: num / (TAU * one_minus_c2),
            dlog,
            d2: -2.0 * c * cos_phi * inv_d + 2.0 * dlog * dlog,
        }
    }
}

impl Gwc {
    /// Samples φ ∈ [−π, π] with density [`Gwc::pdf`] from u ∈ [0, 1], inverting [`Gwc::cdf`]
    /// (clamped into [0, 1], NaN → 0).
    ///
    /// Newton-type steps safeguarded by bisection, started at cdf_WC⁻¹(u; c); see the module
    /// docs for the variable solved for and the stopping rule.
    pub fn sample(&self, u: f64) -> f64 {
        self.sample_with_pdf(u).0
    }

    /// [`Gwc::sample`] with [`Gwc::pdf`] at the sample (equal up to rounding), which the solve
    /// has at hand.
    ///
    /// The unknown is w = cdf_WC(φ), in which cdf(φ) = u reads
    /// H(w) = λ(φ(w) + π)/2π + (1 − λ)·w − u = 0 with φ(w) = cdf_WC⁻¹(w): nearly linear for the
    /// tables' small λ. Halley steps, from w = u and kept inside a bisection bracket, need
    /// H′ = λ/(2π p) + 1 − λ and H″ = λ·φ″/2π, φ″ = −(p′/p)/p² (p = pdf_WC(φ)), which
    /// [`LobePoint`] gives with φ. Once a step is short, φ and p at its end follow from their
    /// Taylor series to second order instead of another inverse (see the module docs).
    pub(crate) fn sample_with_pdf(&self, u: f64) -> (f64, f64) {
        // Pure floor or pure lobe: invert directly
        if self.lambda >= 1.0 {
            return (uniform_azimuth(u), 1.0 / TAU);
        }
        let u = unit_interval(u);
        let mut at = LobePoint::at(u, self.c);
        let (lambda, c) = (self.lambda, self.c.abs());
        if c > C_MAX_FIT {
            // No table stores so narrow a lobe; near its peak φ resolves it poorly, and the
            // solve follows the distribution and density as evaluated, from φ
            if lambda == 0.0 {
                return (at.phi, self.pdf(at.phi));
            }
            return self.sample_in_phi(u, at.phi);
        }
        if lambda == 0.0 {
            return (at.phi, at.pdf);
        }
        // In w while H′ = λ/(2π p) + 1 − λ varies by at most a factor 2 over the lobe, where
        // 2π·p runs from q = (1 − |c|)/(1 + |c|) to 1/q; otherwise cdf itself, in φ, is the
        // tamer function. H′ ≥ 0 is the profile's density: for a signed floor (λ < 0) it is
        // smallest opposite the lobe, where it may reach 0.
        let q = (1.0 - c) / (1.0 + c);
        let in_w = if lambda > 0.0 {
            lambda <= (1.0 - lambda) * q
        } else {
            let (smallest, largest) = (1.0 - lambda + lambda / q, 1.0 - lambda + lambda * q);
            largest <= 2.0 * smallest
        };
        if !in_w {
            return self.sample_in_phi(u, at.phi);
        }
        let residual = |w: f64, phi: f64| lambda * (phi + PI) * INV_TAU + (1.0 - lambda) * w - u;
        let mut w = u;
        let mut h = residual(w, at.phi);
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..SAMPLE_MAX_ITER {
            if h.abs() <= SAMPLE_U_TOL {
                break;
            }
            if h > 0.0 {
                hi = w;
            } else {
                lo = w;
            }
            // One division for the derivatives and the Taylor series: 1/p
            let inv_p = 1.0 / at.pdf;
            let d1 = lambda * inv_p * INV_TAU + (1.0 - lambda);
            let d2 = -lambda * at.dlog * inv_p * inv_p * INV_TAU;
            let den = 2.0 * d1 * d1 - h * d2;
            let step = if den > 0.0 {
                2.0 * h * d1 / den
            } else {
                h / d1
            };
            let next = if w - step > lo && w - step < hi {
                w - step
            } else {
                0.5 * (lo + hi)
            };
            if next <= lo || next >= hi {
                // Bracket down to adjacent floats
                break;
            }
            // A short step: φ(w) and p(φ) to second order, the third-order terms are below
            // the tolerance (cdf error ~ |δ|·(Δp/p)², density error ~ (Δp/p)³)
            let delta = next - w;
            let dphi = delta * inv_p - 0.5 * at.dlog * (delta * inv_p) * (delta * inv_p);
            let dp = at.dlog * dphi;
            if delta.abs() <= TAYLOR_STEP && dp.abs() <= TAYLOR_DENSITY {
                let pdf = at.pdf * (1.0 + dp + 0.5 * at.d2 * dphi * dphi);
                return ((at.phi + dphi).clamp(-PI, PI), self.mix_pdf(pdf));
            }
            at = LobePoint::at(next, self.c);
            w = next;
            h = residual(w, at.phi);
        }
        (at.phi, self.mix_pdf(at.pdf))
    }

    /// The solve of [`Gwc::sample_with_pdf`] in φ: Newton steps on cdf(φ) − u from `start`,
    /// kept inside a bisection bracket, each iterate evaluating cdf and pdf together.
    fn sample_in_phi(&self, u: f64, start: f64) -> (f64, f64) {
        let mut phi = start;
        let (cdf, mut pdf) = self.cdf_and_pdf(phi);
        let mut g = cdf - u;
        let (mut lo, mut hi) = (-PI, PI);
        for _ in 0..SAMPLE_MAX_ITER {
            if g.abs() <= SAMPLE_U_TOL {
                break;
            }
            if g > 0.0 {
                hi = phi;
            } else {
                lo = phi;
            }
            let newton = phi - g / pdf;
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if next <= lo || next >= hi {
                // Bracket down to adjacent floats
                break;
            }
            phi = next;
            let (cdf, density) = self.cdf_and_pdf(phi);
            (g, pdf) = (cdf - u, density);
        }
        (phi, pdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_with_pdf_returns_the_pdf_at_the_sample() {
        // Pure lobe (the pdf from the inverse's sines), pure floor, mixtures, both signs of c
        for (alpha, beta, c) in [
            (0.0, 1.0, 0.8),
            (1.0, 0.0, 0.0),
            (0.1, 1.0, 0.5),
            (0.05, 2.0, -0.8),
            (1e-3, 1.0, 0.999),
            (0.3, 1.0, -0.9999),
        ] {
            let g = Gwc::new(alpha, beta, c).unwrap();
            for u in [0.0, 1e-12, 0.1, 0.5, 0.77, 1.0 - 1e-12, 1.0] {
                let (phi, pdf) = g.sample_with_pdf(u);
                assert_eq!(phi, g.sample(u));
                let want = g.pdf(phi);
                assert!(
                    (pdf / want - 1.0).abs() < 1e-12,
                    "{g:?} u {u}: {pdf} vs {want}"
                );
            }
        }
    }

    #[test]
    fn sample_inverts_cdf_over_random_profiles() {
        // Random lobes up to |c| = 0.999 either way, floors from 1e-12 to 100: the
        // solve in w = cdf_WC(φ), its Taylor finish and the solve in φ all meet the tolerance
        let mut state = 7u64;
        let mut uniform = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let check = |g: Gwc, u: f64| {
            let (phi, pdf) = g.sample_with_pdf(u);
            assert!((g.cdf(phi) - u).abs() <= 2.0 * SAMPLE_U_TOL, "{g:?} u {u}");
            assert!((pdf / g.pdf(phi) - 1.0).abs() < 1e-11, "{g:?} u {u}");
        };
        for _ in 0..200_000 {
            let c = (2.0 * uniform() - 1.0) * 0.999;
            let (alpha, beta) = (10f64.powf(2.0 - 14.0 * uniform()), uniform());
            check(Gwc::new(alpha, beta, c).unwrap(), uniform());
        }
        // Signed floors (λ < 0) anywhere down to the bound, where f(π) = 0
        for _ in 0..100_000 {
            let c = (2.0 * uniform() - 1.0) * 0.999;
            let beta = uniform();
            let alpha = super::super::floor_bound(beta, c) * uniform();
            check(Gwc::new(alpha, beta, c).unwrap(), uniform());
        }
        // A grid through peaked lobes with floors of every size, every u
        for c in [-0.99, -0.95, -0.5, 0.0, 0.5, 0.95, 0.99] {
            for alpha in [1e-9, 1e-3, 0.01, 0.03, 0.1, 1.0, 10.0] {
                for k in 0..=400 {
                    check(Gwc::new(alpha, 1.0, c).unwrap(), f64::from(k) / 400.0);
                }
            }
        }
        // Backward lobes with λ ≈ 0.3–0.7, where a solve in w alone does not converge: H(w)
        // is nearly a step where φ(w) crosses the flat middle of the lobe
        for (alpha, c, u) in [
            (0.063_095_734_448_019_36, -0.989, 0.39),
            (0.1, -0.989, 0.66),
            (0.251_188_643_150_958_24, -0.989, 0.225),
            (0.316_227_766_016_837_94, -0.987, 0.8),
            (0.158_489_319_246_111_43, -0.985, 0.29),
        ] {
            check(Gwc::new(alpha, 1.0, c).unwrap(), u);
        }
        // Beyond C_MAX_FIT the solve follows the forward cdf even for a tiny floor (in w, its
        // Taylor finish would leave 1.3e-12 here, where φ resolves the lobe poorly)
        let g = Gwc::new(
            3.256_576_227_224_831_6e-12,
            0.695_609_687_942_326_6,
            -0.999_994_972_227_05,
        )
        .unwrap();
        let u = 0.570_681_163_124_840_9;
        assert!((g.cdf(g.sample(u)) - u).abs() <= SAMPLE_U_TOL);
    }
}
