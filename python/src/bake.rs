//! `bake` and `bake_materials`: the library bake (`bssrdf_zoo::bake::Baker`, the pipeline of
//! `bssrdf bake`), in memory, optionally written to a file, with the GIL released.

use std::path::{Path, PathBuf};

use bssrdf_zoo::bake::{BakeGrid, Baker, MaterialSpec};
use bssrdf_zoo::format::Compression;
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::materials::{self, Material};
use bssrdf_zoo::table::{Grid, GridPreset, Lobes};
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::errors;
use crate::library::Library;

/// The settings every bake takes, as Python passes them.
struct Settings {
    grid: BakeGrid,
    lobes: Option<Lobes>,
    moments: Moments,
    theta_sampling: bool,
}

impl Settings {
    fn new(
        grid: &Bound<'_, PyAny>,
        lobes: Option<i64>,
        moments: &str,
        theta_sampling: bool,
    ) -> PyResult<Self> {
        let lobes = match lobes {
            None => None,
            Some(1) => Some(Lobes::One),
            Some(2) => Some(Lobes::Two),
            Some(n) => {
                return Err(PyValueError::new_err(format!(
                    "lobes = {n} is not one of None (by eta), 1, 2"
                )))
            }
        };
        Ok(Self {
            grid: parse_grid(grid)?,
            lobes,
            moments: parse_moments(moments)?,
            theta_sampling,
        })
    }

    fn baker(self) -> Baker {
        Baker::new(self.grid)
            .with_moments(self.moments)
            .with_lobes(self.lobes)
            .with_theta_sampling(self.theta_sampling)
    }
}

/// A grid: a preset's name ("coarse", "default", "fine"), node counts (nρ, nθ, nr) placed as
/// Ferrier places them, or a dict of node values {"rho": …, "theta": …, "r": …}.
pub fn parse_grid(grid: &Bound<'_, PyAny>) -> PyResult<BakeGrid> {
    if let Ok(name) = grid.extract::<String>() {
        let preset = match name.as_str() {
            "coarse" => GridPreset::Coarse,
            "default" => GridPreset::Default,
            "fine" => GridPreset::Fine,
            other => {
                return Err(PyValueError::new_err(format!(
                    "grid {other:?} is not one of \"coarse\", \"default\", \"fine\", (n_rho, n_theta, n_r) or a dict of nodes"
                )))
            }
        };
        return Ok(BakeGrid::Preset(preset));
    }
    if let Ok(nodes) = grid.cast::<PyDict>() {
        for key in nodes.keys() {
            let known = key
                .extract::<String>()
                .ok()
                .filter(|k| ["rho", "theta", "r"].contains(&k.as_str()));
            if known.is_none() {
                return Err(PyValueError::new_err(format!(
                    "the grid's dict has an unknown key {}; its keys are rho, theta, r",
                    key_text(&key)?
                )));
            }
        }
        let axis = |name: &str| -> PyResult<Vec<f64>> {
            nodes
                .get_item(name)?
                .ok_or_else(|| PyValueError::new_err(format!("the grid's dict has no {name:?}")))?
                .extract()
        };
        return Ok(BakeGrid::Custom(Grid {
            rho: axis("rho")?,
            theta: axis("theta")?,
            r: axis("r")?,
        }));
    }
    // Counts as Python objects, so that a huge or negative one is named with its range
    let (n_rho, n_theta, n_r): (Bound<'_, PyAny>, Bound<'_, PyAny>, Bound<'_, PyAny>) =
        grid.extract().map_err(|_| {
            PyValueError::new_err(
                "grid is a preset's name, (n_rho, n_theta, n_r) or {\"rho\": ..., \"theta\": ..., \"r\": ...}",
            )
        })?;
    // Each count checked before anything is allocated: the file's axes hold at most
    // MAX_AXIS_LEN nodes, and the placement needs 2 albedos, 2 angles and 4 radii
    let max = i64::from(bssrdf_zoo::format::spec::MAX_AXIS_LEN);
    let count = |name: &str, n: &Bound<'_, PyAny>, min: i64| -> PyResult<usize> {
        // (An int beyond i64 is outside too; what does not convert at all is not a whole number)
        let outside = || {
            Ok::<_, PyErr>(PyValueError::new_err(format!(
                "grid's {name} = {} is outside [{min}, {max}]",
                n.repr()?
            )))
        };
        match n.extract::<i64>() {
            Ok(v) if (min..=max).contains(&v) => Ok(v as usize),
            Ok(_) => Err(outside()?),
            Err(e) if e.is_instance_of::<pyo3::exceptions::PyOverflowError>(n.py()) => {
                Err(outside()?)
            }
            Err(_) => Err(PyValueError::new_err(format!(
                "grid's {name} = {} is not a whole number (an int in [{min}, {max}])",
                n.repr()?
            ))),
        }
    };
    let (n_rho, n_theta, n_r) = (
        count("n_rho", &n_rho, 2)?,
        count("n_theta", &n_theta, 2)?,
        count("n_r", &n_r, 4)?,
    );
    Ok(BakeGrid::Custom(Grid::ferrier(n_rho, n_theta, n_r)))
}

