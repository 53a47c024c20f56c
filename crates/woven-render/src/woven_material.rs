//! The woven material: the Yang–Ikeuchi cloth BRDF (tabulated) on a surface, with the weave
//! pattern deciding, point by point, whether the weft or the warp lies on top.
//!
//! **Interface.** A [`WovenSpec`] says what to render; [`WovenMaterial::build`] prepares it once
//! (a [`TableCache`] shares tables between the materials of a scene and, with
//! [`TableCache::with_disk`], keeps them on disk between runs), and the result is a
//! [`SurfaceMaterial`].
//!
//! **What renders.** Every woven material is rendered from one table: that of its yarn alone
//! ([`Material::yarn_family`]: one yarn family along `x`, the surface's `u`), built with the
//! parts that make it dyeable ([`TableOptions::colour`]). A warp yarn is the same table turned 90°
//! about the normal (along `y`, the surface's `v`).
//! - A material with a weave *pattern*: at surface parameters `(u, v)` the pattern cell
//!   `(⌊v·n_v⌋, ⌊u·n_u⌋)`, `[n_u, n_v] = yarns_per_unit`, says which yarn family is on top, and
//!   that family's BRDF (and colour) shades the point. Far away, cells average to the paper's
//!   γ-mix (docs/spec.md §2.7).
//! - A material with a `weft_fraction` and no pattern: its macro BRDF, the γ-mix
//!   `γ f_weft + (1 − γ) f_warp` of the two turned look-ups, each in its yarn's colour.
//! - A flat fiber surface (no `[yarn]`): the exact model (a fraction of a microsecond per
//!   evaluation), sampled with its table.
//!
//! **Colour.** Dyed fibres have a coloured body and a white sheen: `weft_color` (and
//! `warp_color`) set the fiber's diffuse albedo `ρ0` per channel; the interreflection albedo `ρ`,
//! light that has bounced between fibres, follows in proportion (`ρ = ρ′ c / ρ0′` with the
//! material's own `ρ0′, ρ′`, at most 1; unchanged when `ρ0′ = 0`). The BRDF is affine in both
//! (docs/model.md §7), so one table serves every colour: [`Table::eval_dyed`]. The Fresnel sheen
//! stays white.
//!
//! **Sampling.** The table samples `v` for a given `s` (∝ `f(s, v) cos θ_v`); a camera path
//! knows the viewer `wo` and needs `wi`. So the draw swaps the roles — `wi` is drawn as the `v`
//! of `s = wo`, with the table's density `pdf(s = wo, v = wi)` — and the weight uses the true
//! `f(s = wi, v = wo)` (the paper normalization is not reciprocal). [`SurfaceMaterial::pdf`]
//! returns the same swapped density, so MIS weights use the density actually sampled with. The
//! macro BRDF draws the weft's or the warp's lobe with probabilities `γ` and `1 − γ` and reports
//! the mixture's density.

use crate::color::Rgb;
use crate::material::{MaterialSample, ShadingPoint, SurfaceMaterial};
use crate::Result;
use std::collections::HashMap;
use std::sync::Arc;
use woven::bsdf::Bsdf;
use woven::material::{Material, Weave};
use woven::table::cache::{Cache, Notice};
use woven::table::{Albedos, Table, TableOptions};
use woven::weave::Pattern;
use woven::{Model, Vec3};

/// The wavelength every woven table is built at, nm (the middle of the visible range, green).
pub const WAVELENGTH_NM: f64 = 550.0;

