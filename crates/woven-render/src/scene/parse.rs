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
        Error::Scene {
            path: origin.to_string(),
            key: key_at(text, at),
            line: e.span().map(|s| line_of(text, s.start)),
            message: e.message().trim_end().to_string(),
        }
    })
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
    Woven(RawWoven),
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

/// A `type = "woven"` material.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWoven {
    pub(super) material: String,
    pub(super) pattern: Option<RawPattern>,
    #[serde(default = "default_yarns")]
    pub(super) yarns_per_unit: RawYarns,
    pub(super) weft_color: Option<[f64; 3]>,
    pub(super) warp_color: Option<[f64; 3]>,
    pub(super) u_max_deg: Option<f64>,
    #[serde(default)]
    pub(super) gap: f64,
    pub(super) detail: Option<String>,
    pub(super) irregularity: Option<RawYarns>,
    pub(super) irregularity_length: Option<f64>,
}

fn default_yarns() -> RawYarns {
    RawYarns::Same(woven::surface::DEFAULT_YARNS_PER_UNIT)
}

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum RawYarns {
    Same(f64),
    PerAxis([f64; 2]),
}

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum RawPattern {
    Name(String),
    Matrix(Vec<Vec<u8>>),
    Wif(RawWif),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWif {
    pub(super) wif: String,
}

/// The 1-based line of byte `offset` in `text`.
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// The key a syntax error points at: the name before `=` on its line, or the table header.
fn key_at(text: &str, offset: usize) -> String {
    let start = text[..offset.min(text.len())]
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let line = text[start..].lines().next().unwrap_or("").trim();
    if let Some((k, _)) = line.split_once('=') {
        k.trim().to_string()
    } else if line.starts_with('[') {
        line.trim_matches(|c| c == '[' || c == ']').to_string()
    } else {
        "(file)".to_string()
    }
}
