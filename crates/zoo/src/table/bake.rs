//! Baking an angular table: the GWC profile (E, E_β, c) of every (ρ′, θ, r) node, fitted to
//! PBD (fast rule), and the radial and θ CDFs.
//!
//! # What a node stores
//!
//! - r = 0: E = E_β = 0 (the limit of E ~ r ln(1/r)); c is extrapolated from r₁ and r₂, where
//!   it only sets the spline's slope (see `r0_concentration`).
//! - θ = 0: the isotropic profile with the θ → 0 limit of the lobe's share (see
//!   `normal_incidence_node`).
//! - θ > 0: the closed-form three-anchor fit (Ferrier 2016, §3.3, [`fit_three_anchors`]) through
//!   PBD at cos φ = 0.9530, 0.4050, −0.7527. It leaves the error free elsewhere: at grazing
//!   incidence PBD's relative error against it has four extremes, at φ = 0, near 38°, near 96°
//!   and at φ = π, the largest up to 1.13 % at (ρ′, θ) = (0.99, 89°) where the best GWC stays
//!   at 0.998 %, and far out in r, where the fit clamps α = 0, up to 14 % at φ = π. Where the
//!   fit is weak, the node stores instead its refinement ([`refine_minimax`]) to the smallest
//!   largest relative error over seven azimuths, the anchors plus 0, 38°, 96° and π: four more
//!   PBD samples per refined node. The refinement may take a signed floor (α < 0, the profile
//!   still ≥ 0; `gwc` module docs), which is what PBD needs where the fit clamps α: at
//!   (ρ′, θ) = (0.5, 89°) the stored profiles are 0.20 %, 0.31 % and 0.55 % off (181 azimuths)
//!   at r = 11, 13 and 19, where no profile with α ≥ 0 gets below 0.97 %, 1.33 % and 2.2 %. Weak means θ ≥ 45° (the fit's largest error on the seven
//!   samples, branch `Exact`, is 0.23 % at θ = 40°, 0.37 % at 50°, 1.13 % at 90°) or a branch
//!   other than `Exact` (mostly `AlphaClamped`, at large r, for every θ). Refining the `Exact`
//!   nodes below 45° too would gain at most 0.08 % of error there for 30 % more bake time.
//!   The refinement keeps the three-anchor fit whenever it fails or does not lower the largest
//!   error over the seven samples.
//!
//! Measured on the default grid (η = 1.33): 35,719 of the 56,700 nodes at θ > 0, r > 0 are
//! refined and the bake takes 1.8 times as long. On the 100,000 points per case of
//! `bssrdf validate` (seed 7), the node profiles computed at each point's own (θ, r) reach
//! largest errors of 0.92 %, 0.92 % and 0.998 % at ρ′ = 0.5, 0.9 and 0.99 and θ = 89°, against
//! 1.94 %, 1.04 % and 1.13 % for the three-anchor fit (measured before signed floors, which
//! lower the first: at ρ′ = 0.5 beyond r ≈ 11 no GWC with α ≥ 0 stays under 1 %, 1.3 % at
//! r = 13). The table adds its interpolation. Along
//! θ its spline has slope 0 at 90° like PBD, where θ enters through sin θ only, and at the node
//! before (80° on the default grid) the slope of the quartic even about 90° through the last
//! three nodes ([`Axes::new`]); the chord
//! slope that a plain Catmull-Rom end takes at 90° moved the lookups between 80° and 90° by up
//! to 0.6 % (at 87°, ρ′ = 0.5; 0.3 % at 89°) and put 2.4–2.6 % of the points at (0.9, 89°) and
//! (0.99, 89°) above 1 %, and the central difference at 80° left 1–2 points in 10⁵ at
//! (0.99, 89°) at 1.0000–1.0002 % (docs/accuracy.md). The θ CDF integrates that same spline.

use super::{
    check_rows, node_shares, node_sharpness, AngularTable, Axes, SubsetError, PARAMS_PER_NODE,
};
use crate::catmull_rom::Nodes;
use crate::error::{Error, Result};
use crate::fresnel::Moments;
use crate::gwc::{
    fit_three_anchors, fit_two_lobes, fit_two_lobes_one_sign, one_lobe_of, refine_minimax,
    FitBranch, Gwc, Rebuild, TwoLobe, ANCHOR_COS, C_MAX_FIT,
};
use crate::medium::Boundary;
use crate::pbd::{Pbd, Rule};
use crate::quadrature::GaussLegendre;
use crate::table::ridge::{self, Ridge, RidgeKind};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::f64::consts::{PI, TAU};
use std::ops::Range;
use std::time::Instant;

/// Named grid sizes (accuracy and bake time of each are in docs/accuracy.md and docs/performance.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GridPreset {
    /// 50 × 7 × 40: a quick look.
    Coarse,
    /// 100 × 10 × 64: the report's grid (≈ 1 MiB of f32).
    Default,
    /// 160 × 19 × 96: for reference renders.
    Fine,
}

impl GridPreset {
    /// The grid of this preset for a table with `lobes`: [`Grid::preset`], except that the
    /// default grid of a two-lobe table has 42 radii instead of 64 (ratio 1.33 instead of 1.2
    /// between them), so that with its fifth and sixth value per node it stays within 1 MiB
    /// (100 × 10 × 42 nodes × 24 bytes, 984 KiB). Measured at η = 1.2 and 1.25
    /// (docs/accuracy.md): its error is within 0.02 % of the 64-radius grid's on the report's
    /// protocol, and the bake's check passes. (Fewer angles or albedo rows instead: 6 angles put
    /// (0.5, 60°) at 0.12 %, above the report's 0.08 %; 64 albedo rows miss the far tails at
    /// ρ′ < 0.1 by up to 80 %.)
    ///
    /// Below [`GRAZING_NODES_BELOW_ETA`] the θ nodes are [`GridPreset::grazing_nodes`]: below
    /// η = 1 as refracted angles ([`Grid::below_critical`]), from 1 as the angles of incidence.
    pub fn grid(self, eta: f64, lobes: Lobes) -> Grid {
        let mut grid = match (self, lobes) {
            (GridPreset::Default, Lobes::Two) => Grid::ferrier(100, 10, 42),
            _ => Grid::preset(self),
        };
        if eta < 1.0 {
            grid = grid.below_critical(eta, self.grazing_nodes());
        } else if eta < GRAZING_NODES_BELOW_ETA {
            grid.theta = self
                .grazing_nodes()
                .iter()
                .map(|t| t.to_radians())
                .collect();
        }
        grid
    }

    /// Angles (degrees, from 0 to 90) closer together towards grazing: every 10° (15° on the
    /// coarse grid, 5° on the fine) up to 60°, then closer, where the profile changes fastest
    /// as η nears 1 (the beam runs just under the surface). Below η = 1 they are refracted
    /// angles ([`Grid::below_critical`]). Measured on the report's protocol at η = 0.75, 0.9,
    /// 1, 1.001 and 1.01 (docs/accuracy.md, "Below η = 1" and "Where two lobes are not
    /// enough"). The node at 89.4° (default and fine grids), where the profile goes from a ridge
    /// to the line of the surface beam, takes the bake's check over 85–90° at η = 1 from
    /// 0.50–1.36 % to 0.37–0.81 % in its region means; below cos θ′ = 0.01 (89.43° at η = 1) a
    /// node would also take [`RESCALE_BELOW_COS`]'s 48 PBD values more.
    pub fn grazing_nodes(self) -> &'static [f64] {
        match self {
            GridPreset::Coarse => &[0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 78.0, 84.0, 88.0, 90.0],
            GridPreset::Default => &[
                0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 65.0, 70.0, 74.0, 78.0, 82.0, 85.0, 87.5,
                89.0, 89.4, 90.0,
            ],
            GridPreset::Fine => &[
                0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0,
                70.0, 74.0, 78.0, 82.0, 85.0, 87.5, 89.0, 89.4, 90.0,
            ],
        }
    }
}

