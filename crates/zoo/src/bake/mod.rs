//! The bake of a library: one pipeline, from materials, bare η or a scene to the library file's
//! tables, material records and provenance, which `bssrdf bake` and
//! [`crate::embed::bake_library`] both run, so that a bake in memory and one on the command
//! line give the same file.
//!
//! A [`Baker`] holds the settings (grid, Fresnel moments, lobes, θ sampling, whether to record
//! the bake time); [`Baker::bake`] bakes one table per distinct η of some materials
//! ([`MaterialSpec`]) and bare η values, [`Baker::bake_scene`] only the albedo rows and tables a
//! scene needs. Each table is baked by [`table::bake_rows_lobes`] and then checked by
//! [`table::check`], the bake's own check; the result, a [`BakedLibrary`], holds the built
//! [`LibraryBuilder`] (tables, materials and provenance), every table with its check and its
//! [`BakeReport`], and the warnings. Whether a table above its bound may be written is the
//! caller's decision ([`BakedLibrary::passes`]): `bssrdf bake` refuses unless
//! `--accept-error`, [`crate::embed::bake_library`] keeps it (the check is in the provenance).
//!
//! # The provenance
//!
//! `tool_version` (`bssrdf-zoo` and the crate's version), `settings` (the grid's name, or
//! `"custom"` for a grid given node by node, its dims, the Fresnel moments, θ sampling, the
//! fit's anchors and refinement, the lobes; where a table of the file took them, the fit
//! azimuths of two lobes, the θ nodes near η = 1 and the rule of the node where the beam
//! runs in the surface; and for a scene its plan under `scene`), `quadrature` (PBD's fast rule,
//! and where a table of the file took it, the node rule of two-lobe and surface-beam nodes) and
//! `accuracy` (every table's [`TableCheck`], in file order). These depend on the inputs only:
//! the same bake writes the same bytes on any machine and thread count. The one field measured
//! at run time, `bake_seconds` (the wall-clock time of the tables' bakes, without their
//! checks), is written only when asked for ([`Baker::with_bake_time`]). The thread count is
//! never written (the tables are bit-identical on any count); it is in each table's
//! [`BakeReport`].
//!
//! # Threads
//!
//! Everything runs on the current rayon pool: wrap the call in `ThreadPool::install` to choose
//! the thread count.

mod materials;
mod scene;
mod walk;

pub use materials::MaterialSpec;
pub use walk::{bake_walk_library, WalkLibrary, WalkSettings};

use std::ops::Range;

use serde_json::{json, Value};

use crate::embed::{EmbedError, Library};
use crate::format::{self, Compression, FormatError, LibraryBuilder, Provenance, Verify};
use crate::fresnel::Moments;
use crate::materials::{Material, MaterialError};
use crate::scene::artist::{ArtistError, ReflectanceCurve};
use crate::scene::SceneError;
use crate::table::{self, AngularTable, BakeReport, CheckBounds, Grid, GridPreset, Lobes};
use crate::table::{SubsetError, TableCheck};

/// The grids of a bake: a preset's, whose radii depend on the table's lobes
/// ([`GridPreset::grid`]), or one grid for every table.
#[derive(Debug, Clone, PartialEq)]
pub enum BakeGrid {
    /// A named grid (the command line's `--grid`).
    Preset(GridPreset),
    /// One grid given node by node, for every table whatever its lobes.
    Custom(Grid),
}

impl From<GridPreset> for BakeGrid {
    fn from(preset: GridPreset) -> Self {
        BakeGrid::Preset(preset)
    }
}

impl From<Grid> for BakeGrid {
    fn from(grid: Grid) -> Self {
        BakeGrid::Custom(grid)
    }
}

impl From<&Grid> for BakeGrid {
    fn from(grid: &Grid) -> Self {
        BakeGrid::Custom(grid.clone())
    }
}

