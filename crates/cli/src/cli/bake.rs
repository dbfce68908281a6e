//! `bssrdf bake`: bake angular tables (one per η) for named materials, a material given by its
//! coefficients or by the artist's parameters, a bare η, or a scene manifest (`--scene`, see
//! `bake_scene.rs`), and write them with the materials into one library file, atomically.

use super::eval::MomentsArg;
use super::CliError;
use bssrdf_zoo::format::{self, Compression, LibraryBuilder, Provenance};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::materials::{Library as MaterialLibrary, Material};
use bssrdf_zoo::scene::artist::{self, EffectiveAlbedo};
use bssrdf_zoo::scene::DEFAULT_ETA;
use bssrdf_zoo::table::{self, bake_rows_lobes, AngularTable, Grid, GridPreset, Lobes};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::io::{IsTerminal, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum GridArg {
    /// 50 × 7 × 40.
    Coarse,
    /// 100 × 10 × 64, the report's grid (≈ 1 MiB per η).
    Default,
    /// 160 × 19 × 96.
    Fine,
}

/// `--lobes`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum LobesArg {
    /// Two lobes for η in [1, 1.33), one elsewhere.
    Auto,
    /// One lobe (the report's model).
    #[value(name = "1")]
    One,
    /// Two lobes.
    #[value(name = "2")]
    Two,
}

#[derive(Debug, Args)]
pub struct BakeArgs {
    /// Named materials to bake (see `bssrdf materials`); their tables are shared by η.
    #[arg(value_name = "MATERIAL")]
    pub(super) materials_named: Vec<String>,
    /// Scene manifest (TOML): bake only the albedo rows, tables and sections the scene needs.
    #[arg(long, value_name = "SCENE.toml", conflicts_with_all = [
        "materials_named", "eta", "no_theta_sampling", "sigma_s", "sigma_a", "g",
        "reflectance", "mfp", "name",
    ])]
    pub(super) scene: Option<PathBuf>,
    /// η in [0.75, 2.5] of a bare table (no material), or of the material given by --sigma-s/--sigma-a or
    /// --reflectance/--mfp (default 1.33 there).
    #[arg(long)]
    eta: Option<f64>,
    /// σs per channel, mm⁻¹: a material from coefficients (with --sigma-a, --g, --eta, --name).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "sigma_a", conflicts_with_all = ["reflectance", "mfp"])]
    sigma_s: Option<[f64; 3]>,
    /// σa per channel, mm⁻¹.
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "sigma_s")]
    sigma_a: Option<[f64; 3]>,
    /// Henyey–Greenstein g of that material: one value or R,G,B (default 0).
    #[arg(long, value_name = "G", value_parser = parse_g, allow_hyphen_values = true)]
    g: Option<[f64; 3]>,
    /// Diffuse reflectance per channel in [0, 1]: a material from the artist's parameters,
    /// inverted through the table's effective albedo at θ = 0 (with --mfp).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "mfp")]
    reflectance: Option<[f64; 3]>,
    /// Unreduced mean free path 1/σt per channel, mm (pbrt's convention).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "reflectance")]
    mfp: Option<[f64; 3]>,
    /// Id of the material made from coefficients or reflectance (kebab-case; default "custom").
    #[arg(long, value_name = "ID")]
    name: Option<String>,
    /// Output file (default: MATERIAL.bssrdf for one material or --name, SCENE.bssrdf for
    /// SCENE.toml, table-etaE.bssrdf for --eta E).
    #[arg(short, long, value_name = "FILE")]
    pub(super) output: Option<PathBuf>,
    /// Grid preset.
    #[arg(long, value_enum, default_value = "default")]
    grid: GridArg,
    /// Fresnel moments of the boundary.
    #[arg(long, value_enum, default_value = "exact")]
    fresnel_moments: MomentsArg,
    /// Wrapped Cauchy lobes of the angular profile: 2 for η in [1, 1.33), where one misses the
    /// report's accuracy at grazing incidence, else 1 (auto). At η = 1.05–1.3 two are 28–47
    /// times more accurate at 89°; on the default grid they keep the size (42 radii instead of
    /// 64), on the others they take 1.5 times it; lookups take about 4 times as long
    /// (docs/accuracy.md).
    #[arg(long, value_enum, default_value = "auto")]
    lobes: LobesArg,
    /// Leave out the θ-sampling table (only path tracers need it).
    #[arg(long)]
    no_theta_sampling: bool,
    /// Compress sections with zstd (for distribution; such files are decoded, not mapped).
    #[arg(long)]
    compress: bool,
    /// Record the bake's wall-clock time in the provenance (the file then differs run to run).
    #[arg(long)]
    record_bake_time: bool,
    /// Write the library even where the bake's own check finds a table above its error bound
    /// (docs/accuracy.md); the regions above it are still named on stderr.
    #[arg(long)]
    pub(super) accept_error: bool,
    /// Extra material files (TOML file or folder).
    #[arg(long, value_name = "PATH")]
    pub(super) materials: Option<PathBuf>,
    /// Threads, in [1, 1024] (default: all cores); the result is identical on any count.
    #[arg(long)]
    threads: Option<usize>,
    /// No progress bar or messages on stderr (the bar only ever shows on a terminal).
    #[arg(long, short)]
    pub(super) quiet: bool,
    /// Print a JSON summary on stdout (file, sizes, tables, materials, warnings).
    #[arg(long)]
    pub(super) json: bool,
}

