//! `woven.Material`, its parameter sections, `woven.Model` (the exact BRDF), `woven.presets`
//! and `woven.gonio`.

use crate::arrays::{broadcast, map_batch, per_incidence, Dirs, Numbers};
use crate::IntoPy;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyAttributeError, PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::PathBuf;
use std::sync::Arc;

/// A cloth material: a fiber surface, optionally arranged in yarns and a weave — the contents
/// of a woven material file (TOML, the keys of `woven materials --example`).
///
/// Make one with `Material.preset(name)`, `Material.from_toml(text)` or `Material.load(path)`.
/// Parameters read as attributes of the file's sections (`m.fiber.roughness`,
/// `m.yarn.lateral_length`, `m.weave.pattern`) with the file's names and units (radians);
/// `m.replace({"fiber.roughness": 0.1})` gives a changed copy, validated as a file is.
/// Materials are immutable, comparable (`==`) and picklable.
#[pyclass(module = "woven", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct Material {
    pub(crate) inner: woven::material::Material,
}

#[pymethods]
impl Material {
    /// The built-in preset `name` (see `woven.presets()`).
    ///
    /// Raises ValueError for an unknown name, listing the presets.
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Material> {
        Ok(Material {
            inner: woven::material::Material::preset(name).py_err()?,
        })
    }

    /// A material from the text of a material file; `origin` names it in errors.
    ///
    /// Raises ValueError for malformed TOML, unknown keys or out-of-range values, with the
    /// library's message (the key, its value and the valid range).
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<string>"))]
    fn from_toml(text: &str, origin: &str) -> PyResult<Material> {
        Ok(Material {
            inner: woven::material::Material::from_toml_str(text, origin).py_err()?,
        })
    }

    /// A material file (a WIF pattern path in it is relative to the file's folder).
    ///
    /// Raises OSError if the file cannot be read, ValueError if it is not a valid material.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Material> {
        Ok(Material {
            inner: woven::material::Material::from_path(&path).py_err()?,
        })
    }

    /// A preset name or a material file path, as the command line's `--material` takes.
    #[staticmethod]
    fn open(preset_or_path: &str) -> PyResult<Material> {
        Ok(Material {
            inner: woven::material::Material::from_preset_or_path(preset_or_path).py_err()?,
        })
    }

    /// The material file's text; `self_contained=True` writes a WIF pattern as its matrix.
    #[pyo3(signature = (self_contained = false))]
    fn to_toml(&self, self_contained: bool) -> String {
        if self_contained {
            self.inner.to_self_contained_toml_string()
        } else {
            self.inner.to_toml_string()
        }
    }

    /// The optional `name`.
    #[getter]
    fn name(&self) -> Option<String> {
        self.inner.name.clone()
    }

    /// The `[fiber]` section.
    #[getter]
    fn fiber(&self, py: Python<'_>) -> PyResult<Section> {
        Ok(self
            .section(py, "fiber")?
            .expect("a material always has a fiber"))
    }

    /// The `[yarn]` section, or None for a flat fiber surface.
    #[getter]
    fn yarn(&self, py: Python<'_>) -> PyResult<Option<Section>> {
        self.section(py, "yarn")
    }

    /// The `[weave]` section, or None (γ = 1: one yarn orientation, along x).
    #[getter]
    fn weave(&self, py: Python<'_>) -> PyResult<Option<Section>> {
        self.section(py, "weave")
    }

    /// γ, the visible fraction of weft (1 without a `[weave]` section).
    #[getter]
    fn weft_fraction(&self) -> f64 {
        self.inner.weft_fraction()
    }

    /// The material as nested dicts, with the file's keys.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        toml_to_py(py, &self.toml_value())
    }

    /// A copy with parameters changed: `changes` maps dotted keys (`"fiber.roughness"`,
    /// `"yarn.slope_std"`, `"weave.pattern"`) to new values; None removes a key (or a section).
    ///
    /// Raises ValueError, with the library's message, when the result is not a valid material.
    fn replace(&self, changes: &Bound<'_, PyDict>) -> PyResult<Material> {
        let mut root = self.toml_value();
        for (key, value) in changes.iter() {
            let key: String = key
                .extract()
                .map_err(|_| PyTypeError::new_err("`changes` keys must be strings"))?;
            let parts: Vec<&str> = key.split('.').collect();
            let (last, path) = parts.split_last().expect("split gives one part");
            let mut table = root.as_table_mut().expect("a material is a table");
            for part in path {
                table = table
                    .entry(part.to_string())
                    .or_insert_with(|| toml::Value::Table(Default::default()))
                    .as_table_mut()
                    .ok_or_else(|| {
                        PyValueError::new_err(format!("`{key}`: `{part}` is not a section"))
                    })?;
            }
            if value.is_none() {
                table.remove(*last);
            } else {
                table.insert(last.to_string(), py_to_toml(&value, &key)?);
            }
        }
        let text =
            toml::to_string(&root).map_err(|e| PyValueError::new_err(format!("`changes`: {e}")))?;
        Material::from_toml(&text, "<Material.replace>")
    }

    /// The weave pattern's cells, (rows, cols) booleans, True where the weft floats on top (row
    /// = weft pick along y, column = warp end along x); None without a pattern.
    fn pattern<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(woven::material::Weave::Pattern { pattern, .. }) = &self.inner.weave else {
            return Ok(None);
        };
        let (rows, cols) = (pattern.rows(), pattern.cols());
        let cells: Vec<bool> = (0..rows * cols)
            .map(|k| pattern.is_weft(k / cols, k % cols))
            .collect();
        Ok(Some(
            PyArray1::from_vec(py, cells)
                .reshape([rows, cols])?
                .into_any(),
        ))
    }

    /// The material's yarn alone (its weave removed, γ = 1): what a renderer tabulates and
    /// turns to the warp.
    fn yarn_family(&self) -> Material {
        Material {
            inner: self.inner.yarn_family(),
        }
    }

    /// The material prepared at `wavelength_nm` (nm): a `Model` that evaluates the exact BRDF.
    ///
    /// Raises ValueError for a wavelength out of range.
    #[pyo3(signature = (wavelength_nm = 550.0))]
    fn build(&self, py: Python<'_>, wavelength_nm: f64) -> PyResult<Model> {
        let inner = py.detach(|| self.inner.build(wavelength_nm)).py_err()?;
        Ok(Model {
            inner: Arc::new(inner),
            material: self.clone(),
            wavelength_nm,
        })
    }

    fn __repr__(&self) -> String {
        match &self.inner.name {
            Some(n) => format!("<woven.Material {n:?}>"),
            None => "<woven.Material (unnamed)>".to_string(),
        }
    }

    fn __str__(&self) -> String {
        self.inner.to_toml_string()
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let from_toml = py.get_type::<Material>().getattr("from_toml")?;
        let args = PyTuple::new(py, [self.inner.to_self_contained_toml_string()])?;
        PyTuple::new(py, [from_toml, args.into_any()])
    }
}

