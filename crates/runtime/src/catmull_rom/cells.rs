//! Keyed cells for the segment search of [`super::Nodes`]: a monotone key of x picks a cell
//! that holds at most one node, so that the segment of x is one table read and one comparison,
//! with no search loop and no branch on the data. Node sets where no key below separates the
//! nodes within [`CELLS_PER_NODE`] cells per node fall back to the guide (`guide.rs`).
//!
//! # The key
//! u = x + β and key(x) = (bits(u) >> s) − base, where bits is the IEEE 754 bit pattern and
//! s = 52 − m. Within one binade the bit pattern is linear in |u|, so the key cuts each binade
//! of u into 2^m equal cells; across binades it follows log₂|u|. The sign bit is the top bit,
//! so the bit pattern increases with u where u > 0 and decreases where u < 0. Rounding is
//! monotone, so with u of one sign over [x₀, x_{n−1}] the key is monotone in x. The candidates:
//! - β = δ − x₀, u ≈ x − x₀ + δ > 0, with δ a power-of-2 multiple of the first spacing: cells
//!   2^−m octaves of u wide, fine near x₀ where a geometric grid crowds (the table's radii);
//!   or with δ a power-of-2 multiple of x_{n−1} − x₀: u spans a binade or two, so the cells
//!   have about equal widths, for nodes spaced about uniformly (the table's angles);
//! - β = −(x_{n−1} + δ), u ≈ −(x_{n−1} − x + δ) < 0, the same with δ from the last spacing
//!   (fine near x_{n−1}, where the table's albedos crowd) or from x_{n−1} − x₀.
//!
//! β is never −0, so x = −0 and x = +0 have the same u. Each candidate takes the smallest m
//! that gives every node its own cell; the table keeps the candidate with the fewest cells.
//!
//! # The cells
//! Since the key is monotone, the nodes whose key comes before the cell of x (in the direction
//! of x) all lie below x and those whose key comes after all lie above it; only a node in the
//! cell itself can lie on either side. With L nodes before the cell, the segment of x is
//! therefore L − 1, plus 1 if x reaches the node in the cell: each cell stores L and `upper`,
//! and the segment is L − 1 + [x ≥ upper], with
//! - no node in the cell: upper = +∞ (never reached);
//! - x₀ in the cell: L = 0, upper = x₀, so x < x₀ gives segment −1;
//! - x_{n−1} in the cell: L = n − 1, upper = the float after x_{n−1}, so x = x_{n−1} gives the
//!   last segment and x > x_{n−1} gives segment n − 1;
//! - otherwise node L: upper = x_L.
//!
//! Segments −1 and n − 1 do not exist, so a bounds check on the segment is the range check.
//! An x whose key falls outside the table is outside [x₀, x_{n−1}] or NaN: u of a NaN is a
//! NaN and u of ±∞ is ±∞, whose bit patterns (exponent all ones, either sign) lie outside
//! those of the finite u of one sign that the table covers.
//!
//! # Hot cells
//! [`super::Nodes::weights`] has a short path for the common case: a cell whose segments (one,
//! or two around its node) are all *simple* — interior, with finite factors, and with t ≤ 1
//! over the segment without clamping (the caller decides). Such a cell also stores
//! `hot` = L − 1, so that the segment is `hot` + [x ≥ upper] with no other test; every other
//! cell stores a `hot` that takes the segment out of bounds, sending x to the general path.

use crate::float::next_up;

/// Largest number of cells per node (16 bytes each).
pub(super) const CELLS_PER_NODE: usize = 8;

/// Finest resolution tried, in mantissa bits (2²⁰ cells per binade of u).
const MAX_MANTISSA_BITS: u32 = 20;

/// Bits of the f64 mantissa.
const MANTISSA_BITS: u32 = 52;

/// The offsets δ tried are a spacing times 2^j, j in this range.
const OFFSET_EXPONENTS: std::ops::RangeInclusive<i32> = -4..=4;

/// `hot` of a cell with a segment that is not simple: `hot` + 0 or 1 is out of bounds (the
/// table has fewer nodes, and it does not wrap where usize is 32 bits).
const NOT_HOT: u32 = u32::MAX - 1;

/// One cell (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Cell {
    /// The node in the cell (the float after it for x_{n−1}), +∞ if there is none.
    upper: f64,
    /// L − 1 if the cell's segments are simple, else [`NOT_HOT`].
    hot: u32,
    /// L, the number of nodes before the cell.
    before: u32,
}

