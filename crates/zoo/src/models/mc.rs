//! The Monte Carlo random walk as a model (`mc`): the binned exitance of one [`crate::walk`] run,
//! evaluated by bin lookup.
//!
//! | parameter | unit | valid range |
//! |---|---|---|
//! | ρ′, η, g | – | as [`Params`]; the walk runs with the unreduced albedo a = ρ′/(1 − g + gρ′) |
//! | θ (`McOptions::theta`) | rad | the one incidence the walk ran at, [0, π/2], ≤ asin η if η < 1 |
//! | photons, seed, bins | – | see [`crate::walk::Config`] and [`Bins`] |
//! | component | – | which exits are kept: single, multiple or total (default total) |
//! | result | per reduced mfp², per unit power entering | ≥ 0 |
//!
//! **Units.** The walk runs at σt = 1, so its lengths are unreduced mean free paths. With
//! σ′t = σt(1 − g a), a reduced length is k = 1 − g a times the unreduced one, and an area
//! density per reduced mfp² is the walk's divided by k² (k = 1 for g = 0). The walk already
//! tallies the power leaving (outside the boundary) per unit power entering: no conversion.
//!
//! **Lookup.** The bins hold averages over annular sectors. Mirror bins (φ and −φ) are averaged
//! at construction, which halves the variance and makes the model exactly even in φ; the
//! standard error of the average is taken as the mean of the two (conservative: it ignores any
//! negative correlation). `eval` returns the value of the bin holding (r, |φ|), 0 beyond the
//! last radial edge, and 0 at any θ other than the walk's (it has no data there).
//!
//! **Sampling.** A bin is drawn with probability proportional to its energy (value × area), then a
//! point uniformly in its area; `pdf` = value / binned total. The effective albedo is the walk's
//! reflectance of the component (every exit, binned or not), so the sampler is normalised to
//! the binned part only.
//!
//! Where it breaks down: statistics (each bin carries its standard error), the bin averaging
//! (a bin's value is not the value at its centre where R is curved), and the vertex cap of
//! the walk at ρ′ ≈ 1. Flat half-space, smooth boundary.

use super::{Model, ModelKind, Params, Sample};
use crate::error::Result;
use crate::fresnel::Moments;
use crate::walk::{self, Bins, Component, Estimate, WalkResult};
use std::f64::consts::{PI, TAU};

/// Options of the Monte Carlo model.
#[derive(Debug, Clone, PartialEq)]
pub struct McOptions {
    /// Incidence θ of the walk (radians).
    pub theta: f64,
    /// Photon packets.
    pub photons: u64,
    /// Seed of the walk.
    pub seed: u64,
    /// Bin layout, in the walk's unreduced mean free paths.
    pub bins: Bins,
    /// Which exits the model holds.
    pub component: Component,
}

impl Default for McOptions {
    /// θ = 0, 10⁵ photons, seed 1, the walk's default bins, total exitance.
    fn default() -> Self {
        Self {
            theta: 0.0,
            photons: 100_000,
            seed: 1,
            bins: Bins::default(),
            component: Component::Total,
        }
    }
}

/// The walk's binned exitance of one component, in reduced units.
#[derive(Debug, Clone)]
pub struct McModel {
    params: Params,
    theta: f64,
    component: Component,
    /// Radial edges, reduced mfp (first 0).
    r_edges: Vec<f64>,
    phi_count: usize,
    /// Mirror-averaged values and standard errors, [i · phi_count + j], per reduced mfp².
    value: Vec<f64>,
    stderr: Vec<f64>,
    /// Cumulative energy over bins, for sampling; the last entry is the binned total.
    cumulative: Vec<f64>,
    reflectance: Estimate,
}

impl McModel {
    /// Runs the walk for the parameters and options, and keeps one component.
    pub fn run(params: &Params, options: &McOptions) -> Result<Self> {
        let config = walk::Config {
            albedo: params.albedo(),
            g: params.g(),
            eta: params.eta(),
            theta: options.theta,
            photons: options.photons,
            seed: options.seed,
            bins: options.bins.clone(),
            geometry: walk::Geometry::HalfSpace,
        };
        let result = walk::run(&config)?;
        Self::from_walk(&result, options.component, params.moments())
    }