/// What to render: a material and how its weave maps onto the surface.
#[derive(Clone, Debug)]
pub struct WovenSpec {
    /// The material (its `weave` may hold the pattern the scene chose).
    pub material: Material,
    /// Pattern cells per unit of `u` and per unit of `v` (each > 0); unused without a pattern.
    pub yarns_per_unit: [f64; 2],
    /// The weft's dyed albedo per channel; `None`: the material's own (grey).
    pub weft_color: Option<Rgb>,
    /// The warp's dyed albedo per channel; `None`: the material's own (grey).
    pub warp_color: Option<Rgb>,
    /// The tilt of a yarn's axis out of the cloth plane at the ends of each float, radians
    /// (Irawan & Marschner's `u_max`): it runs linearly from `+u_max` where the yarn comes up
    /// to `−u_max` where it goes under; 0 (the default): flat yarns, the paper's model.
    pub u_max: f64,
    /// The fraction of each cell's width, in `[0, 1)`, between yarns: the crossing yarn below
    /// shows there, and where both families leave a gap, nothing (a hole; the renderer does
    /// not transmit, so it is black); 0 (the default): yarns fill their cells.
    pub gap: f64,
}

impl WovenSpec {
    /// `material` with one pattern cell per unit of uv, its own colours, flat yarns, no gaps.
    pub fn new(material: Material) -> WovenSpec {
        WovenSpec {
            material,
            yarns_per_unit: [1.0, 1.0],
            weft_color: None,
            warp_color: None,
            u_max: 0.0,
            gap: 0.0,
        }
    }
}

/// The table grid to build with.
#[derive(Clone, Debug, Default)]
pub enum TableGrid {
    /// [`TableOptions::for_render`]: seconds per preset, errors below a render's noise.
    #[default]
    Default,
    /// A given grid (tests and drafts use a coarse one); always built dyeable.
    Custom(TableOptions),
}

/// A tabulated woven material, ready to render.
pub struct WovenMaterial {
    layout: Layout,
    weft: [Albedos; 3],
    warp: [Albedos; 3],
    yarns_per_unit: [f64; 2],
    /// The yarn's tilt at the ends of a float, radians (0: flat yarns).
    u_max: f64,
    /// The fraction of each cell's width between yarns, in `[0, 1)`.
    gap: f64,
}

/// Tables built or loaded so far, by the self-contained TOML of the material tabulated (materials
/// that share a yarn share its table), and optionally a folder of tables kept between runs.
#[derive(Default)]
pub struct TableCache {
    tables: HashMap<String, Arc<Table>>,
    disk: Option<Cache>,
    /// Hears why a cached file was not used, or why a table could not be cached.
    note: Option<Note>,
}

/// A sink for the cache's notes, in words.
type Note = Box<dyn Fn(&str) + Send + Sync>;

impl TableCache {
    /// A cache that also keeps tables in `disk` (e.g. [`Cache::user`]): a table built once is
    /// loaded on later runs; a damaged or foreign file is rebuilt.
    pub fn with_disk(disk: Cache) -> TableCache {
        TableCache {
            disk: Some(disk),
            ..TableCache::default()
        }
    }

    /// `note` hears, in words, why a cached file was not used (it is rebuilt) and why a built
    /// table could not be cached (the render goes on).
    pub fn with_notes(mut self, note: impl Fn(&str) + Send + Sync + 'static) -> TableCache {
        self.note = Some(Box::new(note));
        self
    }

