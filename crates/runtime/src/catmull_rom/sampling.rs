//! The sampling triad of [`Nodes`]: [`Nodes::sample`], [`Nodes::pdf`] and [`Nodes::cdf`] of a
//! density shaped like a spline, as described in the module docs of [`super`].

use super::segment::Positive;
use super::{positive_finite, Nodes, Sample};

/// One segment together with the CDF that a caller supplied for it.
#[derive(Debug, Clone, Copy)]
struct Piece {
    positive: Positive,
    /// Cumulative value at the segment's first node.
    c0: f64,
    /// Cumulative increase over the segment, C_{k+1} − C_k.
    dc: f64,
    /// Total, C_{n−1}.
    total: f64,
}

impl Nodes {
    /// Draws x from the density of the spline through `values` (see [`Nodes::pdf`]) by
    /// inverting [`Nodes::cdf`] at `u` ∈ [0, 1].
    ///
    /// `cumulative(k)` is the CDF table Cₖ: normally the running integral written by
    /// [`Nodes::integrate`] or [`Nodes::integrate_positive`] for the same `values`, perhaps
    /// stored rounded or interpolated between table rows. Its last entry is the total T. Find the segment k with Cₖ ≤ u·T < C_{k+1} by binary search, then
    /// solve Cₖ + (C_{k+1} − Cₖ)·P(t)/P(1) = u·T for t by Newton–bisection, where
    /// P(t) = ∫₀ᵗ max(s, 0) dt is the integrated positive part of the segment's cubic.
    ///
    /// Returns `None` if `u` is NaN or outside [0, 1], if T is not positive and finite (for
    /// example all values zero), or if the density at the solution is 0 (for example u = 0
    /// when f₀ = 0). Every returned sample has a positive, finite pdf equal to [`Nodes::pdf`]
    /// at `x` up to rounding, and [`Nodes::cdf`] at `x` gives back `u` up to the solver
    /// tolerance.
    ///
    /// # Sampling a row-interpolated table
    /// Interpolate along the first axis with [`Weights`](super::Weights) and sample along the
    /// second:
    /// ```
    /// use bssrdf_zoo::catmull_rom::Nodes;
    /// # fn main() -> bssrdf_zoo::Result<()> {
    /// let albedo = Nodes::new(vec![0.0, 0.5, 0.9, 1.0])?;
    /// let radius = Nodes::new(vec![0.0, 0.1, 0.3, 1.0, 3.0])?;
    /// let n = radius.as_slice().len();
    /// // One row per albedo node, stored as f32 as a table would be.
    /// let mut profile = Vec::new();
    /// let mut cdf = Vec::new();
    /// for &a in albedo.as_slice() {
    ///     let row: Vec<f64> = radius.as_slice().iter().map(|r| a * r * (-r).exp()).collect();
    ///     let mut row_cdf = vec![0.0; n];
    ///     radius.integrate(|j| row[j], &mut row_cdf);
    ///     profile.extend(row.iter().map(|&v| v as f32));
    ///     cdf.extend(row_cdf.iter().map(|&c| c as f32));
    /// }
    /// let w = albedo.weights(0.7).expect("0.7 is inside the albedo nodes");
    /// let row = |j: usize| w.apply(|i| f64::from(profile[i * n + j]));
    /// let row_cdf = |j: usize| w.apply(|i| f64::from(cdf[i * n + j]));
    /// let s = radius.sample(row, row_cdf, 0.5).expect("the density is positive");
    /// assert!((radius.pdf(row, row_cdf, s.x) - s.pdf).abs() < 1e-9 * s.pdf);
    /// assert!((radius.cdf(row, row_cdf, s.x).unwrap() - 0.5).abs() < 1e-9);
    /// # Ok(())
    /// # }
    /// ```
    pub fn sample(
        &self,
        values: impl Fn(usize) -> f64,
        cumulative: impl Fn(usize) -> f64,
        u: f64,
    ) -> Option<Sample> {
        self.sample_with(|i| self.around(&values, i), cumulative, u, None)
    }

