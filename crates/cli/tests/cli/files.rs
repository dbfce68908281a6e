//! End-to-end tests of the file commands: bake → inspect → eval → sample → validate →
//! pack/unpack, the named materials, the walk, and their error paths (exit code 2 for bad
//! input, 1 for a failed check).

use std::process::Output;

use crate::common::{bssrdf, ok, text};

fn fails_with(o: &Output, code: i32, needle: &str) {
    assert_eq!(o.status.code(), Some(code), "stderr: {}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains(needle),
        "{:?} not in {}",
        needle,
        text(&o.stderr)
    );
    assert!(!text(&o.stderr).contains("panicked"));
}

/// A coarse-grid library of white grapefruit juice in a fresh folder.
fn baked() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    ok(&bssrdf(
        dir.path(),
        &[
            "bake",
            "white-grapefruit-juice",
            "--grid",
            "coarse",
            "--quiet",
        ],
    ));
    assert!(dir.path().join("white-grapefruit-juice.bssrdf").exists());
    dir
}

#[test]
fn bake_is_deterministic_on_any_thread_count() {
    let dir = baked();
    ok(&bssrdf(
        dir.path(),
        &[
            "bake",
            "white-grapefruit-juice",
            "--grid",
            "coarse",
            "-q",
            "--threads",
            "1",
            "-o",
            "one.bssrdf",
        ],
    ));
    let a = std::fs::read(dir.path().join("white-grapefruit-juice.bssrdf")).unwrap();
    let b = std::fs::read(dir.path().join("one.bssrdf")).unwrap();
    assert_eq!(a, b, "same bake, different bytes");
}

#[test]
fn inspect_reports_tables_materials_and_provenance() {
    let dir = baked();
    let json: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        dir.path(),
        &["inspect", "white-grapefruit-juice.bssrdf", "--json"],
    )))
    .unwrap();
    let minor = bssrdf_zoo::format::spec::VERSION_MINOR;
    assert_eq!(json["version"], serde_json::json!([1, minor]));
    // The writer sets `signed-floor` exactly when some node has a negative floor (E_β > E).
    let library = bssrdf_zoo::format::Library::read(
        dir.path().join("white-grapefruit-juice.bssrdf"),
        bssrdf_zoo::format::Verify::Full,
    )
    .unwrap();
    let table = library.table(0).unwrap();
    let signed_floor = table.gwc_params().chunks_exact(3).any(|n| n[1] > n[0]);
    let (bits, names) = if signed_floor {
        (2, serde_json::json!(["signed-floor"]))
    } else {
        (0, serde_json::json!([]))
    };
    assert_eq!(json["required_features"], bits);
    assert_eq!(json["required_feature_names"], names);
    assert_eq!(json["tables"][0]["dims"], serde_json::json!([50, 7, 40]));
    assert_eq!(json["tables"][0]["eta"], 1.33);
    assert_eq!(json["materials"][0]["name"], "white-grapefruit-juice");
    // The bake's own check, per region, with its bounds
    let check = &json["provenance"]["accuracy"]["tables"][0];
    assert_eq!(check["eta"], 1.33);
    assert!(check["bounds"]["mean_rel_error"].as_f64().unwrap() > 0.0);
    let regions = check["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 30, "6 albedo bands x 5 incidence bands");
    for r in regions {
        assert!(r["points"].as_u64().unwrap() > 0, "{r}");
        assert!(r["mean_rel_error"].as_f64().unwrap() <= 0.01, "{r}");
        assert_eq!(r["silent_zeros"], 0, "{r}");
    }
    // What the bake stores: three-anchor fits, minimax-refined where they are weak
    let settings = &json["provenance"]["settings"];
    assert_eq!(
        settings["anchors_cos_phi"],
        serde_json::json!([0.953, 0.405, -0.7527])
    );
    assert_eq!(
        settings["minimax_refinement"],
        serde_json::json!({"theta_min_deg": 45.0, "extra_phi_deg": [0.0, 38.0, 96.0, 180.0], "also_where_the_fit_clamped": true})
    );
    assert!(json["sections"]
        .as_array()
        .unwrap()
        .iter()
        .all(|s| s["crc_verified"] == true));
    let human = ok(&bssrdf(
        dir.path(),
        &["inspect", "white-grapefruit-juice.bssrdf"],
    ));
    assert!(human.contains("every CRC-32 verified"));
    assert!(human.contains(&format!("format 1.{minor},")), "{human}");
}