impl Material {
    /// The material file's contents as a TOML value (a WIF pattern inlined).
    fn toml_value(&self) -> toml::Value {
        toml::from_str(&self.inner.to_self_contained_toml_string())
            .expect("a material's own TOML parses")
    }

    fn section(&self, py: Python<'_>, name: &str) -> PyResult<Option<Section>> {
        let root = self.toml_value();
        let Some(value) = root.get(name) else {
            return Ok(None);
        };
        let dict = toml_to_py(py, value)?.cast_into::<PyDict>()?.unbind();
        Ok(Some(Section {
            name: name.to_string(),
            items: dict,
        }))
    }
}

/// One section of a material file (`[fiber]`, `[yarn]`, `[weave]`): its keys read as attributes
/// (`section.roughness`) or items (`section["roughness"]`), with the file's names and units.
/// Read-only: `Material.replace` makes changed materials.
#[pyclass(module = "woven", frozen)]
pub struct Section {
    name: String,
    items: Py<PyDict>,
}

#[pymethods]
impl Section {
    fn __getattr__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        match self.items.bind(py).get_item(key)? {
            Some(v) => Ok(v),
            None => Err(PyAttributeError::new_err(format!(
                "[{}] has no key `{key}`; it has: {}",
                self.name,
                self.key_list(py)?
            ))),
        }
    }

    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        self.items
            .bind(py)
            .get_item(key)?
            .ok_or_else(|| PyKeyError::new_err(key.to_string()))
    }

    fn __contains__(&self, py: Python<'_>, key: &str) -> PyResult<bool> {
        self.items.bind(py).contains(key)
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.items.bind(py).len()
    }

    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.items
            .bind(py)
            .keys()
            .into_any()
            .try_iter()
            .map(|i| i.into_any())
    }

    fn __dir__(&self, py: Python<'_>) -> Vec<String> {
        self.items
            .bind(py)
            .keys()
            .iter()
            .filter_map(|k| k.extract().ok())
            .collect()
    }

    /// The keys present in the file.
    fn keys<'py>(&self, py: Python<'py>) -> Bound<'py, PyList> {
        self.items.bind(py).keys()
    }

    /// A copy as a plain dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.items.bind(py).copy()
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!("<[{}] {}>", self.name, self.items.bind(py).repr()?))
    }
}

