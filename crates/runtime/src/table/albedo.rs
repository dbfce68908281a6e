//! The spline along the reduced albedo ρ′, with PBD's factor ρ′² taken out (ρ′ for a walk table
//! of the total).
//!
//! PBD carries ρ′² explicitly (S = ρ′² ∫ …, `bssrdf_zoo::pbd`): every energy a table stores, E and
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
//! # The ends of the axis
//!
//! Far out in r every PBD profile falls like the far field of a diffusion source,
//! f(ρ′, r) = (1 + σ_tr r) e^{−σ_tr r} with σ_tr = √(3(1 − ρ′)/(2 − ρ′)) ([`sigma_tr`], Grosjean's
//! D, `crate::medium`): there g changes with ρ′ exponentially, and near ρ′ = 1, where σ_tr falls
//! like √(1 − ρ′), without a derivative. A polynomial in ρ′ follows neither where it has to
//! reach furthest: below node 1, where node 0's g is extrapolated, and in the last segments.
//! Against the profiles the bake stores at a point's own ρ′ (θ = 0 and 89°, η = 1.33, nothing
//! interpolated along θ or r), the spline of g on the default axis was off below ρ′₂ by 0.7 % at
//! r = 5, 5 % at 10, 20 % at 15 and 91 % at 22; at ρ′ < 0.02 its blend turned negative (the
//! table 0) below about 10⁻¹¹ of the profile's peak. In the last three segments (ρ′ > 0.99991)
//! it was off by 2 % at r = 100, 13 % at 200 and 22 % at 243, where PBD is still 10⁻⁸ of its
//! peak ([`HIGH_ALBEDO`]). So at the two ends evaluation splines g/f instead:
//!
//! E(ρ′, r) = f(ρ′, r) ρ′² Σᵢ ŵᵢ Eᵢ/(ρ′ᵢ² f(ρ′ᵢ, r)),
//!
//! below node 1 of an axis from ρ′₀ = 0 with the folded weights ŵ (nodes 1 … m; the
//! extrapolated node 0 is g/f's), and from the segment that holds [`HIGH_ALBEDO`] to the end with
//! the plain Catmull-Rom weights ([`AlbedoAxis::end_weights`]). The weights then depend on r: the
//! lookups apply them at each radius node of their window (`table::lookup::albedo_ends`). Against
//! the same profiles, this spline is within 0.04 % below ρ′₂ (the plain spline of ln g, tried
//! too, within 0.25 %) and 0.003 % in the last segments. There c is the plain spline Σ ŵᵢcᵢ,
//! not the energy-weighted mean: over `examples/tail_error` at ρ′ < 0.02 (η = 1.33, down to
//! 10⁻⁴ of the peak) the table is within 1.18 % of PBD (mean 0.20 %) with it, 1.90 % (0.28 %)
//! with the mean. Only evaluation takes these weights; the samplers keep ωᵢ, whose blends of
//! the rows' radial CDFs they invert, so `sample` and `pdf` stay an exact pair.
//!
//! # A walk table of the total: ρ′ instead of ρ′²
//!
//! The walk's multiple scattering starts like ρ′² as PBD's does (two scatterings at least),
//! but its single scattering is a·S₁ with the single-scattering albedo a = ρ′/(1 − g + gρ′):
//! linear in ρ′, and most of the light below the first albedo node. Taking out ρ′² there put
//! a total table 2–35 times below the walk at ρ′ = 0.03–0.001 (ρ′² g through node 0's
//! extrapolated g, where the truth goes like ρ′). Such a table takes out ρ′ instead
//! ([`AlbedoPower::Linear`]): E/ρ′ is single scattering's S₁/(1 − g) plus a term that vanishes
//! with ρ′, smooth and nonzero at 0, and node 0's g is extrapolated as above. It has no low end:
//! f, the far field of diffusion, does not describe single scattering, which falls like e^{−r}
//! (a path from the entry to an exit r away is at least r long) where f falls like e^{−√3 r}.
//!
//! Lookups find the weights of most points inline ([`AlbedoAxis::hot_weights`]), the fold on
//! segment 1 included, as data; segment 0, the last segment and points the axis' cells miss take
//! [`AlbedoAxis::weights`], out of line. Both give the same weights bit for bit. Evaluation
//! takes the segments from [`HIGH_ALBEDO`] up out of line too ([`AlbedoAxis::hot_eval_weights`]),
//! and at both ends [`AlbedoAxis::end_weights`].

