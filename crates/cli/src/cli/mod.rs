//! Command-line definitions (clap) and dispatch. Each subcommand lives in its own file.

mod bake;
mod bake_scene;
mod bake_walk;
mod completions;
mod diff;
mod eval;
mod inspect;
mod invert;
mod library;
mod materials;
mod output;
mod pack;
mod points;
mod progress;
mod render;
mod sample;
mod validate;
mod values;
mod walk;
mod zoo;

use clap::error::ErrorKind;
use clap::{CommandFactory, Parser, Subcommand};
use std::ffi::OsString;
use std::fmt;
use std::process::ExitCode;

/// Tabulated BSSRDF models: bake, evaluate, sample, validate.
#[derive(Debug, Parser)]
#[command(
    name = "bssrdf",
    version,
    about,
    long_about = None,
    after_help = "Exit status: 0 success; 1 a check failed (validate, diff, the bake's own check); 2 bad input or usage."
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Every command takes negative numbers as values (`--g -0.5`, `--level -3`).
#[derive(Debug, Subcommand)]
enum Command {
    /// Bake angular tables for named materials, coefficients, a scene manifest (--scene) or a
    /// bare η into a library file.
    #[command(allow_negative_numbers = true)]
    Bake(bake::BakeArgs),
    /// Evaluate a model at one point or at every row of a CSV file.
    #[command(allow_negative_numbers = true)]
    Eval(eval::EvalArgs),
    /// Draw samples (r, φ) or path-tracing quadruples from a table, as CSV.
    #[command(allow_negative_numbers = true)]
    Sample(sample::SampleArgs),
    /// Find the reduced albedo ρ′ whose diffuse reflectance (1 − F_r) ρ_eff at θ is a given
    /// value: the artist's colour, per channel.
    #[command(allow_negative_numbers = true)]
    Invert(invert::InvertArgs),
    /// Run the accuracy protocol on a table: error against run time.
    #[command(allow_negative_numbers = true)]
    Validate(validate::ValidateArgs),
    /// Show a library file: version, sections and checksums, tables, materials, provenance.
    #[command(allow_negative_numbers = true)]
    Inspect(inspect::InspectArgs),
    /// Compress a library file with zstd for distribution (lossless).
    #[command(allow_negative_numbers = true)]
    Pack(pack::PackArgs),
    /// Decompress a library file into its mappable form (lossless).
    #[command(allow_negative_numbers = true)]
    Unpack(pack::UnpackArgs),
    /// List the named-material library.
    #[command(allow_negative_numbers = true)]
    Materials(materials::MaterialsArgs),
    /// Run the Monte Carlo random walk alone (the ground truth).
    #[command(allow_negative_numbers = true)]
    Walk(walk::WalkArgs),
    /// Compare every model with the Monte Carlo walk: error against run time.
    #[command(allow_negative_numbers = true)]
    Zoo(zoo::ZooArgs),
    /// Compare two library files: metadata, and every section's differences per table (exit 1
    /// when they differ beyond the tolerance).
    #[command(allow_negative_numbers = true)]
    Diff(diff::DiffArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    #[command(allow_negative_numbers = true)]
    Completions(completions::CompletionsArgs),
    /// Print the man page (roff) on stdout, or write one page per command with --dir.
    #[command(allow_negative_numbers = true)]
    Man(completions::ManArgs),
    /// Picture a beam entering a slab (EXR + PNG), or the difference of two pictures.
    #[command(allow_negative_numbers = true)]
    Render(render::RenderArgs),
}

/// Refuses an option whose value was forgotten, naming it and the option that follows. An
/// option that takes values starting with '-' (`--phi -inf`, `--bins -1,1,2,2`) takes the next
/// argument as its value whatever it is, so in `render --size --theta 30` `--theta` became the
/// size and clap then called `30` a stray argument; for the others clap says only that the
/// value is missing. Here an option that needs a value followed by one of the command's own
/// options names both.
pub fn check_forgotten_values(argv: &[OsString]) -> Result<(), clap::Error> {
    let mut cli = Cli::command();
    // Built, the subcommands know their usage ("bssrdf render [OPTIONS] ...")
    cli.build();
    let Some(sub) = argv.get(1).and_then(|name| cli.find_subcommand_mut(name)) else {
        return Ok(());
    };
    let is_option = |token: &str| match token.strip_prefix("--") {
        Some(long) => {
            let long = long.split('=').next().unwrap_or_default();
            long == "help" || sub.get_arguments().any(|a| a.get_long() == Some(long))
        }
        None => {
            let mut short = token.strip_prefix('-').unwrap_or_default().chars();
            match (short.next(), short.next()) {
                (Some(c), None) => {
                    c == 'h' || sub.get_arguments().any(|a| a.get_short() == Some(c))
                }
                _ => false,
            }
        }
    };
    // An option that needs a value (its value may not start with a hyphen: clap would say only
    // that the value is missing; it may: clap would take the next option as it)
    let needs_value = |option: &str| {
        let named = |a: &clap::Arg| match option.strip_prefix("--") {
            Some(long) => a.get_long() == Some(long),
            None => {
                let mut short = option.strip_prefix('-').unwrap_or_default().chars();
                matches!((short.next(), short.next()), (Some(c), None) if a.get_short() == Some(c))
            }
        };
        sub.get_arguments().any(|a| {
            let required = a.get_num_args().is_none_or(|n| n.min_values() >= 1);
            a.get_action().takes_values() && required && named(a)
        })
    };
    let mut forgotten = None;
    for pair in argv.get(2..).unwrap_or_default().windows(2) {
        let (Some(option), Some(next)) = (pair[0].to_str(), pair[1].to_str()) else {
            continue;
        };
        if option == "--" {
            break;
        }
        if needs_value(option) && is_option(next) {
            forgotten = Some(format!(
                "the value of {option} is missing: {next} is the next option, not a value"
            ));
            break;
        }
    }
    match forgotten {
        Some(message) => Err(sub.error(ErrorKind::InvalidValue, message)),
        None => Ok(()),
    }
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> Result<ExitCode, CliError> {
    match cli.command {
        Command::Bake(args) => bake::run(args),
        Command::Eval(args) => eval::run(args),
        Command::Sample(args) => sample::run(args),
        Command::Invert(args) => invert::run(args),
        Command::Validate(args) => validate::run(args),
        Command::Inspect(args) => inspect::run(args),
        Command::Pack(args) => pack::pack(args),
        Command::Unpack(args) => pack::unpack(args),
        Command::Materials(args) => materials::run(args),
        Command::Walk(args) => walk::run(args),
        Command::Zoo(args) => zoo::run(args),
        Command::Diff(args) => diff::run(args),
        Command::Completions(args) => completions::completions(args),
        Command::Man(args) => completions::man(args),
        Command::Render(args) => render::run(args),
    }
}

pub use values::{check_range, show, show_deg};

pub use bssrdf_zoo::MAX_THREADS;

/// Runs `f` on a pool of `threads` threads, or on the global pool when `None`. --threads is a
/// whole number in [1, MAX_THREADS].
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> T + Send,
) -> Result<T, CliError> {
    match threads {
        None => Ok(f()),
        Some(n) => {
            check_threads(Some(n))?;
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map(|pool| pool.install(f))
                .map_err(|e| CliError::input(format!("--threads {n}: {e}")))
        }
    }
}

/// Refuses fewer photons than a walk takes (`walk`, `zoo`, `render`): every estimate comes
/// with its standard error, which needs two.
pub fn check_photons(photons: u64) -> Result<(), CliError> {
    let min = bssrdf_zoo::walk::MIN_PHOTONS;
    if !(min..=MAX_PHOTONS).contains(&photons) {
        return Err(CliError::input(format!(
            "--photons {} is outside the valid range: [{min}, {}] (a standard error needs two; 1e12 photons are weeks on two cores)",
            values::show_whole(photons),
            values::show_whole(MAX_PHOTONS)
        )));
    }
    Ok(())
}

/// The most photons `walk`, `zoo` and `render` take, and `bake --source walk` per θ node: at a
/// few hundred thousand photons a second per core, a larger count is no run anyone waits for.
pub const MAX_PHOTONS: u64 = 1_000_000_000_000;

/// Refuses a Henyey–Greenstein --g outside (−1, 1), naming the flag.
pub fn check_g(g: f64) -> Result<(), CliError> {
    use std::ops::Bound::Excluded;
    check_range("--g", g, (Excluded(-1.0), Excluded(1.0)))
}

/// Refuses a --threads outside [1, MAX_THREADS] before any work.
pub fn check_threads(threads: Option<usize>) -> Result<(), CliError> {
    match threads {
        Some(n) if !(1..=MAX_THREADS).contains(&n) => Err(CliError::input(format!(
            "--threads {n} is outside the valid range: [1, {MAX_THREADS}]"
        ))),
        _ => Ok(()),
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
    /// A check failed (the bake's own accuracy check): exit code 1.
    Check(String),
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
            CliError::Check(_) => 1,
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
            CliError::Input(m) | CliError::Check(m) => f.write_str(m),
            CliError::Library(e) => write!(f, "{e}"),
            // Every file a command writes maps its errors to Input with the file's name; what is
            // left is the standard streams.
            CliError::Io(e) => write!(f, "cannot write the output (stdout or stderr): {e}"),
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
