//! Catmull-Rom splines on non-uniform nodes: interpolation weights, exact integration, sampling
//! of a density shaped like the spline (with its pdf and CDF), and inversion of a monotone
//! spline.
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
//! - d₁ = (f_{i+2} − fᵢ)·wᵢ/(x_{i+2} − xᵢ), or on the last segment as its [`End`] says:
//!   f_{i+1} − fᵢ ([`End::Chord`], the default) or 0 ([`End::Even`], which also sets the slope
//!   at x_{n−2}, below).
//!
//! Both segments meeting at an interior node use the same slope dy/dx there, so the spline is
//! C¹; it interpolates the node values and, with chord ends, reproduces linear data exactly.
//! It can undershoot below zero next to steep drops (for example in the tail of an exponential
//! profile on a geometric grid).
//!
//! # The even end
//! A function even about the last node a = x_{n−1}, f(a + δ) = f(a − δ), is a function of
//! v = (a − x)² alone: f = F(v). Its slope at a is 0, which the chord slope misses by about
//! f″·w/2. [`End::Even`] uses that slope, and with at least three nodes it also takes the
//! slope at x_{n−2} from the evenness: the slope there of the polynomial even about a through
//! the last three nodes, P(x) = f_{n−1} + A·v + B·v² (a quadratic in v). On equal widths the
//! central difference at x_{n−2} is exact for quadratics in x; this slope is exact for every
//! even quartic on any widths, one order more for even data, at the same three nodes. With δ₁ = a − x_{n−2},
//! δ₂ = a − x_{n−3} and their ratio ρ = δ₁/δ₂ ∈ (0, 1), solving for A and B and taking
//! dP/dx = −2δ₁·(A + 2Bδ₁²) gives, per unit t of the segment that uses it,
//!
//! - last segment [x_{n−2}, a] (width δ₁), slope at its start:
//!   d₀ = k₃f_{n−3} + k₂f_{n−2} + k₁f_{n−1} with k₃ = −2ρ⁴/(1 − ρ²),
//!   k₂ = −2(1 − 2ρ²)/(1 − ρ²), k₁ = −(k₂ + k₃);
//! - segment [x_{n−3}, x_{n−2}] (width δ₂ − δ₁), slope at its end: the same slope,
//!   d₁ = k₃′f_{n−3} + k₂′f_{n−2} + k₁′f_{n−1} with k₃′ = −2ρ³/(1 + ρ),
//!   k₂′ = −2(1 − 2ρ²)/(ρ(1 + ρ)), k₁′ = −(k₂′ + k₃′).
//!
//! This applies while ρ ∈ [`EVEN_SLOPE_RATIOS`] (the last two widths within a factor 3 of each
//! other); otherwise x_{n−2} keeps the central difference, which stays bounded on any widths.
//! On equal widths (ρ = ½) both are (9f_{n−1} − 8f_{n−2} − f_{n−3})/6, against the central
//! difference's (f_{n−1} − f_{n−3})/2; the two agree on c₀ + c₂(x − a)². Both segments keep the
//! Hermite form, each still reads nodes i − 1 … i + 2 only, and the spline stays C¹,
//! interpolates the nodes and has weights summing to 1; only the last two segments differ from
//! the chord rule. The last segment never takes the fast path of [`Nodes::weights`]
//! (`catmull_rom/cells.rs`), and with the even quartic's slope (ρ in the range) neither does
//! the one before (its slope at x_{n−2} is not a central difference). With two nodes there is no x_{n−3}, and only the
//! slope 0 at a applies. The table's θ axis uses the even end when it ends at π/2
//! ([`crate::table::Axes::new`]), where the model depends on θ through sin θ only; there the
//! slope at x_{n−2} closed the last 0.0002 percentage points between the table and Ferrier's
//! "under 1 %" at (ρ′, θ) = (0.99, 89°) (docs/accuracy.md).
//!
//! # Sampling
//! [`Nodes::sample`], [`Nodes::pdf`] and [`Nodes::cdf`] form a triad for a density shaped like
//! the spline. The caller supplies the CDF table C (from [`Nodes::integrate`] or
//! [`Nodes::integrate_positive`], possibly rounded to f32 or interpolated between rows). Each
//! segment gets the probability its table entries give it, spread in proportion to max(s, 0):
//! negative lobes get density 0 instead of a negative one. The triad is exact whenever C never
//! decreases; where it does, see [`Nodes::pdf`] for the (small) discrepancy.
//!
//! # Conventions
//! - Values are read through closures `Fn(usize) -> f64`, called only with node indices in
//!   `0..n`. A caller can therefore interpolate table rows on the fly (see [`Nodes::sample`]),
//!   or read f32 storage. Nothing on the evaluation or sampling paths allocates.
//! - Nothing panics. A NaN or out-of-range argument gives `None` (or 0 for a pdf).
//! - Equations are solved by Newton's method safeguarded by bisection, as in Numerical
//!   Recipes' `rtsafe` (`catmull_rom/segment.rs`). The solve stops when a step is at most
//!   [`T_TOLERANCE`] in t, when the residual is at rounding level (4ε times the polynomial's
//!   summed coefficient magnitudes), when two successive Newton steps predict an error below
//!   [`PREDICTED_TOLERANCE`] in t, or after [`MAX_ITERATIONS`]. pbrt stops at 10⁻⁶ and has no
//!   iteration cap.

