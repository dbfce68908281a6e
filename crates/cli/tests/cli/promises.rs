//! End-to-end tests of the command line's promises (issue 18): no pass on nothing checked, no
//! flag accepted and ignored, no conflicting inputs, one set of CSV columns, negative numbers,
//! every value outside its domain refused with exit 2. The output-file rules are in
//! `outputs.rs`.

use std::path::Path;
use std::process::{Command, Output};

use crate::common::{bare, bssrdf, fails_with, ok, text, with_stdin};

// ---- validate: a case without points is skipped, a run that checked nothing fails ----

/// Bakes `scene` (TOML) on the coarse grid into `s.bssrdf` in a fresh folder.
fn scene_bake(scene: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    ok(&bssrdf(
        dir.path(),
        &[
            "bake", "--scene", "s.toml", "--grid", "coarse", "-q", "-o", "s.bssrdf",
        ],
    ));
    dir
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("stdout is JSON")
}

#[test]
fn validate_skips_cases_without_points_and_nothing_checked_is_no_pass() {
    // Rows around ρ′ 0.85..0.97 only: of table 2's ρ′ 0.5, 0.9, 0.99, only 0.9 is kept.
    let dir = scene_bake(
        "integrator = \"path\"\n[[material]]\nname = \"skin1\"\nalbedo_range = [[0.85, 0.97], [0.85, 0.97], [0.85, 0.97]]\n",
    );
    let d = dir.path();
    let args = [
        "validate",
        "s.bssrdf",
        "--samples",
        "300",
        "--max-mean-error",
        "100",
    ];
    let text_run = ok(&bssrdf(d, &args));
    assert_eq!(
        text_run.matches("skipped: rho outside").count(),
        6,
        "{text_run}"
    );
    assert!(text_run.contains("3 case(s) checked, 0 failed, 6 skipped: pass"));
    let report = json(&bssrdf(d, &[&args[..], &["--json"]].concat()));
    assert_eq!(report["pass"], true);
    assert_eq!(
        (report["checked"].as_u64(), report["skipped"].as_u64()),
        (Some(3), Some(6))
    );
    for row in report["rows"].as_array().unwrap() {
        let skipped = row["rho"] != 0.9;
        assert_eq!(
            row["status"],
            if skipped { "skipped" } else { "ok" },
            "{row}"
        );
        assert_eq!(row["mean_rel_error"].is_null(), skipped, "{row}");
    }

    // Rows around 0.25..0.3: no case of table 2 can be checked.
    let dir = scene_bake(
        "integrator = \"path\"\n[[material]]\nname = \"skin1\"\nalbedo_range = [[0.25, 0.3], [0.25, 0.3], [0.25, 0.3]]\n",
    );
    let o = bssrdf(dir.path(), &args);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stdout));
    assert!(text(&o.stdout).contains("not a pass: no case could be checked"));
    let o = bssrdf(dir.path(), &[&args[..], &["--json"]].concat());
    assert_eq!(o.status.code(), Some(1));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        (report["pass"].as_bool(), report["checked"].as_u64()),
        (Some(false), Some(0))
    );
}

#[test]
fn validate_refuses_values_outside_their_domain() {
    let dir = bare();
    for (value, needle) in [
        ("nan", "--max-mean-error NaN"),
        ("-1", "--max-mean-error -1"),
    ] {
        fails_with(
            &bssrdf(
                dir.path(),
                &["validate", "t.bssrdf", "--max-mean-error", value],
            ),
            2,
            needle,
        );
    }
    // The range as --help writes it
    fails_with(
        &bssrdf(dir.path(), &["validate", "t.bssrdf", "--samples", "0"]),
        2,
        "--samples 0 is outside the valid range: [1, 1e8]",
    );
    fails_with(
        &bssrdf(dir.path(), &["validate", "t.bssrdf", "--samples", "1e9"]),
        2,
        "--samples 1e9 is outside the valid range: [1, 1e8]",
    );
    let help = ok(&bssrdf(dir.path(), &["validate", "--help"]));
    assert!(help.contains("in [1, 1e8]"), "{help}");
}

/// A case passes only when its mean error is within the bound by two standard errors of the
/// mean: one point tells nothing, and a bound just above a noisy mean is no pass either.
#[test]
fn validate_says_inconclusive_when_too_few_points_tell() {
    let dir = bare();
    let d = dir.path();
    let run = |args: &[&str]| {
        let o = bssrdf(
            d,
            &[&["validate", "t.bssrdf", "--json", "-q"][..], args].concat(),
        );
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (o.status.code(), report)
    };
    // One point per case: no standard error, so nothing is ok, whatever the bound
    let (code, report) = run(&["--samples", "1", "--max-mean-error", "10000"]);
    assert_eq!(code, Some(1));
    assert_eq!(
        (report["pass"].as_bool(), report["failed"].as_u64()),
        (Some(false), Some(0))
    );
    for row in report["rows"].as_array().unwrap() {
        assert_eq!(row["status"], "inconclusive", "{row}");
        assert!(row["mean_rel_error_stderr"].is_null(), "{row}");
    }
    let o = bssrdf(
        d,
        &[
            "validate",
            "t.bssrdf",
            "--samples",
            "1",
            "--max-mean-error",
            "10000",
            "-q",
        ],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stdout).contains("9 inconclusive"),
        "{}",
        text(&o.stdout)
    );
    assert!(text(&o.stdout).contains("not a pass: too few points to tell (raise --samples)"));

    // 20 points: a bound between the mean and the mean plus two standard errors
    let (_, report) = run(&["--samples", "20", "--max-mean-error", "10000"]);
    let row = &report["rows"][4];
    let (mean, stderr) = (
        row["mean_rel_error"].as_f64().unwrap(),
        row["mean_rel_error_stderr"].as_f64().unwrap(),
    );
    assert!(stderr > 0.0 && stderr < mean, "{row}");
    let between = format!("{}", 100.0 * (mean + stderr));
    let (code, report) = run(&["--samples", "20", "--max-mean-error", &between]);
    assert_eq!(code, Some(1));
    assert_eq!(report["rows"][4]["status"], "inconclusive", "{report}");
    let above = format!("{}", 100.0 * (mean + 2.5 * stderr));
    let (_, report) = run(&["--samples", "20", "--max-mean-error", &above]);
    assert_eq!(report["rows"][4]["status"], "ok", "{report}");
}

// ---- Tables chosen by η, conflicting inputs refused ----

