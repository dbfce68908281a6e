//! Two wrapped Cauchy lobes over a floor: f(φ) = α + β₁·pdf_WC(φ; c₁) + β₂·pdf_WC(φ; c₂).
//!
//! Near index matching (η ≲ 1.3) and at grazing incidence the refracted beam runs just under
//! the surface, and PBD's azimuthal profile becomes a sharp forward peak over a broad forward
//! body. One lobe over a floor cannot follow both: at (η, ρ′, θ) = (1.2, 0.9, 89°) the best one
//! is 0.48–1.1 % off (mean over φ, weighted by the profile) at r from 0.01 to 10, the best two
//! 0.016–0.045 % (`cargo run --release -p bssrdf-zoo --example angular_families -- 1.2 0.9 89`). Tables store
//! the profile's harmonics, from which lookups rebuild the lobes ([`TwoLobe::from_moments`];
//! format-spec.md §10, `gwc-harmonics`).
//!
//! # Admissible profiles
//!
//! c₁, c₂ ∈ (−1, 1) and α signed, as one lobe's ([`super::floor_bound`]), down to where the
//! profile would dip below 0; β₁, β₂ ≥ 0, or one of them negative (a *signed pair*).
//!
//! **Lobes of one sign.** The minimum of a lobe is opposite its peak, β·(1 − |c|)/(2π(1 + |c|)),
//! and the minimum of the sum is at least the sum of the minima, so the profile is ≥ 0 at every
//! φ when
//!
//! 2πα + Σ βᵢ(1 − |cᵢ|)/(1 + |cᵢ|) ≥ 0, i.e. Σ βᵢ·2|cᵢ|/(1 + |cᵢ|) ≤ E/r = 2πα + β₁ + β₂
//!
//! (exact when both lobes peak on the same side, as PBD's do).
//!
//! **A signed pair**, a lobe less a broader one, is narrower in its flanks than any Cauchy lobe,
//! closer to a von Mises peak exp(κ cos φ). Lookups rebuild one where the harmonics they blend
//! ask for it ([`TwoLobe::from_moments`]). Its least value is not opposite the peak in general,
//! but it has a closed form: in x = cos φ each lobe is monotone and the derivative of the sum
//! vanishes at most once (`lobes_minimum`), so the profile is ≥ 0 when E/r ≥ −2π·min over φ of
//! Σ βᵢ(pdf_WC(φ; cᵢ) − 1/2π).
//!
//! Either way, [`TwoLobe::from_table`] scales both lobes down by one factor where an
//! interpolated cell breaks the condition, keeping E/r and the shapes, as [`super::cap_lobe`]
//! does for one lobe.
//!
//! # Sampling
//!
//! **Lobes of one sign.** A signed floor is not a density of its own, so the sampler draws from
//! the mixture of the profile's non-negative parts, max(2πα, 0)/2π + β₁·pdf_WC(c₁) +
//! β₂·pdf_WC(c₂), normalised: the profile itself wherever α ≥ 0, and where α < 0 a density at
//! least (2πα + β₁ + β₂)/(β₁ + β₂) times the normalised profile (as one lobe's
//! `Gwc::normalised` does), so a renderer's weight S/pdf grows by at most the inverse of that.
//!
//! **A signed pair** is drawn from the profile itself, f/(E/r): the mixture of its parts with
//! weights (2πα, β₁, β₂)/(E/r), one negative, whose distribution function is monotone because
//! the profile is ≥ 0.
//!
//! [`TwoLobe::pdf`] is that density exactly. The draw inverts its distribution function by
//! Newton steps inside a bisection bracket, so [`TwoLobe::cdf`] undoes it.
//!

use std::f64::consts::{PI, TAU};

use super::{cdf_wc, clamp_c, inv_cdf_wc};

/// Largest concentration the two-lobe fit uses (`bssrdf_zoo::gwc::fit_two_lobes`): at (η, ρ′, θ) = (1, 0.9, 89°) PBD's sharp lobe has
/// c ≈ 0.982 at small r.
pub const C_MAX_TWO_LOBES: f64 = 0.999;

