//! `bssrdf bake --source walk`: a walk-angular table for one (η, g), and the refusals of what a
//! walk bake cannot take.

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
    refused(&["--eta", "1.33", "--g", "0.1,0.2,0.3"], "one g");
    refused(
        &["--eta", "1.33", "--g", "1"],
        "--g 1 is outside the valid range: (-1, 1)",
    );
    refused(&["--eta", "1.33", "--g", "nan"], "--g NaN is outside");
    refused(
        &["--eta", "1.33", "--photons", "1e13"],
        "--photons 10000000000000 is outside",
    );
    refused(
        &["--eta", "1.33", "--photons", "100"],
        "--photons 100 is outside the valid range: [131072, 1000000000000]",
    );
    assert!(!d.join("w.bssrdf").exists());
    // And a PBD bake refuses the walk's flags
    for flag in ["--photons", "--seed"] {
        fails_with(
            &bssrdf(d, &["bake", "--eta", "1.33", flag, "5", "-o", "p.bssrdf"]),
            2,
            "a PBD bake has no walk",
        );
    }
}

/// A small walk table (coarse grid, the fewest photons) at η = 1.33, g = 0.5, as `w.bssrdf`.
fn walk_table(d: &std::path::Path) {
    ok(&bssrdf(
        d,
        &[
            "bake",
            "--source",
            "walk",
            "--eta",
            "1.33",
            "--g",
            "0.5",
            "--grid",
            "coarse",
            "--photons",
            "131072",
            "-q",
            "-o",
            "w.bssrdf",
        ],
    ));
}

#[test]
fn a_walk_table_goes_through_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    walk_table(d);
    // inspect names the model, its g and component, and the walk's noise
    let inspect = ok(&bssrdf(d, &["inspect", "w.bssrdf"]));
    assert!(
        inspect.contains("walk-angular g 0.5 component multiple"),
        "{inspect}"
    );
    assert!(inspect.contains("median_rel_stderr"), "{inspect}");
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
    assert!(json.contains("\"model\":\"walk-table\""), "{json}");
    // the Monte Carlo model next to it walks with the file's g and keeps its component
    let mc = ok(&bssrdf(
        d,
        &[&["eval", "w.bssrdf", "--model", "mc", "--json"][..], &at].concat(),
    ));
    assert!(
        mc.contains("\"g\":0.5") && mc.contains("\"component\":\"multiple\""),
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
    // zoo compares it with the walk, at its own eta and g only: at (0.8, 40 deg), g = 0.5, its
    // total is within a few per cent of the walk's where PBD's is 11 % low
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
    ok(&bssrdf(d, &render));
    assert!(d.join("r.exr").exists());
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