    /// The table of `material` on `options`: from memory, from disk, or built (`on_build` is
    /// called first, with the file it will be kept in, if any).
    fn table(
        &mut self,
        material: &Material,
        options: &TableOptions,
        on_build: &dyn Fn(Option<&std::path::Path>),
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Arc<Table>> {
        let key = format!("{options:?}\n{}", material.to_self_contained_toml_string());
        if let Some(t) = self.tables.get(&key) {
            return Ok(Arc::clone(t));
        }
        let build = || -> woven::Result<Table> {
            let model: Model = material.build(WAVELENGTH_NM)?;
            Table::build(&model, material, options, progress)
        };
        let table = match &self.disk {
            None => {
                on_build(None);
                build()?
            }
            Some(disk) => {
                let note = |m: String| {
                    if let Some(note) = &self.note {
                        note(&m);
                    }
                };
                disk.load_or_build(material, WAVELENGTH_NM, options, build, &|n| match n {
                    Notice::Building { path, reason } => {
                        if let Some(r) = reason {
                            note(format!("not using the cached table ({r})"));
                        }
                        on_build(Some(path));
                    }
                    Notice::NotStored { error } => {
                        note(format!("the table could not be cached ({error})"));
                    }
                    Notice::Loaded { .. } => {}
                })?
            }
        };
        let table = Arc::new(table);
        self.tables.insert(key, Arc::clone(&table));
        Ok(table)
    }
}

enum Layout {
    /// A flat fiber surface: the exact model, sampled with its table.
    Flat {
        model: Arc<Model>,
        table: Arc<Table>,
    },
    /// The macro BRDF: the γ-mix of the yarn table and the same turned to the warp.
    Macro {
        yarn: Arc<Table>,
        weft_fraction: f64,
    },
    /// One yarn family per pattern cell.
    Pattern {
        pattern: Pattern,
        yarn: Arc<Table>,
        /// The pattern's own weft fraction γ (for the macro BRDF far away).
        weft_fraction: f64,
        /// Per cell (row-major): the cell's place in the float of its top yarn, `(cells before
        /// it, float length)`; `(0, 0)` where the yarn never goes under (no tilt). Empty
        /// without a tilt.
        floats: Vec<(u16, u16)>,
    },
}

/// Footprints (in pattern cells, the larger side of the pixel's footprint) from which the
/// footprint filter starts blending toward the macro BRDF, and at which it is the macro BRDF.
pub const FILTER_CELLS: [f64; 2] = [0.5, 2.0];

/// Tilts at which the macro BRDF of tilted yarns is evaluated (a midpoint rule over the
/// uniform spread of tilts along floats).
const TILT_NODES: usize = 8;

/// The most lobes mixed at a point: one cell's, and the macro BRDF's (each family at every tilt
/// node on top, and flat where it shows in the other's gaps).
const MAX_LOBES: usize = 2 * (TILT_NODES + 1) + 1;

/// One yarn family's BRDF, tilted about the cross axis, with a weight.
#[derive(Clone, Copy, Debug, Default)]
struct Lobe {
    warp: bool,
    /// The yarn axis's tilt out of the cloth plane toward `+z`, radians.
    tilt: f64,
    weight: f64,
}

/// The lobes a point's BRDF mixes (`f = Σ weight · f_lobe`; the weights sum to at most 1, less
/// over the holes between gapped yarns).
struct Lobes {
    n: usize,
    lobes: [Lobe; MAX_LOBES],
}

impl Lobes {
    fn new() -> Lobes {
        Lobes {
            n: 0,
            lobes: [Lobe::default(); MAX_LOBES],
        }
    }

    /// Adds `weight` of a lobe, to the same lobe's weight when it is already there (a cell's
    /// yarn blended into the γ-mix is one of the mix's two yarns: two look-ups, not three).
    #[inline]
    fn push(&mut self, warp: bool, tilt: f64, weight: f64) {
        if weight > 0.0 {
            if let Some(l) = self.lobes[..self.n]
                .iter_mut()
                .find(|l| l.warp == warp && l.tilt == tilt)
            {
                l.weight += weight;
                return;
            }
            self.lobes[self.n] = Lobe { warp, tilt, weight };
            self.n += 1;
        }
    }

    fn iter(&self) -> impl Iterator<Item = &Lobe> {
        self.lobes[..self.n].iter()
    }

