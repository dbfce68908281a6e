//! The spline along the reduced albedo ρ′, with PBD's factor ρ′² taken out.
//!
//! PBD carries ρ′² explicitly (S = ρ′² ∫ …, [`crate::pbd`]): every energy a table stores, E and
//! E_β, the radial CDF, ρ_eff and the θ CDF, is ρ′² g(ρ′) with g smooth in ρ′ and nonzero at
//! ρ′ = 0 (through σtr = √(3(1 − ρ′)) and D). A Catmull-Rom spline of E itself is badly wrong
//! at low albedo: between ρ′₀ = 0 and ρ′₁ it is nearly linear, ρ′·ρ′₁ g instead of ρ′² g, 3.2
//! times PBD at ρ′ = 0.02 on the default axis (ρ′₁ = 0.0777). So the table splines g:
//!
//! E(ρ′) = ρ′² Σᵢ ŵᵢ(ρ′) Eᵢ/ρ′ᵢ² = Σᵢ ωᵢ Eᵢ, ωᵢ = ŵᵢ (ρ′/ρ′ᵢ)²,
//!
//! with ŵᵢ the Catmull-Rom weights of the axis, except next to a node ρ′₀ = 0. Its E is 0 and
//! says nothing of g(0): taking g(0) = 0 would put the spline 72 % below PBD at ρ′ = 0.02 and
//! 7 % above at 0.1. Its g is instead the polynomial through nodes 1 … m at 0 (Lagrange; m ≤ 4,
//! the nodes up to [`EXTRAPOLATE_BELOW`], at least node 1), so on segments 0 and 1 its weight
//! moves to them: ŵₖ = wₖ + w₀aₖ, aₖ = Π_{j≠k} ρ′ⱼ/(ρ′ⱼ − ρ′ₖ). On the default axis (the cubic
//! through 0.0777 … 0.2763), against PBD at θ = 0 and ρ′ = 0.02, that spline of g is off by
//! 0.003 % at r = 0.1, 0.012 % at r = 1, 0.3 % at r = 5 and 3 % at r = 10 (where there is little
//! energy); the spline through PBD's own g(0) would be off by 0.006–0.7 %, through the parabola
//! of nodes 1–3 by 0.02–6 %.
//!
//! Every energy-like quantity blends with the weights ωᵢ; the lobe concentration c, which is
//! not an energy, is their energy-weighted mean Σ ωᵢcᵢ / Σ ωᵢ ([`AlbedoWeights::c_scale`]),
//! so that a node's c enters as its profile does (node 0's c, which describes no profile, not
//! at all). At a node ρ′ = ρ′ᵢ the weights are those of the plain spline, 1 there and 0
//! elsewhere, and every stored value is reproduced exactly.
//!
//! Lookups find the weights of most points inline ([`AlbedoAxis::hot_weights`]), the fold on
//! segment 1 included, as data; segment 0, the last segment and points the axis' cells miss take
//! [`AlbedoAxis::weights`], out of line. Both give the same weights bit for bit.

use crate::catmull_rom::{Nodes, Weights};

/// The largest ρ′ of a node that may enter the extrapolated g(0) beyond node 1 (see the module
/// docs): towards ρ′ = 1, where σtr = √(3(1 − ρ′)) → 0, g changes faster than a polynomial
/// through such nodes can follow. On an axis whose nodes 1–4 all lie below, the cubic through
/// them; measured on a 12-node axis with ρ′₁ = 0.517, ρ′₂ = 0.767, the cubic's g(0) put the
/// spline at ρ′ = 0.1 hundreds of times off PBD (and negative), the constant g(0) = g₁ 7–220 %.
pub(crate) const EXTRAPOLATE_BELOW: f64 = 0.5;

/// The last node that node 0's weight may move to (nodes 1 … this one, see the module docs):
/// a Catmull-Rom window's worth, so that the folded weights are again four. A scene bake that
/// keeps rows near ρ′ = 0 keeps nodes 0 … this one (`table::subset`).
pub(crate) const FOLD_NODES: usize = 4;

/// The ρ′ axis of a table: its spline nodes and, derived from them once, what
/// [`AlbedoAxis::weights`] needs to weight energies without a division.
#[derive(Debug, Clone)]
pub(crate) struct AlbedoAxis {
    nodes: Nodes,
    /// Per segment, how [`AlbedoAxis::hot_weights`] turns its Catmull-Rom weights into ω.
    hot: Box<[HotSegment]>,
    /// The segment whose weights [`AlbedoAxis::hot_weights`] moves one node up, to nodes 1–4
    /// (segment 1 with a node ρ′₀ = 0 and at least 5 nodes), or `usize::MAX`.
    shifted_segment: usize,
    /// With a node ρ′₀ = 0: the coefficients aₖ of nodes 1 … 4 in its extrapolated g.
    zero_node: Option<[f64; FOLD_NODES]>,
}

