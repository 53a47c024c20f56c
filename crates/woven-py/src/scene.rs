//! `woven.portable_scene`: a `woven render` scene, checked by the renderer's library, as plain
//! Python data for another renderer (`python -m woven.mitsuba`, crates/woven-render's
//! `scene::portable`).

use crate::render::render_err;
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::Path;
use woven::keys::{KeySource, KeyValue, Keys};
use woven::Vec3;
use woven_render::scene::portable::{Portable, PortableGeometry, PortableLight, PortableMaterial};
use woven_render::scene::{CameraSpec, FilmOverrides, SceneDescription, SHOWCASE_SCENE};

/// The scene file `scene` (or `"showcase"`, the built-in one), checked as `woven render` checks
/// it, as plain data for another renderer: a dict with `camera` (`origin`, `target`, `up`,
/// `fov_deg` across the width), `inset` (None, or its `camera` and the `inner` and `outer`
/// rectangles on the film, each `((x, y), (width, height))`, and the `border`'s linear RGB),
/// `size`, `spp`, `seed`,
/// `sampler`, `max_depth` (None: no limit), `rr_depth`, `hide_emitters`, `shapes` (each a dict:
/// `key`, `material`, and `sphere` `(center, radius)` or `positions` (N, 3), `normals` (N, 3)
/// or None, `uvs` (N, 2) and `indices` (M, 3)), `materials` (by name: a dict with `type` and
/// its values; a woven material's `material` is its self-contained TOML and `keys` the other
/// surface keys), and `lights` (dicts with `type` and `sampling_weight`; a sky is its baked map,
/// `pixels` (height, width, 3) in `woven render`'s layout: row 0 the zenith, column x at
/// azimuth 2π (x + ½)/width from +x toward +y). Raises ValueError naming the scene's key that
/// another renderer cannot take.
///
/// `width` and `height` replace the film's (the inset keeps its place, in fractions of it).
#[pyfunction]
#[pyo3(signature = (scene, *, width = None, height = None))]
pub fn portable_scene<'py>(
    py: Python<'py>,
    scene: &str,
    width: Option<usize>,
    height: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let portable = if scene == "showcase" {
        SceneDescription::from_str(SHOWCASE_SCENE, "<showcase>", Path::new("."))
    } else {
        SceneDescription::from_path(Path::new(scene))
    }
    .and_then(|d| {
        d.with_overrides(&FilmOverrides {
            width,
            height,
            ..FilmOverrides::default()
        })
    })
    .and_then(|d| d.portable())
    .map_err(render_err)?;
    to_dict(py, &portable)
}

