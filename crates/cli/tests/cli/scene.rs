//! End-to-end tests of `bake --scene` and of materials given on the command line
//! (`--sigma-s/--sigma-a`, `--reflectance/--mfp`): success, the --json shape, bit-identical
//! lookups against a full bake through the real binary, and every error path (exit 2).

use std::path::Path;
use std::process::Output;

use crate::common::{bssrdf, ok, text};

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("one JSON object")
}

fn fails_with(o: &Output, code: i32, needles: &[&str]) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

const SCENE: &str = r#"
integrator = "path"              # "path" needs the θ-sampling table, "particle" does not
[[material]]
name = "white-grapefruit-juice"  # constant albedo: only the rows around its three ρ′ values
[[material]]
name = "skin1"
albedo_range = [[0.85, 0.97], [0.80, 0.90], [0.60, 0.70]]   # reduced albedo ρ′, per channel
"#;

/// The example scene and the full library of the same materials, both on the coarse grid.
fn scene_and_full() -> (tempfile::TempDir, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    let summary = json(&bssrdf(
        d,
        &[
            "bake",
            "--scene",
            "scene.toml",
            "--grid",
            "coarse",
            "--json",
        ],
    ));
    ok(&bssrdf(
        d,
        &[
            "bake",
            "white-grapefruit-juice",
            "skin1",
            "--grid",
            "coarse",
            "-q",
            "-o",
            "full.bssrdf",
        ],
    ));
    (dir, summary)
}

#[test]
fn scene_bake_reports_tables_materials_and_the_size_saved() {
    let (dir, s) = scene_and_full();
    assert_eq!(s["output"], "scene.bssrdf");
    assert!(dir.path().join("scene.bssrdf").exists());
    let (bytes, full) = (
        s["bytes"].as_u64().unwrap(),
        s["full_bytes"].as_u64().unwrap(),
    );
    let on_disk = std::fs::metadata(dir.path().join("scene.bssrdf"))
        .unwrap()
        .len();
    assert_eq!(bytes, on_disk);
    let full_on_disk = std::fs::metadata(dir.path().join("full.bssrdf"))
        .unwrap()
        .len();
    // The estimate of the full library differs only by the provenance text (the bake's check
    // of each table is about 7 KiB of it).
    assert!(
        full.abs_diff(full_on_disk) < 16384,
        "{full} vs {full_on_disk}"
    );
    assert_eq!(s["saved_bytes"].as_u64().unwrap(), full - bytes);
    let percent = s["saved_percent"].as_f64().unwrap();
    assert!(percent > 50.0 && percent < 100.0, "{percent}");
    assert_eq!(s["integrator"], "path");
    let tables = s["tables"].as_array().unwrap();
    assert!(tables.len() >= 2);
    for t in tables {
        assert_eq!(t["theta_sampling"], true);
        // Below η = 1.33 the tables have two lobes (`--lobes auto`), from 1.33 one
        let lobes = if t["eta"].as_f64().unwrap() < 1.33 {
            2
        } else {
            1
        };
        assert_eq!(t["lobes"], lobes, "{t}");
        let rows = t["rows"].as_array().unwrap();
        assert!(rows[0].as_u64() < rows[1].as_u64());
    }
    let skin = &s["materials"][1];
    assert_eq!(skin["name"], "skin1");
    assert_eq!(
        skin["albedo_range"]["min"],
        serde_json::json!([0.85, 0.8, 0.6])
    );
    assert_eq!(
        skin["albedo_range"]["max"],
        serde_json::json!([0.97, 0.9, 0.7])
    );
    assert_eq!(skin["origin"], "library");
    assert!(s["warnings"].as_array().unwrap().is_empty());
    // The file records the ranges.
    let inspect = json(&bssrdf(dir.path(), &["inspect", "scene.bssrdf", "--json"]));
    assert_eq!(
        inspect["materials"][1]["albedo_range"]["min"],
        skin["albedo_range"]["min"]
    );
    let juice = &inspect["materials"][0]["albedo_range"];
    assert_eq!(juice["min"], juice["max"]);
}

