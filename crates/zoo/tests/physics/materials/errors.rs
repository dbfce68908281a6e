//! Every rejection of a material file or of inline coefficients: one small TOML text per
//! failure, each checked for its own error variant, field and value, and for a message that
//! names the file.

use bssrdf_zoo::materials::{Material, MaterialError, Origin};
use bssrdf_zoo::Error;
use std::path::PathBuf;

const FILE: &str = "user/test-medium.toml";

const GOOD: &str = r#"id = "test-medium"
name = "Test Medium"
eta = 1.33
coefficients = "unreduced"
sigma_s = [1.0, 2.0, 3.0]
sigma_a = [0.1, 0.2, 0.3]
g = [0.5, 0.5, 0.5]
"#;

/// `GOOD` with one line replaced.
fn with(old: &str, new: &str) -> String {
    assert!(GOOD.contains(old), "{old:?} is not in the template");
    GOOD.replacen(old, new, 1)
}

/// Parses `text` as the file `FILE`, expecting a failure whose message names the file.
fn reject(text: &str) -> MaterialError {
    let err = Material::from_toml_str(text, Origin::File(PathBuf::from(FILE)))
        .expect_err("the material should be rejected");
    assert!(err.to_string().starts_with(FILE), "{err}");
    err
}

#[test]
fn the_template_is_valid() {
    let m = Material::from_toml_str(GOOD, Origin::Inline).unwrap();
    assert_eq!(m.id(), "test-medium");
    assert!(m.source().is_none());
}

#[test]
fn nan_is_rejected_naming_field_and_channel() {
    let err = reject(&with(
        "sigma_a = [0.1, 0.2, 0.3]",
        "sigma_a = [0.1, nan, 0.3]",
    ));
    match &err {
        MaterialError::NotFinite { field, value, .. } => {
            assert_eq!(field, "sigma_a[1] (green)");
            assert!(value.is_nan());
        }
        other => panic!("expected NotFinite, got {other:?}"),
    }
    assert_eq!(
        err.to_string(),
        "user/test-medium.toml: sigma_a[1] (green) = NaN is not a finite number"
    );
}

#[test]
fn infinite_eta_and_g_are_not_finite() {
    let err = reject(&with("eta = 1.33", "eta = inf"));
    assert!(matches!(&err, MaterialError::NotFinite { field, value, .. }
        if field == "eta" && *value == f64::INFINITY));
    let err = reject(&with("g = [0.5, 0.5, 0.5]", "g = [0.5, 0.5, -nan]"));
    assert!(matches!(&err, MaterialError::NotFinite { field, .. } if field == "g[2] (blue)"));
}

#[test]
fn negative_sigma_is_rejected() {
    let err = reject(&with(
        "sigma_s = [1.0, 2.0, 3.0]",
        "sigma_s = [-1.0, 2.0, 3.0]",
    ));
    assert!(
        matches!(&err, MaterialError::Negative { field, value, .. }
            if field == "sigma_s[0] (red)" && *value == -1.0),
        "{err:?}"
    );
    assert!(err
        .to_string()
        .contains("sigma_s[0] (red) = -1 is negative"));
}

#[test]
fn g_of_one_is_rejected() {
    for g in ["1.0", "-1.0", "1.5"] {
        let err = reject(&with(
            "g = [0.5, 0.5, 0.5]",
            &format!("g = [0.5, {g}, 0.5]"),
        ));
        assert!(
            matches!(&err, MaterialError::AsymmetryOutOfRange { field, value, .. }
                if field == "g[1] (green)" && *value == g.parse::<f64>().unwrap()),
            "{err:?}"
        );
    }
}

#[test]
fn eta_outside_the_domain_is_rejected() {
    for eta in ["0.0", "-1.33", "0.7", "2.6", "1e6"] {
        let err = reject(&with("eta = 1.33", &format!("eta = {eta}")));
        assert!(err.to_string().contains("[0.75, 2.5]"), "{err}");
        assert!(
            matches!(&err, MaterialError::EtaOutOfRange { value, .. }
                if *value == eta.parse::<f64>().unwrap()),
            "{err:?}"
        );
    }
}

#[test]
fn unknown_fields_are_rejected_at_top_level_and_in_source() {
    let err = reject(&format!("{GOOD}colour = \"red\"\n"));
    assert!(
        matches!(&err, MaterialError::UnknownField { field, .. } if field == "colour"),
        "{err:?}"
    );
    let err = reject(&format!(
        "{GOOD}[source]\ncoefficients = \"my notebook\"\nurl = \"x\"\n"
    ));
    assert!(
        matches!(&err, MaterialError::UnknownField { field, .. } if field == "source.url"),
        "{err:?}"
    );
}

#[test]
fn missing_fields_are_named() {
    let err = reject(&with("eta = 1.33\n", ""));
    assert!(
        matches!(&err, MaterialError::MissingField { field, .. } if field == "eta"),
        "{err:?}"
    );
    let err = reject(&format!("{GOOD}[source]\nnotes = [\"measured\"]\n"));
    assert!(
        matches!(&err, MaterialError::MissingField { field, .. }
            if field == "source.coefficients"),
        "{err:?}"
    );
}

