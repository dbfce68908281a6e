//! The walk's azimuthal harmonics on a set of radii, for many albedos from one walk: what a
//! table fitted to the Monte Carlo truth needs at one incidence.
//!
//! | parameter | unit | range |
//! |---|---|---|
//! | `rho` (per row) | – | reduced albedo ρ′ ∈ [0, 1] |
//! | `g` | – | Henyey–Greenstein asymmetry, (−1, 1) |
//! | `eta` | – | η = n_inside/n_outside in [0.75, 2.5] |
//! | `theta` | radians | [0, π/2]; at most asin η when η < 1 |
//! | `r` (nodes) | reduced mean free paths | ≥ 2, finite, strictly increasing, first ≥ 0 |
//! | `photons` | – | at least [`MIN_HARMONICS_PHOTONS`] |
//!
//! # What is estimated
//! For each row (ρ′) and node rᵢ > 0, the harmonics μₙ(r) = ∫ S(r, φ) cos nφ dφ over [−π, π],
//! n = 0 … 4, of the exitance S per unit reduced area per unit power entering (reduced units,
//! σ′t = 1; φ = 0 forward), separately for single and multiple scattering, each **averaged
//! over a hat kernel in ln r**: 1 at rᵢ, falling linearly to 0 at the neighbouring nodes (at
//! the first node above 0 and at the last, the kernel is symmetric, with the width of its one
//! neighbour). The estimator of node i is the sum over exits of w · hᵢ(r) cos nφ / (r² Δᵢ), Δᵢ
//! the kernel's integral over ln r; its mean is the kernel average of μₙ over ln r, unbiased
//! for it. The average differs from μₙ(rᵢ) by the profile's curvature in ln r over the kernel;
//! a bake corrects that with a model of the same curvature (PBD). A node at r = 0 has no
//! kernel and reads 0.
//!
//! # One walk for every albedo
//! The walk absorbs by weight: a path's geometry does not depend on the albedo a, and an exit
//! after n scattering vertices carries the factor aⁿ. So the walk runs once at the largest
//! albedo a_max of the rows, and each row k takes each exit with the factor (a_k/a_max)ⁿ.
//! Roulette (played on the a_max weight) and the vertex cap act on every row alike, and the
//! estimates of each row have the expectation and (up to roulette) the variance of a walk of
//! its own; the rows' noise is correlated, which keeps it smooth along ρ′. A row's factor is
//! dropped once it falls below 10⁻¹⁵. With g ≠ 0 the rows differ in σ′t/σt = 1 − g a_k as
//! well: each scales the exit radius (and the density) to its own reduced units. The
//! unreduced albedo of a row is a = ρ′/(1 − g + gρ′).
//!
//! # Standard errors and determinism
//! Photons are traced in blocks of [`super::BLOCK`] in parallel, as in [`super::run`]; blocks
//! are grouped in order into [`HARMONICS_BATCHES`] batches (fewer when there are fewer blocks),
//! and the standard error of each estimate is that of the batch means (weighted by the
//! batches' photon counts). Sums are added in block order: the result is bit-identical for a
//! given seed whatever the thread count.

use super::exits::Sink;
use super::rng::photon_stream;
use super::tally::{Order, Surface};
use super::transport::Medium;
use super::{Component, BLOCK};
use crate::error::{finite, in_range, Error, Result};
use rayon::prelude::*;

/// Harmonics per node: μ₀ … μ₈ (a walk table's tilt of PBD matches μ₀ … μ₄, and its share
/// of PBD's ridge near index matching μ₅ … μ₈: `table::walk_bake`).
pub const HARMONICS: usize = 9;

/// Batches of the standard errors (fewer when the walk has fewer blocks).
pub const HARMONICS_BATCHES: usize = 32;

/// The fewest photons: 16 blocks, so that a standard error comes from 16 batches (with two, it
/// has one degree of freedom and can come out near 0, and a bake weighing nodes by 1/σ² would
/// let such a node dominate).
pub const MIN_HARMONICS_PHOTONS: u64 = 16 * BLOCK;

/// A row's factor (a_k/a_max)ⁿ below which its exits are no longer scored.
const FACTOR_FLOOR: f64 = 1e-15;

/// What to walk: the medium, the beam, the rows and the radii.
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicsConfig {
    /// Reduced albedos ρ′ of the rows, each in [0, 1], in any order.
    pub rho: Vec<f64>,
    /// Henyey–Greenstein asymmetry g.
    pub g: f64,
    /// Relative index η.
    pub eta: f64,
    /// Incidence θ before refraction, radians.
    pub theta: f64,
    /// Radii of the nodes, reduced mean free paths.
    pub r: Vec<f64>,
    /// Photon packets.
    pub photons: u64,
    /// Seed of the photons' streams ([`super::rng::photon_stream`]).
    pub seed: u64,
}

