//! The woven surface: a yarn table, a weave pattern laid on a surface's uv, dyes, yarn tilt,
//! gaps and the fine-weave footprint filter — what a woven material means at a point. The one
//! home of that meaning: `woven render`, the Python package (`woven.Surface`) and the Mitsuba 3
//! plugin all evaluate it here.
//!
//! **What renders.** A surface is rendered from one table: that of its yarn alone
//! ([`Material::yarn_family`]: one yarn family along `x`, the surface's `u`), built dyeable
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
//! a weight); [`PointBsdf`] implements [`Bsdf`]: `uc` picks a lobe in proportion to its weight,
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

use crate::bsdf::{known_and_drawn, pair_of, Bsdf, BsdfSample, LobeFlags, Transport};
use crate::cloth::Structure;
use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::fiber::Normalization;
use crate::material::{Material, Weave};
use crate::math::sampling::cosine_hemisphere;
use crate::relief::{Ground, Lean, Relief};
use crate::table::{Albedos, Table, TableOptions};
use crate::weave::{CellPoint, FloatPlace, Pattern};
use crate::yarn::float::FloatProfile;
use crate::yarn::point::{golden_uniform, hash_uniform, YarnDraws};
use crate::yarn::Yarn;
use crate::{Model, Vec3};
use std::f64::consts::{FRAC_1_PI, PI};
use std::sync::Arc;

pub mod irregular;
mod ratio;
pub use irregular::Irregularity;
use ratio::ReliefRatio;
pub use ratio::{
    ENTRIES as RATIO_ENTRIES, MAX_RATIO, PHI as RATIO_PHI, THETA_DEG as RATIO_THETA_DEG,
};

/// Footprints (in pattern cells, the larger side of the pixel's footprint) from which the
/// footprint filter starts blending toward the macro BRDF, and at which it is the macro BRDF.
pub const FILTER_CELLS: [f64; 2] = [0.5, 2.0];

/// Gauss–Legendre nodes over a whole float's lit and seen part (the surface's whole-float lobe
/// and its draws' midpoint tilts).
pub use crate::yarn::float::TILT_NODES;

/// The most lobes mixed at a point: one cell's at fibre and at yarn level, and the macro BRDF's
/// (each family on top, a whole float when tilted, and flat where it shows in the other's
/// gaps).
pub const MAX_LOBES: usize = 6;

/// Footprints (in pattern cells) from which `detail = "auto"` starts blending from fibres to
/// yarns, and at which it shows yarns alone (the footprint filter then takes over at
/// [`FILTER_CELLS`]).
pub const FIBER_CELLS: [f64; 2] = [0.1, 0.35];

/// Strands of fibres across one yarn, each with its own azimuth offset (twisted and isotropic
/// yarns).
pub const STRANDS: u64 = 16;

/// How finely a surface resolves its weave (the `detail` key of woven materials).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Detail {
    /// By the pixel's footprint: fibres where it is well under a yarn's width, yarns from about
    /// a third of a cell ([`FIBER_CELLS`]), the cloth's macro BRDF from two cells
    /// ([`FILTER_CELLS`]), smoothly between.
    #[default]
    Auto,
    /// Every point is a point on its yarn's profile ([`yarn::point`](crate::yarn::point)).
    Fibers,
    /// Every point shades with its cell's yarn BRDF (blending to the macro BRDF under wide
    /// footprints).
    Yarns,
    /// Every point shades with the cloth's macro BRDF, the paper's γ-mix.
    Cloth,
}

impl Detail {
    /// The names, as scene files and the plugin write them.
    pub const NAMES: [&'static str; 4] = ["auto", "fibers", "yarns", "cloth"];

    /// The level named `name` (one of [`NAMES`](Self::NAMES)).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `detail` for any other name.
    pub fn from_name(name: &str) -> Result<Detail> {
        match name {
            "auto" => Ok(Detail::Auto),
            "fibers" => Ok(Detail::Fibers),
            "yarns" => Ok(Detail::Yarns),
            "cloth" => Ok(Detail::Cloth),
            other => Err(Error::InvalidParameter {
                name: "detail".into(),
                value: format!("{other:?}"),
                expected: "one of \"auto\", \"fibers\", \"yarns\", \"cloth\"".into(),
            }),
        }
    }

    /// The level's name.
    pub fn name(self) -> &'static str {
        match self {
            Detail::Auto => "auto",
            Detail::Fibers => "fibers",
            Detail::Yarns => "yarns",
            Detail::Cloth => "cloth",
        }
    }
}

/// The largest yarn tilt [`SurfaceSpec::u_max`], degrees.
pub const MAX_U_MAX_DEG: f64 = 80.0;

/// The largest [`SurfaceSpec::gap`]: yarns keep at least 5 % of their cells.
pub const MAX_GAP: f64 = 0.95;

/// What a woven surface is: a material and how its weave lies on the surface.
#[derive(Clone, Debug)]
pub struct SurfaceSpec {
    /// The material (its `weave` may hold the pattern laid on the surface).
    pub material: Material,
    /// Pattern cells per unit of `u` and per unit of `v` (each > 0); unused without a pattern.
    pub yarns_per_unit: [f64; 2],
    /// The weft's dyed albedo per channel, each in `[0, 1]`; `None`: the material's own (grey).
    pub weft_color: Option<Rgb>,
    /// The warp's dyed albedo per channel, each in `[0, 1]`; `None`: the material's own.
    pub warp_color: Option<Rgb>,
    /// The tilt of a yarn's axis out of the cloth plane at the ends of each float, radians, in
    /// `[0, MAX_U_MAX_DEG]` degrees; 0 (the default): flat yarns, the paper's model.
    pub u_max: f64,
    /// The fraction of each cell's width, in `[0, MAX_GAP]`, between yarns; 0 (the default):
    /// yarns fill their cells.
    pub gap: f64,
    /// How finely the weave is resolved ([`Detail::Auto`] by default).
    pub detail: Detail,
    /// How unevenly each yarn is dyed along its length ([`Irregularity`]; by default not at
    /// all). Needs a pattern.
    pub irregularity: Irregularity,
}

impl SurfaceSpec {
    /// `material` with one pattern cell per unit of uv, its own colours (its `[dye]`, if any),
    /// its own float tilt (`[yarn] u_max_deg`, 0 for the paper's flat yarns), no gaps.
    pub fn new(material: Material) -> SurfaceSpec {
        let dye = material.dye;
        let u_max = material.yarn.map_or(0.0, |y| y.u_max);
        SurfaceSpec {
            material,
            yarns_per_unit: [1.0, 1.0],
            weft_color: dye.weft,
            warp_color: dye.warp,
            u_max,
            gap: 0.0,
            detail: Detail::Auto,
            irregularity: Irregularity::default(),
        }
    }

    /// The material whose table renders the surface: its yarn alone
    /// ([`Material::yarn_family`]), to be tabulated with
    /// [`TableOptions::colour`](crate::table::TableOptions::colour) set.
    pub fn table_material(&self) -> Material {
        self.material.yarn_family()
    }

    /// The floats' profile: tilt [`u_max`](Self::u_max), crest and flanks the material's own
    /// (`[yarn] float_crest`, `float_flank`); only read where `u_max > 0`.
    pub fn float_profile(&self) -> FloatProfile {
        let (crest, flank) = self
            .material
            .yarn
            .map_or((0.0, 0.0), |y| (y.float_crest, y.float_flank));
        FloatProfile::shaped(self.u_max.max(f64::MIN_POSITIVE), crest, flank)
    }