/// The fold of node 0 (module docs) on one segment, as data, so that the weights need no
/// branch: zero except on segment 1 with a node ρ′₀ = 0. One cache line: a lookup reads one.
#[derive(Debug, Clone, Copy)]
#[repr(align(64))]
struct HotSegment {
    /// Added to the weights times node 0's weight: a₁ … a₄ on nodes 1–4 (shifted), or −1, a₁,
    /// a₂, a₃ on nodes 0–3 (not shifted, an axis of 4 nodes).
    fold: [f64; 4],
    /// 1/ρ′ⱼ² of the four nodes the weights come out on (0 outside the axis and at ρ′ⱼ = 0):
    /// segment i's own nodes i − 1 … i + 2, except on the shifted segment (nodes 1–4). The
    /// general path ([`AlbedoAxis::weights`]) reads them too; it folds segments 0 and 1 itself
    /// and never lands on the shifted segment.
    inv_squares: [f64; 4],
}

/// The weights of one ρ′ for the blends of a lookup.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AlbedoWeights {
    /// ωᵢ, for every energy-like value. At a node ρ′ᵢ, ρ′²·(1/ρ′ᵢ²) may round to 1 ± 2⁻⁵²:
    /// the f32 row weights of the blends round that to 1 (and [`AlbedoWeights::apply_rows`]
    /// rounds the weights to f32 likewise), so stored values come back exactly.
    pub(crate) energy: Weights,
    /// 1/Σ ωᵢ: blended with `energy`, c times this is the energy-weighted mean of the nodes' c
    /// (the θ weights sum to 1). Finite: 1/f64::MIN_POSITIVE where no node has energy (ρ′ = 0;
    /// every weight, and so the blended c, is then 0).
    pub(crate) c_scale: f64,
}

/// Two axes are equal when their nodes are (the rest is derived from them).
impl PartialEq for AlbedoAxis {
    fn eq(&self, other: &Self) -> bool {
        self.nodes == other.nodes
    }
}

impl AlbedoAxis {
    /// The axis of `nodes` (validated spline nodes).
    pub(crate) fn new(nodes: Nodes) -> Self {
        let x = nodes.as_slice();
        let inv_square = |j: isize| {
            usize::try_from(j)
                .ok()
                .and_then(|j| x.get(j))
                .map_or(0.0, |&xj| if xj == 0.0 { 0.0 } else { 1.0 / (xj * xj) })
        };
        let inv_squares: Vec<[f64; 4]> = (0..x.len() - 1)
            .map(|i| std::array::from_fn(|k| inv_square(i as isize + k as isize - 1)))
            .collect();
        // Lagrange coefficients at 0 of the nodes 1 … m: at most 4, those at or below
        // EXTRAPOLATE_BELOW, and at least node 1
        let zero_node = (x[0] == 0.0).then(|| {
            let m = x
                .iter()
                .take(FOLD_NODES + 1)
                .skip(2)
                .take_while(|&&xj| xj <= EXTRAPOLATE_BELOW)
                .count()
                + 1;
            std::array::from_fn(|k| {
                let k = k + 1;
                if k > m {
                    return 0.0;
                }
                (1..=m)
                    .filter(|&j| j != k)
                    .map(|j| x[j] / (x[j] - x[k]))
                    .product()
            })
        });
        let shifted_segment = if zero_node.is_some() && x.len() > FOLD_NODES {
            1
        } else {
            usize::MAX
        };
        let hot = (0..inv_squares.len())
            .map(|i| {
                // The fold, and the segment whose nodes the weights come out on
                let (fold, out) = match zero_node {
                    Some(a) if i == shifted_segment => (a, i + 1),
                    Some(a) if i == 1 => ([-1.0, a[0], a[1], a[2]], i),
                    _ => ([0.0; 4], i),
                };
                HotSegment {
                    fold,
                    inv_squares: inv_squares[out],
                }
            })
            .collect();
        Self {
            nodes,
            hot,
            shifted_segment,
            zero_node,
        }
    }

    /// The spline nodes ρ′ᵢ.
    pub(crate) fn nodes(&self) -> &Nodes {
        &self.nodes
    }