/// Where a bake is, given to its progress callback when a table starts and after each block
/// of albedo rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    /// The table being baked, from 0, in file order.
    pub table: usize,
    /// How many tables the bake makes.
    pub tables: usize,
    /// η of that table.
    pub eta: f64,
    /// Its albedo rows (of the grid's ρ′ axis).
    pub rows: Range<usize>,
    /// Albedo rows baked so far, over every table.
    pub rows_done: usize,
    /// Albedo rows of every table.
    pub rows_total: usize,
}

/// A progress callback: called on the thread that runs the bake.
pub type OnProgress<'a> = &'a (dyn Fn(&Progress) + Sync);

/// Why a bake failed. Each names what it was baking.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    /// A table could not be baked (its η or the grid is invalid).
    #[error("cannot bake the table for eta = {eta}: {source}")]
    Table {
        /// η of the table.
        eta: f64,
        /// Why.
        source: SubsetError,
    },
    /// The bake's check could not run on a table (it evaluates PBD at the table's η).
    #[error("cannot check the table for eta = {eta}: {source}")]
    Check {
        /// η of the table.
        eta: f64,
        /// Why.
        source: crate::Error,
    },
    /// A walk table could not be baked (`bssrdf bake --source walk`).
    #[error("cannot bake the walk table for eta = {eta}, g = {g}: {source}")]
    Walk {
        /// η of the table.
        eta: f64,
        /// g of the walk.
        g: f64,
        /// Why.
        source: crate::Error,
    },
    /// The grid's albedo axis cannot be planned on (a scene bake).
    #[error("the grid's albedo axis: {0}")]
    Axis(crate::Error),
    /// A scene's plan failed, a material's `source` is one a file cannot keep, or a material
    /// is given twice.
    #[error(transparent)]
    Scene(Box<SceneError>),
    /// A material given by the artist's parameters cannot be inverted through its table.
    #[error("material {name:?} from reflectance and mfp: {source}")]
    Artist {
        /// The material's id.
        name: String,
        /// Why.
        source: ArtistError,
    },
    /// The coefficients of a material given by the artist's parameters are invalid.
    #[error("material {name:?} from reflectance and mfp: {source}")]
    Material {
        /// The material's id.
        name: String,
        /// Why.
        source: Box<MaterialError>,
    },
    /// The file's records refused a table, a material or the provenance.
    #[error(transparent)]
    Format(#[from] FormatError),
    /// The baked library could not be opened for lookups (in memory).
    #[error(transparent)]
    Embed(#[from] EmbedError),
}

impl From<SceneError> for BakeError {
    fn from(e: SceneError) -> Self {
        BakeError::Scene(Box::new(e))
    }
}

/// The settings of a bake (module docs). Defaults: exact Fresnel moments, the lobes of
/// [`Lobes::for_eta`], θ sampling kept, no bake time.
///
/// ```
/// use bssrdf_zoo::bake::{Baker, MaterialSpec};
/// use bssrdf_zoo::format::Compression;
/// use bssrdf_zoo::table::{Grid, GridPreset};
/// let materials = bssrdf_zoo::materials::Library::builtin();
/// let skin = MaterialSpec::named(materials.get("skin1")?)?;
/// # let baker = Baker::new(Grid::ferrier(6, 4, 10));
/// # /*
/// let baker = Baker::new(GridPreset::Default);
/// # */
/// // Only tables at η = 1.4 (skin1's) and 1.2: two tables, one material.
/// let baked = baker.bake(&[skin], &[1.2], None)?;
/// assert_eq!(baked.tables().len(), 2);
/// assert_eq!(baked.materials()[0].record().tables, [1; 3]);
/// for t in baked.tables() {
///     println!("eta {}: check {}", t.eta(), if t.check().passes() { "passed" } else { "failed" });
/// }
/// assert!(baked.provenance().get("accuracy").is_some());
/// let bytes = baked.to_bytes(Compression::None)?; // or baked.builder().write_atomic(…)
/// # let _ = bytes;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Baker {
    grid: BakeGrid,
    moments: Moments,
    /// `None` chooses by η ([`Lobes::for_eta`]).
    lobes: Option<Lobes>,
    theta_sampling: bool,
    bake_time: bool,
}

