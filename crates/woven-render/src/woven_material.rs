//! The woven material: the Yang–Ikeuchi cloth BRDF (tabulated) on a surface, with the weave
//! pattern deciding, point by point, whether the weft or the warp lies on top.
//!
//! **Interface** (kept small: the lead reworks the inside for colour tables and a disk cache):
//! a [`WovenSpec`] says what to render, [`WovenMaterial::build`] tabulates it once (a
//! [`TableCache`] shares tables between materials of one scene), and the
//! result is a [`SurfaceMaterial`]. Everything else is private.
//!
//! **What renders.**
//! - A material with a weave *pattern*: at surface parameters `(u, v)` the pattern cell
//!   `(⌊v·n_v⌋, ⌊u·n_u⌋)`, `[n_u, n_v] = yarns_per_unit`, says which yarn family is on top. A weft cell
//!   renders the BRDF of the material's yarn with `weft_fraction = 1` (its yarns along `x`, the
//!   surface's `u`); a warp cell the same yarn turned 90° about the normal (along `y`, `v`).
//!   Far away, cells average to the paper's γ-mix (MODEL.md §2.7), which the γ-mix is by
//!   construction: `γ f_weft + (1 − γ) f_warp`.
//! - A material with a `weft_fraction` and no pattern (or a flat fiber surface): its macro BRDF,
//!   weft along `u`.
//!
//! **Colour (provisional).** One table at one wavelength ([`WAVELENGTH_NM`]) serves all three
//! channels; a yarn's colour scales that grey BRDF per channel by `colour / ρ0`, `ρ0` the
//! material's diffuse fiber albedo (by the colour itself when `ρ0 = 0`). That tints the white
//! sheen too, which real dyed fibres do not do; per-channel tables of the parts the BRDF is
//! affine in will replace it.
//!
//! **Sampling.** The table samples `v` for a given `s` (∝ `f(s, v) cos θ_v`); a camera path
//! knows the viewer `wo` and needs `wi`. So the draw swaps the roles — `wi` is drawn as the `v`
//! of `s = wo`, with the table's density `pdf(s = wo, v = wi)` — and the weight uses the true
//! `f(s = wi, v = wo)` (the paper normalization is not reciprocal). [`SurfaceMaterial::pdf`]
//! returns the same swapped density, so MIS weights use the density actually sampled with.

use crate::color::Rgb;
use crate::material::{MaterialSample, ShadingPoint, SurfaceMaterial};
use crate::Result;
use std::collections::HashMap;
use std::sync::Arc;
use woven::bsdf::Bsdf;
use woven::material::{Material, Weave};
use woven::table::{Table, TableOptions};
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
}

/// The table grid to build with.
#[derive(Clone, Debug, Default)]
pub enum TableGrid {
    /// [`TableOptions::for_model`]: the library's accurate default.
    #[default]
    Default,
    /// A given grid (tests use a coarse one).
    Custom(TableOptions),
}

/// A tabulated woven material, ready to render.
pub struct WovenMaterial {
    layout: Layout,
    weft_scale: Rgb,
    warp_scale: Rgb,
    yarns_per_unit: [f64; 2],
}

/// Tables built so far, by the self-contained TOML of the material tabulated: materials that
/// share a yarn (the same preset in two weaves) share its table.
#[derive(Default)]
pub struct TableCache(HashMap<String, Arc<Table>>);

enum Layout {
    /// The macro BRDF, weft along `u`; the colour is the γ-mix of the two scales.
    Macro {
        table: Arc<Table>,
        weft_fraction: f64,
    },
    /// One yarn family per pattern cell.
    Pattern { pattern: Pattern, yarn: Arc<Table> },
}

