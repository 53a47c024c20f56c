//! The keys of a woven surface and their one reader. Each key is one entry of
//! [`SURFACE_KEYS`]: its name, default, valid range and meaning, and the function that reads its
//! value onto a surface. [`SurfaceSpec::from_keys`] reads any [`KeySource`] (a scene file's
//! table, a Python dict, Mitsuba's `Properties`) through that table, so every front end takes
//! the same keys with the same defaults, ranges and messages; adding a key means adding one
//! entry here.
//!
//! ```
//! use woven::keys::{KeyValue, Keys};
//! use woven::surface::SurfaceSpec;
//! let keys = Keys::new()
//!     .with("material", KeyValue::Text("polyester-sateen".into()))
//!     .with("pattern", KeyValue::Text("twill-2/1".into()))
//!     .with("gap", KeyValue::Float(0.2));
//! let read = SurfaceSpec::from_keys(&keys)?;
//! assert_eq!(read.spec.gap, 0.2);
//! assert_eq!(read.spec.yarns_per_unit, [40.0, 40.0]); // the key's default
//! assert!(read.footprint_filter && read.given("gap") && !read.given("detail"));
//!
//! let bad = Keys::new()
//!     .with("material", KeyValue::Text("silk".into()))
//!     .with("gap", KeyValue::Float(1.5));
//! let e = SurfaceSpec::from_keys(&bad).unwrap_err();
//! assert_eq!(e.key, "gap");
//! assert!(e.to_string().contains("`gap` = 1.5: expected a fraction in [0, 0.95]"));
//! # Ok::<(), woven::surface::KeyError>(())
//! ```

use super::irregular::{length_valid, spread_valid};
use super::spec::COLOR_VALID;
use super::{
    Detail, Irregularity, SurfaceSpec, DEFAULT_YARNS_PER_UNIT, FILTER_CELLS, MAX_GAP, MAX_U_MAX_DEG,
};
use crate::color::Rgb;
use crate::error::Error;
use crate::fiber::{DEFAULT_WAVELENGTH_NM, WAVELENGTH_RANGE_NM};
use crate::keys::{shown_key, KeySource, KeyValue, Keys};
use crate::material::{Material, Weave};
use crate::weave::PatternSpec;
use std::path::Path;

/// One key of a woven surface, as scene files (`[material.NAME] type = "woven"`), the Python
/// package (`woven.Surface`, `woven.SURFACE_KEYS`) and the Mitsuba plugin write it: its name,
/// default, valid range, meaning, and how its value is read ([`SurfaceSpec::from_keys`]).
/// [`SURFACE_KEYS`] lists them all; docs/python.md shows that table, and a test holds the two
/// to each other.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceKey {
    /// The key's name.
    pub name: &'static str,
    default: Text,
    valid: Text,
    meaning: Text,
    /// Reads a given value onto the surface read so far (its material laid first).
    update: Update,
}

/// How a key's value is read onto the surface being read.
type Update = fn(&mut KeyedSurface, &KeyValue, &dyn KeySource) -> Result<(), Error>;

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

    /// The error for `value`, which this key does not take: its name, the value, its range.
    fn refuse(&self, value: impl std::fmt::Display) -> Error {
        Error::invalid(self.name, value, self.valid())
    }
}

/// The key `name`'s entry (every reader below is one key's).
fn key(name: &str) -> &'static SurfaceKey {
    SurfaceKey::named(name).expect("a key of SURFACE_KEYS")
}

