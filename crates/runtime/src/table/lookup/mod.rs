//! Lookups in an angular table: evaluate (algorithm 1), sample and pdf (algorithm 2), the
//! path-tracing triple (algorithm 3), the perpendicular model, and world units.
//!
//! Every lookup blends the table's (ρ′, θ) rows with products of weights of the two axes, then
//! interpolates along r ([`TableRef::cell_from`]). The crate's evaluation refines the spline
//! along ρ′ as it does along r: PBD's energies carry the factor ρ′², so the rows are weighted
//! ωᵢ = wᵢ (ρ′/ρ′ᵢ)², the Catmull-Rom weights of E/ρ′² times ρ′², with a node at ρ′ = 0 (E = 0
//! there) folded into its neighbours (`table::albedo`). Every energy-like value (E, E_β, the
//! radial CDF, ρ_eff and the θ CDF) blends with the ωᵢ; the concentration c is their weighted
//! mean, Σ ωᵢcᵢ / Σ ωᵢ. At the two ends of the ρ′ axis evaluation weighs the rows per radius
//! node instead, taking out the far field of diffusion (`albedo_ends`, `table::albedo`, "The ends
//! of the axis"). Samplers and densities use the same weights, so `sample` and `pdf`, and
//! `sample_path` and `pdf_theta`, stay exact pairs; at a node the weights are 1 and 0 and every
//! stored value comes back exactly.

use super::albedo::AlbedoWeights;
use super::{TableRef, HARMONICS_PER_NODE, PARAMS_PER_NODE};
use crate::catmull_rom::Weights;
use crate::float::{f32_rounding_around, snap_to_ends};
use crate::gwc::{cap_lobe, table_value, uniform_azimuth, Gwc, TwoLobe};
use blend::{RadialNear, Slice};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

mod albedo_ends;
mod batch;
mod blend;
mod ridged;
mod sample;
mod separable;
#[cfg(test)]
mod tests;
mod two_lobe;
mod world;

pub use batch::{PathSamplesMut, RadialSamplesMut, SamplesMut};
pub use separable::RadialSample;
pub use world::{reduced_to_mm, MediumRef, World};

/// Between 0 and this reduced albedo the lookups read the table at it and scale its energies
/// by (ρ′/`TINY_ALBEDO`)ᵖ, p the power of ρ′ the table's spline along ρ′ takes out
/// ([`crate::table::AlbedoPower`]): every energy is ρ′ᵖ g(ρ′) with g(ρ′) = g(0)(1 + O(ρ′)), and
/// read at ρ′ itself the f32 weights of the blends underflowed from ρ′ ≈ 10⁻²⁰ (docs/table.md).
pub const TINY_ALBEDO: f64 = 1e-8;

/// One draw of the exit point (algorithm 2), in the units of the lookup that drew it: reduced
/// units from [`TableRef`] and the models (r in mean free paths, the density per mfp²), world
/// units from [`World`] and the renderer handles (mm, mm⁻²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Exit distance.
    pub r: f64,
    /// Exit azimuth, radians in [−π, π], 0 forward.
    pub phi: f64,
    /// Density per unit area of the exit plane, pdf(r, φ)/r.
    pub pdf: f64,
}

/// One draw for path tracing (Ferrier §7.1, algorithm 3): the incidence θ, the exit point
/// (r, φ) relative to the plane of incidence and the azimuth φ′ of the entry point seen from the
/// exit point, in the units of the lookup that drew it (see [`Sample`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSample {
    /// Incidence θ_i before refraction, radians.
    pub theta: f64,
    /// Exit distance.
    pub r: f64,
    /// Exit azimuth relative to the plane of incidence, radians.
    pub phi: f64,
    /// Azimuth of the entry point seen from the exit point, uniform, radians in [−π, π).
    pub phi_prime: f64,
    /// Density of θ, per radian.
    pub pdf_theta: f64,
    /// Joint density pdf_theta · pdf(r, φ | θ) / (2π), per radian per unit area per radian.
    pub pdf: f64,
}

