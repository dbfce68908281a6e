//! Baking the angular table from the Monte Carlo walk instead of PBD: the same (ρ′, θ, r)
//! grid and two-lobe nodes, each node's harmonics measured by the walk.
//!
//! | parameter | unit | range |
//! |---|---|---|
//! | `eta` | – | η in [0.75, 2.5] |
//! | `g` | – | Henyey–Greenstein asymmetry, (−1, 1) |
//! | grid | as [`Grid`] | ρ′ in [0, 1], θ in [0, π/2], r ≥ 0 (reduced mfp) |
//! | `photons` | – | per θ node and row group, at least [`MIN_HARMONICS_PHOTONS`] |
//!
//! # What a node stores
//! The walk's multiple scattering (two or more vertices, the part PBD models; for a total
//! table, single scattering is added after, below) per unit power entering, in reduced units,
//! described as a **tilt of PBD**: at each node the profile is
//! k · P(φ) · (1 + a₁ cos φ + … + a₄ cos 4φ), P PBD's profile at (ρ′, θ, r), with the walk's
//! scale k and tilt (a₁ … a₄). PBD is smooth, shaped like the walk, and without noise; the walk
//! only has to tell how far off it is, which changes slowly along r. The steps, per θ node and
//! row:
//! 1. **Measure.** One walk per group of rows ([`crate::walk::harmonics`]: every albedo of a
//!    group from one walk at its largest) gives, at every node rᵢ > 0, the harmonics μ̂₀ … μ̂₈
//!    averaged over a hat kernel in ln r, with standard errors.
//! 2. **Tilt.** At each node whose μ̂₀ has a relative standard error ≤ [`MAX_REL_STDERR`], the
//!    tilt whose kernel average of the tilted PBD has the walk's μ̂₀ … μ̂₄ (PBD's own kernel
//!    averages by quadrature; four linear equations in a₁ … a₄, then k). Comparing averages
//!    with averages takes the kernel's bias out: the kernel average differs from the value at
//!    rᵢ by the profile's curvature over the kernel, as much as 7 % at r = 10 on the default
//!    two-lobe grid, and PBD has the same curvature (the table's ρ_eff was 2–2.8 % high without
//!    it, measured). A tilt whose factor 1 + Σ aₘ cos mφ would dip below
//!    [`MIN_TILT_FACTOR`] is scaled back until it does not ([`bounded`]), so the profile stays
//!    positive without cutting short a tilt that is large only where it adds up. The terms in
//!    cos 3φ and cos 4φ carry what the walk's shape departs from PBD's beyond a tilt by cos φ
//!    and cos 2φ: at η = 1, 60° the walk's μ̂₃ and μ̂₄ missed by a two-term tilt drift by 3–5
//!    standard errors over a dozen nodes, and without them the sides of the profile came out
//!    low (docs/walk-table.md). **The ridge's share.** Where PBD has the
//!    analytic ridge of grazing incidence near index matching (`table::ridge`: cos θ′ < 0.3,
//!    below η ≈ 1.0483; not for the beam in the surface), the walk's own forward ridge is
//!    weaker and wider than PBD's (at η = 1, θ = 89°, ρ′ = 0.9 the walk over PBD is 0.3 within
//!    10° of φ = 0 and 0.6–1.6 elsewhere), which no smooth tilt follows: there, where the
//!    ridge has its full weight (cos θ′ ≤ 0.1), the tilt has two terms (a₃ = a₄ = 0) matching
//!    μ̂₀ … μ̂₂, and four where it ramps in ([`ridge_tilt_terms`]), and P is PBD less
//!    the ridge's flux part R (its narrow lobe; the broad fluence lobes stay) plus a share s of
//!    R widened by w, P − R + s R_w ([`Ridge::widened`]: every lobe's concentration times
//!    e^{−w}), with s ∈ [0, [`MAX_RIDGE_SHARE`]] and w ∈ [0, [`MAX_RIDGE_WIDENING`]] those whose
//!    tilt matches the harmonics above its own best (χ² with their standard errors: the narrow
//!    ridge is the part of the profile that carries the high harmonics; [`fit_ridge_tilt`]; with
//!    μ̂₃ and μ̂₄ alone the 89° cases at η = 1 were 1.07–1.12 times as far from the walk). A tilt
//!    of four harmonics there, with the share fitted to μ̂₅ … μ̂₈, followed their noise
//!    ([`RIDGE_TILT_TERMS`]).
//!    Widening by more than 0.15 fitted the noise of μ̂₃, μ̂₄ at small r (measured: the 89°
//!    error doubled); with the fluence lobes shared too the sides of the profile came out low.
//!    A total table does not widen ([`max_ridge_widening`]): its single scattering has a ridge
//!    of its own on φ = 0 as narrow as PBD's, and with the multiple scattering's widened the
//!    89° cases at η = 1 came out worse (docs/walk-table.md).
//! 3. **Smooth.** ln k and a₁ … a₄ (with the ridge, ln(μ̂₀/P̄₀), a₁, a₂, s and w, k then
//!    following from them: k and s trade off against each other from node to node) are
//!    smoothed along ln r by a local quadratic fit over [`SMOOTH_NODES`] measured nodes on each
//!    side, weighted by 1/σ² and a tricube. (A line left the curvature of the walk over PBD in
//!    the energy: at η = 1 the tables' ρ_eff came out 0.5 % high at 60° and 1.4 % at 89°,
//!    1–3.5 % between r = 0.1 and 3.) Towards the ends, where fewer than
//!    [`MIN_QUADRATIC_SIDE`] measured nodes lie on one side, a line: in ln r at the near end,
//!    in r at the far end, where both profiles fall exponentially at rates that differ by a
//!    constant (a line in ln r through the last nodes bent ln k up: at η = 1, g = 0.9, 89° and
//!    ρ′ = 0.3 the table was 1.5–2 times the walk at r = 11–17). Between
//!    measured nodes the tilt goes linearly in ln r; before the first it is the first's;
//!    beyond the last ln k goes on along the line in r through the last [`TAIL_NODES`] (far out
//!    both profiles fall exponentially, at rates that differ by a constant), by at most
//!    [`TAIL_MAX_FACTOR`]. A row with no measured node is PBD's ([`WalkBakeReport::rows_from_pbd`]).
//!    The tail is where the table is noisiest: at 10⁵ photons and (ρ′, θ) = (0.9, 60°) its
//!    nodes are measured to r ≈ 16 and the walk is 7–10 % above PBD from r = 12 to 20, which
//!    the table follows only in part (docs/walk-table.md).
//! 4. **Store.** Two lobes fitted to the tilted PBD at the azimuths of the PBD bake
//!    (`two_lobe_node`), scaled to the tilted profile's energy r·μ₀: the walk's energy with a
//!    shape a two-lobe node can hold. (Storing the tilted harmonics themselves rebuilt, through
//!    Prony's method, into spikes of a few per cent of the energy at small r.) At θ = 0 the
//!    node is PBD's isotropic node scaled to the walk's energy; for a beam in the surface
//!    (below η = 1, the critical node) the harmonics of the tilted limit; r = 0 and the nodes
//!    beyond the critical angle as in the PBD bake.
//!
//! # Where the tilt misses the walk
//! Near index matching with strong forward scattering (η = 1, g = 0.9) the walk's multiple
//! scattering at grazing incidence is far more forward than PBD's, and no tilt of a few
//! harmonics reaches it: the tilted profiles miss the walk's harmonics by 5–27 % RMS from 70°
//! on ([`WalkMiss`]). At a θ node where the tilt's miss is beyond the warning
//! ([`WalkMiss::warns`]), each row's nodes get a floor and two wrapped Cauchy lobes fitted
//! straight to the walk's harmonics instead ([`row_lobes`], `table::walk_lobes`): the energy
//! as ln(μ̂₀/P̄₀) times PBD at the node, the shape μ̂₁/μ̂₀ … μ̂₈/μ̂₀, both smoothed along ln r
//! as the tilts are, the lobes' masses signed with the sharper one positive and the profile
//! ≥ 0 (what a stored node's rebuild gives back), stored as their harmonics (refitted at the
//! bake's eight azimuths they lost most of it). They replace the tilt at that θ node if they
//! miss the walk less (χ² per harmonic over the same nodes), between the first and last node
//! the walk measured; before and beyond those the tilt stays (the far tail goes on from PBD).
//! PBD's shape beyond the ninth harmonic is then gone, so where the tilt follows the walk the
//! tilt is kept: at η = 1, g = 0 lobes from 70° on made ρ′ = 0.99 worse (docs/walk-table.md).
//!
//! # The total
//! With [`WalkComponent::Total`] each node's profile is the tilted PBD plus the exact single
//! scattering of its row ([`crate::walk::single`], by quadrature, noise-free): the energy is the
//! sum's, the two lobes are fitted to the sum at the same azimuths, a beam in the surface adds
//! single scattering's ridge to the harmonics, and at θ = 0 the lobe keeps the multiple
//! scattering's share of E. The table is exitance integrated over exit directions, single
//! scattering included; near grazing incidence two lobes do not hold single scattering's shape
//! (docs/walk-table.md, "The total").
//!
//! # What the bake reports of itself
//! Per θ node, how far the stored lobes are from the profiles they were fitted to
//! ([`NodeFit`]: the format's part of the error) and how far those profiles are from the walk's
//! own measured harmonics beyond its noise ([`WalkMiss`]: the tilt's part, which the lobes
//! inherit), with a warning where either is above what the table's goal allows
//! ([`WalkBakeReport::node_fit_warnings`], [`WalkBakeReport::walk_miss_warnings`]).
//!
//! # Row groups
//! A walk's cost per photon grows with its largest albedo (scattering events per photon at
//! θ = 60°, η = 1.33, g = 0: about 130 up to ρ′ = 0.99, 430 up to 0.999, 5,000–7,300 up to 1,
//! heavy-tailed: the vertex cap ends the longest paths). The rows are walked in three groups, ρ′ ≤ 0.99,
//! ≤ 0.999 and above, the last with an eighth of the photons.

use super::bake::{
    assemble, beam_in_surface, checked_grid, node_cell, r0_concentration, stored_node,
    surface_harmonics, to_f32, two_lobe_azimuths, two_lobe_node_of, within_floor,
};
use super::walk_lobes::Lobes;
use super::walk_single::{SingleNode, SinglePart};
use super::{AngularTable, Grid, PARAMS_PER_NODE};
use crate::error::{Error, Result};
use crate::format::{WalkComponent, WalkSource};
use crate::fresnel::Moments;
use crate::gwc::{one_lobe_of, solve_small};
use crate::medium::Boundary;
use crate::pbd::{Pbd, Rule};
use crate::quadrature::GaussLegendre;
use crate::table::ridge::{self, Ridge, RidgeKind};
use crate::walk::harmonics::{
    harmonics, kernels, unreduced_albedo, HarmonicsConfig, WalkHarmonics, HARMONICS,
};
use crate::walk::single::SINGLE_HARMONICS;
use crate::walk::Component;
use rayon::prelude::*;
use std::f64::consts::PI;
use std::time::Instant;

pub use crate::walk::harmonics::MIN_HARMONICS_PHOTONS;

/// Upper ρ′ of each row group but the last (module docs).
pub const WALK_GROUP_EDGES: [f64; 2] = [0.99, 0.999];

/// The last group (ρ′ above 0.999) walks this fraction of the photons.
pub const WALK_LAST_GROUP_SHARE: u64 = 8;

/// What to bake.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkBake {
    /// Relative index η.
    pub eta: f64,
    /// Henyey–Greenstein asymmetry g of the walk.
    pub g: f64,
    /// Nodes of the table.
    pub grid: Grid,
    /// Photons per θ node for each group of rows (the last group takes
    /// 1/[`WALK_LAST_GROUP_SHARE`] of them).
    pub photons: u64,
    /// Seed of the walks.
    pub seed: u64,
    /// Whether to keep the CDF over θ for path tracing.
    pub theta_sampling: bool,
    /// What the table holds: the walk's multiple scattering, or the total with single
    /// scattering added by quadrature (module docs).
    pub component: WalkComponent,
}

/// What a walk bake did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WalkBakeReport {
    /// Wall time, seconds.
    pub seconds: f64,
    /// Threads of the pool.
    pub threads: usize,
    /// Photons walked in all.
    pub photons: u64,
    /// Scattering events of all walks.
    pub scattering_events: u64,
    /// Median relative standard error of the nodes' E with ρ′ ≥ 0.1 and r in [0.01, 20]
    /// reduced mfp.
    pub median_rel_stderr: f64,
    /// 90th percentile of the same.
    pub p90_rel_stderr: f64,
    /// (ρ′ > 0, θ) rows with no node whose μ̂₀ the walk measured within 30 %: stored as PBD's
    /// (the walk saw too little of them; more photons).
    pub rows_from_pbd: usize,
    /// Per θ node above 0 where light enters (not the limit of a beam in the surface), how far
    /// the stored two-lobe nodes are from the profile they were fitted to: the part of the
    /// table's error that is the format's and not the walk's.
    pub node_fit: Vec<NodeFit>,
    /// Per θ node where light enters, how far the profiles the nodes were fitted to are from
    /// the walk's own measured harmonics: the part of the table's error that is the model of
    /// the walk's shape (PBD tilted, or lobes fitted to the walk where the tilt misses it),
    /// beyond the walk's noise.
    pub walk_miss: Vec<WalkMiss>,
}

/// The radii, reduced mfp, over which [`WalkMiss`] compares the profiles with the walk (the
/// far band of [`NodeFit`]: nearer, the multiple scattering's high harmonics are mostly noise).
pub const WALK_MISS_R: [f64; 2] = [NODE_FIT_SPLIT_R, 20.0];