/// A profile with two lobes (see the module docs). Invariants: β₁, β₂ finite, both ≥ 0 or one
/// negative (a signed pair), c₁, c₂ within [−[`C_LIMIT`](super::C_LIMIT), `C_LIMIT`], the
/// profile ≥ 0 at every φ (to rounding).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoLobe {
    alpha: f64,
    beta: [f64; 2],
    c: [f64; 2],
}

impl TwoLobe {
    /// The profile α + β₁·pdf_WC(c₁) + β₂·pdf_WC(c₂) as given, or `None` where it breaks the
    /// invariants: a value not finite, |c| > [`C_LIMIT`](super::C_LIMIT), or the profile below 0
    /// somewhere by more than 10⁻¹² of its scale (module docs, "Admissible profiles"; so two
    /// negative lobes only with a floor that lifts them, which no table gives).
    pub fn new(alpha: f64, beta: [f64; 2], c: [f64; 2]) -> Option<Self> {
        let finite = alpha.is_finite() && beta.iter().chain(&c).all(|v| v.is_finite());
        if !finite || c.iter().any(|&c| c.abs() > super::C_LIMIT) {
            return None;
        }
        let scale = (TAU * alpha).abs() + beta[0].abs() + beta[1].abs();
        // 2π times the profile's least value
        let minimum = TAU * alpha + beta[0] + beta[1] - lobes_need(beta, c);
        (minimum >= -1e-12 * scale).then_some(Self { alpha, beta, c })
    }

    /// The profile of a table cell: E/r = 2πα + β₁ + β₂ and the lobes (β, c), with c clamped
    /// as in [`pdf_wc`](super::pdf_wc), β NaN taken as 0, no lobe where neither β is positive,
    /// E/r negative or not finite as 0, and both β scaled by one factor where the profile would
    /// dip below 0 (module docs). One negative β beside a positive one is kept: a signed pair.
    pub fn from_table(e_per_r: f64, beta: [f64; 2], c: [f64; 2]) -> Self {
        let c = c.map(clamp_c);
        let mut beta = beta.map(|b| if b.is_finite() { b } else { 0.0 });
        if beta[0] <= 0.0 && beta[1] <= 0.0 {
            beta = [0.0; 2];
        }
        let e_per_r = if e_per_r.is_finite() {
            e_per_r.max(0.0)
        } else {
            0.0
        };
        let need = lobes_need(beta, c);
        if need > e_per_r {
            let k = e_per_r / need;
            beta = beta.map(|b| b * k);
        }
        Self {
            alpha: (e_per_r - beta[0] - beta[1]) / TAU,
            beta,
            c,
        }
    }

    /// The profile whose floor and lobes match E/r = 2πα + β₁ + β₂ and the first four
    /// harmonics μₙ = ∫ f(φ) cos nφ dφ = β₁c₁ⁿ + β₂c₂ⁿ, n = 1 … 4 (`m`), which tables
    /// interpolate instead of the lobes' parameters (`table::lookup`). Prony's
    /// method: c₁ and c₂ are the roots of z² − pz + q with μₙ₊₂ = pμₙ₊₁ − qμₙ (n = 1, 2),
    /// clamped into [[`C_MIN_SECOND_LOBE`], [`C_MAX_TWO_LOBES`]] (c₁ only from above), and β₁, β₂
    /// solve μ₁ and μ₂ for them. Where that has no admissible answer (the Hankel determinant
    /// μ₁μ₃ − μ₂² vanishing relative to μ₂², complex roots, c₁ above [`C_MAX_TWO_LOBES`],
    /// clamped roots that meet, β₁ ≤ 0, β₂ < 0 for clamped roots), the limit of a signed pair
    /// whose roots merge, from the first three harmonics ([`Rebuild::MergedRoots`]), where it is
    /// one; else the one lobe of the first two harmonics: c = μ₂/μ₁, β = μ₁/c. Then as
    /// [`TwoLobe::from_table`]. β₂ < 0 is a signed pair (module docs).
    pub fn from_moments(e_per_r: f64, m: [f64; 4]) -> Self {
        Self::from_moments_capped(e_per_r, m, C_MAX_TWO_LOBES, Rebuild::MergedRoots)
    }

