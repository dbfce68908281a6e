//! General Wrapped Cauchy (GWC) angular model of the multiple-scattering profile at fixed radius.
//!
//! At a fixed entry point, incidence angle θ and exit radius r, the angular dependence of the
//! BSSRDF on the exit azimuth φ is approximated by
//!
//! ```text
//! f(φ) = α + β·pdf_WC(φ; c),      pdf_WC(φ; c) = (1/2π)·(1 − c²)/(1 + c² − 2c·cos φ),
//! ```
//!
//! a constant floor plus a wrapped Cauchy lobe (Ferrier 2016, §3.2). φ ∈ [−π, π] in radians,
//! φ = 0 forward (the side the refracted beam travels to).
//!
//! | symbol | meaning                                 | unit                 | range           |
//! |--------|-----------------------------------------|----------------------|-----------------|
//! | α      | isotropic floor                         | unit of f            | [0, ∞)          |
//! | β      | mass of the lobe, ∫ β·pdf_WC dφ         | unit of f × rad      | [0, ∞)          |
//! | c      | lobe concentration (mean resultant)     | 1                    | (−1, 1)         |
//! | E      | radial energy r·∫f dφ = (2πα + β)·r      | unit of f × rad × r  | [0, ∞)          |
//!
//! c > 0 peaks forward (φ = 0), c = 0 is uniform, c < 0 peaks backward (φ = ±π). The report
//! restricts c to [0, 1); we allow negative c because pdf_WC(φ; −c) = pdf_WC(π − |φ|; c) is the
//! same lobe mirrored and every formula below holds unchanged. Photon beam diffusion itself is forward-peaked (the source
//! is nearest the exit point at φ = 0), so its tables only hold c ≥ 0.
//!
//! Tables store (E, β, c) per radius (§3.1, Eq. 1) and evaluation recovers α = (E/r − β)/2π
//! (§4.1, [`Gwc::from_table`]). The normalised density is the mixture
//! λ/2π + (1 − λ)·pdf_WC with λ = 2πα/(2πα + β), the λ of the report's §7.3 rewriting.
//!
//! # Wrapped Cauchy density and distribution
//!
//! With h = |φ|/2, 1 + c² − 2c·cos φ = (1 − c)² + 4c·sin²h = (1 + c)² − 4c·cos²h; the first form
//! has no cancellation for c ≥ 0, the second for c < 0. The report's (§4.2)
//! cdf_WC = 1/2 + arctan(((1+c)/(1−c))·tan(φ/2))/π uses tan(φ/2), which diverges at φ = ±π.
//! We use the equivalent one-sided tail T(|φ|) = ∫_{|φ|}^{π} pdf_WC = atan2((1−c)·cos h,
//! (1+c)·sin h)/π, so cdf_WC = 1 − T for φ ≥ 0 and T for φ < 0. cos h is computed as
//! sin((π − |φ|)/2), which is exactly 0 at the float |φ| = π: the cdf is exactly 0 and 1 at ±π
//! and continuous up to them. The inverse solves the same relation for h.
//!
//! # Sampling
//!
//! cdf(φ) = λ(φ + π)/2π + (1 − λ)·cdf_WC(φ; c) is inverted by Newton steps safeguarded by a
//! bisection bracket (§4.2), started at cdf_WC⁻¹(u) (the α = 0 answer, usually close because
//! 2πα ≪ β in practice). Stops when |cdf(φ) − u| ≤ 10⁻¹³ or the bracket is down to adjacent
//! floats; at most 100 iterations (bisection alone needs about 60).
//!
//! # Where it breaks down
//!
//! - A GWC profile is monotone in |φ|; bumps cannot be represented.
//! - For 1 − |c| below about 10⁻¹⁰ the lobe is narrower than the float spacing allows to sample
//!   accurately; evaluation stays finite but the cdf round trip degrades.
//!
//! Source: A. Ferrier, *Non-perpendicular incidence BSSRDF model*, internship report, 2016:
//! §3.2 (model, Eq. 1), §4.1 (evaluation), §4.2 (sampling), §7.3.

