//! The `bssrdf` command: parses arguments, calls the library, prints.
//!
//! Exit codes: 0 success; 1 a check failed (validate, diff, the bake's own check); 2 bad input or usage.
//! A closed pipe on stdout (`bssrdf sample ... | head`) ends the program quietly with 0; a closed
//! stderr loses the messages, never panics.

mod cli;

use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    let argv: Vec<_> = std::env::args_os().collect();
    if let Err(e) = cli::check_forgotten_values(&argv) {
        e.exit();
    }
    let args = <cli::Cli as clap::Parser>::parse_from(argv);
    match cli::run(args) {
        Ok(code) => code,
        Err(err) if err.is_broken_pipe() => ExitCode::SUCCESS,
        Err(err) => {
            // A closed stderr loses the message, never panics (eprintln! would)
            let _ = writeln!(std::io::stderr(), "error: {err}");
            ExitCode::from(err.exit_code())
        }
    }
}
