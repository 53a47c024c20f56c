//! What a woven surface is ([`SurfaceSpec`]): a material, how its weave lies on the surface's
//! uv, its dyes, its yarns' tilt and gaps, and how finely it is resolved ([`Detail`]); the
//! limits on each, and their checks. The keys the front ends write them with are in
//! `keys.rs` ([`SURFACE_KEYS`](super::SURFACE_KEYS)).

use super::Irregularity;
use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::material::{Material, Weave};
use crate::relief::Relief;
use crate::yarn::float::FloatProfile;

/// How finely a surface resolves its weave (the `detail` key of woven materials).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Detail {
    /// By the pixel's footprint: fibres where it is well under a yarn's width, yarns from about
    /// a third of a cell ([`FIBER_CELLS`](super::FIBER_CELLS)), the cloth's macro BRDF from two cells
    /// ([`FILTER_CELLS`](super::FILTER_CELLS)), smoothly between.
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
        Self::ALL
            .into_iter()
            .find(|d| d.name() == name)
            .ok_or_else(|| Error::InvalidParameter {
                name: "detail".into(),
                value: format!("{name:?}"),
                expected: Self::one_of(),
            })
    }

    /// The level's name (its entry of [`NAMES`](Self::NAMES)).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The valid names as an error states them: `one of "auto", "fibers", "yarns", "cloth"`.
    pub fn one_of() -> String {
        let names: Vec<String> = Self::NAMES.iter().map(|n| format!("{n:?}")).collect();
        format!("one of {}", names.join(", "))
    }

    /// The levels, in the order of [`NAMES`](Self::NAMES).
    const ALL: [Detail; 4] = [Detail::Auto, Detail::Fibers, Detail::Yarns, Detail::Cloth];
}

/// The largest yarn tilt [`SurfaceSpec::u_max`], degrees.
pub const MAX_U_MAX_DEG: f64 = 80.0;

pub use crate::gaps::MAX_GAP;

/// Pattern cells per unit of `u` and of `v` where a surface is not told
/// ([`SurfaceSpec::yarns_per_unit`]): the default of every front end (scene files,
/// `woven.Surface`, the Mitsuba plugin).
pub const DEFAULT_YARNS_PER_UNIT: f64 = 40.0;

/// What a dye must be ([`SurfaceSpec::weft_color`], [`SurfaceSpec::warp_color`]).
pub(super) const COLOR_VALID: &str = "three values in [0, 1]";

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
    /// Whether the weave is a relief ([`relief`](Self::relief)): yarns dip under the yarns they
    /// cross and shadow their neighbours, at every level (fibres and yarns on the relief, the
    /// cloth as their ratio-scaled macro lobes, docs/model.md, "The relief"). `false` (the
    /// default): the paper's BRDF at every level, which `woven eval`, the tables and every fit
    /// are.
    pub relief: bool,
    /// Whether light passes between the yarns ([`gaps`](crate::gaps): the open area the gaps
    /// leave along a direction, a delta lobe straight through): an option beyond the paper,
    /// whose cloth is opaque. Off (the default): nothing passes, as in the paper.
    pub transmission: bool,
}

impl SurfaceSpec {
    /// `material` with [`DEFAULT_YARNS_PER_UNIT`] pattern cells per unit of uv, its own colours
    /// (its `[dye]`, if any), its own float tilt (`[yarn] u_max_deg`, 0 for the paper's flat
    /// yarns), its own gaps and transmission (`[weave] gap` and `transmission`: none for the
    /// paper's opaque cloth), [`Detail::Auto`], no irregularity: the defaults of
    /// [`SURFACE_KEYS`](super::SURFACE_KEYS).
    pub fn new(material: Material) -> SurfaceSpec {
        let dye = material.dye;
        let u_max = material.yarn.map_or(0.0, |y| y.u_max);
        let open = material.openness;
        SurfaceSpec {
            material,
            yarns_per_unit: [DEFAULT_YARNS_PER_UNIT; 2],
            weft_color: dye.weft,
            warp_color: dye.warp,
            u_max,
            gap: open.gap,
            detail: Detail::Auto,
            irregularity: Irregularity::default(),
            relief: false,
            transmission: open.transmission,
        }
    }

    /// The same surface seen from its back: its material's back
    /// ([`Material::back`](crate::material::Material::back): the pattern's complement), all else
    /// the same. Its cells lie where the front's do, and its holes too.
    pub fn back(&self) -> SurfaceSpec {
        SurfaceSpec {
            material: self.material.back(),
            ..self.clone()
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
    /// crowns, laid on its pattern); `None` without a pattern, or with
    /// [`relief`](SurfaceSpec::relief) off.
    pub fn relief_geometry(&self) -> Option<Relief> {
        match &self.material.weave {
            Some(Weave::Pattern { pattern, .. }) if self.relief => Some(Relief::new(
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
    /// `weft_color`, `warp_color`, `u_max`, `gap`, `relief`, `transmission`, `irregularity`,
    /// `irregularity_length`), its
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
                    return invalid(name, format!("{:?}", c.0), COLOR_VALID);
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
        if self.relief && !matches!(self.material.weave, Some(Weave::Pattern { .. })) {
            return invalid(
                "relief",
                "true without a weave pattern".into(),
                "false, or a material whose weave is a pattern (a relief lies on its cells)",
            );
        }
        if self.transmission && self.material.yarn.is_none() {
            return invalid(
                "transmission",
                "true with a flat fiber surface".into(),
                "false: a flat fiber surface (no [yarn]) has no yarns to pass light through or \
                 between",
            );
        }
        self.irregularity.validate_for(&self.material)
    }
}
