//! `bssrdf zoo`: every model against the Monte Carlo walk, error against run time.

use super::CliError;
use bssrdf_zoo::medium::{ETA_MAX, ETA_MIN};
use bssrdf_zoo::models::compare::{self, CompareConfig};
use bssrdf_zoo::models::ModelKind;
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct ZooArgs {
    /// Relative index of refraction η, in [0.75, 2.5].
    #[arg(long, default_value_t = 1.33)]
    eta: f64,
    /// Henyey–Greenstein g of the walk (the diffusion models see only ρ′).
    #[arg(long, default_value_t = 0.0)]
    g: f64,
    /// Photons per walk (one walk per case), in [2, 1e12].
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 1_000_000)]
    photons: u64,
    /// Seed of the reference walks.
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 1)]
    seed: u64,
    /// Models to compare (default: all; walk-table with --walk-table), comma-separated names.
    #[arg(long, value_enum, value_delimiter = ',')]
    models: Vec<ModelKind>,
    /// A library holding a walk-angular table (`bssrdf bake --source walk`) at this --eta and
    /// --g: the walk-table model compares it (a row per case, a point on the plots).
    #[arg(long, value_name = "FILE")]
    walk_table: Option<PathBuf>,
    /// Cases as RHO:THETA_DEG pairs, comma-separated (default: ρ′ 0.5, 0.9, 0.99 × θ 0, 60, 89).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "RHO:THETA",
        allow_hyphen_values = true
    )]
    cases: Vec<String>,
    /// Write SVG figures (error against time; profiles over the walk) into this folder.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
    /// Threads, in [1, 1024] (default: all cores); results do not depend on it.
    #[arg(long, value_parser = super::values::whole::<usize>)]
    threads: Option<usize>,
    /// One JSON object instead of the table.
    #[arg(long)]
    json: bool,
    /// No progress indicator or messages on stderr (the indicator only ever shows on a
    /// terminal).
    #[arg(long, short)]
    quiet: bool,
}

