//! Manifest parsing, validation and the row plan, without baking (a synthetic ρ_eff curve).

use super::*;

fn library() -> Library {
    Library::builtin()
}

/// ρ_eff = 0.95·ρ′² on 21 nodes: A = (1 − F_r(0; η))·0.95·ρ′².
fn curve(eta: f64) -> Result<ReflectanceCurve, ArtistError> {
    let rho: Vec<f64> = (0..21).map(|i| f64::from(i) / 20.0).collect();
    let rho_eff = rho.iter().map(|r| 0.95 * r * r).collect();
    Ok(ReflectanceCurve::synthetic(eta, rho, rho_eff))
}

fn parse(text: &str) -> Result<Scene, SceneError> {
    Scene::from_toml_str(text, &library(), &mut curve)
}

fn error(text: &str) -> String {
    parse(text).unwrap_err().to_string()
}

const EXAMPLE: &str = r#"
integrator = "path"
[[material]]
name = "white-grapefruit-juice"
[[material]]
name = "skin1"
albedo_range = [[0.85, 0.97], [0.80, 0.90], [0.60, 0.70]]
"#;

#[test]
fn the_example_scene_parses() {
    let scene = parse(EXAMPLE).unwrap();
    assert_eq!(scene.integrator(), Integrator::Path);
    let [juice, skin] = scene.materials() else {
        panic!("two materials")
    };
    assert_eq!(juice.origin(), Origin::Library);
    assert!(!juice.declared());
    let rho = juice.material().rho_prime();
    for (range, rho) in juice.ranges().iter().zip(rho) {
        assert_eq!(*range, RhoInterval::point(rho).unwrap());
    }
    assert!(skin.declared());
    assert_eq!(skin.ranges()[2], RhoInterval::new(0.6, 0.7).unwrap());
    assert!(scene.warnings().is_empty(), "{:?}", scene.warnings());
    let record = skin.record([0, 1, 2]);
    assert_eq!(record.name, "skin1");
    let range = record.albedo_range.unwrap();
    assert_eq!((range.min, range.max), ([0.85, 0.8, 0.6], [0.97, 0.9, 0.7]));
}

#[test]
fn integrator_defaults_to_path_and_particle_drops_theta_sampling() {
    let scene = parse("[[material]]\nname = \"skin1\"\n").unwrap();
    assert!(scene.integrator().needs_theta_sampling());
    let scene = parse("integrator = \"particle\"\n[[material]]\nname = \"skin1\"\n").unwrap();
    assert!(!scene.integrator().needs_theta_sampling());
    assert!(error("integrator = \"photon\"\n[[material]]\nname = \"skin1\"\n").contains("photon"));
}

#[test]
fn albedo_range_shapes() {
    let one = |range: &str| {
        let text = format!("[[material]]\nname = \"skin1\"\nalbedo_range = {range}\n");
        parse(&text).map(|s| *s.materials()[0].ranges())
    };
    let i = |lo, hi| RhoInterval::new(lo, hi).unwrap();
    assert_eq!(one("[0.5, 0.9]").unwrap(), [i(0.5, 0.9); 3]);
    assert_eq!(one("0.9").unwrap(), [i(0.9, 0.9); 3]);
    assert_eq!(
        one("[1, 0.5, [0.2, 0.3]]").unwrap(),
        [i(1.0, 1.0), i(0.5, 0.5), i(0.2, 0.3)]
    );
    for bad in [
        "[0.5]",
        "[[0.5, 0.6]]",
        "[0.1, 0.2, 0.3, 0.4]",
        "\"high\"",
        "[[0.1, 0.2, 0.3], 0.5, 0.5]",
    ] {
        let err = one(bad).unwrap_err().to_string();
        assert!(
            err.contains("albedo_range") && err.contains("skin1"),
            "{bad}: {err}"
        );
    }
}

#[test]
fn albedo_ranges_are_validated_and_name_the_value() {
    let text = |range: &str| format!("[[material]]\nname = \"skin1\"\nalbedo_range = {range}\n");
    let err = error(&text("[[0.85, 0.97], [0.80, 1.2], [0.6, 0.7]]"));
    assert!(
        err.contains("albedo_range[g]") && err.contains("1.2") && err.contains("[0, 1]"),
        "{err}"
    );
    let err = error(&text("[[0.85, 0.97], [0.80, 0.9], [0.7, 0.6]]"));
    assert!(
        err.contains("albedo_range[b]") && err.contains("reversed"),
        "{err}"
    );
    let err = error(&text("[nan, 0.9]"));
    assert!(err.contains("NaN"), "{err}");
    let err = error(&text("[-0.1, 0.9]"));
    assert!(err.contains("-0.1"), "{err}");
}

