//! The woven material: a [`WovenSurface`] of the library (what a woven material means at a
//! point: the weave pattern on the surface's uv, dyes, yarn tilt, gaps, the footprint filter;
//! see [`woven::surface`]) with the tables it renders from.
//!
//! **Interface.** A [`WovenSpec`] says what to render; [`WovenMaterial::build`] prepares it once
//! (a [`TableCache`] shares tables between the materials of a scene and, with
//! [`TableCache::with_disk`], keeps them on disk between runs), and the result is a
//! [`SurfaceMaterial`]: the surface's BSDF at each shading point, sampled for camera paths
//! ([`Transport::Radiance`]).

use crate::material::{MaterialSample, ShadingPoint, SurfaceMaterial};
use crate::Result;
use crate::Rgb;
use std::collections::HashMap;
use std::sync::Arc;
use woven::bsdf::{Bsdf, Transport};
use woven::material::Material;
use woven::surface::WovenSurface;
use woven::table::cache::{Cache, Notice};
use woven::table::{Table, TableOptions};
use woven::{Model, Vec3};

/// The wavelength every woven table is built at, nm (the middle of the visible range, green).
pub const WAVELENGTH_NM: f64 = 550.0;

/// What to render: a material and how its weave maps onto the surface (the library's
/// [`SurfaceSpec`](woven::surface::SurfaceSpec)).
pub use woven::surface::SurfaceSpec as WovenSpec;

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
    surface: WovenSurface,
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
        // A crowned table is its yarn's table averaged over the crown.
        let base = if options.crown_deg > 0.0 {
            let plain = TableOptions {
                crown_deg: 0.0,
                ..*options
            };
            Some(self.table(material, &plain, on_build, progress)?)
        } else {
            None
        };
        let build = || -> woven::Result<Table> {
            if let Some(base) = &base {
                return base.crowned_with(options);
            }
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

impl WovenMaterial {
    /// Tabulates `spec` (seconds per material on the default grid), reusing a table in `cache`
    /// when one of the same yarn exists there (or on its disk). `on_build` is called before a
    /// table is built; `progress` gets `(done, total)` rows as the build proceeds.
    ///
    /// # Errors
    /// An invalid material, layout or grid ([`woven::Error`]).
    pub fn build(
        spec: &WovenSpec,
        grid: &TableGrid,
        cache: &mut TableCache,
        on_build: &dyn Fn(),
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<WovenMaterial> {
        spec.validate()?;
        // The yarn alone, weft along x (named as the material, for the cache's file name).
        let yarn_material = spec.table_material();
        let options = match grid {
            TableGrid::Default => TableOptions::for_render(&yarn_material.build(WAVELENGTH_NM)?),
            TableGrid::Custom(o) => TableOptions { colour: true, ..*o },
        };
        let yarn = cache.table(&yarn_material, &options, &|_| on_build(), progress)?;
        let mut surface = WovenSurface::new(spec, yarn)?;
        if surface.resolves_relief() {
            // The resolved yarn: the same table averaged over its crown, cached like it.
            let crowned = TableOptions {
                crown_deg: woven::relief::CROWN_DEG,
                ..options
            };
            let crowned = cache.table(&yarn_material, &crowned, &|_| on_build(), progress)?;
            surface = surface.with_crowned(crowned)?;
        }
        // The resolved levels' tables (a crowned yarn, the relief's ratio, kept on disk).
        let note = |m: &str| {
            if let Some(note) = &cache.note {
                note(m);
            }
        };
        surface.prepare(cache.disk.as_ref().map(|d| d.dir()), &note);
        Ok(WovenMaterial { surface })
    }

    /// The library's surface this material renders.
    pub fn surface(&self) -> &WovenSurface {
        &self.surface
    }
}

impl SurfaceMaterial for WovenMaterial {
    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> Rgb {
        self.surface.at(at).eval(wi, wo)
    }

    #[inline]
    fn sample(&self, wo: Vec3, at: &ShadingPoint, uc: f64, u: [f64; 2]) -> Option<MaterialSample> {
        self.surface.at(at).sample(wo, uc, u, Transport::Radiance)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> f64 {
        self.surface.at(at).pdf(wi, wo, Transport::Radiance)
    }

    fn uses_footprint(&self) -> bool {
        self.surface.uses_footprint()
    }

    fn warp_share(&self, at: &ShadingPoint) -> f64 {
        let mix = self.surface.lobes(at);
        let warp: f64 = mix
            .lobes()
            .iter()
            .filter(|l| l.warp)
            .map(|l| l.weight)
            .sum();
        let total = mix.total();
        if total > 0.0 {
            warp / total
        } else {
            0.0
        }
    }
}