    /// The relief of the surface's weave ([`Relief`]: its floats' hills and its yarns' round
    /// crowns, laid on its pattern); `None` without a pattern.
    pub fn relief(&self) -> Option<Relief> {
        match &self.material.weave {
            Some(Weave::Pattern { pattern, .. }) => Some(Relief::new(
                pattern,
                self.yarns_per_unit,
                self.float_profile(),
                self.gap,
            )),
            _ => None,
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first offending one (`yarns_per_unit`,
    /// `weft_color`, `warp_color`, `u_max`, `gap`, `irregularity`, `irregularity_length`), its
    /// value and the valid range.
    pub fn validate(&self) -> Result<()> {
        let invalid = |name: &str, value: String, expected: &str| {
            Err(Error::InvalidParameter {
                name: name.into(),
                value,
                expected: expected.into(),
            })
        };
        if !self
            .yarns_per_unit
            .iter()
            .all(|n| n.is_finite() && *n > 0.0)
        {
            return invalid(
                "yarns_per_unit",
                format!("{:?}", self.yarns_per_unit),
                "two finite numbers > 0",
            );
        }
        for (name, c) in [
            ("weft_color", self.weft_color),
            ("warp_color", self.warp_color),
        ] {
            if let Some(c) = c {
                if !c.0.iter().all(|x| (0.0..=1.0).contains(x)) {
                    return invalid(name, format!("{:?}", c.0), "three values in [0, 1]");
                }
            }
        }
        if !(0.0..=MAX_U_MAX_DEG.to_radians()).contains(&self.u_max) {
            return invalid(
                "u_max",
                format!("{} rad ({}°)", self.u_max, self.u_max.to_degrees()),
                &format!("radians in [0, {MAX_U_MAX_DEG}°]"),
            );
        }
        if !(0.0..=MAX_GAP).contains(&self.gap) {
            return invalid(
                "gap",
                self.gap.to_string(),
                &format!("a fraction in [0, {MAX_GAP}]"),
            );
        }
        if self.material.yarn.is_none() && (self.u_max > 0.0 || self.gap > 0.0) {
            let name = if self.gap > 0.0 { "gap" } else { "u_max" };
            return invalid(
                name,
                format!(
                    "{} with a flat fiber surface",
                    if name == "gap" { self.gap } else { self.u_max }
                ),
                "0: a flat fiber surface (no [yarn]) has no yarns to tilt or space",
            );
        }
        self.irregularity.validate_for(&self.material)
    }
}

/// A point on a surface as a woven surface reads it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfacePoint {
    /// The surface parameters `(u, v)` at the point.
    pub uv: [f64; 2],
    /// The footprint of the pixel at the point, in uv: `[[∂u/∂x, ∂v/∂x], [∂u/∂y, ∂v/∂y]]`, the
    /// change of `(u, v)` from one film pixel to the next along `x` and along `y`. All zero: no
    /// footprint known (a path's later vertex, a renderer without ray differentials): no
    /// filtering, and [`Detail::Auto`] shades the point at yarn level; infinite entries: a
    /// footprint wider than any pattern.
    pub footprint: [[f64; 2]; 2],
}

/// One yarn family's BRDF, flat or on a tilted float, with a weight.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lobe {
    /// The warp (the table turned 90°), or the weft.
    pub warp: bool,
    /// Where the yarn lies along its float, when floats tilt.
    pub tilt: Tilt,
    /// The lobe's weight in the point's BRDF.
    pub weight: f64,
    /// A macro lobe scaled by the relief's ratio ([`WovenSurface::relief_ratio`]): the cloth's
    /// BRDF as its resolved points average.
    pub resolved: bool,
    /// Where on its yarn the point lies, at fibre level; `None`: the yarn's (or the cloth's)
    /// averaged BRDF.
    pub point: Option<YarnPoint>,
}

/// How a lobe's yarn tilts along its float ([`SurfaceSpec::u_max`], [`FloatProfile`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Tilt {
    /// Flat: the cloth's own frame.
    #[default]
    Flat,
    /// A point of a tilted float: the fraction along the float, in `[0, 1]`, at which the
    /// viewer's ray crosses the cloth plane. The point shades with the facet that ray meets
    /// ([`FloatProfile::seen_at`]), lit or in a neighbouring float's shadow.
    Entering(f64),
    /// A whole tilted float, its points averaged: the macro BRDF's
    /// `(1/1) ∫ f′ cos θ′i cos θ′o / (cos θi cos θo cos ψ) dt` over the part both lit and seen.
    Float,
    /// A point of the weave's relief ([`Relief`]) that the viewer's ray met: its surface leans
    /// by `lean` (its float's tilt, its crown's roll), and it is lit where no yarn of the relief
    /// stands between it and the light.
    Relief {
        /// The lean of the surface there, in the lobe's frame.
        lean: Lean,
        /// Where the ray met the relief: `x`, `y` in cells and the height in `uv`.
        at: [f64; 3],
    },
}

/// A point on a yarn, resolved to its fibres ([`Detail::Fibers`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct YarnPoint {
    /// The position across its strand (one period of the yarn's profile), in `[0, 1]`: 0 and 1
    /// its edges, 1/2 its crest.
    pub across: f64,
    /// The yarn's lateral slope `θ_a` (drawn per yarn from `P(θ_a)`), radians.
    pub theta_a: f64,
    /// The fibres' azimuth offset from the yarn's axis (drawn per strand), radians.
    pub phi: f64,
    /// The probabilities with which a draw here follows the facet's microfacet lobe and the
    /// facet's cosine (the rest: the cloth normal's cosine), in proportion to the reflectance
    /// of the fibre's sheen, body colour and interreflection (each at least 5 %).
    pub draws: [f64; 2],
}

/// The lobes a point's BRDF mixes: `f = Σ weight · f_lobe`; the weights sum to at most 1, less
/// over the holes between gapped yarns.
#[derive(Clone, Copy, Debug)]
pub struct LobeMix {
    n: usize,
    lobes: [Lobe; MAX_LOBES],
}

impl Default for LobeMix {
    fn default() -> LobeMix {
        LobeMix {
            n: 0,
            lobes: [Lobe::default(); MAX_LOBES],
        }
    }
}

impl LobeMix {
    /// Adds `weight` of a lobe, to the same lobe's weight when it is already there (a cell's
    /// yarn blended into the γ-mix is one of the mix's two yarns: two look-ups, not three).
    #[inline]
    fn push(&mut self, warp: bool, tilt: Tilt, weight: f64) {
        if weight > 0.0 {
            if let Some(l) = self.lobes[..self.n]
                .iter_mut()
                .find(|l| l.warp == warp && l.tilt == tilt && l.point.is_none() && !l.resolved)
            {
                l.weight += weight;
                return;
            }
            self.lobes[self.n] = Lobe {
                warp,
                tilt,
                weight,
                point: None,
                resolved: false,
            };
            self.n += 1;
        }
    }

