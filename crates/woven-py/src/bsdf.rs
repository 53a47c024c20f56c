//! `woven.Bsdf` (a reflectance model in colour: the library's `Bsdf` trait with RGB values) and
//! the models behind it: `woven.Microcylinder` (the microcylinder fabrics of Sadeghi et al.
//! 2013), `woven.Sheen` and `woven.RoughPlastic` (the baselines). Every value is the library's;
//! this file converts arrays.

use crate::arrays::{broadcast, map_batch, per_incidence, Dirs, Numbers, UNIFORMS};
use crate::table::split_columns;
use crate::IntoPy;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::path::PathBuf;
use std::sync::Arc;
use woven::baseline::{Distribution, RoughPlasticParams, SheenParams};
use woven::bsdf::{BsdfSample, LobeFlags, Transport};
use woven::catalog::AnyMaterial;
use woven::color::Rgb;
use woven::microcylinder::{albedo_quadrature, ALBEDO_PANELS};
use woven::Vec3;

/// A colour BSDF shared between Python objects.
pub(crate) type SharedRgb = Arc<dyn woven::bsdf::Bsdf<Value = Rgb>>;

/// A reflectance model in colour: `eval`, `pdf`, `sample` and `albedo` of the library's `Bsdf`
/// trait, per RGB channel. Not made directly: `woven.Microcylinder`, `woven.Sheen` and
/// `woven.RoughPlastic` are its kinds.
///
/// Directions as everywhere in woven: `wi` toward the light, `wo` toward the viewer, unit
/// vectors (N, 3) or (3,) in the cloth's frame (z the normal, weft along x, warp along y), both
/// pointing away from the surface; f is in sr⁻¹ without the cosine, 0 below the surface.
/// Batches of 4096 pairs and more run on all cores with the GIL released, and stop for Ctrl-C
/// (KeyboardInterrupt). Arguments are validated as `woven.Table`'s: directions finite and unit
/// length within `woven.UNIT_TOLERANCE`, `uc` and `u` in [0, 1], complex arrays refused; an
/// empty batch gives empty results; a batch over `woven.BATCH_BUDGET_BYTES` raises MemoryError.
#[pyclass(module = "woven", name = "Bsdf", frozen, subclass)]
pub struct PyBsdf {
    pub(crate) inner: SharedRgb,
}

/// A transport mode by name (`Surface`'s convention).
fn mode_arg(mode: &str) -> PyResult<Transport> {
    match mode {
        "radiance" => Ok(Transport::Radiance),
        "importance" => Ok(Transport::Importance),
        other => Err(PyValueError::new_err(format!(
            "`mode` = {other:?}: expected \"radiance\" (wo known, wi drawn) or \"importance\" \
             (wi known, wo drawn)"
        ))),
    }
}

