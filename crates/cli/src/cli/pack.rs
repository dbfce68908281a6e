//! `bssrdf pack FILE` / `bssrdf unpack FILE`: lossless conversion between the zstd-compressed
//! form (for distribution) and the mappable form.

use super::CliError;
use bssrdf_zoo::format::{self, Compression};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct PackArgs {
    #[command(flatten)]
    files: UnpackArgs,
    /// zstd level, in zstd's range (1..=22, and its fast negative levels down to -131072).
    #[arg(long, default_value_t = Compression::DEFAULT_ZSTD_LEVEL)]
    level: i32,
}

#[derive(Debug, Args)]
pub struct UnpackArgs {
    /// Library file to convert.
    file: PathBuf,
    /// Output (default: rewrite FILE in place, atomically; a link is followed, the file's
    /// permissions kept).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn pack(args: PackArgs) -> Result<ExitCode, CliError> {
    convert(&args.files, Some(args.level))
}

pub fn unpack(args: UnpackArgs) -> Result<ExitCode, CliError> {
    convert(&args, None)
}

/// Packs at `level`, or unpacks without one.
fn convert(args: &UnpackArgs, level: Option<i32>) -> Result<ExitCode, CliError> {
    let output = args.output.clone().unwrap_or_else(|| args.file.clone());
    let done = match level {
        Some(level) => format::pack(&args.file, &output, level),
        None => format::unpack(&args.file, &output),
    }
    .map_err(|e| CliError::input(format!("{}: {e}", args.file.display())))?;
    // The summary is lost on a closed stderr, not a panic
    let _ = writeln!(
        std::io::stderr(),
        "{} -> {}: {} -> {} bytes",
        args.file.display(),
        output.display(),
        done.input_bytes,
        done.output_bytes
    );
    Ok(ExitCode::SUCCESS)
}
