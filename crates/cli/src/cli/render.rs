//! `bssrdf render`: a picture of a beam entering a semi-infinite slab (Ferrier's figure 10) as
//! an EXR with a PNG preview beside it, and `--diff` / `--compare` for signed luminance
//! differences (figure 1c). All the work is in `bssrdf_zoo::render`.

use super::CliError;
use bssrdf_zoo::materials::{Material, Rgb};
use bssrdf_zoo::models::ModelKind;
use bssrdf_zoo::render::{
    self, difference, Band, Config, Difference, Orders, Part, Render, Renderer,
};
use bssrdf_zoo::table::GridPreset;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use std::io::Write;
use std::ops::Bound;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// The registry's models a render can draw ([`render::MODELS`]) as command-line values, with
/// the registry's help for each.
fn render_model() -> impl TypedValueParser<Value = ModelKind> {
    PossibleValuesParser::new(render::MODELS.iter().filter_map(|m| m.to_possible_value()))
        .try_map(|name: String| name.parse::<ModelKind>())
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Preset {
    /// Ferrier's figure 10: σs = 1, σa = (0.01, 0.1, 1) mm⁻¹, g = 0, η = 1.33.
    #[value(name = "figure-10")]
    Figure10,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum GridArg {
    Coarse,
    Default,
    Fine,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum OrdersArg {
    /// Single and multiple scattering.
    All,
    /// Multiple scattering only (like the diffusion models).
    Multiple,
}

#[derive(Debug, Args)]
#[command(group = clap::ArgGroup::new("medium").args(["material", "preset", "sigma_s"]))]
pub struct RenderArgs {
    /// A named material (`bssrdf materials`).
    #[arg(long)]
    material: Option<String>,
    /// A built-in medium.
    #[arg(long, value_enum)]
    preset: Option<Preset>,
    /// Scattering coefficients σs per channel, mm⁻¹ (with --sigma-a, --eta, --g).
    #[arg(long, value_name = "R,G,B", value_parser = rgb, requires = "sigma_a",
          allow_hyphen_values = true)]
    sigma_s: Option<[f64; 3]>,
    /// Absorption coefficients σa per channel, mm⁻¹.
    #[arg(long, value_name = "R,G,B", value_parser = rgb, requires = "sigma_s",
          conflicts_with_all = ["material", "preset"], allow_hyphen_values = true)]
    sigma_a: Option<[f64; 3]>,
    /// Relative index of refraction η in [0.75, 2.5] with --sigma-s [default: 1.33].
    #[arg(long, requires = "sigma_s", conflicts_with_all = ["material", "preset"])]
    eta: Option<f64>,
    /// Henyey–Greenstein g of every channel with --sigma-s, in (−1, 1) [default: 0].
    #[arg(long, requires = "sigma_s", conflicts_with_all = ["material", "preset"])]
    g: Option<f64>,
    /// Extra material files (TOML file or folder) for --material.
    #[arg(long, value_name = "PATH")]
    materials: Option<PathBuf>,
    /// Incidence of the beam before refraction, degrees in [0, 90).
    #[arg(long, required_unless_present = "diff")]
    theta: Option<f64>,
    /// How exit points are placed.
    #[arg(long, value_parser = render_model(), default_value = "table")]
    model: ModelKind,
    /// Also render this model with the same settings and write the difference (-o's stem
    /// plus `-MODEL.exr` and `-diff.exr`).
    #[arg(long, value_parser = render_model())]
    compare: Option<ModelKind>,
    /// Photons traced, in [2, 1e12].
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 1_000_000)]
    photons: u64,
    /// Picture size in pixels, each side a whole number in [1, 4096].
    #[arg(long, value_name = "W,H", value_parser = size, default_value = "256,256",
          allow_hyphen_values = true)]
    size: (usize, usize),
    /// Width of the picture along the plane of incidence, mm (square pixels), in (0, 1e6]: wider,
    /// a pixel's exitance (power over its area) underflows the picture's f32.
    #[arg(long, value_name = "MM", default_value_t = 10.0)]
    extent: f64,
    /// Half-angle of the cone of incident light, degrees in [0, 90) (0: collimated), with
    /// --theta + --cone below 90 (grazing light does not enter).
    #[arg(long, value_name = "DEG", default_value_t = 1.0)]
    cone: f64,
    /// Seed of the per-photon streams (the picture does not depend on the thread count).
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 0)]
    seed: u64,
    /// A library holding a walk-angular table (`bssrdf bake --source walk`) at the material's η
    /// and g (the same in every channel), for the walk-table model.
    #[arg(long, value_name = "FILE")]
    walk_table: Option<PathBuf>,
    /// Grid of the table baked for the material's η (not with --model mc or walk-table alone)
    /// [default: default].
    #[arg(long, value_enum)]
    grid: Option<GridArg>,
    /// What the mc model puts in the picture (its statistics keep both; only with mc as
    /// --model or --compare) [default: all].
    #[arg(long, value_enum)]
    orders: Option<OrdersArg>,
    /// Instead of rendering: the signed luminance difference A − B of two renders.
    #[arg(
        long,
        num_args = 2,
        value_names = ["A.exr", "B.exr"],
        conflicts_with_all = [
            "medium", "compare", "theta", "model", "photons", "size", "extent", "cone", "seed",
            "grid", "orders", "threads", "decades", "materials", "walk_table",
        ]
    )]
    diff: Option<Vec<PathBuf>>,
    /// Output EXR (a PNG preview is written beside it).
    #[arg(short, long, value_name = "OUT.exr")]
    output: PathBuf,
    /// Write no PNG previews.
    #[arg(long)]
    no_preview: bool,
    /// Decades of exitance below the brightest pixel that the PNG preview shows (log scale),
    /// > 0.
    #[arg(long, default_value_t = render::png::DECADES, conflicts_with = "no_preview")]
    decades: f64,
    /// Threads, in [1, 1024] (default: all cores).
    #[arg(long, value_parser = super::values::whole::<usize>)]
    threads: Option<usize>,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
    /// One JSON object instead of the summary.
    #[arg(long)]
    json: bool,
}