impl WovenMaterial {
    /// Tabulates `spec` (this takes seconds to a minute: see `woven tabulate`), reusing a table
    /// in `cache` when one of the same material exists. `on_build` is called before a table is
    /// built; `progress` gets `(done, total)` nodes as the build proceeds.
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
        let mut tabulate = |material: &Material| -> Result<Arc<Table>> {
            let key = material.to_self_contained_toml_string();
            if let Some(t) = cache.0.get(&key) {
                return Ok(Arc::clone(t));
            }
            on_build();
            let model: Model = material.build(WAVELENGTH_NM)?;
            let options = match grid {
                TableGrid::Default => TableOptions::for_model(&model),
                TableGrid::Custom(o) => *o,
            };
            let table = Arc::new(Table::build(&model, material, &options, progress)?);
            cache.0.insert(key, Arc::clone(&table));
            Ok(table)
        };
        let layout = match &spec.material.weave {
            Some(Weave::Pattern { pattern, .. }) => {
                // The yarn family alone: all weft (γ = 1), yarns along x.
                let mut single = spec.material.clone();
                single.weave = Some(Weave::WeftFraction(1.0));
                // The name is not part of what a table holds.
                single.name = None;
                Layout::Pattern {
                    pattern: pattern.clone(),
                    yarn: tabulate(&single)?,
                }
            }
            _ => Layout::Macro {
                table: tabulate(&spec.material)?,
                weft_fraction: spec.material.weft_fraction(),
            },
        };
        let grey = spec.material.fiber.diffuse;
        let scale = |c: Option<Rgb>| match c {
            None => Rgb::WHITE,
            Some(c) if grey > 0.0 => c / grey,
            Some(c) => c,
        };
        Ok(WovenMaterial {
            layout,
            weft_scale: scale(spec.weft_color),
            warp_scale: scale(spec.warp_color),
            yarns_per_unit: spec.yarns_per_unit,
        })
    }

    /// The table to use at `at`, whether it is turned to the warp, and the colour scale.
    #[inline]
    fn at(&self, at: &ShadingPoint) -> (&Table, bool, Rgb) {
        match &self.layout {
            Layout::Macro {
                table,
                weft_fraction,
            } => (
                table,
                false,
                self.weft_scale * *weft_fraction + self.warp_scale * (1.0 - weft_fraction),
            ),
            Layout::Pattern { pattern, yarn } => {
                let (u, v) = (
                    at.uv[0] * self.yarns_per_unit[0],
                    at.uv[1] * self.yarns_per_unit[1],
                );
                // Cells per unit → pattern repeats: the pattern is cols × rows cells.
                let weft = if u.is_finite() && v.is_finite() {
                    pattern.weft_at_uv(u / pattern.cols() as f64, v / pattern.rows() as f64)
                } else {
                    true
                };
                if weft {
                    (yarn, false, self.weft_scale)
                } else {
                    (yarn, true, self.warp_scale)
                }
            }
        }
    }
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
        let (table, warp, scale) = self.at(at);
        let (wi, wo) = if warp {
            (to_warp(wi), to_warp(wo))
        } else {
            (wi, wo)
        };
        scale * table.eval(wi, wo)
    }

    fn sample(&self, wo: Vec3, at: &ShadingPoint, u1: f64, u2: f64) -> Option<MaterialSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (table, warp, scale) = self.at(at);
        let wo_t = if warp { to_warp(wo) } else { wo };
        // Roles swapped: wi is drawn as the table's v for s = wo (module docs).
        let drawn = table.sample(wo_t, u1, u2)?;
        let wi_t = drawn.v;
        if wi_t.z <= 0.0 || drawn.pdf.is_nan() || drawn.pdf <= 0.0 {
            return None;
        }
        let f = table.eval(wi_t, wo_t);
        let wi = if warp { from_warp(wi_t) } else { wi_t };
        Some(MaterialSample {
            wi,
            f: scale * f,
            pdf: drawn.pdf,
        })
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let (table, warp, _) = self.at(at);
        let (wi, wo) = if warp {
            (to_warp(wi), to_warp(wo))
        } else {
            (wi, wo)
        };
        table.pdf(wo, wi)
    }
}