/// What the interpolation along r ([`TableRef::cell_from`]) needs of a (ρ′, θ) blend besides
/// its values: the scale that turns the blended c into the ωᵢ-weighted mean of the rows' c
/// ([`AlbedoWeights::c_scale`]), and (ρ′, θ) for the coefficient of the ln(1/r) growth of S.
#[derive(Debug, Clone, Copy)]
struct Blend {
    c_scale: f64,
    rho: f64,
    theta: f64,
}

impl Blend {
    fn new(albedo: &AlbedoWeights, rho: f64, theta: f64) -> Self {
        Self {
            c_scale: albedo.c_scale,
            rho,
            theta,
        }
    }
}

/// The lobe of a cell from [`TableRef::cell_from`]: its share E_β/E of the energy, or (in the
/// first two radius intervals, where the floor grows like ln(1/r)) its β outright.
#[derive(Debug, Clone, Copy)]
enum Lobe {
    Share(f64),
    Beta(f64),
}

/// The profile at one (ρ′, θ, r) as evaluation uses it, from [`TableRef::cell_at_point`].
#[derive(Debug, Clone, Copy)]
enum Cell {
    /// r outside the radial support (negative, NaN, beyond the last node): the value is 0.
    OutsideRadius,
    /// (E/r ≥ 0, β ∈ [0, lobe_cap(E/r, c)], c), the arguments of [`table_value`].
    Profile([f64; 3]),
}

/// The angular profile at one (ρ′, θ, r) as the samplers use it: one lobe, or two for tables
/// with a second lobe.
#[derive(Debug, Clone, Copy)]
enum Profile {
    One(Gwc),
    Two(TwoLobe),
}

impl Cell {
    /// The cell of energy `e` and `lobe` (from [`TableRef::cell_from`]) at `r_eval`: E/r ≥ 0,
    /// and β capped at `lobe_cap(E/r, c)`.
    #[inline(always)]
    fn profile(e: f64, lobe: Lobe, c: f64, r_eval: f64) -> Self {
        let e_per_r = (e / r_eval).max(0.0);
        let beta = match lobe {
            Lobe::Share(share) => share * e_per_r,
            Lobe::Beta(beta) => cap_lobe(beta, e_per_r, c),
        };
        Cell::Profile([e_per_r, beta, c])
    }
}

impl Profile {
    fn sample_with_pdf(&self, u: f64) -> (f64, f64) {
        match self {
            Profile::One(g) => g.sample_with_pdf(u),
            Profile::Two(g) => g.sample_with_pdf(u),
        }
    }

    fn pdf(&self, phi: f64) -> f64 {
        match self {
            Profile::One(g) => g.pdf(phi),
            Profile::Two(g) => g.pdf(phi),
        }
    }

    fn cdf(&self, phi: f64) -> f64 {
        match self {
            Profile::One(g) => g.cdf(phi),
            Profile::Two(g) => g.cdf(phi),
        }
    }
}

impl<'a> TableRef<'a> {
    /// `f` of the slice at (ρ′, θ), `None` outside the axes. The quick ρ′ weights
    /// (`AlbedoAxis::hot_weights`) build it inline, the other points out of line, and `f` runs
    /// on each path's own slice, so that the slice is never copied from one path to the other.
    #[inline(always)]
    fn with_slice<T>(&self, rho: f64, theta: f64, f: impl Fn(&Slice) -> T) -> Option<T> {
        match self.axes.rho.hot_weights(rho) {
            Some(rho_weights) => Some(f(&self.slice_with(&rho_weights, rho, theta)?)),
            None => Some(f(&self.slice_cold(rho, theta)?)),
        }
    }

    #[inline(never)]
    fn slice_cold(&self, rho: f64, theta: f64) -> Option<Slice> {
        self.slice_with(&self.axes.rho.weights(rho)?, rho, theta)
    }

    #[inline(always)]
    fn slice_with(&self, rho_weights: &AlbedoWeights, rho: f64, theta: f64) -> Option<Slice> {
        let theta_weights = self.theta_weights(theta)?;
        let blend = Blend::new(rho_weights, rho, theta);
        Some(self.slice_of(&rho_weights.energy, &theta_weights, blend))
    }

