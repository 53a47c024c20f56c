//! The woven surface: a yarn table, a weave pattern laid on a surface's uv, dyes, yarn tilt,
//! gaps and the fine-weave footprint filter — what a woven material means at a point. The one
//! home of that meaning: `woven render`, the Python package (`woven.Surface`) and the Mitsuba 3
//! plugin all evaluate it here.
//!
//! **What renders.** A surface is rendered from one table: that of its yarn alone
//! ([`Material::yarn_family`](crate::material::Material::yarn_family): one yarn family along `x`, the surface's `u`), built dyeable
//! ([`TableOptions::colour`](crate::table::TableOptions::colour)). A warp yarn is the same table
//! turned 90° about the normal (along `y`, the surface's `v`).
//! - With a weave *pattern*: at surface parameters `(u, v)` the pattern cell at
//!   `(u n_u, v n_v)` ([`Pattern::cell_at`]; `[n_u, n_v]` = `yarns_per_unit`) says which yarn
//!   family is on top, and that family's BRDF (and colour) shades the point. Far away, cells
//!   average to the paper's γ-mix (docs/spec.md §2.7).
//! - With a `weft_fraction` and no pattern: the macro BRDF, the γ-mix
//!   `γ f_weft + (1 − γ) f_warp` of the two turned look-ups, each in its yarn's colour.
//! - A flat fiber surface (no `[yarn]`): the exact model (a fraction of a microsecond per
//!   evaluation), sampled with its table.
//!
//! **Tilt and gaps.** A yarn's axis may tilt out of the cloth plane along its float (Irawan &
//! Marschner's `u_max`): linearly from `+u_max` where the yarn comes up to `−u_max` where it goes
//! under ([`Pattern::floats`]); its BRDF is then the table's in the tilted frame, per unit of
//! cloth area. A `gap` leaves the given fraction of each cell's width between yarns: the crossing
//! yarn below shows there (flat), and where both families leave a gap, nothing (a hole).
//!
//! **Footprint filter.** Where a pixel's footprint spans more than [`FILTER_CELLS`]`[0]` cells,
//! the point's BRDF blends smoothly toward the macro BRDF (the cells' average, with the same
//! tilts and gaps), reached at [`FILTER_CELLS`]`[1]`: fine weaves do not alias into moiré or
//! sparkle.
//!
//! **Colour.** Dyed fibres have a coloured body and a white sheen: `weft_color` (and
//! `warp_color`) set the fiber's diffuse albedo `ρ0` per channel; the interreflection albedo `ρ`,
//! light that has bounced between fibres, follows in proportion (`ρ = ρ′ c / ρ0′` with the
//! material's own `ρ0′, ρ′`, at most 1; unchanged when `ρ0′ = 0`). The BRDF is affine in both
//! (docs/model.md §7), so one table serves every colour ([`Table::eval_dyed`]).
//!
//! **Sampling.** At a point the surface is a mixture of lobes ([`LobeMix`]: a family, its tilt,
//! a weight); [`PointBsdf`] implements [`Bsdf`](crate::bsdf::Bsdf): `uc` picks a lobe in proportion to its weight,
//! `u` draws within it from the table, and the density is the mixture's.
//!
//! ```
//! use std::sync::Arc;
//! use woven::bsdf::{Bsdf, Transport};
//! use woven::material::{Material, Weave};
//! use woven::surface::{SurfacePoint, SurfaceSpec, WovenSurface};
//! use woven::table::{Table, TableOptions};
//! use woven::Vec3;
//!
//! let mut material = Material::preset("polyester-sateen")?;
//! material.weave = Some(Weave::named("twill-2/1")?);
//! let spec = SurfaceSpec { yarns_per_unit: [20.0, 20.0], gap: 0.2, ..SurfaceSpec::new(material) };
//! // The yarn's table (coarse here; a renderer keeps one per yarn in a cache).
//! let yarn = spec.material.yarn_family();
//! let options = TableOptions { n_theta: 5, n_phi: 3, n_h: 13, colour: true, ..TableOptions::default() };
//! let table = Table::build(&yarn.build(550.0)?, &yarn, &options, &|_, _| {})?;
//! let surface = WovenSurface::new(&spec, Arc::new(table))?;
//!
//! let bsdf = surface.at(&SurfacePoint { uv: [0.013, 0.021], footprint: [[0.0; 2]; 2] });
//! let (wi, wo) = (Vec3::from_spherical(0.5, 0.3), Vec3::from_spherical(0.7, 2.0));
//! let f = bsdf.eval(wi, wo); // per channel, sr⁻¹
//! if let Some(s) = bsdf.sample(wo, 0.4, [0.3, 0.8], Transport::Radiance) {
//!     assert!((bsdf.pdf(s.wi, wo, Transport::Radiance) - s.pdf).abs() <= 1e-5 * s.pdf);
//! }
//! # let _ = f;
//! # Ok::<(), woven::Error>(())
//! ```

