//! `bssrdf bake`: bake angular tables (one per η) for named materials, a material given by its
//! coefficients or by the artist's parameters, a bare η, or a scene manifest (`--scene`, see
//! `bake_scene.rs`), and write them with the materials into one library file, atomically.

use super::eval::MomentsArg;
use super::CliError;
use bssrdf_zoo::bake::{BakeError, BakedLibrary, Baker, MaterialSpec, OnProgress, Progress};
use bssrdf_zoo::format::{Compression, LibraryBuilder, WalkComponent};
use bssrdf_zoo::materials::{Library as MaterialLibrary, Material, Origin};
use bssrdf_zoo::scene::artist::{self, ReflectanceCurve};
use bssrdf_zoo::scene::DEFAULT_ETA;
use bssrdf_zoo::table::{AngularTable, GridPreset, Lobes};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::{json, Value};
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

impl From<GridArg> for GridPreset {
    fn from(grid: GridArg) -> Self {
        match grid {
            GridArg::Coarse => GridPreset::Coarse,
            GridArg::Default => GridPreset::Default,
            GridArg::Fine => GridPreset::Fine,
        }
    }
}

/// `--lobes`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum LobesArg {
    /// Two lobes below η = 1.33, one from it up.
    Auto,
    /// One lobe (the report's model).
    #[value(name = "1")]
    One,
    /// Two lobes.
    #[value(name = "2")]
    Two,
}

/// `--source`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum SourceArg {
    /// Photon beam diffusion (PBD), the report's model.
    Pbd,
    /// The Monte Carlo walk, for one --eta and --g.
    Walk,
}

/// `--component` of a walk bake.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum ComponentArg {
    /// Everything that leaves: the walk's multiple scattering plus single scattering computed
    /// exactly by quadrature (what a renderer needs).
    Total,
    /// The walk's multiple scattering alone (two or more vertices: the part PBD models).
    Multiple,
}

impl ComponentArg {
    /// The component of the table's record.
    pub(super) fn component(self) -> WalkComponent {
        match self {
            ComponentArg::Total => WalkComponent::Total,
            ComponentArg::Multiple => WalkComponent::Multiple,
        }
    }
}

