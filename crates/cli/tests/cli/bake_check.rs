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

/// A scene of a white medium (σa = 0: ρ′ = 1) keeps only the last albedo rows, above 0.999:
/// the check covers them (its last band is [0.999, 1]), so a table off there is refused as the
/// full bake is, and one that meets the bound is checked, not passed with no region.
#[test]
fn a_scene_of_white_media_is_checked_at_the_end_of_the_albedo_axis() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let white = |eta: &str| {
        format!("[[material]]\nname = \"my-white\"\nsigma_s = [1, 1, 1]\nsigma_a = [0, 0, 0]\neta = {eta}\n")
    };
    std::fs::write(d.join("index-matched.toml"), white("1")).unwrap();
    let refused = bssrdf(
        d,
        &[
            "bake",
            "--scene",
            "index-matched.toml",
            "--grid",
            "coarse",
            "-o",
            "w1.bssrdf",
        ],
    );
    fails_with(&refused, 1, "above its bound");
    let stderr = text(&refused.stderr);
    assert!(stderr.contains("-1, theta 85-90 deg"), "{stderr}");
    assert!(!d.join("w1.bssrdf").exists());

    std::fs::write(d.join("skin-like.toml"), white("1.3")).unwrap();
    ok(&bssrdf(
        d,
        &[
            "bake",
            "--scene",
            "skin-like.toml",
            "--grid",
            "coarse",
            "-q",
            "-o",
            "w13.bssrdf",
        ],
    ));
    let report: serde_json::Value =
        serde_json::from_str(&ok(&bssrdf(d, &["inspect", "--json", "w13.bssrdf"]))).unwrap();
    let regions = report["provenance"]["accuracy"]["tables"][0]["regions"]
        .as_array()
        .unwrap();
    assert_eq!(regions.len(), 5, "{report}");
    assert!(regions.iter().all(|r| r["rho"][1] == 1.0), "{report}");
}