impl Baker {
    /// A bake on `grid` (a [`GridPreset`], a [`Grid`] or a [`BakeGrid`]) with the defaults.
    pub fn new(grid: impl Into<BakeGrid>) -> Self {
        Self {
            grid: grid.into(),
            moments: Moments::Exact,
            lobes: None,
            theta_sampling: true,
            bake_time: false,
        }
    }

    /// With these Fresnel moments of the boundary.
    pub fn with_moments(self, moments: Moments) -> Self {
        Self { moments, ..self }
    }

    /// With these lobes for every table, or (`None`) those of [`Lobes::for_eta`].
    pub fn with_lobes(self, lobes: Option<Lobes>) -> Self {
        Self { lobes, ..self }
    }

    /// Whether the tables keep their θ-sampling section (only path tracers need it). A scene
    /// bake takes its integrator's choice instead.
    pub fn with_theta_sampling(self, theta_sampling: bool) -> Self {
        Self {
            theta_sampling,
            ..self
        }
    }

    /// Whether the provenance records the bake's wall-clock time (the file then differs from
    /// run to run).
    pub fn with_bake_time(self, bake_time: bool) -> Self {
        Self { bake_time, ..self }
    }

    /// The grids of this bake.
    pub fn grid(&self) -> &BakeGrid {
        &self.grid
    }

    /// The Fresnel moments.
    pub fn moments(&self) -> Moments {
        self.moments
    }

    /// The grid whose albedo rows every table's rows index (a table's grid differs from it in
    /// its radii and, below η = 1, its angles only): a preset's one-lobe grid, or the custom
    /// grid.
    pub fn albedo_grid(&self) -> Grid {
        match &self.grid {
            BakeGrid::Preset(preset) => Grid::preset(*preset),
            BakeGrid::Custom(grid) => grid.clone(),
        }
    }

    /// The lobes of the table this bake makes at η.
    pub fn lobes_at(&self, eta: f64) -> Lobes {
        self.lobes.unwrap_or_else(|| Lobes::for_eta(eta))
    }

    /// The grid of the table this bake makes at η: the preset's for its lobes, or the custom one.
    pub fn grid_at(&self, eta: f64) -> Grid {
        match &self.grid {
            BakeGrid::Preset(preset) => preset.grid(eta, self.lobes_at(eta)),
            BakeGrid::Custom(grid) => grid.clone(),
        }
    }

    /// The bounds of the bake's check: the coarse grid's looser ones
    /// ([`table::CHECK_COARSE_BOUNDS`]), else [`table::CHECK_BOUNDS`].
    pub fn check_bounds(&self) -> CheckBounds {
        match self.grid {
            BakeGrid::Preset(GridPreset::Coarse) => table::CHECK_COARSE_BOUNDS,
            _ => table::CHECK_BOUNDS,
        }
    }

    /// The diffuse-reflectance curve at η through which the artist's parameters are inverted
    /// (for [`crate::scene::Scene::from_toml_str`]): the θ = 0 column of the table this bake
    /// makes at η, with its grid and lobes, so that a scene's materials invert on the table its
    /// file holds (every albedo row: the rows a scene keeps depend on the ρ′ found).
    pub fn curve(&self, eta: f64) -> Result<ReflectanceCurve, ArtistError> {
        ReflectanceCurve::bake(eta, self.moments, &self.grid_at(eta), self.lobes_at(eta))
    }