/// The estimates of a [`harmonics`] walk: per component (single, multiple), row and node, the
/// kernel averages of μ₀ … μ₈ and their standard errors.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkHarmonics {
    rows: usize,
    nodes: usize,
    photons: u64,
    scattering_events: u64,
    /// [component][row][node], component 0 single, 1 multiple.
    mean: Vec<[f64; HARMONICS]>,
    stderr: Vec<[f64; HARMONICS]>,
}

impl WalkHarmonics {
    fn at(&self, component: Component, row: usize, node: usize) -> Option<usize> {
        let c = match component {
            Component::Single => 0,
            Component::Multiple => 1,
            Component::Total | Component::Unscattered => return None,
        };
        (row < self.rows && node < self.nodes).then(|| (c * self.rows + row) * self.nodes + node)
    }

    /// Kernel averages of μ₀ … μ₈ of `component` at `row` (the order of
    /// [`HarmonicsConfig::rho`]) and `node`, per unit power entering, reduced units; `None` for
    /// a row or node out of range, or a component other than single or multiple (the total is
    /// their sum; a half-space lets no unscattered light out).
    pub fn mean(&self, component: Component, row: usize, node: usize) -> Option<[f64; HARMONICS]> {
        self.at(component, row, node).map(|i| self.mean[i])
    }

    /// Standard errors of [`WalkHarmonics::mean`].
    pub fn stderr(
        &self,
        component: Component,
        row: usize,
        node: usize,
    ) -> Option<[f64; HARMONICS]> {
        self.at(component, row, node).map(|i| self.stderr[i])
    }

    /// Photons traced.
    pub fn photons(&self) -> u64 {
        self.photons
    }

    /// Scattering vertices of the walk (at a_max).
    pub fn scattering_events(&self) -> u64 {
        self.scattering_events
    }
}

/// The kernel of one node: ln rᵢ, the widths on each side (in ln r) and 1/Δᵢ.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Kernel {
    centre: f64,
    left: f64,
    right: f64,
    inv_area: f64,
}

impl Kernel {
    fn weight(&self, u: f64) -> f64 {
        let d = u - self.centre;
        let h = if d < 0.0 {
            1.0 + d / self.left
        } else {
            1.0 - d / self.right
        };
        h.max(0.0) * self.inv_area
    }
}

impl Kernel {
    /// The average of `f` (of the radius) over this kernel, by `rule` over ln r on each side of
    /// the node (the hat's kink).
    pub(crate) fn average<const N: usize>(
        &self,
        rule: &crate::quadrature::GaussLegendre,
        f: impl Fn(f64) -> [f64; N],
    ) -> [f64; N] {
        let mut sum = [0.0; N];
        for (from, width, rising) in [
            (self.centre - self.left, self.left, true),
            (self.centre, self.right, false),
        ] {
            for (x, w) in rule.nodes().iter().zip(rule.weights()) {
                let t = 0.5 * (1.0 + x);
                let hat = if rising { t } else { 1.0 - t };
                let v = f((from + t * width).exp());
                for (s, vn) in sum.iter_mut().zip(v) {
                    *s += 0.5 * width * w * hat * vn;
                }
            }
        }
        sum.map(|s| s * self.inv_area)
    }
}

/// Kernels of the nodes (`None` at r = 0).
pub(crate) fn kernels(r: &[f64]) -> Vec<Option<Kernel>> {
    let n = r.len();
    let ln = |i: usize| r[i].ln();
    (0..n)
        .map(|i| {
            if r[i] == 0.0 {
                return None;
            }
            let right = (i + 1 < n).then(|| ln(i + 1) - ln(i));
            let left = (i > 0 && r[i - 1] > 0.0).then(|| ln(i) - ln(i - 1));
            // ≥ 2 nodes with at most one at 0: a node above 0 has a neighbour above 0 unless
            // it is the only one, [0, r₁]
            let (left, right) = match (left, right) {
                (Some(l), Some(r)) => (l, r),
                (Some(l), None) => (l, l),
                (None, Some(r)) => (r, r),
                (None, None) => (1.0, 1.0),
            };
            Some(Kernel {
                centre: ln(i),
                left,
                right,
                inv_area: 2.0 / (left + right),
            })
        })
        .collect()
}

