//! `bssrdf validate FILE`: the report's table-2 protocol on a table, error against run time.
//! Exit 1 when a case's mean error exceeds its bound (the report's figure, or --max-mean-error).

use super::library::{self, TableChoice};
use super::CliError;
use bssrdf_zoo::table::{validate, REPORT_TABLE_2};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Library file.
    file: PathBuf,
    /// Points drawn per (ρ′, θ) case.
    #[arg(long, default_value_t = 100_000)]
    samples: usize,
    /// Seed of the point stream.
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Bound on every case's mean relative error, in per cent (default: the report's figures).
    #[arg(long, value_name = "PERCENT")]
    max_mean_error: Option<f64>,
    /// One JSON object instead of the table.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    choice: TableChoice,
}

pub fn run(args: ValidateArgs) -> Result<ExitCode, CliError> {
    if args.samples == 0 {
        return Err(CliError::input("--samples 0: at least one point per case"));
    }
    let library = library::open(&args.file)?;
    let chosen = args.choice.resolve(&library, &args.file)?;
    let view = chosen
        .table
        .view()
        .map_err(|e| CliError::input(e.to_string()))?;
    let cases: Vec<(f64, f64)> = REPORT_TABLE_2.iter().map(|c| (c.0, c.1)).collect();
    let rows = validate(
        &view,
        chosen.table.moments(),
        &cases,
        args.samples,
        args.seed,
    )?;
    let bound = |row: &bssrdf_zoo::table::ValidationRow| {
        args.max_mean_error
            .map(|p| p / 100.0)
            .or(row.report_mean_rel_error)
            .unwrap_or(f64::INFINITY)
    };
    let pass = rows.iter().all(|r| r.mean_rel_error <= bound(r));
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let json = serde_json::json!({
            "file": args.file.display().to_string(),
            "eta": view.eta(),
            "samples": args.samples,
            "seed": args.seed,
            "pass": pass,
            "rows": rows,
        });
        writeln!(out, "{json}")?;
    } else {
        writeln!(
            out,
            "eta {}: {} points per case, seed {}",
            view.eta(),
            args.samples,
            args.seed
        )?;
        writeln!(
            out,
            "{:>5} {:>6}  {:>9} {:>9} {:>9} {:>8}  {:>9} {:>11} {:>8}  bound %",
            "rho",
            "theta",
            "mean %",
            "p99 %",
            "max %",
            ">1 %",
            "table ns",
            "reference ns",
            "speed-up",
        )?;
        for r in &rows {
            writeln!(
                out,
                "{:>5} {:>6}  {:>9.4} {:>9.3} {:>9.3} {:>8.5}  {:>9.1} {:>11.0} {:>8.0}  {:.3} {}",
                r.rho,
                r.theta_deg,
                100.0 * r.mean_rel_error,
                100.0 * r.p99_rel_error,
                100.0 * r.max_rel_error,
                r.fraction_above_1pct,
                r.table_ns,
                r.reference_ns,
                r.reference_ns / r.table_ns,
                100.0 * bound(r),
                if r.mean_rel_error <= bound(r) {
                    "ok"
                } else {
                    "FAIL"
                }
            )?;
        }
    }
    out.flush()?;
    Ok(if pass {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