use crate::catmull_rom::{Nodes, Weights};
use crate::float::{f32_rounding_around, snap_to_ends};

/// The largest ρ′ of a node that may enter the extrapolated g(0) beyond node 1 (see the module
/// docs): towards ρ′ = 1, where σtr = √(3(1 − ρ′)) → 0, g changes faster than a polynomial
/// through such nodes can follow. On an axis whose nodes 1–4 all lie below, the cubic through
/// them; measured on a 12-node axis with ρ′₁ = 0.517, ρ′₂ = 0.767, the cubic's g(0) put the
/// spline at ρ′ = 0.1 hundreds of times off PBD (and negative), the constant g(0) = g₁ 7–220 %.
pub(crate) const EXTRAPOLATE_BELOW: f64 = 0.5;

/// From the segment that holds this albedo to ρ′ = 1, evaluation splines E/(ρ′² f) along ρ′
/// (module docs, "The ends of the axis"). Towards ρ′ = 1 the far tail, E ~ f = (1 + σ_tr r)
/// e^{−σ_tr r}, has no derivative in ρ′ (σ_tr ~ √(1 − ρ′)), and from ρ′ ≈ 0.999 up PBD at the
/// end of the default r axis (243 reduced mfp) is above 10⁻¹² of its peak (1.1–1.4·10⁻¹² at
/// 0.999, 4.5–6.1·10⁻⁸ at 1; η = 1.33). At r ≈ 243 the plain spline of E/ρ′² is within 0.6 %
/// of the stored profiles below 0.99987 on the default axis, and off by 0.9 %, 1.6 %, 7 % and
/// 21 % in its four segments above, those this albedo selects.
pub(crate) const HIGH_ALBEDO: f64 = 0.9999;

/// The last node that node 0's weight may move to (nodes 1 … this one, see the module docs):
/// a Catmull-Rom window's worth, so that the folded weights are again four. A scene bake that
/// keeps rows near ρ′ = 0 keeps nodes 0 … this one (`table::subset`).
pub(crate) const FOLD_NODES: usize = 4;

/// The ρ′ axis of a table: its spline nodes and, derived from them once, what
/// [`AlbedoAxis::weights`] needs to weight energies without a division.
#[derive(Debug, Clone)]
pub struct AlbedoAxis {
    nodes: Nodes,
    /// The power p of ρ′ taken out of the energies: 2 (PBD's factor ρ′², every table but the
    /// next) or 1 (a walk table of the total, whose single scattering is linear in ρ′).
    power: AlbedoPower,
    /// Per segment, how [`AlbedoAxis::hot_weights`] turns its Catmull-Rom weights into ω.
    hot: Box<[HotSegment]>,
    /// Per segment i, 1/ρ′ⱼᵖ of its nodes i − 1 … i + 2 (0 outside the axis and at ρ′ⱼ = 0).
    inv_powers: Box<[[f64; 4]]>,
    /// The first segment of the high end of the axis (module docs, "The ends of the axis"), if
    /// it has one.
    high: Option<usize>,
    /// ρ′ of its first node (+∞ without one): evaluation from there up is out of line.
    high_from: f64,
    /// The segment whose weights [`AlbedoAxis::hot_weights`] moves one node up, to nodes 1–4
    /// (segment 1 with a node ρ′₀ = 0 and at least 5 nodes), or `usize::MAX`.
    shifted_segment: usize,
    /// With a node ρ′₀ = 0: the coefficients aₖ of nodes 1 … 4 in its extrapolated g.
    zero_node: Option<[f64; FOLD_NODES]>,
}

/// The power p of ρ′ a table's spline along ρ′ takes out of its energies, E = ρ′ᵖ g(ρ′) with g
/// smooth and nonzero at ρ′ = 0 (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AlbedoPower {
    /// p = 2: photon beam diffusion and every multiple-scattering table (PBD carries ρ′²; the
    /// walk's multiple scattering, two scatterings at least, starts like ρ′² too).
    #[default]
    Square,
    /// p = 1: a walk table of the total, whose single scattering, a·S₁ with the single-scattering
    /// albedo a = ρ′/(1 − g + gρ′), is linear in ρ′ as ρ′ → 0 and outweighs the multiple
    /// scattering there (format-spec.md §10).
    Linear,
}

impl AlbedoPower {
    /// ρ′ᵖ.
    #[inline(always)]
    pub(crate) fn of(self, rho: f64) -> f64 {
        match self {
            AlbedoPower::Square => rho * rho,
            AlbedoPower::Linear => rho,
        }
    }
}

