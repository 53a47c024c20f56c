//! `woven.Table` (tabulated BRDFs: build, files, evaluation, sampling, the raw arrays for the
//! Mitsuba plugin) and `woven.export_merl`.

use crate::arrays::{
    broadcast, budget_vec, check_budget, map_batch, Dirs, Numbers, FRACTIONS, UNIFORMS,
};
use crate::material::{map_pairs, material_arg, Material, Model};
use crate::IntoPy;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use woven::bsdf::{Bsdf, Transport};
use woven::progress::Until;
use woven::table::{Albedos, Symmetry, TableOptions};

/// A tabulated BRDF: the exact model stored on a grid, interpolated in well under a microsecond
/// per pair and importance-sampled (`woven tabulate` builds the same; `.wtab` files).
///
/// Build with `Table.build(material)`, or `Table.load(path)`. Directions as everywhere in
/// woven: `wi` toward the light, `wo` toward the viewer, unit vectors (N, 3) in the cloth's frame
/// (z the normal, weft along x, warp along y). Batches of 4096 pairs and more run on all cores
/// with the GIL released, and stop for Ctrl-C (KeyboardInterrupt).
///
/// Arguments are validated as the command line's: directions finite and unit length within
/// `woven.UNIT_TOLERANCE`, uniforms `u` and albedos in [0, 1] (ValueError naming the argument,
/// the row and its value), complex arrays refused (TypeError); an empty batch gives empty
/// results; a batch over `woven.BATCH_BUDGET_BYTES` raises MemoryError before allocating.
#[pyclass(module = "woven", frozen)]
pub struct Table {
    pub(crate) inner: Arc<woven::table::Table>,
}

/// How a build reports progress.
enum Progress {
    None,
    Stderr,
    Callback(Py<PyAny>),
}

/// A build's progress reports, from the worker threads: at most one per percent, to a Python
/// callable or `sys.stderr`, in increasing order of `done` (workers race to the GIL, so a late
/// report of fewer tasks is dropped) and always ending with `done == total`; the first error a
/// callback raises is kept for `finish`.
struct Reporter {
    progress: Progress,
    last: AtomicUsize,
    highest: AtomicUsize,
    failed: Mutex<Option<PyErr>>,
}

impl Reporter {
    /// `progress`: None or True (stderr), False (nothing) or a callable `(done, total)`.
    fn new(progress: Option<&Bound<'_, PyAny>>) -> PyResult<Reporter> {
        let progress = match progress {
            None => Progress::Stderr,
            Some(p) if p.is_callable() => Progress::Callback(p.clone().unbind()),
            Some(p) if p.is_truthy()? => Progress::Stderr,
            Some(_) => Progress::None,
        };
        Ok(Reporter {
            progress,
            last: AtomicUsize::new(usize::MAX),
            highest: AtomicUsize::new(0),
            failed: Mutex::new(None),
        })
    }

    fn report(&self, done: usize, total: usize) {
        if matches!(self.progress, Progress::None) || total == 0 {
            return;
        }
        let percent = done * 100 / total;
        if self.last.swap(percent, Ordering::Relaxed) == percent && done != total {
            return;
        }
        Python::attach(|py| {
            // Under the GIL the reports are serialised: one that lost the race is stale.
            if self.highest.fetch_max(done, Ordering::Relaxed) >= done {
                return;
            }
            let result = match &self.progress {
                Progress::Callback(f) => f.call1(py, (done, total)).map(drop),
                Progress::Stderr => py.import("sys").and_then(|sys| {
                    let end = if done == total { "\n" } else { "" };
                    sys.getattr("stderr")?
                        .call_method1("write", (format!("\rtabulating: {percent:3}%{end}"),))
                        .map(drop)
                }),
                Progress::None => Ok(()),
            };
            if let Err(e) = result {
                self.failed.lock().expect("not poisoned").get_or_insert(e);
            }
        });
    }

    /// Whether a progress callback has raised: the build then stops (its error is `finish`'s).
    fn raised(&self) -> bool {
        self.failed.lock().map_or(true, |f| f.is_some())
    }

