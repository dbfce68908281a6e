//! `bssrdf diff A B`: compares two library files. Metadata (tables, axes, sections, materials)
//! must match; per paired table, every section is compared value by value on the axis nodes
//! both tables hold (so a scene bake can be checked against a full one), with the max and mean
//! absolute and relative differences and where the max is. Provenance and compression are
//! reported, never compared.
//!
//! Exit status: 0 when the metadata match and every value agrees within tolerance, 1 when not,
//! 2 for a missing or invalid file or a bad option. Values a and b agree when
//! |a − b| ≤ max(abs_tolerance, tolerance·max(|a|, |b|)); both default to 0 (bit-equal values).
//!
//! The comparison is the runtime's `format::diff::compare`; this module parses the arguments,
//! opens the files, prints the report as text or JSON and maps it to the exit status.

use super::CliError;
use bssrdf_zoo::format::diff::{
    self, Difference, Location, MetaValue, QuantityDiff, TableDiff, Tolerance,
};
use clap::Args;
use serde_json::{json, Value};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct DiffArgs {
    /// First library file.
    a: PathBuf,
    /// Second library file.
    b: PathBuf,
    /// Relative tolerance: values agree when |a − b| ≤ max(ABS, T·max(|a|, |b|)).
    #[arg(long, value_name = "T", default_value_t = 0.0)]
    tolerance: f64,
    /// Absolute tolerance (see --tolerance).
    #[arg(long, value_name = "ABS", default_value_t = 0.0)]
    abs_tolerance: f64,
    /// One JSON object on stdout instead of the report.
    #[arg(long)]
    json: bool,
    /// Map the files instead of reading them into memory (see `eval --mmap`).
    #[arg(long)]
    mmap: bool,
}

/// A metadata value as JSON (null where absent); the text report prints it the same way.
fn meta_json(value: &MetaValue) -> Value {
    match value {
        MetaValue::Absent => Value::Null,
        MetaValue::Bool(b) => json!(b),
        MetaValue::Count(n) => json!(n),
        MetaValue::Number(x) => json!(x),
        MetaValue::Dims(dims) => json!(dims),
        MetaValue::Fresnel(m) => json!(super::inspect::fresnel_name(*m)),
        MetaValue::Axis(axis) => {
            json!({"nodes": axis.nodes, "first": axis.first, "last": axis.last})
        }
        MetaValue::Text(text) => json!(text),
        MetaValue::PerChannel(rgb) => json!(rgb),
        MetaValue::TableIndices(tables) => json!(tables),
        MetaValue::AlbedoRange(range) => json!(range.map(|r| json!({"min": r.min, "max": r.max}))),
        MetaValue::Json(v) => v.clone(),
    }
}

/// One metadata difference: `item`, `field` and its value in A and in B.
fn difference_json(d: &Difference) -> Value {
    json!({"item": d.item.to_string(), "field": d.field.name(), "a": meta_json(&d.a), "b": meta_json(&d.b)})
}

/// Where a value is, for a quantity over `dims` axes: indices in A and B, ρ′, θ in degrees,
/// r (3-D only) and both values.
fn location_json(at: &Location, dims: usize) -> Value {
    let mut json = json!({
        "index_a": &at.index_a[..dims], "index_b": &at.index_b[..dims],
        "rho": at.rho, "theta_deg": at.theta.to_degrees(),
        "a": at.a, "b": at.b,
    });
    if dims == 3 {
        json["r"] = json!(at.r);
    }
    json
}

/// The same as one line: `[i,j,k]/[i,j,k] rho …, theta … deg, r …: a vs b`.
fn location_text(at: &Location, dims: usize) -> String {
    let idx = |i: &[usize]| {
        i[..dims]
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(",")
    };
    let r = if dims == 3 {
        format!(", r {}", at.r)
    } else {
        String::new()
    };
    format!(
        "[{}]/[{}] rho {}, theta {:.4} deg{r}: {:e} vs {:e}",
        idx(&at.index_a),
        idx(&at.index_b),
        at.rho,
        at.theta.to_degrees(),
        at.a,
        at.b
    )
}

/// One quantity's statistics, with where each max is (null when nothing was compared).
fn quantity_json(q: &QuantityDiff) -> Value {
    let dims = q.quantity().dims();
    json!({
        "section": q.quantity().name(), "count": q.count(),
        "max_abs": q.max_abs(), "mean_abs": q.mean_abs(),
        "max_rel": q.max_rel(), "mean_rel": q.mean_rel(),
        "max_abs_at": q.max_abs_at().map(|at| location_json(at, dims)),
        "max_rel_at": q.max_rel_at().map(|at| location_json(at, dims)),
        "outside_tolerance": q.outside_tolerance(),
    })
}

