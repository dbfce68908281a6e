//! Monte Carlo ground truth: a random walk in a homogeneous medium under a collimated beam.
//!
//! Follows "Measuring BSSRDFs" (the random-walk measurement notes in `shared/papers`, §1
//! random walk, §2 connections), with the changes listed under *Estimator* below.
//!
//! # Setting
//! A semi-infinite medium z < 0 (or a slab −τ < z < 0) with a smooth dielectric boundary on
//! every side, the same relative index η inside over outside on both. Extinction σt = 1: all
//! distances are in (unreduced) mean free paths. A collimated beam at incidence θ from the
//! normal enters at the origin and is refracted to sin θt = sin θ / η; inside, it travels toward
//! +x, so **φ = 0 is forward** (exit points with x > 0 in the plane of incidence).
//! Every quantity is **per unit power entering the medium**: the entry Fresnel transmittance
//! T(θ) is *not* applied, and the specular reflection at entry is not counted. To compare with
//! a reflectance per unit incident power, multiply by T(θ) (or divide that one by it).
//!
//! | parameter   | unit                | range                                          |
//! |-------------|---------------------|------------------------------------------------|
//! | `albedo`    | —                   | a = σs/σt ∈ [0, 1] (unreduced)                 |
//! | `g`         | —                   | Henyey–Greenstein asymmetry, (−1, 1)           |
//! | `eta`       | —                   | η = n_inside/n_outside in [0.75, 2.5]           |
//! | `theta`     | radians             | [0, π/2]; at most asin η when η < 1 (no light enters beyond) |
//! | `photons`   | —                   | ≥ 2 ([`MIN_PHOTONS`]: a standard error needs two) |
//! | `seed`      | —                   | any u64                                        |
//! | `bins`      | mean free paths     | see [`Bins`]                                   |
//! | `geometry`  | mean free paths     | half-space, or slab of optical thickness τ > 0 |
//!
//! # Estimator
//! - **Free flights** s exponential with mean 1 (σt = 1), drawn by `rand_distr`'s `Exp1`
//!   (the ziggurat method of Marsaglia and Tsang 2000: no logarithm on the fast path, which
//!   takes about 99 % of draws).
//! - **Absorption by weight** (implicit capture): at each scattering vertex the weight is
//!   multiplied by a, instead of the paper's killing with probability 1 − a. Same expectation,
//!   less variance.
//! - **Phase function**: Henyey–Greenstein, sampled by inverting its CDF.
//! - **Boundary: the transmitted part leaves, the reflected part by roulette.** Where a flight
//!   reaches a boundary, the Fresnel-transmitted part T = 1 − R(|cos|; 1/η) of its weight
//!   leaves (total internal reflection gives T = 0) and the packet continues, mirrored, with
//!   probability R and its weight w unchanged, which carries the reflected part R·w in
//!   expectation (MCML's choice at a boundary; the transmitted part, though, is scored as a
//!   weight rather than drawn). Splitting instead, continuing with weight R·w, spent a third
//!   of the scattering events of a g = 0 half-space at η = 1.33 (55 a photon against 38) on
//!   packets left with a few per cent of their weight (R ≈ 0.02 at normal incidence), for
//!   variances 1–2 % lower in the bins within 5 mean free paths (`docs/performance.md`, "The
//!   random walk"). The unscattered beam (only a slab sends it back) is still split, so that
//!   the slab's unscattered series is scored without noise, as before. Reflections are not
//!   scattering vertices.
//! - **Russian roulette** below weight 10⁻⁴, survival 1/10 with weight ×10 (MCML's
//!   constants): unbiased.
//! - **Exit estimate along the sampled direction** (the paper's connections, made unbiased
//!   and of bounded variance). Before every flight from p in direction ω, if the ray meets a
//!   boundary at distance d ≤ [`EXPECTED_SCORE_DISTANCE`] (6 mean free paths), the expected
//!   transmitted weight w · e^{−d} · T(|ω_z|) is scored at the point where it meets it; the
//!   flight is then sampled as usual, and a packet reaching the boundary only goes on with its
//!   reflected part (its transmitted part is not scored again). Since E[1{s ≥ d}] = e^{−d},
//!   each flight's expected score equals the analog one, and the scores are at the true exit
//!   points, so any binned tally is unbiased. A flight from farther away reaches the boundary
//!   with probability below e⁻⁶ ≈ 0.25 %: it scores w · T(|ω_z|) only if it does (the analog
//!   score, of the same expectation), which spares the Fresnel factor, the exponential and the
//!   binning of the many deep flights whose expected scores are all but zero. Which of the two a
//!   flight gets depends on d alone, known before the flight is drawn, so the estimator stays
//!   unbiased.
//!   This is the paper's §2 connection from a vertex x_p to a surface point x_o, with x_o drawn
//!   through the phase function (where ω meets the surface) instead of uniformly in a bin's
//!   (r, φ) box. With that density, p(ω)|cos|/d² per unit area, the phase function and the
//!   geometry term cancel and the score is bounded by w. The paper's uniform choice is also
//!   unbiased once the walk stops scoring its own escapes (the notes do not say that it does;
//!   if it does not, those exits are counted twice), but its kernel behaves like
//!   |z|/d³ near a vertex at depth z, so a connection's second moment grows like 1/z²; vertices
//!   come arbitrarily close to the surface and the variance is infinite, which would make the
//!   per-bin standard errors meaningless. The paper also skips the first vertex; here the first
//!   vertex is scored as single scattering.
//! - **Orders**: an exit is *single* scattering if exactly one scattering vertex preceded it,
//!   *multiple* if two or more, *unscattered* if none (only a slab lets the beam out unscattered,
//!   after 0 or more internal reflections).
//! - **Tallies**: exitance per unit area per unit power entering in (r, φ) bins (integrated over
//!   the exit hemisphere; the paper's angular bins are not kept), and reflectance and slab
//!   transmittance counting every exit regardless of bins. Standard errors come from
//!   per-photon second moments: a photon's scores are summed per quantity and per bin before
//!   squaring.
//! - **Vertex cap**: a photon stops after [`MAX_VERTICES`] vertices; its weight then is reported
//!   by [`WalkResult::truncated_weight`]. This only matters for a ≈ 1 in a half-space.
//!
//! # Determinism
//! Photon k draws from its own xoshiro256++ stream seeded from (seed, k) ([`rng`]). Photons
//! are grouped in fixed blocks of [`BLOCK`]; each block is summed in photon order, blocks are
//! traced in parallel (rayon) and added in block order. The result is bit-identical for a given
//! seed whatever the thread count.
//!
//! # Where it breaks down
//! It is exact up to statistics, roulette (unbiased) and the vertex cap. Tallies near the
//! origin and at large r are noisy: the bins' standard errors say how noisy. A smooth boundary
//! and a homogeneous medium only.

