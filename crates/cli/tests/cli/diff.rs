//! End-to-end tests of `bssrdf diff` (exit 0 within tolerance, 1 outside, 2 for bad files) and
//! its --json shape.

use bssrdf_zoo::format::{Compression, LibraryBuilder, Material, Provenance};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{bake, Grid, GridPreset, RidgeKind};
use std::process::Output;

use crate::common::{bssrdf, text};

fn code(o: &Output) -> Option<i32> {
    assert!(!text(&o.stderr).contains("panicked"), "{}", text(&o.stderr));
    o.status.code()
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&text(&o.stdout)).expect("one JSON object")
}

/// Index of the perturbed gwc-params value: ρ′ row 20, θ node 3, r node 10, component c.
const ROW: usize = 20;
const THETA: usize = 3;
const R: usize = 10;

/// `a.bssrdf`, and `b.bssrdf` with one value (c of one node) multiplied by 1 + 1e-4;
/// `ridge.bssrdf`, a.bssrdf's table marked as holding the profile less the ridge (format 1.6),
/// and `ridge-fluence.bssrdf` less the ridge with its fluence part.
fn pair() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let (table, _) = bake(
        1.33,
        Moments::Exact,
        &Grid::preset(GridPreset::Coarse),
        true,
    )
    .unwrap();
    let write = |name: &str, factor: f32, ridge: RidgeKind| {
        let mut data = table.clone().with_ridge(ridge).to_table_data();
        let (_, nt, nr) = table.axes().dims();
        let i = ((ROW * nt + THETA) * nr + R) * 3 + 2;
        data.gwc[i] *= factor;
        let mut b = LibraryBuilder::new();
        b.add_table(data).unwrap();
        b.add_material(Material {
            name: "wax".into(),
            source: String::new(),
            sigma_s: [1.0; 3],
            sigma_a: [0.1; 3],
            g: [0.0; 3],
            eta: 1.33,
            tables: [0; 3],
            albedo_range: None,
        })
        .unwrap();
        b.set_provenance(Provenance::new(format!("test {name}")));
        b.write_atomic(dir.path().join(name), Compression::None)
            .unwrap();
    };
    write("a.bssrdf", 1.0, RidgeKind::None);
    write("b.bssrdf", 1.0 + 1e-4, RidgeKind::None);
    write("ridge.bssrdf", 1.0, RidgeKind::Flux);
    write("ridge-fluence.bssrdf", 1.0, RidgeKind::FluxAndFluence);
    dir
}

#[test]
fn identical_files_exit_0() {
    let dir = pair();
    let o = bssrdf(dir.path(), &["diff", "a.bssrdf", "a.bssrdf"]);
    assert_eq!(code(&o), Some(0), "{}", text(&o.stdout));
    assert!(text(&o.stdout).contains("within tolerance"));
    let j = json(&bssrdf(
        dir.path(),
        &["diff", "a.bssrdf", "a.bssrdf", "--json"],
    ));
    assert_eq!(j["within_tolerance"], true);
    assert_eq!(j["differences"].as_array().unwrap().len(), 0);
    assert_eq!(
        j["tables"][0]["common_dims"],
        serde_json::json!([50, 7, 40])
    );
}

#[test]
fn one_changed_value_is_found_and_located() {
    let dir = pair();
    let d = dir.path();
    let o = bssrdf(d, &["diff", "a.bssrdf", "b.bssrdf", "--json"]);
    assert_eq!(code(&o), Some(1));
    let j = json(&o);
    assert_eq!(j["within_tolerance"], false);
    assert!(
        j["differences"].as_array().unwrap().is_empty(),
        "{}",
        j["differences"]
    );
    // Provenance differs, but is reported, not compared.
    assert_eq!(j["not_compared"][0]["item"], "provenance tool_version");
    let sections = j["tables"][0]["sections"].as_array().unwrap();
    let names: Vec<&str> = sections
        .iter()
        .map(|s| s["section"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "gwc-params E",
            "gwc-params E_beta",
            "gwc-params c",
            "radial-cdf",
            "theta-cdf"
        ]
    );
    for s in sections {
        for key in [
            "count",
            "max_abs",
            "mean_abs",
            "max_rel",
            "mean_rel",
            "outside_tolerance",
        ] {
            assert!(s[key].is_number(), "{key} in {s}");
        }
        let changed = s["section"] == "gwc-params c";
        assert_eq!(s["max_abs"].as_f64().unwrap() > 0.0, changed, "{s}");
    }
    let c = &sections[2];
    assert_eq!(c["outside_tolerance"], 1);
    let rel = c["max_rel"].as_f64().unwrap();
    assert!((rel - 1e-4).abs() < 1e-6, "{rel}");
    let at = &c["max_abs_at"];
    assert_eq!(at["index_a"], serde_json::json!([ROW, THETA, R]));
    assert_eq!(at["index_b"], serde_json::json!([ROW, THETA, R]));
    assert!(
        (at["theta_deg"].as_f64().unwrap() - 45.0).abs() < 1e-4,
        "{at}"
    );
    for key in ["rho", "r", "a", "b"] {
        assert!(at[key].is_number(), "{key} in {at}");
    }
    // Within a relative tolerance of 1e-3: exit 0; 1e-5: exit 1; an absolute one works too.
    assert_eq!(
        code(&bssrdf(
            d,
            &["diff", "a.bssrdf", "b.bssrdf", "--tolerance", "1e-3"]
        )),
        Some(0)
    );
    let strict = bssrdf(d, &["diff", "a.bssrdf", "b.bssrdf", "--tolerance", "1e-5"]);
    assert_eq!(code(&strict), Some(1));
    // Tolerances print in the messages' one number form
    assert!(
        text(&strict.stdout).contains("(tolerance 1e-5 relative, 0 absolute;"),
        "{}",
        text(&strict.stdout)
    );
    assert_eq!(
        code(&bssrdf(
            d,
            &["diff", "a.bssrdf", "b.bssrdf", "--abs-tolerance", "1"]
        )),
        Some(0)
    );
    let human = text(&bssrdf(d, &["diff", "a.bssrdf", "b.bssrdf"]).stdout);
    assert!(human.contains("max abs at [20,3,10]/[20,3,10]"), "{human}");
    assert!(human.contains("DIFFERENT"), "{human}");
}

