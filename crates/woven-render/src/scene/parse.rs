//! The scene file's raw form: what TOML deserializes it into, before any check; syntax errors
//! and unknown keys become [`Error::Scene`] naming the key and the line.

use super::Strategy;
use crate::rng::SamplerKind;
use crate::sky::SkyParams;
use crate::tonemap::ToneMap;
use crate::{Error, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// Deserializes scene text; `origin` names it in messages.
///
/// # Errors
/// [`Error::Scene`] for a syntax error, an unknown key or a value of the wrong type, naming the
/// key (the name before `=` on the line TOML points at, or the table header) and the line.
pub(super) fn parse(text: &str, origin: &str) -> Result<RawScene> {
    toml::from_str(text).map_err(|e| {
        let at = e.span().map_or(0, |s| s.start);
        let key = key_at(text, at);
        // A `type = …` table's values are read from a copy without places, so TOML points at
        // the table (the first of an array): find the table and the value at fault.
        let tagged = if key == "shape[0]" {
            tagged_at_fault::<RawShape>(text, "shape")
        } else if key == "light[0]" {
            tagged_at_fault::<RawLight>(text, "light")
        } else if key.starts_with("material.") && key.matches('.').count() == 1 {
            tagged_at_fault::<RawMaterial>(text, &key)
        } else {
            None
        };
        let (key, line) = tagged.unwrap_or_else(|| (key, e.span().map(|s| line_of(text, s.start))));
        Error::Scene {
            path: origin.to_string(),
            key,
            line,
            message: e.message().trim_end().to_string(),
        }
    })
}

/// Where a table read by its `type` goes wrong: `path` is an array of tables (`shape`: the
/// first element that does not read as a `T`) or a table (`material.m`). The key names the
/// value at fault where one is (the one, `type` aside, whose removal changes the error: values
/// are checked as they are read, and missing ones only after), with the line of the table's header. `None` when the text is not TOML or all
/// reads.
fn tagged_at_fault<T: serde::de::DeserializeOwned>(
    text: &str,
    path: &str,
) -> Option<(String, Option<usize>)> {
    let root: toml::Table = text.parse().ok()?;
    let (key, table, header) = match path.split_once('.') {
        None => {
            let array = root.get(path)?.as_array()?;
            let k = array
                .iter()
                .position(|v| v.clone().try_into::<T>().is_err())?;
            let header = format!("[[{path}]]");
            let line = text
                .lines()
                .enumerate()
                .filter(|(_, l)| l.trim_start().starts_with(&header))
                .nth(k)
                .map(|(i, _)| i + 1);
            (format!("{path}[{k}]"), array[k].as_table()?.clone(), line)
        }
        Some((outer, name)) => {
            let table = root.get(outer)?.as_table()?.get(name)?.as_table()?.clone();
            let header = format!("[{path}]");
            let line = text
                .lines()
                .position(|l| l.trim_start().starts_with(&header))
                .map(|i| i + 1);
            (path.to_string(), table, line)
        }
    };
    let fault = |t: &toml::Table| {
        toml::Value::Table(t.clone())
            .try_into::<T>()
            .err()
            .map(|e| e.message().to_string())
    };
    let original = fault(&table);
    let field = table.keys().filter(|f| *f != "type").find(|f| {
        let mut without = table.clone();
        without.remove(f.as_str());
        fault(&without) != original
    });
    Some((field.map_or(key.clone(), |f| format!("{key}.{f}")), header))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScene {
    pub(super) camera: Spanned<RawCamera>,
    #[serde(default)]
    pub(super) inset: Option<Spanned<RawInset>>,
    #[serde(default)]
    pub(super) film: Option<Spanned<RawFilm>>,
    #[serde(default)]
    pub(super) integrator: Option<Spanned<RawIntegrator>>,
    #[serde(default)]
    pub(super) light: Vec<Spanned<RawLight>>,
    #[serde(default)]
    pub(super) shape: Vec<Spanned<RawShape>>,
    #[serde(default)]
    pub(super) material: BTreeMap<String, Spanned<RawMaterial>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    pub(super) origin: [f64; 3],
    pub(super) target: [f64; 3],
    #[serde(default = "default_up")]
    pub(super) up: [f64; 3],
    pub(super) fov_deg: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawInset {
    pub(super) origin: [f64; 3],
    pub(super) target: [f64; 3],
    #[serde(default = "default_up")]
    pub(super) up: [f64; 3],
    pub(super) fov_deg: f64,
    pub(super) corner: [f64; 2],
    pub(super) size: [f64; 2],
    #[serde(default = "default_border")]
    pub(super) border: i64,
}

fn default_border() -> i64 {
    3
}

fn default_up() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFilm {
    #[serde(default = "default_side")]
    pub(super) width: i64,
    #[serde(default = "default_side")]
    pub(super) height: i64,
    #[serde(default = "default_spp")]
    pub(super) spp: i64,
    #[serde(default)]
    pub(super) seed: u64,
    #[serde(default)]
    pub(super) sampler: SamplerKind,
    #[serde(default)]
    pub(super) exposure: f64,
    #[serde(default)]
    pub(super) tonemap: ToneMap,
    #[serde(default)]
    pub(super) denoise: bool,
}

fn default_side() -> i64 {
    512
}
fn default_spp() -> i64 {
    64
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawIntegrator {
    #[serde(default = "default_depth")]
    pub(super) max_depth: i64,
    #[serde(default)]
    pub(super) hide_emitters: bool,
    #[serde(default = "default_strategy")]
    pub(super) strategy: Strategy,
    #[serde(default = "default_rr")]
    pub(super) rr_depth: i64,
    #[serde(default = "yes")]
    pub(super) footprint_filter: bool,
}

fn yes() -> bool {
    true
}

fn default_depth() -> i64 {
    16
}
fn default_strategy() -> Strategy {
    Strategy::Mis
}
fn default_rr() -> i64 {
    5
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub(super) enum RawLight {
    Point {
        position: [f64; 3],
        intensity: [f64; 3],
        #[serde(default = "one")]
        sampling_weight: f64,
    },
    Environment {
        radiance: Option<[f64; 3]>,
        file: Option<String>,
        #[serde(default = "one")]
        scale: f64,
        #[serde(default = "one")]
        sampling_weight: f64,
    },
    Rectangle {
        corner: [f64; 3],
        edge_u: [f64; 3],
        edge_v: [f64; 3],
        radiance: [f64; 3],
        #[serde(default = "one")]
        sampling_weight: f64,
    },
    /// A Preetham sun and sky ([`crate::sky`]); defaults those of [`SkyParams::default`].
    Sky {
        #[serde(default = "sky_elevation")]
        sun_elevation_deg: f64,
        #[serde(default)]
        sun_azimuth_deg: f64,
        #[serde(default = "sky_turbidity")]
        turbidity: f64,
        #[serde(default = "one")]
        scale: f64,
        #[serde(default = "yes")]
        sun: bool,
        #[serde(default = "one")]
        sampling_weight: f64,
    },
}

fn sky_elevation() -> f64 {
    SkyParams::default().sun_elevation_deg
}
fn sky_turbidity() -> f64 {
    SkyParams::default().turbidity
}

impl RawLight {
    /// The light's `sampling_weight`, whatever its kind.
    pub(super) fn sampling_weight(&self) -> f64 {
        match self {
            RawLight::Point {
                sampling_weight, ..
            }
            | RawLight::Environment {
                sampling_weight, ..
            }
            | RawLight::Rectangle {
                sampling_weight, ..
            }
            | RawLight::Sky {
                sampling_weight, ..
            } => *sampling_weight,
        }
    }
}

fn one() -> f64 {
    1.0
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub(super) enum RawShape {
    Sphere {
        center: [f64; 3],
        radius: f64,
        material: String,
    },
    Rectangle {
        corner: [f64; 3],
        edge_u: [f64; 3],
        edge_v: [f64; 3],
        material: String,
    },
    Cylinder {
        base: [f64; 3],
        axis: [f64; 3],
        radius: f64,
        material: String,
    },
    Mesh {
        file: String,
        #[serde(default = "one")]
        scale: f64,
        #[serde(default)]
        translate: [f64; 3],
        material: String,
    },
    Cloth(RawCloth),
}

/// A `type = "cloth"` shape.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCloth {
    pub(super) corner: [f64; 3],
    pub(super) edge_u: [f64; 3],
    pub(super) edge_v: [f64; 3],
    #[serde(default = "default_folds")]
    pub(super) folds: f64,
    #[serde(default)]
    pub(super) amplitude: f64,
    #[serde(default)]
    pub(super) taper: f64,
    #[serde(default = "default_resolution")]
    pub(super) resolution: [i64; 2],
    pub(super) drape: Option<String>,
    pub(super) center: Option<[f64; 3]>,
    pub(super) radius: Option<f64>,
    pub(super) material: String,
}

fn default_folds() -> f64 {
    3.0
}
fn default_resolution() -> [i64; 2] {
    [240, 60]
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub(super) enum RawMaterial {
    Diffuse {
        reflectance: [f64; 3],
    },
    /// A woven surface: its keys, which the library reads
    /// ([`SurfaceSpec::from_keys`](woven::surface::SurfaceSpec::from_keys)).
    Woven(toml::Table),
    /// A microcylinder fabric: a preset's name or a file.
    Microcylinder {
        material: String,
    },
    /// Mitsuba 3's `roughplastic`, its keys and defaults.
    Roughplastic {
        diffuse_reflectance: Option<[f64; 3]>,
        distribution: Option<String>,
        alpha: Option<f64>,
        int_ior: Option<f64>,
        ext_ior: Option<f64>,
        nonlinear: Option<bool>,
    },
    /// The Charlie sheen over a Lambertian base.
    Sheen {
        diffuse_reflectance: Option<[f64; 3]>,
        sheen_color: Option<[f64; 3]>,
        roughness: Option<f64>,
    },
}

/// The 1-based line of byte `offset` in `text`.
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// The key a syntax error points at, dotted: the name before `=` on its line under its table
/// (`film.width`, `shape[2].radius`), or the table header's.
fn key_at(text: &str, offset: usize) -> String {
    let start = text[..offset.min(text.len())]
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let line = text[start..].lines().next().unwrap_or("").trim();
    if line.starts_with('[') {
        return table_name(text, start);
    }
    // Where the last table header above the line starts.
    let mut header = None;
    let mut at = 0;
    for l in text[..start].split_inclusive('\n') {
        if l.trim_start().starts_with('[') {
            header = Some(at);
        }
        at += l.len();
    }
    match line.split_once('=') {
        Some((k, _)) => match header.map(|h| table_name(text, h)) {
            Some(t) if !t.is_empty() => format!("{t}.{}", k.trim()),
            _ => k.trim().to_string(),
        },
        None => "(file)".to_string(),
    }
}

/// The name of the table whose header line starts at byte `start`: `a.b` for `[a.b]`,
/// `shape[2]` for the third `[[shape]]`.
fn table_name(text: &str, start: usize) -> String {
    let line = text[start..].lines().next().unwrap_or("");
    let line = line.split('#').next().unwrap_or("").trim();
    if let Some(name) = line.strip_prefix("[[").and_then(|l| l.strip_suffix("]]")) {
        let name = name.trim();
        let earlier = text[..start]
            .lines()
            .filter(|l| {
                l.trim()
                    .strip_prefix("[[")
                    .and_then(|l| l.split("]]").next())
                    .is_some_and(|n| n.trim() == name)
            })
            .count();
        format!("{name}[{earlier}]")
    } else {
        line.trim_matches(|c| c == '[' || c == ']')
            .trim()
            .to_string()
    }
}