impl Section {
    fn key_list(&self, py: Python<'_>) -> PyResult<String> {
        Ok(self.__dir__(py).join(", "))
    }
}

/// A TOML value as a Python object (tables as dicts).
fn toml_to_py<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|v| toml_to_py(py, v))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let dict = PyDict::new(py);
            for (k, v) in t {
                dict.set_item(k, toml_to_py(py, v)?)?;
            }
            dict.into_any()
        }
    })
}

/// A Python value as a TOML value (for `Material.replace`); `key` names it in errors.
fn py_to_toml(value: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if value.is_instance_of::<PyInt>() {
        if let Ok(i) = value.extract::<i64>() {
            return Ok(toml::Value::Integer(i));
        }
    }
    if let Ok(s) = value.extract::<String>() {
        return Ok(toml::Value::String(s));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut t = toml::map::Map::new();
        for (k, v) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("`{key}`: keys must be strings")))?;
            let sub = py_to_toml(&v, &format!("{key}.{k}"))?;
            t.insert(k, sub);
        }
        return Ok(toml::Value::Table(t));
    }
    if let Ok(f) = value.extract::<f64>() {
        return Ok(toml::Value::Float(f));
    }
    if let Ok(items) = value.try_iter() {
        let list = items
            .map(|v| py_to_toml(&v?, key))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(list));
    }
    Err(PyTypeError::new_err(format!(
        "`{key}`: {} is not a number, string, bool, list or dict",
        value.get_type().name()?
    )))
}

/// A material prepared at one wavelength: the exact BRDF (`Material.build`).
///
/// `eval` takes about a microsecond per pair for flat fibers and the sateen, about a millisecond
/// for twisted or isotropic yarns (belt cloth, silk); a `Table` takes well under a microsecond.
/// Long calls (`eval` of a large batch, `albedo`) stop for Ctrl-C with KeyboardInterrupt.
#[pyclass(module = "woven", frozen)]
pub struct Model {
    pub(crate) inner: Arc<woven::Model>,
    pub(crate) material: Material,
    pub(crate) wavelength_nm: f64,
}

#[pymethods]
impl Model {
    /// The BRDF f(wi, wo) in sr⁻¹, without the cosine: `wi` toward the light, `wo` toward the
    /// viewer, unit vectors in the cloth's frame, shape (N, 3) or (3,) (one broadcasts against
    /// many). Returns shape (N,), or a float when both are (3,). 0 where either lies below the
    /// surface, unless the material lets light through (`transmits`): then `wo` below is the
    /// diffuse transmission through the yarns, and both below the back's reflection.
    ///
    /// Raises ValueError for a direction that is not finite or not unit length (within
    /// `woven.UNIT_TOLERANCE`), naming the argument, the row and its length; TypeError for a
    /// complex array; MemoryError for a batch over `woven.BATCH_BUDGET_BYTES`. Stops with
    /// KeyboardInterrupt on Ctrl-C.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let model = &*self.inner;
        map_pairs(py, wi, wo, |wi, wo| model.eval(wi, wo))
    }

    /// The directional albedo ∫ f cos θr dωr for light from polar angle `theta_i` and azimuth
    /// `phi_i` (radians; scalars or (N,) arrays, broadcast). Costs a hemisphere quadrature per
    /// angle (milliseconds to a second for cloth), computed on all cores.
    #[pyo3(signature = (theta_i, phi_i = None))]
    fn albedo<'py>(
        &self,
        py: Python<'py>,
        theta_i: &Bound<'py, PyAny>,
        phi_i: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let model = &*self.inner;
        // Each albedo is a quadrature: one task each.
        let (out, _, scalar) = per_incidence(py, theta_i, phi_i, |t, p| [model.albedo(t, p)])?;
        scalar_or_array(py, out, scalar)
    }

    /// The whole transmittance for light from `theta_i`, `phi_i` (as `albedo`): what passes
    /// straight between the yarns and what the yarns transmit; 0 unless the material lets light
    /// through (its `[weave] transmission`).
    #[pyo3(signature = (theta_i, phi_i = None))]
    fn transmittance<'py>(
        &self,
        py: Python<'py>,
        theta_i: &Bound<'py, PyAny>,
        phi_i: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let model = &*self.inner;
        let (out, _, scalar) =
            per_incidence(py, theta_i, phi_i, |t, p| [model.transmittance(t, p)])?;
        scalar_or_array(py, out, scalar)
    }

    /// Whether light passes through the cloth (its material's `[weave] transmission`).
    #[getter]
    fn transmits(&self) -> bool {
        self.inner.transmits()
    }

    /// The material the model was built from.
    #[getter]
    fn material(&self) -> Material {
        self.material.clone()
    }

    /// The wavelength, nm.
    #[getter]
    fn wavelength_nm(&self) -> f64 {
        self.wavelength_nm
    }

    fn __repr__(&self) -> String {
        format!(
            "<woven.Model {} at {} nm>",
            self.material.__repr__(),
            self.wavelength_nm
        )
    }
}

