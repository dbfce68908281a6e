//! The angular table (`table`) and the perpendicular table (`perpendicular`) as models of the
//! zoo: lookups in a baked [`AngularTable`] (Ferrier 2016, §3–4 and §7.1; see [`crate::table`]).
//!
//! | parameter | unit | valid range |
//! |---|---|---|
//! | table | – | baked for the model's η (checked); shared as an `Arc` or baked at construction |
//! | ρ′ reduced albedo | – | within the table's albedo axis |
//! | θ incidence before refraction | rad | [0, π/2]; 0 beyond the critical angle |
//! | r, φ | reduced mfp, rad (0 forward) | 0 beyond the last radius node (≈ 202.85 mfp) |
//! | result | per reduced mfp², per unit power entering | ≥ 0 (the lookup clamps) |
//!
//! - `table`: S_table(r, φ; ρ′, θ), interpolated from PBD samples with a GWC profile in φ; it
//!   approximates PBD multiple scattering (no conversion, same quantity). Sampler: the table's
//!   own (algorithm 2), whose `pdf` is the exact density of `sample`.
//! - `perpendicular`: the θ = 0 slice used at every θ, uniform in φ — what a renderer with a
//!   perpendicular-incidence table (pbrt) assumes. Sampler: r from the θ = 0 radial CDF, φ
//!   uniform.
//!
//! Where they break down: everything PBD does (multiple scattering only), plus interpolation
//! error (docs/accuracy.md: the angular table against PBD); the perpendicular model ignores the
//! forward/backward asymmetry of oblique incidence entirely. At r = 0 the table returns its
//! finite continuous limit from the first radius interval (PBD is +∞ there).

use super::{entering, Model, ModelKind, Params, Sample};
use crate::bake::{BakeGrid, Baker};
use crate::error::{Error, Result};
use crate::format::WalkComponent;
use crate::table::{bake, AngularTable, GridPreset};
use crate::walk::Component;
use std::sync::Arc;

/// Where a table model gets its table.
#[derive(Debug, Clone)]
pub enum TableSource {
    /// Bake one at construction (with the model's η and moments) on a preset, the table
    /// `bssrdf bake --eta ETA --grid PRESET` makes (its grid and lobes at η,
    /// `Baker::grid_at`), or on a custom grid as given.
    Bake(BakeGrid),
    /// Use a table baked elsewhere (its η must be the model's).
    Shared(Arc<AngularTable>),
}

impl Default for TableSource {
    /// Bake the default preset's table for the model's η (`bssrdf bake --eta ETA`).
    fn default() -> Self {
        TableSource::Bake(BakeGrid::Preset(GridPreset::Default))
    }
}

impl TableSource {
    /// The table for parameters: baked, or the shared one after checking its η.
    pub fn table(&self, params: &Params) -> Result<Arc<AngularTable>> {
        match self {
            TableSource::Bake(grid) => {
                let grid = Baker::new(grid.clone()).grid_at(params.eta());
                let (table, _) = bake(params.eta(), params.moments(), &grid, false)?;
                Ok(Arc::new(table))
            }
            TableSource::Shared(table) => {
                if table.eta() != params.eta() {
                    return Err(Error::Mismatch {
                        name: "table eta",
                        found: table.eta().to_string(),
                        expected: params.eta().to_string(),
                    });
                }
                Ok(Arc::clone(table))
            }
        }
    }
}

/// Which lookup a table model uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// The full angular table.
    Angular,
    /// The θ = 0 slice at every θ, uniform in φ.
    Perpendicular,
    /// The full angular table of a walk-angular table (`bake --source walk`).
    Walk,
}

/// A table model for one reduced albedo.
#[derive(Debug, Clone)]
pub struct TableModel {
    table: Arc<AngularTable>,
    rho: f64,
    eta: f64,
    mode: Mode,
}