/// A dict key in a message: a str quoted as Rust quotes it, anything else by its repr.
fn key_text(key: &Bound<'_, PyAny>) -> PyResult<String> {
    match key.extract::<String>() {
        Ok(k) => Ok(format!("{k:?}")),
        Err(_) => Ok(key.repr()?.to_string()),
    }
}

/// Fresnel moments by name: "exact" or "pbrt" (pbrt-v3's polynomial fits).
pub fn parse_moments(name: &str) -> PyResult<Moments> {
    match name {
        "exact" => Ok(Moments::Exact),
        "pbrt" => Ok(Moments::Pbrt),
        other => Err(PyValueError::new_err(format!(
            "moments {other:?} is not one of \"exact\", \"pbrt\""
        ))),
    }
}

/// A material to bake: a built-in material's name, or a dict of coefficients (name, sigma_s,
/// sigma_a, g, eta in mm⁻¹ per R, G, B) or of an artist's parameters (name, reflectance, mfp,
/// g, eta), each with an optional source.
fn parse_material(item: &Bound<'_, PyAny>) -> PyResult<MaterialSpec> {
    if let Ok(name) = item.extract::<String>() {
        let builtin = materials::Library::builtin();
        let material = builtin.get(&name).map_err(errors::value)?;
        return MaterialSpec::named(material).map_err(errors::bake);
    }
    let dict = item.cast::<PyDict>().map_err(|_| {
        PyValueError::new_err(
            "a material is a built-in material's name or a dict (name, sigma_s, sigma_a, g, eta, or name, reflectance, mfp, g, eta)",
        )
    })?;
    // A misspelt key would leave a default in its place ("G" for "g": g = 0), and both kinds
    // of parameters at once one of them unused: both refused
    const KEYS: [&str; 8] = [
        "name",
        "eta",
        "g",
        "source",
        "sigma_s",
        "sigma_a",
        "reflectance",
        "mfp",
    ];
    for key in dict.keys() {
        // A key that is a str, not one that prints like one (it would never be read)
        let known = key
            .extract::<String>()
            .ok()
            .filter(|k| KEYS.contains(&k.as_str()));
        if known.is_none() {
            return Err(PyValueError::new_err(format!(
                "the material's dict has an unknown key {}; its keys are {}",
                key_text(&key)?,
                KEYS.join(", ")
            )));
        }
    }
    let artist = dict.contains("reflectance")? || dict.contains("mfp")?;
    if artist && (dict.contains("sigma_s")? || dict.contains("sigma_a")?) {
        return Err(PyValueError::new_err(
            "the material's dict gives both sigma_s/sigma_a and reflectance/mfp: give one pair",
        ));
    }
    let required = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        dict.get_item(key)?
            .ok_or_else(|| PyValueError::new_err(format!("the material's dict has no {key:?}")))
    };
    let name: String = required("name")?.extract()?;
    // A built-in material's name (any case, an alias) would be two materials of one name
    bssrdf_zoo::scene::check_new_id(&name, &materials::Library::builtin())
        .map_err(errors::value)?;
    let eta: f64 = required("eta")?.extract()?;
    let g: [f64; 3] = match dict.get_item("g")? {
        Some(g) => rgb(&g)?,
        None => [0.0; 3],
    };
    let source: String = match dict.get_item("source")? {
        Some(s) => s.extract()?,
        None => String::new(),
    };
    if dict.contains("reflectance")? {
        let reflectance = rgb(&required("reflectance")?)?;
        let mfp = rgb(&required("mfp")?)?;
        return MaterialSpec::diffuse(&name, reflectance, mfp, g, eta, source)
            .map_err(errors::bake);
    }
    let sigma_s = rgb(&required("sigma_s")?)?;
    let sigma_a = rgb(&required("sigma_a")?)?;
    let material =
        Material::from_coefficients(&name, sigma_s, sigma_a, g, eta).map_err(errors::value)?;
    Ok(MaterialSpec::new(material, source))
}

/// One value for all three channels, or three.
fn rgb(value: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    match value.extract::<f64>() {
        Ok(v) => Ok([v; 3]),
        Err(_) => value.extract(),
    }
}

/// Refuses, before any work, an output `path` the write would refuse (a folder, a path ending
/// in /, a new file in a folder that does not exist), as `bssrdf bake -o` does: an `OSError`
/// by its cause, naming `path`.
pub fn check_output(path: &Path) -> PyResult<()> {
    bssrdf_zoo::format::check_writable(path).map_err(errors::written)
}

