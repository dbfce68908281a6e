//! One segment of a spline as a cubic in its parameter t ∈ [0, 1], in the Hermite form of the
//! module docs of [`super`]: its value, slope and exact integral, and its positive part
//! max(s, 0) for [`Nodes::integrate_positive`](super::Nodes::integrate_positive) and the
//! sampling triad (`sampling.rs`).
//!
//! The positive part: if the Bernstein coefficients of s are all ≥ 0, s ≥ 0 on all of [0, 1]
//! (convex hull property). Otherwise s is monotone between the roots of ds/dt, so cutting
//! [0, 1] at its roots in each of those (at most three) pieces leaves at most four parts where
//! s > 0.
//!
//! Roots, and the t where the integral of the positive part reaches a goal, are found by
//! `newton_bisection` (end of this file): Newton's method safeguarded by bisection, with the
//! stopping rules and tolerances of the module docs of [`super`].
//! [`Nodes::invert`](super::Nodes::invert) solves s(t) = y with it too.

use super::{MAX_ITERATIONS, PREDICTED_TOLERANCE, T_TOLERANCE};

/// One segment of a spline: its ends, end values and end slopes in t-units.
#[derive(Debug, Clone, Copy)]
pub(super) struct Segment {
    pub(super) x0: f64,
    pub(super) x1: f64,
    pub(super) f0: f64,
    pub(super) f1: f64,
    pub(super) d0: f64,
    pub(super) d1: f64,
}

/// A segment with the parts of t ∈ [0, 1] where its cubic is positive.
#[derive(Debug, Clone, Copy)]
pub(super) struct Positive {
    pub(super) segment: Segment,
    /// Increasing, disjoint intervals of t where s > 0; unused entries are empty (a = b).
    parts: [(f64, f64); 4],
    /// P(1) = ∫₀¹ max(s, 0) dt.
    pub(super) mass: f64,
}

impl Segment {
    pub(super) fn width(&self) -> f64 {
        self.x1 - self.x0
    }

    /// The point at parameter t, kept inside [x0, x1] despite rounding.
    pub(super) fn at(&self, t: f64) -> f64 {
        (self.x0 + self.width() * t).clamp(self.x0, self.x1)
    }

    /// The parameter t of x, clamped to [0, 1].
    pub(super) fn t_at(&self, x: f64) -> f64 {
        ((x - self.x0) / self.width()).clamp(0.0, 1.0)
    }

    /// Coefficients of s(t) = c₀ + c₁t + c₂t² + c₃t³: c₀ = f₀, c₁ = d₀,
    /// c₂ = 3(f₁ − f₀) − 2d₀ − d₁, c₃ = 2(f₀ − f₁) + d₀ + d₁.
    fn coefficients(&self) -> [f64; 4] {
        let (f0, f1, d0, d1) = (self.f0, self.f1, self.d0, self.d1);
        [
            f0,
            d0,
            3.0 * (f1 - f0) - 2.0 * d0 - d1,
            2.0 * (f0 - f1) + d0 + d1,
        ]
    }

    /// s(t).
    pub(super) fn value(&self, t: f64) -> f64 {
        horner(self.coefficients(), t)
    }

    /// s and its integral with their coefficients computed once, for repeated evaluation.
    fn cubic(&self) -> Cubic {
        let c = self.coefficients();
        Cubic {
            c,
            integral: [c[0], c[1] / 2.0, c[2] / 3.0, c[3] / 4.0],
        }
    }

    /// ds/dt.
    pub(super) fn slope(&self, t: f64) -> f64 {
        let [_, c1, c2, c3] = self.coefficients();
        c1 + t * (2.0 * c2 + t * 3.0 * c3)
    }

    /// S(t) = ∫₀ᵗ s dt = c₀t + c₁t²/2 + c₂t³/3 + c₃t⁴/4 (t-units).
    fn integral_to(&self, t: f64) -> f64 {
        self.cubic().integral_to(t)
    }

    /// S(1) = (f₀ + f₁)/2 + (d₀ − d₁)/12.
    pub(super) fn integral(&self) -> f64 {
        (self.f0 + self.f1) / 2.0 + (self.d0 - self.d1) / 12.0
    }

    /// Σ|terms| of s on [0, 1], the scale of its rounding error.
    pub(super) fn value_scale(&self) -> f64 {
        self.coefficients().iter().map(|c| c.abs()).sum()
    }