use std::f64::consts::{PI, TAU};

use crate::error::{finite, in_range, Error, Result};

/// Largest |c| used in evaluation: inputs beyond it (or NaN, taken as 0) are clamped to it.
pub const C_LIMIT: f64 = 1.0 - f64::EPSILON;

/// Tolerance on |cdf(φ) − u| at which [`Gwc::sample`] stops.
pub const SAMPLE_U_TOL: f64 = 1e-13;

/// Iteration cap of the Newton–bisection in [`Gwc::sample`].
const SAMPLE_MAX_ITER: usize = 100;

/// Checks that `value` is finite and ≥ 0 (−0 allowed), naming it in the error otherwise.
fn non_negative(name: &'static str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value < 0.0 {
        return Err(Error::Negative { name, value });
    }
    Ok(value)
}

/// Whether φ lies in [−π, π] (false for NaN).
fn in_domain(phi: f64) -> bool {
    phi.abs() <= PI
}

/// Clamps c into [−C_LIMIT, C_LIMIT], NaN to 0.
fn clamp_c(c: f64) -> f64 {
    if c.is_nan() {
        0.0
    } else {
        c.clamp(-C_LIMIT, C_LIMIT)
    }
}

/// (sin h, cos h) for h = |φ|/2, with cos h exactly 0 at |φ| = π (the float `PI`).
fn half_angle(phi: f64) -> (f64, f64) {
    let a = phi.abs();
    ((0.5 * a).sin(), (0.5 * (PI - a)).sin())
}

/// One-sided tail mass ∫_{|φ|}^{π} pdf_WC, from (sin h, cos h), in [0, 1/2].
fn tail_wc(s: f64, co: f64, c: f64) -> f64 {
    ((1.0 - c) * co).atan2((1.0 + c) * s) / PI
}

/// Wrapped Cauchy density pdf_WC(φ; c) = (1/2π)(1 − c²)/(1 + c² − 2c·cos φ), in rad⁻¹.
///
/// Zero for φ outside [−π, π] or NaN; c is clamped into [−[`C_LIMIT`], `C_LIMIT`] (NaN → 0).
pub fn pdf_wc(phi: f64, c: f64) -> f64 {
    if !in_domain(phi) {
        return 0.0;
    }
    let c = clamp_c(c);
    let (s, co) = half_angle(phi);
    // Denominator 1 + c² − 2c·cos φ without cancellation
    let den = if c >= 0.0 {
        (1.0 - c) * (1.0 - c) + 4.0 * c * s * s
    } else {
        (1.0 + c) * (1.0 + c) - 4.0 * c * co * co
    };
    (1.0 - c) * (1.0 + c) / (TAU * den)
}

/// Wrapped Cauchy distribution function ∫_{−π}^{φ} pdf_WC, exactly 0 at −π and 1 at π.
///
/// Equal to 1/2 + arctan(((1+c)/(1−c))·tan(φ/2))/π (Ferrier 2016, §4.2) inside (−π, π), but
/// evaluated without tan so it is continuous up to ±π. φ ≤ −π or NaN gives 0, φ ≥ π gives 1;
/// c is clamped as in [`pdf_wc`].
pub fn cdf_wc(phi: f64, c: f64) -> f64 {
    if phi.is_nan() || phi <= -PI {
        return 0.0;
    }
    if phi >= PI {
        return 1.0;
    }
    let (s, co) = half_angle(phi);
    let t = tail_wc(s, co, clamp_c(c));
    if phi >= 0.0 {
        1.0 - t
    } else {
        t
    }
}

