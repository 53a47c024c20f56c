//! Python bindings of the `woven` library: the native module `woven._woven`, which the Python
//! package `woven` (`python/woven`) re-exports with its Mitsuba 3 plugin.
//!
//! A thin layer: every number comes from the library; this crate only converts and validates
//! NumPy arrays (`arrays`: finite numbers, unit directions, a memory budget per array),
//! broadcasts, releases the GIL, spreads large batches over rayon's pool while checking for
//! Ctrl-C, and maps the library's errors to Python exceptions (`ValueError` for parameters and
//! file contents, `OSError` for files that cannot be read or written). Directions are those of
//! the library's `Bsdf` trait: `wi` toward the light (the paper's `s`), `wo` toward the viewer
//! (`v`), unit vectors in the cloth's frame (`z` the macro normal, weft along `x`, warp along
//! `y`). The Python-facing documentation is in the docstrings below and the stubs
//! (`python/woven/_woven.pyi`); docs/python.md shows it at work.

mod arrays;
mod bsdf;
mod fit;
mod keys;
mod material;
mod render;
mod scene;
mod signals;
mod standard;
mod surface;
mod table;

use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// An error's message as Python shows it: a key or a name of megabytes, echoed from the input,
/// cut (`woven::error::clip_words`).
pub(crate) fn message(err: &impl std::fmt::Display) -> String {
    woven::error::clip_words(&err.to_string()).into_owned()
}

/// A library error as the Python exception that fits it.
pub(crate) fn to_py(err: woven::Error) -> PyErr {
    match &err {
        woven::Error::Io { .. } => PyOSError::new_err(crate::message(&err)),
        // Stopped by a signal whose own exception is raised instead: this is what is left.
        woven::Error::Cancelled => PyKeyboardInterrupt::new_err(crate::message(&err)),
        _ => PyValueError::new_err(crate::message(&err)),
    }
}

/// The library's result, with its error as a Python exception.
pub(crate) trait IntoPy<T> {
    /// The value, or the error as a Python exception.
    fn py_err(self) -> PyResult<T>;
}

impl<T> IntoPy<T> for woven::Result<T> {
    fn py_err(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}

/// woven: the Yang–Ikeuchi woven-cloth BRDF (native part; import `woven`).
#[pymodule]
fn _woven(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<material::Material>()?;
    m.add_class::<material::Section>()?;
    m.add_class::<material::Model>()?;
    m.add_class::<table::Table>()?;
    m.add_class::<surface::Surface>()?;
    m.add_class::<bsdf::PyBsdf>()?;
    m.add_class::<bsdf::Microcylinder>()?;
    m.add_class::<bsdf::Sheen>()?;
    m.add_class::<bsdf::RoughPlastic>()?;
    m.add_function(wrap_pyfunction!(material::presets, m)?)?;
    m.add_function(wrap_pyfunction!(bsdf::open_material, m)?)?;
    m.add_function(wrap_pyfunction!(scene::portable_scene, m)?)?;
    m.add("STANDARD_VERSION", woven_fit::standard::STANDARD_VERSION)?;
    m.add_function(wrap_pyfunction!(standard::standard_surface, m)?)?;
    m.add_function(wrap_pyfunction!(standard::standard_eval, m)?)?;
    m.add_function(wrap_pyfunction!(scene::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(material::gonio, m)?)?;
    m.add_function(wrap_pyfunction!(material::from_spherical, m)?)?;
    m.add_function(wrap_pyfunction!(material::to_spherical, m)?)?;
    m.add_function(wrap_pyfunction!(table::export_merl, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(fit::set_threads, m)?)?;
    m.add_function(wrap_pyfunction!(fit::threads, m)?)?;
    m.add_function(wrap_pyfunction!(fit::comparison_table, m)?)?;
    m.add_function(wrap_pyfunction!(fit::datasets, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("PARALLEL_MIN", arrays::PARALLEL_MIN)?;
    m.add("BATCH_BUDGET_BYTES", arrays::BATCH_BUDGET_BYTES)?;
    m.add("UNIT_TOLERANCE", arrays::UNIT_TOLERANCE)?;
    m.add("MAX_DYED_DIFFUSE", woven::table::Albedos::MAX_DYED_DIFFUSE)?;
    m.add("JIT_LAYOUT_VERSION", woven::surface::JIT_LAYOUT_VERSION)?;
    m.add("SURFACE_KEYS", surface_keys(m.py())?)?;
    Ok(())
}

/// `woven.SURFACE_KEYS`: the library's table of a woven surface's keys
/// ([`woven::surface::SURFACE_KEYS`]), a tuple of dicts `{"name", "default", "valid",
/// "meaning"}` (strings), in the table's order.
fn surface_keys(py: Python<'_>) -> PyResult<Bound<'_, PyTuple>> {
    let rows = woven::surface::SURFACE_KEYS
        .iter()
        .map(|k| {
            let row = PyDict::new(py);
            row.set_item("name", k.name)?;
            row.set_item("default", k.default())?;
            row.set_item("valid", k.valid())?;
            row.set_item("meaning", k.meaning())?;
            Ok(row)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyTuple::new(py, rows)
}
