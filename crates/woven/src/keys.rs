//! Values as front ends hand them to the library: a scene file's table, a Python dict, Mitsuba
//! 3's `Properties`. Each front end turns what it holds into [`KeyValue`]s behind a
//! [`KeySource`], and the library reads its own keys from that (one reader: for a woven
//! surface, [`SurfaceSpec::from_keys`](crate::surface::SurfaceSpec::from_keys); for a weave
//! pattern, [`PatternSpec::from_value`](crate::weave::PatternSpec::from_value)), so that every
//! door states the same defaults, ranges and messages.
//!
//! ```
//! use woven::keys::{KeySource, KeyValue, Keys};
//! let keys = Keys::new()
//!     .with("gap", KeyValue::Float(0.2))
//!     .with("pattern", KeyValue::Text("twill-2/1".into()));
//! assert_eq!(keys.get("gap").and_then(|v| v.number()), Some(0.2));
//! assert_eq!(keys.names(), ["gap", "pattern"]);
//! assert_eq!(KeyValue::List(vec![KeyValue::Integer(1), KeyValue::Float(0.5)]).to_string(), "[1, 0.5]");
//! ```

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// One value of a key, in the shapes scene files (TOML), Python and Mitsuba share.
#[derive(Clone, Debug, PartialEq)]
pub enum KeyValue {
    /// `true` or `false`.
    Bool(bool),
    /// A whole number (TOML's integers, Python's `int`).
    Integer(i64),
    /// A number with a fraction (or any float, NaN included: readers refuse what they must).
    Float(f64),
    /// Words: a name, a path, or numbers in a string (Mitsuba's XML has no lists).
    Text(String),
    /// A list of values.
    List(Vec<KeyValue>),
    /// Named values (a TOML inline table, a Python dict), in the order given.
    Table(Vec<(String, KeyValue)>),
}

impl KeyValue {
    /// The value as a number: an integer or a float.
    pub fn number(&self) -> Option<f64> {
        match *self {
            KeyValue::Integer(i) => Some(i as f64),
            KeyValue::Float(x) => Some(x),
            _ => None,
        }
    }

    /// What kind of value it is, in words (for errors that refuse its type).
    pub fn kind(&self) -> &'static str {
        match self {
            KeyValue::Bool(_) => "a boolean",
            KeyValue::Integer(_) => "an integer",
            KeyValue::Float(_) => "a number",
            KeyValue::Text(_) => "a string",
            KeyValue::List(_) => "a list",
            KeyValue::Table(_) => "a table",
        }
    }
}

/// The longest a value is shown in an error, in characters: a huge list or string given by
/// mistake (or by hostile input) is cut, with a note of how much was left out.
const MAX_SHOWN_CHARS: usize = 160;

/// Shown as TOML writes it (`0.5`, `"satin-5"`, `[1, 0]`, `{ wif = "a.wif" }`), control
/// characters escaped and long values cut, so that an error can quote it safely.
impl fmt::Display for KeyValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut out = String::new();
        write_value(self, &mut out);
        let total = out.chars().count();
        if total > MAX_SHOWN_CHARS {
            let head: String = out.chars().take(MAX_SHOWN_CHARS - 40).collect();
            write!(
                f,
                "{head}… ({} more characters)",
                total - (MAX_SHOWN_CHARS - 40)
            )
        } else {
            f.write_str(&out)
        }
    }
}

/// Appends `v` to `out` as TOML writes it, stopping once `out` is longer than an error shows.
fn write_value(v: &KeyValue, out: &mut String) {
    if out.len() > 4 * MAX_SHOWN_CHARS {
        return;
    }
    match v {
        KeyValue::Bool(b) => out.push_str(&b.to_string()),
        KeyValue::Integer(i) => out.push_str(&i.to_string()),
        KeyValue::Float(x) => out.push_str(&x.to_string()),
        KeyValue::Text(s) => out.push_str(&format!("{:?}", clip(s))),
        KeyValue::List(items) => {
            out.push('[');
            for (i, item) in items.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                write_value(item, out);
                if out.len() > 4 * MAX_SHOWN_CHARS {
                    break;
                }
            }
            out.push(']');
        }
        KeyValue::Table(entries) => {
            out.push_str("{ ");
            for (i, (k, item)) in entries.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                out.push_str(&format!("{} = ", shown_key(k)));
                write_value(item, out);
            }
            out.push_str(" }");
        }
    }
}

