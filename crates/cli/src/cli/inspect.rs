//! `bssrdf inspect FILE`: version, sizes, required features by name (`zstd-sections`,
//! `signed-floor`), sections with their checksums (verified), materials, tables with their
//! model (and a walk-angular table's g and component), axes and ridge kind (what the nodes
//! hold the profile less: no ridge, its flux part or the ridge with its fluence part),
//! provenance. Names from the file are
//! printed with control characters escaped.

use super::CliError;
use bssrdf_zoo::error::Number;
use bssrdf_zoo::format::spec::required_features;
use bssrdf_zoo::format::{AxisKind, Codec, FresnelMoments, SectionKind, KEY_ACCURACY};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{RidgeKind, TableCheck};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct InspectArgs {
    /// Library file.
    file: PathBuf,
    /// One JSON object instead of the report.
    #[arg(long)]
    json: bool,
}

/// Escapes control characters, so that a hostile name cannot drive the terminal, and the
/// characters that reorder or hide text ([`reorders_text`]), so that it cannot pass for another.
pub fn escape(s: &str) -> String {
    s.chars()
        .flat_map(|c| {
            if c.is_control() || reorders_text(c) {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            }
        })
        .collect()
}

/// The invisible characters that reorder or hide the text around them (Unicode's
/// bidirectional controls, the zero-width characters and the byte-order mark): a name holding
/// them would print as another name. The format refuses only control characters (Cc).
fn reorders_text(c: char) -> bool {
    matches!(
        c,
        '\u{061c}' | '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2060}'..='\u{2069}' | '\u{feff}'
    )
}

fn axis_summary(values: &[f32]) -> String {
    match values {
        [] => "(empty)".into(),
        [only] => format!("1 node: {only}"),
        [first, .., last] => format!("{} nodes, {first} … {last}", values.len()),
    }
}

fn codec_name(codec: Codec) -> &'static str {
    match codec {
        Codec::None => "none",
        Codec::Zstd => "zstd",
    }
}

/// As `--fresnel-moments` names them ([`Moments::name`]).
pub(super) fn fresnel_name(m: FresnelMoments) -> &'static str {
    Moments::from(m).name()
}

fn section_name(kind: u32) -> String {
    SectionKind::from_code(kind)
        .map_or_else(|| format!("extension 0x{kind:x}"), |k| k.name().to_string())
}