/// Parses "R,G,B": exactly three comma-separated numbers.
fn parse_rgb(text: &str) -> Result<[f64; 3], String> {
    super::values::exactly(text, "R,G,B")
}

/// Parses "G" (every channel) or "R,G,B".
fn parse_g(text: &str) -> Result<[f64; 3], String> {
    match super::values::list::<f64>(text)?.as_slice() {
        [g] => Ok([*g; 3]),
        [r, g, b] => Ok([*r, *g, *b]),
        other => Err(format!(
            "expected one number or 3 comma-separated numbers (R,G,B), got {}",
            other.len()
        )),
    }
}

/// What every bake shares: grid, moments, threads, the progress bar, and how to write.
pub(super) struct Baker {
    pub grid: Grid,
    preset: GridPreset,
    pub moments: Moments,
    threads: Option<usize>,
    /// `--lobes`: `None` chooses by η ([`table::Lobes::for_eta`]).
    lobes: Option<Lobes>,
    bar: ProgressBar,
    compression: Compression,
    record_bake_time: bool,
    pub seconds: f64,
    /// What the bake's check found above its bound, one line per region.
    failures: Vec<String>,
}

impl Baker {
    pub fn new(args: &BakeArgs) -> Self {
        let preset = match args.grid {
            GridArg::Coarse => GridPreset::Coarse,
            GridArg::Default => GridPreset::Default,
            GridArg::Fine => GridPreset::Fine,
        };
        // The bar draws only on a terminal: hidden for pipes, files, CI and --quiet.
        let bar = if args.quiet || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template(
                "baking [{bar:32}] {pos}/{len} albedo rows, {msg} ({elapsed}, ~{eta} left)",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar
        };
        Self {
            grid: Grid::preset(preset),
            preset,
            moments: args.fresnel_moments.into(),
            threads: args.threads,
            lobes: match args.lobes {
                LobesArg::Auto => None,
                LobesArg::One => Some(Lobes::One),
                LobesArg::Two => Some(Lobes::Two),
            },
            bar,
            compression: if args.compress {
                Compression::Zstd {
                    level: Compression::DEFAULT_ZSTD_LEVEL,
                }
            } else {
                Compression::None
            },
            record_bake_time: args.record_bake_time,
            seconds: 0.0,
            failures: Vec::new(),
        }
    }

    /// The lobes of the table this bake makes at η (`--lobes`, or by η).
    pub fn lobes_at(&self, eta: f64) -> Lobes {
        self.lobes.unwrap_or_else(|| Lobes::for_eta(eta))
    }

