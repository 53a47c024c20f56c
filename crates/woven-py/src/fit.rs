//! `woven.fit` (one fit of measured data, as `woven fit --data` runs it: the `woven-fit`
//! library's [`FitRequest`]) and the thread-pool size that `woven.batch`'s workers cap.

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;
use std::time::Instant;
use woven_fit::data::DataError;
use woven_fit::request::FitRequest;
use woven_fit::{FitError, FitOptions, ModelKind, Residual};

/// A fitter error as the Python exception that fits it: files that cannot be read are OSError,
/// everything else ValueError, with the library's message.
pub(crate) fn fit_err(err: FitError) -> PyErr {
    match &err {
        FitError::Material(woven::Error::Io { .. }) => PyOSError::new_err(crate::message(&err)),
        _ => PyValueError::new_err(crate::message(&err)),
    }
}

/// A measurement file's error: OSError when it cannot be read, ValueError for its contents.
fn data_err(err: DataError) -> PyErr {
    match &err {
        DataError::Io { .. } => PyOSError::new_err(crate::message(&err)),
        _ => PyValueError::new_err(crate::message(&err)),
    }
}

/// The options of a fit from the keyword arguments, over `FitOptions::default()`.
#[allow(clippy::too_many_arguments)]
fn options(
    seed: u32,
    starts: Option<usize>,
    refine: Option<usize>,
    max_iterations: Option<usize>,
    subset: Option<usize>,
    final_subset: Option<usize>,
    residual: &str,
    saturation: Option<f64>,
) -> PyResult<FitOptions> {
    let base = FitOptions::default();
    let options = FitOptions {
        residual: Residual::parse(residual).map_err(fit_err)?,
        seed,
        starts: starts.unwrap_or(base.starts),
        refine: refine.unwrap_or(base.refine),
        max_iterations: max_iterations.unwrap_or(base.max_iterations),
        subset: subset.unwrap_or(base.subset),
        final_subset: final_subset.unwrap_or(base.final_subset),
        saturation,
        ..base
    };
    options.check().map_err(fit_err)?;
    Ok(options)
}

/// Fits `model` to the measurements `data`, as `woven fit --data DATA --model MODEL` does.
///
/// `data` is anything `woven fit --data` takes: a measurement file's path (the fitter's CSV, the
/// CSV `woven gonio` writes, a CUReT, RGL or MERL-grid file of data/), or `FILE#N` / `FILE#NAME`
/// for one sample of a file of several. `model`: "cloth", "fiber", "lambert", "microfacet",
/// "sheen" or "microcylinder". `init`: the starting material (a preset name or file; for
/// "microcylinder" a microcylinder fabric); `fix`: parameters held, a list of "name=value";
/// `free`: names let vary. `seed`, `starts`, `refine`, `max_iterations`, `subset`,
/// `final_subset`, `residual` ("log" or "relative") and `saturation` as in `woven fit --help`
/// (defaults: the library's, those of `woven fit`). Deterministic for a seed. Runs on rayon's
/// pool with the GIL released (`woven.set_threads` caps it).
///
/// Returns a dict of plain values: `dataset` (the data's name), `model`, `points`
/// (measurements fitted), `rms_log`, `relative_rms`, `material_toml` (the text `woven fit -o`
/// writes: a material file for cloth, fiber and microcylinder, the parameters as TOML for the
/// baselines), `parameters` (name → value) and `seconds` (the fit's wall time).
///
/// Raises OSError for a file that cannot be read, ValueError for bad data, an unknown model or
/// parameter, a value out of range, or a fit the data cannot determine (the library's message).
#[pyfunction]
#[pyo3(signature = (data, model = "cloth", *, init = None, fix = None, free = None, seed = 1,
    starts = None, refine = None, max_iterations = None, subset = None, final_subset = None,
    residual = "log", saturation = None))]
