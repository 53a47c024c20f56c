//! The woven material: a [`WovenSurface`] of the library (what a woven material means at a
//! point: the weave pattern on the surface's uv, dyes, yarn tilt, gaps, the footprint filter;
//! see [`woven::surface`]) with the tables it renders from.
//!
//! **Interface.** A [`WovenSpec`] says what to render; [`WovenMaterial::build`] prepares it once
//! (a [`TableCache`] shares tables between the materials of a scene and, with
//! [`TableCache::with_disk`], keeps them on disk between runs), and the result is a
//! [`SurfaceMaterial`]: the surface's BSDF at each shading point, sampled for camera paths
//! ([`Transport::Radiance`](woven::bsdf::Transport::Radiance)).

use crate::material::{BsdfScratch, MaterialBsdf, ShadingPoint, SurfaceMaterial};
use crate::Result;
use woven::progress::Progress;
use woven::surface::WovenSurface;
use woven::table::TableOptions;

/// The wavelength every woven table is built at, nm (the middle of the visible range, green):
/// the library's default (the `wavelength_nm` of `woven::surface::SURFACE_KEYS`).
pub const WAVELENGTH_NM: f64 = woven::fiber::DEFAULT_WAVELENGTH_NM;

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
    /// The cloth seen from behind, where it lets light through and is met from there: its
    /// back ([`WovenSpec::back`], the pattern's complement) on the same table.
    back: Option<Box<WovenMaterial>>,
}

/// The tables a scene's woven materials render from: the library's
/// [`Tables`](woven::table::cache::Tables) (materials that share a yarn share its table; with
/// `with_disk`, kept on disk between runs; crowned tables built from their yarn's).
pub use woven::table::cache::Tables as TableCache;

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
        progress: &dyn Progress,
    ) -> Result<WovenMaterial> {
        spec.validate()?;
        // The yarn alone, weft along x (named as the material, for the cache's file name).
        let yarn_material = spec.table_material();
        let options = match grid {
            TableGrid::Default => TableOptions::for_render(&yarn_material.build(WAVELENGTH_NM)?),
            TableGrid::Custom(o) => TableOptions { colour: true, ..*o },
        };
        let yarn = cache.table(
            &yarn_material,
            WAVELENGTH_NM,
            &options,
            &|_| on_build(),
            progress,
        )?;
        // The resolved levels' tables (a crowned yarn, the relief's ratio, kept on disk).
        let face = |spec: &WovenSpec, cache: &mut TableCache| {
            WovenSurface::new(spec, yarn.clone())?.prepared_from(
                cache,
                &yarn_material,
                WAVELENGTH_NM,
                &options,
                &|_| on_build(),
                progress,
            )
        };
        let surface = face(spec, cache)?;
        let back = if spec.transmission && spec.material.weave.is_some() {
            Some(Box::new(WovenMaterial {
                surface: face(&spec.back(), cache)?,
                back: None,
            }))
        } else {
            None
        };
        Ok(WovenMaterial { surface, back })
    }

    /// The library's surface this material renders.
    pub fn surface(&self) -> &WovenSurface {
        &self.surface
    }
}

impl SurfaceMaterial for WovenMaterial {
    #[inline]
    fn bsdf<'a, 's>(
        &'a self,
        at: &ShadingPoint,
        scratch: &'s mut BsdfScratch<'a>,
    ) -> &'s MaterialBsdf<'a> {
        scratch.woven(&self.surface, at)
    }

    fn uses_footprint(&self) -> bool {
        self.surface.uses_footprint()
    }

    fn transmits(&self) -> bool {
        self.surface.transmits()
    }

    fn back(&self) -> Option<&dyn SurfaceMaterial> {
        self.back.as_deref().map(|b| b as &dyn SurfaceMaterial)
    }

    #[inline]
    fn pass_through(&self, at: &ShadingPoint, d: woven::Vec3) -> f64 {
        self.surface.pass_through(at, d)
    }
}