#[pymethods]
impl PyBsdf {
    /// f(wi, wo) per channel, sr⁻¹, without the cosine: (N, 3), or (3,) when both are (3,)
    /// (one direction broadcasts against many). 0 where either lies below the surface.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (wi, wo) = (Dirs::extract(wi, "wi")?, Dirs::extract(wo, "wo")?);
        let n = broadcast(("wi", wi.n), ("wo", wo.n))?;
        let b = &*self.inner;
        let out = map_batch::<3, _>(py, n, |i| b.eval(wi.get(i), wo.get(i)).0)?;
        rows_of_three(py, out, n, wi.single && wo.single)
    }

    /// The density, per unit solid angle, with which `sample` in `mode` draws the unknown
    /// direction of the pair: `wi` for a known `wo` in "radiance" (a camera path, the default),
    /// `wo` for a known `wi` in "importance". (N,), or a float when both are (3,).
    #[pyo3(signature = (wi, wo, mode = "radiance"))]
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
        mode: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mode = mode_arg(mode)?;
        let (wi, wo) = (Dirs::extract(wi, "wi")?, Dirs::extract(wo, "wo")?);
        let n = broadcast(("wi", wi.n), ("wo", wo.n))?;
        let b = &*self.inner;
        let out = map_batch::<1, _>(py, n, |i| [b.pdf(wi.get(i), wo.get(i), mode)])?;
        crate::material::scalar_or_array(py, out, wi.single && wo.single)
    }

    /// Draws the unknown direction for `known` (`wo` in mode "radiance": returns `wi`; `wi` in
    /// mode "importance": returns `wo`), `uc` (N,) or a scalar choosing the lobe and `u` (N, 2)
    /// or (2,) drawing within it: `(drawn (N, 3), f (N, 3), pdf (N,))`, f the value of the drawn
    /// pair and pdf the density `pdf` gives it. The Monte Carlo weight is f · cos θ_drawn / pdf.
    /// A failed draw (below the horizon, or `known` below the surface) has all zeros; its zero
    /// vector is no direction (`eval` and `pdf` refuse it): keep the draws with `pdf > 0`.
    #[pyo3(signature = (known, uc, u, mode = "radiance"))]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        known: &Bound<'py, PyAny>,
        uc: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        mode: &str,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let mode = mode_arg(mode)?;
        let (known, uc, u) = (
            Dirs::extract(known, "known")?,
            Numbers::extract_checked(uc, "uc", UNIFORMS)?,
            Dirs::extract_checked(u, "u", 2, UNIFORMS)?,
        );
        let n = broadcast(("known", known.n), ("u", u.n))?;
        let n = broadcast(("known and u", n), ("uc", uc.n))?;
        let b = &*self.inner;
        let out = map_batch::<7, _>(py, n, |i| {
            let c = uc.get(if uc.n == 1 { 0 } else { i });
            let (a, bb) = u.get2(i);
            match b.sample(known.get(i), c, [a, bb], mode) {
                Some(s) => {
                    let d = drawn(&s, mode);
                    [d.x, d.y, d.z, s.f.0[0], s.f.0[1], s.f.0[2], s.pdf]
                }
                None => [0.0; 7],
            }
        })?;
        split_columns(py, out, n, &[3, 3, 1])
    }

    /// The directional albedo ∫ f(wi, wo) cos θo dωo per channel for light from polar angle
    /// `theta_i` and azimuth `phi_i` (radians; scalars or (N,) arrays, broadcast), by the
    /// library's Gauss–Legendre rule over the hemisphere (`microcylinder::albedo_quadrature`,
    /// what `Microcylinder::albedo` computes): (N, 3), or (3,) for scalars.
    #[pyo3(signature = (theta_i, phi_i = None))]
    fn albedo<'py>(
        &self,
        py: Python<'py>,
        theta_i: &Bound<'py, PyAny>,
        phi_i: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let b = &*self.inner;
        // Each albedo is a quadrature: one task each.
        let (out, n, scalar) = per_incidence(py, theta_i, phi_i, |t, p| {
            let wi = Vec3::from_spherical(t, p);
            albedo_quadrature(|wo| b.eval(wi, wo), ALBEDO_PANELS).0
        })?;
        rows_of_three(py, out, n, scalar)
    }

    /// The kinds of scattering, as the library's lobe flags name them: a subset of
    /// "reflection", "glossy", "diffuse", "anisotropic".
    #[getter]
    fn lobes(&self) -> Vec<&'static str> {
        let f = self.inner.lobes();
        [
            (LobeFlags::REFLECTION, "reflection"),
            (LobeFlags::GLOSSY, "glossy"),
            (LobeFlags::DIFFUSE, "diffuse"),
            (LobeFlags::ANISOTROPIC, "anisotropic"),
        ]
        .into_iter()
        .filter(|(bit, _)| f.contains(*bit))
        .map(|(_, name)| name)
        .collect()
    }
}

/// The drawn direction of a sample in `mode`.
fn drawn<V>(s: &BsdfSample<V>, mode: Transport) -> Vec3 {
    match mode {
        Transport::Radiance => s.wi,
        Transport::Importance => s.wo,
    }
}

/// Values three per row as an (n, 3) array, or (3,) for one pair of single directions.
fn rows_of_three(
    py: Python<'_>,
    values: Vec<f64>,
    n: usize,
    single: bool,
) -> PyResult<Bound<'_, PyAny>> {
    let array = PyArray1::from_vec(py, values);
    if single {
        Ok(array.into_any())
    } else {
        Ok(array.reshape([n, 3])?.into_any())
    }
}

/// A microcylinder fabric (Sadeghi et al. 2013; docs/microcylinder.md): two kinds of thread as
/// dielectric cylinders, in colour. `Microcylinder(name)` takes a preset
/// (`Microcylinder.preset_names()`: the six fabrics of the paper's Table II) or the path of a
/// fabric file (TOML with `model = "microcylinder"`), as the command line's `--material` does;
/// `Microcylinder.from_toml(text)` reads a file's text. A woven material's name raises
/// ValueError (use `woven.Material`).
///
/// `eval(wi, wo)` is `woven eval --rgb`'s value: f per channel (N, 3), sr⁻¹, without the cosine,
/// with the library's energy guard; `sample` and `pdf` are the library's importance sampling.
#[pyclass(module = "woven", extends = PyBsdf, frozen)]
pub struct Microcylinder {
    inner: Arc<woven::microcylinder::Microcylinder>,
}