    fn total(&self) -> f64 {
        self.iter().map(|l| l.weight).sum()
    }
}

/// The runs of equal values along a periodic line: per element `(elements before it in its run,
/// run length)`; all `(0, 0)` when the whole line is one value (a run without ends).
fn runs(values: &[bool]) -> Vec<(u16, u16)> {
    let n = values.len();
    let mut out = vec![(0, 0); n];
    // A run's first element: its predecessor differs.
    let Some(s) = (0..n).find(|&i| values[i] != values[(i + n - 1) % n]) else {
        return out;
    };
    let mut j = 0;
    while j < n {
        let first = values[(s + j) % n];
        let mut len = 1;
        while j + len < n && values[(s + j + len) % n] == first {
            len += 1;
        }
        for k in 0..len {
            // Patterns have at most 4096 threads a side.
            out[(s + j + k) % n] = (k as u16, len as u16);
        }
        j += len;
    }
    out
}

/// Per cell of `pattern` (row-major): its place in the float of the yarn on top there — along
/// the row for the weft, along the column for the warp.
fn floats(pattern: &Pattern) -> Vec<(u16, u16)> {
    let (rows, cols) = (pattern.rows(), pattern.cols());
    let mut out = vec![(0, 0); rows * cols];
    for r in 0..rows {
        let line: Vec<bool> = (0..cols).map(|c| pattern.is_weft(r, c)).collect();
        for (c, run) in runs(&line).into_iter().enumerate() {
            if line[c] {
                out[r * cols + c] = run;
            }
        }
    }
    for c in 0..cols {
        let line: Vec<bool> = (0..rows).map(|r| !pattern.is_weft(r, c)).collect();
        for (r, run) in runs(&line).into_iter().enumerate() {
            if line[r] {
                out[r * cols + c] = run;
            }
        }
    }
    out
}

/// A direction in the frame of a yarn tilted by `(sin, cos)` of its tilt: the axis `x` turned
/// toward `+z`.
#[inline]
fn into_tilted(d: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(c * d.x + s * d.z, d.y, c * d.z - s * d.x)
}

/// Back from a tilted yarn's frame.
#[inline]
fn from_tilted(d: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z)
}

/// `x ↦ 3x² − 2x³` on `[0, 1]`, clamped.
#[inline]
fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