    /// [`AlbedoAxis::weights`] where they are quickest to find, `None` elsewhere: in an interior
    /// segment that the axis' cells find directly (`Nodes::hot_weights`; not segment 0), bit
    /// for bit the same weights. Lookups take the other points out of line rather than merge
    /// the two paths' weights as they do θ's and r's: merged, these went through memory
    /// (measured 2–5 ns slower an evaluation, merged before the scaling or after it). For the
    /// same reason the fold on segment 1 is data ([`HotSegment`]), not a branch (a branch in
    /// here cost about 12 ns).
    #[inline(always)]
    pub(crate) fn hot_weights(&self, rho: f64) -> Option<AlbedoWeights> {
        let w = self.nodes.hot_weights(rho)?;
        let (segment, w) = (w.segment(), w.as_array());
        let hot = self.hot.get(segment)?;
        // All bits set where the weights move one node up (a compare, not a load)
        let shift = 0u64.wrapping_sub(u64::from(segment == self.shifted_segment));
        let shifted = [w[1], w[2], w[3], 0.0];
        let select =
            |on: f64, off: f64| f64::from_bits((on.to_bits() & shift) | (off.to_bits() & !shift));
        let w: [f64; 4] = std::array::from_fn(|k| select(shifted[k], w[k]) + w[0] * hot.fold[k]);
        let segment = segment + (shift & 1) as usize;
        Some(Self::energy_weights(rho, segment, w, hot.inv_squares))
    }

    /// The weights at ρ′ (module docs), `None` outside the axis or for NaN.
    pub(crate) fn weights(&self, rho: f64) -> Option<AlbedoWeights> {
        let w = self.nodes.weights(rho)?;
        let (segment, w) = if w.segment() <= 1 && self.zero_node.is_some() {
            self.fold_zero_node(&w)
        } else {
            (w.segment(), w.as_array())
        };
        let inv_squares = self.hot.get(segment).map_or([0.0; 4], |h| h.inv_squares);
        Some(Self::energy_weights(rho, segment, w, inv_squares))
    }

    /// ωᵢ = ŵᵢ ρ′²/ρ′ᵢ² from the weights ŵ of nodes `segment` − 1 … `segment` + 2 and their
    /// 1/ρ′ᵢ².
    #[inline(always)]
    fn energy_weights(
        rho: f64,
        segment: usize,
        w: [f64; 4],
        inv_squares: [f64; 4],
    ) -> AlbedoWeights {
        let rho2 = rho * rho;
        let energy: [f64; 4] = std::array::from_fn(|k| w[k] * (rho2 * inv_squares[k]));
        // The sum rounded to f32: the c it divides is blended in f32, and at a node (the weights
        // then 1 ± 2⁻⁵² and 0, or 1e-16 at the axis' last) it is exactly 1. Where it is 0 (no
        // energy), so is every blended c, and the floor keeps c · scale at 0.
        let sum = f64::from(((energy[0] + energy[1]) + (energy[2] + energy[3])) as f32);
        AlbedoWeights {
            energy: Weights::from_parts(segment, energy),
            c_scale: 1.0 / sum.max(f64::MIN_POSITIVE),
        }
    }

    /// The weights ŵ of a point in segment 0 or 1 with node 0 at ρ′ = 0: node 0's weight moved
    /// to nodes 1–4 by the coefficients `a`. Returned as the weights of a segment whose four
    /// nodes hold all of them: segment 2 (nodes 1 … 4), or on an axis of fewer than 5 nodes
    /// (whose missing nodes have a = 0) segment n − 3 or 0.
    fn fold_zero_node(&self, w: &Weights) -> (usize, [f64; 4]) {
        let a = self.zero_node.unwrap_or_default();
        // Weights of nodes 0 … 4
        let mut by_node = [0.0; FOLD_NODES + 1];
        for (k, wk) in w.as_array().into_iter().enumerate() {
            if let Some(slot) = (w.segment() + k)
                .checked_sub(1)
                .and_then(|i| by_node.get_mut(i))
            {
                *slot += wk;
            }
        }
        let w0 = std::mem::take(&mut by_node[0]);
        for (wk, ak) in by_node[1..].iter_mut().zip(a) {
            *wk += w0 * ak;
        }
        let segment = self.nodes.as_slice().len().saturating_sub(3).min(2);
        let w = std::array::from_fn(|k| {
            (segment + k)
                .checked_sub(1)
                .map_or(0.0, |node| by_node[node])
        });
        (segment, w)
    }
}

impl AlbedoWeights {
    /// Σ ωᵢ f(i) over the nodes of nonzero weight: an energy-like value at ρ′ from its values
    /// at the nodes.
    pub(crate) fn apply(&self, f: impl Fn(usize) -> f64) -> f64 {
        self.energy.apply(f)
    }