mod cells;
mod guide;
mod sampling;
mod segment;
#[cfg(test)]
mod tests;

use crate::error::{finite, in_range, Error, Result};
use cells::Cells;
use guide::Guide;
use segment::{newton_bisection, Segment};

/// Tolerance of the Newton–bisection solves, in units of the segment parameter t.
///
/// A Newton step this small means the quadratic convergence has already left an error far
/// below it, so results are accurate to about 10⁻¹² of the segment width or better, except
/// where the residual reaches rounding level first.
pub const T_TOLERANCE: f64 = 1e-12;

/// The ratios ρ = δ₁/δ₂ of the last three nodes for which an even end takes its slope at
/// x_{n−2} from the even quartic (module docs): the last two widths, δ₁ and δ₂ − δ₁, within a
/// factor 3 of each other. There the slope's weights stay below 6 in size; as ρ → 0 or 1 they
/// grow like 1/ρ or 1/(1 − ρ) (a difference over a short width, scaled to a long one), so
/// outside it x_{n−2} keeps the central difference. The table's θ axes have ρ = ½.
pub const EVEN_SLOPE_RATIOS: std::ops::RangeInclusive<f64> = 0.25..=0.75;

/// Iteration cap of the Newton–bisection solves. Each iteration is either a Newton step that at
/// least halves the step before last, or a bisection, so the cap is a guard rather than a
/// limit: the tests' samplers average 3–4.5 iterations, at most 13.
pub const MAX_ITERATIONS: usize = 100;

/// Error in t, predicted from the observed quadratic convergence, at which a Newton–bisection
/// solve stops without a confirming evaluation (see `newton_bisection`).
pub const PREDICTED_TOLERANCE: f64 = 1e-10;

/// The slope of a spline at its last node, x_{n−1} (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum End {
    /// The slope of the last segment's chord, (f_{n−1} − f_{n−2})/w_{n−2}: pbrt's rule.
    #[default]
    Chord,
    /// Slope 0, and at x_{n−2} the slope of the even quartic through the last three nodes
    /// (module docs): for data even about the last node.
    Even,
}

