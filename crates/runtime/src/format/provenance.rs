//! Provenance of a library: which tool baked it, with which settings and quadrature, how long
//! it took and how accurate it measured. Stored as one JSON object in canonical form (keys
//! sorted by bytes, no whitespace, serde_json number formatting), so the same provenance always
//! gives the same bytes. Only people and tools read it; nothing in it is evaluated.
//!
//! JSON libraries keep the last of duplicate keys silently and serde_json writes NaN as null,
//! so this module parses with its own visitor that rejects duplicate keys and null values.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Number, Value};

use super::error::{FormatError, FormatResult};
use super::spec::{MAX_JSON_DEPTH, MAX_PROVENANCE_BYTES};

/// Key of the tool version (string, required).
pub const KEY_TOOL_VERSION: &str = "tool_version";
/// Key of the bake time in seconds (number ≥ 0, optional).
pub const KEY_BAKE_SECONDS: &str = "bake_seconds";
/// Key of the bake settings (object, optional).
pub const KEY_SETTINGS: &str = "settings";
/// Key of the quadrature description (object, optional).
pub const KEY_QUADRATURE: &str = "quadrature";
/// Key of the accuracy measured at bake (object, optional).
pub const KEY_ACCURACY: &str = "accuracy";

/// A JSON object describing how a library was made. Always holds a `tool_version` string;
/// never holds null (serde_json turns NaN into null, so a null is taken as a NaN that slipped
/// through) or a non-object under the `settings`, `quadrature` and `accuracy` keys.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    fields: BTreeMap<String, Value>,
}

impl Provenance {
    /// Provenance naming the tool that made the file, e.g. `"bssrdf-zoo 0.1.0"`.
    pub fn new(tool_version: impl Into<String>) -> Provenance {
        let mut fields = BTreeMap::new();
        fields.insert(
            KEY_TOOL_VERSION.to_owned(),
            Value::String(tool_version.into()),
        );
        Provenance { fields }
    }

    /// Adds the bake time in seconds, given by the caller (the writer never reads a clock).
    pub fn with_bake_seconds(self, seconds: f64) -> FormatResult<Provenance> {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(provenance_error(format!(
                "bake_seconds = {seconds} must be finite and >= 0"
            )));
        }
        self.with(KEY_BAKE_SECONDS, json_number(KEY_BAKE_SECONDS, seconds)?)
    }

    /// Adds the bake settings (an object).
    pub fn with_settings(self, settings: Value) -> FormatResult<Provenance> {
        self.with(KEY_SETTINGS, settings)
    }

    /// Adds the quadrature description (an object).
    pub fn with_quadrature(self, quadrature: Value) -> FormatResult<Provenance> {
        self.with(KEY_QUADRATURE, quadrature)
    }

    /// Adds the accuracy measured at bake (an object).
    pub fn with_accuracy(self, accuracy: Value) -> FormatResult<Provenance> {
        self.with(KEY_ACCURACY, accuracy)
    }

    /// Adds or replaces any key. The value must hold no null, and the known keys their types.
    pub fn with(mut self, key: &str, value: Value) -> FormatResult<Provenance> {
        check_key(key, &value)?;
        check_no_null(&value, key, 1)?;
        self.fields.insert(key.to_owned(), value);
        Ok(self)
    }

    /// Name and version of the tool that baked the library.
    pub fn tool_version(&self) -> &str {
        self.fields
            .get(KEY_TOOL_VERSION)
            .and_then(Value::as_str)
            .unwrap_or_default()
    }

    /// Bake time in seconds, if recorded.
    pub fn bake_seconds(&self) -> Option<f64> {
        self.fields.get(KEY_BAKE_SECONDS).and_then(Value::as_f64)
    }

    /// The value under `key`, if any.
    pub fn get(&self, key: &str) -> Option<&Value> {
        self.fields.get(key)
    }

    /// Every key and value, keys in byte order.
    pub fn fields(&self) -> impl Iterator<Item = (&str, &Value)> {
        self.fields.iter().map(|(k, v)| (k.as_str(), v))
    }

    /// The canonical JSON bytes stored in a file.
    pub fn to_canonical_json(&self) -> Vec<u8> {
        let mut out = Vec::new();
        write_object(self.fields.iter(), &mut out);
        out
    }

    /// Parses provenance JSON, rejecting duplicate keys, nulls, deep nesting and wrong types.
    pub fn from_json(bytes: &[u8]) -> FormatResult<Provenance> {
        if bytes.len() as u64 > MAX_PROVENANCE_BYTES {
            return Err(provenance_error(format!(
                "{} bytes, more than the cap of {MAX_PROVENANCE_BYTES}",
                bytes.len()
            )));
        }
        let duplicate = RefCell::new(None);
        let seed = StrictSeed {
            depth: 0,
            duplicate: &duplicate,
        };
        let mut de = serde_json::Deserializer::from_slice(bytes);
        let parsed = seed.deserialize(&mut de).and_then(|v| de.end().map(|()| v));
        if let Some(key) = duplicate.into_inner() {
            return Err(FormatError::ProvenanceDuplicateKey { key });
        }
        let value = parsed.map_err(|e| provenance_error(e.to_string()))?;
        let Value::Object(map) = value else {
            return Err(provenance_error("the top level is not an object".into()));
        };
        let mut fields = BTreeMap::new();
        for (key, value) in map {
            check_key(&key, &value)?;
            fields.insert(key, value);
        }
        if !fields.get(KEY_TOOL_VERSION).is_some_and(Value::is_string) {
            return Err(provenance_error(
                "tool_version is missing or not a string".into(),
            ));
        }
        Ok(Provenance { fields })
    }
}