pub fn run(args: InspectArgs) -> Result<ExitCode, CliError> {
    // Every CRC is checked here: a file that opens has all its checksums verified.
    let library = super::library::open(&args.file, false)?;
    let (major, minor) = library.version();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let sections: Vec<_> = library
            .sections()
            .iter()
            .map(|s| {
                serde_json::json!({
                    "kind": section_name(s.kind), "table": s.table, "dtype": s.dtype.name(),
                    "codec": codec_name(s.codec), "required": s.required, "dims": s.dims,
                    "offset": s.offset, "stored_len": s.stored_len, "raw_len": s.raw_len,
                    "crc32": format!("{:08x}", s.crc32), "crc_verified": true,
                })
            })
            .collect();
        let tables: Vec<_> = library
            .tables()
            .map(|t| serde_json::json!({
                "index": t.index(), "model": t.model().name(),
                "walk_g": t.walk().map(|w| w.g),
                "walk_component": t.walk().map(|w| w.component.name()),
                "eta": t.eta(),
                "fresnel_moments": fresnel_name(t.fresnel()), "dims": t.dims(),
                "rho": t.axis(AxisKind::Rho), "theta": t.axis(AxisKind::Theta), "r": t.axis(AxisKind::R),
                "theta_sampling": t.theta_cdf().is_some(),
                "lobes": if t.harmonics().is_some() { 2 } else { 1 },
                "ridge": t.ridge().is_some(), "ridge_kind": t.ridge().name(),
            }))
            .collect();
        let materials: Vec<_> = library
            .materials()
            .iter()
            .map(|m| serde_json::json!({
                "name": m.name, "source": m.source, "sigma_s": m.sigma_s, "sigma_a": m.sigma_a,
                "g": m.g, "eta": m.eta, "tables": m.tables,
                "albedo_range": m.albedo_range.map(|r| serde_json::json!({"min": r.min, "max": r.max})),
            }))
            .collect();
        let provenance: serde_json::Map<String, serde_json::Value> = library
            .provenance()
            .map(|p| {
                p.fields()
                    .map(|(k, v)| (k.to_string(), v.clone()))
                    .collect()
            })
            .unwrap_or_default();
        let json = serde_json::json!({
            "file": args.file.display().to_string(), "version": [major, minor],
            "file_size": library.file_size(), "compressed": library.is_compressed(),
            "alignment": library.alignment(),
            "required_features": library.required_features(),
            "required_feature_names": required_features::names(library.required_features()),
            "optional_features": library.optional_features(),
            "sections": sections, "tables": tables, "materials": materials, "provenance": provenance,
        });
        writeln!(out, "{json}")?;
        out.flush()?;
        return Ok(ExitCode::SUCCESS);
    }
    writeln!(out, "{}", escape(&args.file.display().to_string()))?;
    let required = library.required_features();
    let required_names = match required_features::names(required) {
        names if names.is_empty() => String::new(),
        names => format!(" ({})", names.join(", ")),
    };
    writeln!(
        out,
        "  format {major}.{minor}, {} bytes, {}, sections aligned to {} bytes, features required {required:#x}{required_names} optional {:#x}",
        library.file_size(),
        if library.is_compressed() { "zstd-compressed (decoded at open)" } else { "uncompressed (mappable)" },
        library.alignment(),
        library.optional_features()
    )?;
    writeln!(
        out,
        "sections ({}), every CRC-32 verified:",
        library.sections().len()
    )?;
    for s in library.sections() {
        writeln!(
            out,
            "  {:<18} table {:<4} {:<3} {:<4} dims {:?}  offset {:>8}  {:>8} -> {:>8} bytes  crc {:08x}{}",
            section_name(s.kind),
            s.table.map_or("-".to_string(), |t| t.to_string()),
            s.dtype.name(),
            codec_name(s.codec),
            s.dims,
            s.offset,
            s.stored_len,
            s.raw_len,
            s.crc32,
            if s.required { "  required" } else { "" }
        )?;
    }
    writeln!(out, "tables ({}):", library.table_count())?;
    for t in library.tables() {
        let walk = t.walk().map_or(String::new(), |w| {
            format!(" g {} component {}", Number(w.g), w.component.name())
        });
        writeln!(
            out,
            "  [{}] {}{walk} eta {} moments {} dims {:?} lobes {} theta-sampling {} ridge {}",
            t.index(),
            t.model().name(),
            Number(t.eta()),
            fresnel_name(t.fresnel()),
            t.dims(),
            if t.harmonics().is_some() { 2 } else { 1 },
            if t.theta_cdf().is_some() { "yes" } else { "no" },
            match t.ridge() {
                RidgeKind::None => "no",
                kind => kind.name(),
            }
        )?;
        writeln!(out, "      rho:   {}", axis_summary(t.axis(AxisKind::Rho)))?;
        writeln!(
            out,
            "      theta: {} (radians)",
            axis_summary(t.axis(AxisKind::Theta))
        )?;
        writeln!(
            out,
            "      r:     {} (reduced mfp)",
            axis_summary(t.axis(AxisKind::R))
        )?;
    }
    writeln!(out, "materials ({}):", library.materials().len())?;
    for m in library.materials() {
        writeln!(
            out,
            "  {:<24} eta {} sigma_s {:?} sigma_a {:?} g {:?} tables {:?}",
            escape(&m.name),
            Number(m.eta),
            m.sigma_s,
            m.sigma_a,
            m.g,
            m.tables
        )?;
        if let Some(range) = m.albedo_range {
            writeln!(out, "      albedo range {:?} … {:?}", range.min, range.max)?;
        }
        if !m.source.is_empty() {
            writeln!(out, "      source: {}", escape(&m.source))?;
        }
    }
    if let Some(p) = library.provenance() {
        writeln!(out, "provenance:")?;
        for (key, value) in p.fields() {
            if let Some(lines) = (key == KEY_ACCURACY).then(|| check_lines(value)).flatten() {
                writeln!(out, "  {key}: the bake's check, per table and region")?;
                for line in lines {
                    writeln!(out, "    {}", escape(&line))?;
                }
                continue;
            }
            // Objects and arrays pretty-printed, indented under their key.
            let pretty = serde_json::to_string_pretty(value).unwrap_or_else(|_| value.to_string());
            let mut lines = pretty.lines();
            writeln!(
                out,
                "  {}: {}",
                escape(key),
                escape(lines.next().unwrap_or(""))
            )?;
            for line in lines {
                writeln!(out, "    {}", escape(line))?;
            }
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// The bake's check (`table::check`) as stored under `accuracy`, a line per region: `None`
/// for anything else (files of earlier versions stored other figures there; those print as
/// JSON).
fn check_lines(accuracy: &serde_json::Value) -> Option<Vec<String>> {
    let tables: Vec<TableCheck> = serde_json::from_value(accuracy.get("tables")?.clone()).ok()?;
    let mut lines = Vec::new();
    for table in &tables {
        let bounds = &table.bounds;
        lines.push(format!(
            "eta {}: bound mean {} %, coverage {} % down to {:e} of the peak",
            table.eta,
            100.0 * bounds.mean_rel_error,
            100.0 * bounds.coverage_rel_error,
            bounds.peak_fraction
        ));
        // No region to list: not an empty table, which would read as a pass
        if let Some(note) = table.nothing_checked() {
            lines.push(format!("  {note}"));
            continue;
        }
        lines.push(format!(
            "  {:>11} {:>11} {:>6} {:>8} {:>8} {:>8} {:>8}  {:>5} {:>8} {:>5}",
            "rho",
            "theta deg",
            "points",
            "mean %",
            "p99 %",
            "max %",
            ">1 %",
            "cover",
            "max %",
            "zeros"
        ));
        for r in &table.regions {
            lines.push(format!(
                "  {:>11} {:>11} {:>6} {:>8.3} {:>8.3} {:>8.3} {:>8.4}  {:>5} {:>8.3} {:>5}  {}",
                format!(
                    "{}-{}",
                    super::values::show_band(r.rho[0]),
                    super::values::show_band(r.rho[1])
                ),
                format!(
                    "{}-{}",
                    super::show_deg(r.theta_deg[0]),
                    super::show_deg(r.theta_deg[1])
                ),
                r.points,
                100.0 * r.mean_rel_error,
                100.0 * r.p99_rel_error,
                100.0 * r.max_rel_error,
                r.fraction_above_1pct,
                r.coverage_points,
                100.0 * r.coverage_max_rel_error,
                r.silent_zeros,
                if r.passes(bounds) {
                    "ok"
                } else {
                    "ABOVE BOUND"
                }
            ));
        }
    }
    Some(lines)
}

#[cfg(test)]
mod tests {
    use super::escape;

    #[test]
    fn names_print_as_what_they_hold() {
        assert_eq!(escape("skin1"), "skin1");
        assert_eq!(escape("jus d'orange é"), "jus d'orange é");
        assert_eq!(escape("a\tb\u{1b}[2J"), "a\\tb\\u{1b}[2J");
        // A right-to-left override would print "skin1" followed by reversed text
        assert_eq!(escape("skin1\u{202e}lmx."), "skin1\\u{202e}lmx.");
        assert_eq!(escape("\u{200b}wax\u{feff}"), "\\u{200b}wax\\u{feff}");
    }
}