use crate::cloth::Structure;
use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::material::Weave;
use crate::relief::Relief;
use crate::table::{Albedos, Table};
use crate::weave::{FloatPlace, Pattern};
use crate::yarn::float::FloatProfile;
use crate::yarn::point::YarnDraws;
use crate::Model;
use std::sync::Arc;

// The surface's ideas, one module each: `spec` (what a surface is, its limits and checks),
// `keys` (the keys front ends write it with, and their one reader), `route` (what a JIT
// renderer traces and what it asks the library for), `dyes` (the surface's dyes),
// `layout` (the pattern's cells, tilt, gaps and relief, the γ-mix and the footprint filter: a
// point's lobes), `fibers` (the fibre level: per-yarn draws, a point on its yarn), `lobe` (one
// lobe's BRDF, density and draws in its frame), `point` (the BSDF at a point), `tables` (the
// tables a surface renders from: its yarn's, the crowned table, the tilted floats' and the
// relief's ratio), `ratio` (that ratio's table), `irregular`
// (uneven dyeing along the yarns), `texel` (the layout as another renderer's textures carry it). This file: the surface itself, how it is built, what it
// reports.
mod dyes;
mod fibers;
pub mod irregular;
mod keys;
mod layout;
mod lobe;
mod pass;
mod point;
mod ratio;
mod route;
mod spec;
mod tables;
mod texel;
pub mod translucent;

use dyes::Dyes;
use fibers::Fibers;
pub use fibers::{YarnPoint, STRANDS};
pub use irregular::Irregularity;
pub use keys::{KeyError, KeyedSurface, SurfaceKey, SURFACE_KEYS};
use layout::Entry;
pub use layout::{Lobe, LobeMix, SurfacePoint, Tilt, FIBER_CELLS, FILTER_CELLS, MAX_LOBES};
pub use point::PointBsdf;
use ratio::ReliefRatio;
pub use ratio::{
    ENTRIES as RATIO_ENTRIES, MAX_RATIO, PHI as RATIO_PHI, THETA_DEG as RATIO_THETA_DEG,
};
pub use route::{
    JitFloat, JitLayout, LayoutKind, LibraryReason, MacroLobe, Route, JIT_LAYOUT_VERSION,
};
pub use spec::{Detail, SurfaceSpec, DEFAULT_YARNS_PER_UNIT, MAX_GAP, MAX_U_MAX_DEG};
use tables::SurfaceTables;
pub use texel::Texel;

/// Gauss–Legendre nodes over a whole float's lit and seen part (what a whole float's table,
/// [`Table::tilted`](crate::table::Table::tilted), tabulates).
pub use crate::yarn::float::TILT_NODES;

/// What a surface lays on its uv.
#[derive(Clone, Debug)]
enum Layout {
    /// A flat fiber surface: the exact model, sampled with its table.
    Flat { model: Arc<Model> },
    /// A table rendered as it is: the BRDF it was built for, everywhere.
    Whole,
    /// The macro BRDF: the γ-mix of the yarn table and the same turned to the warp.
    Macro { weft_fraction: f64 },
    /// One yarn family per pattern cell.
    Pattern {
        pattern: Pattern,
        /// The pattern's own weft fraction γ (for the macro BRDF far away).
        weft_fraction: f64,
        /// [`Pattern::floats`]; empty without a tilt.
        floats: Vec<FloatPlace>,
    },
}

/// A woven surface, ready to evaluate at points ([`WovenSurface::at`]): what it lays on its uv
/// (the layout: the pattern, its cells' size, the floats' tilt, the gaps, the relief), its dyes
/// (`surface/dyes.rs`) and the tables it renders from (`surface/tables.rs`).
#[derive(Clone, Debug)]
pub struct WovenSurface {
    layout: Layout,
    yarns_per_unit: [f64; 2],
    u_max: f64,
    /// The floats' profile: tilt `u_max`, the material's crest and flanks.
    float: FloatProfile,
    gap: f64,
    detail: Detail,
    /// The exact yarn and its draws, where fibres are resolved ([`Detail::Auto`] and
    /// [`Detail::Fibers`] on a pattern).
    fibers: Option<Fibers>,
    /// The weave's relief, where [`SurfaceSpec::relief`] is on (on a pattern): the geometry of
    /// every level.
    relief: Option<Relief>,
    /// The yarns' cross-section where light passes between them ([`SurfaceSpec::transmission`]).
    open: Option<crate::gaps::YarnSection>,
    /// The forward lobe's spread of the light through the yarns
    /// ([`forward_spread`](crate::translucency::forward_spread)).
    spread: f64,
    /// The light through the yarns ([`translucent`]), worked out when first asked.
    translucency: std::sync::OnceLock<translucent::Translucency>,
    dyes: Dyes,
    tables: SurfaceTables,
}

