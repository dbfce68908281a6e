//! `bssrdf bake`: bake angular tables (one per η) for named materials or a bare η, and write
//! them with the materials into one library file, atomically.

use super::eval::MomentsArg;
use super::CliError;
use bssrdf_zoo::format::{self, Compression, LibraryBuilder, Provenance};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{self, bake, AngularTable, Grid, GridPreset};
use clap::{Args, ValueEnum};
use serde_json::json;
use std::collections::BTreeMap;
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
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

#[derive(Debug, Args)]
pub struct BakeArgs {
    /// Named materials to bake (see `bssrdf materials`); their tables are shared by η.
    #[arg(value_name = "MATERIAL")]
    materials_named: Vec<String>,
    /// Bake a bare table for this η when no material is named.
    #[arg(long)]
    eta: Option<f64>,
    /// Output file (default: <material>.bssrdf for one material, table-eta<η>.bssrdf for --eta).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Grid preset.
    #[arg(long, value_enum, default_value = "default")]
    grid: GridArg,
    /// Fresnel moments of the boundary.
    #[arg(long, value_enum, default_value = "exact")]
    fresnel_moments: MomentsArg,
    /// Leave out the θ-sampling table (only path tracers need it).
    #[arg(long)]
    no_theta_sampling: bool,
    /// Compress sections with zstd (for distribution; such files are decoded, not mapped).
    #[arg(long)]
    compress: bool,
    /// Record the bake's wall-clock time in the provenance (the file then differs run to run).
    #[arg(long)]
    record_bake_time: bool,
    /// Extra material files (TOML file or folder).
    #[arg(long, value_name = "PATH")]
    materials: Option<PathBuf>,
    /// Threads (default: all cores); the result is identical on any count.
    #[arg(long)]
    threads: Option<usize>,
    /// No progress messages on stderr.
    #[arg(long, short)]
    quiet: bool,
}

/// Points per case of the accuracy check run at bake and stored in the provenance.
const BAKE_CHECK_SAMPLES: usize = 400;