    /// The first error a progress callback raised, if any.
    fn finish(self) -> PyResult<()> {
        match self.failed.into_inner().expect("not poisoned") {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

impl woven::progress::Progress for Reporter {
    fn update(&self, done: usize, total: usize) {
        self.report(done, total)
    }

    fn cancelled(&self) -> bool {
        self.raised()
    }
}

/// The options of a named grid for `model`.
fn grid_options(grid: &str, model: &woven::Model) -> PyResult<TableOptions> {
    match grid {
        "model" => Ok(TableOptions::for_model(model)),
        "render" => Ok(TableOptions::for_render(model)),
        "default" => Ok(TableOptions::default()),
        other => Err(PyValueError::new_err(format!(
            "`grid` = {other:?}: expected \"model\", \"render\" or \"default\""
        ))),
    }
}

#[pymethods]
impl Table {
    /// Tabulates `material` (a Material, preset name or file path) at `wavelength_nm`.
    ///
    /// `grid` picks the node counts: "model" (the default: `woven tabulate`'s, refined for
    /// smooth fibers), "render" (`woven render`'s coarser, dyeable grid, seconds per preset) or
    /// "default" (`TableOptions::default()`); the keyword arguments override single options
    /// (`n_theta`, `theta_max_deg`, `n_phi`, `n_h`, `n_h_isotropic`, `azimuth_nodes`, `colour`:
    /// also tabulate ∂f/∂ρ0 for `eval_dyed`; `exact_regions`: evaluate the exact model where
    /// interpolation is poor — near-forward pairs and half vectors near the horizon — as the
    /// grids do by default, or interpolate everywhere, as the Mitsuba plugin's traced code does). `threads=0` uses every core. `progress=True`
    /// writes a percentage to `sys.stderr`; a callable gets `(rows_done, rows_total)`.
    ///
    /// Takes seconds (flat fibers, the sateen) to minutes (twisted and isotropic yarns on the
    /// model grid); the GIL is released meanwhile. Raises ValueError for an invalid material,
    /// wavelength or option (the library's message names it).
    #[staticmethod]
    #[pyo3(signature = (material, wavelength_nm = 550.0, *, grid = "model", n_theta = None,
        theta_max_deg = None, n_phi = None, n_h = None, n_h_isotropic = None,
        azimuth_nodes = None, colour = None, exact_regions = None, threads = 0, progress = None))]
    fn build(
        py: Python<'_>,
        material: &Bound<'_, PyAny>,
        wavelength_nm: f64,
        grid: &str,
        n_theta: Option<usize>,
        theta_max_deg: Option<f64>,
        n_phi: Option<usize>,
        n_h: Option<usize>,
        n_h_isotropic: Option<usize>,
        azimuth_nodes: Option<usize>,
        colour: Option<bool>,
        exact_regions: Option<bool>,
        threads: usize,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Table> {
        let material = material_arg(material)?;
        let model = py.detach(|| material.inner.build(wavelength_nm)).py_err()?;
        let base = grid_options(grid, &model)?;
        let options = TableOptions {
            n_theta: n_theta.unwrap_or(base.n_theta),
            theta_max_deg: theta_max_deg.unwrap_or(base.theta_max_deg),
            n_phi: n_phi.unwrap_or(base.n_phi),
            n_h: n_h.unwrap_or(base.n_h),
            n_h_isotropic: n_h_isotropic.unwrap_or(base.n_h_isotropic),
            azimuth_nodes: azimuth_nodes.unwrap_or(base.azimuth_nodes),
            colour: colour.unwrap_or(base.colour),
            threads,
            exact_regions: exact_regions.unwrap_or(base.exact_regions),
            crown_deg: 0.0,
        };
        let reporter = Reporter::new(progress)?;
        let table = crate::signals::until_interrupted(py, |stop| {
            let progress = Until {
                progress: &reporter,
                stop,
            };
            woven::table::Table::build(&model, &material.inner, &options, &progress)
        })?;
        // A callback that raised stopped the build: its exception is the one to raise.
        reporter.finish()?;
        let table = table.py_err()?;
        Ok(Table {
            inner: Arc::new(table),
        })
    }

    /// The table `woven render` uses for `material` at `wavelength_nm`, from the user's table
    /// cache (`$XDG_CACHE_HOME/woven` or `~/.cache/woven`, shared with `woven render`), or built
    /// on `grid` (default "render": dyeable, seconds per preset) and stored there. A damaged or
    /// foreign cache file is rebuilt, never trusted. Pass `material.yarn_family()` for the
    /// table of a material's yarn alone, which is what `woven render` and the Mitsuba plugin
    /// tabulate. `progress` as in `build`.
    #[staticmethod]
    #[pyo3(signature = (material, wavelength_nm = 550.0, *, grid = "render", progress = None))]
    fn cached(
        py: Python<'_>,
        material: &Bound<'_, PyAny>,
        wavelength_nm: f64,
        grid: &str,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Table> {
        let material = material_arg(material)?;
        let mut user = UserTables::open()?;
        let (table, _) = cached_table(
            py,
            &mut user,
            &material.inner,
            wavelength_nm,
            grid,
            progress,
        )?;
        Ok(Table { inner: table })
    }

    /// A table file (`.wtab`, from `Table.save` or `woven tabulate`).
    ///
    /// Raises OSError if it cannot be read, ValueError if it is not a valid table file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Table> {
        let table = py.detach(|| woven::table::Table::load(&path)).py_err()?;
        Ok(Table {
            inner: Arc::new(table),
        })
    }

    /// Writes the table to `path` atomically (a temporary file renamed into place).
    ///
    /// Raises OSError if it cannot be written.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| self.inner.save(&path)).py_err()
    }