    /// [`TwoLobe::from_moments`] with the sharper lobe's concentration at most `cap` (clamped
    /// as to [`C_MAX_TWO_LOBES`]), by the table's `rebuild`: lookups pass the sharpest lobe of
    /// the nodes they blend (`table::node_sharpness`).
    pub fn from_moments_capped(e_per_r: f64, m: [f64; 4], cap: f64, rebuild: Rebuild) -> Self {
        if let Some((beta, c)) = prony(m, e_per_r, cap, rebuild) {
            return Self::from_table(e_per_r, beta, c);
        }
        let (beta, c) = one_lobe_of(m[0], m[1]);
        Self::from_table(e_per_r, [beta, 0.0], [c, c])
    }

    /// The harmonics μₙ = β₁c₁ⁿ + β₂c₂ⁿ, n = 1 … 4 ([`TwoLobe::from_moments`]).
    pub fn harmonics(&self) -> [f64; 4] {
        std::array::from_fn(|n| {
            let n = n as i32 + 1;
            self.beta[0] * self.c[0].powi(n) + self.beta[1] * self.c[1].powi(n)
        })
    }

    /// The floor α (signed).
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The lobes' masses (β₁, β₂).
    pub fn beta(&self) -> [f64; 2] {
        self.beta
    }

    /// The lobes' concentrations (c₁, c₂).
    pub fn c(&self) -> [f64; 2] {
        self.c
    }

    /// ∫ f dφ = 2πα + β₁ + β₂.
    pub fn integral(&self) -> f64 {
        TAU * self.alpha + self.beta[0] + self.beta[1]
    }

    /// f(φ), ≥ 0; 0 for φ outside [−π, π] or NaN.
    pub fn eval(&self, phi: f64) -> f64 {
        if !super::in_domain(phi) {
            return 0.0;
        }
        let [l1, l2] = self.lobes_at(phi);
        (self.alpha + self.beta[0] * l1 + self.beta[1] * l2).max(0.0)
    }

    /// pdf_WC(φ; c₁) and pdf_WC(φ; c₂) at φ ∈ [−π, π] ([`pdf_wc`](super::pdf_wc)'s values),
    /// from one half-angle.
    fn lobes_at(&self, phi: f64) -> [f64; 2] {
        let (s, co) = super::half_angle(phi);
        self.c.map(|c| super::pdf_wc_half(s, co, clamp_c(c)))
    }

    /// Weights of the sampler's mixture (floor, lobe 1, lobe 2), summing to 1: the uniform
    /// density alone for the zero profile. For lobes of one sign, the profile's non-negative
    /// parts; for a signed pair, the profile itself, (2πα, β₁, β₂)/(E/r), with a negative
    /// weight (module docs, "Sampling").
    fn mixture(&self) -> [f64; 3] {
        let parts = if self.is_signed() {
            [TAU * self.alpha, self.beta[0], self.beta[1]]
        } else {
            [(TAU * self.alpha).max(0.0), self.beta[0], self.beta[1]]
        };
        let total: f64 = parts.iter().sum();
        if total > 0.0 && total.is_finite() {
            parts.map(|p| p / total)
        } else {
            [1.0, 0.0, 0.0]
        }
    }

    /// Whether one lobe is negative (a signed pair, module docs).
    pub fn is_signed(&self) -> bool {
        self.beta[0] < 0.0 || self.beta[1] < 0.0
    }

    /// Density of [`TwoLobe::sample`] in rad⁻¹ (module docs); 0 outside [−π, π] or NaN.
    pub fn pdf(&self, phi: f64) -> f64 {
        if !super::in_domain(phi) {
            return 0.0;
        }
        let [p0, p1, p2] = self.mixture();
        let [l1, l2] = self.lobes_at(phi);
        p0 / TAU + p1 * l1 + p2 * l2
    }