    /// Adds a fibre-level lobe (never merged: its geometry is its own).
    #[inline]
    fn push_point(&mut self, warp: bool, tilt: Tilt, weight: f64, point: YarnPoint) {
        if weight > 0.0 {
            self.lobes[self.n] = Lobe {
                warp,
                tilt,
                weight,
                point: Some(point),
                resolved: false,
            };
            self.n += 1;
        }
    }

    /// Marks every lobe from the `from`-th on as scaled by the relief's ratio.
    fn resolve_from(&mut self, from: usize) {
        for l in &mut self.lobes[from..self.n] {
            l.resolved = true;
        }
    }

    /// The lobes, in the order they were added.
    pub fn lobes(&self) -> &[Lobe] {
        &self.lobes[..self.n]
    }

    /// The sum of the weights.
    pub fn total(&self) -> f64 {
        self.lobes().iter().map(|l| l.weight).sum()
    }
}

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

/// A woven surface, ready to evaluate at points ([`WovenSurface::at`]).
#[derive(Clone, Debug)]
pub struct WovenSurface {
    yarn: Arc<Table>,
    layout: Layout,
    /// The material's own albedos (what dyes replace).
    own: Albedos,
    weft: [Albedos; 3],
    warp: [Albedos; 3],
    yarns_per_unit: [f64; 2],
    u_max: f64,
    /// The floats' profile: tilt `u_max`, the material's crest and flanks.
    float: FloatProfile,
    gap: f64,
    detail: Detail,
    irregularity: Irregularity,
    /// The exact yarn and its draws, where fibres are resolved ([`Detail::Auto`] and
    /// [`Detail::Fibers`] on a pattern).
    fibers: Option<Fibers>,
    /// The weave's relief, where fibres are resolved: the resolved levels' geometry.
    relief: Option<Relief>,
    /// The relief's ratio table ([`WovenSurface::relief_ratio`]), built on first use.
    ratio: std::sync::OnceLock<Arc<ReliefRatio>>,
    /// The yarn's table averaged over its crown ([`Table::crowned`]), built on first use: the
    /// resolved macro lobes' BRDF before the ratio.
    crowned: std::sync::OnceLock<Arc<Table>>,
}

/// What resolving fibres needs: the exact model of the yarn alone, and its draws.
#[derive(Clone, Debug)]
struct Fibers {
    model: Arc<Model>,
    draws: YarnDraws,
    /// [`Pattern::floats`] and the pattern's columns: where each float starts, for the slope
    /// drawn per float.
    floats: Vec<FloatPlace>,
    cols: usize,
    /// How far the strands shift across the weft's and the warp's yarn per cell along it, in
    /// yarn widths: `tan α` times the cell's length over the yarn's width, `α` the helix angle
    /// ([`YarnDraws::helix_angle`]), `uv` taken as isotropic.
    helix: [f64; 2],
}

impl Fibers {
    fn yarn(&self) -> &Yarn {
        match self.model.structure() {
            Structure::Woven { yarn, .. } => yarn,
            Structure::Flat(_) => unreachable!("fibres are resolved on yarns only"),
        }
    }

    /// The uniform number of the slope of the float of yarn `index` (of family `warp`) over the
    /// cell at `(x, y)` (in cells): the yarn's golden-ratio point, rotated by a hash of where
    /// along the yarn the float starts (the cell itself where the yarn is not on top).
    fn slope_uniform(&self, index: i64, warp: bool, (x, y, cell): (f64, f64, &CellPoint)) -> f64 {
        let along = (if warp { y } else { x }).floor() as i64;
        let place = self.floats.get(cell.row * self.cols + cell.col);
        let start = match place {
            Some(f) if cell.weft != warp && f.len > 0 => along - i64::from(f.before),
            _ => along,
        };
        let family = u64::from(warp);
        let rotation = hash_uniform(start as u64, 0xF10A7 + family);
        (golden_uniform(index, family) + rotation).fract()
    }

    /// [`YarnPoint::draws`] for a yarn dyed `albedos`: the sheen's, the body's and the
    /// interreflection's reflectance (channel means), each at least 5 % of the draws.
    fn draw_shares(&self, albedos: &[Albedos; 3]) -> [f64; 2] {
        let yarn = self.yarn();
        let h = yarn.params().interreflection;
        let rho0 = albedos.iter().map(|a| a.diffuse).sum::<f64>() / 3.0;
        let rho = albedos.iter().map(|a| a.interreflection).sum::<f64>() / 3.0;
        let sheen = match yarn.fiber().params().normalization {
            Normalization::Paper => 1.0 - rho0,
            Normalization::None => 1.0,
        };
        let raw = [(1.0 - h) * sheen, (1.0 - h) * rho0, h * rho].map(|x| x.max(0.0));
        let total: f64 = raw.iter().sum::<f64>().max(1e-12);
        let floored = raw.map(|x| (x / total).max(0.05));
        let total: f64 = floored.iter().sum();
        [floored[0] / total, floored[1] / total]
    }
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
            yarn,
            layout,
            own,
            weft: own.dyed(spec.weft_color),
            warp: own.dyed(spec.warp_color),
            yarns_per_unit: spec.yarns_per_unit,
            u_max: spec.u_max,
            float: spec.float_profile(),
            gap: spec.gap,
            detail: spec.detail,
            irregularity: spec.irregularity,
            relief: fibers.as_ref().and_then(|_| spec.relief()),
            fibers,
            ratio: std::sync::OnceLock::new(),
            crowned: std::sync::OnceLock::new(),
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
            yarn: table,
            layout: Layout::Whole,
            own,
            weft: own.dyed(color),
            warp: own.dyed(color),
            yarns_per_unit: [1.0, 1.0],
            u_max: 0.0,
            float: FloatProfile::new(f64::MIN_POSITIVE),
            gap: 0.0,
            detail: Detail::Yarns,
            irregularity: Irregularity::default(),
            fibers: None,
            relief: None,
            ratio: std::sync::OnceLock::new(),
            crowned: std::sync::OnceLock::new(),
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

