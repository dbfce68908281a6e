//! A guide for the segment search of [`super::Nodes`]: cells over x, each with the range of
//! segments that can hold its points, so that finding the segment of x is one table read and,
//! usually, at most one comparison instead of a binary search over all the nodes. Only node
//! sets that the keyed cells (`cells.rs`) cannot separate use it.
//!
//! For v ≥ 0 the IEEE 754 bit pattern of v increases with v, and shifted right to keep the
//! exponent and the top m bits of the mantissa it is a piecewise-linear approximation of
//! 2^m·log₂ v. Keys of that kind are cells 2^−m octaves wide wherever v lies. Taken of v = x
//! they are fine near 0, where a geometric grid (the table's radii) crowds its nodes; taken of
//! v = x_{n−1} − x they are fine near the last node, where the albedo nodes crowd; and either
//! is narrower than the spacing of a uniform grid (the table's angles) after its first few
//! nodes. The guide takes the finest m within [`CELLS_PER_NODE`] cells per node for each
//! orientation and keeps the one whose fullest cell holds fewer nodes; where nodes still share
//! a cell, the search ends with a binary search among them.
//!
//! Cells come from evaluating the key at the nodes only: since rounding is monotone, so is the
//! key, and segment i (xᵢ ≤ x < x_{i+1}) meets exactly the cells from key(xᵢ) to key(x_{i+1}).

/// Largest number of cells per node (4 bytes each).
const CELLS_PER_NODE: usize = 8;

/// Finest resolution tried, in mantissa bits (2²⁰ cells per octave).
const MAX_MANTISSA_BITS: u32 = 20;

/// Bits of the f64 mantissa.
const MANTISSA_BITS: u32 = 52;

/// How a key measures x.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Orientation {
    /// v = x (nodes ≥ 0): fine near 0.
    FromZero,
    /// v = x_{n−1} − x: fine near the last node.
    FromLast,
}

/// The cells of one node set (see the module docs).
#[derive(Debug, Clone)]
pub(super) struct Guide {
    orientation: Orientation,
    /// The last node, x_{n−1}.
    last: f64,
    /// Right shift of the bit pattern: 52 − m.
    shift: u32,
    /// Shifted pattern of the smallest positive v at a node: smaller ones share its cell.
    floor: u64,
    /// Cell of x₀ for `FromLast` (cells count down from it), unused for `FromZero`.
    top: u64,
    /// The first segment meeting each cell, then n − 2 to close the last cell: cell c holds
    /// segments `first[c]` to `first[c + 1]` at most.
    first: Box<[u32]>,
}

impl Guide {
    /// The guide of strictly increasing, finite nodes `x` (at least 2), or `None` if none
    /// stays within the cell budget or the nodes are too many for u32 segment indices.
    pub(super) fn new(x: &[f64]) -> Option<Self> {
        let n = x.len();
        if n < 2 || u32::try_from(n).is_err() {
            return None;
        }
        let from_zero = (x[0] >= 0.0)
            .then(|| Self::with(x, Orientation::FromZero))
            .flatten();
        let from_last = Self::with(x, Orientation::FromLast);
        match (from_zero, from_last) {
            (Some(a), Some(b)) => Some(if b.fullest() < a.fullest() { b } else { a }),
            (a, b) => a.or(b),
        }
    }

    /// The finest guide of one orientation within the cell budget.
    fn with(x: &[f64], orientation: Orientation) -> Option<Self> {
        let n = x.len();
        let last = *x.last()?;
        let v = |xi: f64| match orientation {
            Orientation::FromZero => xi.abs(),
            Orientation::FromLast => last - xi,
        };
        // The smallest positive v at a node, and the largest (at x₀ or x_{n−1})
        let smallest = x
            .iter()
            .map(|&xi| v(xi))
            .filter(|&vi| vi > 0.0)
            .reduce(f64::min)?;
        let largest = v(x[0]).max(v(last));
        let budget = (CELLS_PER_NODE * n).max(16) as u64;
        let (shift, floor, top) = (0..=MAX_MANTISSA_BITS).rev().find_map(|m| {
            let shift = MANTISSA_BITS - m;
            let (floor, top) = (smallest.to_bits() >> shift, largest.to_bits() >> shift);
            (top - floor < budget).then_some((shift, floor, top - floor))
        })?;
        let mut guide = Self {
            orientation,
            last,
            shift,
            floor,
            top,
            first: Box::new([]),
        };
        // Cell c's first segment is the first i with cell(x_{i+1}) ≥ c (the last one always is)
        let cells = guide.cell(last).max(guide.cell(x[0])) + 1;
        let mut first = Vec::with_capacity(cells + 1);
        let mut i = 0;
        for c in 0..cells {
            while i + 2 < n && guide.cell(x[i + 1]) < c {
                i += 1;
            }
            first.push(i as u32);
        }
        first.push((n - 2) as u32);
        guide.first = first.into();
        Some(guide)
    }

    /// The cell of x in [x₀, x_{n−1}], nondecreasing in x.
    #[inline]
    fn cell(&self, x: f64) -> usize {
        let key = |v: f64| (v.to_bits() >> self.shift).max(self.floor) - self.floor;
        let c = match self.orientation {
            // |x|: x = −0 is in range when x₀ = 0, and its bit pattern is not
            Orientation::FromZero => key(x.abs()),
            Orientation::FromLast => self.top.saturating_sub(key(self.last - x)),
        };
        usize::try_from(c).unwrap_or(usize::MAX)
    }

    /// Most segments meeting one cell, less one: the length of the final binary search.
    fn fullest(&self) -> u32 {
        self.first
            .windows(2)
            .map(|w| w[1] - w[0])
            .max()
            .unwrap_or(0)
    }

    /// The segments [lo, hi] among which the one holding x lies, for x in [x₀, x_{n−1}].
    #[inline]
    pub(super) fn range(&self, x: f64) -> (usize, usize) {
        let cell = self.cell(x).min(self.first.len().saturating_sub(2));
        match (self.first.get(cell), self.first.get(cell + 1)) {
            (Some(&lo), Some(&hi)) => (lo as usize, hi as usize),
            _ => (0, self.first.last().map_or(0, |&hi| hi as usize)),
        }
    }
}