fn provenance_error(message: String) -> FormatError {
    FormatError::ProvenanceJson { message }
}

/// A JSON number from a finite f64 (serde_json would turn NaN into null).
pub fn json_number(name: &str, value: f64) -> FormatResult<Value> {
    Number::from_f64(value)
        .map(Value::Number)
        .ok_or_else(|| provenance_error(format!("{name} = {value} is not a finite number")))
}

fn check_key(key: &str, value: &Value) -> FormatResult<()> {
    let ok = match key {
        KEY_TOOL_VERSION => value.is_string(),
        KEY_BAKE_SECONDS => value.as_f64().is_some_and(|s| s >= 0.0),
        KEY_SETTINGS | KEY_QUADRATURE | KEY_ACCURACY => value.is_object(),
        _ => true,
    };
    if ok {
        Ok(())
    } else {
        Err(provenance_error(format!(
            "{key} = {value} has the wrong type or range"
        )))
    }
}

/// Refuses a null anywhere in `value`, and an array or object nested deeper than
/// [`MAX_JSON_DEPTH`] levels: `value` lies at `depth` (the top object's fields at 1), and an
/// array or object at depth d is level d + 1.
fn check_no_null(value: &Value, path: &str, depth: usize) -> FormatResult<()> {
    if matches!(value, Value::Array(_) | Value::Object(_)) && depth >= MAX_JSON_DEPTH {
        return Err(provenance_error(format!(
            "{path} nests deeper than {MAX_JSON_DEPTH} levels"
        )));
    }
    match value {
        Value::Null => Err(provenance_error(format!(
            "{path} is null (a NaN turned into null?); leave the key out instead"
        ))),
        Value::Array(items) => items
            .iter()
            .enumerate()
            .try_for_each(|(i, v)| check_no_null(v, &format!("{path}[{i}]"), depth + 1)),
        Value::Object(map) => map
            .iter()
            .try_for_each(|(k, v)| check_no_null(v, &format!("{path}.{k}"), depth + 1)),
        _ => Ok(()),
    }
}

