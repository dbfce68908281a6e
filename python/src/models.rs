//! `models.eval`: every model of the zoo's registry (`bssrdf_zoo::models::ModelKind`) at
//! broadcast points, built by the registry's `build` and evaluated as `bssrdf eval --model`
//! evaluates it.

use std::sync::Arc;

use bssrdf_zoo::bake::BakeGrid;
use bssrdf_zoo::fresnel::{refracted_cos, Moments};
use bssrdf_zoo::models::dirpole::DirpoleFresnel;
use bssrdf_zoo::models::table::TableSource;
use bssrdf_zoo::models::{self, Model, ModelKind, Options, Params};
use bssrdf_zoo::table::{FileTable, GridPreset};
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
/// (a preset's name, counts (nρ, nθ, nr) or a dict of nodes, as `bake` takes it; default: the
/// default grid); `walk-table` looks up `table`, which must be a walk-angular table
/// (`bssrdf bake --source walk`); `g` defaults to its g (else 0). `mc` runs a walk of `photons`
/// photons (default 100,000) from `seed` (default 1) for each (ρ′, θ), as
/// `bssrdf eval --model mc` does. An argument the model does not use is refused (`table` and
/// `grid` but for the table models, `grid` with `table`, `g` but for `mc` and `walk-table`,
/// `photons` and `seed` but for `mc`, `moments` for `mc` and `walk-table` or other than the
/// table's). A model is built once for each run of points sharing its parameters. Where no
/// light enters (η < 1 beyond the critical angle) every model gives 0, at points that are in
/// their domain.
#[pyfunction]
#[pyo3(signature = (name, rho, theta, r, phi, *, eta = None, g = None, sigma_t = None, moments = None, table = None, grid = None, photons = None, seed = None))]
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
    grid: Option<&Bound<'py, PyAny>>,
    photons: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let kind: ModelKind = name.parse().map_err(errors::value)?;
    let uses_table = matches!(
        kind,
        ModelKind::Table | ModelKind::Perpendicular | ModelKind::WalkTable
    );
    let mc = kind == ModelKind::MonteCarlo;
    // No argument accepted and ignored
    let unused = [
        (
            "table=",
            table.is_some() && !uses_table,
            "the table models' (table, perpendicular, walk-table)",
        ),
        (
            "grid=",
            grid.is_some() && !matches!(kind, ModelKind::Table | ModelKind::Perpendicular),
            "the bake's of the table and perpendicular models",
        ),
        (
            "grid=",
            grid.is_some() && table.is_some(),
            "the bake's, and table= is given",
        ),
        (
            "g=",
            g.is_some() && !matches!(kind, ModelKind::MonteCarlo | ModelKind::WalkTable),
            "the mc and walk-table models' (the walk's anisotropy)",
        ),
        ("photons=", photons.is_some() && !mc, "the mc model's"),
        ("seed=", seed.is_some() && !mc, "the mc model's"),
        (
            "moments=",
            moments.is_some() && matches!(kind, ModelKind::MonteCarlo | ModelKind::WalkTable),
            "the diffusion models' (the walk takes the exact Fresnel equations)",
        ),
    ];
    if let Some((arg, _, whose)) = unused.iter().find(|(_, refused, _)| *refused) {
        return Err(errors::value(format!(
            "{arg} is {whose}, not the {} model's: drop it",
            kind.name()
        )));
    }
    let mut options = Options::default();
    options.mc.photons = photons.map_or(Ok(100_000), crate::args::photons)?;
    options.mc.seed = seed.map_or(Ok(1), crate::args::seed)?;
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
        (Some(m), Some(t)) if parse_moments(m)? != t.moments() => {
            return Err(errors::value(format!(
                "moments={m:?} conflicts with table=, baked with {:?} moments",
                t.moments().name()
            )))
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
                let grid = match grid {
                    Some(grid) => crate::bake::parse_grid(grid)?,
                    None => BakeGrid::Preset(GridPreset::Default),
                };
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
    let mut built: Option<Built> = None;
    let mut value =
        move |rho: f64, theta: f64, r: f64, phi: f64, sigma_t: f64| -> Result<f64, String> {
            // (90° as a table's θ axis stores it, f32(π/2), is 90°: `Table.sample_path` draws it)
            let grazing = f64::from(std::f64::consts::FRAC_PI_2 as f32);
            bssrdf_zoo::error::in_range("theta", theta, 0.0, grazing)
                .and_then(|_| bssrdf_zoo::error::non_negative("r", r))
                .and_then(|_| bssrdf_zoo::error::finite("r", r))
                .and_then(|_| bssrdf_zoo::error::finite("phi", phi))
                .and_then(|_| bssrdf_zoo::error::in_range("rho", rho, 0.0, 1.0))
                .map_err(|e| e.to_string())?;
            if !(sigma_t > 0.0 && sigma_t.is_finite()) {
                return Err(format!(
                    "sigma_t = {} is outside (0, inf): a finite positive sigma_t' in mm^-1",
                    bssrdf_zoo::error::number(sigma_t)
                ));
            }
            let theta = theta.min(std::f64::consts::FRAC_PI_2);
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
        // A table no lookup can interpolate is a FormatError, as its own lookups raise
        self.lookups()?;
        let record = self.record()?;
        FileTable::new(record)
            .and_then(|t| t.to_owned_table())
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }
}
