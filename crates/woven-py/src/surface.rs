//! `woven.Surface`: the library's woven surface (`woven::surface`) — a weave pattern on a
//! surface's uv, dyes, yarn tilt, gaps and the footprint filter — evaluated, sampled and laid
//! out point by point, as `woven render` and the Mitsuba plugin use it.

use crate::arrays::{map_batch, Dirs, Numbers, FRACTIONS, UNIFORMS};
use crate::keys::{key_error, key_value, keys_of};
use crate::material::Material;
use crate::table::{cached_table, prepared, split_columns, Table, UserTables};
use crate::IntoPy;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::sync::Arc;
use woven::bsdf::{Bsdf, Transport};
use woven::color::Rgb;
use woven::keys::{KeySource, KeyValue, Keys};
use woven::surface::{
    KeyedSurface, PointBsdf, Route, SurfacePoint, SurfaceSpec, Tilt, WovenSurface, MAX_LOBES,
};
use woven::table::TableOptions;

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
    pub(crate) inner: Arc<WovenSurface>,
    material: Option<woven::material::Material>,
    /// `footprint_filter`: off, calls' footprints are ignored (as `woven render` with the
    /// integrator's filter off).
    filter: bool,
    /// The face seen from behind, where light passes through a weave (`SurfaceSpec::back`).
    back: Option<Arc<WovenSurface>>,
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

    /// Point `i`: its uv and footprint (none: all zero).
    fn point(&self, i: usize) -> SurfacePoint {
        let (u, v) = self.uv.get2(i);
        let footprint = self.footprint.as_ref().map_or([[0.0; 2]; 2], |f| {
            let r = f.get4(i);
            [[r[0], r[1]], [r[2], r[3]]]
        });
        SurfacePoint {
            uv: [u, v],
            footprint,
        }
    }

    /// The surface's BSDF at point `i`, dyed anew where dyes were given.
    fn bsdf<'s>(&self, surface: &'s WovenSurface, i: usize) -> PointBsdf<'s> {
        let (weft, warp) = self.dyes.at(i);
        surface.at(&self.point(i)).dyed(weft, warp)
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