/// A library read from a stream (a pipe, a device) is read only as far as its header allows:
/// `/dev/zero` ends at its first bytes, which are not the magic, instead of filling memory.
#[cfg(target_os = "linux")]
#[test]
fn a_stream_is_read_only_as_far_as_its_header_allows() {
    let dir = tempfile::tempdir().unwrap();
    for args in [&["inspect", "/dev/zero"][..], &["validate", "/dev/zero"]] {
        fails_with(
            &bssrdf(dir.path(), args),
            2,
            "/dev/zero: not a bssrdf library file: its first bytes are (hex) 00 00 00 00 00 00 00 00 00 00 00 00, where a library file's are 89 42 53 53 52 44 46 0d 0a 1a 0a 00",
        );
    }
}

#[test]
fn inspect_names_the_required_features() {
    // The spec's example has negative floors (E_β > E), so it sets required feature bit 1.
    let dir = tempfile::tempdir().unwrap();
    let example = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/valid/spec-example.bssrdf");
    std::fs::copy(example, dir.path().join("example.bssrdf")).unwrap();
    // Valid with one albedo node and one angle, but the lookups need two per axis: they say
    // so, naming the file, the table and the axis
    for args in [
        &[
            "eval",
            "example.bssrdf",
            "--rho",
            "0.5",
            "--theta",
            "0",
            "--r",
            "1",
        ][..],
        &["validate", "example.bssrdf"],
        &["sample", "example.bssrdf", "--rho", "0.5", "-n", "1"],
        &["invert", "example.bssrdf", "--reflectance", "0.1"],
    ] {
        fails_with(
            &bssrdf(dir.path(), args),
            2,
            "example.bssrdf: table 0: axis rho has 1 node(s): lookups interpolate along every axis and need at least 2 (the file itself is valid)",
        );
    }
    let human = ok(&bssrdf(dir.path(), &["inspect", "example.bssrdf"]));
    assert!(
        human.contains("features required 0x2 (signed-floor) optional 0x0"),
        "{human}"
    );
    let json: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        dir.path(),
        &["inspect", "example.bssrdf", "--json"],
    )))
    .unwrap();
    assert_eq!(json["required_features"], 2);
    assert_eq!(
        json["required_feature_names"],
        serde_json::json!(["signed-floor"])
    );
    ok(&bssrdf(dir.path(), &["pack", "example.bssrdf"]));
    let human = ok(&bssrdf(dir.path(), &["inspect", "example.bssrdf"]));
    assert!(
        human.contains("features required 0x3 (zstd-sections, signed-floor)"),
        "{human}"
    );
}

