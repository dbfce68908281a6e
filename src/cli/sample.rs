//! `bssrdf sample FILE`: draws (r, φ) from a table for one (ρ′, θ), or the path-tracing
//! quadruple (θ, r, φ, φ′), as CSV on stdout. The columns are those `eval --points` reads
//! (`rho,theta_deg,r,phi_deg,pdf`, `r_mm` with --material, `phi_prime_deg` before `pdf` with
//! --path-tracing), so `bssrdf sample FILE … | bssrdf eval FILE --points -` works.

use super::library::{self, TableChoice};
use super::CliError;
use bssrdf_zoo::rng::SplitMix64;
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
    #[arg(short = 'n', long, default_value_t = 1000)]
    count: u64,
    /// Seed of the random stream (output is pinned for a seed).
    #[arg(long, default_value_t = 0)]
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
    super::values::check_kept(rho_name, rho, &view)?;
    let mut rng = SplitMix64::new(args.seed);
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let r_column = if chosen.material.is_some() {
        "r_mm"
    } else {
        "r"
    };
    if args.path_tracing {
        if !view.has_theta_sampling() {
            return Err(CliError::input(format!(
                "{} was baked without the theta-sampling table (--no-theta-sampling): path tracing needs it",
                args.file.display()
            )));
        }
        writeln!(out, "rho,theta_deg,{r_column},phi_deg,phi_prime_deg,pdf")?;
        for _ in 0..args.count {
            let u = [
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
                rng.next_f64(),
            ];
            match view.sample_path(rho, u) {
                Some(s) => writeln!(
                    out,
                    "{rho},{},{},{},{},{:e}",
                    s.theta.to_degrees(),
                    s.r / scale,
                    s.phi.to_degrees(),
                    s.phi_prime.to_degrees(),
                    s.pdf * scale * scale
                )?,
                None => return no_sample(rho, None),
            }
        }
    } else {
        let theta = theta_deg.to_radians();
        writeln!(out, "rho,theta_deg,{r_column},phi_deg,pdf")?;
        for _ in 0..args.count {
            match view.sample(rho, theta, rng.next_f64(), rng.next_f64()) {
                Some(s) => writeln!(
                    out,
                    "{rho},{theta_deg},{},{},{:e}",
                    s.r / scale,
                    s.phi.to_degrees(),
                    s.pdf_area * scale * scale
                )?,
                None => return no_sample(rho, Some(theta_deg)),
            }
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn no_sample(rho: f64, theta: Option<f64>) -> Result<ExitCode, CliError> {
    Err(CliError::input(match theta {
        Some(t) => format!("no light leaves at rho {rho}, theta {t}: nothing to sample (rho = 0, or beyond the critical angle)"),
        None => format!("no light leaves at rho {rho}: nothing to sample"),
    }))
}