/// The first characters of a long string (a value is quoted with `{:?}`, which escapes control
/// characters).
fn clip(s: &str) -> &str {
    match s.char_indices().nth(4 * MAX_SHOWN_CHARS) {
        Some((at, _)) => &s[..at],
        None => s,
    }
}

/// A key's name as an error shows it: bare when it is a plain name, quoted (control characters
/// escaped, cut when long) otherwise.
pub fn shown_key(name: &str) -> String {
    let plain = !name.is_empty()
        && name.len() <= 64
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if plain {
        name.to_string()
    } else {
        let clipped: String = name.chars().take(64).collect();
        format!("{clipped:?}")
    }
}

/// Where a reader finds the keys it reads: a scene's table, a Python dict, Mitsuba's
/// `Properties`, each behind a small adapter.
pub trait KeySource {
    /// The value given for the key `name`, if any.
    fn get(&self, name: &str) -> Option<KeyValue>;

    /// Every key given, in order (a reader refuses those it does not know).
    fn names(&self) -> Vec<String>;

    /// Where a file a value names lies: a relative path against the source's folder (a scene
    /// file's), as given where the source has none.
    fn path(&self, file: &str) -> PathBuf {
        PathBuf::from(file)
    }
}

/// Keys in a map, with an optional folder that relative paths resolve against: the
/// [`KeySource`] a front end fills (Python's keyword arguments, a plugin's properties).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Keys {
    map: BTreeMap<String, KeyValue>,
    base: Option<PathBuf>,
}

impl Keys {
    /// No keys.
    pub fn new() -> Keys {
        Keys::default()
    }

    /// Sets `name` to `value` (replacing an earlier value).
    pub fn insert(&mut self, name: impl Into<String>, value: KeyValue) {
        self.map.insert(name.into(), value);
    }

    /// These keys and `name` = `value`.
    pub fn with(mut self, name: impl Into<String>, value: KeyValue) -> Keys {
        self.insert(name, value);
        self
    }

    /// These keys, with relative paths resolving against `folder`.
    pub fn in_folder(mut self, folder: impl AsRef<Path>) -> Keys {
        self.base = Some(folder.as_ref().to_path_buf());
        self
    }

    /// Takes the key `name` out, returning its value.
    pub fn remove(&mut self, name: &str) -> Option<KeyValue> {
        self.map.remove(name)
    }
}

impl KeySource for Keys {
    fn get(&self, name: &str) -> Option<KeyValue> {
        self.map.get(name).cloned()
    }

    fn names(&self) -> Vec<String> {
        self.map.keys().cloned().collect()
    }

    fn path(&self, file: &str) -> PathBuf {
        match &self.base {
            Some(dir) => dir.join(file),
            None => PathBuf::from(file),
        }
    }
}

#[cfg(feature = "serde")]
mod toml_values {
    use super::{KeySource, KeyValue, Keys};

    impl From<toml::Value> for KeyValue {
        fn from(v: toml::Value) -> KeyValue {
            match v {
                toml::Value::Boolean(b) => KeyValue::Bool(b),
                toml::Value::Integer(i) => KeyValue::Integer(i),
                toml::Value::Float(x) => KeyValue::Float(x),
                toml::Value::String(s) => KeyValue::Text(s),
                // A date has no key to read it: words a reader refuses with its type.
                toml::Value::Datetime(d) => KeyValue::Text(d.to_string()),
                toml::Value::Array(a) => KeyValue::List(a.into_iter().map(Into::into).collect()),
                toml::Value::Table(t) => {
                    KeyValue::Table(t.into_iter().map(|(k, v)| (k, v.into())).collect())
                }
            }
        }
    }

    impl From<toml::Table> for Keys {
        fn from(t: toml::Table) -> Keys {
            let mut keys = Keys::new();
            for (k, v) in t {
                keys.insert(k, v.into());
            }
            keys
        }
    }