/// `f(wi, wo)` over the pairs of two direction arguments (N, 3) or (3,), broadcast: (N,), or a
/// float when both are (3,). The GIL is released for large batches ([`map_batch`]).
pub(crate) fn map_pairs<'py>(
    py: Python<'py>,
    wi: &Bound<'py, PyAny>,
    wo: &Bound<'py, PyAny>,
    f: impl Fn(woven::Vec3, woven::Vec3) -> f64 + Sync + Send,
) -> PyResult<Bound<'py, PyAny>> {
    let (wi, wo) = (Dirs::extract(wi, "wi")?, Dirs::extract(wo, "wo")?);
    let n = broadcast(("wi", wi.n), ("wo", wo.n))?;
    let out = map_batch::<1, _>(py, n, |i| [f(wi.get(i), wo.get(i))])?;
    scalar_or_array(py, out, wi.single && wo.single)
}

/// `values` as a float (when `scalar`) or a (N,) array.
pub(crate) fn scalar_or_array(
    py: Python<'_>,
    values: Vec<f64>,
    scalar: bool,
) -> PyResult<Bound<'_, PyAny>> {
    if scalar {
        Ok(PyFloat::new(py, values[0]).into_any())
    } else {
        Ok(PyArray1::from_vec(py, values).into_any())
    }
}

/// Unit directions from polar angles `theta` and azimuths `phi` (radians; scalars or (N,)
/// arrays, broadcast): (N, 3), or (3,) for two scalars — `(sin θ cos φ, sin θ sin φ, cos θ)`,
/// computed as the library (and `woven eval`) computes them.
#[pyfunction]
pub fn from_spherical<'py>(
    py: Python<'py>,
    theta: &Bound<'py, PyAny>,
    phi: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let (theta, phi) = (
        Numbers::extract(theta, "theta")?,
        Numbers::extract(phi, "phi")?,
    );
    let n = broadcast(("theta", theta.n), ("phi", phi.n))?;
    let at = |v: &Numbers, i: usize| v.get(if v.n == 1 { 0 } else { i });
    let out = map_batch::<3, _>(py, n, |i| {
        let d = woven::Vec3::from_spherical(at(&theta, i), at(&phi, i));
        [d.x, d.y, d.z]
    })?;
    let array = PyArray1::from_vec(py, out);
    if theta.scalar && phi.scalar {
        Ok(array.into_any())
    } else {
        Ok(array.reshape([n, 3])?.into_any())
    }
}

/// `(theta, phi)` of directions (N, 3) or (3,): polar angles in [0, π] and azimuths in (−π, π],
/// radians; (N,) arrays, or floats for one direction. The directions need not be unit length,
/// but must be finite.
#[pyfunction]
pub fn to_spherical<'py>(
    py: Python<'py>,
    d: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let d = Dirs::extract_width(d, "d", 3)?;
    let out = map_batch::<2, _>(py, d.n, |i| {
        let (t, p) = d.get(i).to_spherical();
        [t, p]
    })?;
    let (theta, phi): (Vec<f64>, Vec<f64>) = out.chunks_exact(2).map(|c| (c[0], c[1])).unzip();
    Ok((
        scalar_or_array(py, theta, d.single)?,
        scalar_or_array(py, phi, d.single)?,
    ))
}

/// The names of the built-in presets: the paper's, `filament-satin`, then those grounded in measured fabrics.
#[pyfunction]
pub fn presets() -> Vec<&'static str> {
    woven::material::Material::all_preset_names()
}