/// Below this η the presets' θ nodes are [`GridPreset::grazing_nodes`]: between η = 1 and 1.05
/// they bring (ρ′, 85°) from 5–21 % to 0.7–1.0 % (η = 1 and 1.001) and from 0.7–0.9 % to
/// 0.3–0.4 % (1.01); from η = 1.05 up they change nothing measurable (0.064–0.114 % against
/// 0.071–0.114 % at 85°), and the 1 MiB kept from η = 1.2 has no room for them.
pub const GRAZING_NODES_BELOW_ETA: f64 = 1.05;

/// Node values of the three axes to bake.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Reduced albedo nodes in [0, 1].
    pub rho: Vec<f64>,
    /// Incidence nodes in [0, π/2], radians.
    pub theta: Vec<f64>,
    /// Radius nodes ≥ 0, reduced mean free paths.
    pub r: Vec<f64>,
}

/// 0.0025·1.2⁶²: with r_i = 0.0025·q^i (i = 1 … n − 1) and q = (R_Q/0.0025)^{1/(n−2)}, a 64-node
/// axis gets exactly the report's q = 1.2, so r₁ = 0.003 and r₆₃ = 0.0025·1.2⁶³ ≈ 243.4 mean
/// free paths (pbrt's table starts one step earlier, r₁ = 0.0025, and ends at 202.85).
const R_Q: f64 = 202.850_184_525_988;

impl Grid {
    /// The grid of a preset.
    pub fn preset(preset: GridPreset) -> Self {
        let (n_rho, n_theta, n_r) = match preset {
            GridPreset::Coarse => (50, 7, 40),
            GridPreset::Default => (100, 10, 64),
            GridPreset::Fine => (160, 19, 96),
        };
        Self::ferrier(n_rho, n_theta, n_r)
    }

    /// Ferrier's node placement for any counts (ρ, θ ≥ 2; r ≥ 4): ρ_i = (1 − e^{−8i/(n−1)})/(1 − e^{−8}),
    /// θ uniform over [0, 90°], r₀ = 0 and r_i = 0.0025·q^i (q = 1.2 for 64 nodes, see `R_Q`).
    pub fn ferrier(n_rho: usize, n_theta: usize, n_r: usize) -> Self {
        let (n_rho, n_theta, n_r) = (n_rho.max(2), n_theta.max(2), n_r.max(4));
        let rho = (0..n_rho)
            .map(|i| {
                let x = -8.0 * i as f64 / (n_rho - 1) as f64;
                // −expm1 keeps the smallest nodes accurate.
                (-x.exp_m1() / -(-8.0f64).exp_m1()).min(1.0)
            })
            .collect();
        let theta = (0..n_theta)
            .map(|j| 0.5 * PI * j as f64 / (n_theta - 1) as f64)
            .collect();
        let q = (R_Q / 0.0025).powf(1.0 / (n_r - 2) as f64);
        let r = std::iter::once(0.0)
            .chain((1..n_r).map(|i| 0.0025 * q.powi(i as i32)))
            .collect();
        Self { rho, theta, r }
    }
}

impl Grid {
    /// This grid with the θ axis of a table below η = 1: a node at the incidence θ = asin(η sin θ′)
    /// of each refracted angle θ′ of `refracted_deg` (from 0 to 90°), so that the last one is
    /// the critical angle asin η, then one at 90°.
    ///
    /// Below η = 1 light refracts away from the normal and enters only below the critical
    /// angle, where the refracted beam turns grazing (θ′ → 90°) and the transmittance falls to
    /// 0 like a square root. Nodes uniform in θ leave the last lit interval (50°–60° at η = 0.9,
    /// θ′ from 58° to 74°) too wide for the profile's change (7–10 % off at 55°), and every
    /// node beyond the critical angle holds 0, which bends the spline below it. Nodes placed by
    /// θ′ follow the beam instead. The critical node holds the limit of the profile there
    /// ([`beam_in_surface`]), and the bake gives the node at 90°, beyond it, the same values,
    /// so that the spline's slope at the critical node does not see a 0 (lookups beyond the
    /// critical angle are 0 whatever it gives there, and the θ CDF takes nothing beyond it).
    /// Its node is the f32 at or above asin η, so that every angle at which light enters lies
    /// below it.
    pub fn below_critical(mut self, eta: f64, refracted_deg: &[f64]) -> Self {
        let mut theta: Vec<f64> = refracted_deg
            .iter()
            .map(|&t| {
                if t >= 90.0 {
                    critical_node(eta)
                } else {
                    (eta * t.to_radians().sin()).asin()
                }
            })
            .collect();
        theta.push(0.5 * PI);
        // Increasing after the rounding to f32 (close to η = 1 the critical node may round to
        // the 90° one)
        theta.dedup_by(|b, a| *b as f32 <= *a as f32);
        self.theta = theta;
        self
    }
}

/// The f32 at or above the critical angle asin η of an η < 1 (nodes are stored as f32): the
/// node of [`Grid::below_critical`] where the refracted beam runs in the surface.
pub fn critical_node(eta: f64) -> f64 {
    let critical = eta.min(1.0).asin();
    let node = critical as f32;
    // The next f32 up of a positive finite f32 has the next bit pattern
    f64::from(if f64::from(node) < critical {
        f32::from_bits(node.to_bits() + 1)
    } else {
        node
    })
}

/// Below this cos θ′ a node's refracted beam is taken to run in the surface
/// ([`beam_in_surface`]): its forward ridge is then narrower than 0.06° in φ, which no fit
/// through a few azimuths resolves, and within 0.01 % of the limit in energy.
pub const SURFACE_BEAM_COS: f64 = 1e-3;

/// Above this cos θ′ (θ′ below 25.8°) a two-lobe table's nodes take one lobe, the node of a
/// one-lobe table (three PBD values, one more closed-form fit, [`node_cell`]), stored with the
/// lobe's own r·μ₃ = E_β c³ and r·μ₄ = E_β c⁴, which the lookups rebuild into that one lobe.
/// Near normal incidence one lobe holds the profile as well as two: at η = 1 the protocol's
/// mean errors at 15° and 25° move by at most 0.007 % (`examples/protocol_sweep.rs`,
/// docs/performance.md, "Baking"), for a fraction of a two-lobe node's cost. From
/// cos θ′ = 0.75 (θ′ up to 41°, the nodes 10°–40° at η = 1) one lobe costs too much: 35° went
/// from 0.020 to 0.139 % at ρ′ = 0.9.
pub const ONE_LOBE_ABOVE_COS: f64 = 0.9;

