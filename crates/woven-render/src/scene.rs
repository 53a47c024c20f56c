//! Scene files (TOML): parsing, validation, and building a renderable [`Scene`].
//!
//! The format is documented in `docs/render.md` and by [`EXAMPLE_SCENE`] (`woven render
//! --example`). Loading has two steps: [`SceneDescription`] parses and checks the file (fast, no
//! tables), [`Scene::build`] tabulates the woven materials and builds the geometry. Unknown keys
//! are errors; every error names the file, the key and, where TOML gives it, the line. Paths in
//! a scene are relative to the scene file's folder.

use crate::accel::Accel;
use crate::camera::Camera;
use crate::color::Rgb;
use crate::geometry::{Mesh, Primitive};
use crate::light::{Distribution1D, Environment, Light};
use crate::material::{Diffuse, SurfaceMaterial};
use crate::rng::SamplerKind;
use crate::shapes::{self, Cloth, Drape};
use crate::woven_material::{TableCache, TableGrid, WovenMaterial, WovenSpec};
use crate::{Error, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use toml::Spanned;
use woven::material::{Material, PatternSpec, Weave};
use woven::weave::Pattern;
use woven::Vec3;

/// A complete, commented scene to start from (`woven render --example`).
pub const EXAMPLE_SCENE: &str = include_str!("../scenes/example.toml");

/// The built-in showcase (`woven render` without a file, and bare `woven`).
pub const SHOWCASE_SCENE: &str = include_str!("../scenes/showcase.toml");

/// The longest scene file read, bytes (a guard against reading an endless stream).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The largest film side, pixels.
pub const MAX_FILM_SIDE: usize = 1 << 14;

/// The most samples per pixel.
pub const MAX_SPP: usize = 1 << 20;

/// The camera as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraSpec {
    /// Eye position.
    pub origin: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Up, roughly.
    pub up: Vec3,
    /// Horizontal field of view, degrees in (0, 180).
    pub fov_deg: f64,
}

/// The film.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Samples per pixel.
    pub spp: usize,
    /// Random seed.
    pub seed: u64,
    /// How a pixel's samples are drawn.
    pub sampler: SamplerKind,
    /// The index of the first sample a render takes (0 from a file): a progressive render
    /// renders passes of `spp` samples at 0, `spp`, 2 `spp`, … with one seed, and the passes'
    /// mean is then one render of all their samples (with Sobol points, stratified together).
    pub first_sample: u64,
}

/// Which sampling strategies the path tracer combines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// Light sampling and BSDF sampling, by multiple importance sampling (power heuristic).
    Mis,
    /// BSDF sampling only (point lights then contribute nothing).
    Bsdf,
    /// Light sampling only (emitters hit by BSDF-sampled rays are not counted).
    Light,
}

/// The `[integrator]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorSettings {
    /// Mitsuba's `max_depth`: 1 = emitters only, 2 = direct lighting, …; `None`: unlimited.
    pub max_depth: Option<u32>,
    /// Whether emitters seen directly by the camera render black.
    pub hide_emitters: bool,
    /// The sampling strategies.
    pub strategy: Strategy,
    /// Path depth from which Russian roulette may end a path (Mitsuba's `rr_depth`).
    pub rr_depth: u32,
    /// Whether woven materials see the pixel's footprint (ray differentials) and blend from
    /// the yarn of each pattern cell to the macro BRDF where the footprint covers cells
    /// (docs/render.md, "Fine weaves"); `false`: every point shows its cell's yarn.
    pub footprint_filter: bool,
}

/// A shape as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeDesc {
    /// A sphere.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f64,
    },
    /// A parallelogram.
    Rectangle {
        /// A corner.
        corner: Vec3,
        /// First edge.
        edge_u: Vec3,
        /// Second edge.
        edge_v: Vec3,
    },
    /// An open cylinder.
    Cylinder {
        /// Base centre.
        base: Vec3,
        /// Base to top.
        axis: Vec3,
        /// Radius.
        radius: f64,
    },
    /// An OBJ mesh.
    Mesh {
        /// The file (resolved against the scene's folder).
        path: PathBuf,
        /// Uniform scale applied first.
        scale: f64,
        /// Translation applied after the scale.
        translate: Vec3,
    },
    /// A procedural cloth hanging in folds.
    Cloth(Cloth),
    /// A procedural cloth draped over a sphere.
    Drape(Drape),
}

