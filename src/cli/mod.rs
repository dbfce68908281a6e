//! Command-line definitions (clap) and dispatch. Each subcommand lives in its own file.

mod eval;

use clap::{Parser, Subcommand};
use std::fmt;
use std::process::ExitCode;

/// Tabulated BSSRDF models: bake, evaluate, sample, validate.
#[derive(Debug, Parser)]
#[command(name = "bssrdf", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Evaluate a model at one point or at every row of a CSV file.
    #[command(allow_negative_numbers = true)]
    Eval(eval::EvalArgs),
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> Result<ExitCode, CliError> {
    match cli.command {
        Command::Eval(args) => eval::run(args),
    }
}

/// Errors of the command line: bad input (exit 2), failed checks (exit 1), I/O.
#[derive(Debug)]
pub enum CliError {
    /// Bad input or usage: exit code 2.
    Input(String),
    /// The library rejected a value: exit code 2.
    Library(bssrdf_zoo::Error),
    /// Reading or writing failed.
    Io(std::io::Error),
}

impl CliError {
    pub fn input(message: impl Into<String>) -> Self {
        CliError::Input(message.into())
    }

    /// The documented exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) | CliError::Library(_) => 2,
            CliError::Io(_) => 2,
        }
    }

    /// Whether this is a closed pipe on output, which ends the program quietly.
    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, CliError::Io(e) if e.kind() == std::io::ErrorKind::BrokenPipe)
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) => f.write_str(m),
            CliError::Library(e) => write!(f, "{e}"),
            CliError::Io(e) => write!(f, "{e}"),
        }
    }
}

impl From<bssrdf_zoo::Error> for CliError {
    fn from(e: bssrdf_zoo::Error) -> Self {
        CliError::Library(e)
    }
}

impl From<std::io::Error> for CliError {
    fn from(e: std::io::Error) -> Self {
        CliError::Io(e)
    }
}
