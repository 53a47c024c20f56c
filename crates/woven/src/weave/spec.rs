//! The pattern value, as every door writes it: a weave's name, a 0/1 matrix, or
//! `{ wif = "FILE" }` ([`PatternSpec`]). Material files (`[weave] pattern`), woven surfaces'
//! `pattern` key (scenes, Python, the Mitsuba plugin) and serde all read it here
//! ([`PatternSpec::from_value`]), then build its [`Pattern`] ([`PatternSpec::pattern`]).

use super::{Pattern, MAX_THREADS};
use crate::error::{Error, Result};
use crate::keys::KeyValue;
use std::path::{Path, PathBuf};

/// How a weave pattern is named.
#[derive(Clone, Debug, PartialEq)]
pub enum PatternSpec {
    /// `"plain"`, `"twill-2/1"`, `"satin-5"`, `"sateen-5"`, …
    Name(String),
    /// An explicit 0/1 matrix, rows = weft picks.
    Matrix(Vec<Vec<u8>>),
    /// `{ wif = "file.wif" }`: a material file keeps it relative to its folder, a surface's key
    /// as its source resolved it ([`KeySource::path`](crate::keys::KeySource::path)).
    Wif(PathBuf),
}

/// The forms a pattern value takes, as an error states them.
pub const PATTERN_FORMS: &str = "a name (\"plain\", \"twill-2/1\", \"satin-5\", \
     \"sateen-5\"), a 0/1 matrix of rows like [[1, 0], [0, 1]], or { wif = \"FILE\" }";

impl PatternSpec {
    /// Reads a pattern value; errors name `name` (`weave.pattern` in material files, `pattern`
    /// for a surface), or the cell or key within it (`weave.pattern[2][0]`,
    /// `pattern.wiff`). A WIF file's path is kept as written: [`pattern`](Self::pattern)
    /// resolves it.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for any other shape, a matrix over [`MAX_THREADS`] a side
    /// (refused before it is copied), a cell other than 0 or 1, a table with a key other than
    /// `wif`.
    pub fn from_value(value: &KeyValue, name: &str) -> Result<PatternSpec> {
        match value {
            KeyValue::Text(n) => Ok(PatternSpec::Name(n.clone())),
            KeyValue::List(rows) => matrix(rows, name).map(PatternSpec::Matrix),
            KeyValue::Table(entries) => {
                if let Some((k, v)) = entries.iter().find(|(k, _)| k != "wif") {
                    return Err(Error::invalid(
                        format!("{name}.{}", crate::keys::shown_key(k)),
                        v,
                        "only `wif`, a WIF file's path, in a pattern table (an unknown field)",
                    ));
                }
                match entries.first() {
                    Some((_, KeyValue::Text(file))) => Ok(PatternSpec::Wif(PathBuf::from(file))),
                    Some((_, other)) => Err(Error::invalid(
                        format!("{name}.wif"),
                        other,
                        "a path to a WIF file",
                    )),
                    None => Err(Error::invalid(
                        format!("{name}.wif"),
                        "(missing)",
                        "a path to a WIF file",
                    )),
                }
            }
            other => Err(Error::invalid(name, other, PATTERN_FORMS)),
        }
    }

    /// The pattern it names; a WIF file's path is first passed to `resolve` (which joins a
    /// relative path to the folder of what named it). The file must be a regular file within
    /// [`MAX_WIF_BYTES`](super::MAX_WIF_BYTES).
    ///
    /// # Errors
    /// An unknown name or a bad matrix ([`Pattern::from_name`], [`Pattern::from_matrix`]); a
    /// WIF file that cannot be read or parsed ([`Pattern::from_wif_path`]).
    pub fn pattern(&self, resolve: impl Fn(&Path) -> PathBuf) -> Result<Pattern> {
        match self {
            PatternSpec::Name(n) => Pattern::from_name(n),
            PatternSpec::Matrix(m) => Pattern::from_matrix(m.clone()),
            PatternSpec::Wif(p) => Pattern::from_wif_path(resolve(p)),
        }
    }