pub fn run(args: BakeArgs) -> Result<ExitCode, CliError> {
    let moments: Moments = args.fresnel_moments.into();
    let library = super::materials::library(args.materials.as_deref())?;
    let materials = args
        .materials_named
        .iter()
        .map(|name| {
            library
                .get(name)
                .cloned()
                .map_err(|e| CliError::input(e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut etas: Vec<f64> = materials.iter().map(|m| m.eta()).collect();
    match (materials.is_empty(), args.eta) {
        (true, Some(eta)) => etas.push(eta),
        (true, None) => {
            return Err(CliError::input(
                "name at least one material (see `bssrdf materials`) or give --eta",
            ))
        }
        (false, Some(_)) => {
            return Err(CliError::input(
                "--eta bakes a bare table; materials bring their own eta: give one or the other",
            ))
        }
        (false, None) => {}
    }
    etas.sort_by(f64::total_cmp);
    etas.dedup();
    let output = match (&args.output, materials.as_slice()) {
        (Some(path), _) => path.clone(),
        (None, [one]) => PathBuf::from(format!("{}.bssrdf", one.id())),
        (None, []) => PathBuf::from(format!("table-eta{}.bssrdf", etas[0])),
        (None, _) => {
            return Err(CliError::input(
                "several materials go into one library: name it with -o FILE",
            ))
        }
    };
    let preset = match args.grid {
        GridArg::Coarse => GridPreset::Coarse,
        GridArg::Default => GridPreset::Default,
        GridArg::Fine => GridPreset::Fine,
    };
    let grid = Grid::preset(preset);
    let progress = !args.quiet && std::io::stderr().is_terminal();

    let mut builder = LibraryBuilder::new();
    let mut table_of_eta = BTreeMap::new();
    let mut accuracy = Vec::new();
    let mut seconds = 0.0;
    for (k, &eta) in etas.iter().enumerate() {
        if progress {
            eprint!("\rbaking table {}/{} (eta = {eta}) …", k + 1, etas.len());
        }
        let (table, report) = super::with_threads(args.threads, || {
            bake(eta, moments, &grid, !args.no_theta_sampling)
        })??;
        seconds += report.seconds;
        accuracy.push(bake_check(&table, eta, moments)?);
        let index = builder
            .add_table(table.to_table_data())
            .map_err(format_error)?;
        table_of_eta.insert(eta.to_bits(), index as u32);
    }
    if progress {
        eprintln!();
    }
    for m in &materials {
        let index = table_of_eta[&m.eta().to_bits()];
        builder
            .add_material(format::Material {
                name: m.id().to_string(),
                source: m
                    .source()
                    .map(|s| s.coefficients().chars().take(250).collect())
                    .unwrap_or_default(),
                sigma_s: m.sigma_s(),
                sigma_a: m.sigma_a(),
                g: m.g(),
                eta: m.eta(),
                tables: [index; 3],
                albedo_range: None,
            })
            .map_err(format_error)?;
    }
    let mut provenance = Provenance::new(concat!("bssrdf-zoo ", env!("CARGO_PKG_VERSION")))
        .with_settings(json!({
            "grid": format!("{preset:?}").to_lowercase(),
            "dims": [grid.rho.len(), grid.theta.len(), grid.r.len()],
            "fresnel_moments": format!("{moments:?}").to_lowercase(),
            "theta_sampling": !args.no_theta_sampling,
            "anchors_cos_phi": bssrdf_zoo::gwc::ANCHOR_COS,
        }))
        .and_then(|p| {
            p.with_quadrature(json!({
                "rule": "fast",
                "description": "composite 8-point Gauss-Legendre in u, t = t* + h sinh u, panels at the closest approach and at 3, 12, 46 nats of the exponent",
                "points_per_panel": bssrdf_zoo::pbd::FAST_POINTS_PER_PANEL,
            }))
        })
        .and_then(|p| p.with_accuracy(json!({ "tables": accuracy })))
        .map_err(format_error)?;
    if args.record_bake_time {
        provenance = provenance
            .with_bake_seconds(seconds)
            .map_err(format_error)?;
    }
    builder.set_provenance(provenance);
    let compression = if args.compress {
        Compression::Zstd {
            level: Compression::DEFAULT_ZSTD_LEVEL,
        }
    } else {
        Compression::None
    };
    builder
        .write_atomic(&output, compression)
        .map_err(|e| CliError::input(format!("cannot write {}: {e}", output.display())))?;
    if !args.quiet {
        let size = std::fs::metadata(&output).map(|m| m.len()).unwrap_or(0);
        let mut err = std::io::stderr().lock();
        writeln!(
            err,
            "wrote {} ({} table(s), {} material(s), {:.1} KiB) in {seconds:.2} s",
            output.display(),
            etas.len(),
            materials.len(),
            size as f64 / 1024.0
        )?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The table-2 protocol on a few hundred points per case: the accuracy stored at bake.
fn bake_check(
    table: &AngularTable,
    eta: f64,
    moments: Moments,
) -> Result<serde_json::Value, CliError> {
    let cases: Vec<(f64, f64)> = table::REPORT_TABLE_2.iter().map(|c| (c.0, c.1)).collect();
    let rows = table::validate(&table.view(), moments, &cases, BAKE_CHECK_SAMPLES, 1)?;
    let per_case: Vec<_> = rows
        .iter()
        .map(|r| json!({"rho": r.rho, "theta_deg": r.theta_deg, "mean_rel_error": r.mean_rel_error, "max_rel_error": r.max_rel_error}))
        .collect();
    Ok(json!({"eta": eta, "samples_per_case": BAKE_CHECK_SAMPLES, "seed": 1, "cases": per_case}))
}

pub fn format_error(e: format::FormatError) -> CliError {
    CliError::input(e.to_string())
}
