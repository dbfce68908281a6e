//! Catmull-Rom splines on non-uniform nodes: interpolation weights, exact integration, and
//! inversion of a monotone spline.
//!
//! This is the spline pbrt uses for its BSSRDF tables (pbrt-v3 `core/interpolation.cpp`,
//! pbrt-v4 `util/math.cpp` and `util/sampling.cpp`), after Catmull and Rom, "A class of local
//! interpolating splines" (1974), with derivatives from non-uniform finite differences.
//!
//! # The spline
//! Nodes x₀ < x₁ < … < x_{n−1} (n ≥ 2, finite, validated once by [`Nodes::new`]) carry values
//! f₀ … f_{n−1}. On segment i, with width wᵢ = x_{i+1} − xᵢ and parameter t = (x − xᵢ)/wᵢ ∈ [0, 1],
//! the spline is the cubic Hermite polynomial
//!
//! s(t) = h₀₀(t)·fᵢ + h₀₁(t)·f_{i+1} + h₁₀(t)·d₀ + h₁₁(t)·d₁,
//!
//! h₀₀ = 2t³ − 3t² + 1, h₀₁ = −2t³ + 3t², h₁₀ = t³ − 2t² + t, h₁₁ = t³ − t²,
//!
//! where d₀, d₁ are the slopes at the two ends in t-units (per unit t, not per unit x):
//! - d₀ = (f_{i+1} − f_{i−1})·wᵢ/(x_{i+1} − x_{i−1}), or f_{i+1} − fᵢ on the first segment;
//! - d₁ = (f_{i+2} − fᵢ)·wᵢ/(x_{i+2} − xᵢ), or f_{i+1} − fᵢ on the last segment.
//!
//! Both segments meeting at an interior node use the same slope dy/dx there, so the spline is
//! C¹; it interpolates the node values and reproduces linear data exactly. It can undershoot
//! below zero next to steep drops (for example in the tail of an exponential profile on a
//! geometric grid).
//!
//! # Conventions
//! - Values are read through closures `Fn(usize) -> f64`, called only with node indices in
//!   `0..n`. A caller can therefore interpolate table rows on the fly or read f32
//!   storage. Nothing on the evaluation or sampling paths allocates.
//! - Nothing panics. A NaN or out-of-range argument gives `None`.
//! - Equations are solved by Newton's method safeguarded by bisection, as in Numerical
//!   Recipes' `rtsafe`. The solve stops when a step is at most [`T_TOLERANCE`] in t, when the
//!   residual is at rounding level (4ε times the polynomial's summed coefficient magnitudes),
//!   or after [`MAX_ITERATIONS`]. pbrt stops at 10⁻⁶ and has no iteration cap.

use crate::error::{finite, in_range, Error, Result};

/// Tolerance of the Newton–bisection solves, in units of the segment parameter t.
///
/// A Newton step this small means the quadratic convergence has already left an error far
/// below it, so results are accurate to about 10⁻¹² of the segment width or better, except
/// where the residual reaches rounding level first.
pub const T_TOLERANCE: f64 = 1e-12;

/// Iteration cap of the Newton–bisection solves. Each iteration is either a Newton step that at
/// least halves the step before last, or a bisection, so the cap is a guard rather than a
/// limit.
pub const MAX_ITERATIONS: usize = 100;

/// Strictly increasing, finite spline nodes (at least 2), validated once at construction.
#[derive(Debug, Clone, PartialEq)]
pub struct Nodes {
    x: Box<[f64]>,
}

/// The Catmull-Rom weights of the four nodes around one point.
///
/// `as_array()[k]` belongs to node `segment() + k − 1`. Weights of nodes outside the array
/// (node −1 on the first segment, node n on the last) are exactly 0, and [`Weights::iter`]
/// skips them, so no caller needs to index outside the array.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    segment: usize,
    len: usize,
    w: [f64; 4],
}