/// white-grapefruit-juice (η 1.33, table 1) and skin1 (η 1.3, table 0), coarse.
fn two() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    ok(&bssrdf(
        dir.path(),
        &[
            "bake",
            "white-grapefruit-juice",
            "skin1",
            "--grid",
            "coarse",
            "-q",
            "-o",
            "two.bssrdf",
        ],
    ));
    dir
}

#[test]
fn eta_selects_the_table_or_is_refused() {
    let dir = two();
    let d = dir.path();
    let point = ["--rho", "0.5", "--theta", "30", "--r", "1"];
    let value = |extra: &[&str]| -> String {
        ok(&bssrdf(
            d,
            &[&["eval", "two.bssrdf"][..], extra, &point].concat(),
        ))
    };
    assert_eq!(value(&["--eta", "1.3"]), value(&["--table", "0"]));
    assert_eq!(value(&["--eta", "1.33"]), value(&["--table", "1"]));
    assert_ne!(value(&["--eta", "1.3"]), value(&["--eta", "1.33"]));
    // Every model: the table of that η, or a refusal naming the file's η.
    for model in ["table", "pbd", "dipole"] {
        fails_with(
            &bssrdf(
                d,
                &[&["eval", "two.bssrdf", "--model", model, "--eta", "2.0"][..], &point].concat(),
            ),
            2,
            "--eta 2: two.bssrdf has no table at this eta; its tables: 1.3 (table 0), 1.33 (table 1)",
        );
    }
    for args in [
        &["sample", "two.bssrdf", "--rho", "0.5", "--eta", "1.5"][..],
        &["validate", "two.bssrdf", "--eta", "1.5"],
    ] {
        fails_with(&bssrdf(d, args), 2, "has no table at this eta");
    }
    fails_with(
        &bssrdf(
            d,
            &[
                &["eval", "two.bssrdf", "--eta", "1.3", "--table", "1"][..],
                &point,
            ]
            .concat(),
        ),
        2,
        "--table 1 holds eta 1.33, not --eta 1.3",
    );
    let pbd_json = json(&bssrdf(
        d,
        &[
            &[
                "eval",
                "two.bssrdf",
                "--model",
                "pbd",
                "--eta",
                "1.3",
                "--json",
            ][..],
            &point,
        ]
        .concat(),
    ));
    assert_eq!(pbd_json["eta"], 1.3);
}

#[test]
fn conflicting_inputs_are_refused_naming_both() {
    let dir = two();
    let d = dir.path();
    let at = ["--theta", "30", "--r", "1"];
    let eval = |extra: &[&str]| bssrdf(d, &[&["eval", "two.bssrdf"][..], extra, &at].concat());
    let o = eval(&["--material", "skin1", "--rho", "0.5"]);
    fails_with(&o, 2, "--material");
    fails_with(&o, 2, "--rho");
    let o = bssrdf(
        d,
        &[
            "sample",
            "two.bssrdf",
            "--material",
            "skin1",
            "--rho",
            "0.5",
        ],
    );
    fails_with(&o, 2, "--rho");
    fails_with(
        &eval(&["--material", "skin1", "--table", "1"]),
        2,
        "--table 1 holds eta 1.33, but --material skin1 has eta 1.3",
    );
    fails_with(
        &eval(&["--material", "skin1", "--eta", "1.33"]),
        2,
        "--eta 1.33 conflicts with --material skin1, whose eta is 1.3",
    );
    fails_with(
        &eval(&["--fresnel-moments", "pbrt", "--rho", "0.5"]),
        2,
        "--fresnel-moments pbrt conflicts with the table, baked with exact moments",
    );
    // The dirpole's own fits are neither: with a file they conflict too
    fails_with(
        &eval(&[
            "--model",
            "dirpole",
            "--fresnel-moments",
            "authors",
            "--rho",
            "0.5",
        ]),
        2,
        "--fresnel-moments authors conflicts with the table, baked with exact moments",
    );
    fails_with(
        &eval(&["--quadrature", "fast", "--rho", "0.5"]),
        2,
        "--quadrature applies to the pbd model only",
    );
    fails_with(
        &bssrdf(
            d,
            &[
                "sample",
                "two.bssrdf",
                "--rho",
                "0.5",
                "--path-tracing",
                "--theta",
                "30",
            ],
        ),
        2,
        "--theta",
    );
    // A points file whose ρ′ is not the material's.
    let o = with_stdin(
        d,
        &["eval", "two.bssrdf", "--material", "skin1", "--points", "-"],
        "rho,theta_deg,r_mm,phi_deg\n0.5,0,1,0\n",
    );
    fails_with(&o, 2, "stdin:2: column rho = 0.5 conflicts with --material");
    assert!(o.stdout.is_empty());
    let o = with_stdin(
        d,
        &["eval", "two.bssrdf", "--material", "skin1", "--points", "-"],
        "theta_deg,r,phi_deg\n0,1,0\n",
    );
    fails_with(&o, 2, "name the column r_mm, not r");
}

// ---- One set of CSV columns: sample | eval ----

#[test]
fn sample_output_feeds_eval_points() {
    let dir = two();
    let d = dir.path();
    for (sample, eval) in [
        (
            vec![
                "sample",
                "two.bssrdf",
                "--rho",
                "0.9",
                "--theta",
                "30",
                "-n",
                "5",
            ],
            vec!["eval", "two.bssrdf", "--points", "-"],
        ),
        (
            vec![
                "sample",
                "two.bssrdf",
                "--rho",
                "0.9",
                "--path-tracing",
                "-n",
                "5",
            ],
            vec!["eval", "two.bssrdf", "--points", "-"],
        ),
        (
            vec![
                "sample",
                "two.bssrdf",
                "--material",
                "skin1",
                "--channel",
                "g",
                "-n",
                "5",
            ],
            vec![
                "eval",
                "two.bssrdf",
                "--material",
                "skin1",
                "--channel",
                "g",
                "--points",
                "-",
            ],
        ),
    ] {
        let samples = ok(&bssrdf(d, &sample));
        let o = with_stdin(d, &eval, &samples);
        let out = ok(&o);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 6, "{out}");
        assert_eq!(
            lines[0],
            format!("{},value", samples.lines().next().unwrap())
        );
        for (row, sampled) in lines[1..].iter().zip(samples.lines().skip(1)) {
            assert!(row.starts_with(sampled), "{row} does not copy {sampled}");
            let value: f64 = row.rsplit(',').next().unwrap().parse().unwrap();
            assert!(value > 0.0, "{row}");
        }
        // The same rows as JSON lines.
        let o = with_stdin(d, &[&eval[..], &["--json"]].concat(), &samples);
        let lines: Vec<serde_json::Value> = ok(&o)
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 5);
        assert!(lines.iter().all(|j| j["value"].as_f64().unwrap() > 0.0));
    }
}