/// Inverse of [`cdf_wc`]: the φ ∈ [−π, π] with cdf_WC(φ; c) = u.
///
/// Equal to 2·arctan(((1−c)/(1+c))·tan(π(u − 1/2))) (Ferrier 2016, §4.2), evaluated without
/// tan. u is clamped into [0, 1] (NaN → 0); c is clamped as in [`pdf_wc`].
pub fn inv_cdf_wc(u: f64, c: f64) -> f64 {
    let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
    let c = clamp_c(c);
    // Tail mass t beyond |φ| and its complement m = 1/2 − t, both without cancellation
    let (t, m, sign) = if u >= 0.5 {
        (1.0 - u, u - 0.5, 1.0)
    } else {
        (u, 0.5 - u, -1.0)
    };
    // Solve π·t = atan2((1−c)·cos h, (1+c)·sin h) for h = |φ|/2
    let h = ((1.0 - c) * (PI * m).sin()).atan2((1.0 + c) * (PI * t).sin());
    sign * (2.0 * h).min(PI)
}

/// A General Wrapped Cauchy profile f(φ) = α + β·pdf_WC(φ; c) (see the module docs).
///
/// Invariants: α, β finite and ≥ 0, 2πα + β finite, |c| < 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gwc {
    alpha: f64,
    beta: f64,
    c: f64,
    /// Weight of the uniform part in the normalised density, 2πα/(2πα + β); 1 if both are 0.
    lambda: f64,
}

impl Gwc {
    /// Builds a profile from α (unit of f), β (unit of f × rad) and c (dimensionless).
    ///
    /// Errors ([`Error::NotFinite`], [`Error::Negative`], [`Error::OutOfRange`]) if α or β is
    /// not finite or negative, if c is NaN or outside [−[`C_LIMIT`], `C_LIMIT`] (the floats in
    /// (−1, 1)), or if 2πα + β overflows. α = β = 0 is allowed (the zero profile).
    pub fn new(alpha: f64, beta: f64, c: f64) -> Result<Self> {
        for (name, value) in [("alpha", alpha), ("beta", beta)] {
            non_negative(name, value)?;
        }
        in_range("c", c, -C_LIMIT, C_LIMIT)?;
        finite("2*pi*alpha + beta", TAU * alpha + beta)?;
        Ok(Self::from_parts(alpha, beta, c))
    }

    /// Builds from values already known to satisfy the invariants (up to 2πα + β overflow,
    /// which only affects [`Gwc::integral`]).
    fn from_parts(alpha: f64, beta: f64, c: f64) -> Self {
        let iso = TAU * alpha;
        let lambda = if iso + beta > 0.0 {
            // 1/(1 + β/2πα) keeps λ in [0, 1] even if 2πα + β overflows
            if alpha > 0.0 {
                1.0 / (1.0 + beta / iso)
            } else {
                0.0
            }
        } else {
            1.0
        };
        Self {
            alpha,
            beta,
            c,
            lambda,
        }
    }

    /// Builds the profile a table cell (E, β, c) describes at radius r > 0, with
    /// α = (E/r − β)/2π (Ferrier 2016, §4.1).
    ///
    /// Interpolated cells may be slightly inconsistent; this never fails and clamps as follows:
    /// - c: NaN → 0, then into [−[`C_LIMIT`], `C_LIMIT`];
    /// - β: NaN or ±∞ → 0, negative → 0;
    /// - E/r: negative → 0; then β is clamped to at most E/r, so α ≥ 0 and the stored energy E
    ///   is kept exactly (2πα + β = E/r) while the lobe shape c is kept;
    /// - E/r not finite (r = 0 row, r ≤ 0, E non-finite): the energy carries no information,
    ///   α = 0 and the profile is β·pdf_WC alone.
    pub fn from_table(e: f64, beta: f64, c: f64, r: f64) -> Self {
        let c = clamp_c(c);
        let beta = if beta.is_finite() { beta.max(0.0) } else { 0.0 };
        let e_per_r = e / r;
        if r > 0.0 && e_per_r.is_finite() {
            let e_per_r = e_per_r.max(0.0);
            let beta = beta.min(e_per_r);
            Self::from_parts((e_per_r - beta) / TAU, beta, c)
        } else {
            Self::from_parts(0.0, beta, c)
        }
    }

