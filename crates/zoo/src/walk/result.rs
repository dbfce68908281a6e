//! What a run returns: reflectances and transmittances with standard errors, the binned exitance
//! R(r, φ; θ), a CSV writer for the bins and a serde summary.
//!
//! All quantities are per unit power *entering* the medium (the entry Fresnel transmittance is
//! not applied). Reflectances are dimensionless; binned exitance is per unit area, in inverse
//! squared mean free paths.

use super::tally::{mean_and_stderr, scalar, Sums, COMPONENTS};
use super::{Bins, Config, Geometry};
use serde::ser::{Serialize, Serializer};
use std::io::{self, Write};

/// A Monte Carlo estimate and its standard error (one standard deviation of the mean).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Estimate {
    /// The estimate.
    pub value: f64,
    /// Its standard error, from per-photon second moments; NaN for a single photon.
    pub stderr: f64,
}

/// Which exits a quantity counts, by the number of scattering vertices before the exit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Component {
    /// No scattering vertex: the collimated beam after internal reflections (slabs only).
    Unscattered,
    /// Exactly one scattering vertex.
    Single,
    /// Two or more scattering vertices.
    Multiple,
    /// All exits.
    Total,
}

impl Component {
    /// All components, in tally order.
    pub const ALL: [Component; 4] = [
        Component::Unscattered,
        Component::Single,
        Component::Multiple,
        Component::Total,
    ];

    fn index(self) -> usize {
        match self {
            Component::Unscattered => 0,
            Component::Single => 1,
            Component::Multiple => 2,
            Component::Total => 3,
        }
    }
}

/// Exitance of the lit surface in (r, φ) bins, per unit area per unit power entering.
#[derive(Debug, Clone)]
pub struct BinnedExitance {
    bins: Bins,
    /// Component-major: index c · bins + (i · phi_count + j).
    value: Vec<f64>,
    stderr: Vec<f64>,
}

impl BinnedExitance {
    /// The bin layout.
    pub fn layout(&self) -> &Bins {
        &self.bins
    }

    /// Radial edges (mean free paths), see [`Bins::r_edges`].
    pub fn r_edges(&self) -> &[f64] {
        self.bins.r_edges()
    }

    /// Azimuthal edges (radians, φ = 0 forward), see [`Bins::phi_edges`].
    pub fn phi_edges(&self) -> &[f64] {
        self.bins.phi_edges()
    }

    fn flat(&self, c: Component, i: usize, j: usize) -> Option<usize> {
        if i >= self.bins.radial_count() || j >= self.bins.phi_count() {
            return None;
        }
        Some(c.index() * self.bins.len() + i * self.bins.phi_count() + j)
    }

    /// Mean exitance in bin (i, j) (mean free paths⁻²); `None` outside the layout.
    pub fn value(&self, c: Component, i: usize, j: usize) -> Option<f64> {
        self.flat(c, i, j).map(|k| self.value[k])
    }

    /// Standard error of [`Self::value`].
    pub fn stderr(&self, c: Component, i: usize, j: usize) -> Option<f64> {
        self.flat(c, i, j).map(|k| self.stderr[k])
    }

    /// Area of bin (i, j) (squared mean free paths).
    pub fn area(&self, i: usize, j: usize) -> Option<f64> {
        self.bins.area(i, j)
    }
}

/// The result of [`super::run`].
#[derive(Debug, Clone)]
pub struct WalkResult {
    config: Config,
    scattering_events: u64,
    reflectance: [Estimate; COMPONENTS],
    binned_reflectance: Estimate,
    transmittance: Option<[Estimate; COMPONENTS]>,
    truncated_weight: Estimate,
    exitance: BinnedExitance,
}

impl WalkResult {
    pub(crate) fn new(config: &Config, sums: &Sums) -> Self {
        let n = sums.photons;
        let est = |k: usize| {
            let (value, stderr) =
                mean_and_stderr(sums.scalar_sum[k], sums.scalar_sq[k], n, sums.scale);
            Estimate { value, stderr }
        };
        let reflectance = scalar::R.map(est);
        let transmittance = match config.geometry {
            Geometry::HalfSpace => None,
            Geometry::Slab { .. } => Some(scalar::T.map(est)),
        };
        let bins = config.bins.clone();
        let nb = bins.len();
        let mut value = vec![0.0; COMPONENTS * nb];
        let mut stderr = vec![0.0; COMPONENTS * nb];
        for c in 0..COMPONENTS {
            for i in 0..bins.radial_count() {
                for j in 0..bins.phi_count() {
                    let b = i * bins.phi_count() + j;
                    let k = c * nb + b;
                    let area = bins.area(i, j).unwrap_or(f64::NAN);
                    let (m, s) = mean_and_stderr(sums.bin_sum[k], sums.bin_sq[k], n, sums.scale);
                    value[k] = m / area;
                    stderr[k] = s / area;
                }
            }
        }
        Self {
            config: config.clone(),
            scattering_events: sums.events,
            reflectance,
            binned_reflectance: est(scalar::R_BINNED),
            transmittance,
            truncated_weight: est(scalar::TRUNCATED),
            exitance: BinnedExitance {
                bins,
                value,
                stderr,
            },
        }
    }

    /// The configuration that produced this result.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Number of photons traced.
    pub fn photons(&self) -> u64 {
        self.config.photons
    }

    /// Seed of the run.
    pub fn seed(&self) -> u64 {
        self.config.seed
    }

    /// Number of scattering vertices over all photons.
    pub fn scattering_events(&self) -> u64 {
        self.scattering_events
    }