    /// The Catmull-Rom weights along θ, `None` outside the axis ([`TableRef::snap_theta`] at
    /// its ends); hot cells apart, see `Nodes::hot_weights`.
    #[inline(always)]
    pub(super) fn theta_weights(&self, theta: f64) -> Option<Weights> {
        match self.axes.theta().hot_weights(theta) {
            Some(w) => Some(w),
            None => self.axes.theta().weights(self.snap_theta(theta)),
        }
    }

    /// The incidences the θ axis takes, radians: its nodes' range widened at each end by f32
    /// rounding (2⁻²⁴ of the node). The axes are stored in f32, and an angle given in f64 lies
    /// up to that far from its node (45° = π/4 just below the f32 node of a table kept from
    /// 45°); [`TableRef::snap_theta`] takes such an angle as the node.
    pub fn theta_domain(&self) -> [f64; 2] {
        let nodes = self.axes.theta();
        f32_rounding_around(nodes.first(), nodes.last())
    }

    /// θ, or the first or last node of the θ axis where θ lies outside it but inside
    /// [`TableRef::theta_domain`].
    pub fn snap_theta(&self, theta: f64) -> f64 {
        let nodes = self.axes.theta();
        snap_to_ends(theta, [nodes.first(), nodes.last()], self.theta_domain())
    }

    /// The reduced albedos the lookups take: the albedo axis with its ends' f32 rounding, within
    /// [0, 1] (`AlbedoAxis::domain`). A ρ′ in it but outside the nodes is looked up at the
    /// end node.
    pub fn rho_domain(&self) -> [f64; 2] {
        self.axes.rho_domain()
    }

    /// Whether ρ′ lies in [`TableRef::rho_domain`] (false for NaN).
    pub fn keeps_rho(&self, rho: f64) -> bool {
        self.axes.keeps_rho(rho)
    }

    /// Whether θ (radians) lies in [`TableRef::theta_domain`]: where the lookups at θ have
    /// weights along θ.
    pub fn keeps_theta(&self, theta: f64) -> bool {
        let [lo, hi] = self.theta_domain();
        (lo..=hi).contains(&theta)
    }

    /// S ≈ slope·ln(1/r) + const as r → 0, slope = ρ′² C_E cos θ′/π: sources at depth t ≫ r
    /// each add ρ′² C_E/(4π)·κ z_r/d_r³ ≈ ρ′² C_E cos θ′/(π t) (κ ≈ 4t, z_r = t cos θ′, d_r ≈ t).
    fn log_slope(&self, rho: f64, theta: f64) -> f64 {
        let sin_t = theta.sin() / self.eta;
        let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
        rho * rho * self.boundary.c_e() * cos_t / PI
    }

    /// The GWC profile at (slice, r), from the radius and weights of [`TableRef::radius`], for
    /// the samplers: its normalised density in φ is the table's, its energy the plain spline
    /// of E (see [`TableRef::cell_from`]; the density does not depend on it).
    /// `near`, the radial draw's reads, gives the window where it holds it (the same bits).
    #[inline(always)]
    fn profile(&self, s: &Slice, r_eval: f64, w: &Weights, near: Option<&RadialNear>) -> Profile {
        let first = self.radial_window(w);
        let acc = match near.and_then(|near| near.window(first)) {
            Some(window) => window,
            None => self.window_out_of_line(s, first),
        };
        if let Some(second) = self.harmonics {
            // The samplers' profile: normalised (E/r = 1) except in the first two intervals,
            // where the harmonics are outright and E/r the plain spline's
            let shares = self.harmonic_shares(s, second, first, w);
            let e_per_r = if w.segment() <= 1 && self.axes.r().as_slice()[0] == 0.0 {
                let (e, _, _) = self.cell_from::<false>(acc, first, r_eval, w, s.blend);
                (e / r_eval).max(0.0)
            } else {
                1.0
            };
            let g = self.two_lobe_cell(|| acc, &shares, first, r_eval, w, e_per_r);
            return Profile::Two(g);
        }
        Profile::One(
            match self.cell_from::<false>(acc, first, r_eval, w, s.blend) {
                (_, Lobe::Share(share), c) => Gwc::normalised(share, c),
                (e, Lobe::Beta(beta), c) => Gwc::from_table(e, beta, c, r_eval),
            },
        )
    }