    /// [`Nodes::sample`] with the values read four at a time: `around(i)` gives those of nodes
    /// i − 1 … i + 2 (entries for nodes outside the array are not used), as
    /// [`Nodes::around`] does. A caller that interpolates table rows reads each row once.
    ///
    /// `hint` is a guess of the segment (for a table, the segment of the row with the largest
    /// weight): the search starts there and walks, reading Cₖ at the nodes it passes, instead
    /// of bisecting all the nodes. Any hint gives the same segment wherever C increases; a
    /// good one saves most of the reads of C, which for an interpolated table are the
    /// expensive part of a draw.
    pub(crate) fn sample_with(
        &self,
        around: impl Fn(usize) -> [f64; 4],
        cumulative: impl Fn(usize) -> f64,
        u: f64,
        hint: Option<usize>,
    ) -> Option<Sample> {
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let total = cumulative(self.x.len() - 1);
        if !positive_finite(total) {
            return None;
        }
        let goal = u * total;
        let (k, c0, c1) = match hint {
            Some(hint) => self.find_cumulative_near(&cumulative, goal, total, hint),
            None => self.find_cumulative(&cumulative, goal, total),
        };
        let piece = Piece {
            positive: self.segment_from(k, around(k))?.positive(),
            c0,
            dc: c1 - c0,
            total,
        };
        let positive = piece.positive;
        if !positive_finite(piece.dc) || !positive_finite(positive.mass) {
            return None;
        }
        let share = ((goal - piece.c0) / piece.dc).clamp(0.0, 1.0);
        let segment = &positive.segment;
        let mut t = positive.solve(share * positive.mass);
        let mut x = segment.at(t);
        if x >= segment.x1 && k + 2 < self.x.len() {
            // On the next node [`Nodes::pdf_with`] reads the next segment, whose density may
            // differ (0 where C stops rising, as u → 1 at a tail that underflows): the draw
            // stays in its own segment, a step of one f64 below the node
            x = crate::float::next_down(segment.x1);
            t = segment.t_at(x);
        }
        let pdf = piece.pdf(t);
        if pdf <= 0.0 {
            return None;
        }
        Some(Sample {
            x,
            value: segment.value(t),
            pdf,
        })
    }

    /// The density that [`Nodes::sample`] draws from, per unit of x, at `x`:
    ///
    /// p(x) = (C_{k+1} − Cₖ)·max(s(x), 0)/(wₖ·Pₖ·T) on segment k, with Pₖ = ∫₀¹ max(s, 0) dt.
    ///
    /// Each segment carries the probability (C_{k+1} − Cₖ)/T that the table gives it, spread in
    /// proportion to the positive part of the spline: negative lobes get density 0. With C
    /// from [`Nodes::integrate_positive`] this is max(s(x), 0)/T; with C from
    /// [`Nodes::integrate`] and a spline ≥ 0 it is s(x)/T. A table rounded to f32 only
    /// rescales each segment slightly. Sample, pdf and cdf are an exact triad whenever C never
    /// decreases.
    ///
    /// C can decrease when it comes from [`Nodes::integrate`] and a tail undershoots, or when
    /// table rows are interpolated with Catmull-Rom weights (some are negative). Segments where
    /// it decreases get density 0, and the sampler cannot reach the stretch before them where C
    /// exceeds its later values. Sampler and pdf then disagree by about the total decrease of
    /// C, relative to T (2·10⁻⁷ for the exponential profile of the tests on pbrt's radius
    /// grid).
    ///
    /// Returns 0 for NaN `x`, `x` outside [x₀, x_{n−1}], a total T that is not positive and
    /// finite, and segments where C_{k+1} − Cₖ or Pₖ is not positive.
    pub fn pdf(
        &self,
        values: impl Fn(usize) -> f64,
        cumulative: impl Fn(usize) -> f64,
        x: f64,
    ) -> f64 {
        self.pdf_with(|i| self.around(&values, i), cumulative, x)
    }

    /// [`Nodes::pdf`] with the values read four at a time, as in [`Nodes::sample_with`].
    pub(crate) fn pdf_with(
        &self,
        around: impl Fn(usize) -> [f64; 4],
        cumulative: impl Fn(usize) -> f64,
        x: f64,
    ) -> f64 {
        let total = cumulative(self.x.len() - 1);
        self.find_segment(x)
            .and_then(|k| self.piece(k, &around, &cumulative, total))
            .map_or(0.0, |piece| piece.pdf(piece.positive.segment.t_at(x)))
    }