fn write_value(value: &Value, out: &mut Vec<u8>) {
    match value {
        Value::Object(map) => write_object(map.iter(), out),
        Value::Array(items) => {
            out.push(b'[');
            for (i, item) in items.iter().enumerate() {
                if i > 0 {
                    out.push(b',');
                }
                write_value(item, out);
            }
            out.push(b']');
        }
        // Scalars: serde_json's own compact formatting (shortest round-trip numbers).
        scalar => out.extend_from_slice(scalar.to_string().as_bytes()),
    }
}

fn write_object<'a>(entries: impl Iterator<Item = (&'a String, &'a Value)>, out: &mut Vec<u8>) {
    let mut entries: Vec<_> = entries.collect();
    entries.sort_by(|a, b| a.0.as_bytes().cmp(b.0.as_bytes()));
    out.push(b'{');
    for (i, (key, value)) in entries.into_iter().enumerate() {
        if i > 0 {
            out.push(b',');
        }
        out.extend_from_slice(Value::String(key.clone()).to_string().as_bytes());
        out.push(b':');
        write_value(value, out);
    }
    out.push(b'}');
}

/// Deserializes a JSON value, failing on duplicate keys (recorded in `duplicate`), on null and
/// on nesting deeper than [`MAX_JSON_DEPTH`] levels of arrays and objects (the top object is
/// level 1, at `depth` 0; an array or object at depth d is level d + 1, empty or not).
#[derive(Clone, Copy)]
struct StrictSeed<'a> {
    depth: usize,
    duplicate: &'a RefCell<Option<String>>,
}

impl<'de> DeserializeSeed<'de> for StrictSeed<'_> {
    type Value = Value;

    fn deserialize<D: de::Deserializer<'de>>(self, deserializer: D) -> Result<Value, D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl StrictSeed<'_> {
    /// Refuses an array or object at this depth if it would be level 33 or deeper.
    fn check_level<E: de::Error>(&self) -> Result<(), E> {
        if self.depth >= MAX_JSON_DEPTH {
            return Err(E::custom(format!(
                "nests deeper than {MAX_JSON_DEPTH} levels"
            )));
        }
        Ok(())
    }
}