impl WovenMaterial {
    /// Tabulates `spec` (seconds per material on the default grid), reusing a table in `cache`
    /// when one of the same yarn exists there (or on its disk). `on_build` is called before a
    /// table is built; `progress` gets `(done, total)` rows as the build proceeds.
    ///
    /// # Errors
    /// An invalid material or grid ([`woven::Error`]).
    pub fn build(
        spec: &WovenSpec,
        grid: &TableGrid,
        cache: &mut TableCache,
        on_build: &dyn Fn(),
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<WovenMaterial> {
        // The yarn alone, weft along x (named as the material, for the cache's file name).
        let yarn_material = spec.material.yarn_family();
        let model = yarn_material.build(WAVELENGTH_NM)?;
        let options = match grid {
            TableGrid::Default => TableOptions::for_render(&model),
            TableGrid::Custom(o) => TableOptions { colour: true, ..*o },
        };
        let yarn = cache.table(&yarn_material, &options, &|_| on_build(), progress)?;
        let layout = if spec.material.yarn.is_none() {
            Layout::Flat {
                model: Arc::new(model),
                table: yarn,
            }
        } else {
            match &spec.material.weave {
                Some(Weave::Pattern { pattern, .. }) => Layout::Pattern {
                    pattern: pattern.clone(),
                    yarn,
                    weft_fraction: pattern.weft_fraction(),
                    floats: if spec.u_max > 0.0 {
                        floats(pattern)
                    } else {
                        Vec::new()
                    },
                },
                _ => Layout::Macro {
                    yarn,
                    weft_fraction: spec.material.weft_fraction(),
                },
            }
        };
        let own = Albedos::of(&spec.material);
        Ok(WovenMaterial {
            layout,
            weft: dyed(own, spec.weft_color),
            warp: dyed(own, spec.warp_color),
            yarns_per_unit: spec.yarns_per_unit,
            u_max: spec.u_max,
            gap: spec.gap,
        })
    }

    /// The weight of the macro BRDF at `at`: 0 while the pixel's footprint spans less than
    /// [`FILTER_CELLS`]`[0]` pattern cells, 1 from [`FILTER_CELLS`]`[1]` on, smooth between. The
    /// footprint's size is the longer side of its bounding box in uv, in cells.
    #[inline]
    fn macro_weight(&self, at: &ShadingPoint) -> f64 {
        let [a, b] = at.footprint;
        let cells = (self.yarns_per_unit[0] * (a[0].abs() + b[0].abs()))
            .max(self.yarns_per_unit[1] * (a[1].abs() + b[1].abs()));
        if cells > FILTER_CELLS[0] {
            smoothstep((cells - FILTER_CELLS[0]) / (FILTER_CELLS[1] - FILTER_CELLS[0]))
        } else {
            0.0
        }
    }

    /// The lobes of a macro BRDF with weft fraction `g`, scaled by `scale`: each family on top
    /// over `(1 − gap)` of its cells' width (at tilts spread uniformly over `±u_max`), and
    /// seen flat in the other family's gaps where it is not itself in a gap.
    fn push_macro(&self, lobes: &mut Lobes, g: f64, scale: f64) {
        let gap = self.gap;
        if gap == 0.0 && self.u_max == 0.0 {
            lobes.push(false, 0.0, scale * g);
            lobes.push(true, 0.0, scale * (1.0 - g));
            return;
        }
        let top = [(1.0 - gap) * g, (1.0 - gap) * (1.0 - g)];
        let below = [gap * (1.0 - gap) * (1.0 - g), gap * (1.0 - gap) * g];
        for (k, warp) in [false, true].into_iter().enumerate() {
            if self.u_max == 0.0 {
                lobes.push(warp, 0.0, scale * (top[k] + below[k]));
            } else {
                for i in 0..TILT_NODES {
                    let t = (2 * i + 1) as f64 / TILT_NODES as f64 - 1.0;
                    lobes.push(warp, self.u_max * t, scale * top[k] / TILT_NODES as f64);
                }
                lobes.push(warp, 0.0, scale * below[k]);
            }
        }
    }

    /// The lobe of the pattern cell at `at`, with weight `scale`: the yarn on top, tilted by
    /// its place along its float; in a gap across it, the crossing yarn below (flat); in a
    /// gap of both, nothing.
    fn push_cell(
        &self,
        lobes: &mut Lobes,
        pattern: &Pattern,
        floats: &[(u16, u16)],
        at: &ShadingPoint,
        scale: f64,
    ) {
        let (u, v) = (
            at.uv[0] * self.yarns_per_unit[0],
            at.uv[1] * self.yarns_per_unit[1],
        );
        if !(u.is_finite() && v.is_finite()) {
            lobes.push(false, 0.0, scale);
            return;
        }
        let (rows, cols) = (pattern.rows(), pattern.cols());
        // As Pattern::weft_at_uv(u / cols, v / rows) locates the cell.
        let (x, y) = (u / cols as f64 * cols as f64, v / rows as f64 * rows as f64);
        let cell = |t: f64, n: usize| (t.floor().rem_euclid(n as f64) as usize).min(n - 1);
        let (row, col) = (cell(y, rows), cell(x, cols));
        let weft = pattern.is_weft(row, col);
        if self.gap == 0.0 && self.u_max == 0.0 {
            lobes.push(!weft, 0.0, scale);
            return;
        }
        let (fu, fv) = (x - x.floor(), y - y.floor());
        // A yarn covers the middle (1 − gap) of the cell across its axis: the weft spans v,
        // the warp spans u.
        let half = 0.5 * (1.0 - self.gap);
        let covers = |warp: bool| ((if warp { fu } else { fv }) - 0.5).abs() < half;
        if covers(!weft) {
            let tilt = match floats.get(row * cols + col) {
                Some(&(before, len)) if len > 0 => {
                    let along = if weft { fu } else { fv };
                    self.u_max * (1.0 - 2.0 * (before as f64 + along) / len as f64)
                }
                _ => 0.0,
            };
            lobes.push(!weft, tilt, scale);
        } else if covers(weft) {
            lobes.push(weft, 0.0, scale);
        }
    }

    /// The lobes mixed at `at` (yarn layouts).
    fn lobes(&self, at: &ShadingPoint) -> Lobes {
        let mut lobes = Lobes::new();
        match &self.layout {
            Layout::Flat { .. } => {}
            Layout::Macro { weft_fraction, .. } => self.push_macro(&mut lobes, *weft_fraction, 1.0),
            Layout::Pattern {
                pattern,
                weft_fraction,
                floats,
                ..
            } => {
                let w = self.macro_weight(at);
                if w < 1.0 {
                    self.push_cell(&mut lobes, pattern, floats, at, 1.0 - w);
                }
                if w > 0.0 {
                    self.push_macro(&mut lobes, *weft_fraction, w);
                }
            }
        }
        lobes
    }

    /// One lobe's BRDF per channel: the weft, or the warp (turned), in its tilted frame. A
    /// tilted yarn's BRDF is taken per unit of cloth area: `f′ cos θ′i cos θ′o / (cos θi cos θo
    /// cos ψ)`, its own cosines over the cloth's, and its area `1/cos ψ` per unit of cloth.
    #[inline]
    fn lobe_eval(&self, yarn: &Table, lobe: &Lobe, wi: Vec3, wo: Vec3) -> Rgb {
        let (wi, wo, albedos) = if lobe.warp {
            (to_warp(wi), to_warp(wo), &self.warp)
        } else {
            (wi, wo, &self.weft)
        };
        if lobe.tilt == 0.0 {
            return Rgb(yarn.eval_dyed(wi, wo, albedos));
        }
        let sc = lobe.tilt.sin_cos();
        let (ti, to) = (into_tilted(wi, sc), into_tilted(wo, sc));
        if ti.z <= 0.0 || to.z <= 0.0 {
            return Rgb::BLACK;
        }
        Rgb(yarn.eval_dyed(ti, to, albedos)) * (ti.z * to.z / (wi.z * wo.z * sc.1))
    }

    /// The density of drawing `wi` for `wo` from one lobe.
    #[inline]
    fn lobe_pdf(yarn: &Table, lobe: &Lobe, wi: Vec3, wo: Vec3) -> f64 {
        let (wi, wo) = if lobe.warp {
            (to_warp(wi), to_warp(wo))
        } else {
            (wi, wo)
        };
        if lobe.tilt == 0.0 {
            return yarn.pdf(wo, wi);
        }
        let sc = lobe.tilt.sin_cos();
        let (ti, to) = (into_tilted(wi, sc), into_tilted(wo, sc));
        if ti.z <= 0.0 || to.z <= 0.0 {
            return 0.0;
        }
        yarn.pdf(to, ti)
    }

    /// Draws `wi` for `wo` from one lobe's table (roles swapped: module docs), with its density
    /// (a rotation keeps densities per solid angle).
    #[inline]
    fn lobe_sample(yarn: &Table, lobe: &Lobe, wo: Vec3, u1: f64, u2: f64) -> Option<(Vec3, f64)> {
        let mut w = if lobe.warp { to_warp(wo) } else { wo };
        let sc = lobe.tilt.sin_cos();
        if lobe.tilt != 0.0 {
            w = into_tilted(w, sc);
            if w.z <= 0.0 {
                return None;
            }
        }
        let (mut wi, pdf) = yarn.sample_direction(w, u1, u2)?;
        if wi.z <= 0.0 || pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        if lobe.tilt != 0.0 {
            wi = from_tilted(wi, sc);
        }
        if lobe.warp {
            wi = from_warp(wi);
        }
        (wi.z > 0.0).then_some((wi, pdf))
    }

    fn eval_lobes(&self, yarn: &Table, lobes: &Lobes, wi: Vec3, wo: Vec3) -> Rgb {
        let mut f = Rgb::BLACK;
        for l in lobes.iter() {
            f += self.lobe_eval(yarn, l, wi, wo) * l.weight;
        }
        f
    }

    fn pdf_lobes(yarn: &Table, lobes: &Lobes, wi: Vec3, wo: Vec3) -> f64 {
        let mut p = 0.0;
        for l in lobes.iter() {
            p += l.weight * Self::lobe_pdf(yarn, l, wi, wo);
        }
        let total = lobes.total();
        if total == 1.0 || total == 0.0 {
            p
        } else {
            p / total
        }
    }
}

/// The albedos per channel for a dye `colour` of a material whose own albedos are `own`.
fn dyed(own: Albedos, colour: Option<Rgb>) -> [Albedos; 3] {
    let Some(c) = colour else {
        return [own; 3];
    };
    c.0.map(|c| Albedos {
        diffuse: c.clamp(0.0, 0.999),
        interreflection: if own.diffuse > 0.0 {
            (own.interreflection * c / own.diffuse).clamp(0.0, 1.0)
        } else {
            own.interreflection
        },
    })
}

/// Into the frame of a warp yarn: a 90° turn about `z` taking `y` (the warp) to `x`.
#[inline]
fn to_warp(d: Vec3) -> Vec3 {
    Vec3::new(d.y, -d.x, d.z)
}

/// Back from the warp yarn's frame.
#[inline]
fn from_warp(d: Vec3) -> Vec3 {
    Vec3::new(-d.y, d.x, d.z)
}

impl SurfaceMaterial for WovenMaterial {
    fn eval(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::BLACK;
        }
        match &self.layout {
            Layout::Flat { model, .. } => {
                let affine = model.eval_affine(wi, wo);
                Rgb(self
                    .weft
                    .map(|a| affine.at(a.diffuse, a.interreflection).max(0.0)))
            }
            Layout::Macro { yarn, .. } | Layout::Pattern { yarn, .. } => {
                self.eval_lobes(yarn, &self.lobes(at), wi, wo)
            }
        }
    }