    /// The grid of the table this bake makes at η: the preset's for its lobes
    /// ([`GridPreset::grid`]). Its albedo rows are always those of [`Baker::grid`].
    pub fn grid_at(&self, eta: f64) -> Grid {
        self.preset.grid(self.lobes_at(eta))
    }

    /// Announces `rows` more albedo rows to the progress bar.
    pub fn plan_rows(&self, rows: usize) {
        self.bar.inc_length(rows as u64);
    }

    /// Bakes the albedo rows `rows` of the grid at η (all of them for a full table).
    pub fn bake(
        &mut self,
        eta: f64,
        rows: Range<usize>,
        theta_sampling: bool,
        label: String,
    ) -> Result<AngularTable, CliError> {
        let base = self.bar.position();
        self.bar.set_message(label);
        let grid = &self.grid_at(eta);
        let (moments, bar) = (self.moments, &self.bar);
        let lobes = self.lobes_at(eta);
        let (table, report) = super::with_threads(self.threads, || {
            bake_rows_lobes(eta, moments, grid, rows, theta_sampling, lobes, &|k| {
                bar.set_position(base + k as u64)
            })
        })?
        .map_err(|e| {
            CliError::input(format!(
                "cannot bake the table for eta = {}: {e}",
                super::show(eta)
            ))
        })?;
        self.seconds += report.seconds;
        Ok(table)
    }

    /// The effective-albedo curve at η on this grid (for the artist's parameters).
    pub fn curve(&self, eta: f64) -> Result<EffectiveAlbedo, artist::ArtistError> {
        let (grid, moments) = (&self.grid, self.moments);
        match super::with_threads(self.threads, || EffectiveAlbedo::bake(eta, moments, grid)) {
            Ok(result) => result,
            // Only a bad --threads fails here, and it failed before any bake already.
            Err(_) => EffectiveAlbedo::bake(eta, moments, grid),
        }
    }

    /// The bake's own check of `table` ([`table::check`]): the accuracy stored in the
    /// provenance. Regions above the bound are kept for [`Baker::verdict`].
    pub fn check(&mut self, table: &AngularTable) -> Result<Value, CliError> {
        let moments = self.moments;
        let bounds = match self.preset {
            GridPreset::Coarse => table::CHECK_COARSE_BOUNDS,
            GridPreset::Default | GridPreset::Fine => table::CHECK_BOUNDS,
        };
        let result = super::with_threads(self.threads, || {
            table::check(&table.view(), moments, bounds)
        })??;
        for r in result.failures() {
            self.failures.push(format!(
                "  eta {}, rho {}-{}, theta {}-{} deg: mean {:.3} % over {} points (bound {} %), coverage max {:.3} % over {} points (bound {} %), {} silent zero(s)",
                super::show(result.eta),
                super::show(r.rho[0]),
                super::show(r.rho[1]),
                super::show(round3(r.theta_deg[0])),
                super::show(round3(r.theta_deg[1])),
                100.0 * r.mean_rel_error,
                r.points,
                super::show(100.0 * result.bounds.mean_rel_error),
                100.0 * r.coverage_max_rel_error,
                r.coverage_points,
                super::show(100.0 * result.bounds.coverage_rel_error),
                r.silent_zeros,
            ));
        }
        serde_json::to_value(&result).map_err(|e| CliError::input(e.to_string()))
    }

    /// After every table's check: an error (exit 1) naming the regions above the bound, unless
    /// `accept` (`--accept-error`), which only reports them on stderr (not with `quiet`).
    pub fn verdict(&self, accept: bool, quiet: bool) -> Result<(), CliError> {
        if self.failures.is_empty() {
            return Ok(());
        }
        let regions = self.failures.join("\n");
        if accept {
            if !quiet {
                self.bar.suspend(|| {
                    eprintln!("warning: written with --accept-error; the bake's check found these regions above its bound:\n{regions}")
                });
            }
            Ok(())
        } else {
            self.bar.finish_and_clear();
            Err(CliError::Check(format!(
                "the bake's check found these regions above its bound (docs/accuracy.md), so nothing was written:\n{regions}\n--accept-error writes the file anyway"
            )))
        }
    }

