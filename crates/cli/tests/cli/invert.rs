//! `bssrdf invert`: the reduced albedo for a diffuse reflectance, on a file's table or on the
//! table baked without one; its output against the library's inversion bit for bit; every
//! refusal (exit 2, nothing on stdout); help, completions and the man page.

use bssrdf_zoo::embed::Library;

use crate::common::{bare, bssrdf, fails_with, ok, text};

fn json(o: &std::process::Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).unwrap()
}

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn invert_gives_the_librarys_reduced_albedo_and_its_json_keys() {
    let dir = bare();
    let d = dir.path();
    let library = Library::read(d.join("t.bssrdf")).unwrap();
    let view_owner = library.table(0).unwrap();
    let view = view_owner.view();
    for (theta_deg, values) in [
        ("0", "0.2,0.5,0.9"),
        ("60", "0.5"),
        ("89.9", "0.001,0,0.01"),
        // ρ′ of about 1e-15: printed in exponent form, not as 15 zeros, to every bit
        ("0", "1e-30"),
    ] {
        let out = ok(&bssrdf(
            d,
            &[
                "invert",
                "t.bssrdf",
                "--reflectance",
                values,
                "--theta",
                theta_deg,
            ],
        ));
        let theta = theta_deg.parse::<f64>().unwrap().to_radians();
        assert!(!out.contains("0.000000"), "{out}");
        let printed: Vec<f64> = out.trim().split(',').map(|v| v.parse().unwrap()).collect();
        let wanted: Vec<f64> = values.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(printed.len(), wanted.len());
        for (rho, a) in printed.iter().zip(&wanted) {
            let expected = view.rho_prime_for_reflectance(*a, theta).unwrap();
            assert_eq!(rho.to_bits(), expected.to_bits(), "{a} at {theta_deg}");
        }
    }
    let v = json(&bssrdf(
        d,
        &[
            "invert",
            "t.bssrdf",
            "--reflectance",
            "0.2,0.5,0.9",
            "--json",
        ],
    ));
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "effective_albedo",
            "eta",
            "fresnel_moments",
            "grid",
            "range",
            "reflectance",
            "rho_prime",
            "table",
            "theta_deg",
            "transmittance",
            "walk_component"
        ]
    );
    assert_eq!(v["table"], 0);
    assert!(v["grid"].is_null());
    assert_eq!(v["eta"], 1.33);
    assert_eq!(v["fresnel_moments"], "exact");
    let t = v["transmittance"].as_f64().unwrap();
    assert!((t - (1.0 - (0.33f64 / 2.33).powi(2))).abs() < 1e-15, "{t}");
    let range = numbers(&v["range"]);
    assert_eq!(range[0], 0.0);
    assert!((0.92..0.94).contains(&range[1]), "{range:?}");
    // A = T ρ_eff at the ρ′ found
    for ((a, rho_eff), rho) in numbers(&v["reflectance"])
        .iter()
        .zip(numbers(&v["effective_albedo"]))
        .zip(numbers(&v["rho_prime"]))
    {
        assert!((t * rho_eff - a).abs() < 1e-7, "{a}: {rho} gives {rho_eff}");
    }
}

#[test]
fn invert_without_a_file_bakes_the_table_bake_would_make() {
    let dir = bare();
    let d = dir.path();
    let args = ["--reflectance", "0.2,0.5,0.9", "--theta", "30"];
    let from_file = ok(&bssrdf(d, &[&["invert", "t.bssrdf"][..], &args].concat()));
    let baked = bssrdf(
        d,
        &[&["invert", "--grid", "coarse", "--threads", "1"][..], &args].concat(),
    );
    assert_eq!(ok(&baked), from_file);
    let v = json(&bssrdf(
        d,
        &[
            "invert",
            "--grid",
            "coarse",
            "--eta",
            "1.5",
            "--reflectance",
            "0.5",
            "--json",
        ],
    ));
    assert!(v["table"].is_null());
    assert_eq!(v["grid"], "coarse");
    assert_eq!(v["eta"], 1.5);
}

