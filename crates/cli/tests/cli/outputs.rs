//! End-to-end tests of the command line's output files (issue 18): devices, FIFOs and
//! `/dev/stdout` written through and never replaced, links followed, modes kept, stale
//! temporaries of dead writers removed, no output overwriting an input or another output.

use std::path::Path;

#[cfg(unix)]
use crate::common::shell;
use crate::common::{bare, bssrdf, fails_with, ok};

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
    // render: the EXR is written through with --no-preview; a preview named after the device
    // is refused.
    let render = [
        "render",
        "--preset",
        "figure-10",
        "--theta",
        "0",
        "--photons",
        "100",
        "--size",
        "4,4",
        "-q",
        "-o",
    ];
    fails_with(
        &bssrdf(d, &[&render[..], &["/dev/full", "--no-preview"]].concat()),
        2,
        "/dev/full",
    );
    fails_with(
        &bssrdf(d, &[&render[..], &["/dev/null"]].concat()),
        2,
        "-o /dev/null is not a regular file",
    );
    ok(&bssrdf(
        d,
        &[&render[..], &["/dev/null", "--no-preview"]].concat(),
    ));
    assert!(!Path::new("/dev/null.png").exists());
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
    // Dead but fresh: its PID may be another PID namespace's, whose writer still runs.
    let fresh = d.join(".t.bssrdf.4194305.1.tmp");
    for p in [&dead, &alive, &other, &fresh] {
        std::fs::write(p, b"partial").unwrap();
    }
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(2 * 3600);
    for p in [&dead, &alive, &other] {
        let file = std::fs::File::options().write(true).open(p).unwrap();
        file.set_modified(old).unwrap();
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
    assert!(
        fresh.exists(),
        "a temporary younger than an hour was removed"
    );
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
        "-o x.png and -o's PNG preview x.png are the same file",
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

#[cfg(unix)]
#[test]
fn dev_stdout_is_written_through_on_a_pipe_and_on_a_file() {
    let dir = bare();
    let d = dir.path();
    let size = std::fs::metadata(d.join("t.bssrdf")).unwrap().len();
    let bake = "$B bake --eta 1.33 --grid coarse -q -o /dev/stdout";
    // A pipe: /dev/stdout -> /proc/self/fd/1 -> "pipe:[N]", which names no path.
    let piped = shell(d, &format!("set -e; {bake} | wc -c"));
    assert!(
        piped.status.success(),
        "{}",
        String::from_utf8_lossy(&piped.stderr)
    );
    let count: u64 = String::from_utf8_lossy(&piped.stdout)
        .trim()
        .parse()
        .unwrap();
    assert_eq!(count, size);
    // A regular file behind /dev/stdout: written through (appended), nothing renamed over it.
    let to_file = shell(d, &format!("echo head > out.bin && {bake} >> out.bin"));
    assert!(
        to_file.status.success(),
        "{}",
        String::from_utf8_lossy(&to_file.stderr)
    );
    let bytes = std::fs::read(d.join("out.bin")).unwrap();
    assert_eq!(&bytes[..5], b"head\n");
    assert_eq!(&bytes[5..], &std::fs::read(d.join("t.bssrdf")).unwrap()[..]);
    let plain = shell(d, &format!("{bake} > plain.bin && $B inspect plain.bin"));
    assert!(
        plain.status.success(),
        "{}",
        String::from_utf8_lossy(&plain.stderr)
    );
    // --json counts the bytes written, also into /dev/null.
    let o = ok(&bssrdf(
        d,
        &[
            "bake",
            "--eta",
            "1.33",
            "--grid",
            "coarse",
            "-q",
            "--json",
            "-o",
            "/dev/null",
        ],
    ));
    let v: serde_json::Value = serde_json::from_str(o.trim()).unwrap();
    assert_eq!(v["bytes"].as_u64(), Some(size), "{o}");
}

/// An output given as "-" is refused by every command that writes a file: it would be a file
/// named "-", not stdout.
#[test]
fn an_output_named_dash_is_refused() {
    let dir = bare();
    let d = dir.path();
    for args in [
        vec!["pack", "t.bssrdf", "-o", "-"],
        vec!["unpack", "t.bssrdf", "-o", "-"],
        vec!["bake", "--eta", "1.33", "--grid", "coarse", "-q", "-o", "-"],
        vec![
            "walk",
            "--albedo",
            "0.9",
            "--photons",
            "1000",
            "--profile",
            "-",
        ],
    ] {
        let what = args[args.len() - 2];
        fails_with(
            &bssrdf(d, &args),
            2,
            &format!("{what} - would be a file named \"-\", not stdout"),
        );
        assert!(!d.join("-").exists(), "{args:?}");
    }
    // A file named "-" is ./-
    ok(&bssrdf(d, &["pack", "t.bssrdf", "-o", "./-"]));
    assert!(d.join("-").is_file());
}

/// pack and unpack rewrite FILE in place through a temporary file; never through a descriptor
/// that leads to the input (it would be written into itself, and a pipe would never end), and
/// an -o that is the input is refused as for every command.
#[cfg(unix)]
#[test]
fn pack_and_unpack_never_write_into_their_input() {
    let dir = bare();
    let d = dir.path();
    let original = std::fs::read(d.join("t.bssrdf")).unwrap();
    for (script, needle) in [
        (
            "$B pack /dev/stdin < t.bssrdf",
            "FILE /dev/stdin is not a regular file that can be rewritten in place",
        ),
        (
            "cat t.bssrdf | $B unpack /dev/stdin",
            "FILE /dev/stdin is not a regular file",
        ),
        (
            "$B unpack t.bssrdf -o /dev/stdout >> t.bssrdf",
            "-o /dev/stdout is the input FILE t.bssrdf",
        ),
        (
            "$B pack t.bssrdf -o /dev/fd/3 3>> t.bssrdf",
            "-o /dev/fd/3 is the input FILE t.bssrdf",
        ),
        (
            "$B pack t.bssrdf -o ./t.bssrdf",
            "-o ./t.bssrdf is the input",
        ),
        // The same spelling as FILE is FILE too (in place is -o left out)
        (
            "$B pack t.bssrdf -o t.bssrdf",
            "-o t.bssrdf is the input FILE",
        ),
        (
            "$B unpack t.bssrdf -o t.bssrdf",
            "-o t.bssrdf is the input FILE",
        ),
        (
            "$B unpack t.bssrdf -o ./t.bssrdf",
            "-o ./t.bssrdf is the input",
        ),
        (
            "ln -sf t.bssrdf link.bssrdf && $B pack link.bssrdf -o t.bssrdf",
            "-o t.bssrdf is the input FILE link.bssrdf",
        ),
        (
            "$B pack no-such.bssrdf --level 99",
            "--level 99 is outside the valid range: [-131072, 22]",
        ),
        ("$B pack no-such.bssrdf", "No such file or directory"),
        (
            "mkdir -p folder && $B unpack folder",
            "FILE folder is a folder",
        ),
    ] {
        let out = shell(d, script);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{script}: {stderr}");
        assert!(stderr.contains(needle), "{script}: {stderr}");
        assert_eq!(
            std::fs::read(d.join("t.bssrdf")).unwrap(),
            original,
            "{script}"
        );
    }
    // In place, and to a stream, still work
    let round = shell(d, "$B pack t.bssrdf --level -3 && $B unpack t.bssrdf -o /dev/stdout > u.bssrdf && $B unpack t.bssrdf");
    assert!(
        round.status.success(),
        "{}",
        String::from_utf8_lossy(&round.stderr)
    );
    assert_eq!(std::fs::read(d.join("t.bssrdf")).unwrap(), original);
    assert_eq!(std::fs::read(d.join("u.bssrdf")).unwrap(), original);
}

#[cfg(unix)]
#[test]
fn a_replaced_file_keeps_its_mode_and_a_new_one_gets_the_umask() {
    use std::os::unix::fs::PermissionsExt;
    let dir = bare();
    let d = dir.path();
    for mode in [0o600, 0o644, 0o640, 0o755] {
        std::fs::set_permissions(d.join("t.bssrdf"), std::fs::Permissions::from_mode(mode))
            .unwrap();
        ok(&bssrdf(d, &["pack", "t.bssrdf"]));
        let now = std::fs::metadata(d.join("t.bssrdf")).unwrap();
        assert_eq!(now.permissions().mode() & 0o7777, mode);
    }
    let new = shell(d, "umask 027 && $B pack t.bssrdf -o new.bssrdf");
    assert!(
        new.status.success(),
        "{}",
        String::from_utf8_lossy(&new.stderr)
    );
    let mode = std::fs::metadata(d.join("new.bssrdf"))
        .unwrap()
        .permissions()
        .mode();
    assert_eq!(mode & 0o777, 0o640);
}

#[cfg(unix)]
#[test]
fn man_pages_are_written_by_the_safe_writer() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("man")).unwrap();
    // A page that is a link to a file: the link stays, its target gets the page.
    std::os::unix::fs::symlink("../kept.1", d.join("man/bssrdf-bake.1")).unwrap();
    ok(&bssrdf(d, &["man", "--dir", "man"]));
    let link = std::fs::symlink_metadata(d.join("man/bssrdf-bake.1")).unwrap();
    assert!(link.file_type().is_symlink());
    let page = std::fs::read_to_string(d.join("kept.1")).unwrap();
    assert!(page.contains("bake"), "{page}");
    assert!(std::fs::read_to_string(d.join("man/bssrdf.1"))
        .unwrap()
        .contains("EXIT STATUS"));
    // A folder where a page goes is refused with its name, not overwritten.
    std::fs::remove_file(d.join("man/bssrdf-eval.1")).unwrap();
    std::fs::create_dir(d.join("man/bssrdf-eval.1")).unwrap();
    fails_with(
        &bssrdf(d, &["man", "--dir", "man"]),
        2,
        "bssrdf-eval.1: it is a folder, not a regular file",
    );
    // ... before any page is written: in a new folder, nothing is left behind
    std::fs::create_dir_all(d.join("fresh/bssrdf-zoo.1")).unwrap();
    fails_with(
        &bssrdf(d, &["man", "--dir", "fresh"]),
        2,
        "bssrdf-zoo.1: it is a folder",
    );
    let left: Vec<_> = std::fs::read_dir(d.join("fresh")).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
    // A link into a missing folder, and a --dir that is a file, are refused the same way
    std::fs::create_dir(d.join("links")).unwrap();
    std::os::unix::fs::symlink("/nonexistent/dir/x", d.join("links/bssrdf-walk.1")).unwrap();
    fails_with(
        &bssrdf(d, &["man", "--dir", "links"]),
        2,
        "its folder /nonexistent/dir does not exist",
    );
    assert_eq!(std::fs::read_dir(d.join("links")).unwrap().count(), 1);
    std::fs::write(d.join("plain"), "x").unwrap();
    fails_with(
        &bssrdf(d, &["man", "--dir", "plain"]),
        2,
        "--dir plain is not a folder for the pages",
    );
}