    /// The table this bake makes at η, alone: every albedo row on its grid with its lobes and
    /// moments, without the θ-sampling section and unchecked, for lookups that need no file
    /// (`bssrdf invert` without one). Its rows equal those of the file [`Baker::bake`] writes
    /// for η, bit for bit. Runs on the current rayon pool.
    pub fn table(&self, eta: f64) -> Result<AngularTable, BakeError> {
        let (grid, lobes) = (self.grid_at(eta), self.lobes_at(eta));
        let rows = 0..grid.rho.len();
        table::bake_rows_lobes(eta, self.moments, &grid, rows, false, lobes, &|_| {})
            .map(|(table, _)| table)
            .map_err(|source| BakeError::Table { eta, source })
    }

    /// Bakes and checks the tables `plan` (η and albedo rows each, in file order), adding them
    /// to `builder`.
    fn bake_tables(
        &self,
        plan: &[(f64, Range<usize>)],
        theta_sampling: bool,
        builder: &mut LibraryBuilder,
        progress: Option<OnProgress<'_>>,
    ) -> Result<Vec<BakedTable>, BakeError> {
        let rows_total = plan.iter().map(|(_, rows)| rows.len()).sum();
        let mut rows_done = 0;
        let mut tables = Vec::with_capacity(plan.len());
        for (k, (eta, rows)) in plan.iter().enumerate() {
            let (eta, base) = (*eta, rows_done);
            let at = |done: usize| Progress {
                table: k,
                tables: plan.len(),
                eta,
                rows: rows.clone(),
                rows_done: base + done,
                rows_total,
            };
            if let Some(progress) = progress {
                progress(&at(0));
            }
            let on_rows = |done: usize| {
                if let Some(progress) = progress {
                    progress(&at(done));
                }
            };
            let (grid, lobes) = (self.grid_at(eta), self.lobes_at(eta));
            let (table, report) = table::bake_rows_lobes(
                eta,
                self.moments,
                &grid,
                rows.clone(),
                theta_sampling,
                lobes,
                &on_rows,
            )
            .map_err(|source| BakeError::Table { eta, source })?;
            let check = table::check(&table.view(), self.moments, self.check_bounds())
                .map_err(|source| BakeError::Check { eta, source })?;
            let index = builder.add_table(table.to_table_data())?;
            rows_done += rows.len();
            tables.push(BakedTable {
                index,
                rows: rows.clone(),
                table,
                check,
                report,
            });
        }
        Ok(tables)
    }