/// A walk-angular table (format 1.5) shows its model, g and component, in the report and in
/// `--json`; a pbd-angular one its model, without a walk.
#[test]
fn inspect_shows_the_model_and_the_walk() {
    let dir = tempfile::tempdir().unwrap();
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/valid");
    for name in ["walk-table.bssrdf", "tiny.bssrdf"] {
        std::fs::copy(data.join(name), dir.path().join(name)).unwrap();
    }
    let human = ok(&bssrdf(dir.path(), &["inspect", "walk-table.bssrdf"]));
    assert!(
        human.contains("[0] walk-angular g 0.75 component total eta 1.3 moments exact"),
        "{human}"
    );
    assert!(
        human.contains("features required 0x34 (harmonics, merged-roots, walk-tables)"),
        "{human}"
    );
    let json: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        dir.path(),
        &["inspect", "walk-table.bssrdf", "--json"],
    )))
    .unwrap();
    let table = &json["tables"][0];
    assert_eq!(table["model"], "walk-angular");
    assert_eq!(table["walk_g"], 0.75);
    assert_eq!(table["walk_component"], "total");
    assert_eq!(table["lobes"], 2);
    let human = ok(&bssrdf(dir.path(), &["inspect", "tiny.bssrdf"]));
    assert!(
        human.contains("[0] pbd-angular eta 1.3 moments exact"),
        "{human}"
    );
    let json: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        dir.path(),
        &["inspect", "tiny.bssrdf", "--json"],
    )))
    .unwrap();
    let table = &json["tables"][0];
    assert_eq!(table["model"], "pbd-angular");
    assert!(table["walk_g"].is_null() && table["walk_component"].is_null());
    // The lookups are a two-lobe table's: the walk's table answers like any other
    let value = ok(&bssrdf(
        dir.path(),
        &[
            "eval",
            "walk-table.bssrdf",
            "--rho",
            "0.6",
            "--theta",
            "0.5",
            "--r",
            "0.05",
        ],
    ));
    assert!(value.trim().parse::<f64>().unwrap() > 0.0, "{value}");
}

/// A table whose nodes hold the profile less the ridge (format 1.6; `ridge` = 1, or 2 with its
/// fluence part) says which, in the report and in `--json` (`ridge` and `ridge_kind`), with the
/// file's required feature bit 6 by name; a table without it says no.
#[test]
fn inspect_shows_the_ridge_kind() {
    let dir = tempfile::tempdir().unwrap();
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/valid");
    for (name, shown, kind) in [
        ("ridge.bssrdf", "flux", "flux"),
        ("ridge-fluence.bssrdf", "flux+fluence", "flux+fluence"),
        ("tiny.bssrdf", "no", "none"),
    ] {
        std::fs::copy(data.join(name), dir.path().join(name)).unwrap();
        let human = ok(&bssrdf(dir.path(), &["inspect", name]));
        assert!(
            human.contains(&format!(
                "dims [2, 2, 4] lobes 1 theta-sampling yes ridge {shown}\n"
            )),
            "{human}"
        );
        let ridge = kind != "none";
        let features = if ridge {
            "0x40 (ridge)"
        } else {
            "0x0 optional"
        };
        assert!(
            human.contains(&format!("features required {features}")),
            "{human}"
        );
        let json: serde_json::Value =
            serde_json::from_str(&ok(&bssrdf(dir.path(), &["inspect", name, "--json"]))).unwrap();
        assert_eq!(json["tables"][0]["ridge"], ridge, "{name}");
        assert_eq!(json["tables"][0]["ridge_kind"], kind, "{name}");
    }
}

