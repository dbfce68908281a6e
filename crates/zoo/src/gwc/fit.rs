//! Fits of the GWC profile to samples of a radial-azimuthal profile, for the bake.
//!
//! # Three-anchor fit (§3.3), derived
//!
//! Let x = cos φ and w = 2c/(1 + c²) ∈ (−1, 1), so c = w/(1 + √(1 − w²)) and
//! (1 − c²)/(1 + c²) = √(1 − w²). Dividing numerator and denominator of pdf_WC by 1 + c²,
//!
//! ```text
//! f = α + D/(1 − w·x),   D = β·√(1 − w²)/2π ≥ 0.
//! ```
//!
//! (The report's variables are a = 1/w, b = √(a² − 1), c = a − b for a > 1, B = D/w.) Differences
//! f_i − f_j = D·w·(x_i − x_j)/((1 − w·x_i)(1 − w·x_j)) lose α, and their ratio loses D:
//!
//! ```text
//! K = (f1 − f2)/(f2 − f3) = k·(1 − w·x3)/(1 − w·x1),   k = (x1 − x2)/(x2 − x3),
//! w = (K − k)/(K·x1 − k·x3)          (= 1/a, the report's a),
//! ```
//!
//! evaluated multiplied through by (f2 − f3)(x2 − x3) so that f2 = f3 needs no division by zero.
//! Then α and D follow from anchors 1 and 3:
//!
//! ```text
//! D = (f1 − f3)(1 − w·x1)(1 − w·x3) / (w·(x1 − x3)),
//! α = (f1·x1 − f3·x3)·(w − w0) / (w·(x1 − x3)),   w0 = (f1 − f3)/(f1·x1 − f3·x3),
//! β = 2π·D/√(1 − w²) = 2π·D·(1 + c²)/(1 − c²).
//! ```
//!
//! In the report's variables: β = (2π/b)·(f1 − f2)·[1/(a − x1) − 1/(a − x2)]⁻¹ and
//! α = f1 − β·b/(2π·(a − x1)). **The report prints [1/(a − x1) − 1/(a − x3)]⁻¹**, pairing the
//! difference f1 − f2 with anchors 1 and 3; the correct bracket uses anchor 2 (or, equivalently,
//! keeps anchor 3 and uses f1 − f3). Its a, b, c and α are right. The test
//! `paper_printed_beta_misses_the_anchors` shows the printed β failing.
//!
//! # Admissible fits and fallbacks
//!
//! Admissible means α ≥ 0, β ≥ 0 and |c| ≤ [`C_MAX_FIT`], so the stored profile is ≥ 0 on
//! [−π, π]. Samples are first divided by their maximum, so the fit is scale-invariant from
//! subnormal to 10³⁰⁰ (a sample over 10³⁰⁰ times smaller than the largest becomes subnormal and
//! loses precision). Orient by the larger of f1, f3 (the *peak anchor* p: 1 forward, 3
//! backward) and write t = ±w, positive for a lobe on that side; W = 2·C/(1 + C²) is the t of
//! C = C_MAX_FIT. With α = 0, 1/f = (1 − w·x)/D is linear in x; let t0 be the α = 0 profile
//! through anchors 1 and 3, t_pair the one through p and anchor 2. Then:
//!
//! - along the family through anchors 1 and 3 (w free), α has the sign of t − t0 and the value
//!   at anchor 2 is strictly monotone in w, so the exact fit has α ≥ 0 iff t_exact ≥ t0, iff
//!   anchor 2 lies on or above the α = 0 curve through 1 and 3, iff t_pair ≥ t0;
//! - for fixed anchor values β grows like 1/(1 − |c|) (a spike inside |φ| < φ1 that no anchor
//!   sees), so fallbacks keep the anchors nearest the peak, which carry the energy.
//!
//! The rules, in order, each meeting its neighbours where their results coincide (the fit is
//! continuous in the samples):
//!
//! | case                                                   | result                                         | branch                |
//! |--------------------------------------------------------|------------------------------------------------|-----------------------|
//! | NaN, ±∞ or negative f_i                                 | `Err` naming the sample                        | —                     |
//! | f1 = f2 = f3 = 0 (underflow far out in r)               | α = β = c = 0                                  | `Zero`                |
//! | f1 = f2 = f3 > 0                                        | α = f1, β = 0, c = 0                           | `Uniform`             |
//! | t_pair < t0: exact fit needs α < 0, e.g. the cosine limit K = k (w = 0 with β → ∞, α → −∞), a von Mises profile, f1 = f2 > f3 | α = 0 through p and anchor 2 (t = t_pair; t = 0, the constant f_p, if f2 = f_p) | `AlphaClamped` |
//! | … and t_pair > W (f_p/f2 > 12.65 forward)               | α = 0, \|c\| = C_MAX_FIT through p              | `PeakAndAlphaClamped` |
//! | t0 > W: α ≥ 0 cannot reach the contrast f1/f3 (> 37.2 forward), e.g. f3 = 0 | α = 0, \|c\| = C_MAX_FIT through p | `PeakAndAlphaClamped` |
//! | t_exact > W: needs \|c\| > C_MAX_FIT or has no real c (a ≤ 1, K > k(1 − x3)/(1 − x1) ≈ 17.65), e.g. f2 = f3 ≠ f1 | \|c\| = C_MAX_FIT, α ≥ 0 and β through anchors 1 and 3 | `PeakClamped` |
//! | otherwise                                               | all three anchors                              | `Exact`               |
//! | f2 outside [min(f1, f3), max(f1, f3)]                   | f2 moved to the nearer of f1, f3, then as above (only p is kept); f1 = f3 gives α = f1, β = 0 (α = max(f1, f3) when they agree only relative to f2) | `NonMonotone` |
//!
//! The report's choice for f2 = f3 (c = 0, β = 2π·f1, α = 0) is the constant f1: it misses
//! anchors 2 and 3 unless the profile is flat. For a flat profile we put the constant in α,
//! the limit of the exact branch as a profile flattens (β → 0); flattening through
//! `AlphaClamped` (f2 → f1) reaches the same function with the constant in β instead.
//!
//! # Refinement
//!
//! [`refine_minimax`] (`gwc/minimax.rs`) moves any admissible fit, the three-anchor one
//! included, to the GWC with a floor no lower than [`floor_bound`] (so signed floors included)
//! of smallest largest relative error over a few more samples, and keeps the fit unless that
//! lowers the error at the samples. Tables store it where the
//! three-anchor fit is weak (`table::bake`): their (E, E_β, c) stay GWC parameters, which no
//! longer pass exactly through the anchors there.
//!
//! # Where it breaks down
//!
//! - A GWC profile is monotone in |φ|; bumps between the anchors cannot be represented.
//! - With α ≥ 0 the contrast of any GWC is bounded by its c → 1 limit 1/(1 − cos φ):
//!   f(φ1)/f(φ2) < 12.7 and f(φ1)/f(φ3) < 37.3. Sharper profiles land in
//!   `PeakAndAlphaClamped`, whose spike at c = C_MAX_FIT can overestimate the energy many times
//!   (about 20× for e^(5·cos φ)).
//! - Profiles flatter than lobe plus floor need α < 0 and land in `AlphaClamped`: every von
//!   Mises e^(κ·cos φ) does (energy +5 % at κ = 0.5, +14 % at κ = 2, +31 % at κ = 4, the far
//!   anchor overestimated). Photon beam diffusion at large r is of this kind: on the report's
//!   grid (η = 1.33, all ρ′, θ, r) the crate's PBD gives 75 % `Exact`, 15 % `AlphaClamped`
//!   (energy within 7 %, all at large r), 10 % `Uniform` (θ = 0), 1 % `Zero`, and no
//!   `PeakClamped` or `PeakAndAlphaClamped`. The refinement's signed floor represents them
//!   (e^(cos φ/2): 0.77 % at the seven samples of the bake instead of 25 %); profiles flatter
//!   still, whose best signed floor touches 0, stay approximate.
//! - Three anchors say nothing about |φ| < φ1 ≈ 17.6°: a narrow peak there is a guess. Hence
//!   C_MAX_FIT = 0.99 for the fit: a lobe of half-width ≈ 1 − c ≈ 0.6° is far below what
//!   anchors at 17.6° resolve, and K is already within 0.1 % of its c → 1 limit.
//! - For 1 − |c| below about 10⁻¹⁰ the lobe is narrower than the float spacing allows to sample
//!   accurately; evaluation stays finite but the cdf round trip degrades.
//!
//! Source: A. Ferrier, *Non-perpendicular incidence BSSRDF model*, internship report, 2016:
//! §3.2 (model, Eq. 1), §3.3 (anchors, fit), §4.1 (evaluation), §4.2 (sampling), §7.3.