/// A material as the file gives it.
#[derive(Clone, Debug)]
pub enum MaterialDesc {
    /// Lambertian.
    Diffuse {
        /// Reflectance per channel.
        reflectance: Rgb,
    },
    /// The woven-cloth BRDF.
    Woven(Box<WovenSpec>),
}

/// A parsed and checked scene file, before any table or geometry is built.
#[derive(Clone, Debug)]
pub struct SceneDescription {
    /// Where it came from (for messages).
    pub origin: String,
    /// The camera.
    pub camera: CameraSpec,
    /// The film.
    pub film: Film,
    /// The integrator.
    pub integrator: IntegratorSettings,
    /// Lights in file order (a rectangle light adds geometry too).
    pub lights: Vec<LightDesc>,
    /// Each light's `sampling_weight` (Mitsuba's): next-event estimation picks a light with
    /// probability proportional to it. All 1 by default (a uniform choice).
    pub light_weights: Vec<f64>,
    /// Shapes in file order, each with its material's name.
    pub shapes: Vec<(ShapeDesc, String)>,
    /// Materials by name.
    pub materials: BTreeMap<String, MaterialDesc>,
}

/// A light as the file gives it.
#[derive(Clone, Debug)]
pub enum LightDesc {
    /// A point light.
    Point {
        /// Position.
        position: Vec3,
        /// Intensity, W/sr.
        intensity: Rgb,
    },
    /// A uniform environment.
    EnvironmentConstant {
        /// Radiance.
        radiance: Rgb,
        /// Multiplier.
        scale: f64,
    },
    /// An environment map.
    EnvironmentMap {
        /// The EXR file (resolved).
        path: PathBuf,
        /// Multiplier.
        scale: f64,
    },
    /// A rectangle emitter.
    Rectangle {
        /// A corner.
        corner: Vec3,
        /// First edge.
        edge_u: Vec3,
        /// Second edge.
        edge_v: Vec3,
        /// Radiance.
        radiance: Rgb,
    },
}

// ---------------------------------------------------------------------------------------------
// The file's raw form.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    camera: Spanned<RawCamera>,
    #[serde(default)]
    film: Option<Spanned<RawFilm>>,
    #[serde(default)]
    integrator: Option<Spanned<RawIntegrator>>,
    #[serde(default)]
    light: Vec<Spanned<RawLight>>,
    #[serde(default)]
    shape: Vec<Spanned<RawShape>>,
    #[serde(default)]
    material: BTreeMap<String, Spanned<RawMaterial>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    origin: [f64; 3],
    target: [f64; 3],
    #[serde(default = "default_up")]
    up: [f64; 3],
    fov_deg: f64,
}

fn default_up() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFilm {
    #[serde(default = "default_side")]
    width: i64,
    #[serde(default = "default_side")]
    height: i64,
    #[serde(default = "default_spp")]
    spp: i64,
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    sampler: SamplerKind,
}

