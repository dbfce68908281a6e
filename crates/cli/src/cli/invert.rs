//! `bssrdf invert [FILE] --reflectance A|R,G,B [--theta DEG]`: the reduced albedo ρ′ whose
//! diffuse reflectance A = (1 − F_r(θ)) ρ_eff(ρ′, θ) on a table is the value given
//! (`TableRef::rho_prime_for_reflectance`, `table::reflectance` in the runtime). The table is
//! one of FILE (`--table`, `--eta`, else the first), or without FILE the one `bssrdf bake --eta E`
//! would make, baked in memory (`Baker::table`).

use super::bake::GridArg;
use super::eval::MomentsArg;
use super::library::{self, TableChoice};
use super::{check_range, show, CliError};
use bssrdf_zoo::bake::Baker;
use bssrdf_zoo::format::{WalkComponent, WalkSource};
use bssrdf_zoo::fresnel::{entry_transmittance, Moments};
use bssrdf_zoo::medium::{ETA_MAX, ETA_MIN};
use bssrdf_zoo::scene::DEFAULT_ETA;
use bssrdf_zoo::table::{GridPreset, ReflectanceError, TableRef};
use clap::Args;
use serde_json::json;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// One reflectance, or three (R,G,B).
#[derive(Debug, Clone, PartialEq)]
pub struct Reflectances(Vec<f64>);

/// Parses "A" or "R,G,B".
fn parse_reflectances(text: &str) -> Result<Reflectances, String> {
    let values = super::values::list::<f64>(text)?;
    match values.len() {
        1 | 3 => Ok(Reflectances(values)),
        n => Err(format!(
            "expected one number or 3 comma-separated numbers (R,G,B), got {n}"
        )),
    }
}

#[derive(Debug, Args)]
pub struct InvertArgs {
    /// Library file whose table to invert on. Without it, the table `bssrdf bake --eta E` would
    /// make is baked in memory (under a second on the default grid).
    file: Option<PathBuf>,
    /// The diffuse reflectance A wanted, one value or R,G,B: multiply scattered power leaving
    /// per unit power arriving at θ, the entry Fresnel transmittance included, in
    /// [A(first albedo row), A(last row)] of the table at θ ([0, 0.93] at θ = 0, η = 1.33).
    #[arg(long, value_name = "A|R,G,B", value_parser = parse_reflectances, allow_hyphen_values = true)]
    reflectance: Reflectances,
    /// Incidence θ before refraction, degrees in [0, 90].
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    theta: f64,
    /// η in [0.75, 2.5]: with FILE, selects its table with this η (refused when it has none);
    /// without, the η of the table baked (default 1.33).
    #[arg(long, allow_hyphen_values = true)]
    eta: Option<f64>,
    /// Index of the table in FILE (default: the one of --eta, else the first); only with FILE.
    #[arg(long, value_parser = super::values::whole::<usize>)]
    table: Option<usize>,
    /// Map FILE instead of reading it into memory; only with FILE.
    #[arg(long)]
    mmap: bool,
    /// Grid of the table baked without FILE [default: default].
    #[arg(long, value_enum)]
    grid: Option<GridArg>,
    /// Fresnel moments of the table baked without FILE [default: exact].
    #[arg(long, value_enum)]
    fresnel_moments: Option<MomentsArg>,
    /// Threads of the bake without FILE, in [1, 1024] (default: all cores); the result is
    /// identical on any count.
    #[arg(long, value_parser = super::values::whole::<usize>)]
    threads: Option<usize>,
    /// Print a JSON object on stdout (the table, T(θ), the range, ρ′ and ρ_eff per value).
    #[arg(long)]
    json: bool,
}

/// `--reflectance` or, for three values, `--reflectance[r]` … `[b]`.
fn name(count: usize, k: usize) -> String {
    if count == 1 {
        "--reflectance".to_string()
    } else {
        format!("--reflectance[{}]", ["r", "g", "b"][k])
    }
}

/// What a table's ρ_eff holds, as the refusal of a reflectance names it: multiple scattering
/// (PBD, a walk table of that component), or single scattering too (a walk table's total).
fn holds(walk: Option<WalkSource>) -> &'static str {
    match walk.map(|w| w.component) {
        Some(WalkComponent::Total) => "single and multiple scattering, the walk's total",
        _ => "multiple scattering only",
    }
}

/// The refusal of one value, in the command line's words; `walk`: the table's walk, if it was
/// measured from one.
fn refusal(
    flag: &str,
    theta_deg: f64,
    walk: Option<WalkSource>,
    error: ReflectanceError,
) -> CliError {
    CliError::input(match error {
        ReflectanceError::OutOfRange {
            reflectance,
            min,
            max,
            rho_min,
            rho_max,
            ..
        } => format!(
            "{flag} {} is outside the valid range: [{}, {}], the diffuse reflectance (1 - F_r) rho_eff this table reaches at --theta {} ({}; rho' from {} to {})",
            show(reflectance),
            show(min),
            show(max),
            show(theta_deg),
            holds(walk),
            show(rho_min),
            show(rho_max)
        ),
        ReflectanceError::NoLight { eta, .. } if eta < 1.0 && theta_deg < 90.0 => format!(
            "--theta {}: no light enters beyond the critical angle, asin(eta = {}): --theta at most {} deg; every rho' gives a diffuse reflectance of 0",
            show(theta_deg),
            show(eta),
            // The largest --theta that lets light in, as this command tests it
            show(super::values::last_degree(eta, |deg| {
                entry_transmittance(deg.to_radians(), eta) > 0.0
            }))
        ),
        ReflectanceError::NoLight { .. } => format!(
            "--theta {}: no light enters at grazing incidence: every rho' gives a diffuse reflectance of 0",
            show(theta_deg)
        ),
        other => format!("--theta {}: {other}", show(theta_deg)),
    })
}