/// How far the profiles of one θ node's nodes with ρ′ ≥ 0.1 and r in [`WALK_MISS_R`] (those the
/// walk measured well enough to tilt) are from the walk's measured harmonics μ̂₁ … μ̂₈, kernel
/// averages against kernel averages. The profile is the one the stored lobes were fitted to,
/// before the single scattering of a total table (which is exact): what [`NodeFit`] measures
/// comes on top.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WalkMiss {
    /// The incidence, degrees, as in [`NodeFit`].
    pub theta_deg: f64,
    /// Nodes compared.
    pub nodes: usize,
    /// The relative root mean square over φ of the profile less the walk, beyond the walk's
    /// noise (√ of the nodes' unbiased estimates, weighted by their precision; 0 where that
    /// mean is below 0, that is within the noise); `None` (left out of JSON, whose readers refuse null) without a node.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms: Option<f64>,
    /// Mean over the nodes of χ² per harmonic, Σₙ (Δμₙ/σₙ)²/8: about 1 where the profiles are
    /// the walk's within its noise; `None` (left out of JSON, whose readers refuse null) without a node.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chi2: Option<f64>,
    /// What the nodes of this θ node were fitted to.
    pub profile: WalkProfile,
    /// Where that is [`WalkProfile::Lobes`], the [`WalkMiss::rms`] of the tilted PBD they
    /// replaced; `None` (left out) otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tilt_rms: Option<f64>,
    /// Likewise its [`WalkMiss::chi2`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tilt_chi2: Option<f64>,
}

/// The profile the nodes of a θ node were fitted to (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum WalkProfile {
    /// PBD tilted to the walk's harmonics.
    Tilt,
    /// A floor and two lobes fitted straight to the walk's harmonics, where the tilt misses
    /// the walk by more than [`WALK_MISS_WARNING`] and χ² [`WALK_MISS_CHI2`] and the lobes
    /// miss it less.
    Lobes,
}

impl WalkMiss {
    /// The miss of the tilted PBD over `nodes`.
    fn of(theta_deg: f64, nodes: &[NodeMiss]) -> WalkMiss {
        let n = nodes.len();
        let weight: f64 = nodes.iter().map(|m| m.weight).sum();
        let excess = nodes.iter().map(|m| m.weight * m.excess).sum::<f64>() / weight;
        WalkMiss {
            theta_deg,
            nodes: n,
            rms: (n > 0).then(|| excess.max(0.0).sqrt()),
            chi2: (n > 0).then(|| nodes.iter().map(|m| m.chi2).sum::<f64>() / n as f64),
            profile: WalkProfile::Tilt,
            tilt_rms: None,
            tilt_chi2: None,
        }
    }

    /// This miss, of lobes, where they replaced the tilt whose miss is `tilt`.
    fn instead_of(&self, tilt: &WalkMiss) -> WalkMiss {
        WalkMiss {
            profile: WalkProfile::Lobes,
            tilt_rms: tilt.rms,
            tilt_chi2: tilt.chi2,
            ..*self
        }
    }

    /// Whether the miss is beyond [`WALK_MISS_WARNING`] RMS with χ² above
    /// [`WALK_MISS_CHI2`]: a miss the walk tells from its noise, larger than the table's goal.
    pub fn warns(&self) -> bool {
        self.rms.is_some_and(|rms| rms > WALK_MISS_WARNING)
            && self.chi2.is_some_and(|chi2| chi2 > WALK_MISS_CHI2)
    }
}

/// How well the stored nodes of one θ node hold the profiles the bake fitted them to (the
/// tilted PBD, plus single scattering for a total table), over the nodes with ρ′ ≥ 0.1 in two
/// bands of radius: each node's error is the share of its energy the stored lobes put
/// elsewhere (relative L1 over φ: Σ |stored − profile| / Σ profile at 36 azimuths).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct NodeFit {
    /// The incidence, degrees, to 10⁻⁴° (the axis holds it in f32 radians, 10 degrees as
    /// 9.9999997…; f32 steps there are 10⁻⁵° and finer).
    pub theta_deg: f64,
    /// r in [0.01, [`NODE_FIT_SPLIT_R`]) reduced mfp: where single scattering is most of a
    /// total's profile near grazing incidence, and where a multiple table's tilt follows the
    /// walk's noise in μ̂₃, μ̂₄, which two lobes smooth away (most of this band's figure for a
    /// multiple table: it halves with four times the photons, docs/walk-table.md).
    pub near: FitBand,
    /// r in [[`NODE_FIT_SPLIT_R`], 20] reduced mfp.
    pub far: FitBand,
}

/// [`NodeFit`]'s figures over the nodes of one band of radius.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FitBand {
    /// Nodes measured.
    pub nodes: usize,
    /// Mean over the nodes of their error (fraction); `None` (left out of JSON, whose readers refuse null) without a node.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean: Option<f64>,
    /// 90th percentile of it; `None` (left out of JSON, whose readers refuse null) without a node.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p90: Option<f64>,
}

impl FitBand {
    fn of(mut errors: Vec<f64>) -> FitBand {
        errors.sort_by(f64::total_cmp);
        let n = errors.len();
        FitBand {
            nodes: n,
            mean: (n > 0).then(|| errors.iter().sum::<f64>() / n as f64),
            p90: quantile_of(&errors, 0.9),
        }
    }
}

/// The value at fraction `q` of the way through `sorted` (the nearest rank); `None` if empty.
fn quantile_of(sorted: &[f64], q: f64) -> Option<f64> {
    let last = sorted.len().checked_sub(1)?;
    Some(sorted[(last as f64 * q).round() as usize])
}

/// The radius (reduced mfp) between [`NodeFit`]'s two bands.
pub const NODE_FIT_SPLIT_R: f64 = 0.1;

/// The node fit above which a bake warns ([`WalkBakeReport::node_fit_warnings`]): nodes that
/// miss their profiles by 2 % of their energy are off by more than the walk table's goal, 1.5
/// times the noise of a 10⁷-photon walk (1.2–1.9 % at g = 0, docs/walk-table.md), on that alone.
pub const NODE_FIT_WARNING: f64 = 0.02;

/// The miss of the walk above which a bake warns ([`WalkBakeReport::walk_miss_warnings`]), as
/// [`WalkMiss::rms`]: profiles 2 % RMS off the walk beyond its noise are off by more than the
/// walk table's goal on that alone, as for [`NODE_FIT_WARNING`].
pub const WALK_MISS_WARNING: f64 = 0.02;

/// The χ² per harmonic ([`WalkMiss::chi2`]) a θ node's miss must also exceed for a warning: a
/// miss the walk tells from its noise (within it χ² is about 1: 0.8–1.1 over every θ node of
/// the default bakes at η = 1.33, docs/walk-table.md).
pub const WALK_MISS_CHI2: f64 = 2.0;

impl WalkBakeReport {
    /// One warning per θ node whose profiles miss the walk's measured harmonics by more than
    /// [`WALK_MISS_WARNING`] RMS beyond its noise, with χ² per harmonic above
    /// [`WALK_MISS_CHI2`]: there the tilt of PBD does not follow the walk's shape, and no fit
    /// of the lobes mends that.
    pub fn walk_miss_warnings(&self) -> Vec<String> {
        self.walk_miss
            .iter()
            .filter_map(|miss| {
                let (rms, chi2) = (miss.rms?, miss.chi2?);
                miss.warns().then(|| {
                    format!(
                        "at theta {:.1} deg the profile the nodes were fitted to ({}) is {:.1} % RMS over phi away from the walk's own measured harmonics beyond its noise (chi2 {:.1} per harmonic, over {} nodes at r {}-{} reduced mfp; more than {:.0} %): the table inherits that miss, whatever its lobes do (docs/walk-table.md, \"The bake's own measure of it\")",
                        miss.theta_deg,
                        match miss.profile {
                            WalkProfile::Tilt => "PBD tilted to the walk's harmonics",
                            WalkProfile::Lobes => "two lobes fitted to the walk's harmonics",
                        },
                        100.0 * rms,
                        chi2,
                        miss.nodes,
                        WALK_MISS_R[0],
                        WALK_MISS_R[1],
                        100.0 * WALK_MISS_WARNING
                    )
                })
            })
            .collect()
    }

    /// One warning per θ node whose nodes miss their profiles by more than
    /// [`NODE_FIT_WARNING`] of their energy on average: in the far band, and for a total table
    /// (`component`) in the near band too (a multiple table's near band is mostly the walk's
    /// noise, which the lobes smooth away; a total's is single scattering's shape).
    pub fn node_fit_warnings(&self, component: WalkComponent) -> Vec<String> {
        let over = |band: &FitBand| band.mean.filter(|&m| m > NODE_FIT_WARNING);
        self.node_fit
            .iter()
            .filter_map(|fit| {
                let far = over(&fit.far).map(|m| (m, "0.1-20"));
                let near = over(&fit.near)
                    .filter(|_| component == WalkComponent::Total)
                    .map(|m| (m, "0.01-0.1"));
                let (mean, band) = far.into_iter().chain(near).max_by(|a, b| a.0.total_cmp(&b.0))?;
                Some(format!(
                    "at theta {:.1} deg the stored nodes are {:.1} % of their energy away from the profile they were fitted to (PBD tilted to the walk's harmonics{}), on average (r {band} reduced mfp; more than {:.0} %): two lobes do not hold the walk's shape there (docs/walk-table.md, \"What two lobes cannot hold\")",
                    fit.theta_deg,
                    100.0 * mean,
                    if component == WalkComponent::Total {
                        ", plus single scattering"
                    } else {
                        ""
                    },
                    100.0 * NODE_FIT_WARNING
                ))
            })
            .collect()
    }
}

/// A row's cells, the relative standard errors and the node fit errors it adds to the report,
/// and whether the walk measured a node of it.
type RowCells = (Vec<[f64; 5]>, Vec<f64>, [Vec<f64>; 2], bool);

/// Points of the kernel averages of PBD on each side of a node, in ln r.
const CONTROL_POINTS: usize = 3;

/// Largest relative standard error of a node's μ̂₀ for its own tilt to be measured; a noisier
/// node takes the nearest measured node's (module docs).
const MAX_REL_STDERR: f64 = 0.3;

/// Half-width, in reliable nodes, of the local fit that smooths the walk/PBD ratio along r.
const SMOOTH_NODES: usize = 6;

/// The fewest points on each side of a node for its smoothing to be quadratic ([`smooth_tilt`]).
const MIN_QUADRATIC_SIDE: usize = 3;

/// Points of PBD's harmonics over φ ([`control_harmonics`]).
const CONTROL_AZIMUTHS: usize = 16;