fn default_side() -> i64 {
    512
}
fn default_spp() -> i64 {
    64
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawIntegrator {
    #[serde(default = "default_depth")]
    max_depth: i64,
    #[serde(default)]
    hide_emitters: bool,
    #[serde(default = "default_strategy")]
    strategy: Strategy,
    #[serde(default = "default_rr")]
    rr_depth: i64,
    #[serde(default = "yes")]
    footprint_filter: bool,
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
enum RawLight {
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
}

impl RawLight {
    fn sampling_weight(&self) -> f64 {
        match self {
            RawLight::Point {
                sampling_weight, ..
            }
            | RawLight::Environment {
                sampling_weight, ..
            }
            | RawLight::Rectangle {
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
enum RawShape {
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
    Cloth {
        corner: [f64; 3],
        edge_u: [f64; 3],
        edge_v: [f64; 3],
        #[serde(default = "default_folds")]
        folds: f64,
        #[serde(default)]
        amplitude: f64,
        #[serde(default)]
        taper: f64,
        #[serde(default = "default_resolution")]
        resolution: [i64; 2],
        drape: Option<String>,
        center: Option<[f64; 3]>,
        radius: Option<f64>,
        material: String,
    },
}

fn default_folds() -> f64 {
    3.0
}
fn default_resolution() -> [i64; 2] {
    [240, 60]
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum RawMaterial {
    Diffuse {
        reflectance: [f64; 3],
    },
    Woven {
        material: String,
        pattern: Option<RawPattern>,
        #[serde(default = "default_yarns")]
        yarns_per_unit: RawYarns,
        weft_color: Option<[f64; 3]>,
        warp_color: Option<[f64; 3]>,
        #[serde(default)]
        u_max_deg: f64,
        #[serde(default)]
        gap: f64,
    },
}

/// The largest yarn tilt `u_max_deg`, degrees.
pub const MAX_U_MAX_DEG: f64 = 80.0;

/// The largest gap fraction.
pub const MAX_GAP: f64 = 0.95;

fn default_yarns() -> RawYarns {
    RawYarns::Same(40.0)
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawYarns {
    Same(f64),
    PerAxis([f64; 2]),
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawPattern {
    Name(String),
    Matrix(Vec<Vec<u8>>),
    Wif(RawWif),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWif {
    wif: String,
}

// ---------------------------------------------------------------------------------------------
// Checks.

/// The 1-based line of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
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

/// Builds [`Error::Scene`] errors for one file.
struct Checker<'a> {
    origin: &'a str,
    text: &'a str,
}

impl Checker<'_> {
    fn err(&self, key: &str, span_start: usize, message: impl Into<String>) -> Error {
        Error::Scene {
            path: self.origin.to_string(),
            key: key.to_string(),
            line: Some(line_of(self.text, span_start)),
            message: message.into(),
        }
    }

    fn vec(&self, key: &str, at: usize, v: [f64; 3]) -> Result<Vec3> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(Vec3::new(v[0], v[1], v[2]))
        } else {
            Err(self.err(key, at, format!("{v:?}: expected three finite numbers")))
        }
    }

    fn nonzero(&self, key: &str, at: usize, v: [f64; 3]) -> Result<Vec3> {
        let x = self.vec(key, at, v)?;
        if x.length() > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, at, format!("{v:?}: expected a non-zero vector")))
        }
    }

    fn rgb(&self, key: &str, at: usize, v: [f64; 3], max: Option<f64>) -> Result<Rgb> {
        let ok = v
            .iter()
            .all(|c| c.is_finite() && *c >= 0.0 && max.is_none_or(|m| *c <= m));
        if ok {
            Ok(Rgb(v))
        } else {
            let range = match max {
                Some(m) => format!("each in [0, {m}]"),
                None => "each finite and >= 0".to_string(),
            };
            Err(self.err(key, at, format!("{v:?}: expected three numbers, {range}")))
        }
    }

    fn positive(&self, key: &str, at: usize, x: f64) -> Result<f64> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, at, format!("{x}: expected a finite number > 0")))
        }
    }

    fn range(&self, key: &str, at: usize, x: i64, lo: i64, hi: i64) -> Result<usize> {
        if (lo..=hi).contains(&x) {
            Ok(x as usize)
        } else {
            Err(self.err(key, at, format!("{x}: expected an integer in [{lo}, {hi}]")))
        }
    }

    fn edges(&self, key: &str, at: usize, eu: [f64; 3], ev: [f64; 3]) -> Result<(Vec3, Vec3)> {
        let u = self.nonzero(&format!("{key}.edge_u"), at, eu)?;
        let v = self.nonzero(&format!("{key}.edge_v"), at, ev)?;
        if u.cross(v).length() <= 1e-12 * u.length() * v.length() {
            return Err(self.err(
                &format!("{key}.edge_v"),
                at,
                "parallel to edge_u: the edges must span a parallelogram",
            ));
        }
        Ok((u, v))
    }
}

