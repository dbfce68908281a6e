//! Two wrapped Cauchy lobes over a floor: f(φ) = α + β₁·pdf_WC(φ; c₁) + β₂·pdf_WC(φ; c₂).
//!
//! Near index matching (η ≲ 1.3) and at grazing incidence the refracted beam runs just under
//! the surface, and PBD's azimuthal profile becomes a sharp forward peak over a broad forward
//! body. One lobe over a floor cannot follow both: at (η, ρ′, θ) = (1.2, 0.9, 89°) the best one
//! is 0.48–1.1 % off (mean over φ, weighted by the profile) at r from 0.01 to 10, the best two
//! 0.016–0.045 % (`cargo run --release --example angular_families -- 1.2 0.9 89`). Tables store
//! the profile's harmonics, from which lookups rebuild the lobes ([`TwoLobe::from_moments`];
//! format-spec.md §10, `gwc-harmonics`).
//!
//! # Admissible profiles
//!
//! β₁, β₂ ≥ 0, c₁, c₂ ∈ (−1, 1) and α signed, as one lobe's ([`super::floor_bound`]), down to
//! where the profile would dip below 0. The minimum of a lobe is opposite its peak,
//! β·(1 − |c|)/(2π(1 + |c|)), and the minimum of the sum is at least the sum of the minima, so
//! the profile is ≥ 0 at every φ when
//!
//! 2πα + Σ βᵢ(1 − |cᵢ|)/(1 + |cᵢ|) ≥ 0, i.e. Σ βᵢ·2|cᵢ|/(1 + |cᵢ|) ≤ E/r = 2πα + β₁ + β₂
//!
//! (exact when both lobes peak on the same side, as PBD's do). [`TwoLobe::from_table`] scales
//! both lobes down by one factor where an interpolated cell breaks it, keeping E/r and the
//! shapes, as [`super::cap_lobe`] does for one lobe.
//!
//! # Sampling
//!
//! A signed floor is not a density of its own, so the sampler draws from the mixture of the
//! profile's non-negative parts, max(2πα, 0)/2π + β₁·pdf_WC(c₁) + β₂·pdf_WC(c₂), normalised:
//! the profile itself wherever α ≥ 0, and where α < 0 a density at least (2πα + β₁ + β₂)/(β₁ + β₂)
//! times the normalised profile (as one lobe's `Gwc::normalised` does), so a renderer's weight
//! S/pdf grows by at most the inverse of that. [`TwoLobe::pdf`] is that density
//! exactly. The draw inverts the mixture's distribution function (monotone, since every part
//! is ≥ 0) by Newton steps inside a bisection bracket, so [`TwoLobe::cdf`] undoes it.
//!
//! # The fit
//!
//! [`fit`] takes PBD at azimuths in [0, π] and finds the profile of smallest weighted squared
//! relative error, Σ wₖ (f(φₖ)/yₖ − 1)² with wₖ = yₖ·Δφₖ: the error of the points a renderer
//! draws in proportion to the profile. For fixed (c₁, c₂) the profile is linear in (α, β₁, β₂),
//! solved by least squares with β ≥ 0 and the profile ≥ 0 at φ = π (where both lobes of
//! c ≥ 0 have their minimum) as active constraints; (c₁, c₂) is searched on a grid uniform in
//! s = −ln(1 − c) and refined by coordinate steps. Lobe 1 is the sharper (c₁ ≥ c₂ ≥ 0): PBD
//! peaks forward, and labelling the lobes by sharpness keeps their parameters continuous from
//! node to node wherever the two concentrations stay apart.

use std::f64::consts::{PI, TAU};

use super::{cdf_wc, clamp_c, inv_cdf_wc, pdf_wc};

/// Largest concentration [`fit`] uses: at (η, ρ′, θ) = (1, 0.9, 89°) PBD's sharp lobe has
/// c ≈ 0.982 at small r.
pub const C_MAX_TWO_LOBES: f64 = 0.999;

