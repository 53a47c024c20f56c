//! What a woven surface is ([`SurfaceSpec`]): a material, how its weave lies on the surface's
//! uv, its dyes, its yarns' tilt and gaps, and how finely it is resolved ([`Detail`]); the
//! limits on each, and their checks; and the keys the front ends write them with
//! ([`SURFACE_KEYS`]: each key's name, default, valid range and meaning, in one place).

use super::irregular::{length_valid, spread_valid};
use super::{Irregularity, FILTER_CELLS};
use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::fiber::{DEFAULT_WAVELENGTH_NM, WAVELENGTH_RANGE_NM};
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

/// The largest [`SurfaceSpec::gap`]: yarns keep at least 5 % of their cells.
pub const MAX_GAP: f64 = 0.95;

/// Pattern cells per unit of `u` and of `v` where a surface is not told
/// ([`SurfaceSpec::yarns_per_unit`]): the default of every front end (scene files,
/// `woven.Surface`, the Mitsuba plugin).
pub const DEFAULT_YARNS_PER_UNIT: f64 = 40.0;

/// What a dye must be ([`SurfaceSpec::weft_color`], [`SurfaceSpec::warp_color`]).
const COLOR_VALID: &str = "three values in [0, 1]";

/// One key of a woven surface, as scene files (`[material.NAME] type = "woven"`), the Python
/// package (`woven.Surface`, `woven.SURFACE_KEYS`) and the Mitsuba plugin write it: its name,
/// default, valid range and meaning. [`SURFACE_KEYS`] lists them all; docs/python.md shows
/// that table, and a test holds the two to each other.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceKey {
    /// The key's name.
    pub name: &'static str,
    default: Text,
    valid: Text,
    meaning: Text,
}

/// A cell of [`SurfaceKey`]'s table: words, or words made from the library's constants (their
/// one home).
#[derive(Clone, Copy, Debug)]
enum Text {
    Words(&'static str),
    Made(fn() -> String),
}

impl Text {
    fn text(self) -> String {
        match self {
            Text::Words(w) => w.to_string(),
            Text::Made(f) => f(),
        }
    }
}

impl SurfaceKey {
    /// What the key is where it is not given.
    pub fn default(&self) -> String {
        self.default.text()
    }

    /// The values it takes (what an error names as expected).
    pub fn valid(&self) -> String {
        self.valid.text()
    }

    /// What the key means.
    pub fn meaning(&self) -> String {
        self.meaning.text()
    }

    /// The key `name` of [`SURFACE_KEYS`], if it is one.
    pub fn named(name: &str) -> Option<&'static SurfaceKey> {
        SURFACE_KEYS.iter().find(|k| k.name == name)
    }
}