/// The keys of a woven surface: the one home of each key's name, default, valid range, meaning
/// and reader ([`SurfaceKey`]). Front ends hand their values to [`SurfaceSpec::from_keys`].
pub const SURFACE_KEYS: &[SurfaceKey] = &[
    SurfaceKey {
        name: "material",
        default: Text::Words("none: required (woven.Surface and the plugin take `table` instead)"),
        valid: Text::Words("a preset's name (`woven materials`) or a material file (TOML)"),
        meaning: Text::Words(
            "the cloth: its fibres, its yarn and its weave; the surface renders from the table \
             of its yarn alone",
        ),
        // Laid first, by `from_keys` itself: every other key's default is the material's.
        update: |_, _, _| Ok(()),
    },
    SurfaceKey {
        name: "pattern",
        default: Text::Words("the material's own weave"),
        valid: Text::Words(
            "a weave's name (\"plain\", \"twill-2/1\", \"satin-5\", …), a 0/1 matrix (rows of \
             0 and 1) or { wif = \"FILE\" }",
        ),
        meaning: Text::Words(
            "the weave laid on the surface's uv: the cell at (u·n_u, v·n_v) puts the weft \
             (along u) or the warp (along v) on top",
        ),
        update: read_pattern,
    },
    SurfaceKey {
        name: "weft_fraction",
        default: Text::Words("the material's own weave"),
        valid: Text::Words("a fraction in [0, 1]; not with `pattern`"),
        meaning: Text::Words(
            "γ in place of the weave: the macro BRDF γ f_weft + (1 − γ) f_warp everywhere",
        ),
        update: read_weft_fraction,
    },
    SurfaceKey {
        name: "yarns_per_unit",
        default: Text::Made(|| DEFAULT_YARNS_PER_UNIT.to_string()),
        valid: Text::Words("a number > 0 for both, or a pair (n_u, n_v)"),
        meaning: Text::Words(
            "pattern cells per unit of u and of v (n_u, n_v; the built-in draped cloths' uv is \
             in metres); unused without a pattern",
        ),
        update: |s, v, _| {
            let k = key("yarns_per_unit");
            let pair = pair(k, v)?;
            if !pair.iter().all(|n| n.is_finite() && *n > 0.0) {
                return Err(k.refuse(v));
            }
            s.spec.yarns_per_unit = pair;
            Ok(())
        },
    },
    SurfaceKey {
        name: "weft_color",
        default: Text::Words("the material's [dye] weft, else its own albedo (grey)"),
        valid: Text::Words(COLOR_VALID),
        meaning: Text::Words(
            "the weft's dyed fibre albedo ρ0 per channel (linear RGB); the interreflection \
             albedo follows in proportion, the sheen stays white",
        ),
        update: |s, v, _| {
            s.spec.weft_color = Some(colour(key("weft_color"), v)?);
            Ok(())
        },
    },
    SurfaceKey {
        name: "warp_color",
        default: Text::Words("the material's [dye] warp, else its own albedo (grey)"),
        valid: Text::Words(COLOR_VALID),
        meaning: Text::Words("the warp's dyed fibre albedo ρ0 per channel, as `weft_color`"),
        update: |s, v, _| {
            s.spec.warp_color = Some(colour(key("warp_color"), v)?);
            Ok(())
        },
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
        update: |s, v, _| {
            s.spec.u_max = within(key("u_max_deg"), v, 0.0, MAX_U_MAX_DEG)?.to_radians();
            Ok(())
        },
    },
    SurfaceKey {
        name: "gap",
        default: Text::Words("the material's [weave] gap, else 0 (yarns fill their cells)"),
        valid: Text::Made(|| {
            format!("a fraction in [0, {MAX_GAP}]; 0 for a flat fiber surface (no [yarn])")
        }),
        meaning: Text::Words(
            "the fraction of each cell's width between yarns: the crossing yarn shows there, \
             and a hole where both leave one",
        ),
        update: |s, v, _| {
            s.spec.gap = within(key("gap"), v, 0.0, MAX_GAP)?;
            Ok(())
        },
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
        update: |s, v, _| {
            let KeyValue::Text(name) = v else {
                return Err(key("detail").refuse(v));
            };
            s.spec.detail = Detail::from_name(name).map_err(|_| key("detail").refuse(v))?;
            Ok(())
        },
    },
    SurfaceKey {
        name: "relief",
        default: Text::Words("false"),
        valid: Text::Words("true or false; true needs a pattern"),
        meaning: Text::Words(
            "lay the weave as a relief at every level: yarns dip under the yarns they cross and \
             shadow their neighbours, and the cloth level carries the ratio they average to \
             (docs/model.md, \"The relief\"). false: the paper's BRDF at every level, the one \
             `woven eval`, the tables and every fit have",
        ),
        update: |s, v, _| {
            let KeyValue::Bool(on) = v else {
                return Err(key("relief").refuse(v));
            };
            s.spec.relief = *on;
            Ok(())
        },
    },
    SurfaceKey {
        name: "transmission",
        default: Text::Words("the material's [weave] transmission, else false (opaque)"),
        valid: Text::Words("true or false"),
        meaning: Text::Words(
            "let light through the cloth: straight through the share of the gaps left open \
             along a direction (the yarns' cross-section closes them as it tilts), and \
             diffusely through the yarns, what they neither reflect nor absorb (docs/model.md, \
             \"The open area\", \"Light through the yarns\"); the cloth is two-sided. false: \
             the paper's opaque cloth",
        ),
        update: |s, v, _| {
            let KeyValue::Bool(on) = v else {
                return Err(key("transmission").refuse(v));
            };
            s.spec.transmission = *on;
            Ok(())
        },
    },
    SurfaceKey {
        name: "irregularity",
        default: Text::Made(|| Irregularity::default().spread[0].to_string()),
        valid: Text::Made(|| format!("{}: one number or (weft, warp)", spread_valid())),
        meaning: Text::Words(
            "σ, the spread of the log of each yarn's dye factor along its length: 0 dyes every \
             yarn alike; needs a pattern",
        ),
        update: |s, v, _| {
            let k = key("irregularity");
            s.spec.irregularity.spread = pair(k, v)?;
            s.spec.irregularity.validate().map_err(|_| k.refuse(v))
        },
    },
    SurfaceKey {
        name: "irregularity_length",
        default: Text::Made(|| Irregularity::default().length.to_string()),
        valid: Text::Made(length_valid),
        meaning: Text::Words("ℓ, the distance along a yarn over which its dye factor changes"),
        update: |s, v, _| {
            let k = key("irregularity_length");
            s.spec.irregularity.length = v.number().ok_or_else(|| k.refuse(v))?;
            s.spec.irregularity.validate().map_err(|_| k.refuse(v))
        },
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
        update: |s, v, _| {
            let [lo, hi] = WAVELENGTH_RANGE_NM;
            s.wavelength_nm = within(key("wavelength_nm"), v, lo, hi)?;
            Ok(())
        },
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
                 each call passes (none: no filtering), and with false ignores it"
            )
        }),
        update: |s, v, _| {
            let KeyValue::Bool(on) = v else {
                return Err(key("footprint_filter").refuse(v));
            };
            s.footprint_filter = *on;
            Ok(())
        },
    },
];

