//! Helpers shared by the end-to-end tests of the `bssrdf` binary.
// Each test crate uses a subset of these.

use std::path::Path;
use std::process::{Command, Output, Stdio};

/// Runs `bssrdf ARGS` in `dir`.
pub fn bssrdf(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bssrdf"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Lossy UTF-8 of captured output.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Stdout of a run that must succeed (its stderr in the failure message otherwise).
pub fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{:?}: {}", o.status, text(&o.stderr));
    text(&o.stdout)
}

/// Asserts exit `code` and `needle` in stderr, and no panic.
pub fn fails_with(o: &Output, code: i32, needle: &str) {
    assert_eq!(o.status.code(), Some(code), "stderr: {}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains(needle),
        "{needle:?} not in {}",
        text(&o.stderr)
    );
    assert!(!text(&o.stderr).contains("panicked"));
}

/// Runs `bssrdf ARGS` in `dir` with `stdin` on its standard input.
pub fn with_stdin(dir: &Path, args: &[&str], stdin: &str) -> Output {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_bssrdf"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut input = child.stdin.take().expect("stdin is piped");
    input
        .write_all(stdin.as_bytes())
        .expect("stdin takes the input");
    drop(input);
    child.wait_with_output().expect("the binary ends")
}

/// A coarse bare table at η = 1.33 as `t.bssrdf` in a fresh folder.
pub fn bare() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    ok(&bssrdf(
        dir.path(),
        &[
            "bake", "--eta", "1.33", "--grid", "coarse", "-q", "-o", "t.bssrdf",
        ],
    ));
    dir
}

/// Runs `sh -c SCRIPT` in `dir` with `$B` the binary; its output and exit status.
#[cfg(unix)]
pub fn shell(dir: &Path, script: &str) -> Output {
    Command::new("sh")
        .current_dir(dir)
        .env("B", env!("CARGO_BIN_EXE_bssrdf"))
        .args(["-c", script])
        .output()
        .expect("sh runs")
}
