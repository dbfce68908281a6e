//! Errors of the material library: one variant per failure. Each names the file (or
//! "built-in materials/…", or "inline material") and, where there is one, the field and the bad
//! value, so that a message alone is enough to fix the file.

use crate::error::Number;
use std::path::PathBuf;
use thiserror::Error;

/// Every error the material library returns.
#[derive(Debug, Error)]
pub enum MaterialError {
    /// A file or directory could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A material file that is not UTF-8 text (a TOML file is), perhaps a library file.
    #[error("{}: not a material file: material files are TOML text, and this is not UTF-8{}", path.display(), if *library { "; it is a library file, whose materials `bssrdf inspect` lists and commands given the file as FILE find by --material" } else { "" })]
    NotText { path: PathBuf, library: bool },
    /// A directory given to the loader holds no `*.toml` file.
    #[error("{}: no material files (*.toml) in this directory", path.display())]
    EmptyDirectory { path: PathBuf },
    /// The text is not TOML, or a field has the wrong type.
    #[error("{file}: {message}")]
    Parse { file: String, message: String },
    /// A field the schema does not know (`deny_unknown_fields`).
    #[error("{file}: {at}: unknown field `{field}`")]
    UnknownField {
        file: String,
        /// "line L, column C" of the field's key.
        at: String,
        field: String,
    },
    /// A required field is absent.
    #[error("{file}: missing field `{field}`")]
    MissingField { file: String, field: String },
    /// A per-channel array does not have exactly three values (red, green, blue).
    #[error("{file}: {field} has {count} values; it needs 3 (red, green, blue)")]
    ChannelCount {
        file: String,
        field: String,
        count: usize,
    },
    /// A number is NaN or infinite.
    #[error("{file}: {field} = {} is not a finite number", Number(*value))]
    NotFinite {
        file: String,
        field: String,
        value: f64,
    },
    /// A coefficient that must be non-negative is negative.
    #[error("{file}: {field} = {} is negative; it must be >= 0", Number(*value))]
    Negative {
        file: String,
        field: String,
        value: f64,
    },
    /// The Henyey–Greenstein g is outside the open interval (−1, 1).
    #[error("{file}: {field} = {} is outside (-1, 1)", Number(*value))]
    AsymmetryOutOfRange {
        file: String,
        field: String,
        value: f64,
    },
    /// `coefficients = "reduced"` states σ′s with g = 0, but a g is not 0.
    #[error(
        "{file}: {field} = {}, but coefficients = \"reduced\" gives sigma_s' with g = 0; \
         set g to 0 or give unreduced coefficients",
        Number(*value)
    )]
    ReducedWithAsymmetry {
        file: String,
        field: String,
        value: f64,
    },
    /// The relative index of refraction is outside the models' domain.
    #[error(
        "{file}: eta = {} is outside [{}, {}]",
        Number(*value),
        Number(*min),
        Number(*max)
    )]
    EtaOutOfRange {
        file: String,
        value: f64,
        min: f64,
        max: f64,
    },
    /// The display name is empty or only white space.
    #[error("{file}: name is empty")]
    EmptyName { file: String },
    /// An id or alias is not kebab-case.
    #[error(
        "{file}: {field} = {value:?} is not a kebab-case id (lowercase ASCII letters and digits, \
         words joined by single hyphens, e.g. \"white-grapefruit-juice\")"
    )]
    BadId {
        file: String,
        field: String,
        value: String,
    },
    /// A channel's coefficients were rejected by [`crate::medium::Medium::new`]
    /// (in practice: σs(1 − g) + σa = 0, a vacuum).
    #[error("{file}: {channel} channel: {source}")]
    Medium {
        file: String,
        channel: &'static str,
        #[source]
        source: crate::Error,
    },
    /// An id or alias is already taken. Built-in materials are never overridden.
    #[error(
        "material id `{id}` of {second} is already defined by {first}; materials are never \
         overridden: give yours another id"
    )]
    DuplicateId {
        id: String,
        first: String,
        second: String,
    },
    /// No material has this id or alias.
    #[error("no material named {query:?}{}", did_you_mean(suggestions))]
    NotFound {
        query: String,
        suggestions: Vec<String>,
    },
}

fn did_you_mean(suggestions: &[String]) -> String {
    match suggestions {
        [] => String::new(),
        [one] => format!("; did you mean `{one}`?"),
        [init @ .., last] => {
            let init: Vec<String> = init.iter().map(|s| format!("`{s}`")).collect();
            format!("; did you mean {} or `{last}`?", init.join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn not_found_message_lists_suggestions() {
        let err = |s: &[&str]| MaterialError::NotFound {
            query: "milc".into(),
            suggestions: s.iter().map(|s| s.to_string()).collect(),
        };
        assert_eq!(err(&[]).to_string(), "no material named \"milc\"");
        assert_eq!(
            err(&["skim-milk"]).to_string(),
            "no material named \"milc\"; did you mean `skim-milk`?"
        );
        assert_eq!(
            err(&["a", "b", "c"]).to_string(),
            "no material named \"milc\"; did you mean `a`, `b` or `c`?"
        );
    }
}