/// Tables that differ only in their ridge field hold the same numbers for different profiles:
/// the field is a difference, shown by the kind's name (quoted, as every text is), and the
/// files differ; so do the two kinds of ridge.
#[test]
fn tables_that_differ_only_in_the_ridge_flag_differ() {
    let dir = pair();
    let d = dir.path();
    let o = bssrdf(d, &["diff", "a.bssrdf", "ridge.bssrdf", "--json"]);
    assert_eq!(code(&o), Some(1));
    let j = json(&o);
    assert_eq!(
        j["differences"],
        serde_json::json!([{"item": "table 0 / 0", "field": "ridge", "a": "none", "b": "flux"}])
    );
    for s in j["tables"][0]["sections"].as_array().unwrap() {
        assert_eq!(s["max_abs"], 0.0, "{s}");
    }
    let human = text(&bssrdf(d, &["diff", "a.bssrdf", "ridge.bssrdf"]).stdout);
    assert!(human.contains(r#"ridge: "none" vs "flux""#), "{human}");
    assert!(human.contains("DIFFERENT"), "{human}");
    let o = bssrdf(
        d,
        &["diff", "ridge.bssrdf", "ridge-fluence.bssrdf", "--json"],
    );
    assert_eq!(code(&o), Some(1));
    assert_eq!(
        json(&o)["differences"],
        serde_json::json!([
            {"item": "table 0 / 0", "field": "ridge", "a": "flux", "b": "flux+fluence"}
        ])
    );
}

#[test]
fn a_scene_bake_matches_the_full_bake_on_its_rows() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("s.toml"),
        "[[material]]\nname = \"skin1\"\nalbedo_range = [0.6, 0.7]\n",
    )
    .unwrap();
    let run = |args: &[&str]| assert_eq!(code(&bssrdf(d, args)), Some(0));
    run(&["bake", "--scene", "s.toml", "--grid", "coarse", "-q"]);
    run(&[
        "bake",
        "skin1",
        "--grid",
        "coarse",
        "-q",
        "-o",
        "full.bssrdf",
    ]);
    let o = bssrdf(d, &["diff", "s.bssrdf", "full.bssrdf", "--json"]);
    // Different axes and albedo ranges: exit 1; but every value on the shared nodes is equal.
    assert_eq!(code(&o), Some(1));
    let j = json(&o);
    let fields: Vec<&str> = j["differences"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["field"].as_str().unwrap())
        .collect();
    assert!(
        fields.contains(&"axis-rho") && fields.contains(&"albedo_range"),
        "{fields:?}"
    );
    let t = &j["tables"][0];
    assert!(t["common_dims"][0].as_u64().unwrap() >= 4);
    for s in t["sections"].as_array().unwrap() {
        assert_eq!(s["max_abs"], 0.0, "{s}");
    }
}

#[test]
fn negative_zero_tolerances_are_zero() {
    let dir = pair();
    let d = dir.path();
    let args = [
        "diff",
        "a.bssrdf",
        "b.bssrdf",
        "--tolerance",
        "-0",
        "--abs-tolerance",
        "-0.0",
    ];
    let o = bssrdf(d, &args);
    assert_eq!(code(&o), Some(1));
    assert!(
        text(&o.stdout).contains("(tolerance 0 relative, 0 absolute;"),
        "{}",
        text(&o.stdout)
    );
    let o = bssrdf(d, &[&args[..], &["--json"]].concat());
    let j = json(&o);
    for key in ["tolerance", "abs_tolerance"] {
        let t = j[key].as_f64().unwrap();
        assert!(t == 0.0 && t.is_sign_positive(), "{key}: {}", j[key]);
    }
}

#[test]
fn missing_or_corrupt_files_and_bad_tolerances_exit_2() {
    let dir = pair();
    let d = dir.path();
    let o = bssrdf(d, &["diff", "a.bssrdf", "absent.bssrdf"]);
    assert_eq!(code(&o), Some(2));
    assert!(text(&o.stderr).contains("absent.bssrdf"));
    std::fs::write(d.join("bad.bssrdf"), b"not a library file at all").unwrap();
    let o = bssrdf(d, &["diff", "bad.bssrdf", "a.bssrdf"]);
    assert_eq!(code(&o), Some(2));
    assert!(text(&o.stderr).contains("bad.bssrdf"));
    let mut bytes = std::fs::read(d.join("a.bssrdf")).unwrap();
    let n = bytes.len();
    bytes[n - 50] ^= 1;
    std::fs::write(d.join("flipped.bssrdf"), &bytes).unwrap();
    let o = bssrdf(d, &["diff", "a.bssrdf", "flipped.bssrdf"]);
    assert_eq!(code(&o), Some(2));
    assert!(text(&o.stderr).contains("flipped.bssrdf"));
    for bad in ["-1", "nan"] {
        let o = bssrdf(
            d,
            &[
                "diff",
                "a.bssrdf",
                "b.bssrdf",
                &format!("--tolerance={bad}"),
            ],
        );
        assert_eq!(code(&o), Some(2), "{bad}");
        assert!(
            text(&o.stderr).contains("--tolerance"),
            "{}",
            text(&o.stderr)
        );
    }
}