/// Bakes the table of `config` from the walk (module docs). Deterministic for a seed on any
/// thread count (runs on the current rayon pool); `progress(n)` receives photons as they are
/// walked, [`walk_bake_photons`] in all.
pub fn bake_walk(
    config: &WalkBake,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(AngularTable, WalkBakeReport)> {
    let start = Instant::now();
    let (eta, grid) = (config.eta, &config.grid);
    let boundary = Boundary::new(eta, Moments::Exact)?;
    let (grid, axes) = checked_grid(grid)?;
    let grid = &grid;
    let (n_rho, n_theta, n_r) = axes.dims();
    let groups = row_groups(&grid.rho);
    for (_, share) in groups.iter().filter(|(rows, _)| !rows.is_empty()) {
        check_photons(config.photons / share)?;
    }

    let mut params = vec![0.0f32; n_rho * n_theta * n_r * PARAMS_PER_NODE];
    let mut second = vec![0.0f32; n_rho * n_theta * n_r * 2];
    let (mut photons, mut events) = (0u64, 0u64);
    let mut rel_stderr = Vec::new();
    let r_max = grid.r[n_r - 1];
    let mut rows_from_pbd = 0;
    let mut node_fit = Vec::new();
    let mut walk_miss = Vec::new();
    let rules = (
        GaussLegendre::new(CONTROL_POINTS),
        GaussLegendre::new(CONTROL_AZIMUTHS),
    );
    for (j, &theta_node) in grid.theta.iter().enumerate() {
        let theta = theta_node.min(0.5 * PI);
        // Beyond the critical angle no light enters: `assemble` copies the critical node
        if crate::fresnel::refracted_cos(theta, eta).is_none() && !beam_in_surface(eta, theta) {
            continue;
        }
        // The critical node rounded to f32 may lie a hair beyond asin η
        let walk_theta = if eta < 1.0 {
            theta.min(eta.asin())
        } else {
            theta
        };
        let in_surface = beam_in_surface(eta, theta);
        let single = match config.component {
            WalkComponent::Multiple => None,
            WalkComponent::Total => Some(SinglePart::new(
                config.g, eta, walk_theta, in_surface, &grid.r,
            )?),
        };
        // Walk every group of rows and tilt PBD to each row
        let mut rows = Vec::with_capacity(n_rho);
        for (group, (members, share)) in groups.iter().enumerate() {
            if members.is_empty() {
                continue;
            }
            let walk = HarmonicsConfig {
                rho: members.iter().map(|&i| grid.rho[i]).collect(),
                g: config.g,
                eta,
                theta: walk_theta,
                r: grid.r.clone(),
                photons: config.photons / share,
                seed: crate::rng::mix64(
                    crate::rng::mix64(config.seed) ^ (j as u64 * 4 + group as u64 + 1),
                ),
            };
            let h = harmonics(&walk, progress)?;
            photons += h.photons();
            events += h.scattering_events();
            let tilted: Vec<Result<(usize, RowPbd, RowTilts)>> = members
                .par_iter()
                .enumerate()
                .map(|(k, &i)| {
                    let pbd = RowPbd::new(grid.rho[i], boundary, theta, r_max)?;
                    let tilts = row_tilts(&h, k, &grid.r, &pbd.control(&rules, config.component));
                    Ok((i, pbd, tilts))
                })
                .collect();
            for row in tilted {
                rows.push(row?);
            }
        }
        let theta_deg = (theta.to_degrees() * 1e4).round() / 1e4;
        let tilts: Vec<(usize, &RowTilts)> = rows.iter().map(|(i, _, t)| (*i, t)).collect();
        let (profiles, miss) = node_profiles(&tilts, grid, theta_deg, theta > 0.0 && !in_surface);
        walk_miss.push(miss);
        // Each row's cells from its profiles, in parallel
        let cells: Vec<Result<(usize, RowCells)>> = rows
            .into_par_iter()
            .zip(profiles)
            .map(|((i, pbd, tilts), profiles)| {
                let albedo = unreduced_albedo(grid.rho[i], config.g);
                let single = single.as_ref().map(|part| (part, albedo));
                let control = pbd.control(&rules, config.component);
                let (out, fits) = row_cells(&profiles, &grid.r, &control, single)?;
                let noise = reported(grid.rho[i], &grid.r, &tilts.rel, |r| {
                    (0.01..=20.0).contains(&r)
                });
                let fits = [
                    reported(grid.rho[i], &grid.r, &fits, |r| {
                        (0.01..NODE_FIT_SPLIT_R).contains(&r)
                    }),
                    reported(grid.rho[i], &grid.r, &fits, |r| {
                        (NODE_FIT_SPLIT_R..=20.0).contains(&r)
                    }),
                ];
                Ok((i, (out, noise, fits, !tilts.reliable.is_empty())))
            })
            .collect();
        let mut fit_errors = [Vec::new(), Vec::new()];
        for row in cells {
            let (i, (harm, noise, fits, measured)) = row?;
            rel_stderr.extend(noise);
            for (band, fits) in fit_errors.iter_mut().zip(fits) {
                band.extend(fits);
            }
            // ρ′ = 0 has nothing to measure and is PBD's (0) by right
            if !measured && grid.rho[i] > 0.0 {
                rows_from_pbd += 1;
            }
            let base = (i * n_theta + j) * n_r;
            for (node, cell) in harm.iter().enumerate() {
                let at = base + node;
                params[at * PARAMS_PER_NODE] = to_f32(cell[0]);
                params[at * PARAMS_PER_NODE + 1] = to_f32(cell[1]);
                params[at * PARAMS_PER_NODE + 2] = cell[2] as f32;
                second[at * 2] = to_f32(cell[3]);
                second[at * 2 + 1] = to_f32(cell[4]);
            }
        }
        let [near, far] = fit_errors;
        if !near.is_empty() || !far.is_empty() {
            node_fit.push(NodeFit {
                theta_deg,
                near: FitBand::of(near),
                far: FitBand::of(far),
            });
        }
    }
    let table = assemble(
        eta,
        Moments::Exact,
        grid,
        axes,
        (params, second),
        config.theta_sampling,
        crate::table::ridge::RidgeKind::None,
    )?
    // Marked as the walk's: its lookups then spline the total along ρ′ as single scattering
    // needs (`AngularTable::with_walk`)
    .with_walk(WalkSource {
        g: config.g,
        component: config.component,
    });
    rel_stderr.sort_by(f64::total_cmp);
    let quantile = |q: f64| quantile_of(&rel_stderr, q).unwrap_or(f64::NAN);
    let report = WalkBakeReport {
        seconds: start.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
        photons,
        scattering_events: events,
        median_rel_stderr: quantile(0.5),
        p90_rel_stderr: quantile(0.9),
        rows_from_pbd,
        node_fit,
        walk_miss,
    };
    Ok((table, report))
}

/// The photons a [`bake_walk`] of `config` walks in all (for a progress bar).
pub fn walk_bake_photons(config: &WalkBake) -> u64 {
    let groups = row_groups(&config.grid.rho);
    let lit = config
        .grid
        .theta
        .iter()
        .filter(|&&t| {
            let t = f64::from(t as f32).min(0.5 * PI);
            crate::fresnel::refracted_cos(t, config.eta).is_some() || beam_in_surface(config.eta, t)
        })
        .count() as u64;
    let per_theta: u64 = groups
        .iter()
        .filter(|(rows, _)| !rows.is_empty())
        .map(|(_, share)| config.photons / share)
        .sum();
    lit * per_theta
}

/// The rows of each group and the divisor of its photons.
fn row_groups(rho: &[f64]) -> [(Vec<usize>, u64); 3] {
    let mut groups = [
        (Vec::new(), 1),
        (Vec::new(), 1),
        (Vec::new(), WALK_LAST_GROUP_SHARE),
    ];
    for (i, &p) in rho.iter().enumerate() {
        let g = WALK_GROUP_EDGES
            .iter()
            .take_while(|&&edge| p > edge)
            .count();
        groups[g].0.push(i);
    }
    groups
}

fn check_photons(photons: u64) -> Result<()> {
    if photons < MIN_HARMONICS_PHOTONS {
        return Err(Error::CountOutOfRange {
            name: "photons of a row group",
            value: photons,
            min: MIN_HARMONICS_PHOTONS,
            max: u64::MAX,
        });
    }
    Ok(())
}

/// The values at a row's nodes that the report counts: those of a row of albedo ρ′ ≥ 0.1 at
/// radii r `in_band`.
fn reported<T: Copy>(
    rho: f64,
    r: &[f64],
    values: &[Option<T>],
    in_band: impl Fn(f64) -> bool,
) -> Vec<T> {
    if rho < 0.1 {
        return Vec::new();
    }
    r.iter()
        .zip(values)
        .filter(|(&r, _)| in_band(r))
        .filter_map(|(_, v)| *v)
        .collect()
}

/// The profile of every node of a θ node's rows (`rows`: (row, its tilts)) and the θ node's
/// [`WalkMiss`]: the tilted PBD, or, where `lobes_allowed` (θ above 0, light not in the surface)
/// and the tilts' miss of the walk warns ([`WalkMiss::warns`]), lobes fitted to the walk's
/// harmonics ([`row_lobes`]) wherever they were fitted, if their miss is the smaller (χ² per
/// harmonic over the same nodes; module docs, "Where the tilt misses the walk").
fn node_profiles(
    rows: &[(usize, &RowTilts)],
    grid: &Grid,
    theta_deg: f64,
    lobes_allowed: bool,
) -> (Vec<Vec<Option<NodeProfile>>>, WalkMiss) {
    let miss_of = |misses: &mut dyn Iterator<Item = (usize, &[Option<NodeMiss>])>| {
        let nodes: Vec<NodeMiss> = misses
            .flat_map(|(i, m)| {
                reported(grid.rho[i], &grid.r, m, |r| {
                    (WALK_MISS_R[0]..=WALK_MISS_R[1]).contains(&r)
                })
            })
            .collect();
        WalkMiss::of(theta_deg, &nodes)
    };
    let tilt_miss = miss_of(&mut rows.iter().map(|(i, t)| (*i, t.misses.as_slice())));
    let tilted = |t: &RowTilts| t.tilts.iter().map(|t| t.map(NodeProfile::Tilted)).collect();
    if !(lobes_allowed && tilt_miss.warns()) {
        return (rows.iter().map(|(_, t)| tilted(t)).collect(), tilt_miss);
    }
    let lobes: Vec<_> = rows
        .par_iter()
        .map(|(_, t)| row_lobes(t, &grid.r))
        .collect();
    let lobes_miss = miss_of(
        &mut rows
            .iter()
            .zip(&lobes)
            .map(|((i, _), (_, m))| (*i, m.as_slice())),
    );
    let closer = lobes_miss
        .chi2
        .zip(tilt_miss.chi2)
        .is_some_and(|(lobes, tilt)| lobes < tilt);
    if !closer {
        return (rows.iter().map(|(_, t)| tilted(t)).collect(), tilt_miss);
    }
    let profiles = rows
        .iter()
        .zip(lobes)
        .map(|((_, t), (lobes, _))| {
            t.tilts
                .iter()
                .zip(lobes)
                .map(|(tilt, lobes)| match lobes {
                    Some(l) => Some(NodeProfile::Lobes(l)),
                    None => tilt.map(NodeProfile::Tilted),
                })
                .collect()
        })
        .collect();
    (profiles, lobes_miss.instead_of(&tilt_miss))
}

/// PBD at one (ρ′, θ) and its analytic ridge: what a row's [`Control`] refers to.
struct RowPbd {
    pbd: Pbd,
    /// The incidence, `None` for a beam in the surface.
    theta: Option<f64>,
    ridge: Option<Ridge>,
    /// The harmonics of the tilt beside the ridge's share ([`ridge_tilt_terms`]).
    ridge_tilt_terms: usize,
}

impl RowPbd {
    fn new(rho: f64, boundary: Boundary, theta: f64, r_max: f64) -> Result<RowPbd> {
        let eta = boundary.eta();
        let in_surface = beam_in_surface(eta, theta);
        let refracted = crate::fresnel::refracted_cos(theta, eta);
        // (the beam in the surface keeps PBD's own shape). The flux part alone: the narrow
        // lobe that the walk has weaker and wider; its broad fluence lobes stay in PBD (module
        // docs, "The ridge's share")
        let ridge = refracted
            .filter(|_| !in_surface && ridge::reaches(eta))
            .and_then(|c| Ridge::with_cos(RidgeKind::Flux, &boundary, rho, c, r_max));
        Ok(RowPbd {
            pbd: Pbd::new(rho, boundary)?,
            theta: (!in_surface).then_some(theta),
            ridge,
            ridge_tilt_terms: refracted.map_or(RIDGE_TILT_TERMS, ridge_tilt_terms),
        })
    }

    fn control<'a>(
        &'a self,
        rules: &'a (GaussLegendre, GaussLegendre),
        component: WalkComponent,
    ) -> Control<'a> {
        Control {
            pbd: &self.pbd,
            theta: self.theta,
            rules,
            ridge: self.ridge.as_ref(),
            max_widening: max_ridge_widening(component),
            ridge_tilt_terms: self.ridge_tilt_terms,
        }
    }
}

/// PBD at one (ρ′, θ), the model of the correction: `theta` `None` for a beam in the surface.
struct Control<'a> {
    pbd: &'a Pbd,
    theta: Option<f64>,
    rules: &'a (GaussLegendre, GaussLegendre),
    /// PBD's analytic ridge at this (ρ′, θ), where it has weight (module docs, "The ridge").
    ridge: Option<&'a Ridge>,
    /// The most the walk's share of the ridge may be widened ([`fit_ridge_tilt`]).
    max_widening: f64,
    /// The harmonics of the tilt beside the ridge's share ([`ridge_tilt_terms`]).
    ridge_tilt_terms: usize,
}

/// The most harmonics of a tilt, 1 + a₁ cos φ + … + a₄ cos 4φ ([`fit_tilt`]).
const TILT_TERMS: usize = 4;

/// A tilt's coefficients a₁ … a₄ (a₃ = a₄ = 0 for a two-term tilt).
type Shape = [f64; TILT_TERMS];

/// PBD's harmonics kept for the correction: μ₀ … μ₈ (a tilt's cos 4φ moves μ₄ to μ₈).
const PBD_HARMONICS: usize = HARMONICS + TILT_TERMS;

/// One node of a row as the walk measured it, with PBD at the node and its kernel average.
struct Measured {
    mean: [f64; HARMONICS],
    /// Standard errors of μ̂₀ … μ̂₈.
    se: [f64; HARMONICS],
    /// Relative standard error of μ̂₀ (`None` where μ̂₀ ≤ 0 or r = 0).
    rel: Option<f64>,
    /// PBD's harmonics at the node and their kernel average, less the ridge's where there
    /// is one (then in `ridge`).
    at_node: [f64; PBD_HARMONICS],
    average: [f64; PBD_HARMONICS],
    /// The ridge's harmonics at the node and their kernel average (0 without a ridge).
    ridge: [[f64; PBD_HARMONICS]; 2],
}

impl Measured {
    /// PBD's energy μ₀ at the node, its whole ridge included.
    fn pbd_at_node(&self) -> f64 {
        with_share(&self.at_node, &self.ridge[0], 1.0, 0.0)[0]
    }

    /// PBD's energy μ₀ averaged over the node's kernel, its whole ridge included (P̄₀).
    fn pbd_average(&self) -> f64 {
        with_share(&self.average, &self.ridge[1], 1.0, 0.0)[0]
    }

    /// Whether the node's walk/PBD ratio is known well enough to stand for its neighbours'.
    fn reliable(&self) -> bool {
        // (PBD itself, its ridge included: less it, the energy can be ≤ 0 far out)
        self.rel.is_some_and(|x| x <= MAX_REL_STDERR)
            && self.pbd_at_node() > 0.0
            && self.pbd_average() > 0.0
    }

    /// Whether PBD with the share s of its ridge, tilted by its aₘ, holds energy at the node
    /// and in its kernel average (where the ridge reaches past PBD, less of it may not).
    fn holds_energy(&self, tilt: Tilt) -> bool {
        let (a, s, w) = (shape(&tilt), tilt[SHARE], tilt[WIDENING]);
        let at = |smooth, ridge| tilted(&with_share(smooth, ridge, s, w), 0.0, a)[0] > 0.0;
        at(&self.at_node, &self.ridge[0])
            && (self.average[0] == 0.0 || at(&self.average, &self.ridge[1]))
    }
}

