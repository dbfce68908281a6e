//! The (ρ′, θ) neighbourhood of a lookup ([`Slice`]) and the blends over it: the one routine
//! the samplers, densities and ρ_eff use ([`TableRef::blend`]), and evaluation's fast leaf that
//! sums the same rows without building the slice ([`TableRef::window_at`]). `lookup/tests.rs`
//! holds both to a plain sum written from the table's layout, bit for bit.

use super::{Blend, TableRef, PARAMS_PER_NODE};
use crate::catmull_rom::Weights;

/// The (ρ′, θ) neighbourhood of a lookup: the nonzero products of the weights of the two axes
/// (at most 4 × 4: the energy weights ωᵢ along ρ′, `table::albedo`, and the Catmull-Rom weights
/// along θ) with the offsets (i·nθ + j)·nr of their rows in the radial arrays, and the
/// [`Blend`].
///
/// Rows of zero weight are left out, loads included (at a node of an axis, θ = 0 in the
/// perpendicular model, 12 of the 16 are). The rows in use are padded with weight-0 copies of
/// the last one to a multiple of 4, so that the loops over them unroll by 4; a padding row
/// adds exactly 0 (the values are finite).
#[derive(Debug, Clone, Copy)]
pub(super) struct Slice {
    /// Rows in use: 4, 8, 12 or 16.
    pub(super) len: usize,
    /// Index of node 0 of each row in `radial_cdf` (in `params`, times `PARAMS_PER_NODE`).
    pub(super) offsets: [u32; 16],
    /// f32: the table's values are f32 and are blended in f32 (see `blend`); the blends
    /// in f64 widen them (exactly).
    pub(super) weights: [f32; 16],
    pub(super) blend: Blend,
}