pub fn run(mut args: ZooArgs) -> Result<ExitCode, CliError> {
    super::check_range("--eta", args.eta, ETA_MIN..=ETA_MAX)?;
    super::check_g(args.g)?;
    // −0 is 0, and printed so
    args.g += 0.0;
    super::check_photons(args.photons)?;
    let mut config = CompareConfig::new(args.eta, args.g, args.photons, args.seed);
    if !args.models.is_empty() {
        if let Some((first, k)) = first_repeat(&args.models) {
            return Err(CliError::input(format!(
                "--models lists {} twice (at positions {} and {}); give each model once",
                args.models[k],
                first + 1,
                k + 1
            )));
        }
        config.models = args.models.clone();
    }
    match (&args.walk_table, config.models.contains(&ModelKind::WalkTable)) {
        (Some(path), listed) => {
            if !listed && !args.models.is_empty() {
                return Err(CliError::input(
                    "--walk-table gives the walk-table model its table; add walk-table to --models, or drop --walk-table",
                ));
            }
            if !listed {
                // Before the walk's own row, the reference's noise level, which ends the list
                let at = config.models.len().saturating_sub(1);
                config.models.insert(at, ModelKind::WalkTable);
            }
            config.options.walk_table = Some(std::sync::Arc::new(super::library::walk_table(
                "--walk-table",
                path,
                args.eta,
                args.g,
            )?));
        }
        (None, true) => {
            return Err(CliError::input(
                "the walk-table model needs its table: --walk-table FILE (bake one with `bssrdf bake --source walk --eta ETA --g G`)",
            ))
        }
        (None, false) => {}
    }
    if !args.cases.is_empty() {
        config.cases = args
            .cases
            .iter()
            .map(|c| parse_case(c))
            .collect::<Result<_, _>>()?;
        if let Some((first, k)) = first_repeat(&config.cases) {
            let (rho, theta) = config.cases[k];
            return Err(CliError::input(format!(
                "--cases lists {}:{} twice (at positions {} and {}); give each case once",
                super::show(rho),
                super::show(theta),
                first + 1,
                k + 1
            )));
        }
    }
    check_critical(&args, &config.cases)?;
    super::check_threads(args.threads)?;
    // The plots' folder is made now, not after the walks
    if let Some(dir) = &args.plot {
        if dir.exists() && !dir.is_dir() {
            return Err(CliError::input(format!(
                "--plot {} is a file, not a folder for the figures",
                dir.display()
            )));
        }
        // (a folder made now holds no figure yet: only an existing one is checked, first)
        if dir.is_dir() {
            check_plots(dir, args.walk_table.as_deref())?;
        }
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::input(format!("cannot create {}: {e}", dir.display())))?;
    }
    // Per case: its reference walk, then each model.
    let bar = super::progress::bar(
        compare::progress_steps(&config),
        "walks and models",
        args.quiet,
    );
    bar.set_message(format!(
        "{} case(s), {} photons",
        config.cases.len(),
        config.photons
    ));
    let report = super::with_threads(args.threads, || {
        compare::run_with_progress(&config, &|n| bar.inc(n))
    })??;
    bar.finish_and_clear();
    if let Some(dir) = &args.plot {
        let files = compare::write_svgs(&report, dir).map_err(|e| {
            CliError::input(format!("cannot write plots into {}: {e}", dir.display()))
        })?;
        if !args.quiet {
            let _ = writeln!(
                std::io::stderr(),
                "wrote {} figure(s) into {}",
                files.len(),
                dir.display()
            );
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        serde_json::to_writer(&mut out, &report).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        write!(out, "{}", report.markdown())?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// Refuses, before the walks, figures that could not be written or would overwrite the
/// --walk-table or stdout: `pareto.svg` and the profile figures already in the folder (the new
/// ones are named after the cases as the walks resolve them, `profiles-rho{ρ′}-theta{θ}.svg`).
fn check_plots(dir: &Path, walk_table: Option<&Path>) -> Result<(), CliError> {
    let mut figures = vec![dir.join("pareto.svg")];
    if let Ok(entries) = std::fs::read_dir(dir) {
        for entry in entries.flatten() {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            if name.starts_with("profiles-rho") && name.ends_with(".svg") {
                figures.push(entry.path());
            }
        }
    }
    let outputs: Vec<(&str, &Path)> = figures
        .iter()
        .map(|f| ("the --plot figure", f.as_path()))
        .collect();
    let inputs: Vec<(&str, &Path)> = walk_table
        .map(|t| ("--walk-table", t))
        .into_iter()
        .collect();
    // stdout redirected into the folder has made its file already: it is among those listed
    for (what, path) in &outputs {
        let instead = "redirect stdout outside the --plot folder";
        super::output::not_on_stdout(what, path, "its table (or --json report)", instead)?;
    }
    super::output::check(&outputs, &inputs)
}

/// Below η = 1 light enters only up to the critical angle asin η: refuses a case beyond it,
/// naming it (the default cases' 60° and 89° lie beyond it for η < 0.87 and η < 0.9998).
/// An η outside its domain is left to the comparison's own check.
fn check_critical(args: &ZooArgs, cases: &[(f64, f64)]) -> Result<(), CliError> {
    if !(0.75..1.0).contains(&args.eta) {
        return Ok(());
    }
    let critical = super::values::critical_deg(args.eta);
    match cases
        .iter()
        .find(|case| !super::values::enters(case.1, args.eta))
    {
        Some(&(rho, theta)) => Err(CliError::input(format!(
            "{} case {}:{} lies beyond the critical angle of --eta {}: light enters only up to asin(eta) = {} deg; give --cases with theta in [0, {}]",
            if args.cases.is_empty() {
                "the default"
            } else {
                "the --cases"
            },
            super::show(rho),
            super::show(theta),
            super::show(args.eta),
            // In full: the stated range is the one checked (rounded, it would be narrower)
            super::show(critical),
            super::show(critical),
        ))),
        None => Ok(()),
    }
}

/// The first item of `items` equal to an earlier one: (the earlier one's index, its index).
fn first_repeat<T: PartialEq>(items: &[T]) -> Option<(usize, usize)> {
    (0..items.len()).find_map(|k| {
        let first = items[..k].iter().position(|x| x == &items[k])?;
        Some((first, k))
    })
}

fn parse_case(text: &str) -> Result<(f64, f64), CliError> {
    let bad = || {
        CliError::input(format!(
            "--cases {text:?}: expected RHO:THETA_DEG, e.g. 0.9:60"
        ))
    };
    let (rho, theta) = text.split_once(':').ok_or_else(bad)?;
    let rho: f64 = rho.trim().parse().map_err(|_| bad())?;
    let theta: f64 = theta.trim().parse().map_err(|_| bad())?;
    super::check_range("--cases rho", rho, 0.0..=1.0)?;
    super::check_range("--cases theta", theta, 0.0..=90.0)?;
    Ok((rho, theta))
}
