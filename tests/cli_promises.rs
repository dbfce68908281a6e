//! End-to-end tests of the command line's promises (issue 18): no pass on nothing checked, no
//! flag accepted and ignored, no conflicting inputs, no device or input overwritten, one set
//! of CSV columns, negative numbers, every value outside its domain refused with exit 2.

use std::path::Path;
use std::process::{Command, Output, Stdio};

mod cli_common;
use cli_common::{bssrdf, ok, text};

fn fails_with(o: &Output, code: i32, needle: &str) {
    assert_eq!(o.status.code(), Some(code), "stderr: {}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains(needle),
        "{needle:?} not in {}",
        text(&o.stderr)
    );
    assert!(!text(&o.stderr).contains("panicked"));
}

/// Runs `bssrdf ARGS` in `dir` with `stdin` on its standard input.
fn with_stdin(dir: &Path, args: &[&str], stdin: &str) -> Output {
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
fn bare() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    ok(&bssrdf(
        dir.path(),
        &[
            "bake", "--eta", "1.33", "--grid", "coarse", "-q", "-o", "t.bssrdf",
        ],
    ));
    dir
}

// ---- Outputs: devices, links, modes, stale temporaries, inputs ----

#[cfg(unix)]
#[test]
fn devices_are_written_through_never_replaced() {
    use std::os::unix::fs::FileTypeExt;
    let dir = bare();
    let d = dir.path();
    // /dev/full: the write fails, the error names the device, the node stays a device.
    for args in [
        vec!["pack", "t.bssrdf", "-o", "/dev/full"],
        vec!["unpack", "t.bssrdf", "-o", "/dev/full"],
        vec![
            "bake",
            "--eta",
            "1.33",
            "--grid",
            "coarse",
            "-q",
            "-o",
            "/dev/full",
        ],
        vec![
            "walk",
            "--albedo",
            "0.5",
            "--photons",
            "100",
            "--profile",
            "/dev/full",
        ],
    ] {
        fails_with(&bssrdf(d, &args), 2, "/dev/full");
        let kind = std::fs::metadata("/dev/full").unwrap().file_type();
        assert!(kind.is_char_device(), "{args:?} replaced /dev/full");
    }
    ok(&bssrdf(d, &["pack", "t.bssrdf", "-o", "/dev/null"]));
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    // A folder is refused with its name.
    std::fs::create_dir(d.join("folder")).unwrap();
    fails_with(
        &bssrdf(d, &["pack", "t.bssrdf", "-o", "folder"]),
        2,
        "folder: it is a folder, not a regular file",
    );
}

#[cfg(unix)]
#[test]
fn links_are_followed_and_modes_kept() {
    use std::os::unix::fs::PermissionsExt;
    let dir = bare();
    let d = dir.path();
    std::os::unix::fs::symlink("t.bssrdf", d.join("link.bssrdf")).unwrap();
    std::fs::set_permissions(d.join("t.bssrdf"), std::fs::Permissions::from_mode(0o640)).unwrap();
    ok(&bssrdf(d, &["pack", "link.bssrdf"]));
    let link = std::fs::symlink_metadata(d.join("link.bssrdf")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced");
    let target = std::fs::metadata(d.join("t.bssrdf")).unwrap();
    assert_eq!(target.permissions().mode() & 0o777, 0o640);
    let inspect = ok(&bssrdf(d, &["inspect", "t.bssrdf"]));
    assert!(inspect.contains("zstd"), "{inspect}");
}

#[test]
fn stale_temporaries_of_dead_writers_are_removed() {
    let dir = bare();
    let d = dir.path();
    // A PID above Linux's maximum (2^22) never runs; this process runs.
    let dead = d.join(".t.bssrdf.4194305.0.tmp");
    let alive = d.join(format!(".t.bssrdf.{}.0.tmp", std::process::id()));
    let other = d.join(".u.bssrdf.4194305.0.tmp");
    for p in [&dead, &alive, &other] {
        std::fs::write(p, b"partial").unwrap();
    }
    ok(&bssrdf(
        d,
        &[
            "bake", "--eta", "1.33", "--grid", "coarse", "-q", "-o", "t.bssrdf",
        ],
    ));
    if Path::new("/proc/self").exists() {
        assert!(!dead.exists(), "the dead writer's file stayed");
    }
    assert!(alive.exists(), "a running writer's file was removed");
    assert!(other.exists(), "another target's file was removed");
}

#[test]
fn outputs_never_overwrite_inputs_or_each_other() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let render = [
        "render",
        "--preset",
        "figure-10",
        "--theta",
        "0",
        "--photons",
        "200",
        "--size",
        "4,4",
        "-q",
    ];
    let with = |extra: &[&str]| -> Vec<String> {
        render.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let run = |args: Vec<String>| {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        bssrdf(d, &refs)
    };
    fails_with(
        &run(with(&["-o", "x.png"])),
        2,
        "-o x.png and the PNG preview of -o x.png are the same file",
    );
    assert!(!d.join("x.png").exists());
    ok(&run(with(&["-o", "a.exr"])));
    let before = std::fs::read(d.join("a.exr")).unwrap();
    fails_with(
        &bssrdf(d, &["render", "--diff", "a.exr", "a.exr", "-o", "a.exr"]),
        2,
        "-o a.exr is the input --diff a.exr",
    );
    assert_eq!(std::fs::read(d.join("a.exr")).unwrap(), before);
    let scene = "[integrator]\nkind = \"path\"\n";
    std::fs::write(d.join("s.toml"), scene).unwrap();
    fails_with(
        &bssrdf(d, &["bake", "--scene", "s.toml", "-o", "s.toml"]),
        2,
        "-o s.toml is the input --scene s.toml",
    );
    assert_eq!(std::fs::read_to_string(d.join("s.toml")).unwrap(), scene);
}
