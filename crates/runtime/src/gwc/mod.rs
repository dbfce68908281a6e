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
//! | α      | isotropic floor (signed, see below)     | unit of f            | [−β·min pdf_WC, ∞) |
//! | β      | mass of the lobe, ∫ β·pdf_WC dφ         | unit of f × rad      | [0, ∞)          |
//! | c      | lobe concentration (mean resultant)     | 1                    | (−1, 1)         |
//! | E      | radial energy r·∫f dφ = (2πα + β)·r      | unit of f × rad × r  | [0, ∞)          |
//!
//! c > 0 peaks forward (φ = 0), c = 0 is uniform, c < 0 peaks backward (φ = ±π). The report
//! restricts c to [0, 1); we allow negative c because pdf_WC(φ; −c) = pdf_WC(π − |φ|; c) is the
//! same lobe mirrored, every formula below holds unchanged, and it makes the three-anchor fit
//! total: any monotone profile, forward or backward, has an admissible fit, and the parameters
//! pass continuously through c = 0. Photon beam diffusion itself is forward-peaked (the source
//! is nearest the exit point at φ = 0), so its tables only hold c ≥ 0.
//!
//! Tables store (E, β, c) per radius (§3.1, Eq. 1) and evaluation recovers α = (E/r − β)/2π
//! (§4.1, [`Gwc::from_table`]). The normalised density is the mixture
//! λ/2π + (1 − λ)·pdf_WC with λ = 2πα/(2πα + β), the λ of the report's §7.3 rewriting.
//!
//! **Signed floors.** The report keeps α ≥ 0. We also allow α < 0 down to
//! [`floor_bound`] = −β·min pdf_WC = −β(1 − |c|)/(2π(1 + |c|)), where the profile touches 0
//! opposite its lobe: a lobe less a constant, still ≥ 0 at every φ (λ < 0, and the mixture is
//! still a density). Profiles flatter than lobe plus floor, such as photon beam diffusion far out
//! in r and at low albedo, need it: at (ρ′, θ, r) = (0.5, 89°, 13) the best GWC over 181
//! azimuths is 1.33 % off with α ≥ 0 and 0.34 % with a signed floor; at (0.078, 70°, 0.7),
//! 2.0 % and 0.30 %. Equivalently β ≤ [`lobe_cap`]`(E/r, c)` = E/r·(1 + |c|)/(2|c|). The
//! three-anchor fit below keeps the report's α ≥ 0; the minimax refinement reaches signed
//! floors, and tables store them (format 1.1, required feature `signed-floor`).
//!
//! Near index matching one lobe is not enough at grazing incidence; [`TwoLobe`] adds a second
//! (`gwc/two_lobe.rs`), which tables below η = 1.33 store by default.
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
//! cdf(φ) = λ(φ + π)/2π + (1 − λ)·cdf_WC(φ; c) is inverted by Newton-type steps safeguarded
//! by a bisection bracket (§4.2), started at cdf_WC⁻¹(u) (the α = 0 answer, usually close
//! because 2πα ≪ β in practice), in the variable w = cdf_WC(φ) where that is the tamer one and
//! in φ elsewhere (`gwc/sample.rs`). Stops when the residual is at most 10⁻¹³ or the bracket is
//! down to adjacent floats; at most 100 iterations (bisection alone needs about 60). The
//! density at the sample comes with it.
//!
//! Source: A. Ferrier, *Non-perpendicular incidence BSSRDF model*, internship report, 2016:
//! §3.2 (model, Eq. 1), §3.3 (anchors, fit), §4.1 (evaluation), §4.2 (sampling), §7.3.

mod sample;
mod trig;
mod two_lobe;

pub use sample::{uniform_azimuth, unit_interval};
pub use two_lobe::{
    harmonics_are_signed, one_lobe_of, sharp_concentration, Rebuild, TwoLobe, C_MAX_TWO_LOBES,
    C_MIN_SECOND_LOBE, MERGED_DEPARTURE, MERGED_SPLIT,
};

use std::f64::consts::{PI, TAU};

use crate::error::{finite, in_range, non_negative, Result};
use crate::float::next_towards;
use trig::{atan2_quadrant, sin_quarter};

/// Largest |c| the three-anchor fit of the bake produces, hence the largest a table holds (`bssrdf_zoo::gwc::fit`).
pub const C_MAX_FIT: f64 = 0.99;

/// Largest |c| used in evaluation: inputs beyond it (or NaN, taken as 0) are clamped to it.
pub const C_LIMIT: f64 = 1.0 - f64::EPSILON;

/// Tolerance on |cdf(φ) − u| at which [`Gwc::sample`] stops.
pub const SAMPLE_U_TOL: f64 = 1e-13;

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
    (sin_quarter(0.5 * a), sin_quarter(0.5 * (PI - a)))
}