    /// The first of the four consecutive radius nodes, inside the axis, that hold the weights
    /// of `w` (nodes segment − 1 … segment + 2; tables have at least 4 radius nodes).
    fn radial_window(&self, w: &Weights) -> usize {
        let (_, _, n_r) = self.axes.dims();
        w.segment().saturating_sub(1).min(n_r.saturating_sub(4))
    }

    /// The cell (E, lobe, c) of the profile at `r_eval` (E, β = share·E/r or the lobe's β, and
    /// c are the arguments of [`Gwc::from_table`]), from (E, E_β, c) blended at the radius nodes
    /// `first..first + 4` (as [`TableRef::window`] gives them, with the energy weights
    /// along ρ′), the radius weights `w` at `r_eval` and the [`Blend`].
    ///
    /// Along r, E is interpolated as exp(Catmull-Rom of ln E) wherever the four nodes of the
    /// segment hold positive energy (`LOG_ENERGY`): E(r) is close to the exponential of a
    /// smooth function, and on the 1.2-ratio grid this removes most of the spline's error in the
    /// exponential tail (docs/table.md gives the measured effect). Elsewhere (the first interval,
    /// where E(0) = 0, and underflowed tails) E is the plain spline. With `LOG_ENERGY` the
    /// lobe's share is the spline of the nodes' shares E_β/E (where all four hold energy);
    /// without, the ratio of the plain splines of E_β and E, which agrees with it except in
    /// steep tails. c is the plain spline along r of the rows' ωᵢ-weighted mean c. The
    /// profile's normalised density in φ (the floor's weight λ = 1 − share, and c) does not
    /// depend on how E is interpolated, except in the first two intervals: the samplers skip
    /// the logarithms (`LOG_ENERGY = false`). Sampling keeps the plain spline of E along r, so
    /// sample and pdf stay an exact pair (S/pdf and ρ_eff then differ by a median 8e-5, see the
    /// module docs).
    #[inline(always)]
    fn cell_from<const LOG_ENERGY: bool>(
        &self,
        acc: [f32; 12],
        first: usize,
        r_eval: f64,
        w: &Weights,
        blend: Blend,
    ) -> (f64, Lobe, f64) {
        let c_scale = blend.c_scale;
        let segment = w.segment();
        let params: [[f64; 3]; 4] =
            std::array::from_fn(|k| std::array::from_fn(|j| f64::from(acc[3 * k + j])));
        let weights = node_weights(first, w);
        let r_nodes = self.axes.r().as_slice();
        if segment <= 1 && r_nodes[0] == 0.0 {
            return self.first_intervals_cell(params, first, r_eval, blend);
        }
        // (The energies' logarithms come straight from the window, which keeps the blend's
        // loads vectorised.)
        let ln = if LOG_ENERGY {
            ln_energies(acc)
        } else {
            [0.0; 4]
        };
        let (mut e_lin, mut e_beta, mut c, mut ln_e) = (0.0, 0.0, 0.0, 0.0);
        let mut node_share = 0.0;
        let mut positive = true;
        for ((&wk, [e, eb, ck]), ln) in weights.iter().zip(params).zip(ln) {
            if wk == 0.0 {
                continue;
            }
            e_lin += wk * e;
            e_beta += wk * eb;
            // c_scale in the weight, which is ready long before the blended c
            c += (wk * c_scale) * ck;
            if e > 0.0 {
                ln_e += wk * f64::from(ln);
                if LOG_ENERGY {
                    node_share += wk * (eb / e);
                }
            } else {
                positive = false;
            }
        }
        // All four node energies positive: ln E interpolates even where the plain spline of E
        // undershoots below zero in a steep tail (it would give 0 there).
        let e = if LOG_ENERGY && positive {
            ln_e.exp()
        } else {
            e_lin
        };
        // The lobe's share. Where all four nodes hold energy, evaluation takes the spline of
        // the nodes' shares E_β/E, smooth in r (from 0.99 to 1.04 between r = 4 and 40 at
        // (0.5, 89°)); the ratio of the splines of E_β and E, which undershoot differently in a
        // steep tail (E falls 30-fold per interval at r ≈ 15 there), moves it by several per
        // cent, and a signed floor turns that into errors of 100 % and more opposite the lobe.
        // The samplers keep the ratio (four divisions less per draw): sample and pdf stay an
        // exact pair, and only draws in such tails, a few in 10⁶ on the protocol's cases,
        // follow a rougher φ law.
        let share = if LOG_ENERGY && positive {
            node_share
        } else if e_lin > 0.0 {
            e_beta / e_lin
        } else {
            0.0
        };
        // Evaluation caps it at (1 + |c|)/(2|c|) (`gwc::lobe_cap`): above 1 the floor is
        // signed, beyond the cap the profile would dip below 0 opposite the lobe. The samplers'
        // `Gwc::normalised` clamps it into [0, 1] itself.
        let share = if LOG_ENERGY {
            cap_lobe(share.max(0.0), 1.0, c)
        } else {
            share
        };
        (e, Lobe::Share(share), c)
    }