    /// The provenance of a bake; `scene` adds the scene's plan to the settings.
    pub fn provenance(
        &self,
        theta_sampling: bool,
        scene: Option<Value>,
        accuracy: Vec<Value>,
    ) -> Result<Provenance, CliError> {
        let grid = &self.grid;
        let two = self.preset.grid(Lobes::Two);
        let mut settings = json!({
            "grid": format!("{:?}", self.preset).to_lowercase(),
            "dims": [grid.rho.len(), grid.theta.len(), grid.r.len()],
            "two_lobe_dims": [two.rho.len(), two.theta.len(), two.r.len()],
            "fresnel_moments": self.moments.name(),
            "theta_sampling": theta_sampling,
            "anchors_cos_phi": bssrdf_zoo::gwc::ANCHOR_COS,
            "minimax_refinement": {
                "theta_min_deg": bssrdf_zoo::table::REFINE_THETA_MIN_DEG,
                "extra_phi_deg": bssrdf_zoo::table::REFINE_PHI_DEG,
                "also_where_the_fit_clamped": true,
            },
            "lobes": match self.lobes {
                None => json!({"auto": {"two_from_eta": 1.0, "two_below_eta": bssrdf_zoo::table::TWO_LOBES_BELOW_ETA}}),
                Some(Lobes::One) => json!(1),
                Some(Lobes::Two) => json!(2),
            },
            "two_lobe_fit": {
                "azimuths_deg": bssrdf_zoo::table::two_lobe_azimuths().map(f64::to_degrees),
                "stored": "E, E_beta, c of the one lobe with the first two harmonics; r*mu3, r*mu4",
            },
        });
        if let (Some(scene), Some(map)) = (scene, settings.as_object_mut()) {
            map.insert("scene".into(), scene);
        }
        let mut provenance = Provenance::new(concat!("bssrdf-zoo ", env!("CARGO_PKG_VERSION")))
            .with_settings(settings)
            .and_then(|p| {
                p.with_quadrature(json!({
                    "rule": "fast",
                    "description": "composite 8-point Gauss-Legendre in u, t = t* + h sinh u, panels at the closest approach and at 3, 12, 46 nats of the exponent",
                    "points_per_panel": bssrdf_zoo::pbd::FAST_POINTS_PER_PANEL,
                }))
            })
            .and_then(|p| p.with_accuracy(json!({ "tables": accuracy })))
            .map_err(format_error)?;
        if self.record_bake_time {
            provenance = provenance
                .with_bake_seconds(self.seconds)
                .map_err(format_error)?;
        }
        Ok(provenance)
    }

    /// Writes the library atomically; returns the bytes written (also through a device or a
    /// FIFO, whose size on disk says nothing).
    pub fn write(&self, builder: &LibraryBuilder, output: &Path) -> Result<u64, CliError> {
        self.bar.finish_and_clear();
        builder.write_atomic(output, self.compression).map_err(|e| {
            // The writer's own errors name the file already.
            let message = e.to_string();
            if message.contains(&output.display().to_string()) {
                CliError::input(message)
            } else {
                CliError::input(format!("cannot write {}: {message}", output.display()))
            }
        })
    }

    pub fn compressed(&self) -> bool {
        self.compression != Compression::None
    }
}

/// `x` rounded to 3 decimals, for band edges such as the critical angle 48.590329…°.
fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Refuses an output that is one of the bake's inputs (the scene, the material files).
pub(super) fn check_output(args: &BakeArgs, output: &Path) -> Result<(), CliError> {
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(scene) = &args.scene {
        inputs.push(("--scene", scene.as_path()));
    }
    if let Some(m) = &args.materials {
        inputs.push(("--materials", m.as_path()));
    }
    super::output::check(&[("-o", output)], &inputs)
}

/// A material from the command line's coefficients or artist's parameters.
enum Custom {
    Coefficients(Box<Material>),
    Diffuse {
        name: String,
        reflectance: [f64; 3],
        mfp: [f64; 3],
        g: [f64; 3],
        eta: f64,
    },
}

