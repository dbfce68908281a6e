//! `bssrdf walk`: the Monte Carlo random walk alone (unreduced single-scattering albedo and g:
//! the walk is the physics, not a model of it).

use super::CliError;
use bssrdf_zoo::medium::{ETA_MAX, ETA_MIN};
use bssrdf_zoo::walk::bins::{MAX_PHI, MAX_RADIAL};
use bssrdf_zoo::walk::{self, Bins, Config, Geometry};
use clap::Args;
use std::io::Write;
use std::ops::Bound;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct WalkArgs {
    /// Single-scattering albedo σs/σt (unreduced), in [0, 1].
    #[arg(long)]
    albedo: f64,
    /// Henyey–Greenstein g, in (−1, 1).
    #[arg(long, default_value_t = 0.0)]
    g: f64,
    /// Relative index of refraction η (medium over outside), in [0.75, 2.5].
    #[arg(long, default_value_t = 1.33)]
    eta: f64,
    /// Incidence angle θ before refraction, degrees in [0, 90] (at 90°, the limit of grazing
    /// light: the walk counts per unit power entering).
    #[arg(long, default_value_t = 0.0)]
    theta: f64,
    /// Number of photons entering the medium, in [2, 1e12] (a standard error needs two).
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 1_000_000)]
    photons: u64,
    /// Seed of the per-photon random streams (results do not depend on the thread count).
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 0)]
    seed: u64,
    /// A slab of this optical thickness instead of a half-space.
    #[arg(long, value_name = "TAU")]
    slab: Option<f64>,
    /// Bins of the profile: r_min,r_max in mean free paths (1e-150 <= r_min < r_max <= 1e150), then the
    /// radial and φ bin counts, whole numbers in [1, 10000] and [1, 3600], with
    /// (radial + 1) × φ ≤ 262144. With --profile, which writes the binned profile, or --json,
    /// which gives the bins and the reflectance inside them (binned_reflectance).
    #[arg(long, value_name = "R_MIN,R_MAX,NR,NPHI", value_parser = parse_bins,
          allow_hyphen_values = true)]
    bins: Option<[f64; 4]>,
    /// Write the binned exitance R(r, φ) with standard errors to this CSV file.
    #[arg(long, value_name = "OUT.csv")]
    profile: Option<PathBuf>,
    /// Threads, in [1, 1024] (default: all cores).
    #[arg(long, value_parser = super::values::whole::<usize>)]
    threads: Option<usize>,
    /// One JSON object instead of the summary.
    #[arg(long)]
    json: bool,
    /// No progress bar (it only ever shows on a terminal).
    #[arg(long, short)]
    quiet: bool,
}

/// Parses "R_MIN,R_MAX,NR,NPHI": exactly four comma-separated numbers.
fn parse_bins(text: &str) -> Result<[f64; 4], String> {
    super::values::exactly(text, "R_MIN,R_MAX,NR,NPHI")
}

