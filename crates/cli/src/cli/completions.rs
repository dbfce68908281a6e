//! `bssrdf completions SHELL` and `bssrdf man`: shell completion scripts and roff manual pages,
//! generated from the clap definitions, so they never drift from the real options.
//!
//! Both are rendered into memory first and then written, so a closed pipe or a full disk is an
//! error like any other output error (the generators themselves panic on write errors).

use super::{Cli, CliError};
use clap::{Args, CommandFactory};
use clap_mangen::roff::{roman, Roff};
use clap_mangen::Man;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete for. Install, e.g.:
    /// bash: `bssrdf completions bash > ~/.local/share/bash-completion/completions/bssrdf`;
    /// zsh: `bssrdf completions zsh > ~/.zfunc/_bssrdf` (with ~/.zfunc in fpath);
    /// fish: `bssrdf completions fish > ~/.config/fish/completions/bssrdf.fish`.
    #[arg(value_enum)]
    shell: clap_complete::Shell,
}

#[derive(Debug, Args)]
pub struct ManArgs {
    /// Write bssrdf.1 and one page per command (bssrdf-bake.1, …) into this folder instead of
    /// printing bssrdf.1 on stdout.
    #[arg(long, value_name = "DIR")]
    dir: Option<PathBuf>,
}

/// The exit codes, for the man page (the same text is in the README and `bssrdf --help`).
const EXIT_STATUS: [(&str, &str); 3] = [
    (
        "0",
        "success; for diff: the files agree within the tolerance",
    ),
    (
        "1",
        "a check failed: validate found a case above its bound, a case it could not tell (too few points: inconclusive) or nothing to check; diff found differences; bake's own check found a table above its bound (nothing written unless --accept-error)",
    ),
    (
        "2",
        "bad input or usage: an invalid value, a missing or corrupt file, an unknown option",
    ),
];

pub fn completions(args: CompletionsArgs) -> Result<ExitCode, CliError> {
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut Cli::command(), "bssrdf", &mut script);
    let mut out = std::io::stdout().lock();
    out.write_all(&script)?;
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// The top-level page: clap's sections plus EXIT STATUS.
fn main_page() -> Result<Vec<u8>, CliError> {
    let mut cmd = Cli::command();
    cmd.build();
    let man = Man::new(cmd);
    let mut page = Vec::new();
    man.render_title(&mut page)?;
    man.render_name_section(&mut page)?;
    man.render_synopsis_section(&mut page)?;
    man.render_description_section(&mut page)?;
    man.render_options_section(&mut page)?;
    man.render_subcommands_section(&mut page)?;
    let mut roff = Roff::default();
    roff.control("SH", ["EXIT STATUS"]);
    for (code, meaning) in EXIT_STATUS {
        roff.control("TP", [])
            .text([roman(code)])
            .text([roman(meaning)]);
    }
    roff.text([roman(
        "Errors name the bad value. A closed pipe on standard output ends the program quietly with 0.",
    )]);
    roff.to_writer(&mut page)?;
    man.render_version_section(&mut page)?;
    Ok(page)
}

pub fn man(args: ManArgs) -> Result<ExitCode, CliError> {
    let page = main_page()?;
    match args.dir {
        Some(dir) => {
            let fail = |e: std::io::Error| {
                CliError::input(format!("cannot write man pages to {}: {e}", dir.display()))
            };
            if dir.exists() && !dir.is_dir() {
                return Err(CliError::input(format!(
                    "--dir {} is not a folder for the pages",
                    dir.display()
                )));
            }
            // Every page rendered and every path checked before the first is written: a page
            // that cannot be written stops the command before it leaves half a set
            let mut cmd = Cli::command().disable_help_subcommand(true);
            cmd.build();
            // clap's own bssrdf.1 lacks the exit codes: ours replaces it.
            let mut pages = vec![(dir.join("bssrdf.1"), page)];
            for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
                let man = clap_mangen::Man::new(sub.clone());
                let mut bytes = Vec::new();
                man.render(&mut bytes).map_err(fail)?;
                pages.push((dir.join(man.get_filename()), bytes));
            }
            std::fs::create_dir_all(&dir).map_err(fail)?;
            let outputs: Vec<(&str, &std::path::Path)> = pages
                .iter()
                .map(|(path, _)| ("the page", path.as_path()))
                .collect();
            super::output::check(&outputs, &[])?;
            for (path, bytes) in &pages {
                // The safe writer: no torn page, no device replaced
                bssrdf_zoo::format::write_file_atomic(path, bytes)
                    .map_err(|e| CliError::input(format!("cannot write a man page: {e}")))?;
            }
        }
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(&page)?;
            out.flush()?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