/// One segment of a spline: its ends, end values and end slopes in t-units.
#[derive(Debug, Clone, Copy)]
struct Segment {
    x0: f64,
    x1: f64,
    f0: f64,
    f1: f64,
    d0: f64,
    d1: f64,
}

impl Nodes {
    /// Validates the nodes: at least 2, all finite, strictly increasing.
    ///
    /// Errors name the offending node (or node count).
    pub fn new(x: impl Into<Box<[f64]>>) -> Result<Self> {
        let x = x.into();
        in_range("number of spline nodes", x.len() as f64, 2.0, f64::INFINITY)?;
        for &xi in x.iter() {
            finite("spline node", xi)?;
        }
        for pair in x.windows(2) {
            if let [previous, next] = *pair {
                if next <= previous {
                    return Err(Error::OutOfRange {
                        name: "spline node (nodes must strictly increase)",
                        value: next,
                        min: previous,
                        max: f64::INFINITY,
                    });
                }
            }
        }
        Ok(Self { x })
    }

    /// The node positions.
    pub fn as_slice(&self) -> &[f64] {
        &self.x
    }

    /// The Catmull-Rom weights at `x`, or `None` if `x` is NaN or outside [x₀, x_{n−1}].
    ///
    /// Find segment i with xᵢ ≤ x (the last segment for x = x_{n−1}) by binary search. With the
    /// basis of the module docs, the weights of nodes i−1 … i+2 are
    ///
    /// (−s₀h₁₀, h₀₀ − s₁h₁₁, h₀₁ + s₀h₁₀, s₁h₁₁), s₀ = wᵢ/(x_{i+1} − x_{i−1}), s₁ = wᵢ/(x_{i+2} − xᵢ);
    ///
    /// on the first segment h₁₀ moves from nodes (i−1, i+1) to (i, i+1) with s₀ = 1, and on the
    /// last segment h₁₁ moves from nodes (i, i+2) to (i, i+1) with s₁ = 1. They sum to 1. At a
    /// node, its weight is exactly 1 and the others exactly 0.
    pub fn weights(&self, x: f64) -> Option<Weights> {
        let i = self.find_segment(x)?;
        let (x0, x1) = (*self.x.get(i)?, *self.x.get(i + 1)?);
        let width = x1 - x0;
        let t = ((x - x0) / width).clamp(0.0, 1.0);
        let (t2, t3) = (t * t, t * t * t);
        let mut w = [0.0, 2.0 * t3 - 3.0 * t2 + 1.0, -2.0 * t3 + 3.0 * t2, 0.0];
        let (h10, h11) = (t3 - 2.0 * t2 + t, t3 - t2);
        // Slope at xᵢ: central difference, or one-sided on the first segment
        match i.checked_sub(1).and_then(|h| self.x.get(h)) {
            Some(&x_before) => {
                let s0 = width / (x1 - x_before);
                w[0] -= h10 * s0;
                w[2] += h10 * s0;
            }
            None => {
                w[1] -= h10;
                w[2] += h10;
            }
        }
        // Slope at x_{i+1}: central difference, or one-sided on the last segment
        match self.x.get(i + 2) {
            Some(&x_after) => {
                let s1 = width / (x_after - x0);
                w[1] -= h11 * s1;
                w[3] += h11 * s1;
            }
            None => {
                w[1] -= h11;
                w[2] += h11;
            }
        }
        Some(Weights {
            segment: i,
            len: self.x.len(),
            w,
        })
    }

    /// The spline through `values` at `x`: Σₖ wₖ·f_{node k}, or `None` if `x` is NaN or outside
    /// [x₀, x_{n−1}]. Not clamped: the result can be negative where the spline undershoots.
    pub fn evaluate(&self, values: impl Fn(usize) -> f64, x: f64) -> Option<f64> {
        Some(self.weights(x)?.apply(values))
    }