/// A key whose value was refused, and why: what [`SurfaceSpec::from_keys`] returns, so that a
/// front end can point at the key (a scene, at its line).
#[derive(Debug, thiserror::Error)]
#[error("{}", self.message())]
pub struct KeyError {
    /// The key: one of [`SURFACE_KEYS`] (or the place within its value: `pattern[0][1]`), or
    /// the unknown key given.
    pub key: String,
    /// What is wrong with it (an [`Error::InvalidParameter`] names the key, its value and the
    /// range; a material file's error names the file).
    #[source]
    pub error: Error,
}

impl KeyError {
    /// `key`'s error; where the error names a place within the key's value (`pattern[0][1]`,
    /// `pattern.wif`), that place.
    fn new(key: &str, error: Error) -> KeyError {
        let key = match &error {
            Error::InvalidParameter { name, .. } if name.starts_with(key) => name.clone(),
            _ => key.to_string(),
        };
        KeyError { key, error }
    }

    /// The error's words: the library's, which name the key, or for a file's error the key and
    /// then the file's.
    fn message(&self) -> String {
        match &self.error {
            Error::InvalidParameter { .. } => self.error.to_string(),
            other => format!("`{}`: {other}", shown_key(&self.key)),
        }
    }
}

/// A woven surface read from its keys ([`SurfaceSpec::from_keys`]): the surface, and the two
/// keys that are not the surface's but its front end's (the wavelength its table is built at,
/// whether it filters by the footprint), and which keys were given.
#[derive(Clone, Debug)]
pub struct KeyedSurface {
    /// The surface.
    pub spec: SurfaceSpec,
    /// `wavelength_nm` (the library's default where not given).
    pub wavelength_nm: f64,
    /// `footprint_filter` (on where not given).
    pub footprint_filter: bool,
    given: Vec<&'static str>,
}

impl KeyedSurface {
    /// Whether the key `name` was given (not left to its default).
    pub fn given(&self, name: &str) -> bool {
        self.given.contains(&name)
    }

    /// The keys given, in [`SURFACE_KEYS`]'s order.
    pub fn given_keys(&self) -> &[&'static str] {
        &self.given
    }
}

impl SurfaceSpec {
    /// The surface the keys of `source` describe: its `material` (a preset's name, or a
    /// material file resolved by [`KeySource::path`]) with every other key of
    /// [`SURFACE_KEYS`] read by that key's own reader, and each key not given left at its
    /// default. The one reader of a surface's keys: scenes, `woven.Surface` and the Mitsuba
    /// plugin hand it their values.
    ///
    /// # Errors
    /// A [`KeyError`] naming the first key refused: one not in [`SURFACE_KEYS`], a value out of
    /// its range or of another shape (naming the value and the range), a material that cannot
    /// be read, a combination the surface cannot take (`pattern` with `weft_fraction`, a tilt
    /// or gap on a flat fiber surface, irregularity without a pattern).
    pub fn from_keys(source: &impl KeySource) -> Result<KeyedSurface, KeyError> {
        let k = key("material");
        let material = match source.get(k.name) {
            Some(KeyValue::Text(name)) => open_material(&name, &source.path(&name)),
            Some(other) => Err(k.refuse(&other)),
            None => Err(k.refuse("(missing)")),
        }
        .map_err(|e| KeyError::new(k.name, e))?;
        read_keys(material, source, true)
    }