#[test]
fn unknown_fields_and_missing_materials_are_errors() {
    let err = error("[[material]]\nname = \"skin1\"\nalbedo = 0.5\n");
    assert!(err.contains("albedo"), "{err}");
    let err = error("integrater = \"path\"\n[[material]]\nname = \"skin1\"\n");
    assert!(err.contains("integrater"), "{err}");
    let err = error("[[material]]\nname = \"skinn1\"\n");
    assert!(
        err.contains("skinn1") && err.contains("skin1"),
        "suggestion missing: {err}"
    );
    assert!(matches!(
        parse("integrator = \"path\"\n"),
        Err(SceneError::NoMaterials)
    ));
    let err = error("[[material]]\nname = \"skin1\"\n[[material]]\nname = \"Skin1\"\n");
    assert!(err.contains("twice"), "{err}");
    assert!(error("[[material]\nname = 1").starts_with("scene manifest:"));
}

#[test]
fn inline_coefficients_and_eta() {
    let scene = parse(
        "[[material]]\nname = \"my-wax\"\nsigma_s = [1.0, 1.1, 1.2]\nsigma_a = [0.01, 0.02, 0.05]\ng = 0.3\neta = 1.45\n",
    )
    .unwrap();
    let m = &scene.materials()[0];
    assert_eq!(m.origin(), Origin::Coefficients);
    assert_eq!(m.material().eta(), 1.45);
    assert_eq!(m.material().g(), [0.3; 3]);
    let plain =
        parse("[[material]]\nname = \"my-wax\"\nsigma_s = [1, 1, 1]\nsigma_a = [0, 0, 1]\n")
            .unwrap();
    assert_eq!(plain.materials()[0].material().eta(), DEFAULT_ETA);
    // A library material with another η.
    let scene = parse("[[material]]\nname = \"skin1\"\neta = 1.4\n").unwrap();
    assert_eq!(scene.materials()[0].material().eta(), 1.4);
    assert!(scene.materials()[0]
        .record([0; 3])
        .source
        .contains("eta 1.4"));
}

#[test]
fn inline_errors_name_the_field_and_value() {
    let m = |body: &str| error(&format!("[[material]]\nname = \"wax\"\n{body}\n"));
    assert!(m("sigma_s = [1, 1]\nsigma_a = [1, 1, 1]").contains("sigma_s has 2 values"));
    assert!(m("sigma_s = [-1, 1, 1]\nsigma_a = [1, 1, 1]").contains("-1"));
    assert!(m("sigma_s = [1, 1, 1]\nsigma_a = [1, 1, 1]\ng = 1").contains("(-1, 1)"));
    assert!(m("sigma_s = [1, 1, 1]\nsigma_a = [1, 1, 1]\neta = 0").contains("eta = 0"));
    assert!(m("sigma_s = [1, 1, 1]").contains("sigma_s needs sigma_a"));
    assert!(m("mfp = [1, 1, 1]").contains("mfp needs reflectance"));
    assert!(m("sigma_s = [1, 1, 1]\nsigma_a = [1, 1, 1]\nmfp = [1, 1, 1]").contains("not both"));
    assert!(m("sigma_s = [1, \"a\", 1]\nsigma_a = [1, 1, 1]").contains("sigma_s[1]"));
    assert!(m("reflectance = [0.5, 0.5, 1.5]\nmfp = [1, 1, 1]").contains("reflectance[b] = 1.5"));
    assert!(m("reflectance = [0.5, 0.5, 0.5]\nmfp = [1, 0, 1]").contains("mfp[g] = 0"));
    let named = error("[[material]]\nname = \"skin1\"\ng = 0.5\n");
    assert!(named.contains("inline materials only"), "{named}");
    // A library material's η from the manifest is the manifest's, not an inline material's
    let eta = error("[[material]]\nname = \"skin1\"\neta = 3\n");
    assert_eq!(
        eta,
        "material \"skin1\": eta = 3 is outside [0.75, 2.5] (the manifest's eta for this \
         library material)"
    );
    let err = error("[[material]]\nname = \"My Wax\"\nsigma_s = [1, 1, 1]\nsigma_a = [1, 1, 1]\n");
    assert!(err.contains("kebab-case"), "{err}");
}