#[test]
fn points_files_are_read_whole_and_checked_first() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let eval = ["eval", "--points", "-", "--quadrature", "fast"];
    // A UTF-8 byte-order mark and quoted fields are fine.
    let out = ok(&with_stdin(
        d,
        &eval,
        "\u{feff}rho,theta_deg,r,phi_deg\n\"0.9\",0,1,0\n",
    ));
    assert!(
        out.starts_with("rho,theta_deg,r,phi_deg,value\n0.9,0,1,0,"),
        "{out}"
    );
    // A bad row after good ones: nothing printed, the error names line and column.
    let o = with_stdin(d, &eval, "rho,theta_deg,r,phi_deg\n0.9,0,1,0\n0.9,95,1,0\n");
    fails_with(
        &o,
        2,
        "stdin:3: column theta_deg 95 is outside the valid range: [0, 90]",
    );
    assert!(o.stdout.is_empty());
    for (input, needle) in [
        (
            "rho,theta_deg,r,phi_deg,rho\n0.9,0,1,0,0.9\n",
            "column \"rho\" appears twice",
        ),
        (
            "rho,theta_deg,r,phi_deg,value\n0.9,0,1,0,1\n",
            "column \"value\" is the one eval writes",
        ),
        (
            "rho,theta_deg,r_mm,phi_deg\n0.9,0,1,0\n",
            "column r_mm is in mm, which needs --material",
        ),
        (
            "rho,theta_deg,r,phi_deg\n0.9,0,1\n",
            "stdin:2: the row has 3 fields, the header 4",
        ),
        ("", "is empty"),
        // A row of empty fields is a row: refused, not dropped (rows in = rows out)
        (
            "rho,theta_deg,r,phi_deg\n0.9,0,1,0\n,,,\n0.9,0,1,0\n",
            "stdin:3: column rho = \"\" is not a number",
        ),
    ] {
        fails_with(&with_stdin(d, &eval, input), 2, needle);
    }
    std::fs::create_dir(d.join("pts")).unwrap();
    fails_with(
        &bssrdf(d, &["eval", "--points", "pts"]),
        2,
        "points file pts is a folder",
    );
}

#[test]
fn points_errors_name_the_physical_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let eval = ["eval", "--points", "-", "--quadrature", "fast"];
    let header = "rho,theta_deg,r,phi_deg";
    for (input, needle) in [
        // Blank lines count: the bad row is the file's sixth line
        (
            format!("{header}\n0.9,0,1,0\n\n\n\n0.9,95,1,0\n"),
            "stdin:6: column theta_deg 95",
        ),
        // Every line ending counts: a lone \r, and \r\n once
        (
            format!("{header}\r0.9,0,1,0\r0.9,95,1,0\r"),
            "stdin:3: column theta_deg",
        ),
        (
            format!("{header}\r\n0.9,0,1,0\r\n\r\n0.9,95,1,0\r\n"),
            "stdin:4: column theta_deg",
        ),
        // A quoted field over two lines: the next row starts on line 4
        (
            format!("{header},note\n0.9,0,1,0,\"a\nb\"\n0.9,95,1,0,c\n"),
            "stdin:4: column theta_deg",
        ),
        // A row with the wrong number of fields, in the same form
        (
            format!("{header}\n0.9,0,1,0\n\n0.9,0,1\n"),
            "stdin:4: the row has 3 fields, the header 4",
        ),
    ] {
        let o = with_stdin(d, &eval, &input);
        fails_with(&o, 2, needle);
        assert!(
            !text(&o.stderr).contains("CSV error"),
            "{}",
            text(&o.stderr)
        );
    }
}

#[test]
fn points_columns_not_read_are_copied_through_as_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A quoted field with spaces, a byte that is not UTF-8, spaces around a number and a name
    let input: &[u8] = b"rho,theta_deg, r ,phi_deg,label,raw\n0.9,0, 1 ,0,\" x \",\xff\xfeab\n";
    std::fs::write(d.join("p.csv"), input).unwrap();
    let o = bssrdf(d, &["eval", "--points", "p.csv", "--quadrature", "fast"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let expected: &[u8] = b"rho,theta_deg, r ,phi_deg,label,raw,value\n0.9,0, 1 ,0, x ,\xff\xfeab,";
    assert!(o.stdout.starts_with(expected), "{:?}", text(&o.stdout));
    // The value is the one of the same point without the extra columns
    let plain = ok(&with_stdin(
        d,
        &["eval", "--points", "-", "--quadrature", "fast"],
        "rho,theta_deg,r,phi_deg\n0.9,0,1,0\n",
    ));
    let last = |out: &str| out.trim_end().rsplit(',').next().unwrap().to_string();
    assert_eq!(last(&text(&o.stdout)), last(&plain));
}

// ---- Negative numbers, bins, threads, progress ----

#[test]
fn negative_numbers_are_values() {
    let dir = bare();
    let d = dir.path();
    ok(&bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "0.9",
            "--g",
            "-0.5",
            "--photons",
            "1000",
        ],
    ));
    ok(&bssrdf(
        d,
        &["pack", "t.bssrdf", "-o", "fast.bssrdf", "--level", "-3"],
    ));
    for (args, needle) in [
        (
            &["diff", "t.bssrdf", "t.bssrdf", "--tolerance", "-1"][..],
            "--tolerance -1",
        ),
        (
            &["validate", "t.bssrdf", "--max-mean-error", "-1"],
            "--max-mean-error -1",
        ),
        (&["bake", "--eta", "-1", "-q", "-o", "n.bssrdf"], "--eta -1"),
        (
            &["eval", "--rho", "0.5", "--theta", "-5", "--r", "1"],
            "--theta -5 is outside",
        ),
        (
            &[
                "eval", "--rho", "0.5", "--theta", "0", "--r", "1", "--phi", "-inf",
            ],
            "--phi -inf is outside the valid range: any finite number",
        ),
        (
            &["eval", "--rho", "-0.5", "--theta", "0", "--r", "1"],
            "--rho -0.5",
        ),
        (&["sample", "t.bssrdf", "--rho", "-0.5"], "--rho -0.5"),
        // Comma lists that start with a negative number are values too
        (
            &["walk", "--albedo", "0.9", "--bins", "-1,1,2,2"],
            "r_min = -1 must be > 0",
        ),
        (&["zoo", "--cases", "-0.5:0"], "--cases rho -0.5 is outside"),
        (
            &[
                "render",
                "--sigma-s",
                "-1,1,1",
                "--sigma-a",
                "1,1,1",
                "--theta",
                "30",
                "-o",
                "x.exr",
            ],
            "sigma_s[0] (red) = -1 is negative",
        ),
        (
            &[
                "render",
                "--preset",
                "figure-10",
                "--theta",
                "30",
                "--size",
                "-1,1",
                "-o",
                "x.exr",
            ],
            "invalid value '-1,1' for '--size <W,H>'",
        ),
    ] {
        fails_with(&bssrdf(d, args), 2, needle);
    }
}