    /// Integrates the spline through `values` exactly over [x₀, x_{n−1}], writing the running
    /// integral to `cumulative` (C₀ = 0, Cₖ = ∫_{x₀}^{xₖ} s dx), and returns the total C_{n−1}.
    ///
    /// Segment i contributes wᵢ·((fᵢ + f_{i+1})/2 + (d₀ − d₁)/12), the integral of its cubic.
    /// This is pbrt's `IntegrateCatmullRom` (its total is ρ_eff). Where the spline undershoots,
    /// C can decrease.
    /// Returns `None` if `cumulative.len()` is not the number of nodes.
    pub fn integrate(&self, values: impl Fn(usize) -> f64, cumulative: &mut [f64]) -> Option<f64> {
        self.accumulate(values, cumulative, |segment| segment.integral())
    }

    /// Running sum of wᵢ·`integral(segment i)`, for the integrals above.
    fn accumulate(
        &self,
        values: impl Fn(usize) -> f64,
        cumulative: &mut [f64],
        integral: impl Fn(Segment) -> f64,
    ) -> Option<f64> {
        if cumulative.len() != self.x.len() {
            return None;
        }
        let mut total = 0.0;
        for (i, c) in cumulative.iter_mut().enumerate() {
            if let Some(segment) = i.checked_sub(1).and_then(|h| self.segment(h, &values)) {
                total += segment.width() * integral(segment);
            }
            *c = total;
        }
        Some(total)
    }

    /// Solves s(x) = y for x, for a spline through increasing `values` (pbrt's
    /// `InvertCatmullRom`, used to invert albedo ↦ effective albedo).
    ///
    /// Clamps like pbrt: y ≤ f₀ gives x₀ and y ≥ f_{n−1} gives x_{n−1}. Otherwise find the
    /// segment with fᵢ ≤ y < f_{i+1} by binary search and solve s(t) = y there by
    /// Newton–bisection, starting from the secant guess (y − fᵢ)/(f_{i+1} − fᵢ). For values that
    /// are not increasing the result is some x in that segment. `None` if `y` is NaN.
    pub fn invert(&self, values: impl Fn(usize) -> f64, y: f64) -> Option<f64> {
        if y.is_nan() {
            return None;
        }
        let (first, last) = self.ends();
        if y <= values(0) {
            return Some(first);
        }
        if y >= values(self.x.len() - 1) {
            return Some(last);
        }
        let i = find_interval(self.x.len(), |i| values(i) <= y);
        let segment = self.segment(i, &values)?;
        let guess = (y - segment.f0) / (segment.f1 - segment.f0);
        let t = newton_bisection(
            |t| (segment.value(t), segment.slope(t)),
            y,
            segment.value_scale(),
            (0.0, 1.0),
            guess,
        );
        Some(segment.at(t))
    }

    /// First and last node.
    fn ends(&self) -> (f64, f64) {
        match *self.x {
            [first, .., last] => (first, last),
            // Unreachable: `new` guarantees at least two nodes.
            _ => (0.0, 0.0),
        }
    }

    /// The segment i containing `x` (xᵢ ≤ x, the last one for x = x_{n−1}), or `None` if `x`
    /// is NaN or outside [x₀, x_{n−1}].
    fn find_segment(&self, x: f64) -> Option<usize> {
        let (first, last) = self.ends();
        if x.is_nan() || x < first || x > last {
            return None;
        }
        Some(find_interval(self.x.len(), |i| {
            self.x.get(i).is_some_and(|&xi| xi <= x)
        }))
    }

    /// Segment i of the spline through `values`, with the slopes of the module docs.
    fn segment(&self, i: usize, values: &impl Fn(usize) -> f64) -> Option<Segment> {
        let (x0, x1) = (*self.x.get(i)?, *self.x.get(i + 1)?);
        let (f0, f1) = (values(i), values(i + 1));
        let width = x1 - x0;
        let d0 = match i.checked_sub(1).and_then(|h| Some((h, *self.x.get(h)?))) {
            Some((h, x_before)) => (f1 - values(h)) * width / (x1 - x_before),
            None => f1 - f0,
        };
        let d1 = match self.x.get(i + 2) {
            Some(&x_after) => (values(i + 2) - f0) * width / (x_after - x0),
            None => f1 - f0,
        };
        Some(Segment {
            x0,
            x1,
            f0,
            f1,
            d0,
            d1,
        })
    }
}