#[derive(Debug, Args)]
pub struct BakeArgs {
    /// Where the table's numbers come from: photon beam diffusion, or the Monte Carlo random
    /// walk for one --eta and --g (a walk-angular table, of --component: a few minutes on two
    /// cores at g = 0 and the default --photons, about four times as long at g = 0.9;
    /// docs/walk-table.md).
    #[arg(long, value_enum, default_value = "pbd")]
    pub(super) source: SourceArg,
    /// Photons per θ node of a --source walk bake, for each group of albedo rows (the rows
    /// above ρ′ = 0.999 take an eighth of them), in [131072, 1e12], default 250000; the
    /// table's noise falls like 1/√photons.
    #[arg(long, value_parser = super::values::whole::<u64>)]
    pub(super) photons: Option<u64>,
    /// Seed of a --source walk bake's walks, default 1 (the table is bit-identical for a seed
    /// on any thread count).
    #[arg(long, value_parser = super::values::whole::<u64>)]
    pub(super) seed: Option<u64>,
    /// What a --source walk table holds: total (default), the walk's multiple scattering plus
    /// single scattering computed exactly by quadrature, integrated over exit directions like
    /// the rest; or multiple, the walk's multiple scattering alone, the part PBD models
    /// (docs/walk-table.md).
    #[arg(long, value_enum)]
    pub(super) component: Option<ComponentArg>,
    /// Named materials to bake (see `bssrdf materials`); their tables are shared by η.
    #[arg(value_name = "MATERIAL")]
    pub(super) materials_named: Vec<String>,
    /// Scene manifest (TOML): bake only the albedo rows, tables and sections the scene needs.
    #[arg(long, value_name = "SCENE.toml", conflicts_with_all = [
        "materials_named", "eta", "no_theta_sampling", "sigma_s", "sigma_a", "g",
        "reflectance", "mfp", "name",
    ])]
    pub(super) scene: Option<PathBuf>,
    /// η in [0.75, 2.5] of a bare table (no material) or of a --source walk table, or of the
    /// material given by --sigma-s/--sigma-a or --reflectance/--mfp (default 1.33 there).
    #[arg(long)]
    pub(super) eta: Option<f64>,
    /// σs per channel, mm⁻¹: a material from coefficients (with --sigma-a, --g, --eta, --name).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "sigma_a", conflicts_with_all = ["reflectance", "mfp"])]
    pub(super) sigma_s: Option<[f64; 3]>,
    /// σa per channel, mm⁻¹.
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "sigma_s", conflicts_with_all = ["reflectance", "mfp"])]
    sigma_a: Option<[f64; 3]>,
    /// Henyey–Greenstein g of that material: one value or R,G,B (default 0); with --source
    /// walk, the walk's g (one value, default 0).
    #[arg(long, value_name = "G", value_parser = parse_g, allow_hyphen_values = true)]
    pub(super) g: Option<GArg>,
    /// Diffuse reflectance per channel in [0, 1]: a material from the artist's parameters,
    /// inverted through the table's diffuse reflectance (1 − F_r) ρ_eff at θ = 0 (with --mfp;
    /// above the largest, clamped to ρ′ = 1 with a warning).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "mfp")]
    pub(super) reflectance: Option<[f64; 3]>,
    /// Unreduced mean free path 1/σt per channel, mm (pbrt's convention).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true,
          requires = "reflectance")]
    mfp: Option<[f64; 3]>,
    /// Id of the material made from coefficients or reflectance (kebab-case; default "custom").
    #[arg(long, value_name = "ID")]
    pub(super) name: Option<String>,
    /// Output file (default: MATERIAL.bssrdf for one material or --name, SCENE.bssrdf for
    /// SCENE.toml (its last extension replaced: shot.v1.toml gives shot.v1.bssrdf),
    /// table-etaE.bssrdf for --eta E, walk-etaE-gG.bssrdf for --source walk).
    #[arg(short, long, value_name = "FILE")]
    pub(super) output: Option<PathBuf>,
    /// Grid preset.
    #[arg(long, value_enum, default_value = "default")]
    pub(super) grid: GridArg,
    /// Fresnel moments of the boundary [default: exact].
    #[arg(long, value_enum)]
    pub(super) fresnel_moments: Option<MomentsArg>,
    /// Wrapped Cauchy lobes of the angular profile: 2 below η = 1.33, where one misses the
    /// report's accuracy at grazing incidence (or refraction), else 1 (auto). At η = 1.05–1.3 two
    /// are 28–47 times more accurate at 89°; on the default grid they keep the size (42 radii
    /// instead of 64), on the others they take 1.5 times it; lookups take 2–3 times as long
    /// (docs/accuracy.md).
    #[arg(long, value_enum, default_value = "auto")]
    pub(super) lobes: LobesArg,
    /// Leave out the θ-sampling table (only path tracers need it).
    #[arg(long)]
    pub(super) no_theta_sampling: bool,
    /// Compress sections with zstd (for distribution; such files are decoded, not mapped).
    #[arg(long)]
    pub(super) compress: bool,
    /// Record the bake's wall-clock time in the provenance (the file then differs run to run).
    #[arg(long)]
    pub(super) record_bake_time: bool,
    /// Write the library even where the bake's own check finds a table above its error bound
    /// (docs/accuracy.md); the regions above it are still named on stderr.
    #[arg(long)]
    pub(super) accept_error: bool,
    /// Extra material files (TOML file or folder).
    #[arg(long, value_name = "PATH")]
    pub(super) materials: Option<PathBuf>,
    /// Threads, in [1, 1024] (default: all cores); the result is identical on any count.
    #[arg(long, value_parser = super::values::whole::<usize>)]
    pub(super) threads: Option<usize>,
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
/// `--g` as given: its value per channel, and whether it was a list (R,G,B), which a walk
/// bake refuses however equal its values.
#[derive(Debug, Clone, Copy)]
pub(super) struct GArg {
    pub(super) rgb: [f64; 3],
    pub(super) listed: bool,
}

fn parse_g(text: &str) -> Result<GArg, String> {
    let (rgb, listed) = match super::values::list::<f64>(text)?.as_slice() {
        [g] => ([*g; 3], false),
        [r, g, b] => ([*r, *g, *b], true),
        other => {
            return Err(format!(
                "expected one number or 3 comma-separated numbers (R,G,B), got {}",
                other.len()
            ))
        }
    };
    Ok(GArg { rgb, listed })
}

/// The library's bake of these arguments ([`bssrdf_zoo::bake`]).
pub(super) fn baker(args: &BakeArgs) -> Baker {
    Baker::new(GridPreset::from(args.grid))
        .with_moments(args.fresnel_moments.unwrap_or(MomentsArg::Exact).into())
        .with_lobes(match args.lobes {
            LobesArg::Auto => None,
            LobesArg::One => Some(Lobes::One),
            LobesArg::Two => Some(Lobes::Two),
        })
        .with_theta_sampling(!args.no_theta_sampling)
        .with_bake_time(args.record_bake_time)
}