#[test]
fn artist_parameters_invert_through_the_curve() {
    // The reflectance includes the entry Fresnel transmittance at normal incidence:
    // T₀·0.95·0.5² (the curve's value at its node, ρ_eff stored as f32) gives ρ′ = 0.5, to the
    // curve's resolution (its rows blend with f32 weights, which round to 1 and 0 within 1e-8
    // of a node).
    let t0 = crate::fresnel::entry_transmittance(0.0, DEFAULT_ETA);
    let at_node = curve(DEFAULT_ETA).unwrap().at(0.5).unwrap();
    assert!((at_node - t0 * 0.95 * 0.25).abs() < 1e-8);
    let scene = parse(&format!(
        "[[material]]\nname = \"jade\"\nreflectance = [{at_node}, 0.5, 0.99]\nmfp = [2, 1, 0.5]\n"
    ))
    .unwrap();
    let m = &scene.materials()[0];
    assert_eq!(m.origin(), Origin::Diffuse);
    let rho = m.material().rho_prime();
    assert!((rho[0] - 0.5).abs() < 1e-8, "{rho:?}");
    assert!((m.material().sigma_s()[0] + m.material().sigma_a()[0] - 0.5).abs() < 1e-12);
    // Without the entry Fresnel, 0.2375 would have given 0.5; with it, a larger ρ′.
    let plain = parse(
        "[[material]]\nname = \"jade\"\nreflectance = [0.2375, 0.5, 0.5]\nmfp = [2, 1, 0.5]\n",
    )
    .unwrap();
    let rho_plain = plain.materials()[0].material().rho_prime()[0];
    assert!((rho_plain - 0.5 / t0.sqrt()).abs() < 1e-6, "{rho_plain}");
    // 0.99 is above the largest diffuse reflectance, 0.95·T₀: clamped, with a warning.
    assert_eq!(rho[2], 1.0);
    let warnings = scene.warnings();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("channel b: reflectance 0.99 is above") && w.contains("clamped")),
        "{warnings:?}"
    );
}

#[test]
fn own_albedo_outside_the_declared_range_is_a_warning() {
    let scene = parse("[[material]]\nname = \"skin1\"\nalbedo_range = [0.1, 0.2]\n").unwrap();
    let w = scene.warnings();
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].contains("outside the declared range"));
}

#[test]
fn the_plan_shares_rows_per_eta_and_splits_disjoint_runs() {
    let axis = Nodes::new((0..=100).map(|i| f64::from(i) / 100.0).collect::<Vec<_>>()).unwrap();
    let scene = parse(
        "[[material]]\nname = \"a\"\nsigma_s = [1, 1, 1]\nsigma_a = [1, 1, 1]\nalbedo_range = [[0.1, 0.12], [0.11, 0.2], [0.8, 0.8]]\n\
         [[material]]\nname = \"b\"\nsigma_s = [1, 1, 1]\nsigma_a = [1, 1, 1]\neta = 1.5\n",
    )
    .unwrap();
    let plan = scene.plan(&axis).unwrap();
    // η = 1.33: rows 9..23 (r and g merged; 0.2 is node 20, its segment 20) and 79..83 (b); η = 1.5: around ρ′ = 0.5.
    let rows: Vec<_> = plan
        .tables
        .iter()
        .map(|t| (t.eta, t.rows.clone()))
        .collect();
    assert_eq!(rows, vec![(1.33, 9..23), (1.33, 79..83), (1.5, 49..53)]);
    assert_eq!(plan.channel_tables, vec![[0, 0, 1], [2, 2, 2]]);
    assert_eq!(plan.tables[0].serves.len(), 2);
    assert_eq!(plan.tables[2].serves.len(), 1);
    // A range the axis does not cover.
    let short = Nodes::new(vec![0.0, 0.5]).unwrap();
    let err = scene.plan(&short).unwrap_err().to_string();
    assert!(err.contains("outside the table's albedo axis"), "{err}");
}
