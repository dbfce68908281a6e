//! `bssrdf bake --source walk`: a walk-angular table for one (η, g), of either component (total
//! by default, or multiple), and the refusals of what a walk bake cannot take.

use crate::common::{bssrdf, fails_with, ok};

#[test]
fn a_walk_bake_refuses_what_it_would_not_use() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let walk = ["bake", "--source", "walk", "-o", "w.bssrdf", "-q"];
    let refused = |extra: &[&str], needle: &str| {
        fails_with(&bssrdf(d, &[&walk[..], extra].concat()), 2, needle);
    };
    refused(&["--eta", "1.33", "skin1"], "without materials");
    refused(
        &["--eta", "1.33", "--sigma-s", "1,1,1", "--sigma-a", "0,0,0"],
        "without materials",
    );
    refused(&["--scene", "s.toml"], "without materials");
    refused(
        &["--eta", "1.33", "--fresnel-moments", "pbrt"],
        "exact Fresnel",
    );
    refused(&["--eta", "1.33", "--lobes", "1"], "two lobes");
    refused(&["--eta", "1.33", "--accept-error"], "no such check");
    refused(&[], "--source walk needs --eta");
    refused(
        &["--eta", "3"],
        "--eta 3 is outside the valid range: [0.75, 2.5]",
    );
    refused(
        &["--eta", "1.33", "--g", "0.1,0.2,0.3"],
        "--g 0.1,0.2,0.3: a walk table holds one g, given as one value",
    );
    // A list is refused however equal its values: --g takes one value here
    refused(
        &["--eta", "1.33", "--g", "0.5,0.5,0.5"],
        "--g 0.5,0.5,0.5: a walk table holds one g, given as one value",
    );
    refused(
        &["--eta", "1.33", "--g", "1"],
        "--g 1 is outside the valid range: (-1, 1)",
    );
    refused(&["--eta", "1.33", "--g", "nan"], "--g NaN is outside");
    refused(
        &["--eta", "1.33", "--photons", "1e13"],
        "--photons 1e13 is outside the valid range: [131072, 1e12]",
    );
    // The range as --help writes it
    refused(
        &["--eta", "1.33", "--photons", "100"],
        "--photons 100 is outside the valid range: [131072, 1e12]",
    );
    let help = ok(&bssrdf(d, &["bake", "--help"]));
    assert!(help.contains("in [131072, 1e12]"), "{help}");
    assert!(!d.join("w.bssrdf").exists());
    refused(&["--eta", "1.33", "--component", "single"], "--component");
    assert!(!d.join("w.bssrdf").exists());
    // And a PBD bake refuses the walk's flags
    for flag in ["--photons", "--seed"] {
        fails_with(
            &bssrdf(d, &["bake", "--eta", "1.33", flag, "5", "-o", "p.bssrdf"]),
            2,
            "a PBD bake has no walk",
        );
    }
    for component in ["total", "multiple"] {
        fails_with(
            &bssrdf(
                d,
                &[
                    "bake",
                    "--eta",
                    "1.33",
                    "--component",
                    component,
                    "-o",
                    "p.bssrdf",
                ],
            ),
            2,
            &format!("--component {component} chooses what a --source walk table holds"),
        );
    }
    assert!(!d.join("p.bssrdf").exists());
}

/// A small walk table (coarse grid, the fewest photons) at η = 1.33 and `g`, of the default
/// component with `component` `None`, as `file`; the bake's `--json` summary.
fn walk_table(
    d: &std::path::Path,
    g: &str,
    component: Option<&str>,
    file: &str,
) -> serde_json::Value {
    let mut args = vec![
        "bake",
        "--source",
        "walk",
        "--eta",
        "1.33",
        "--g",
        g,
        "--grid",
        "coarse",
        "--photons",
        "131072",
        "-q",
        "--json",
        "-o",
        file,
    ];
    if let Some(c) = component {
        args.extend(["--component", c]);
    }
    serde_json::from_str(&ok(&bssrdf(d, &args))).unwrap()
}

