//! `woven.render`: a scene file rendered by the `woven-render` library, as `woven render` does.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use woven_render::render::{render_with_progress, RenderOptions};
use woven_render::scene::{FilmOverrides, Scene, SceneDescription};
use woven_render::woven_material::{TableCache, TableGrid};

/// A renderer error as the Python exception that fits it, with the library's message.
pub(crate) fn render_err(err: woven_render::Error) -> PyErr {
    match &err {
        woven_render::Error::Io { .. } | woven_render::Error::Woven(woven::Error::Io { .. }) => {
            PyOSError::new_err(crate::message(&err))
        }
        _ => PyValueError::new_err(crate::message(&err)),
    }
}

/// Renders the scene file `scene` (TOML, docs/render.md), as `woven render SCENE -o OUTPUT`.
///
/// `output`: a file ending in .exr (linear float32 RGB) or .png (sRGB through the scene's
/// display settings), written atomically; None writes nothing. `spp`, `width`, `height` and
/// `seed` override the scene's `[film]`; `threads` (None: rayon's global pool, which
/// `woven.set_threads` sizes) the render's workers. `cache=True` keeps woven tables in the
/// user's cache (`$XDG_CACHE_HOME/woven`, shared with `woven render`); False builds them anew.
///
/// Returns a dict: `scene`, `width`, `height`, `spp`, `seconds` (the render's wall time),
/// `invalid_samples` and `pixels`, the linear RGB image as a float64 array (height, width, 3),
/// row 0 at the top. Raises ValueError for a bad scene or setting, OSError for files that
/// cannot be read or written (the library's message names the key or file).
#[pyfunction]
#[pyo3(signature = (scene, output = None, *, spp = None, width = None, height = None,
    seed = None, threads = None, cache = true))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    scene: PathBuf,
    output: Option<PathBuf>,
    spp: Option<usize>,
    width: Option<usize>,
    height: Option<usize>,
    seed: Option<u64>,
    threads: Option<usize>,
    cache: bool,
) -> PyResult<Bound<'py, PyDict>> {
    for (name, value) in [("spp", spp), ("width", width), ("height", height)] {
        if value == Some(0) {
            return Err(PyValueError::new_err(format!(
                "`{name}` = 0: expected at least 1"
            )));
        }
    }
    let image = crate::signals::until_interrupted(py, |stop| -> woven_render::Result<_> {
        let desc = SceneDescription::from_path(&scene)?.with_overrides(&FilmOverrides {
            spp,
            width,
            height,
            seed,
            ..FilmOverrides::default()
        })?;
        let tables = match woven::table::cache::Cache::user() {
            Ok(disk) if cache => TableCache::with_disk(disk),
            _ => TableCache::default(),
        };
        let built = Scene::build_with(&desc, &TableGrid::Default, tables, &|_| {}, stop)?;
        let image = render_with_progress(&built, &RenderOptions { threads }, stop)?;
        if let Some(path) = &output {
            woven_render::output::write(&image, path, &desc.film.display)?;
        }
        Ok(image)
    })?
    .map_err(render_err)?;
    let flat: Vec<f64> = image.pixels.iter().flat_map(|p| p.0).collect();
    let pixels = PyArray1::from_vec(py, flat).reshape([image.height, image.width, 3])?;
    let out = PyDict::new(py);
    out.set_item("scene", Path::new(&scene).display().to_string())?;
    out.set_item("width", image.width)?;
    out.set_item("height", image.height)?;
    out.set_item("spp", image.spp)?;
    out.set_item("seconds", image.seconds)?;
    out.set_item("invalid_samples", image.invalid_samples)?;
    out.set_item("pixels", pixels)?;
    Ok(out)
}