/// A surface of `spec` on a small dyeable table of its yarn (`[n_theta, n_phi, n_h]`): what the
/// surface module's tests build.
#[cfg(test)]
pub(crate) fn test_surface(spec: &SurfaceSpec, [n_theta, n_phi, n_h]: [usize; 3]) -> WovenSurface {
    let yarn = spec.table_material();
    let options = crate::table::TableOptions {
        n_theta,
        n_phi,
        n_h,
        colour: true,
        ..crate::table::TableOptions::default()
    };
    let table = Table::build(&yarn.build(550.0).unwrap(), &yarn, &options, &|_, _| {}).unwrap();
    WovenSurface::new(spec, Arc::new(table)).unwrap()
}

impl WovenSurface {
    /// The surface `spec` renders with `yarn`, the table of
    /// [`spec.table_material()`](SurfaceSpec::table_material) (a flat fiber surface builds its
    /// exact model at the table's wavelength).
    ///
    /// # Errors
    /// An invalid `spec` ([`SurfaceSpec::validate`]); `weft_color` or `warp_color` with a
    /// table that is not dyeable; an invalid material.
    pub fn new(spec: &SurfaceSpec, yarn: Arc<Table>) -> Result<WovenSurface> {
        spec.validate()?;
        for (name, c) in [
            ("weft_color", spec.weft_color),
            ("warp_color", spec.warp_color),
        ] {
            if c.is_some() && !yarn.is_dyeable() {
                return Err(Error::InvalidParameter {
                    name: name.into(),
                    value: format!("{:?}", c.map(|c| c.0)),
                    expected: "no dye, or a table built dyeable (TableOptions::colour)".into(),
                });
            }
        }
        let layout = if spec.material.yarn.is_none() {
            Layout::Flat {
                model: Arc::new(spec.material.build(yarn.wavelength_nm())?),
            }
        } else {
            match &spec.material.weave {
                Some(Weave::Pattern { pattern, .. }) => Layout::Pattern {
                    pattern: pattern.clone(),
                    weft_fraction: pattern.weft_fraction(),
                    floats: if spec.u_max > 0.0 {
                        pattern.floats()
                    } else {
                        Vec::new()
                    },
                },
                _ => Layout::Macro {
                    weft_fraction: spec.material.weft_fraction(),
                },
            }
        };
        let own = Albedos::of(&spec.material);
        let resolves = matches!(spec.detail, Detail::Auto | Detail::Fibers);
        let fibers = if resolves && matches!(layout, Layout::Pattern { .. }) {
            let model = spec.table_material().build(yarn.wavelength_nm())?;
            let draws = match model.structure() {
                Structure::Woven { yarn, .. } => YarnDraws::new(yarn),
                Structure::Flat(_) => unreachable!("a pattern has yarns"),
            };
            let (floats, cols) = match &layout {
                Layout::Pattern { pattern, .. } => (pattern.floats(), pattern.cols()),
                _ => unreachable!("fibres are resolved on patterns only"),
            };
            let slant = draws.helix_angle().tan() / (1.0 - spec.gap);
            let [n_u, n_v] = spec.yarns_per_unit;
            Some(Fibers {
                model: Arc::new(model),
                draws,
                floats,
                cols,
                helix: [slant * n_v / n_u, slant * n_u / n_v],
            })
        } else {
            None
        };
        Ok(WovenSurface {
            layout,
            yarns_per_unit: spec.yarns_per_unit,
            u_max: spec.u_max,
            float: spec.float_profile(),
            gap: spec.gap,
            detail: spec.detail,
            relief: spec.relief_geometry(),
            open: if spec.transmission {
                Some(crate::gaps::YarnSection::new(spec.gap)?)
            } else {
                None
            },
            spread: crate::translucency::forward_spread(
                spec.material.fiber.eta.at(yarn.wavelength_nm()),
                spec.material.fiber.model.alpha(),
                spec.material.yarn.as_ref(),
            ),
            fibers,
            translucency: std::sync::OnceLock::new(),
            dyes: Dyes::new(own, [spec.weft_color, spec.warp_color], spec.irregularity),
            tables: SurfaceTables::new(yarn),
        })
    }