/// Below this cos θ′ (and from [`SURFACE_BEAM_COS`]) a two-lobe node keeps the shape of its
/// fit through azimuths but takes the profile's own energy, μ₀ integrated over φ as for a
/// surface-beam node (48 evaluations of PBD instead of none): the forward ridge is then
/// narrower than the fit's azimuths resolve, and the fit's energy was up to 55 % high
/// (cos θ′ = 1.1·10⁻³, η = 1 + 6·10⁻⁷ at 90°; 15 % at 4.5·10⁻³, 2.6 % at 0.014). The bake's
/// check improves with it too (region means 7.2 → 5.6 % at η = 1 + 2·10⁻⁶). Kept to 0.01, the
/// 90° node of η up to 1.00005: from 0.03 it also took η = 1's 89° node (4.2–4.5 → 3.9–4.3 %
/// on the report's protocol) for 0.4–0.9 s more per bake.
pub const RESCALE_BELOW_COS: f64 = 0.01;

/// Whether the node at incidence θ (radians, as stored) is baked as the limit θ′ → 90° of a
/// refracted beam running in the surface (by its harmonics, with the ridge): where light
/// enters with cos θ′ below [`SURFACE_BEAM_COS`] (η = 1 at 90°, η within 5·10⁻⁷ above 1 at
/// 90°, or just below a critical angle), and at the critical node of an η < 1
/// ([`critical_node`]), which lies at or just beyond the critical angle and stands for it.
///
/// PBD's value with the beam exactly in the surface is not the limit of the profile: as
/// θ′ → 90° a ridge of finite energy gathers on φ = 0 ([`Pbd::surface_ridge`]), which the
/// exact value leaves out (28 % of ρ_eff at (η, ρ′) = (1, 0.9)). A node holding the exact
/// value pulled the θ spline 10–60 % off between its neighbours (η = 1 from 87.5° up), and the
/// critical node of an η < 1, which held 0, pulled the last lit interval down to 0.
pub fn beam_in_surface(eta: f64, theta: f64) -> bool {
    match crate::fresnel::refracted_cos(theta.min(0.5 * PI), eta) {
        Some(cos_t) => cos_t < SURFACE_BEAM_COS,
        None => eta < 1.0 && theta == critical_node(eta),
    }
}

/// What a bake did: time, and how often each branch of the GWC fit was taken.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BakeReport {
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Threads used.
    pub threads: usize,
    /// Count of nodes per fit branch (by name): a one-lobe fit's branch, `TwoLobes`, or
    /// `SurfaceBeam` for the limit where the refracted beam runs in the surface.
    pub fit_branches: BTreeMap<String, usize>,
    /// Nodes whose stored profile is the minimax refinement of their three-anchor fit.
    pub refined: usize,
}

/// How many wrapped Cauchy lobes a table's angular profile has (`gwc` module docs): one, the
/// report's model, or two, for index-matched and nearly matched media, where PBD's profile at
/// grazing incidence is a sharp forward peak over a broad body (`gwc::TwoLobe`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Lobes {
    /// One lobe over a floor: (E, E_β, c) per node.
    One,
    /// Two lobes over a floor: (E, E_β₁, c₁) and (rμ₃, rμ₄) per node.
    Two,
}

/// Below this η a bake takes two lobes unless told otherwise ([`Lobes::for_eta`]): there one
/// lobe misses the report's table-2 figures at 60° and 89° (docs/accuracy.md).
pub const TWO_LOBES_BELOW_ETA: f64 = 1.33;

impl Lobes {
    /// The lobes a bake takes by default at η: two below [`TWO_LOBES_BELOW_ETA`], one from it
    /// up. Below η = 1, on the θ axis placed by the refracted angle ([`Grid::below_critical`]),
    /// one lobe is 0.6–34 % off between 45° and the critical angle at η = 0.9, two 0.02–1.9 %
    /// (docs/accuracy.md, "Below η = 1").
    pub fn for_eta(eta: f64) -> Self {
        if eta < TWO_LOBES_BELOW_ETA {
            Lobes::Two
        } else {
            Lobes::One
        }
    }
}

/// Bakes the angular table for one η with the fast PBD quadrature, with the lobes of
/// [`Lobes::for_eta`].
///
/// Deterministic: every node is computed independently and written to its own slot, so the
/// table is bit-identical on any thread count. Runs on the current rayon pool (wrap the call in
/// `ThreadPool::install` to choose the thread count). `theta_sampling` keeps the CDF over θ
/// used by path tracing.
pub fn bake(
    eta: f64,
    moments: Moments,
    grid: &Grid,
    theta_sampling: bool,
) -> Result<(AngularTable, BakeReport)> {
    bake_lobes(eta, moments, grid, theta_sampling, Lobes::for_eta(eta))
}