    /// Reflectance (power leaving the lit surface anywhere, per unit power entering) of one
    /// component.
    pub fn reflectance(&self, c: Component) -> Estimate {
        self.reflectance[c.index()]
    }

    /// Total diffuse reflectance: every exit through the lit surface.
    pub fn total_reflectance(&self) -> Estimate {
        self.reflectance(Component::Total)
    }

    /// Single-scattering reflectance.
    pub fn single_reflectance(&self) -> Estimate {
        self.reflectance(Component::Single)
    }

    /// Multiple-scattering reflectance.
    pub fn multiple_reflectance(&self) -> Estimate {
        self.reflectance(Component::Multiple)
    }

    /// Reflectance through r < r_max, the part the bins hold (all components).
    pub fn binned_reflectance(&self) -> Estimate {
        self.binned_reflectance
    }

    /// Transmittance through the far side of a slab (`None` for the half-space).
    pub fn transmittance(&self, c: Component) -> Option<Estimate> {
        self.transmittance.map(|t| t[c.index()])
    }

    /// Total transmittance of a slab, unscattered part included.
    pub fn total_transmittance(&self) -> Option<Estimate> {
        self.transmittance(Component::Total)
    }

    /// Weight of photons stopped at [`super::MAX_VERTICES`] scattering vertices, per unit
    /// power entering: an upper bound on the energy the estimates miss for that reason.
    pub fn truncated_weight(&self) -> Estimate {
        self.truncated_weight
    }

    /// The binned exitance R(r, φ; θ).
    pub fn bins(&self) -> &BinnedExitance {
        &self.exitance
    }

    /// Writes the bins as CSV: a header, then one row per bin, radial bins outer, φ inner:
    /// `r_lo,r_hi,phi_lo_deg,phi_hi_deg,single,single_stderr,multiple,multiple_stderr,total,total_stderr`.
    /// r in mean free paths, φ in degrees (0 forward), exitance in mean free paths⁻² per unit
    /// power entering. `total` includes unscattered exits (slabs only).
    pub fn to_csv<W: Write>(&self, mut w: W) -> io::Result<()> {
        writeln!(
            w,
            "r_lo,r_hi,phi_lo_deg,phi_hi_deg,single,single_stderr,multiple,multiple_stderr,total,total_stderr"
        )?;
        let e = &self.exitance;
        let (re, pe) = (e.r_edges(), e.phi_edges());
        for i in 0..e.bins.radial_count() {
            for j in 0..e.bins.phi_count() {
                write!(
                    w,
                    "{},{},{},{}",
                    re[i],
                    re[i + 1],
                    pe[j].to_degrees(),
                    pe[j + 1].to_degrees()
                )?;
                for c in [Component::Single, Component::Multiple, Component::Total] {
                    let v = e.value(c, i, j).unwrap_or(f64::NAN);
                    let s = e.stderr(c, i, j).unwrap_or(f64::NAN);
                    write!(w, ",{v},{s}")?;
                }
                writeln!(w)?;
            }
        }
        w.flush()
    }
}

/// The JSON summary: reflectances and their errors, the run's parameters and counts.
#[derive(serde::Serialize)]
struct Summary<'a> {
    total_reflectance: f64,
    total_reflectance_stderr: f64,
    single_reflectance: f64,
    single_reflectance_stderr: f64,
    multiple_reflectance: f64,
    multiple_reflectance_stderr: f64,
    unscattered_reflectance: f64,
    unscattered_reflectance_stderr: f64,
    binned_reflectance: f64,
    binned_reflectance_stderr: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    total_transmittance: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    total_transmittance_stderr: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    unscattered_transmittance: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    unscattered_transmittance_stderr: Option<f64>,
    truncated_weight: f64,
    truncated_weight_stderr: f64,
    photons: u64,
    seed: u64,
    scattering_events: u64,
    albedo: f64,
    g: f64,
    eta: f64,
    theta_deg: f64,
    geometry: &'a Geometry,
    bins: &'a Bins,
}

impl Serialize for WalkResult {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let r = |c| self.reflectance(c);
        let t = self.total_transmittance();
        let c = &self.config;
        Summary {
            total_reflectance: r(Component::Total).value,
            total_reflectance_stderr: r(Component::Total).stderr,
            single_reflectance: r(Component::Single).value,
            single_reflectance_stderr: r(Component::Single).stderr,
            multiple_reflectance: r(Component::Multiple).value,
            multiple_reflectance_stderr: r(Component::Multiple).stderr,
            unscattered_reflectance: r(Component::Unscattered).value,
            unscattered_reflectance_stderr: r(Component::Unscattered).stderr,
            binned_reflectance: self.binned_reflectance.value,
            binned_reflectance_stderr: self.binned_reflectance.stderr,
            total_transmittance: t.map(|e| e.value),
            total_transmittance_stderr: t.map(|e| e.stderr),
            unscattered_transmittance: self.transmittance(Component::Unscattered).map(|e| e.value),
            unscattered_transmittance_stderr: self
                .transmittance(Component::Unscattered)
                .map(|e| e.stderr),
            truncated_weight: self.truncated_weight.value,
            truncated_weight_stderr: self.truncated_weight.stderr,
            photons: c.photons,
            seed: c.seed,
            scattering_events: self.scattering_events,
            albedo: c.albedo,
            g: c.g,
            eta: c.eta,
            theta_deg: c.theta.to_degrees(),
            geometry: &c.geometry,
            bins: &c.bins,
        }
        .serialize(serializer)
    }
}