/// The harmonics of k · P(φ) · (1 + Σₘ aₘ cos mφ), P the profile of harmonics `p`
/// (μₙ = ∫ P cos nφ dφ, so cos mφ · cos nφ moves half of μₙ to μₙ₋ₘ and half to μₙ₊ₘ).
fn tilted(p: &[f64; PBD_HARMONICS], ln_k: f64, a: Shape) -> [f64; HARMONICS] {
    let at = |n: i32| p[n.unsigned_abs() as usize];
    std::array::from_fn(|n| {
        let n = n as i32;
        let moved: f64 = (1..)
            .zip(a)
            .map(|(m, am)| 0.5 * am * (at(n - m) + at(n + m)))
            .sum();
        ln_k.exp() * (at(n) + moved)
    })
}

/// 1 + Σₘ aₘ cos mφ.
fn tilt_factor(a: &Shape, phi: f64) -> f64 {
    1.0 + (1..)
        .zip(a)
        .map(|(m, am)| am * (f64::from(m) * phi).cos())
        .sum::<f64>()
}

/// Smallest value a tilt's factor 1 + Σₘ aₘ cos mφ may take: the tilted profile stays
/// positive.
const MIN_TILT_FACTOR: f64 = 0.05;

/// Azimuths from 0 to π (ends included) at which [`lowest_factor`] evaluates a tilt.
const FACTOR_AZIMUTHS: usize = 256;

/// A lower bound of 1 + Σₘ aₘ cos mφ over φ: its least value at [`FACTOR_AZIMUTHS`] azimuths
/// h apart, less h²/8 · Σₘ m²|aₘ| (how far a function whose second derivative is bounded by
/// that can dip below the chord between two of them). Tight to about 2·10⁻⁵ · Σₘ m²|aₘ|.
fn lowest_factor(a: &Shape) -> f64 {
    let h = PI / (FACTOR_AZIMUTHS - 1) as f64;
    let curvature: f64 = (1..)
        .zip(a)
        .map(|(m, am)| f64::from(m * m) * am.abs())
        .sum();
    let least = (0..FACTOR_AZIMUTHS)
        .map(|i| tilt_factor(a, i as f64 * h))
        .fold(f64::INFINITY, f64::min);
    least - h * h / 8.0 * curvature
}

/// `a` scaled back, where its factor would dip below [`MIN_TILT_FACTOR`] (by
/// [`lowest_factor`]), to the scale at which it just reaches it; 0 where it is not finite.
/// A tilt is scaled back only where its terms add up to nearly −1 at some azimuth: one whose
/// terms do not (1 + 0.6 cos φ + 0.45 cos 2φ, least 0.45) keeps what a bound on Σ |aₘ| would
/// cut.
fn bounded(a: Shape) -> Shape {
    let size: f64 = a.iter().map(|x| x.abs()).sum();
    if !size.is_finite() {
        return [0.0; TILT_TERMS];
    }
    if size <= 1.0 - MIN_TILT_FACTOR {
        return a;
    }
    // 1 + t·(lowest − 1) = MIN_TILT_FACTOR: the bound scales with a, the 1 does not
    let dip = 1.0 - lowest_factor(&a);
    if dip <= 1.0 - MIN_TILT_FACTOR {
        a
    } else {
        a.map(|x| x * (1.0 - MIN_TILT_FACTOR) / dip)
    }
}

/// The tilt (ln k, a₁ … a_`terms`) whose [`tilted`] kernel averages of PBD have the walk's
/// μ̂₀ … μ̂_`terms` (`terms` 2 or [`TILT_TERMS`]): `terms` linear equations for the aₘ from
/// μ̂ₙ/μ̂₀, then k from μ̂₀; the tilt [`bounded`].
fn fit_tilt(mean: &[f64; HARMONICS], p: &[f64; PBD_HARMONICS], terms: usize) -> (f64, Shape) {
    let at = |n: i32| p[n.unsigned_abs() as usize];
    // What cos mφ moves into μₙ
    let moved = |m: i32, n: i32| 0.5 * (at(n - m) + at(n + m));
    // Σₘ aₘ (Mₘ(n) − qₙ Mₘ(0)) = qₙ P₀ − Pₙ, qₙ = μ̂ₙ/μ̂₀, n = 1 … terms
    let mut system = [[0.0; TILT_TERMS + 1]; TILT_TERMS];
    for (n, row) in (1..).zip(system.iter_mut().take(terms)) {
        let q = mean[n as usize] / mean[0];
        for (m, x) in (1..).zip(row.iter_mut().take(terms)) {
            *x = moved(m, n) - q * moved(m, 0);
        }
        row[TILT_TERMS] = q * at(0) - at(n);
    }
    let a = bounded(solve_small(&mut system, terms).unwrap_or([0.0; TILT_TERMS]));
    let base = at(0) + (1..).zip(a).map(|(m, am)| am * moved(m, 0)).sum::<f64>();
    ((mean[0] / base).ln(), a)
}

/// The walk's tilt of PBD with the share s of PBD's ridge it keeps, widened by w:
/// (ln k, a₁ … a₄, s, w).
type Tilt = [f64; TILT_LEN];

/// The numbers of a [`Tilt`].
const TILT_LEN: usize = TILT_TERMS + 3;

/// Where s and w sit in a [`Tilt`].
const SHARE: usize = TILT_TERMS + 1;
const WIDENING: usize = TILT_TERMS + 2;

/// The tilt (ln k, a, s, w).
fn tilt_of(ln_k: f64, a: Shape, s: f64, w: f64) -> Tilt {
    let mut tilt = [0.0; TILT_LEN];
    tilt[0] = ln_k;
    tilt[1..=TILT_TERMS].copy_from_slice(&a);
    (tilt[SHARE], tilt[WIDENING]) = (s, w);
    tilt
}

/// The coefficients a₁ … a₄ of a tilt.
fn shape(tilt: &Tilt) -> Shape {
    std::array::from_fn(|m| tilt[m + 1])
}

/// A node's smoothed tilt and the harmonics of PBD with the tilt's share of its ridge.
type NodeTilt = (Tilt, [f64; PBD_HARMONICS]);

/// The tilt (ln k, a₁ … a₄, s, w) of a node from the walk's energy over PBD's, ln(μ̂₀/P̄₀), in
/// place of ln k: k = (μ̂₀/P̄₀) P̄₀/B̄, B̄ the energy of PBD with the share s of its ridge widened
/// by w, tilted by its aₘ (kernel averages, or the node's harmonics where it has none).
fn scale_of(m: &Measured, mut tilt: Tilt) -> Tilt {
    let (smooth, ridge) = if m.average[0] > 0.0 {
        (&m.average, &m.ridge[1])
    } else {
        (&m.at_node, &m.ridge[0])
    };
    let (ratio, s, w) = (tilt[0], tilt[SHARE], tilt[WIDENING]);
    let full = with_share(smooth, ridge, 1.0, 0.0)[0];
    let base = tilted(&with_share(smooth, ridge, s, w), 0.0, shape(&tilt))[0];
    if full > 0.0 && base > 0.0 {
        tilt[0] = ratio + (full / base).ln();
    }
    tilt
}

/// The largest share of PBD's ridge a walk node may keep.
pub const MAX_RIDGE_SHARE: f64 = 1.5;

/// The most a walk node may widen PBD's ridge: w in [`Ridge::widened`], each lobe's width
/// (1 − κ for the narrow ones) grown by up to this much.
pub const MAX_RIDGE_WIDENING: f64 = 0.15;

/// The most a table of `component` widens the walk's share of the ridge: a multiple table
/// [`MAX_RIDGE_WIDENING`], a total one 0. In a total table single scattering puts its own
/// ridge, as narrow as cos θ′, on φ = 0, and the nodes' sharp lobe holds both ridges best when
/// they are alike (module docs, "The ridge's share").
pub fn max_ridge_widening(component: WalkComponent) -> f64 {
    match component {
        WalkComponent::Multiple => MAX_RIDGE_WIDENING,
        WalkComponent::Total => 0.0,
    }
}

/// `smooth` + s · e^{−nw} · `ridge`, harmonic by harmonic n: PBD with the share s of its ridge
/// widened by w ([`Ridge::widened`]).
fn with_share(
    smooth: &[f64; PBD_HARMONICS],
    ridge: &[f64; PBD_HARMONICS],
    s: f64,
    w: f64,
) -> [f64; PBD_HARMONICS] {
    std::array::from_fn(|n| smooth[n] + s * (-w * n as f64).exp() * ridge[n])
}

/// The tilt of `terms` harmonics ([`ridge_tilt_terms`]) of PBD less its ridge plus the share
/// s of it widened by w whose kernel averages have the walk's μ̂₀ … μ̂_terms ([`fit_tilt`])
/// and, of the shares s ∈ [0, MAX_RIDGE_SHARE] and widenings w ∈ [0, `max_widening`] (at most
/// [`MAX_RIDGE_WIDENING`]), the harmonics above them, up to μ̂₈, closest (χ² with their standard errors): the ridge
/// is the profile's only part narrow enough to carry the high harmonics, and the walk's is
/// weaker and wider than PBD's near index matching. Without a ridge, (s, w) = (1, 0) (PBD
/// itself) and the tilt of [`TILT_TERMS`] harmonics that matches μ̂₀ … μ̂₄.
fn fit_ridge_tilt(m: &Measured, max_widening: f64, terms: usize) -> Tilt {
    let [_, ridge] = &m.ridge;
    if ridge.iter().all(|&x| x == 0.0) {
        let (ln_k, a) = fit_tilt(&m.mean, &m.average, TILT_TERMS);
        return tilt_of(ln_k, a, 1.0, 0.0);
    }
    // The tilt at (s, w) and its misses of the harmonics above it in standard errors
    let fit = |s: f64, w: f64| {
        let p = with_share(&m.average, ridge, s, w);
        let (ln_k, a) = fit_tilt(&m.mean, &p, terms);
        (misses(m, &tilted(&p, ln_k, a), terms), (ln_k, a))
    };
    let chi2 = |s: f64, w: f64| {
        let z = fit(s, w).0;
        let c = dot(&z, &z);
        if c.is_finite() {
            c
        } else {
            f64::INFINITY
        }
    };
    // A grid over (s, w), the first of equal misfits
    const STEPS: usize = 30;
    const WIDENING_STEPS: usize = 12;
    let step = MAX_RIDGE_SHARE / STEPS as f64;
    let max_widening = max_widening.clamp(0.0, MAX_RIDGE_WIDENING);
    let widening_steps = if max_widening > 0.0 {
        WIDENING_STEPS
    } else {
        0
    };
    let w_step = max_widening / WIDENING_STEPS as f64;
    let (mut best, mut s, mut w) = (0..=widening_steps)
        .flat_map(|j| (0..=STEPS).map(move |k| (k as f64 * step, j as f64 * w_step)))
        .map(|(s, w)| (chi2(s, w), s, w))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((f64::INFINITY, 1.0, 0.0));
    // then Levenberg–Marquardt steps on the two misses inside the bounds (s and w trade off
    // against each other along a narrow valley, which steps along one of them cross slowly)
    let mut lambda = 1e-3;
    for _ in 0..REFINE_STEPS {
        if !best.is_finite() || best == 0.0 {
            break;
        }
        let (z, _) = fit(s, w);
        // central differences, one-sided at the bounds
        let column = |x: f64, hi: f64, h: f64, at: &dyn Fn(f64) -> [f64; HARMONICS]| {
            let (a, b) = ((x - h).max(0.0), (x + h).min(hi));
            let (za, zb) = (at(a), at(b));
            std::array::from_fn(|n| (zb[n] - za[n]) / (b - a))
        };
        let js = column(s, MAX_RIDGE_SHARE, 1e-6, &|x| fit(x, w).0);
        let jw = if max_widening > 0.0 {
            column(w, max_widening, 1e-6, &|x| fit(s, x).0)
        } else {
            [0.0; HARMONICS]
        };
        // (JᵀJ + λ diag JᵀJ) δ = −Jᵀz
        let (a, b, d) = (dot(&js, &js), dot(&js, &jw), dot(&jw, &jw));
        let (gs, gw) = (dot(&js, &z), dot(&jw, &z));
        let (a, d) = (a * (1.0 + lambda), d * (1.0 + lambda));
        let det = a * d - b * b;
        // (where w does not act, s = 0, a step in s alone)
        let (ds, dw) = if det > 1e-12 * a * d {
            ((-d * gs + b * gw) / det, (b * gs - a * gw) / det)
        } else if a > 0.0 {
            (-gs / a, 0.0)
        } else {
            break;
        };
        let (s1, w1) = (
            (s + ds).clamp(0.0, MAX_RIDGE_SHARE),
            (w + dw).clamp(0.0, max_widening),
        );
        let c = chi2(s1, w1);
        if c < best {
            let moved = (s1 - s).abs() + (w1 - w).abs();
            (best, s, w) = (c, s1, w1);
            lambda = (lambda * 0.1).max(1e-12);
            if moved <= 1e-12 {
                break;
            }
        } else {
            lambda *= 10.0;
            if lambda > 1e8 {
                break;
            }
        }
    }
    let (ln_k, a) = fit(s, w).1;
    tilt_of(ln_k, a, s, w)
}

/// The misses of the walk's harmonics above the first `matched` by the harmonics `h`, in
/// standard errors of the walk (0 for μ̂₀ … μ̂_`matched`).
fn misses(m: &Measured, h: &[f64; HARMONICS], matched: usize) -> [f64; HARMONICS] {
    std::array::from_fn(|n| {
        if n <= matched {
            0.0
        } else {
            (h[n] - m.mean[n]) / m.se[n].max(1e-300)
        }
    })
}