impl Custom {
    fn eta(&self) -> f64 {
        match self {
            Custom::Coefficients(m) => m.eta(),
            Custom::Diffuse { eta, .. } => *eta,
        }
    }
}

/// The material of --sigma-s/--sigma-a or --reflectance/--mfp, validated before any bake.
fn custom(args: &BakeArgs, library: &MaterialLibrary) -> Result<Option<Custom>, CliError> {
    let given = args.sigma_s.is_some() || args.reflectance.is_some();
    if !given {
        if args.g.is_some() || args.name.is_some() {
            return Err(CliError::input(
                "--g and --name describe a material given by --sigma-s/--sigma-a or --reflectance/--mfp; give one of those",
            ));
        }
        return Ok(None);
    }
    let eta = args.eta.unwrap_or(DEFAULT_ETA);
    super::check_range(
        "--eta",
        eta,
        bssrdf_zoo::medium::ETA_MIN..=bssrdf_zoo::medium::ETA_MAX,
    )?;
    let name = args.name.clone().unwrap_or_else(|| "custom".to_string());
    if library.get(&name).is_ok() {
        return Err(CliError::input(format!(
            "--name {name} is a material of the library (see `bssrdf materials`): choose another id"
        )));
    }
    let g = args.g.unwrap_or([0.0; 3]);
    match (args.sigma_s, args.sigma_a, args.reflectance, args.mfp) {
        (Some(s), Some(a), _, _) => Material::from_coefficients(&name, s, a, g, eta)
            .map(|m| Some(Custom::Coefficients(Box::new(m))))
            .map_err(|e| CliError::input(format!("--sigma-s/--sigma-a material: {e}"))),
        (_, _, Some(reflectance), Some(mfp)) => {
            artist::check(reflectance, mfp, g).map_err(|e| {
                CliError::input(format!("--reflectance/--mfp material {name:?}: {e}"))
            })?;
            // The id rules, checked now rather than after the bake.
            Material::from_coefficients(&name, [1.0; 3], [1.0; 3], g, eta)
                .map_err(|e| CliError::input(format!("--name: {e}")))?;
            Ok(Some(Custom::Diffuse {
                name,
                reflectance,
                mfp,
                g,
                eta,
            }))
        }
        // clap's `requires` pairs the flags.
        _ => Ok(None),
    }
}

/// The file's record of a material with every channel on one table, no albedo range. Its
/// `source` was checked by [`bssrdf_zoo::scene::check_source`] when the material was named.
pub(super) fn record(m: &Material, source: &str, table: u32) -> format::Material {
    format::Material {
        name: m.id().to_string(),
        source: source.to_string(),
        sigma_s: m.sigma_s(),
        sigma_a: m.sigma_a(),
        g: m.g(),
        eta: m.eta(),
        tables: [table; 3],
        albedo_range: None,
    }
}

