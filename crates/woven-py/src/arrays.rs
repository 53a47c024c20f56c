//! NumPy arrays in and out: direction batches `(N, 3)` (or one direction `(3,)`), angle batches
//! `(N,)`, broadcasting of one against many, and batch loops that release the GIL, use all
//! cores for large batches and stop for Ctrl-C.
//!
//! Every argument array of the module is read here, so every entry point validates alike:
//! complex arrays are refused (TypeError), every number must be finite, directions unit length
//! within [`UNIT_TOLERANCE`], and colours, albedos and uniforms in their ranges (ValueError
//! naming the argument, the row and its value). No array a call makes — an argument's float64
//! copy or a result — may exceed [`BATCH_BUDGET_BYTES`] (MemoryError, checked before
//! allocating), and an allocation the system refuses is a MemoryError too.

use crate::signals::interruptible;
use numpy::{
    AllowTypeChange, PyArrayDescrMethods, PyArrayLikeDyn, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyMemoryError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use woven::Vec3;

/// Batches at least this long run on rayon's pool; shorter ones on the calling thread (a
/// thread hand-off costs microseconds, a table look-up a fraction of one).
pub const PARALLEL_MIN: usize = 4096;

/// Items per rayon task: big enough that scheduling is noise next to table look-ups.
const CHUNK: usize = 1024;

/// The most memory one array of a call may take, in bytes (2 GiB: 268,435,456 float64s, about
/// 89 million directions or 38 million rows of `Surface.sample`'s seven columns): an argument's
/// float64 copy or a result. A call over it raises MemoryError before allocating; split the
/// batch. `woven.BATCH_BUDGET_BYTES` in Python.
pub const BATCH_BUDGET_BYTES: usize = 2 << 30;

/// How far from 1 a direction's length may be: the tolerance of the library's own unit-length
/// assertions (`Microcylinder::eval`, the MERL export). Unit vectors rounded to float32 (length
/// within about 1e-7 of 1) pass; an unnormalised vector does not.
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// Items a batch on the calling thread computes between checks for signals.
const SIGNAL_ITEMS: usize = 64;

/// What the numbers of an argument must be, besides finite.
#[derive(Clone, Copy)]
pub enum Valid {
    /// Any finite number.
    Finite,
    /// Rows of three: unit vectors (length within [`UNIT_TOLERANCE`] of 1).
    Unit,
    /// Each number in `[lo, hi]`; `what` names them in errors ("uniforms", "colour channels").
    Range(f64, f64, &'static str),
}

/// Uniform random numbers for sampling: in [0, 1].
pub const UNIFORMS: Valid = Valid::Range(0.0, 1.0, "uniforms");

/// Colours (dyed fibre albedos per channel, linear RGB) and albedos: in [0, 1].
pub const FRACTIONS: Valid = Valid::Range(0.0, 1.0, "fractions");

/// A batch of rows read from an array-like: `n` rows (1 for a single row).
pub struct Dirs {
    data: Vec<f64>,
    /// Rows.
    pub n: usize,
    /// Whether the input was a single row of shape `(width,)`.
    pub single: bool,
}

impl Dirs {
    /// Reads `obj` (anything `numpy.asarray(obj, float)` accepts) as unit directions, (N, 3) or
    /// (3,); `name` is the argument's name in errors.
    pub fn extract(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Dirs> {
        Self::extract_checked(obj, name, 3, Valid::Unit)
    }

    /// Reads `obj` as rows of `width` finite numbers: shape (N, width) or (width,).
    pub fn extract_width(obj: &Bound<'_, PyAny>, name: &str, width: usize) -> PyResult<Dirs> {
        Self::extract_checked(obj, name, width, Valid::Finite)
    }

    /// Reads `obj` as rows of `width` numbers, (N, width) or (width,), each row `valid`.
    pub fn extract_checked(
        obj: &Bound<'_, PyAny>,
        name: &str,
        width: usize,
        valid: Valid,
    ) -> PyResult<Dirs> {
        let expected = format!("(N, {width}) or ({width},)");
        let array = array_like(obj, name, &expected)?;
        let shape = array.shape().to_vec();
        let single = match shape.as_slice() {
            [w] if *w == width => true,
            [_, w] if *w == width => false,
            _ => {
                let what = if matches!(valid, Valid::Unit) {
                    " (unit direction vectors)"
                } else {
                    ""
                };
                return Err(PyValueError::new_err(format!(
                    "`{name}` must have shape {expected}{what}, got {}",
                    shape_str(&shape)
                )));
            }
        };
        let n = if single { 1 } else { shape[0] };
        Ok(Dirs {
            data: read_rows(&array, name, n, width, single, valid)?,
            n,
            single,
        })
    }

    /// Row `i` of a width-2 batch (row 0 for a broadcast single row).
    #[inline]
    pub fn get2(&self, i: usize) -> (f64, f64) {
        let i = if self.n == 1 { 0 } else { i };
        (self.data[2 * i], self.data[2 * i + 1])
    }

    /// Row `i` of a (N, 4) array (row 0 of a single row).
    #[inline]
    pub fn get4(&self, i: usize) -> [f64; 4] {
        let i = if self.n == 1 { 0 } else { i };
        [
            self.data[4 * i],
            self.data[4 * i + 1],
            self.data[4 * i + 2],
            self.data[4 * i + 3],
        ]
    }

    /// Row `i` of a width-3 batch (row 0 for a broadcast single row).
    #[inline]
    pub fn get(&self, i: usize) -> Vec3 {
        let i = if self.n == 1 { 0 } else { i };
        Vec3::new(self.data[3 * i], self.data[3 * i + 1], self.data[3 * i + 2])
    }
}

/// A batch of numbers: `(N,)` or a scalar.
pub struct Numbers {
    data: Vec<f64>,
    /// Items (1 for a scalar).
    pub n: usize,
    /// Whether the input was a scalar.
    pub scalar: bool,
}

impl Numbers {
    /// Reads `obj` as a finite scalar or a 1-D array of finite numbers; `name` names it in
    /// errors.
    pub fn extract(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Numbers> {
        Self::extract_checked(obj, name, Valid::Finite)
    }

    /// Reads `obj` as a scalar or a 1-D array, each number `valid`.
    pub fn extract_checked(obj: &Bound<'_, PyAny>, name: &str, valid: Valid) -> PyResult<Numbers> {
        let array = array_like(obj, name, "(N,) or a scalar")?;
        let shape = array.shape().to_vec();
        if shape.len() > 1 {
            return Err(PyValueError::new_err(format!(
                "`{name}` must have shape (N,) or be a scalar, got {}",
                shape_str(&shape)
            )));
        }
        let scalar = shape.is_empty();
        let n = if scalar { 1 } else { shape[0] };
        Ok(Numbers {
            data: read_rows(&array, name, n, 1, scalar, valid)?,
            n,
            scalar,
        })
    }

    /// Item `i`.
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        self.data[i]
    }

    /// Reads `obj` as rows of `width` numbers, (C, width) or (width,), each row `valid`: the
    /// numbers row by row.
    pub fn extract_rows(
        obj: &Bound<'_, PyAny>,
        name: &str,
        width: usize,
        valid: Valid,
    ) -> PyResult<Vec<f64>> {
        Ok(Dirs::extract_checked(obj, name, width, valid)?.data)
    }

    /// The items.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }
}

/// A shape as Python writes it: `(4, 2)`, `(3,)`, `()`.
fn shape_str(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// `obj` as a float64 array: a `TypeError` for a complex one (whose imaginary parts a cast
/// would drop), a `ValueError` naming the argument and the shape expected for anything else
/// that is not numbers.
fn array_like<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    shape: &str,
) -> PyResult<PyArrayLikeDyn<'py, f64, AllowTypeChange>> {
    let not_numbers = |e: PyErr| {
        PyValueError::new_err(format!(
            "`{name}` must be an array of numbers of shape {shape}: {e}"
        ))
    };
    let array = obj
        .py()
        .import("numpy")?
        .call_method1("asarray", (obj,))
        .map_err(not_numbers)?;
    if let Ok(a) = array.cast::<PyUntypedArray>() {
        if a.dtype().kind() == b'c' {
            return Err(PyTypeError::new_err(format!(
                "`{name}` is a complex array ({}): expected real numbers of shape {shape}",
                a.dtype()
            )));
        }
    }
    array
        .extract::<PyArrayLikeDyn<'py, f64, AllowTypeChange>>()
        .map_err(not_numbers)
}

/// The numbers of `array` (`rows` rows of `width`; `single` for one row given alone) copied
/// within the batch budget, each row checked to be `valid`: a `ValueError` names the argument,
/// the row, its value and the valid range.
fn read_rows(
    array: &PyArrayLikeDyn<'_, f64, AllowTypeChange>,
    name: &str,
    rows: usize,
    width: usize,
    single: bool,
    valid: Valid,
) -> PyResult<Vec<f64>> {
    let mut data = budget_vec(&format!("`{name}`"), rows, width)?;
    data.extend(array.as_array().iter().copied());
    for (i, row) in data.chunks_exact(width).enumerate() {
        if let Some(expected) = invalid(row, valid) {
            let value = match row {
                [x] => x.to_string(),
                _ => format!("{row:?}"),
            };
            let at = if single {
                format!("`{name}` = {value}")
            } else {
                format!("`{name}`[{i}] = {value}")
            };
            return Err(PyValueError::new_err(format!("{at}: expected {expected}")));
        }
    }
    Ok(data)
}

/// What `row` should be, when it is not `valid`.
fn invalid(row: &[f64], valid: Valid) -> Option<String> {
    if row.iter().any(|x| !x.is_finite()) {
        return Some(match valid {
            Valid::Range(lo, hi, what) => format!("finite {what} in [{lo}, {hi}]"),
            _ => "finite numbers".into(),
        });
    }
    match valid {
        Valid::Finite => None,
        Valid::Unit => {
            let length = row.iter().map(|x| x * x).sum::<f64>().sqrt();
            ((length - 1.0).abs() > UNIT_TOLERANCE).then(|| {
                let tolerance = UNIT_TOLERANCE;
                format!(
                    "a unit vector, its length within {tolerance:e} of 1 (this one's is {length})"
                )
            })
        }
        Valid::Range(lo, hi, what) => {
            (!row.iter().all(|x| (lo..=hi).contains(x))).then(|| format!("{what} in [{lo}, {hi}]"))
        }
    }
}

const GIB: f64 = (1u64 << 30) as f64;

/// A `MemoryError` unless `rows` rows of `width` float64s (`what`: an argument, or "the result")
/// fit the batch budget; it names the budget and by how much they exceed it.
pub fn check_budget(what: &str, rows: usize, width: usize) -> PyResult<()> {
    let bytes = rows as f64 * width as f64 * 8.0;
    if bytes <= BATCH_BUDGET_BYTES as f64 {
        return Ok(());
    }
    let budget = BATCH_BUDGET_BYTES as f64;
    Err(PyMemoryError::new_err(format!(
        "{what}: {rows} rows × {width} float64s take {:.2} GiB, {:.2} GiB over the batch budget \
         of {} GiB an array (woven.BATCH_BUDGET_BYTES): split the batch",
        bytes / GIB,
        (bytes - budget) / GIB,
        budget / GIB
    )))
}

/// An empty vector with room for `rows` rows of `width` float64s of `what`: a `MemoryError` over
/// the batch budget ([`check_budget`]), or when the system cannot provide the memory.
pub fn budget_vec(what: &str, rows: usize, width: usize) -> PyResult<Vec<f64>> {
    check_budget(what, rows, width)?;
    let mut v = Vec::new();
    v.try_reserve_exact(rows * width).map_err(|e| {
        PyMemoryError::new_err(format!(
            "{what}: {rows} rows × {width} float64s ({:.2} GiB) could not be allocated: {e}",
            (rows * width * 8) as f64 / GIB
        ))
    })?;
    Ok(v)
}

/// The incidences of a directional albedo: `theta_i` (polar angles in `[0, π/2]`) and `phi_i`
/// (finite azimuths; 0 when `None`), radians, scalars or `(N,)` arrays broadcast together, with
/// their common length. A `ValueError` names the argument, the index and the valid range.
pub fn incidences(
    py: Python<'_>,
    theta_i: &Bound<'_, PyAny>,
    phi_i: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Numbers, Numbers, usize)> {
    let theta = Numbers::extract(theta_i, "theta_i")?;
    let phi = match phi_i {
        Some(p) => Numbers::extract(p, "phi_i")?,
        None => Numbers::extract(&0.0f64.into_pyobject(py)?.into_any(), "phi_i")?,
    };
    let n = broadcast(("theta_i", theta.n), ("phi_i", phi.n))?;
    for (i, &t) in theta.as_slice().iter().enumerate() {
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&t) {
            return Err(PyValueError::new_err(format!(
                "`theta_i`[{i}] = {t}: expected a polar angle in [0, π/2] radians"
            )));
        }
    }
    Ok((theta, phi, n))
}

/// The broadcast length of two batches (`1` broadcasts; an empty one against a single row is
/// empty), or a `ValueError` naming both.
pub fn broadcast(a: (&str, usize), b: (&str, usize)) -> PyResult<usize> {
    match (a.1, b.1) {
        (x, y) if x == y => Ok(x),
        (1, y) => Ok(y),
        (x, 1) => Ok(x),
        (x, y) => Err(PyValueError::new_err(format!(
            "`{}` has {x} rows and `{}` has {y}: expected the same number, or one of them a single direction",
            a.0, b.0
        ))),
    }
}

/// `f(i)` for `i in 0..n` into a vector of `K` values per item: on the calling thread for short
/// batches, on all cores with the GIL released from [`PARALLEL_MIN`] items. The result is within
/// the batch budget; a signal stops the batch ([`run_batch`]).
pub fn map_batch<const K: usize, F>(py: Python<'_>, n: usize, f: F) -> PyResult<Vec<f64>>
where
    F: Fn(usize) -> [f64; K] + Sync + Send,
{
    run_batch(py, n, PARALLEL_MIN, CHUNK, f)
}

/// `f(θi, φi)` for each incidence of `theta_i` and `phi_i` (radians; scalars or (N,) arrays,
/// broadcast, checked as [`incidences`] checks them), one task each ([`map_each`]): the values,
/// `N`, and whether both were scalars.
pub fn per_incidence<const K: usize, F>(
    py: Python<'_>,
    theta_i: &Bound<'_, PyAny>,
    phi_i: Option<&Bound<'_, PyAny>>,
    f: F,
) -> PyResult<(Vec<f64>, usize, bool)>
where
    F: Fn(f64, f64) -> [f64; K] + Sync + Send,
{
    let (theta, phi, n) = incidences(py, theta_i, phi_i)?;
    let at = |v: &Numbers, i: usize| v.get(if v.n == 1 { 0 } else { i });
    let out = map_each::<K, _>(py, n, |i| f(at(&theta, i), at(&phi, i)))?;
    Ok((out, n, theta.scalar && phi.scalar))
}

/// As [`map_batch`] for costly items (a quadrature each): each item its own rayon task, the GIL
/// released from one item up.
pub fn map_each<const K: usize, F>(py: Python<'_>, n: usize, f: F) -> PyResult<Vec<f64>>
where
    F: Fn(usize) -> [f64; K] + Sync + Send,
{
    run_batch(py, n, 1, 1, f)
}

/// `f(i)` for `i in 0..n`, `K` values each: below `parallel_min` items on the calling thread,
/// checking for signals every [`SIGNAL_ITEMS`] items; from it on rayon's pool in tasks of `chunk`
/// items, the GIL released, with the calling thread checking for signals ([`interruptible`](crate::signals::interruptible)).
/// A signal handler's exception (Ctrl-C: `KeyboardInterrupt`) stops the batch and is raised.
fn run_batch<const K: usize, F>(
    py: Python<'_>,
    n: usize,
    parallel_min: usize,
    chunk: usize,
    f: F,
) -> PyResult<Vec<f64>>
where
    F: Fn(usize) -> [f64; K] + Sync + Send,
{
    let mut out = budget_vec("the result", n, K)?;
    out.resize(n * K, 0.0);
    let stop = AtomicBool::new(false);
    let fill = |out: &mut [f64], start: usize| {
        for (j, slot) in out.chunks_exact_mut(K).enumerate() {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            slot.copy_from_slice(&f(start + j));
        }
    };
    if n < parallel_min {
        for (c, block) in out.chunks_mut(SIGNAL_ITEMS * K).enumerate() {
            py.check_signals()?;
            fill(block, c * SIGNAL_ITEMS);
        }
    } else {
        py.detach(|| {
            interruptible(&stop, || {
                out.par_chunks_mut(chunk * K)
                    .enumerate()
                    .for_each(|(c, block)| fill(block, c * chunk))
            })
        })?;
    }
    Ok(out)
}