/// The widest picture, mm: a kilometre. At 1e21 mm an 8 × 8 picture's pixels, 1.6e40 mm²
/// each, held exitances below f32's smallest number and the picture was all 0 while its
/// summary put the light in it; at 1e6 mm and 4096 pixels a side a pixel is 6e10 mm², and the
/// exitance of all the power in it, 1.7e-11 mm⁻², is far from f32's limits.
const MAX_EXTENT_MM: f64 = 1e6;

/// `R,G,B` as three numbers (clap reports the error with exit code 2).
fn rgb(s: &str) -> Result<[f64; 3], String> {
    super::values::exactly(s, "R,G,B")
}

/// `W,H` as two whole numbers of pixels, each in [1, `render::MAX_SIDE`].
fn size(s: &str) -> Result<(usize, usize), String> {
    let [w, h] = super::values::exactly::<f64, 2>(s, "W,H (whole numbers of pixels)")?;
    // (`exactly` took two values: the sides as typed, for the message)
    let typed: Vec<&str> = s.split(',').map(str::trim).collect();
    let max = bssrdf_zoo::render::MAX_SIDE;
    let side = |x: f64, typed: &str| {
        if x.fract() == 0.0 && (1.0..=max as f64).contains(&x) {
            Ok(x as usize)
        } else {
            Err(format!(
                "each side is a whole number of pixels in [1, {max}], not {typed}"
            ))
        }
    };
    Ok((side(w, typed[0])?, side(h, typed[1])?))
}

fn input(e: impl std::fmt::Display) -> CliError {
    CliError::input(e.to_string())
}