/// One-sided tail mass ∫_{|φ|}^{π} pdf_WC, from (sin h, cos h), in [0, 1/2]: both arguments of
/// the atan2 are ≥ 0 (`trig::atan2_quadrant`, as in the inverse, `sample::LobePoint::at`).
fn tail_wc(s: f64, co: f64, c: f64) -> f64 {
    atan2_quadrant((1.0 - c) * co, (1.0 + c) * s) / PI
}

/// pdf_WC from (sin h, cos h) and a clamped c.
fn pdf_wc_half(s: f64, co: f64, c: f64) -> f64 {
    (1.0 - c) * (1.0 + c) / (TAU * wc_denominator(s, co, c))
}

/// 1 + c² − 2c·cos φ from (sin h, cos h) and a clamped c, without cancellation.
fn wc_denominator(s: f64, co: f64, c: f64) -> f64 {
    if c >= 0.0 {
        (1.0 - c) * (1.0 - c) + 4.0 * c * s * s
    } else {
        (1.0 + c) * (1.0 + c) - 4.0 * c * co * co
    }
}

/// f(φ) = α + β·pdf_WC(φ; c) of the profile with 2πα + β = `e_per_r` (E/r ≥ 0) and lobe β
/// (0 ≤ β ≤ [`lobe_cap`]`(E/r, c)`), for φ in [−π, π], without building it: (E/r + β(L − 1))/2π with
/// L = 2π·pdf_WC(φ; c) and c clamped as in [`Gwc::from_table`]. Equal to
/// `Gwc::from_table(E, β, c, r).eval(φ)` up to rounding, with fewer dependent divisions after E
/// is known (an evaluation's E comes last, out of a logarithm).
#[inline]
pub(crate) fn table_value(e_per_r: f64, beta: f64, c: f64, phi: f64) -> f64 {
    let (s, co) = half_angle(phi);
    let c = clamp_c(c);
    let lobe = (1.0 - c) * (1.0 + c) / wc_denominator(s, co, c);
    ((e_per_r + beta * (lobe - 1.0)) * (1.0 / TAU)).max(0.0)
}

/// The lowest floor α that keeps α + β·pdf_WC(φ; c) ≥ 0 at every φ: −β·min pdf_WC
/// = −β(1 − |c|)/(2π(1 + |c|)) (the minimum is opposite the lobe), ≤ 0. c is clamped as in
/// [`pdf_wc`].
pub fn floor_bound(beta: f64, c: f64) -> f64 {
    let c = clamp_c(c).abs();
    -beta * (1.0 - c) / (TAU * (1.0 + c))
}

/// The largest lobe β of a profile with 2πα + β = `e_per_r` (E/r ≥ 0) that stays ≥ 0:
/// 2πα = E/r − β ≥ −β(1 − |c|)/(1 + |c|) gives β ≤ E/r·(1 + |c|)/(2|c|), at least E/r (α = 0
/// is always admissible). At c = 0 it is E/r: the lobe is uniform and any split is the same
/// profile, the one with α ≥ 0 is kept. c is clamped as in [`pdf_wc`].
pub fn lobe_cap(e_per_r: f64, c: f64) -> f64 {
    let c = clamp_c(c).abs();
    if c == 0.0 {
        e_per_r
    } else {
        e_per_r * (1.0 + c) / (2.0 * c)
    }
}

/// min(β, [`lobe_cap`]`(E/r, c)`) for β ≥ 0 and E/r ≥ 0, dividing only when β exceeds the cap
/// (rarely: lookups call it on interpolated cells, whose β is within it but near the nodes
/// that sit on it). NaN β is returned as is.
#[inline]
pub(crate) fn cap_lobe(beta: f64, e_per_r: f64, c: f64) -> f64 {
    let a = clamp_c(c).abs();
    // At c = 0 the cap is E/r itself (see `lobe_cap`)
    if beta * (2.0 * a) > e_per_r * (1.0 + a) || (a == 0.0 && beta > e_per_r) {
        lobe_cap(e_per_r, c)
    } else {
        beta
    }
}

/// cdf_WC for φ inside (−π, π), from (sin h, cos h) and a clamped c.
fn cdf_wc_half(phi: f64, s: f64, co: f64, c: f64) -> f64 {
    let t = tail_wc(s, co, c);
    if phi >= 0.0 {
        1.0 - t
    } else {
        t
    }
}