#[test]
fn two_channels_are_rejected() {
    let err = reject(&with("sigma_s = [1.0, 2.0, 3.0]", "sigma_s = [1.0, 2.0]"));
    assert!(
        matches!(&err, MaterialError::ChannelCount { field, count: 2, .. } if field == "sigma_s"),
        "{err:?}"
    );
    let err = reject(&with("g = [0.5, 0.5, 0.5]", "g = [0.5, 0.5, 0.5, 0.5]"));
    assert!(matches!(&err, MaterialError::ChannelCount { field, count: 4, .. } if field == "g"));
    let err = reject(&format!(
        "{GOOD}[source]\ncoefficients = \"x\"\npbrt_reduced_sigma_s = [1.0]\n"
    ));
    assert!(
        matches!(&err, MaterialError::ChannelCount { field, count: 1, .. }
        if field == "source.pbrt_reduced_sigma_s")
    );
}

#[test]
fn bad_ids_and_aliases_are_rejected() {
    for id in [
        "Test-Medium",
        "test_medium",
        "test medium",
        "",
        "test--medium",
    ] {
        let err = reject(&with("id = \"test-medium\"", &format!("id = {id:?}")));
        assert!(
            matches!(&err, MaterialError::BadId { field, value, .. } if field == "id" && value == id),
            "{err:?}"
        );
    }
    let err = reject(&format!("aliases = [\"tm\", \"TM\"]\n{GOOD}"));
    assert!(
        matches!(&err, MaterialError::BadId { field, value, .. }
            if field == "aliases[1]" && value == "TM"),
        "{err:?}"
    );
}

#[test]
fn an_empty_name_is_rejected() {
    let err = reject(&with("name = \"Test Medium\"", "name = \"  \""));
    assert!(matches!(err, MaterialError::EmptyName { .. }), "{err:?}");
}

#[test]
fn reduced_coefficients_require_g_zero() {
    let err = reject(&with(
        "coefficients = \"unreduced\"",
        "coefficients = \"reduced\"",
    ));
    assert!(
        matches!(&err, MaterialError::ReducedWithAsymmetry { field, value, .. }
            if field == "g[0] (red)" && *value == 0.5),
        "{err:?}"
    );
}

#[test]
fn a_vacuum_channel_is_rejected() {
    let text = with("sigma_s = [1.0, 2.0, 3.0]", "sigma_s = [1.0, 0.0, 3.0]");
    let text = text.replace("sigma_a = [0.1, 0.2, 0.3]", "sigma_a = [0.1, 0.0, 0.3]");
    let err = reject(&text);
    assert!(
        matches!(
            &err,
            MaterialError::Medium {
                channel: "green",
                source: Error::Vacuum,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn wrong_types_and_bad_toml_are_parse_errors() {
    for text in [
        with("eta = 1.33", "eta = \"1.33\""),
        with("coefficients = \"unreduced\"", "coefficients = \"partly\""),
        with("sigma_a = [0.1, 0.2, 0.3]", "sigma_a = [0.1, \"x\", 0.3]"),
        format!("{GOOD}source = \"a paper\"\n"),
        "id = \"test-medium\"\nname = ".to_string(),
    ] {
        let err = reject(&text);
        assert!(
            matches!(&err, MaterialError::Parse { message, .. } if message.starts_with("line ")),
            "{err:?}"
        );
    }
}

#[test]
fn integers_are_accepted_where_numbers_are_expected() {
    let text =
        with("eta = 1.33", "eta = 1").replace("sigma_s = [1.0, 2.0, 3.0]", "sigma_s = [1, 2, 3]");
    let m = Material::from_toml_str(&text, Origin::Inline).unwrap();
    assert_eq!((m.eta(), m.sigma_s()), (1.0, [1.0, 2.0, 3.0]));
}

#[test]
fn inline_coefficients_are_validated_like_files() {
    let ok = |id: &str, s: f64, g: f64, eta: f64| {
        Material::from_coefficients(id, [s, 1.0, 1.0], [0.1; 3], [g; 3], eta)
    };
    assert!(ok("mine", 1.0, 0.0, 1.3).is_ok());
    let err = ok("mine", f64::NAN, 0.0, 1.3).unwrap_err();
    assert!(matches!(&err, MaterialError::NotFinite { field, .. } if field == "sigma_s[0] (red)"));
    assert!(err.to_string().starts_with("inline material: "), "{err}");
    assert!(matches!(
        ok("mine", -1.0, 0.0, 1.3),
        Err(MaterialError::Negative { .. })
    ));
    assert!(matches!(
        ok("mine", 1.0, 1.0, 1.3),
        Err(MaterialError::AsymmetryOutOfRange { .. })
    ));
    assert!(matches!(
        ok("mine", 1.0, 0.0, 0.0),
        Err(MaterialError::EtaOutOfRange { .. })
    ));
    assert!(matches!(
        ok("Mine", 1.0, 0.0, 1.3),
        Err(MaterialError::BadId { .. })
    ));
}