    impl KeySource for toml::Table {
        fn get(&self, name: &str) -> Option<KeyValue> {
            toml::Table::get(self, name).cloned().map(Into::into)
        }

        fn names(&self) -> Vec<String> {
            self.keys().cloned().collect()
        }
    }

    /// Any value serde can describe, read as a [`KeyValue`] (the pattern value's serde form,
    /// [`PatternSpec`](crate::weave::PatternSpec), reads through it).
    impl<'de> serde::Deserialize<'de> for KeyValue {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<KeyValue, D::Error> {
            d.deserialize_any(Visitor)
        }
    }

    struct Visitor;

    impl<'de> serde::de::Visitor<'de> for Visitor {
        type Value = KeyValue;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a boolean, a number, a string, a list or a table")
        }
        fn visit_bool<E>(self, v: bool) -> Result<KeyValue, E> {
            Ok(KeyValue::Bool(v))
        }
        fn visit_i64<E>(self, v: i64) -> Result<KeyValue, E> {
            Ok(KeyValue::Integer(v))
        }
        fn visit_u64<E>(self, v: u64) -> Result<KeyValue, E> {
            Ok(i64::try_from(v).map_or(KeyValue::Float(v as f64), KeyValue::Integer))
        }
        fn visit_f64<E>(self, v: f64) -> Result<KeyValue, E> {
            Ok(KeyValue::Float(v))
        }
        fn visit_str<E>(self, v: &str) -> Result<KeyValue, E> {
            Ok(KeyValue::Text(v.to_string()))
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut s: A) -> Result<KeyValue, A::Error> {
            let mut items = Vec::new();
            while let Some(item) = s.next_element()? {
                items.push(item);
            }
            Ok(KeyValue::List(items))
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, mut m: A) -> Result<KeyValue, A::Error> {
            let mut entries = Vec::new();
            while let Some((k, v)) = m.next_entry::<String, KeyValue>()? {
                entries.push((k, v));
            }
            Ok(KeyValue::Table(entries))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_values_and_control_characters_are_shown_safely() {
        let long = KeyValue::Text("x".repeat(100_000));
        let shown = long.to_string();
        assert!(shown.chars().count() < MAX_SHOWN_CHARS + 40, "{shown}");
        assert!(shown.contains("more characters"), "{shown}");
        let bell = KeyValue::Text("a\u{7}b".into()).to_string();
        assert!(!bell.contains('\u{7}') && bell.contains("\\u{7}"), "{bell}");
        let many = KeyValue::List(vec![KeyValue::Integer(1); 100_000]).to_string();
        assert!(many.len() < 400, "{many}");
        assert_eq!(shown_key("gap"), "gap");
        assert_eq!(shown_key("a\u{1b}[2J"), "\"a\\u{1b}[2J\"");
    }

    #[test]
    fn a_folder_resolves_relative_paths() {
        let keys = Keys::new().in_folder("/scenes");
        assert_eq!(keys.path("a.wif"), PathBuf::from("/scenes/a.wif"));
        assert_eq!(Keys::new().path("a.wif"), PathBuf::from("a.wif"));
    }

    #[cfg(feature = "serde")]
    #[test]
    fn toml_values_read_as_key_values() {
        let t: toml::Table =
            toml::from_str("a = 1\nb = [0.5, \"x\"]\nc = { wif = \"f\" }\nd = true").unwrap();
        assert_eq!(KeySource::get(&t, "a"), Some(KeyValue::Integer(1)));
        assert_eq!(
            KeySource::get(&t, "b"),
            Some(KeyValue::List(vec![
                KeyValue::Float(0.5),
                KeyValue::Text("x".into())
            ]))
        );
        assert_eq!(
            KeySource::get(&t, "c").unwrap().to_string(),
            "{ wif = \"f\" }"
        );
        assert_eq!(KeySource::get(&t, "d"), Some(KeyValue::Bool(true)));
        let v: KeyValue = toml::from_str::<toml::Table>("x = [[1, 0]]").unwrap()["x"]
            .clone()
            .into();
        assert_eq!(v.to_string(), "[[1, 0]]");
    }
}
