//! Helpers shared by the end-to-end tests of the `bssrdf` binary.
// Each test crate uses a subset of these.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

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