    /// The CDF of the sampled density at `x`, the inverse of [`Nodes::sample`]: on segment k,
    /// u = (Cₖ + (C_{k+1} − Cₖ)·P(t)/P(1))/T, clamped to [0, 1]; 0 below x₀ and 1 above x_{n−1}.
    ///
    /// On a segment with P(1) ≤ 0, which the sampler never selects, P(t)/P(1) is replaced by t.
    /// `None` if `x` is NaN or the total T is not positive and finite.
    pub fn cdf(
        &self,
        values: impl Fn(usize) -> f64,
        cumulative: impl Fn(usize) -> f64,
        x: f64,
    ) -> Option<f64> {
        let total = cumulative(self.x.len() - 1);
        if x.is_nan() || !positive_finite(total) {
            return None;
        }
        let (first, last) = self.ends();
        if x <= first {
            return Some(0.0);
        }
        if x >= last {
            return Some(1.0);
        }
        let k = self.find_segment(x)?;
        let piece = self.piece(k, &|i| self.around(&values, i), &cumulative, total)?;
        let positive = piece.positive;
        let t = positive.segment.t_at(x);
        let share = if positive_finite(positive.mass) {
            (positive.integral_to(t) / positive.mass).clamp(0.0, 1.0)
        } else {
            t
        };
        Some(((piece.c0 + piece.dc * share) / total).clamp(0.0, 1.0))
    }

    /// The segment k with Cₖ ≤ `goal` < C_{k+1} (as [`super::find_interval`] finds it), with Cₖ and
    /// C_{k+1}: the search has read them already unless k = 0 (C₀ is read then) or
    /// k + 1 = n − 1 (C_{n−1} is `total`).
    fn find_cumulative(
        &self,
        cumulative: &impl Fn(usize) -> f64,
        goal: f64,
        total: f64,
    ) -> (usize, f64, f64) {
        let len = self.x.len();
        Self::bisect_cumulative(cumulative, goal, (1, f64::NAN), (len - 1, total))
    }

    /// Bisection for the segment of `goal` among the nodes lo … hi: the first node i in
    /// [lo, hi] with Cᵢ > `goal` ends segment i − 1, where node hi counts as above `goal` (it is
    /// known to be, or is the last node). `below` is C_{lo−1} if known (NaN if not: it is read
    /// when needed), `above` is C_hi.
    fn bisect_cumulative(
        cumulative: &impl Fn(usize) -> f64,
        goal: f64,
        (mut lo, below): (usize, f64),
        (mut hi, above): (usize, f64),
    ) -> (usize, f64, f64) {
        let first = lo;
        let (mut c_below, mut c_above) = (below, above);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            let c = cumulative(mid);
            if c <= goal {
                (lo, c_below) = (mid + 1, c);
            } else {
                (hi, c_above) = (mid, c);
            }
        }
        let k = lo - 1;
        if lo == first && c_below.is_nan() {
            c_below = cumulative(k);
        }
        (k, c_below, c_above)
    }

    /// [`Nodes::find_cumulative`] started from segment `hint`: reads C at its two nodes, walks
    /// at most two segments towards `goal`, and bisects what is left beyond. Where C increases,
    /// exactly one segment k (0 ≤ k ≤ n − 2) has (k = 0 or Cₖ ≤ goal) and
    /// (k = n − 2 or goal < C_{k+1}), and both searches return it; where C decreases somewhere,
    /// either may return another segment that also satisfies both conditions.
    fn find_cumulative_near(
        &self,
        cumulative: &impl Fn(usize) -> f64,
        goal: f64,
        total: f64,
        hint: usize,
    ) -> (usize, f64, f64) {
        let last = self.x.len() - 1;
        let c = |i: usize| if i == last { total } else { cumulative(i) };
        let mut k = hint.min(last - 1);
        let (mut c0, mut c1) = (cumulative(k), c(k + 1));
        for _ in 0..2 {
            if k > 0 && goal < c0 {
                (k, c1) = (k - 1, c0);
                c0 = cumulative(k);
            } else if k + 1 < last && c1 <= goal {
                (k, c0) = (k + 1, c1);
                c1 = c(k + 1);
            } else {
                return (k, c0, c1);
            }
        }
        if k > 0 && goal < c0 {
            // Below node k, which is above goal
            Self::bisect_cumulative(cumulative, goal, (1, f64::NAN), (k, c0))
        } else if k + 1 < last && c1 <= goal {
            // Beyond node k + 1, which is at most goal
            Self::bisect_cumulative(cumulative, goal, (k + 2, c1), (last, total))
        } else {
            (k, c0, c1)
        }
    }

    /// Segment k with its cumulative values.
    fn piece(
        &self,
        k: usize,
        around: &impl Fn(usize) -> [f64; 4],
        cumulative: &impl Fn(usize) -> f64,
        total: f64,
    ) -> Option<Piece> {
        let positive = self.segment_from(k, around(k))?.positive();
        let c0 = cumulative(k);
        Some(Piece {
            positive,
            c0,
            dc: cumulative(k + 1) - c0,
            total,
        })
    }
}