    fn sample(&self, wo: Vec3, at: &ShadingPoint, u1: f64, u2: f64) -> Option<MaterialSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (yarn, lobes) = match &self.layout {
            Layout::Flat { table, .. } => {
                let flat = Lobe {
                    warp: false,
                    tilt: 0.0,
                    weight: 1.0,
                };
                let (wi, pdf) = Self::lobe_sample(table, &flat, wo, u1, u2)?;
                return (pdf > 0.0 && pdf.is_finite()).then(|| MaterialSample {
                    wi,
                    f: self.eval(wi, wo, at),
                    pdf,
                });
            }
            Layout::Macro { yarn, .. } | Layout::Pattern { yarn, .. } => (yarn, self.lobes(at)),
        };
        // A lobe with probability ∝ its weight, u1 reused within its share; the density is the
        // mixture's.
        let last = lobes.n.checked_sub(1)?;
        let x = u1 * lobes.total();
        let mut before = 0.0;
        let mut pick = 0;
        while pick < last && x >= before + lobes.lobes[pick].weight {
            before += lobes.lobes[pick].weight;
            pick += 1;
        }
        let lobe = &lobes.lobes[pick];
        let u1 = ((x - before) / lobe.weight).clamp(0.0, 1.0 - f64::EPSILON);
        let (wi, pdf) = Self::lobe_sample(yarn, lobe, wo, u1, u2)?;
        let pdf = if lobes.n == 1 {
            pdf
        } else {
            Self::pdf_lobes(yarn, &lobes, wi, wo)
        };
        (pdf > 0.0 && pdf.is_finite()).then(|| MaterialSample {
            wi,
            f: self.eval_lobes(yarn, &lobes, wi, wo),
            pdf,
        })
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        match &self.layout {
            Layout::Flat { table, .. } => table.pdf(wo, wi),
            Layout::Macro { yarn, .. } | Layout::Pattern { yarn, .. } => {
                Self::pdf_lobes(yarn, &self.lobes(at), wi, wo)
            }
        }
    }

    fn uses_footprint(&self) -> bool {
        matches!(self.layout, Layout::Pattern { .. })
    }
}