/// The tables of skin1 (η = 1.3) in both files, for channel b (ρ′ ∈ [0.6, 0.7]) and r.
fn skin_tables(dir: &Path) -> ([String; 2], String) {
    let scene = json(&bssrdf(dir, &["inspect", "scene.bssrdf", "--json"]));
    let full = json(&bssrdf(dir, &["inspect", "full.bssrdf", "--json"]));
    let skin = |j: &serde_json::Value| {
        j["materials"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == "skin1")
            .unwrap()["tables"]
            .clone()
    };
    let (s, f) = (skin(&scene), skin(&full));
    ([s[2].to_string(), s[0].to_string()], f[0].to_string())
}

#[test]
fn lookups_inside_the_ranges_print_the_same_bits_as_the_full_bake() {
    let (dir, _) = scene_and_full();
    let d = dir.path();
    let ([blue, red], full) = skin_tables(d);
    for (table, lo, hi) in [(&blue, 0.6, 0.7), (&red, 0.85, 0.97)] {
        let mut csv = String::from("rho,theta_deg,r,phi_deg\n");
        for i in 0..=20 {
            let rho = lo + (hi - lo) * f64::from(i) / 20.0;
            for (theta, r, phi) in [
                (0.0, 0.01, 0.0),
                (35.0, 0.7, 30.0),
                (60.0, 2.5, 180.0),
                (89.0, 0.2, -45.0),
            ] {
                csv += &format!("{rho},{theta},{r},{phi}\n");
            }
        }
        std::fs::write(d.join("points.csv"), &csv).unwrap();
        let eval = |file: &str, t: &str| {
            ok(&bssrdf(
                d,
                &["eval", file, "--table", t, "--points", "points.csv"],
            ))
        };
        assert_eq!(eval("scene.bssrdf", table), eval("full.bssrdf", &full));
        for rho in [lo, (lo + hi) / 2.0, hi] {
            let rho = rho.to_string();
            let sample = |file: &str, t: &str, extra: &[&str]| {
                let mut a = vec![
                    "sample", file, "--table", t, "--rho", &rho, "-n", "200", "--seed", "5",
                ];
                a.extend_from_slice(extra);
                ok(&bssrdf(d, &a))
            };
            for extra in [&["--theta", "45"][..], &["--path-tracing"][..]] {
                assert_eq!(
                    sample("scene.bssrdf", table, extra),
                    sample("full.bssrdf", &full, extra),
                    "rho {rho} {extra:?}"
                );
            }
        }
    }
    // By material: ρ′ and σ′t come from the file's record, r in mm.
    let by_material = |file: &str| {
        ok(&bssrdf(
            d,
            &[
                "eval",
                file,
                "--material",
                "skin1",
                "--channel",
                "g",
                "--theta",
                "30",
                "--r",
                "0.8",
            ],
        ))
    };
    assert_eq!(by_material("scene.bssrdf"), by_material("full.bssrdf"));
}

#[test]
fn lookups_outside_the_kept_rows_are_errors_naming_the_range() {
    let (dir, _) = scene_and_full();
    let ([blue, _], _) = skin_tables(dir.path());
    let o = bssrdf(
        dir.path(),
        &[
            "eval",
            "scene.bssrdf",
            "--table",
            &blue,
            "--rho",
            "0.2",
            "--theta",
            "0",
            "--r",
            "1",
        ],
    );
    fails_with(&o, 2, &["0.2", "keeps", "never extrapolated"]);
    let o = bssrdf(
        dir.path(),
        &[
            "sample",
            "scene.bssrdf",
            "--table",
            &blue,
            "--rho",
            "0.99",
            "-n",
            "3",
        ],
    );
    fails_with(&o, 2, &["0.99", "keeps"]);
}