    /// A table rendered as it is (the BRDF it was built for, its weave's γ-mix included), dyed
    /// `color` (`None`: its material's own albedos).
    ///
    /// # Errors
    /// `color` with a table that is not dyeable or records no material.
    pub fn whole(table: Arc<Table>, color: Option<Rgb>) -> Result<WovenSurface> {
        let own = match (table.material(), color) {
            (Some(m), _) => Albedos::of(m),
            (None, None) => Albedos {
                diffuse: 0.0,
                interreflection: 0.0,
            },
            (None, Some(c)) => {
                return Err(Error::InvalidParameter {
                    name: "weft_color".into(),
                    value: format!("{:?}", c.0),
                    expected: "no dye: the table records no material to dye".into(),
                })
            }
        };
        if color.is_some() && !table.is_dyeable() {
            return Err(Error::InvalidParameter {
                name: "weft_color".into(),
                value: format!("{:?}", color.map(|c| c.0)),
                expected: "no dye, or a table built dyeable (TableOptions::colour)".into(),
            });
        }
        if let Some(c) = color {
            if !c.0.iter().all(|x| (0.0..=1.0).contains(x)) {
                return Err(Error::InvalidParameter {
                    name: "weft_color".into(),
                    value: format!("{:?}", c.0),
                    expected: "three values in [0, 1]".into(),
                });
            }
        }
        Ok(WovenSurface {
            layout: Layout::Whole,
            yarns_per_unit: [1.0, 1.0],
            u_max: 0.0,
            float: FloatProfile::new(f64::MIN_POSITIVE),
            gap: 0.0,
            detail: Detail::Yarns,
            fibers: None,
            relief: None,
            open: None,
            spread: crate::translucency::MIN_FORWARD_SPREAD,
            translucency: std::sync::OnceLock::new(),
            dyes: Dyes::new(own, [color; 2], Irregularity::default()),
            tables: SurfaceTables::new(table),
        })
    }

    /// The floats' profile (its tilt is [`u_max`](Self::u_max), at least the smallest positive
    /// number).
    pub fn float_profile(&self) -> FloatProfile {
        self.float
    }

    /// Pattern cells per unit of `u` and of `v`.
    pub fn yarns_per_unit(&self) -> [f64; 2] {
        self.yarns_per_unit
    }

    /// The yarns' tilt at the ends of a float, radians.
    pub fn u_max(&self) -> f64 {
        self.u_max
    }

    /// The fraction of each cell's width between yarns.
    pub fn gap(&self) -> f64 {
        self.gap
    }

    /// The weft fraction γ of the macro BRDF (1 for a flat surface or a whole table).
    pub fn weft_fraction(&self) -> f64 {
        match &self.layout {
            Layout::Macro { weft_fraction } | Layout::Pattern { weft_fraction, .. } => {
                *weft_fraction
            }
            _ => 1.0,
        }
    }

    /// [`Pattern::floats`] of the pattern, as the surface uses them (empty without a tilt).
    pub fn floats(&self) -> &[FloatPlace] {
        match &self.layout {
            Layout::Pattern { floats, .. } => floats,
            _ => &[],
        }
    }

    /// The yarn's table.
    pub fn table(&self) -> &Arc<Table> {
        &self.tables.yarn
    }

    /// The weave pattern laid on the surface, if any.
    pub fn pattern(&self) -> Option<&Pattern> {
        match &self.layout {
            Layout::Pattern { pattern, .. } => Some(pattern),
            _ => None,
        }
    }

    /// Whether the surface reads [`SurfacePoint::footprint`] (only patterns filter).
    pub fn uses_footprint(&self) -> bool {
        matches!(self.layout, Layout::Pattern { .. })
            && matches!(self.detail, Detail::Auto | Detail::Yarns)
    }

    /// How finely the surface resolves its weave.
    pub fn detail(&self) -> Detail {
        self.detail
    }

    /// Whether the surface is a flat fiber surface (evaluated with the exact model).
    pub fn is_flat(&self) -> bool {
        matches!(self.layout, Layout::Flat { .. })
    }

    /// The dye rule of the surface's own albedos ([`Albedos::dye_rule`]): how a colour read per
    /// point (a front end's texture) sets a family's albedos, as [`albedos`](Self::albedos) are
    /// set from `weft_color` and `warp_color`.
    pub fn dye_rule(&self) -> crate::table::DyeRule {
        self.dyes.rule()
    }

    /// The albedos per channel of the weft (`warp = false`) or the warp.
    pub fn albedos(&self, warp: bool) -> &[Albedos; 3] {
        self.dyes.albedos(warp)
    }
}