/// Wrapped Cauchy density pdf_WC(φ; c) = (1/2π)(1 − c²)/(1 + c² − 2c·cos φ), in rad⁻¹.
///
/// Zero for φ outside [−π, π] or NaN; c is clamped into [−[`C_LIMIT`], `C_LIMIT`] (NaN → 0).
pub fn pdf_wc(phi: f64, c: f64) -> f64 {
    if !in_domain(phi) {
        return 0.0;
    }
    let (s, co) = half_angle(phi);
    pdf_wc_half(s, co, clamp_c(c))
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
    cdf_wc_half(phi, s, co, clamp_c(c))
}

/// Inverse of [`cdf_wc`]: the φ ∈ [−π, π] with cdf_WC(φ; c) = u.
///
/// Equal to 2·arctan(((1−c)/(1+c))·tan(π(u − 1/2))) (Ferrier 2016, §4.2), evaluated without
/// tan. u is clamped into [0, 1] (NaN → 0); c is clamped as in [`pdf_wc`].
pub fn inv_cdf_wc(u: f64, c: f64) -> f64 {
    inv_cdf_wc_with_pdf(u, c).0
}

/// [`inv_cdf_wc`] and pdf_WC there.
fn inv_cdf_wc_with_pdf(u: f64, c: f64) -> (f64, f64) {
    let at = sample::LobePoint::at(u, c);
    (at.phi, at.pdf)
}

