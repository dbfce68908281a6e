//! `bssrdf sample FILE`: draws (r, φ) from a table for one (ρ′, θ), or the path-tracing
//! quadruple (θ, r, φ, φ′), as CSV on stdout. The columns are those `eval --points` reads
//! (`rho,theta_deg,r,phi_deg,pdf`, `r_mm` with --material, `phi_prime_deg` before `pdf` with
//! --path-tracing), so `bssrdf sample FILE … | bssrdf eval FILE --points -` works.

use super::library::{self, TableChoice};
use super::{show, CliError};
use bssrdf_zoo::format::Library;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct SampleArgs {
    /// Library file.
    file: PathBuf,
    /// Reduced albedo ρ′ in [0, 1] (not with --material, which gives it).
    #[arg(
        long,
        allow_hyphen_values = true,
        conflicts_with = "material",
        required_unless_present = "material"
    )]
    rho: Option<f64>,
    /// Incidence θ in degrees, in [0, 90] [default: 0] (not with --path-tracing, which samples
    /// θ).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "path_tracing")]
    theta: Option<f64>,
    /// Number of samples.
    #[arg(short = 'n', long, value_parser = super::values::whole::<u64>, default_value_t = 1000)]
    count: u64,
    /// Seed of the random stream (output is pinned for a seed).
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 0)]
    seed: u64,
    /// Draw (θ, r, φ, φ′) for path tracing (Ferrier algorithm 3).
    #[arg(long)]
    path_tracing: bool,
    #[command(flatten)]
    choice: TableChoice,
}

pub fn run(args: SampleArgs) -> Result<ExitCode, CliError> {
    let library = library::open(&args.file, args.choice.mmap)?;
    let chosen = args.choice.resolve(&library, &args.file)?;
    let view = chosen
        .table
        .view()
        .map_err(|e| CliError::input(e.to_string()))?;
    let (rho, scale) = match &chosen.material {
        Some((_, rho, st)) => (*rho, *st),
        None => (args.rho.unwrap_or_default(), 1.0),
    };
    let rho_name = if chosen.material.is_some() {
        "the material's rho'"
    } else {
        "--rho"
    };
    super::check_range(rho_name, rho, 0.0..=1.0)?;
    let theta_deg = args.theta.unwrap_or(0.0);
    super::check_range("--theta", theta_deg, 0.0..=90.0)?;
    // Both modes: nothing is written before ρ′ is known to be inside the kept rows.
    let table = (chosen.index, &view);
    super::values::check_kept(rho_name, rho, table, &chosen.siblings)?;
    if !args.path_tracing {
        super::values::check_theta_kept("--theta", theta_deg, &view)?;
    }
    let mut rng = SplitMix64::seed_from_u64(args.seed);
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let r_column = if chosen.material.is_some() {
        "r_mm"
    } else {
        "r"
    };
    if args.path_tracing && !view.has_theta_sampling() {
        return Err(CliError::input(format!(
            "{} {}: path tracing needs it",
            args.file.display(),
            no_theta_sampling(&library)
        )));
    }
    // One CSV row per draw; `None` where nothing can be drawn.
    let theta = theta_deg.to_radians();
    let draw = |rng: &mut SplitMix64| -> Option<String> {
        if args.path_tracing {
            let u = [
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
            ];
            let s = view.sample_path(rho, u)?;
            Some(format!(
                "{},{},{},{},{},{:e}",
                show(rho),
                s.theta.to_degrees(),
                s.r / scale,
                s.phi.to_degrees(),
                s.phi_prime.to_degrees(),
                s.pdf * scale * scale
            ))
        } else {
            let s = view.sample(rho, theta, rng.next_f64(), rng.next_f64())?;
            Some(format!(
                "{},{theta_deg},{},{},{:e}",
                show(rho),
                s.r / scale,
                s.phi.to_degrees(),
                s.pdf * scale * scale
            ))
        }
    };
    let refuse = || no_sample(rho, (!args.path_tracing).then_some(theta_deg));
    // The first draw before the header: a run that cannot sample writes nothing.
    let first = match args.count {
        0 => None,
        _ => Some(draw(&mut rng).ok_or_else(refuse)?),
    };
    if args.path_tracing {
        writeln!(out, "rho,theta_deg,{r_column},phi_deg,phi_prime_deg,pdf")?;
    } else {
        writeln!(out, "rho,theta_deg,{r_column},phi_deg,pdf")?;
    }
    if let Some(row) = first {
        writeln!(out, "{row}")?;
    }
    for _ in 1..args.count {
        let row = draw(&mut rng).ok_or_else(refuse)?;
        writeln!(out, "{row}")?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn no_sample(rho: f64, theta: Option<f64>) -> CliError {
    let rho = super::show(rho);
    CliError::input(match theta {
        Some(t) => format!("no light leaves at rho {rho}, theta {t}: nothing to sample (rho = 0 scatters nothing, and no light enters beyond the critical angle)"),
        None => format!("no light leaves at rho {rho}: nothing to sample"),
    })
}

/// Why a file has no theta-sampling table, as its provenance tells: a scene bake for particle
/// tracing keeps none, a plain bake drops it with --no-theta-sampling.
fn no_theta_sampling(library: &Library) -> &'static str {
    let settings = library.provenance().and_then(|p| p.get("settings"));
    let integrator = settings
        .and_then(|s| s.pointer("/scene/integrator"))
        .and_then(|i| i.as_str());
    let theta_sampling = settings
        .and_then(|s| s.get("theta_sampling"))
        .and_then(|t| t.as_bool());
    match (integrator, theta_sampling) {
        (Some("particle"), _) => {
            "was baked from a scene with integrator = \"particle\", which keeps no theta-sampling table (integrator = \"path\" keeps it)"
        }
        (_, Some(false)) => "was baked without the theta-sampling table (--no-theta-sampling)",
        _ => "has no theta-sampling table",
    }
}