    /// The value it was read from ([`from_value`](Self::from_value) reads it back).
    pub fn to_value(&self) -> KeyValue {
        match self {
            PatternSpec::Name(n) => KeyValue::Text(n.clone()),
            PatternSpec::Matrix(m) => KeyValue::List(
                m.iter()
                    .map(|row| {
                        KeyValue::List(row.iter().map(|&c| KeyValue::Integer(c.into())).collect())
                    })
                    .collect(),
            ),
            PatternSpec::Wif(p) => KeyValue::Table(vec![(
                "wif".into(),
                KeyValue::Text(p.display().to_string()),
            )]),
        }
    }
}

/// Rows of 0 and 1, checked for size before anything is copied.
fn matrix(rows: &[KeyValue], name: &str) -> Result<Vec<Vec<u8>>> {
    let width = |r: &KeyValue| match r {
        KeyValue::List(cells) => cells.len(),
        _ => 0,
    };
    let cols = rows.iter().map(width).max().unwrap_or(0);
    if rows.len() > MAX_THREADS || cols > MAX_THREADS {
        return Err(Error::invalid(
            name,
            format!("a matrix of {} rows and up to {cols} columns", rows.len()),
            format!("at most {MAX_THREADS} rows and columns (a larger draft is not a repeat)"),
        ));
    }
    let mut m = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        let KeyValue::List(cells) = row else {
            return Err(Error::invalid(format!("{name}[{i}]"), row, PATTERN_FORMS));
        };
        let mut r = Vec::with_capacity(cells.len());
        for (j, c) in cells.iter().enumerate() {
            match c {
                KeyValue::Integer(x @ (0 | 1)) => r.push(*x as u8),
                other => return Err(Error::invalid(format!("{name}[{i}][{j}]"), other, "0 or 1")),
            }
        }
        m.push(r);
    }
    Ok(m)
}

/// The pattern value read from any serde format, through [`KeyValue`] and
/// [`PatternSpec::from_value`] (its messages, under the name `pattern`).
#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for PatternSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let value = KeyValue::deserialize(d)?;
        PatternSpec::from_value(&value, "pattern").map_err(serde::de::Error::custom)
    }
}

#[cfg(all(test, feature = "serde"))]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<PatternSpec> {
        let t: toml::Table = toml::from_str(&format!("p = {text}")).unwrap();
        PatternSpec::from_value(&t["p"].clone().into(), "pattern")
    }

    #[test]
    fn each_form_reads_and_writes_back() {
        for text in ["\"twill-2/1\"", "[[1, 0], [0, 1]]", "{ wif = \"a.wif\" }"] {
            let spec = read(text).unwrap();
            assert_eq!(
                PatternSpec::from_value(&spec.to_value(), "p").unwrap(),
                spec
            );
            assert_eq!(spec.to_value().to_string(), text);
        }
        let spec: PatternSpec =
            toml::from_str::<std::collections::BTreeMap<String, PatternSpec>>("p = [[1, 1, 0]]")
                .unwrap()
                .remove("p")
                .unwrap();
        assert_eq!(spec, PatternSpec::Matrix(vec![vec![1, 1, 0]]));
    }

    #[test]
    fn bad_values_name_the_place_and_the_forms() {
        let message = |text: &str| read(text).unwrap_err().to_string();
        assert!(message("3").contains(PATTERN_FORMS));
        let m = message("[[1, 2]]");
        assert!(
            m.contains("`pattern[0][1]` = 2") && m.contains("0 or 1"),
            "{m}"
        );
        let m = message("{ wiff = \"a.wif\" }");
        assert!(
            m.contains("`pattern.wiff`") && m.contains("an unknown field"),
            "{m}"
        );
        let m = message("{ wif = 3 }");
        assert!(m.contains("`pattern.wif` = 3"), "{m}");
        let big = format!("[[{}]]", vec!["1"; MAX_THREADS + 1].join(", "));
        assert!(message(&big).contains("at most"));
        let m = read("\"satin5\"").unwrap().pattern(Path::to_path_buf);
        assert!(m.unwrap_err().to_string().contains("satin5"));
    }
}
