//! Material descriptions and their TOML files (the project's material-file contract).
//!
//! A material is a `[fiber]` table, optionally arranged in yarns (`[yarn]`) and a weave
//! (`[weave]`). Every key, with its meaning and valid range (this example parses, and is tested):
//!
//! ```
//! # use woven::material::Material;
//! let toml = r#"
//! name = "my-fabric"             # optional
//!
//! [fiber]
//! model = "rough"                # "rough" (docs/spec.md §1.3, default) | "htsg" (§1.4)
//! eta = 1.6                      # η; or eta = { cauchy_a = 1.55, cauchy_b_nm2 = 4000.0 }
//! roughness = 0.05               # σ_h/τ, for "rough"; "htsg" takes sigma_h_um and tau_um (µm)
//! diffuse = 0.1                  # ρ0, in [0, 1)
//! normalization = "paper"        # "paper" (β of Eq. (15), default) | "none" (reciprocal)
//!
//! [yarn]                         # absent: a flat fiber surface
//! lateral_length = 20.0          # L (the arc radius is 1)
//! slope_mean = 0.0               # μ, radians
//! slope_std = 1.2                # σ, radians; 0 = the single profile θ_a = μ
//! interreflection = 0.2          # ħ in [0, 1]
//! interreflection_albedo = 0.5   # ρ in [0, 1]
//! twist_std = 0.0                # σ_t, radians; 0 = fibers along the yarn axis
//! isotropic = false              # true: Eq. (22) (twist_std is then an error)
//!
//! [weave]                        # absent: γ = 1, one yarn orientation along x (φ = 0)
//! weft_fraction = 0.5            # γ; or pattern = "plain" (below)
//! gap = 0.0                      # the share of each cell's width between yarns, [0, 0.95]
//! transmission = false           # true: light passes between and through the yarns
//! "#;
//! let material = Material::from_toml_str(toml, "my-fabric.toml")?;
//! assert_eq!(material.weft_fraction(), 0.5);
//! let model = material.build(550.0)?; // ready to evaluate at 550 nm
//! # let _ = model;
//!
//! // The full physical-optics fiber takes absolute lengths instead of the ratio:
//! let htsg = "[fiber]\nmodel = \"htsg\"\neta = 1.6\nsigma_h_um = 0.2\ntau_um = 2.0\n";
//! assert!(Material::from_toml_str(htsg, "htsg.toml").is_ok());
//! // A pattern gives γ instead of weft_fraction: "plain", "twill-2/1", "satin-5", "sateen-5",
//! // a 0/1 matrix (1 where the weft floats on top), or a WIF draft { wif = "draft.wif" }.
//! let twill = "[fiber]\neta = 1.6\nroughness = 0.2\n[yarn]\nlateral_length = 4.0\nslope_mean = 0.4\n\
//!              [weave]\npattern = \"twill-2/1\"\n";
//! assert!((Material::from_toml_str(twill, "twill.toml")?.weft_fraction() - 1.0 / 3.0).abs() < 1e-12);
//! let matrix = "[fiber]\neta = 1.6\nroughness = 0.2\n[yarn]\nlateral_length = 4.0\nslope_mean = 0.4\n\
//!               [weave]\npattern = [[1, 0], [0, 1]]\n";
//! assert_eq!(Material::from_toml_str(matrix, "matrix.toml")?.weft_fraction(), 0.5);
//! // … and the roughness twice is an error that names the key:
//! let both = "[fiber]\nmodel = \"htsg\"\neta = 1.6\nroughness = 0.1\nsigma_h_um = 0.2\ntau_um = 2.0\n";
//! assert!(Material::from_toml_str(both, "both.toml").is_err());
//! # Ok::<(), woven::Error>(())
//! ```
//!
//! All angles in files are radians. Unknown keys, missing required keys, out-of-range values and
//! a key that does not belong to the chosen model are errors naming the key, the value and the
//! valid range. [`Material::preset`] gives the built-in presets (`polyester-sateen`,
//! `belt-cloth`, `silk`, `filament-satin`), which are files of this form.