/// One row as the tally sees it.
#[derive(Debug, Clone, Copy)]
struct Row {
    /// Position in the config's order.
    index: usize,
    /// a_k / a_max.
    ratio: f64,
    /// σ′t/σt = 1 − g a_k: reduced radius = radius × scale, density ÷ scale².
    scale: f64,
}

/// Sums of one block: [component][row][node][harmonic] in the config's row order.
struct BlockSums {
    sums: Vec<[f64; HARMONICS]>,
    events: u64,
}

/// The per-photon sink: the rows' factors and the block's sums.
struct Tally<'a> {
    rows: &'a [Row],
    kernels: &'a [Option<Kernel>],
    /// Node radii (for locating an exit).
    r: &'a [f64],
    n_rows: usize,
    factor: Vec<f64>,
    /// Rows (sorted by ratio, descending) whose factor is still scored.
    active: usize,
    out: BlockSums,
}

impl Tally<'_> {
    fn start_photon(&mut self) {
        self.factor.iter_mut().for_each(|f| *f = 1.0);
        self.active = self.rows.len();
    }
}

impl Sink for Tally<'_> {
    fn exit(&mut self, surface: Surface, x: f64, y: f64, weight: f64, order: Order) {
        let component = match (surface, order) {
            (Surface::Top, Order::Single) => 0,
            (Surface::Top, Order::Multiple) => 1,
            _ => return,
        };
        let radius = x.hypot(y);
        if radius.is_nan() || radius <= 0.0 {
            return;
        }
        // cos nφ by the recurrence of Chebyshev: cos(n+1)φ = 2 cos φ cos nφ − cos(n−1)φ
        let c1 = x / radius;
        let mut cos = [1.0; HARMONICS];
        cos[1] = c1;
        for n in 2..HARMONICS {
            cos[n] = 2.0 * c1 * cos[n - 1] - cos[n - 2];
        }
        let n_nodes = self.r.len();
        for (row, &factor) in self.rows[..self.active].iter().zip(&self.factor) {
            let reduced = radius * row.scale;
            // The nodes whose kernel holds `reduced`: the two about it, or the one past an end
            let above = self.r.partition_point(|&v| v < reduced);
            let w = weight * factor / (reduced * reduced);
            let u = reduced.ln();
            let base = (component * self.n_rows + row.index) * n_nodes;
            for node in above.saturating_sub(1)..(above + 1).min(n_nodes) {
                if let Some(kernel) = &self.kernels[node] {
                    let k = w * kernel.weight(u);
                    if k > 0.0 {
                        let cell = &mut self.out.sums[base + node];
                        for (s, c) in cell.iter_mut().zip(&cos) {
                            *s += k * c;
                        }
                    }
                }
            }
        }
    }

    fn vertex(&mut self) {
        self.out.events += 1;
        for (f, row) in self.factor[..self.active].iter_mut().zip(self.rows) {
            *f *= row.ratio;
        }
        while self.active > 0 && self.factor[self.active - 1] < FACTOR_FLOOR {
            self.active -= 1;
        }
    }

    fn truncate(&mut self, _weight: f64) {}
}

impl HarmonicsConfig {
    /// Checks every parameter, naming the first bad one.
    pub fn validate(&self) -> Result<()> {
        if self.rho.is_empty() {
            return Err(Error::CountOutOfRange {
                name: "rho rows",
                value: 0,
                min: 1,
                max: u64::MAX,
            });
        }
        for &rho in &self.rho {
            in_range("rho", rho, 0.0, 1.0)?;
        }
        super::validate_beam(self.g, self.eta, self.theta)?;
        if self.r.len() < 2 {
            return Err(Error::CountOutOfRange {
                name: "r nodes",
                value: self.r.len() as u64,
                min: 2,
                max: u64::MAX,
            });
        }
        in_range("first r node", self.r[0], 0.0, f64::MAX)?;
        for pair in self.r.windows(2) {
            finite("r node", pair[1])?;
            if pair[0] >= pair[1] {
                return Err(Error::EdgesNotIncreasing {
                    lo_name: "r node",
                    lo: pair[0],
                    hi_name: "the next r node",
                    hi: pair[1],
                });
            }
        }
        if self.photons < MIN_HARMONICS_PHOTONS {
            return Err(Error::CountOutOfRange {
                name: "photons",
                value: self.photons,
                min: MIN_HARMONICS_PHOTONS,
                max: u64::MAX,
            });
        }
        Ok(())
    }
}