pub fn run(args: RenderArgs) -> Result<ExitCode, CliError> {
    super::check_range(
        "--decades",
        args.decades,
        (Bound::Excluded(0.0), Bound::Unbounded),
    )?;
    check_outputs(&args)?;
    if let Some(files) = &args.diff {
        return run_diff(&args, files);
    }
    super::check_photons(args.photons)?;
    check_used(&args)?;
    let material = material(&args)?;
    let mut config = config(&args, args.model)?;
    check_light_enters(&args, material.eta())?;
    config.walk_table = walk_table(&args, &material)?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let (main, main_files) = render_one(&args, &config, &material, &args.output)?;
    let mut report = serde_json::json!({ "render": summary_json(&main, &main_files) });
    if !args.json {
        print_summary(&mut out, &main, &main_files)?;
    }
    if let Some(other) = args.compare {
        let other_config = Config {
            model: other,
            ..config.clone()
        };
        let other_path = sibling(&args.output, other.name());
        let (second, second_files) = render_one(&args, &other_config, &material, &other_path)?;
        let diff = difference(&main.0.picture, &second.0.picture).map_err(input)?;
        let diff_files = write_diff(&args, &diff, &sibling(&args.output, "diff"))?;
        if args.json {
            report["compare"] = summary_json(&second, &second_files);
            report["difference"] = diff_json(&diff, &diff_files);
        } else {
            writeln!(out)?;
            print_summary(&mut out, &second, &second_files)?;
            writeln!(out)?;
            print_diff(&mut out, &diff, &diff_files)?;
        }
    }
    if args.json {
        writeln!(out, "{report}")?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn material(args: &RenderArgs) -> Result<Material, CliError> {
    if let Some(name) = &args.material {
        return super::materials::named(name, args.materials.as_deref());
    }
    if args.preset == Some(Preset::Figure10) {
        return Ok(render::figure_10_material());
    }
    match (&args.sigma_s, &args.sigma_a) {
        (Some(s), Some(a)) => {
            let g = args.g.unwrap_or(0.0);
            let eta = args.eta.unwrap_or(1.33);
            Material::from_coefficients("coefficients", *s, *a, [g; 3], eta).map_err(input)
        }
        _ => Err(CliError::input(
            "give a medium: --material NAME, --preset figure-10, or --sigma-s R,G,B --sigma-a R,G,B",
        )),
    }
}

fn config(args: &RenderArgs, model: ModelKind) -> Result<Config, CliError> {
    let theta = args.theta.unwrap_or(0.0);
    super::check_range("--theta", theta, 0.0..90.0)?;
    super::check_range("--cone", args.cone, 0.0..90.0)?;
    if theta + args.cone >= 90.0 {
        return Err(CliError::input(format!(
            "--theta {} plus --cone {} reaches 90 deg, where grazing light does not enter: keep their sum below 90",
            super::show(theta),
            super::show(args.cone)
        )));
    }
    super::check_range(
        "--extent",
        args.extent,
        (Bound::Excluded(0.0), Bound::Included(MAX_EXTENT_MM)),
    )?;
    if args.compare == Some(args.model) {
        return Err(CliError::input(format!(
            "--compare {0} is the --model: a picture compared with itself; give another model",
            args.model.name()
        )));
    }
    let config = Config {
        model,
        // (−0 is 0, and printed so)
        theta: (theta + 0.0).to_radians(),
        cone: (args.cone + 0.0).to_radians(),
        photons: args.photons,
        seed: args.seed,
        width: args.size.0,
        height: args.size.1,
        extent: args.extent,
        grid: match args.grid.unwrap_or(GridArg::Default) {
            GridArg::Coarse => GridPreset::Coarse,
            GridArg::Default => GridPreset::Default,
            GridArg::Fine => GridPreset::Fine,
        },
        orders: match args.orders.unwrap_or(OrdersArg::All) {
            OrdersArg::All => Orders::All,
            OrdersArg::Multiple => Orders::Multiple,
        },
        walk_table: None,
    };
    config.validate().map_err(input)?;
    Ok(config)
}

/// Refuses a beam of which no part enters (η < 1, the whole cone beyond the critical angle):
/// its picture would be black, where `walk`, `zoo` and `invert` refuse such an incidence.
fn check_light_enters(args: &RenderArgs, eta: f64) -> Result<(), CliError> {
    let theta = args.theta.unwrap_or(0.0);
    let lowest = (theta - args.cone).max(0.0);
    if super::values::enters(lowest, eta) {
        return Ok(());
    }
    Err(CliError::input(format!(
        "--theta {} with --cone {} lies beyond the critical angle of eta {}, asin(eta) = {} deg: no light enters; keep --theta - --cone at most that",
        super::show(theta),
        super::show(args.cone),
        super::show(eta),
        super::show(super::values::critical_deg(eta))
    )))
}

/// Refuses --materials without --material, --sigma-a, --eta and --g without --sigma-s, and
/// --grid and --orders where no model of the run uses them (the rest of the combinations clap
/// refuses; its `requires` does not fire when the required flag is in a group with one given).
fn check_used(args: &RenderArgs) -> Result<(), CliError> {
    let coefficients = [
        ("--sigma-a", args.sigma_a.is_some()),
        ("--eta", args.eta.is_some()),
        ("--g", args.g.is_some()),
    ];
    if let Some((flag, _)) = coefficients.iter().find(|(_, on)| *on) {
        if args.sigma_s.is_none() {
            return Err(CliError::input(format!(
                "{flag} describes a medium given by --sigma-s/--sigma-a; give those, or drop {flag}"
            )));
        }
    }
    if args.materials.is_some() && args.material.is_none() {
        return Err(CliError::input(
            "--materials adds files to look --material up in; give --material NAME, or drop --materials",
        ));
    }
    let models: Vec<ModelKind> = std::iter::once(args.model).chain(args.compare).collect();
    let mc = models.contains(&ModelKind::MonteCarlo);
    if args.orders.is_some() && !mc {
        return Err(CliError::input(
            "--orders applies to the mc model only (--model mc or --compare mc); the other models picture multiple scattering",
        ));
    }
    let bakes = |m: &&ModelKind| !matches!(m, ModelKind::MonteCarlo | ModelKind::WalkTable);
    if args.grid.is_some() && !models.iter().any(|m| bakes(&m)) {
        return Err(CliError::input(
            "--grid applies to the table models a render bakes tables for; the mc model bakes none, and the walk-table model's table has its own grid",
        ));
    }
    match (args.walk_table.is_some(), models.contains(&ModelKind::WalkTable)) {
        (true, false) => Err(CliError::input(
            "--walk-table gives the walk-table model its table: add --model walk-table or --compare walk-table, or drop --walk-table",
        )),
        (false, true) => Err(CliError::input(
            "the walk-table model needs its table: --walk-table FILE (bake one with `bssrdf bake --source walk --eta ETA --g G` at the material's eta and g)",
        )),
        _ => Ok(()),
    }
}

/// The walk table of --walk-table at the material's η and g (every channel's, which must be
/// one), if given.
fn walk_table(
    args: &RenderArgs,
    material: &Material,
) -> Result<Option<std::sync::Arc<bssrdf_zoo::table::AngularTable>>, CliError> {
    let Some(path) = &args.walk_table else {
        return Ok(None);
    };
    let g = material.channel(Rgb::ALL[0]).g();
    if Rgb::ALL.iter().any(|&c| material.channel(c).g() != g) {
        return Err(CliError::input(format!(
            "the material's g differs between channels ({:?}): a walk table holds one g, so the walk-table model draws media of one g only",
            Rgb::ALL.map(|c| material.channel(c).g())
        )));
    }
    let table = super::library::walk_table("--walk-table", path, material.eta(), g)?;
    Ok(Some(std::sync::Arc::new(table)))
}

/// Refuses a run whose outputs (the EXRs and their PNG previews) would overwrite one another
/// or an input (`--diff`'s pictures, `--materials`, `--walk-table`), before any work.
fn check_outputs(args: &RenderArgs) -> Result<(), CliError> {
    // A device or FIFO is written through, but the files named after it (previews, --compare
    // pictures) would land beside it, e.g. /dev/null.png.
    let special = std::fs::metadata(&args.output).is_ok_and(|m| !m.is_file());
    if special && (!args.no_preview || args.compare.is_some()) {
        return Err(CliError::input(format!(
            "-o {} is not a regular file: the PNG preview and --compare pictures are named after it; write to a file, or add --no-preview (without --compare)",
            args.output.display()
        )));
    }
    let mut exrs = vec![("-o", args.output.clone())];
    if let Some(other) = args.compare {
        exrs.push(("the --compare render", sibling(&args.output, other.name())));
        exrs.push(("the difference picture", sibling(&args.output, "diff")));
    }
    let mut outputs = Vec::new();
    for (what, exr) in exrs {
        if !args.no_preview {
            outputs.push((what, exr.with_extension("png"), true));
        }
        outputs.push((what, exr, false));
    }
    let named: Vec<(String, PathBuf)> = outputs
        .into_iter()
        .map(|(what, path, png)| {
            let what = if png {
                format!("{what}'s PNG preview")
            } else {
                what.to_string()
            };
            (what, path)
        })
        .collect();
    let outputs: Vec<(&str, &Path)> = named
        .iter()
        .map(|(w, p)| (w.as_str(), p.as_path()))
        .collect();
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(files) = &args.diff {
        inputs.extend(files.iter().map(|f| ("--diff", f.as_path())));
    }
    let material_files = super::materials::input_files(args.materials.as_deref());
    for file in &material_files {
        inputs.push(("--materials", file.as_path()));
    }
    if let Some(table) = &args.walk_table {
        inputs.push(("--walk-table", table.as_path()));
    }
    for (what, path) in &outputs {
        let instead = "write the picture to a file";
        super::output::not_on_stdout(what, path, "its summary", instead)?;
    }
    super::output::check(&outputs, &inputs)
}

/// `dir/stem.exr` → `dir/stem-suffix.exr`.
fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy());
    path.with_file_name(format!("{stem}-{suffix}.exr"))
}

