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
    Pattern { pattern: Pattern, yarn: Arc<Table> },
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
        })
    }

    /// Whether the warp lies on top at `at` (patterned materials only).
    #[inline]
    fn warp_on_top(&self, pattern: &Pattern, at: &ShadingPoint) -> bool {
        let (u, v) = (
            at.uv[0] * self.yarns_per_unit[0],
            at.uv[1] * self.yarns_per_unit[1],
        );
        // Cells per unit → pattern repeats: the pattern is cols × rows cells.
        u.is_finite()
            && v.is_finite()
            && !pattern.weft_at_uv(u / pattern.cols() as f64, v / pattern.rows() as f64)
    }

    /// One yarn family's BRDF per channel: the weft, or the warp (turned).
    #[inline]
    fn family(&self, yarn: &Table, warp: bool, wi: Vec3, wo: Vec3) -> Rgb {
        if warp {
            Rgb(yarn.eval_dyed(to_warp(wi), to_warp(wo), &self.warp))
        } else {
            Rgb(yarn.eval_dyed(wi, wo, &self.weft))
        }
    }

    /// The density of drawing `wi` for `wo` from one yarn family's table.
    #[inline]
    fn family_pdf(yarn: &Table, warp: bool, wi: Vec3, wo: Vec3) -> f64 {
        if warp {
            yarn.pdf(to_warp(wo), to_warp(wi))
        } else {
            yarn.pdf(wo, wi)
        }
    }

    /// Draws `wi` for `wo` from one yarn family's table (roles swapped: module docs), with its
    /// density.
    #[inline]
    fn family_sample(yarn: &Table, warp: bool, wo: Vec3, u1: f64, u2: f64) -> Option<(Vec3, f64)> {
        let wo_t = if warp { to_warp(wo) } else { wo };
        let (wi, pdf) = yarn.sample_direction(wo_t, u1, u2)?;
        if wi.z <= 0.0 || pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some((if warp { from_warp(wi) } else { wi }, pdf))
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
            Layout::Macro {
                yarn,
                weft_fraction: g,
            } => {
                let mut f = Rgb::BLACK;
                if *g > 0.0 {
                    f += self.family(yarn, false, wi, wo) * *g;
                }
                if *g < 1.0 {
                    f += self.family(yarn, true, wi, wo) * (1.0 - g);
                }
                f
            }
            Layout::Pattern { pattern, yarn } => {
                self.family(yarn, self.warp_on_top(pattern, at), wi, wo)
            }
        }
    }

    fn sample(&self, wo: Vec3, at: &ShadingPoint, u1: f64, u2: f64) -> Option<MaterialSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (wi, pdf) = match &self.layout {
            Layout::Flat { table, .. } => Self::family_sample(table, false, wo, u1, u2)?,
            Layout::Macro {
                yarn,
                weft_fraction: g,
            } => {
                // The weft's lobe with probability γ, u1 reused within its share; the density
                // is the mixture's.
                let (warp, u1) = if u1 < *g {
                    (false, u1 / g)
                } else {
                    (true, (u1 - g) / (1.0 - g))
                };
                let (wi, _) = Self::family_sample(yarn, warp, wo, u1.min(1.0 - f64::EPSILON), u2)?;
                (wi, self.pdf(wi, wo, at))
            }
            Layout::Pattern { pattern, yarn } => {
                Self::family_sample(yarn, self.warp_on_top(pattern, at), wo, u1, u2)?
            }
        };
        (pdf > 0.0 && pdf.is_finite()).then(|| MaterialSample {
            wi,
            f: self.eval(wi, wo, at),
            pdf,
        })
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        match &self.layout {
            Layout::Flat { table, .. } => Self::family_pdf(table, false, wi, wo),
            Layout::Macro {
                yarn,
                weft_fraction: g,
            } => {
                let mut p = 0.0;
                if *g > 0.0 {
                    p += g * Self::family_pdf(yarn, false, wi, wo);
                }
                if *g < 1.0 {
                    p += (1.0 - g) * Self::family_pdf(yarn, true, wi, wo);
                }
                p
            }
            Layout::Pattern { pattern, yarn } => {
                Self::family_pdf(yarn, self.warp_on_top(pattern, at), wi, wo)
            }
        }
    }
}