impl SceneDescription {
    /// Reads and checks a scene file.
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be read; [`Error::Scene`] naming the key and line otherwise.
    pub fn from_path(path: &Path) -> Result<SceneDescription> {
        use std::io::Read;
        let file = std::fs::File::open(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut text = String::new();
        file.take(MAX_SCENE_BYTES + 1)
            .read_to_string(&mut text)
            .map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        if text.len() as u64 > MAX_SCENE_BYTES {
            return Err(Error::Scene {
                path: path.display().to_string(),
                key: "(file)".into(),
                line: None,
                message: "longer than 16 MiB: not a scene file".into(),
            });
        }
        let base = path.parent().unwrap_or(Path::new("."));
        Self::from_str(&text, &path.display().to_string(), base)
    }

    /// Parses and checks scene text; `origin` names it in messages, relative paths resolve
    /// against `base`.
    ///
    /// # Errors
    /// [`Error::Scene`] naming the key and line.
    pub fn from_str(text: &str, origin: &str, base: &Path) -> Result<SceneDescription> {
        let raw: RawScene = toml::from_str(text).map_err(|e| {
            let at = e.span().map_or(0, |s| s.start);
            Error::Scene {
                path: origin.to_string(),
                key: key_at(text, at),
                line: e.span().map(|s| line_of(text, s.start)),
                message: e.message().trim_end().to_string(),
            }
        })?;
        let c = Checker { origin, text };

        // [camera]
        let at = raw.camera.span().start;
        let cam = raw.camera.into_inner();
        let origin_v = c.vec("camera.origin", at, cam.origin)?;
        let target = c.vec("camera.target", at, cam.target)?;
        let up = c.nonzero("camera.up", at, cam.up)?;
        if (target - origin_v).length() <= 0.0 {
            return Err(c.err(
                "camera.target",
                at,
                "equals camera.origin: nothing to look at",
            ));
        }
        if (target - origin_v)
            .normalize()
            .cross(up.normalize())
            .length()
            < 1e-9
        {
            return Err(c.err("camera.up", at, "parallel to the view direction"));
        }
        if !(cam.fov_deg > 0.0 && cam.fov_deg < 180.0) {
            return Err(c.err(
                "camera.fov_deg",
                at,
                format!("{}: expected degrees in (0, 180)", cam.fov_deg),
            ));
        }
        let camera = CameraSpec {
            origin: origin_v,
            target,
            up,
            fov_deg: cam.fov_deg,
        };

        // [film]
        let film = match raw.film {
            None => Film {
                width: 512,
                height: 512,
                spp: 64,
                seed: 0,
                sampler: SamplerKind::default(),
                first_sample: 0,
            },
            Some(f) => {
                let at = f.span().start;
                let f = f.into_inner();
                let side = MAX_FILM_SIDE as i64;
                Film {
                    width: c.range("film.width", at, f.width, 1, side)?,
                    height: c.range("film.height", at, f.height, 1, side)?,
                    spp: c.range("film.spp", at, f.spp, 1, MAX_SPP as i64)?,
                    seed: f.seed,
                    sampler: f.sampler,
                    first_sample: 0,
                }
            }
        };

        // [integrator]
        let integrator = match raw.integrator {
            None => IntegratorSettings {
                max_depth: Some(16),
                hide_emitters: false,
                strategy: Strategy::Mis,
                rr_depth: 5,
                footprint_filter: true,
            },
            Some(i) => {
                let at = i.span().start;
                let i = i.into_inner();
                let max_depth = match i.max_depth {
                    -1 => None,
                    d if (1..=1024).contains(&d) => Some(d as u32),
                    d => {
                        return Err(c.err(
                            "integrator.max_depth",
                            at,
                            format!("{d}: expected 1..=1024, or -1 for unlimited"),
                        ))
                    }
                };
                IntegratorSettings {
                    max_depth,
                    hide_emitters: i.hide_emitters,
                    strategy: i.strategy,
                    rr_depth: c.range("integrator.rr_depth", at, i.rr_depth, 1, 1024)? as u32,
                    footprint_filter: i.footprint_filter,
                }
            }
        };

        // [[light]]
        let mut lights = Vec::new();
        let mut light_weights = Vec::new();
        let mut environments = 0;
        for (k, l) in raw.light.into_iter().enumerate() {
            let at = l.span().start;
            let key = format!("light[{k}]");
            let l = l.into_inner();
            let weight = l.sampling_weight();
            if !(weight.is_finite() && weight > 0.0) {
                return Err(c.err(
                    &format!("{key}.sampling_weight"),
                    at,
                    format!("{weight}: expected a finite number > 0"),
                ));
            }
            light_weights.push(weight);
            lights.push(match l {
                RawLight::Point {
                    position,
                    intensity,
                    ..
                } => LightDesc::Point {
                    position: c.vec(&format!("{key}.position"), at, position)?,
                    intensity: c.rgb(&format!("{key}.intensity"), at, intensity, None)?,
                },
                RawLight::Environment {
                    radiance,
                    file,
                    scale,
                    ..
                } => {
                    environments += 1;
                    if environments > 1 {
                        return Err(c.err(
                            &key,
                            at,
                            "a second environment: a scene has at most one",
                        ));
                    }
                    if !(scale.is_finite() && scale >= 0.0) {
                        return Err(c.err(
                            &format!("{key}.scale"),
                            at,
                            format!("{scale}: expected a finite number >= 0"),
                        ));
                    }
                    match (radiance, file) {
                        (Some(r), None) => LightDesc::EnvironmentConstant {
                            radiance: c.rgb(&format!("{key}.radiance"), at, r, None)?,
                            scale,
                        },
                        (None, Some(f)) => LightDesc::EnvironmentMap {
                            path: base.join(f),
                            scale,
                        },
                        _ => {
                            return Err(c.err(
                                &key,
                                at,
                                "an environment takes exactly one of `radiance` and `file`",
                            ))
                        }
                    }
                }
                RawLight::Rectangle {
                    corner,
                    edge_u,
                    edge_v,
                    radiance,
                    ..
                } => {
                    let (edge_u, edge_v) = c.edges(&key, at, edge_u, edge_v)?;
                    LightDesc::Rectangle {
                        corner: c.vec(&format!("{key}.corner"), at, corner)?,
                        edge_u,
                        edge_v,
                        radiance: c.rgb(&format!("{key}.radiance"), at, radiance, None)?,
                    }
                }
            });
        }

        // [material.NAME]
        let mut materials = BTreeMap::new();
        for (name, m) in raw.material {
            let at = m.span().start;
            let key = format!("material.{name}");
            let desc = match m.into_inner() {
                RawMaterial::Diffuse { reflectance } => MaterialDesc::Diffuse {
                    reflectance: c.rgb(
                        &format!("{key}.reflectance"),
                        at,
                        reflectance,
                        Some(1.0),
                    )?,
                },
                RawMaterial::Woven {
                    material,
                    pattern,
                    yarns_per_unit,
                    weft_color,
                    warp_color,
                    u_max_deg,
                    gap,
                } => {
                    let mkey = format!("{key}.material");
                    let mut woven = if Material::preset_toml(&material).is_some() {
                        Material::preset(&material)
                    } else {
                        Material::from_path(base.join(&material))
                    }
                    .map_err(|e| c.err(&mkey, at, format!("`{material}`: {e}")))?;
                    if let Some(p) = pattern {
                        let pkey = format!("{key}.pattern");
                        let (spec, pat) = match p {
                            RawPattern::Name(n) => {
                                (PatternSpec::Name(n.clone()), Pattern::from_name(&n))
                            }
                            RawPattern::Matrix(m) => {
                                (PatternSpec::Matrix(m.clone()), Pattern::from_matrix(m))
                            }
                            RawPattern::Wif(RawWif { wif }) => {
                                let path = base.join(&wif);
                                (
                                    PatternSpec::Wif(path.clone()),
                                    Pattern::from_wif_path(&path),
                                )
                            }
                        };
                        let pattern = pat.map_err(|e| c.err(&pkey, at, e.to_string()))?;
                        woven.weave = Some(Weave::Pattern { spec, pattern });
                        woven
                            .validate()
                            .map_err(|e| c.err(&pkey, at, e.to_string()))?;
                    }
                    if !(u_max_deg.is_finite() && (0.0..=MAX_U_MAX_DEG).contains(&u_max_deg)) {
                        return Err(c.err(
                            &format!("{key}.u_max_deg"),
                            at,
                            format!("{u_max_deg}: expected degrees in [0, {MAX_U_MAX_DEG}]"),
                        ));
                    }
                    if !(gap.is_finite() && (0.0..=MAX_GAP).contains(&gap)) {
                        return Err(c.err(
                            &format!("{key}.gap"),
                            at,
                            format!("{gap}: expected a fraction in [0, {MAX_GAP}]"),
                        ));
                    }
                    if woven.yarn.is_none() && (u_max_deg > 0.0 || gap > 0.0) {
                        let k = if gap > 0.0 { "gap" } else { "u_max_deg" };
                        return Err(c.err(
                            &format!("{key}.{k}"),
                            at,
                            format!(
                                "`{material}` is a flat fiber surface (no [yarn]): it has no yarns to tilt or space; remove `{k}`"
                            ),
                        ));
                    }
                    let color = |k: &str, v: Option<[f64; 3]>| -> Result<Option<Rgb>> {
                        v.map(|v| c.rgb(&format!("{key}.{k}"), at, v, Some(1.0)))
                            .transpose()
                    };
                    MaterialDesc::Woven(Box::new(WovenSpec {
                        material: woven,
                        yarns_per_unit: {
                            let ykey = format!("{key}.yarns_per_unit");
                            let [nu, nv] = match yarns_per_unit {
                                RawYarns::Same(n) => [n, n],
                                RawYarns::PerAxis(p) => p,
                            };
                            [c.positive(&ykey, at, nu)?, c.positive(&ykey, at, nv)?]
                        },
                        weft_color: color("weft_color", weft_color)?,
                        warp_color: color("warp_color", warp_color)?,
                        u_max: u_max_deg.to_radians(),
                        gap,
                    }))
                }
            };
            materials.insert(name, desc);
        }

        // [[shape]]
        let mut shapes = Vec::new();
        for (k, s) in raw.shape.into_iter().enumerate() {
            let at = s.span().start;
            let key = format!("shape[{k}]");
            let (desc, material) = match s.into_inner() {
                RawShape::Sphere {
                    center,
                    radius,
                    material,
                } => (
                    ShapeDesc::Sphere {
                        center: c.vec(&format!("{key}.center"), at, center)?,
                        radius: c.positive(&format!("{key}.radius"), at, radius)?,
                    },
                    material,
                ),
                RawShape::Rectangle {
                    corner,
                    edge_u,
                    edge_v,
                    material,
                } => {
                    let (edge_u, edge_v) = c.edges(&key, at, edge_u, edge_v)?;
                    (
                        ShapeDesc::Rectangle {
                            corner: c.vec(&format!("{key}.corner"), at, corner)?,
                            edge_u,
                            edge_v,
                        },
                        material,
                    )
                }
                RawShape::Cylinder {
                    base: b,
                    axis,
                    radius,
                    material,
                } => (
                    ShapeDesc::Cylinder {
                        base: c.vec(&format!("{key}.base"), at, b)?,
                        axis: c.nonzero(&format!("{key}.axis"), at, axis)?,
                        radius: c.positive(&format!("{key}.radius"), at, radius)?,
                    },
                    material,
                ),
                RawShape::Mesh {
                    file,
                    scale,
                    translate,
                    material,
                } => (
                    ShapeDesc::Mesh {
                        path: base.join(file),
                        scale: c.positive(&format!("{key}.scale"), at, scale)?,
                        translate: c.vec(&format!("{key}.translate"), at, translate)?,
                    },
                    material,
                ),
                RawShape::Cloth {
                    corner,
                    edge_u,
                    edge_v,
                    folds,
                    amplitude,
                    taper,
                    resolution,
                    drape,
                    center,
                    radius,
                    material,
                } => {
                    let (edge_u, edge_v) = c.edges(&key, at, edge_u, edge_v)?;
                    let over_sphere = match drape.as_deref() {
                        None | Some("folds") => false,
                        Some("sphere") => true,
                        Some(other) => {
                            return Err(c.err(
                                &format!("{key}.drape"),
                                at,
                                format!(
                                    "`{other}`: expected \"folds\" (the default) or \"sphere\""
                                ),
                            ))
                        }
                    };
                    if !over_sphere {
                        if let Some(k) =
                            [("center", center.is_some()), ("radius", radius.is_some())]
                                .into_iter()
                                .find_map(|(k, given)| given.then_some(k))
                        {
                            return Err(c.err(
                                &format!("{key}.{k}"),
                                at,
                                "a cloth's sphere is only for drape = \"sphere\"",
                            ));
                        }
                    }
                    if !(folds.is_finite() && (0.0..=1000.0).contains(&folds)) {
                        return Err(c.err(
                            &format!("{key}.folds"),
                            at,
                            format!("{folds}: expected a number in [0, 1000]"),
                        ));
                    }
                    if !amplitude.is_finite() {
                        return Err(c.err(
                            &format!("{key}.amplitude"),
                            at,
                            format!("{amplitude}: expected a finite number"),
                        ));
                    }
                    if !(0.0..=1.0).contains(&taper) {
                        return Err(c.err(
                            &format!("{key}.taper"),
                            at,
                            format!("{taper}: expected a number in [0, 1]"),
                        ));
                    }
                    let rkey = format!("{key}.resolution");
                    let resolution = [
                        c.range(&rkey, at, resolution[0], 1, 4096)?,
                        c.range(&rkey, at, resolution[1], 1, 4096)?,
                    ];
                    if over_sphere {
                        let missing = |k: &str| {
                            c.err(
                                &format!("{key}.{k}"),
                                at,
                                "missing: drape = \"sphere\" needs the sphere's `center` and `radius`",
                            )
                        };
                        let center = center.ok_or_else(|| missing("center"))?;
                        let radius = radius.ok_or_else(|| missing("radius"))?;
                        let drape = Drape {
                            corner: c.vec(&format!("{key}.corner"), at, corner)?,
                            edge_u,
                            edge_v,
                            center: c.vec(&format!("{key}.center"), at, center)?,
                            radius: c.positive(&format!("{key}.radius"), at, radius)?,
                            folds,
                            amplitude,
                            resolution,
                        };
                        (ShapeDesc::Drape(drape), material)
                    } else {
                        (
                            ShapeDesc::Cloth(Cloth {
                                corner: c.vec(&format!("{key}.corner"), at, corner)?,
                                edge_u,
                                edge_v,
                                folds,
                                amplitude,
                                taper,
                                resolution,
                            }),
                            material,
                        )
                    }
                }
            };
            if !materials.contains_key(&material) {
                let known: Vec<&str> = materials.keys().map(String::as_str).collect();
                return Err(c.err(
                    &format!("{key}.material"),
                    at,
                    format!(
                        "`{material}` is not defined: add a [material.{material}] table (defined: {})",
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ),
                ));
            }
            shapes.push((desc, material));
        }

        Ok(SceneDescription {
            origin: origin.to_string(),
            camera,
            film,
            integrator,
            lights,
            light_weights,
            shapes,
            materials,
        })
    }
}

/// A scene ready to render: camera, lights, geometry with its BVH, and built materials.
pub struct Scene {
    /// The film settings.
    pub film: Film,
    /// The integrator settings.
    pub integrator: IntegratorSettings,
    /// The camera.
    pub camera: Camera,
    /// The lights.
    pub lights: Vec<Light>,
    /// Index of the environment light in `lights`, if any.
    pub environment: Option<usize>,
    /// How next-event estimation picks a light: in proportion to the lights' sampling weights.
    pub light_choice: Distribution1D,
    /// The geometry.
    pub accel: Accel,
    /// For each primitive: its material (index into `materials`), or `None` for a light's
    /// surface; and for a rectangle light's surface, the light's index.
    pub prim_info: Vec<PrimInfo>,
    /// The built materials.
    pub materials: Vec<Box<dyn SurfaceMaterial>>,
}

/// What a primitive is made of.
#[derive(Clone, Copy, Debug)]
pub struct PrimInfo {
    /// Its material, `None` for an emitter's (non-reflecting) surface.
    pub material: Option<usize>,
    /// The light whose surface it is.
    pub light: Option<usize>,
}

impl Scene {
    /// Builds the scene: tabulates woven materials (`grid`), loads meshes and environment maps,
    /// builds the BVH. `on_table` is called with a woven material's name before a table is
    /// built for it (materials sharing a yarn share its table); `progress` receives the table build's `(done, total)`.
    ///
    /// # Errors
    /// Files that cannot be read; materials the model library refuses.
    pub fn build(
        desc: &SceneDescription,
        grid: &TableGrid,
        on_table: &dyn Fn(&str),
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Scene> {
        Scene::build_with(desc, grid, TableCache::default(), on_table, progress)
    }

    /// [`build`](Self::build) with the tables of `cache` (e.g. [`TableCache::with_disk`], so that
    /// tables built on an earlier run are loaded, not built).
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_with(
        desc: &SceneDescription,
        grid: &TableGrid,
        mut cache: TableCache,
        on_table: &dyn Fn(&str),
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Scene> {
        let camera = Camera::new(
            desc.camera.origin,
            desc.camera.target,
            desc.camera.up,
            desc.camera.fov_deg,
            desc.film.width,
            desc.film.height,
        );
        // Materials used by some shape, in name order.
        let mut index_of = BTreeMap::new();
        let mut materials: Vec<Box<dyn SurfaceMaterial>> = Vec::new();
        for (name, m) in &desc.materials {
            if !desc.shapes.iter().any(|(_, n)| n == name) {
                continue;
            }
            let built: Box<dyn SurfaceMaterial> = match m {
                MaterialDesc::Diffuse { reflectance } => Box::new(Diffuse {
                    reflectance: *reflectance,
                }),
                MaterialDesc::Woven(spec) => Box::new(WovenMaterial::build(
                    spec,
                    grid,
                    &mut cache,
                    &|| on_table(name),
                    progress,
                )?),
            };
            index_of.insert(name.clone(), materials.len());
            materials.push(built);
        }

        let mut prims = Vec::new();
        let mut prim_info = Vec::new();
        let mut meshes: Vec<Mesh> = Vec::new();
        let mut lights = Vec::new();
        let mut environment = None;
        for l in &desc.lights {
            let index = lights.len();
            lights.push(match l {
                LightDesc::Point {
                    position,
                    intensity,
                } => Light::Point {
                    position: *position,
                    intensity: *intensity,
                },
                LightDesc::EnvironmentConstant { radiance, scale } => {
                    environment = Some(index);
                    Light::Environment(Environment::constant(*radiance, *scale))
                }
                LightDesc::EnvironmentMap { path, scale } => {
                    environment = Some(index);
                    Light::Environment(Environment::from_exr(path, *scale)?)
                }
                LightDesc::Rectangle {
                    corner,
                    edge_u,
                    edge_v,
                    radiance,
                } => {
                    prims.push(Primitive::Rectangle {
                        corner: *corner,
                        edge_u: *edge_u,
                        edge_v: *edge_v,
                    });
                    prim_info.push(PrimInfo {
                        material: None,
                        light: Some(index),
                    });
                    Light::Rectangle {
                        corner: *corner,
                        edge_u: *edge_u,
                        edge_v: *edge_v,
                        radiance: *radiance,
                        prim: prims.len() - 1,
                    }
                }
            });
        }
        for (k, (shape, name)) in desc.shapes.iter().enumerate() {
            let info = PrimInfo {
                material: Some(index_of[name]),
                light: None,
            };
            let mut add_mesh = |mesh: Mesh| {
                let m = meshes.len();
                for t in 0..mesh.indices.len() {
                    prims.push(Primitive::Triangle { mesh: m, index: t });
                    prim_info.push(info);
                }
                meshes.push(mesh);
            };
            match shape {
                ShapeDesc::Sphere { center, radius } => {
                    prims.push(Primitive::Sphere {
                        center: *center,
                        radius: *radius,
                    });
                    prim_info.push(info);
                }
                ShapeDesc::Rectangle {
                    corner,
                    edge_u,
                    edge_v,
                } => {
                    prims.push(Primitive::Rectangle {
                        corner: *corner,
                        edge_u: *edge_u,
                        edge_v: *edge_v,
                    });
                    prim_info.push(info);
                }
                ShapeDesc::Cylinder { base, axis, radius } => {
                    prims.push(Primitive::Cylinder {
                        base: *base,
                        axis: *axis,
                        radius: *radius,
                    });
                    prim_info.push(info);
                }
                ShapeDesc::Mesh {
                    path,
                    scale,
                    translate,
                } => add_mesh(shapes::load_obj(
                    path,
                    *scale,
                    *translate,
                    &format!("shape[{k}].file"),
                )?),
                ShapeDesc::Cloth(cloth) => add_mesh(cloth.mesh()),
                ShapeDesc::Drape(drape) => add_mesh(drape.mesh()),
            }
        }
        let mut integrator = desc.integrator.clone();
        // Footprints only where a material reads them.
        integrator.footprint_filter &= materials.iter().any(|m| m.uses_footprint());
        Ok(Scene {
            film: desc.film.clone(),
            integrator,
            camera,
            lights,
            environment,
            light_choice: Distribution1D::new(&desc.light_weights),
            accel: Accel::new(prims, meshes),
            prim_info,
            materials,
        })
    }
}