fn dot(u: &[f64; HARMONICS], v: &[f64; HARMONICS]) -> f64 {
    u.iter().zip(v).map(|(a, b)| a * b).sum()
}

/// Harmonics of the tilt where PBD has its ridge at full weight ([`fit_ridge_tilt`],
/// [`ridge_tilt_terms`]). With more, the tilt and the share trade off against each other and
/// the fit follows the noise of the harmonics left to the share: at η = 1, 89° the zoo's mean
/// errors were 1.02–1.17 times those of two terms with three (the share fitted to μ̂₄ … μ̂₈) and
/// 1.1–1.9 times with four (μ̂₅ … μ̂₈; the ridge up to twice the walk's within 10° of φ = 0 at
/// r = 0.04–0.14).
const RIDGE_TILT_TERMS: usize = 2;

/// The harmonics of the tilt beside the ridge's share at cos θ′ = `cos_t`: [`RIDGE_TILT_TERMS`]
/// where the ridge has its full weight (cos θ′ ≤ [`ridge::FULL_WEIGHT_COS`]), [`TILT_TERMS`]
/// where it ramps in. There the ridge is a small part of the profile and the two terms left
/// the walk's shape beyond the share: at η = 1 (74° and 78°) the profiles missed the walk's
/// harmonics by 3.5–4.1 % RMS at g = 0 and 18–23 % at g = 0.9 (`walk_miss`), against 1.8–2.3 %
/// and 7–9 % with four, and the total table at 75° and 80° went from 1.05–1.40 to 0.92–1.29
/// times the floor of 10⁷-photon walks (docs/walk-table.md).
fn ridge_tilt_terms(cos_t: f64) -> usize {
    if cos_t <= ridge::FULL_WEIGHT_COS {
        RIDGE_TILT_TERMS
    } else {
        TILT_TERMS
    }
}

/// Levenberg–Marquardt steps of [`fit_ridge_tilt`] at most.
const REFINE_STEPS: usize = 60;

/// The tilt of every node of row `row` (module docs; `None` at r = 0 and where PBD is 0), the
/// relative standard error of each node's μ̂₀, and whether any node was measured well enough
/// to tilt (if none was, the row is PBD's).
fn row_tilts(h: &WalkHarmonics, row: usize, r: &[f64], control: &Control) -> RowTilts {
    let (gl, azimuths) = control.rules;
    let pbd_at = |x: f64| control_harmonics(control.pbd, x, control.theta, azimuths, control.ridge);
    let ridge_at = |x: f64| {
        control
            .ridge
            .map_or([0.0; PBD_HARMONICS], |g| g.harmonics::<PBD_HARMONICS>(x))
    };
    let kernels = kernels(r);
    let measured: Vec<Measured> = (0..r.len())
        .map(|node| {
            let kernel = kernels[node];
            let mean = h.mean(Component::Multiple, row, node).unwrap_or_default();
            let se = h.stderr(Component::Multiple, row, node).unwrap_or_default();
            if r[node] == 0.0 {
                let zero = [0.0; PBD_HARMONICS];
                return Measured {
                    mean,
                    se,
                    rel: None,
                    at_node: zero,
                    average: zero,
                    ridge: [zero; 2],
                };
            }
            Measured {
                mean,
                se,
                rel: (mean[0] > 0.0).then(|| se[0] / mean[0]),
                at_node: pbd_at(r[node]),
                average: kernel.map_or([0.0; PBD_HARMONICS], |k| k.average(gl, pbd_at)),
                ridge: [
                    ridge_at(r[node]),
                    kernel.map_or([0.0; PBD_HARMONICS], |k| k.average(gl, ridge_at)),
                ],
            }
        })
        .collect();
    let reliable: Vec<usize> = (0..r.len()).filter(|&k| measured[k].reliable()).collect();
    // The walk against PBD at each reliable node, as a tilt of PBD's profile, smoothed along
    // ln r (`smooth_tilt`)
    // With a ridge, k and s trade off against each other from node to node (both move the
    // energy), so what is smoothed is the walk's energy over PBD's, ln(μ̂₀/P̄₀), and k follows
    // from it and the smoothed shape (`scale_of`)
    let energy_form = control.ridge.is_some();
    let tilts: Vec<(f64, f64, Tilt)> = reliable
        .iter()
        .map(|&k| {
            let m = &measured[k];
            let rel = m.rel.unwrap_or(MAX_REL_STDERR);
            let mut tilt = fit_ridge_tilt(m, control.max_widening, control.ridge_tilt_terms);
            if energy_form {
                tilt[0] = (m.mean[0] / m.pbd_average()).ln();
            }
            (r[k].ln(), 1.0 / (rel * rel), tilt)
        })
        .collect();
    let smoothed: Vec<Tilt> = (0..reliable.len())
        .map(|i| smooth_tilt(&tilts, i))
        .collect();
    // Beyond the last measured node, ln k goes on along the line in r through the last ones
    // (far out both profiles fall exponentially, at rates that differ by a constant), by at
    // most a factor TAIL_MAX_FACTOR; between two measured nodes the tilt goes linearly in ln r
    // from one to the other; before the first it is the first's. A row with no measured node
    // is PBD's (no tilt).
    let slope = tail_slope(&tilts, &reliable, r);
    let max_step = TAIL_MAX_FACTOR.ln();
    let node_tilts: Vec<Option<NodeTilt>> = (0..r.len())
        .map(|node| {
            let here = &measured[node];
            if r[node] == 0.0 || here.pbd_at_node() <= 0.0 {
                return None;
            }
            let after = reliable.partition_point(|&k| k < node);
            let tilt = match (after.checked_sub(1), reliable.get(after)) {
                (None, Some(_)) => smoothed[0],
                (Some(i), None) => {
                    let mut tilt = smoothed[i];
                    let step = slope * (r[node] - r[reliable[i]]);
                    tilt[0] += step.clamp(-max_step, max_step);
                    tilt
                }
                (Some(_), Some(_)) => within_measured(&smoothed, &reliable, r, node)?,
                (None, None) => tilt_of(0.0, [0.0; TILT_TERMS], 1.0, 0.0),
            };
            let tilt = match tilt {
                // A share whose profile holds no energy at this node gives way to PBD's own
                _ if energy_form && !here.holds_energy(tilt) => {
                    scale_of(here, tilt_of(tilt[0], shape(&tilt), 1.0, 0.0))
                }
                _ if energy_form => scale_of(here, tilt),
                _ => tilt,
            };
            Some((
                tilt,
                with_share(&here.at_node, &here.ridge[0], tilt[SHARE], tilt[WIDENING]),
            ))
        })
        .collect();
    let rel = measured.iter().map(|m| m.rel).collect();
    // How far each measured node's profile is from the walk's own harmonics
    let misses = (0..r.len())
        .map(|node| {
            let m = &measured[node];
            let (tilt, _) = node_tilts[node].as_ref()?;
            m.reliable().then(|| NodeMiss::of_tilt(m, tilt))?
        })
        .collect();
    RowTilts {
        tilts: node_tilts,
        rel,
        misses,
        nodes: measured,
        reliable,
    }
}

/// The value at `node` of `smoothed` (one per reliable node, in the order of `reliable`): its
/// own at a reliable node, linear in ln r between two; `None` before the first and beyond the
/// last.
fn within_measured<const N: usize>(
    smoothed: &[[f64; N]],
    reliable: &[usize],
    r: &[f64],
    node: usize,
) -> Option<[f64; N]> {
    let after = reliable.partition_point(|&k| k < node);
    let k = *reliable.get(after)?;
    if k == node {
        return Some(smoothed[after]);
    }
    let i = after.checked_sub(1)?;
    let (u0, u1) = (r[reliable[i]].ln(), r[k].ln());
    let t = (r[node].ln() - u0) / (u1 - u0);
    Some(std::array::from_fn(|n| {
        smoothed[i][n] + t * (smoothed[after][n] - smoothed[i][n])
    }))
}

/// What [`row_tilts`] finds of a row, node by node.
struct RowTilts {
    /// The smoothed tilts (`None` at r = 0 and where PBD is 0).
    tilts: Vec<Option<NodeTilt>>,
    /// The relative standard error of each node's μ̂₀.
    rel: Vec<Option<f64>>,
    /// At each node the walk measured well enough to tilt, the tilted profile's miss of the
    /// walk's harmonics ([`NodeMiss`]).
    misses: Vec<Option<NodeMiss>>,
    /// Every node as the walk measured it.
    nodes: Vec<Measured>,
    /// The nodes measured well enough to tilt ([`Measured::reliable`]; if none was, the row
    /// is PBD's).
    reliable: Vec<usize>,
}

/// The profile of every node of a row as lobes fitted straight to the walk's harmonics (module
/// docs, "Where the tilt misses the walk"; `None` outside the measured nodes, at r = 0 and where
/// no admissible lobes hold the harmonics), and at each reliable node their miss of the walk.
///
/// At each reliable node, ln(μ̂₀/P̄₀) (the walk's energy over PBD's, kernel averages) and the
/// shape μ̂ₙ/μ̂₀, n = 1 … 8, smoothed along ln r as the tilts are ([`smooth_along_r`]) and
/// linear in ln r between two; the energy at the node e₀ = (μ̂₀/P̄₀)·P₀ (PBD at the node: the
/// kernel's bias taken out as for the tilt); [`Lobes::fit`] to e₀·(1, μ̂₁/μ̂₀, …) with weights
/// from the node's own standard errors, relative ones at least [`LEAST_REL_STDERR`].
fn row_lobes(row: &RowTilts, r: &[f64]) -> (Vec<Option<Lobes>>, Vec<Option<NodeMiss>>) {
    let points: Vec<(f64, f64, [f64; HARMONICS])> = row
        .reliable
        .iter()
        .map(|&k| {
            let m = &row.nodes[k];
            let rel = m.rel.unwrap_or(MAX_REL_STDERR);
            let mut v = m.mean.map(|x| x / m.mean[0]);
            v[0] = (m.mean[0] / m.pbd_average()).ln();
            (r[k].ln(), 1.0 / (rel * rel), v)
        })
        .collect();
    let smoothed: Vec<[f64; HARMONICS]> = (0..points.len())
        .map(|i| smooth_along_r(&points, i))
        .collect();
    let lobes: Vec<Option<Lobes>> = (0..r.len())
        .map(|node| {
            let v = within_measured(&smoothed, &row.reliable, r, node)?;
            let m = &row.nodes[node];
            let e0 = v[0].exp() * m.pbd_at_node();
            if !(e0 > 0.0 && m.mean[0] > 0.0) {
                return None;
            }
            let y = std::array::from_fn(|n| if n == 0 { e0 } else { v[n] * e0 });
            let w = std::array::from_fn(|n| {
                let rel = (m.se[n] / m.mean[0]).max(LEAST_REL_STDERR);
                1.0 / (rel * e0).powi(2)
            });
            Lobes::fit(&y, &w)
        })
        .collect();
    // Their kernel averages: the lobes' shape with the smoothed kernel-average energy
    let misses = (0..r.len())
        .map(|node| {
            let (m, l) = (&row.nodes[node], lobes[node].as_ref()?);
            if !m.reliable() {
                return None;
            }
            let h = l.harmonics::<HARMONICS>();
            let scale = m.pbd_average() / m.pbd_at_node();
            NodeMiss::between(m, &h.map(|x| x * scale))
        })
        .collect();
    (lobes, misses)
}

/// The least relative standard error a harmonic weighs with in [`row_lobes`]' fits (where the
/// walk's own is smaller, a node would be fitted as exact).
const LEAST_REL_STDERR: f64 = 1e-4;

/// How far the profile a node is fitted to (PBD with its share of the ridge, tilted: the
/// smoothed tilt, as stored) is from the walk's own measured harmonics μ̂₁ … μ̂₈ at the node,
/// kernel averages against kernel averages. By Parseval the relative mean square of the
/// difference over φ, ∫ Δ² dφ / (2π · mean²), is (Δμ₀² + 2 Σₙ Δμₙ²)/μ̂₀²; the walk's noise
/// adds 2 Σ σₙ² to its expectation, which is taken out. Δμ₀ is left out: the tilt's scale
/// matches it but for the smoothing, and the energy is checked apart (ρ_eff against the walk).
#[derive(Debug, Clone, Copy)]
struct NodeMiss {
    /// 2 Σₙ (Δμₙ² − σₙ²) / μ̂₀², n = 1 … 8: unbiased for the relative mean square miss.
    excess: f64,
    /// The inverse of its variance under noise alone, 1 / (8 Σₙ σₙ⁴ / μ̂₀⁴) (a normal
    /// Δμₙ of variance σₙ² has Var(2Δμₙ²) = 8σₙ⁴): what a node weighs in the θ node's mean.
    weight: f64,
    /// Σₙ (Δμₙ/σₙ)² / 8: about 1 where the profile is the walk's within its noise.
    chi2: f64,
}

impl NodeMiss {
    /// The miss of the tilted PBD of `tilt`.
    fn of_tilt(m: &Measured, tilt: &Tilt) -> Option<NodeMiss> {
        let p = with_share(&m.average, &m.ridge[1], tilt[SHARE], tilt[WIDENING]);
        NodeMiss::between(m, &tilted(&p, tilt[0], shape(tilt)))
    }

    /// The miss of a profile of kernel averages `h`.
    fn between(m: &Measured, h: &[f64; HARMONICS]) -> Option<NodeMiss> {
        let e0 = m.mean[0];
        let (mut excess, mut var, mut chi2) = (0.0, 0.0, 0.0);
        for ((hn, mean), se) in h.iter().zip(m.mean).zip(m.se).skip(1) {
            let (d, se) = ((hn - mean) / e0, se / e0);
            excess += 2.0 * (d * d - se * se);
            var += 8.0 * se.powi(4);
            chi2 += (d / se).powi(2);
        }
        let chi2 = chi2 / (HARMONICS - 1) as f64;
        (e0 > 0.0 && excess.is_finite() && var > 0.0 && chi2.is_finite()).then_some(NodeMiss {
            excess,
            weight: 1.0 / var,
            chi2,
        })
    }
}