pub mod bins;
mod exits;
pub mod harmonics;
mod result;
pub mod rng;
pub mod single;
mod tally;
mod transport;

#[cfg(test)]
mod single_tests;
#[cfg(test)]
mod tests;

pub use bins::Bins;
pub use exits::{Exit, ExitWalk, PhotonPath};
pub use result::{BinnedExitance, Component, Estimate, WalkResult};
pub use transport::{
    hg_phase, sample_hg_cos, EXPECTED_SCORE_DISTANCE, MAX_VERTICES, ROULETTE_SURVIVAL,
    ROULETTE_WEIGHT,
};

use crate::error::{finite, in_range, Error, Result};
use rayon::prelude::*;
use rng::photon_stream;
use std::f64::consts::FRAC_PI_2;
use tally::{PhotonTally, Sums};
use transport::Medium;

/// Photons per block: the unit of parallel work and of the fixed summation order.
pub const BLOCK: u64 = 1024;

/// The fewest photons a walk takes: every estimate comes with its standard error, which needs
/// two.
pub const MIN_PHOTONS: u64 = 2;

/// Shape of the medium.
/// In JSON one shape for both: `{"kind": "half-space"}`, `{"kind": "slab", "thickness": τ}`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Geometry {
    /// The half-space z < 0.
    HalfSpace,
    /// The slab −thickness < z < 0, thickness in mean free paths (> 0), the same boundary on
    /// both sides.
    Slab {
        /// Optical thickness τ (mean free paths).
        thickness: f64,
    },
}

/// Parameters of a run; checked by [`Config::validate`] (and by [`run`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Single-scattering albedo a = σs/σt (unreduced), in [0, 1].
    pub albedo: f64,
    /// Henyey–Greenstein asymmetry g, in (−1, 1).
    pub g: f64,
    /// Relative index η = n_inside/n_outside, > 0.
    pub eta: f64,
    /// Incidence angle θ from the normal before refraction, radians, in [0, π/2].
    pub theta: f64,
    /// Number of photon packets, ≥ 1.
    pub photons: u64,
    /// Seed of the random streams.
    pub seed: u64,
    /// Exit-point bins of the lit surface.
    pub bins: Bins,
    /// Half-space or slab.
    pub geometry: Geometry,
}