/// A render with its wall-clock seconds and thread count.
type Timed = (Render, f64, usize);

fn render_one(
    args: &RenderArgs,
    config: &Config,
    material: &Material,
    path: &Path,
) -> Result<(Timed, Vec<PathBuf>), CliError> {
    let work = || -> Result<Timed, CliError> {
        let renderer = Renderer::new(config, material).map_err(input)?;
        let bar = super::progress::bar(config.photons, "photons", args.quiet);
        bar.set_message(config.model.name());
        let start = Instant::now();
        let result = renderer.run(&|n| bar.inc(n));
        bar.finish_and_clear();
        Ok((
            result,
            start.elapsed().as_secs_f64(),
            rayon::current_num_threads(),
        ))
    };
    let timed = super::with_threads(args.threads, work)??;
    let mut files = vec![path.to_path_buf()];
    render::exr::write_rgb(path, &timed.0.picture).map_err(input)?;
    if !args.no_preview {
        let png = path.with_extension("png");
        render::png::write_preview(&png, &timed.0.picture, args.decades).map_err(input)?;
        files.push(png);
    }
    Ok((timed, files))
}

fn write_diff(args: &RenderArgs, diff: &Difference, path: &Path) -> Result<Vec<PathBuf>, CliError> {
    render::exr::write_luminance(path, diff.frame(), diff.values(), diff.meta()).map_err(input)?;
    let mut files = vec![path.to_path_buf()];
    if !args.no_preview {
        let png = path.with_extension("png");
        render::png::write_difference_preview(&png, diff.frame(), diff.values()).map_err(input)?;
        files.push(png);
    }
    Ok(files)
}