#[cfg(unix)]
#[test]
fn zoo_plots_are_written_by_the_safe_writer() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("plots")).unwrap();
    std::os::unix::fs::symlink("../pareto-kept.svg", d.join("plots/pareto.svg")).unwrap();
    let zoo = [
        "zoo",
        "--photons",
        "1000",
        "--cases",
        "0.5:0",
        "--models",
        "dipole",
        "-q",
        "--plot",
        "plots",
    ];
    ok(&bssrdf(d, &zoo));
    let link = std::fs::symlink_metadata(d.join("plots/pareto.svg")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced");
    assert!(std::fs::read_to_string(d.join("pareto-kept.svg"))
        .unwrap()
        .starts_with("<svg"));
    std::fs::remove_file(d.join("plots/profiles-rho0.5-theta0.svg")).unwrap();
    std::fs::create_dir(d.join("plots/profiles-rho0.5-theta0.svg")).unwrap();
    fails_with(
        &bssrdf(d, &zoo),
        2,
        "profiles-rho0.5-theta0.svg: it is a folder, not a regular file",
    );
}

/// zoo --plot writes its figures into a folder and its report on stdout: stdout redirected onto
/// a figure (the shell makes the file before the command starts) is refused before the walks,
/// and the report is never lost under a figure.
#[cfg(target_os = "linux")]
#[test]
fn zoo_refuses_stdout_redirected_onto_one_of_its_figures() {
    let dir = bare();
    let d = dir.path();
    std::fs::create_dir(d.join("plots")).unwrap();
    let zoo = "$B zoo -q --photons 100 --cases 0.5:0 --models dipole";
    for (script, needle) in [
        (
            format!("{zoo} --plot plots --json > plots/profiles-rho0.5-theta0.svg"),
            "the --plot figure plots/profiles-rho0.5-theta0.svg is stdout, where the command writes its table (or --json report)",
        ),
        (
            format!("cd plots && {zoo} --plot . > pareto.svg"),
            "the --plot figure ./pareto.svg is stdout",
        ),
    ] {
        let o = shell(d, &script);
        assert_eq!(o.status.code(), Some(2), "{script}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{script}: {err}");
    }
    assert_eq!(std::fs::read(d.join("plots/pareto.svg")).unwrap(), b"");
    // Redirected elsewhere, the same run writes its figures and its report
    let o = shell(d, &format!("{zoo} --plot plots --json > report.json"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = std::fs::read_to_string(d.join("report.json")).unwrap();
    assert!(serde_json::from_str::<serde_json::Value>(&report).is_ok());
    assert!(std::fs::metadata(d.join("plots/pareto.svg")).unwrap().len() > 0);
}
