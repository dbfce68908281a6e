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

use std::f64::consts::TAU;

use super::{TwoLobe, C_MAX_TWO_LOBES};

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
    let problem = Problem::new(&versine, &y, &w, signed);
    let s_max = -(1.0 - C_MAX_TWO_LOBES).ln();
    let s_of = |c: f64| -(1.0 - c.clamp(0.0, C_MAX_TWO_LOBES)).ln();
    let (mut s, mut step) = match hint {
        // From a neighbour's concentrations (the bake's previous radius): the optimum moves
        // little from node to node
        Some(c) => ([s_of(c[0]), s_of(c[1])], HINT_STEP),
        None => {
            let steps = (s_max / GRID_STEP).floor() as usize;
            let grid: Vec<f64> = (0..=steps).map(|k| k as f64 * GRID_STEP).collect();
            let columns: Vec<Column> = grid.iter().map(|&s| problem.lobe(c_of(s))).collect();
            let mut best = (f64::INFINITY, [0.0, 0.0]);
            for (a, &s1) in grid.iter().enumerate() {
                for (b, &s2) in grid[..=a].iter().enumerate() {
                    let cost = problem.solve_columns([&columns[a], &columns[b]]).0;
                    if cost < best.0 {
                        best = (cost, [s1, s2]);
                    }
                }
            }
            (best.1, GRID_STEP)
        }
    };
    // Coordinate refinement: halving steps; only the moved lobe is recomputed. Every point a
    // step has left costs more than the current one (the cost only falls), so the trial that
    // would return to the point just left is skipped: the same path, a fifth fewer solves.
    let mut lobes = [problem.lobe(c_of(s[0])), problem.lobe(c_of(s[1]))];
    let (mut cost, mut coef) = problem.solve_columns([&lobes[0], &lobes[1]]);
    let mut left = None;
    while step > REFINE_TOLERANCE {
        let mut moved = false;
        for axis in 0..2 {
            for dir in [-1.0, 1.0] {
                let mut t = s;
                t[axis] = (t[axis] + dir * step).clamp(0.0, s_max);
                if t[0] < t[1] || t == s || left == Some(t) {
                    continue;
                }
                let trial = problem.lobe(c_of(t[axis]));
                let pair = if axis == 0 {
                    [&trial, &lobes[1]]
                } else {
                    [&lobes[0], &trial]
                };
                let (c, x) = problem.solve_columns(pair);
                if c < cost {
                    left = Some(s);
                    (cost, coef, s, moved) = (c, x, t, true);
                    lobes[axis] = trial;
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    let c = [lobes[0].c, lobes[1].c];
    let [alpha, b1, b2] = coef;
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
/// weights, and the inner products of the floor's column (all ones) with itself and the values.
struct Problem<'a> {
    versine: &'a [f64],
    y: &'a [f64],
    w: &'a [f64],
    /// Σ w, Σ w·y and Σ (w·y)·y: the Gram entry, right-hand side and constant of the floor.
    weight: f64,
    data: f64,
    data_square: f64,
    /// Whether signed pairs are candidates.
    signed: bool,
}

/// A lobe's column of the least squares: its concentration, its values at the azimuths and at
/// π, and its inner products with the floor, itself and the values (Σ w·l, Σ (w·l)·l,
/// Σ (w·l)·y), which do not depend on the other lobe: a step of the refinement moves one lobe
/// and recomputes only the products of the two.
struct Column {
    c: f64,
    values: Vec<f64>,
    at_pi: f64,
    floor: f64,
    square: f64,
    data: f64,
}

impl<'a> Problem<'a> {
    fn new(versine: &'a [f64], y: &'a [f64], w: &'a [f64], signed: bool) -> Self {
        let (mut weight, mut data, mut data_square) = (0.0, 0.0, 0.0);
        for (&y, &w) in y.iter().zip(w) {
            weight += w;
            data += w * y;
            data_square += w * y * y;
        }
        Problem {
            versine,
            y,
            w,
            weight,
            data,
            data_square,
            signed,
        }
    }

    /// The column of pdf_WC(φₖ; c) at the azimuths, c ∈ [0, 1):
    /// (1 − c²)/(2π((1 − c)² + 2c(1 − cos φ))).
    fn lobe(&self, c: f64) -> Column {
        let (a, b) = ((1.0 - c) * (1.0 + c) / TAU, (1.0 - c) * (1.0 - c));
        let values: Vec<f64> = self
            .versine
            .iter()
            .map(|&v| a / (b + 2.0 * c * v))
            .collect();
        let (mut floor, mut square, mut data) = (0.0, 0.0, 0.0);
        for ((&l, &y), &w) in values.iter().zip(self.y).zip(self.w) {
            floor += w * l;
            square += w * l * l;
            data += w * l * y;
        }
        Column {
            c,
            values,
            // pdf_WC(π; c) by the columns' own formula (1 − cos π = 2); within an ulp or two
            // of `pdf_wc(π, c)`, not always its bits
            at_pi: a / (b + 4.0 * c),
            floor,
            square,
            data,
        }
    }

    /// Σ w (m − y)² = cᵀGc − 2c·b + Σ w y² of the coefficients `coef`.
    fn cost(&self, g: &[[f64; 3]; 3], b: &[f64; 3], yy: f64, coef: [f64; 3]) -> f64 {
        let quad: f64 = (0..3)
            .map(|i| coef[i] * (0..3).map(|j| g[i][j] * coef[j]).sum::<f64>())
            .sum();
        let lin: f64 = (0..3).map(|i| coef[i] * b[i]).sum();
        (quad - 2.0 * lin + yy).max(0.0)
    }

    /// For the lobes `l`: the weighted squared relative error of the best (α, β₁, β₂) with
    /// β ≥ 0 and f(π) ≥ 0, or a signed pair ≥ 0 everywhere, and those coefficients. Tries the
    /// free solution, then each set of active constraints (a lobe left out, α pinned so that
    /// f(π) = 0), and keeps the best admissible one.
    fn solve_columns(&self, l: [&Column; 2]) -> (f64, [f64; 3]) {
        self.solve_columns_with(l, true)
    }

    /// [`Problem::solve_columns`], leaving out the candidates a larger admissible one covers
    /// (`prune`) or trying them all (the tests hold the two to the same result).
    fn solve_columns_with(&self, l: [&Column; 2], prune: bool) -> (f64, [f64; 3]) {
        let c = [l[0].c, l[1].c];
        // Gram matrix and right-hand side of the columns (1, pdf_WC(c₁), pdf_WC(c₂)); of the
        // products of the two lobes both orders, each summed as (w·lᵢ)·lⱼ
        let (mut g12, mut g21) = (0.0, 0.0);
        for ((&a, &b), &w) in l[0].values.iter().zip(&l[1].values).zip(self.w) {
            g12 += w * a * b;
            g21 += w * b * a;
        }
        let g = [
            [self.weight, l[0].floor, l[1].floor],
            [l[0].floor, l[0].square, g12],
            [l[1].floor, g21, l[1].square],
        ];
        let (b, yy) = ([self.data, l[0].data, l[1].data], self.data_square);
        let at_pi = [1.0, l[0].at_pi, l[1].at_pi];
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
        // A candidate inside another's subspace ([α, β₁] inside [α, β₁, β₂] less one lobe, a
        // pinned lobe inside the pinned pair) costs at least as much as that one's optimum:
        // once that optimum is admissible, the smaller candidate cannot be the best
        let mut admissible = [false; 7];
        for (index, t) in candidates.into_iter().enumerate() {
            let covered = match index {
                3 => admissible[1] || admissible[2],
                5 | 6 => admissible[4],
                _ => false,
            };
            if prune && covered {
                continue;
            }
            let m = t.len();
            let mut a = if index == 0 {
                // The free solution's basis is the columns themselves: its normal equations are
                // G and b (`normal_equations` of the identity, whose zeros and ones add nothing)
                std::array::from_fn(|p| [g[p][0], g[p][1], g[p][2], b[p]])
            } else {
                normal_equations(t, &g, &b)
            };
            // (one call per size, so that each is unrolled for its m)
            let x = match m {
                3 => solve_cofactors(&a).or_else(|| solve_small(&mut a, 3)),
                2 => solve_small(&mut a, 2),
                _ => solve_small(&mut a, 1),
            };
            let Some(x) = x else {
                continue;
            };
            let coef: [f64; 3] = std::array::from_fn(|i| (0..m).map(|p| x[p] * t[p][i]).sum());
            // β₁ ≥ 0; β₂ ≥ 0 with f(π) ≥ 0 (where both lobes have their minimum), or β₂ < 0 (a
            // signed pair, the broader lobe negative) with the profile ≥ 0 at every φ
            if coef[1] < 0.0 {
                continue;
            }
            let cost = self.cost(&g, &b, yy, coef);
            let admissible_signed = |coef: [f64; 3]| {
                self.signed && TwoLobe::new(coef[0], [coef[1], coef[2]], c).is_some()
            };
            if coef[2] < 0.0 {
                if index == 0 && admissible_signed(coef) {
                    // The free solution is admissible (profiles ≥ 0 everywhere are a convex
                    // set): the optimum, as below
                    return (cost, coef);
                }
                if cost < signed.0 && admissible_signed(coef) {
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
            admissible[index] = true;
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

/// The normal equations of the least squares in the basis whose vectors are the rows of `t`
/// (m ≤ 3 of them): TGTᵀ augmented by Tb, in the first m rows and columns.
fn normal_equations(t: &[[f64; 3]], g: &[[f64; 3]; 3], b: &[f64; 3]) -> [[f64; 4]; 3] {
    let mut a = [[0.0; 4]; 3];
    for (p, tp) in t.iter().enumerate() {
        for (q, tq) in t.iter().enumerate() {
            a[p][q] = (0..3)
                .map(|i| tp[i] * (0..3).map(|j| g[i][j] * tq[j]).sum::<f64>())
                .sum();
        }
        a[p][3] = (0..3).map(|i| tp[i] * b[i]).sum();
    }
    a
}

/// Solves the 3 × 3 system whose augmented rows are `a` by cofactors (Cramer's rule): every
/// cofactor at once and one division, a short chain of dependent operations, where elimination
/// is a chain of divisions. `None` unless the determinant is above 10⁻⁶ of the product of the
/// diagonal (which bounds a Gram matrix's): nearer singular, [`solve_small`] pivots.
#[inline(always)]
fn solve_cofactors(a: &[[f64; 4]; 3]) -> Option<[f64; 3]> {
    let m = |i: usize, j: usize| a[i][j];
    // Cofactors of the first row, then the determinant along it
    let c0 = m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1);
    let c1 = m(1, 2) * m(2, 0) - m(1, 0) * m(2, 2);
    let c2 = m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0);
    let det = m(0, 0) * c0 + m(0, 1) * c1 + m(0, 2) * c2;
    let diagonal = (m(0, 0) * m(1, 1) * m(2, 2)).abs();
    if det.is_nan() || det.abs() <= 1e-6 * diagonal {
        return None;
    }
    let b = [a[0][3], a[1][3], a[2][3]];
    // x = adj(A) b / det, the adjugate's rows being the cofactors' columns
    let x0 = c0 * b[0]
        + (m(0, 2) * m(2, 1) - m(0, 1) * m(2, 2)) * b[1]
        + (m(0, 1) * m(1, 2) - m(0, 2) * m(1, 1)) * b[2];
    let x1 = c1 * b[0]
        + (m(0, 0) * m(2, 2) - m(0, 2) * m(2, 0)) * b[1]
        + (m(0, 2) * m(1, 0) - m(0, 0) * m(1, 2)) * b[2];
    let x2 = c2 * b[0]
        + (m(0, 1) * m(2, 0) - m(0, 0) * m(2, 1)) * b[1]
        + (m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0)) * b[2];
    let inverse = 1.0 / det;
    let x = [x0 * inverse, x1 * inverse, x2 * inverse];
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Solves the system of the first m equations in the first m unknowns whose augmented rows
/// are `a` (m ≤ N, right-hand side in column N, W = N + 1) by Gaussian elimination with
/// partial pivoting, the other unknowns 0; `None` if singular.
#[inline(always)]
pub(crate) fn solve_small<const N: usize, const W: usize>(
    a: &mut [[f64; W]; N],
    m: usize,
) -> Option<[f64; N]> {
    debug_assert!(W == N + 1 && m <= N);
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
    let mut x = [0.0; N];
    for i in (0..m).rev() {
        let s: f64 = (i + 1..m).map(|j| a[i][j] * x[j]).sum();
        x[i] = (a[i][N] - s) / a[i][i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gwc::pdf_wc;
    use crate::rng::{SeedableRng, SplitMix64, UnitF64};

    /// The cofactor solve agrees with pivoted elimination wherever it answers, over Gram
    /// matrices of random columns (8 rows, weights and scales over 20 decades, some nearly
    /// dependent), and leaves the singular ones to elimination.
    #[test]
    fn the_cofactor_solve_agrees_with_elimination() {
        let mut rng = SplitMix64::seed_from_u64(12);
        let (mut answered, mut declined) = (0, 0);
        for case in 0..20_000 {
            let scale = 10f64.powf(20.0 * rng.next_f64() - 10.0);
            let columns: [[f64; 8]; 3] =
                std::array::from_fn(|_| std::array::from_fn(|_| scale * (rng.next_f64() - 0.3)));
            // Every fourth case: the last column nearly a copy of the second
            let near = 10f64.powf(-12.0 * rng.next_f64());
            let columns = if case % 4 == 0 {
                [columns[0], columns[1], columns[1].map(|v| v * (1.0 + near))]
            } else {
                columns
            };
            let w: [f64; 8] = std::array::from_fn(|_| rng.next_f64());
            let y: [f64; 8] = std::array::from_fn(|_| rng.next_f64());
            let mut a = [[0.0; 4]; 3];
            for p in 0..3 {
                for q in 0..3 {
                    a[p][q] = (0..8).map(|k| w[k] * columns[p][k] * columns[q][k]).sum();
                }
                a[p][3] = (0..8).map(|k| w[k] * columns[p][k] * y[k]).sum();
            }
            let cofactors = solve_cofactors(&a);
            let eliminated = solve_small(&mut a.clone(), 3);
            match (cofactors, eliminated) {
                (Some(x), Some(z)) => {
                    answered += 1;
                    let size = z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    for (u, v) in x.iter().zip(&z) {
                        assert!(
                            (u - v).abs() <= 1e-7 * size,
                            "case {case}: {x:?} against {z:?}"
                        );
                    }
                }
                (Some(x), None) => {
                    panic!("case {case}: cofactors {x:?} where elimination declines")
                }
                (None, _) => declined += 1,
            }
        }
        assert!(
            answered > 10_000 && declined > 1000,
            "{answered} answered, {declined} declined"
        );
    }

    /// Leaving out the candidates that a larger admissible one covers changes no solution: over
    /// random profiles (a floor and two lobes of either sign, or rising away from φ = 0, noise up to
    /// ±50 %, values down to 10⁻⁶ of the largest) and random pairs of concentrations, with and without signed pairs,
    /// the pruned solve returns the cost and coefficients of trying every candidate, bit for bit.
    #[test]
    fn pruned_candidates_change_no_solution() {
        let mut rng = SplitMix64::seed_from_u64(11);
        let phi = crate::table::two_lobe_azimuths();
        let versine: Vec<f64> = phi.iter().map(|&p| 2.0 * (0.5 * p).sin().powi(2)).collect();
        let mut constrained = 0;
        for case in 0..20_000 {
            let c = [0.99 * rng.next_f64(), 0.99 * rng.next_f64()];
            let beta = [rng.next_f64(), rng.next_f64() - 0.5];
            let floor = rng.next_f64() - 0.2;
            // Every third profile rising away from φ = 0, where lobes of either sign only make it
            // worse and the floor alone is the best candidate
            let y: Vec<f64> = phi
                .iter()
                .map(|&p| {
                    let f = if case % 3 == 1 {
                        1.0 + beta[0] * (1.0 - p.cos())
                    } else {
                        floor + beta[0] * pdf_wc(p, c[0]) + beta[1] * pdf_wc(p, c[1])
                    };
                    (f * (1.0 + rng.next_f64() - 0.5)).abs().max(1e-6)
                })
                .collect();
            let w: Vec<f64> = y.iter().map(|v| 1.0 / v).collect();
            let problem = Problem::new(&versine, &y, &w, case % 2 == 0);
            let lobes = [
                problem.lobe(0.999 * rng.next_f64()),
                problem.lobe(0.999 * rng.next_f64()),
            ];
            let pruned = problem.solve_columns_with([&lobes[0], &lobes[1]], true);
            let all = problem.solve_columns_with([&lobes[0], &lobes[1]], false);
            assert_eq!(
                (pruned.0.to_bits(), pruned.1.map(f64::to_bits)),
                (all.0.to_bits(), all.1.map(f64::to_bits)),
                "case {case}"
            );
            // Count the solutions on a constraint (a lobe left out, or the floor pinned to 0 at
            // π): the solves that try the candidates pruning may leave out
            let [alpha, b1, b2] = all.1;
            let at_pi = alpha + b1 * lobes[0].at_pi + b2 * lobes[1].at_pi;
            let on_constraint = b1 == 0.0 || b2 == 0.0 || at_pi.abs() <= 1e-9 * (b1 + b2.abs());
            constrained += usize::from(on_constraint);
        }
        assert!(constrained > 1000, "only {constrained} constrained cases");
    }

    /// The free solution's shortcut takes G and b as they are: what `normal_equations` gives
    /// in the identity basis, bit for bit, over random Gram matrices of every sign and scale
    /// (and one of zeros).
    #[test]
    fn the_free_solution_uses_the_identity_basis_normal_equations() {
        let mut rng = SplitMix64::seed_from_u64(3);
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for case in 0..10_000 {
            let mut value = || {
                let v = (rng.next_f64() - 0.5) * 10f64.powf(40.0 * rng.next_f64() - 20.0);
                if case == 0 {
                    0.0
                } else {
                    v
                }
            };
            let g: [[f64; 3]; 3] = std::array::from_fn(|_| std::array::from_fn(|_| value()));
            let b: [f64; 3] = std::array::from_fn(|_| value());
            let a = normal_equations(&identity, &g, &b);
            for p in 0..3 {
                let direct = [g[p][0], g[p][1], g[p][2], b[p]];
                // (== holds 0 and −0 equal: a zero's sign changes no solution)
                for (x, y) in a[p].iter().zip(direct) {
                    assert!(x == &y, "case {case}, row {p}: {x} against {y}");
                }
            }
        }
    }
}