use crate::cloth::Structure;
use crate::color::Rgb;
use crate::error::check_range;
use crate::error::{Error, Result};
use crate::fiber::{Fiber, FiberModel, FiberParams, Ior, Normalization};
use crate::weave::Pattern;
use crate::yarn::{Yarn, YarnParams};
use std::path::Path;

/// The longest material file [`Material::from_path`] reads, in bytes (1 MiB): room for an inline
/// pattern of several hundred threads square (larger drafts belong in a WIF file); the limit stops
/// an endless stream (`/dev/zero`, a pipe) or a huge matrix from filling memory.
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// A complete material: a fiber surface, optionally arranged in yarns and a weave.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Optional human-readable name.
    pub name: Option<String>,
    /// The `[fiber]` table.
    pub fiber: FiberParams,
    /// The `[yarn]` table; `None` for a flat fiber surface.
    pub yarn: Option<YarnParams>,
    /// The `[weave]` table; `None` means `γ = 1` (one yarn orientation, along `x`).
    pub weave: Option<Weave>,
    /// The `[dye]` table: the colours the weft and warp are dyed (none: the material's own grey).
    pub dye: Dye,
    /// The `[weave]` keys `gap` and `transmission`: how open the cloth is, and whether light
    /// passes through it (by default neither: the paper's opaque cloth).
    pub openness: Openness,
}

/// How open a cloth is: the `[weave]` keys `gap` and `transmission`, options beyond the paper
/// (docs/model.md, "The open area" and "Light through the yarns"). A surface laid in a scene takes
/// them as its own `gap` and `transmission` unless it sets them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Openness {
    /// `weave.gap`: the share of each cell's width between yarns, in `[0, MAX_GAP]`
    /// ([`MAX_GAP`](crate::gaps::MAX_GAP)). Each family then covers its
    /// [`Cover`](crate::gaps::Cover) and `gap²` of the cloth is open. 0 (the default): yarns fill
    /// their cells, as in the paper.
    pub gap: f64,
    /// `weave.transmission`: whether light passes between the yarns (the open area along a
    /// direction, [`open_area`](crate::gaps::open_area)) and through them (a diffuse
    /// transmission that closes each direction's energy). `false` (the default): the cloth is
    /// opaque, as in the paper.
    pub transmission: bool,
}

/// The colours a material's yarns are dyed: each replaces the fibres' diffuse albedo `ρ0` per
/// channel and scales the interreflection albedo `ρ` with it ([`Albedos::dyed`](crate::table::Albedos::dyed));
/// the Fresnel sheen stays white. A surface laid in a scene may override either.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dye {
    /// `dye.weft`: the weft's colour (a flat fiber surface's only colour), each channel in
    /// `[0, 1]`.
    pub weft: Option<Rgb>,
    /// `dye.warp`: the warp's colour, each channel in `[0, 1]`.
    pub warp: Option<Rgb>,
}

impl Dye {
    /// Whether neither family is dyed.
    pub fn is_none(&self) -> bool {
        self.weft.is_none() && self.warp.is_none()
    }