    /// Distribution function of [`TwoLobe::pdf`] from −π: 0 at −π (and below, or NaN), 1 at π.
    pub fn cdf(&self, phi: f64) -> f64 {
        if phi.is_nan() || phi <= -PI {
            return 0.0;
        }
        if phi >= PI {
            return 1.0;
        }
        let [p0, p1, p2] = self.mixture();
        (p0 * (phi + PI) / TAU + p1 * cdf_wc(phi, self.c[0]) + p2 * cdf_wc(phi, self.c[1]))
            .clamp(0.0, 1.0)
    }

    /// φ ∈ [−π, π] with [`TwoLobe::cdf`] = u (u clamped into [0, 1], NaN → 0), and
    /// [`TwoLobe::pdf`] there.
    ///
    /// Starts from the inverse of the heaviest part alone; Newton steps on cdf(φ) − u, each
    /// kept inside a bracket that every step shrinks (bisection when a step would leave it),
    /// until the residual is at most [`super::SAMPLE_U_TOL`] or the bracket is down to
    /// adjacent floats (at most 200 steps).
    pub fn sample_with_pdf(&self, u: f64) -> (f64, f64) {
        let u = super::unit_interval(u);
        let weights = self.mixture();
        let heaviest = (0..3).fold(0, |m, k| if weights[k] > weights[m] { k } else { m });
        // (A signed pair's positive lobe may weigh more than 1, its weights summing to 1 with
        // one negative: never one part alone)
        if weights[heaviest] >= 1.0 && !self.is_signed() {
            // One part alone: invert it directly
            let phi = match heaviest {
                0 => super::uniform_azimuth(u),
                k => inv_cdf_wc(u, self.c[k - 1]),
            };
            return (phi, self.pdf(phi));
        }
        let mut phi = match heaviest {
            0 => super::uniform_azimuth(u),
            k => inv_cdf_wc(u, self.c[k - 1]),
        };
        let (mut lo, mut hi) = (-PI, PI);
        for _ in 0..200 {
            let (cdf, p) = self.cdf_and_pdf(phi, weights);
            let f = cdf - u;
            if f.abs() <= super::SAMPLE_U_TOL {
                break;
            }
            if f > 0.0 {
                hi = phi;
            } else {
                lo = phi;
            }
            if super::next_towards(lo, hi) >= hi {
                break;
            }
            let step = phi - f / p;
            phi = if p > 0.0 && step > lo && step < hi {
                step
            } else {
                0.5 * (lo + hi)
            };
        }
        (phi, self.pdf(phi))
    }

    /// [`TwoLobe::cdf`] and [`TwoLobe::pdf`] at φ ∈ [−π, π] with the mixture's `weights`,
    /// from one half-angle per lobe.
    fn cdf_and_pdf(&self, phi: f64, weights: [f64; 3]) -> (f64, f64) {
        let (s, co) = super::half_angle(phi);
        let (mut cdf, mut pdf) = (weights[0] * (phi + PI) / TAU, weights[0] / TAU);
        for (&w, &c) in weights[1..].iter().zip(&self.c) {
            if w != 0.0 {
                let c = clamp_c(c);
                let tail = super::tail_wc(s, co, c);
                cdf += w * if phi >= 0.0 { 1.0 - tail } else { tail };
                pdf += w * super::pdf_wc_half(s, co, c);
            }
        }
        (cdf.clamp(0.0, 1.0), pdf)
    }

    /// [`TwoLobe::sample_with_pdf`]'s φ.
    pub fn sample(&self, u: f64) -> f64 {
        self.sample_with_pdf(u).0
    }
}

/// How the lookups of a two-lobe table rebuild its lobes from the harmonics they blend
/// (format-spec.md §10 step 4): a table's files say which (required feature bit 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Rebuild {
    /// Formats 1.2 and 1.3: the lobes of Prony's roots, else one lobe.
    Roots,
    /// Format 1.4, required feature bit 4 (`merged-roots`): the lobes of Prony's roots, else
    /// the limit of a signed pair whose roots merge (format-spec.md §10 step 4b), else one
    /// lobe. What this crate bakes.
    #[default]
    MergedRoots,
}

