//! Subsets of albedo rows: a table that keeps only the ρ′ rows a scene needs, and baking just
//! those rows.
//!
//! # Which rows keep lookups bit-identical
//! A lookup at ρ′ blends the nodes of its Catmull-Rom segment i (xᵢ ≤ ρ′ < x_{i+1}) and one
//! neighbour on each side, nodes i − 1 … i + 2, with weights computed from those four node
//! positions alone ([`crate::catmull_rom::Nodes::weights`]): the end slopes use the central
//! differences over (x_{i−1}, x_{i+1}) and (xᵢ, x_{i+2}), or one-sided differences where node
//! i − 1 or i + 2 does not exist. A subset whose axis started at node i (not at node 0) would
//! take the one-sided slope on its first segment and change the weights. So for every declared
//! interval [lo, hi] with lo in segment a and hi in segment b of the full axis, the subset keeps
//! nodes a − 1 … b + 2 (clamped to the axis): two nodes on each side of every point of the
//! interval, where they exist. Then every segment met inside the interval is a segment of the
//! full axis with the same four nodes, the same x values, hence the same weights bit for bit;
//! each row's values (E, E_β, c, the radial CDF and the θ CDF) depend only on its own ρ′, so
//! evaluation, sampling and the pdfs inside the interval are bit-identical to the full table's.
//! The factors (ρ′/ρ′ᵢ)² that scale the weights (`table::albedo`) depend on those nodes alone
//! too, except next to a node ρ′₀ = 0: in segments 0 and 1 node 0's weight moves to nodes 1–4,
//! by coefficients from those four positions, so there the subset keeps nodes 0 … 4 (node 0
//! tells it to move the weight).
//! (A point exactly at node x_{b+1} belongs to segment b + 1, whose nodes b … b + 3 the subset
//! may lack: the interval's `hi` is handled by its own segment, so only points of [lo, hi] are
//! covered, and the tests check the ends themselves.)
//!
//! Between an interval's end and the subset's first or last node, lookups still interpolate
//! (with one-sided end slopes, no longer bit-identical); beyond the subset's axis they return
//! `None`, never an extrapolation. Intervals whose rows overlap or touch are merged into one run
//! of consecutive rows; disjoint runs become separate tables (a run with a gap inside would
//! interpolate across the gap).
//!
//! # Baking only the needed rows
//! Every (ρ′, θ) row of a bake is computed independently (PBD at its nodes, the fit, the
//! radial CDF of the row, the θ CDF of the ρ′ row), so [`bake_rows`] bakes a run of rows in
//! blocks with [`super::bake`] on a grid holding only those albedo nodes and concatenates them:
//! the result equals the same rows of a full bake bit for bit (tested), at the cost of the rows
//! kept, and the blocks give a progress callback.

use super::albedo::FOLD_NODES;
use super::{AngularTable, Axes, TableError, HARMONICS_PER_NODE, PARAMS_PER_NODE};
use crate::catmull_rom::Nodes;
use std::ops::Range;

/// A closed interval of reduced albedo ρ′ ∈ [lo, hi] ⊂ [0, 1] (dimensionless); `lo = hi` for a
/// constant albedo.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RhoInterval {
    lo: f64,
    hi: f64,
}