/// Whole-number flags say what is wrong with a value (clap's own parse said "invalid digit
/// found in string"), and take exponent form.
#[test]
fn whole_number_flags_name_what_is_wrong() {
    let dir = bare();
    let d = dir.path();
    for (args, needle) in [
        (
            &["sample", "t.bssrdf", "--rho", "0.5", "-n", "-1"][..],
            "-1 is negative",
        ),
        (
            &["walk", "--albedo", "0.5", "--threads", "-1"],
            "-1 is negative",
        ),
        (
            &["walk", "--albedo", "0.5", "--seed", "1.5"],
            "1.5 is not a whole number",
        ),
        (
            &["validate", "t.bssrdf", "--samples", "1e30"],
            "1e30 is too large",
        ),
        (
            &["pack", "t.bssrdf", "--level", "2.5"],
            "2.5 is not a whole number",
        ),
    ] {
        let out = bssrdf(d, args);
        fails_with(&out, 2, needle);
        assert!(!text(&out.stderr).contains("invalid digit"), "{args:?}");
    }
    let few = ok(&bssrdf(
        d,
        &["sample", "t.bssrdf", "--rho", "0.5", "-n", "1e1"],
    ));
    assert_eq!(few.lines().count(), 11, "a header and 10 rows: {few}");
}

/// An option that takes negative values takes the next argument as its value, so a forgotten
/// value meets the next option: the error says the value is missing, not that "--theta" is a
/// bad number.
#[test]
fn an_option_given_as_a_value_is_a_missing_value() {
    let dir = bare();
    let d = dir.path();
    for (args, missing) in [
        (
            &["render", "--preset", "figure-10", "--size", "--theta", "30"][..],
            "the value of --size is missing: --theta is the next option, not a value",
        ),
        (
            &[
                "render",
                "--preset",
                "figure-10",
                "--theta",
                "30",
                "--size",
                "-o",
                "x.exr",
            ],
            "the value of --size is missing: -o is the next option",
        ),
        (
            &["render", "--sigma-s", "--sigma-a", "1,1,1", "--theta", "30"],
            "the value of --sigma-s is missing: --sigma-a is",
        ),
        (
            &["eval", "--rho", "--theta", "30", "--r", "1"],
            "the value of --rho is missing: --theta is",
        ),
        (
            &["eval", "--rho", "0.5", "--theta", "30", "--r", "--phi=0"],
            "the value of --r is missing: --phi=0 is",
        ),
        (
            &["sample", "t.bssrdf", "--rho", "--theta", "30"],
            "the value of --rho is missing",
        ),
        (
            &["invert", "--reflectance", "0.5", "--eta", "--help"],
            "the value of --eta is missing: --help is",
        ),
        (
            &["walk", "--albedo", "0.9", "--bins", "--photons", "10"],
            "the value of --bins is missing: --photons is",
        ),
        (
            &["bake", "--sigma-s", "--sigma-a", "1,1,1", "-o", "c.bssrdf"],
            "the value of --sigma-s is missing: --sigma-a is",
        ),
    ] {
        fails_with(&bssrdf(d, args), 2, missing);
    }
    // Negative values stay values, and after `--` nothing is read as an option
    let after = bssrdf(d, &["sample", "--rho", "0.5", "--", "--theta"]);
    fails_with(&after, 2, "--theta");
    assert!(
        !text(&after.stderr).contains("is missing"),
        "{}",
        text(&after.stderr)
    );
    fails_with(
        &bssrdf(d, &["eval", "--rho", "0.5", "--theta", "-5", "--r", "1"]),
        2,
        "--theta -5 is outside",
    );
}

