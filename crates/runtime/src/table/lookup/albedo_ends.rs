//! Evaluation at the two ends of the albedo axis, below its first node above ρ′ = 0 and from
//! the segment that holds ρ′ = 0.9999 up (`table::albedo`, "The ends of the axis"): the spline
//! along ρ′ of E/(ρ′² f), f = (1 + σ_tr r) e^{−σ_tr r}, instead of E/ρ′².
//!
//! The rows are weighted per radius node r_j of the window: row i (nodes 1 … 4 below node 1,
//! node 0's weight folded into them) weighs
//!
//! ŵᵢ (ρ′/ρ′ᵢ)² f(ρ′, r_j)/f(ρ′ᵢ, r_j), f(ρ′, r)/f(ρ′ᵢ, r) = (1 + σ_tr r)/(1 + σ_tr,ᵢ r) · e^{(σ_tr,ᵢ − σ_tr) r},
//!
//! ŵᵢ the weights of the spline (they sum to 1), for E and E_β; c is the plain spline Σᵢ ŵᵢcᵢ.
//! The blend stays linear in the rows, so a row that is off (a θ blend near grazing at η ≈ 1,
//! where the nodes change abruptly) moves it no more than it moves the plain spline.
//!
//! Below node 1 the window holds E/ρ′², and the cell is scaled by ρ′² at the end, in f64: the
//! far tail is not lost to f32 at any ρ′ > 0. At the high end it holds E, so that at a node the
//! node's values come back exactly.
//!
//! Only evaluation takes this path. The samplers keep the weights ωᵢ of every other ρ′ (the
//! radial CDF is a linear blend of the rows'), so `sample` and `pdf` stay an exact pair; they
//! follow the plain spline of E along r anyway.
//!
//! 1/f(ρ′ᵢ, r_j) comes with the axes (`Axes::far`), so a lookup takes four exponentials, f at
//! its own ρ′ and the window's radius nodes: an evaluation here costs about 1.5–1.9 times one
//! elsewhere (docs/performance.md).

use super::blend::axpy12;
use super::{Blend, Cell, Lobe, TableRef, PARAMS_PER_NODE};
use crate::catmull_rom::Weights;
use crate::gwc::cap_lobe;
use crate::table::albedo::{far_field, sigma_tr, EndWeights};

/// Values of one radius window: (E, E_β, c) at four radius nodes.
const WINDOW: usize = 4 * PARAMS_PER_NODE;

impl TableRef<'_> {
    /// [`TableRef::cell_at_point`] at the ends of the albedo axis, with `ends` the weights
    /// there (module docs).
    #[inline(never)]
    pub(super) fn cell_at_point_albedo_ends(
        &self,
        ends: &EndWeights,
        rho: f64,
        theta: f64,
        r: f64,
    ) -> Option<Cell> {
        let theta_weights = self.theta_weights(theta)?;
        let Some((r_eval, w)) = self.radius(r) else {
            return Some(Cell::OutsideRadius);
        };
        let first = self.radial_window(&w);
        // The window holds E/ρ′² times window_rho²: 1 below node 1, ρ′² at the high end
        let window_rho = if ends.low { 1.0 } else { rho };
        let window = self.ends_window(ends, rho, window_rho, &theta_weights, first);
        // The blend's c is already the mean; the ln(1/r) growth of the first intervals is that
        // of E at window_rho
        let blend = Blend {
            c_scale: 1.0,
            rho: window_rho,
            theta,
        };
        let (e, lobe, c) = self.cell_from::<true>(window, first, r_eval, &w, blend);
        let scale = if ends.low { rho * rho } else { 1.0 };
        let e_per_r = (scale * e / r_eval).max(0.0);
        let beta = match lobe {
            Lobe::Share(share) => share * e_per_r,
            Lobe::Beta(beta) => cap_lobe(scale * beta, e_per_r, c),
        };
        Some(Cell::Profile([e_per_r, beta, c]))
    }

    /// The rows of the spline at `ends` and their weights at the radius nodes `first..first + 4`
    /// (module docs): per row, its albedo node i, the weight of its energies (E, E_β) at each
    /// radius node, ŵᵢ/ρ′ᵢ² · f(ρ′, r_j)/f(ρ′ᵢ, r_j) times `window_rho`², and ŵᵢ, the weight of
    /// its c; `None` for rows of weight 0. A table's other per-node values blend with them as
    /// E_β and c do: energies with the first, shapes with the second.
    fn ends_rows(
        &self,
        ends: &EndWeights,
        rho: f64,
        window_rho: f64,
        first: usize,
    ) -> [Option<(usize, [f64; 4], f64)>; 4] {
        let (n_rho, _, n_r) = self.axes.dims();
        let r_nodes = self.axes.r().as_slice();
        // f(ρ′, r_j) at the window's radius nodes, times window_rhoᵖ (p the power of ρ′ the
        // axis takes out: 2, or 1 for a walk table of the total, which has only the high end)
        let sigma = sigma_tr(rho);
        let window_rho_p = self.axes.rho.power().of(window_rho);
        let near: [f64; 4] = std::array::from_fn(|n| {
            let r = r_nodes.get(first + n).copied().unwrap_or(0.0);
            window_rho_p * far_field(sigma, r)
        });
        let weights = ends.weights.as_array();
        std::array::from_fn(|k| {
            let wk = weights[k];
            let i = (ends.weights.segment() + k)
                .checked_sub(1)
                .filter(|&i| i < n_rho && wk != 0.0)?;
            let inv_far = self.axes.far.row(i, n_r).get(first..).unwrap_or_default();
            let energy = std::array::from_fn(|n| {
                wk * ends.inv_powers[k] * near[n] * inv_far.get(n).copied().unwrap_or(0.0)
            });
            Some((i, energy, wk))
        })
    }

    /// (E, E_β, c) at the radius nodes `first..first + 4` (module docs), E and E_β over ρ′²
    /// times `window_rho`².
    fn ends_window(
        &self,
        ends: &EndWeights,
        rho: f64,
        window_rho: f64,
        theta_weights: &Weights,
        first: usize,
    ) -> [f32; WINDOW] {
        let (_, n_theta, n_r) = self.axes.dims();
        let mut acc = [0.0f64; WINDOW];
        for (i, energy, wk) in self
            .ends_rows(ends, rho, window_rho, first)
            .into_iter()
            .flatten()
        {
            // The row blended over θ, in f32 as every lookup's GWC window (`TableRef::window_at`)
            let mut row = [0.0f32; WINDOW];
            for (j, weight) in theta_weights.iter() {
                let base = ((i * n_theta + j) * n_r + first) * PARAMS_PER_NODE;
                if let Some(window) = self.params.get(base..).and_then(<[f32]>::first_chunk) {
                    axpy12(&mut row, weight as f32, window);
                }
            }
            for ((acc, row), energy) in acc
                .chunks_exact_mut(PARAMS_PER_NODE)
                .zip(row.chunks_exact(PARAMS_PER_NODE))
                .zip(energy)
            {
                acc[0] += energy * f64::from(row[0]);
                acc[1] += energy * f64::from(row[1]);
                acc[2] += wk * f64::from(row[2]);
            }
        }
        acc.map(|v| v as f32)
    }
}