#[test]
fn eval_table_agrees_with_pbd_and_materials_use_millimetres() {
    let dir = baked();
    let value = |args: &[&str]| -> f64 { ok(&bssrdf(dir.path(), args)).trim().parse().unwrap() };
    let table = value(&[
        "eval",
        "white-grapefruit-juice.bssrdf",
        "--rho",
        "0.9",
        "--theta",
        "60",
        "--r",
        "1",
    ]);
    let pbd = value(&[
        "eval", "--model", "pbd", "--rho", "0.9", "--theta", "60", "--r", "1",
    ]);
    assert!((table / pbd - 1.0).abs() < 0.01, "{table} vs {pbd}");
    // With a material, r is in mm and S in mm⁻²: S_mm = σ′t² S(σ′t r).
    let json: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        dir.path(),
        &[
            "eval",
            "white-grapefruit-juice.bssrdf",
            "--material",
            "white-grapefruit-juice",
            "--channel",
            "b",
            "--theta",
            "30",
            "--r",
            "2",
            "--json",
        ],
    )))
    .unwrap();
    assert_eq!(json["r_unit"], "mm");
    let rho = json["rho"].as_f64().unwrap();
    // Blue channel of white grapefruit juice: σs = 0.75282, σa = 0.056781, g = 0.565.
    let st = 0.75282 * (1.0 - 0.565) + 0.056781;
    assert!((rho - 0.75282 * (1.0 - 0.565) / st).abs() < 1e-12);
    let reduced = value(&[
        "eval",
        "white-grapefruit-juice.bssrdf",
        "--rho",
        &rho.to_string(),
        "--theta",
        "30",
        "--r",
        &(2.0 * st).to_string(),
    ]);
    assert!((json["value"].as_f64().unwrap() / (st * st * reduced) - 1.0).abs() < 1e-6);
    // and bit for bit what a renderer's channel handle gives, over points of a CSV (σ′t² S, in
    // that order: (S σ′t) σ′t differs by an ulp at about a third of them)
    let points: Vec<[f64; 3]> = (0..60)
        .map(|k| {
            let k = f64::from(k);
            [
                (k * 1.47) % 89.0,
                0.05 + (k * 0.731) % 6.0,
                (k * 37.0) % 360.0 - 180.0,
            ]
        })
        .collect();
    let csv: String = std::iter::once("theta_deg,r_mm,phi_deg\n".to_string())
        .chain(
            points
                .iter()
                .map(|p| format!("{},{},{}\n", p[0], p[1], p[2])),
        )
        .collect();
    std::fs::write(dir.path().join("points.csv"), csv).unwrap();
    let rows = ok(&bssrdf(
        dir.path(),
        &[
            "eval",
            "white-grapefruit-juice.bssrdf",
            "--material",
            "white-grapefruit-juice",
            "--channel",
            "b",
            "--points",
            "points.csv",
            "--json",
        ],
    ));
    let file = dir.path().join("white-grapefruit-juice.bssrdf");
    let library = bssrdf_zoo::embed::Library::read(file).unwrap();
    let blue = library
        .channel("white-grapefruit-juice", bssrdf_zoo::embed::Rgb::Blue)
        .unwrap();
    let lines: Vec<&str> = rows.lines().collect();
    assert_eq!(lines.len(), points.len());
    for (line, p) in lines.iter().zip(&points) {
        let row: serde_json::Value = serde_json::from_str(line).unwrap();
        let phi = p[2].to_radians();
        let handle = blue.eval(p[0].to_radians(), p[1], phi).unwrap();
        let value = row["value"].as_f64().unwrap();
        assert_eq!(
            value.to_bits(),
            handle.to_bits(),
            "{p:?}: {value} against {handle}"
        );
    }
}

#[test]
fn sample_is_pinned_for_a_seed_and_writes_csv() {
    let dir = baked();
    let run = |seed: &str| {
        ok(&bssrdf(
            dir.path(),
            &[
                "sample",
                "white-grapefruit-juice.bssrdf",
                "--rho",
                "0.9",
                "--theta",
                "60",
                "-n",
                "50",
                "--seed",
                seed,
            ],
        ))
    };
    let a = run("3");
    assert_eq!(a, run("3"));
    assert_ne!(a, run("4"));
    let lines: Vec<&str> = a.lines().collect();
    assert_eq!(lines[0], "rho,theta_deg,r,phi_deg,pdf");
    assert_eq!(lines.len(), 51);
    for line in &lines[1..] {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!((v[0], v[1]), (0.9, 60.0));
        assert!(v[2] > 0.0 && v[3].abs() <= 180.0 && v[4] > 0.0);
    }
    let path = ok(&bssrdf(
        dir.path(),
        &[
            "sample",
            "white-grapefruit-juice.bssrdf",
            "--rho",
            "0.9",
            "--path-tracing",
            "-n",
            "5",
        ],
    ));
    assert!(path.starts_with("rho,theta_deg,r,phi_deg,phi_prime_deg,pdf\n"));
}

#[test]
fn validate_exits_1_when_a_bound_fails() {
    let dir = baked();
    let json: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        dir.path(),
        &[
            "validate",
            "white-grapefruit-juice.bssrdf",
            "--samples",
            "200",
            "--json",
            "--max-mean-error",
            "5",
        ],
    )))
    .unwrap();
    assert_eq!(json["pass"], true);
    assert_eq!(json["rows"].as_array().unwrap().len(), 9);
    let o = bssrdf(
        dir.path(),
        &[
            "validate",
            "white-grapefruit-juice.bssrdf",
            "--samples",
            "200",
            "--max-mean-error",
            "0.0001",
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("FAIL"));
}