use std::f64::consts::TAU;

use super::{Gwc, C_MAX_FIT};
use crate::error::{in_range, non_negative, Result};
use crate::float::next_towards;

/// Anchor cosines (cos φ1, cos φ2, cos φ3) of the three-anchor fit (Ferrier 2016, §3.3).
pub const ANCHOR_COS: [f64; 3] = [0.9530, 0.4050, -0.7527];

/// Which branch of the three-anchor fit produced a [`GwcFit`] (see the table in the module
/// docs), for table statistics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FitBranch {
    /// The fit passes through all three anchors.
    Exact,
    /// All samples are 0: the zero profile.
    Zero,
    /// All samples are equal and positive: α = f1, β = 0, c = 0.
    Uniform,
    /// The exact fit needs α < 0: α = 0, through the peak anchor (the larger of anchors 1 and
    /// 3) and anchor 2.
    AlphaClamped,
    /// The exact fit needs |c| > [`C_MAX_FIT`] or has no real c: |c| = C_MAX_FIT, through
    /// anchors 1 and 3.
    PeakClamped,
    /// The samples are more contrasted than any admissible GWC: α = 0, |c| = C_MAX_FIT, through
    /// the peak anchor only.
    PeakAndAlphaClamped,
    /// f2 lies outside the range of f1 and f3: it is moved to the nearer of the two first.
    NonMonotone,
}

