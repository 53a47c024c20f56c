//! Python values as the library's [`KeyValue`]s: the adapter through which `woven.Surface`'s
//! keyword arguments (and so the Mitsuba plugin's properties) reach the library's one reader of
//! a surface's keys (`woven::surface::SurfaceSpec::from_keys`).

use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};
use woven::keys::{shown_key, KeyValue, Keys};
use woven::surface::KeyError;

/// The deepest a value may nest (a pattern's matrix is two deep, a WIF table one).
const MAX_DEPTH: usize = 4;

/// The most items a list may hold, in all: a pattern of at most `MAX_THREADS`² cells and a
/// little more; the library refuses what is too large with its own limits.
const MAX_ITEMS: usize = 1 << 20;

/// `value` as a key's value: a bool, an int, a float (NumPy's scalars too), a str, a sequence
/// (list, tuple, NumPy array) or a dict of these.
///
/// # Errors
/// TypeError naming `name` for anything else, or a value nested or sized beyond any key's.
pub(crate) fn key_value(value: &Bound<'_, PyAny>, name: &str) -> PyResult<KeyValue> {
    let mut items = 0;
    convert(value, name, 0, &mut items)
}

fn convert(
    v: &Bound<'_, PyAny>,
    name: &str,
    depth: usize,
    items: &mut usize,
) -> PyResult<KeyValue> {
    let refuse = |why: &str| {
        PyTypeError::new_err(format!(
            "`{}`: {why}",
            woven::error::clip_words(&shown_key(name))
        ))
    };
    if depth > MAX_DEPTH {
        return Err(refuse("a value nested deeper than any key's"));
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(KeyValue::Bool(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        // An int beyond i64 is out of every key's range: shown as the float it is near.
        return Ok(v.extract::<i64>().map_or_else(
            |_| KeyValue::Float(v.extract().unwrap_or(f64::INFINITY)),
            KeyValue::Integer,
        ));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(KeyValue::Float(v.extract()?));
    }
    if let Some(scalar) = numpy_scalar(v)? {
        return Ok(scalar);
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(KeyValue::Text(s.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut entries = Vec::new();
        for (k, item) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| refuse("a dict's keys must be strings"))?;
            let value = convert(&item, &format!("{name}.{k}"), depth + 1, items)?;
            entries.push((k, value));
        }
        return Ok(KeyValue::Table(entries));
    }
    if let Ok(iter) = v.try_iter() {
        let mut list = Vec::new();
        for item in iter {
            *items += 1;
            if *items > MAX_ITEMS {
                return Err(refuse("a value with more items than any key takes"));
            }
            list.push(convert(&item?, name, depth + 1, items)?);
        }
        return Ok(KeyValue::List(list));
    }
    let type_name = v.get_type().name()?.to_string();
    Err(refuse(&format!(
        "a {} is not a key's value: give a bool, a number, a str, a sequence or a dict",
        woven::error::clip_words(&type_name)
    )))
}

/// A NumPy scalar (or 0-d array) by its dtype's kind: a bool, an integer or a float; None for
/// anything else.
fn numpy_scalar(v: &Bound<'_, PyAny>) -> PyResult<Option<KeyValue>> {
    if !v.hasattr("dtype")? || !v.hasattr("ndim")? || v.getattr("ndim")?.extract::<usize>()? != 0 {
        return Ok(None);
    }
    let kind: String = v.getattr("dtype")?.getattr("kind")?.extract()?;
    Ok(match kind.as_str() {
        "b" => Some(KeyValue::Bool(v.call_method0("item")?.extract()?)),
        "i" | "u" => Some(
            v.extract::<i64>()
                .map_or(KeyValue::Float(f64::INFINITY), KeyValue::Integer),
        ),
        "f" => Some(KeyValue::Float(v.extract()?)),
        _ => None,
    })
}

/// The keyword arguments given (None: left out) as the library's keys.
pub(crate) fn keys_of(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Keys> {
    let mut keys = Keys::new();
    if let Some(kwargs) = kwargs {
        for (k, v) in kwargs.iter() {
            let k: String = k.extract()?;
            if !v.is_none() {
                keys.insert(k.clone(), key_value(&v, &k)?);
            }
        }
    }
    Ok(keys)
}

/// A key the library refused, as Python's ValueError (the key, its value and its range; long
/// words cut).
pub(crate) fn key_error(e: KeyError) -> PyErr {
    let message = crate::message(&e);
    match e.error {
        woven::Error::Io { .. } => PyOSError::new_err(message),
        _ => PyValueError::new_err(message),
    }
}