impl Cell {
    /// The segment of x in the cell: −1 (wrapped) below x₀, n − 1 above x_{n−1}.
    #[inline]
    pub(super) fn segment(&self, x: f64) -> usize {
        (self.before as usize + usize::from(x >= self.upper)).wrapping_sub(1)
    }

    /// The segment of x in the cell if the cell is hot, else an index out of bounds.
    #[inline]
    pub(super) fn hot_segment(&self, x: f64) -> usize {
        self.hot as usize + usize::from(x >= self.upper)
    }
}

/// The key and the cells of one node set (see the module docs); no cells when no key works.
#[derive(Debug, Clone)]
pub(super) struct Cells {
    beta: f64,
    /// Right shift of the bit pattern of u: 52 − m.
    shift: u32,
    /// Shifted bit pattern of u at the end of [x₀, x_{n−1}] where it is smallest.
    base: u64,
    cells: Box<[Cell]>,
}

impl Cells {
    /// The cells of strictly increasing, finite nodes `x` (at least 2) whose segments i with
    /// `simple(i)` may be hot, or an empty table (every key misses it) if no candidate key
    /// separates the nodes within the cell budget or the nodes are too many for u32 counts.
    pub(super) fn new(x: &[f64], simple: impl Fn(usize) -> bool) -> Self {
        if x.len() >= NOT_HOT as usize {
            return Self::empty();
        }
        let best = Self::candidates(x)
            .filter_map(|beta| Self::finest(x, beta))
            .min_by_key(|(_, keys)| count(keys));
        match best {
            Some((mut cells, keys)) => {
                cells.cells = fill(x, &keys, simple);
                cells
            }
            None => Self::empty(),
        }
    }

    /// No cells: every key misses.
    fn empty() -> Self {
        Self {
            beta: 0.0,
            shift: 0,
            base: 0,
            cells: Box::new([]),
        }
    }

    /// Whether the table is empty (every key misses it).
    pub(super) fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The cell of x, or `None` if its key misses the table (always for NaN and ±∞).
    #[inline]
    pub(super) fn get(&self, x: f64) -> Option<&Cell> {
        self.cells.get(self.key(x)?)
    }

    /// (bits(x + β) >> s) − base, wrapping; `None` only where usize is narrower than u64.
    #[inline]
    fn key(&self, x: f64) -> Option<usize> {
        let u = x + self.beta;
        usize::try_from((u.to_bits() >> self.shift).wrapping_sub(self.base)).ok()
    }

    /// The β of the candidate keys of the module docs.
    fn candidates(x: &[f64]) -> impl Iterator<Item = f64> + '_ {
        let n = x.len();
        let (first, last) = (x[0], x[n - 1]);
        let range = last - first;
        let (d_first, d_last) = (x[1] - first, last - x[n - 2]);
        OFFSET_EXPONENTS.flat_map(move |j| {
            let scale = 2f64.powi(j);
            [
                d_first * scale - first,
                range * scale - first,
                -(last + d_last * scale),
                -(last + range * scale),
            ]
        })
    }

    /// The key with this β and the smallest m that gives every node its own cell within the
    /// budget (its table still empty), with the nodes' keys; `None` if there is none.
    fn finest(x: &[f64], beta: f64) -> Option<(Self, Vec<usize>)> {
        let n = x.len();
        // +0, not −0, so that u(−0) = u(+0)
        let beta = if beta == 0.0 { 0.0 } else { beta };
        let (u_first, u_last) = (x[0] + beta, x[n - 1] + beta);
        // Finite, and of one sign over [x₀, x_{n−1}] (monotone: the ends suffice); u is −0
        // only for x = −0 and β = −0
        let positive = u_first >= 0.0 && u_last >= 0.0;
        let negative = u_first < 0.0 && u_last < 0.0;
        if !(beta.is_finite() && u_first.is_finite() && u_last.is_finite())
            || !(positive || negative)
        {
            return None;
        }
        let (low, high) = {
            let (a, b) = (u_first.to_bits(), u_last.to_bits());
            (a.min(b), a.max(b))
        };
        let budget = (CELLS_PER_NODE * n).max(32) as u64;
        (0..=MAX_MANTISSA_BITS).find_map(|m| {
            let shift = MANTISSA_BITS - m;
            let base = low >> shift;
            if (high >> shift) - base >= budget {
                return None;
            }
            let cells = Self {
                beta,
                shift,
                base,
                cells: Box::new([]),
            };
            let keys: Vec<usize> = x.iter().map(|&xi| cells.key(xi)).collect::<Option<_>>()?;
            let distinct = keys.windows(2).all(|pair| pair[0] != pair[1]);
            distinct.then_some((cells, keys))
        })
    }
}