#[test]
#[ignore = "a second walk bake, about a minute of CPU; the default suite checks the multiple component through the library (crates/zoo/tests/table/walk.rs, the_walk_library_records_its_component)"]
fn a_multiple_walk_table_says_so_everywhere() {
    // `--component multiple`: the walk's multiple scattering alone, and every command knows it
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    walk_table(d, "0", Some("multiple"), "m.bssrdf");
    let inspect = ok(&bssrdf(d, &["inspect", "m.bssrdf"]));
    assert!(
        inspect.contains("walk-angular g 0 component multiple"),
        "{inspect}"
    );
    assert!(!inspect.contains("single_scattering"), "{inspect}");
    let at = [
        "--eta", "1.33", "--rho", "0.8", "--theta", "40", "--r", "0.5", "--phi", "10", "--json",
    ];
    for model in ["walk-table", "mc"] {
        let json = ok(&bssrdf(
            d,
            &[&["eval", "m.bssrdf", "--model", model][..], &at].concat(),
        ));
        assert!(json.contains("\"component\":\"multiple\""), "{json}");
    }
    let zoo = ok(&bssrdf(
        d,
        &[
            "zoo",
            "--photons",
            "20000",
            "--cases",
            "0.8:40",
            "--models",
            "walk-table,mc",
            "--walk-table",
            "m.bssrdf",
            "--json",
            "-q",
        ],
    ));
    let zoo: serde_json::Value = serde_json::from_str(&zoo).unwrap();
    let rows = zoo["rows"].as_array().unwrap();
    let row = |model: &str| rows.iter().find(|r| r["model"] == model).unwrap();
    assert_eq!(row("walk-table")["component"], "multiple");
    // the zoo's mc row is a second walk's total, compared with the reference's total
    assert_eq!(row("mc")["component"], "total");
}