/// The keys of a woven surface: the one home of each key's name, default, valid range and
/// meaning ([`SurfaceKey`]). Front ends take a key's default from the library (they leave the
/// key out of the [`SurfaceSpec`] they build) and check its range here.
pub const SURFACE_KEYS: &[SurfaceKey] = &[
    SurfaceKey {
        name: "material",
        default: Text::Words("none: required (woven.Surface and the plugin take `table` instead)"),
        valid: Text::Words("a preset's name (`woven materials`) or a material file (TOML)"),
        meaning: Text::Words(
            "the cloth: its fibres, its yarn and its weave; the surface renders from the table \
             of its yarn alone",
        ),
    },
    SurfaceKey {
        name: "pattern",
        default: Text::Words("the material's own weave"),
        valid: Text::Words(
            "a weave's name (\"plain\", \"twill-2/1\", \"satin-5\", …); in scenes also a 0/1 \
             matrix or { wif = \"…\" }",
        ),
        meaning: Text::Words(
            "the weave laid on the surface's uv: the cell at (u·n_u, v·n_v) puts the weft \
             (along u) or the warp (along v) on top",
        ),
    },
    SurfaceKey {
        name: "weft_fraction",
        default: Text::Words("the material's own weave"),
        valid: Text::Words("a fraction in [0, 1]; not with `pattern`"),
        meaning: Text::Words(
            "γ in place of the weave: the macro BRDF γ f_weft + (1 − γ) f_warp everywhere \
             (woven.Surface and the plugin; scenes give a `pattern`)",
        ),
    },
    SurfaceKey {
        name: "yarns_per_unit",
        default: Text::Made(|| DEFAULT_YARNS_PER_UNIT.to_string()),
        valid: Text::Words("a number > 0 for both, or a pair (n_u, n_v)"),
        meaning: Text::Words(
            "pattern cells per unit of u and of v (n_u, n_v; the built-in draped cloths' uv is \
             in metres); unused without a pattern",
        ),
    },
    SurfaceKey {
        name: "weft_color",
        default: Text::Words("the material's [dye] weft, else its own albedo (grey)"),
        valid: Text::Words(COLOR_VALID),
        meaning: Text::Words(
            "the weft's dyed fibre albedo ρ0 per channel (linear RGB); the interreflection \
             albedo follows in proportion, the sheen stays white",
        ),
    },
    SurfaceKey {
        name: "warp_color",
        default: Text::Words("the material's [dye] warp, else its own albedo (grey)"),
        valid: Text::Words(COLOR_VALID),
        meaning: Text::Words("the warp's dyed fibre albedo ρ0 per channel, as `weft_color`"),
    },
    SurfaceKey {
        name: "u_max_deg",
        default: Text::Words("the material's [yarn] u_max_deg, else 0 (the paper's flat yarns)"),
        valid: Text::Made(|| {
            format!("degrees in [0, {MAX_U_MAX_DEG}]; 0 for a flat fiber surface (no [yarn])")
        }),
        meaning: Text::Words(
            "the yarns' tilt out of the cloth plane at the ends of each float (Irawan & \
             Marschner's u_max): +u_max where a yarn comes up, −u_max where it goes under",
        ),
    },
    SurfaceKey {
        name: "gap",
        default: Text::Words("0"),
        valid: Text::Made(|| {
            format!("a fraction in [0, {MAX_GAP}]; 0 for a flat fiber surface (no [yarn])")
        }),
        meaning: Text::Words(
            "the fraction of each cell's width between yarns: the crossing yarn shows there, \
             and a hole where both leave one",
        ),
    },
    SurfaceKey {
        name: "detail",
        default: Text::Made(|| format!("{:?}", Detail::default().name())),
        valid: Text::Made(Detail::one_of),
        meaning: Text::Words(
            "how finely the weave is resolved: \"fibers\" each point a point on its yarn's \
             profile, \"yarns\" each cell its yarn's BRDF, \"cloth\" the γ-mix everywhere, \
             \"auto\" by the pixel's footprint, yarns where none is known (docs/render.md, \
             levels of detail)",
        ),
    },
    SurfaceKey {
        name: "irregularity",
        default: Text::Made(|| Irregularity::default().spread[0].to_string()),
        valid: Text::Made(|| format!("{}: one number or (weft, warp)", spread_valid())),
        meaning: Text::Words(
            "σ, the spread of the log of each yarn's dye factor along its length: 0 dyes every \
             yarn alike; needs a pattern",
        ),
    },
    SurfaceKey {
        name: "irregularity_length",
        default: Text::Made(|| Irregularity::default().length.to_string()),
        valid: Text::Made(length_valid),
        meaning: Text::Words("ℓ, the distance along a yarn over which its dye factor changes"),
    },
    SurfaceKey {
        name: "wavelength_nm",
        default: Text::Made(|| DEFAULT_WAVELENGTH_NM.to_string()),
        valid: Text::Made(|| {
            let [lo, hi] = WAVELENGTH_RANGE_NM;
            format!("nm in [{lo}, {hi}]")
        }),
        meaning: Text::Words(
            "the wavelength the yarn's table is built at (woven.Surface and the plugin; \
             `woven render` builds every table at the default)",
        ),
    },
    SurfaceKey {
        name: "footprint_filter",
        default: Text::Words("true"),
        valid: Text::Words("true or false"),
        meaning: Text::Made(|| {
            let [from, to] = FILTER_CELLS;
            format!(
                "blend toward the macro BRDF as a pixel's footprint grows from {from} to {to} \
                 cells: fine weaves without moiré or sparkle. A key of [integrator] in scenes, \
                 a material key in the Mitsuba plugin; woven.Surface filters by the footprint \
                 each call passes (none: no filtering)"
            )
        }),
    },
];

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
    /// `material` with [`DEFAULT_YARNS_PER_UNIT`] pattern cells per unit of uv, its own colours
    /// (its `[dye]`, if any), its own float tilt (`[yarn] u_max_deg`, 0 for the paper's flat
    /// yarns), no gaps, [`Detail::Auto`], no irregularity: the defaults of [`SURFACE_KEYS`].
    pub fn new(material: Material) -> SurfaceSpec {
        let dye = material.dye;
        let u_max = material.yarn.map_or(0.0, |y| y.u_max);
        SurfaceSpec {
            material,
            yarns_per_unit: [DEFAULT_YARNS_PER_UNIT; 2],
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
        self.irregularity.validate_for(&self.material)
    }
}
