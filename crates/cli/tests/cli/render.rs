//! `bssrdf render` end to end: files written, summaries printed, bad input refused with exit
//! code 2 and the value named.

use std::process::Output;

use crate::common::{bssrdf, ok};

fn fails_with(o: &Output, needle: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(needle), "{needle:?} not in {err}");
}

const SMALL: [&str; 6] = ["--photons", "3000", "--size", "32,24", "--grid", "coarse"];

#[test]
fn render_compare_and_diff_write_their_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args = vec!["render", "--preset", "figure-10", "-q", "-o", "beam.exr"];
    args.extend(SMALL);
    args.extend(["--theta", "60", "--compare", "perpendicular"]);
    let out = ok(&bssrdf(d, &args));
    assert!(
        out.contains("table model, ferrier-figure-10, theta 60 deg"),
        "{out}"
    );
    assert!(out.contains("perpendicular model"), "{out}");
    assert!(out.contains("reflected at entry"), "{out}");
    assert!(out.contains("centroid x"), "{out}");
    assert!(out.contains("relative L1"), "{out}");
    for f in [
        "beam.exr",
        "beam.png",
        "beam-perpendicular.exr",
        "beam-perpendicular.png",
        "beam-diff.exr",
        "beam-diff.png",
    ] {
        assert!(d.join(f).is_file(), "{f} missing");
    }
    let out = ok(&bssrdf(
        d,
        &[
            "render",
            "--diff",
            "beam.exr",
            "beam-perpendicular.exr",
            "-o",
            "again.exr",
            "--json",
        ],
    ));
    let json: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!(json["centroid_shift_mm"].as_f64().unwrap() > 0.1, "{json}");
    assert!(json["relative_l1"].as_f64().unwrap() > 0.0, "{json}");
    assert!(d.join("again.png").is_file());
}

#[test]
fn materials_and_coefficients_render_with_json_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args = vec![
        "render",
        "--material",
        "skin1",
        "--model",
        "mc",
        "--no-preview",
        "--json",
        "-o",
        "skin.exr",
        "--threads",
        "1",
    ];
    args.extend(["--photons", "200", "--theta", "30"]);
    let out = ok(&bssrdf(d, &args));
    let json: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let stats = &json["render"]["stats"];
    assert_eq!(stats["photons"], 200);
    assert!(stats["single"]["red"]["power"]["value"].as_f64().unwrap() > 0.0);
    assert_eq!(json["render"]["meta"]["material"], "skin1");
    assert!(d.join("skin.exr").is_file() && !d.join("skin.png").exists());

    let mut args = vec![
        "render",
        "--sigma-s",
        "1,1,1",
        "--sigma-a",
        "0.01,0.1,1",
        "--g",
        "-0.2",
        "--eta",
        "1.4",
        "-q",
        "-o",
        "c.exr",
        "--theta",
        "60",
    ];
    args.extend(SMALL);
    let out = ok(&bssrdf(d, &args));
    assert!(out.contains("table model, coefficients"), "{out}");
}

#[test]
fn bad_input_exits_2_and_names_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let with = |extra: &[&str]| {
        let mut args = vec!["render", "--preset", "figure-10", "-q", "-o", "x.exr"];
        args.extend(["--photons", "3000", "--grid", "coarse"]);
        args.extend(extra);
        bssrdf(d, &args)
    };
    fails_with(&with(&["--theta", "95"]), "--theta 95");
    // Each message names the flags and the values as given
    fails_with(
        &with(&["--theta", "30", "--cone", "60"]),
        "--theta 30 plus --cone 60 reaches 90 deg",
    );
    fails_with(
        &with(&["--theta", "6", "--size", "0,5"]),
        "each side is a whole number of pixels in [1, 4096], not 0",
    );
    fails_with(
        &with(&["--theta", "6", "--size", "-16,16"]),
        "each side is a whole number of pixels in [1, 4096], not -16",
    );
    fails_with(&with(&["--theta", "6", "--size", "16.5,16"]), "not 16.5");
    fails_with(
        &with(&["--theta", "6", "--extent", "1e21"]),
        "--extent 1e21 is outside the valid range: (0, 1e6]",
    );
    fails_with(
        &with(&["--theta", "6", "--size", "16,100000"]),
        "each side is a whole number of pixels in [1, 4096], not 100000",
    );
    fails_with(
        &with(&["--theta", "6", "--compare", "table"]),
        "--compare table is the --model",
    );
    fails_with(
        &with(&["--theta", "6", "--size", "5"]),
        "expected 2 comma-separated numbers W,H",
    );
    fails_with(
        &with(&["--theta", "6", "--extent", "-2"]),
        "--extent -2 is outside the valid range",
    );
    let zero = [
        "render",
        "--preset",
        "figure-10",
        "--theta",
        "6",
        "--photons",
        "0",
    ];
    fails_with(
        &bssrdf(d, &[&zero[..], &["-o", "x.exr"]].concat()),
        "--photons 0 is outside the valid range: [2, 1e12]",
    );
    fails_with(&with(&["--theta", "6", "--model", "dipole"]), "dipole");
    let no_medium = bssrdf(d, &["render", "--theta", "10", "-o", "x.exr"]);
    fails_with(&no_medium, "--preset figure-10");
    let typo = bssrdf(
        d,
        &[
            "render",
            "--material",
            "skin-1",
            "--theta",
            "10",
            "-o",
            "x.exr",
        ],
    );
    fails_with(&typo, "skin1");
    let bad_sigma = bssrdf(
        d,
        &[
            "render",
            "--sigma-s",
            "1,-1,1",
            "--sigma-a",
            "0,0,0",
            "--theta",
            "10",
            "-o",
            "x.exr",
        ],
    );
    fails_with(&bad_sigma, "-1");
    let missing = bssrdf(d, &["render", "--diff", "a.exr", "b.exr", "-o", "d.exr"]);
    fails_with(&missing, "a.exr");
    std::fs::write(d.join("junk.exr"), b"not an exr").unwrap();
    let junk = bssrdf(
        d,
        &["render", "--diff", "junk.exr", "junk.exr", "-o", "d.exr"],
    );
    fails_with(&junk, "junk.exr");
    assert!(!d.join("x.exr").exists() && !d.join("d.exr").exists());
}