pub fn run(mut args: WalkArgs) -> Result<ExitCode, CliError> {
    // The walk's own checks name its parameters; these name the flags
    super::check_range("--albedo", args.albedo, 0.0..=1.0)?;
    super::check_g(args.g)?;
    // −0 is 0, and printed so (in the JSON too)
    (args.albedo, args.g, args.theta) = (args.albedo + 0.0, args.g + 0.0, args.theta + 0.0);
    super::check_range("--eta", args.eta, ETA_MIN..=ETA_MAX)?;
    if let Some(tau) = args.slab {
        super::check_range("--slab", tau, (Bound::Excluded(0.0), Bound::Unbounded))?;
    }
    super::check_range("--theta", args.theta, 0.0..=90.0)?;
    // Below η = 1 no light enters beyond the critical angle (the walk's own check, in degrees)
    if (0.75..1.0).contains(&args.eta) && !super::values::enters(args.theta, args.eta) {
        // In full: the stated range is the one checked (rounded, it would be narrower)
        let critical = super::show(super::values::critical_deg(args.eta));
        return Err(CliError::input(format!(
            "--theta {} is outside the valid range at --eta {}: [0, {critical}] deg, below the critical angle asin(eta) (beyond it no light enters)",
            super::show(args.theta),
            super::show(args.eta)
        )));
    }
    super::check_photons(args.photons)?;
    let mut config = Config::new(args.albedo, args.g, args.eta, args.theta.to_radians());
    config.photons = args.photons;
    config.seed = args.seed;
    if let Some(tau) = args.slab {
        config.geometry = Geometry::Slab { thickness: tau };
    }
    if let Some(b) = args.bins {
        // Whole numbers here; their ranges are the bins' own (`Bins::new`)
        let count = |v: f64, name: &str, max: usize| {
            if v.fract() == 0.0 && (1.0..=max as f64).contains(&v) {
                Ok(v as usize)
            } else {
                Err(CliError::input(format!(
                    "--bins {name} = {} must be a whole number in [1, {max}]",
                    super::show(v)
                )))
            }
        };
        config.bins = Bins::new(
            b[0],
            b[1],
            count(b[2], "radial count", MAX_RADIAL)?,
            count(b[3], "phi count", MAX_PHI)?,
        )
        .map_err(|e| CliError::input(format!("--bins: {e}")))?;
    }
    config.validate()?;
    if args.bins.is_some() && args.profile.is_none() && !args.json {
        return Err(CliError::input(
            "--bins sets the bins of the profile, which only --profile writes (and --json sums, as binned_reflectance): give one of them, or drop --bins",
        ));
    }
    if let Some(path) = &args.profile {
        super::output::check(&[("--profile", path)], &[])?;
        let instead = "write the profile to a file";
        super::output::not_on_stdout("--profile", path, "its summary", instead)?;
    }
    let start = Instant::now();
    let bar = super::progress::bar(config.photons, "photons", args.quiet);
    bar.set_message("walking");
    let result = super::with_threads(args.threads, || {
        walk::run_with_progress(&config, &|n| bar.inc(n))
    })??;
    bar.finish_and_clear();
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.profile {
        let mut csv = Vec::new();
        result.to_csv(&mut csv)?;
        // The writer's errors name the file already
        bssrdf_zoo::format::write_file_atomic(path, &csv)
            .map_err(|e| CliError::input(e.to_string()))?;
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let mut json = serde_json::to_value(&result).map_err(std::io::Error::from)?;
        if let Some(map) = json.as_object_mut() {
            map.insert("seconds".into(), serde_json::json!(seconds));
            // θ as given, not its round trip through radians (60, not 59.99999999999999).
            map.insert("theta_deg".into(), serde_json::json!(args.theta));
        }
        writeln!(out, "{json}")?;
    } else {
        let photons = result.photons();
        let show =
            |name: &str, e: walk::Estimate| format!("{name:<25} {}", estimate_text(e, photons));
        writeln!(
            out,
            "{}",
            show("total reflectance", result.total_reflectance())
        )?;
        writeln!(
            out,
            "{}",
            show("single scattering", result.single_reflectance())
        )?;
        writeln!(
            out,
            "{}",
            show("multiple scattering", result.multiple_reflectance())
        )?;
        // A slab: light that crossed it without scattering, after a reflection at its far
        // side or through it (the totals include it; a half-space returns none)
        if let Some(t) = result.total_transmittance() {
            let unscattered = result.reflectance(walk::Component::Unscattered);
            writeln!(out, "{}", show("unscattered reflectance", unscattered))?;
            writeln!(out, "{}", show("total transmittance", t))?;
            if let Some(u) = result.transmittance(walk::Component::Unscattered) {
                writeln!(out, "{}", show("unscattered transmittance", u))?;
            }
        }
        // Weight the vertex cap stopped is in none of the lines above: say so where there is
        // some (albedo ≈ 1 with g near 1 loses a large part of the light there)
        let truncated = result.truncated_weight();
        if truncated.value > 0.0 {
            writeln!(
                out,
                "{} (photons stopped at the cap of {} scattering vertices; missing from the lines above)",
                show("truncated weight", truncated),
                walk::MAX_VERTICES
            )?;
        }
        writeln!(
            out,
            "(per unit power entering; {} photons, {} scattering events, {:.2} s, {:.1} M events/s)",
            result.photons(),
            result.scattering_events(),
            seconds,
            result.scattering_events() as f64 / seconds / 1e6
        )?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// An estimate and its standard error as text, each with six decimals, or in exponent form
/// below 10⁻³ (where six decimals would print a nonzero value as 0). An estimate no photon
/// scored is 0 with no spread; its error bar is then the 95 % upper bound 3/N (the "rule of
/// three"), said as such rather than "0 ± 0". A spread of exactly 0 (every photon scored the
/// same) prints as 0.
fn estimate_text(e: walk::Estimate, photons: u64) -> String {
    if e.value == 0.0 && e.stderr == 0.0 {
        let bound = (3.0 / photons as f64).min(1.0);
        return format!("0 (no photon scored; below {bound:.1e} at 95 %)");
    }
    let value = if e.value.abs() >= 1e-3 {
        format!("{:.6}", e.value)
    } else {
        format!("{:.4e}", e.value)
    };
    let stderr = if e.stderr == 0.0 || e.stderr >= 1e-3 {
        format!("{:.6}", e.stderr)
    } else {
        format!("{:.1e}", e.stderr)
    };
    format!("{value} ± {stderr}")
}