pub fn run(args: InvertArgs) -> Result<ExitCode, CliError> {
    // Every value checked before any work: θ, η, each reflectance in [0, 1] (the table's own
    // range is known once it is read or baked), and the flags that need, or exclude, FILE.
    check_range("--theta", args.theta, 0.0..=90.0)?;
    if let Some(eta) = args.eta {
        check_range("--eta", eta, ETA_MIN..=ETA_MAX)?;
    }
    let count = args.reflectance.0.len();
    for (k, &a) in args.reflectance.0.iter().enumerate() {
        check_range(&name(count, k), a, 0.0..=1.0)?;
    }
    let with_file = [("--table", args.table.is_some()), ("--mmap", args.mmap)];
    let without_file = [
        ("--grid", args.grid.is_some()),
        ("--fresnel-moments", args.fresnel_moments.is_some()),
        ("--threads", args.threads.is_some()),
    ];
    match &args.file {
        None => {
            if let Some((flag, _)) = with_file.iter().find(|(_, on)| *on) {
                return Err(CliError::input(format!(
                    "{flag} chooses how to read a library FILE; give one, or drop {flag}"
                )));
            }
        }
        Some(_) => {
            if let Some((flag, _)) = without_file.iter().find(|(_, on)| *on) {
                return Err(CliError::input(format!(
                    "{flag} sets the table baked without a FILE; a FILE's table carries its own: drop {flag}"
                )));
            }
        }
    }
    super::check_threads(args.threads)?;
    let theta = args.theta.to_radians();
    match &args.file {
        Some(path) => {
            let file = library::open(path, args.mmap)?;
            let chosen =
                TableChoice::of_table(args.table, args.eta, args.mmap).resolve(&file, path)?;
            let view = chosen
                .table
                .view()
                .map_err(|e| CliError::input(e.to_string()))?;
            let moments = chosen.table.moments();
            let walk = chosen.table.record().walk();
            invert_and_print(&args, &view, moments, Some(chosen.index), walk, None)
        }
        None => {
            let eta = args.eta.unwrap_or(DEFAULT_ETA);
            if entry_transmittance(theta, eta) == 0.0 {
                return Err(refusal(
                    "--reflectance",
                    args.theta,
                    None,
                    ReflectanceError::NoLight { theta, eta },
                ));
            }
            let (preset, grid_name) = match args.grid.unwrap_or(GridArg::Default) {
                GridArg::Coarse => (GridPreset::Coarse, "coarse"),
                GridArg::Default => (GridPreset::Default, "default"),
                GridArg::Fine => (GridPreset::Fine, "fine"),
            };
            let moments: Moments = args.fresnel_moments.unwrap_or(MomentsArg::Exact).into();
            let baker = Baker::new(preset).with_moments(moments);
            let table = super::with_threads(args.threads, || baker.table(eta))?
                .map_err(|e| CliError::input(e.to_string()))?;
            invert_and_print(&args, &table.view(), moments, None, None, Some(grid_name))
        }
    }
}

/// Inverts every reflectance on `view` (all refused before anything is printed) and prints
/// ρ′, comma-separated, or the JSON object. `walk`: the walk a file's table was measured with.
fn invert_and_print(
    args: &InvertArgs,
    view: &TableRef<'_>,
    moments: Moments,
    table: Option<usize>,
    walk: Option<WalkSource>,
    grid: Option<&str>,
) -> Result<ExitCode, CliError> {
    let theta = args.theta.to_radians();
    let values = &args.reflectance.0;
    let refuse = |k: usize, e| refusal(&name(values.len(), k), args.theta, walk, e);
    let range = view.reflectance_range(theta).map_err(|e| refuse(0, e))?;
    let rho: Vec<f64> = values
        .iter()
        .enumerate()
        .map(|(k, &a)| {
            view.rho_prime_for_reflectance(a, theta)
                .map_err(|e| refuse(k, e))
        })
        .collect::<Result<_, _>>()?;
    // One line: the ρ′ values, or the JSON object.
    let line = if args.json {
        let rho_eff: Vec<Option<f64>> = rho
            .iter()
            .map(|&r| view.effective_albedo(r, theta))
            .collect();
        json!({
            "eta": view.eta(),
            "fresnel_moments": moments.name(),
            "table": table,
            "walk_component": walk.map(|w| w.component.name()),
            "grid": grid,
            "theta_deg": args.theta,
            "transmittance": entry_transmittance(theta, view.eta()),
            "range": range,
            "reflectance": values,
            "rho_prime": rho,
            "effective_albedo": rho_eff,
        })
        .to_string()
    } else {
        let text: Vec<String> = rho.iter().copied().map(show).collect();
        text.join(",")
    };
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    writeln!(out, "{line}")?;
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}