/// The cells (E, E_β, c, r·μ₃, r·μ₄) of a row from its nodes' tilts (module docs): at r = 0
/// zeros (the bake then extends c); at θ = 0 PBD's isotropic node scaled to the walk's energy;
/// for a beam in the surface the harmonics of the tilted limit; elsewhere the two lobes fitted
/// to the tilted PBD at the azimuths of the PBD bake, scaled to the walk's energy. With
/// `single` (the θ node's single scattering and the row's unreduced albedo: a `total` table)
/// each node's profile is the tilted PBD plus the exact single scattering: its energy is the
/// sum's, its lobes are fitted to the sum at the same azimuths, its harmonics at a beam in the
/// surface are the sum's, and at θ = 0 the lobe keeps the multiple scattering's share of E.
///
/// With the cells, per node, how far the stored two lobes are from the profile they were fitted
/// to ([`node_fit_error`]; `None` at r = 0, θ = 0, a beam in the surface and a node of no energy).
fn row_cells(
    profiles: &[Option<NodeProfile>],
    r: &[f64],
    control: &Control,
    single: Option<(&SinglePart, f64)>,
) -> Result<(Vec<[f64; 5]>, Vec<NodeFitError>)> {
    let mut hint = None;
    let mut cells = Vec::with_capacity(r.len());
    let mut fits = Vec::with_capacity(r.len());
    for (node, profile) in profiles.iter().enumerate() {
        let r = r[node];
        let one = |r| {
            single.map_or(SingleNode::ZERO, |(part, albedo)| {
                part.node(albedo, node, r)
            })
        };
        let (tilt, at_node) = match profile {
            None => {
                cells.push([0.0; 5]);
                fits.push(None);
                continue;
            }
            Some(NodeProfile::Lobes(lobes)) => {
                // Stored as its harmonics, which the lookups' rebuild gives back as the lobes
                // (module docs, "Where the tilt misses the walk": refitted at the bake's
                // azimuths they lost most of it)
                let one = one(r);
                let h = lobes.harmonics::<SINGLE_HARMONICS>();
                let cell = harmonics_cell(std::array::from_fn(|n| h[n] + one.harmonics[n]), r);
                let stored = stored_node(cell, r);
                let check = check_azimuths();
                let fit_error = node_fit_error(
                    &check.map(|p| stored.eval(p)),
                    &std::array::from_fn(|i| lobes.eval(check[i]) + one.at_check[i]),
                );
                cells.push(cell);
                fits.push(fit_error);
                continue;
            }
            Some(NodeProfile::Tilted((tilt, at_node))) => (tilt, at_node),
        };
        let one = one(r);
        let (ln_k, a, share) = (tilt[0], shape(tilt), tilt[SHARE]);
        // The ridge and the walk's widened share of it
        let ridges = control.ridge.map(|g| (g, g.widened(tilt[WIDENING])));
        let m = tilted(at_node, ln_k, a);
        let energy = r * (m[0] + one.harmonics[0]);
        let mut fit_error = None;
        let cell = match control.theta {
            None => {
                // The stored shape is the limit's own, by the bake's accurate rule (the
                // control's coarse one only enters ratios of nearby radii)
                let m = tilted(&surface_harmonics(control.pbd, r, None), ln_k, a);
                harmonics_cell(std::array::from_fn(|n| m[n] + one.harmonics[n]), r)
            }
            Some(0.0) => {
                let [e, e_beta, _] = node_cell(control.pbd, 0.0, r)?.cell;
                [energy, (e_beta * energy / e).min(energy), 0.0, 0.0, 0.0]
            }
            Some(theta) => {
                // The tilted PBD with the walk's share of its ridge, plus single scattering
                // `s1` (0 for a multiple table)
                let profile = |p: f64, s1: f64| {
                    let pbd = control.pbd.eval(theta, r, p, Rule::Fast);
                    let pbd = match &ridges {
                        Some((g, wide)) => {
                            (pbd - g.eval(r, p) + share * wide.eval(r, p)).max(1e-3 * pbd)
                        }
                        None => pbd,
                    };
                    ln_k.exp() * pbd * tilt_factor(&a, p) + s1
                };
                let (cell, error) = fitted_cell(&profile, &one, energy, r, &mut hint);
                fit_error = error;
                cell
            }
        };
        cells.push(cell);
        fits.push(fit_error.filter(|_| r > 0.0));
    }
    if r[0] == 0.0 && r.len() >= 3 {
        let mut flat: Vec<f32> = cells
            .iter()
            .flat_map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
            .collect();
        flat[2] = r0_concentration(&flat, r);
        cells[0][2] = f64::from(flat[2]);
    }
    Ok((cells, fits))
}

/// The cell (E, E_β, c, r·μ₃, r·μ₄) at radius r of two lobes fitted to `profile(φ, S₁(φ))` (S₁
/// the node's single scattering `one`) at the bake's azimuths, scaled to the energy E
/// `energy`, and how far the stored node is from the profile ([`node_fit_error`]); `hint` is the
/// fit's start, the next node's after it.
fn fitted_cell(
    profile: &dyn Fn(f64, f64) -> f64,
    one: &SingleNode,
    energy: f64,
    r: f64,
    hint: &mut Option<[f64; 2]>,
) -> ([f64; 5], NodeFitError) {
    let (phi, y): (Vec<f64>, Vec<f64>) = two_lobe_azimuths()
        .iter()
        .zip(one.at_azimuths)
        .map(|(&p, s1)| (p, profile(p, s1)))
        .filter(|(_, v)| v.is_finite())
        .unzip();
    let (fit, next) = two_lobe_node_of(&phi, &y, r, *hint);
    *hint = next;
    if fit[0] <= 0.0 {
        return ([0.0; 5], None);
    }
    let k = energy / fit[0];
    let cell = [energy, fit[1] * k, fit[2], fit[3] * k, fit[4] * k];
    let stored = stored_node(cell, r);
    let check = check_azimuths();
    let error = node_fit_error(
        &check.map(|p| stored.eval(p)),
        &std::array::from_fn(|i| profile(check[i], one.at_check[i])),
    );
    (cell, error)
}

/// The cell (E, E_β, c, r·μ₃, r·μ₄) at radius r of the profile of harmonics μ₀ … μ₄ `m`.
fn harmonics_cell(m: [f64; SINGLE_HARMONICS], r: f64) -> [f64; 5] {
    let (beta, c) = one_lobe_of(m[1], m[2]);
    [
        r * m[0],
        r * within_floor(beta, c, m[0]),
        c,
        r * m[3],
        r * m[4],
    ]
}

/// What a node's profile is: PBD tilted to the walk ([`row_tilts`]), or lobes fitted straight
/// to the walk's harmonics ([`row_lobes`]).
#[derive(Debug, Clone, Copy)]
enum NodeProfile {
    Tilted(NodeTilt),
    Lobes(Lobes),
}

/// A node's [`node_fit_error`], `None` where it has none.
type NodeFitError = Option<f64>;

/// Azimuths at which a bake compares each stored node with the profile it was fitted to
/// ([`node_fit_error`]): the midpoints of 36 equal intervals of [0, π] (profiles are even in φ).
pub(super) const CHECK_AZIMUTHS: usize = 36;

/// The [`CHECK_AZIMUTHS`] azimuths, radians.
pub(super) fn check_azimuths() -> [f64; CHECK_AZIMUTHS] {
    std::array::from_fn(|i| PI * (i as f64 + 0.5) / CHECK_AZIMUTHS as f64)
}

/// How far a stored node is from its profile, both at [`check_azimuths`]: the relative L1
/// error Σ |stored − profile| / Σ profile (∫ |Δ| dφ / ∫ S dφ by the midpoint rule), the share
/// of the node's energy the stored lobes put elsewhere. Azimuths where either is not finite
/// are left out; `None` where the profile holds nothing.
fn node_fit_error(stored: &[f64; CHECK_AZIMUTHS], profile: &[f64; CHECK_AZIMUTHS]) -> Option<f64> {
    let (off, energy) = stored
        .iter()
        .zip(profile)
        .filter(|(s, p)| s.is_finite() && p.is_finite())
        .fold((0.0, 0.0), |(off, energy), (s, p)| {
            (off + (s - p).abs(), energy + p)
        });
    (energy > 0.0).then(|| off / energy)
}