/// The fold of node 0 (module docs) on one segment, as data, so that the weights need no
/// branch: zero except on segment 1 with a node ρ′₀ = 0. One cache line: a lookup reads one.
#[derive(Debug, Clone, Copy)]
#[repr(align(64))]
struct HotSegment {
    /// Added to the weights times node 0's weight: a₁ … a₄ on nodes 1–4 (shifted), or −1, a₁,
    /// a₂, a₃ on nodes 0–3 (not shifted, an axis of 4 nodes).
    fold: [f64; 4],
    /// 1/ρ′ⱼᵖ of the four nodes the weights come out on (0 outside the axis and at ρ′ⱼ = 0):
    /// segment i's own nodes i − 1 … i + 2, except on the shifted segment (nodes 1–4). The
    /// general path ([`AlbedoAxis::weights`]) reads the unshifted ones (`AlbedoAxis::inv_powers`).
    inv_powers: [f64; 4],
}

/// The weights of one ρ′ for the blends of a lookup.
#[derive(Debug, Clone, Copy)]
pub struct AlbedoWeights {
    /// ωᵢ, for every energy-like value. At a node ρ′ᵢ, ρ′ᵖ·(1/ρ′ᵢᵖ) may round to 1 ± 2⁻⁵²:
    /// the f32 row weights of the blends round that to 1 (and [`AlbedoWeights::apply_rows`]
    /// rounds the weights to f32 likewise), so stored values come back exactly.
    pub(crate) energy: Weights,
    /// 1/Σ ωᵢ: blended with `energy`, c times this is the energy-weighted mean of the nodes' c
    /// (the θ weights sum to 1). Finite: 1/f64::MIN_POSITIVE where no node has energy (ρ′ = 0;
    /// every weight, and so the blended c, is then 0).
    pub(crate) c_scale: f64,
}

/// The weights of a point at an end of the axis, for the spline of E/(ρ′² f) that evaluation
/// takes there ([`AlbedoAxis::end_weights`], module docs).
#[derive(Debug, Clone, Copy)]
pub(crate) struct EndWeights {
    /// The spline's weights: they sum to 1, and a node at ρ′ = 0 (or outside the axis) has
    /// weight 0.
    pub(crate) weights: Weights,
    /// 1/ρ′ᵢᵖ of the nodes `weights.segment()` − 1 … + 2 (0 outside the axis).
    pub(crate) inv_powers: [f64; 4],
    /// Whether the point is at the low end (below node 1), else at the high end.
    pub(crate) low: bool,
}

/// Two axes are equal when their nodes are (the rest is derived from them).
impl PartialEq for AlbedoAxis {
    fn eq(&self, other: &Self) -> bool {
        self.nodes == other.nodes
    }
}

impl AlbedoAxis {
    /// The axis of `nodes` (validated spline nodes), taking out ρ′².
    pub fn new(nodes: Nodes) -> Self {
        Self::with_power(nodes, AlbedoPower::Square)
    }

    /// The axis of `nodes`, taking out ρ′ to `power`.
    pub fn with_power(nodes: Nodes, power: AlbedoPower) -> Self {
        let x = nodes.as_slice();
        let inv_power = |j: isize| {
            usize::try_from(j)
                .ok()
                .and_then(|j| x.get(j))
                .map_or(0.0, |&xj| if xj == 0.0 { 0.0 } else { 1.0 / power.of(xj) })
        };
        let inv_powers: Vec<[f64; 4]> = (0..x.len() - 1)
            .map(|i| std::array::from_fn(|k| inv_power(i as isize + k as isize - 1)))
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
        let high = high_end(x);
        let high_from = high.map_or(f64::INFINITY, |first| x[first]);
        let hot = (0..inv_powers.len())
            .map(|i| {
                // The fold, and the segment whose nodes the weights come out on
                let (fold, out) = match zero_node {
                    Some(a) if i == shifted_segment => (a, i + 1),
                    Some(a) if i == 1 => ([-1.0, a[0], a[1], a[2]], i),
                    _ => ([0.0; 4], i),
                };
                HotSegment {
                    fold,
                    inv_powers: inv_powers[out],
                }
            })
            .collect();
        Self {
            nodes,
            power,
            hot,
            inv_powers: inv_powers.into(),
            high,
            high_from,
            shifted_segment,
            zero_node,
        }
    }