#[test]
fn walk_bins_threads_and_photons_keep_their_domains() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "0.9",
            "--photons",
            "1000",
            "--bins",
            "0.01,100,10,4",
            "--profile",
            "p.csv",
        ],
    ));
    let profile = std::fs::read_to_string(d.join("p.csv")).unwrap();
    assert!(profile.lines().count() > 40, "{profile}");
    // Small estimates keep their digits (exponent form), and every slab estimate has its error
    let dark = ok(&bssrdf(
        d,
        &["walk", "--albedo", "0.001", "--photons", "1000"],
    ));
    let multiple = dark.lines().find(|l| l.starts_with("multiple")).unwrap();
    let (value, error) = multiple.split_once(" ± ").expect(&dark);
    assert!(value.contains("e-") && error.contains("e-"), "{dark}");
    // A small standard error beside a large value keeps its digits too
    let thin = ok(&bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "0",
            "--photons",
            "20000",
            "--slab",
            "1e-9",
        ],
    ));
    let total = thin
        .lines()
        .find(|l| l.starts_with("total reflectance"))
        .unwrap();
    let (_, error) = total.split_once(" ± ").expect(&thin);
    assert!(error.contains("e-"), "{thin}");
    // A slab's lines add up: total = single + multiple + unscattered, each printed
    let slab_text = ok(&bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "0.9",
            "--photons",
            "20000",
            "--slab",
            "0.5",
        ],
    ));
    let value = |name: &str| -> f64 {
        let line = slab_text
            .lines()
            .find(|l| l.starts_with(name))
            .expect(&slab_text);
        line[name.len()..]
            .split(" ± ")
            .next()
            .unwrap()
            .trim()
            .parse()
            .unwrap()
    };
    let parts = value("single scattering")
        + value("multiple scattering")
        + value("unscattered reflectance");
    assert!(
        (value("total reflectance") - parts).abs() < 3e-6,
        "{slab_text}"
    );
    assert!(value("unscattered transmittance") > 0.0, "{slab_text}");
    let slab: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "0.9",
            "--photons",
            "1000",
            "--slab",
            "1",
            "--json",
        ],
    )))
    .unwrap();
    for key in [
        "unscattered_transmittance",
        "total_transmittance",
        "truncated_weight",
    ] {
        assert!(slab[format!("{key}_stderr")].is_number(), "{key} in {slab}");
    }
    fails_with(
        &bssrdf(d, &["walk", "--albedo", "0.9", "--bins", "0.01,100,10"]),
        2,
        "expected 4 comma-separated numbers",
    );
    // The bins shape the profile, which only --profile writes and --json sums
    fails_with(
        &bssrdf(d, &["walk", "--albedo", "0.9", "--bins", "0.01,100,10,4"]),
        2,
        "--bins sets the bins of the profile, which only --profile writes (and --json sums, as binned_reflectance)",
    );
    // At 90° the walk gives the grazing limit per unit power entering, as zoo and eval's mc
    let grazing = json(&bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "0.9",
            "--theta",
            "90",
            "--photons",
            "2000",
            "--json",
        ],
    ));
    assert!(
        grazing["total_reflectance"].as_f64().unwrap() > 0.0,
        "{grazing}"
    );
    // Below eta = 1, incidences beyond the critical angle are refused in degrees, by flag
    fails_with(
        &bssrdf(
            d,
            &["walk", "--albedo", "0.5", "--eta", "0.75", "--theta", "60"],
        ),
        2,
        "--theta 60 is outside the valid range at --eta 0.75: [0, 48.590377890729144] deg",
    );
    // The bound stated is itself taken (at η = 0.8, asin η in degrees would not be)
    let walk = ["walk", "--albedo", "0.5", "--eta", "0.8", "--theta"];
    stated_bound_is_taken(
        d,
        &[&walk[..], &["60"]].concat(),
        ("[0, ", "]"),
        &[&walk[..], &["{}", "--photons", "100"]].concat(),
    );
    // So is invert's (its own test: the entry transmittance is above 0), which printed asin η
    // in degrees, itself refused
    for eta in ["0.8", "0.9999999"] {
        let invert = [
            "invert",
            "--reflectance",
            "0",
            "--grid",
            "coarse",
            "--eta",
            eta,
        ];
        stated_bound_is_taken(
            d,
            &[&invert[..], &["--theta", "89.99999"]].concat(),
            ("--theta at most ", " deg"),
            &[&invert[..], &["--theta", "{}"]].concat(),
        );
    }
    fails_with(
        &bssrdf(d, &["zoo", "-q", "--eta", "0.75"]),
        2,
        "the default case 0.5:60 lies beyond the critical angle of --eta 0.75",
    );
    fails_with(
        &bssrdf(
            d,
            &["zoo", "-q", "--eta", "0.75", "--cases", "0.9:10,0.9:50"],
        ),
        2,
        "the --cases case 0.9:50 lies beyond the critical angle",
    );
    fails_with(
        &bssrdf(d, &["zoo", "-q", "--cases", "0.9:0,0.5:60,0.9:0"]),
        2,
        "--cases lists 0.9:0 twice (at positions 1 and 3)",
    );
    // A row with no bin precise enough says why, in the table's notes and in --json
    let few = [
        "zoo",
        "-q",
        "--photons",
        "200",
        "--models",
        "dipole",
        "--cases",
        "0.9:0",
    ];
    let table = ok(&bssrdf(d, &few));
    assert!(
        table.contains("dipole at ρ′ 0.9, θ 0°: no bin of the walk"),
        "{table}"
    );
    let report = json(&bssrdf(d, &[&few[..], &["--json"]].concat()));
    let note = &report["rows"][0]["note"];
    assert!(
        note.as_str().is_some_and(|n| n.contains("raise --photons")),
        "{report}"
    );
    // An output that cannot be written is refused before the work (10⁸ photons would take
    // minutes), and named once
    std::fs::create_dir(d.join("folder")).unwrap();
    let o = bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "0.9",
            "--photons",
            "100000000",
            "--profile",
            "folder",
        ],
    );
    fails_with(
        &o,
        2,
        "cannot write folder: it is a folder, not a regular file",
    );
    assert_eq!(text(&o.stderr).matches("cannot write").count(), 1);
    // Every walk estimate has its standard error: one photon is refused by each command
    for args in [
        &["walk", "--albedo", "0.9", "--photons", "1"][..],
        &[
            "zoo",
            "-q",
            "--photons",
            "1",
            "--cases",
            "0.9:0",
            "--models",
            "pbd",
        ],
        &[
            "render",
            "--preset",
            "figure-10",
            "--theta",
            "30",
            "--grid",
            "coarse",
            "--photons",
            "1",
            "-o",
            "one.exr",
        ],
    ] {
        fails_with(
            &bssrdf(d, args),
            2,
            "--photons 1 is outside the valid range: [2, 1e12]",
        );
        // and so are more photons than anyone waits for (weeks on two cores)
        let many: Vec<&str> = args
            .iter()
            .map(|&a| if a == "1" { "1e13" } else { a })
            .collect();
        fails_with(
            &bssrdf(d, &many),
            2,
            "--photons 1e13 is outside the valid range: [2, 1e12]",
        );
    }
    assert!(!d.join("one.exr").exists());
    for args in [
        &["bake", "--eta", "1.33", "-q", "--threads", "100000"][..],
        &["walk", "--albedo", "0.9", "--threads", "100000"],
        &["zoo", "--threads", "100000"],
        &[
            "render",
            "--preset",
            "figure-10",
            "--theta",
            "0",
            "-o",
            "r.exr",
            "--threads",
            "100000",
        ],
    ] {
        fails_with(
            &bssrdf(d, args),
            2,
            "--threads 100000 is outside the valid range: [1, 1024]",
        );
    }
    fails_with(
        &bssrdf(d, &["bake", "--eta", "1.33", "-q", "--threads", "0"]),
        2,
        "--threads 0",
    );
    // unpack has no level to take.
    fails_with(
        &bssrdf(d, &["unpack", "x.bssrdf", "--level", "3"]),
        2,
        "--level",
    );
}

