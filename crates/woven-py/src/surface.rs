//! `woven.Surface`: the library's woven surface (`woven::surface`) — a weave pattern on a
//! surface's uv, dyes, yarn tilt, gaps and the footprint filter — evaluated, sampled and laid
//! out point by point, as `woven render` and the Mitsuba plugin use it.

use crate::arrays::{map_batch, Dirs, Numbers, FRACTIONS, UNIFORMS};
use crate::material::{material_arg, Material};
use crate::table::{cached_table, prepared, split_columns, Table, UserTables};
use crate::IntoPy;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::sync::Arc;
use woven::bsdf::{Bsdf, Transport};
use woven::color::Rgb;
use woven::fiber::DEFAULT_WAVELENGTH_NM;
use woven::material::Weave;
use woven::surface::{
    Detail, Irregularity, Lobe, PointBsdf, SurfacePoint, SurfaceSpec, Tilt, WovenSurface,
    FILTER_CELLS, MAX_LOBES,
};

/// A woven surface: what a woven material means at each point of a surface (the `woven`
/// material of `woven render` scenes and of the Mitsuba plugin, with the same parameters).
///
/// `Surface(material, ...)` tabulates the material's yarn alone on `woven render`'s grid, or
/// loads that table from the cache `woven render` shares; `Surface(table=t, ...)` uses a table
/// you built: as it is (the BRDF it was built for), or, with `pattern` or `weft_fraction`, as
/// the yarn of that weave (a table of a yarn alone, `Material.yarn_family()`).
///
/// Parameters: the surface keys of `woven.SURFACE_KEYS` (each key's default, valid range and
/// meaning; docs/python.md shows that table): `pattern` (a weave name replacing the material's
/// weave), `weft_fraction` (γ in place of the weave: the macro BRDF), `yarns_per_unit`
/// (pattern cells per unit of uv: a number or `(n_u, n_v)`), `weft_color` / `warp_color` (dyed
/// fiber albedos ρ0 per channel), `u_max_deg` (yarn tilt at the ends of each float, degrees),
/// `gap` (fraction of each cell between yarns), `detail` ("auto", "fibers", "yarns" or
/// "cloth": how finely the weave is resolved; see docs/render.md), `irregularity` (the spread
/// of the log of each yarn's dye along its length: a number or `(weft, warp)`; needs a
/// pattern), `irregularity_length` (pattern cells over which it changes) and `wavelength_nm`
/// (of the table built). A key left out (None) takes the library's default, the same as in
/// `woven render` scenes. Raises ValueError naming a parameter that is out of range.
///
/// Points: `uv` (N, 2) surface parameters; `footprint` (N, 4) the pixel's footprint in uv,
/// `(du/dx, dv/dx, du/dy, dv/dy)` (None: a point, no filtering). Directions in the surface's
/// frame (`z` the normal, `x` along u: the weft): `wi` toward the light, `wo` toward the viewer.
///
/// Arguments are validated as `woven.Table`'s: directions finite and unit length within
/// `woven.UNIT_TOLERANCE`, `uv` and `footprint` finite, per-point colours, `uc` and `u` in
/// [0, 1] (ValueError naming the argument, the row and its value), complex arrays refused
/// (TypeError). An empty batch gives empty results; a batch over `woven.BATCH_BUDGET_BYTES`
/// raises MemoryError before allocating; large batches run on all cores with the GIL released
/// and stop for Ctrl-C (KeyboardInterrupt).
#[pyclass(module = "woven", frozen)]
pub struct Surface {
    inner: Arc<WovenSurface>,
    material: Option<woven::material::Material>,
}

/// A number for both, or a pair (`pair` says of what); `None` when not given (or None).
fn pair_arg(obj: Option<&Bound<'_, PyAny>>, name: &str, pair: &str) -> PyResult<Option<[f64; 2]>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    if let Ok(n) = obj.extract::<f64>() {
        return Ok(Some([n, n]));
    }
    if let Ok(v) = obj.extract::<Vec<f64>>() {
        if let [a, b] = v[..] {
            return Ok(Some([a, b]));
        }
    }
    Err(PyValueError::new_err(format!(
        "`{name}` = {obj}: expected a number or a pair {pair}"
    )))
}