    /// Validates each colour.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `dye.weft` or `dye.warp`.
    pub fn validate(&self) -> Result<()> {
        for (name, c) in [("dye.weft", self.weft), ("dye.warp", self.warp)] {
            if let Some(c) = c {
                if !c.0.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)) {
                    return Err(Error::invalid(
                        name,
                        format!("{:?}", c.0),
                        "three numbers, each in [0, 1]",
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The `[weave]` table: the weft fraction `γ`, given directly or by a pattern.
#[derive(Clone, Debug, PartialEq)]
pub enum Weave {
    /// `weft_fraction = γ`.
    WeftFraction(f64),
    /// `pattern = …`: `γ` is the pattern's weft fraction.
    Pattern {
        /// How the file named the pattern (kept so the material writes back as it was read).
        spec: PatternSpec,
        /// The pattern.
        pattern: Pattern,
    },
}

/// How a material file names its weave pattern (the pattern value's one reader).
pub use crate::weave::PatternSpec;

impl Weave {
    /// The named pattern (`"plain"`, `"twill-2/1"`, `"satin-5"`, …; [`Pattern::from_name`]),
    /// written back under its name.
    ///
    /// # Errors
    /// An unknown name ([`Pattern::from_name`]).
    pub fn named(name: &str) -> Result<Weave> {
        Ok(Weave::Pattern {
            spec: PatternSpec::Name(name.into()),
            pattern: Pattern::from_name(name)?,
        })
    }

    /// `γ`, the visible fraction of weft.
    pub fn weft_fraction(&self) -> f64 {
        match self {
            Weave::WeftFraction(g) => *g,
            Weave::Pattern { pattern, .. } => pattern.weft_fraction(),
        }
    }
}

impl Material {
    /// A flat fiber surface.
    pub fn flat(fiber: FiberParams) -> Self {
        Material {
            name: None,
            fiber,
            yarn: None,
            weave: None,
            dye: Dye::default(),
            openness: Openness::default(),
        }
    }

    /// `γ` (1 when there is no `[weave]` table).
    pub fn weft_fraction(&self) -> f64 {
        self.weave.as_ref().map_or(1.0, Weave::weft_fraction)
    }

    /// The material's yarn alone: one yarn family, along `x` (the weft), its weave removed
    /// (`γ = 1`); a flat fiber surface is returned as it is. A renderer that resolves the weave
    /// shades each point with this BRDF, turned to the yarn on top there; the material's own BRDF
    /// is its `γ`-mix with the same turned by 90° (docs/spec.md §2.7).
    pub fn yarn_family(&self) -> Material {
        let mut m = self.clone();
        m.weave = None;
        // A surface leaves its own gaps between the yarns it lays (SurfaceSpec::gap).
        m.openness = Openness::default();
        // A surface tilts the yarn itself (SurfaceSpec::u_max, which takes the material's).
        if let Some(y) = &mut m.yarn {
            (y.u_max, y.float_crest, y.float_flank) = (0.0, 0.0, 0.0);
        }
        m
    }

    /// The same cloth seen from its back: where one family lies on top the other shows below,
    /// so its pattern is the complement ([`Pattern::complement`]: a satin's back is its sateen)
    /// and its weft fraction `1 − γ`. Seen from below, it is the front turned over about the weft
    /// (`y` and `z` reversed), which keeps every yarn's axis; the dyes stay with their families.
    pub fn back(&self) -> Material {
        let mut m = self.clone();
        m.weave = self.weave.as_ref().map(|w| match w {
            Weave::WeftFraction(g) => Weave::WeftFraction(1.0 - g),
            Weave::Pattern { pattern, .. } => {
                let back = pattern.complement();
                Weave::Pattern {
                    spec: PatternSpec::Matrix(back.to_matrix()),
                    pattern: back,
                }
            }
        });
        m
    }

    /// Validates every parameter.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first offending key.
    pub fn validate(&self) -> Result<()> {
        self.fiber.validate()?;
        if let Some(y) = &self.yarn {
            y.validate()?;
        }
        if let Some(Weave::WeftFraction(g)) = &self.weave {
            check_range("weave.weft_fraction", *g, 0.0, 1.0)?;
        }
        self.dye.validate()?;
        if self.dye.warp.is_some() && self.yarn.is_none() {
            return Err(Error::invalid(
                "dye.warp",
                "(a warp colour)",
                "no warp colour on a flat fiber surface: it has one family of fibres; give `dye.weft`",
            ));
        }
        if self.weave.is_some() && self.yarn.is_none() {
            return Err(Error::invalid(
                "weave",
                "(a [weave] table)",
                "a [yarn] table too: a weave arranges yarns, and a flat fiber surface has none",
            ));
        }
        check_range("weave.gap", self.openness.gap, 0.0, crate::gaps::MAX_GAP)?;
        if self.weave.is_none() && self.openness != Openness::default() {
            let name = if self.openness.gap > 0.0 {
                "weave.gap"
            } else {
                "weave.transmission"
            };
            return Err(Error::invalid(
                name,
                "(without a weave)",
                "a [weave] table with a pattern or weft_fraction: gaps lie between a weave's yarns",
            ));
        }
        Ok(())
    }

    /// Prepares the material for evaluation at `wavelength_nm` (builds the β table).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an out-of-range parameter or wavelength.
    pub fn build(&self, wavelength_nm: f64) -> Result<crate::Model> {
        self.validate()?;
        self.build_with(Fiber::new(&self.fiber, wavelength_nm)?)
    }

    /// [`build`](Self::build) with its fiber already prepared (`fiber` must be built from
    /// `self.fiber`: a fitter keeps the β tables of the roughnesses it has tried).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an out-of-range yarn or gap.
    pub fn build_with(&self, fiber: Fiber) -> Result<crate::Model> {
        let structure = |m: &Material, fiber: Fiber| -> Result<Structure> {
            Ok(match &m.yarn {
                None => Structure::Flat(fiber),
                Some(y) => Structure::Woven {
                    yarn: Box::new(Yarn::new(fiber, *y)?),
                    weft_fraction: m.weft_fraction(),
                    gap: m.openness.gap,
                },
            })
        };
        if !self.openness.transmission {
            return Ok(crate::Model::new(structure(self, fiber)?));
        }
        let back = crate::Model::new(structure(&self.back(), fiber.clone())?);
        crate::Model::new(structure(self, fiber)?).transmitting(self.openness.gap, back)
    }

    /// The names of the built-in presets, usable wherever a material file is: the paper's three
    /// fits ([`paper_preset_names`](Self::paper_preset_names)), then `filament-satin`, a smooth
    /// filament satin beyond them (docs/model.md "Presets").
    pub fn preset_names() -> &'static [&'static str] {
        &["polyester-sateen", "belt-cloth", "silk", "filament-satin"]
    }

    /// The presets that reproduce the paper's Figs. 8–10 (docs/spec.md §5).
    pub fn paper_preset_names() -> &'static [&'static str] {
        &Self::preset_names()[..3]
    }

    /// The presets grounded in measured fabrics: the woven model fitted to each woven fabric of
    /// the microcylinder model of Sadeghi et al. 2013 (docs/microcylinder.md §11), with the
    /// options beyond the paper that the fits use (shaped floats, a glossy body) and their dyes.
    /// Listed apart from [`preset_names`](Self::preset_names): their exact evaluation averages
    /// each tilted float over up to 19 facets, too slow for the tests that sweep every preset.
    pub fn grounded_preset_names() -> &'static [&'static str] {
        &[
            "satin-charmeuse",
            "silk-crepe-de-chine",
            "linen-plain",
            "silk-shot",
        ]
    }

    /// The presets of open cloth that lets light through (`[weave] gap` and `transmission`:
    /// docs/model.md, "Light through the yarns"): `cotton-voile`, a sheer.
    pub fn open_preset_names() -> &'static [&'static str] {
        &["cotton-voile"]
    }

    /// Every built-in preset: [`preset_names`](Self::preset_names), then
    /// [`grounded_preset_names`](Self::grounded_preset_names), then
    /// [`open_preset_names`](Self::open_preset_names).
    pub fn all_preset_names() -> Vec<&'static str> {
        let mut all = Self::preset_names().to_vec();
        all.extend_from_slice(Self::grounded_preset_names());
        all.extend_from_slice(Self::open_preset_names());
        all
    }

