//! `bssrdf validate FILE`: the report's table-2 protocol on every table of a file, each
//! against its own η (or on the one --table, --eta or --material names), error against run
//! time.
//!
//! Each case is `ok` (its mean error plus two standard errors of that mean is within its
//! bound: the report's figure, or --max-mean-error), `FAIL` (the mean exceeds the bound),
//! `inconclusive` (the mean is within the bound, but not by two standard errors: too few
//! points to tell) or `skipped` (no point could be checked: ρ′ outside the albedo rows the
//! file keeps, or no light leaves). Exit 0 when at least one case was checked and every
//! checked case is ok; exit 1 otherwise (a run that checked nothing is not a pass).

use super::library::{self, TableChoice};
use super::values::show_whole;
use super::CliError;
use bssrdf_zoo::table::{validate, FileTable, ValidationRow, REPORT_TABLE_2};
use clap::Args;
use serde_json::json;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// Largest --samples: 10⁸ points per case.
const MAX_SAMPLES: usize = 100_000_000;

#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Library file.
    file: PathBuf,
    /// Points drawn per (ρ′, θ) case, in [1, 1e8].
    #[arg(long, value_parser = super::values::whole::<usize>, default_value_t = 100_000)]
    samples: usize,
    /// Seed of the point stream.
    #[arg(long, value_parser = super::values::whole::<u64>, default_value_t = 7)]
    seed: u64,
    /// Bound on every case's mean relative error, in per cent, in [0, 10000] (default: the
    /// report's figures).
    #[arg(long, value_name = "PERCENT")]
    max_mean_error: Option<f64>,
    /// One JSON object instead of the table.
    #[arg(long)]
    json: bool,
    /// No progress bar (it only ever shows on a terminal).
    #[arg(long, short)]
    quiet: bool,
    #[command(flatten)]
    choice: TableChoice,
}

/// The verdict on one case.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Status {
    Ok,
    Fail,
    /// Mean below the bound, but not by two standard errors: too few points to tell.
    Inconclusive,
    Skipped,
}

impl Status {
    fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Fail => "fail",
            Status::Inconclusive => "inconclusive",
            Status::Skipped => "skipped",
        }
    }
}