#[test]
fn particle_scenes_drop_the_theta_sampling_section() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("p.toml"),
        "integrator = \"particle\"\n[[material]]\nname = \"skin1\"\n",
    )
    .unwrap();
    let s = json(&bssrdf(
        d,
        &[
            "bake", "--scene", "p.toml", "--grid", "coarse", "--json", "-q",
        ],
    ));
    assert_eq!(s["output"], "p.bssrdf");
    assert_eq!(s["integrator"], "particle");
    for t in s["tables"].as_array().unwrap() {
        assert_eq!(t["theta_sampling"], false);
    }
    let o = bssrdf(
        d,
        &[
            "sample",
            "p.bssrdf",
            "--material",
            "skin1",
            "--path-tracing",
            "-n",
            "2",
        ],
    );
    // The message names the real reason: the scene's integrator, not --no-theta-sampling
    fails_with(
        &o,
        2,
        &[
            "p.bssrdf was baked from a scene with integrator = \"particle\", which keeps no theta-sampling table",
            "path tracing needs it",
        ],
    );
    assert!(!text(&o.stderr).contains("--no-theta-sampling"));
    // A plain bake without it names the flag
    ok(&bssrdf(
        d,
        &[
            "bake",
            "--eta",
            "1.33",
            "--grid",
            "coarse",
            "--no-theta-sampling",
            "-q",
            "-o",
            "nt.bssrdf",
        ],
    ));
    let o = bssrdf(
        d,
        &[
            "sample",
            "nt.bssrdf",
            "--rho",
            "0.5",
            "--path-tracing",
            "-n",
            "2",
        ],
    );
    fails_with(
        &o,
        2,
        &["nt.bssrdf was baked without the theta-sampling table (--no-theta-sampling)"],
    );
}

#[test]
fn the_default_output_replaces_only_the_last_extension() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = "integrator = \"particle\"\n[[material]]\nname = \"skin1\"\n";
    for name in ["shot.v1.toml", "shot.v2.toml"] {
        std::fs::write(d.join(name), scene).unwrap();
        let s = json(&bssrdf(
            d,
            &["bake", "--scene", name, "--grid", "coarse", "--json", "-q"],
        ));
        assert_eq!(s["output"], name.replace(".toml", ".bssrdf"));
    }
    // Two files, neither overwriting the other; no shot.bssrdf
    assert!(d.join("shot.v1.bssrdf").is_file() && d.join("shot.v2.bssrdf").is_file());
    assert!(!d.join("shot.bssrdf").exists());
}

#[test]
fn inline_scene_materials_and_stderr_without_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("inline.toml"),
        "[[material]]\nname = \"my-wax\"\nsigma_s = [1.0, 1.1, 1.2]\nsigma_a = [0.01, 0.02, 0.05]\ng = 0.3\neta = 1.45\n\
         [[material]]\nname = \"jade\"\nreflectance = [0.5, 0.7, 0.99]\nmfp = [2, 3, 1.5]\n",
    )
    .unwrap();
    let o = bssrdf(
        d,
        &[
            "bake",
            "--scene",
            "inline.toml",
            "--grid",
            "coarse",
            "--json",
        ],
    );
    let s: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    assert_eq!(s["materials"][0]["origin"], "coefficients");
    assert_eq!(s["materials"][0]["eta"], 1.45);
    assert_eq!(s["materials"][1]["origin"], "diffuse");
    assert_eq!(s["materials"][1]["rho_prime"][2], 1.0);
    let warnings = s["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains("clamped")),
        "{warnings:?}"
    );
    // stderr is a pipe here: the summary and the warning, never a progress bar.
    let err = text(&o.stderr);
    assert!(err.contains("warning:") && err.contains("saved"), "{err}");
    assert!(!err.contains('\r') && !err.contains("baking ["), "{err:?}");
}