/// A General Wrapped Cauchy profile f(φ) = α + β·pdf_WC(φ; c) (see the module docs).
///
/// Invariants: β finite and ≥ 0, |c| < 1, α finite and at least [`floor_bound`]`(β, c)`
/// (the profile is ≥ 0 at every φ; α < 0 is a *signed floor*, a lobe less a constant), and
/// 2πα + β finite.
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
    /// Errors ([`crate::Error::NotFinite`], [`crate::Error::Negative`], [`crate::Error::OutOfRange`]) if α or β is
    /// not finite, if β is negative, if c is NaN or outside [−[`C_LIMIT`], `C_LIMIT`] (the
    /// floats in (−1, 1)), if α is below [`floor_bound`]`(β, c)` (the profile would dip below 0
    /// opposite the lobe), or if 2πα + β overflows. α = β = 0 is allowed (the zero profile).
    pub fn new(alpha: f64, beta: f64, c: f64) -> Result<Self> {
        finite("alpha", alpha)?;
        non_negative("beta", beta)?;
        in_range("c", c, -C_LIMIT, C_LIMIT)?;
        if alpha < 0.0 {
            in_range("alpha", alpha, floor_bound(beta, c), 0.0)?;
        }
        finite("2*pi*alpha + beta", TAU * alpha + beta)?;
        Ok(Self::from_parts(alpha, beta, c))
    }

    /// Builds from values already known to satisfy the invariants (up to 2πα + β overflow,
    /// which only affects [`Gwc::integral`]).
    fn from_parts(alpha: f64, beta: f64, c: f64) -> Self {
        let iso = TAU * alpha;
        let lambda = if iso + beta > 0.0 {
            if alpha > 0.0 {
                // 1/(1 + β/2πα) keeps λ in [0, 1] even if 2πα + β overflows
                1.0 / (1.0 + beta / iso)
            } else {
                // A signed floor: |2πα| < β, so 2πα + β > 0 cannot overflow; λ < 0
                iso / (iso + beta)
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
    /// - E/r: negative → 0; then β is clamped to at most [`lobe_cap`]`(E/r, c)` (β > E/r is a
    ///   signed floor α < 0; beyond the cap the profile would dip below 0), so the stored energy
    ///   E is kept exactly (2πα + β = E/r) while the lobe shape c is kept;
    /// - E/r not finite (r = 0 row, r ≤ 0, E non-finite): the energy carries no information,
    ///   α = 0 and the profile is β·pdf_WC alone.
    pub fn from_table(e: f64, beta: f64, c: f64, r: f64) -> Self {
        let c = clamp_c(c);
        let beta = if beta.is_finite() { beta.max(0.0) } else { 0.0 };
        let e_per_r = e / r;
        if r > 0.0 && e_per_r.is_finite() {
            let e_per_r = e_per_r.max(0.0);
            let beta = cap_lobe(beta, e_per_r, c);
            // × 1/2π: a division less on the path of every lookup (α moves by an ulp at most)
            Self::from_parts((e_per_r - beta) * (1.0 / TAU), beta, c)
        } else {
            Self::from_parts(0.0, beta, c)
        }
    }

    /// The profile of unit integral (2πα + β = 1) whose lobe carries `share` ∈ [0, 1] of it
    /// (NaN → 0), with c clamped as in [`Gwc::from_table`]: what a sampler needs of a table
    /// cell, since the normalised density depends on the share and c only. λ = 1 − share
    /// directly, without the divisions of [`Gwc::from_table`].
    ///
    /// A share above 1, a signed floor, is drawn as 1: the lobe alone, which inverts in closed
    /// form, where a signed floor needs a Newton solve (one more inversion of the lobe; it
    /// slowed the table's `sample` by 8 %, a quarter of its draws being in such cells). The
    /// density of the draw is that lobe's, so sample and pdf stay an exact pair. The signed
    /// profile's own density (1 − λ)·pdf_WC + λ/2π (λ < 0) is at most 1 + |λ| times the lobe's
    /// (at its peak) and falls to 0 opposite it, so a renderer's weights S/pdf grow by at most
    /// that factor (`table::lookup` states |λ| on the default table).
    pub(crate) fn normalised(share: f64, c: f64) -> Self {
        let share = if share.is_nan() {
            0.0
        } else {
            share.clamp(0.0, 1.0)
        };
        Self {
            alpha: (1.0 - share) * (1.0 / TAU),
            beta: share,
            c: clamp_c(c),
            lambda: 1.0 - share,
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
        // ≥ 0 exactly: a signed floor at its bound cancels to rounding opposite the lobe
        (self.alpha + self.beta * pdf_wc(phi, self.c)).max(0.0)
    }

    /// Normalised density f(φ)/∫f in rad⁻¹; 0 outside [−π, π] or for NaN.
    ///
    /// The zero profile is given the uniform density 1/2π, consistent with [`Gwc::sample`].
    pub fn pdf(&self, phi: f64) -> f64 {
        if !in_domain(phi) {
            return 0.0;
        }
        self.mix_pdf(pdf_wc(phi, self.c))
    }

    /// λ/2π + (1 − λ)·`lobe`, the density from the lobe's (≥ 0: with λ < 0, a signed floor at
    /// its bound, it cancels to rounding opposite the lobe).
    fn mix_pdf(&self, lobe: f64) -> f64 {
        (self.lambda / TAU + (1.0 - self.lambda) * lobe).max(0.0)
    }

    /// λ(φ + π)/2π + (1 − λ)·`lobe`, clamped into [0, 1]: the distribution from the lobe's.
    fn mix_cdf(&self, phi: f64, lobe: f64) -> f64 {
        let uniform = (phi + PI) / TAU;
        (self.lambda * uniform + (1.0 - self.lambda) * lobe).clamp(0.0, 1.0)
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
        self.mix_cdf(phi, cdf_wc(phi, self.c))
    }

    /// [`Gwc::cdf`] and [`Gwc::pdf`] at φ ∈ [−π, π], from one sin h and cos h.
    fn cdf_and_pdf(&self, phi: f64) -> (f64, f64) {
        let (s, co) = half_angle(phi);
        let c = clamp_c(self.c);
        let cdf = if phi <= -PI {
            0.0
        } else if phi >= PI {
            1.0
        } else {
            self.mix_cdf(phi, cdf_wc_half(phi, s, co, c))
        };
        (cdf, self.mix_pdf(pdf_wc_half(s, co, c)))
    }
}

#[cfg(test)]
mod tests {

    /// The samplers' normalised profile draws and weighs φ like the full profile it stands for.
    #[test]
    fn normalised_profile_matches_the_table_profile_in_phi() {
        for (e, share, c) in [
            (0.3, 0.0, 0.2),
            (2.0, 0.4, 0.9),
            (1e-30, 1.0, -0.5),
            (5.0, 0.17, 0.0),
        ] {
            let r = 0.7;
            let full = Gwc::from_table(e, share * e / r, c, r);
            let unit = Gwc::normalised(share, c);
            assert!((unit.integral() - 1.0).abs() < 1e-15);
            for k in 0..=40 {
                let phi = -PI + TAU * f64::from(k) / 40.0;
                let (a, b) = (full.pdf(phi), unit.pdf(phi));
                assert!(
                    (a - b).abs() <= 1e-14 * a.max(1.0),
                    "pdf at {phi}: {a} vs {b}"
                );
                let (a, b) = (full.cdf(phi), unit.cdf(phi));
                assert!((a - b).abs() <= 1e-14, "cdf at {phi}: {a} vs {b}");
            }
            for u in [0.0, 0.1, 0.5, 0.93, 1.0] {
                let (a, b) = (full.sample(u), unit.sample(u));
                assert!((a - b).abs() <= 1e-12, "sample at {u}: {a} vs {b}");
            }
        }
        assert_eq!(Gwc::normalised(f64::NAN, 0.3).integral(), 1.0);
    }
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn half_angle_cosine_vanishes_exactly_at_pi() {
        assert_eq!(half_angle(PI), (sin_quarter(FRAC_PI_2), 0.0));
        assert_eq!(half_angle(-PI).1, 0.0);
        assert_eq!(half_angle(0.0), (0.0, 1.0));
    }
}