/// [`bake`] with the given lobes.
pub fn bake_lobes(
    eta: f64,
    moments: Moments,
    grid: &Grid,
    theta_sampling: bool,
    lobes: Lobes,
) -> Result<(AngularTable, BakeReport)> {
    let start = Instant::now();
    let boundary = Boundary::new(eta, moments)?;
    let (grid, axes) = checked_grid(grid)?;
    let grid = &grid;
    let (n_rho, n_theta, n_r) = axes.dims();
    let anchors = ANCHOR_COS.map(f64::acos);

    // One row = one (ρ′, θ) pair: nr nodes of (E, E_β, c), the branch of each fit and the
    // count of refined nodes.
    let rows: Vec<(usize, usize)> = (0..n_rho)
        .flat_map(|i| (0..n_theta).map(move |j| (i, j)))
        .collect();
    // Two-lobe tables whose θ axis reaches the ridge's weight store S less it (`ridge`)
    let with_ridge = if lobes == Lobes::Two && ridge::reaches(eta) {
        RidgeKind::NEWEST
    } else {
        RidgeKind::None
    };
    let r_max = grid.r[n_r - 1];
    let baked: Vec<Result<BakedRow>> = rows
        .par_iter()
        .map(|&(i, j)| {
            let pbd = Pbd::new(grid.rho[i], boundary)?;
            let surface = beam_in_surface(eta, grid.theta[j]);
            let theta = grid.theta[j].min(0.5 * PI);
            // (the critical node of an η < 1, beyond the critical angle by its f32 rounding,
            // holds the limit cos θ′ → 0)
            let cos_t = match crate::fresnel::refracted_cos(theta, eta) {
                None if surface => Some(0.0),
                c => c,
            };
            let ridge =
                cos_t.and_then(|c| Ridge::with_cos(with_ridge, &boundary, grid.rho[i], c, r_max));
            // Near normal incidence a two-lobe table's nodes take one lobe
            let one_lobe_node = cos_t.is_some_and(|c| c > ONE_LOBE_ABOVE_COS);
            let mut row = Vec::with_capacity(n_r * PARAMS_PER_NODE);
            let mut second = Vec::new();
            let mut branches = Vec::with_capacity(n_r);
            let mut refined = 0;
            let mut hint = None;
            for &r in &grid.r {
                if surface && r > 0.0 {
                    let [e, e_beta, c, m3, m4] = surface_cells(&pbd, r, lobes, ridge.as_ref());
                    row.extend([to_f32(e), to_f32(e_beta), c as f32]);
                    if lobes == Lobes::Two {
                        second.extend([to_f32(m3), to_f32(m4)]);
                    }
                    branches.push(NodeKind::SurfaceBeam);
                    continue;
                }
                if lobes == Lobes::Two && theta > 0.0 && r > 0.0 && !one_lobe_node {
                    let ([e, e_beta, c, m3, m4], fitted) =
                        two_lobe_node(&pbd, theta, r, hint, ridge.as_ref());
                    hint = fitted;
                    let [e, e_beta, c, m3, m4] = match crate::fresnel::refracted_cos(theta, eta) {
                        Some(cos_t) if cos_t < RESCALE_BELOW_COS && e > 0.0 => {
                            // The fit's shape with the profile's own energy (less the ridge's)
                            let ridge_mass = ridge.as_ref().map_or(0.0, |g| g.harmonics::<1>(r)[0]);
                            let mass = surface_harmonics::<5>(&pbd, r, Some(theta))[0];
                            let k = r * (mass - ridge_mass).max(0.0) / e;
                            [e * k, e_beta * k, c, m3 * k, m4 * k]
                        }
                        _ => [e, e_beta, c, m3, m4],
                    };
                    row.extend([to_f32(e), to_f32(e_beta), c as f32]);
                    second.extend([to_f32(m3), to_f32(m4)]);
                    branches.push(NodeKind::TwoLobes);
                    continue;
                }
                let node = node_at(&pbd, theta, r, anchors)?;
                let [e, e_beta, c] = node.cell;
                row.extend([to_f32(e), to_f32(e_beta), c as f32]);
                if lobes == Lobes::Two {
                    // The one lobe's own r·μ₃, r·μ₄ (0 at θ = 0, where c = 0, and at r = 0)
                    second.extend([to_f32(e_beta * c.powi(3)), to_f32(e_beta * c.powi(4))]);
                }
                branches.push(NodeKind::Fit(node.branch));
                refined += usize::from(node.refined);
            }
            if grid.r[0] == 0.0 && n_r >= 3 {
                row[2] = r0_concentration(&row, &grid.r);
            }
            Ok((row, second, branches, refined))
        })
        .collect();

    let mut params = Vec::with_capacity(n_rho * n_theta * n_r * PARAMS_PER_NODE);
    let mut harmonics = Vec::new();
    let mut fit_branches = BTreeMap::new();
    let mut refined = 0;
    for row in baked {
        let (values, second, branches, row_refined) = row?;
        params.extend(values);
        harmonics.extend(second);
        refined += row_refined;
        for b in branches {
            *fit_branches.entry(b.name()).or_insert(0) += 1;
        }
    }

    let table = assemble(
        eta,
        moments,
        grid,
        axes,
        (params, harmonics),
        theta_sampling,
        with_ridge,
    )?;
    let report = BakeReport {
        seconds: start.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
        fit_branches,
        refined,
    };
    Ok((table, report))
}

/// The grid a bake bakes on, checked (ρ′ nodes in [0, 1], θ in [0, π/2], r ≥ 0), with its node
/// values rounded to f32: a table read back from a file then has exactly the axes it was baked
/// on. With the table's axes.
pub(super) fn checked_grid(grid: &Grid) -> Result<(Grid, Axes)> {
    for &rho in &grid.rho {
        crate::error::in_range("rho node", rho, 0.0, 1.0)?;
    }
    for &theta in &grid.theta {
        // π/2 rounded to f32 is 1.5707964, a hair above the f64 π/2: allowed and clamped.
        crate::error::in_range("theta node", theta, 0.0, f64::from((0.5 * PI) as f32))?;
    }
    for &r in &grid.r {
        crate::error::in_range("r node", r, 0.0, f64::MAX)?;
    }
    let round = |v: &[f64]| -> Vec<f64> { v.iter().map(|&x| f64::from(x as f32)).collect() };
    let grid = Grid {
        rho: round(&grid.rho),
        theta: round(&grid.theta),
        r: round(&grid.r),
    };
    let axes = Axes::new(grid.rho.clone(), grid.theta.clone(), grid.r.clone())?;
    Ok((grid, axes))
}

/// The table of a bake's node values (`params`, and `harmonics`, empty with one lobe, in the
/// order of the grid's rows): below η = 1 the nodes beyond the critical node copy it, then the
/// radial CDFs, the θ CDF (`theta_sampling`) and the table. With `ridge` the nodes hold S less
/// the analytic ridge (`ridge`), whose energy the θ CDF adds at each node.
pub(super) fn assemble(
    eta: f64,
    moments: Moments,
    grid: &Grid,
    axes: Axes,
    (mut params, mut harmonics): (Vec<f32>, Vec<f32>),
    theta_sampling: bool,
    ridge: RidgeKind,
) -> Result<AngularTable> {
    let (n_rho, n_theta, n_r) = axes.dims();
    // Below η = 1, the nodes beyond a critical node (`Grid::below_critical`), where no light
    // enters, take its values: a 0 there bent the last lit interval through the spline's slope
    // at the critical node (15 % off in ρ_eff at η = 1 − 10⁻⁷), and lookups beyond it are 0
    let critical = grid
        .theta
        .iter()
        .position(|&t| crate::fresnel::refracted_cos(t.min(0.5 * PI), eta).is_none())
        .filter(|&j| beam_in_surface(eta, grid.theta[j]));
    if let Some(jc) = critical {
        let per_row = [n_r * PARAMS_PER_NODE, harmonics.len() / (n_rho * n_theta)];
        for (values, width) in [(&mut params, per_row[0]), (&mut harmonics, per_row[1])] {
            for i in 0..n_rho {
                let from = (i * n_theta + jc) * width;
                for j in jc + 1..n_theta {
                    values.copy_within(from..from + width, (i * n_theta + j) * width);
                }
            }
        }
    }

    // Radial CDF of the spline through the stored (f32) E of each row.
    let mut radial_cdf = vec![0.0f32; n_rho * n_theta * n_r];
    let mut cumulative = vec![0.0f64; n_r];
    for (row, out) in radial_cdf.chunks_mut(n_r).enumerate() {
        let e = |k: usize| f64::from(params[(row * n_r + k) * PARAMS_PER_NODE]);
        axes.r().integrate_positive(e, &mut cumulative);
        // A running integral of a positive part, as the format wants it (≥ 0, never
        // decreasing): a part's mass S(b) − S(a) between close roots can round below 0
        let mut running = 0.0f64;
        for (o, c) in out.iter_mut().zip(&cumulative) {
            running = running.max(*c);
            *o = to_f32(running);
        }
    }

    // Below η = 1 the θ CDF ends with the interval that holds the critical angle (the critical
    // node's on the presets): the nodes beyond, where no light enters, take no share
    let entering = grid
        .theta
        .iter()
        .take_while(|&&t| crate::fresnel::refracted_cos(t.min(0.5 * PI), eta).is_some())
        .count();
    let lit = (entering + 1).min(n_theta);
    let mut table = AngularTable::from_parts(eta, moments, axes, params, radial_cdf, None)
        .map_err(Error::from)?
        .with_ridge(ridge);
    if theta_sampling {
        // The totals θ draws read (`TableRef::node_total`: the ridge's energy included)
        let view = table.view();
        let totals: Vec<f64> = (0..n_rho * n_theta)
            .map(|k| view.node_total(k / n_theta, k % n_theta))
            .collect();
        let theta_cdf = theta_cdf(view.axes().theta(), &totals, n_theta, lit);
        table = table.with_theta_cdf(theta_cdf).map_err(Error::from)?;
    }
    if !harmonics.is_empty() {
        table = table.with_harmonics(harmonics).map_err(Error::from)?;
    }
    Ok(table)
}