pub fn run(args: ValidateArgs) -> Result<ExitCode, CliError> {
    if !(1..=MAX_SAMPLES).contains(&args.samples) {
        return Err(CliError::input(format!(
            "--samples {} is outside the valid range: [1, {}]",
            show_whole(args.samples as u64),
            show_whole(MAX_SAMPLES as u64)
        )));
    }
    if let Some(p) = args.max_mean_error {
        super::check_range("--max-mean-error", p, 0.0..=1e4)?;
    }
    // −0 is 0 (and printed as 0)
    let max_mean_error = args.max_mean_error.map(|p| p + 0.0);
    // --materials and --channel only with --material, and --eta in its domain, before the file
    args.choice.check_eta()?;
    let library = library::open(&args.file, args.choice.mmap)?;
    // Every table, each against its own eta, unless the choice names one.
    let choice = &args.choice;
    let tables: Vec<(usize, FileTable<'_>)> =
        if choice.table.is_none() && choice.eta.is_none() && choice.material.is_none() {
            library
                .tables()
                .enumerate()
                .map(|(i, record)| {
                    FileTable::new(record).map(|t| (i, t)).map_err(|e| {
                        CliError::input(format!("{}: table {i}: {e}", args.file.display()))
                    })
                })
                .collect::<Result<_, _>>()?
        } else {
            let chosen = choice.resolve(&library, &args.file)?;
            vec![(chosen.index, chosen.table)]
        };
    // The protocol measures a table against PBD, the model it tabulates; a walk table is
    // measured against the walk (`bssrdf zoo --walk-table`)
    let (walks, tables): (Vec<_>, Vec<_>) = tables
        .into_iter()
        .partition(|(_, t)| t.record().walk().is_some());
    let pointer = "the report's protocol measures a PBD table against PBD; measure a walk table against the walk with `bssrdf zoo --walk-table FILE --eta ETA --g G`";
    if tables.is_empty() {
        return Err(CliError::input(format!(
            "{}: nothing to validate: {} walk-angular table(s) and no PBD table chosen; {pointer}",
            args.file.display(),
            walks.len()
        )));
    }
    if !walks.is_empty() && !args.quiet {
        let list: Vec<String> = walks.iter().map(|(i, _)| i.to_string()).collect();
        let mut err = std::io::stderr().lock();
        writeln!(
            err,
            "note: table(s) {} are walk-angular and not checked: {pointer}",
            list.join(", ")
        )?;
    }
    let cases = REPORT_TABLE_2.len();
    let bar = super::progress::bar((cases * tables.len()) as u64, "cases", args.quiet);
    bar.set_message("validating");
    let mut checked_tables = Vec::with_capacity(tables.len());
    for (index, table) in &tables {
        let view = table.view().map_err(|e| CliError::input(e.to_string()))?;
        let mut rows = Vec::with_capacity(cases);
        // One case at a time for the bar; case k keeps the seed seed + k it has in a single call.
        for (k, case) in REPORT_TABLE_2.iter().enumerate() {
            let seed = args.seed.wrapping_add(k as u64);
            let row = validate(
                &view,
                table.moments(),
                &[(case.0, case.1)],
                args.samples,
                seed,
            )?;
            rows.extend(row);
            bar.inc(1);
        }
        let kept = view.axes().rho();
        let kept_theta = view.axes().theta().as_slice();
        let theta_kept = rows
            .iter()
            .map(|row| (row.theta_deg, view.keeps_theta(row.theta_deg.to_radians())))
            .collect();
        checked_tables.push(Checked {
            index: *index,
            eta: view.eta(),
            kept: (kept.first(), kept.last()),
            rho_domain: view.rho_domain(),
            kept_theta: (kept_theta[0], kept_theta[kept_theta.len() - 1]),
            theta_kept,
            rows,
        });
    }
    bar.finish_and_clear();
    let bound = |row: &ValidationRow| {
        max_mean_error
            .map(|p| p / 100.0)
            .or(row.report_mean_rel_error)
            .unwrap_or(f64::INFINITY)
    };
    let status = |row: &ValidationRow| {
        if row.samples == 0 {
            Status::Skipped
        } else if row.mean_rel_error > bound(row) {
            Status::Fail
        } else if row.mean_rel_error + 2.0 * row.mean_rel_error_stderr > bound(row) {
            Status::Inconclusive
        } else {
            Status::Ok
        }
    };
    let reason = |t: &Checked, row: &ValidationRow| {
        let (lo, hi) = t.kept;
        let (theta_lo, theta_hi) = t.kept_theta;
        if !(t.rho_domain[0]..=t.rho_domain[1]).contains(&row.rho) {
            format!(
                "rho outside the albedo rows this table keeps, [{}, {}]",
                super::show(lo),
                super::show(hi)
            )
        } else if t
            .theta_kept
            .iter()
            .any(|&(theta, kept)| theta == row.theta_deg && !kept)
        {
            format!(
                "theta outside the incidence range this table keeps, [{}, {}] deg",
                super::show_deg(theta_lo.to_degrees()),
                super::show_deg(theta_hi.to_degrees())
            )
        } else {
            "no light leaves (rho' = 0, or no light enters beyond the critical angle): no point to check".to_string()
        }
    };
    let count = |rows: &[ValidationRow], s: Status| rows.iter().filter(|r| status(r) == s).count();
    // (checked, failed, inconclusive, skipped)
    let tally = |rows: &[ValidationRow]| {
        let (failed, skipped) = (count(rows, Status::Fail), count(rows, Status::Skipped));
        let inconclusive = count(rows, Status::Inconclusive);
        (rows.len() - skipped, failed, inconclusive, skipped)
    };
    let all_rows: Vec<ValidationRow> = checked_tables
        .iter()
        .flat_map(|t| t.rows.iter().cloned())
        .collect();
    let (checked, failed, inconclusive, skipped) = tally(&all_rows);
    let pass = checked > 0 && failed == 0 && inconclusive == 0;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let row_json = |t: &Checked, r: &ValidationRow| {
            let s = status(r);
            let measured = |v: f64| if s == Status::Skipped { None } else { Some(v) };
            json!({
                "table": t.index,
                "eta": t.eta,
                "rho": r.rho,
                "theta_deg": r.theta_deg,
                "status": s.name(),
                "skip_reason": (s == Status::Skipped).then(|| reason(t, r)),
                "samples": r.samples,
                "mean_rel_error": measured(r.mean_rel_error),
                "mean_rel_error_stderr": measured(r.mean_rel_error_stderr)
                    .filter(|e| e.is_finite()),
                "p99_rel_error": measured(r.p99_rel_error),
                "max_rel_error": measured(r.max_rel_error),
                "fraction_above_1pct": measured(r.fraction_above_1pct),
                "table_ns": measured(r.table_ns),
                "reference_ns": measured(r.reference_ns),
                "bound_mean_rel_error": bound(r).is_finite().then(|| bound(r)),
            })
        };
        let per_table: Vec<_> = checked_tables
            .iter()
            .map(|t| {
                let (checked, failed, inconclusive, skipped) = tally(&t.rows);
                json!({
                    "table": t.index, "eta": t.eta, "checked": checked, "failed": failed,
                    "inconclusive": inconclusive, "skipped": skipped,
                    "pass": checked > 0 && failed == 0 && inconclusive == 0,
                })
            })
            .collect();
        let rows: Vec<_> = checked_tables
            .iter()
            .flat_map(|t| t.rows.iter().map(move |r| (t, r)))
            .map(|(t, r)| row_json(t, r))
            .collect();
        let json = json!({
            "file": args.file.display().to_string(),
            "samples": args.samples,
            "seed": args.seed,
            "checked": checked,
            "failed": failed,
            "inconclusive": inconclusive,
            "skipped": skipped,
            "pass": pass,
            "tables": per_table,
            "skipped_tables": walks
                .iter()
                .map(|(i, _)| json!({ "table": i, "reason": pointer }))
                .collect::<Vec<_>>(),
            "rows": rows,
        });
        writeln!(out, "{json}")?;
    } else {
        for t in &checked_tables {
            writeln!(
                out,
                "table {}, eta {}: {} points per case, seed {}",
                t.index, t.eta, args.samples, args.seed
            )?;
            writeln!(
                out,
                "{:>5} {:>6}  {:>9} {:>9} {:>9} {:>9} {:>8}  {:>9} {:>11} {:>8}  bound %",
                "rho",
                "theta",
                "mean %",
                "s.e. %",
                "p99 %",
                "max %",
                ">1 %",
                "table ns",
                "reference ns",
                "speed-up",
            )?;
            for r in &t.rows {
                let s = status(r);
                if s == Status::Skipped {
                    writeln!(
                        out,
                        "{:>5} {:>6}  skipped: {}",
                        r.rho,
                        r.theta_deg,
                        reason(t, r)
                    )?;
                    continue;
                }
                writeln!(
                    out,
                    "{:>5} {:>6}  {:>9.4} {:>9.4} {:>9.3} {:>9.3} {:>8.5}  {:>9.1} {:>11.0} {:>8.0}  {:.3} {}",
                    r.rho,
                    r.theta_deg,
                    100.0 * r.mean_rel_error,
                    100.0 * r.mean_rel_error_stderr,
                    100.0 * r.p99_rel_error,
                    100.0 * r.max_rel_error,
                    r.fraction_above_1pct,
                    r.table_ns,
                    r.reference_ns,
                    r.reference_ns / r.table_ns,
                    100.0 * bound(r),
                    match s {
                        Status::Ok => "ok",
                        Status::Inconclusive =>
                            "INCONCLUSIVE: the bound is within two standard errors of the mean",
                        _ => "FAIL",
                    }
                )?;
            }
        }
        let verdict = if pass {
            "pass"
        } else if checked == 0 {
            "not a pass: no case could be checked"
        } else if failed == 0 {
            "not a pass: too few points to tell (raise --samples)"
        } else {
            "FAIL"
        };
        let inconclusive = match inconclusive {
            0 => String::new(),
            n => format!(", {n} inconclusive"),
        };
        let walk_tables = match walks.len() {
            0 => String::new(),
            n => format!(" ({n} walk-angular table(s) not checked)"),
        };
        writeln!(
            out,
            "{} table(s){walk_tables}, {checked} case(s) checked, {failed} failed{inconclusive}, {skipped} skipped: {verdict}",
            checked_tables.len()
        )?;
    }
    out.flush()?;
    Ok(if pass {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// One table's protocol: its index in the file, η, the albedos it keeps and its rows.
struct Checked {
    index: usize,
    eta: f64,
    kept: (f64, f64),
    /// The albedos its lookups take (`TableRef::rho_domain`).
    rho_domain: [f64; 2],
    /// The θ axis's first and last node, radians.
    kept_theta: (f64, f64),
    /// Each case's θ (degrees) and whether the θ axis holds it (`TableRef::keeps_theta`).
    theta_kept: Vec<(f64, bool)>,
    rows: Vec<ValidationRow>,
}
