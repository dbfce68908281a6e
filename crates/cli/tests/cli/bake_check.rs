//! The bake checks itself: a table above its bound is not written (exit 1) unless
//! --accept-error, and validate checks every table of a file against its own eta.

use crate::common::{bssrdf, fails_with, ok, text};

#[test]
fn a_table_above_its_bound_is_refused_unless_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // eta = 1 is index matched: grazing light runs under the surface and one wrapped Cauchy
    // lobe per node cannot follow its profile (docs/accuracy.md)
    let bake = ["bake", "--eta", "1", "--grid", "coarse", "-o", "one.bssrdf"];
    let refused = bssrdf(d, &bake);
    fails_with(&refused, 1, "above its bound");
    let stderr = text(&refused.stderr);
    assert!(stderr.contains("eta 1, rho"), "{stderr}");
    assert!(stderr.contains("--accept-error"), "{stderr}");
    assert!(!d.join("one.bssrdf").exists());

    let accepted = bssrdf(d, &[&bake[..], &["--accept-error"]].concat());
    ok(&accepted);
    assert!(text(&accepted.stderr).contains("written with --accept-error"));
    assert!(d.join("one.bssrdf").exists());
    // The check is in the file, and inspect shows the regions above the bound
    let inspect = ok(&bssrdf(d, &["inspect", "one.bssrdf"]));
    assert!(inspect.contains("ABOVE BOUND"), "{inspect}");

    let quiet = bssrdf(d, &[&bake[..], &["--accept-error", "-q"]].concat());
    ok(&quiet);
    assert_eq!(text(&quiet.stderr), "");

    // --json carries the same warning, also with -q
    let json = ok(&bssrdf(
        d,
        &[&bake[..], &["--accept-error", "-q", "--json"]].concat(),
    ));
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    let warnings = json["warnings"].as_array().unwrap();
    assert!(
        warnings.iter().any(|w| w.as_str().is_some_and(|w| w
            .starts_with("written with --accept-error")
            && w.contains("eta 1, rho"))),
        "{json}"
    );
}

#[test]
fn validate_checks_every_table_against_its_own_eta() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // apple has eta 1.3, white grapefruit juice 1.33: two tables
    ok(&bssrdf(
        d,
        &[
            "bake",
            "apple",
            "white-grapefruit-juice",
            "--grid",
            "coarse",
            "-q",
            "-o",
            "two.bssrdf",
        ],
    ));
    let run = |extra: &[&str]| {
        let out = bssrdf(
            d,
            &[
                &["validate", "two.bssrdf", "--samples", "300", "--json", "-q"][..],
                extra,
                &["--max-mean-error", "5"],
            ]
            .concat(),
        );
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let all = run(&[]);
    let tables = all["tables"].as_array().unwrap();
    assert_eq!(tables.len(), 2);
    assert_eq!(tables[0]["eta"], 1.3);
    assert_eq!(tables[1]["eta"], 1.33);
    let rows = all["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 18);
    assert_eq!(rows[0]["table"], 0);
    assert_eq!(rows[17]["table"], 1);
    assert_eq!(all["checked"], 18);
    // A choice checks the one table
    let one = run(&["--eta", "1.33"]);
    assert_eq!(one["tables"].as_array().unwrap().len(), 1);
    assert_eq!(one["rows"].as_array().unwrap().len(), 9);
    assert_eq!(one["rows"][0]["eta"], 1.33);
}