    /// The lobes of the macro BRDF (weight 1 in all, less the holes): what every point blends
    /// toward under a wide footprint; the whole BRDF of a surface without a pattern.
    pub fn macro_lobes(&self) -> LobeMix {
        let mut mix = LobeMix::default();
        match &self.layout {
            Layout::Flat { .. } | Layout::Whole => mix.push(false, Tilt::Flat, 1.0),
            Layout::Macro { weft_fraction } | Layout::Pattern { weft_fraction, .. } => {
                self.push_macro(&mut mix, *weft_fraction, 1.0)
            }
        }
        mix
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
        &self.yarn
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

    /// The albedos per channel of the weft (`warp = false`) or the warp.
    pub fn albedos(&self, warp: bool) -> &[Albedos; 3] {
        if warp {
            &self.warp
        } else {
            &self.weft
        }
    }

    /// The weight of the macro BRDF at `at`: 0 while the pixel's footprint spans less than
    /// [`FILTER_CELLS`]`[0]` pattern cells, 1 from [`FILTER_CELLS`]`[1]` on, smooth between. The
    /// footprint's size is the longer side of its bounding box in uv, in cells.
    #[inline]
    pub fn macro_weight(&self, at: &SurfacePoint) -> f64 {
        match self.detail {
            Detail::Cloth => 1.0,
            Detail::Fibers => 0.0,
            Detail::Auto | Detail::Yarns => ramp(self.footprint_cells(at), FILTER_CELLS),
        }
    }

    /// The share of the fibre level in a cell's BRDF at `at`: 1 at [`Detail::Fibers`], 0 at
    /// yarns and cloth; under [`Detail::Auto`] 1 while the footprint spans less than
    /// [`FIBER_CELLS`]`[0]` cells, 0 from [`FIBER_CELLS`]`[1]`, smooth between — and 0 without a
    /// footprint (all zero): a path's later vertices average their light over many paths, and
    /// the yarn level is that average (docs/model.md §8) at a fraction of the fibre level's
    /// variance.
    #[inline]
    pub fn fiber_weight(&self, at: &SurfacePoint) -> f64 {
        match (self.detail, &self.fibers) {
            (_, None) => 0.0,
            (Detail::Fibers, _) => 1.0,
            (Detail::Auto, _) => {
                let cells = self.footprint_cells(at);
                if cells > 0.0 {
                    1.0 - ramp(cells, FIBER_CELLS)
                } else {
                    0.0
                }
            }
            _ => 0.0,
        }
    }

    /// The footprint's size at `at`: the longer side of its bounding box in uv, in cells.
    #[inline]
    fn footprint_cells(&self, at: &SurfacePoint) -> f64 {
        let [a, b] = at.footprint;
        (self.yarns_per_unit[0] * (a[0].abs() + b[0].abs()))
            .max(self.yarns_per_unit[1] * (a[1].abs() + b[1].abs()))
    }

    /// The lobes mixed at `at`. A flat fiber surface has one (its table, for sampling).
    pub fn lobes(&self, at: &SurfacePoint) -> LobeMix {
        let (mix, entry) = self.split(at);
        match entry {
            Some(e) => self.with_relief(mix, &e, Vec3::new(0.0, 0.0, 1.0)),
            None => mix,
        }
    }

    /// The lobes at `at` that do not depend on the view, and, on a relief, where the viewer's
    /// ray enters it (the rest of the point's lobes: [`with_relief`](Self::with_relief)).
    #[inline]
    fn split(&self, at: &SurfacePoint) -> (LobeMix, Option<Entry>) {
        let mut mix = LobeMix::default();
        let mut entry = None;
        match &self.layout {
            Layout::Flat { .. } | Layout::Whole => mix.push(false, Tilt::Flat, 1.0),
            Layout::Macro { weft_fraction } => self.push_macro(&mut mix, *weft_fraction, 1.0),
            Layout::Pattern {
                pattern,
                weft_fraction,
                floats,
            } => {
                let w = self.macro_weight(at);
                let (x, y) = (
                    at.uv[0] * self.yarns_per_unit[0],
                    at.uv[1] * self.yarns_per_unit[1],
                );
                if w < 1.0 {
                    if self.relief.is_some() && x.is_finite() && y.is_finite() {
                        entry = Some(Entry {
                            x,
                            y,
                            weight: 1.0 - w,
                            fibers: self.fiber_weight(at),
                        });
                    } else {
                        self.push_cell(&mut mix, pattern, floats, at, 1.0 - w);
                    }
                }
                if w > 0.0 {
                    let from = mix.n;
                    self.push_macro(&mut mix, *weft_fraction, w);
                    if self.relief.is_some() {
                        mix.resolve_from(from);
                    }
                }
            }
        }
        (mix, entry)
    }

    /// `mix` with the lobes of the relief point that a ray toward `view` entering at `e` meets:
    /// its yarn (at fibre level with the share `e.fibers`, at yarn level with the rest), or the
    /// yarn below in a gap, or nothing in a hole.
    fn with_relief(&self, mut mix: LobeMix, e: &Entry, view: Vec3) -> LobeMix {
        let (Some(relief), Some(pattern)) = (&self.relief, self.pattern()) else {
            return mix;
        };
        let hit = relief.hit(e.x, e.y, view);
        let at = [hit.x, hit.y, hit.z];
        let cell = pattern.cell_at(hit.x, hit.y);
        let (warp, lean) = match hit.ground {
            Ground::Top { warp, t, across } => {
                let tilt = match t {
                    Some(t) if self.u_max > 0.0 => relief.tilt(warp, t),
                    _ => 0.0,
                };
                // In the warp's frame (y turned to x) its +y is the cloth's −x.
                let roll = Relief::roll(if warp { -across } else { across });
                let lean = Lean {
                    tilt: tilt.sin_cos(),
                    roll: roll.sin_cos(),
                };
                (warp, lean)
            }
            Ground::Below { warp } => (warp, Lean::FLAT),
            Ground::Hole => return mix,
        };
        let tilt = Tilt::Relief { lean, at };
        self.push_yarn(
            &mut mix,
            warp,
            tilt,
            e.weight,
            e.fibers,
            (hit.x, hit.y, &cell),
        );
        mix
    }

    /// Builds now what the resolved levels would build on first use: the crowned yarn table and
    /// the relief's ratio table, the ratio read from `dir` when it was stored there before (and
    /// stored there when built). Nothing to do without a relief (`detail` other than `"fibers"`
    /// and `"auto"`, or no pattern). `note` hears why a stored ratio was not used, or why a built
    /// one could not be stored (the surface works either way).
    pub fn prepare(&self, dir: Option<&std::path::Path>, note: &dyn Fn(&str)) {
        if self.relief.is_none() {
            return;
        }
        let _ = self.crowned();
        self.ratio.get_or_init(|| {
            Arc::new(match dir {
                Some(dir) => ReliefRatio::load_or_build(self, dir, note),
                None => ReliefRatio::build(self),
            })
        });
    }

    /// This surface ready for its resolved levels, from `tables`: its yarn's crowned table
    /// (`options` crowned at [`CROWN_DEG`](crate::relief::CROWN_DEG): from memory, from disk, or
    /// built from the yarn's table on `options`) and the relief's ratio, kept in the tables'
    /// folder ([`prepare`](Self::prepare)). A surface that does not resolve the relief is
    /// returned as it is. `material` is the yarn tabulated ([`SurfaceSpec::table_material`]),
    /// `on_build` and `progress` as [`Tables::table`](crate::table::cache::Tables::table) has
    /// them; the tables' notes hear why a stored file was not used.
    ///
    /// # Errors
    /// An invalid material or options.
    pub fn prepared_from(
        self,
        tables: &mut crate::table::cache::Tables,
        material: &Material,
        wavelength_nm: f64,
        options: &TableOptions,
        on_build: &dyn Fn(Option<&std::path::Path>),
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<WovenSurface> {
        if !self.resolves_relief() {
            return Ok(self);
        }
        let crowned = TableOptions {
            crown_deg: crate::relief::CROWN_DEG,
            ..*options
        };
        let crowned = tables.table(material, wavelength_nm, &crowned, on_build, progress)?;
        let surface = self.with_crowned(crowned)?;
        let dir = tables.disk().map(|d| d.dir().to_path_buf());
        surface.prepare(dir.as_deref(), &|m| tables.note(m));
        Ok(surface)
    }

    /// Whether the surface resolves its weave's relief (`detail` `"fibers"` or `"auto"` on a
    /// pattern): then it reads a crowned yarn table ([`with_crowned`](Self::with_crowned)) and
    /// the relief's ratio ([`prepare`](Self::prepare)).
    pub fn resolves_relief(&self) -> bool {
        self.relief.is_some()
    }

    /// This surface with `crowned` as its crowned yarn table, the yarn's table built with
    /// [`TableOptions::crown_deg`] = [`CROWN_DEG`](crate::relief::CROWN_DEG) (a renderer keeps it
    /// in its table cache; without it, the surface builds it from the yarn's table on first use).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `crowned` for a table of another crown.
    pub fn with_crowned(self, crowned: Arc<Table>) -> Result<WovenSurface> {
        if crowned.crown_deg() != crate::relief::CROWN_DEG {
            return Err(Error::InvalidParameter {
                name: "crowned".into(),
                value: format!("a table crowned at {}°", crowned.crown_deg()),
                expected: format!("a table crowned at {}°", crate::relief::CROWN_DEG),
            });
        }
        let _ = self.crowned.set(crowned);
        Ok(self)
    }

    /// The yarn's table averaged over its crown (built on first use).
    fn crowned(&self) -> &Table {
        self.crowned.get_or_init(|| {
            // On the yarn table's grid (an isotropic yarn's: the renderer's azimuths).
            let (n_theta, n_phi, n_h) = self.yarn.dims();
            let options = TableOptions {
                n_theta,
                n_phi: if n_phi > 1 {
                    n_phi
                } else {
                    crate::table::N_PHI_RENDER
                },
                n_h,
                ..TableOptions::default()
            };
            Arc::new(self.yarn.crowned(crate::relief::CROWN_DEG, &options))
        })
    }

    /// Both families' relief ratios `[R_weft, R_warp]` at `(s, v)` ([`relief_ratio`](Self::relief_ratio)).
    fn relief_ratios(&self, s: Vec3, v: Vec3) -> [f64; 2] {
        if self.relief.is_none() {
            return [1.0; 2];
        }
        self.ratio
            .get_or_init(|| Arc::new(ReliefRatio::build(self)))
            .pair(s, v)
    }

    /// The relief's ratio `R_F(s, v)` for the family `warp` (the module `ratio`'s table, built
    /// on first use): what scales the macro lobes of a resolving surface. 1 without a relief.
    pub fn relief_ratio(&self, warp: bool, s: Vec3, v: Vec3) -> f64 {
        if self.relief.is_none() {
            return 1.0;
        }
        self.ratio
            .get_or_init(|| Arc::new(ReliefRatio::build(self)))
            .at(warp, s, v)
    }

    /// The surface's BSDF at `at`.
    #[inline]
    pub fn at(&self, at: &SurfacePoint) -> PointBsdf<'_> {
        let (mix, entry) = self.split(at);
        let factors = self.dye_factors(at);
        PointBsdf {
            surface: self,
            entry,
            mix,
            seen: std::sync::OnceLock::new(),
            weft: scaled(self.weft, factors[0]),
            warp: scaled(self.warp, factors[1]),
            factors,
        }
    }

    /// The weft's and the warp's dye factors at `at` ([`Irregularity::factor`] of the yarns
    /// through the point); 1 and 1 without irregularity.
    pub fn dye_factors(&self, at: &SurfacePoint) -> [f64; 2] {
        if !self.irregularity.is_active() || !matches!(self.layout, Layout::Pattern { .. }) {
            return [1.0, 1.0];
        }
        let x = at.uv[0] * self.yarns_per_unit[0];
        let y = at.uv[1] * self.yarns_per_unit[1];
        if !(x.is_finite() && y.is_finite()) {
            return [1.0, 1.0];
        }
        // The weft runs along x: its yarns are the rows, its length x; the warp the other way.
        [
            self.irregularity.factor(y.floor() as i64, false, x),
            self.irregularity.factor(x.floor() as i64, true, y),
        ]
    }

    /// The lobes of a macro BRDF with weft fraction `g`, scaled by `scale`: each family on top
    /// over `(1 − gap)` of its cells' width (a whole float when floats tilt), and seen flat in
    /// the other family's gaps where it is not itself in a gap.
    fn push_macro(&self, mix: &mut LobeMix, g: f64, scale: f64) {
        let gap = self.gap;
        if gap == 0.0 && self.u_max == 0.0 {
            mix.push(false, Tilt::Flat, scale * g);
            mix.push(true, Tilt::Flat, scale * (1.0 - g));
            return;
        }
        let top = [(1.0 - gap) * g, (1.0 - gap) * (1.0 - g)];
        let below = [gap * (1.0 - gap) * (1.0 - g), gap * (1.0 - gap) * g];
        for (k, warp) in [false, true].into_iter().enumerate() {
            if self.u_max == 0.0 {
                mix.push(warp, Tilt::Flat, scale * (top[k] + below[k]));
            } else {
                mix.push(warp, Tilt::Float, scale * top[k]);
                mix.push(warp, Tilt::Flat, scale * below[k]);
            }
        }
    }

    /// The lobes of the pattern cell at `at`, with weight `scale`: the yarn on top, tilted by
    /// its place along its float; in a gap across it, the crossing yarn below (flat); in a
    /// gap of both, nothing. Each at fibre level (its share [`fiber_weight`](Self::fiber_weight))
    /// and at yarn level. A non-finite uv shades as the weft.
    fn push_cell(
        &self,
        mix: &mut LobeMix,
        pattern: &Pattern,
        floats: &[FloatPlace],
        at: &SurfacePoint,
        scale: f64,
    ) {
        let (x, y) = (
            at.uv[0] * self.yarns_per_unit[0],
            at.uv[1] * self.yarns_per_unit[1],
        );
        if !(x.is_finite() && y.is_finite()) {
            mix.push(false, Tilt::Flat, scale);
            return;
        }
        let cell = pattern.cell_at(x, y);
        let top = !cell.weft;
        let fibers = self.fiber_weight(at);
        if self.gap == 0.0 && self.u_max == 0.0 {
            self.push_yarn(mix, top, Tilt::Flat, scale, fibers, (x, y, &cell));
            return;
        }
        // A yarn covers the middle (1 − gap) of the cell across its axis: the weft spans y,
        // the warp spans x.
        let half = 0.5 * (1.0 - self.gap);
        let covers = |warp: bool| ((if warp { cell.x } else { cell.y }) - 0.5).abs() < half;
        if covers(top) {
            let tilt = match floats.get(cell.row * pattern.cols() + cell.col) {
                Some(f) if f.len > 0 => {
                    let along = if top { cell.y } else { cell.x };
                    Tilt::Entering((f64::from(f.before) + along) / f64::from(f.len))
                }
                _ => Tilt::Flat,
            };
            self.push_yarn(mix, top, tilt, scale, fibers, (x, y, &cell));
        } else if covers(!top) {
            self.push_yarn(mix, !top, Tilt::Flat, scale, fibers, (x, y, &cell));
        }
    }

    /// The lobes of the yarn of family `warp` at a point of a cell (`(x, y)` in cells): at fibre
    /// level with weight `scale · fibers`, at yarn level with the rest.
    fn push_yarn(
        &self,
        mix: &mut LobeMix,
        warp: bool,
        tilt: Tilt,
        scale: f64,
        fibers: f64,
        (x, y, cell): (f64, f64, &CellPoint),
    ) {
        if let Some(f) = self.fibers.as_ref().filter(|_| fibers > 0.0) {
            // Across the yarn: the weft spans y, the warp x (its frame turns y to x, so its
            // profile's e_u runs along −x); a gap's share of the cell is not yarn.
            let g = self.gap;
            let frac = if warp { cell.x } else { cell.y };
            let mut across = ((frac - 0.5 * g) / (1.0 - g)).clamp(0.0, 1.0);
            if warp {
                across = 1.0 - across;
            }
            // Each float of each yarn (a pick for the weft, an end for the warp, counted over
            // the whole surface; a float from where it comes up) draws its slope, each strand
            // of fibres its azimuth: golden-ratio points by the yarn's index, rotated per float
            // by a hash, so neighbours differ, a yarn's cross-section varies along it, and a
            // patch of a few dozen yarns averages to the model.
            let index = (if warp { x } else { y }).floor() as i64;
            let family = u64::from(warp);
            let theta_a = f.draws.slope(f.slope_uniform(index, warp, (x, y, cell)));
            // The yarn is STRANDS strands side by side, each one period of the yarn's profile
            // (its fibres' prism). Strands wind about the yarn at its helix angle: across the
            // yarn they shift by `helix` yarn widths per cell along it (wrapping round), so they
            // show as diagonal stripes, and every place along the yarn still holds each strand.
            let along = if warp { y } else { x };
            let wound = (across + along * f.helix[usize::from(warp)]) * STRANDS as f64;
            let strand = (wound.floor() as i64).rem_euclid(STRANDS as i64);
            let phi = if f.draws.varies_in_azimuth() {
                let fibre = index.wrapping_mul(STRANDS as i64).wrapping_add(strand);
                f.draws.twist(golden_uniform(fibre, 2 + family))
            } else {
                0.0
            };
            let point = YarnPoint {
                across: wound - wound.floor(),
                theta_a,
                phi,
                draws: f.draw_shares(if warp { &self.warp } else { &self.weft }),
            };
            mix.push_point(warp, tilt, scale * fibers, point);
        }
        mix.push(warp, tilt, scale * (1.0 - fibers));
    }

    /// One lobe's BRDF per channel: the weft, or the warp (turned), flat or on its float.
    ///
    /// On a tilted float a point shades as the facet the viewer's ray meets
    /// ([`FloatProfile::seen_at`]), if lit: `f′(ti, to) cos θ′i / cos θi` — the facet's radiance
    /// for unit irradiance on the cloth, its own incident cosine over the cloth's — so no point
    /// is brighter than its facet. The whole float ([`Tilt::Float`]) is those points' mean: the
    /// facets both lit and seen, each over its projected area toward the viewer,
    /// `cos θ′o / (cos θo cos ψ)` per unit of cloth ([`TILT_NODES`] Gauss–Legendre nodes). At
    /// fibre level the same holds for the point's BRDF, whose profile lies in the tilted frame
    /// (the tilt turns the yarn about its cross axis; the profile runs across it).
    #[inline]
    fn lobe_eval(
        &self,
        lobe: &Lobe,
        albedos: &[Albedos; 3],
        wi: Vec3,
        wo: Vec3,
        ratio: Option<f64>,
    ) -> Rgb {
        if let (Tilt::Relief { at, .. }, Some(relief)) = (lobe.tilt, &self.relief) {
            if !relief.sees(at, wi) {
                return Rgb::BLACK;
            }
        }
        if let Some(ratio) = ratio {
            return self.lobe_value(lobe, albedos, wi, wo) * ratio;
        }
        self.lobe_value(lobe, albedos, wi, wo)
    }

    /// [`lobe_eval`](Self::lobe_eval) before the relief: a relief point as if lit, a macro lobe
    /// unscaled.
    #[inline]
    fn lobe_value(&self, lobe: &Lobe, albedos: &[Albedos; 3], wi: Vec3, wo: Vec3) -> Rgb {
        self.lobe_with(lobe, wi, wo, |table, a, b| {
            match (&lobe.point, &self.fibers) {
                (Some(p), Some(f)) => point_eval(f, p, albedos, a, b),
                _ => Rgb(table.eval_dyed(a, b, albedos)),
            }
        })
    }

    /// [`lobe_value`](Self::lobe_value) of an averaged lobe (not a fibre point) at the
    /// material's own albedos, one value (what the relief's ratio is built from).
    #[inline]
    fn lobe_value_own(&self, lobe: &Lobe, wi: Vec3, wo: Vec3) -> f64 {
        debug_assert!(lobe.point.is_none());
        self.lobe_with(lobe, wi, wo, |table, a, b| table.eval(a, b))
    }

    /// A lobe's value from `value(table, s′, v′)`, the BRDF of a facet in its own frame read
    /// from `table`: the yarn's, or for a resolved macro lobe the crowned yarn's on the relief's
    /// floats.
    #[inline]
    fn lobe_with<V>(
        &self,
        lobe: &Lobe,
        wi: Vec3,
        wo: Vec3,
        value: impl Fn(&Table, Vec3, Vec3) -> V,
    ) -> V
    where
        V: Default + std::ops::AddAssign + std::ops::Mul<f64, Output = V>,
    {
        let (wi, wo) = into_lobe_frame(lobe, wi, wo);
        let (table, float) = match (&self.relief, lobe.resolved) {
            (Some(relief), true) => (self.crowned(), &relief.float(lobe.warp)),
            _ => (&*self.yarn, &self.float),
        };
        let value = |a: Vec3, b: Vec3| value(table, a, b);
        // A leaning facet's radiance for unit irradiance on the cloth: its BRDF in its own
        // frame, times its incident cosine over the cloth's.
        let leaning = |lean: Lean| {
            let (ti, to) = (lean.into_frame(wi), lean.into_frame(wo));
            if ti.z <= 0.0 || to.z <= 0.0 {
                return V::default();
            }
            value(ti, to) * (ti.z / wi.z)
        };
        match lobe.tilt {
            Tilt::Flat => value(wi, wo),
            Tilt::Entering(entry) => {
                let t = float.seen_at(entry, wo);
                match float.lit(wi) {
                    Some((lo, hi)) if (lo..=hi).contains(&t) => {}
                    _ => return V::default(),
                }
                leaning(Lean::tilted(float.tilt(t).sin_cos()))
            }
            Tilt::Relief { lean, .. } => leaning(lean),
            Tilt::Float => float.average(wi, wo, value),
        }
    }

    /// The tilt (sine, cosine) a draw for `known` (in the lobe's frame) uses, drawing a tilt
    /// node of a whole float with `u` (returned stretched back to `[0, 1)`): the facet that
    /// `known`'s ray meets for a point, the [`TILT_NODES`] midpoints of a whole float. `None`
    /// for a flat lobe.
    #[inline]
    fn draw_tilt(&self, lobe: &Lobe, known: Vec3, u: f64) -> (Option<Lean>, f64) {
        let float = &self.float;
        match lobe.tilt {
            Tilt::Flat => (None, u),
            Tilt::Entering(entry) => {
                let t = float.seen_at(entry, known);
                (Some(Lean::tilted(float.tilt(t).sin_cos())), u)
            }
            Tilt::Relief { lean, .. } => (Some(lean), u),
            Tilt::Float => {
                let x = u * TILT_NODES as f64;
                let i = (x as usize).min(TILT_NODES - 1);
                let t = (i as f64 + 0.5) / TILT_NODES as f64;
                (
                    Some(Lean::tilted(float.tilt(t).sin_cos())),
                    (x - i as f64).clamp(0.0, 1.0 - f64::EPSILON),
                )
            }
        }
    }

    /// The density of drawing `drawn` for `known` from one lobe (a rotation keeps densities per
    /// solid angle); for a whole float, the mean over its tilt nodes.
    #[inline]
    fn lobe_pdf(&self, lobe: &Lobe, known: Vec3, drawn: Vec3) -> f64 {
        let (k, d) = into_lobe_frame(lobe, known, drawn);
        let untilted = |k: Vec3, d: Vec3| match (&lobe.point, &self.fibers) {
            (Some(p), Some(f)) => point_pdf(f, p, k, d),
            _ => self.yarn.pdf_direction(k, d),
        };
        let tilted = |lean: Lean| {
            let (k, d) = (lean.into_frame(k), lean.into_frame(d));
            if k.z <= 0.0 || d.z <= 0.0 {
                0.0
            } else {
                untilted(k, d)
            }
        };
        match lobe.tilt {
            Tilt::Flat => untilted(k, d),
            Tilt::Entering(_) | Tilt::Relief { .. } => {
                tilted(self.draw_tilt(lobe, k, 0.0).0.unwrap_or(Lean::FLAT))
            }
            Tilt::Float => {
                let float = &self.float;
                (0..TILT_NODES)
                    .map(|i| {
                        let t = (i as f64 + 0.5) / TILT_NODES as f64;
                        tilted(Lean::tilted(float.tilt(t).sin_cos()))
                    })
                    .sum::<f64>()
                    / TILT_NODES as f64
            }
        }
    }

    /// Draws a direction for `known` from one lobe, with its density
    /// ([`lobe_pdf`](Self::lobe_pdf)); for a whole float, the density of the tilt node it was
    /// drawn from (the lobe's is the nodes' mean, which [`PointBsdf`]'s `sample` takes).
    #[inline]
    fn lobe_sample(&self, lobe: &Lobe, known: Vec3, u: [f64; 2]) -> Option<(Vec3, f64)> {
        let k0 = if lobe.warp { to_warp(known) } else { known };
        let (lean, u0) = self.draw_tilt(lobe, k0, u[0]);
        let k = match lean {
            Some(lean) => lean.into_frame(k0),
            None => k0,
        };
        if k.z <= 0.0 {
            return None;
        }
        let (mut d, pdf) = match (&lobe.point, &self.fibers) {
            (Some(p), Some(f)) => point_sample(f, p, k, [u0, u[1]])?,
            _ => self.yarn.sample_direction(k, u0, u[1])?,
        };
        if d.z <= 0.0 || pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        if let Some(lean) = lean {
            d = lean.from_frame(d);
        }
        if lobe.warp {
            d = from_warp(d);
        }
        if d.z <= 0.0 {
            return None;
        }
        Some((d, pdf))
    }
}

/// The BRDF per channel at a point on a yarn (in its lobe's frame: the yarn along `x`):
/// `(1 − ħ) f_point + ħ ρ/π` ([`Yarn::point_parts`], Eq. (20')), dyed as the table is.
#[inline]
fn point_eval(f: &Fibers, p: &YarnPoint, albedos: &[Albedos; 3], s: Vec3, v: Vec3) -> Rgb {
    let yarn = f.yarn();
    let parts = yarn.point_parts(s, v, p.phi, p.theta_a, p.across);
    let (fixed, per_diffuse) = yarn.fiber().affine_in_diffuse(parts);
    let h = yarn.params().interreflection;
    Rgb(albedos.map(|a| {
        ((1.0 - h) * (fixed + a.diffuse * per_diffuse) + h * a.interreflection * FRAC_1_PI).max(0.0)
    }))
}

/// The density of a fibre-level draw: the facet's Beckmann lobe (the fiber's roughness) about
/// its normal with probability [`YarnPoint::draws`]`[0]`, cosine-weighted about the facet's
/// normal with [`YarnPoint::draws`]`[1]` (the facet's body colour, `∝ s·a`: a lit facet's diffuse light is
/// then drawn with a bounded weight), else cosine-weighted about the cloth's normal (the
/// interreflection). The facet is the one `known`'s ray meets.
#[inline]
fn point_pdf(f: &Fibers, p: &YarnPoint, known: Vec3, drawn: Vec3) -> f64 {
    if known.z <= 0.0 || drawn.z <= 0.0 {
        return 0.0;
    }
    let a = f.yarn().point_normal(known, p.phi, p.theta_a, p.across);
    point_pdf_about(f, p, a, known, drawn)
}

/// [`point_pdf`] about the facet normal `a` that `known`'s ray meets (found once by the caller).
#[inline]
fn point_pdf_about(f: &Fibers, p: &YarnPoint, a: Vec3, known: Vec3, drawn: Vec3) -> f64 {
    let glossy = beckmann_reflection_pdf(known, drawn, a, f.yarn().fiber().alpha());
    let [g, c] = p.draws;
    g * glossy + c * drawn.dot(a).max(0.0) * FRAC_1_PI + (1.0 - g - c) * drawn.z * FRAC_1_PI
}

/// A fibre-level draw for `known` and its density ([`point_pdf`]).
#[inline]
fn point_sample(f: &Fibers, p: &YarnPoint, known: Vec3, u: [f64; 2]) -> Option<(Vec3, f64)> {
    let [g, c] = p.draws;
    let yarn = f.yarn();
    let a = yarn.point_normal(known, p.phi, p.theta_a, p.across);
    let drawn = if u[0] < g {
        let h = sample_beckmann(a, yarn.fiber().alpha(), [u[0] / g, u[1]]);
        let kh = known.dot(h);
        if kh <= 0.0 {
            return None;
        }
        h * (2.0 * kh) - known
    } else if u[0] < g + c {
        let d = cosine_hemisphere(((u[0] - g) / c).min(1.0), u[1]);
        let (t, b) = basis(a);
        (t * d.x + b * d.y + a * d.z).normalize()
    } else {
        // Horizon draws are rejected below.
        cosine_hemisphere(((u[0] - g - c) / (1.0 - g - c)).min(1.0), u[1])
    };
    if drawn.z <= 0.0 {
        return None;
    }
    let pdf = point_pdf_about(f, p, a, known, drawn);
    (pdf > 0.0 && pdf.is_finite()).then_some((drawn, pdf))
}

/// A Beckmann microfacet normal of width `alpha` about `n`, drawn ∝ `D(h) (h·n)`.
#[inline]
fn sample_beckmann(n: Vec3, alpha: f64, [u1, u2]: [f64; 2]) -> Vec3 {
    let tan2 = -alpha * alpha * (1.0 - u1).max(1e-300).ln();
    let cos = 1.0 / (1.0 + tan2).sqrt();
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    let (t, b) = basis(n);
    (t * (sin * phi.cos()) + b * (sin * phi.sin()) + n * cos).normalize()
}

/// The density of the direction `drawn` reflected from `known` about a Beckmann normal of width
/// `alpha` about `n` (drawn by [`sample_beckmann`]): `D(h) (h·n) / (4 |drawn·h|)`.
#[inline]
fn beckmann_reflection_pdf(known: Vec3, drawn: Vec3, n: Vec3, alpha: f64) -> f64 {
    let h = (known + drawn).normalize();
    let (cos, dh) = (h.dot(n), drawn.dot(h));
    if cos <= 0.0 || dh <= 0.0 || !cos.is_finite() {
        return 0.0;
    }
    let c2 = cos * cos;
    let tan2 = (1.0 - c2) / c2;
    let d = (-tan2 / (alpha * alpha)).exp() / (PI * alpha * alpha * c2 * c2);
    d * cos / (4.0 * dh)
}

/// Two unit vectors completing `n` to a right-handed orthonormal basis (Duff et al.'s).
#[inline]
fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Where a viewer's ray enters a surface's relief, and the shares of the lobes it meets there.
#[derive(Clone, Copy, Debug)]
struct Entry {
    /// The entry, in cells.
    x: f64,
    y: f64,
    /// The cell's share of the point's BRDF (the rest is the macro BRDF's).
    weight: f64,
    /// The fibre level's share of the cell's.
    fibers: f64,
}

/// `albedos` with the body scaled by `factor` (an [`Irregularity`]'s), each kept in its range
/// (`ρ0 ≤ 0.999`, `ρ ≤ 1`, as [`Albedos::dyed`] keeps them).
fn scaled(albedos: [Albedos; 3], factor: f64) -> [Albedos; 3] {
    if factor == 1.0 {
        return albedos;
    }
    albedos.map(|a| Albedos {
        diffuse: (a.diffuse * factor).min(0.999),
        interreflection: (a.interreflection * factor).min(1.0),
    })
}

/// A woven surface's BSDF at one point: its mixture of lobes.
#[derive(Clone, Debug)]
pub struct PointBsdf<'a> {
    surface: &'a WovenSurface,
    /// On a relief, where the viewer's ray enters it: the lobes it meets depend on the view.
    entry: Option<Entry>,
    /// The lobes that do not depend on the view.
    mix: LobeMix,
    /// The first view's lobes on a relief ([`mix_seen_from`](Self::mix_seen_from)).
    seen: std::sync::OnceLock<(Vec3, LobeMix)>,
    weft: [Albedos; 3],
    warp: [Albedos; 3],
    /// The weft's and the warp's dye factors here ([`WovenSurface::dye_factors`]).
    factors: [f64; 2],
}

