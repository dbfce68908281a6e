//! `bssrdf pack FILE` / `bssrdf unpack FILE`: lossless conversion between the zstd-compressed
//! form (for distribution) and the mappable form.

use super::CliError;
use bssrdf_zoo::format::{self, Compression};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct PackArgs {
    /// Library file to convert.
    file: PathBuf,
    /// Output (default: rewrite FILE in place, atomically).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// zstd level (pack only).
    #[arg(long, default_value_t = Compression::DEFAULT_ZSTD_LEVEL)]
    level: i32,
}

pub fn run(args: PackArgs, compress: bool) -> Result<ExitCode, CliError> {
    let output = args.output.clone().unwrap_or_else(|| args.file.clone());
    let done = if compress {
        format::pack(&args.file, &output, args.level)
    } else {
        format::unpack(&args.file, &output)
    }
    .map_err(|e| CliError::input(format!("{}: {e}", args.file.display())))?;
    eprintln!(
        "{} -> {}: {} -> {} bytes",
        args.file.display(),
        output.display(),
        done.input_bytes,
        done.output_bytes
    );
    Ok(ExitCode::SUCCESS)
}