#[allow(clippy::too_many_arguments)]
pub fn fit<'py>(
    py: Python<'py>,
    data: &str,
    model: &str,
    init: Option<String>,
    fix: Option<Vec<String>>,
    free: Option<Vec<String>>,
    seed: u32,
    starts: Option<usize>,
    refine: Option<usize>,
    max_iterations: Option<usize>,
    subset: Option<usize>,
    final_subset: Option<usize>,
    residual: &str,
    saturation: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let request = FitRequest {
        model: ModelKind::parse(model).map_err(fit_err)?,
        init,
        fix: fix.unwrap_or_default(),
        free: free.unwrap_or_default(),
        options: options(
            seed,
            starts,
            refine,
            max_iterations,
            subset,
            final_subset,
            residual,
            saturation,
        )?,
    };
    let start = Instant::now();
    let result = crate::signals::until_interrupted(py, |stop| {
        let dataset = woven_fit::data::load(Path::new(data)).map_err(data_err)?;
        request.run(&dataset, stop).map_err(fit_err)
    })??;
    let seconds = start.elapsed().as_secs_f64();
    let out = PyDict::new(py);
    out.set_item("dataset", &result.dataset)?;
    out.set_item("model", result.model.name())?;
    out.set_item("points", result.observations.len())?;
    out.set_item("rms_log", result.rms_log)?;
    out.set_item("relative_rms", result.relative_rms)?;
    let toml = result
        .material_toml()
        .unwrap_or_else(|| result.params_toml());
    out.set_item("material_toml", toml)?;
    let params = PyDict::new(py);
    for p in &result.params.params {
        params.set_item(&p.name, p.value)?;
    }
    out.set_item("parameters", params)?;
    out.set_item("seconds", seconds)?;
    Ok(out)
}

/// Sizes rayon's global thread pool, which fits and renders run on, to `threads` workers, if
/// this process has not used it yet; returns the pool's size after the call (equal to `threads`
/// when it took effect, the size fixed earlier otherwise). Table builds and renders with
/// `threads=0` also follow the environment variable `RAYON_NUM_THREADS`, which `woven.batch`
/// sets alongside. Raises ValueError for `threads` = 0.
#[pyfunction]
pub fn set_threads(threads: usize) -> PyResult<usize> {
    if threads == 0 {
        return Err(PyValueError::new_err(
            "`threads` = 0: expected at least 1 worker thread",
        ));
    }
    // An error here means the pool exists already; its size is then the answer.
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global();
    Ok(rayon::current_num_threads())
}

/// The size of rayon's global thread pool in this process (fits and renders run on it).
#[pyfunction]
pub fn threads() -> usize {
    rayon::current_num_threads()
}

/// One model's result in a row of `comparison_table`: `(model, rms_log, relative_rms)` of a fit
/// that ran, or `(model, error)` of one that could not.
#[derive(FromPyObject)]
pub(crate) enum FitCell {
    Ran(String, f64, f64),
    Failed(String, String),
}

/// The Markdown table `woven fit --compare` prints and writes (`--report`): one row per dataset,
/// each model's RMS log error and relative RMS, the best of a row in bold, and for MERL
/// materials the published SGD and ABC fits scored alike.
///
/// `rows`: a list of `(data, fits)`, where `data` is what `woven.fit` takes (a path or
/// `FILE#N`; the dataset is read for its name, its measurement count and the published fits)
/// and `fits` a list of `(model, rms_log, relative_rms)` or `(model, error_message)`. Raises
/// OSError or ValueError for a dataset that cannot be read (the library's message).
#[pyfunction]
pub fn comparison_table(py: Python<'_>, rows: Vec<(String, Vec<FitCell>)>) -> PyResult<String> {
    py.detach(|| {
        let mut table = Vec::with_capacity(rows.len());
        for (data, cells) in rows {
            let dataset = woven_fit::data::load(Path::new(&data)).map_err(data_err)?;
            let mut fits: Vec<(String, woven_fit::report::Outcome)> = cells
                .into_iter()
                .map(|c| match c {
                    FitCell::Ran(m, log, rel) => (m, Ok((log, rel))),
                    FitCell::Failed(m, e) => (m, Err(e)),
                })
                .collect();
            fits.extend(woven_fit::report::published_errors(&dataset));
            table.push(woven_fit::Comparison {
                dataset: dataset.name.clone(),
                points: dataset.samples.len(),
                fits,
            });
        }
        Ok(woven_fit::report::comparison_table(&table))
    })
}

/// The datasets of a measurement file, each as `FILE#NAME` that `woven.fit` takes: one entry per
/// material of a file of several (CUReT's 61 samples), the path itself for a file of one.
/// Raises OSError or ValueError for a file that cannot be read or is not a measurement file.
#[pyfunction]
pub fn datasets(py: Python<'_>, path: &str) -> PyResult<Vec<String>> {
    let names = py
        .detach(|| woven_fit::data::materials(Path::new(path)))
        .map_err(data_err)?;
    if names.len() <= 1 {
        return Ok(vec![path.to_string()]);
    }
    Ok(names.iter().map(|n| format!("{path}#{n}")).collect())
}