/// What a bake stores at one node, before rounding to f32 (at r₀ = 0 the bake then replaces
/// the c of this cell, 0, by its extrapolation from r₁ and r₂).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeCell {
    /// (E, E_β, c): radial energy E = (2πα + β)·r, lobe share E_β = β·r (both in reduced
    /// units: S × rad × reduced mfp), concentration c.
    pub cell: [f64; 3],
    /// Branch of the three-anchor fit (`Zero` at r = 0).
    pub branch: FitBranch,
    /// Whether the stored profile is the minimax refinement of the three-anchor fit.
    pub refined: bool,
}

/// The cell a bake stores at the node (ρ′ of `pbd`, θ, r), in f64: θ in radians within
/// [0, π/2] (larger values are taken as π/2), r ≥ 0 in reduced mean free paths. Exposed so
/// that tests and experiments can check the stored profile at any (θ, r), not only at nodes.
pub fn node_cell(pbd: &Pbd, theta: f64, r: f64) -> Result<NodeCell> {
    crate::error::in_range("theta", theta, 0.0, f64::from((0.5 * PI) as f32))?;
    crate::error::in_range("r", r, 0.0, f64::MAX)?;
    node_at(pbd, theta.min(0.5 * PI), r, ANCHOR_COS.map(f64::acos))
}

/// [`node_cell`] with validated arguments and the anchor azimuths.
fn node_at(pbd: &Pbd, theta: f64, r: f64, anchors: [f64; 3]) -> Result<NodeCell> {
    if r == 0.0 {
        // Limit r → 0: E = r∫S dφ ~ r ln(1/r) → 0, and the profile is isotropic.
        return Ok(NodeCell {
            cell: [0.0; PARAMS_PER_NODE],
            branch: FitBranch::Zero,
            refined: false,
        });
    }
    if theta == 0.0 {
        let (cell, branch) = normal_incidence_node(pbd, r, anchors)?;
        return Ok(NodeCell {
            cell,
            branch,
            refined: false,
        });
    }
    let (g, branch, refined) = oblique_node(pbd, theta, r, anchors)?;
    Ok(NodeCell {
        cell: [r * g.integral(), r * g.beta(), g.c()],
        branch,
        refined,
    })
}

/// Incidence from which every node is refined, degrees. Below it, only nodes whose
/// three-anchor fit left its anchors (any branch but `Exact`) are (module docs).
pub const REFINE_THETA_MIN_DEG: f64 = 45.0;

/// Azimuths at which the refinement samples PBD besides the anchors, degrees: the ends 0 and
/// 180, and 38 and 96, near the interior extremes of PBD's error against its fits (37–42° and
/// 94–101° on the default grid at θ ≥ 60° and r < 1, where that error is largest).
pub const REFINE_PHI_DEG: [f64; 4] = [0.0, 38.0, 96.0, 180.0];

/// [`REFINE_THETA_MIN_DEG`] in radians, less a hair so that a node at π/4 is refined whichever
/// way its f32 rounding goes.
const REFINE_THETA_MIN: f64 = REFINE_THETA_MIN_DEG * PI / 180.0 * (1.0 - 1e-6);

/// A node at θ > 0: the three-anchor fit, refined where it is weak (see [`REFINE_THETA_MIN`])
/// to the smallest largest relative error over seven azimuths: the three anchors, where it is
/// exact, and [`REFINE_PHI_DEG`], near the four extremes of its error. Returns the profile to
/// store, the fit's branch and whether the refinement was kept ([`refine_minimax`] keeps the
/// fit unless it lowers the largest error over the seven samples; so does an invalid sample,
/// which PBD does not produce at r > 0).
fn oblique_node(
    pbd: &Pbd,
    theta: f64,
    r: f64,
    anchors: [f64; 3],
) -> Result<(Gwc, FitBranch, bool)> {
    let f = anchors.map(|phi| pbd.eval(theta, r, phi, Rule::Fast));
    let fit = fit_three_anchors(f[0], f[1], f[2])?;
    if theta < REFINE_THETA_MIN && fit.branch == FitBranch::Exact {
        return Ok((fit.gwc, fit.branch, false));
    }
    // 180·π/180 is π exactly; min keeps the samples inside [0, π] regardless
    let extra_phi = REFINE_PHI_DEG.map(|d| (d * PI / 180.0).min(PI));
    let extra = extra_phi.map(|phi| pbd.eval(theta, r, phi, Rule::Fast));
    // In increasing φ: 0, anchor 1 (17.6°), 38°, anchor 2 (66.1°), 96°, anchor 3 (138.8°), π
    let phi = [
        extra_phi[0],
        anchors[0],
        extra_phi[1],
        anchors[1],
        extra_phi[2],
        anchors[2],
        extra_phi[3],
    ];
    let samples = [extra[0], f[0], extra[1], f[1], extra[2], f[2], extra[3]];
    Ok(match refine_minimax(&fit.gwc, &phi, &samples) {
        Ok(m) => (m.gwc, fit.branch, m.refined),
        Err(_) => (fit.gwc, fit.branch, false),
    })
}

/// The c stored at r₀ = 0, from a row's stored cells (node r₀ first, then r₁ and r₂).
///
/// The profile at r = 0 has E = E_β = 0, so c there describes nothing; it only enters the
/// Catmull-Rom slope of c at r₁, which the lookups use on [r₁, r₂] (the first interval
/// [0, r₁] takes its shape from r₁ alone). A stored 0, PBD's isotropic limit, pulled that
/// slope to about c₁/r₂ and c on [r₁, r₂] towards 0. The straight line through (r₁, c₁) and
/// (r₂, c₂), extended to r = 0, makes the slope at r₁ the one-sided difference, as at the
/// first node of any axis. Largest error of `bssrdf validate`'s points on [r₁, r₂], before →
/// after: 1.37 % → 1.14 % at (ρ′, θ) = (0.9, 89°), seed 7; 1.25 % → 1.00 % at (0.5, 60°),
/// seed 2024; 0.96 % → 0.67 % at (0.9, 89°), seed 1. Clamped to ±[`C_MAX_FIT`]; 0 at θ = 0,
/// where every c is 0.
pub(super) fn r0_concentration(row: &[f32], r: &[f64]) -> f32 {
    let c = |k: usize| f64::from(row[k * PARAMS_PER_NODE + 2]);
    let slope = (c(2) - c(1)) / (r[2] - r[1]);
    (c(1) - slope * r[1]).clamp(-C_MAX_FIT, C_MAX_FIT) as f32
}

/// One baked (ρ′, θ) row: nr cells of (E, E_β, c), nr of (rμ₃, rμ₄) with two lobes (empty
/// with one), how each node was made, and how many nodes were refined.
type BakedRow = (Vec<f32>, Vec<f32>, Vec<NodeKind>, usize);