impl Piece {
    /// The sampled density at parameter t, ΔC·max(s(t), 0)/(w·P(1)·T), or 0 where the
    /// segment cannot be sampled.
    fn pdf(&self, t: f64) -> f64 {
        let Positive { segment, mass, .. } = self.positive;
        if !positive_finite(self.dc) || !positive_finite(mass) || !positive_finite(self.total) {
            return 0.0;
        }
        let p = self.dc * segment.value(t).max(0.0) / (segment.width() * mass * self.total);
        if positive_finite(p) {
            p
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Nodes;

    /// Where C stops rising before the last node (a tail's increments below the f32 rounding
    /// of a table's total), draws with u next to 1 reach the end of the last segment that
    /// holds mass: they stay below its right node, whose own segment has density 0, and their
    /// density is `pdf`'s there. (u = 1 itself finds the flat last segment and draws nothing.)
    #[test]
    fn draws_at_the_end_of_the_mass_have_pdf_s_density() {
        let nodes = Nodes::new(vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]).expect("increasing nodes");
        let values = [0.0, 0.0, 1e-3, 1.0, 1.0, 0.0];
        let mut c = [0.0; 6];
        nodes
            .integrate_positive(|k| values[k], &mut c)
            .expect("a positive total");
        (c[4], c[5]) = (c[3], c[3]);
        for u in [1.0 - f64::EPSILON / 2.0, 1.0 - f64::EPSILON, 1.0 - 1e-12] {
            let s = nodes.sample(|k| values[k], |k| c[k], u).expect("a draw");
            let pdf = nodes.pdf(|k| values[k], |k| c[k], s.x);
            assert!(s.x < 3.0 && s.pdf > 0.0, "u = {u}: {s:?}");
            assert!(
                (s.pdf / pdf - 1.0).abs() < 1e-9,
                "u = {u}: {s:?}, pdf {pdf}"
            );
        }
    }

    /// The hinted search returns the bisection's segment and cumulative values for every hint
    /// and every goal, node values and the ends included, where C increases.
    #[test]
    fn hinted_search_agrees_with_bisection() {
        let nodes = Nodes::new((0..12).map(|i| f64::from(i).powf(1.5)).collect::<Vec<_>>())
            .expect("increasing nodes");
        let c: Vec<f64> = (0..12).map(|i| f64::from(i * i) + f64::from(i)).collect();
        let total = c[11];
        let cumulative = |k: usize| c[k];
        let goals = (0..=200)
            .map(|j| total * f64::from(j) / 200.0)
            .chain(c.iter().copied());
        for goal in goals {
            let want = nodes.find_cumulative(&cumulative, goal, total);
            for hint in 0..14 {
                let got = nodes.find_cumulative_near(&cumulative, goal, total, hint);
                assert_eq!(got, want, "goal {goal}, hint {hint}");
            }
        }
    }

    /// Where C decreases, the hinted search still returns a segment that brackets the goal.
    #[test]
    fn hinted_search_brackets_the_goal_where_the_cdf_dips() {
        let nodes = Nodes::new((0..8).map(f64::from).collect::<Vec<_>>()).expect("nodes");
        let c = [0.0, 1.0, 3.0, 2.5, 4.0, 6.0, 5.9, 8.0];
        let cumulative = |k: usize| c[k];
        for j in 0..=80 {
            let goal = 8.0 * f64::from(j) / 80.0;
            for hint in 0..8 {
                let (k, c0, c1) = nodes.find_cumulative_near(&cumulative, goal, 8.0, hint);
                assert!(k <= 6);
                assert_eq!((c0, c1), (c[k], c[k + 1]));
                assert!(k == 0 || c0 <= goal, "goal {goal}, hint {hint}: C_k = {c0}");
                assert!(
                    k == 6 || goal < c1,
                    "goal {goal}, hint {hint}: C_k+1 = {c1}"
                );
            }
        }
    }
}