pub fn run(args: BakeArgs) -> Result<ExitCode, CliError> {
    super::check_threads(args.threads)?;
    let mut baker = Baker::new(&args);
    if let Some(scene) = &args.scene {
        return super::bake_scene::run(&args, &mut baker, scene);
    }
    let library = super::materials::library(args.materials.as_deref())?;
    let mut materials: Vec<(Material, String)> = args
        .materials_named
        .iter()
        .map(|name| {
            let m = library
                .get(name)
                .map_err(|e| CliError::input(e.to_string()))?;
            let source = m
                .source()
                .map(|s| s.coefficients().to_string())
                .unwrap_or_default();
            bssrdf_zoo::scene::check_source(name, &source)
                .map_err(|e| CliError::input(e.to_string()))?;
            Ok((m.clone(), source))
        })
        .collect::<Result<_, CliError>>()?;
    let custom = custom(&args, &library)?;
    if args.materials.is_some() && materials.is_empty() && custom.is_none() {
        return Err(CliError::input(
            "--materials adds files to look material names up in; name a MATERIAL from them, or drop --materials",
        ));
    }
    let mut etas: Vec<f64> = materials.iter().map(|(m, _)| m.eta()).collect();
    etas.extend(custom.as_ref().map(Custom::eta));
    match (etas.is_empty(), args.eta, &custom) {
        (true, Some(eta), _) => etas.push(eta),
        (true, None, _) => {
            return Err(CliError::input(
                "name at least one material (see `bssrdf materials`), give --sigma-s/--sigma-a or --reflectance/--mfp, a --scene, or --eta",
            ))
        }
        (false, Some(_), None) => {
            return Err(CliError::input(
                "--eta bakes a bare table; materials bring their own eta: give one or the other",
            ))
        }
        _ => {}
    }
    etas.sort_by(f64::total_cmp);
    etas.dedup();
    let custom_name = custom.as_ref().map(|c| match c {
        Custom::Coefficients(m) => m.id().to_string(),
        Custom::Diffuse { name, .. } => name.clone(),
    });
    let output = match (&args.output, materials.as_slice(), &custom_name) {
        (Some(path), _, _) => path.clone(),
        (None, [one], None) => PathBuf::from(format!("{}.bssrdf", one.0.id())),
        (None, [], Some(name)) => PathBuf::from(format!("{name}.bssrdf")),
        (None, [], None) => PathBuf::from(format!("table-eta{}.bssrdf", etas[0])),
        (None, _, _) => {
            return Err(CliError::input(
                "several materials go into one library: name it with -o FILE",
            ))
        }
    };
    check_output(&args, &output)?;

    let theta_sampling = !args.no_theta_sampling;
    let n_rho = baker.grid.rho.len();
    baker.plan_rows(n_rho * etas.len());
    let mut builder = LibraryBuilder::new();
    let mut tables: BTreeMap<u64, (u32, AngularTable)> = BTreeMap::new();
    let mut accuracy = Vec::new();
    let mut table_json = Vec::new();
    for (k, &eta) in etas.iter().enumerate() {
        let label = format!("table {}/{} (eta {eta})", k + 1, etas.len());
        let table = baker.bake(eta, 0..n_rho, theta_sampling, label)?;
        accuracy.push(baker.check(&table)?);
        let index = builder
            .add_table(table.to_table_data())
            .map_err(format_error)?;
        table_json.push(table_summary(index, &table, 0..n_rho));
        tables.insert(eta.to_bits(), (index as u32, table));
    }
    let mut warnings = Vec::new();
    match custom {
        Some(Custom::Coefficients(m)) => {
            materials.push((*m, "command line: --sigma-s/--sigma-a".into()));
        }
        Some(Custom::Diffuse {
            name,
            reflectance,
            mfp,
            g,
            eta,
        }) => {
            let table = tables.get(&eta.to_bits()).map(|(_, t)| t);
            let m = diffuse_material(&name, reflectance, mfp, g, eta, table, &mut warnings)?;
            let source = format!("command line: reflectance {reflectance:?}, mfp {mfp:?} mm, inverted through the table's rho_eff at theta = 0");
            materials.push((m, source));
        }
        None => {}
    }
    let mut material_json = Vec::new();
    for (m, source) in &materials {
        let index = tables.get(&m.eta().to_bits()).map_or(0, |t| t.0);
        builder
            .add_material(record(m, source, index))
            .map_err(format_error)?;
        material_json.push(json!({
            "name": m.id(), "eta": m.eta(), "tables": [index, index, index], "rho_prime": m.rho_prime(),
            "albedo_range": Value::Null,
        }));
    }
    builder.set_provenance(baker.provenance(theta_sampling, None, accuracy)?);
    baker.verdict(args.accept_error, args.quiet)?;
    let bytes = baker.write(&builder, &output)?;
    let summary = Summary {
        output: &output,
        bytes,
        full_bytes: None,
        integrator: None,
        tables: table_json,
        materials: material_json,
        warnings,
    };
    summary.print(&args, &baker)?;
    Ok(ExitCode::SUCCESS)
}