#[test]
fn pack_and_unpack_are_lossless() {
    let dir = baked();
    let original = std::fs::read(dir.path().join("white-grapefruit-juice.bssrdf")).unwrap();
    ok(&bssrdf(
        dir.path(),
        &[
            "pack",
            "white-grapefruit-juice.bssrdf",
            "-o",
            "packed.bssrdf",
        ],
    ));
    let packed = std::fs::read(dir.path().join("packed.bssrdf")).unwrap();
    assert!(packed.len() < original.len());
    // A packed file evaluates exactly like the mappable one.
    let eval = |file: &str| {
        ok(&bssrdf(
            dir.path(),
            &[
                "eval", file, "--rho", "0.5", "--theta", "40", "--r", "0.7", "--phi", "20",
            ],
        ))
    };
    assert_eq!(eval("white-grapefruit-juice.bssrdf"), eval("packed.bssrdf"));
    ok(&bssrdf(dir.path(), &["unpack", "packed.bssrdf"]));
    assert_eq!(
        std::fs::read(dir.path().join("packed.bssrdf")).unwrap(),
        original
    );
}

#[test]
fn materials_lists_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&ok(&bssrdf(dir.path(), &["materials", "--json"]))).unwrap();
    assert_eq!(json.as_array().unwrap().len(), 47);
    assert!(ok(&bssrdf(dir.path(), &["materials"])).contains("white-grapefruit-juice"));
}

#[test]
fn walk_prints_the_reflectances_and_writes_the_profile() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(&bssrdf(
        dir.path(),
        &[
            "walk",
            "--albedo",
            "0.9",
            "--eta",
            "1",
            "--photons",
            "20000",
            "--json",
            "--profile",
            "p.csv",
            "--seed",
            "5",
        ],
    ));
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "total_reflectance",
        "single_reflectance",
        "multiple_reflectance",
        "total_reflectance_stderr",
        "single_reflectance_stderr",
        "multiple_reflectance_stderr",
    ] {
        assert!(json[key].as_f64().is_some(), "missing {key}");
    }
    let csv = std::fs::read_to_string(dir.path().join("p.csv")).unwrap();
    assert!(csv.starts_with("r_lo,r_hi,phi_lo_deg,phi_hi_deg,single,single_stderr,multiple,multiple_stderr,total,total_stderr"));
}