    /// The provenance of a bake of `tables` (module docs); `scene` adds a scene's plan to the
    /// settings.
    fn provenance(
        &self,
        theta_sampling: bool,
        scene: Option<Value>,
        tables: &[BakedTable],
    ) -> Result<Provenance, BakeError> {
        let (name, grid, grazing) = match &self.grid {
            BakeGrid::Preset(preset) => (
                format!("{preset:?}").to_lowercase(),
                Grid::preset(*preset),
                Some(preset.grazing_nodes()),
            ),
            BakeGrid::Custom(grid) => ("custom".to_string(), grid.clone(), None),
        };
        let dims = |g: &Grid| [g.rho.len(), g.theta.len(), g.r.len()];
        // The rules of two lobes, of the θ nodes near η = 1 and of the node where the beam runs
        // in the surface are recorded only where a table of the file took them
        let two_lobes = tables.iter().any(|t| t.table.harmonics().is_some());
        let near_eta_1 = tables
            .iter()
            .any(|t| t.table.eta() < table::GRAZING_NODES_BELOW_ETA);
        let surface = tables.iter().any(|t| {
            let theta = t.table.axes().theta().as_slice();
            theta
                .iter()
                .any(|&node| table::beam_in_surface(t.table.eta(), node))
        });
        let mut settings = json!({
            "grid": name,
            "dims": dims(&grid),
            "fresnel_moments": self.moments.name(),
            "theta_sampling": theta_sampling,
            "anchors_cos_phi": crate::gwc::ANCHOR_COS,
            "minimax_refinement": {
                "theta_min_deg": table::REFINE_THETA_MIN_DEG,
                "extra_phi_deg": table::REFINE_PHI_DEG,
                "also_where_the_fit_clamped": true,
            },
            "lobes": match self.lobes {
                None => json!({"auto": {"two_below_eta": table::TWO_LOBES_BELOW_ETA}}),
                Some(Lobes::One) => json!(1),
                Some(Lobes::Two) => json!(2),
            },
        });
        if two_lobes {
            settings["two_lobe_fit"] = json!({
                "azimuths_deg": table::two_lobe_azimuths().map(f64::to_degrees),
                "stored": "E, E_beta, c of the one lobe with the first two harmonics; r*mu3, r*mu4",
            });
        }
        if surface {
            settings["beam_in_surface"] = json!({
                "cos_refracted_below": table::SURFACE_BEAM_COS,
                "and": "the critical node below eta = 1",
                "stored": "the limit theta' -> 90 deg by its harmonics: PBD with the beam in the surface (the node rule) over phi, a first panel [0, min(pi/100, 0.3/(sigma_tr r))] of 4 Gauss-Legendre points less the closed-form a ln(1/phi), then 8-point panels a decade wide, plus the ridge rho'^2 C_E kappa e^-r/(2r) on phi = 0",
            });
        }
        if tables.iter().any(|t| t.table.ridge().is_some()) {
            settings["ridge"] = json!({
                "weight_full_below_cos_refracted": table::ridge::FULL_WEIGHT_COS,
                "weight_zero_from_cos_refracted": table::ridge::ZERO_WEIGHT_COS,
                "width_floor_cos_refracted": table::ridge::MIN_WIDTH_COS,
                "fluence_lobes": table::ridge::FLUENCE_LOBES,
                "fluence_widest_lobe": table::ridge::FLUENCE_MAX_WIDTH,
                "stored": "the profile less the analytic ridge with its fluence part (format-spec.md section 10, The ridge), which lookups add back; where the beam runs in the surface, the limit's harmonics less the ridge's",
            });
        }
        if let (Some(grazing), true) = (grazing, near_eta_1) {
            // A custom grid is baked as given at every η
            settings["theta_nodes_near_eta_1"] = json!({
                "below_eta": table::GRAZING_NODES_BELOW_ETA,
                "deg": grazing,
                "below_eta_1": "refracted angles, then 90",
            });
        }
        if let (Some(scene), Some(map)) = (scene, settings.as_object_mut()) {
            map.insert("scene".into(), scene);
        }
        let accuracy = tables
            .iter()
            .map(|t| serde_json::to_value(&t.check))
            .collect::<Result<Vec<Value>, _>>()
            .map_err(|e| FormatError::ProvenanceJson {
                message: e.to_string(),
            })?;
        let mut provenance = Provenance::new(concat!("bssrdf-zoo ", env!("CARGO_PKG_VERSION")))
            .with_settings(settings)?
            .with_quadrature(quadrature(two_lobes || surface))?
            .with_accuracy(json!({ "tables": accuracy }))?;
        if self.bake_time {
            provenance = provenance.with_bake_seconds(seconds(tables))?;
        }
        Ok(provenance)
    }
}

/// Wall-clock seconds of the tables' bakes (their checks not included).
fn seconds(tables: &[BakedTable]) -> f64 {
    tables.iter().map(|t| t.report.seconds).sum()
}

/// One table of a bake: where it is in the file, its albedo rows, the table, its check and
/// what its bake did.
#[derive(Debug, Clone)]
pub struct BakedTable {
    index: usize,
    rows: Range<usize>,
    table: AngularTable,
    check: TableCheck,
    report: BakeReport,
}