impl Weights {
    /// The segment i containing the point; `as_array()[k]` belongs to node i + k − 1.
    pub fn segment(&self) -> usize {
        self.segment
    }

    /// The four weights of nodes i−1 … i+2, 0 for nodes outside the array.
    pub fn as_array(&self) -> [f64; 4] {
        self.w
    }

    /// The (node index, weight) pairs of nodes inside the array with a nonzero weight.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> {
        let Weights { segment, len, w } = *self;
        w.into_iter().enumerate().filter_map(move |(k, weight)| {
            let node = (segment + k).checked_sub(1)?;
            (node < len && weight != 0.0).then_some((node, weight))
        })
    }

    /// Σ weight·f(node) over [`Weights::iter`]: the spline through the values `f` at the point.
    pub fn apply(&self, f: impl Fn(usize) -> f64) -> f64 {
        self.iter().map(|(node, weight)| weight * f(node)).sum()
    }
}

impl Segment {
    fn width(&self) -> f64 {
        self.x1 - self.x0
    }

    /// The point at parameter t, kept inside [x0, x1] despite rounding.
    fn at(&self, t: f64) -> f64 {
        (self.x0 + self.width() * t).clamp(self.x0, self.x1)
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
    fn value(&self, t: f64) -> f64 {
        let [c0, c1, c2, c3] = self.coefficients();
        c0 + t * (c1 + t * (c2 + t * c3))
    }

    /// ds/dt.
    fn slope(&self, t: f64) -> f64 {
        let [_, c1, c2, c3] = self.coefficients();
        c1 + t * (2.0 * c2 + t * 3.0 * c3)
    }

    /// S(1) = (f₀ + f₁)/2 + (d₀ − d₁)/12.
    fn integral(&self) -> f64 {
        (self.f0 + self.f1) / 2.0 + (self.d0 - self.d1) / 12.0
    }

    /// Σ|terms| of s on [0, 1], the scale of its rounding error.
    fn value_scale(&self) -> f64 {
        self.coefficients().iter().map(|c| c.abs()).sum()
    }
}

/// Binary search for the segment k ∈ [0, len − 2] with `pred(k)` true and `pred(k + 1)` false,
/// treating `pred(0)` as true and `pred(len − 1)` as false; for a monotone predicate, the last
/// k where it holds, clamped. Calls `pred` only with indices in 1..len−1.
fn find_interval(len: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (1, len.saturating_sub(1));
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if pred(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo - 1
}

/// Solves g(t) = goal on [lo, hi], where `g` returns (g(t), g′(t)), g increases on [lo, hi]
/// and g(lo) ≤ goal ≤ g(hi).
///
/// Newton steps are kept while they land inside the bracket and at least halve the step
/// before last; otherwise the bracket is bisected (the safeguard of Numerical Recipes'
/// `rtsafe`). A NaN or out-of-range `guess` starts from the midpoint. Always returns a t in
/// [lo, hi].
fn newton_bisection(
    g: impl Fn(f64) -> (f64, f64),
    goal: f64,
    scale: f64,
    (lo, hi): (f64, f64),
    guess: f64,
) -> f64 {
    let residual_tolerance = 4.0 * f64::EPSILON * scale;
    let (mut a, mut b) = (lo, hi);
    let (mut step, mut step_before) = (hi - lo, hi - lo);
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
            step = newton;
            t = next;
        } else {
            step = 0.5 * (b - a);
            t = a + step;
        }
        if step.abs() <= T_TOLERANCE {
            return t;
        }
    }
    t
}
