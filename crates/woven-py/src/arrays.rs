//! NumPy arrays in and out: direction batches `(N, 3)` (or one direction `(3,)`), angle batches
//! `(N,)`, broadcasting of one against many, and batch loops that release the GIL and use all
//! cores for large batches.

use numpy::{AllowTypeChange, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::prelude::*;
use woven::Vec3;

/// Batches at least this long run on rayon's pool; shorter ones on the calling thread (a
/// thread hand-off costs microseconds, a table look-up a fraction of one).
pub const PARALLEL_MIN: usize = 4096;

/// Items per rayon task: big enough that scheduling is noise next to table look-ups.
const CHUNK: usize = 1024;

/// A batch of directions read from an array-like: `n` rows (1 for a single `(3,)` direction).
pub struct Dirs {
    data: Vec<f64>,
    /// Rows.
    pub n: usize,
    /// Whether the input was a single direction of shape `(3,)`.
    pub single: bool,
}

impl Dirs {
    /// Reads `obj` (anything `numpy.asarray(obj, float)` accepts) as directions; `name` is the
    /// argument's name in errors.
    pub fn extract(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Dirs> {
        Self::extract_width(obj, name, 3)
    }

    /// Reads `obj` as rows of `width` numbers: shape (N, width) or (width,).
    pub fn extract_width(obj: &Bound<'_, PyAny>, name: &str, width: usize) -> PyResult<Dirs> {
        let expected = format!("(N, {width}) or ({width},)");
        let array = array_like(obj, name, &expected)?;
        let shape = array.shape().to_vec();
        let single = match shape.as_slice() {
            [w] if *w == width => true,
            [_, w] if *w == width => false,
            _ => {
                let what = if width == 3 {
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
        let data: Vec<f64> = array.as_array().iter().copied().collect();
        Ok(Dirs {
            n: if single { 1 } else { shape[0] },
            data,
            single,
        })
    }

    /// Row `i` of a width-2 batch (row 0 for a broadcast single row).
    #[inline]
    pub fn get2(&self, i: usize) -> (f64, f64) {
        let i = if self.n == 1 { 0 } else { i };
        (self.data[2 * i], self.data[2 * i + 1])
    }

    /// Row `i` (row 0 for a broadcast single row).
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
    /// Reads `obj` as a scalar or a 1-D array; `name` names it in errors.
    pub fn extract(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Numbers> {
        let array = array_like(obj, name, "(N,) or a scalar")?;
        let shape = array.shape().to_vec();
        if shape.len() > 1 {
            return Err(PyValueError::new_err(format!(
                "`{name}` must have shape (N,) or be a scalar, got {}",
                shape_str(&shape)
            )));
        }
        let data: Vec<f64> = array.as_array().iter().copied().collect();
        Ok(Numbers {
            n: data.len(),
            scalar: shape.is_empty(),
            data,
        })
    }

    /// Item `i`.
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        self.data[i]
    }

    /// Reads `obj` as rows of `width` numbers, (C, width) or (width,): the numbers row by row.
    pub fn extract_rows(obj: &Bound<'_, PyAny>, name: &str, width: usize) -> PyResult<Vec<f64>> {
        Ok(Dirs::extract_width(obj, name, width)?.data)
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

/// `obj` as a float64 array, or a `ValueError` naming the argument and the shape expected.
fn array_like<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    shape: &str,
) -> PyResult<PyArrayLikeDyn<'py, f64, AllowTypeChange>> {
    obj.extract::<PyArrayLikeDyn<'py, f64, AllowTypeChange>>()
        .map_err(|e| {
            PyValueError::new_err(format!(
                "`{name}` must be an array of numbers of shape {shape}: {e}"
            ))
        })
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
    if let Some((i, p)) = phi
        .as_slice()
        .iter()
        .enumerate()
        .find(|(_, p)| !p.is_finite())
    {
        return Err(PyValueError::new_err(format!(
            "`phi_i`[{i}] = {p}: expected a finite azimuth in radians"
        )));
    }
    Ok((theta, phi, n))
}

/// The broadcast length of two batches (`1` broadcasts), or a `ValueError` naming both.
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

/// `f(i)` for `i in 0..n` into a vector of `K` values per item, with the GIL released and on all
/// cores when `n` is large.
pub fn map_batch<const K: usize, F>(py: Python<'_>, n: usize, f: F) -> Vec<f64>
where
    F: Fn(usize) -> [f64; K] + Sync + Send,
{
    let mut out = vec![0.0; n * K];
    let fill = |out: &mut [f64], start: usize| {
        for (j, slot) in out.chunks_exact_mut(K).enumerate() {
            slot.copy_from_slice(&f(start + j));
        }
    };
    if n < PARALLEL_MIN {
        fill(&mut out, 0);
    } else {
        py.detach(|| {
            out.par_chunks_mut(CHUNK * K)
                .enumerate()
                .for_each(|(c, chunk)| fill(chunk, c * CHUNK));
        });
    }
    out
}
