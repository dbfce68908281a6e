//! Reading one material file: field names checked first (so an unknown or missing field is a
//! typed error), then typed deserialisation, then validation of every value.

use super::{Channel, Coefficients, Material, MaterialError, Origin, Rgb, Source};
use crate::medium::Medium;
use serde::Deserialize;

/// Top-level fields of a material file, and which of them are required.
const FIELDS: [(&str, bool); 9] = [
    ("id", true),
    ("name", true),
    ("aliases", false),
    ("eta", true),
    ("coefficients", true),
    ("sigma_s", true),
    ("sigma_a", true),
    ("g", true),
    ("source", false),
];

/// Fields of the `[source]` table, and which of them are required.
const SOURCE_FIELDS: [(&str, bool); 4] = [
    ("coefficients", true),
    ("eta", false),
    ("pbrt_reduced_sigma_s", false),
    ("notes", false),
];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    id: String,
    name: String,
    #[serde(default)]
    aliases: Vec<String>,
    eta: f64,
    coefficients: Coefficients,
    sigma_s: Vec<f64>,
    sigma_a: Vec<f64>,
    g: Vec<f64>,
    source: Option<RawSource>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSource {
    coefficients: String,
    eta: Option<String>,
    pbrt_reduced_sigma_s: Option<Vec<f64>>,
    #[serde(default)]
    notes: Vec<String>,
}

/// Parses and validates one material file.
pub(super) fn material_from_toml(text: &str, origin: Origin) -> Result<Material, MaterialError> {
    let file = origin.to_string();
    let parse_error = |e: toml::de::Error| MaterialError::Parse {
        file: file.clone(),
        message: describe(text, &e),
    };
    // Check field names on the spanned, untyped table first: serde's own messages for these
    // are text, and the spans give an unknown field its line
    let table = toml::de::DeTable::parse(text).map_err(parse_error)?;
    let table = table.get_ref();
    check_fields(text, &file, "", table, &FIELDS)?;
    if let Some(toml::de::DeValue::Table(source)) = table.get("source").map(|v| v.get_ref()) {
        check_fields(text, &file, "source.", source, &SOURCE_FIELDS)?;
    }
    let raw: RawMaterial = toml::from_str(text).map_err(parse_error)?;

    check_id(&file, "id", &raw.id)?;
    if raw.name.trim().is_empty() {
        return Err(MaterialError::EmptyName { file });
    }
    for (i, alias) in raw.aliases.iter().enumerate() {
        check_id(&file, &format!("aliases[{i}]"), alias)?;
    }
    let channels = channels(
        &file,
        raw.coefficients,
        &raw.sigma_s,
        &raw.sigma_a,
        &raw.g,
        raw.eta,
    )?;
    let source = match raw.source {
        None => None,
        Some(s) => {
            let pbrt_reduced_sigma_s = match &s.pbrt_reduced_sigma_s {
                None => None,
                Some(values) => Some(non_negative_triple(
                    &file,
                    "source.pbrt_reduced_sigma_s",
                    values,
                )?),
            };
            Some(Source {
                coefficients: s.coefficients,
                eta: s.eta,
                pbrt_reduced_sigma_s,
                notes: s.notes,
            })
        }
    };
    Ok(Material {
        id: raw.id,
        name: raw.name,
        aliases: raw.aliases,
        eta: raw.eta,
        coefficients: raw.coefficients,
        channels,
        source,
        origin,
    })
}

/// Rejects keys outside `fields`, naming the line of the first, and reports the first
/// required one that is absent. `text` is the file's, which the keys' spans index.
fn check_fields(
    text: &str,
    file: &str,
    prefix: &str,
    table: &toml::de::DeTable<'_>,
    fields: &[(&str, bool)],
) -> Result<(), MaterialError> {
    if let Some(key) = table.keys().find(|key| {
        !fields
            .iter()
            .any(|(name, _)| *name == key.get_ref().as_ref())
    }) {
        return Err(MaterialError::UnknownField {
            file: file.to_string(),
            at: position(text, key.span().start),
            field: format!("{prefix}{}", key.get_ref()),
        });
    }
    if let Some((name, _)) = fields
        .iter()
        .find(|(name, required)| *required && !table.contains_key(*name))
    {
        return Err(MaterialError::MissingField {
            file: file.to_string(),
            field: format!("{prefix}{name}"),
        });
    }
    Ok(())
}

/// A TOML error as "line L, column C: message" (1-based), without the source excerpt.
fn describe(text: &str, error: &toml::de::Error) -> String {
    let message = error.message().trim_end();
    match error.span() {
        Some(span) => format!("{}: {message}", position(text, span.start)),
        None => message.to_string(),
    }
}

/// "line L, column C" (1-based) of byte `offset` of `text`.
fn position(text: &str, offset: usize) -> String {
    let mut start = offset.min(text.len());
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    format!("line {line}, column {column}")
}

/// Whether `id` is kebab-case: non-empty words of lowercase ASCII letters and digits joined by
/// single hyphens.
pub(super) fn is_kebab_case(id: &str) -> bool {
    !id.is_empty()
        && id.split('-').all(|word| {
            !word.is_empty()
                && word
                    .bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit())
        })
}