#[test]
fn invert_refuses_every_value_outside_its_domain() {
    let dir = bare();
    let d = dir.path();
    let refused = |args: &[&str], needle: &str| {
        let o = bssrdf(d, &[&["invert"][..], args].concat());
        fails_with(&o, 2, needle);
        assert!(o.stdout.is_empty(), "{args:?}: {}", text(&o.stdout));
    };
    fn file<'a>(extra: &[&'a str]) -> Vec<&'a str> {
        [&["t.bssrdf"][..], extra].concat()
    }
    // Reflectances outside [0, 1] or not numbers (the table's own range is below)
    for (value, needle) in [
        (
            "-0.1",
            "--reflectance -0.1 is outside the valid range: [0, 1]",
        ),
        (
            "1.5",
            "--reflectance 1.5 is outside the valid range: [0, 1]",
        ),
        (
            "nan",
            "--reflectance NaN is outside the valid range: [0, 1]",
        ),
        (
            "inf",
            "--reflectance inf is outside the valid range: [0, 1]",
        ),
        (
            "0.5,-1,0.5",
            "--reflectance[g] -1 is outside the valid range: [0, 1]",
        ),
        (
            "0.5,0.5",
            "expected one number or 3 comma-separated numbers",
        ),
        ("x", "\"x\" is not a number"),
    ] {
        refused(&file(&["--reflectance", value]), needle);
        // Checked before any bake without a file, too
        refused(&["--reflectance", value], needle);
    }
    // θ, η
    for (flag, value, needle) in [
        (
            "--theta",
            "95",
            "--theta 95 is outside the valid range: [0, 90]",
        ),
        (
            "--theta",
            "-1",
            "--theta -1 is outside the valid range: [0, 90]",
        ),
        (
            "--theta",
            "nan",
            "--theta NaN is outside the valid range: [0, 90]",
        ),
        (
            "--eta",
            "3",
            "--eta 3 is outside the valid range: [0.75, 2.5]",
        ),
    ] {
        refused(&file(&["--reflectance", "0.5", flag, value]), needle);
        refused(&["--reflectance", "0.5", flag, value], needle);
    }
    // Reflectances above the table's range (named with it); no light (grazing incidence,
    // beyond the critical angle); flags that need a FILE or that a FILE's table makes
    // meaningless; tables the file does not hold.
    let cases: [(&[&str], &str); 15] = [
        (
            &["t.bssrdf", "--reflectance", "0.95"],
            "--reflectance 0.95 is outside the valid range: [0, 0.93",
        ),
        (
            &["t.bssrdf", "--reflectance", "0.5,0.5,0.95"],
            "--reflectance[b] 0.95 is outside the valid range: [0, 0.93",
        ),
        (
            &["t.bssrdf", "--reflectance", "0.5", "--theta", "89.9"],
            "--reflectance 0.5 is outside the valid range: [0, 0.01",
        ),
        (
            &["t.bssrdf", "--reflectance", "0", "--theta", "90"],
            "--theta 90: no light enters at grazing incidence",
        ),
        (
            &["--reflectance", "0.1", "--theta", "90"],
            "--theta 90: no light enters at grazing incidence",
        ),
        (
            &["--reflectance", "0.1", "--theta", "60", "--eta", "0.8"],
            "--theta 60: no light enters beyond the critical angle, asin(eta = 0.8): --theta at most 53.1",
        ),
        (
            &["--reflectance", "0.5", "--table", "0"],
            "--table chooses how to read a library FILE",
        ),
        (
            &["--reflectance", "0.5", "--mmap"],
            "--mmap chooses how to read a library FILE",
        ),
        (
            &["t.bssrdf", "--reflectance", "0.5", "--grid", "coarse"],
            "--grid sets the table baked without a FILE",
        ),
        (
            &[
                "t.bssrdf",
                "--reflectance",
                "0.5",
                "--fresnel-moments",
                "pbrt",
            ],
            "--fresnel-moments sets the table baked without a FILE",
        ),
        (
            &["t.bssrdf", "--reflectance", "0.5", "--threads", "2"],
            "--threads sets the table baked without a FILE",
        ),
        (
            &["--reflectance", "0.5", "--threads", "0"],
            "--threads 0 is outside the valid range",
        ),
        (
            &["t.bssrdf", "--reflectance", "0.5", "--table", "3"],
            "--table 3: t.bssrdf holds 1 table(s)",
        ),
        (
            &["t.bssrdf", "--reflectance", "0.5", "--eta", "1.5"],
            "--eta 1.5: t.bssrdf has no table at this eta; its tables: 1.33 (table 0)",
        ),
        (
            &[
                "t.bssrdf",
                "--reflectance",
                "0.5",
                "--eta",
                "1.5",
                "--table",
                "0",
            ],
            "--table 0 holds eta 1.33, not --eta 1.5",
        ),
    ];
    for (args, needle) in cases {
        refused(args, needle);
    }
    refused(&file(&[]), "--reflectance");
}

#[test]
fn invert_is_in_the_help_completions_and_man_pages() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert!(ok(&bssrdf(d, &["--help"])).contains("invert"));
    let bash = ok(&bssrdf(d, &["completions", "bash"]));
    assert!(bash.contains("invert") && bash.contains("--reflectance"));
    ok(&bssrdf(d, &["man", "--dir", "pages"]));
    let page = std::fs::read_to_string(d.join("pages/bssrdf-invert.1")).unwrap();
    assert!(page.contains("reflectance") && page.contains("theta"));
}