impl Rebuild {
    /// The rule's name in reports: `roots` or `merged-roots` (the feature bit's name).
    pub fn name(self) -> &'static str {
        match self {
            Rebuild::Roots => "roots",
            Rebuild::MergedRoots => "merged-roots",
        }
    }
}

/// The lobes (β, c) with harmonics (μ₁ … μ₄), by Prony's method ([`TwoLobe::from_moments`]),
/// `None` where they are not two admissible lobes. `energy`: the profile's E/r in the units of
/// `m`, which sets what counts as a signed pair whose roots have merged ([`merged_roots`]).
fn prony(m: [f64; 4], energy: f64, cap: f64, rebuild: Rebuild) -> Option<([f64; 2], [f64; 2])> {
    let [m1, m2, m3, m4] = m;
    let det = m1 * m3 - m2 * m2;
    // (NaN harmonics fail here too)
    if det.is_nan() || det.abs() <= 1e-9 * m2 * m2 {
        return None;
    }
    let p = (m1 * m4 - m2 * m3) / det;
    let q = (m2 * m4 - m3 * m3) / det;
    let disc = p * p - 4.0 * q;
    // Two lobes of the four harmonics where they are admissible, else the limit of a signed
    // pair of the first three ([`merged_roots`])
    let roots = (disc > 0.0).then(|| {
        // The larger root without cancellation, the smaller from the product q
        let c1 = 0.5 * (p + p.signum() * disc.sqrt());
        let c2 = if c1 != 0.0 { q / c1 } else { 0.0 };
        if c1 >= c2 {
            (c1, c2)
        } else {
            (c2, c1)
        }
    });
    let merged = || match rebuild {
        Rebuild::Roots => None,
        Rebuild::MergedRoots => lobes_of(m, merged_roots(m, det, energy)?, cap),
    };
    roots
        .and_then(|roots| lobes_of(m, roots, cap))
        .or_else(merged)
}

/// The lobes (β, c) of [`prony`] with the roots (c₁ ≥ c₂) it found: `None` where they are not
/// two admissible lobes.
fn lobes_of(m: [f64; 4], (c1, c2): (f64, f64), cap: f64) -> Option<([f64; 2], [f64; 2])> {
    let [m1, m2, ..] = m;
    // Roots outside [C_MIN_SECOND_LOBE, C_MAX_TWO_LOBES] are clamped into it and the masses
    // solved for the clamped pair: the same lobes where the roots lie inside, and continuous
    // across its edges. (Falling back to the one lobe of μ₁, μ₂ where c₂ crossed 0 jumped the
    // profile by 0.1–0.3 % between neighbouring lookups; as c₂ → 0 the exact lobes need
    // β₂ → ∞ against a floor → −∞, their limit a cos φ term.)
    if c1 > C_MAX_TWO_LOBES {
        // Sharper than any fit: no node's lobe but an artefact of blending harmonics of nearly
        // one lobe, whose second root is ill-determined. Clamped to C_MAX_TWO_LOBES, it put a
        // lobe of a few thousandths of the mass there, a spike at φ = 0 of 2.2 times the
        // profile at η = 1.01, ρ′ = 0.5, θ = 75°, r = 5.63 (`examples/worst_points`).
        return None;
    }
    let clamped = (
        c1.min(C_MAX_TWO_LOBES.min(cap)),
        c2.clamp(C_MIN_SECOND_LOBE, C_MAX_TWO_LOBES),
    );
    let (c1, c2, inside) = (clamped.0, clamped.1, clamped == (c1, c2));
    if c1 <= c2 {
        return None;
    }
    let b1 = (m2 - m1 * c2) / (c1 * (c1 - c2));
    let b2 = (m1 * c1 - m2) / (c2 * (c1 - c2));
    // The broader lobe may be negative (a signed pair: the sharper one narrowed towards a
    // von Mises-like peak; `from_table` keeps the profile ≥ 0) where the roots are the
    // harmonics' own; masses solved for clamped roots must both be ≥ 0, as before the clamp
    // the pair matched no harmonics of its own.
    let signs = b1 > 0.0 && (b2 >= 0.0 || inside);
    (signs && b1.is_finite() && b2.is_finite()).then_some(([b1, b2], [c1, c2]))
}

