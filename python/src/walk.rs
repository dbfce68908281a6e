//! `walk`: the Monte Carlo random walk (`bssrdf_zoo::walk::run`) with the GIL released, its
//! binned exitance returned as arrays with their standard errors.

use bssrdf_zoo::walk::{Bins, Component, Config, Estimate, Geometry, WalkResult};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;

use crate::errors;

/// The result of a walk: per unit power entering, lengths in (unreduced) mean free paths.
/// Binned exitance per mfp² has shape (radial bins, φ bins), bin (i, j) covering
/// r ∈ [r_edges[i], r_edges[i+1]) and φ ∈ [phi_edges[j], phi_edges[j+1]) (radians, 0 forward).
/// Estimates are (value, standard error) pairs.
#[pyclass(frozen, get_all, module = "bssrdf_zoo")]
pub struct Walk {
    /// Radial bin edges, mean free paths (the first bin starts at 0).
    r_edges: Py<PyAny>,
    /// Azimuthal bin edges, radians in [−π, π].
    phi_edges: Py<PyAny>,
    /// Exitance of single scattering per bin, mfp⁻².
    single: Py<PyAny>,
    /// Its standard errors.
    single_stderr: Py<PyAny>,
    /// Exitance of multiple scattering per bin, mfp⁻².
    multiple: Py<PyAny>,
    /// Its standard errors.
    multiple_stderr: Py<PyAny>,
    /// Exitance of every exit per bin, mfp⁻².
    total: Py<PyAny>,
    /// Its standard errors.
    total_stderr: Py<PyAny>,
    /// Total reflectance (value, standard error), every exit whether binned or not.
    reflectance: (f64, f64),
    /// Reflectance of single scattering.
    single_reflectance: (f64, f64),
    /// Reflectance of multiple scattering.
    multiple_reflectance: (f64, f64),
    /// Total transmittance of a slab, or None for a half-space.
    transmittance: Option<(f64, f64)>,
    /// Weight left in photons stopped at the vertex cap.
    truncated_weight: (f64, f64),
    /// Photons traced.
    photons: u64,
    /// Scattering events in all.
    scattering_events: u64,
}

fn estimate(e: Estimate) -> (f64, f64) {
    (e.value, e.stderr)
}

impl Walk {
    fn new(py: Python<'_>, result: &WalkResult) -> PyResult<Self> {
        let bins = result.bins();
        let (n_r, n_phi) = (bins.layout().radial_count(), bins.layout().phi_count());
        let edges = |values: &[f64]| PyArray1::from_slice(py, values).into_any().unbind();
        let binned = |value: &dyn Fn(usize, usize) -> Option<f64>| -> PyResult<Py<PyAny>> {
            let values: Vec<f64> = (0..n_r)
                .flat_map(|i| (0..n_phi).map(move |j| (i, j)))
                .map(|(i, j)| value(i, j).unwrap_or(f64::NAN))
                .collect();
            Ok(PyArray1::from_vec(py, values)
                .reshape([n_r, n_phi])?
                .into_any()
                .unbind())
        };
        let component = |c: Component| -> PyResult<(Py<PyAny>, Py<PyAny>)> {
            Ok((
                binned(&|i, j| bins.value(c, i, j))?,
                binned(&|i, j| bins.stderr(c, i, j))?,
            ))
        };
        let (single, single_stderr) = component(Component::Single)?;
        let (multiple, multiple_stderr) = component(Component::Multiple)?;
        let (total, total_stderr) = component(Component::Total)?;
        Ok(Self {
            r_edges: edges(bins.r_edges()),
            phi_edges: edges(bins.phi_edges()),
            single,
            single_stderr,
            multiple,
            multiple_stderr,
            total,
            total_stderr,
            reflectance: estimate(result.total_reflectance()),
            single_reflectance: estimate(result.single_reflectance()),
            multiple_reflectance: estimate(result.multiple_reflectance()),
            transmittance: result.total_transmittance().map(estimate),
            truncated_weight: estimate(result.truncated_weight()),
            photons: result.photons(),
            scattering_events: result.scattering_events(),
        })
    }
}

#[pymethods]
impl Walk {
    fn __repr__(&self) -> String {
        format!(
            "<bssrdf_zoo.Walk: {} photons, reflectance {} ± {}>",
            self.photons, self.reflectance.0, self.reflectance.1
        )
    }
}

/// Runs the random walk: single-scattering albedo a = σs/σt (unreduced), g, η, incidence θ
/// (radians), photons, seed, bins (r_min, r_max, radial count, φ count) in mean free paths, a
/// slab's optical thickness, threads (all cores when None; the result does not depend on it).
#[pyfunction]
#[pyo3(signature = (albedo, *, g = 0.0, eta = 1.33, theta = 0.0, photons = 1_000_000, seed = 0, bins = None, slab = None, threads = None))]
#[allow(clippy::too_many_arguments)]
pub fn walk(
    py: Python<'_>,
    albedo: f64,
    g: f64,
    eta: f64,
    theta: f64,
    #[pyo3(from_py_with = crate::args::photons)] photons: u64,
    #[pyo3(from_py_with = crate::args::seed)] seed: u64,
    #[pyo3(from_py_with = crate::args::bins)] bins: Option<(f64, f64, usize, usize)>,
    slab: Option<f64>,
    #[pyo3(from_py_with = crate::args::threads)] threads: Option<usize>,
) -> PyResult<Walk> {
    let mut config = Config::new(albedo, g, eta, theta);
    config.photons = photons;
    config.seed = seed;
    if let Some((r_min, r_max, radial, phi)) = bins {
        config.bins = Bins::new(r_min, r_max, radial, phi).map_err(errors::value)?;
    }
    if let Some(thickness) = slab {
        config.geometry = Geometry::Slab { thickness };
    }
    let result = py
        .detach(|| crate::on_threads(threads, || bssrdf_zoo::walk::run(&config)))?
        .map_err(errors::value)?;
    Walk::new(py, &result)
}