/// A colour argument: three numbers.
fn color_arg(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<Rgb>> {
    obj.map(|o| {
        o.extract::<[f64; 3]>().map(Rgb).map_err(|_| {
            PyValueError::new_err(format!("`{name}` = {o}: expected three numbers in [0, 1]"))
        })
    })
    .transpose()
}

/// The material with `pattern` or `weft_fraction` in place of its weave.
fn with_weave(
    mut material: woven::material::Material,
    pattern: Option<&str>,
    weft_fraction: Option<f64>,
) -> PyResult<woven::material::Material> {
    match (pattern, weft_fraction) {
        (Some(_), Some(_)) => Err(PyValueError::new_err(
            "give at most one of `pattern` and `weft_fraction`",
        )),
        (Some(p), None) => {
            material.weave = Some(Weave::named(p).py_err()?);
            Ok(material)
        }
        (None, Some(g)) => {
            if material.yarn.is_none() {
                return Err(PyValueError::new_err(
                    "`weft_fraction` needs a material with yarns ([yarn])",
                ));
            }
            if !(0.0..=1.0).contains(&g) {
                return Err(PyValueError::new_err(format!(
                    "`weft_fraction` = {g}: expected a fraction in [0, 1]"
                )));
            }
            material.weave = Some(Weave::WeftFraction(g));
            Ok(material)
        }
        (None, None) => Ok(material),
    }
}

/// The points of a call: uv (N, 2), footprints (N, 4) and dyes (N, 3), each also one row.
struct Points {
    uv: Dirs,
    footprint: Option<Dirs>,
    dyes: Dyes,
}

impl Points {
    fn extract(
        uv: &Bound<'_, PyAny>,
        footprint: Option<&Bound<'_, PyAny>>,
        weft_color: Option<&Bound<'_, PyAny>>,
        warp_color: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Points> {
        Ok(Points {
            uv: Dirs::extract_width(uv, "uv", 2)?,
            footprint: footprint
                .filter(|o| !o.is_none())
                .map(|o| Dirs::extract_width(o, "footprint", 4))
                .transpose()?,
            dyes: Dyes::extract(weft_color, warp_color)?,
        })
    }

    /// The row count of these arrays and `others` (each N or 1).
    fn rows(&self, others: &[(&str, usize)]) -> PyResult<usize> {
        let n = |d: &Option<Dirs>| d.as_ref().map_or(1, |d| d.n);
        let mut all = vec![
            ("uv", self.uv.n),
            ("footprint", n(&self.footprint)),
            ("weft_color", n(&self.dyes.weft)),
            ("warp_color", n(&self.dyes.warp)),
        ];
        all.extend_from_slice(others);
        rows(&all)
    }

    /// The surface's BSDF at point `i`, dyed anew where dyes were given.
    fn bsdf<'s>(&self, surface: &'s WovenSurface, i: usize) -> PointBsdf<'s> {
        let (u, v) = self.uv.get2(i);
        let footprint = self.footprint.as_ref().map_or([[0.0; 2]; 2], |f| {
            let r = f.get4(i);
            [[r[0], r[1]], [r[2], r[3]]]
        });
        let (weft, warp) = self.dyes.at(i);
        surface
            .at(&SurfacePoint {
                uv: [u, v],
                footprint,
            })
            .dyed(weft, warp)
    }
}

/// Per-point dyes: (N, 3) or (3,) colours.
struct Dyes {
    weft: Option<Dirs>,
    warp: Option<Dirs>,
}

impl Dyes {
    fn extract(weft: Option<&Bound<'_, PyAny>>, warp: Option<&Bound<'_, PyAny>>) -> PyResult<Dyes> {
        let get = |o: Option<&Bound<'_, PyAny>>, name| {
            o.filter(|o| !o.is_none())
                .map(|o| Dirs::extract_checked(o, name, 3, FRACTIONS))
                .transpose()
        };
        Ok(Dyes {
            weft: get(weft, "weft_color")?,
            warp: get(warp, "warp_color")?,
        })
    }

    fn at(&self, i: usize) -> (Option<Rgb>, Option<Rgb>) {
        let c = |d: &Option<Dirs>| {
            d.as_ref().map(|d| {
                let v = d.get(i);
                Rgb([v.x, v.y, v.z])
            })
        };
        (c(&self.weft), c(&self.warp))
    }
}