    /// Σ|terms| of S on [0, 1], the scale of its rounding error.
    fn integral_scale(&self) -> f64 {
        let [c0, c1, c2, c3] = self.coefficients();
        c0.abs() + c1.abs() / 2.0 + c2.abs() / 3.0 + c3.abs() / 4.0
    }
}

/// A segment's cubic s(t) = c₀ + c₁t + c₂t² + c₃t³ and its integral, coefficients precomputed
/// (the division by 3 in S would otherwise be repeated at every step of a solve).
#[derive(Debug, Clone, Copy)]
struct Cubic {
    c: [f64; 4],
    /// c₀, c₁/2, c₂/3, c₃/4.
    integral: [f64; 4],
}

/// c₀ + c₁t + c₂t² + c₃t³ by Horner's scheme.
#[inline]
fn horner([c0, c1, c2, c3]: [f64; 4], t: f64) -> f64 {
    c0 + t * (c1 + t * (c2 + t * c3))
}

impl Cubic {
    /// s(t).
    #[inline]
    pub(super) fn value(&self, t: f64) -> f64 {
        horner(self.c, t)
    }

    /// S(t) = ∫₀ᵗ s dt.
    #[inline]
    fn integral_to(&self, t: f64) -> f64 {
        let [i0, i1, i2, i3] = self.integral;
        t * (i0 + t * (i1 + t * (i2 + t * i3)))
    }
}

impl Segment {
    /// Bernstein coefficients of s on [0, 1]: f₀, f₀ + d₀/3, f₁ − d₁/3, f₁.
    fn bernstein(&self) -> [f64; 4] {
        [
            self.f0,
            self.f0 + self.d0 / 3.0,
            self.f1 - self.d1 / 3.0,
            self.f1,
        ]
    }

    /// The parameters t in (0, 1) where ds/dt = 0, sorted; 1 stands in for a missing one.
    fn critical_points(&self) -> [f64; 2] {
        // Roots of a·t² + b·t + c = 3c₃t² + 2c₂t + c₁, in the cancellation-free form
        let [_, c1, c2, c3] = self.coefficients();
        let (a, b, c) = (3.0 * c3, 2.0 * c2, c1);
        let roots = if a == 0.0 {
            [-c / b, f64::NAN]
        } else {
            let q = -0.5 * (b + (b * b - 4.0 * a * c).sqrt().copysign(b));
            [q / a, c / q]
        };
        let [p, q] = roots.map(|t| if t > 0.0 && t < 1.0 { t } else { 1.0 });
        if p <= q {
            [p, q]
        } else {
            [q, p]
        }
    }

    /// The root of s in [a, b] if s changes sign there (s must be monotone on [a, b]), else b.
    fn root_in(&self, a: f64, b: f64) -> f64 {
        let (sa, sb) = (self.value(a), self.value(b));
        let changes_sign = (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0);
        if !changes_sign {
            return b;
        }
        let sign = if sb > sa { 1.0 } else { -1.0 };
        newton_bisection(
            |t| (sign * self.value(t), sign * self.slope(t)),
            0.0,
            self.value_scale(),
            (a, b),
            a + (b - a) * sa / (sa - sb),
        )
    }

    /// The segment with the parts of [0, 1] where s > 0 and their integral P(1).
    pub(super) fn positive(self) -> Positive {
        let parts = if self.bernstein().iter().all(|&c| c >= 0.0) {
            // Convex hull property: s ≥ 0 on all of [0, 1]
            [(0.0, 1.0), (1.0, 1.0), (1.0, 1.0), (1.0, 1.0)]
        } else {
            // Cut at the roots; s is monotone between critical points, so there are at most 3
            let [p, q] = self.critical_points();
            let [r0, r1, r2] = [(0.0, p), (p, q), (q, 1.0)].map(|(a, b)| self.root_in(a, b));
            let mut parts = [(1.0, 1.0); 4];
            for (part, cut) in parts.iter_mut().zip([0.0, r0, r1, r2, 1.0].windows(2)) {
                if let [a, b] = *cut {
                    if b > a && self.value(0.5 * (a + b)) > 0.0 {
                        *part = (a, b);
                    }
                }
            }
            parts
        };
        // Empty parts (a = b) add exactly 0: skipped
        let cubic = self.cubic();
        let mass = parts
            .iter()
            .filter(|&&(a, b)| b > a)
            .map(|&(a, b)| cubic.integral_to(b) - cubic.integral_to(a))
            .sum();
        Positive {
            segment: self,
            parts,
            mass,
        }
    }
}