    /// The BRDF f(wi, wo), sr⁻¹, without the cosine: arrays (N, 3) or (3,) (one broadcasts
    /// against many); returns (N,), or a float when both are (3,). 0 below the surface.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = &*self.inner;
        map_pairs(py, wi, wo, |wi, wo| t.eval(wi, wo))
    }

    /// As `eval`, but interpolated everywhere: accurate tables of single-orientation yarns
    /// evaluate near-forward pairs (|wi + wo| < 0.5) and pairs whose half vector lies within 5°
    /// of the horizon with the exact model; this skips that (what the Mitsuba plugin's Dr.Jit
    /// code computes).
    fn eval_interpolated<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = &*self.inner;
        map_pairs(py, wi, wo, |wi, wo| t.eval_interpolated(wi, wo))
    }

    /// The BRDF for other albedos (dyed fibers): `albedos` is (C, 2) — per channel the fiber's
    /// diffuse albedo ρ0 and the yarn's interreflection albedo ρ, each in [0, 1]; returns (N, C). The table must
    /// be dyeable (`colour=True`; `is_dyeable`); otherwise every channel is the table's own f.
    fn eval_dyed<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
        albedos: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (wi, wo) = (Dirs::extract(wi, "wi")?, Dirs::extract(wo, "wo")?);
        let n = broadcast(("wi", wi.n), ("wo", wo.n))?;
        let a = Numbers::extract_rows(albedos, "albedos", 2, FRACTIONS)?;
        let channels: Vec<Albedos> = (0..a.len() / 2)
            .map(|c| Albedos {
                diffuse: a[2 * c],
                interreflection: a[2 * c + 1],
            })
            .collect();
        let c = channels.len();
        check_budget("the result", n, c)?;
        let t = &*self.inner;
        let out = map_batch::<1, _>(py, n * c, |k| {
            let (i, ch) = (k / c, k % c);
            t.eval_dyed(wi.get(i), wo.get(i), &[channels[ch]])
        })?;
        PyArray1::from_vec(py, out).reshape([n, c])
    }

    /// Draws the unknown direction for `known` with the uniforms `u` (N, 2) (or (2,)) in [0, 1], as
    /// `woven.Surface.sample` does: in mode "radiance" (the default) `known` is `wo` (toward the
    /// viewer) and `wi` is drawn; in mode "importance" `known` is `wi` and `wo` is drawn, ∝ f
    /// cos θo. Returns `(drawn, weight, pdf)`: (N, 3) directions, (N,) weights (f times the drawn
    /// direction's cosine over the pdf, with the paper normalization's mode factor) and (N,)
    /// densities per unit solid angle. A failed draw (below the horizon, or `known` below the
    /// surface) has `drawn` = 0, weight 0 and pdf 0; that zero vector is no direction (`eval`
    /// and `pdf` refuse it): keep the draws with `pdf > 0` before passing them back.
    #[pyo3(signature = (known, u, mode = "radiance"))]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        known: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        mode: &str,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let mode = crate::surface::mode_arg(mode)?;
        let known = Dirs::extract(known, "known")?;
        let u = Dirs::extract_checked(u, "u", 2, UNIFORMS)?;
        let n = broadcast(("known", known.n), ("u", u.n))?;
        let t = &*self.inner;
        let out = map_batch::<5, _>(py, n, |i| {
            let (a, b) = u.get2(i);
            match t.sample(known.get(i), 0.5, [a, b], mode) {
                Some(s) => {
                    let d = match mode {
                        Transport::Radiance => s.wi,
                        Transport::Importance => s.wo,
                    };
                    [d.x, d.y, d.z, s.weight(mode), s.pdf]
                }
                None => [0.0; 5],
            }
        })?;
        split_columns(py, out, n, &[3, 1, 1])
    }

    /// `sample` without the BRDF: the drawn `wo` (N, 3) and its density (N,) (0 for a failed
    /// draw) — what a renderer uses when it evaluates f itself, or draws the light direction for
    /// a given viewer with the roles swapped (the Mitsuba plugin).
    fn sample_direction<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let wi = Dirs::extract(wi, "wi")?;
        let u = Dirs::extract_checked(u, "u", 2, UNIFORMS)?;
        let n = broadcast(("wi", wi.n), ("u", u.n))?;
        let t = &*self.inner;
        let out = map_batch::<4, _>(py, n, |i| {
            let (a, b) = u.get2(i);
            match t.sample_direction(wi.get(i), a, b) {
                Some((v, pdf)) => [v.x, v.y, v.z, pdf],
                None => [0.0; 4],
            }
        })?;
        split_columns(py, out, n, &[3, 1])
    }

    /// The density (per unit solid angle) with which `sample` in `mode` draws the unknown
    /// direction: `wi` for a known `wo` ("radiance", the default), `wo` for a known `wi`
    /// ("importance"). (N,), or a float when both are (3,).
    #[pyo3(signature = (wi, wo, mode = "radiance"))]
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
        mode: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mode = crate::surface::mode_arg(mode)?;
        let t = &*self.inner;
        map_pairs(py, wi, wo, |wi, wo| t.pdf(wi, wo, mode))
    }

    /// The material the table was built from (None for a table that records none).
    #[getter]
    fn material(&self) -> Option<Material> {
        self.inner.material().map(|m| Material { inner: m.clone() })
    }

    /// The wavelength the table was built at, nm.
    #[getter]
    fn wavelength_nm(&self) -> f64 {
        self.inner.wavelength_nm()
    }

    /// `(n_theta, n_phi, n_h)` of each half of the grid.
    #[getter]
    fn dims(&self) -> (usize, usize, usize) {
        self.inner.dims()
    }

    /// "isotropic" (one axis azimuth) or "mirror" (axis azimuths over [0, π/2]).
    #[getter]
    fn symmetry(&self) -> &'static str {
        symmetry_name(self.inner.symmetry())
    }

    /// Whether the table holds ∂f/∂ρ0 for `eval_dyed`.
    #[getter]
    fn is_dyeable(&self) -> bool {
        self.inner.is_dyeable()
    }

    /// The stored node values f (float32, sr⁻¹), a copy: the light half then the view half,
    /// shape (2, n_theta, n_phi, n_h, n_h).
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (a, b, c) = self.inner.dims();
        Ok(PyArray1::from_slice(py, self.inner.values())
            .reshape([2, a, b, c, c])?
            .into_any())
    }

    /// The table's arrays and grid for code that repeats its look-up (the Mitsuba plugin): a
    /// dict of float32 arrays (`values`, `body`, `marginal`, `conditional`) and the grid's
    /// parameters (see `crates/woven/src/table/raw.rs` and docs/python.md).
    fn raw<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = self.inner.raw();
        let d = PyDict::new(py);
        d.set_item("symmetry", symmetry_name(r.symmetry))?;
        for (name, axis) in [("theta", r.theta), ("phi", r.phi), ("t", r.t)] {
            d.set_item(
                name,
                PyDict::from_sequence(
                    &vec![
                        ("lo", axis.lo.into_pyobject(py)?.into_any()),
                        ("hi", axis.hi.into_pyobject(py)?.into_any()),
                        ("n", axis.n.into_pyobject(py)?.into_any()),
                        ("grading", axis.grading.into_pyobject(py)?.into_any()),
                    ]
                    .into_pyobject(py)?,
                )?,
            )?;
        }
        d.set_item("slope_scale", r.slope_scale)?;
        d.set_item("values", PyArray1::from_slice(py, r.values))?;
        match r.body {
            Some(b) => d.set_item("body", PyArray1::from_slice(py, b))?,
            None => d.set_item("body", py.None())?,
        }
        d.set_item("per_interreflection", r.per_interreflection)?;
        match r.own {
            Some(a) => d.set_item("own", (a.diffuse, a.interreflection))?,
            None => d.set_item("own", py.None())?,
        }
        match r.crown {
            Some(g) => d.set_item("crown", PyArray1::from_slice(py, g))?,
            None => d.set_item("crown", py.None())?,
        }
        d.set_item("marginal", PyArray1::from_slice(py, r.marginal))?;
        d.set_item("conditional", PyArray1::from_slice(py, r.conditional))?;
        d.set_item("horizon_weight", r.horizon_weight)?;
        d.set_item("turn_deg", r.turn_deg)?;
        d.set_item("forward_exact", r.forward_exact)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let (a, b, c) = self.inner.dims();
        let name = self
            .inner
            .material()
            .and_then(|m| m.name.clone())
            .unwrap_or_else(|| "(unnamed)".into());
        format!(
            "<woven.Table {name:?} at {} nm, {} grid {a}×{b}×{c}², {}>",
            self.inner.wavelength_nm(),
            symmetry_name(self.inner.symmetry()),
            if self.inner.is_dyeable() {
                "dyeable"
            } else {
                "not dyeable"
            }
        )
    }
}