#[test]
fn progress_shows_on_a_terminal_only() {
    let dir = bare();
    let d = dir.path();
    let long = [
        &["walk", "--albedo", "0.9", "--photons", "200000"][..],
        &[
            "validate",
            "t.bssrdf",
            "--samples",
            "200",
            "--max-mean-error",
            "100",
        ],
        &[
            "zoo",
            "--photons",
            "2000",
            "--models",
            "dipole",
            "--cases",
            "0.5:0",
        ],
    ];
    // Piped: nothing on stderr, with or without -q.
    for args in long {
        let o = bssrdf(d, args);
        assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
        assert!(o.stderr.is_empty(), "{args:?}: {}", text(&o.stderr));
    }
    // On a terminal (util-linux `script` gives one): a bar, and none with -q.
    let script = Path::new("/usr/bin/script");
    if !script.exists() {
        return;
    }
    let exe = env!("CARGO_BIN_EXE_bssrdf");
    for (args, shown) in [
        (long[0], "walking"),
        (long[1], "validating"),
        (long[2], "walks and models"),
    ] {
        for quiet in [false, true] {
            let line = format!(
                "{exe} {}{} >/dev/null",
                args.join(" "),
                if quiet { " -q" } else { "" }
            );
            let o = Command::new(script)
                .current_dir(d)
                .args(["-qec", &line, "/dev/null"])
                .output()
                .unwrap();
            assert!(o.status.success(), "{line}: {}", text(&o.stdout));
            assert_eq!(
                text(&o.stdout).contains(shown),
                !quiet,
                "{line}: {}",
                text(&o.stdout)
            );
        }
    }
}

#[test]
fn files_are_read_into_memory_unless_mmap() {
    let dir = bare();
    let d = dir.path();
    let point = [
        "eval", "t.bssrdf", "--rho", "0.5", "--theta", "30", "--r", "1",
    ];
    let read = ok(&bssrdf(d, &point));
    assert_eq!(read, ok(&bssrdf(d, &[&point[..], &["--mmap"]].concat())));
    ok(&bssrdf(d, &["diff", "t.bssrdf", "t.bssrdf", "--mmap"]));
    ok(&bssrdf(
        d,
        &["sample", "t.bssrdf", "--rho", "0.5", "-n", "2", "--mmap"],
    ));
    // A folder is named as one, for every command that opens a library.
    std::fs::create_dir(d.join("dir.bssrdf")).unwrap();
    for args in [
        &[
            "eval",
            "dir.bssrdf",
            "--rho",
            "0.5",
            "--theta",
            "0",
            "--r",
            "1",
        ][..],
        &["sample", "dir.bssrdf", "--rho", "0.5"],
        &["validate", "dir.bssrdf"],
        &["diff", "dir.bssrdf", "t.bssrdf"],
    ] {
        fails_with(
            &bssrdf(d, args),
            2,
            "dir.bssrdf is a folder, not a library file",
        );
    }
}

// ---- Flags that nothing would read are refused ----

#[test]
fn render_refuses_flags_it_would_ignore() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let diff = ["render", "--diff", "a.exr", "b.exr", "-o", "d.exr"];
    for extra in [
        &["--theta", "3"][..],
        &["--model", "pbd"],
        &["--photons", "10"],
        &["--size", "4,4"],
        &["--extent", "2"],
        &["--cone", "2"],
        &["--seed", "1"],
        &["--grid", "coarse"],
        &["--orders", "multiple"],
        &["--threads", "1"],
        &["--decades", "3"],
        &["--materials", "m.toml"],
    ] {
        let o = bssrdf(d, &[&diff[..], extra].concat());
        fails_with(&o, 2, "cannot be used with");
        assert!(text(&o.stderr).contains(extra[0]), "{extra:?}");
    }
    let render = [
        "render",
        "--preset",
        "figure-10",
        "--theta",
        "0",
        "--photons",
        "10",
        "--size",
        "4,4",
        "-q",
        "-o",
        "x.exr",
    ];
    let with = |extra: &[&str]| bssrdf(d, &[&render[..], extra].concat());
    fails_with(
        &with(&["--materials", "m.toml"]),
        2,
        "--materials adds files to look --material up in",
    );
    for extra in [
        &["--sigma-a", "1,1,1"][..],
        &["--eta", "1.5"],
        &["--g", "0.3"],
        &["--eta", "1.5", "--no-preview"],
    ] {
        fails_with(&with(extra), 2, "cannot be used with");
    }
    fails_with(
        &with(&["--no-preview", "--decades", "3"]),
        2,
        "cannot be used with",
    );
    fails_with(
        &with(&["--orders", "multiple"]),
        2,
        "--orders applies to the mc model only",
    );
    fails_with(
        &with(&["--model", "mc", "--grid", "coarse"]),
        2,
        "--grid applies to the table models",
    );
    assert!(!d.join("x.exr").exists());
    // Used: --orders with mc compared, --grid with a table model.
    ok(&with(&[
        "--compare",
        "mc",
        "--orders",
        "multiple",
        "--grid",
        "coarse",
    ]));
    // bake: --materials with nothing named from it.
    std::fs::write(
        d.join("m.toml"),
        "id = \"mine\"\nname = \"Mine\"\neta = 1.3\ncoefficients = \"reduced\"\nsigma_s = [1.0, 1.0, 1.0]\nsigma_a = [0.1, 0.1, 0.1]\ng = [0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    fails_with(
        &bssrdf(
            d,
            &[
                "bake",
                "--eta",
                "1.33",
                "--materials",
                "m.toml",
                "-o",
                "t.bssrdf",
            ],
        ),
        2,
        "--materials adds files to look material names up in",
    );
    // Nor when the materials named come from the built-in library only
    fails_with(
        &bssrdf(
            d,
            &["bake", "skin1", "--materials", "m.toml", "-o", "t.bssrdf"],
        ),
        2,
        "--materials adds files to look material names up in",
    );
    assert!(!d.join("t.bssrdf").exists());
    // Nor next to a material the command finds elsewhere (built in, or in the file)
    ok(&bssrdf(
        d,
        &["bake", "skin1", "--grid", "coarse", "-q", "-o", "s.bssrdf"],
    ));
    for (args, needle) in [
        (
            &[
                "eval",
                "s.bssrdf",
                "--material",
                "skin1",
                "--materials",
                "m.toml",
                "--theta",
                "0",
                "--r",
                "1",
            ][..],
            "but skin1 is a material of s.bssrdf: drop --materials",
        ),
        (
            &[
                "render",
                "--material",
                "skin1",
                "--materials",
                "m.toml",
                "--theta",
                "30",
                "-o",
                "r.exr",
            ],
            "but skin1 is built in: drop --materials",
        ),
    ] {
        fails_with(&bssrdf(d, args), 2, needle);
    }
    // A library written where the command writes text would be mixed with it
    #[cfg(target_os = "linux")]
    {
        fails_with(
            &bssrdf(d, &["bake", "--eta", "1.33", "-q", "-o", "/dev/stderr"]),
            2,
            "-o /dev/stderr is the command's stderr, where its messages go",
        );
        fails_with(
            &bssrdf(
                d,
                &["bake", "--eta", "1.33", "-q", "--json", "-o", "/dev/stdout"],
            ),
            2,
            "-o /dev/stdout is stdout, where the command writes its --json summary",
        );
        // walk and render always print their summary on stdout
        fails_with(
            &bssrdf(
                d,
                &[
                    "walk",
                    "--albedo",
                    "0.9",
                    "--photons",
                    "100",
                    "--profile",
                    "/dev/stdout",
                ],
            ),
            2,
            "--profile /dev/stdout is stdout, where the command writes its summary",
        );
        fails_with(
            &bssrdf(
                d,
                &[
                    "render",
                    "--preset",
                    "figure-10",
                    "--theta",
                    "30",
                    "--photons",
                    "100",
                    "--no-preview",
                    "-o",
                    "/dev/stdout",
                ],
            ),
            2,
            "-o /dev/stdout is stdout, where the command writes its summary",
        );
    }
    // Outputs that cannot be written are refused before the work: a path ending in /, one
    // through a file, a link into a folder that does not exist, the command's stderr
    std::fs::write(d.join("plain"), "x").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("missingdir/x.bssrdf", d.join("dangling")).unwrap();
    for (output, needle) in [
        ("nothere/", "cannot write nothere/: the path names a folder"),
        (
            "plain/y.bssrdf",
            "cannot write plain/y.bssrdf: Not a directory",
        ),
        (
            "dangling",
            "cannot write dangling: its folder missingdir does not exist",
        ),
    ] {
        let args = ["bake", "--eta", "1.33", "-q", "-o", output];
        fails_with(&bssrdf(d, &args), 2, needle);
    }
    // Outputs that cannot be written are refused before the work
    fails_with(
        &bssrdf(d, &["bake", "--eta", "1.33", "-q", "-o", "nodir/x.bssrdf"]),
        2,
        "cannot write nodir/x.bssrdf: its folder nodir does not exist",
    );
    fails_with(
        &bssrdf(
            d,
            &[
                "zoo",
                "-q",
                "--photons",
                "100000000",
                "--plot",
                "m.toml",
                "--cases",
                "0.9:0",
            ],
        ),
        2,
        "--plot m.toml is a file, not a folder for the figures",
    );
    // A file of a --materials folder is an input too: never the output
    std::fs::create_dir(d.join("mats")).unwrap();
    std::fs::copy(d.join("m.toml"), d.join("mats/m.toml")).unwrap();
    let before = std::fs::read(d.join("mats/m.toml")).unwrap();
    // Nor a new *.toml there, which later runs would read as a material file
    for (output, needle) in [
        ("mats/m.toml", "refusing to overwrite an input"),
        (
            "mats/new.toml",
            "-o mats/new.toml is a *.toml file of the --materials folder mats",
        ),
    ] {
        let args = [
            "bake",
            "mine",
            "--materials",
            "mats",
            "--grid",
            "coarse",
            "-o",
            output,
        ];
        fails_with(&bssrdf(d, &args), 2, needle);
    }
    assert_eq!(std::fs::read(d.join("mats/m.toml")).unwrap(), before);
    assert!(!d.join("mats/new.toml").exists());
}

