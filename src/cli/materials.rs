//! `bssrdf materials`: the named-material library, one line per material.

use super::CliError;
use bssrdf_zoo::materials::Library;
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

pub fn run(args: MaterialsArgs) -> Result<ExitCode, CliError> {
    let library = library(args.materials.as_deref())?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let all: Vec<_> = library.iter().collect();
        serde_json::to_writer_pretty(&mut out, &all).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        writeln!(
            out,
            "{:<26} {:>5}  {:<26} {:<26} {:<20} source",
            "id", "eta", "sigma_s (mm^-1, R G B)", "sigma_a (mm^-1, R G B)", "g (R G B)"
        )?;
        for m in library.iter() {
            let triple = |v: [f64; 3]| format!("{:.4} {:.4} {:.4}", v[0], v[1], v[2]);
            let source = m.source().map_or("(none given)", |s| s.coefficients());
            let short: String = source.chars().take(40).collect();
            writeln!(
                out,
                "{:<26} {:>5}  {:<26} {:<26} {:<20} {}",
                m.id(),
                m.eta(),
                triple(m.sigma_s()),
                triple(m.sigma_a()),
                format!("{:.3} {:.3} {:.3}", m.g()[0], m.g()[1], m.g()[2]),
                short
            )?;
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}
