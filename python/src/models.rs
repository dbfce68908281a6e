//! `models.eval`: every model of the zoo's registry (`bssrdf_zoo::models::ModelKind`) at
//! broadcast points, built by the registry's `build` and evaluated as `bssrdf eval --model`
//! evaluates it.

use std::sync::Arc;

use bssrdf_zoo::bake::BakeGrid;
use bssrdf_zoo::fresnel::{refracted_cos, Moments};
use bssrdf_zoo::models::dirpole::DirpoleFresnel;
use bssrdf_zoo::models::table::TableSource;
use bssrdf_zoo::models::{self, Model, ModelKind, Options, Params};
use bssrdf_zoo::table::{FileTable, Grid, GridPreset};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::bake::parse_moments;
use crate::errors;
use crate::points::{self, Arg};
use crate::table::Table;

/// The registry's model names, in display order.
#[pyfunction]
pub fn model_names() -> Vec<&'static str> {
    ModelKind::ALL.iter().map(|k| k.name()).collect()
}

/// A model built for one point's parameters, kept while the next points share them, in world
/// units for σ′t (reduced units are σ′t = 1, where `models::World` changes no bit).
struct Built {
    key: [u64; 3],
    model: models::World<Box<dyn Model>>,
}

/// R(r, φ; θ) of model `name` at every point of the broadcast of ρ′, θ, r, φ: per reduced mfp²
/// at r in reduced mfp, or with `sigma_t` (σ′t, mm⁻¹) per mm² at r in mm.
///
/// `eta` defaults to the table's η for the table models given `table`, else 1.33; `moments` is
/// "exact" (default; the table's with `table`), "pbrt", or for `dirpole` "authors". The table
/// models (`table`, `perpendicular`) look up `table` or a table baked once at η on `grid`
/// (counts (nρ, nθ, nr); default: the default grid); `walk-table` looks up `table`, which must
/// be a walk-angular table (`bssrdf bake --source walk`); `g` defaults to its g (else 0). `mc` runs a walk of `photons` photons from
/// `seed` for each (ρ′, θ), as `bssrdf eval --model mc` does. A model is built once for each
/// run of points sharing its parameters. Where no light enters (η < 1 beyond the critical
/// angle) every model gives 0.
#[pyfunction]
#[pyo3(signature = (name, rho, theta, r, phi, *, eta = None, g = None, sigma_t = None, moments = None, table = None, grid = None, photons = 100_000, seed = 1))]
#[allow(clippy::too_many_arguments)]
pub fn model_eval<'py>(
    py: Python<'py>,
    name: &str,
    rho: Arg<'py>,
    theta: Arg<'py>,
    r: Arg<'py>,
    phi: Arg<'py>,
    eta: Option<f64>,
    g: Option<f64>,
    sigma_t: Option<Arg<'py>>,
    moments: Option<&str>,
    table: Option<PyRef<'py, Table>>,
    grid: Option<(usize, usize, usize)>,
    #[pyo3(from_py_with = crate::args::photons)] photons: u64,
    #[pyo3(from_py_with = crate::args::seed)] seed: u64,
) -> PyResult<Bound<'py, PyAny>> {
    let kind: ModelKind = name.parse().map_err(errors::value)?;
    let uses_table = matches!(
        kind,
        ModelKind::Table | ModelKind::Perpendicular | ModelKind::WalkTable
    );
    let mut options = Options::default();
    options.mc.photons = photons;
    options.mc.seed = seed;
    let file_table = match (&table, uses_table) {
        (Some(t), true) => Some(t.owned_table()?),
        _ => None,
    };
    // A walk table is the walk-table model's, a PBD table the table models' (as `bssrdf eval`)
    if let Some(t) = &file_table {
        match (kind, t.walk()) {
            (ModelKind::Table | ModelKind::Perpendicular, Some(_)) => {
                return Err(errors::value(
                    "table= is a walk-angular table (`bssrdf bake --source walk`): the walk-table model evaluates it",
                ))
            }
            (ModelKind::WalkTable, None) => {
                return Err(errors::value(
                    "the walk-table model's table is a PBD table, not a walk-angular one",
                ))
            }
            _ => {}
        }
    }
    // The walk table's g unless given
    let g = match (&file_table, g) {
        (Some(t), None) if kind == ModelKind::WalkTable => t.walk().map_or(0.0, |w| w.g),
        (_, g) => g.unwrap_or(0.0),
    };
    let eta = match (&file_table, eta) {
        (Some(t), None) => t.eta(),
        (_, eta) => eta.unwrap_or(1.33),
    };
    let moments = match (moments, &file_table) {
        (Some("authors"), _) if kind == ModelKind::Dirpole => {
            options.dirpole.fresnel = DirpoleFresnel::AuthorsFits;
            Moments::Exact
        }
        (Some(m), _) => parse_moments(m)?,
        (None, Some(t)) => t.moments(),
        (None, None) => Moments::Exact,
    };
    if kind == ModelKind::WalkTable {
        // The walk table is the one given: baked beforehand for one (η, g), never here
        let table = file_table.ok_or_else(|| {
            errors::value(
                "the walk-table model needs table=, a walk-angular table (`bssrdf bake --source walk`)",
            )
        })?;
        options.walk_table = Some(Arc::new(table));
    } else if uses_table {
        let shared = match file_table {
            Some(t) => Arc::new(t),
            None => {
                let grid = grid.map_or(BakeGrid::Preset(GridPreset::Default), |(a, b, c)| {
                    BakeGrid::Custom(Grid::ferrier(a, b, c))
                });
                let source = TableSource::Bake(grid);
                let params = Params::new(0.5, eta, moments).map_err(errors::value)?;
                py.detach(|| source.table(&params)).map_err(errors::value)?
            }
        };
        options.table = TableSource::Shared(shared);
    }
    // Validated once here, so that a bad η or g is named before any point.
    Params::new(0.5, eta, moments)
        .and_then(|p| p.with_g(g))
        .map_err(errors::value)?;
    let mc = kind == ModelKind::MonteCarlo;
    let mut built: Option<Built> = None;
    let mut value =
        move |rho: f64, theta: f64, r: f64, phi: f64, sigma_t: f64| -> Result<f64, String> {
            bssrdf_zoo::error::in_range("theta", theta, 0.0, std::f64::consts::FRAC_PI_2)
                .and_then(|_| bssrdf_zoo::error::non_negative("r", r))
                .and_then(|_| bssrdf_zoo::error::finite("r", r))
                .and_then(|_| bssrdf_zoo::error::finite("phi", phi))
                .map_err(|e| e.to_string())?;
            // Where no light enters (η < 1 beyond the critical angle) every model gives 0.
            if refracted_cos(theta, eta).is_none() {
                return Ok(0.0);
            }
            let key = [
                rho.to_bits(),
                if mc { theta.to_bits() } else { 0 },
                sigma_t.to_bits(),
            ];
            if built.as_ref().is_none_or(|b| b.key != key) {
                let params = Params::new(rho, eta, moments)
                    .and_then(|p| p.with_g(g))
                    .map_err(|e| e.to_string())?;
                let mut options = options.clone();
                options.mc.theta = theta;
                let model = models::build(kind, &params, &options)
                    .and_then(|m| models::World::new(m, sigma_t))
                    .map_err(|e| e.to_string())?;
                built = Some(Built { key, model });
            }
            let model = &built.as_ref().ok_or("no model")?.model;
            Ok(model.eval(theta, r, phi))
        };
    let [v] = match &sigma_t {
        None => points::map(
            py,
            ["rho", "theta", "r", "phi"],
            [&rho, &theta, &r, &phi],
            |[rho, t, r, p]| Ok([value(rho, t, r, p, 1.0)?]),
        )?,
        Some(st) => points::map(
            py,
            ["rho", "theta", "r", "phi", "sigma_t"],
            [&rho, &theta, &r, &phi, st],
            |[rho, t, r, p, st]| Ok([value(rho, t, r, p, st)?]),
        )?,
    };
    Ok(v)
}

impl Table {
    /// An owned copy of the table's arrays, as the table models hold it.
    pub fn owned_table(&self) -> PyResult<bssrdf_zoo::table::AngularTable> {
        let record = self.record()?;
        FileTable::new(record)
            .and_then(|t| t.to_owned_table())
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }
}