/// What the command adds to the library's bake: the threads, the progress bar, the verdict on
/// the bake's check, and the atomic write.
pub(super) struct Session {
    threads: Option<usize>,
    bar: ProgressBar,
    compression: Compression,
}

impl Session {
    pub fn new(args: &BakeArgs) -> Self {
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
            threads: args.threads,
            bar,
            compression: if args.compress {
                Compression::Zstd {
                    level: Compression::DEFAULT_ZSTD_LEVEL,
                }
            } else {
                Compression::None
            },
        }
    }

    /// Runs `bake` on --threads threads with the progress bar following it; `rows` adds each
    /// table's albedo rows to its label (scene bakes).
    pub fn bake<T: Send>(
        &self,
        rows: bool,
        bake: impl FnOnce(OnProgress<'_>) -> Result<T, BakeError> + Send,
    ) -> Result<Result<T, BakeError>, CliError> {
        let bar = &self.bar;
        let progress = |p: &Progress| {
            let mut label = format!("table {}/{} (eta {}", p.table + 1, p.tables, p.eta);
            if rows {
                label += &format!(", rows {}..{}", p.rows.start, p.rows.end);
            }
            bar.set_length(p.rows_total as u64);
            bar.set_message(label + ")");
            bar.set_position(p.rows_done as u64);
        };
        super::with_threads(self.threads, || bake(&progress))
    }

    /// The diffuse-reflectance curve at η of `baker` (for the artist's parameters).
    pub fn curve(&self, baker: &Baker, eta: f64) -> Result<ReflectanceCurve, artist::ArtistError> {
        match super::with_threads(self.threads, || baker.curve(eta)) {
            Ok(result) => result,
            // Only a bad --threads fails here, and it failed before any bake already.
            Err(_) => baker.curve(eta),
        }
    }

    /// After the bake: an error (exit 1) naming the regions above the bound of the bake's
    /// check, unless `accept` (`--accept-error`), which returns them as a warning for the
    /// summary instead (stderr, and the `warnings` of `--json`).
    pub fn verdict(&self, baked: &BakedLibrary, accept: bool) -> Result<Option<String>, CliError> {
        let mut failures = Vec::new();
        for result in baked.tables().iter().map(|t| t.check()) {
            // A table whose rows leave no region to check is not a pass
            if let Some(note) = result.nothing_checked() {
                failures.push(format!("  eta {}: {note}", super::show(result.eta)));
            }
            for r in result.failures() {
                failures.push(format!(
                    "  eta {}, rho {}-{}, theta {}-{} deg: mean {:.3} % over {} points (bound {} %), coverage max {:.3} % over {} points (bound {} %), {} silent zero(s)",
                    super::show(result.eta),
                    super::values::show_band(r.rho[0]),
                    super::values::show_band(r.rho[1]),
                    super::show_deg(r.theta_deg[0]),
                    super::show_deg(r.theta_deg[1]),
                    100.0 * r.mean_rel_error,
                    r.points,
                    super::show(100.0 * result.bounds.mean_rel_error),
                    100.0 * r.coverage_max_rel_error,
                    r.coverage_points,
                    super::show(100.0 * result.bounds.coverage_rel_error),
                    r.silent_zeros,
                ));
            }
        }
        if failures.is_empty() {
            return Ok(None);
        }
        let regions = failures.join("\n");
        if accept {
            Ok(Some(format!(
                "written with --accept-error; the bake's check found these regions above its bound:\n{regions}"
            )))
        } else {
            self.bar.finish_and_clear();
            Err(CliError::Check(format!(
                "the bake's check found these regions above its bound (docs/accuracy.md), so nothing was written:\n{regions}\n--accept-error writes the file anyway"
            )))
        }
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

/// The command's message for a failed bake (exit 2).
pub(super) fn bake_error(e: BakeError) -> CliError {
    match e {
        BakeError::Table { eta, source } => CliError::input(format!(
            "cannot bake the table for eta = {}: {source}",
            super::show(eta)
        )),
        BakeError::Check { source, .. } | BakeError::Axis(source) => CliError::Library(source),
        BakeError::Artist { name, source } => {
            CliError::input(format!("--reflectance/--mfp material {name:?}: {source}"))
        }
        BakeError::Material { name, source } => {
            CliError::input(format!("--reflectance/--mfp material {name:?}: {source}"))
        }
        other => CliError::input(other.to_string()),
    }
}

/// Refuses an output that is one of the bake's inputs (the scene, the material files: the
/// `--materials` file, or each `*.toml` of its folder).
pub(super) fn check_output(args: &BakeArgs, output: &Path) -> Result<(), CliError> {
    let material_files = super::materials::input_files(args.materials.as_deref());
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(scene) = &args.scene {
        inputs.push(("--scene", scene.as_path()));
    }
    for file in &material_files {
        inputs.push(("--materials", file.as_path()));
    }
    super::output::check(&[("-o", output)], &inputs)?;
    if args.json {
        let instead = "drop --json or write the library elsewhere";
        super::output::not_on_stdout("-o", output, "its --json summary", instead)?;
    }
    // A new *.toml in the --materials folder would be read as a material file by later runs
    if let Some(dir) = args.materials.as_deref().filter(|m| m.is_dir()) {
        let folder = match output.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let same = |a: &Path, b: &Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y);
        let toml = output
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        if toml && same(folder, dir) {
            return Err(CliError::input(format!(
                "-o {} is a *.toml file of the --materials folder {}: later runs would read the library as a material file; write it elsewhere",
                output.display(),
                dir.display()
            )));
        }
    }
    Ok(())
}

/// Refuses `--materials` when none of the bake's `materials` comes from its files: the flag
/// would be accepted and change nothing.
pub(super) fn check_materials_used<'m>(
    args: &BakeArgs,
    mut materials: impl Iterator<Item = &'m Material>,
) -> Result<(), CliError> {
    let from_files = materials.any(|m| matches!(m.origin(), Origin::File(_)));
    if args.materials.is_some() && !from_files {
        return Err(CliError::input(
            "--materials adds files to look material names up in; name a MATERIAL from them, or drop --materials",
        ));
    }
    Ok(())
}