/// The material of --reflectance/--mfp, inverted through the θ = 0 column of the table baked
/// at its η.
fn diffuse_material(
    name: &str,
    reflectance: [f64; 3],
    mfp: [f64; 3],
    g: [f64; 3],
    eta: f64,
    table: Option<&AngularTable>,
    warnings: &mut Vec<String>,
) -> Result<Material, CliError> {
    let err = |e: String| CliError::input(format!("--reflectance/--mfp material {name:?}: {e}"));
    let table = table.ok_or_else(|| err(format!("no table at eta = {eta}")))?;
    let curve = EffectiveAlbedo::from_table(table).map_err(|e| err(e.to_string()))?;
    let d = curve
        .diffuse(reflectance, mfp, g)
        .map_err(|e| err(e.to_string()))?;
    for (c, inv) in d.inverted.iter().enumerate() {
        if inv.clamped {
            warnings.push(format!(
                "material {name:?}, channel {}: reflectance {} is above the largest effective albedo of the table, {:.4} (multiple scattering only, at reduced albedo 1); clamped to reduced albedo 1",
                ["r", "g", "b"][c],
                reflectance[c],
                curve.max()
            ));
        }
    }
    Material::from_coefficients(name, d.sigma_s, d.sigma_a, g, eta).map_err(|e| err(e.to_string()))
}

/// One table of the summary.
pub(super) fn table_summary(index: usize, table: &AngularTable, rows: Range<usize>) -> Value {
    let rho = table.axes().rho().as_slice();
    json!({
        "index": index,
        "eta": table.eta(),
        "rows": [rows.start, rows.end],
        "rho": [rho.first(), rho.last()],
        "dims": table.axes().dims(),
        "theta_sampling": table.theta_cdf().is_some(),
    })
}

/// What a bake prints: a line on stderr, or with --json an object on stdout.
pub(super) struct Summary<'a> {
    pub output: &'a Path,
    pub bytes: u64,
    /// Size of the same materials baked in full (scene bakes).
    pub full_bytes: Option<u64>,
    pub integrator: Option<&'static str>,
    pub tables: Vec<Value>,
    pub materials: Vec<Value>,
    pub warnings: Vec<String>,
}

impl Summary<'_> {
    pub fn print(&self, args: &BakeArgs, baker: &Baker) -> Result<(), CliError> {
        let saved = self.full_bytes.map(|full| {
            let saved = full as i64 - self.bytes as i64;
            (full, saved, 100.0 * saved as f64 / full.max(1) as f64)
        });
        if !args.quiet {
            let mut err = std::io::stderr().lock();
            for w in &self.warnings {
                writeln!(err, "warning: {w}")?;
            }
            writeln!(
                err,
                "wrote {} ({} table(s), {} material(s), {} bytes, {:.1} KiB) in {:.2} s",
                self.output.display(),
                self.tables.len(),
                self.materials.len(),
                self.bytes,
                self.bytes as f64 / 1024.0,
                baker.seconds
            )?;
            if let Some((full, saved, percent)) = saved {
                let compressed = if baker.compressed() {
                    ", uncompressed"
                } else {
                    ""
                };
                writeln!(
                    err,
                    "the full library of these materials (every albedo row, theta-sampling{compressed}) would be {full} bytes: saved {saved} bytes ({percent:.1} %)"
                )?;
            }
        }
        if args.json {
            let json = json!({
                "output": self.output.display().to_string(),
                "bytes": self.bytes,
                "full_bytes": saved.map(|s| s.0),
                "saved_bytes": saved.map(|s| s.1),
                "saved_percent": saved.map(|s| s.2),
                "integrator": self.integrator,
                "seconds": baker.seconds,
                "tables": self.tables,
                "materials": self.materials,
                "warnings": self.warnings,
            });
            let mut out = std::io::stdout().lock();
            writeln!(out, "{json}")?;
            out.flush()?;
        }
        Ok(())
    }
}

pub fn format_error(e: format::FormatError) -> CliError {
    CliError::input(e.to_string())
}
