//! End-to-end tests of numbers on the command line (issue 18): messages print 1e308, not 309
//! digits; η's domain [0.75, 2.5] everywhere; eval's JSON value a number or null with its
//! limit; ρ′ checked against a table's kept albedo rows before any output, and a material's
//! table chosen by them; material sources over 256 bytes refused, never cut.

use crate::common::{bare, bssrdf, fails_with, ok, text};

// ---- Numbers in messages and JSON ----

#[test]
fn large_values_print_short_and_eta_has_its_domain() {
    let dir = bare();
    let d = dir.path();
    let render = ["render", "--preset", "figure-10", "-q", "-o", "x.exr"];
    for (args, needle) in [
        (
            [&render[..], &["--theta", "1e308"]].concat(),
            "--theta 1e308 is outside the valid range: [0, 90)",
        ),
        (
            [&render[..], &["--theta", "0", "--cone", "1e300"]].concat(),
            "--cone 1e300 is outside the valid range: [0, 90)",
        ),
        (
            vec!["walk", "--albedo", "0.5", "--theta", "1e308"],
            "--theta 1e308 is outside the valid range: [0, 90]",
        ),
        (
            vec!["validate", "t.bssrdf", "--max-mean-error", "-1e308"],
            "--max-mean-error -1e308 is outside the valid range: [0, 1e4]",
        ),
        (
            vec![
                "diff",
                "t.bssrdf",
                "t.bssrdf",
                "--tolerance",
                "1e308",
                "--abs-tolerance",
                "-1e300",
            ],
            "--abs-tolerance -1e300 is outside the valid range: a finite number >= 0",
        ),
        (
            vec!["diff", "t.bssrdf", "t.bssrdf", "--abs-tolerance", "1e400"],
            "--abs-tolerance inf is outside the valid range: a finite number >= 0 (a number \
             beyond ±1.8e308 reads as ±inf)",
        ),
        (
            vec![
                "eval", "t.bssrdf", "--eta", "1e308", "--rho", "0.5", "--theta", "0", "--r", "1",
            ],
            "--eta 1e308 is outside the valid range: [0.75, 2.5]",
        ),
        (
            vec!["sample", "t.bssrdf", "--eta", "2.6", "--rho", "0.5"],
            "--eta 2.6 is outside the valid range: [0.75, 2.5]",
        ),
        (
            vec![
                "bake",
                "--sigma-s",
                "1,1,1",
                "--sigma-a",
                "1,1,1",
                "--eta",
                "1e308",
            ],
            "--eta 1e308 is outside the valid range: [0.75, 2.5]",
        ),
    ] {
        let o = bssrdf(d, &args);
        fails_with(&o, 2, needle);
        assert!(!text(&o.stderr).contains("000000000"), "{args:?}");
    }
    let help = ok(&bssrdf(d, &["eval", "--help"]));
    assert!(help.contains("[0.75, 2.5]"), "{help}");
}

#[test]
fn eval_json_values_are_numbers_or_null_with_their_limit() {
    let dir = tempfile::tempdir().unwrap();
    let at = |r: &str| -> serde_json::Value {
        let o = ok(&bssrdf(
            dir.path(),
            &[
                "eval", "--model", "pbd", "--rho", "0.5", "--theta", "0", "--r", r, "--json",
            ],
        ));
        serde_json::from_str(o.trim()).unwrap()
    };
    let zero = at("0");
    assert!(zero["value"].is_null(), "{zero}");
    assert_eq!(zero["limit"], "inf");
    let one = at("1");
    assert!(one["value"].is_f64(), "{one}");
    assert!(one["limit"].is_null(), "{one}");
}

/// The one r > 0 where pbd is infinite (docs/cli.md, docs/accuracy.md): the refracted beam in
/// the surface (η = 1, θ = 90°) passes through the exit point on φ = 0; any other φ is finite.
#[test]
fn pbd_with_the_beam_in_the_surface_is_infinite_on_phi_0_only() {
    let dir = tempfile::tempdir().unwrap();
    let eval = |phi: &str, json: bool| {
        let mut args = vec![
            "eval", "--model", "pbd", "--eta", "1", "--rho", "0.5", "--theta", "90", "--r", "1",
            "--phi", phi,
        ];
        if json {
            args.push("--json");
        }
        ok(&bssrdf(dir.path(), &args))
    };
    for phi in ["0", "-0", "360"] {
        assert_eq!(eval(phi, false).trim(), "inf", "{phi}");
        let j: serde_json::Value = serde_json::from_str(eval(phi, true).trim()).unwrap();
        assert!(j["value"].is_null(), "{j}");
        assert_eq!(j["limit"], "inf", "{j}");
    }
    for phi in ["1", "1e-300", "180"] {
        let v: f64 = eval(phi, false).trim().parse().unwrap();
        assert!(v.is_finite() && v > 0.0, "{phi}: {v}");
    }
}

// ---- The kept albedo rows: checked before any output, tables chosen by them ----

/// A scene of apple (η 1.3) whose channels keep two disjoint runs of rows: two tables of
/// η 1.3, the first [0, 0.48], the second around 0.95.
fn two_runs() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let scene = "integrator = \"path\"\n[[material]]\nname = \"apple\"\nalbedo_range = [[0.95, 0.96], [0.95, 0.96], [0.10, 0.12]]\n";
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    ok(&bssrdf(
        dir.path(),
        &[
            "bake", "--scene", "s.toml", "--grid", "coarse", "-q", "-o", "s.bssrdf",
        ],
    ));
    dir
}