impl Microcylinder {
    fn wrap(m: woven::microcylinder::Microcylinder) -> PyClassInitializer<Microcylinder> {
        let inner = Arc::new(m);
        let shared: SharedRgb = Arc::clone(&inner) as SharedRgb;
        PyClassInitializer::from(PyBsdf { inner: shared }).add_subclass(Microcylinder { inner })
    }
}

#[pymethods]
impl Microcylinder {
    /// A preset's name (`Microcylinder.preset_names()`) or a fabric file's path.
    ///
    /// Raises ValueError for an unknown name (listing the presets), a woven material, or an
    /// invalid file (naming the key, its value and the valid range); OSError if a file cannot be
    /// read.
    #[new]
    fn new(py: Python<'_>, material: PathBuf) -> PyResult<PyClassInitializer<Microcylinder>> {
        let arg = material.to_string_lossy().into_owned();
        match py
            .detach(|| AnyMaterial::from_preset_or_path(&arg))
            .py_err()?
        {
            AnyMaterial::Microcylinder(m) => Ok(Self::wrap(m)),
            AnyMaterial::Woven(_) => Err(PyValueError::new_err(format!(
                "`material` = {arg:?} is a woven material, not a microcylinder fabric: open it \
                 with woven.Material.open (the microcylinder fabrics: {})",
                woven::microcylinder::Microcylinder::preset_names().join(", ")
            ))),
        }
    }

    /// A fabric from the text of a fabric file (`model = "microcylinder"`); `origin` names it in
    /// errors.
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<string>"))]
    fn from_toml(py: Python<'_>, text: &str, origin: &str) -> PyResult<Py<Microcylinder>> {
        let m = py
            .detach(|| woven::microcylinder::Microcylinder::from_toml_str(text, origin))
            .py_err()?;
        Py::new(py, Self::wrap(m))
    }

    /// The names of the built-in fabrics (the paper's Table II).
    #[staticmethod]
    fn preset_names() -> Vec<&'static str> {
        woven::microcylinder::Microcylinder::preset_names().to_vec()
    }

    /// The fabric's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// The number of tangents (quadrature nodes) along each thread's curve: (thread 1, thread 2).
    #[getter]
    fn tangent_counts(&self) -> (usize, usize) {
        let [a, b] = self.inner.tangent_counts();
        (a, b)
    }

    /// The printed model's f per channel without the energy guard (docs/microcylinder.md §6):
    /// as `eval`.
    fn eval_unguarded<'py>(
        &self,
        py: Python<'py>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (wi, wo) = (Dirs::extract(wi, "wi")?, Dirs::extract(wo, "wo")?);
        let n = broadcast(("wi", wi.n), ("wo", wo.n))?;
        let m = &*self.inner;
        let out = map_batch::<3, _>(py, n, |i| {
            let (a, b) = (wi.get(i), wo.get(i));
            if a.z <= 0.0 || b.z <= 0.0 {
                [0.0; 3]
            } else {
                m.eval_unguarded(a, b).0
            }
        })?;
        rows_of_three(py, out, n, wi.single && wo.single)
    }

    fn __repr__(&self) -> String {
        format!("<woven.Microcylinder {:?}>", self.inner.name)
    }
}

/// A preset name or a material file of either model, as the command line's `--material` reads
/// it: a `woven.Material` for a woven material, a `woven.Microcylinder` for a microcylinder
/// fabric (a `microcylinder-*` preset, or a file with `model = "microcylinder"`).
///
/// Raises ValueError for an unknown name (listing the presets of both kinds) or an invalid file,
/// OSError if a file cannot be read.
#[pyfunction]
pub fn open_material(py: Python<'_>, preset_or_path: PathBuf) -> PyResult<Py<PyAny>> {
    let arg = preset_or_path.to_string_lossy().into_owned();
    match py
        .detach(|| AnyMaterial::from_preset_or_path(&arg))
        .py_err()?
    {
        AnyMaterial::Microcylinder(m) => Ok(Py::new(py, Microcylinder::wrap(m))?.into_any()),
        AnyMaterial::Woven(m) => {
            Ok(Py::new(py, crate::material::Material { inner: m })?.into_any())
        }
    }
}

/// An RGB colour argument: a number (grey) or three numbers, each in [0, 1] (checked by the
/// library's constructor).
fn rgb_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Rgb> {
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(Rgb::grey(x));
    }
    let v = Numbers::extract(obj, name)?;
    match v.as_slice() {
        [r, g, b] if !v.scalar => Ok(Rgb([*r, *g, *b])),
        _ => Err(PyValueError::new_err(format!(
            "`{name}` must be a number or three numbers (r, g, b), got {} numbers",
            v.n
        ))),
    }
}