    /// [`TableRef::cell_from`] in the first two radius intervals (segment ≤ 1, r₀ = 0), from
    /// the window's nodes 1 and 2. Out of line and cold: a few draws in 10³ land there.
    #[cold]
    #[inline(never)]
    fn first_intervals_cell(
        &self,
        params: [[f64; 3]; 4],
        first: usize,
        r_eval: f64,
        blend: Blend,
    ) -> (f64, Lobe, f64) {
        let Blend {
            c_scale,
            rho,
            theta,
        } = blend;
        let r_nodes = self.axes.r().as_slice();
        // The first two intervals, from r₀ = 0 to r₂: PBD grows like slope·ln(1/r),
        // isotropically, and what is left, P(r, φ) = S(r, φ) − slope·ln(r₁/r), is smooth
        // and nearly linear in r there (its curvature moves it by 0.2 % of itself over
        // [0, r₁] at grazing incidence). So the cell is the log plus the straight line
        // through the profiles P of nodes 1 and 2: (E/r − 2π·slope·ln(r₁/r), β, c) linear
        // in r, extended down to r = 0. The spline through node 0 (E = 0, where PBD is
        // infinite) bends them instead: 0.5 % off at θ = 0 mid-interval, where the nodes
        // are exact, and its constant P(r₁) beyond r₁ left 1.9 % of drift at φ = π (docs/table.md,
        // "Accuracy").
        // (An axis of two nodes has no node 2: P is then constant, P(r₁).)
        let two_pi_slope = TAU * self.log_slope(rho, theta);
        let node = |k: usize, r: f64| {
            let [e, e_beta, c] = params[k - first];
            // the blended c is Σ ωᵢcᵢ; its weighted mean is that times c_scale
            let c = c * c_scale;
            let e_per_r = (e / r).max(0.0);
            // P's isotropic part at node k: E/r less the log's value there
            let p = e_per_r - two_pi_slope * (r_nodes[1] / r).ln();
            [p, cap_lobe((e_beta / r).max(0.0), e_per_r, c), c]
        };
        let a = node(1, r_nodes[1]);
        let (b, t) = match r_nodes.get(2) {
            Some(&r2) => (node(2, r2), (r_eval - r_nodes[1]) / (r2 - r_nodes[1])),
            None => (a, 0.0),
        };
        let [p, beta, c] = std::array::from_fn(|j| a[j] + t * (b[j] - a[j]));
        let e_per_r = p + two_pi_slope * (r_nodes[1] / r_eval).ln();
        (e_per_r * r_eval, Lobe::Beta(beta.max(0.0)), c)
    }