#[test]
fn scene_errors_exit_2_and_name_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bake = |name: &str, body: &str| {
        std::fs::write(d.join(name), body).unwrap();
        bssrdf(d, &["bake", "--scene", name, "--grid", "coarse", "-q"])
    };
    fails_with(
        &bake("missing.toml", "[[material]]\nname = \"skinn1\"\n"),
        2,
        &["missing.toml", "skinn1", "skin1"],
    );
    // An inline material takes a new id, not a library one's nor an alias
    for (file, name, library) in [
        ("lib.toml", "skin1", "skin1"),
        ("alias.toml", "skimmilk", "skim-milk"),
    ] {
        fails_with(
            &bake(
                file,
                &format!("[[material]]\nname = \"{name}\"\nsigma_s = [1, 1, 1]\nsigma_a = [0.01, 0.02, 0.05]\n"),
            ),
            2,
            &[file, "inline coefficients need a new id", &format!("library material {library:?}")],
        );
    }
    // A control character in a source is refused before the bake, naming material and byte
    fails_with(
        &bake(
            "ctrl.toml",
            "[[material]]\nname = \"my-wax\"\nsigma_s = [1, 1, 1]\nsigma_a = [0.1, 0.1, 0.1]\nsource = \"a\\nb\"\n",
        ),
        2,
        &["ctrl.toml", "my-wax", "control character '\\n' at byte 1"],
    );
    fails_with(
        &bake(
            "range.toml",
            "[[material]]\nname = \"skin1\"\nalbedo_range = [[0.85, 0.97], [0.80, 1.5], [0.6, 0.7]]\n",
        ),
        2,
        &["skin1", "albedo_range[g]", "1.5", "[0, 1]"],
    );
    fails_with(
        &bake(
            "nan.toml",
            "[[material]]\nname = \"skin1\"\nalbedo_range = [nan, 0.9]\n",
        ),
        2,
        &["skin1", "NaN"],
    );
    fails_with(
        &bake(
            "reversed.toml",
            "[[material]]\nname = \"skin1\"\nalbedo_range = [0.9, 0.8]\n",
        ),
        2,
        &["reversed", "0.9"],
    );
    fails_with(
        &bake(
            "unknown.toml",
            "[[material]]\nname = \"skin1\"\nalbedo_rnage = [0.8, 0.9]\n",
        ),
        2,
        &["albedo_rnage"],
    );
    fails_with(
        &bake("empty.toml", "integrator = \"path\"\n"),
        2,
        &["no material"],
    );
    fails_with(
        &bake(
            "twice.toml",
            "[[material]]\nname = \"skin1\"\n[[material]]\nname = \"skin1\"\n",
        ),
        2,
        &["twice"],
    );
    fails_with(
        &bssrdf(d, &["bake", "--scene", "absent.toml", "-q"]),
        2,
        &["absent.toml"],
    );
    fails_with(
        &bssrdf(d, &["bake", "skin1", "--scene", "missing.toml", "-q"]),
        2,
        &["--scene"],
    );
}

#[test]
fn coefficient_materials_bake_and_evaluate() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let s = json(&bssrdf(
        d,
        &[
            "bake",
            "--grid",
            "coarse",
            "-q",
            "--json",
            "--sigma-s",
            "1,1.1,1.2",
            "--sigma-a",
            "0.01,0.02,0.05",
            "--g",
            "0.3",
            "--eta",
            "1.45",
            "--name",
            "my-wax",
        ],
    ));
    assert_eq!(s["output"], "my-wax.bssrdf");
    let m = &s["materials"][0];
    assert_eq!(
        (m["name"].as_str(), m["eta"].as_f64()),
        (Some("my-wax"), Some(1.45))
    );
    let rho = 1.0 * 0.7 / (1.0 * 0.7 + 0.01);
    assert!((m["rho_prime"][0].as_f64().unwrap() - rho).abs() < 1e-12);
    assert!(s["full_bytes"].is_null());
    let v = ok(&bssrdf(
        d,
        &[
            "eval",
            "my-wax.bssrdf",
            "--material",
            "my-wax",
            "--theta",
            "20",
            "--r",
            "1",
        ],
    ));
    assert!(v.trim().parse::<f64>().unwrap() > 0.0);
    // With a named material in the same library.
    let s = json(&bssrdf(
        d,
        &[
            "bake",
            "skin1",
            "--grid",
            "coarse",
            "-q",
            "--json",
            "--sigma-s",
            "1,1,1",
            "--sigma-a",
            "1,1,1",
            "-o",
            "both.bssrdf",
        ],
    ));
    assert_eq!(s["materials"].as_array().unwrap().len(), 2);
    assert_eq!(s["tables"].as_array().unwrap().len(), 2);
}