    /// As [`from_keys`](Self::from_keys), on `material` given apart (a Python `Material`, a
    /// table's yarn): `source` must not give `material` too.
    ///
    /// # Errors
    /// As [`from_keys`](Self::from_keys); `material` given in `source` too.
    pub fn from_keys_on(
        material: Material,
        source: &impl KeySource,
    ) -> Result<KeyedSurface, KeyError> {
        read_keys(material, source, false)
    }
}

/// A material by name: a preset, or a file at `path` (a name that is a file, or looks like a
/// path). A name that is neither is taken for a mistyped preset: the error lists the presets.
fn open_material(name: &str, path: &Path) -> Result<Material, Error> {
    let a_file = path.exists() || name.contains('/') || name.ends_with(".toml");
    if Material::preset_toml(name).is_some() || !a_file {
        Material::preset(name)
    } else {
        Material::from_path(path)
    }
}

/// Every key of `source` onto `material`'s surface, in [`SURFACE_KEYS`]'s order; then what no
/// one key can check alone.
fn read_keys(
    material: Material,
    source: &impl KeySource,
    material_key: bool,
) -> Result<KeyedSurface, KeyError> {
    let dyn_source: &dyn KeySource = source;
    let names = source.names();
    if let Some(unknown) = names
        .iter()
        .find(|n| SurfaceKey::named(n).is_none() || (n.as_str() == "material" && !material_key))
    {
        let expected = if unknown == "material" {
            "the material given once (here it is given apart from the keys)".to_string()
        } else {
            let all: Vec<String> = SURFACE_KEYS
                .iter()
                .map(|k| format!("`{}`", k.name))
                .collect();
            format!("a surface key (unknown field): one of {}", all.join(", "))
        };
        let value = source.get(unknown).map_or(String::new(), |v| v.to_string());
        let error = Error::invalid(shown_key(unknown), value, expected);
        return Err(KeyError::new(unknown, error));
    }
    let mut read = KeyedSurface {
        spec: SurfaceSpec::new(material),
        wavelength_nm: DEFAULT_WAVELENGTH_NM,
        footprint_filter: true,
        given: Vec::new(),
    };
    for k in SURFACE_KEYS {
        if let Some(v) = source.get(k.name) {
            (k.update)(&mut read, &v, dyn_source).map_err(|e| KeyError::new(k.name, e))?;
            read.given.push(k.name);
        }
    }
    check_together(&read)?;
    Ok(read)
}

/// What the keys must be together: a tilt or gap needs yarns, irregularity a pattern, and the
/// surface passes its own checks ([`SurfaceSpec::validate`]).
fn check_together(read: &KeyedSurface) -> Result<(), KeyError> {
    let spec = &read.spec;
    if spec.material.yarn.is_none() && (spec.u_max > 0.0 || spec.gap > 0.0) {
        let (name, value) = if spec.gap > 0.0 {
            ("gap", spec.gap)
        } else {
            ("u_max_deg", spec.u_max.to_degrees())
        };
        let error = Error::invalid(
            name,
            format!("{value} on a flat fiber surface"),
            format!(
                "0: a flat fiber surface (no [yarn]) has no yarns to tilt or space; remove \
                 `{name}`"
            ),
        );
        return Err(KeyError::new(name, error));
    }
    spec.validate().map_err(|e| {
        // The library's checks name the surface's fields; the key of `u_max` is in degrees.
        let name = match &e {
            Error::InvalidParameter { name, .. } if name == "u_max" => "u_max_deg".to_string(),
            Error::InvalidParameter { name, .. } => name.clone(),
            _ => "material".to_string(),
        };
        KeyError::new(&name, e)
    })
}

/// `pattern`: the weave laid on the surface (a name, a matrix, or a WIF file the source
/// resolves).
fn read_pattern(s: &mut KeyedSurface, v: &KeyValue, source: &dyn KeySource) -> Result<(), Error> {
    let spec = PatternSpec::from_value(v, "pattern")?;
    // A WIF file as the source resolves it (a scene's, against its folder); kept so.
    let spec = match spec {
        PatternSpec::Wif(p) => PatternSpec::Wif(source.path(&p.display().to_string())),
        other => other,
    };
    let pattern = spec.pattern(Path::to_path_buf)?;
    let material = &mut s.spec.material;
    material.weave = Some(Weave::Pattern { spec, pattern });
    material.validate()
}

