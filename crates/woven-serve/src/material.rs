//! Materials as the page sends them: JSON objects shaped like the material file
//! (`{"fiber": {…}, "yarn": {…}, "weave": {…}}`), read by the woven library's own parser and
//! validation, so that every range and every message is the library's.

use crate::error::{ApiError, ApiResult};
use serde::Deserialize;
use serde_json::Value;
use woven::material::Material;
use woven::weave::{Pattern, PatternSpec};

/// Where errors say the material came from.
const ORIGIN: &str = "<explorer>";

/// Reads a material from its JSON form: the same keys, tables and values as a material file
/// (`woven::material`), which the library then parses and validates.
///
/// # Errors
/// [`ApiError::Invalid`] naming the key for out-of-range values (the library's message);
/// [`ApiError::Malformed`] (422) for what cannot be a material file: unknown keys, wrong types.
pub fn from_json(value: &Value) -> ApiResult<Material> {
    if !value.is_object() {
        return Err(ApiError::invalid(
            "material",
            short(value),
            "an object with a `fiber` table (and optionally `yarn`, `weave`)",
        ));
    }
    // A `{ wif = "file" }` pattern would have the library read a file on the server: the page
    // uploads drafts through `/api/wif` and sends their matrix instead.
    let pattern = value.pointer("/weave/pattern");
    if pattern.is_some_and(|p| matches!(PatternSpec::deserialize(p), Ok(PatternSpec::Wif(_)))) {
        return Err(ApiError::invalid(
            "weave.pattern",
            short(&value["weave"]["pattern"]),
            "a pattern name or a 0/1 matrix (upload a WIF draft to /api/wif for its matrix)",
        ));
    }
    let toml_value = to_toml(value, "material")?;
    let text = toml::to_string(&toml_value)
        .map_err(|e| ApiError::unprocessable(format!("material: {e}")))?;
    Ok(Material::from_toml_str(&text, ORIGIN)?)
}

/// The material's file form as JSON: what [`from_json`] reads back (for presets).
pub fn to_json(material: &Material) -> Value {
    let text = material.to_self_contained_toml_string();
    let value: toml::Value = toml::from_str(&text).expect("the library writes valid TOML");
    serde_json::to_value(value).expect("TOML values are JSON values")
}

/// A JSON value as TOML: objects become tables, `null` is refused (TOML has none), integers
/// stay integers (the library reads them where numbers are expected).
fn to_toml(value: &Value, path: &str) -> ApiResult<toml::Value> {
    Ok(match value {
        Value::Null => {
            return Err(ApiError::invalid(
                path,
                "null",
                "a value (leave the key out for its default)",
            ))
        }
        Value::Bool(b) => toml::Value::Boolean(*b),
        Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => toml::Value::Integer(i),
            (None, Some(x)) => toml::Value::Float(x),
            _ => return Err(ApiError::invalid(path, n, "a number")),
        },
        Value::String(s) => toml::Value::String(s.clone()),
        Value::Array(items) => toml::Value::Array(
            items
                .iter()
                .enumerate()
                .map(|(i, v)| to_toml(v, &format!("{path}[{i}]")))
                .collect::<ApiResult<_>>()?,
        ),
        Value::Object(map) => {
            let mut table = toml::map::Map::new();
            for (k, v) in map {
                let sub = if path == "material" {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                table.insert(k.clone(), to_toml(v, &sub)?);
            }
            toml::Value::Table(table)
        }
    })
}

/// A pattern as the page draws it: its 0/1 matrix (rows = weft picks, 1 where the weft floats
/// on top) and its weft fraction `γ`.
#[derive(Debug, serde::Serialize)]
pub struct PatternView {
    /// The matrix.
    pub matrix: Vec<Vec<u8>>,
    /// `γ`.
    pub weft_fraction: f64,
    /// The pattern's name, when it is a named weave.
    pub name: Option<String>,
}

impl PatternView {
    /// The view of `pattern`.
    pub fn of(pattern: &Pattern) -> Self {
        PatternView {
            matrix: pattern.to_matrix(),
            weft_fraction: pattern.weft_fraction(),
            name: pattern.name(),
        }
    }
}

/// A short rendering of a JSON value for error messages.
pub fn short(value: &Value) -> String {
    let text = value.to_string();
    if text.chars().count() > 60 {
        format!("{}…", text.chars().take(60).collect::<String>())
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_survive_the_json_round_trip() {
        for name in Material::preset_names() {
            let m = Material::preset(name).unwrap();
            let back = from_json(&to_json(&m)).unwrap();
            assert_eq!(back.fiber, m.fiber, "{name}");
            assert_eq!(back.yarn, m.yarn, "{name}");
            assert_eq!(back.weft_fraction(), m.weft_fraction(), "{name}");
        }
    }

    #[test]
    fn out_of_range_values_name_the_key_and_the_range() {
        let v = serde_json::json!({"fiber": {"eta": 1.6, "roughness": 7.0}});
        match from_json(&v).unwrap_err() {
            ApiError::Invalid {
                field,
                value,
                expected,
            } => {
                assert_eq!(field, "fiber.roughness");
                assert_eq!(value, "7");
                assert!(expected.contains("[0.005, 2]"), "{expected}");
            }
            other => panic!("{other:?}"),
        }
        let v = serde_json::json!({"fiber": {"eta": 1.6, "roughness": 0.1, "colour": 1}});
        assert!(matches!(
            from_json(&v).unwrap_err(),
            ApiError::Malformed { .. }
        ));
        // No file on the server is ever read: a WIF path is refused before the library sees it.
        let v = serde_json::json!({"fiber": {"eta": 1.6, "roughness": 0.1},
            "yarn": {"lateral_length": 2.0, "slope_mean": 0.3},
            "weave": {"pattern": {"wif": "/etc/passwd"}}});
        assert!(
            matches!(from_json(&v).unwrap_err(), ApiError::Invalid { field, .. } if field == "weave.pattern")
        );
        let v = serde_json::json!({"fiber": {"eta": null, "roughness": 0.1}});
        assert!(
            matches!(from_json(&v).unwrap_err(), ApiError::Invalid { field, .. } if field == "fiber.eta")
        );
    }
}