pub(super) fn check_id(file: &str, field: &str, id: &str) -> Result<(), MaterialError> {
    if is_kebab_case(id) {
        Ok(())
    } else {
        Err(MaterialError::BadId {
            file: file.to_string(),
            field: field.to_string(),
            value: id.to_string(),
        })
    }
}

/// "sigma_a[1] (green)": an array element, named as in the file and by its channel.
fn element(field: &str, channel: Rgb) -> String {
    format!("{field}[{}] ({})", channel.index(), channel.name())
}

/// Checks that a per-channel array has exactly three values.
fn triple(file: &str, field: &str, values: &[f64]) -> Result<[f64; 3], MaterialError> {
    <[f64; 3]>::try_from(values).map_err(|_| MaterialError::ChannelCount {
        file: file.to_string(),
        field: field.to_string(),
        count: values.len(),
    })
}

fn finite(file: &str, field: impl FnOnce() -> String, value: f64) -> Result<f64, MaterialError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(MaterialError::NotFinite {
            file: file.to_string(),
            field: field(),
            value,
        })
    }
}

/// Three finite, non-negative values (a coefficient in mm⁻¹ per channel).
fn non_negative_triple(file: &str, field: &str, values: &[f64]) -> Result<[f64; 3], MaterialError> {
    let values = triple(file, field, values)?;
    for channel in Rgb::ALL {
        let value = finite(file, || element(field, channel), values[channel.index()])?;
        if value < 0.0 {
            return Err(MaterialError::Negative {
                file: file.to_string(),
                field: element(field, channel),
                value,
            });
        }
    }
    Ok(values)
}

/// Validates η and the per-channel coefficients and builds the three channels.
pub(super) fn channels(
    file: &str,
    coefficients: Coefficients,
    sigma_s: &[f64],
    sigma_a: &[f64],
    g: &[f64],
    eta: f64,
) -> Result<[Channel; 3], MaterialError> {
    let eta = finite(file, || "eta".to_string(), eta)?;
    if crate::medium::validate_eta(eta).is_err() {
        return Err(MaterialError::EtaOutOfRange {
            file: file.to_string(),
            value: eta,
            min: crate::medium::ETA_MIN,
            max: crate::medium::ETA_MAX,
        });
    }
    let sigma_s = non_negative_triple(file, "sigma_s", sigma_s)?;
    let sigma_a = non_negative_triple(file, "sigma_a", sigma_a)?;
    let g = triple(file, "g", g)?;
    for channel in Rgb::ALL {
        let value = finite(file, || element("g", channel), g[channel.index()])?;
        if value <= -1.0 || value >= 1.0 {
            return Err(MaterialError::AsymmetryOutOfRange {
                file: file.to_string(),
                field: element("g", channel),
                value,
            });
        }
        if coefficients == Coefficients::Reduced && value != 0.0 {
            return Err(MaterialError::ReducedWithAsymmetry {
                file: file.to_string(),
                field: element("g", channel),
                value,
            });
        }
    }
    let channel = |c: Rgb| {
        let i = c.index();
        // −0 as 0 (equal, and listed as given by `materials`)
        Medium::new(sigma_s[i] + 0.0, sigma_a[i] + 0.0, g[i] + 0.0, eta)
            .map(|medium| Channel { medium })
            .map_err(|source| MaterialError::Medium {
                file: file.to_string(),
                channel: c.name(),
                source,
            })
    };
    Ok([
        channel(Rgb::Red)?,
        channel(Rgb::Green)?,
        channel(Rgb::Blue)?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kebab_case_accepts_words_and_digits_only() {
        for good in ["apple", "chicken1", "white-grapefruit-juice", "a-1-b"] {
            assert!(is_kebab_case(good), "{good}");
        }
        for bad in [
            "",
            "Apple",
            "white_grapefruit",
            "white--juice",
            "-apple",
            "apple-",
            "white grapefruit",
            "crème",
        ] {
            assert!(!is_kebab_case(bad), "{bad}");
        }
    }

    #[test]
    fn parse_errors_give_line_and_column() {
        let err = material_from_toml("id = \"a\"\nname = [", Origin::Inline).unwrap_err();
        match err {
            MaterialError::Parse { message, .. } => {
                assert!(message.starts_with("line 2, column "), "{message}")
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn an_unknown_field_is_named_with_its_line() {
        let text = "id = \"my-x\"\nname = \"X\"\ncolour = \"red\"\n";
        let err = material_from_toml(text, Origin::Inline).unwrap_err();
        assert!(
            err.to_string()
                .ends_with("line 3, column 1: unknown field `colour`"),
            "{err}"
        );
        let whole = "id = \"my-x\"\nname = \"X\"\neta = 1.3\ncoefficients = \"reduced\"\n\
                     sigma_s = [1, 1, 1]\nsigma_a = [0, 0, 0]\ng = [0, 0, 0]\n";
        let text = format!("{whole}[source]\ncoefficients = \"x\"\n  note = \"y\"\n");
        let err = material_from_toml(&text, Origin::Inline).unwrap_err();
        assert!(
            err.to_string()
                .ends_with("line 10, column 3: unknown field `source.note`"),
            "{err}"
        );
    }
}