impl Config {
    /// A half-space run with 10⁶ photons, seed 0 and the default bins.
    pub fn new(albedo: f64, g: f64, eta: f64, theta: f64) -> Self {
        Self {
            albedo,
            g,
            eta,
            theta,
            photons: 1_000_000,
            seed: 0,
            bins: Bins::default(),
            geometry: Geometry::HalfSpace,
        }
    }

    /// Checks every parameter, naming the first bad one.
    pub fn validate(&self) -> Result<()> {
        in_range("albedo", self.albedo, 0.0, 1.0)?;
        validate_beam(self.g, self.eta, self.theta)?;
        // A standard error needs two photons; every estimate of the walk carries one
        if self.photons < MIN_PHOTONS {
            return Err(Error::CountOutOfRange {
                name: "photons",
                value: self.photons,
                min: MIN_PHOTONS,
                max: u64::MAX,
            });
        }
        if let Geometry::Slab { thickness } = self.geometry {
            finite("thickness", thickness)?;
            if thickness <= 0.0 {
                return Err(Error::NotPositive {
                    name: "thickness",
                    value: thickness,
                });
            }
        }
        Ok(())
    }

    fn medium(&self) -> Medium {
        let thickness = match self.geometry {
            Geometry::HalfSpace => None,
            Geometry::Slab { thickness } => Some(thickness),
        };
        Medium::new(self.albedo, self.g, self.eta, self.theta, thickness)
    }
}

/// Checks the phase function and the beam of a walk: g in (−1, 1), η in the models' domain, θ
/// in [0, π/2] and, below η = 1, at most the critical angle (beyond it no power enters to
/// normalise by).
pub(crate) fn validate_beam(g: f64, eta: f64, theta: f64) -> Result<()> {
    finite("g", g)?;
    if g.abs() >= 1.0 {
        return Err(Error::AsymmetryOutOfRange(g));
    }
    crate::medium::validate_eta(eta)?;
    in_range("theta", theta, 0.0, FRAC_PI_2)?;
    // Compared as angles: at θ = asin η, sin θ can round one ulp above η
    if eta < 1.0 && theta > eta.asin() {
        return Err(Error::OutOfRange {
            name: "theta",
            value: theta,
            min: 0.0,
            max: eta.asin(),
        });
    }
    Ok(())
}

/// Traces `config.photons` photons and returns the tallies.
///
/// Runs on the current rayon thread pool; the result does not depend on its size.
pub fn run(config: &Config) -> Result<WalkResult> {
    run_with_progress(config, &|_| {})
}

/// [`run`], calling `progress(n)` after each chunk of photons with the `n` photons it traced
/// (for a progress bar; the result is the same).
pub fn run_with_progress(config: &Config, progress: &(dyn Fn(u64) + Sync)) -> Result<WalkResult> {
    config.validate()?;
    let medium = config.medium();
    let blocks = config.photons.div_ceil(BLOCK);
    let mut total = Sums::new(config.bins.len(), tally::square_scale(config.albedo));
    // Blocks are traced a chunk at a time to bound memory; chunking never changes the order
    // in which block sums are added, so it does not change the result.
    let chunk = 4 * rayon::current_num_threads().max(1) as u64;
    let mut start = 0;
    while start < blocks {
        let end = blocks.min(start + chunk);
        let parts: Vec<Sums> = (0..(end - start) as usize)
            .into_par_iter()
            .map(|k| trace_block(config, &medium, start + k as u64))
            .collect();
        for part in &parts {
            total.merge(part);
        }
        progress(config.photons.min(end * BLOCK) - start * BLOCK);
        start = end;
    }
    Ok(WalkResult::new(config, &total))
}

/// Traces the photons of block `block`, in index order.
fn trace_block(config: &Config, medium: &Medium, block: u64) -> Sums {
    let first = block * BLOCK;
    let last = config.photons.min(first + BLOCK);
    let mut tally = PhotonTally::new(&config.bins, tally::square_scale(config.albedo));
    for index in first..last {
        let mut rng = photon_stream(config.seed, index);
        medium.trace(&mut rng, &mut tally);
        tally.end_photon();
    }
    tally.into_sums()
}