/// The number of cells from the nodes' keys (one end's key is 0).
fn count(keys: &[usize]) -> usize {
    keys.iter().max().map_or(0, |&k| k + 1)
}

/// The cells of the module docs from the nodes' keys (distinct and monotone).
fn fill(x: &[f64], keys: &[usize], simple: impl Fn(usize) -> bool) -> Box<[Cell]> {
    let n = x.len();
    let increasing = keys.first() < keys.last();
    (0..count(keys))
        .map(|c| {
            // Nodes before cell c in the direction of x, and the node in it
            let before = keys.partition_point(|&k| if increasing { k < c } else { k > c });
            let upper = match keys.get(before) {
                Some(&k) if k == c && before == n - 1 => next_up(x[n - 1]),
                Some(&k) if k == c => x[before],
                _ => f64::INFINITY,
            };
            // Segments L − 1, and L if the cell holds a node (counts fit u32: see `new`)
            let with_node = usize::from(upper < f64::INFINITY);
            let hot = before
                .checked_sub(1)
                .is_some_and(|lo| (lo..=lo + with_node).all(&simple));
            Cell {
                upper,
                hot: if hot { (before - 1) as u32 } else { NOT_HOT },
                before: before as u32,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{Cells, CELLS_PER_NODE, NOT_HOT};
    use crate::float::{next_down, next_up};

    /// The default table's axes as the bake builds them (f32-rounded).
    fn default_axes() -> [Vec<f64>; 3] {
        let grid = bssrdf_zoo::table::Grid::preset(bssrdf_zoo::table::GridPreset::Default);
        let round = |v: &[f64]| v.iter().map(|&x| f64::from(x as f32)).collect();
        [round(&grid.rho), round(&grid.theta), round(&grid.r)]
    }

    /// Each default axis gets cells within the budget, and the midpoints of its interior
    /// segments are in hot cells, but for those sharing a cell with node 1 or n − 2 (the
    /// cell's other segment is an end one).
    #[test]
    fn default_axes_get_cells() {
        for x in default_axes() {
            let n = x.len();
            let cells = Cells::new(&x, |i| (1..n - 2).contains(&i));
            assert!(!cells.is_empty(), "{x:?}");
            assert!(
                cells.cells.len() <= CELLS_PER_NODE * n,
                "{}",
                cells.cells.len()
            );
            let hot: Vec<usize> = (1..n - 2)
                .filter(|&i| {
                    let mid = 0.5 * (x[i] + x[i + 1]);
                    cells.get(mid).map(|c| c.hot_segment(mid)) == Some(i)
                })
                .collect();
            assert!(hot.len() + 2 >= n - 3, "{hot:?} of {x:?}");
        }
    }

    /// Cells give the segment of each node and of the floats next to it (−1 below x₀, n − 1
    /// above x_{n−1}, as a count of the nodes ≤ x gives it); a key that misses means outside.
    #[test]
    fn cells_give_the_segment() {
        let grids = default_axes().into_iter().chain([
            vec![0.0, 1.0],
            vec![-3.0, -1.0, -0.5, 2.0],
            vec![-2.0, -1.0],
            vec![1e-300, 1e-299, 1e-298],
            vec![1e6, 1e6 + 0.5, 1e6 + 3.0],
        ]);
        for x in grids {
            let (n, first, last) = (x.len(), x[0], x[x.len() - 1]);
            let cells = Cells::new(&x, |_| false);
            assert!(!cells.is_empty(), "{x:?}");
            let want = |v: f64| match x.iter().filter(|&&xi| xi <= v).count() {
                _ if v == last => n - 2,
                count => count.wrapping_sub(1),
            };
            for v in x.iter().flat_map(|&xj| [next_down(xj), xj, next_up(xj)]) {
                match cells.get(v) {
                    Some(cell) => assert_eq!(cell.segment(v), want(v), "{v:e} on {x:?}"),
                    None => assert!(v < first || v > last, "{v:e} on {x:?}"),
                }
                // No cell is hot when no segment is simple
                assert!(cells.get(v).is_none_or(|cell| cell.hot == NOT_HOT));
            }
            for v in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                assert!(cells.get(v).is_none(), "{v} on {x:?}");
            }
        }
    }

    /// Nodes too close for any key within the budget get no cells.
    #[test]
    fn crowded_nodes_get_no_cells() {
        let x = [0.0, 1.0, 1.0 + f64::EPSILON, 1.0 + 2.0 * f64::EPSILON, 2.0];
        assert!(Cells::new(&x, |_| true).is_empty());
    }
}