/// The same as a line of the text report, plus two lines locating the maxima when they are
/// not 0.
fn quantity_text(q: &QuantityDiff) -> String {
    let name = q.quantity().name();
    if q.count() == 0 {
        return format!("  {name:<18} no common nodes");
    }
    let mut text = format!(
        "  {name:<18} max abs {:<10.3e} mean abs {:<10.3e} max rel {:<10.3e} mean rel {:<10.3e} {} outside",
        q.max_abs(),
        q.mean_abs(),
        q.max_rel(),
        q.mean_rel(),
        q.outside_tolerance(),
    );
    if let (true, Some(abs_at), Some(rel_at)) = (q.max_abs() > 0.0, q.max_abs_at(), q.max_rel_at())
    {
        let dims = q.quantity().dims();
        text += &format!("\n      max abs at {}", location_text(abs_at, dims));
        text += &format!("\n      max rel at {}", location_text(rel_at, dims));
    }
    text
}

/// One pair of tables: indices, η, common dims, counts and the quantities.
fn table_json(t: &TableDiff) -> Value {
    json!({
        "a": t.a(), "b": t.b(), "eta": t.eta(),
        "common_dims": t.common_dims(),
        "values_compared": t.values_compared(),
        "outside_tolerance": t.outside_tolerance(),
        "sections": t.quantities().iter().map(quantity_json).collect::<Vec<_>>(),
    })
}

/// Compares the two files and prints the report; exit 1 when they differ.
pub fn run(mut args: DiffArgs) -> Result<ExitCode, CliError> {
    for (name, value) in [
        ("tolerance", args.tolerance),
        ("abs-tolerance", args.abs_tolerance),
    ] {
        super::check_range(&format!("--{name}"), value, 0.0..)?;
    }
    // −0 is 0 (and printed as 0, in the JSON too)
    args.tolerance += 0.0;
    args.abs_tolerance += 0.0;
    let tolerance = Tolerance::new(args.tolerance, args.abs_tolerance)
        .map_err(|e| CliError::input(e.to_string()))?;
    let a = super::library::open(&args.a, args.mmap)?;
    let b = super::library::open(&args.b, args.mmap)?;
    let report = diff::compare(&a, &b, tolerance);
    let (diffs, info) = (report.differences(), report.not_compared());
    let outside = report.outside_tolerance();
    let within = report.within_tolerance();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let json = json!({
            "a": args.a.display().to_string(), "b": args.b.display().to_string(),
            "tolerance": args.tolerance, "abs_tolerance": args.abs_tolerance,
            "within_tolerance": within,
            "differences": diffs.iter().map(difference_json).collect::<Vec<_>>(),
            "not_compared": info.iter().map(difference_json).collect::<Vec<_>>(),
            "tables": report.tables().iter().map(table_json).collect::<Vec<_>>(),
        });
        writeln!(out, "{json}")?;
    } else {
        writeln!(
            out,
            "A: {} ({} table(s), {} material(s))\nB: {} ({} table(s), {} material(s))",
            args.a.display(),
            a.table_count(),
            a.materials().len(),
            args.b.display(),
            b.table_count(),
            b.materials().len()
        )?;
        if diffs.is_empty() {
            writeln!(out, "metadata: identical")?;
        } else {
            writeln!(out, "metadata: {} difference(s)", diffs.len())?;
            for d in diffs {
                let (x, y) = (meta_json(&d.a), meta_json(&d.b));
                writeln!(out, "  {} {}: {x} vs {y}", d.item, d.field.name())?;
            }
        }
        if !info.is_empty() {
            let items: Vec<String> = info
                .iter()
                .map(|d| format!("{} {}", d.item, d.field.name()))
                .collect();
            writeln!(out, "not compared, differ: {}", items.join(", "))?;
        }
        for t in report.tables() {
            // η and the dims as JSON prints them (`1.0`, `[6,7,40]`).
            writeln!(
                out,
                "table {} (A) vs {} (B), eta {}: {} values on {} common nodes",
                t.a(),
                t.b(),
                json!(t.eta()),
                t.values_compared(),
                json!(t.common_dims())
            )?;
            for q in t.quantities() {
                writeln!(out, "{}", quantity_text(q))?;
            }
        }
        writeln!(
            out,
            "{} (tolerance {} relative, {} absolute; {} value(s) outside)",
            if within {
                "within tolerance"
            } else {
                "DIFFERENT"
            },
            super::show(args.tolerance),
            super::show(args.abs_tolerance),
            outside
        )?;
    }
    out.flush()?;
    Ok(if within {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