/// How a bake made a node, as [`BakeReport::fit_branches`] counts it.
#[derive(Debug, Clone, Copy)]
enum NodeKind {
    /// A one-lobe fit, by its branch.
    Fit(FitBranch),
    /// A two-lobe fit.
    TwoLobes,
    /// The limit of a refracted beam in the surface ([`beam_in_surface`]).
    SurfaceBeam,
}

impl NodeKind {
    fn name(self) -> String {
        match self {
            NodeKind::Fit(branch) => format!("{branch:?}"),
            NodeKind::TwoLobes => "TwoLobes".to_string(),
            NodeKind::SurfaceBeam => "SurfaceBeam".to_string(),
        }
    }
}

/// Azimuths at which a two-lobe node samples PBD: φₖ = π(k/7)², k = 0 … 7, denser towards
/// φ = 0, where the sharp lobe is (its half-width 1 − c₁ is 0.02 rad at (η, θ) = (1, 89°)).
/// Eight are enough: the fits through 8, 10, 12 and 16 such azimuths are within 0.005 % of
/// each other (mean error over 721 azimuths against PBD's reference rule, at (η, ρ′, θ) =
/// (1.2, 0.9, 89°), (1.2, 0.5, 89°), (1.05, 0.99, 89°), (1.33, 0.5, 89°), (1.2, 0.5, 45°),
/// r from 0.003 to 30), and PBD's evaluations are most of a two-lobe bake.
pub fn two_lobe_azimuths() -> [f64; 8] {
    std::array::from_fn(|k| PI * (k as f64 / 7.0).powi(2))
}

/// A node at θ > 0, r > 0 of a two-lobe table, from the [`fit_two_lobes`] profile through
/// PBD at [`two_lobe_azimuths`]: (E, E_β, c) of the one lobe with its first two harmonics
/// ([`one_lobe_of`]) and r times its third and fourth, r·μ₃ and r·μ₄; 0 where PBD underflows.
/// `hint`: the concentrations of the row's previous radius, where the fit starts; returned
/// for the next.
fn two_lobe_node(
    pbd: &Pbd,
    theta: f64,
    r: f64,
    hint: Option<[f64; 2]>,
    ridge: Option<&Ridge>,
) -> ([f64; 5], Option<[f64; 2]>) {
    let azimuths = two_lobe_azimuths();
    // At exact index matching and grazing incidence the refracted beam runs in the surface and
    // PBD is infinite at φ = 0: the fit takes the azimuths where it is finite. With the ridge,
    // the nodes hold PBD less it, at least RIDGE_FLOOR of PBD: off the ridge at low albedo and
    // large r the ridge's lobe can reach past PBD, and a fit through a value ≤ 0 fails (the
    // node would hold 0)
    let less_ridge = |p: f64, v: f64| match ridge {
        Some(g) => (v - g.eval(r, p)).max(RIDGE_FLOOR * v),
        None => v,
    };
    let (phi, y): (Vec<f64>, Vec<f64>) = azimuths
        .iter()
        .map(|&p| (p, less_ridge(p, pbd.eval_node(theta, r, p))))
        .filter(|(_, v)| v.is_finite())
        .unzip();
    two_lobe_node_of(&phi, &y, r, hint)
}

/// The two-lobe node at radius r of a profile sampled at azimuths `phi` (values `y`), as
/// [`two_lobe_node`] stores PBD's: the cells of [`fit_two_lobes`] and the concentrations for
/// the next radius' `hint`.
pub(super) fn two_lobe_node_of(
    phi: &[f64],
    y: &[f64],
    r: f64,
    hint: Option<[f64; 2]>,
) -> ([f64; 5], Option<[f64; 2]>) {
    let fit = fit_two_lobes(phi, y, hint).and_then(|g| {
        if !g.is_signed() {
            return Some(g);
        }
        // A signed pair whose stored form rebuilds into another profile (an ill-conditioned
        // pair: nearly equal concentrations and large, cancelling masses, which the f32
        // harmonics do not carry) gives way to the best lobes of one sign
        let error = |f: &dyn Fn(f64) -> f64| -> f64 {
            phi.iter()
                .zip(y)
                .map(|(&p, &v)| if v > 0.0 { (f(p) / v - 1.0).abs() } else { 0.0 })
                .fold(0.0, f64::max)
        };
        let stored = stored_two_lobes(&g, r);
        if error(&|p| stored.eval(p)) <= 2.0 * error(&|p| g.eval(p)) + STORED_TOLERANCE {
            Some(g)
        } else {
            fit_two_lobes_one_sign(phi, y, hint)
        }
    });
    match fit {
        Some(g) => (two_lobe_cells(&g, r), Some(g.c())),
        None => ([0.0; 5], None),
    }
}

/// The node at radius r > 0 of a refracted beam in the surface ([`beam_in_surface`]): the limit
/// θ′ → 90° of the profile, stored by its harmonics ([`surface_harmonics`]): E = r·μ₀ and the
/// one lobe of μ₁, μ₂ (format-spec.md §10), with r·μ₃ and r·μ₄ for two lobes (0 with one).
/// A fit through a few azimuths, as at other nodes, misses the profile's energy there: PBD with
/// the beam in the surface grows like ln(1/φ) towards φ = 0, and the fits were 6 % high in ρ_eff
/// at ρ′ = 0.1 (η = 1).
fn surface_cells(pbd: &Pbd, r: f64, lobes: Lobes, ridge: Option<&Ridge>) -> [f64; 5] {
    let full = surface_harmonics::<5>(pbd, r, None);
    // Less the analytic ridge's, whose mass the limit's line ridge carries
    let less = ridge.map_or([0.0; 5], |g| g.harmonics::<5>(r));
    let [m0, m1, m2, m3, m4]: [f64; 5] = std::array::from_fn(|n| full[n] - less[n]);
    let (beta, c) = one_lobe_of(m1, m2);
    match lobes {
        Lobes::Two => [r * m0, r * within_floor(beta, c, m0), c, r * m3, r * m4],
        Lobes::One => {
            // c capped as every one-lobe node's, and β with it so that β c stays μ₁
            let (beta, c) = if c > C_MAX_FIT {
                (m1 / C_MAX_FIT, C_MAX_FIT)
            } else {
                (beta, c)
            };
            [r * m0, r * within_floor(beta, c, m0), c, 0.0, 0.0]
        }
    }
}

/// The lobe mass β of concentration c at most (1 + c)/(2c) of the energy e: the one lobe of
/// μ₁, μ₂ over a floor that stays ≥ 0 (format-spec.md §10).
pub(super) fn within_floor(beta: f64, c: f64, e: f64) -> f64 {
    if c > 0.0 {
        beta.min(e * (1.0 + c) / (2.0 * c))
    } else {
        beta
    }
}