    /// The TOML text of a built-in preset, or `None` for an unknown name.
    pub fn preset_toml(name: &str) -> Option<&'static str> {
        match name {
            "polyester-sateen" => Some(include_str!("../presets/polyester-sateen.toml")),
            "belt-cloth" => Some(include_str!("../presets/belt-cloth.toml")),
            "silk" => Some(include_str!("../presets/silk.toml")),
            "filament-satin" => Some(include_str!("../presets/filament-satin.toml")),
            "satin-charmeuse" => Some(include_str!("../presets/satin-charmeuse.toml")),
            "silk-crepe-de-chine" => Some(include_str!("../presets/silk-crepe-de-chine.toml")),
            "linen-plain" => Some(include_str!("../presets/linen-plain.toml")),
            "silk-shot" => Some(include_str!("../presets/silk-shot.toml")),
            "cotton-voile" => Some(include_str!("../presets/cotton-voile.toml")),
            _ => None,
        }
    }
}

#[cfg(feature = "serde")]
mod file {
    use super::*;
    use serde::{Deserialize, Serialize};

    #[derive(Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    struct RawMaterial {
        #[serde(skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        fiber: RawFiber,
        #[serde(skip_serializing_if = "Option::is_none")]
        yarn: Option<RawYarn>,
        #[serde(skip_serializing_if = "Option::is_none")]
        weave: Option<RawWeave>,
        #[serde(skip_serializing_if = "Option::is_none")]
        dye: Option<RawDye>,
    }

    #[derive(Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    struct RawDye {
        #[serde(skip_serializing_if = "Option::is_none")]
        weft: Option<[f64; 3]>,
        #[serde(skip_serializing_if = "Option::is_none")]
        warp: Option<[f64; 3]>,
    }

    #[derive(Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    struct RawYarn {
        lateral_length: Option<f64>,
        slope_mean: Option<f64>,
        #[serde(default)]
        slope_std: f64,
        #[serde(default)]
        interreflection: f64,
        #[serde(default)]
        interreflection_albedo: f64,
        #[serde(default)]
        twist_std: f64,
        #[serde(default)]
        isotropic: bool,
        #[serde(default, skip_serializing_if = "is_zero")]
        u_max_deg: f64,
        #[serde(default, skip_serializing_if = "is_zero")]
        float_crest: f64,
        #[serde(default, skip_serializing_if = "is_zero")]
        float_flank: f64,
    }

    fn is_zero(x: &f64) -> bool {
        *x == 0.0
    }

    #[derive(Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    struct RawWeave {
        #[serde(skip_serializing_if = "Option::is_none")]
        weft_fraction: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        pattern: Option<toml::Value>,
        #[serde(default, skip_serializing_if = "is_zero")]
        gap: f64,
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        transmission: bool,
    }

    impl RawYarn {
        fn into_params(self) -> Result<YarnParams> {
            let p = YarnParams {
                lateral_length: self.lateral_length.ok_or_else(|| {
                    missing(
                        "yarn.lateral_length",
                        "L in [0, 1e6] arc radii (required in [yarn])",
                    )
                })?,
                slope_mean: self.slope_mean.ok_or_else(|| {
                    missing(
                        "yarn.slope_mean",
                        "μ in [0, π/2] radians (required in [yarn])",
                    )
                })?,
                slope_std: self.slope_std,
                interreflection: self.interreflection,
                interreflection_albedo: self.interreflection_albedo,
                twist_std: self.twist_std,
                isotropic: self.isotropic,
                u_max: self.u_max_deg.to_radians(),
                float_crest: self.float_crest,
                float_flank: self.float_flank,
            };
            p.validate()?;
            Ok(p)
        }

        fn from_params(p: &YarnParams) -> Self {
            RawYarn {
                lateral_length: Some(p.lateral_length),
                slope_mean: Some(p.slope_mean),
                slope_std: p.slope_std,
                interreflection: p.interreflection,
                interreflection_albedo: p.interreflection_albedo,
                twist_std: p.twist_std,
                isotropic: p.isotropic,
                u_max_deg: p.u_max.to_degrees(),
                float_crest: p.float_crest,
                float_flank: p.float_flank,
            }
        }
    }

    impl RawWeave {
        fn openness(&self) -> Openness {
            Openness {
                gap: self.gap,
                transmission: self.transmission,
            }
        }

        fn into_weave(self, base: Option<&Path>) -> Result<Weave> {
            match (self.weft_fraction, self.pattern) {
                (Some(_), Some(_)) => Err(Error::invalid(
                    "weave.pattern",
                    "(given with weave.weft_fraction)",
                    "either weft_fraction or pattern, not both",
                )),
                (None, None) => Err(missing(
                    "weave.weft_fraction",
                    "weft_fraction in [0, 1] or a pattern (the [weave] table is empty)",
                )),
                (Some(g), None) => {
                    check_range("weave.weft_fraction", g, 0.0, 1.0)?;
                    Ok(Weave::WeftFraction(g))
                }
                (None, Some(v)) => parse_pattern(v, base),
            }
        }

        /// `inline`: write a WIF pattern as its matrix rather than its path.
        fn from_weave(w: &Weave, openness: Openness, inline: bool) -> Self {
            let Openness { gap, transmission } = openness;
            match w {
                Weave::WeftFraction(g) => RawWeave {
                    weft_fraction: Some(*g),
                    pattern: None,
                    gap,
                    transmission,
                },
                Weave::Pattern { spec, pattern } => RawWeave {
                    gap,
                    transmission,
                    weft_fraction: None,
                    pattern: Some(match spec {
                        PatternSpec::Name(n) => toml::Value::String(n.clone()),
                        PatternSpec::Wif(_) if inline => matrix_value(&pattern.to_matrix()),
                        PatternSpec::Matrix(m) => matrix_value(m),
                        PatternSpec::Wif(p) => {
                            let mut t = toml::map::Map::new();
                            t.insert("wif".into(), toml::Value::String(p.display().to_string()));
                            toml::Value::Table(t)
                        }
                    }),
                },
            }
        }
    }

    /// A 0/1 matrix as a TOML array of arrays.
    fn matrix_value(m: &[Vec<u8>]) -> toml::Value {
        toml::Value::Array(
            m.iter()
                .map(|row| {
                    toml::Value::Array(
                        row.iter()
                            .map(|&c| toml::Value::Integer(c as i64))
                            .collect(),
                    )
                })
                .collect(),
        )
    }

    fn parse_pattern(v: toml::Value, base: Option<&Path>) -> Result<Weave> {
        let spec = PatternSpec::from_value(&v.into(), "weave.pattern")?;
        // A WIF file's path stays as written (the material writes it back so); it is read
        // from the material file's folder.
        let pattern = spec.pattern(|rel| match base {
            Some(dir) if rel.is_relative() => dir.join(rel),
            _ => rel.to_path_buf(),
        })?;
        Ok(Weave::Pattern { spec, pattern })
    }

    #[derive(Deserialize, Serialize, Default)]
    #[serde(deny_unknown_fields)]
    struct RawFiber {
        #[serde(skip_serializing_if = "Option::is_none")]
        model: Option<String>,
        #[serde(skip_serializing_if = "Option::is_none")]
        eta: Option<toml::Value>,
        #[serde(skip_serializing_if = "Option::is_none")]
        roughness: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        sigma_h_um: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        tau_um: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        diffuse: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        normalization: Option<String>,
        #[serde(default, skip_serializing_if = "is_zero")]
        body_gloss: f64,
        #[serde(default, skip_serializing_if = "is_zero")]
        body_roughness: f64,
    }

    fn missing(key: &str, why: &str) -> Error {
        Error::invalid(key, "(missing)", why)
    }

    fn not_for(key: &str, value: f64, model: &str, instead: &str) -> Error {
        Error::invalid(
            key,
            value,
            format!("no `{key}` with model = \"{model}\" (use {instead})"),
        )
    }

    fn parse_eta(v: &toml::Value) -> Result<Ior> {
        match v {
            toml::Value::Float(x) => Ok(Ior::Constant(*x)),
            toml::Value::Integer(i) => Ok(Ior::Constant(*i as f64)),
            toml::Value::Table(t) => {
                for k in t.keys() {
                    if k != "cauchy_a" && k != "cauchy_b_nm2" {
                        return Err(Error::invalid(
                            format!("fiber.eta.{k}"),
                            &t[k],
                            "only `cauchy_a` and `cauchy_b_nm2` in an eta table",
                        ));
                    }
                }
                let num = |k: &str| -> Result<f64> {
                    match t.get(k) {
                        Some(toml::Value::Float(x)) => Ok(*x),
                        Some(toml::Value::Integer(i)) => Ok(*i as f64),
                        Some(other) => {
                            Err(Error::invalid(format!("fiber.eta.{k}"), other, "a number"))
                        }
                        None => Err(missing(
                            &format!("fiber.eta.{k}"),
                            "a number (both Cauchy coefficients are required)",
                        )),
                    }
                };
                Ok(Ior::Cauchy {
                    cauchy_a: num("cauchy_a")?,
                    cauchy_b_nm2: num("cauchy_b_nm2")?,
                })
            }
            other => Err(Error::invalid(
                "fiber.eta",
                other,
                "a number, or { cauchy_a = A, cauchy_b_nm2 = B }",
            )),
        }
    }

    impl RawFiber {
        fn into_params(self) -> Result<FiberParams> {
            let model_name = self.model.as_deref().unwrap_or("rough");
            let model = match model_name {
                "rough" => {
                    if let Some(x) = self.sigma_h_um {
                        return Err(not_for(
                            "fiber.sigma_h_um",
                            x,
                            "rough",
                            "`roughness`, or model = \"htsg\"",
                        ));
                    }
                    if let Some(x) = self.tau_um {
                        return Err(not_for(
                            "fiber.tau_um",
                            x,
                            "rough",
                            "`roughness`, or model = \"htsg\"",
                        ));
                    }
                    let roughness = self.roughness.ok_or_else(|| {
                        missing(
                            "fiber.roughness",
                            "σ_h/τ in [0.005, 2] (required for model = \"rough\")",
                        )
                    })?;
                    FiberModel::Rough { roughness }
                }
                "htsg" => {
                    if let Some(x) = self.roughness {
                        return Err(not_for(
                            "fiber.roughness",
                            x,
                            "htsg",
                            "`sigma_h_um` and `tau_um`",
                        ));
                    }
                    let sigma_h_um = self.sigma_h_um.ok_or_else(|| {
                        missing(
                            "fiber.sigma_h_um",
                            "σ_h in µm, (0, 10] (required for model = \"htsg\")",
                        )
                    })?;
                    let tau_um = self.tau_um.ok_or_else(|| {
                        missing(
                            "fiber.tau_um",
                            "τ in µm, (0, 100] (required for model = \"htsg\")",
                        )
                    })?;
                    FiberModel::Htsg { sigma_h_um, tau_um }
                }
                other => {
                    return Err(Error::invalid(
                        "fiber.model",
                        format!("{other:?}"),
                        "\"rough\" or \"htsg\"",
                    ))
                }
            };
            let eta =
                parse_eta(self.eta.as_ref().ok_or_else(|| {
                    missing("fiber.eta", "a refractive index in [1, 4] (required)")
                })?)?;
            let normalization = match self.normalization.as_deref().unwrap_or("paper") {
                "paper" => Normalization::Paper,
                "none" => Normalization::None,
                other => {
                    return Err(Error::invalid(
                        "fiber.normalization",
                        format!("{other:?}"),
                        "\"paper\" or \"none\"",
                    ))
                }
            };
            let params = FiberParams {
                model,
                eta,
                diffuse: self.diffuse.unwrap_or(0.0),
                normalization,
                body_gloss: self.body_gloss,
                body_roughness: self.body_roughness,
            };
            params.validate()?;
            Ok(params)
        }

        fn from_params(p: &FiberParams) -> Self {
            let mut raw = RawFiber::default();
            match p.model {
                FiberModel::Rough { roughness } => {
                    raw.model = Some("rough".into());
                    raw.roughness = Some(roughness);
                }
                FiberModel::Htsg { sigma_h_um, tau_um } => {
                    raw.model = Some("htsg".into());
                    raw.sigma_h_um = Some(sigma_h_um);
                    raw.tau_um = Some(tau_um);
                }
            }
            raw.eta = Some(match p.eta {
                Ior::Constant(x) => toml::Value::Float(x),
                Ior::Cauchy {
                    cauchy_a,
                    cauchy_b_nm2,
                } => {
                    let mut t = toml::map::Map::new();
                    t.insert("cauchy_a".into(), toml::Value::Float(cauchy_a));
                    t.insert("cauchy_b_nm2".into(), toml::Value::Float(cauchy_b_nm2));
                    toml::Value::Table(t)
                }
            });
            raw.diffuse = Some(p.diffuse);
            (raw.body_gloss, raw.body_roughness) = (p.body_gloss, p.body_roughness);
            raw.normalization = Some(
                match p.normalization {
                    Normalization::Paper => "paper",
                    Normalization::None => "none",
                }
                .into(),
            );
            raw
        }
    }

    impl Material {
        /// Parses a material from TOML text; `origin` names the source in errors.
        ///
        /// # Errors
        /// [`Error::Parse`] for malformed TOML, unknown or mistyped keys (with the line);
        /// [`Error::InvalidParameter`] for missing keys and out-of-range values.
        ///
        /// ```
        /// let m = woven::material::Material::from_toml_str(
        ///     "[fiber]\neta = 1.6\nroughness = 0.05\ndiffuse = 0.1\n", "<doc>")?;
        /// assert_eq!(m.fiber.diffuse, 0.1);
        /// let err = woven::material::Material::from_toml_str(
        ///     "[fiber]\neta = 1.6\nroughness = 7.0\n", "<doc>").unwrap_err();
        /// assert!(err.to_string().contains("fiber.roughness"));
        /// # Ok::<(), woven::Error>(())
        /// ```
        pub fn from_toml_str(text: &str, origin: &str) -> Result<Self> {
            Self::parse(text, origin, None)
        }

        fn parse(text: &str, origin: &str, base: Option<&Path>) -> Result<Self> {
            let raw: RawMaterial = toml::from_str(text).map_err(|e| Error::Parse {
                path: origin.to_string(),
                message: e.to_string().trim_end().to_string(),
            })?;
            let openness = raw
                .weave
                .as_ref()
                .map_or_else(Openness::default, RawWeave::openness);
            let material = Material {
                name: raw.name,
                fiber: raw.fiber.into_params()?,
                yarn: raw.yarn.map(RawYarn::into_params).transpose()?,
                weave: raw.weave.map(|w| w.into_weave(base)).transpose()?,
                openness,
                dye: raw.dye.map_or_else(Dye::default, |d| Dye {
                    weft: d.weft.map(Rgb),
                    warp: d.warp.map(Rgb),
                }),
            };
            material.validate()?;
            Ok(material)
        }

        /// A built-in preset by name (see [`Material::preset_names`]).
        ///
        /// # Errors
        /// [`Error::InvalidParameter`] naming `material` for an unknown name.
        pub fn preset(name: &str) -> Result<Self> {
            let text = Material::preset_toml(name).ok_or_else(|| {
                Error::invalid(
                    "material",
                    format!("{name:?}"),
                    format!(
                        "a material file or a preset: {}",
                        Material::all_preset_names().join(", ")
                    ),
                )
            })?;
            Self::parse(text, &format!("<preset {name}>"), None)
        }

        /// A preset name or a material file path: what a `--material` argument accepts.
        ///
        /// # Errors
        /// As [`preset`](Self::preset) and [`from_path`](Self::from_path).
        pub fn from_preset_or_path(arg: &str) -> Result<Self> {
            if Material::preset_toml(arg).is_some() {
                Self::preset(arg)
            } else if Path::new(arg).exists() || arg.contains('/') || arg.ends_with(".toml") {
                Self::from_path(arg)
            } else {
                Self::preset(arg)
            }
        }

        /// Reads and parses a material file.
        ///
        /// # Errors
        /// [`Error::Io`] if the file cannot be read; [`Error::Parse`] if it is longer than
        /// [`MAX_FILE_BYTES`]; otherwise as [`from_toml_str`](Self::from_toml_str).
        pub fn from_path(path: impl AsRef<Path>) -> Result<Self> {
            let path = path.as_ref();
            let text = crate::fsutil::read_text_capped(path, MAX_FILE_BYTES, "a material file")?;
            Self::parse(&text, &path.display().to_string(), path.parent())
        }

        /// The material as TOML text that [`from_toml_str`](Self::from_toml_str) reads back
        /// unchanged (a WIF pattern stays a path, relative to the material file's folder).
        pub fn to_toml_string(&self) -> String {
            self.to_toml(false)
        }

        /// As [`to_toml_string`](Self::to_toml_string), with a WIF pattern written as its 0/1
        /// matrix: text that parses anywhere, for records kept away from the material file
        /// (a table's header, say). Otherwise the same text.
        pub fn to_self_contained_toml_string(&self) -> String {
            self.to_toml(true)
        }

        fn to_toml(&self, inline: bool) -> String {
            let raw = RawMaterial {
                name: self.name.clone(),
                fiber: RawFiber::from_params(&self.fiber),
                yarn: self.yarn.as_ref().map(RawYarn::from_params),
                weave: self
                    .weave
                    .as_ref()
                    .map(|w| RawWeave::from_weave(w, self.openness, inline)),
                dye: (!self.dye.is_none()).then(|| RawDye {
                    weft: self.dye.weft.map(|c| c.0),
                    warp: self.dye.warp.map(|c| c.0),
                }),
            };
            toml::to_string_pretty(&raw).expect("a material always serializes")
        }
    }
}