#[test]
fn channel_needs_a_material() {
    let dir = bare();
    let d = dir.path();
    for args in [
        &[
            "eval",
            "--model",
            "pbd",
            "--rho",
            "0.5",
            "--channel",
            "g",
            "--theta",
            "0",
            "--r",
            "1",
        ][..],
        &[
            "eval",
            "t.bssrdf",
            "--rho",
            "0.5",
            "--channel",
            "g",
            "--theta",
            "0",
            "--r",
            "1",
        ],
        &[
            "sample",
            "t.bssrdf",
            "--rho",
            "0.5",
            "--channel",
            "b",
            "-n",
            "1",
        ],
    ] {
        let o = bssrdf(d, args);
        fails_with(&o, 2, "--channel picks a colour channel of --material");
        assert!(o.stdout.is_empty());
    }
}

/// A table that keeps only some angles (here 45° to 90°, a valid file: format-spec.md allows
/// any subset of the axes) refuses an incidence outside them by name, in eval, sample and
/// validate, instead of "no value" or "no light leaves".
#[test]
fn an_incidence_outside_the_kept_angles_is_named() {
    use bssrdf_zoo::format::{Compression, LibraryBuilder, Provenance};
    use bssrdf_zoo::fresnel::Moments;
    use bssrdf_zoo::table::{bake, Grid};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut grid = Grid::ferrier(12, 3, 12);
    grid.theta = vec![45f64.to_radians(), 70f64.to_radians(), 90f64.to_radians()];
    let (table, _) = bake(1.33, Moments::Exact, &grid, true).unwrap();
    let mut builder = LibraryBuilder::new();
    builder.add_table(table.to_table_data()).unwrap();
    builder.set_provenance(Provenance::new("test: angles 45 to 90 deg"));
    builder
        .write_atomic(d.join("high.bssrdf"), Compression::None)
        .unwrap();
    let needle = "--theta 10 is outside the incidence range this table keeps, [45, 90] deg";
    let eval = [
        "eval",
        "high.bssrdf",
        "--rho",
        "0.5",
        "--theta",
        "10",
        "--r",
        "1",
    ];
    fails_with(&bssrdf(d, &eval), 2, needle);
    let sample = [
        "sample",
        "high.bssrdf",
        "--rho",
        "0.5",
        "--theta",
        "10",
        "-n",
        "2",
    ];
    fails_with(&bssrdf(d, &sample), 2, needle);
    // The end nodes given in degrees are the nodes (45° lies just below the f32 node π/4)
    for theta in ["45", "60", "90"] {
        ok(&bssrdf(
            d,
            &[
                "eval",
                "high.bssrdf",
                "--rho",
                "0.5",
                "--theta",
                theta,
                "--r",
                "1",
            ],
        ));
        ok(&bssrdf(
            d,
            &[
                "sample",
                "high.bssrdf",
                "--rho",
                "0.5",
                "--theta",
                theta,
                "-n",
                "2",
            ],
        ));
    }
    fails_with(
        &bssrdf(
            d,
            &[
                "eval",
                "high.bssrdf",
                "--model",
                "perpendicular",
                "--rho",
                "0.5",
                "--theta",
                "0",
                "--r",
                "1",
            ],
        ),
        2,
        "the perpendicular model's theta 0 is outside the incidence range this table keeps",
    );
    let validate = text(&bssrdf(d, &["validate", "high.bssrdf", "--samples", "50"]).stdout);
    assert!(
        validate
            .contains("skipped: theta outside the incidence range this table keeps, [45, 90] deg"),
        "{validate}"
    );
}