#[test]
fn a_walk_table_goes_through_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The default component: the total, single scattering included
    let summary = walk_table(d, "0.5", None, "w.bssrdf");
    // the summary says how well the nodes hold their profiles, per θ node above 0, in two
    // bands of radius (the coarse grid: every 15° from 15° to 90°)
    // and warns where they miss them by more than 2 % of their energy: near the entry point at
    // grazing incidence, single scattering's cut-off shape
    let warnings = summary["warnings"].as_array().unwrap();
    assert!(
        warnings.iter().any(|w| {
            let w = w.as_str().unwrap();
            w.contains("at theta 90.0 deg") && w.contains("r 0.01-0.1 reduced mfp")
        }),
        "{summary}"
    );
    // and how far the profiles the nodes were fitted to are from the walk's own harmonics,
    // per θ node where light enters (θ = 0 too), here within the walk's noise: no warning
    let misses = summary["tables"][0]["walk_miss"].as_array().unwrap();
    assert_eq!(misses.len(), 7, "{summary}");
    for miss in misses {
        assert!(miss["nodes"].as_u64().unwrap() > 0, "{miss}");
        assert!(miss["rms"].as_f64().unwrap() < 0.02, "{miss}");
        assert!(
            (0.3..3.0).contains(&miss["chi2"].as_f64().unwrap()),
            "{miss}"
        );
    }
    assert!(
        !warnings.iter().any(|w| w
            .as_str()
            .unwrap()
            .contains("walk's own measured harmonics")),
        "{summary}"
    );
    let fits = summary["tables"][0]["node_fit"].as_array().unwrap();
    assert_eq!(fits.len(), 6, "{summary}");
    for fit in fits {
        for band in ["near", "far"] {
            assert!(fit[band]["nodes"].as_u64().unwrap() > 0, "{fit}");
            let mean = fit[band]["mean"].as_f64().unwrap();
            assert!((0.0..1.0).contains(&mean), "{fit}");
        }
    }
    // inspect names the model, its g and component, the walk's noise and how single
    // scattering was added, with its exit-direction assumption
    let inspect = ok(&bssrdf(d, &["inspect", "w.bssrdf"]));
    assert!(
        inspect.contains("walk-angular g 0.5 component total"),
        "{inspect}"
    );
    assert!(inspect.contains("median_rel_stderr"), "{inspect}");
    assert!(inspect.contains("node_fit"), "{inspect}");
    assert!(inspect.contains("walk_miss"), "{inspect}");
    assert!(
        inspect.contains("single_scattering") && inspect.contains("exit_directions"),
        "{inspect}"
    );
    // eval takes it as the walk-table model, and refuses to call it a PBD table
    let at = [
        "--eta", "1.33", "--rho", "0.8", "--theta", "40", "--r", "0.5", "--phi", "10",
    ];
    let value: f64 = ok(&bssrdf(d, &[&["eval", "w.bssrdf"][..], &at].concat()))
        .trim()
        .parse()
        .unwrap();
    assert!(value > 0.0 && value.is_finite());
    let json = ok(&bssrdf(
        d,
        &[&["eval", "w.bssrdf", "--json"][..], &at].concat(),
    ));
    assert!(
        json.contains("\"model\":\"walk-table\"") && json.contains("\"component\":\"total\""),
        "{json}"
    );
    // the Monte Carlo model next to it walks with the file's g and keeps its component
    let mc = ok(&bssrdf(
        d,
        &[&["eval", "w.bssrdf", "--model", "mc", "--json"][..], &at].concat(),
    ));
    assert!(
        mc.contains("\"g\":0.5") && mc.contains("\"component\":\"total\""),
        "{mc}"
    );
    fails_with(
        &bssrdf(
            d,
            &[&["eval", "w.bssrdf", "--model", "table"][..], &at].concat(),
        ),
        2,
        "walk-angular",
    );
    // sample draws from it
    let csv = ok(&bssrdf(
        d,
        &[
            "sample", "w.bssrdf", "--eta", "1.33", "--rho", "0.8", "--theta", "40", "-n", "5",
            "--seed", "1",
        ],
    ));
    assert_eq!(csv.lines().count(), 6, "{csv}");
    // validate measures PBD tables against PBD: nothing to do here, and it says so
    fails_with(
        &bssrdf(d, &["validate", "w.bssrdf"]),
        2,
        "bssrdf zoo --walk-table",
    );
    // zoo compares it with the walk's total, at its own eta and g only: at (0.8, 40 deg),
    // g = 0.5, its total is within a few per cent of the walk's, where PBD (multiple
    // scattering, against the walk's multiple scattering) is 11 % low
    let zoo = ok(&bssrdf(
        d,
        &[
            "zoo",
            "--eta",
            "1.33",
            "--g",
            "0.5",
            "--photons",
            "20000",
            "--cases",
            "0.8:40",
            "--models",
            "pbd,walk-table",
            "--walk-table",
            "w.bssrdf",
            "--json",
            "-q",
        ],
    ));
    let zoo: serde_json::Value = serde_json::from_str(&zoo).unwrap();
    let total = |model: &str| -> f64 {
        let rows = zoo["rows"].as_array().unwrap();
        let row = rows.iter().find(|r| r["model"] == model).unwrap();
        row["total_rel_err"].as_f64().unwrap()
    };
    let (walk, pbd) = (total("walk-table"), total("pbd"));
    assert!(
        walk.abs() < 0.05 && pbd < -0.08,
        "walk table {walk}, pbd {pbd}"
    );
    let rows = zoo["rows"].as_array().unwrap();
    let component =
        |model: &str| rows.iter().find(|r| r["model"] == model).unwrap()["component"].clone();
    assert_eq!(component("walk-table"), "total");
    assert_eq!(component("pbd"), "multiple");
    fails_with(
        &bssrdf(
            d,
            &[
                "zoo",
                "--eta",
                "1.33",
                "--g",
                "0",
                "--walk-table",
                "w.bssrdf",
                "-q",
            ],
        ),
        2,
        "holds no walk table at eta 1.33 and g 0 (it holds a walk table at eta 1.33, g 0.5)",
    );
    fails_with(
        &bssrdf(d, &["zoo", "--models", "walk-table", "-q"]),
        2,
        "needs its table: --walk-table FILE",
    );
    // render draws with it a medium of its eta and g
    let render = [
        "render",
        "--sigma-s",
        "1,1,1",
        "--sigma-a",
        "0.1,0.1,0.1",
        "--eta",
        "1.33",
        "--g",
        "0.5",
        "--theta",
        "30",
        "--photons",
        "2000",
        "--size",
        "16,16",
        "--no-preview",
        "--model",
        "walk-table",
        "--walk-table",
        "w.bssrdf",
        "-o",
        "r.exr",
    ];
    // render draws it as single and multiple scattering together: its summary shows the
    // total alone, with the table's expected power
    let summary = ok(&bssrdf(d, &render));
    assert!(d.join("r.exr").exists());
    assert!(
        summary.contains("total red") && !summary.contains("multiple red"),
        "{summary}"
    );
    let mut other_g = render.to_vec();
    other_g[8] = "0.2";
    fails_with(
        &bssrdf(d, &other_g),
        2,
        "holds no walk table at eta 1.33 and g 0.2",
    );
    let without: Vec<&str> = [&render[..render.len() - 4], &["-o", "r2.exr"]].concat();
    fails_with(
        &bssrdf(d, &without),
        2,
        "the walk-table model needs its table",
    );
}
