//! `woven.standard_surface`: a woven surface on the standard lobes other renderers carry, and its
//! layout baked into textures (`woven_fit::standard`): what `woven.blender` builds Cycles
//! materials from.

use crate::surface::Surface;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use woven_fit::standard::textures::{LayoutImages, FACTOR_RANGE};
use woven_fit::standard::{project_surface, StandardFamily};

/// A woven surface on the standard lobes (a sheen over Lambert + anisotropic GGX along each
/// yarn family, fitted to the family's flat yarn at yarn level; colours fitted per channel), and
/// its layout as 16-bit PNG textures of one tile.
///
/// Returns a dict: `"weft"` and `"warp"` (each: `diffuse`, `specular`, `sheen` per channel,
/// `alpha` `[along, across]` the yarn, `sheen_roughness`, `rms_log` and `isotropic_rms_log`,
/// and `cycles` and `gltf`: the GGX lobe in each renderer's own parameters),
/// `yarns_per_unit`, `cells` (pattern cells the tile spans, `[u, v]`), `texels_per_cell`,
/// `factor_range` (a dye factor's texture value times it), `translucent` (where the surface
/// lets light through: what a point on a yarn transmits per channel, as a Lambertian
/// translucency, its holes passing light straight through; None for an opaque surface, its
/// holes black), and with `folder`, `files`: the
/// paths of `STEM-layout.png` (weft share R, warp share G) and `STEM-factors.png` (weft R,
/// warp G dye factors
/// over `factor_range`), each written whole. Raises ValueError naming `texels_per_cell` outside
/// [1, 64], OSError when a file cannot be written.
#[pyfunction]
#[pyo3(signature = (surface, folder = None, stem = "woven", texels_per_cell = 16))]
pub fn standard_surface<'py>(
    py: Python<'py>,
    surface: &Surface,
    folder: Option<PathBuf>,
    stem: &str,
    texels_per_cell: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let inner = surface.inner.clone();
    let (standard, images) = py
        .detach(|| {
            let standard = project_surface(&inner)?;
            let images = LayoutImages::bake(&inner, texels_per_cell)?;
            Ok::<_, woven_fit::FitError>((standard, images))
        })
        .map_err(crate::fit::fit_err)?;
    let d = PyDict::new(py);
    d.set_item("weft", family(py, &standard.weft)?)?;
    d.set_item("warp", family(py, &standard.warp)?)?;
    d.set_item("yarns_per_unit", standard.yarns_per_unit.to_vec())?;
    d.set_item("cells", images.cells.to_vec())?;
    d.set_item("texels_per_cell", images.texels_per_cell)?;
    d.set_item("factor_range", FACTOR_RANGE)?;
    d.set_item("translucent", standard.translucent.map(|t| t.to_vec()))?;
    if let Some(folder) = folder {
        let files = py
            .detach(|| images.write(&folder, stem))
            .map_err(crate::fit::fit_err)?;
        let f = PyDict::new(py);
        f.set_item("layout", files.layout)?;
        f.set_item("factors", files.factors)?;
        d.set_item("files", f)?;
    }
    Ok(d)
}

/// One family's dict.
fn family<'py>(py: Python<'py>, f: &StandardFamily) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("diffuse", f.diffuse.to_vec())?;
    d.set_item("specular", f.specular.to_vec())?;
    d.set_item("sheen", f.sheen.to_vec())?;
    d.set_item("alpha", f.lobes.alpha.to_vec())?;
    d.set_item("sheen_roughness", f.lobes.sheen_roughness)?;
    d.set_item("rms_log", f.rms_log)?;
    d.set_item("isotropic_rms_log", f.isotropic_rms_log)?;
    let c = f.cycles();
    let cycles = PyDict::new(py);
    cycles.set_item("roughness", c.roughness)?;
    cycles.set_item("anisotropy", c.anisotropy)?;
    cycles.set_item("rotation", c.rotation)?;
    cycles.set_item("alpha", c.alpha.to_vec())?;
    d.set_item("cycles", cycles)?;
    let g = f.gltf();
    let gltf = PyDict::new(py);
    gltf.set_item("roughness", g.roughness)?;
    gltf.set_item("anisotropy_strength", g.anisotropy_strength)?;
    gltf.set_item("along_yarn", g.along_yarn)?;
    d.set_item("gltf", gltf)?;
    Ok(d)
}

/// A family's standard lobes (a `"weft"` or `"warp"` dict of `woven.standard_surface`) per
/// channel at directions `wi`, `wo` ((N, 3) or (3,), unit, the yarn along `x`): sr⁻¹ without the
/// cosine, (N, 3). What a renderer given those parameters renders: the goniometer's yardstick.
/// Raises ValueError naming a missing key or a parameter out of range.
#[pyfunction]
pub fn standard_eval<'py>(
    py: Python<'py>,
    family: &Bound<'py, PyDict>,
    wi: &Bound<'py, PyAny>,
    wo: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    use numpy::PyArrayMethods;
    let get = |key: &str| -> PyResult<Bound<'py, PyAny>> {
        family.get_item(key)?.ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "`family` has no key `{key}`: expected a family dict of woven.standard_surface"
            ))
        })
    };
    let alpha: [f64; 2] = get("alpha")?.extract()?;
    let f = StandardFamily {
        lobes: woven_fit::projection::StandardLobes {
            diffuse: 0.0,
            specular: 1.0,
            alpha,
            sheen: 0.0,
            sheen_roughness: get("sheen_roughness")?.extract()?,
        },
        diffuse: get("diffuse")?.extract()?,
        specular: get("specular")?.extract()?,
        sheen: get("sheen")?.extract()?,
        rms_log: f64::NAN,
        isotropic_rms_log: f64::NAN,
    };
    f.eval(
        woven::Vec3::new(0.0, 0.0, 1.0),
        woven::Vec3::new(0.0, 0.0, 1.0),
    )
    .map_err(crate::fit::fit_err)?;
    let (wi, wo) = (
        crate::arrays::Dirs::extract(wi, "wi")?,
        crate::arrays::Dirs::extract(wo, "wo")?,
    );
    let n = wi.n.max(wo.n);
    if wi.n != wo.n && wi.n != 1 && wo.n != 1 {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "`wi` has {} rows and `wo` {}: expected as many, or one",
            wi.n, wo.n
        )));
    }
    let out = crate::arrays::map_batch(py, n, |k| {
        f.eval(wi.get(k), wo.get(k)).unwrap_or([f64::NAN; 3])
    })?;
    numpy::PyArray1::from_vec(py, out).reshape([n, 3])
}