#[test]
fn sample_checks_the_kept_rows_before_writing_and_materials_find_their_table() {
    let dir = two_runs();
    let d = dir.path();
    for mode in [&[][..], &["--path-tracing"]] {
        let o = bssrdf(
            d,
            &[
                &[
                    "sample", "s.bssrdf", "--table", "0", "--rho", "0.9", "-n", "2",
                ][..],
                mode,
            ]
            .concat(),
        );
        fails_with(&o, 2, "--rho 0.9 is outside the albedo range table 0 keeps");
        assert!(o.stdout.is_empty(), "{mode:?}: {}", text(&o.stdout));
    }
    // The README's words for eval.
    fails_with(
        &bssrdf(
            d,
            &[
                "eval", "s.bssrdf", "--table", "1", "--rho", "0.2", "--theta", "0", "--r", "1",
            ],
        ),
        2,
        "--rho 0.2 is outside the albedo range table 1 keeps, [",
    );
    // The refusal names the other table of the same η that keeps ρ′ (the scene's other run)
    let mut hinted = 0;
    for (table, other) in [("0", "1"), ("1", "0")] {
        for rho in ["0.955", "0.11"] {
            let args = [
                "eval", "s.bssrdf", "--table", table, "--rho", rho, "--theta", "0", "--r", "1",
            ];
            let o = bssrdf(d, &args);
            if !o.status.success() {
                let hint =
                    format!("table {other}, of the same eta, keeps it: give --table {other}");
                fails_with(&o, 2, &hint);
                hinted += 1;
            }
        }
    }
    assert_eq!(hinted, 2);
    // skin1 (η 1.3, not in the file): its red ρ′ 0.959 is in table 1, not in table 0.
    let v: f64 = ok(&bssrdf(
        d,
        &[
            "eval",
            "s.bssrdf",
            "--material",
            "skin1",
            "--channel",
            "r",
            "--theta",
            "0",
            "--r",
            "1",
        ],
    ))
    .trim()
    .parse()
    .unwrap();
    assert!(v.is_finite() && v > 0.0);
    let csv = ok(&bssrdf(
        d,
        &[
            "sample",
            "s.bssrdf",
            "--material",
            "skin1",
            "--channel",
            "r",
            "-n",
            "2",
        ],
    ));
    assert_eq!(csv.lines().count(), 3, "{csv}");
}

/// The ends of a table's albedo rows as `inspect` prints them (the shortest form of their f32
/// nodes) are albedos `eval` and `sample` take, at the row; a millionth beyond is refused.
#[test]
fn the_albedo_ends_inspect_prints_are_taken() {
    let dir = two_runs();
    let d = dir.path();
    let shown = ok(&bssrdf(d, &["inspect", "s.bssrdf"]));
    let mut ends = Vec::new();
    for line in shown.lines().filter(|l| l.trim_start().starts_with("rho:")) {
        // "rho:   N nodes, FIRST … LAST"
        let range = line.split(", ").nth(1).unwrap();
        let (a, b) = range.split_once(" … ").unwrap();
        ends.push([a.trim().to_string(), b.trim().to_string()]);
    }
    assert_eq!(ends.len(), 2, "{shown}");
    for (table, [first, last]) in ends.iter().enumerate() {
        let table = table.to_string();
        for rho in [first, last] {
            let v = ok(&bssrdf(
                d,
                &[
                    "eval", "s.bssrdf", "--table", &table, "--rho", rho, "--theta", "30", "--r",
                    "1",
                ],
            ));
            let v: f64 = v.trim().parse().unwrap();
            assert!(v.is_finite() && v >= 0.0, "table {table}, rho {rho}: {v}");
            // (ρ′ = 0 scatters nothing: no sample, and an error that says so)
            if rho.parse::<f64>().unwrap() > 0.0 {
                ok(&bssrdf(
                    d,
                    &[
                        "sample", "s.bssrdf", "--table", &table, "--rho", rho, "--theta", "30",
                        "-n", "2",
                    ],
                ));
            }
        }
        let beyond: f64 = last.parse::<f64>().unwrap() + 1e-6;
        fails_with(
            &bssrdf(
                d,
                &[
                    "eval",
                    "s.bssrdf",
                    "--table",
                    &table,
                    "--rho",
                    &beyond.to_string(),
                    "--theta",
                    "30",
                    "--r",
                    "1",
                ],
            ),
            2,
            "is outside the albedo range table",
        );
    }
}

#[test]
fn material_sources_over_256_bytes_are_refused_not_cut() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let long = "x".repeat(257);
    std::fs::write(
        d.join("m.toml"),
        format!("id = \"long-source\"\nname = \"Long\"\neta = 1.3\ncoefficients = \"reduced\"\nsigma_s = [1.0, 1.0, 1.0]\nsigma_a = [0.1, 0.1, 0.1]\ng = [0.0, 0.0, 0.0]\n\n[source]\ncoefficients = \"{long}\"\n"),
    )
    .unwrap();
    fails_with(
        &bssrdf(
            d,
            &[
                "bake",
                "long-source",
                "--materials",
                "m.toml",
                "--grid",
                "coarse",
                "-q",
            ],
        ),
        2,
        "source is 257 bytes; a library file keeps at most 256",
    );
    assert!(!d.join("long-source.bssrdf").exists());
    std::fs::write(d.join("s.toml"), "[[material]]\nname = \"long-source\"\n").unwrap();
    fails_with(
        &bssrdf(
            d,
            &[
                "bake",
                "--scene",
                "s.toml",
                "--materials",
                "m.toml",
                "--grid",
                "coarse",
                "-q",
            ],
        ),
        2,
        "source is",
    );
}