/// A profile with two lobes (see the module docs). Invariants: β₁, β₂ ≥ 0 and finite, c₁, c₂
/// within [−[`C_LIMIT`](super::C_LIMIT), `C_LIMIT`], the profile ≥ 0 at every φ (to rounding).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoLobe {
    alpha: f64,
    beta: [f64; 2],
    c: [f64; 2],
}

impl TwoLobe {
    /// The profile of a table cell: E/r = 2πα + β₁ + β₂ and the lobes (β, c), with c clamped
    /// as in [`pdf_wc`], β NaN or negative taken as 0, E/r negative or not finite as 0, and
    /// both β scaled by one factor where the profile would dip below 0 (module docs).
    pub fn from_table(e_per_r: f64, beta: [f64; 2], c: [f64; 2]) -> Self {
        let c = c.map(clamp_c);
        let mut beta = beta.map(|b| if b.is_finite() { b.max(0.0) } else { 0.0 });
        let e_per_r = if e_per_r.is_finite() {
            e_per_r.max(0.0)
        } else {
            0.0
        };
        let need: f64 = (0..2)
            .map(|i| {
                let a = c[i].abs();
                beta[i] * 2.0 * a / (1.0 + a)
            })
            .sum();
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
    /// μ₁μ₃ − μ₂² vanishing relative to μ₂², complex roots, clamped roots that meet, a negative
    /// mass), the one lobe of the first two harmonics: c = μ₂/μ₁, β = μ₁/c. Then as
    /// [`TwoLobe::from_table`].
    pub fn from_moments(e_per_r: f64, m: [f64; 4]) -> Self {
        let [m1, m2, m3, m4] = m;
        if let Some((beta, c)) = prony(m1, m2, m3, m4) {
            return Self::from_table(e_per_r, beta, c);
        }
        let (beta, c) = one_lobe_of(m1, m2);
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
        (self.alpha + self.beta[0] * pdf_wc(phi, self.c[0]) + self.beta[1] * pdf_wc(phi, self.c[1]))
            .max(0.0)
    }

    /// Weights of the sampler's mixture (floor, lobe 1, lobe 2), summing to 1: the uniform
    /// density alone for the zero profile.
    fn mixture(&self) -> [f64; 3] {
        let parts = [(TAU * self.alpha).max(0.0), self.beta[0], self.beta[1]];
        let total: f64 = parts.iter().sum();
        if total > 0.0 && total.is_finite() {
            parts.map(|p| p / total)
        } else {
            [1.0, 0.0, 0.0]
        }
    }

    /// Density of [`TwoLobe::sample`] in rad⁻¹ (module docs); 0 outside [−π, π] or NaN.
    pub fn pdf(&self, phi: f64) -> f64 {
        if !super::in_domain(phi) {
            return 0.0;
        }
        let [p0, p1, p2] = self.mixture();
        p0 / TAU + p1 * pdf_wc(phi, self.c[0]) + p2 * pdf_wc(phi, self.c[1])
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
        if weights[heaviest] >= 1.0 {
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
            if w > 0.0 {
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

/// The lobes (β, c) with harmonics (μ₁ … μ₄), by Prony's method ([`TwoLobe::from_moments`]),
/// `None` where they are not two admissible lobes.
fn prony(m1: f64, m2: f64, m3: f64, m4: f64) -> Option<([f64; 2], [f64; 2])> {
    let det = m1 * m3 - m2 * m2;
    // (NaN harmonics fail here too)
    if det.is_nan() || det.abs() <= 1e-9 * m2 * m2 {
        return None;
    }
    let p = (m1 * m4 - m2 * m3) / det;
    let q = (m2 * m4 - m3 * m3) / det;
    let disc = p * p - 4.0 * q;
    if disc.is_nan() || disc <= 0.0 {
        return None;
    }
    // The larger root without cancellation, the smaller from the product q
    let c1 = 0.5 * (p + p.signum() * disc.sqrt());
    let c2 = if c1 != 0.0 { q / c1 } else { 0.0 };
    let (c1, c2) = if c1 >= c2 { (c1, c2) } else { (c2, c1) };
    // Roots outside [C_MIN_SECOND_LOBE, C_MAX_TWO_LOBES] are clamped into it and the masses
    // solved for the clamped pair: the same lobes where the roots lie inside, and continuous
    // across its edges. (Falling back to the one lobe of μ₁, μ₂ where c₂ crossed 0 jumped the
    // profile by 0.1–0.3 % between neighbouring lookups; as c₂ → 0 the exact lobes need
    // β₂ → ∞ against a floor → −∞, their limit a cos φ term.)
    let (c1, c2) = (
        c1.min(C_MAX_TWO_LOBES),
        c2.clamp(C_MIN_SECOND_LOBE, C_MAX_TWO_LOBES),
    );
    if c1 <= c2 {
        return None;
    }
    let b1 = (m2 - m1 * c2) / (c1 * (c1 - c2));
    let b2 = (m1 * c1 - m2) / (c2 * (c1 - c2));
    (b1 >= 0.0 && b2 >= 0.0 && b1.is_finite() && b2.is_finite()).then_some(([b1, b2], [c1, c2]))
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

/// Concentrations of the fit's grid: s = −ln(1 − c) from 0 in steps of [`GRID_STEP`] up to
/// that of [`C_MAX_TWO_LOBES`].
const GRID_STEP: f64 = 0.7;

/// The first step in s of [`fit`]'s refinement from a hint.
const HINT_STEP: f64 = 0.1;

/// The coordinate refinement of [`fit`] stops when its step in s is below this.
const REFINE_TOLERANCE: f64 = 1e-3;

/// The c of s = −ln(1 − c), capped at [`C_MAX_TWO_LOBES`].
fn c_of(s: f64) -> f64 {
    (-(-s).exp_m1()).clamp(0.0, C_MAX_TWO_LOBES)
}

/// The profile of least weighted squared relative error against PBD's values `y` at the
/// azimuths `phi` (in [0, π], increasing, at least 5 of them, the last π), with c₁ ≥ c₂ ≥ 0
/// (module docs). `None` where some value is not finite or negative, or none is positive (the
/// caller stores the zero profile).
pub fn fit(phi: &[f64], y: &[f64], hint: Option<[f64; 2]>) -> Option<TwoLobe> {
    let n = phi.len();
    if n < 5 || y.len() != n || y.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
        return None;
    }
    let scale = y.iter().copied().fold(0.0, f64::max);
    if scale <= 0.0 {
        return None;
    }
    // Weights of the squared relative error: Δφ (trapezoid) over y, the profile's own weight
    // y·Δφ divided by y² (a zero sample weighs nothing: the fit cannot be relative there)
    let w: Vec<f64> = (0..n)
        .map(|k| {
            let left = if k > 0 { phi[k] - phi[k - 1] } else { 0.0 };
            let right = if k + 1 < n { phi[k + 1] - phi[k] } else { 0.0 };
            let yk = y[k] / scale;
            if yk > 0.0 {
                0.5 * (left + right) / yk
            } else {
                0.0
            }
        })
        .collect();
    let y: Vec<f64> = y.iter().map(|v| v / scale).collect();
    // 1 − cos φ = 2 sin²(φ/2), without cancellation near φ = 0 where the sharp lobe is
    let versine: Vec<f64> = phi.iter().map(|&p| 2.0 * (0.5 * p).sin().powi(2)).collect();
    let problem = Problem {
        versine: &versine,
        y: &y,
        w: &w,
    };
    let s_max = -(1.0 - C_MAX_TWO_LOBES).ln();
    let s_of = |c: f64| -(1.0 - c.clamp(0.0, C_MAX_TWO_LOBES)).ln();
    let (mut s, mut step) = match hint {
        // From a neighbour's concentrations (the bake's previous radius): the optimum moves
        // little from node to node
        Some(c) => ([s_of(c[0]), s_of(c[1])], HINT_STEP),
        None => {
            let steps = (s_max / GRID_STEP).floor() as usize;
            let grid: Vec<f64> = (0..=steps).map(|k| k as f64 * GRID_STEP).collect();
            let columns: Vec<Vec<f64>> = grid.iter().map(|&s| problem.lobe(c_of(s))).collect();
            let mut best = (f64::INFINITY, [0.0, 0.0]);
            for (a, &s1) in grid.iter().enumerate() {
                for (b, &s2) in grid[..=a].iter().enumerate() {
                    let at_pi = [pdf_wc(PI, c_of(s1)), pdf_wc(PI, c_of(s2))];
                    let cost = problem.solve_columns([&columns[a], &columns[b]], at_pi).0;
                    if cost < best.0 {
                        best = (cost, [s1, s2]);
                    }
                }
            }
            (best.1, GRID_STEP)
        }
    };
    // Coordinate refinement: halving steps; only the moved lobe is recomputed
    let mut lobes = [problem.lobe(c_of(s[0])), problem.lobe(c_of(s[1]))];
    let at_pi = |s: f64| pdf_wc(PI, c_of(s));
    let mut cost = problem
        .solve_columns([&lobes[0], &lobes[1]], [at_pi(s[0]), at_pi(s[1])])
        .0;
    while step > REFINE_TOLERANCE {
        let mut moved = false;
        for axis in 0..2 {
            for dir in [-1.0, 1.0] {
                let mut t = s;
                t[axis] = (t[axis] + dir * step).clamp(0.0, s_max);
                if t[0] < t[1] || t == s {
                    continue;
                }
                let trial = problem.lobe(c_of(t[axis]));
                let pair: [&[f64]; 2] = if axis == 0 {
                    [&trial, &lobes[1]]
                } else {
                    [&lobes[0], &trial]
                };
                let c = problem.solve_columns(pair, [at_pi(t[0]), at_pi(t[1])]).0;
                if c < cost {
                    (cost, s, moved) = (c, t, true);
                    lobes[axis] = trial;
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    let c = [c_of(s[0]), c_of(s[1])];
    let (_, [alpha, b1, b2]) = problem.solve(c);
    Some(TwoLobe {
        alpha: alpha * scale,
        beta: [b1 * scale, b2 * scale],
        c,
    })
}

/// The linear part of [`fit`]: azimuths (as 1 − cos φ), values scaled to a largest 1,
/// weights.
struct Problem<'a> {
    versine: &'a [f64],
    y: &'a [f64],
    w: &'a [f64],
}

impl Problem<'_> {
    /// pdf_WC(φₖ; c) at the azimuths, c ∈ [0, 1): (1 − c²)/(2π((1 − c)² + 2c(1 − cos φ))).
    fn lobe(&self, c: f64) -> Vec<f64> {
        let (a, b) = ((1.0 - c) * (1.0 + c) / TAU, (1.0 - c) * (1.0 - c));
        self.versine
            .iter()
            .map(|&v| a / (b + 2.0 * c * v))
            .collect()
    }

    /// For concentrations `c`: the weighted squared relative error of the best (α, β₁, β₂)
    /// with β ≥ 0 and f(π) ≥ 0, and those coefficients. Tries the free solution, then each
    /// set of active constraints (a lobe left out, α pinned so that f(π) = 0), and keeps the
    /// best admissible one.
    fn solve(&self, c: [f64; 2]) -> (f64, [f64; 3]) {
        let (l1, l2) = (self.lobe(c[0]), self.lobe(c[1]));
        self.solve_columns([&l1, &l2], c.map(|c| pdf_wc(PI, c)))
    }

    /// [`Problem::solve`] from the lobes' values at the azimuths and at π.
    fn solve_columns(&self, lobes: [&[f64]; 2], lobes_at_pi: [f64; 2]) -> (f64, [f64; 3]) {
        // Gram matrix and right-hand side of the columns (1, pdf_WC(c₁), pdf_WC(c₂))
        let mut g = [[0.0; 3]; 3];
        let (mut b, mut yy) = ([0.0; 3], 0.0);
        for (k, (&y, &w)) in self.y.iter().zip(self.w).enumerate() {
            let col = [1.0, lobes[0][k], lobes[1][k]];
            for i in 0..3 {
                for j in 0..3 {
                    g[i][j] += w * col[i] * col[j];
                }
                b[i] += w * col[i] * y;
            }
            yy += w * y * y;
        }
        let at_pi = [1.0, lobes_at_pi[0], lobes_at_pi[1]];
        let mut best = (f64::INFINITY, [0.0; 3]);
        // Each candidate is a basis of combinations of the columns (rows of T): coefficients
        // x in that basis give the profile's (α, β₁, β₂) = Tᵀx
        let pinned = |i: usize| {
            let mut t = [0.0; 3];
            t[i] = 1.0;
            t[0] = -at_pi[i];
            t
        };
        let e = |i: usize| {
            let mut t = [0.0; 3];
            t[i] = 1.0;
            t
        };
        let candidates: [&[[f64; 3]]; 7] = [
            &[e(0), e(1), e(2)],
            &[e(0), e(1)],
            &[e(0), e(2)],
            &[e(0)],
            &[pinned(1), pinned(2)],
            &[pinned(1)],
            &[pinned(2)],
        ];
        for (index, t) in candidates.into_iter().enumerate() {
            let m = t.len();
            let mut a = [[0.0; 4]; 3];
            for p in 0..m {
                for q in 0..m {
                    a[p][q] = (0..3)
                        .map(|i| t[p][i] * (0..3).map(|j| g[i][j] * t[q][j]).sum::<f64>())
                        .sum();
                }
                a[p][3] = (0..3).map(|i| t[p][i] * b[i]).sum();
            }
            let Some(x) = solve_small(&mut a, m) else {
                continue;
            };
            let coef: [f64; 3] = std::array::from_fn(|i| (0..m).map(|p| x[p] * t[p][i]).sum());
            if coef[1] < 0.0 || coef[2] < 0.0 {
                continue;
            }
            let floor: f64 = (0..3).map(|i| coef[i] * at_pi[i]).sum();
            if floor < -1e-12 * (coef[0].abs() + coef[1] + coef[2]) {
                continue;
            }
            // Σ w (m − y)² = cᵀGc − 2c·b + Σ w y²
            let quad: f64 = (0..3)
                .map(|i| coef[i] * (0..3).map(|j| g[i][j] * coef[j]).sum::<f64>())
                .sum();
            let lin: f64 = (0..3).map(|i| coef[i] * b[i]).sum();
            let cost = (quad - 2.0 * lin + yy).max(0.0);
            if index == 0 {
                // The free least-squares solution is admissible: the problem is convex, so it
                // is the constrained optimum too
                return (cost, coef);
            }
            if cost < best.0 {
                best = (cost, coef);
            }
        }
        best
    }
}

/// Solves the m × m system whose augmented rows are `a` (m ≤ 3, right-hand side in column 3)
/// by Gaussian elimination with partial pivoting; `None` if singular.
fn solve_small(a: &mut [[f64; 4]; 3], m: usize) -> Option<[f64; 3]> {
    let scale = (0..m).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    for i in 0..m {
        let p = (i..m).max_by(|&x, &z| a[x][i].abs().total_cmp(&a[z][i].abs()))?;
        a.swap(i, p);
        let pivot = a[i][i];
        if pivot.is_nan() || pivot.abs() <= 1e-13 * scale {
            return None;
        }
        let row = a[i];
        for below in a.iter_mut().take(m).skip(i + 1) {
            let f = below[i] / pivot;
            for (x, &y) in below[i..].iter_mut().zip(&row[i..]) {
                *x -= f * y;
            }
        }
    }
    let mut x = [0.0; 3];
    for i in (0..m).rev() {
        let s: f64 = (i + 1..m).map(|j| a[i][j] * x[j]).sum();
        x[i] = (a[i][3] - s) / a[i][i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

// The fit's largest concentration is one evaluation represents as is.
const _: () = assert!(C_MAX_TWO_LOBES < super::C_LIMIT);