impl PointBsdf<'_> {
    /// The lobes mixed here.
    pub fn mix(&self) -> LobeMix {
        self.mix_seen_from(Vec3::new(0.0, 0.0, 1.0))
    }

    /// The lobes mixed here for a viewer toward `view` (or, drawing for a known light, toward
    /// it): on a relief, the yarn that the ray toward `view` meets first.
    #[inline]
    pub fn mix_seen_from(&self, view: Vec3) -> LobeMix {
        let Some(e) = &self.entry else {
            return self.mix;
        };
        // A renderer asks for the same view several times at a vertex (eval, sample, pdf): the
        // first view's march is kept.
        if let Some((seen, mix)) = self.seen.get() {
            if *seen == view {
                return *mix;
            }
        }
        let mix = self.surface.with_relief(self.mix, e, view);
        let _ = self.seen.set((view, mix));
        mix
    }

    /// The same point with other dyes where given (a textured colour, read at the point), each
    /// channel clamped to `[0, 1]`, and varied along the yarns as the surface's are.
    pub fn dyed(mut self, weft_color: Option<Rgb>, warp_color: Option<Rgb>) -> Self {
        if weft_color.is_some() {
            self.weft = scaled(self.surface.own.dyed(weft_color), self.factors[0]);
        }
        if warp_color.is_some() {
            self.warp = scaled(self.surface.own.dyed(warp_color), self.factors[1]);
        }
        self
    }

    fn pdf_mix(&self, mix: &LobeMix, known: Vec3, drawn: Vec3) -> f64 {
        let mut p = 0.0;
        for l in mix.lobes() {
            p += l.weight * self.surface.lobe_pdf(l, known, drawn);
        }
        let total = mix.total();
        if total == 1.0 || total == 0.0 {
            p
        } else {
            p / total
        }
    }
}