/// How far a signed pair's third harmonic must depart from that of the one lobe of its first
/// two, relative to E/r, for the merged pair of [`Rebuild::MergedRoots`] (format-spec.md §10
/// step 4b): the departure at which a node counts as a signed pair (`table::SIGNED_DEPARTURE`).
/// One lobe's harmonics rounded to f32 depart by at most about 1.5·10⁻⁷ of E/r, where Prony's
/// roots are noise.
pub const MERGED_DEPARTURE: f64 = 1e-4;

/// Half the gap between the two lobes of a merged pair ([`Rebuild::MergedRoots`]), relative to
/// the merged lobe's width 1 − c: the pair then departs from the limit by about MERGED_SPLIT² of
/// the profile, and its masses are about 1/MERGED_SPLIT times its lobe part, which they cancel
/// down to it.
pub const MERGED_SPLIT: f64 = 1e-3;

/// The roots c₁ > c₂ of a signed pair whose roots have merged, for harmonics whose roots by
/// Prony's method give no admissible lobes ([`prony`]; `det` = μ₁μ₃ − μ₂²). Blending the
/// harmonics of signed pairs whose roots lie close together, as PBD's do in far tails near
/// grazing incidence, gives such harmonics, where [`Rebuild::Roots`] reads the one lobe of μ₁
/// and μ₂: on the default table at η = 1.1 its largest error between nodes is 17 % against
/// PBD, this pair's 6.8 % (`examples/rebuild_rules`, docs/accuracy.md).
///
/// The limit of a signed pair as its roots merge at c is a lobe and its derivative in c,
/// μₙ = βcⁿ + γncⁿ⁻¹, for which det = −γ²c² < 0: μ₃ departs from the one lobe of μ₁ and μ₂
/// (μ₂²/μ₁) by −det/μ₁. Its first three harmonics put c at a root of μ₁z² − 2μ₂z + μ₃ = 0,
/// z = (μ₂ ± √−det)/μ₁, with γ = (μ₂ − cμ₁)/c: the smaller root, whose γ > 0 (for c > 0)
/// sharpens the lobe, as a signed pair's negative broader lobe does (the larger would broaden
/// it, a sharper negative lobe, which step 4 refuses). Where the harmonics are those of such a
/// limit, p/2 is that root, so the profile is continuous where the two roots of Prony's method
/// merge.
///
/// `None` where det ≥ 0 (no signed pair), μ₁ ≤ 0, or the departure is at most the allowance
/// a = [`MERGED_DEPARTURE`]·`energy` (E/r), that is −det ≤ A = a·μ₁. From A to 4A, s = √−det
/// (which grows with γ) is replaced by 2(√−det − √A), which rises from 0 to s there at twice
/// its rate, so that the pair meets the one lobe where the departure falls to a instead of
/// jumping to it. The pair c ± [`MERGED_SPLIT`]·(1 − c) with masses solved for μ₁ and μ₂
/// stands for the limit.
fn merged_roots(m: [f64; 4], det: f64, energy: f64) -> Option<(f64, f64)> {
    let [m1, m2, ..] = m;
    let allowance = MERGED_DEPARTURE * m1 * energy;
    if !(det < 0.0 && m1 > 0.0 && -det > allowance) {
        return None;
    }
    let s = (-det).sqrt();
    let s = if -det >= 4.0 * allowance {
        s
    } else {
        2.0 * (s - allowance.sqrt())
    };
    let c = (m2 - s) / m1;
    let split = MERGED_SPLIT * (1.0 - c);
    Some((c + split, c - split))
}