    /// The radius at which to evaluate r, with its Catmull-Rom weights; `None` for r outside
    /// [0, r_max] or NaN. PBD diverges like ln(1/r) at r = 0; the table caps that growth at
    /// r = 10⁻⁹ r₁: every r below, 0 and subnormals included, has the value there (finite,
    /// documented).
    // Inlined: returned through memory, its weights would be written as scalars and read back
    // as pairs (a store-forwarding stall).
    #[inline(always)]
    fn radius(&self, r: f64) -> Option<(f64, Weights)> {
        if r.is_nan() || r < 0.0 {
            return None;
        }
        let r_eval = r.max(self.first_radius() * 1e-9);
        // Hot cells apart, see `Nodes::hot_weights`
        let w = match self.axes.r().hot_weights(r_eval) {
            Some(w) => w,
            None => self.axes.r().weights(r_eval)?,
        };
        Some((r_eval, w))
    }

    /// The angular profile at (slice, r), `None` where [`TableRef::radius`] is; `near` as in
    /// [`TableRef::profile`].
    fn profile_at(&self, s: &Slice, r: f64, near: Option<&RadialNear>) -> Option<Profile> {
        let (r_eval, w) = self.radius(r)?;
        Some(self.profile(s, r_eval, &w, near))
    }

    fn first_radius(&self) -> f64 {
        self.axes.r().as_slice().get(1).copied().unwrap_or(1.0)
    }

    /// S_table(r, φ; ρ′, θ) in reduced units (algorithm 1). `None` if (ρ′, θ) lies outside the
    /// stored axes (a scene bake keeps only some albedo rows: never extrapolated). Outside the
    /// radial support (r < 0, r beyond the last node, NaN r or φ) and beyond the critical angle
    /// (η < 1) the value is 0. A table with the ridge adds it to what its nodes give
    /// (`lookup::ridged`).
    pub fn eval(&self, rho: f64, theta: f64, r: f64, phi: f64) -> Option<f64> {
        if let Some(scale) = self.tiny_scale(rho) {
            return Some(scale * self.eval(TINY_ALBEDO, theta, r, phi)?);
        }
        let nodes = self.eval_nodes(rho, theta, r, phi)?;
        if self.ridge.is_some() {
            return Some(self.with_ridge_value(nodes, rho, theta, r, phi));
        }
        Some(nodes)
    }

    /// For ρ′ between 0 and [`TINY_ALBEDO`], the factor (ρ′/[`TINY_ALBEDO`])ᵖ of the energies
    /// the table gives at [`TINY_ALBEDO`]; `None` elsewhere. There every energy of a table is
    /// ρ′ᵖ g(ρ′) with g(ρ′) = g(0)(1 + O(ρ′)) (`table::albedo`), so the energy lookups read the
    /// table at [`TINY_ALBEDO`] and scale, and the densities ([`TableRef::read_albedo`]) take
    /// its values as they are, both to within 10⁻⁸ of themselves. Read at ρ′ itself, the weights
    /// ρ′ᵖ/ρ′ᵢᵖ, f32 in the blends, underflowed: below ρ′ ≈ 10⁻²⁰ ρ_eff was 62 % low to 8.8
    /// times high, then 0, and the sampler failed or disagreed with eval.
    #[inline(always)]
    fn tiny_scale(&self, rho: f64) -> Option<f64> {
        (rho > 0.0 && rho < TINY_ALBEDO).then(|| self.axes.rho.power().of(rho / TINY_ALBEDO))
    }

    /// The albedo at which the densities and draws read the table for `rho`: [`TINY_ALBEDO`]
    /// between 0 and it ([`TableRef::tiny_scale`]), else ρ′.
    #[inline(always)]
    pub(super) fn read_albedo(&self, rho: f64) -> f64 {
        if rho > 0.0 && rho < TINY_ALBEDO {
            TINY_ALBEDO
        } else {
            rho
        }
    }