/// The slope in r of ln k over the last [`TAIL_NODES`] measured nodes of a row (weighted least
/// squares, weights 1/σ²), 0 with fewer than three.
fn tail_slope(tilts: &[(f64, f64, Tilt)], reliable: &[usize], r: &[f64]) -> f64 {
    let n = tilts.len();
    if n < 3 {
        return 0.0;
    }
    let from = n.saturating_sub(TAIL_NODES);
    let (mut sw, mut sx, mut sxx, mut sy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (i, (_, w, y)) in tilts.iter().enumerate().skip(from) {
        let x = r[reliable[i]];
        sw += w;
        sx += w * x;
        sxx += w * x * x;
        sy += w * y[0];
        sxy += w * x * y[0];
    }
    let det = sw * sxx - sx * sx;
    if det.is_nan() || det <= 1e-12 * sw * sxx {
        return 0.0;
    }
    (sw * sxy - sx * sy) / det
}

/// The most the far tail's ln k may move beyond the last measured node (a factor).
const TAIL_MAX_FACTOR: f64 = 2.0;

/// Measured nodes at the end of a row whose ln k sets the slope of the far tail.
const TAIL_NODES: usize = 5;

/// The local quadratic fit in ln r, at point `i`, of the points within [`SMOOTH_NODES`] of it
/// ((ln r, weight, values) in increasing r): weighted least squares with the points' weights
/// times the tricube of their distance in points; a line where fewer than
/// [`MIN_QUADRATIC_SIDE`] points lie on one side of `i` (towards the ends of a row, where a
/// parabola through one side's points swings with their noise), in ln r at the near end and
/// in r at the far end (module docs, "Smooth"), the point itself where the window holds fewer
/// than three. A line leaves the curvature of the walk over PBD in ln r in
/// its value, which is not small near index matching (module docs, "Smooth").
fn smooth_tilt(points: &[(f64, f64, Tilt)], i: usize) -> Tilt {
    let fit = smooth_along_r(points, i);
    tilt_of(
        fit[0],
        bounded(shape(&fit)),
        fit[SHARE].clamp(0.0, MAX_RIDGE_SHARE),
        fit[WIDENING].clamp(0.0, MAX_RIDGE_WIDENING),
    )
}

/// The local quadratic fit of [`smooth_tilt`], of any N numbers per point.
fn smooth_along_r<const N: usize>(points: &[(f64, f64, [f64; N])], i: usize) -> [f64; N] {
    let lo = i.saturating_sub(SMOOTH_NODES);
    let hi = (i + SMOOTH_NODES + 1).min(points.len());
    if hi - lo < 3 {
        return points[i].2;
    }
    let u0 = points[i].0;
    // Towards the far end a line in r: there both profiles fall exponentially, at rates that
    // differ by a constant, so the log of their ratio is linear in r (a line in ln r through
    // the last nodes bent it up: module docs, "Smooth")
    let far_end = hi - 1 - i < MIN_QUADRATIC_SIDE && i - lo >= MIN_QUADRATIC_SIDE;
    // Σ w xᵏ, k = 0 … 4, and Σ w xᵏ y, k = 0 … 2
    let mut m = [0.0; 5];
    let mut t = [[0.0; N]; 3];
    for (j, (u, weight, y)) in points.iter().enumerate().take(hi).skip(lo) {
        let d = j.abs_diff(i) as f64 / (SMOOTH_NODES + 1) as f64;
        let w = weight * (1.0 - d * d * d).powi(3);
        let x = if far_end { u.exp() - u0.exp() } else { u - u0 };
        let mut xk = w;
        for (k, mk) in m.iter_mut().enumerate() {
            *mk += xk;
            if k < 3 {
                for (tn, yn) in t[k].iter_mut().zip(y) {
                    *tn += xk * yn;
                }
            }
            xk *= x;
        }
    }
    // The intercept at x = 0, c₀ = Σₖ cₖ tₖ / det, by Cramer's rule on the normal equations
    let quadratic = {
        let det = m[0] * (m[2] * m[4] - m[3] * m[3]) - m[1] * (m[1] * m[4] - m[2] * m[3])
            + m[2] * (m[1] * m[3] - m[2] * m[2]);
        let c = [
            m[2] * m[4] - m[3] * m[3],
            m[2] * m[3] - m[1] * m[4],
            m[1] * m[3] - m[2] * m[2],
        ];
        let balanced = (i - lo).min(hi - 1 - i) >= MIN_QUADRATIC_SIDE;
        (balanced && det > 1e-12 * m[0] * m[2] * m[4]).then_some((c, det))
    };
    let (c, det) = match quadratic {
        Some(fit) => fit,
        None => {
            let det = m[0] * m[2] - m[1] * m[1];
            if det.is_nan() || det <= 1e-12 * m[0] * m[2] {
                return points[i].2;
            }
            ([m[2], -m[1], 0.0], det)
        }
    };
    std::array::from_fn(|n| (0..3).map(|k| c[k] * t[k][n]).sum::<f64>() / det)
}

/// PBD's harmonics μ₀ … μ₁₂ at radius r > 0 and incidence `theta`, or (`None`) in the limit of a
/// refracted beam in the surface with its ridge ([`Pbd::surface_ridge`]), by Gauss-Legendre
/// in t with φ = π t², points gathered towards the forward peak. Coarse (the profile's forward
/// ridge is as narrow as cos θ′), but only the ratios of values at nearby radii by the same
/// rule enter the correction, where its error cancels to first order.
fn control_harmonics(
    pbd: &Pbd,
    r: f64,
    theta: Option<f64>,
    rule: &GaussLegendre,
    less: Option<&Ridge>,
) -> [f64; PBD_HARMONICS] {
    let mut m = [if theta.is_none() {
        pbd.surface_ridge(r)
    } else {
        0.0
    }; PBD_HARMONICS];
    for (x, w) in rule.nodes().iter().zip(rule.weights()) {
        let t = 0.5 * (1.0 + x);
        let phi = PI * t * t;
        let value = match theta {
            Some(theta) => pbd.eval(theta, r, phi, Rule::Fast),
            None => pbd.eval_surface_beam(r, phi, Rule::Fast),
        } - less.map_or(0.0, |g| g.eval(r, phi));
        // ∫ over [−π, π] of an even profile, dφ = 2π t dt, dt = dx/2
        let s = 2.0 * w * 0.5 * 2.0 * PI * t * value;
        for (n, mn) in m.iter_mut().enumerate() {
            *mn += s * (n as f64 * phi).cos();
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{SeedableRng, SplitMix64, UnitF64};

    /// The harmonics μ₀ … μ₆ of a wrapped Cauchy lobe of mass `mass`: mass·κⁿ.
    fn lobe(mass: f64, kappa: f64) -> [f64; PBD_HARMONICS] {
        std::array::from_fn(|n| mass * kappa.powi(n as i32))
    }

    fn measured(
        mean: [f64; HARMONICS],
        smooth: [f64; PBD_HARMONICS],
        ridge: [f64; PBD_HARMONICS],
    ) -> Measured {
        Measured {
            mean,
            se: [1e-4 * mean[0]; HARMONICS],
            rel: Some(1e-4),
            at_node: smooth,
            average: smooth,
            ridge: [ridge; 2],
        }
    }

    #[test]
    fn the_ridge_share_its_widening_and_the_tilt_are_recovered_from_the_walks_harmonics() {
        // Walk harmonics made as a tilt of a broad profile plus a share of a narrow ridge,
        // widened: the fit finds harmonics the walk's and, over their whole range, the share,
        // the widening and the tilt that made them
        // (two harmonics where the ridge has full weight, four where it ramps in)
        let mut rng = SplitMix64::seed_from_u64(11);
        for (k, terms) in [RIDGE_TILT_TERMS, TILT_TERMS]
            .into_iter()
            .cycle()
            .take(400)
            .enumerate()
        {
            let mut u = || rng.next_f64();
            let high = if terms == TILT_TERMS { 1.0 } else { 0.0 };
            let broad = lobe(1.0, 0.2 + 0.5 * u());
            let floor = 0.3 * u();
            let smooth: [f64; PBD_HARMONICS] =
                std::array::from_fn(|n| broad[n] + if n == 0 { floor } else { 0.0 });
            let ridge = lobe(0.1 + 0.9 * u(), 0.95 + 0.049 * u());
            let share = MAX_RIDGE_SHARE * u();
            let widening = MAX_RIDGE_WIDENING * u();
            let want = tilt_of(
                u() - 0.5,
                [
                    0.6 * (u() - 0.5),
                    0.3 * (u() - 0.5),
                    high * 0.2 * (u() - 0.5),
                    high * 0.1 * (u() - 0.5),
                ],
                share,
                widening,
            );
            let mean = tilted(
                &with_share(&smooth, &ridge, share, widening),
                want[0],
                shape(&want),
            );
            let m = measured(mean, smooth, ridge);
            let got = fit_ridge_tilt(&m, MAX_RIDGE_WIDENING, terms);
            // a tilt of `terms` harmonics, whose harmonics are the walk's, to 10⁻⁶ of μ̂₀, up
            // to μ̂₈
            assert!(shape(&got)[terms..].iter().all(|&a| a == 0.0), "{k}");
            let h = tilted(
                &with_share(&smooth, &ridge, got[SHARE], got[WIDENING]),
                got[0],
                shape(&got),
            );
            for n in 0..HARMONICS {
                assert!(
                    (h[n] - mean[n]).abs() < 1e-6 * mean[0],
                    "{n}: {h:?} against {mean:?}, {got:?}"
                );
            }
            // and so are its parameters, where the ridge carries enough to tell the widening
            if share > 0.1 {
                for (g, w) in got.iter().zip(want) {
                    assert!((g - w).abs() < 1e-4, "{got:?} against {want:?}");
                }
            }
        }
    }

    #[test]
    fn the_tilt_beside_the_ridge_has_four_terms_where_the_ridge_ramps_in() {
        use crate::table::ridge::{weight, FULL_WEIGHT_COS, ZERO_WEIGHT_COS};
        for cos_t in [1e-5, 0.05, FULL_WEIGHT_COS] {
            assert_eq!(
                (weight(cos_t), ridge_tilt_terms(cos_t)),
                (1.0, RIDGE_TILT_TERMS)
            );
        }
        for cos_t in [FULL_WEIGHT_COS + 1e-9, 0.2, ZERO_WEIGHT_COS - 1e-9] {
            assert!(weight(cos_t) < 1.0);
            assert_eq!(ridge_tilt_terms(cos_t), TILT_TERMS);
        }
    }

    #[test]
    fn a_total_tables_share_is_not_widened() {
        assert_eq!(max_ridge_widening(WalkComponent::Total), 0.0);
        assert_eq!(
            max_ridge_widening(WalkComponent::Multiple),
            MAX_RIDGE_WIDENING
        );
        // Harmonics of an unwidened share come back with w = 0 and their share and tilt, and
        // a widened one's best unwidened fit keeps w = 0
        let mut rng = SplitMix64::seed_from_u64(12);
        for widening in [0.0, 0.1] {
            for _ in 0..50 {
                let mut u = || rng.next_f64();
                let smooth = lobe(1.0, 0.2 + 0.5 * u());
                let ridge = lobe(0.1 + 0.9 * u(), 0.95 + 0.049 * u());
                let share = 0.1 + 1.3 * u();
                let want = tilt_of(
                    u() - 0.5,
                    [0.6 * (u() - 0.5), 0.3 * (u() - 0.5), 0.0, 0.0],
                    share,
                    0.0,
                );
                let mean = tilted(
                    &with_share(&smooth, &ridge, share, widening),
                    want[0],
                    shape(&want),
                );
                let got = fit_ridge_tilt(&measured(mean, smooth, ridge), 0.0, RIDGE_TILT_TERMS);
                assert_eq!(got[WIDENING], 0.0);
                if widening == 0.0 {
                    for (g, w) in got.iter().zip(want) {
                        assert!((g - w).abs() < 1e-5, "{got:?} against {want:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_smoothing_keeps_a_parabola_in_ln_r_a_line_in_ln_r_at_the_near_end_and_in_r_at_the_far_end(
    ) {
        // Values quadratic in ln r come back exactly where a node has MIN_QUADRATIC_SIDE
        // points on each side (a line would be off by the curvature), values linear in ln r
        // everywhere but where fewer lie beyond a node (the far end), values linear in r there,
        // whatever the weights
        let mut rng = SplitMix64::seed_from_u64(5);
        let n = 20;
        let points = |f: &dyn Fn(f64) -> f64, rng: &mut SplitMix64| -> Vec<(f64, f64, Tilt)> {
            (0..n)
                .map(|i| {
                    let u = -3.0 + 0.28 * i as f64;
                    let tilt = tilt_of(f(u), [0.1 * f(u), 0.0, 0.0, 0.0], 1.0, 0.0);
                    (u, 0.5 + rng.next_f64(), tilt)
                })
                .collect()
        };
        let parabola = |u: f64| 0.3 - 0.2 * u + 0.15 * u * u;
        let line = |u: f64| -0.4 + 0.7 * u;
        let tail = |u: f64| 0.2 - 0.9 * u.exp();
        let curved = points(&parabola, &mut rng);
        let straight = points(&line, &mut rng);
        let falling = points(&tail, &mut rng);
        let mut bent = 0;
        for i in 0..n {
            let inner = i >= MIN_QUADRATIC_SIDE && i + MIN_QUADRATIC_SIDE < n;
            let far_end = i + MIN_QUADRATIC_SIDE >= n;
            let got = smooth_tilt(&curved, i)[0];
            let want = parabola(curved[i].0);
            if inner {
                assert!((got - want).abs() < 1e-12, "{i}: {got} {want}");
            }
            let (data, f) = if far_end {
                (&falling, &tail as &dyn Fn(f64) -> f64)
            } else {
                (&straight, &line as &dyn Fn(f64) -> f64)
            };
            let got = smooth_tilt(data, i);
            let want = f(data[i].0);
            assert!((got[0] - want).abs() < 1e-12, "{i}: {got:?}");
            assert!((got[1] - 0.1 * want).abs() < 1e-12, "{i}: {got:?}");
            // (a line in ln r at the far end is off a line in r)
            if far_end {
                let in_ln_r = smooth_tilt(&straight, i)[0] - line(straight[i].0);
                bent += usize::from(in_ln_r.abs() > 1e-6);
            }
        }
        assert_eq!(bent, MIN_QUADRATIC_SIDE);
    }

    #[test]
    fn without_a_ridge_the_tilt_is_pbds_alone() {
        let smooth = lobe(1.0, 0.6);
        let mean = tilted(&smooth, 0.2, [0.1, -0.05, 0.03, 0.02]);
        let got = fit_ridge_tilt(
            &measured(mean, smooth, [0.0; PBD_HARMONICS]),
            MAX_RIDGE_WIDENING,
            RIDGE_TILT_TERMS,
        );
        let (ln_k, a) = fit_tilt(&mean, &smooth, TILT_TERMS);
        assert_eq!(got, tilt_of(ln_k, a, 1.0, 0.0));
        // and the energy form gives back the k of the fit
        let m = measured(mean, smooth, lobe(0.3, 0.99));
        let fit = fit_ridge_tilt(&m, MAX_RIDGE_WIDENING, RIDGE_TILT_TERMS);
        let ratio = (m.mean[0] / m.pbd_average()).ln();
        let mut energy_form = fit;
        energy_form[0] = ratio;
        let back = scale_of(&m, energy_form);
        assert!((back[0] - fit[0]).abs() < 1e-12, "{back:?} against {fit:?}");
    }

    /// A profile of two wrapped Cauchy lobes and a floor, at φ, and its harmonics.
    fn two_lobes(x: [f64; 5]) -> (impl Fn(f64) -> f64, [f64; PBD_HARMONICS]) {
        let [m1, k1, m2, k2, floor] = x;
        let wc =
            |k: f64, phi: f64| (1.0 - k * k) / (2.0 * PI * (1.0 + k * k - 2.0 * k * phi.cos()));
        let profile = move |phi: f64| m1 * wc(k1, phi) + m2 * wc(k2, phi) + floor / (2.0 * PI);
        let h = std::array::from_fn(|n| {
            m1 * k1.powi(n as i32) + m2 * k2.powi(n as i32) + if n == 0 { floor } else { 0.0 }
        });
        (profile, h)
    }

    #[test]
    fn the_tilts_harmonics_are_the_tilted_profiles_by_quadrature() {
        // tilted() against P(φ)(1 + Σ aₘ cos mφ) integrated over φ by the trapezoid rule
        // (exact for these periodic profiles to ~κ^N), over random profiles and tilts
        let mut rng = SplitMix64::seed_from_u64(21);
        for _ in 0..200 {
            let mut u = || rng.next_f64();
            let (profile, h) = two_lobes([u(), 0.8 * u(), u(), 0.8 * u(), 0.3 * u()]);
            let a = bounded(std::array::from_fn(|_| u() - 0.5));
            let ln_k = u() - 0.5;
            let got = tilted(&h, ln_k, a);
            let n = 2048;
            for (k, g) in got.iter().enumerate() {
                let want: f64 = (0..n)
                    .map(|i| {
                        let phi = -PI + 2.0 * PI * (i as f64 + 0.5) / n as f64;
                        profile(phi) * tilt_factor(&a, phi) * (k as f64 * phi).cos()
                    })
                    .sum::<f64>()
                    * 2.0
                    * PI
                    / n as f64
                    * ln_k.exp();
                assert!(
                    (g - want).abs() < 1e-9 * got[0],
                    "{k}: {got:?} against {want}"
                );
            }
        }
    }

    #[test]
    fn a_four_term_tilt_is_recovered_from_the_walks_harmonics() {
        // Walk harmonics made as a four-term tilt of a profile: the fit of every term matches
        // μ̂₀ … μ̂₄ and gives back the tilt; the fit of two matches μ̂₀ … μ̂₂
        let mut rng = SplitMix64::seed_from_u64(22);
        for _ in 0..400 {
            let mut u = || rng.next_f64();
            let (_, smooth) = two_lobes([u(), 0.9 * u(), u(), 0.9 * u(), 0.3 * u()]);
            let a = bounded(std::array::from_fn(|m| (u() - 0.5) / (m + 1) as f64));
            let ln_k = u() - 0.5;
            let mean = tilted(&smooth, ln_k, a);
            let (got_k, got) = fit_tilt(&mean, &smooth, TILT_TERMS);
            assert!((got_k - ln_k).abs() < 1e-8, "{got_k} against {ln_k}");
            for (g, w) in got.iter().zip(a) {
                assert!((g - w).abs() < 1e-7, "{got:?} against {a:?}");
            }
            let (k2, two) = fit_tilt(&mean, &smooth, 2);
            assert_eq!(&two[2..], [0.0; 2]);
            let h = tilted(&smooth, k2, two);
            if lowest_factor(&two) > MIN_TILT_FACTOR + 1e-9 {
                for n in 0..3 {
                    assert!(
                        (h[n] - mean[n]).abs() < 1e-9 * mean[0],
                        "{h:?} against {mean:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_bounded_tilt_keeps_its_factor_above_the_floor_and_no_further_from_it() {
        // 1 + Σ aₘ cos mφ of the bounded tilt on 20,001 azimuths (not the 256 of the bound):
        // never below MIN_TILT_FACTOR; a tilt scaled back reaches to within 1e-3 of it (the bound
        // is not much looser than the factor), one left alone is the same tilt
        let fine = |a: &Shape| {
            (0..=20_000)
                .map(|i| tilt_factor(a, PI * f64::from(i) / 20_000.0))
                .fold(f64::INFINITY, f64::min)
        };
        let mut rng = SplitMix64::seed_from_u64(23);
        let (mut scaled, mut kept) = (0, 0);
        for i in 0..2000 {
            let mut u = || rng.next_f64();
            let spread = if i % 2 == 0 { 1.0 } else { 4.0 };
            let a: Shape = std::array::from_fn(|m| spread * (u() - 0.5) / (m + 1) as f64);
            let b = bounded(a);
            let least = fine(&b);
            assert!(least >= MIN_TILT_FACTOR, "{a:?} to {b:?}: {least}");
            if b == a {
                kept += 1;
                assert!(lowest_factor(&a) >= MIN_TILT_FACTOR, "{a:?}");
            } else {
                scaled += 1;
                assert!(least < MIN_TILT_FACTOR + 1e-3, "{a:?} to {b:?}: {least}");
                let t = b[0] / a[0];
                assert!(b.iter().zip(a).all(|(x, y)| (x - t * y).abs() < 1e-12));
            }
        }
        assert!(scaled > 200 && kept > 200, "{scaled} scaled, {kept} kept");
        // a tilt whose terms do not add up anywhere keeps what a bound on Σ |aₘ| would cut
        let apart = [0.6, 0.45, 0.0, 0.0];
        assert_eq!(bounded(apart), apart);
        assert_eq!(bounded([f64::NAN, 0.1, 0.0, 0.0]), [0.0; TILT_TERMS]);
    }

    /// A node whose profile (PBD's harmonics `profile`, untilted: no ridge, ln k = 0, a = 0)
    /// the walk measured as `walk`, with standard errors `se`.
    fn untilted(profile: [f64; PBD_HARMONICS], walk: [f64; HARMONICS], se: f64) -> NodeMiss {
        let m = Measured {
            mean: walk,
            se: [se; HARMONICS],
            rel: Some(se / walk[0]),
            at_node: profile,
            average: profile,
            ridge: [[0.0; PBD_HARMONICS]; 2],
        };
        NodeMiss::of_tilt(&m, &tilt_of(0.0, [0.0; TILT_TERMS], 1.0, 0.0)).unwrap()
    }

    #[test]
    fn the_walk_miss_is_the_relative_rms_of_the_difference_over_phi() {
        // Two profiles of the same energy, each a floor and a wrapped Cauchy lobe cut to the
        // harmonics the walk measures; their relative RMS difference over φ by the midpoint
        // rule (exact for these trigonometric polynomials), against the miss from their
        // harmonics by Parseval, the walk's noise negligible
        let harmonics = |beta: f64, kappa: f64| -> [f64; PBD_HARMONICS] {
            std::array::from_fn(|n| match n {
                0 => 1.0,
                n if n < HARMONICS => beta * kappa.powi(n as i32),
                _ => 0.0,
            })
        };
        let profile = |mu: &[f64; PBD_HARMONICS], phi: f64| {
            (mu[0]
                + 2.0
                    * (1..HARMONICS)
                        .map(|n| mu[n] * (n as f64 * phi).cos())
                        .sum::<f64>())
                / (2.0 * PI)
        };
        for (a, b) in [
            ((0.5, 0.6), (0.4, 0.7)),
            ((0.9, 0.9), (0.6, 0.8)),
            ((0.2, 0.3), (0.2, 0.3)),
        ] {
            let (f, g) = (harmonics(a.0, a.1), harmonics(b.0, b.1));
            let points = 64;
            let mean_square = (0..points)
                .map(|i| {
                    let phi = 2.0 * PI * (i as f64 + 0.5) / points as f64 - PI;
                    (profile(&f, phi) - profile(&g, phi)).powi(2)
                })
                .sum::<f64>()
                / points as f64;
            let by_quadrature = mean_square.sqrt() / (1.0 / (2.0 * PI));
            let walk = std::array::from_fn(|n| g[n]);
            let miss = WalkMiss::of(0.0, &[untilted(f, walk, 1e-12)]);
            let rms = miss.rms.unwrap();
            assert!(
                (rms - by_quadrature).abs() <= 1e-9 + 1e-9 * by_quadrature,
                "{rms} {by_quadrature}"
            );
        }
    }

    #[test]
    fn the_walk_miss_takes_out_the_walks_noise_and_chi2_tells_a_miss_from_it() {
        // 2,000 nodes whose walk is the profile plus normal noise of σ = 2 % of μ₀ in every
        // harmonic: within the noise the RMS miss comes out near 0 (not the noise's own 2·8
        // σ²) and χ² near 1; with the walk off the profile by δ₃ = 0.03 and δ₅ = −0.02 (an RMS
        // miss of √(2 (δ₃² + δ₅²)) = 5.1 %), the RMS is that, and χ² has the misses' share
        let mut rng = SplitMix64::seed_from_u64(11);
        let mut normal = move || {
            let (u, v) = (rng.next_f64(), rng.next_f64());
            (-2.0 * (1.0 - u).ln()).sqrt() * (2.0 * PI * v).cos()
        };
        let profile: [f64; PBD_HARMONICS] = std::array::from_fn(|n| {
            if n < HARMONICS {
                0.7f64.powi(n as i32)
            } else {
                0.0
            }
        });
        let sigma = 0.02;
        for (offset, expected) in [
            ([0.0, 0.0], 0.0),
            ([0.03, -0.02], (2.0f64 * (0.03 * 0.03 + 0.02 * 0.02)).sqrt()),
        ] {
            let nodes: Vec<NodeMiss> = (0..2000)
                .map(|_| {
                    let walk = std::array::from_fn(|n| {
                        let off = match n {
                            3 => offset[0],
                            5 => offset[1],
                            _ => 0.0,
                        };
                        profile[n] - off + if n > 0 { sigma * normal() } else { 0.0 }
                    });
                    untilted(profile, walk, sigma)
                })
                .collect();
            let miss = WalkMiss::of(0.0, &nodes);
            let (rms, chi2) = (miss.rms.unwrap(), miss.chi2.unwrap());
            if expected == 0.0 {
                assert!(rms < 0.005, "{miss:?}");
                assert!((chi2 - 1.0).abs() < 0.05, "{miss:?}");
            } else {
                assert!(
                    (rms - expected).abs() < 0.05 * expected,
                    "{miss:?} {expected}"
                );
                // 1 for the noise, plus (δ₃/σ)² + (δ₅/σ)² = 2.25 + 1 over the 8 harmonics
                assert!((chi2 - 1.40625).abs() < 0.05, "{miss:?}");
            }
        }
        // No node: no figures, not 0, and none in its JSON (a provenance refuses null)
        let none = WalkMiss::of(10.0, &[]);
        assert_eq!((none.nodes, none.rms, none.chi2), (0, None, None));
        let json = serde_json::to_value(none).unwrap();
        assert_eq!(
            json,
            serde_json::json!({"theta_deg": 10.0, "nodes": 0, "profile": "tilt"})
        );
        let json = serde_json::to_value(FitBand::of(Vec::new())).unwrap();
        assert_eq!(json, serde_json::json!({"nodes": 0}));
    }

    #[test]
    fn a_node_that_is_its_profile_has_no_fit_error_and_a_scaled_one_its_scale() {
        // The stored node of a profile that two lobes hold exactly (a two-lobe profile) rebuilds
        // it within 10⁻³ of its energy (its shares of E stored in f32, the lobes rebuilt from
        // them and capped: at most 3.8·10⁻⁴ over these profiles); 10 % more everywhere is an
        // error of 0.1, 10 % more and 10 % less on alternate azimuths too; azimuths where either
        // is not finite are left out, and a profile of no energy has no figure
        let mut rng = SplitMix64::seed_from_u64(24);
        let check = check_azimuths();
        assert!(check.windows(2).all(|w| w[0] < w[1]) && check[0] > 0.0 && check[35] < PI);
        let mut worst = 0.0f64;
        for _ in 0..100 {
            let mut u = || rng.next_f64();
            let (profile, h) = two_lobes([u(), 0.8 * u(), u(), 0.8 * u(), 0.3 * u()]);
            let r = 0.05 + u();
            let (beta, c) = one_lobe_of(h[1], h[2]);
            let cell = [r * h[0], r * beta, c, r * h[3], r * h[4]];
            let stored = super::super::bake::stored_node(cell, r);
            let want = check.map(profile);
            let got = check.map(|p| stored.eval(p));
            worst = worst.max(node_fit_error(&got, &want).unwrap());
            let error = node_fit_error(&want.map(|v| 1.1 * v), &want).unwrap();
            assert!((error - 0.1).abs() < 1e-12, "{error}");
            let alternating = std::array::from_fn(|i| want[i] * if i % 2 == 0 { 1.1 } else { 0.9 });
            let error = node_fit_error(&alternating, &want).unwrap();
            assert!((error - 0.1).abs() < 1e-12, "{error}");
            let mut holes = want;
            holes[6] = f64::NAN;
            let mut scaled = want.map(|v| 1.1 * v);
            scaled[7] = f64::INFINITY;
            let error = node_fit_error(&scaled, &holes).unwrap();
            assert!((error - 0.1).abs() < 1e-12, "{error}");
        }
        assert!(worst < 1e-3, "{worst}");
        assert_eq!(node_fit_error(&[1.0; 36], &[0.0; 36]), None);
        // A band's figures; a band without a node has none, not 0
        let band = FitBand::of(vec![0.3, 0.1, 0.2]);
        assert_eq!(band.nodes, 3);
        assert!((band.mean.unwrap() - 0.2).abs() < 1e-15 && band.p90 == Some(0.3));
        let empty = FitBand::of(Vec::new());
        assert_eq!((empty.nodes, empty.mean, empty.p90), (0, None, None));
    }

    #[test]
    fn a_bake_warns_where_its_nodes_miss_their_profiles() {
        // Far bands above 2 % warn for either component, near bands only for a total; a band
        // without a node does not
        let band = |mean: Option<f64>| FitBand {
            nodes: usize::from(mean.is_some()),
            mean,
            p90: mean,
        };
        let fit = |theta_deg, near, far| NodeFit {
            theta_deg,
            near: band(near),
            far: band(far),
        };
        let report = WalkBakeReport {
            seconds: 1.0,
            threads: 1,
            photons: 1,
            scattering_events: 1,
            median_rel_stderr: 0.01,
            p90_rel_stderr: 0.02,
            rows_from_pbd: 0,
            node_fit: vec![
                fit(30.0, Some(0.05), Some(0.005)),
                fit(60.0, Some(0.001), Some(0.019)),
                fit(85.0, None, Some(0.035)),
                fit(89.0, Some(0.07), Some(0.03)),
            ],
            walk_miss: Vec::new(),
        };
        let multiple = report.node_fit_warnings(WalkComponent::Multiple);
        assert_eq!(multiple.len(), 2, "{multiple:?}");
        assert!(multiple[0].contains("theta 85.0 deg") && multiple[0].contains("3.5 %"));
        assert!(multiple[1].contains("theta 89.0 deg") && multiple[1].contains("3.0 %"));
        assert!(multiple[0].contains("(PBD tilted to the walk's harmonics)"));
        let total = report.node_fit_warnings(WalkComponent::Total);
        assert_eq!(total.len(), 3, "{total:?}");
        assert!(total[0].contains("theta 30.0 deg") && total[0].contains("5.0 %"));
        assert!(total[2].contains("7.0 %") && total[2].contains("r 0.01-0.1 reduced"));
        assert!(total[0].contains("(PBD tilted to the walk's harmonics, plus single scattering)"));
        // The profiles' miss of the walk warns above 2 % RMS where χ² tells it from the noise;
        // a θ node without a node does not
        let miss = |theta_deg, rms: Option<f64>, chi2: Option<f64>| WalkMiss {
            theta_deg,
            nodes: usize::from(rms.is_some()),
            rms,
            chi2,
            profile: WalkProfile::Tilt,
            tilt_rms: None,
            tilt_chi2: None,
        };
        let report = WalkBakeReport {
            walk_miss: vec![
                miss(60.0, Some(0.001), Some(0.9)),
                miss(74.0, Some(0.043), Some(3.6)),
                miss(80.0, Some(0.05), Some(1.5)),
                miss(85.0, Some(0.015), Some(9.0)),
                miss(89.0, Some(0.24), Some(26.4)),
                miss(90.0, None, None),
            ],
            ..report
        };
        let warnings = report.walk_miss_warnings();
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(warnings[0].contains("theta 74.0 deg") && warnings[0].contains("4.3 % RMS"));
        assert!(
            warnings[0].contains("chi2 3.6 per harmonic"),
            "{warnings:?}"
        );
        assert!(warnings[1].contains("theta 89.0 deg") && warnings[1].contains("24.0 % RMS"));
    }
}