/// The common row count of broadcast arguments (each N rows or 1; N may be 0, an empty batch,
/// as `broadcast` has it).
fn rows(args: &[(&str, usize)]) -> PyResult<usize> {
    let n = args.iter().map(|a| a.1).find(|&k| k != 1).unwrap_or(1);
    for (name, k) in args {
        if *k != n && *k != 1 {
            return Err(PyValueError::new_err(format!(
                "`{name}` has {k} rows where others have {n}: expected {n} or 1"
            )));
        }
    }
    Ok(n)
}

/// A `mode` argument: "radiance" or "importance".
pub(crate) fn mode_arg(mode: &str) -> PyResult<Transport> {
    match mode {
        "radiance" => Ok(Transport::Radiance),
        "importance" => Ok(Transport::Importance),
        other => Err(PyValueError::new_err(format!(
            "`mode` = {other:?}: expected \"radiance\" (wo known, wi drawn) or \"importance\""
        ))),
    }
}

#[pymethods]
impl Surface {
    #[new]
    #[pyo3(signature = (material = None, *, table = None, pattern = None, weft_fraction = None,
        yarns_per_unit = None, weft_color = None, warp_color = None, u_max_deg = None, gap = None,
        detail = None, irregularity = None, irregularity_length = None, wavelength_nm = None,
        progress = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        material: Option<&Bound<'_, PyAny>>,
        table: Option<&Bound<'_, Table>>,
        pattern: Option<&str>,
        weft_fraction: Option<f64>,
        yarns_per_unit: Option<&Bound<'_, PyAny>>,
        weft_color: Option<&Bound<'_, PyAny>>,
        warp_color: Option<&Bound<'_, PyAny>>,
        u_max_deg: Option<f64>,
        gap: Option<f64>,
        detail: Option<&str>,
        irregularity: Option<&Bound<'_, PyAny>>,
        irregularity_length: Option<f64>,
        wavelength_nm: Option<f64>,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Surface> {
        let detail = detail.map(Detail::from_name).transpose().py_err()?;
        let spread = pair_arg(irregularity, "irregularity", "(weft, warp)")?;
        let yarns = pair_arg(yarns_per_unit, "yarns_per_unit", "(n_u, n_v)")?;
        let wavelength_nm = wavelength_nm.unwrap_or(DEFAULT_WAVELENGTH_NM);
        let (weft_color, warp_color) = (
            color_arg(weft_color, "weft_color")?,
            color_arg(warp_color, "warp_color")?,
        );
        // What is not given is the library's default (`SurfaceSpec::new`, the defaults of
        // SURFACE_KEYS): the material's own `[dye]` and `[yarn] u_max_deg`, and the rest as in
        // `woven render` scenes.
        let layout = |material| {
            let own = SurfaceSpec::new(material);
            SurfaceSpec {
                yarns_per_unit: yarns.unwrap_or(own.yarns_per_unit),
                weft_color: weft_color.or(own.weft_color),
                warp_color: warp_color.or(own.warp_color),
                u_max: u_max_deg.map_or(own.u_max, f64::to_radians),
                gap: gap.unwrap_or(own.gap),
                detail: detail.unwrap_or(own.detail),
                irregularity: Irregularity {
                    spread: spread.unwrap_or(own.irregularity.spread),
                    length: irregularity_length.unwrap_or(own.irregularity.length),
                },
                ..own
            }
        };
        let (spec, yarn, user) = match (material, table) {
            (Some(m), None) => {
                let m = with_weave(material_arg(m)?.inner, pattern, weft_fraction)?;
                let spec = layout(m);
                spec.validate().py_err()?;
                let mut user = UserTables::open()?;
                let (t, options) = cached_table(
                    py,
                    &mut user,
                    &spec.table_material(),
                    wavelength_nm,
                    "render",
                    progress,
                )?;
                (spec, t, Some((user, options)))
            }
            (None, Some(t)) => {
                let t = Arc::clone(&t.get().inner);
                if pattern.is_none() && weft_fraction.is_none() {
                    if warp_color.is_some()
                        || u_max_deg.is_some_and(|u| u != 0.0)
                        || gap.is_some_and(|g| g != 0.0)
                    {
                        return Err(PyValueError::new_err(
                            "`warp_color`, `u_max_deg` and `gap` need a weave: give `pattern` or `weft_fraction` with `table`",
                        ));
                    }
                    let surface = WovenSurface::whole(Arc::clone(&t), weft_color).py_err()?;
                    return Ok(Surface {
                        inner: Arc::new(surface),
                        material: t.material().cloned(),
                    });
                }
                let m = match t.material() {
                    Some(m) if m.weave.is_none() && m.yarn.is_some() => m.clone(),
                    _ => {
                        return Err(PyValueError::new_err(
                            "`pattern` or `weft_fraction` with `table` needs the table of a yarn alone (a material without [weave]: Material.yarn_family())",
                        ))
                    }
                };
                let m = with_weave(m, pattern, weft_fraction)?;
                (layout(m), t, None)
            }
            _ => {
                return Err(PyValueError::new_err(
                    "give exactly one of `material` and `table`",
                ))
            }
        };
        let base = Arc::clone(&yarn);
        let surface = WovenSurface::new(&spec, yarn).py_err()?;
        let yarn_material = spec.table_material();
        // A table of the caller's own: its crowned table and the relief's ratio are built from
        // it for this surface alone, never stored where another table's would be.
        let tables = match user {
            Some(user) => Some(user),
            None if surface.resolves_relief() => {
                let model = py.detach(|| yarn_material.build(wavelength_nm)).py_err()?;
                let options = woven::table::TableOptions::for_render(&model);
                let mut session = UserTables::session();
                session
                    .tables
                    .insert(&yarn_material, wavelength_nm, &options, base);
                Some((session, options))
            }
            None => None,
        };
        let surface = match tables {
            Some((mut user, options)) => prepared(
                py,
                &mut user,
                surface,
                &yarn_material,
                wavelength_nm,
                &options,
            )?,
            None => surface,
        };
        Ok(Surface {
            inner: Arc::new(surface),
            material: Some(spec.material),
        })
    }