    /// The spline nodes ρ′ᵢ.
    pub fn nodes(&self) -> &Nodes {
        &self.nodes
    }

    /// The power of ρ′ the spline takes out of the energies.
    pub fn power(&self) -> AlbedoPower {
        self.power
    }

    /// [`AlbedoAxis::hot_weights`] for evaluation: `None` also from the high end of the axis up
    /// (and for NaN), where evaluation takes [`AlbedoAxis::end_weights`] out of line. The
    /// samplers keep the quick weights there.
    #[inline(always)]
    pub(crate) fn hot_eval_weights(&self, rho: f64) -> Option<AlbedoWeights> {
        if rho < self.high_from {
            self.hot_weights(rho)
        } else {
            None
        }
    }

    /// [`AlbedoAxis::weights`] where they are quickest to find, `None` elsewhere: in an interior
    /// segment that the axis' cells find directly (`Nodes::hot_weights`; not segment 0), bit
    /// for bit the same weights. Lookups take the other points out of line rather than merge
    /// the two paths' weights as they do θ's and r's: merged, these go through memory. For the
    /// same reason the fold on segment 1 is data ([`HotSegment`]), not a branch.
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
        Some(Self::energy_weights(
            self.power.of(rho),
            segment,
            w,
            hot.inv_powers,
        ))
    }

    /// The albedos the axis takes: its nodes' range widened at each end by f32 rounding (2⁻²⁴
    /// of the node), within [0, 1]. The nodes are stored in f32, and an albedo given in f64 lies
    /// up to that far from its node (0.9 just above the f32 node of a table whose last row is
    /// 0.9, or the shortest f32 form of a node as `inspect` prints it);
    /// [`AlbedoAxis::snap`] takes such an albedo as the node.
    pub fn domain(&self) -> [f64; 2] {
        let [lo, hi] = f32_rounding_around(self.nodes.first(), self.nodes.last());
        [lo.max(0.0), hi.min(1.0)]
    }

    /// Whether ρ′ lies in [`AlbedoAxis::domain`] (false for NaN).
    pub fn keeps(&self, rho: f64) -> bool {
        let [lo, hi] = self.domain();
        (lo..=hi).contains(&rho)
    }

    /// ρ′, or the first or last node where ρ′ lies outside the nodes but inside
    /// [`AlbedoAxis::domain`].
    pub fn snap(&self, rho: f64) -> f64 {
        snap_to_ends(rho, [self.nodes.first(), self.nodes.last()], self.domain())
    }

    /// The weights at ρ′ (module docs), `None` outside [`AlbedoAxis::domain`] or for NaN (ρ′
    /// in the domain but outside the nodes takes the end node's weights,
    /// [`AlbedoAxis::snap`]).
    pub fn weights(&self, rho: f64) -> Option<AlbedoWeights> {
        let rho = self.snap(rho);
        let w = self.nodes.weights(rho)?;
        let (segment, w) = if w.segment() <= 1 && self.zero_node.is_some() {
            self.fold_zero_node(&w)
        } else {
            (w.segment(), w.as_array())
        };
        let inv_powers = self.inv_powers.get(segment).copied().unwrap_or_default();
        Some(Self::energy_weights(
            self.power.of(rho),
            segment,
            w,
            inv_powers,
        ))
    }

    /// The weights of the spline of E/(ρ′² f) at the ends of the axis (module docs, "The ends
    /// of the axis"): below node 1 of an axis from ρ′₀ = 0, ŵ with node 0's weight folded into
    /// nodes 1 … m as in [`AlbedoAxis::weights`]; from the segment that holds [`HIGH_ALBEDO`]
    /// up, the Catmull-Rom weights. `None` elsewhere and for NaN.
    pub(crate) fn end_weights(&self, rho: f64) -> Option<EndWeights> {
        let rho = self.snap(rho);
        let x = self.nodes.as_slice();
        // (x has at least two nodes; NaN fails the comparisons)
        // (A linear power has no low end: its g, single scattering's, has no diffusion far field)
        let low = self.power == AlbedoPower::Square && self.zero_node.is_some() && rho < x[1];
        let (segment, w) = if low {
            self.fold_zero_node(&self.nodes.weights(rho)?)
        } else if self.high.is_some_and(|first| rho >= x[first]) {
            let w = self.nodes.weights(rho)?;
            (w.segment(), w.as_array())
        } else {
            return None;
        };
        let inv_powers = self.inv_powers.get(segment).copied().unwrap_or_default();
        Some(EndWeights {
            weights: Weights::from_parts(segment, w),
            inv_powers,
            low,
        })
    }

    /// ωᵢ = ŵᵢ ρ′ᵖ/ρ′ᵢᵖ from ρ′ᵖ (`rho_p`), the weights ŵ of nodes `segment` − 1 … `segment` + 2
    /// and their 1/ρ′ᵢᵖ.
    #[inline(always)]
    fn energy_weights(
        rho_p: f64,
        segment: usize,
        w: [f64; 4],
        inv_powers: [f64; 4],
    ) -> AlbedoWeights {
        let energy: [f64; 4] = std::array::from_fn(|k| w[k] * (rho_p * inv_powers[k]));
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
        if w.segment() == 0 && self.nodes.as_slice().len() > FOLD_NODES {
            // The loop below on segment 0 (weights of nodes −1, 0, 1, 2), written out: the same
            // operations, the same bits
            let [_, w0, w1, w2] = w.as_array();
            return (
                2,
                [
                    w1 + w0 * a[0],
                    w2 + w0 * a[1],
                    0.0 + w0 * a[2],
                    0.0 + w0 * a[3],
                ],
            );
        }
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

/// 1/f(ρ′ᵢ, r_j) at every radius node of the rows the splines at the ends of the axis use
/// (module docs, "The ends of the axis"): nodes 1 … 4 of an axis from ρ′₀ = 0 and the nodes of
/// the high end's segments. Derived from the axes once, so that a lookup there takes four
/// exponentials (f at its own ρ′), not sixteen.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FarField {
    /// Per albedo node, the start of its row in `inv`, or `u32::MAX` for a node without one.
    rows: Box<[u32]>,
    /// The rows, n_r values each: min(1/f, 10³⁰⁰), finite where f underflows (far beyond where
    /// any stored E does).
    inv: Box<[f64]>,
}

