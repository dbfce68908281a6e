//! `bssrdf materials`: the named-material library, one line per material.

use super::CliError;
use bssrdf_zoo::materials::{Coefficients, Library, Material, Origin};
use clap::Args;
use std::io::Write;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct MaterialsArgs {
    /// Add the materials of a TOML file or of every *.toml in a folder.
    #[arg(long, value_name = "PATH")]
    materials: Option<std::path::PathBuf>,
    /// One JSON array instead of the table.
    #[arg(long)]
    json: bool,
}

/// The built-in library plus a user's file or folder, if given.
pub fn library(extra: Option<&std::path::Path>) -> Result<Library, CliError> {
    let mut library = Library::builtin();
    if let Some(path) = extra {
        library
            .load_path(path)
            .map_err(|e| CliError::input(e.to_string()))?;
    }
    Ok(library)
}

/// The material `--material NAME` names, from the built-in library plus `--materials PATH`;
/// with `--materials` it must come from those files (else the flag would change nothing).
pub fn named(name: &str, extra: Option<&std::path::Path>) -> Result<Material, CliError> {
    let m = library(extra)?
        .get(name)
        .cloned()
        .map_err(|e| CliError::input(e.to_string()))?;
    if extra.is_some() && !matches!(m.origin(), Origin::File(_)) {
        return Err(CliError::input(format!(
            "--materials adds files to look --material up in, but {name} is built in: drop --materials"
        )));
    }
    Ok(m)
}

/// The files a command reads for `--materials PATH` (the file, or each `*.toml` of the
/// folder): inputs that no output may replace. A folder that cannot be listed gives none here;
/// loading it reports why.
pub fn input_files(extra: Option<&std::path::Path>) -> Vec<std::path::PathBuf> {
    extra
        .map(|path| Library::files_of(path).unwrap_or_default())
        .unwrap_or_default()
}

pub fn run(args: MaterialsArgs) -> Result<ExitCode, CliError> {
    let library = library(args.materials.as_deref())?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let all: Vec<_> = library.iter().collect();
        serde_json::to_writer_pretty(&mut out, &all).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        // sigma_s as the source states it: unreduced σs with its g, or, for "reduced"
        // materials, σ′s with g = 0 (the `sigma_s` column says which).
        let width = library
            .iter()
            .map(|m| m.id().len())
            .max()
            .unwrap_or(2)
            .max(2);
        let triple =
            |v: [f64; 3], f: fn(f64) -> String| format!("{} {} {}", f(v[0]), f(v[1]), f(v[2]));
        let rows: Vec<[String; 6]> = library
            .iter()
            .map(|m| {
                let kind = match m.coefficients() {
                    Coefficients::Reduced => "reduced",
                    Coefficients::Unreduced => "unreduced",
                };
                let source = m.source().map_or("(none given)", |s| s.coefficients());
                [
                    m.eta().to_string(),
                    kind.to_string(),
                    triple(m.sigma_s(), sig4),
                    triple(m.sigma_a(), sig4),
                    triple(m.g(), sig4_inside_unit),
                    // Cut at 40 characters, marked: `--json` gives it whole.
                    if source.chars().count() > 40 {
                        source.chars().take(39).chain(['…']).collect()
                    } else {
                        source.to_string()
                    },
                ]
            })
            .collect();
        let col = |k: usize, title: &str| {
            rows.iter()
                .map(|r| r[k].chars().count())
                .max()
                .unwrap_or(0)
                .max(title.chars().count())
        };
        let titles = [
            "eta",
            "sigma_s is",
            "sigma_s (mm^-1, R G B)",
            "sigma_a (mm^-1, R G B)",
            "g (R G B)",
        ];
        let w: Vec<usize> = titles.iter().enumerate().map(|(k, t)| col(k, t)).collect();
        // One line: the id, eta right-aligned, the other columns left-aligned, then the source.
        let mut line = |id: &str, cells: [&str; 6]| {
            writeln!(
                out,
                "{id:<width$}  {:>w0$}  {:<w1$}  {:<w2$}  {:<w3$}  {:<w4$}  {}",
                cells[0],
                cells[1],
                cells[2],
                cells[3],
                cells[4],
                cells[5],
                w0 = w[0],
                w1 = w[1],
                w2 = w[2],
                w3 = w[3],
                w4 = w[4],
            )
        };
        line(
            "id",
            [
                titles[0], titles[1], titles[2], titles[3], titles[4], "source",
            ],
        )?;
        for (m, r) in library.iter().zip(&rows) {
            line(m.id(), std::array::from_fn(|k| r[k].as_str()))?;
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// Four significant digits, so that small coefficients do not show as 0.0000.
fn sig4(v: f64) -> String {
    sig(v, 4)
}

/// `digits` significant digits.
fn sig(v: f64, digits: i32) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let magnitude = v.abs().log10().floor();
    if !(-4.0..6.0).contains(&magnitude) {
        let decimals = (digits - 1) as usize;
        return format!("{v:.decimals$e}");
    }
    let decimals = (f64::from(digits - 1) - magnitude).max(0.0) as usize;
    format!("{v:.decimals$}")
}

/// [`sig4`] of a g in (−1, 1), with as many more digits as keep it inside: 0.99999 shows as
/// 0.99999, not as 1.0000, which is outside g's domain.
fn sig4_inside_unit(g: f64) -> String {
    (4..=17)
        .map(|digits| sig(g, digits))
        .find(|shown| shown.parse::<f64>().is_ok_and(|x| x.abs() < 1.0))
        .unwrap_or_else(|| g.to_string())
}

#[cfg(test)]
mod tests {
    use super::{sig4, sig4_inside_unit};

    #[test]
    fn four_digits_and_a_g_never_shown_outside_its_domain() {
        assert_eq!(sig4(0.00257), "0.002570");
        assert_eq!(sig4(12.21), "12.21");
        assert_eq!(sig4(1.5e-7), "1.500e-7");
        assert_eq!(sig4_inside_unit(0.947), "0.9470");
        assert_eq!(sig4_inside_unit(0.0), "0");
        assert_eq!(sig4_inside_unit(0.99999), "0.99999");
        assert_eq!(sig4_inside_unit(-0.999999), "-0.999999");
        let just_below = 1.0 - f64::EPSILON;
        assert!(sig4_inside_unit(just_below).parse::<f64>().unwrap() < 1.0);
    }
}