impl Bsdf for PointBsdf<'_> {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        let flags = LobeFlags::REFLECTION | LobeFlags::GLOSSY | LobeFlags::DIFFUSE;
        let flags = flags | LobeFlags::ANISOTROPIC;
        if self.surface.uses_footprint() {
            flags | LobeFlags::SPATIALLY_VARYING
        } else {
            flags
        }
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::BLACK;
        }
        if let Layout::Flat { model } = &self.surface.layout {
            let affine = model.eval_affine(wi, wo);
            return Rgb(self
                .weft
                .map(|a| affine.at(a.diffuse, a.interreflection).max(0.0)));
        }
        let mut f = Rgb::BLACK;
        // Both families' relief ratios in one read, when a resolved macro lobe needs them.
        let mut ratios = None;
        for l in self.mix_seen_from(wo).lobes() {
            let albedos = if l.warp { &self.warp } else { &self.weft };
            let ratio = l.resolved.then(|| {
                ratios.get_or_insert_with(|| self.surface.relief_ratios(wi, wo))
                    [usize::from(l.warp)]
            });
            f += self.surface.lobe_eval(l, albedos, wi, wo, ratio) * l.weight;
        }
        f
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        self.pdf_mix(&self.mix_seen_from(known), known, drawn)
    }

    fn sample(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Rgb>> {
        if known.z <= 0.0 {
            return None;
        }
        // A lobe with probability ∝ its weight; the density is the mixture's.
        let mix = self.mix_seen_from(known);
        let lobes = mix.lobes();
        let last = lobes.len().checked_sub(1)?;
        let x = uc * mix.total();
        let mut before = 0.0;
        let mut pick = 0;
        while pick < last && x >= before + lobes[pick].weight {
            before += lobes[pick].weight;
            pick += 1;
        }
        let (drawn, pdf) = self.surface.lobe_sample(&lobes[pick], known, u)?;
        // A whole float's draw came from one of its tilt nodes: its density is the nodes'
        // mean, as is that of a mixture of lobes.
        let pdf = if lobes.len() == 1 && lobes[pick].tilt != Tilt::Float {
            pdf
        } else {
            self.pdf_mix(&mix, known, drawn)
        };
        let (wi, wo) = pair_of(known, drawn, mode);
        (pdf > 0.0 && pdf.is_finite()).then(|| BsdfSample {
            wi,
            wo,
            f: self.eval(wi, wo),
            pdf,
            lobe: LobeFlags::REFLECTION | LobeFlags::GLOSSY,
        })
    }
}

/// A pair of directions in the frame of a lobe's family (turned for the warp; not yet tilted).
#[inline]
fn into_lobe_frame(lobe: &Lobe, a: Vec3, b: Vec3) -> (Vec3, Vec3) {
    if lobe.warp {
        (to_warp(a), to_warp(b))
    } else {
        (a, b)
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

/// 0 up to `edges[0]`, 1 from `edges[1]`, [`smoothstep`] between.
#[inline]
fn ramp(x: f64, edges: [f64; 2]) -> f64 {
    if x > edges[0] {
        smoothstep((x - edges[0]) / (edges[1] - edges[0]))
    } else {
        0.0
    }
}

/// `x ↦ 3x² − 2x³` on `[0, 1]`, clamped.
#[inline]
fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}