    /// What the nodes give at the point: S, or S less the ridge for a table with one.
    #[inline(always)]
    fn eval_nodes(&self, rho: f64, theta: f64, r: f64, phi: f64) -> Option<f64> {
        if let Some(second) = self.harmonics {
            return self.eval_two_lobes(second, rho, theta, r, phi);
        }
        let cell = self.cell_at_point(rho, theta, r)?;
        if !phi.is_finite() || !self.light_enters(theta) {
            return Some(0.0);
        }
        Some(match cell {
            Cell::Profile([e_per_r, beta, c]) => table_value(e_per_r, beta, c, wrap_phi(phi)),
            Cell::OutsideRadius => 0.0,
        })
    }

    /// The profile at (ρ′, θ, r) as (E/r ≥ 0, β ∈ [0, lobe_cap(E/r, c)], c), the same profile as
    /// [`Gwc::from_table`] builds from [`TableRef::cell_from`], without building a slice
    /// (evaluation needs nothing else of it): `None` if (ρ′, θ) is outside the axes, `OutsideRadius`
    /// where [`TableRef::radius`] is `None`.
    #[inline(always)]
    fn cell_at_point(&self, rho: f64, theta: f64, r: f64) -> Option<Cell> {
        if self.axes.dims().2 < 4 {
            return self.cell_at_point_short(rho, theta, r);
        }
        // Points off the quick ρ′ weights out of line (`AlbedoAxis::hot_weights`)
        let Some(albedo) = self.axes.rho.hot_eval_weights(rho) else {
            return self.cell_at_point_cold(rho, theta, r);
        };
        self.cell_at_point_with(albedo, rho, theta, r)
    }

    /// [`TableRef::cell_at_point`] of a table of fewer than 4 radii, from the slice's
    /// [`TableRef::window`]: [`TableRef::window_at`] reads 4 radius nodes of each row, which
    /// run past the last row of such a table. Out of line: no table the crate bakes has so few.
    #[cold]
    #[inline(never)]
    fn cell_at_point_short(&self, rho: f64, theta: f64, r: f64) -> Option<Cell> {
        let s = self.with_slice(rho, theta, |s| *s)?;
        let Some((r_eval, w)) = self.radius(r) else {
            return Some(Cell::OutsideRadius);
        };
        let first = self.radial_window(&w);
        let (e, lobe, c) =
            self.cell_from::<true>(self.window(&s, first), first, r_eval, &w, s.blend);
        Some(Cell::profile(e, lobe, c, r_eval))
    }

    #[inline(never)]
    fn cell_at_point_cold(&self, rho: f64, theta: f64, r: f64) -> Option<Cell> {
        // At the ends of the albedo axis, the spline of E/(ρ′² f) (`albedo_ends`)
        if let Some(ends) = self.axes.rho.end_weights(rho) {
            return self.cell_at_point_albedo_ends(&ends, rho, theta, r);
        }
        self.cell_at_point_with(self.axes.rho.weights(rho)?, rho, theta, r)
    }

    #[inline(always)]
    fn cell_at_point_with(
        &self,
        albedo: AlbedoWeights,
        rho: f64,
        theta: f64,
        r: f64,
    ) -> Option<Cell> {
        // The weight searches first: they are independent and overlap in the pipeline
        let theta_weights = self.theta_weights(theta)?;
        let Some((r_eval, w)) = self.radius(r) else {
            return Some(Cell::OutsideRadius);
        };
        let first = self.radial_window(&w);
        let acc = self.window_at(&albedo.energy, &theta_weights, first);
        let blend = Blend::new(&albedo, rho, theta);
        let (e, lobe, c) = self.cell_from::<true>(acc, first, r_eval, &w, blend);
        Some(Cell::profile(e, lobe, c, r_eval))
    }

    /// The perpendicular-incidence model: the θ = 0 slice at every θ, uniform in φ (pbrt's
    /// assumption), S = E(ρ′, 0, r)/(2πr).
    pub fn eval_perpendicular(&self, rho: f64, r: f64) -> Option<f64> {
        if let Some(scale) = self.tiny_scale(rho) {
            return Some(scale * self.eval_perpendicular(TINY_ALBEDO, r)?);
        }
        Some(match self.cell_at_point(rho, 0.0, r)? {
            Cell::Profile([e_per_r, ..]) => e_per_r / TAU,
            Cell::OutsideRadius => 0.0,
        })
    }