    /// [`AlbedoWeights::apply`] with ωᵢ rounded to f32, as the lookups' blends round their row
    /// weights: at a node, exactly the node's value.
    pub(crate) fn apply_rows(&self, f: impl Fn(usize) -> f64) -> f64 {
        self.energy
            .iter()
            .map(|(node, weight)| f64::from(weight as f32) * f(node))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis(x: &[f64]) -> AlbedoAxis {
        AlbedoAxis::new(Nodes::new(x.to_vec()).unwrap())
    }

    /// ρ′² g(ρ′) at ρ′ from the nodes' ρ′ᵢ² g(ρ′ᵢ).
    fn spline(a: &AlbedoAxis, g: impl Fn(f64) -> f64, rho: f64) -> f64 {
        let x = a.nodes().as_slice();
        a.weights(rho).unwrap().apply(|i| x[i] * x[i] * g(x[i]))
    }

    #[test]
    fn rho_squared_times_a_line_is_reproduced() {
        // Catmull-Rom reproduces lines (central and chord slopes are exact for them), and the
        // extrapolated g(0) of a line is exact where two nodes at or below 1/2 extrapolate it
        // (of a constant only, with one): what is left is the rounding of the weights
        for (x, slope) in [
            (vec![0.0, 0.0777, 0.1493, 0.2153, 0.2763, 0.4], -3.0),
            (vec![0.0, 0.25, 0.5, 0.75, 1.0], -3.0),
            (vec![0.0, 0.2, 0.45, 0.8], -3.0),
            (vec![0.0, 0.2, 0.4], -3.0),
            (vec![0.0, 0.3, 0.6], 0.0),
            (vec![0.0, 0.5], 0.0),
            (vec![0.2, 0.3, 0.6, 0.8], -3.0),
        ] {
            let a = axis(&x);
            let g = |r: f64| 2.0 + slope * r;
            for rho in [0.0, 0.01, 0.05, 0.1, 0.2, 0.25, 0.35, 0.5] {
                if a.weights(rho).is_none() {
                    continue;
                }
                let got = spline(&a, g, rho);
                let want = rho * rho * g(rho);
                assert!(
                    (got - want).abs() <= 1e-6 * want.abs(),
                    "{x:?} {rho}: {got} {want}"
                );
            }
        }
    }

    #[test]
    fn node_zero_takes_the_polynomial_through_the_nodes_below_one_half() {
        // With g(ρ′) a parabola and three nodes below 1/2, node 0's extrapolated g is exact, so
        // on segments 0 and 1 the spline of g is the plain Catmull-Rom spline through g(0)
        let x = [0.0, 0.1, 0.25, 0.45, 0.7];
        let a = axis(&x);
        let g = |r: f64| 1.0 + r - 4.0 * r * r;
        let plain = Nodes::new(x.to_vec()).unwrap();
        for rho in [0.02, 0.05, 0.09, 0.12, 0.2] {
            let want = rho * rho * plain.evaluate(|i| g(x[i]), rho).unwrap();
            let got = spline(&a, g, rho);
            assert!((got / want - 1.0).abs() < 1e-6, "{rho}: {got} {want}");
        }
    }

    #[test]
    fn nodes_are_reproduced_exactly_and_c_scale_normalises() {
        let x: Vec<f64> = (0..100)
            .map(|i| ((1.0 - (-8.0 * i as f64 / 99.0).exp()) / (1.0 - (-8.0f64).exp())) as f32)
            .map(f64::from)
            .collect();
        let a = axis(&x);
        for (i, &xi) in x.iter().enumerate() {
            let w = a.weights(xi).unwrap();
            let nonzero: Vec<(usize, f64)> = w.energy.iter().collect();
            if i == 0 {
                assert!(nonzero.is_empty() && w.c_scale.is_finite(), "{nonzero:?}");
            } else {
                // 1 in f32 at the node (1 ± 2⁻⁵² in f64), 0 elsewhere (3e-16 for node 98 at the
                // last node, the spline's own)
                for (j, wj) in nonzero {
                    let ok = if j == i {
                        wj as f32 == 1.0
                    } else {
                        wj.abs() < 1e-15
                    };
                    assert!(ok, "{i}: {j} {wj}");
                }
                assert_eq!(w.c_scale, 1.0);
                assert_eq!(w.apply_rows(|j| if j == i { 0.3 } else { 0.0 }), 0.3);
            }
        }
        for rho in [1e-6, 0.01, 0.1, 0.5, 0.99] {
            let w = a.weights(rho).unwrap();
            let sum: f64 = w.energy.iter().map(|(_, wi)| wi).sum();
            assert!(sum > 0.0 && (sum * w.c_scale - 1.0).abs() < 1e-7, "{rho}");
            if let Some(hot) = a.hot_weights(rho) {
                // The fold as data equals the general path's, bit for bit
                let general = a.weights(rho).unwrap();
                assert_eq!(hot.energy, general.energy, "{rho}");
                assert_eq!(hot.c_scale, general.c_scale, "{rho}");
            } else {
                assert!(rho < x[1], "{rho}");
            }
        }
    }
}