impl TableModel {
    /// A table model for validated parameters; ρ′ must lie within the table's albedo axis.
    pub fn new(params: &Params, source: &TableSource, mode: Mode) -> Result<Self> {
        let table = source.table(params)?;
        let rho = params.rho_prime();
        let axis = table.axes().rho().as_slice();
        let (lo, hi) = (axis[0], axis[axis.len() - 1]);
        if table.view().effective_albedo(rho, 0.0).is_none() {
            return Err(Error::OutOfRange {
                name: "rho' (the table's albedo axis)",
                value: rho,
                min: lo,
                max: hi,
            });
        }
        Ok(Self {
            table,
            rho,
            eta: params.eta(),
            mode,
        })
    }

    /// The walk-table model: `table`, a walk-angular table for the parameters' η and g (a walk
    /// table holds one g: [`AngularTable::is_walk_at`]), at their ρ′.
    pub fn walk(params: &Params, table: Option<&Arc<AngularTable>>) -> Result<Self> {
        let Some(table) = table else {
            return Err(Error::Mismatch {
                name: "walk-table model",
                found: "no walk table".to_string(),
                expected: "a table baked by `bssrdf bake --source walk` (zoo: --walk-table FILE)"
                    .to_string(),
            });
        };
        let Some(walk) = table.walk() else {
            return Err(Error::Mismatch {
                name: "walk-table model's table",
                found: "a PBD table".to_string(),
                expected: "a walk-angular table (`bssrdf bake --source walk`)".to_string(),
            });
        };
        if !table.is_walk_at(table.eta(), params.g()) {
            return Err(Error::Mismatch {
                name: "walk table g",
                found: walk.g.to_string(),
                expected: params.g().to_string(),
            });
        }
        let source = TableSource::Shared(Arc::clone(table));
        Self::new(params, &source, Mode::Walk)
    }

    /// The table.
    pub fn table(&self) -> &Arc<AngularTable> {
        &self.table
    }
}

impl Model for TableModel {
    fn kind(&self) -> ModelKind {
        match self.mode {
            Mode::Angular => ModelKind::Table,
            Mode::Perpendicular => ModelKind::Perpendicular,
            Mode::Walk => ModelKind::WalkTable,
        }
    }

    fn component(&self) -> Component {
        match self.table.walk().map(|w| w.component) {
            Some(WalkComponent::Total) => Component::Total,
            _ => Component::Multiple,
        }
    }

    fn eval(&self, theta: f64, r: f64, phi: f64) -> f64 {
        if entering(theta, self.eta).is_none() {
            return 0.0;
        }
        let view = self.table.view();
        let value = match self.mode {
            Mode::Angular | Mode::Walk => view.eval(self.rho, theta, r, phi),
            Mode::Perpendicular => view.eval_perpendicular(self.rho, r),
        };
        value.filter(|v| v.is_finite()).unwrap_or(0.0)
    }

    fn effective_albedo(&self, theta: f64) -> Option<f64> {
        if entering(theta, self.eta).is_none() {
            return Some(0.0);
        }
        let theta = match self.mode {
            Mode::Angular | Mode::Walk => theta,
            Mode::Perpendicular => 0.0,
        };
        self.table.view().effective_albedo(self.rho, theta)
    }

    fn sample(&self, theta: f64, u: [f64; 2]) -> Option<Sample> {
        entering(theta, self.eta)?;
        let view = self.table.view();
        let s = match self.mode {
            Mode::Angular | Mode::Walk => view.sample(self.rho, theta, u[0], u[1])?,
            Mode::Perpendicular => view.sample_perpendicular(self.rho, u[0], u[1])?,
        };
        Some(Sample {
            r: s.r,
            phi: s.phi,
            pdf: s.pdf,
        })
    }

    fn pdf(&self, theta: f64, r: f64, phi: f64) -> f64 {
        if entering(theta, self.eta).is_none() {
            return 0.0;
        }
        let view = self.table.view();
        match self.mode {
            Mode::Angular | Mode::Walk => view.pdf(self.rho, theta, r, phi),
            // The θ = 0 slice is isotropic (c = 0): its φ density is 1/(2π) for every φ.
            Mode::Perpendicular => view.pdf(self.rho, 0.0, r, 0.0),
        }
    }
}