impl FarField {
    /// The rows of `axis` at the radius nodes `r` (at least 0 each).
    pub(crate) fn new(axis: &AlbedoAxis, r: &[f64]) -> Self {
        let x = axis.nodes.as_slice();
        let n = x.len();
        let low = if axis.zero_node.is_some() {
            1..(FOLD_NODES + 1).min(n)
        } else {
            0..0
        };
        let high = axis.high.map_or(n..n, |first| first.saturating_sub(1)..n);
        let mut rows = vec![u32::MAX; n].into_boxed_slice();
        let mut inv = Vec::new();
        for i in low.chain(high) {
            if rows[i] != u32::MAX {
                continue;
            }
            // Offsets fit u32: a table's f32 arrays are far smaller
            rows[i] = inv.len() as u32;
            let sigma = sigma_tr(x[i]);
            inv.extend(r.iter().map(|&rj| {
                let s = sigma * rj;
                let v = s.exp() / (1.0 + s);
                // (NaN and negative values only from radius nodes below 0, which a file may hold)
                if v > 0.0 {
                    v.min(1e300)
                } else {
                    0.0
                }
            }));
        }
        Self {
            rows,
            inv: inv.into(),
        }
    }

    /// 1/f(ρ′ᵢ, r_j) of node i at every radius node; empty for a node without a row.
    pub(crate) fn row(&self, i: usize, n_r: usize) -> &[f64] {
        match self.rows.get(i) {
            Some(&start) if start != u32::MAX => {
                let start = start as usize;
                self.inv.get(start..start + n_r).unwrap_or_default()
            }
            _ => &[],
        }
    }
}

/// f = (1 + σ_tr r) e^{−σ_tr r}, the far field of a diffusion source (module docs, "The ends
/// of the axis"), for σ_tr ≥ 0 and r ≥ 0 in (0, 1]; 0 where it would be negative or NaN (radius
/// nodes below 0, which a file may hold).
pub(crate) fn far_field(sigma_tr: f64, r: f64) -> f64 {
    let s = sigma_tr * r;
    let f = (1.0 + s) * (-s).exp();
    if f > 0.0 {
        f.min(1e300)
    } else {
        0.0
    }
}

/// σ_tr = √(3(1 − ρ′)/(2 − ρ′)) in reduced units (Grosjean's D = (2 − ρ′)/3, `crate::medium`),
/// for ρ′ ∈ [0, 1]: the rate of the far field f = (1 + σ_tr r) e^{−σ_tr r} that evaluation takes
/// out at the ends of the axis (module docs, "The ends of the axis").
pub(crate) fn sigma_tr(rho: f64) -> f64 {
    ((1.0 - rho) / ((2.0 - rho) / 3.0)).sqrt()
}