#[test]
fn error_paths_exit_2_and_name_the_problem() {
    let dir = baked();
    let d = dir.path();
    fails_with(
        &bssrdf(d, &["bake", "white-grapfruit-juice", "-q"]),
        2,
        "white-grapefruit-juice",
    );
    fails_with(&bssrdf(d, &["bake", "-q"]), 2, "--eta");
    fails_with(
        &bssrdf(
            d,
            &[
                "eval",
                "missing.bssrdf",
                "--rho",
                "0.5",
                "--theta",
                "0",
                "--r",
                "1",
            ],
        ),
        2,
        "missing.bssrdf",
    );
    std::fs::write(
        d.join("corrupt.bssrdf"),
        b"\x89BSSRDF\r\n\x1a\n\0 not really",
    )
    .unwrap();
    fails_with(
        &bssrdf(d, &["inspect", "corrupt.bssrdf"]),
        2,
        "corrupt.bssrdf",
    );
    let mut bytes = std::fs::read(d.join("white-grapefruit-juice.bssrdf")).unwrap();
    let n = bytes.len();
    bytes[n - 100] ^= 0x55;
    std::fs::write(d.join("flipped.bssrdf"), &bytes).unwrap();
    fails_with(
        &bssrdf(
            d,
            &[
                "eval",
                "flipped.bssrdf",
                "--rho",
                "0.5",
                "--theta",
                "0",
                "--r",
                "1",
            ],
        ),
        2,
        "flipped.bssrdf",
    );
    fails_with(
        &bssrdf(
            d,
            &[
                "eval",
                "white-grapefruit-juice.bssrdf",
                "--rho",
                "1.5",
                "--theta",
                "0",
                "--r",
                "1",
            ],
        ),
        2,
        "--rho 1.5",
    );
    fails_with(
        &bssrdf(
            d,
            &[
                "eval", "--model", "table", "--rho", "0.5", "--theta", "0", "--r", "1",
            ],
        ),
        2,
        "FILE",
    );
    fails_with(
        &bssrdf(
            d,
            &[
                "sample",
                "white-grapefruit-juice.bssrdf",
                "--rho",
                "0",
                "-n",
                "3",
            ],
        ),
        2,
        "nothing to sample",
    );
    fails_with(&bssrdf(d, &["walk", "--albedo", "1.5"]), 2, "1.5");
    fails_with(&bssrdf(d, &["walk", "--albedo", "0.5", "--g", "1"]), 2, "g");
    fails_with(
        &bssrdf(
            d,
            &[
                "eval", "--model", "pbd", "--eta", "0", "--rho", "0.5", "--theta", "0", "--r", "1",
            ],
        ),
        2,
        "--eta 0 is outside the valid range",
    );
    // A material file with NaN, and one with a negative σ.
    std::fs::write(
        d.join("bad.toml"),
        "id = \"bad-wax\"\nname = \"Bad wax\"\neta = 1.4\ncoefficients = \"unreduced\"\nsigma_s = [1.0, nan, 1.0]\nsigma_a = [0.1, 0.1, 0.1]\ng = [0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    fails_with(
        &bssrdf(d, &["bake", "bad-wax", "--materials", "bad.toml", "-q"]),
        2,
        "sigma_s",
    );
    std::fs::write(
        d.join("neg.toml"),
        "id = \"neg-wax\"\nname = \"Neg wax\"\neta = 1.4\ncoefficients = \"unreduced\"\nsigma_s = [1.0, 1.0, 1.0]\nsigma_a = [0.1, -0.1, 0.1]\ng = [0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    fails_with(
        &bssrdf(d, &["materials", "--materials", "neg.toml"]),
        2,
        "sigma_a",
    );
}

#[test]
fn eval_reaches_every_model_of_the_zoo() {
    let dir = tempfile::tempdir().unwrap();
    for model in ["pbd", "pbd-fast", "dipole", "dirpole", "burley"] {
        let v: f64 = ok(&bssrdf(
            dir.path(),
            &[
                "eval", "--model", model, "--rho", "0.9", "--theta", "60", "--r", "1", "--phi", "0",
            ],
        ))
        .trim()
        .parse()
        .unwrap();
        assert!(v.is_finite() && v > 0.0, "{model}: {v}");
    }
}

#[test]
fn zoo_prints_a_row_per_model_and_case_and_writes_plots() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(&bssrdf(
        dir.path(),
        &[
            "zoo",
            "--photons",
            "5000",
            "--cases",
            "0.9:60",
            "--models",
            "dipole,burley,pbd-fast",
            "--json",
            "--plot",
            "plots",
        ],
    ));
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(json["rows"].as_array().unwrap().len(), 3);
    assert!(dir.path().join("plots/pareto.svg").exists());
    fails_with(
        &bssrdf(dir.path(), &["zoo", "--models", "dipol", "--photons", "10"]),
        2,
        "dipole",
    );
    // A model listed twice is refused, not compared twice.
    fails_with(
        &bssrdf(
            dir.path(),
            &["zoo", "--models", "dipole,burley,dipole", "--photons", "10"],
        ),
        2,
        "--models lists dipole twice (at positions 1 and 3)",
    );
    fails_with(
        &bssrdf(dir.path(), &["zoo", "--cases", "0.9", "--photons", "10"]),
        2,
        "RHO:THETA",
    );
}