impl Surface {
    /// A material (a `woven.Material`, a preset's name or a file) with `keys`: its yarn's table
    /// from the cache `woven render` shares, or built there.
    fn of_material(
        py: Python<'_>,
        material: &Bound<'_, PyAny>,
        mut keys: Keys,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Surface> {
        let read = match material.cast::<Material>() {
            Ok(m) => SurfaceSpec::from_keys_on(m.get().inner.clone(), &keys),
            Err(_) => {
                // A path (str or os.PathLike) or a preset's name.
                let name = match material.extract::<std::path::PathBuf>() {
                    Ok(p) => KeyValue::Text(p.to_string_lossy().into_owned()),
                    Err(_) => key_value(material, "material")?,
                };
                keys.insert("material", name);
                SurfaceSpec::from_keys(&keys)
            }
        }
        .map_err(key_error)?;
        let mut user = UserTables::open()?;
        let (yarn, options) = cached_table(
            py,
            &mut user,
            &read.spec.table_material(),
            read.wavelength_nm,
            "render",
            progress,
        )?;
        Surface::laid(py, &read, yarn, Some((user, options)))
    }

    /// A table of the caller's: as it is (no `pattern` nor `weft_fraction`: the BRDF it was
    /// built for, dyed by `weft_color`), or as the yarn of the weave the keys give.
    fn on_table(py: Python<'_>, table: Arc<woven::table::Table>, keys: Keys) -> PyResult<Surface> {
        let names = keys.names();
        let weave = names.iter().any(|n| n == "pattern" || n == "weft_fraction");
        let Some(own) = table.material().cloned() else {
            if names.iter().any(|n| n != "footprint_filter") {
                return Err(PyValueError::new_err(format!(
                    "{}: the table records no material, so it takes no key but `footprint_filter`",
                    names.join(", ")
                )));
            }
            // Only `footprint_filter` is given: the library reads it, on any material.
            let any = woven::material::Material::preset("silk").py_err()?;
            let filter = SurfaceSpec::from_keys_on(any, &keys)
                .map_err(key_error)?
                .footprint_filter;
            let surface = WovenSurface::whole(Arc::clone(&table), None).py_err()?;
            return Ok(Surface {
                inner: Arc::new(surface),
                material: None,
                filter,
                back: None,
            });
        };
        if !weave {
            let extra: Vec<&String> = names
                .iter()
                .filter(|n| !matches!(n.as_str(), "weft_color" | "footprint_filter"))
                .collect();
            if !extra.is_empty() {
                return Err(PyValueError::new_err(format!(
                    "{} need a weave: give `pattern` or `weft_fraction` with `table` (a table alone takes `weft_color` and `footprint_filter`)",
                    extra.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
                )));
            }
            let read = SurfaceSpec::from_keys_on(own.clone(), &keys).map_err(key_error)?;
            let colour = read
                .given("weft_color")
                .then_some(read.spec.weft_color)
                .flatten();
            let surface = WovenSurface::whole(Arc::clone(&table), colour).py_err()?;
            return Ok(Surface {
                inner: Arc::new(surface),
                material: Some(own),
                filter: read.footprint_filter,
                back: None,
            });
        }
        if own.weave.is_some() || own.yarn.is_none() {
            return Err(PyValueError::new_err(
                "`pattern` or `weft_fraction` with `table` needs the table of a yarn alone (a material without [weave]: Material.yarn_family())",
            ));
        }
        let read = SurfaceSpec::from_keys_on(own, &keys).map_err(key_error)?;
        Surface::laid(py, &read, table, None)
    }

    /// The surface `read` describes on its yarn's table; `tables`: the cache the table came
    /// from and its grid (None: a table of the caller's own, whose crowned table and relief
    /// ratio are built for this surface alone, never stored where another table's would be).
    fn laid(
        py: Python<'_>,
        read: &KeyedSurface,
        yarn: Arc<woven::table::Table>,
        tables: Option<(UserTables, TableOptions)>,
    ) -> PyResult<Surface> {
        let spec = &read.spec;
        let front = WovenSurface::new(spec, Arc::clone(&yarn)).py_err()?;
        let yarn_material = spec.table_material();
        let mut tables = match tables {
            Some(t) => Some(t),
            None if front.resolves_relief() => {
                let model = py
                    .detach(|| yarn_material.build(read.wavelength_nm))
                    .py_err()?;
                let options = TableOptions::for_render(&model);
                let mut session = UserTables::session();
                session.tables.insert(
                    &yarn_material,
                    read.wavelength_nm,
                    &options,
                    Arc::clone(&yarn),
                );
                Some((session, options))
            }
            None => None,
        };
        // Each face's resolved levels (a crowned yarn, the relief's ratio) from the same cache.
        let mut prepare = |surface: WovenSurface| match tables.as_mut() {
            Some((user, options)) => prepared(
                py,
                user,
                surface,
                &yarn_material,
                read.wavelength_nm,
                options,
            ),
            None => Ok(surface),
        };
        let front = prepare(front)?;
        // A cloth that lets light through is seen from behind as its back face (the pattern's
        // complement), as `woven render` shades it.
        let back = match spec.transmission && spec.material.weave.is_some() {
            true => Some(Arc::new(prepare(
                WovenSurface::new(&spec.back(), yarn).py_err()?,
            )?)),
            false => None,
        };
        Ok(Surface {
            inner: Arc::new(front),
            material: Some(spec.material.clone()),
            filter: read.footprint_filter,
            back,
        })
    }

    /// The footprint a call passes, as the surface takes it: none with `footprint_filter` off.
    fn footprint<'a, 'py>(
        &self,
        footprint: Option<&'a Bound<'py, PyAny>>,
    ) -> Option<&'a Bound<'py, PyAny>> {
        footprint.filter(|_| self.filter)
    }
}

#[pymethods]
impl Surface {
    #[new]
    #[pyo3(signature = (material = None, *, table = None, progress = None, **keys))]
    fn new(
        py: Python<'_>,
        material: Option<&Bound<'_, PyAny>>,
        table: Option<&Bound<'_, Table>>,
        progress: Option<&Bound<'_, PyAny>>,
        keys: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Surface> {
        let keys = keys_of(keys)?;
        match (material.filter(|m| !m.is_none()), table) {
            (Some(m), None) => Surface::of_material(py, m, keys, progress),
            (None, Some(t)) => Surface::on_table(py, Arc::clone(&t.get().inner), keys),
            _ => Err(PyValueError::new_err(
                "give exactly one of `material` and `table`",
            )),
        }
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
        let points = Points::extract(uv, self.footprint(footprint), weft_color, warp_color)?;
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
        let points = Points::extract(uv, self.footprint(footprint), None, None)?;
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
        let points = Points::extract(uv, self.footprint(footprint), weft_color, warp_color)?;
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
        let points = Points::extract(uv, self.footprint(footprint), None, None)?;
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
    /// Dr.Jit variants): the library's `JitLayout` (woven::surface) as a dict, every rule
    /// evaluated in Rust: `version` (the layout's version, `woven.JIT_LAYOUT_VERSION`), `kind`
    /// (what each point traces: "flat", "whole", "macro" — a pattern at "cloth" too — or
    /// "pattern"), `detail`, `yarns_per_unit`, `u_max` (radians), `float` (the floats' profile,
    /// None without a tilt: `{"knots": [(t, ψ)], "rises": [...], "top": h}`, the tilt linear
    /// between knots, the height at `t` in the piece from knot `k`
    /// `rises[k] + ∫_{t_k}^t tan ψ − top`), `gap`, `weft_fraction`, `filter_cells`
    /// (the footprint filter's start and end, in cells), `macro` (the macro BRDF's lobes: a
    /// list of `(warp, float, weight)`, `float` true for a whole tilted float), `albedos`
    /// (`{"weft": [(ρ0, ρ)] * 3, "warp": ...}`), `dye_rule` (`(cap, slope, offset)`: a colour
    /// `c` per channel, NaN read as 0 and clamped to `[0, 1]`, dyes `ρ0 = min(c, cap)`,
    /// `ρ = clamp(slope c + offset, 0, 1)`; `cap` also bounds a `ρ0` the irregularity
    /// scales), `irregularity` (None where each yarn is dyed evenly, else
    /// `{"spread": [σ_weft, σ_warp], "length": ℓ}`), and for a pattern `cells` (rows × cols, 1 where
    /// the weft is on top) and `floats` (rows × cols × 2: cells before in the float, float
    /// length; empty without a tilt).
    fn layout<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let lay = self.inner.jit_layout();
        let d = PyDict::new(py);
        d.set_item("version", lay.version)?;
        d.set_item("kind", lay.kind.name())?;
        d.set_item("detail", lay.detail.name())?;
        d.set_item("yarns_per_unit", lay.yarns_per_unit.to_vec())?;
        d.set_item("u_max", lay.u_max)?;
        let float = match &lay.float {
            Some(f) => {
                let p = PyDict::new(py);
                p.set_item("knots", f.knots.clone())?;
                p.set_item("rises", f.rises.clone())?;
                p.set_item("top", f.top)?;
                p.into_any()
            }
            None => py.None().into_bound(py),
        };
        d.set_item("float", float)?;
        d.set_item("gap", lay.gap)?;
        d.set_item("weft_fraction", lay.weft_fraction)?;
        d.set_item("filter_cells", lay.filter_cells.to_vec())?;
        let lobes: Vec<(bool, bool, f64)> = lay
            .macro_lobes
            .iter()
            .map(|l| (l.warp, l.whole_float, l.weight))
            .collect();
        d.set_item("macro", PyList::new(py, lobes)?)?;
        let albedos = PyDict::new(py);
        for (name, a) in ["weft", "warp"].into_iter().zip(&lay.albedos) {
            let a: Vec<(f64, f64)> = a.iter().map(|a| (a.diffuse, a.interreflection)).collect();
            albedos.set_item(name, a)?;
        }
        d.set_item("albedos", albedos)?;
        let rule = lay.dye_rule;
        d.set_item("dye_rule", (rule.cap, rule.slope, rule.offset))?;
        let irregular = match &lay.irregularity {
            Some(i) => {
                let p = PyDict::new(py);
                p.set_item("spread", i.spread.to_vec())?;
                p.set_item("length", i.length)?;
                p.into_any()
            }
            None => py.None().into_bound(py),
        };
        d.set_item("irregularity", irregular)?;
        if let Some(first) = lay.cells.first() {
            let (rows, cols) = (lay.cells.len(), first.len());
            d.set_item(
                "cells",
                PyArray1::from_vec(py, lay.cells.concat()).reshape([rows, cols])?,
            )?;
            let floats: Vec<u16> = lay.floats.iter().flat_map(|f| [f.before, f.len]).collect();
            let shape = if floats.is_empty() {
                [0, 0, 2]
            } else {
                [rows, cols, 2]
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

    /// Why a JIT variant of the Mitsuba plugin hands this surface to the library lane by lane
    /// (the library's rule, `WovenSurface::route`), or None where it traces it in Dr.Jit.
    #[getter]
    fn route(&self) -> Option<String> {
        match self.inner.route() {
            Route::Traced => None,
            Route::Library(why) => Some(why.to_string()),
        }
    }

    /// `footprint_filter`: whether calls' footprints filter the weave (off: they are ignored).
    #[getter]
    fn footprint_filter(&self) -> bool {
        self.filter
    }

    /// Whether the surface reads footprints (only patterns filter).
    #[getter]
    fn uses_footprint(&self) -> bool {
        self.inner.uses_footprint()
    }

    /// Whether light passes between the yarns (``transmission`` on, and the yarns leave gaps).
    #[getter]
    fn transmits(&self) -> bool {
        self.inner.transmits()
    }

    /// The face seen from behind (the weave turned over: its pattern's complement, the weft's
    /// share ``1 − γ``), on the same yarn table, where the surface lets light through a weave;
    /// None otherwise. A renderer shades a hit from behind with it, its directions turned half
    /// a turn about the weft (x, y, z) → (x, −y, −z), as `woven render` does.
    #[getter]
    fn back(&self) -> Option<Surface> {
        let back = self.back.as_ref()?;
        Some(Surface {
            inner: Arc::clone(back),
            material: self.material.as_ref().map(|m| m.back()),
            filter: self.filter,
            back: None,
        })
    }

    /// The share (N,) of the light along ``d`` (the surface's frame, either side; (N, 3) or
    /// (3,)) that passes straight through at ``uv`` ((N, 2) or (2,)) seen with ``footprint``
    /// ((N, 4) or (4,); none: the yarn level): the open area ``O(d)`` at the cloth level, and at
    /// the yarn level ``O(d) / gap²`` in a hole between gapped yarns and 0 on a yarn; 0
    /// everywhere without ``transmission``.
    #[pyo3(signature = (uv, d, footprint = None))]
    fn pass_through<'py>(
        &self,
        py: Python<'py>,
        uv: &Bound<'py, PyAny>,
        d: &Bound<'py, PyAny>,
        footprint: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let points = Points::extract(uv, self.footprint(footprint), None, None)?;
        let d = Dirs::extract(d, "d")?;
        let n = points.rows(&[("d", d.n)])?;
        let s = &*self.inner;
        let out = map_batch::<1, _>(py, n, |i| [s.pass_through(&points.point(i), d.get(i))])?;
        Ok(PyArray1::from_vec(py, out).into_any())
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