/// Strictly increasing, finite spline nodes (at least 2), validated once at construction, with
/// the [`End`] condition at the last one.
#[derive(Debug, Clone)]
pub struct Nodes {
    x: Box<[f64]>,
    /// The slope at x_{n−1}; only the last segment depends on it (and, for [`End::Even`], the
    /// one before).
    end: End,
    /// For [`End::Even`] with at least three nodes and ρ in [`EVEN_SLOPE_RATIOS`], the slope at
    /// x_{n−2} in t-units of the two segments that meet there, as weights of f_{n−3}, f_{n−2},
    /// f_{n−1}: `[before, last]`, for segments n − 3 and n − 2 (module docs).
    even: Option<[[f64; 3]; 2]>,
    /// Per segment, what [`Nodes::weights`] needs of it, derived from `x` once so that it does
    /// no division.
    spans: Box<[Span]>,
    /// Cells that give the segment of x directly (`catmull_rom/cells.rs`), or none. Their hot
    /// segments are those where [`Span::is_simple`].
    cells: Cells,
    /// Without cells: cells that narrow the search down to a few nodes (nodes ≥ 0 only).
    guide: Option<Guide>,
}

/// Segment i as [`Nodes::weights`] reads it: xᵢ, 1/wᵢ and the factors s₀ = wᵢ/(x_{i+1} − x_{i−1})
/// and s₁ = wᵢ/(x_{i+2} − xᵢ) of the two end slopes (NaN where the end is one-sided; unused
/// there).
#[derive(Debug, Clone, Copy)]
struct Span {
    x0: f64,
    inv_width: f64,
    s0: f64,
    s1: f64,
}

/// The Catmull-Rom weights of the four nodes around one point.
///
/// `as_array()[k]` belongs to node `segment() + k − 1`. Weights of nodes outside the array
/// (node −1 on the first segment, node n on the last) are exactly 0, and [`Weights::iter`]
/// skips them, so no caller needs to index outside the array.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    segment: usize,
    w: [f64; 4],
}

/// One draw from the density of a spline (see [`Nodes::sample`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// The sampled point, in [x₀, x_{n−1}].
    pub x: f64,
    /// The spline value s(x) (> 0).
    pub value: f64,
    /// The probability density at `x`, per unit of x (> 0 and finite).
    pub pdf: f64,
}

/// Two node sets are equal when their positions and end conditions are (the rest is derived
/// from them).
impl PartialEq for Nodes {
    fn eq(&self, other: &Self) -> bool {
        self.x == other.x && self.end == other.end
    }
}