fn to_dict<'py>(py: Python<'py>, p: &Portable) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("camera", camera(py, &p.camera)?)?;
    match &p.inset {
        Some(i) => {
            let inset = PyDict::new(py);
            inset.set_item("camera", camera(py, &i.camera)?)?;
            inset.set_item("inner", i.inner)?;
            inset.set_item("outer", i.outer)?;
            // The border's linear colour, as `woven render` draws it.
            inset.set_item("border", woven_render::render::INSET_BORDER.0)?;
            d.set_item("inset", inset)?;
        }
        None => d.set_item("inset", py.None())?,
    }
    d.set_item("size", p.size)?;
    d.set_item("spp", p.spp)?;
    d.set_item("seed", p.seed)?;
    d.set_item("sampler", p.sampler)?;
    d.set_item("max_depth", p.max_depth)?;
    d.set_item("rr_depth", p.rr_depth)?;
    d.set_item("hide_emitters", p.hide_emitters)?;
    let shapes = PyList::empty(py);
    for s in &p.shapes {
        let shape = PyDict::new(py);
        shape.set_item("key", &s.key)?;
        shape.set_item("material", &s.material)?;
        match &s.geometry {
            PortableGeometry::Sphere { center, radius } => {
                shape.set_item("sphere", (xyz(*center), *radius))?;
            }
            PortableGeometry::Triangles(mesh) => {
                let flat = |v: &[Vec3]| v.iter().flat_map(|p| xyz(*p)).collect::<Vec<f64>>();
                let n = mesh.positions.len();
                let array = |values: Vec<f64>, cols: usize| {
                    PyArray1::from_vec(py, values).reshape([n, cols])
                };
                shape.set_item("positions", array(flat(&mesh.positions), 3)?)?;
                if mesh.normals.is_empty() {
                    shape.set_item("normals", py.None())?;
                } else {
                    shape.set_item("normals", array(flat(&mesh.normals), 3)?)?;
                }
                let uvs: Vec<f64> = if mesh.uvs.is_empty() {
                    vec![0.0; 2 * n]
                } else {
                    mesh.uvs.iter().flatten().copied().collect()
                };
                shape.set_item("uvs", array(uvs, 2)?)?;
                let idx: Vec<u32> = mesh.indices.iter().flatten().copied().collect();
                let m = mesh.indices.len();
                shape.set_item("indices", PyArray1::from_vec(py, idx).reshape([m, 3])?)?;
            }
        }
        shapes.append(shape)?;
    }
    d.set_item("shapes", shapes)?;
    let materials = PyDict::new(py);
    for (name, m) in &p.materials {
        materials.set_item(name, material(py, m)?)?;
    }
    d.set_item("materials", materials)?;
    let lights = PyList::empty(py);
    for (l, weight) in &p.lights {
        let light = self::light(py, l)?;
        light.set_item("sampling_weight", *weight)?;
        lights.append(light)?;
    }
    d.set_item("lights", lights)?;
    Ok(d)
}

fn xyz(v: Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn camera<'py>(py: Python<'py>, c: &CameraSpec) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("origin", xyz(c.origin))?;
    d.set_item("target", xyz(c.target))?;
    d.set_item("up", xyz(c.up))?;
    d.set_item("fov_deg", c.fov_deg)?;
    Ok(d)
}

fn material<'py>(py: Python<'py>, m: &PortableMaterial) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match m {
        PortableMaterial::Diffuse { reflectance } => {
            d.set_item("type", "diffuse")?;
            d.set_item("reflectance", reflectance.0)?;
        }
        PortableMaterial::Woven { material, keys } => {
            d.set_item("type", "woven")?;
            d.set_item("material", material)?;
            d.set_item("keys", keys_dict(py, keys)?)?;
        }
        PortableMaterial::Microcylinder { fabric } => {
            d.set_item("type", "microcylinder")?;
            d.set_item("material", fabric)?;
        }
        PortableMaterial::RoughPlastic {
            diffuse_reflectance,
            specular_reflectance,
            distribution,
            alpha,
            int_ior,
            ext_ior,
            nonlinear,
        } => {
            d.set_item("type", "roughplastic")?;
            d.set_item("diffuse_reflectance", diffuse_reflectance.0)?;
            d.set_item("specular_reflectance", specular_reflectance.0)?;
            d.set_item("distribution", *distribution)?;
            d.set_item("alpha", *alpha)?;
            d.set_item("int_ior", *int_ior)?;
            d.set_item("ext_ior", *ext_ior)?;
            d.set_item("nonlinear", *nonlinear)?;
        }
    }
    Ok(d)
}

/// Surface keys as Python values (what `woven.Surface` and the plugin read back).
fn keys_dict<'py>(py: Python<'py>, keys: &Keys) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for name in keys.names() {
        if let Some(v) = keys.get(&name) {
            d.set_item(name, value(py, &v)?)?;
        }
    }
    Ok(d)
}