/// A baseline: the Charlie sheen (glTF `KHR_materials_sheen`, Estevez–Kulla) over a Lambertian
/// base scaled by the sheen's albedo (`woven::baseline::Sheen`). `diffuse` and `sheen_color`
/// are a number or (r, g, b), each in [0, 1]; `roughness` in [0.1, 1] (α = roughness²).
#[pyclass(module = "woven", extends = PyBsdf, frozen)]
pub struct Sheen {
    params: SheenParams,
}

#[pymethods]
impl Sheen {
    /// Raises ValueError naming a parameter out of range.
    #[new]
    #[pyo3(signature = (*, diffuse = None, sheen_color = None, roughness = None))]
    fn new(
        diffuse: Option<&Bound<'_, PyAny>>,
        sheen_color: Option<&Bound<'_, PyAny>>,
        roughness: Option<f64>,
    ) -> PyResult<PyClassInitializer<Sheen>> {
        let d = SheenParams::default();
        let params = SheenParams {
            diffuse: diffuse.map_or(Ok(d.diffuse), |x| rgb_arg(x, "diffuse"))?,
            sheen_color: sheen_color.map_or(Ok(d.sheen_color), |x| rgb_arg(x, "sheen_color"))?,
            roughness: roughness.unwrap_or(d.roughness),
        };
        let sheen = woven::baseline::Sheen::new(&params).py_err()?;
        Ok(PyClassInitializer::from(PyBsdf {
            inner: Arc::new(sheen),
        })
        .add_subclass(Sheen { params }))
    }

    fn __repr__(&self) -> String {
        let p = &self.params;
        format!(
            "<woven.Sheen diffuse={:?} sheen_color={:?} roughness={}>",
            p.diffuse.0, p.sheen_color.0, p.roughness
        )
    }
}

/// A baseline: Mitsuba 3's `roughplastic` (`woven::baseline::RoughPlastic`), a rough dielectric
/// coating over a diffuse base. Defaults are Mitsuba's: `distribution` "beckmann" (or "ggx"),
/// `alpha` 0.1 in [0.001, 1], `int_ior` 1.49 and `ext_ior` 1.000277 in [1, 4],
/// `diffuse_reflectance` 0.5 and `specular_reflectance` 1 (a number or (r, g, b) in [0, 1]),
/// `nonlinear` False.
#[pyclass(module = "woven", extends = PyBsdf, frozen)]
pub struct RoughPlastic {
    params: RoughPlasticParams,
}

#[pymethods]
impl RoughPlastic {
    /// Raises ValueError naming a parameter out of range.
    #[new]
    #[pyo3(signature = (*, distribution = "beckmann", alpha = None, int_ior = None,
        ext_ior = None, diffuse_reflectance = None, specular_reflectance = None,
        nonlinear = false))]
    fn new(
        distribution: &str,
        alpha: Option<f64>,
        int_ior: Option<f64>,
        ext_ior: Option<f64>,
        diffuse_reflectance: Option<&Bound<'_, PyAny>>,
        specular_reflectance: Option<&Bound<'_, PyAny>>,
        nonlinear: bool,
    ) -> PyResult<PyClassInitializer<RoughPlastic>> {
        let d = RoughPlasticParams::default();
        let distribution = Distribution::parse(distribution).ok_or_else(|| {
            PyValueError::new_err(format!(
                "`distribution` = {distribution:?}: expected {}",
                Distribution::NAMES
            ))
        })?;
        let params = RoughPlasticParams {
            distribution,
            alpha: alpha.unwrap_or(d.alpha),
            int_ior: int_ior.unwrap_or(d.int_ior),
            ext_ior: ext_ior.unwrap_or(d.ext_ior),
            diffuse_reflectance: diffuse_reflectance.map_or(Ok(d.diffuse_reflectance), |x| {
                rgb_arg(x, "diffuse_reflectance")
            })?,
            specular_reflectance: specular_reflectance.map_or(Ok(d.specular_reflectance), |x| {
                rgb_arg(x, "specular_reflectance")
            })?,
            nonlinear,
        };
        let plastic = woven::baseline::RoughPlastic::new(&params).py_err()?;
        Ok(PyClassInitializer::from(PyBsdf {
            inner: Arc::new(plastic),
        })
        .add_subclass(RoughPlastic { params }))
    }

    fn __repr__(&self) -> String {
        let p = &self.params;
        format!(
            "<woven.RoughPlastic {:?} alpha={} int_ior={} ext_ior={}>",
            p.distribution, p.alpha, p.int_ior, p.ext_ior
        )
    }
}

/// `obj` as a colour BSDF, if it is one.
pub(crate) fn bsdf_arg(obj: &Bound<'_, PyAny>) -> Option<SharedRgb> {
    obj.cast::<PyBsdf>()
        .ok()
        .map(|b| Arc::clone(&b.get().inner))
}