    /// Wraps a finished half-space walk (any g), converting to reduced units.
    pub fn from_walk(result: &WalkResult, component: Component, moments: Moments) -> Result<Self> {
        let config = result.config();
        let (a, g) = (config.albedo, config.g);
        let k = 1.0 - g * a;
        let rho_prime = if k > 0.0 {
            (a * (1.0 - g) / k).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let params = Params::new(rho_prime, config.eta, moments)?.with_g(g)?;
        let bins = result.bins();
        let layout = bins.layout();
        let (n_r, n_phi) = (layout.radial_count(), layout.phi_count());
        let r_edges: Vec<f64> = bins.r_edges().iter().map(|&r| k * r).collect();
        let mut value = vec![0.0; n_r * n_phi];
        let mut stderr = vec![0.0; n_r * n_phi];
        let per_area = 1.0 / (k * k);
        for i in 0..n_r {
            for j in 0..n_phi {
                let m = n_phi - 1 - j;
                let v = |jj| bins.value(component, i, jj).unwrap_or(0.0);
                let s = |jj| bins.stderr(component, i, jj).unwrap_or(f64::NAN);
                value[i * n_phi + j] = 0.5 * (v(j) + v(m)) * per_area;
                stderr[i * n_phi + j] = 0.5 * (s(j) + s(m)) * per_area;
            }
        }
        let mut cumulative = Vec::with_capacity(n_r * n_phi);
        let mut sum = 0.0;
        let dphi = TAU / n_phi as f64;
        for i in 0..n_r {
            let area = 0.5 * (r_edges[i + 1].powi(2) - r_edges[i].powi(2)) * dphi;
            for j in 0..n_phi {
                sum += value[i * n_phi + j].max(0.0) * area;
                cumulative.push(sum);
            }
        }
        Ok(Self {
            params,
            theta: config.theta,
            component,
            r_edges,
            phi_count: n_phi,
            value,
            stderr,
            cumulative,
            reflectance: result.reflectance(component),
        })
    }

    /// The incidence the walk ran at (radians).
    pub fn theta(&self) -> f64 {
        self.theta
    }
    /// The parameters (ρ′ recovered from the walk's albedo and g).
    pub fn params(&self) -> &Params {
        &self.params
    }
    /// Radial edges in reduced mfp, starting at 0.
    pub fn r_edges(&self) -> &[f64] {
        &self.r_edges
    }
    /// Number of azimuthal bins (uniform over [−π, π), φ = 0 forward).
    pub fn phi_count(&self) -> usize {
        self.phi_count
    }
    /// Mirror-averaged value of bin (i, j), per reduced mfp².
    pub fn bin_value(&self, i: usize, j: usize) -> Option<f64> {
        (j < self.phi_count)
            .then(|| self.value.get(i * self.phi_count + j).copied())
            .flatten()
    }
    /// Its (conservative) standard error.
    pub fn bin_stderr(&self, i: usize, j: usize) -> Option<f64> {
        (j < self.phi_count)
            .then(|| self.stderr.get(i * self.phi_count + j).copied())
            .flatten()
    }
    /// The walk's reflectance of the component, with its standard error.
    pub fn reflectance(&self) -> Estimate {
        self.reflectance
    }

    /// (i, j) of the bin holding (r, |φ|), `None` outside the bins.
    pub fn bin_of(&self, r: f64, phi: f64) -> Option<(usize, usize)> {
        let n_r = self.r_edges.len() - 1;
        if r.is_nan() || r < 0.0 || r >= self.r_edges[n_r] || !phi.is_finite() {
            return None;
        }
        let i = self.r_edges.partition_point(|&e| e <= r).saturating_sub(1);
        let folded = (phi + PI).rem_euclid(TAU) - PI;
        let j = ((folded.abs() + PI) / TAU * self.phi_count as f64) as usize;
        Some((i.min(n_r - 1), j.min(self.phi_count - 1)))
    }

    fn binned_total(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }
}

impl Model for McModel {
    fn kind(&self) -> ModelKind {
        ModelKind::MonteCarlo
    }

    fn component(&self) -> Component {
        self.component
    }

    fn eval(&self, theta: f64, r: f64, phi: f64) -> f64 {
        if (theta - self.theta).abs() > 1e-9 {
            return 0.0;
        }
        self.bin_of(r, phi)
            .and_then(|(i, j)| self.bin_value(i, j))
            .map_or(0.0, |v| v.max(0.0))
    }

    fn effective_albedo(&self, theta: f64) -> Option<f64> {
        ((theta - self.theta).abs() <= 1e-9).then_some(self.reflectance.value)
    }

    fn sample(&self, theta: f64, u: [f64; 2]) -> Option<Sample> {
        let total = self.binned_total();
        if (theta - self.theta).abs() > 1e-9 || total <= 0.0 || !(0.0..1.0).contains(&u[0]) {
            return None;
        }
        let target = u[0] * total;
        let bin = self
            .cumulative
            .partition_point(|&c| c <= target)
            .min(self.cumulative.len() - 1);
        let low = if bin == 0 {
            0.0
        } else {
            self.cumulative[bin - 1]
        };
        let width = self.cumulative[bin] - low;
        if width <= 0.0 {
            return None;
        }
        let v = ((target - low) / width).clamp(0.0, 1.0);
        let (i, j) = (bin / self.phi_count, bin % self.phi_count);
        let (r0, r1) = (self.r_edges[i], self.r_edges[i + 1]);
        let r = (r0 * r0 + v * (r1 * r1 - r0 * r0)).sqrt().clamp(r0, r1);
        let dphi = TAU / self.phi_count as f64;
        let (lo, hi) = (-PI + dphi * j as f64, -PI + dphi * (j + 1) as f64);
        let phi = (lo + dphi * crate::gwc::unit_interval(u[1])).clamp(-PI, PI);
        // A draw on an edge of its bin (v = 1, u = 0, rounding) is read by `bin_of` (which folds
        // φ onto [0, π]) in the next bin, whose density is another, or past the last radius in
        // none: such a coordinate (probability 0) moves to the middle of its bin
        let folded_j = j.max(self.phi_count - 1 - j);
        let r = match self.bin_of(r, phi) {
            Some((bi, _)) if bi == i => r,
            _ => 0.5 * (r0 + r1),
        };
        let phi = match self.bin_of(r, phi) {
            Some((_, bj)) if bj == folded_j => phi,
            _ => 0.5 * (lo + hi),
        };
        let pdf = self.pdf(theta, r, phi);
        (pdf > 0.0 && pdf.is_finite()).then_some(Sample { r, phi, pdf })
    }

    fn pdf(&self, theta: f64, r: f64, phi: f64) -> f64 {
        let total = self.binned_total();
        if total <= 0.0 {
            return 0.0;
        }
        self.eval(theta, r, phi) / total
    }
}