impl TableRef<'_> {
    #[inline(always)]
    pub(super) fn slice_of(
        &self,
        rho_weights: &Weights,
        theta_weights: &Weights,
        blend: Blend,
    ) -> Slice {
        let (n_rho, n_theta, n_r) = self.axes.dims();
        // Nodes segment − 1 … segment + 2 of each axis. Those outside the axis have weight 0
        // and are left out below; clamped, their offsets stay in bounds anyway. Offsets fit
        // u32: the format caps a table far below 2³² values.
        let node = |w: &Weights, k: usize, n: usize| (w.segment() + k).clamp(1, n) - 1;
        let mut theta_offsets = [0; 4];
        for (b, offset) in theta_offsets.iter_mut().enumerate() {
            *offset = node(theta_weights, b, n_theta) * n_r;
        }
        let (wr, wt) = (rho_weights.as_array(), theta_weights.as_array());
        let (mut offsets, mut weights) = ([0u32; 16], [0.0f32; 16]);
        for a in 0..4 {
            let rho_offset = node(rho_weights, a, n_rho) * n_theta * n_r;
            for b in 0..4 {
                offsets[4 * a + b] = (rho_offset + theta_offsets[b]) as u32;
                weights[4 * a + b] = (wr[a] * wt[b]) as f32;
            }
        }
        let mut len = 16;
        // A product is 0 where a factor is (or where it underflows f32: that row adds 0 anyway)
        if wr.contains(&0.0) || wt.contains(&0.0) {
            // Keep the rows of nonzero weight in order, then pad with weight-0 copies of the
            // last one (there is one: the weights of each axis sum to 1, so the largest product
            // is at least 1/16).
            len = 0;
            for k in 0..16 {
                if weights[k] != 0.0 {
                    (offsets[len], weights[len]) = (offsets[k], weights[k]);
                    len += 1;
                }
            }
            let last = offsets[len.saturating_sub(1)];
            while len % 4 != 0 {
                (offsets[len], weights[len]) = (last, 0.0);
                len += 1;
            }
        }
        Slice {
            len,
            offsets,
            weights,
            blend,
        }
    }

    /// The one blend of every lookup: Σ over the slice's rows, in row order, of the row's
    /// weight × N values of the row, `values[(offset + node)·per_node + STEP·j]` for j < N,
    /// summed in `A`. `per_node` is the number of values per radius node of the array (1 for
    /// `radial_cdf`, `PARAMS_PER_NODE` for `params`); STEP picks every STEP-th value, so one
    /// call gives the (E, E_β, c) window of four nodes (N = 12, STEP = 1), the energies of four
    /// nodes (N = 4, STEP = `PARAMS_PER_NODE`) or one node's value (N = 1). The N values must
    /// lie in the row (a row whose values run past the array would add nothing).
    ///
    /// The precision is part of the results (pinned by crates/zoo/tests/table/pinned.rs): the
    /// GWC window blends in f32, like the stored values, so its 12 lanes vectorise; the rounding
    /// is ~1e-7 of the largest term, up to ~5e-5 of the result where the Catmull-Rom terms nearly
    /// cancel (steep tails), below the table's interpolation error. The radial CDF and the
    /// energies the radial sampler reads blend in f64, in row order as one sum: the rows' CDFs
    /// nearly cancel in C_{k+1} − C_k, and in f32 or in another order the radial density of a
    /// thin segment would move far beyond rounding.
    #[inline(always)]
    pub(super) fn blend<A: Lane, const N: usize, const STEP: usize>(
        s: &Slice,
        values: &[f32],
        node: usize,
        per_node: usize,
    ) -> [A; N] {
        let mut acc = [A::ZERO; N];
        let n = s.len.min(16);
        // Rows in groups of 4 (the slice pads to a multiple of 4): unrolled, less loop overhead
        for group in 0..n / 4 {
            for k in 4 * group..4 * group + 4 {
                let base = (s.offsets[k] as usize + node) * per_node;
                if let Some(row) = values.get(base..base + N * STEP) {
                    let w = A::from(s.weights[k]);
                    for (j, acc) in acc.iter_mut().enumerate() {
                        *acc = *acc + w * A::from(row[STEP * j]);
                    }
                }
            }
        }
        acc
    }

    /// (E, E_β, c) at the four consecutive radius nodes `first..first + 4`, blended over the
    /// slice in f32 ([`TableRef::blend`]).
    #[inline(always)]
    pub(super) fn window(&self, s: &Slice, first: usize) -> [f32; 12] {
        let (_, _, n_r) = self.axes.dims();
        if n_r < 4 {
            return self.short_window(s);
        }
        Self::blend::<f32, 12, 1>(s, self.params, first, PARAMS_PER_NODE)
    }

    /// [`TableRef::window`] of a table of fewer than 4 radii: its nodes, then 0 for the nodes
    /// past the axis (which the weights along r give 0). Node by node: a row's window of 4
    /// would run into the next row, and past the end of the array at the last one.
    #[cold]
    #[inline(never)]
    pub(super) fn short_window(&self, s: &Slice) -> [f32; 12] {
        let (_, _, n_r) = self.axes.dims();
        let mut window = [0.0; 12];
        for (node, values) in window
            .chunks_exact_mut(PARAMS_PER_NODE)
            .take(n_r)
            .enumerate()
        {
            let blend =
                Self::blend::<f32, PARAMS_PER_NODE, 1>(s, self.params, node, PARAMS_PER_NODE);
            values.copy_from_slice(&blend);
        }
        window
    }

    /// [`TableRef::window`] as a call, for the samplers: inlined into [`TableRef::profile`],
    /// whose reads of (E, E_β, c) interleave, the 12-wide blend compiles to half-filled vectors.
    #[inline(never)]
    pub(super) fn window_out_of_line(&self, s: &Slice, first: usize) -> [f32; 12] {
        self.window(s, first)
    }

    /// E at the radius nodes k − 1 … k + 2 of a segment k (0 for nodes outside the axis), in
    /// f64, for the radial sampler ([`TableRef::blend`]).
    #[inline]
    pub(super) fn energies_around(&self, s: &Slice, k: usize) -> [f64; 4] {
        let (_, _, n_r) = self.axes.dims();
        if n_r < 4 {
            return [0, 1, 2, 3].map(|j| match (k + j).checked_sub(1) {
                Some(node) if node < n_r => self.energy(s, node),
                _ => 0.0,
            });
        }
        let first = energy_window(k, n_r);
        let e = Self::blend::<f64, 4, PARAMS_PER_NODE>(s, self.params, first, PARAMS_PER_NODE);
        around_from_window(first, k, e)
    }

    /// The radial sampler's reads near segment `k`, in one pass over the slice's rows: E at the
    /// four nodes of [`TableRef::energies_around`]'s window for k, the radial CDF at the same
    /// nodes, and the CDF's total (its last node). Each value is the sum, in row order and in
    /// f64, that [`TableRef::energies_around`] and [`TableRef::cdf`] give: the same bits, for
    /// a fifth of the passes (a draw reads C at two to four nodes and the total, and E around
    /// one segment, usually `k` or its neighbour). With `WINDOW`, also the (E, E_β, c) window
    /// of [`TableRef::window`] at the same nodes, in f32 and in the same order, for the profile
    /// at the drawn r (whose segment is usually `k`). `None` for tables of fewer than 4 radii
    /// and where a row's values would run past the arrays (never, for a slice of the table).
    #[inline(always)]
    pub(super) fn radial_near<const WINDOW: bool>(
        &self,
        s: &Slice,
        k: usize,
    ) -> Option<RadialNear> {
        let (_, _, n_r) = self.axes.dims();
        if n_r < 4 {
            return None;
        }
        let first = energy_window(k, n_r);
        let (mut cdf, mut energy, mut total) = ([0.0f64; 4], [0.0f64; 4], 0.0f64);
        let mut window = [0.0f32; 4 * PARAMS_PER_NODE];
        let n = s.len.min(16);
        for k in 0..n {
            let row = s.offsets[k] as usize;
            let lo = (row + first) * PARAMS_PER_NODE;
            let (Some(c), Some(&t), Some(p)) = (
                self.radial_cdf.get(row + first..row + first + 4),
                self.radial_cdf.get(row + n_r - 1),
                self.params
                    .get(lo..)
                    .and_then(<[f32]>::first_chunk::<{ 4 * PARAMS_PER_NODE }>),
            ) else {
                return None;
            };
            if WINDOW {
                axpy12(&mut window, s.weights[k], p);
            }
            let w = f64::from(s.weights[k]);
            for j in 0..4 {
                cdf[j] += w * f64::from(c[j]);
                energy[j] += w * f64::from(p[PARAMS_PER_NODE * j]);
            }
            total += w * f64::from(t);
        }
        Some(RadialNear {
            first,
            cdf,
            energy,
            total,
            last: n_r - 1,
            window: WINDOW.then_some(window),
        })
    }

    /// E at radius node k, in f64 ([`TableRef::blend`]).
    pub(super) fn energy(&self, s: &Slice, k: usize) -> f64 {
        Self::blend::<f64, 1, 1>(s, self.params, k, PARAMS_PER_NODE)[0]
    }

    /// The radial CDF at radius node k, in f64 ([`TableRef::blend`]).
    pub(super) fn cdf(&self, s: &Slice, k: usize) -> f64 {
        Self::blend::<f64, 1, 1>(s, self.radial_cdf, k, 1)[0]
    }

    /// [`TableRef::window`] over the slice of (`rho_weights`, the energy weights along ρ′,
    /// `theta_weights`) without building it, for evaluation, which needs nothing else of the
    /// slice: the same rows in the same order, so the same sums (`lookup/tests.rs` holds the
    /// two to each other bit for bit). A fast leaf: built and summed through a slice,
    /// evaluation takes about a fifth longer (docs/performance.md). For tables of at least 4
    /// radii: it reads 4 radius nodes of each row, which run past the last row of the others
    /// ([`TableRef::cell_at_point`] sends them through the slice).
    #[inline(always)]
    pub(super) fn window_at(
        &self,
        rho_weights: &Weights,
        theta_weights: &Weights,
        first: usize,
    ) -> [f32; 12] {
        const WINDOW: usize = 4 * PARAMS_PER_NODE;
        let (n_rho, n_theta, n_r) = self.axes.dims();
        let (row_len, lo) = (n_r * PARAMS_PER_NODE, first * PARAMS_PER_NODE);
        let mut acc = [0.0f32; WINDOW];
        // The θ nodes inside the axis, consecutive rows of one slab per ρ′ node, and their
        // weights (entry k of the four belongs to node segment + k − 1)
        let segment = theta_weights.segment();
        let (j0, j1) = (segment.saturating_sub(1), (segment + 2).min(n_theta - 1));
        let (wr, wt) = (rho_weights.as_array(), theta_weights.as_array());
        if j1 == j0 + 3 && rho_weights.segment() >= 1 && rho_weights.segment() + 2 < n_rho {
            // Inside both axes (the usual case): 4 slabs of 4 rows, each slab checked once. A
            // zero weight (a lookup on a node) adds exactly 0: no test needed.
            let i0 = rho_weights.segment() - 1;
            for (a, &wa) in wr.iter().enumerate() {
                let start = ((i0 + a) * n_theta + j0) * row_len + lo;
                let Some(slab) = self.params.get(start..start + 3 * row_len + WINDOW) else {
                    continue;
                };
                for (b, &wb) in wt.iter().enumerate() {
                    let w = (wa * wb) as f32;
                    let off = b * row_len;
                    if let Some(window) =
                        slab.get(off..off + WINDOW).and_then(|v| v.try_into().ok())
                    {
                        axpy12(&mut acc, w, window);
                    }
                }
            }
            return acc;
        }
        let theta_all = theta_weights.as_array();
        let Some(theta_w) = theta_all.get(j0 + 1 - segment..=j1 + 1 - segment) else {
            return acc;
        };
        for (k, &wa) in rho_weights.as_array().iter().enumerate() {
            let Some(i) = (rho_weights.segment() + k)
                .checked_sub(1)
                .filter(|&i| i < n_rho)
            else {
                continue;
            };
            let start = (i * n_theta + j0) * row_len;
            let Some(slab) = self.params.get(start..start + theta_w.len() * row_len) else {
                continue;
            };
            for (row, &wb) in slab.chunks_exact(row_len).zip(theta_w) {
                let w = (wa * wb) as f32;
                if w == 0.0 {
                    continue;
                }
                if let Some(window) = row.get(lo..).and_then(<[f32]>::first_chunk::<WINDOW>) {
                    axpy12(&mut acc, w, window);
                }
            }
        }
        acc
    }
}