/// `weft_fraction`: γ in place of the material's weave.
fn read_weft_fraction(
    s: &mut KeyedSurface,
    v: &KeyValue,
    source: &dyn KeySource,
) -> Result<(), Error> {
    let k = key("weft_fraction");
    if source.get("pattern").is_some() {
        return Err(Error::invalid(
            k.name,
            v,
            "`pattern` or `weft_fraction`, not both",
        ));
    }
    let g = within(k, v, 0.0, 1.0)?;
    if s.spec.material.yarn.is_none() {
        return Err(Error::invalid(
            k.name,
            v,
            "no `weft_fraction` for a flat fiber surface: a material with yarns ([yarn])",
        ));
    }
    s.spec.material.weave = Some(Weave::WeftFraction(g));
    Ok(())
}

/// A number in `[lo, hi]`.
fn within(k: &SurfaceKey, v: &KeyValue, lo: f64, hi: f64) -> Result<f64, Error> {
    match v.number() {
        Some(x) if x.is_finite() && (lo..=hi).contains(&x) => Ok(x),
        _ => Err(k.refuse(v)),
    }
}

/// One number for both (weft and warp, u and v), or two: a list, or a string of one or two
/// numbers ("40", "40, 60": Mitsuba's XML has no lists). Finite; the key checks its range.
fn pair(k: &SurfaceKey, v: &KeyValue) -> Result<[f64; 2], Error> {
    let numbers: Option<Vec<f64>> = match v {
        // A list is a pair: one number is given bare.
        KeyValue::List(items) if items.len() == 2 => items.iter().map(KeyValue::number).collect(),
        KeyValue::List(_) => None,
        KeyValue::Text(t) => t
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|p| !p.is_empty())
            .map(|p| p.parse().ok())
            .collect(),
        other => other.number().map(|x| vec![x]),
    };
    match numbers.as_deref() {
        Some(&[x]) if x.is_finite() => Ok([x, x]),
        Some(&[a, b]) if a.is_finite() && b.is_finite() => Ok([a, b]),
        _ => Err(k.refuse(v)),
    }
}

/// A colour: three numbers in [0, 1].
fn colour(k: &SurfaceKey, v: &KeyValue) -> Result<Rgb, Error> {
    let KeyValue::List(items) = v else {
        return Err(k.refuse(v));
    };
    let c: Option<Vec<f64>> = items.iter().map(KeyValue::number).collect();
    match c.as_deref() {
        Some(&[r, g, b]) if [r, g, b].iter().all(|x| (0.0..=1.0).contains(x)) => Ok(Rgb([r, g, b])),
        _ => Err(k.refuse(v)),
    }
}

impl SurfaceSpec {
    /// The keys that read back as this surface on its material
    /// ([`from_keys_on`](Self::from_keys_on)`(self.material, …)`): every key but `material`,
    /// `pattern` and `weft_fraction` (the material carries its weave), and `u_max_deg` only
    /// where the tilt is not the material's own. What a front end hands another renderer (the
    /// Mitsuba plugin's scene translation) so that it reads the same surface.
    pub fn to_keys(&self) -> Keys {
        use KeyValue::{Float, List, Text};
        let pair = |p: [f64; 2]| List(vec![Float(p[0]), Float(p[1])]);
        let rgb = |c: Rgb| List(c.0.iter().map(|&x| Float(x)).collect());
        let mut keys = Keys::new()
            .with("yarns_per_unit", pair(self.yarns_per_unit))
            .with("gap", Float(self.gap))
            .with("detail", Text(self.detail.name().into()))
            .with("relief", KeyValue::Bool(self.relief))
            .with("transmission", KeyValue::Bool(self.transmission))
            .with("irregularity", pair(self.irregularity.spread))
            .with("irregularity_length", Float(self.irregularity.length));
        for (name, colour) in [
            ("weft_color", self.weft_color),
            ("warp_color", self.warp_color),
        ] {
            if let Some(c) = colour {
                keys.insert(name, rgb(c));
            }
        }
        if self.u_max != SurfaceSpec::new(self.material.clone()).u_max {
            keys.insert("u_max_deg", Float(self.u_max.to_degrees()));
        }
        keys
    }
}