fn run_diff(args: &RenderArgs, files: &[PathBuf]) -> Result<ExitCode, CliError> {
    let (Some(a), Some(b)) = (files.first(), files.get(1)) else {
        return Err(CliError::input("--diff needs two files: A.exr B.exr"));
    };
    let pa = render::exr::read_picture(a).map_err(input)?;
    let pb = render::exr::read_picture(b).map_err(input)?;
    let diff = difference(&pa, &pb).map_err(input)?;
    let written = write_diff(args, &diff, &args.output)?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        writeln!(out, "{}", diff_json(&diff, &written))?;
    } else {
        print_diff(&mut out, &diff, &written)?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn names(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_summary(out: &mut impl Write, timed: &Timed, files: &[PathBuf]) -> std::io::Result<()> {
    let (r, seconds, threads) = timed;
    let s = &r.stats;
    let get = |k: &str| {
        r.picture
            .get(&format!("bssrdf:{k}"))
            .unwrap_or("?")
            .to_string()
    };
    writeln!(
        out,
        "{} model, {}, theta {} deg (cone {} deg), {} photons, seed {}: {:.2} s on {} threads ({:.0} photons/s/thread)",
        get("model"),
        get("material"),
        get("theta_deg"),
        get("cone_deg"),
        s.photons,
        get("seed"),
        seconds,
        threads,
        s.photons as f64 / seconds.max(1e-9) / *threads as f64
    )?;
    writeln!(
        out,
        "reflected at entry (Fresnel, not imaged): {:.6} ± {:.6} of the incident power",
        s.reflected.value, s.reflected.stderr
    )?;
    writeln!(
        out,
        "{:<19} {:>22} {:>10} {:>10} {:>24} {:>24}",
        "exits per unit", "power", "expected", "in picture", "centroid x (mm)", "centroid y (mm)"
    )?;
    // A total walk table's exits are single and multiple scattering together
    let parts: &[Part] = if !s.split {
        &[Part::Total]
    } else if s.get(Part::Single, Band::Luminance).power.value > 0.0 {
        &[Part::Single, Part::Multiple, Part::Total]
    } else {
        &[Part::Multiple]
    };
    for &part in parts {
        for (i, band) in Band::ALL.into_iter().enumerate() {
            let b = s.get(part, band);
            let expected = match (part, s.expected) {
                (Part::Multiple | Part::Total, Some(e)) if i < 3 => format!("{:.6}", e[i]),
                (Part::Multiple | Part::Total, Some(e)) => format!("{:.6}", e.iter().sum::<f64>()),
                _ => "-".to_string(),
            };
            let in_picture = if part == parts[parts.len() - 1] {
                format!("{:.6}", s.in_picture[i])
            } else {
                "-".to_string()
            };
            writeln!(
                out,
                "{:<19} {:>10.6} ± {:<9.6} {:>10} {:>10} {} {}",
                format!("{} {}", render::part_name(part), render::band_name(band)),
                b.power.value,
                b.power.stderr,
                expected,
                in_picture,
                centroid_cell(b.centroid_x_mm),
                centroid_cell(b.centroid_y_mm)
            )?;
        }
    }
    if s.scattering_events > 0 {
        writeln!(out, "scattering events: {}", s.scattering_events)?;
    }
    if s.lost_samples > 0 {
        writeln!(
            out,
            "photons whose exit could not be sampled: {}",
            s.lost_samples
        )?;
    }
    writeln!(out, "wrote {}", names(files))
}

fn summary_json(timed: &Timed, files: &[PathBuf]) -> serde_json::Value {
    let (r, seconds, threads) = timed;
    let meta: serde_json::Map<String, serde_json::Value> = r
        .picture
        .meta()
        .iter()
        .map(|(k, v)| {
            let key = k.trim_start_matches(render::META_PREFIX);
            (key.to_string(), meta_value(key, v))
        })
        .collect();
    serde_json::json!({
        "meta": meta,
        "stats": r.stats,
        "seconds": seconds,
        "threads": threads,
        "files": files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
    })
}

fn print_diff(out: &mut impl Write, d: &Difference, files: &[PathBuf]) -> std::io::Result<()> {
    writeln!(
        out,
        "difference A - B of luminance R+G+B (B the reference): relative L1 {:.6}, relative L2 {:.6}",
        d.relative_l1, d.relative_l2
    )?;
    writeln!(
        out,
        "centroid x in the picture: A {:.5} mm, B {:.5} mm, shift A - B {:.5} mm",
        d.centroid_a_mm,
        d.centroid_b_mm,
        d.centroid_shift_mm()
    )?;
    writeln!(out, "wrote {}", names(files))
}

/// A centroid column of the text summary: value ± standard error, or "none" where no light
/// leaves the surface (its centroid is undefined; `--json` gives null).
fn centroid_cell(c: bssrdf_zoo::walk::Estimate) -> String {
    if c.value.is_finite() && c.stderr.is_finite() {
        format!("{:>10.5} ± {:<11.5}", c.value, c.stderr)
    } else {
        format!("{:>10}   {:<11}", "none", "")
    }
}

/// How the JSON summary types each metadata key of a render: fixed per key, never guessed
/// from the text (a material id "1e3" stays a string; a u64 seed stays exact).
#[derive(Clone, Copy)]
enum MetaKind {
    Count,
    Number,
    Text,
}

fn meta_kind(key: &str) -> MetaKind {
    match key {
        "photons" | "seed" => MetaKind::Count,
        "theta_deg" | "cone_deg" | "extent_mm" | "eta" | "reflected_at_entry" | "centroid_x_mm" => {
            MetaKind::Number
        }
        _ => MetaKind::Text,
    }
}

/// A picture's metadata value in JSON, typed by its key ([`meta_kind`]); a number the text
/// does not hold (never written by this program) is null.
fn meta_value(key: &str, text: &str) -> serde_json::Value {
    match meta_kind(key) {
        MetaKind::Count => text
            .parse::<u64>()
            .map_or(serde_json::Value::Null, |n| serde_json::json!(n)),
        MetaKind::Number => match text.parse::<f64>() {
            Ok(v) if v.is_finite() => serde_json::json!(v),
            _ => serde_json::Value::Null,
        },
        MetaKind::Text => serde_json::json!(text),
    }
}

fn diff_json(d: &Difference, files: &[PathBuf]) -> serde_json::Value {
    serde_json::json!({
        "relative_l1": d.relative_l1,
        "relative_l2": d.relative_l2,
        "centroid_a_mm": d.centroid_a_mm,
        "centroid_b_mm": d.centroid_b_mm,
        "centroid_shift_mm": d.centroid_shift_mm(),
        "files": files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
    })
}