    /// f(wi, wo) per channel, sr⁻¹ without the cosine: (N, 3). `weft_color` and `warp_color`
    /// (N, 3) or (3,), channels in [0, 1], if given, dye each point anew (a textured colour
    /// read at the points).
    #[pyo3(signature = (uv, wi, wo, footprint = None, weft_color = None, warp_color = None))]
    #[allow(clippy::too_many_arguments)]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        uv: &Bound<'py, PyAny>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
        footprint: Option<&Bound<'py, PyAny>>,
        weft_color: Option<&Bound<'py, PyAny>>,
        warp_color: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let points = Points::extract(uv, footprint, weft_color, warp_color)?;
        let (wi, wo) = (Dirs::extract(wi, "wi")?, Dirs::extract(wo, "wo")?);
        let n = points.rows(&[("wi", wi.n), ("wo", wo.n)])?;
        let s = &*self.inner;
        let out = map_batch::<3, _>(py, n, |i| points.bsdf(s, i).eval(wi.get(i), wo.get(i)).0)?;
        Ok(PyArray1::from_vec(py, out).reshape([n, 3])?.into_any())
    }

    /// The density (N,) with which `sample` draws the unknown direction: `wi` for `wo` in
    /// mode "radiance" (a camera path), `wo` for `wi` in mode "importance".
    #[pyo3(signature = (uv, wi, wo, footprint = None, mode = "radiance"))]
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        uv: &Bound<'py, PyAny>,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
        footprint: Option<&Bound<'py, PyAny>>,
        mode: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mode = mode_arg(mode)?;
        let points = Points::extract(uv, footprint, None, None)?;
        let (wi, wo) = (Dirs::extract(wi, "wi")?, Dirs::extract(wo, "wo")?);
        let n = points.rows(&[("wi", wi.n), ("wo", wo.n)])?;
        let s = &*self.inner;
        let out = map_batch::<1, _>(py, n, |i| {
            [points.bsdf(s, i).pdf(wi.get(i), wo.get(i), mode)]
        })?;
        Ok(PyArray1::from_vec(py, out).into_any())
    }

    /// Draws the unknown direction for `known` (`wo` in mode "radiance": returns `wi`; `wi` in
    /// mode "importance": returns `wo`) with `uc` (N,) choosing the lobe and `u` (N, 2) drawing
    /// within it: `(drawn (N, 3), f (N, 3), pdf (N,))`; a failed draw has all zeros (its zero
    /// vector is no direction: keep the draws with `pdf > 0` before passing them back). Dyes as
    /// in `eval`.
    #[pyo3(signature = (uv, known, uc, u, footprint = None, mode = "radiance", weft_color = None,
        warp_color = None))]
    #[allow(clippy::too_many_arguments)]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        uv: &Bound<'py, PyAny>,
        known: &Bound<'py, PyAny>,
        uc: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        footprint: Option<&Bound<'py, PyAny>>,
        mode: &str,
        weft_color: Option<&Bound<'py, PyAny>>,
        warp_color: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let mode = mode_arg(mode)?;
        let points = Points::extract(uv, footprint, weft_color, warp_color)?;
        let (known, uc, u) = (
            Dirs::extract(known, "known")?,
            Numbers::extract_checked(uc, "uc", UNIFORMS)?,
            Dirs::extract_checked(u, "u", 2, UNIFORMS)?,
        );
        let n = points.rows(&[("known", known.n), ("uc", uc.n), ("u", u.n)])?;
        let s = &*self.inner;
        let out = map_batch::<7, _>(py, n, |i| {
            let c = uc.get(if uc.n == 1 { 0 } else { i });
            let (a, b) = u.get2(i);
            match points.bsdf(s, i).sample(known.get(i), c, [a, b], mode) {
                Some(smp) => {
                    let d = match mode {
                        Transport::Radiance => smp.wi,
                        Transport::Importance => smp.wo,
                    };
                    [d.x, d.y, d.z, smp.f.0[0], smp.f.0[1], smp.f.0[2], smp.pdf]
                }
                None => [0.0; 7],
            }
        })?;
        split_columns(py, out, n, &[3, 3, 1])
    }

    /// The lobes mixed at each point, as four (N, MAX_LOBES) arrays: `warp` (1.0 for the warp,
    /// the table turned 90°; 0.0 for the weft), `float` (where a tilted yarn lies along its
    /// float: the fraction in [0, 1] at which the viewer's ray enters it; 2 for a whole float,
    /// averaged; −1 for a flat yarn), `weight` (0 past the point's
    /// last lobe) and `across` (a fibre-level lobe's place across its yarn, in [0, 1]; −1 for
    /// a yarn's or the cloth's averaged BRDF). `f = Σ weight · f_lobe`.
    #[pyo3(signature = (uv, footprint = None))]
    fn lobes<'py>(
        &self,
        py: Python<'py>,
        uv: &Bound<'py, PyAny>,
        footprint: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let points = Points::extract(uv, footprint, None, None)?;
        let n = points.rows(&[])?;
        let s = &*self.inner;
        let out = map_batch::<{ 4 * MAX_LOBES }, _>(py, n, |i| {
            let bsdf = points.bsdf(s, i);
            let mut row = [0.0; 4 * MAX_LOBES];
            for (k, l) in bsdf.mix().lobes().iter().enumerate() {
                row[k] = if l.warp { 1.0 } else { 0.0 };
                row[MAX_LOBES + k] = along(l.tilt);
                row[2 * MAX_LOBES + k] = l.weight;
                row[3 * MAX_LOBES + k] = l.point.map_or(-1.0, |p| p.across);
            }
            row
        })?;
        split_columns(py, out, n, &[MAX_LOBES; 4])
    }

    /// What the surface lays on its uv, for code that re-traces it (the Mitsuba plugin's
    /// Dr.Jit variants): a dict with `kind` ("flat", "whole", "macro" or "pattern"),
    /// `yarns_per_unit`, `u_max` (radians), `float_shape` (the floats' `(crest, flank)`, `(0, 0)`
    /// for a linear tilt), `gap`, `weft_fraction`, `filter_cells` (the
    /// footprint filter's start and end, in cells), `macro` (the macro BRDF's lobes: a list of
    /// `(warp, float, weight)`, `float` true for a whole tilted float), `albedos` (`{"weft": [(ρ0, ρ)] * 3, "warp": ...}`), and for a
    /// pattern `cells` (rows × cols, 1 where the weft is on top) and `floats` (rows × cols × 2:
    /// cells before in the float, float length; empty without a tilt).
    fn layout<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &*self.inner;
        let d = PyDict::new(py);
        let kind = if s.is_flat() {
            "flat"
        } else if s.pattern().is_some() {
            "pattern"
        } else if s.weft_fraction() == 1.0 && s.macro_lobes().lobes().len() == 1 {
            "whole"
        } else {
            "macro"
        };
        d.set_item("kind", kind)?;
        d.set_item("detail", s.detail().name())?;
        d.set_item("yarns_per_unit", s.yarns_per_unit().to_vec())?;
        d.set_item("u_max", s.u_max())?;
        d.set_item("float_shape", s.float_profile().shape())?;
        d.set_item("gap", s.gap())?;
        d.set_item("weft_fraction", s.weft_fraction())?;
        d.set_item("filter_cells", FILTER_CELLS.to_vec())?;
        let lobes: Vec<(bool, bool, f64)> = s
            .macro_lobes()
            .lobes()
            .iter()
            .map(|l: &Lobe| (l.warp, l.tilt == Tilt::Float, l.weight))
            .collect();
        d.set_item("macro", PyList::new(py, lobes)?)?;
        let albedos = PyDict::new(py);
        for (name, warp) in [("weft", false), ("warp", true)] {
            let a: Vec<(f64, f64)> = s
                .albedos(warp)
                .iter()
                .map(|a| (a.diffuse, a.interreflection))
                .collect();
            albedos.set_item(name, a)?;
        }
        d.set_item("albedos", albedos)?;
        if let Some(p) = s.pattern() {
            let cells: Vec<u8> = p.to_matrix().concat();
            d.set_item(
                "cells",
                PyArray1::from_vec(py, cells).reshape([p.rows(), p.cols()])?,
            )?;
            let floats: Vec<u16> = s.floats().iter().flat_map(|f| [f.before, f.len]).collect();
            let shape = if floats.is_empty() {
                [0, 0, 2]
            } else {
                [p.rows(), p.cols(), 2]
            };
            d.set_item("floats", PyArray1::from_vec(py, floats).reshape(shape)?)?;
        }
        Ok(d)
    }

    /// The yarn's table (or the whole table).
    #[getter]
    fn table(&self) -> Table {
        Table {
            inner: Arc::clone(self.inner.table()),
        }
    }

    /// The material laid on the surface (its weave the surface's), or None.
    #[getter]
    fn material(&self) -> Option<Material> {
        self.material.clone().map(|inner| Material { inner })
    }

    /// The yarn's table averaged over a whole tilted float (what a whole float reads in its
    /// family's frame, outside the resolved levels; built on first use), or None without a
    /// tilt.
    #[getter]
    fn float_table(&self, py: Python<'_>) -> Option<Table> {
        let inner = &self.inner;
        py.detach(|| inner.float_table().cloned())
            .map(|inner| Table { inner })
    }

    /// Whether the surface reads footprints (only patterns filter).
    #[getter]
    fn uses_footprint(&self) -> bool {
        self.inner.uses_footprint()
    }

    fn __repr__(&self) -> String {
        let s = &*self.inner;
        format!(
            "Surface(pattern={}, yarns_per_unit={:?}, u_max_deg={}, gap={}, weft_fraction={})",
            s.pattern().map_or("None".into(), |p| format!(
                "{:?}",
                p.name()
                    .unwrap_or_else(|| format!("{}x{}", p.rows(), p.cols()))
            )),
            s.yarns_per_unit(),
            s.u_max().to_degrees(),
            s.gap(),
            s.weft_fraction()
        )
    }
}

/// A lobe's place along its float as `Surface.lobes` reports it: −1 flat, the entry fraction
/// for a point of a tilted float, 2 for a whole float.
fn along(tilt: Tilt) -> f64 {
    match tilt {
        Tilt::Flat => -1.0,
        Tilt::Entering(t) => t,
        Tilt::Relief { lean, .. } => lean.tilt.0.asin(),
        Tilt::Float => 2.0,
    }
}