fn symmetry_name(s: Symmetry) -> &'static str {
    match s {
        Symmetry::Isotropic => "isotropic",
        Symmetry::Mirror => "mirror",
    }
}

/// Rows of `widths.iter().sum()` columns split into arrays: (n, w) for w > 1, (n,) for w = 1.
pub(crate) fn split_columns<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    n: usize,
    widths: &[usize],
) -> PyResult<Bound<'py, PyTuple>> {
    let k: usize = widths.iter().sum();
    let mut parts = Vec::new();
    let mut start = 0;
    for &w in widths {
        let mut col = budget_vec("the result", n, w)?;
        for row in data.chunks_exact(k) {
            col.extend_from_slice(&row[start..start + w]);
        }
        let array = PyArray1::from_vec(py, col);
        parts.push(if w == 1 {
            array.into_any()
        } else {
            array.reshape([n, w])?.into_any()
        });
        start += w;
    }
    PyTuple::new(py, parts)
}

/// Writes a BRDF in the MERL binary layout (90 θh × 90 θd × 180 φd bins, grey, 34,992,012
/// bytes), which Mitsuba, pbrt and most BRDF tools read. `source` is a Table or a Model of an
/// isotropic material (a flat fiber surface, or yarns with `isotropic = true`); exact models
/// of woven yarns take a millisecond a bin: tabulate them first. Written atomically.
///
/// Raises ValueError for an anisotropic material, OSError if the file cannot be written.
#[pyfunction]
#[pyo3(signature = (source, path, threads = 0))]
pub fn export_merl(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    path: PathBuf,
    threads: usize,
) -> PyResult<()> {
    use woven::export::merl::{check_isotropic, MerlBrdf};
    enum Source {
        Table(Arc<woven::table::Table>),
        Model(Arc<woven::Model>),
    }
    let brdf = if let Ok(t) = source.cast::<Table>() {
        let t = &t.get().inner;
        let material = t.material().ok_or_else(|| {
            PyValueError::new_err("the table records no material to check for isotropy")
        })?;
        check_isotropic(material).py_err()?;
        Source::Table(Arc::clone(t))
    } else if let Ok(m) = source.cast::<Model>() {
        let m = m.get();
        check_isotropic(&m.material.inner).py_err()?;
        Source::Model(Arc::clone(&m.inner))
    } else {
        return Err(PyTypeError::new_err(
            "`source` must be a woven.Table or a woven.Model",
        ));
    };
    crate::signals::until_interrupted(py, |stop| {
        let merl = match &brdf {
            Source::Table(t) => MerlBrdf::from_fn_threaded(|s, v| t.eval(s, v), threads, stop),
            Source::Model(m) => MerlBrdf::from_fn_threaded(|s, v| m.eval(s, v), threads, stop),
        }?;
        merl.save(&path)
    })?
    .py_err()
}