/// The energy E/r the lobes (β, c) need for the profile to be ≥ 0 at every φ: −2π times the
/// least value of their part Σ βᵢ(pdf_WC(φ; cᵢ) − 1/2π) (module docs, "Admissible profiles").
/// For lobes of one sign Σ βᵢ·2|cᵢ|/(1 + |cᵢ|), their minima opposite their peaks.
fn lobes_need(beta: [f64; 2], c: [f64; 2]) -> f64 {
    if beta.iter().any(|&b| b < 0.0) {
        -TAU * lobes_minimum(beta, c)
    } else {
        (0..2)
            .map(|i| {
                let a = c[i].abs();
                beta[i] * 2.0 * a / (1.0 + a)
            })
            .sum()
    }
}

/// The least value over φ of the lobes' part Σ βᵢ(pdf_WC(φ; cᵢ) − 1/2π) (zero mean), for any
/// signs of β and c. In x = cos φ each lobe is monotone, (1 − c²)/(2π(1 + c² − 2cx)), and the
/// derivative of the sum, Σ βᵢcᵢ(1 − cᵢ²)/(π(1 + cᵢ² − 2cᵢx)²), vanishes where
/// D₂ = √K·D₁ with Dᵢ = 1 + cᵢ² − 2cᵢx and K = −β₂c₂(1 − c₂²)/(β₁c₁(1 − c₁²)) > 0: linear in
/// x, so at most once. The least value is at x = ±1 or there.
fn lobes_minimum(beta: [f64; 2], c: [f64; 2]) -> f64 {
    let at = |x: f64| -> f64 {
        (0..2)
            .map(|i| {
                let c = c[i];
                beta[i] * ((1.0 - c) * (1.0 + c) / (TAU * (1.0 + c * c - 2.0 * c * x)) - 1.0 / TAU)
            })
            .sum()
    };
    let mut least = at(1.0).min(at(-1.0));
    let a: [f64; 2] = std::array::from_fn(|i| beta[i] * c[i] * (1.0 - c[i]) * (1.0 + c[i]));
    if a[0] != 0.0 && -a[1] / a[0] > 0.0 {
        let k = (-a[1] / a[0]).sqrt();
        let denominator = 2.0 * (k * c[0] - c[1]);
        let x = (k * (1.0 + c[0] * c[0]) - (1.0 + c[1] * c[1])) / denominator;
        if x > -1.0 && x < 1.0 {
            least = least.min(at(x));
        }
    }
    least
}

/// The concentration of the sharper lobe of the profile with harmonics `m` and E/r = 1
/// ([`TwoLobe::from_moments_capped`] by `rebuild`), or of its one lobe where it has not two; 0
/// with none.
pub fn sharp_concentration(m: [f64; 4], rebuild: Rebuild) -> f64 {
    match prony(m, 1.0, C_MAX_TWO_LOBES, rebuild) {
        Some((_, c)) => c[0],
        None => one_lobe_of(m[0], m[1]).1,
    }
}

/// Whether the profile with harmonics `m` and energy E/r `energy` (in the units of `m`) is a
/// signed pair ([`TwoLobe::from_moments_capped`] by `rebuild`).
pub fn harmonics_are_signed(m: [f64; 4], energy: f64, rebuild: Rebuild) -> bool {
    prony(m, energy, C_MAX_TWO_LOBES, rebuild).is_some_and(|(beta, _)| beta[1] < 0.0)
}

/// The smallest concentration [`TwoLobe::from_moments`] gives the second lobe (see the clamp in
/// `prony`): its mass stays within about μ₁/0.05 = 20 μ₁.
pub const C_MIN_SECOND_LOBE: f64 = 0.05;

/// The one lobe (β, c) with harmonics μ₁ and μ₂: c = μ₂/μ₁, β = μ₁/c; no lobe (0, 0) where
/// μ₁ or μ₂ is not positive.
pub fn one_lobe_of(m1: f64, m2: f64) -> (f64, f64) {
    if m1 > 0.0 && m2 > 0.0 {
        let c = (m2 / m1).min(C_MAX_TWO_LOBES);
        (m1 / c, c)
    } else {
        (0.0, 0.0)
    }
}

// The fit's largest concentration is one evaluation represents as is.
const _: () = assert!(C_MAX_TWO_LOBES < super::C_LIMIT);
