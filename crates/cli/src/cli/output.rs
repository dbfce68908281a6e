//! Checks on the files a command writes, before its work: each one writable as what it is,
//! not `-`, no two outputs on one file, no output on an input.

use super::CliError;
use std::path::{Path, PathBuf};

/// A path as the file system resolves it: links followed, `..` removed. A path that does not
/// exist yet is its resolved folder joined with its file name.
fn identity(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match (std::fs::canonicalize(dir), path.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => path.to_path_buf(),
    }
}

/// Refuses outputs that name the same file as another output or as an input. Each path comes
/// with what it is on the command line (`"-o"`, `"--scene"`, `"the PNG preview"`), which the
/// message names.
pub fn check(outputs: &[(&str, &Path)], inputs: &[(&str, &Path)]) -> Result<(), CliError> {
    // A folder (or a device that is no stream) is refused now, not after the work
    for (what, path) in outputs {
        // "-" reads as stdout but would be a file named "-": stdout is /dev/stdout here
        if path.as_os_str() == "-" {
            return Err(CliError::input(format!(
                "{what} - would be a file named \"-\", not stdout: write to stdout with /dev/stdout, or to that file with ./-"
            )));
        }
        bssrdf_zoo::format::check_writable(path).map_err(|e| CliError::input(e.to_string()))?;
        // Messages (warnings, errors) go to stderr: a file written there would mix with them
        if is_stream_of(path, "/dev/stderr") {
            return Err(CliError::input(format!(
                "{what} {} is the command's stderr, where its messages go: the file would be mixed with them",
                path.display()
            )));
        }
    }
    let ids: Vec<PathBuf> = outputs.iter().map(|(_, p)| identity(p)).collect();
    for (i, (what, path)) in outputs.iter().enumerate() {
        for (j, (other, other_path)) in outputs.iter().enumerate().take(i) {
            if ids[i] == ids[j] || same_regular_file(path, other_path) {
                return Err(CliError::input(format!(
                    "{what} {} and {other} {} are the same file: one would overwrite the other",
                    path.display(),
                    other_path.display()
                )));
            }
        }
        for (input, input_path) in inputs {
            if ids[i] == identity(input_path) || same_regular_file(path, input_path) {
                return Err(CliError::input(format!(
                    "{what} {} is the input {input} {}: refusing to overwrite an input",
                    path.display(),
                    input_path.display()
                )));
            }
        }
    }
    Ok(())
}

/// Whether two paths lead to one existing regular file, whatever leads there: another name of
/// it (a hard link), a symbolic link, or a descriptor (`/dev/stdout` with the shell's stdout
/// redirected into it). Same device and inode; devices and pipes are never the same file
/// here (`/dev/null` may be every output of a command).
fn same_regular_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => {
                x.is_file() && y.is_file() && x.dev() == y.dev() && x.ino() == y.ino()
            }
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (a, b);
        false
    }
}

/// Refuses an output that is the command's stdout when the command prints `prints` there too:
/// the file would be mixed with it. `instead` says how to avoid it.
pub fn not_on_stdout(what: &str, path: &Path, prints: &str, instead: &str) -> Result<(), CliError> {
    if is_stream_of(path, "/dev/stdout") {
        return Err(CliError::input(format!(
            "{what} {} is stdout, where the command writes {prints}: the file would be mixed with it; {instead}",
            path.display()
        )));
    }
    Ok(())
}

/// Whether `path` is the file a standard stream (`/dev/stdin`, `/dev/stdout`, `/dev/stderr`) leads to: the
/// same device and inode, whatever the path's spelling (`/dev/fd/2`, `/proc/self/fd/2`).
pub fn is_stream_of(path: &Path, stream: &str) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(path), std::fs::metadata(stream)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (path, stream);
        false
    }
}