impl Nodes {
    /// Validates the nodes: at least 2, all finite, strictly increasing. The spline takes the
    /// chord slope at both ends (see [`Nodes::with_end`]).
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
        Ok(Self::build(x, End::Chord))
    }

    /// The node set of validated nodes `x` (at least two, finite, increasing) with the slope
    /// `end` at the last one: spans, the slope at x_{n−2} of an even end, and cells whose hot
    /// segments are the simple spans (see [`Span::is_simple`]).
    fn build(x: Box<[f64]>, end: End) -> Self {
        let spans: Box<[Span]> = (0..x.len() - 1)
            .map(|i| {
                let width = x[i + 1] - x[i];
                let s0 = i
                    .checked_sub(1)
                    .map_or(f64::NAN, |h| width / (x[i + 1] - x[h]));
                let s1 = x
                    .get(i + 2)
                    .map_or(f64::NAN, |&after| width / (after - x[i]));
                Span {
                    x0: x[i],
                    inv_width: 1.0 / width,
                    s0,
                    s1,
                }
            })
            .collect();
        let even = match (end, &*x) {
            (End::Even, [.., before, penultimate, last]) => {
                let rho = (last - penultimate) / (last - before);
                EVEN_SLOPE_RATIOS.contains(&rho).then(|| even_slopes(rho))
            }
            _ => None,
        };
        // Segment n − 3 of an even end takes its slope at x_{n−2} from the even quartic: not
        // the simple formula
        let central = x.len() - usize::from(even.is_some());
        let cells = Cells::new(&x, |i| {
            i + 3 <= central && spans.get(i).is_some_and(|span| span.is_simple(i, &x))
        });
        let guide = if cells.is_empty() {
            Guide::new(&x)
        } else {
            None
        };
        Self {
            x,
            end,
            even,
            spans,
            cells,
            guide,
        }
    }

    /// The same nodes with the slope `end` at the last node. Weights, integrals, sampling and
    /// inversion all follow it; it changes the last segment only, or with [`End::Even`] the
    /// last two.
    #[must_use]
    pub fn with_end(self, end: End) -> Self {
        Self::build(self.x, end)
    }

    /// The slope at the last node.
    pub fn end(&self) -> End {
        self.end
    }

    /// The node positions.
    pub fn as_slice(&self) -> &[f64] {
        &self.x
    }

    /// The first node.
    pub fn first(&self) -> f64 {
        self.x[0]
    }

    /// The last node.
    pub fn last(&self) -> f64 {
        self.x[self.x.len() - 1]
    }

    /// The Catmull-Rom weights at `x`, or `None` if `x` is NaN or outside [x₀, x_{n−1}].
    ///
    /// Find segment i with xᵢ ≤ x (the last segment for x = x_{n−1}): keyed cells computed with
    /// the nodes (`catmull_rom/cells.rs`) give it with one comparison, or a guide
    /// (`catmull_rom/guide.rs`) and a binary search do. With the basis of the module docs, the
    /// weights of nodes i−1 … i+2 are
    ///
    /// (−s₀h₁₀, h₀₀ − s₁h₁₁, h₀₁ + s₀h₁₀, s₁h₁₁), s₀ = wᵢ/(x_{i+1} − x_{i−1}), s₁ = wᵢ/(x_{i+2} − xᵢ);
    ///
    /// on the first segment h₁₀ moves from nodes (i−1, i+1) to (i, i+1) with s₀ = 1, and on the
    /// last segment h₁₁ moves from nodes (i, i+2) to (i, i+1) with s₁ = 1 ([`End::Chord`]) or
    /// drops out ([`End::Even`]). An even end also gives h₁₀ of the last segment and h₁₁ of the
    /// one before the weights of its slope at x_{n−2} (module docs). They sum to 1. At a node,
    /// its weight is exactly 1 and the others exactly 0.
    #[inline]
    pub fn weights(&self, x: f64) -> Option<Weights> {
        // The common case: a hot cell gives a simple segment (`cells.rs`). Everything else
        // (end segments, x outside or NaN, node sets without cells) takes the general path,
        // which returns the whole result so that this one needs no saved registers.
        match self.hot_weights(x) {
            Some(w) => Some(w),
            None => self.other_weights(x),
        }
    }

    /// [`Nodes::weights`] where that is quickest: x in a hot cell (an interior segment that
    /// the cells find directly, the common case); `None` everywhere else, bit for bit the same
    /// weights. For a caller that keeps them apart from the general path's until its own `?`
    /// (`match nodes.hot_weights(x) { Some(w) => w, None => nodes.weights(x)? }`) or takes the
    /// other points out of line: merged as one `Option`, as [`Nodes::weights`] returns them,
    /// they go through memory, written as scalars, and the table's blends read them back as
    /// pairs, which stalls store forwarding (for the three axes of a table, 10 ns of an
    /// evaluation and 9 ns of a draw).
    #[inline(always)]
    pub(crate) fn hot_weights(&self, x: f64) -> Option<Weights> {
        let cell = self.cells.get(x)?;
        let i = cell.hot_segment(x);
        let span = self.spans.get(i)?;
        Some(Weights {
            segment: i,
            w: span.simple_weights(x),
        })
    }

    /// [`Nodes::weights`] where [`Nodes::hot_weights`] has none: x in a cell that is not hot
    /// for it, or missed by the cells (no cells, x NaN or outside).
    #[cold]
    #[inline(never)]
    fn other_weights(&self, x: f64) -> Option<Weights> {
        match self.cells.get(x) {
            Some(cell) => self.general_weights(x, cell.segment(x)),
            None => self.general_weights(x, self.search(x)?),
        }
    }

    /// [`Nodes::weights`] on segment i, any segment; `None` if there is no segment i.
    #[inline(always)]
    fn general_weights(&self, x: f64, i: usize) -> Option<Weights> {
        let span = self.spans.get(i)?;
        let (near, far) = self.slopes(i);
        Some(Weights {
            segment: i,
            w: span.weights(span.t(x), near, far),
        })
    }

    /// The slopes of segment i at xᵢ and at x_{i+1} (module docs).
    #[inline(always)]
    fn slopes(&self, i: usize) -> (Slope, Slope) {
        let n = self.x.len();
        // Interior segments away from the end first: the common case, and the only one on the
        // sampling paths' hot loops
        if i > 0 && i + 3 < n {
            return (Slope::Central, Slope::Central);
        }
        let near = match &self.even {
            Some([_, last]) if i + 2 == n => Slope::Even(*last),
            _ if i == 0 => Slope::Chord,
            _ => Slope::Central,
        };
        let far = match (&self.even, self.end) {
            (Some([before, _]), _) if i + 3 == n => Slope::Even(*before),
            _ if i + 2 < n => Slope::Central,
            (_, End::Chord) => Slope::Chord,
            (_, End::Even) => Slope::Zero,
        };
        (near, far)
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
    /// C can decrease; see [`Nodes::integrate_positive`] for a CDF that cannot.
    /// Returns `None` if `cumulative.len()` is not the number of nodes.
    pub fn integrate(&self, values: impl Fn(usize) -> f64, cumulative: &mut [f64]) -> Option<f64> {
        self.accumulate(values, cumulative, |segment| segment.integral())
    }

    /// Like [`Nodes::integrate`], but integrates the positive part max(s, 0): segment i
    /// contributes wᵢ·Pᵢ with Pᵢ = ∫₀¹ max(s, 0) dt, which needs the roots of the cubic where
    /// it undershoots. The result never decreases, so with it [`Nodes::sample`],
    /// [`Nodes::pdf`] and [`Nodes::cdf`] describe exactly the density max(s, 0)/T.
    pub fn integrate_positive(
        &self,
        values: impl Fn(usize) -> f64,
        cumulative: &mut [f64],
    ) -> Option<f64> {
        self.accumulate(values, cumulative, |segment| segment.positive().mass)
    }

    /// Running sum of wᵢ·`integral(segment i)`, for the two integrals above.
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
    #[inline]
    pub(crate) fn find_segment(&self, x: f64) -> Option<usize> {
        match self.cells.get(x) {
            Some(cell) => Some(cell.segment(x)).filter(|&i| i < self.spans.len()),
            None => self.search(x),
        }
    }

    /// The segment search without cells: range check, then the guide and a binary search.
    fn search(&self, x: f64) -> Option<usize> {
        let (first, last) = self.ends();
        if x.is_nan() || x < first || x > last {
            return None;
        }
        // Segments lo ≤ i ≤ hi can hold x, so nodes up to lo are ≤ x: count those after it
        let (lo, hi) = match &self.guide {
            Some(guide) => guide.range(x),
            None => (0, self.x.len() - 2),
        };
        let after = self
            .x
            .get(lo + 1..=hi)
            .map_or(0, |nodes| nodes.partition_point(|&xi| xi <= x));
        Some(lo + after)
    }

    /// The values of nodes i − 1 … i + 2, 0 for nodes outside the array (`values` is only
    /// called with indices inside it).
    fn around(&self, values: &impl Fn(usize) -> f64, i: usize) -> [f64; 4] {
        let n = self.x.len();
        let at = |j: usize| if j < n { values(j) } else { 0.0 };
        [
            i.checked_sub(1).map_or(0.0, at),
            at(i),
            at(i + 1),
            at(i + 2),
        ]
    }

    /// Segment i of the spline through `values`, with the slopes of the module docs.
    fn segment(&self, i: usize, values: &impl Fn(usize) -> f64) -> Option<Segment> {
        self.segment_from(i, self.around(values, i))
    }

    /// Segment i from the values of nodes i − 1 … i + 2 (those outside the array unused).
    #[inline(always)]
    fn segment_from(&self, i: usize, [f_before, f0, f1, f_after]: [f64; 4]) -> Option<Segment> {
        let (x0, x1) = (*self.x.get(i)?, *self.x.get(i + 1)?);
        // Slopes by the span's factors w/(x_{i+1} − x_{i−1}) and w/(x_{i+2} − xᵢ): no division
        let span = self.spans.get(i)?;
        let (near, far) = self.slopes(i);
        let d0 = match near {
            Slope::Central => (f1 - f_before) * span.s0,
            Slope::Chord => f1 - f0,
            Slope::Zero => 0.0,
            Slope::Even([k3, k2, k1]) => k3 * f_before + k2 * f0 + k1 * f1,
        };
        let d1 = match far {
            Slope::Central => (f_after - f0) * span.s1,
            Slope::Chord => f1 - f0,
            Slope::Zero => 0.0,
            Slope::Even([k3, k2, k1]) => k3 * f0 + k2 * f1 + k1 * f_after,
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

    /// Weights `w` of nodes `segment` − 1 … `segment` + 2 derived from a spline's, for a
    /// caller that reweights the nodes (the table's energies along ρ′, `table::albedo`). The
    /// entries of nodes outside the array must be 0, as in the weights it derives them from.
    pub(crate) fn from_parts(segment: usize, w: [f64; 4]) -> Self {
        Self { segment, w }
    }

    /// The four weights of nodes i−1 … i+2, 0 for nodes outside the array.
    pub fn as_array(&self) -> [f64; 4] {
        self.w
    }

    /// The (node index, weight) pairs of nodes inside the array with a nonzero weight (nodes
    /// outside it have weight exactly 0).
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> {
        let Weights { segment, w } = *self;
        w.into_iter().enumerate().filter_map(move |(k, weight)| {
            let node = (segment + k).checked_sub(1)?;
            (weight != 0.0).then_some((node, weight))
        })
    }

    /// Σ weight·f(node) over [`Weights::iter`]: the spline through the values `f` at the point.
    pub fn apply(&self, f: impl Fn(usize) -> f64) -> f64 {
        self.iter().map(|(node, weight)| weight * f(node)).sum()
    }
}

impl Span {
    /// Whether segment i (this span, of nodes `x`) is simple: interior (1 ≤ i ≤ n − 3), with
    /// finite 1/wᵢ, s₀ and s₁, and t ≤ 1 without clamping for every x in [xᵢ, x_{i+1}), checked
    /// at the float below x_{i+1} since t increases with x. [`Span::simple_weights`] needs this.
    fn is_simple(&self, i: usize, x: &[f64]) -> bool {
        let interior = i >= 1 && i + 3 <= x.len();
        let finite = [self.inv_width, self.s0, self.s1]
            .iter()
            .all(|f| f.is_finite());
        interior
            && finite
            && x.get(i + 1)
                .is_some_and(|&x1| (crate::float::next_down(x1) - self.x0) * self.inv_width <= 1.0)
    }

    /// t = (x − xᵢ)/wᵢ for x in the span, clamped to [0, 1] (only rounding takes it out).
    fn t(&self, x: f64) -> f64 {
        ((x - self.x0) * self.inv_width).clamp(0.0, 1.0)
    }

    /// [`Span::weights`] at x in a simple span (see [`Span::is_simple`]), bit for bit.
    ///
    /// t = (x − xᵢ)/wᵢ needs no clamp there: x ≥ xᵢ makes it ≥ 0 (or −0 at x = −0, xᵢ = 0,
    /// which the clamp keeps too), and the span is simple, so t ≤ 1. With d = 2t³ − 3t²,
    /// h₀₀ = d + 1 and h₀₁ = −d, and with P = s₀h₁₀, Q = s₁h₁₁ the weights are
    /// (0 − P, h₀₀ − Q, P − d, 0 + Q): the operations of [`Span::weights`] on an interior
    /// segment, but P − d for h₀₁ + P. Those agree bit for bit: rounding is symmetric, so
    /// h₀₁ = −d where d ≠ 0; d = +0 where t² and t³ are +0, and then h₀₁ = +0 and P ≥ +0; and
    /// at t = −0, d = −0 and P = −0, and both give +0. `tests.rs` checks this over many t.
    #[inline]
    fn simple_weights(&self, x: f64) -> [f64; 4] {
        self.interior_weights((x - self.x0) * self.inv_width)
    }

    /// The weights at t ∈ [0, 1] (or −0) on an interior segment with s₀, s₁ ≥ 0, as
    /// [`Span::simple_weights`] computes them.
    #[inline]
    fn interior_weights(&self, t: f64) -> [f64; 4] {
        let (t2, t3) = (t * t, t * t * t);
        let d = 2.0 * t3 - 3.0 * t2;
        let (h10, h11) = (t3 - 2.0 * t2 + t, t3 - t2);
        let (p, q) = (h10 * self.s0, h11 * self.s1);
        [0.0 - p, (d + 1.0) - q, p - d, 0.0 + q]
    }

    /// The weights at t ∈ [0, 1] (or −0) on this segment with the slopes `near` at xᵢ and
    /// `far` at x_{i+1} (see [`Nodes::slopes`]), from the formula of [`Nodes::weights`].
    fn weights(&self, t: f64, near: Slope, far: Slope) -> [f64; 4] {
        let (t2, t3) = (t * t, t * t * t);
        let mut w = [0.0, 2.0 * t3 - 3.0 * t2 + 1.0, -2.0 * t3 + 3.0 * t2, 0.0];
        let (h10, h11) = (t3 - 2.0 * t2 + t, t3 - t2);
        // Slope at xᵢ, over nodes i − 1 … i + 1; at x_{i+1}, over nodes i … i + 2
        add_slope(&mut w, h10, near, self.s0, 0);
        add_slope(&mut w, h11, far, self.s1, 1);
        w
    }
}

/// Adds h times the slope `slope` to the weights `w` of nodes i − 1 … i + 2: a slope over the
/// three nodes from `w[first]` (0 for the slope at xᵢ, 1 at x_{i+1}), `s` the span's factor of
/// its central difference.
fn add_slope(w: &mut [f64; 4], h: f64, slope: Slope, s: f64, first: usize) {
    let nodes = w.get_mut(first..).unwrap_or_default();
    match (slope, nodes) {
        (Slope::Central, [before, _, after, ..]) => {
            *before -= h * s;
            *after += h * s;
        }
        (Slope::Chord, _) => {
            w[1] -= h;
            w[2] += h;
        }
        (Slope::Even(k), nodes) => {
            for (w, k) in nodes.iter_mut().zip(k) {
                *w += h * k;
            }
        }
        _ => {}
    }
}

/// The slope of a segment at one of its ends, in t-units (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Slope {
    /// The central difference, by the span's factor s₀ (at xᵢ) or s₁ (at x_{i+1}).
    Central,
    /// The segment's chord f_{i+1} − fᵢ (at x₀, and at x_{n−1} with [`End::Chord`]).
    Chord,
    /// 0 (at x_{n−1} with [`End::Even`]).
    Zero,
    /// The even end's slope at x_{n−2}: weights of f_{n−3}, f_{n−2}, f_{n−1}.
    Even([f64; 3]),
}

/// The slope at x_{n−2} of the polynomial even about x_{n−1} through the last three nodes,
/// for the even end (module docs), from ρ = δ₁/δ₂ ∈ (0, 1): `[before, last]`, in t-units of
/// segments n − 3 and n − 2, as weights of f_{n−3}, f_{n−2}, f_{n−1}.
fn even_slopes(rho: f64) -> [[f64; 3]; 2] {
    let rho2 = rho * rho;
    let weights = |k3: f64, k2: f64| [k3, k2, -(k2 + k3)];
    let before = weights(
        -2.0 * rho2 * rho / (1.0 + rho),
        -2.0 * (1.0 - 2.0 * rho2) / (rho * (1.0 + rho)),
    );
    let last = weights(
        -2.0 * rho2 * rho2 / (1.0 - rho2),
        -2.0 * (1.0 - 2.0 * rho2) / (1.0 - rho2),
    );
    [before, last]
}

/// x > 0 and finite (false for NaN).
fn positive_finite(x: f64) -> bool {
    x > 0.0 && x < f64::INFINITY
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