/// A file written elsewhere may pair a material with a table of another η (the format allows
/// it): a lookup through the material would be neither the material's nor the table's, so
/// eval, sample and validate refuse it naming both η, whatever --eta says; the table itself
/// stays open to --table and --rho.
#[test]
fn a_material_paired_with_a_table_of_another_eta_is_refused_naming_both() {
    use bssrdf_zoo::format::{Compression, LibraryBuilder, Material, Provenance};
    use bssrdf_zoo::fresnel::Moments;
    use bssrdf_zoo::table::{bake, Grid};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (table, _) = bake(1.3, Moments::Exact, &Grid::ferrier(12, 3, 12), true).unwrap();
    let mut builder = LibraryBuilder::new();
    builder.add_table(table.to_table_data()).unwrap();
    builder
        .add_material(Material {
            name: "wax".into(),
            source: String::new(),
            sigma_s: [1.0; 3],
            sigma_a: [0.1; 3],
            g: [0.0; 3],
            eta: 1.5,
            tables: [0; 3],
            albedo_range: None,
        })
        .unwrap();
    builder.set_provenance(Provenance::new(
        "test: a material of eta 1.5 on a table of 1.3",
    ));
    builder
        .write_atomic(d.join("m.bssrdf"), Compression::None)
        .unwrap();
    let needle =
        "material wax of m.bssrdf has eta 1.5, but its table 0 (red channel) holds eta 1.3";
    for eta in [&[][..], &["--eta", "1.5"], &["--eta", "1.3"]] {
        let point = ["--material", "wax", "--theta", "30"];
        let eval = [&["eval", "m.bssrdf", "--r", "1"][..], &point, eta].concat();
        let o = bssrdf(d, &eval);
        assert!(!o.status.success() && o.stdout.is_empty(), "{eta:?}");
        fails_with(&o, 2, "has eta 1.5, but its table 0");
        let sample = [&["sample", "m.bssrdf", "-n", "1"][..], &point, eta].concat();
        fails_with(&bssrdf(d, &sample), 2, "has eta 1.5, but its table 0");
    }
    fails_with(
        &bssrdf(
            d,
            &[
                "eval",
                "m.bssrdf",
                "--material",
                "wax",
                "--theta",
                "30",
                "--r",
                "1",
            ],
        ),
        2,
        needle,
    );
    fails_with(
        &bssrdf(
            d,
            &[
                "validate",
                "m.bssrdf",
                "--material",
                "wax",
                "--samples",
                "3",
                "-q",
            ],
        ),
        2,
        needle,
    );
    ok(&bssrdf(
        d,
        &[
            "eval", "m.bssrdf", "--table", "0", "--rho", "0.5", "--theta", "30", "--r", "1",
        ],
    ));
}

/// A closed stderr loses the messages but never panics (exit 101): an error still exits 2, a
/// success 0.
#[test]
fn a_closed_stderr_is_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    for (args, code) in [
        (&["eval", "--rho", "2", "--theta", "0", "--r", "1"][..], 2),
        (&["walk", "--albedo", "0.9", "--photons", "100"], 0),
    ] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_bssrdf"))
            .current_dir(dir.path())
            .args(args)
            .stdout(std::process::Stdio::null())
            .stderr(writer)
            .status()
            .unwrap();
        assert_eq!(status.code(), Some(code), "{args:?}");
    }
}

/// The bound that the refusal of `refused` states in its message, between `before` and
/// `after`, is taken by the same command: `args`, with `{}` standing for the bound.
fn stated_bound_is_taken(
    d: &std::path::Path,
    refused: &[&str],
    (before, after): (&str, &str),
    args: &[&str],
) {
    let message = text(&bssrdf(d, refused).stderr);
    let bound = message
        .split(before)
        .nth(1)
        .and_then(|rest| rest.split(after).next())
        .expect(&message);
    let args: Vec<&str> = args
        .iter()
        .map(|&a| if a == "{}" { bound } else { a })
        .collect();
    ok(&bssrdf(d, &args));
}

/// The weight the vertex cap stops is in none of the reflectances: the text says how much,
/// as `--json`'s `truncated_weight` does (at albedo 1 and g = 0.9999 a fifth of the light,
/// which the total reflectance, 0.76 for a true 1, would otherwise hide).
#[test]
fn walk_text_shows_the_weight_the_vertex_cap_truncated() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = ["walk", "--albedo", "1", "--g", "0.9999", "--photons", "100"];
    let text = ok(&bssrdf(d, &args));
    let line = text
        .lines()
        .find(|l| l.starts_with("truncated weight"))
        .unwrap_or_else(|| panic!("no truncated weight in {text}"));
    assert!(line.contains("missing from the lines above"), "{line}");
    let shown: f64 = line["truncated weight".len()..]
        .split(" ± ")
        .next()
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    let mut json_args = args.to_vec();
    json_args.push("--json");
    let json: serde_json::Value = serde_json::from_str(&ok(&bssrdf(d, &json_args))).unwrap();
    let truncated = json["truncated_weight"].as_f64().unwrap();
    assert!(truncated > 0.05, "{json}");
    assert!(
        (shown - truncated).abs() < 1e-6,
        "{shown} against {truncated}"
    );
    // Nothing truncated, no line
    let light = ok(&bssrdf(
        d,
        &["walk", "--albedo", "0.5", "--photons", "1000"],
    ));
    assert!(!light.contains("truncated"), "{light}");
}

/// The zoo's table and notes print ρ′ and θ by the one number formatter, the shorter of plain
/// and exponent form: `1e-300`, not three hundred digits.
#[test]
fn zoo_prints_its_cases_with_the_number_formatter() {
    let dir = tempfile::tempdir().unwrap();
    let text = ok(&bssrdf(
        dir.path(),
        &[
            "zoo",
            "--eta",
            "1",
            "--photons",
            "2",
            "--cases",
            "1e-300:1e-7",
            "--models",
            "dipole",
            "-q",
        ],
    ));
    assert!(text.contains("| 1e-300 | 1e-7° | dipole |"), "{text}");
    assert!(text.contains("at ρ′ 1e-300, θ 1e-7°"), "{text}");
    assert!(!text.contains("0.0000000000"), "{text}");
}