    /// Isotropic floor α (unit of f).
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Lobe mass β (unit of f × rad).
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Lobe concentration c ∈ (−1, 1); negative peaks backward.
    pub fn c(&self) -> f64 {
        self.c
    }

    /// ∫_{−π}^{π} f dφ = 2πα + β (Ferrier 2016, Eq. 1), unit of f × rad.
    pub fn integral(&self) -> f64 {
        TAU * self.alpha + self.beta
    }

    /// The table cell (E, β, c) of this profile at radius r, with E = r·(2πα + β).
    pub fn table_cell(&self, r: f64) -> [f64; 3] {
        [r * self.integral(), self.beta, self.c]
    }

    /// f(φ) = α + β·pdf_WC(φ; c); 0 for φ outside [−π, π] or NaN. Even in φ.
    ///
    /// Overflows to +∞ only when the true value exceeds `f64::MAX`.
    pub fn eval(&self, phi: f64) -> f64 {
        if !in_domain(phi) {
            return 0.0;
        }
        self.alpha + self.beta * pdf_wc(phi, self.c)
    }

    /// Normalised density f(φ)/∫f in rad⁻¹; 0 outside [−π, π] or for NaN.
    ///
    /// The zero profile is given the uniform density 1/2π, consistent with [`Gwc::sample`].
    pub fn pdf(&self, phi: f64) -> f64 {
        if !in_domain(phi) {
            return 0.0;
        }
        self.lambda / TAU + (1.0 - self.lambda) * pdf_wc(phi, self.c)
    }

    /// Distribution function ∫_{−π}^{φ} pdf, the inverse of [`Gwc::sample`]:
    /// λ(φ + π)/2π + (1 − λ)·cdf_WC(φ; c) (Ferrier 2016, §4.2).
    ///
    /// Exactly 0 at −π and 1 at π; 0 below −π or for NaN, 1 above π.
    pub fn cdf(&self, phi: f64) -> f64 {
        if phi.is_nan() || phi <= -PI {
            return 0.0;
        }
        if phi >= PI {
            return 1.0;
        }
        let uniform = (phi + PI) / TAU;
        (self.lambda * uniform + (1.0 - self.lambda) * cdf_wc(phi, self.c)).clamp(0.0, 1.0)
    }

    /// Samples φ ∈ [−π, π] with density [`Gwc::pdf`] from u ∈ [0, 1], inverting [`Gwc::cdf`]
    /// (clamped into [0, 1], NaN → 0).
    ///
    /// Newton–bisection started at cdf_WC⁻¹(u; c); see the module docs for the stopping rule.
    pub fn sample(&self, u: f64) -> f64 {
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        // Pure floor or pure lobe: invert directly
        if self.lambda >= 1.0 {
            return (TAU * u - PI).clamp(-PI, PI);
        }
        let start = inv_cdf_wc(u, self.c);
        if self.lambda <= 0.0 {
            return start;
        }
        // Newton steps kept inside a shrinking bracket [lo, hi] around the root
        let (mut lo, mut hi) = (-PI, PI);
        let mut phi = start;
        for _ in 0..SAMPLE_MAX_ITER {
            let g = self.cdf(phi) - u;
            if g.abs() <= SAMPLE_U_TOL {
                break;
            }
            if g > 0.0 {
                hi = phi;
            } else {
                lo = phi;
            }
            let newton = phi - g / self.pdf(phi);
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
        }
        phi
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn half_angle_cosine_vanishes_exactly_at_pi() {
        assert_eq!(half_angle(PI), (FRAC_PI_2.sin(), 0.0));
        assert_eq!(half_angle(-PI).1, 0.0);
        assert_eq!(half_angle(0.0), (0.0, 1.0));
    }
}