impl BakedTable {
    /// Its index in the file.
    pub fn index(&self) -> usize {
        self.index
    }
    /// Its η.
    pub fn eta(&self) -> f64 {
        self.table.eta()
    }
    /// The albedo rows of the bake's grid it holds ([`Baker::albedo_grid`]).
    pub fn rows(&self) -> Range<usize> {
        self.rows.clone()
    }
    /// The table.
    pub fn table(&self) -> &AngularTable {
        &self.table
    }
    /// The bake's check of it ([`table::check`], with [`Baker::check_bounds`]).
    pub fn check(&self) -> &TableCheck {
        &self.check
    }
    /// What its bake did: wall-clock time, threads, fit branches.
    pub fn report(&self) -> &BakeReport {
        &self.report
    }
}

/// One material of a bake: the material (for a [`MaterialSpec::diffuse`], its coefficients as
/// inverted) and its record in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct BakedMaterial {
    material: Material,
    record: format::Material,
}

impl BakedMaterial {
    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }
    /// Its record in the file (tables per channel, albedo range, source).
    pub fn record(&self) -> &format::Material {
        &self.record
    }
}

/// What a bake made: the library's builder with tables, materials and provenance, and what the
/// bake found on the way.
#[derive(Debug, Clone)]
pub struct BakedLibrary {
    builder: LibraryBuilder,
    tables: Vec<BakedTable>,
    materials: Vec<BakedMaterial>,
    provenance: Provenance,
    warnings: Vec<String>,
    full_bytes: Option<u64>,
}

impl BakedLibrary {
    /// The library's builder (tables, materials, provenance), ready to write.
    pub fn builder(&self) -> &LibraryBuilder {
        &self.builder
    }
    /// The builder, to write or to add to.
    pub fn into_builder(self) -> LibraryBuilder {
        self.builder
    }
    /// The library file's bytes.
    pub fn to_bytes(&self, compression: Compression) -> Result<Vec<u8>, FormatError> {
        self.builder.to_bytes(compression)
    }
    /// The library in memory, opened for lookups (verified in full).
    pub fn into_library(self) -> Result<Library, BakeError> {
        let bytes = self.builder.to_bytes(Compression::None)?;
        let file = format::Library::from_bytes(&bytes, Verify::Full)?;
        Ok(Library::from_format(file)?)
    }
    /// The tables, in file order, each with its check.
    pub fn tables(&self) -> &[BakedTable] {
        &self.tables
    }
    /// The materials, in the order given.
    pub fn materials(&self) -> &[BakedMaterial] {
        &self.materials
    }
    /// The provenance written in the file.
    pub fn provenance(&self) -> &Provenance {
        &self.provenance
    }
    /// Whether every table passed the bake's check.
    pub fn passes(&self) -> bool {
        self.tables.iter().all(|t| t.check.passes())
    }
    /// Things worth telling that are not errors (a reflectance clamped to the table's largest
    /// effective albedo, a scene material's ρ′ outside its declared range).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
    /// Wall-clock seconds of the tables' bakes (their checks not included).
    pub fn seconds(&self) -> f64 {
        seconds(&self.tables)
    }
    /// For a scene bake: the bytes of the library of the same materials baked in full (every
    /// albedo row, θ sampling, uncompressed, the same provenance).
    pub fn full_bytes(&self) -> Option<u64> {
        self.full_bytes
    }
}

/// The provenance's `quadrature`: PBD's fast rule, and (`node_rule`) the node rule where a
/// table of the file fitted two lobes or had a surface-beam node.
fn quadrature(node_rule: bool) -> Value {
    let mut quadrature = json!({
        "rule": "fast",
        "description": crate::pbd::fast_rule_description(),
        "points_per_panel": crate::pbd::FAST_POINTS_PER_PANEL,
    });
    if node_rule {
        quadrature["node_rule"] = json!({
            "points_per_panel": crate::pbd::NODE_POINTS_PER_PANEL,
            "description": "the fast rule's panels with this many Gauss-Legendre points",
            "where": "the azimuths two-lobe nodes are fitted through, and the harmonics of the surface-beam nodes",
        });
    }
    quadrature
}