/// The user's table cache (shared with `woven render`) for one call, as the library's
/// [`Tables`](woven::table::cache::Tables); its notes (a damaged file rebuilt, a table that could
/// not be stored) become Python warnings.
pub(crate) struct UserTables {
    pub(crate) tables: woven::table::cache::Tables,
    notes: Arc<Mutex<Vec<String>>>,
}

impl UserTables {
    /// Over the user's cache folder.
    pub(crate) fn open() -> PyResult<UserTables> {
        let notes = Arc::new(Mutex::new(Vec::new()));
        let heard = Arc::clone(&notes);
        let tables =
            woven::table::cache::Tables::with_disk(woven::table::cache::Cache::user().py_err()?)
                .with_notes(move |m| {
                    heard
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push(m.into())
                });
        Ok(UserTables { tables, notes })
    }

    /// Tables for this call alone, kept nowhere.
    pub(crate) fn session() -> UserTables {
        UserTables {
            tables: woven::table::cache::Tables::default(),
            notes: Arc::new(Mutex::new(Vec::new())),
        }
    }

    /// Raises each note heard so far as a `UserWarning`.
    pub(crate) fn warn(&self, py: Python<'_>) -> PyResult<()> {
        let notes = std::mem::take(&mut *self.notes.lock().unwrap_or_else(|e| e.into_inner()));
        for note in notes {
            let message =
                std::ffi::CString::new(format!("woven table cache: {note}")).unwrap_or_default();
            PyErr::warn(
                py,
                &py.get_type::<pyo3::exceptions::PyUserWarning>(),
                &message,
                1,
            )?;
        }
        Ok(())
    }
}