    /// Effective albedo ρ_eff(ρ′, θ) = ∫ E dr: the total multiply scattered power per unit power
    /// entering, as the table represents it; 0 where the blend of the rows' totals is negative
    /// (as [`TableRef::eval`] is 0 where the blended E is): the θ spline undershoots between a
    /// lit node and an unlit one beyond the critical angle (η < 1). A table with the ridge adds
    /// the ridge's energy up to its last radius.
    pub fn effective_albedo(&self, rho: f64, theta: f64) -> Option<f64> {
        if let Some(scale) = self.tiny_scale(rho) {
            return Some(scale * self.effective_albedo(TINY_ALBEDO, theta)?);
        }
        let enters = self.light_enters(theta);
        let nodes = self.with_slice(rho, theta, |s| if enters { self.total(s) } else { 0.0 })?;
        Some(nodes + self.ridge_at(rho, theta).map_or(0.0, |r| r.energy()))
    }

    /// Whether light enters at θ (radians, within the axis): always for η ≥ 1, below the
    /// critical angle asin η otherwise. Beyond it every lookup gives 0 or no sample: the nodes
    /// there hold 0, but the spline through them and the last nodes below is not 0 between.
    fn light_enters(&self, theta: f64) -> bool {
        self.eta >= 1.0 || crate::fresnel::refracted_cos(theta.min(FRAC_PI_2), self.eta).is_some()
    }

    fn total(&self, s: &Slice) -> f64 {
        let (_, _, n_r) = self.axes.dims();
        self.cdf(s, n_r - 1).max(0.0)
    }
}

/// The weights of the window nodes `first..first + 4` from the radius weights `w`: node
/// first + k takes entry first + k + 1 − segment of the four, whose entries for nodes −1 and
/// n_r (dropped here) are 0.
#[inline(always)]
fn node_weights(first: usize, w: &Weights) -> [f64; 4] {
    let wa = w.as_array();
    match (first + 1).checked_sub(w.segment()) {
        Some(0) => wa,
        Some(_) => [wa[1], wa[2], wa[3], 0.0],
        None => [0.0, wa[0], wa[1], wa[2]],
    }
}

/// ln E of the four nodes of a (E, E_β, c) window where E > 0 (0 for the others; the caller
/// reads only the nodes with weight). The nodes are f32 values: their logarithms in f32 lose
/// nothing. Out of line, so that the four library calls do not force the caller's sums to and
/// from the stack; it takes no weights, which would go through memory.
#[inline(never)]
fn ln_energies(window: [f32; 12]) -> [f32; 4] {
    std::array::from_fn(|k| {
        let e = window[PARAMS_PER_NODE * k];
        if e > 0.0 {
            e.ln()
        } else {
            0.0
        }
    })
}

/// Maps any finite φ into [−π, π] (the profile is 2π-periodic and even), as an odd function:
/// wrap(−φ) = −wrap(φ), so that a value at −φ is the value at φ bit for bit and a CDF's at −φ
/// its mirror. |φ| is reduced by `%`, exact for the f64 2π (φ + π, as before, rounded: off by
/// 1.4·10⁻⁵ relative between ±10¹² rad and unrelated from 10¹⁷ on); what is left is that
/// 2π in f64 is 2.4·10⁻¹⁶ below 2π, so at |φ| = 2πk the angle is off by k·2.4·10⁻¹⁶ rad
/// (10⁻⁷ rad at 2.6·10⁹ rad).
fn wrap_phi(phi: f64) -> f64 {
    if (-PI..=PI).contains(&phi) {
        return phi;
    }
    let a = phi.abs() % TAU;
    let a = if a > PI { a - TAU } else { a };
    if phi < 0.0 {
        -a
    } else {
        a
    }
}