/// The harmonics μₙ = ∫ S cos nφ dφ over [−π, π], n = 0 … N − 1 (0 … 4 for the bake), at
/// radius r > 0 of PBD at incidence `theta`, or (`None`) of the limit θ′ → 90°: PBD with the
/// beam in the surface (by the node rule, [`Pbd::eval_surface_beam_node`]) plus its ridge. By 8-point Gauss-Legendre
/// panels a decade wide in φ up to π, which follow the ridge of width cos θ′ of a beam just
/// under the surface and, in the limit, S's growth like ln(1/φ) towards 0:
/// - at `theta`, the panels start at π·10⁻⁵ after a first one [0, π·10⁻⁵] (48 evaluations of
///   PBD, within 2·10⁻⁴ of μ₀; tested);
/// - in the limit, the first panel is [0, φ₀] with φ₀ = min(π·10⁻², 0.3/(σtr r)), where
///   S = a ln(1/φ) + g(φ) with a known ([`Pbd::surface_log_coefficient`]) and g nearly
///   constant (it departs from its limit like x² ln x, x = σtr r φ ≤ 0.3): 4 points integrate
///   S cos nφ − a ln(1/φ) there and a·φ₀(1 + ln(1/φ₀)) adds the rest; then the decades from φ₀
///   (20 evaluations at r ≲ 3, up to 36 at the grid's largest radii; within 10⁻⁴ of μ₀,
///   tested). The limit's ridge on φ = 0 ([`Pbd::surface_ridge`]) is a lobe of concentration
///   1 whose every harmonic is its mass.
pub(super) fn surface_harmonics<const N: usize>(pbd: &Pbd, r: f64, theta: Option<f64>) -> [f64; N] {
    let (eight, four) = (GaussLegendre::new(8), GaussLegendre::new(4));
    let value = |phi: f64| match theta {
        Some(theta) => pbd.eval(theta, r, phi, Rule::Fast),
        None => pbd.eval_surface_beam_node(r, phi),
    };
    // ∫ over [−π, π] of an even profile: twice the one over [0, π]
    let mut m = [0.0; N];
    let add = |m: &mut [f64; N], rule: &GaussLegendre, a: f64, b: f64, log: f64| {
        let (half, mid) = (0.5 * (b - a), 0.5 * (a + b));
        for (x, w) in rule.nodes().iter().zip(rule.weights()) {
            let phi = mid + half * x;
            let (v, singular) = (value(phi), log * (1.0 / phi).ln());
            for (n, mn) in m.iter_mut().enumerate() {
                *mn += 2.0 * w * half * (v * (n as f64 * phi).cos() - singular);
            }
        }
    };
    let first = match theta {
        Some(_) => {
            let first = PI * 1e-5;
            add(&mut m, &eight, 0.0, first, 0.0);
            first
        }
        None => {
            let first = (PI * 1e-2).min(0.3 / (pbd.sigma_tr() * r));
            let log = pbd.surface_log_coefficient(r);
            add(&mut m, &four, 0.0, first, log);
            let rest = 2.0 * log * first * (1.0 + (1.0 / first).ln()) + pbd.surface_ridge(r);
            for mn in &mut m {
                *mn += rest;
            }
            first
        }
    };
    // Then up to each of π·10⁻⁴, …, π·10⁻¹, π that lies beyond twice the last edge
    let mut a = first;
    for b in (0..5).rev().map(|k| PI * 10f64.powi(-k)) {
        if b > 2.0 * a || b == PI {
            add(&mut m, &eight, a, b, 0.0);
            a = b;
        }
    }
    m
}

/// The least share of PBD a node with the ridge keeps at an azimuth where the ridge reaches
/// past PBD (`two_lobe_node`): the node's profile stays > 0 there, so its fit exists.
const RIDGE_FLOOR: f64 = 1e-3;

/// How much further than the fit itself (besides twice as far) a signed pair's stored form may
/// be from PBD at the fit's azimuths, relative (`two_lobe_node`).
const STORED_TOLERANCE: f64 = 1e-3;

/// The values a two-lobe node stores for the profile `g` at radius `r`, in f64: (E, E_β, c) of
/// the one lobe with its first two harmonics ([`one_lobe_of`]) and r·μ₃, r·μ₄.
fn two_lobe_cells(g: &TwoLobe, r: f64) -> [f64; 5] {
    let [m1, m2, m3, m4] = g.harmonics();
    let (beta, c) = one_lobe_of(m1, m2);
    let e = g.integral();
    // The one lobe of μ₁ and μ₂ is ≥ 0 over the floor, as the format wants of every
    // (E, E_β, c), for every pair of lobes of one sign; for a signed pair it may reach
    // below, up to 0.25 % of E (far tails of the default bake at η = 1.05), and μ₁, μ₂
    // are scaled down by that much
    [r * e, r * within_floor(beta, c, e), c, r * m3, r * m4]
}

/// The profile a lookup rebuilds at a node of `g` at radius `r` from its stored f32 values
/// ([`stored_node`]). (A pair of nearly equal concentrations and large cancelling masses
/// rebuilds from these into another profile than from its harmonics in f64.)
fn stored_two_lobes(g: &TwoLobe, r: f64) -> TwoLobe {
    stored_node(two_lobe_cells(g, r), r)
}

/// The profile a lookup rebuilds at a two-lobe node (E, E_β, c, r·μ₃, r·μ₄) at radius r > 0,
/// from the cell in f32: the node's shares of E ([`node_shares`]), capped at its sharpness
/// ([`node_sharpness`]), as format-spec.md §10 has it.
pub(super) fn stored_node(cell: [f64; 5], r: f64) -> TwoLobe {
    let cell = cell.map(|v| v as f32);
    let e_per_r = f64::from(cell[0]) / r;
    let m = node_shares(cell).map(|s| f64::from(s) * e_per_r);
    let rebuild = Rebuild::MergedRoots;
    TwoLobe::from_moments_capped(
        e_per_r,
        m,
        f64::from(node_sharpness(cell, rebuild)),
        rebuild,
    )
}

/// Incidence at which the θ → 0 limit of the lobe mass is taken (radians).
const THETA_LIMIT: f64 = 1e-3;

/// A node at θ = 0. The profile is isotropic there, so any split of E between the floor and a
/// lobe with c = 0 describes it exactly; the split matters only for interpolation towards 10°.
/// As θ → 0 the anisotropy vanishes like c ~ sin θ′ while β tends to a finite limit (the ratio of
/// the first two Fourier harmonics of the profile), so the node stores c = 0, E from the exact
/// isotropic value and E_β = r·β(θ = 10⁻³ rad), at most E (β is even in θ: the limit is off
/// by ~10⁻⁶).
/// The flat-profile fit would store β = 0, halving the anisotropy interpolated at 5° (a 1–2 %
/// error, measured).
fn normal_incidence_node(pbd: &Pbd, r: f64, anchors: [f64; 3]) -> Result<([f64; 3], FitBranch)> {
    let e = TAU * r * pbd.eval(0.0, r, 0.0, Rule::Fast);
    let f = anchors.map(|phi| pbd.eval(THETA_LIMIT, r, phi, Rule::Fast));
    let fit = fit_three_anchors(f[0], f[1], f[2])?;
    // Where the small-θ profile is flatter than a lobe over a non-negative floor the fit clamps
    // α = 0; its lobe is still the admissible shape closest to the limit.
    let e_beta = (r * fit.gwc.beta()).min(e);
    Ok(([e, e_beta, 0.0], fit.branch))
}