/// The table of `material` on `grid` from the user's table cache, or built there, and the grid's
/// options: [`Table::cached`] and `woven.Surface`.
pub(crate) fn cached_table(
    py: Python<'_>,
    user: &mut UserTables,
    material: &woven::material::Material,
    wavelength_nm: f64,
    grid: &str,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Arc<woven::table::Table>, TableOptions)> {
    let model = py.detach(|| material.build(wavelength_nm)).py_err()?;
    let options = grid_options(grid, &model)?;
    let reporter = Reporter::new(progress)?;
    let tables = &mut user.tables;
    let table = crate::signals::until_interrupted(py, |stop| {
        let progress = Until {
            progress: &reporter,
            stop,
        };
        tables.table(material, wavelength_nm, &options, &|_| {}, &progress)
    })?;
    reporter.finish()?;
    let table = table.py_err()?;
    user.warn(py)?;
    Ok((table, options))
}

/// `surface` with what its resolved levels read, from `user`'s tables (the cache `woven render`
/// shares, or the session's own): its yarn's table averaged over the crown and the relief's ratio
/// table. A surface that does not resolve the relief is returned as it is.
pub(crate) fn prepared(
    py: Python<'_>,
    user: &mut UserTables,
    surface: woven::surface::WovenSurface,
    material: &woven::material::Material,
    wavelength_nm: f64,
    options: &TableOptions,
) -> PyResult<woven::surface::WovenSurface> {
    let tables = &mut user.tables;
    let surface = crate::signals::until_interrupted(py, |stop| {
        surface.prepared_from(tables, material, wavelength_nm, options, &|_| {}, stop)
    })?
    .py_err()?;
    user.warn(py)?;
    Ok(surface)
}