/// The paper's virtual goniometer (§4, Fig. 7): light and sensor 90° apart, the sample turned to
/// azimuth A and tilted by t, so θi = 45° + t, θr = 45° − t, φi = A, φr = A + 180°.
///
/// `material` is a Material (built at `wavelength_nm`), a Model, or a colour `woven.Bsdf` (a
/// `Microcylinder`: its luminance, Rec. 709, as `woven gonio` reads it); `azimuth_deg` and `tilt_deg`
/// are lists or arrays of degrees (tilts in (−45°, 45°); default: the paper's −42° to 42° by 3°).
/// Returns a dict of (M,) arrays over every azimuth (outer) × tilt (inner): `azimuth_deg`,
/// `tilt_deg`, `theta_i`, `theta_r` (radians) and `radiance` = f cos θi for unit irradiance,
/// sr⁻¹ — the numbers `woven gonio` prints.
#[pyfunction]
#[pyo3(signature = (material, azimuth_deg = None, tilt_deg = None, wavelength_nm = 550.0))]
pub fn gonio<'py>(
    py: Python<'py>,
    material: &Bound<'py, PyAny>,
    azimuth_deg: Option<&Bound<'py, PyAny>>,
    tilt_deg: Option<&Bound<'py, PyAny>>,
    wavelength_nm: f64,
) -> PyResult<Bound<'py, PyDict>> {
    enum Source {
        Model(Arc<woven::Model>),
        Colour(woven::catalog::Luminance<crate::bsdf::SharedRgb>),
    }
    let source = if let Ok(m) = material.cast::<Model>() {
        Source::Model(Arc::clone(&m.get().inner))
    } else if let Ok(m) = material.cast::<Material>() {
        Source::Model(m.get().build(py, wavelength_nm)?.inner)
    } else if let Some(b) = crate::bsdf::bsdf_arg(material) {
        // A colour BSDF (a microcylinder fabric) reads as its luminance, as in `woven gonio`.
        Source::Colour(woven::catalog::Luminance(b))
    } else {
        return Err(PyTypeError::new_err(
            "`material` must be a woven.Material, a woven.Model or a woven.Bsdf \
             (woven.Microcylinder, woven.Sheen, woven.RoughPlastic)",
        ));
    };
    let azimuths = match azimuth_deg {
        Some(a) => Numbers::extract(a, "azimuth_deg")?.as_slice().to_vec(),
        None => vec![0.0, 45.0, 90.0],
    };
    let tilts = match tilt_deg {
        Some(t) => Numbers::extract(t, "tilt_deg")?.as_slice().to_vec(),
        None => woven::gonio::paper_tilts_deg(),
    };
    for (name, list, lo, hi) in [
        ("azimuth_deg", &azimuths, -1e6, 1e6),
        ("tilt_deg", &tilts, -45.0, 45.0),
    ] {
        for (i, &x) in list.iter().enumerate() {
            let ok = if name == "tilt_deg" {
                x > lo && x < hi
            } else {
                x.is_finite()
            };
            if !ok {
                let expected = if name == "tilt_deg" {
                    "a tilt in (-45, 45) degrees (at ±45° light or sensor grazes the sample)"
                } else {
                    "a finite angle in degrees"
                };
                return Err(PyValueError::new_err(format!(
                    "`{name}`[{i}] = {x}: expected {expected}"
                )));
            }
        }
    }
    // One reading a task (a cloth reading takes milliseconds), on all cores, Ctrl-C heard.
    let grid = woven::gonio::sweep_grid(&azimuths, &tilts);
    let readings = crate::arrays::map_each::<3, _>(py, grid.len(), |i| {
        let (azimuth, tilt) = grid[i];
        let r = match &source {
            Source::Model(m) => woven::gonio::read(&**m, azimuth, tilt),
            Source::Colour(b) => woven::gonio::read(b, azimuth, tilt),
        };
        [r.theta_i, r.theta_r, r.radiance]
    })?;
    let out = PyDict::new(py);
    let column = |k: usize| {
        readings
            .iter()
            .skip(k)
            .step_by(3)
            .copied()
            .collect::<Vec<_>>()
    };
    let (azimuth, tilt): (Vec<f64>, Vec<f64>) = grid.into_iter().unzip();
    out.set_item("azimuth_deg", PyArray1::from_vec(py, azimuth))?;
    out.set_item("tilt_deg", PyArray1::from_vec(py, tilt))?;
    out.set_item("theta_i", PyArray1::from_vec(py, column(0)))?;
    out.set_item("theta_r", PyArray1::from_vec(py, column(1)))?;
    out.set_item("radiance", PyArray1::from_vec(py, column(2)))?;
    Ok(out)
}

/// A material given as a `Material`, a preset name or a file path.
pub(crate) fn material_arg(obj: &Bound<'_, PyAny>) -> PyResult<Material> {
    if let Ok(m) = obj.cast::<Material>() {
        return Ok(m.get().clone());
    }
    if let Ok(s) = obj.extract::<PathBuf>() {
        return Material::open(&s.to_string_lossy());
    }
    Err(PyTypeError::new_err(
        "`material` must be a woven.Material, a preset name or a material file path",
    ))
}