impl RhoInterval {
    /// Validates 0 ≤ lo ≤ hi ≤ 1, both numbers (NaN is rejected).
    pub fn new(lo: f64, hi: f64) -> Result<Self, SubsetError> {
        for value in [lo, hi] {
            if value.is_nan() {
                return Err(SubsetError::NotANumber);
            }
            if !(0.0..=1.0).contains(&value) {
                return Err(SubsetError::OutsideUnit { value });
            }
        }
        if lo > hi {
            return Err(SubsetError::Reversed { lo, hi });
        }
        Ok(Self { lo, hi })
    }
    /// The single albedo `value`.
    pub fn point(value: f64) -> Result<Self, SubsetError> {
        Self::new(value, value)
    }
    /// Lower end.
    pub fn lo(&self) -> f64 {
        self.lo
    }
    /// Upper end.
    pub fn hi(&self) -> f64 {
        self.hi
    }
    /// The smallest interval holding both.
    pub fn union(&self, other: &RhoInterval) -> RhoInterval {
        RhoInterval {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }
}

/// Why a subset of albedo rows was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SubsetError {
    /// A reduced albedo is NaN.
    #[error("reduced albedo is NaN; it must be a number in [0, 1]")]
    NotANumber,
    /// A reduced albedo lies outside [0, 1].
    #[error("reduced albedo {value} is outside [0, 1]")]
    OutsideUnit { value: f64 },
    /// An interval's ends are in decreasing order.
    #[error("albedo range [{lo}, {hi}] is reversed: min must be <= max")]
    Reversed { lo: f64, hi: f64 },
    /// An interval is not covered by the table's albedo axis.
    #[error("reduced albedo {value} is outside the table's albedo axis [{first}, {last}]")]
    OutsideAxis { value: f64, first: f64, last: f64 },
    /// A row range is empty, has a single row (a spline needs two) or runs past the axis.
    #[error("albedo rows {start}..{end} are not a run of at least 2 of the table's {rows} rows")]
    Rows {
        start: usize,
        end: usize,
        rows: usize,
    },
    /// Tables to join do not share η, Fresnel moments, θ and r axes, or their ρ′ rows overlap.
    #[error("tables to join differ: {0}")]
    Mismatch(&'static str),
    /// The table assembled from the rows was rejected.
    #[error(transparent)]
    Table(#[from] TableError),
    /// Baking the rows (or building their axes) failed.
    #[error(transparent)]
    Library(#[from] crate::Error),
}

/// The rows `a − 1 … b + 2` (clamped) that keep lookups inside `interval` bit-identical, where
/// a and b are the full axis's segments of its ends, and at least rows 0 … 4 if a ≤ 1 and
/// ρ′₀ = 0 (see the module docs).
pub fn rows_for(axis: &Nodes, interval: RhoInterval) -> Result<Range<usize>, SubsetError> {
    let nodes = axis.as_slice();
    let n = nodes.len();
    let segment = |value: f64| {
        axis.weights(value)
            .map(|w| w.segment())
            .ok_or(SubsetError::OutsideAxis {
                value,
                first: nodes.first().copied().unwrap_or(f64::NAN),
                last: nodes.last().copied().unwrap_or(f64::NAN),
            })
    };
    let (a, b) = (segment(interval.lo)?, segment(interval.hi)?);
    let end = if a <= 1 && nodes.first() == Some(&0.0) {
        (b + 3).max(FOLD_NODES + 1)
    } else {
        b + 3
    };
    Ok(a.saturating_sub(1)..end.min(n))
}

/// Sorts row ranges and merges those that overlap or touch into runs of consecutive rows.
pub fn merge_runs(ranges: impl IntoIterator<Item = Range<usize>>) -> Vec<Range<usize>> {
    let mut ranges: Vec<Range<usize>> = ranges.into_iter().filter(|r| !r.is_empty()).collect();
    ranges.sort_by_key(|r| (r.start, r.end));
    let mut runs: Vec<Range<usize>> = Vec::with_capacity(ranges.len());
    for r in ranges {
        match runs.last_mut() {
            Some(last) if r.start <= last.end => last.end = last.end.max(r.end),
            _ => runs.push(r),
        }
    }
    runs
}

/// The merged runs of rows for several intervals (see [`rows_for`] and [`merge_runs`]).
pub fn kept_rows(
    axis: &Nodes,
    intervals: &[RhoInterval],
) -> Result<Vec<Range<usize>>, SubsetError> {
    let ranges = intervals
        .iter()
        .map(|&i| rows_for(axis, i))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(merge_runs(ranges))
}

/// Checks that `rows` is a run of at least 2 of `n` albedo rows.
pub fn check_rows(rows: &Range<usize>, n: usize) -> Result<(), SubsetError> {
    if rows.start + 2 > rows.end || rows.end > n {
        return Err(SubsetError::Rows {
            start: rows.start,
            end: rows.end,
            rows: n,
        });
    }
    Ok(())
}

impl AngularTable {
    /// The table restricted to the albedo rows `rows` (at least 2), every array copied as is:
    /// lookups inside intervals whose [`rows_for`] lies within `rows` are bit-identical.
    pub fn subset_rows(&self, rows: Range<usize>) -> Result<AngularTable, SubsetError> {
        let (n_rho, n_theta, n_r) = self.axes().dims();
        check_rows(&rows, n_rho)?;
        let node = n_theta * n_r;
        let axes = Axes::new(
            self.axes().rho().as_slice()[rows.clone()].to_vec(),
            self.axes().theta().as_slice().to_vec(),
            self.axes().r().as_slice().to_vec(),
        )?;
        let slice = |data: &[f32], per_row: usize| -> Vec<f32> {
            data[rows.start * per_row..rows.end * per_row].to_vec()
        };
        let table = AngularTable::from_parts(
            self.eta(),
            self.moments(),
            axes,
            slice(self.params(), node * PARAMS_PER_NODE),
            slice(self.radial_cdf(), node),
            self.theta_cdf().map(|t| slice(t, n_theta)),
        )?;
        let table = match self.harmonics() {
            Some(h) => {
                table.with_harmonics_by(slice(h, node * HARMONICS_PER_NODE), self.rebuild())?
            }
            None => table,
        };
        Ok(with_walk_of(table, self.walk()).with_ridge(self.ridge()))
    }

    /// The same table without the θ-sampling CDF (for renderers that only particle-trace).
    pub fn without_theta_sampling(&self) -> Result<AngularTable, SubsetError> {
        let table = AngularTable::from_parts(
            self.eta(),
            self.moments(),
            self.axes().clone(),
            self.params().to_vec(),
            self.radial_cdf().to_vec(),
            None,
        )?;
        let table = match self.harmonics() {
            Some(h) => table.with_harmonics_by(h.to_vec(), self.rebuild())?,
            None => table,
        };
        Ok(with_walk_of(table, self.walk()).with_ridge(self.ridge()))
    }

    /// Joins tables holding consecutive albedo rows of the same bake (same η, moments, θ and r
    /// axes, walk, ridge kind, increasing ρ′, all with or all without the θ CDF) into one.
    pub fn concat_rows(parts: &[AngularTable]) -> Result<AngularTable, SubsetError> {
        let first = parts.first().ok_or(SubsetError::Mismatch("no tables"))?;
        let mut rho: Vec<f64> = Vec::new();
        let (mut params, mut radial, mut theta) = (Vec::new(), Vec::new(), Vec::new());
        let mut harmonics = Vec::new();
        for p in parts {
            if p.eta().to_bits() != first.eta().to_bits() || p.moments() != first.moments() {
                return Err(SubsetError::Mismatch("eta or Fresnel moments"));
            }
            if p.axes().theta() != first.axes().theta() || p.axes().r() != first.axes().r() {
                return Err(SubsetError::Mismatch("theta or r axis"));
            }
            if p.theta_cdf().is_some() != first.theta_cdf().is_some() {
                return Err(SubsetError::Mismatch("theta-sampling table"));
            }
            if p.harmonics().is_some() != first.harmonics().is_some() {
                return Err(SubsetError::Mismatch("number of lobes"));
            }
            if p.rebuild() != first.rebuild() {
                return Err(SubsetError::Mismatch("rebuild of the lobes (merged roots)"));
            }
            if p.walk() != first.walk() {
                return Err(SubsetError::Mismatch("model or walk (g, component)"));
            }
            if p.ridge() != first.ridge() {
                return Err(SubsetError::Mismatch(
                    "ridge kind (none, flux, flux+fluence)",
                ));
            }
            rho.extend_from_slice(p.axes().rho().as_slice());
            params.extend_from_slice(p.params());
            radial.extend_from_slice(p.radial_cdf());
            theta.extend_from_slice(p.theta_cdf().unwrap_or(&[]));
            harmonics.extend_from_slice(p.harmonics().unwrap_or(&[]));
        }
        // Nodes::new rejects rows that do not increase across the parts.
        let axes = Axes::new(
            rho,
            first.axes().theta().as_slice().to_vec(),
            first.axes().r().as_slice().to_vec(),
        )
        .map_err(|_| SubsetError::Mismatch("albedo rows must increase across the tables"))?;
        let table = AngularTable::from_parts(
            first.eta(),
            first.moments(),
            axes,
            params,
            radial,
            first.theta_cdf().map(|_| theta),
        )?;
        let table = match first.harmonics() {
            Some(_) => table.with_harmonics_by(harmonics, first.rebuild())?,
            None => table,
        };
        Ok(with_walk_of(table, first.walk()).with_ridge(first.ridge()))
    }
}

/// `table` marked with the walk of the table it was cut from, if that one had one.
fn with_walk_of(table: AngularTable, walk: Option<crate::format::WalkSource>) -> AngularTable {
    match walk {
        Some(walk) => table.with_walk(walk),
        None => table,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis() -> Nodes {
        Nodes::new((0..10).map(|i| f64::from(i) / 9.0).collect::<Vec<_>>()).unwrap()
    }

    #[test]
    fn intervals_reject_nan_outside_and_reversed() {
        assert_eq!(
            RhoInterval::new(f64::NAN, 0.5),
            Err(SubsetError::NotANumber)
        );
        assert_eq!(
            RhoInterval::new(0.2, 1.5),
            Err(SubsetError::OutsideUnit { value: 1.5 })
        );
        assert_eq!(
            RhoInterval::new(-0.1, 0.5),
            Err(SubsetError::OutsideUnit { value: -0.1 })
        );
        assert_eq!(
            RhoInterval::new(0.6, 0.5),
            Err(SubsetError::Reversed { lo: 0.6, hi: 0.5 })
        );
        assert!(RhoInterval::point(1.0).is_ok());
    }

    #[test]
    fn rows_keep_two_nodes_each_side_where_they_exist() {
        let a = axis();
        let r = |lo, hi| rows_for(&a, RhoInterval::new(lo, hi).unwrap()).unwrap();
        // 0.5 lies in segment 4 ([4/9, 5/9]): nodes 3 … 6.
        assert_eq!(r(0.5, 0.5), 3..7);
        // At the first node, ρ′ = 0: segment 0, whose node 0 moves its weight to nodes 1–4
        // (`table::albedo`).
        assert_eq!(r(0.0, 0.0), 0..5);
        // At the last node: last segment 8, nodes 7 … 9.
        assert_eq!(r(1.0, 1.0), 7..10);
        // Exactly at an interior node (4/9): its segment is 4, so nodes 3 … 6.
        assert_eq!(r(4.0 / 9.0, 4.0 / 9.0), 3..7);
        assert_eq!(r(0.15, 0.5), 0..7);
    }

    #[test]
    fn runs_merge_when_they_overlap_or_touch() {
        assert_eq!(merge_runs([5..8, 0..3, 2..4]), vec![0..4, 5..8]);
        assert_eq!(merge_runs([0..3, 3..6]), vec![0..6]);
        assert_eq!(merge_runs(vec![4..4, 6..6]), Vec::<Range<usize>>::new());
    }

    #[test]
    fn outside_the_axis_is_an_error_naming_the_value() {
        let a = Nodes::new(vec![0.2, 0.4, 0.6]).unwrap();
        let err = rows_for(&a, RhoInterval::point(0.9).unwrap()).unwrap_err();
        assert_eq!(
            err,
            SubsetError::OutsideAxis {
                value: 0.9,
                first: 0.2,
                last: 0.6
            }
        );
        assert!(err.to_string().contains("0.9"));
    }
}