/// Checks `path`, then runs the bake on `threads` threads (all cores when None) with the GIL
/// released, warns of its warnings and of a table above the check's bound or whose check saw
/// no region, writes `path` if given and returns the library in memory.
fn run(
    py: Python<'_>,
    baker: Baker,
    specs: &[MaterialSpec],
    etas: &[f64],
    threads: Option<usize>,
    path: Option<PathBuf>,
) -> PyResult<Library> {
    if let Some(path) = &path {
        check_output(path)?;
    }
    let baked = py
        .detach(|| crate::on_threads(threads, || baker.bake(specs, etas, None)))?
        .map_err(errors::bake)?;
    let warn = |message: String| {
        PyErr::warn(
            py,
            &py.get_type::<PyUserWarning>(),
            &std::ffi::CString::new(message).unwrap_or_default(),
            1,
        )
    };
    for message in baked.warnings() {
        warn(message.clone())?;
    }
    for table in baked.tables().iter().filter(|t| !t.check().passes()) {
        // A check that saw no region is no finding of 0 regions above the bound
        let finding = match table.check().nothing_checked() {
            Some(note) => format!(": {note}"),
            None => format!(
                " is above the bake check's bound in {} region(s)",
                table.check().failures().count()
            ),
        };
        warn(format!(
            "the table at eta = {}{finding}: see the library's provenance[\"accuracy\"]",
            table.eta(),
        ))?;
    }
    if let Some(path) = &path {
        py.detach(|| baked.builder().write_atomic(path, Compression::None))
            .map_err(errors::written)?;
    }
    let library = baked.into_library().map_err(errors::bake)?;
    Ok(Library::new(library, path))
}

/// Bakes one table per η (a float or a sequence of them), without materials.
#[pyfunction]
#[pyo3(signature = (eta = None, grid = None, *, lobes = None, moments = "exact", theta_sampling = true, threads = None, path = None))]
#[allow(clippy::too_many_arguments)]
pub fn bake(
    py: Python<'_>,
    eta: Option<&Bound<'_, PyAny>>,
    grid: Option<&Bound<'_, PyAny>>,
    #[pyo3(from_py_with = crate::args::lobes)] lobes: Option<i64>,
    moments: &str,
    theta_sampling: bool,
    #[pyo3(from_py_with = crate::args::threads)] threads: Option<usize>,
    path: Option<PathBuf>,
) -> PyResult<Library> {
    let etas: Vec<f64> = match eta {
        None => vec![1.33],
        Some(e) => match e.extract::<f64>() {
            Ok(v) => vec![v],
            Err(_) => e.extract()?,
        },
    };
    if etas.is_empty() {
        return Err(PyValueError::new_err(
            "eta is an empty sequence: give at least one eta to bake",
        ));
    }
    // (One table per η: a repeated one would be baked once, quietly)
    if let Some((k, &twice)) = etas
        .iter()
        .enumerate()
        .find(|&(k, e)| etas[..k].contains(e))
    {
        return Err(PyValueError::new_err(format!(
            "eta = {} is given twice (at positions {} and {k}): one table per eta",
            bssrdf_zoo::error::number(twice),
            etas.iter().position(|e| *e == twice).unwrap_or(0)
        )));
    }
    let default = PyString::new(py, "default");
    let settings = Settings::new(grid.unwrap_or(&default), lobes, moments, theta_sampling)?;
    run(py, settings.baker(), &[], &etas, threads, path)
}

/// Bakes a library of materials (names of built-in materials, or dicts): one table per
/// distinct η of the materials and of `etas`, one record per material.
#[pyfunction]
#[pyo3(signature = (materials, grid = None, *, etas = Vec::new(), lobes = None, moments = "exact", theta_sampling = true, threads = None, path = None))]
#[allow(clippy::too_many_arguments)]
pub fn bake_materials(
    py: Python<'_>,
    materials: Vec<Bound<'_, PyAny>>,
    grid: Option<&Bound<'_, PyAny>>,
    etas: Vec<f64>,
    #[pyo3(from_py_with = crate::args::lobes)] lobes: Option<i64>,
    moments: &str,
    theta_sampling: bool,
    #[pyo3(from_py_with = crate::args::threads)] threads: Option<usize>,
    path: Option<PathBuf>,
) -> PyResult<Library> {
    if materials.is_empty() && etas.is_empty() {
        return Err(PyValueError::new_err(
            "materials and etas are both empty: give at least one material or eta to bake",
        ));
    }
    let specs = materials
        .iter()
        .map(parse_material)
        .collect::<PyResult<Vec<_>>>()?;
    let default = PyString::new(py, "default");
    let settings = Settings::new(grid.unwrap_or(&default), lobes, moments, theta_sampling)?;
    run(py, settings.baker(), &specs, &etas, threads, path)
}

/// The ids of the built-in named materials.
#[pyfunction]
pub fn builtin_materials() -> Vec<String> {
    materials::Library::builtin()
        .iter()
        .map(|m| m.id().to_owned())
        .collect()
}