/// Result of a three-anchor fit: an admissible profile and the branch taken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GwcFit {
    /// The fitted profile (α ≥ 0, β ≥ 0, |c| ≤ [`C_MAX_FIT`]).
    pub gwc: Gwc,
    /// How it was obtained.
    pub branch: FitBranch,
}

/// Fits a GWC profile to samples f_i = f(φ_i) at the report's anchors [`ANCHOR_COS`]
/// (Ferrier 2016, §3.3). See [`fit_anchors`].
pub fn fit_three_anchors(f1: f64, f2: f64, f3: f64) -> Result<GwcFit> {
    fit_anchors(ANCHOR_COS, [f1, f2, f3])
}

/// Fits a GWC profile to samples `f` = [f(φ1), f(φ2), f(φ3)] at anchors with cosines
/// `cos_phi` = [cos φ1, cos φ2, cos φ3], 1 ≥ cos φ1 > cos φ2 > cos φ3 ≥ −1, cos φ1 > 0 > cos φ3.
///
/// Closed form and fallbacks are derived in the module docs. Errors ([`crate::Error::OutOfRange`],
/// [`crate::Error::NotFinite`], [`crate::Error::Negative`]) if an anchor cosine is invalid, a sample is NaN,
/// infinite or negative, or the fitted α or β overflows (samples within a factor of about 10³
/// of `f64::MAX`). Never returns NaN.
pub fn fit_anchors(cos_phi: [f64; 3], f: [f64; 3]) -> Result<GwcFit> {
    let [x1, x2, x3] = cos_phi;
    // Strict bounds as closed ones: the floats next to 0, and next to the other anchors
    in_range("cos_phi1", x1, next_towards(0.0, 1.0), 1.0)?;
    in_range("cos_phi3", x3, -1.0, next_towards(0.0, -1.0))?;
    in_range("cos_phi2", x2, next_towards(x3, x1), next_towards(x1, x3))?;
    for (name, value) in ["f1", "f2", "f3"].into_iter().zip(f) {
        non_negative(name, value)?;
    }

    // Zero profile; then work in units of the largest sample (scale invariance, no overflow)
    let scale = f[0].max(f[1]).max(f[2]);
    if scale == 0.0 {
        return done(0.0, 0.0, 0.0, FitBranch::Zero);
    }
    let [g1, g2, g3] = f.map(|v| v / scale);
    if g1 == g2 && g2 == g3 {
        return done(f[0], 0.0, 0.0, FitBranch::Uniform);
    }
    if g1 == g3 {
        // Anchors 1 and 3 agree (to the precision of the largest sample) but anchor 2 does not:
        // no monotone profile, keep the constant
        return done(f[0].max(f[2]), 0.0, 0.0, FitBranch::NonMonotone);
    }

    // Orient towards the peak: peak anchor p, and t = side·w > 0 for a lobe on that side
    let forward = g1 > g3;
    let side = if forward { 1.0 } else { -1.0 };
    let (gp, xp) = if forward { (g1, x1) } else { (g3, x3) };
    let t_max = 2.0 * C_MAX_FIT / (1.0 + C_MAX_FIT * C_MAX_FIT);

    // A monotone profile cannot take f2 outside [min(f1, f3), max(f1, f3)]
    let g2c = g2.clamp(g1.min(g3), g1.max(g3));
    let label = |branch| {
        if g2c == g2 {
            branch
        } else {
            FitBranch::NonMonotone
        }
    };

    // α = 0 profiles (1/f linear in cos φ) through anchors 1 and 3, and through p and 2
    let den0 = g1 * x1 - g3 * x3;
    let w0 = (g1 - g3) / den0;
    let w_pair = (gp - g2c) / (gp * xp - g2c * x2);
    let (t0, t_pair) = (side * w0, side * w_pair);
    if t_pair < t0 {
        // The exact fit needs α < 0: α = 0 through the peak anchor and anchor 2
        let (t, branch) = if t_pair > t_max {
            (t_max, FitBranch::PeakAndAlphaClamped)
        } else {
            (t_pair.max(0.0), FitBranch::AlphaClamped)
        };
        let w = side * t;
        return done_w(0.0, gp * (1.0 - w * xp), w, t_max, scale, label(branch));
    }
    if t0 > t_max {
        // α ≥ 0 through anchors 1 and 3 needs |c| > C_MAX_FIT: α = 0 through the peak anchor
        let w = side * t_max;
        let branch = label(FitBranch::PeakAndAlphaClamped);
        return done_w(0.0, gp * (1.0 - w * xp), w, t_max, scale, branch);
    }

    // Exact w from K = (f1 − f2)/(f2 − f3), multiplied through by (f2 − f3)(x2 − x3)
    let (d12, d23) = (g1 - g2c, g2c - g3);
    let (c12, c23) = (x1 - x2, x2 - x3);
    let w_exact = (d12 * c23 - c12 * d23) / (d12 * c23 * x1 - c12 * d23 * x3);
    // t_exact ≥ t0 here up to rounding; beyond t_max the lobe is capped
    let t_exact = side * w_exact;
    let (t, branch) = if t_exact > t_max {
        (t_max, FitBranch::PeakClamped)
    } else {
        (t_exact.max(t0), FitBranch::Exact)
    };

    // α and D through anchors 1 and 3
    let w = side * t;
    let span = w * (x1 - x3);
    let alpha = den0 * (w - w0) / span;
    let d = (g1 - g3) * (1.0 - w * x1) * (1.0 - w * x3) / span;
    done_w(alpha, d, w, t_max, scale, label(branch))
}

/// Wraps (α, β, c) in a fit result.
fn done(alpha: f64, beta: f64, c: f64, branch: FitBranch) -> Result<GwcFit> {
    Ok(GwcFit {
        gwc: Gwc::new(alpha, beta, c)?,
        branch,
    })
}

/// Converts the normalised (α, D, w) to (α, β, c) in the samples' unit and wraps it; |w| at
/// `t_max` maps to exactly ±C_MAX_FIT.
fn done_w(alpha: f64, d: f64, w: f64, t_max: f64, scale: f64, branch: FitBranch) -> Result<GwcFit> {
    // c = w/(1 + √(1 − w²)), β = 2π·D·(1 + c²)/(1 − c²)
    let c = if w.abs() == t_max {
        C_MAX_FIT.copysign(w)
    } else {
        w / (1.0 + ((1.0 - w) * (1.0 + w)).sqrt())
    };
    let beta = TAU * d * (1.0 + c * c) / ((1.0 - c) * (1.0 + c));
    done(alpha * scale, beta * scale, c, branch)
}
