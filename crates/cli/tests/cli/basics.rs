//! End-to-end tests of the `bssrdf` command: success, --json shape, and each error path.

use crate::common::{text, with_stdin};
use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// Runs `bssrdf ARGS` in the test's own folder.
fn bssrdf(args: &[&str]) -> Output {
    crate::common::bssrdf(Path::new("."), args)
}

fn bssrdf_with_stdin(args: &[&str], stdin: &str) -> Output {
    with_stdin(Path::new("."), args, stdin)
}

fn stdout(o: &Output) -> String {
    text(&o.stdout)
}
fn stderr(o: &Output) -> String {
    text(&o.stderr)
}

#[test]
fn eval_pbd_prints_the_value() {
    let o = bssrdf(&[
        "eval", "--model", "pbd", "--eta", "1.33", "--rho", "0.9", "--theta", "60", "--r", "1",
        "--phi", "0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: f64 = stdout(&o).trim().parse().unwrap();
    assert!((v / 2.559541511151654e-2 - 1.0).abs() < 1e-9, "{v}");
}

#[test]
fn eval_json_has_the_documented_keys() {
    let o = bssrdf(&[
        "eval",
        "--rho",
        "0.5",
        "--theta",
        "0",
        "--r",
        "0.127771746",
        "--json",
        "--fresnel-moments",
        "pbrt",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    for key in [
        "model",
        "eta",
        "fresnel_moments",
        "quadrature",
        "rho",
        "theta_deg",
        "r",
        "phi_deg",
        "value",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    assert_eq!(json["fresnel_moments"], "pbrt");
    // pbrt-v3's own value at this point (tests/data/pbrt-v3-pbd-profile-eta1.33-g0.csv).
    let v = json["value"].as_f64().unwrap();
    assert!((v / 0.0241326919 - 1.0).abs() < 1e-3, "{v}");
}

#[test]
fn eval_points_reads_stdin_and_writes_csv() {
    let input = "rho,theta_deg,r,phi_deg\n0.9,60,1,0\n0.5,0,0.1,180\n";
    let o = bssrdf_with_stdin(&["eval", "--points", "-", "--quadrature", "fast"], input);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "rho,theta_deg,r,phi_deg,value");
    assert_eq!(lines.len(), 3);
    let first: f64 = lines[1].rsplit(',').next().unwrap().parse().unwrap();
    assert!((first / 2.559541511151654e-2 - 1.0).abs() < 1e-6);
}

#[test]
fn bad_input_exits_2_and_names_the_value() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["eval", "--rho", "1.5", "--theta", "0", "--r", "1"],
            "--rho 1.5",
        ),
        (
            &["eval", "--rho", "0.5", "--theta", "91", "--r", "1"],
            "--theta 91",
        ),
        (
            &["eval", "--rho", "0.5", "--theta", "0", "--r", "-1"],
            "--r -1",
        ),
        (
            &["eval", "--rho", "NaN", "--theta", "0", "--r", "1"],
            "--rho NaN",
        ),
        (
            &[
                "eval", "--rho", "0.5", "--theta", "0", "--r", "1", "--eta", "0",
            ],
            "--eta 0 is outside the valid range",
        ),
        (&["eval", "--rho", "0.5", "--theta", "0"], "--r"),
    ];
    for (args, needle) in cases {
        let o = bssrdf(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"));
    }
}

#[test]
fn bad_points_files_exit_2_with_the_line() {
    let o = bssrdf_with_stdin(&["eval", "--points", "-"], "rho,theta_deg,r\n0.5,0,1\n");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("phi_deg"), "{}", stderr(&o));
    let o = bssrdf_with_stdin(
        &["eval", "--points", "-"],
        "rho,theta_deg,r,phi_deg\n0.5,0,abc,0\n",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains(":2: column r = \"abc\""),
        "{}",
        stderr(&o)
    );
    let o = bssrdf(&["eval", "--points", "/nonexistent/points.csv"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("/nonexistent/points.csv"));
}

#[test]
fn a_closed_pipe_ends_quietly() {
    let rows: String = (0..20000)
        .map(|i| format!("0.5,30,{},0\n", 0.01 + i as f64 * 1e-3))
        .collect();
    let mut child = Command::new(env!("CARGO_BIN_EXE_bssrdf"))
        .args(["eval", "--points", "-", "--quadrature", "fast"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(format!("rho,theta_deg,r,phi_deg\n{rows}").as_bytes());
    });
    // Read one line, then close our end of the pipe.
    let mut out = child.stdout.take().unwrap();
    let mut buf = [0u8; 64];
    let _ = std::io::Read::read(&mut out, &mut buf);
    drop(out);
    let o = child.wait_with_output().unwrap();
    writer.join().unwrap();
    assert!(o.status.success(), "{:?} {}", o.status, stderr(&o));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}