#[test]
fn reflectance_materials_invert_and_warn_when_clamped() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = bssrdf(
        d,
        &[
            "bake",
            "--grid",
            "coarse",
            "--json",
            "--reflectance",
            "0.5,0.8,0.99",
            "--mfp",
            "1,2,0.5",
            "--name",
            "jade",
        ],
    );
    let s: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    let rho = s["materials"][0]["rho_prime"].as_array().unwrap().clone();
    let rho: Vec<f64> = rho.iter().map(|v| v.as_f64().unwrap()).collect();
    assert!(rho[0] < rho[1] && rho[1] < 1.0 && rho[2] == 1.0, "{rho:?}");
    assert!(text(&o.stderr).contains("warning:"), "{}", text(&o.stderr));
    // σt = 1/mfp (the inversion itself is tested against the table in crates/zoo/tests/table/subset.rs).
    let e = json(&bssrdf(d, &["inspect", "jade.bssrdf", "--json"]));
    let sigma_s = e["materials"][0]["sigma_s"][0].as_f64().unwrap();
    let sigma_a = e["materials"][0]["sigma_a"][0].as_f64().unwrap();
    assert!((sigma_s + sigma_a - 1.0).abs() < 1e-12, "mfp = 1/sigma_t");
}

#[test]
fn command_line_material_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bake = |extra: &[&str]| {
        let mut a = vec!["bake", "--grid", "coarse", "-q"];
        a.extend_from_slice(extra);
        bssrdf(d, &a)
    };
    fails_with(
        &bake(&["--sigma-s", "1,1", "--sigma-a", "1,1,1"]),
        2,
        &["--sigma-s", "1,1", "3 comma-separated"],
    );
    fails_with(
        &bake(&["--sigma-s", "-1,1,1", "--sigma-a", "1,1,1"]),
        2,
        &["sigma_s[0]", "-1", "negative"],
    );
    fails_with(
        &bake(&["--sigma-s", "1,1,1", "--sigma-a", "1,1,1", "--g", "1"]),
        2,
        &["g[0]", "= 1", "(-1, 1)"],
    );
    fails_with(
        &bake(&["--sigma-s", "1,1,1", "--sigma-a", "1,1,1", "--eta", "0"]),
        2,
        &["--eta 0"],
    );
    fails_with(&bake(&["--sigma-s", "1,1,1"]), 2, &["--sigma-a"]);
    fails_with(
        &bake(&["--sigma-s", "1,x,1", "--sigma-a", "1,1,1"]),
        2,
        &["\"x\" is not a number"],
    );
    fails_with(
        &bake(&["--reflectance", "0.5,0.5,1.2", "--mfp", "1,1,1"]),
        2,
        &["reflectance[b] = 1.2"],
    );
    fails_with(
        &bake(&["--reflectance", "0.5,0.5,0.5", "--mfp", "1,-1,1"]),
        2,
        &["mfp[g] = -1"],
    );
    fails_with(
        &bake(&[
            "--sigma-s",
            "1,1,1",
            "--sigma-a",
            "1,1,1",
            "--name",
            "My Wax",
        ]),
        2,
        &["My Wax", "kebab-case"],
    );
    fails_with(&bake(&["--g", "0.5", "--eta", "1.3"]), 2, &["--g"]);
}