impl Positive {
    /// P(t) = ∫₀ᵗ max(s, 0) dt.
    pub(super) fn integral_to(&self, t: f64) -> f64 {
        let segment = self.segment;
        self.parts
            .iter()
            .map(|&(a, b)| segment.integral_to(t.clamp(a, b)) - segment.integral_to(a))
            .sum::<f64>()
            .max(0.0)
    }

    /// The t with P(t) = `target` ∈ [0, P(1)]: the part holding it, then Newton–bisection.
    pub(super) fn solve(&self, target: f64) -> f64 {
        let segment = self.segment;
        let cubic = segment.cubic();
        let (mut before, mut end) = (0.0, 0.0);
        for &(a, b) in &self.parts {
            if b <= a {
                // Empty (mass exactly 0)
                continue;
            }
            let start = cubic.integral_to(a);
            let mass = cubic.integral_to(b) - start;
            if mass <= 0.0 {
                continue;
            }
            end = b;
            let remaining = target - before;
            if remaining <= 0.0 {
                return a;
            }
            if remaining < mass {
                // Start from the inverse of the integral of the chord over [a, b]
                let (v0, v1) = (cubic.value(a), cubic.value(b));
                let k = (v1 - v0) / (b - a);
                let guess = a + 2.0 * remaining / (v0 + (v0 * v0 + 2.0 * k * remaining).sqrt());
                return newton_bisection(
                    |t| (cubic.integral_to(t), cubic.value(t)),
                    start + remaining,
                    segment.integral_scale(),
                    (a, b),
                    guess,
                );
            }
            before += mass;
        }
        end
    }
}

/// Solves g(t) = goal on [lo, hi], where `g` returns (g(t), g′(t)), g increases on [lo, hi]
/// and g(lo) ≤ goal ≤ g(hi).
///
/// Newton steps are kept while they land inside the bracket and at least halve the step
/// before last; otherwise the bracket is bisected (the safeguard of Numerical Recipes'
/// `rtsafe`). A NaN or out-of-range `guess` starts from the midpoint. Always returns a t in
/// [lo, hi].
///
/// Two Newton steps in a row, δ₁ then δ₂, measure the quadratic convergence: the error left
/// after δ₂ is about K·δ₂² with K ≈ |δ₂|/δ₁². Once that estimate is below
/// [`PREDICTED_TOLERANCE`] (and |δ₂| ≤ 10⁻⁴, so that it is asymptotic) the solve ends there
/// instead of evaluating g once more to confirm it: the spline samplers' solves then take 2
/// evaluations of g where they took 3 (the sampled density is evaluated at the returned point,
/// so the sample and its pdf stay exact; only where in [lo, hi] the goal lands moves, by
/// about 10⁻¹⁰ of the segment at most).
pub(super) fn newton_bisection(
    g: impl Fn(f64) -> (f64, f64),
    goal: f64,
    scale: f64,
    (lo, hi): (f64, f64),
    guess: f64,
) -> f64 {
    let residual_tolerance = 4.0 * f64::EPSILON * scale;
    let (mut a, mut b) = (lo, hi);
    let (mut step, mut step_before) = (hi - lo, hi - lo);
    let mut previous_newton: Option<f64> = None;
    let mut t = if guess >= lo && guess <= hi {
        guess
    } else {
        0.5 * (lo + hi)
    };
    for _ in 0..MAX_ITERATIONS {
        let (value, derivative) = g(t);
        let residual = value - goal;
        if residual.abs() <= residual_tolerance {
            return t;
        }
        // Narrow the bracket around the root
        if residual < 0.0 {
            a = t;
        } else {
            b = t;
        }
        // Take a Newton step if it stays inside and converges fast enough, else bisect
        let newton = residual / derivative;
        let next = t - newton;
        let fast = newton.abs() <= 0.5 * step_before.abs();
        step_before = step;
        if next > a && next < b && fast {
            // Error left after this step, from the last two Newton steps (see above)
            let converged = previous_newton.is_some_and(|before: f64| {
                newton.abs() <= 1e-4
                    && newton.abs() * newton * newton <= PREDICTED_TOLERANCE * before * before
            });
            step = newton;
            t = next;
            if converged {
                return t;
            }
            previous_newton = Some(newton);
        } else {
            step = 0.5 * (b - a);
            t = a + step;
            previous_newton = None;
        }
        if step.abs() <= T_TOLERANCE {
            return t;
        }
    }
    t
}