/// The unreduced albedo a = ρ′/(1 − g + gρ′) of reduced albedo ρ′ under asymmetry g.
pub fn unreduced_albedo(rho: f64, g: f64) -> f64 {
    rho / (1.0 - g + g * rho)
}

/// Walks `config.photons` photons at the largest albedo of the rows and returns the kernel
/// averages of every row's harmonics (module docs). Runs on the current rayon pool;
/// `progress(n)` is called with the photons of each finished chunk.
pub fn harmonics(
    config: &HarmonicsConfig,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<WalkHarmonics> {
    config.validate()?;
    let albedo: Vec<f64> = config
        .rho
        .iter()
        .map(|&rho| unreduced_albedo(rho, config.g))
        .collect();
    let a_max = albedo.iter().copied().fold(0.0, f64::max);
    let mut rows: Vec<Row> = albedo
        .iter()
        .enumerate()
        .map(|(index, &a)| Row {
            index,
            ratio: if a_max > 0.0 { a / a_max } else { 1.0 },
            scale: 1.0 - config.g * a,
        })
        .collect();
    // Descending ratios: the rows still scored are a prefix
    rows.sort_by(|a, b| b.ratio.total_cmp(&a.ratio).then(a.index.cmp(&b.index)));
    let kernels = kernels(&config.r);
    let medium = Medium::new(a_max, config.g, config.eta, config.theta, None);
    let (n_rows, n_nodes) = (config.rho.len(), config.r.len());
    let cells = 2 * n_rows * n_nodes;

    let blocks = config.photons.div_ceil(BLOCK);
    let n_batches = (HARMONICS_BATCHES as u64).min(blocks) as usize;
    // Block k is in batch ⌊kB/blocks⌋: contiguous, in order, none empty (B ≤ blocks)
    let batch_of =
        |block: u64| (u128::from(block) * n_batches as u128 / u128::from(blocks)) as usize;
    let mut batch_sums = vec![vec![[0.0; HARMONICS]; cells]; n_batches];
    let mut batch_photons = vec![0u64; n_batches];
    let mut events = 0u64;
    let chunk = 4 * rayon::current_num_threads().max(1) as u64;
    let mut start = 0;
    while start < blocks {
        let end = blocks.min(start + chunk);
        let parts: Vec<BlockSums> = (start..end)
            .into_par_iter()
            .map(|block| {
                let mut tally = Tally {
                    rows: &rows,
                    kernels: &kernels,
                    r: &config.r,
                    n_rows,
                    factor: vec![1.0; rows.len()],
                    active: rows.len(),
                    out: BlockSums {
                        sums: vec![[0.0; HARMONICS]; cells],
                        events: 0,
                    },
                };
                let first = block * BLOCK;
                for index in first..config.photons.min(first + BLOCK) {
                    let mut rng = photon_stream(config.seed, index);
                    tally.start_photon();
                    medium.trace(&mut rng, &mut tally);
                }
                tally.out
            })
            .collect();
        for (block, part) in (start..end).zip(parts) {
            let b = batch_of(block);
            for (s, p) in batch_sums[b].iter_mut().zip(&part.sums) {
                for (x, y) in s.iter_mut().zip(p) {
                    *x += y;
                }
            }
            batch_photons[b] += config.photons.min((block + 1) * BLOCK) - block * BLOCK;
            events += part.events;
        }
        progress(config.photons.min(end * BLOCK) - start * BLOCK);
        start = end;
    }

    // Mean over all photons; standard error of the photon-weighted batch means
    let total = config.photons as f64;
    let mut mean = vec![[0.0; HARMONICS]; cells];
    let mut stderr = vec![[0.0; HARMONICS]; cells];
    for cell in 0..cells {
        for n in 0..HARMONICS {
            let sum: f64 = batch_sums.iter().map(|b| b[cell][n]).sum();
            let m = sum / total;
            let spread: f64 = batch_sums
                .iter()
                .zip(&batch_photons)
                .map(|(b, &p)| {
                    let p = p as f64;
                    p * (b[cell][n] / p - m).powi(2)
                })
                .sum();
            mean[cell][n] = m;
            stderr[cell][n] = (spread / ((n_batches - 1) as f64 * total)).sqrt();
        }
    }
    // The rows' densities per unit reduced area: ÷ scale² was taken per exit through the
    // reduced radius (w / r′²); nothing more to scale
    Ok(WalkHarmonics {
        rows: n_rows,
        nodes: n_nodes,
        photons: config.photons,
        scattering_events: events,
        mean,
        stderr,
    })
}