fn value<'py>(py: Python<'py>, v: &KeyValue) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        KeyValue::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        KeyValue::Integer(i) => i.into_pyobject(py)?.into_any(),
        KeyValue::Float(x) => x.into_pyobject(py)?.into_any(),
        KeyValue::Text(t) => t.into_pyobject(py)?.into_any(),
        KeyValue::List(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(value(py, item)?)?;
            }
            list.into_any()
        }
        KeyValue::Table(entries) => {
            let d = PyDict::new(py);
            for (k, item) in entries {
                d.set_item(k, value(py, item)?)?;
            }
            d.into_any()
        }
    })
}

fn light<'py>(py: Python<'py>, l: &PortableLight) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match l {
        PortableLight::Point {
            position,
            intensity,
        } => {
            d.set_item("type", "point")?;
            d.set_item("position", xyz(*position))?;
            d.set_item("intensity", intensity.0)?;
        }
        PortableLight::Constant { radiance } => {
            d.set_item("type", "constant")?;
            d.set_item("radiance", radiance.0)?;
        }
        PortableLight::Map {
            width,
            height,
            pixels,
        } => {
            d.set_item("type", "map")?;
            let flat: Vec<f64> = pixels.iter().flat_map(|p| p.0).collect();
            let array = PyArray1::from_vec(py, flat).reshape([*height, *width, 3])?;
            d.set_item("pixels", array)?;
        }
        PortableLight::MapFile { path, scale } => {
            d.set_item("type", "map_file")?;
            d.set_item("path", path.display().to_string())?;
            d.set_item("scale", *scale)?;
        }
        PortableLight::Rectangle {
            corner,
            edge_u,
            edge_v,
            radiance,
        } => {
            d.set_item("type", "rectangle")?;
            d.set_item("corner", xyz(*corner))?;
            d.set_item("edge_u", xyz(*edge_u))?;
            d.set_item("edge_v", xyz(*edge_v))?;
            d.set_item("radiance", radiance.0)?;
        }
    }
    Ok(d)
}

/// Writes `pixels` (height, width, 3; linear RGB, row 0 at the top) to `path` as `woven render`
/// writes its images: a `.exr` linear float32, a `.png` sRGB through the display (exposure and
/// tone map) of the scene file `scene` (or `"showcase"`; None: the default display), written to
/// a temporary file and renamed into place. Raises ValueError for another extension or pixels
/// that are not finite, OSError when the file cannot be written.
#[pyfunction]
#[pyo3(signature = (pixels, path, scene = None))]
pub fn write_image(
    pixels: numpy::PyReadonlyArray3<'_, f64>,
    path: std::path::PathBuf,
    scene: Option<&str>,
) -> PyResult<()> {
    let shape = pixels.shape();
    let (height, width) = (shape[0], shape[1]);
    if shape[2] != 3 || width == 0 || height == 0 {
        return Err(PyValueError::new_err(format!(
            "`pixels` has shape {shape:?}: expected (height, width, 3), not empty"
        )));
    }
    let values = pixels.as_array();
    if values.iter().any(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(
            "`pixels` holds a value that is not finite: expected finite linear RGB",
        ));
    }
    let display = match scene {
        None => woven_render::tonemap::Display::default(),
        Some("showcase") => {
            SceneDescription::from_str(SHOWCASE_SCENE, "<showcase>", Path::new("."))
                .map_err(render_err)?
                .film
                .display
        }
        Some(file) => {
            SceneDescription::from_path(Path::new(file))
                .map_err(render_err)?
                .film
                .display
        }
    };
    let rgb: Vec<woven_render::Rgb> = values
        .as_standard_layout()
        .as_slice()
        .expect("a standard layout")
        .chunks_exact(3)
        .map(|c| woven_render::Rgb([c[0], c[1], c[2]]))
        .collect();
    let image = woven_render::render::Image {
        width,
        height,
        std_error: vec![woven_render::Rgb::BLACK; rgb.len()],
        pixels: rgb,
        invalid_samples: 0,
        spp: 0,
        seconds: 0.0,
        noisy: None,
    };
    woven_render::output::write(&image, &path, &display).map_err(render_err)
}