impl<'de> Visitor<'de> for StrictSeed<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value other than null")
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Value, E> {
        Ok(Value::Number(v.into()))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Value, E> {
        Ok(Value::Number(v.into()))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Value, E> {
        Number::from_f64(v)
            .map(Value::Number)
            .ok_or_else(|| E::custom(format!("number {v} is not finite")))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_owned()))
    }

    fn visit_string<E: de::Error>(self, v: String) -> Result<Value, E> {
        Ok(Value::String(v))
    }

    fn visit_unit<E: de::Error>(self) -> Result<Value, E> {
        Err(E::custom(
            "null is not allowed (a NaN turned into null?); leave the key out instead",
        ))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        self.check_level()?;
        let inner = StrictSeed {
            depth: self.depth + 1,
            ..self
        };
        let mut items = Vec::new();
        while let Some(item) = seq.next_element_seed(inner)? {
            items.push(item);
        }
        Ok(Value::Array(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut access: A) -> Result<Value, A::Error> {
        self.check_level()?;
        let inner = StrictSeed {
            depth: self.depth + 1,
            ..self
        };
        let mut map = Map::new();
        while let Some(key) = access.next_key::<String>()? {
            if map.contains_key(&key) {
                let message = format!("duplicate key {key:?}");
                *self.duplicate.borrow_mut() = Some(key);
                return Err(de::Error::custom(message));
            }
            let value = access.next_value_seed(inner)?;
            map.insert(key, value);
        }
        Ok(Value::Object(map))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_json_sorts_keys_and_has_no_whitespace() {
        let p = Provenance::new("t 1")
            .with_bake_seconds(2.5)
            .unwrap()
            .with_settings(serde_json::json!({"z": 1, "a": [1.5, "x"]}))
            .unwrap();
        let text = String::from_utf8(p.to_canonical_json()).unwrap();
        assert_eq!(
            text,
            r#"{"bake_seconds":2.5,"settings":{"a":[1.5,"x"],"z":1},"tool_version":"t 1"}"#
        );
        assert_eq!(Provenance::from_json(text.as_bytes()).unwrap(), p);
    }

    #[test]
    fn numbers_read_back_keep_their_shortest_form() {
        // Shortest round-trip forms that a best-effort float parser reads 1 ulp off
        // (0.012062905218408027 came back as ...028 before float_roundtrip).
        let text = r#"{"accuracy":{"e":[0.012062905218408027,0.012094787878159763,5e-324,1.7976931348623157e+308]},"tool_version":"t"}"#;
        let p = Provenance::from_json(text.as_bytes()).unwrap();
        assert_eq!(String::from_utf8(p.to_canonical_json()).unwrap(), text);
    }

    /// §11: arrays and objects nest at most 32 levels, the top object the first; an empty one
    /// at level 33 counts as one (it passed, where one holding a value did not).
    #[test]
    fn nesting_stops_at_32_levels_empty_or_not() {
        let nested = |levels: usize, inner: &str| {
            let arrays = levels - 1;
            format!(
                r#"{{"tool_version":"t","x":{}{inner}{}}}"#,
                "[".repeat(arrays),
                "]".repeat(arrays)
            )
        };
        for inner in ["", "1"] {
            let ok = nested(32, inner);
            assert!(Provenance::from_json(ok.as_bytes()).is_ok(), "{ok}");
            let deep = nested(33, inner);
            let err = Provenance::from_json(deep.as_bytes()).unwrap_err();
            assert_eq!(err.code(), "provenance-json", "{deep}");
            assert!(err.to_string().contains("deeper than 32 levels"), "{err}");
        }
        // The writer's check agrees: a field's value at level 2, so 31 arrays reach level 32
        let base = Provenance::from_json(br#"{"tool_version":"t"}"#).unwrap();
        let arrays = |n: usize| -> Value {
            serde_json::from_str(&format!("{}{}", "[".repeat(n), "]".repeat(n))).unwrap()
        };
        assert!(base.clone().with("x", arrays(31)).is_ok());
        assert!(base.with("x", arrays(32)).is_err());
    }

    #[test]
    fn duplicate_keys_are_rejected_at_any_depth() {
        for text in [
            r#"{"tool_version":"a","tool_version":"b"}"#,
            r#"{"tool_version":"a","settings":{"k":1,"k":2}}"#,
        ] {
            let err = Provenance::from_json(text.as_bytes()).unwrap_err();
            assert_eq!(err.code(), "provenance-duplicate-key", "{text}");
        }
    }

    #[test]
    fn null_nan_and_wrong_types_are_rejected() {
        assert!(Provenance::new("t").with_bake_seconds(f64::NAN).is_err());
        assert!(Provenance::new("t").with("x", Value::Null).is_err());
        assert!(Provenance::new("t")
            .with_accuracy(serde_json::json!([1]))
            .is_err());
        for text in [
            r#"{"tool_version":null}"#,
            r#"{"tool_version":"a","x":[1,null]}"#,
            r#"{"bake_seconds":1}"#,
            r#"["tool_version"]"#,
            r#"{"tool_version":"a"} x"#,
            r#"{"tool_version":"a","bake_seconds":-1}"#,
        ] {
            let err = Provenance::from_json(text.as_bytes()).unwrap_err();
            assert_eq!(err.code(), "provenance-json", "{text}");
        }
    }

    #[test]
    fn deep_nesting_is_rejected_without_overflow() {
        let deep = format!(
            r#"{{"tool_version":"a","x":{}1{}}}"#,
            "[".repeat(100),
            "]".repeat(100)
        );
        let err = Provenance::from_json(deep.as_bytes()).unwrap_err();
        assert_eq!(err.code(), "provenance-json");
    }
}