/// CDF over θ of ρ_eff(ρ′, θ) (`totals`, per albedo row and θ node), per albedo row: the running integral
/// of the spline of `theta`, so with its end condition (slope 0 at 90°, [`Axes::new`]), as
/// every lookup that samples θ with it interpolates, over the first `lit` nodes; constant from
/// there (below η = 1, beyond the critical node, where no light enters).
fn theta_cdf(theta: &Nodes, totals: &[f64], n_theta: usize, lit: usize) -> Vec<f32> {
    let mut out = vec![0.0f32; totals.len()];
    let mut cumulative = vec![0.0f64; n_theta];
    for (i, chunk) in out.chunks_mut(n_theta).enumerate() {
        let rho_eff = |j: usize| totals[i * n_theta + j];
        theta.integrate_positive(rho_eff, &mut cumulative);
        let last_lit = cumulative[lit.clamp(1, n_theta) - 1];
        for (j, (o, c)) in chunk.iter_mut().zip(&cumulative).enumerate() {
            *o = to_f32(if j < lit { *c } else { last_lit });
        }
    }
    out
}

/// f64 → f32, flushing values below the smallest normal f32 to 0 (far tails underflow; keeping
/// subnormals would only slow lookups down).
pub(super) fn to_f32(v: f64) -> f32 {
    let f = v as f32;
    if f.abs() < f32::MIN_POSITIVE {
        0.0
    } else {
        f
    }
}
impl Grid {
    /// The grid with only the albedo nodes `rows` (at least 2 of them).
    pub fn rho_rows(&self, rows: Range<usize>) -> std::result::Result<Grid, SubsetError> {
        check_rows(&rows, self.rho.len())?;
        Ok(Grid {
            rho: self.rho[rows].to_vec(),
            theta: self.theta.clone(),
            r: self.r.clone(),
        })
    }

    /// The albedo axis as the bake stores it (node values rounded to f32), for planning rows.
    pub fn rho_axis(&self) -> crate::Result<Nodes> {
        Nodes::new(
            self.rho
                .iter()
                .map(|&x| f64::from(x as f32))
                .collect::<Vec<_>>(),
        )
    }
}

/// Bakes only the albedo rows `rows` of `grid` (at least 2), in blocks, calling `progress` with
/// the number of albedo rows done after each block. The result equals
/// `bake(eta, moments, grid, theta_sampling)?.0.subset_rows(rows)` bit for bit (see the module
/// docs) and takes the time of the rows kept. Runs on the current rayon pool.
pub fn bake_rows(
    eta: f64,
    moments: Moments,
    grid: &Grid,
    rows: Range<usize>,
    theta_sampling: bool,
    progress: &dyn Fn(usize),
) -> std::result::Result<(AngularTable, BakeReport), SubsetError> {
    let lobes = Lobes::for_eta(eta);
    bake_rows_lobes(eta, moments, grid, rows, theta_sampling, lobes, progress)
}

/// [`bake_rows`] with the given lobes (as [`bake_lobes`]).
pub fn bake_rows_lobes(
    eta: f64,
    moments: Moments,
    grid: &Grid,
    rows: Range<usize>,
    theta_sampling: bool,
    lobes: Lobes,
    progress: &dyn Fn(usize),
) -> std::result::Result<(AngularTable, BakeReport), SubsetError> {
    check_rows(&rows, grid.rho.len())?;
    let start = Instant::now();
    // Blocks of ≥ 2 rows (a spline axis needs two) with ~64 (ρ′, θ) rows per thread, so the
    // pool stays busy inside a block while the callback still moves often.
    let threads = rayon::current_num_threads().max(1);
    let block = (64 * threads).div_ceil(grid.theta.len().max(1)).max(2);
    let mut blocks: Vec<Range<usize>> = rows
        .clone()
        .step_by(block)
        .map(|s| s..(s + block).min(rows.end))
        .collect();
    if let [.., before, last] = blocks.as_mut_slice() {
        if last.len() < 2 {
            before.end = last.end;
        }
    }
    blocks.retain(|b| b.len() >= 2);
    let mut parts = Vec::with_capacity(blocks.len());
    let mut fit_branches = BTreeMap::new();
    let mut refined = 0;
    let mut done = 0;
    for b in blocks {
        let block_grid = grid.rho_rows(b.clone())?;
        let (table, report) = bake_lobes(eta, moments, &block_grid, theta_sampling, lobes)?;
        for (branch, count) in report.fit_branches {
            *fit_branches.entry(branch).or_insert(0) += count;
        }
        refined += report.refined;
        parts.push(table);
        done += b.len();
        progress(done);
    }
    let table = AngularTable::concat_rows(&parts)?;
    let report = BakeReport {
        seconds: start.elapsed().as_secs_f64(),
        threads,
        fit_branches,
        refined,
    };
    Ok((table, report))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_harmonics_of_a_beam_in_the_surface_match_an_adaptive_quadrature() {
        // The fixed panels of `surface_harmonics` against adaptive Gauss-Kronrod to 1e-12 over
        // breaks down to 10⁻¹², the ridge added alike, relative to μ₀: within 10⁻⁴ (measured
        // 3.7e-5, at r = 200; the first panel [0, φ₀] with a ln(1/φ) taken out; the earlier
        // rule of 48 points, a panel [0, π·10⁻⁵] and then decades, 5e-5, and 3.2e-4 with 6
        // points a panel)
        let breaks: Vec<f64> = std::iter::once(0.0)
            .chain((0..=12).rev().map(|k| PI * 10f64.powi(-k)))
            .collect();
        let mut worst: f64 = 0.0;
        for (eta, rho) in [(1.0, 0.05), (1.0, 0.9), (0.9, 0.5), (0.75, 0.999)] {
            let pbd = Pbd::new(rho, Boundary::new(eta, Moments::Exact).unwrap()).unwrap();
            for r in [0.003, 0.05, 0.5, 3.0, 30.0, 200.0] {
                let got: [f64; 5] = surface_harmonics(&pbd, r, None);
                for (n, &m) in got.iter().enumerate() {
                    let f = |phi: f64| {
                        (n as f64 * phi).cos() * pbd.eval_surface_beam(r, phi, Rule::Fast)
                    };
                    let half = crate::quadrature::adaptive(f, &breaks, 1e-12, 0.0, 20_000);
                    let want = 2.0 * half.value + pbd.surface_ridge(r);
                    let error = (m - want).abs() / got[0];
                    worst = worst.max(error);
                    assert!(error < 1e-4, "{eta} {rho} {r} {n}: {m} vs {want}");
                }
            }
        }
        // And of PBD itself for a beam just under the surface (the ridge of width cos θ′)
        for (cos_t, rho) in [(1e-3, 0.3), (0.01, 0.9), (0.01, 0.05)] {
            let pbd = Pbd::new(rho, Boundary::new(1.0, Moments::Exact).unwrap()).unwrap();
            let theta = f64::acos(cos_t);
            for r in [0.003, 0.5, 3.0, 30.0, 200.0] {
                let got: [f64; 5] = surface_harmonics(&pbd, r, Some(theta));
                let f = |phi: f64| pbd.eval(theta, r, phi, Rule::Fast);
                let want = 2.0 * crate::quadrature::adaptive(f, &breaks, 1e-12, 0.0, 20_000).value;
                let error = (got[0] - want).abs() / want;
                worst = worst.max(error);
                // (1.4e-4 at r = 200 and ρ′ = 0.05, S ~ 1e-93, where the profile is sharpest)
                assert!(error < 2e-4, "{cos_t} {rho} {r}: {} vs {want}", got[0]);
            }
        }
        eprintln!("surface harmonics: largest error {worst:.2e} of mu_0");
    }
}
