//! The fit of two wrapped Cauchy lobes over a floor ([`TwoLobe`]) to PBD's azimuthal profile.
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

use super::{pdf_wc, TwoLobe, C_MAX_TWO_LOBES};

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
    fit_with(phi, y, hint, true)
}

/// [`fit`] with lobes of one sign only (β₁, β₂ ≥ 0).
pub fn fit_one_sign(phi: &[f64], y: &[f64], hint: Option<[f64; 2]>) -> Option<TwoLobe> {
    fit_with(phi, y, hint, false)
}

/// [`fit`], with signed pairs or without.
fn fit_with(phi: &[f64], y: &[f64], hint: Option<[f64; 2]>, signed: bool) -> Option<TwoLobe> {
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
        signed,
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
                    let cost = problem
                        .solve_columns([&columns[a], &columns[b]], [c_of(s1), c_of(s2)])
                        .0;
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
    let mut cost = problem
        .solve_columns([&lobes[0], &lobes[1]], [c_of(s[0]), c_of(s[1])])
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
                let c = problem.solve_columns(pair, [c_of(t[0]), c_of(t[1])]).0;
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
    let (alpha, beta) = (alpha * scale, [b1 * scale, b2 * scale]);
    // The constraints keep the profile ≥ 0 to rounding; `from_table` caps a larger dip.
    TwoLobe::new(alpha, beta, c).or_else(|| {
        Some(TwoLobe::from_table(
            TAU * alpha + beta[0] + beta[1],
            beta,
            c,
        ))
    })
}

/// The linear part of [`fit`]: azimuths (as 1 − cos φ), values scaled to a largest 1,
/// weights.
struct Problem<'a> {
    versine: &'a [f64],
    y: &'a [f64],
    w: &'a [f64],
    /// Whether signed pairs are candidates.
    signed: bool,
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
        self.solve_columns([&l1, &l2], c)
    }

    /// Σ w (m − y)² = cᵀGc − 2c·b + Σ w y² of the coefficients `coef`.
    fn cost(&self, g: &[[f64; 3]; 3], b: &[f64; 3], yy: f64, coef: [f64; 3]) -> f64 {
        let quad: f64 = (0..3)
            .map(|i| coef[i] * (0..3).map(|j| g[i][j] * coef[j]).sum::<f64>())
            .sum();
        let lin: f64 = (0..3).map(|i| coef[i] * b[i]).sum();
        (quad - 2.0 * lin + yy).max(0.0)
    }

    /// [`Problem::solve`] from the lobes' values at the azimuths and at π.
    fn solve_columns(&self, lobes: [&[f64]; 2], c: [f64; 2]) -> (f64, [f64; 3]) {
        let lobes_at_pi = c.map(|c| pdf_wc(PI, c));
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
        // The best pair of lobes of one sign, and the best signed pair
        let (mut best, mut signed) = ((f64::INFINITY, [0.0; 3]), (f64::INFINITY, [0.0; 3]));
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
            // β₁ ≥ 0; β₂ ≥ 0 with f(π) ≥ 0 (where both lobes have their minimum), or β₂ < 0 (a
            // signed pair, the broader lobe negative) with the profile ≥ 0 at every φ
            if coef[1] < 0.0 {
                continue;
            }
            let cost = self.cost(&g, &b, yy, coef);
            if coef[2] < 0.0 {
                if self.signed
                    && cost < signed.0
                    && TwoLobe::new(coef[0], [coef[1], coef[2]], c).is_some()
                {
                    signed = (cost, coef);
                }
                continue;
            }
            let floor: f64 = (0..3).map(|i| coef[i] * at_pi[i]).sum();
            if floor < -1e-12 * (coef[0].abs() + coef[1] + coef[2]) {
                continue;
            }
            if index == 0 {
                // The free least-squares solution is admissible: the problem is convex, so it
                // is the constrained optimum too
                return (cost, coef);
            }
            if cost < best.0 {
                best = (cost, coef);
            }
        }
        if signed.0 < best.0 {
            signed
        } else {
            best
        }
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