/// The material of --sigma-s/--sigma-a or --reflectance/--mfp, validated before any bake.
fn custom(args: &BakeArgs, library: &MaterialLibrary) -> Result<Option<MaterialSpec>, CliError> {
    let given = args.sigma_s.is_some() || args.reflectance.is_some();
    if !given {
        // (Naming the flags given)
        let flags = match (args.g.is_some(), args.name.is_some()) {
            (true, true) => Some("--g and --name describe"),
            (true, false) => Some("--g describes"),
            (false, true) => Some("--name describes"),
            (false, false) => None,
        };
        if let Some(flags) = flags {
            return Err(CliError::input(format!(
                "{flags} a material given by --sigma-s/--sigma-a or --reflectance/--mfp; give one of those"
            )));
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
    if bssrdf_zoo::scene::check_new_id(&name, library).is_err() {
        return Err(CliError::input(format!(
            "--name {name} is a material of the library (see `bssrdf materials`): choose another id"
        )));
    }
    let g = args.g.map_or([0.0; 3], |g| g.rgb);
    match (args.sigma_s, args.sigma_a, args.reflectance, args.mfp) {
        (Some(s), Some(a), _, _) => Material::from_coefficients(&name, s, a, g, eta)
            .map(|m| Some(MaterialSpec::new(m, "command line: --sigma-s/--sigma-a")))
            .map_err(|e| CliError::input(format!("--sigma-s/--sigma-a material: {e}"))),
        (_, _, Some(reflectance), Some(mfp)) => {
            let source = format!("command line: reflectance {reflectance:?}, mfp {mfp:?} mm, inverted through the table's (1 - F_r) rho_eff at theta = 0");
            MaterialSpec::diffuse(&name, reflectance, mfp, g, eta, source)
                .map(Some)
                .map_err(|e| match e {
                    BakeError::Material { source, .. } => {
                        CliError::input(format!("--name: {source}"))
                    }
                    e => bake_error(e),
                })
        }
        // clap's `requires` pairs the flags.
        _ => Ok(None),
    }
}

pub fn run(args: BakeArgs) -> Result<ExitCode, CliError> {
    super::check_threads(args.threads)?;
    if args.source == SourceArg::Walk {
        return super::bake_walk::run(&args);
    }
    for (flag, given) in [
        ("--photons", args.photons.is_some()),
        ("--seed", args.seed.is_some()),
    ] {
        if given {
            return Err(CliError::input(format!(
                "{flag} sets the walk of --source walk; a PBD bake has no walk"
            )));
        }
    }
    if let Some(component) = args.component {
        return Err(CliError::input(format!(
            "--component {} chooses what a --source walk table holds; a PBD bake holds PBD's multiple scattering: add --source walk or drop --component",
            component.component().name(),
        )));
    }
    let baker = baker(&args);
    let session = Session::new(&args);
    if let Some(scene) = &args.scene {
        return super::bake_scene::run(&args, &baker, &session, scene);
    }
    let library = super::materials::library(args.materials.as_deref())?;
    let mut materials: Vec<MaterialSpec> = args
        .materials_named
        .iter()
        .map(|name| {
            let m = library
                .get(name)
                .map_err(|e| CliError::input(e.to_string()))?;
            // Checked here to name the material as given (an alias, say).
            let source = m.source().map(|s| s.coefficients()).unwrap_or_default();
            bssrdf_zoo::scene::check_source(name, source)
                .map_err(|e| CliError::input(e.to_string()))?;
            MaterialSpec::named(m).map_err(|e| CliError::input(e.to_string()))
        })
        .collect::<Result<_, CliError>>()?;
    let named: Vec<&Material> = args
        .materials_named
        .iter()
        .filter_map(|name| library.get(name).ok())
        .collect();
    check_materials_used(&args, named.into_iter())?;
    let custom = custom(&args, &library)?;
    let mut etas: Vec<f64> = materials.iter().map(MaterialSpec::eta).collect();
    etas.extend(custom.as_ref().map(MaterialSpec::eta));
    // A bare table: --eta with no material.
    let mut bare = Vec::new();
    match (etas.is_empty(), args.eta, &custom) {
        (true, Some(eta), _) => {
            super::check_range(
                "--eta",
                eta,
                bssrdf_zoo::medium::ETA_MIN..=bssrdf_zoo::medium::ETA_MAX,
            )?;
            bare.push(eta)
        }
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
    let custom_name = custom.as_ref().map(|c| c.id().to_string());
    let output = match (
        &args.output,
        materials.as_slice(),
        &custom_name,
        bare.as_slice(),
    ) {
        (Some(path), _, _, _) => path.clone(),
        (None, [one], None, _) => PathBuf::from(format!("{}.bssrdf", one.id())),
        (None, [], Some(name), _) => PathBuf::from(format!("{name}.bssrdf")),
        (None, [], None, [eta]) => PathBuf::from(format!("table-eta{eta}.bssrdf")),
        (None, _, _, _) => {
            return Err(CliError::input(
                "several materials go into one library: name it with -o FILE",
            ))
        }
    };
    check_output(&args, &output)?;

    materials.extend(custom);
    let baked = session
        .bake(false, |progress| {
            baker.bake(&materials, &bare, Some(progress))
        })?
        .map_err(bake_error)?;
    let tables = baked
        .tables()
        .iter()
        .map(|t| table_summary(t.index(), t.table(), t.rows()))
        .collect();
    let materials = baked
        .materials()
        .iter()
        .map(|m| {
            let (material, record) = (m.material(), m.record());
            json!({
                "name": record.name, "eta": record.eta, "tables": record.tables,
                "rho_prime": material.rho_prime(), "albedo_range": Value::Null,
            })
        })
        .collect();
    let accepted = session.verdict(&baked, args.accept_error)?;
    let bytes = session.write(baked.builder(), &output)?;
    let summary = Summary {
        output: &output,
        bytes,
        full_bytes: None,
        integrator: None,
        seconds: baked.seconds(),
        tables,
        materials,
        warnings: baked.warnings().iter().cloned().chain(accepted).collect(),
    };
    summary.print(&args, &session)?;
    Ok(ExitCode::SUCCESS)
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
        "lobes": if table.harmonics().is_some() { 2 } else { 1 },
    })
}

/// What a bake prints: a line on stderr, or with --json an object on stdout.
pub(super) struct Summary<'a> {
    pub output: &'a Path,
    pub bytes: u64,
    /// Size of the same materials baked in full (scene bakes).
    pub full_bytes: Option<u64>,
    pub integrator: Option<&'static str>,
    /// Wall-clock seconds of the tables' bakes.
    pub seconds: f64,
    pub tables: Vec<Value>,
    pub materials: Vec<Value>,
    pub warnings: Vec<String>,
}

impl Summary<'_> {
    pub fn print(&self, args: &BakeArgs, session: &Session) -> Result<(), CliError> {
        self.print_with(args, session.compressed())
    }

    /// [`Summary::print`], saying whether the file was written compressed.
    pub fn print_with(&self, args: &BakeArgs, compressed: bool) -> Result<(), CliError> {
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
                self.seconds
            )?;
            if let Some((full, saved, percent)) = saved {
                let compressed = if compressed { ", uncompressed" } else { "" };
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
                "seconds": self.seconds,
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