/// The first segment of the high end of the axis `x`: the segment that holds [`HIGH_ALBEDO`],
/// or the first if every node lies above it; `None` if no segment reaches above it or a node
/// lies above 1. Defined by the nodes around [`HIGH_ALBEDO`] alone, so that a scene bake's
/// subset of the rows (`table::subset`) evaluates as the whole table does.
fn high_end(x: &[f64]) -> Option<usize> {
    let n = x.len();
    // (The nodes are finite)
    if x[n - 1] > 1.0 {
        return None;
    }
    match x.iter().rposition(|&xi| xi <= HIGH_ALBEDO) {
        Some(i) if i + 1 < n => Some(i),
        Some(_) => None,
        None => Some(0),
    }
}

impl AlbedoWeights {
    /// Σ ωᵢ f(i) over the nodes of nonzero weight: an energy-like value at ρ′ from its values
    /// at the nodes.
    pub fn apply(&self, f: impl Fn(usize) -> f64) -> f64 {
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
    fn the_ends_take_their_own_weights_and_the_hot_path_leaves_them() {
        let x: Vec<f64> = (0..100)
            .map(|i| ((1.0 - (-8.0 * i as f64 / 99.0).exp()) / (1.0 - (-8.0f64).exp())) as f32)
            .map(f64::from)
            .collect();
        let a = axis(&x);
        // The segment that holds HIGH_ALBEDO and those above it, and nothing else from the top
        let first = a.high.unwrap();
        assert!(
            x[first] <= HIGH_ALBEDO && x[first + 1] > HIGH_ALBEDO,
            "{first}"
        );
        for rho in [0.0, 1e-9, 0.01, 0.07, x[first], 0.99995, 0.99999, 1.0] {
            let ends = a.end_weights(rho).unwrap();
            let w = ends.weights.as_array();
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{rho}: {w:?}");
            assert_eq!(ends.low, rho < x[1], "{rho}");
            // Node 0 never carries weight; each weighted node has its 1/ρ′ᵢ²
            for (k, (node, wk)) in ends.weights.iter().enumerate() {
                assert!(node > 0 && wk != 0.0, "{rho}: {k}");
            }
            for (k, &inv) in ends.inv_powers.iter().enumerate() {
                if w[k] != 0.0 {
                    let node = ends.weights.segment() + k - 1;
                    assert_eq!(inv, 1.0 / (x[node] * x[node]), "{rho}");
                }
            }
            assert!(a.hot_eval_weights(rho).is_none(), "{rho}");
        }
        for rho in [x[1], 0.1, 0.5, 0.999, 0.99985] {
            assert!(a.end_weights(rho).is_none(), "{rho}");
        }
        // At a node of the high end the weights are 1 there and 0 elsewhere (3e-16 for node
        // 98 at the last node, the spline's own)
        for (i, &xi) in x.iter().enumerate().skip(first) {
            for (node, wk) in a.end_weights(xi).unwrap().weights.iter() {
                let want = if node == i { 1.0 } else { 0.0 };
                assert!((wk - want).abs() < 1e-15, "{i}: {node} {wk}");
            }
        }
    }

    #[test]
    fn the_high_end_depends_on_the_nodes_around_it_alone() {
        // A subset of rows has the whole axis' high end where it keeps the nodes around 0.999,
        // none where it stops below, and is all high end where every node lies above
        assert_eq!(high_end(&[0.3, 0.6, 0.9]), None);
        assert_eq!(high_end(&[0.9, 0.99995, 1.0]), Some(0));
        assert_eq!(high_end(&[0.5, 0.9998, 0.99995, 1.0]), Some(1));
        assert_eq!(high_end(&[0.5, 0.9999, 1.0]), Some(1));
        assert_eq!(high_end(&[0.99995, 1.0]), Some(0));
        assert_eq!(high_end(&[0.5, 1.5]), None);
    }

    #[test]
    fn sigma_tr_is_the_diffusion_constants() {
        for rho in [0.0, 0.1, 0.5, 0.9, 0.999, 1.0] {
            let d = crate::medium::ReducedDiffusion::new(rho).unwrap();
            assert_eq!(sigma_tr(rho), d.sigma_tr, "{rho}");
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
