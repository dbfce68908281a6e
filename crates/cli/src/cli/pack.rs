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
    /// zstd level in [-131072, 22]: 1 to 22 from fast to small, 0 zstd's default (3), the
    /// negative ones faster still.
    #[arg(long, value_parser = super::values::whole::<i32>, default_value_t = Compression::DEFAULT_ZSTD_LEVEL, allow_hyphen_values = true)]
    level: i32,
}

#[derive(Debug, Args)]
pub struct UnpackArgs {
    /// Library file to convert.
    file: PathBuf,
    /// Output (default: rewrite FILE in place, atomically; a link is followed, the file's
    /// permissions kept). An output that is FILE, by any name, is refused: leave -o out.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn pack(args: PackArgs) -> Result<ExitCode, CliError> {
    let levels = bssrdf_zoo::format::zstd_levels();
    if !levels.contains(&args.level) {
        return Err(CliError::input(format!(
            "--level {} is outside the valid range: [{}, {}]",
            args.level,
            levels.start(),
            levels.end()
        )));
    }
    convert(&args.files, Some(args.level))
}

pub fn unpack(args: UnpackArgs) -> Result<ExitCode, CliError> {
    convert(&args, None)
}

/// Packs at `level`, or unpacks without one.
fn convert(args: &UnpackArgs, level: Option<i32>) -> Result<ExitCode, CliError> {
    let output = args.output.clone().unwrap_or_else(|| args.file.clone());
    if args.output.is_none() {
        // In place: FILE is replaced through a temporary file, which needs a path to a regular
        // file. Through a descriptor (`/dev/stdin` redirected from the file, or a pipe) the
        // output would be written into the input it is read from.
        // (A FILE that does not exist is left to the conversion's own "cannot open".)
        let meta = std::fs::metadata(&args.file).ok();
        if meta.as_ref().is_some_and(|m| m.is_dir()) {
            return Err(CliError::input(format!(
                "FILE {} is a folder, not a library file",
                args.file.display()
            )));
        }
        if bssrdf_zoo::format::through_descriptor(&args.file) || meta.is_some_and(|m| !m.is_file())
        {
            return Err(CliError::input(format!(
                "FILE {} is not a regular file that can be rewritten in place (a stream or a descriptor): give the output with -o",
                args.file.display()
            )));
        }
    } else {
        // Any -o that is FILE, however spelled (`-o FILE` too), is refused like every output
        // on an input: in place is asked for by leaving -o out
        super::output::check(&[("-o", &output)], &[("FILE", &args.file)])?;
    }
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