/// The first node of the window of four radius nodes, inside an axis of `n_r` ≥ 4 nodes, that
/// holds the nodes k − 1 … k + 2 of segment k that lie in the axis.
fn energy_window(k: usize, n_r: usize) -> usize {
    k.saturating_sub(1).min(n_r - 4)
}

/// E at the nodes k − 1 … k + 2 of segment k from the window of four nodes from `first`
/// ([`energy_window`]), 0 for the nodes outside the axis.
fn around_from_window(first: usize, k: usize, e: [f64; 4]) -> [f64; 4] {
    match (first + 1).checked_sub(k) {
        Some(0) => e,
        Some(_) => [0.0, e[0], e[1], e[2]],
        None => [e[1], e[2], e[3], 0.0],
    }
}

/// What [`TableRef::radial_near`] blends: the radial CDF and E at the four radius nodes from
/// `first`, the CDF's total at node `last`, and if asked the (E, E_β, c) window there.
#[derive(Debug, Clone, Copy)]
pub(super) struct RadialNear {
    first: usize,
    cdf: [f64; 4],
    energy: [f64; 4],
    total: f64,
    last: usize,
    window: Option<[f32; 4 * PARAMS_PER_NODE]>,
}

impl RadialNear {
    /// The blended radial CDF at node k if the window holds it.
    pub(super) fn cdf(&self, k: usize) -> Option<f64> {
        if k == self.last {
            return Some(self.total);
        }
        self.cdf.get(k.checked_sub(self.first)?).copied()
    }

    /// [`TableRef::window`] at `first` if this holds it.
    pub(super) fn window(&self, first: usize) -> Option<[f32; 12]> {
        self.window.filter(|_| first == self.first)
    }

    /// [`TableRef::energies_around`] of segment k if the window holds its nodes.
    pub(super) fn energies_around(&self, k: usize) -> Option<[f64; 4]> {
        let n_r = self.last + 1;
        (energy_window(k, n_r) == self.first)
            .then(|| around_from_window(self.first, k, self.energy))
    }
}

/// acc += w·x over 12 lanes, written as three independent 4-lane updates so that it compiles to
/// packed SIMD instructions.
#[inline(always)]
pub(super) fn axpy12(acc: &mut [f32; 12], w: f32, x: &[f32; 12]) {
    for k in 0..12 {
        acc[k] += w * x[k];
    }
}

/// The number type a [`TableRef::blend`] sums in: f32 or f64, from the table's f32 values.
pub(super) trait Lane:
    Copy + From<f32> + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self>
{
    const ZERO: Self;
}

impl Lane for f32 {
    const ZERO: Self = 0.0;
}

impl Lane for f64 {
    const ZERO: Self = 0.0;
}
