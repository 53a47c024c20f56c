//! Scene files (TOML): parsing, validation, and building a renderable [`Scene`].
//!
//! The format is documented in `docs/render.md` and by [`EXAMPLE_SCENE`] (`woven render
//! --example`). Loading has three steps, each in its own file: `parse.rs` deserializes the text
//! into the file's raw form (syntax, unknown keys, types), `check.rs` checks every value and
//! reference and gives a [`SceneDescription`] (fast, no tables), and `build.rs`
//! ([`Scene::build`]) tabulates the woven materials, loads meshes and maps and builds the
//! geometry. Unknown keys are errors; every error names the file, the key and, where TOML gives
//! it, the line. Paths in a scene are relative to the scene file's folder.

mod build;
mod check;
mod overrides;
mod parse;
pub mod portable;

pub use overrides::FilmOverrides;

use crate::accel::Accel;
use crate::camera::Camera;
use crate::color::Rgb;
use crate::light::Light;
use crate::material::SurfaceMaterial;
use crate::rng::SamplerKind;
use crate::shapes::{Cloth, Drape};
use crate::sky::SkyParams;
use crate::tonemap::Display;
use crate::woven_material::WovenSpec;
use crate::{Error, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use woven::math::sampling::Distribution1D;
use woven::Vec3;

/// A complete, commented scene to start from (`woven render --example`).
pub const EXAMPLE_SCENE: &str = include_str!("../../scenes/example.toml");

/// Where a mesh's OBJ text comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshSource {
    /// A file (resolved against the scene's folder).
    File(PathBuf),
    /// One of the meshes built into the renderer ([`BUILTIN_MESHES`](crate::shapes::BUILTIN_MESHES)),
    /// by name: `file = "builtin:NAME"`.
    Builtin(&'static str),
}

/// The built-in showcase (`woven render` without a file, and bare `woven`).
pub const SHOWCASE_SCENE: &str = include_str!("../../scenes/showcase.toml");

/// The longest scene file read, bytes (16 MiB: a guard against a wrong path filling memory).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The largest film side, pixels.
pub const MAX_FILM_SIDE: usize = 1 << 14;

/// The most samples per pixel.
pub const MAX_SPP: usize = 1 << 20;
/// The largest `[film] exposure`, stops either way.
pub const MAX_EXPOSURE: f64 = 20.0;
/// The range of a light's `sampling_weight`: only ratios matter, and within it any number of
/// lights' weights sum without overflow.
pub const SAMPLING_WEIGHT_RANGE: (f64, f64) = (1e-12, 1e12);

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

/// `[inset]`: a second camera whose view fills a rectangle of the film, framed by a border (a
/// close-up beside the whole, as in a figure). Its rays see the same scene and light.
#[derive(Clone, Debug, PartialEq)]
pub struct InsetSpec {
    /// Its camera; `fov_deg` spans the inset's width.
    pub camera: CameraSpec,
    /// Its top-left corner, border included, as fractions of the film's width and height
    /// (`[0, 0]` the film's top-left), so it keeps its place when the film is resized.
    pub corner: [f64; 2],
    /// Its width and height, border included, as fractions of the film's.
    pub size: [f64; 2],
    /// The border's width, pixels, in `[0, 64]` (drawn white).
    pub border: usize,
}

impl InsetSpec {
    /// Its rectangles on a film of `film` pixels: the inner one (its camera's film) and the
    /// outer one (with the border), each as top-left pixel and size. The border narrows where
    /// the inset is too small for it.
    pub fn pixels(&self, film: [usize; 2]) -> Rectangles {
        let at = |k: usize| {
            let x0 = ((self.corner[k] * film[k] as f64).round() as usize).min(film[k] - 1);
            let w = ((self.size[k] * film[k] as f64).round() as usize).clamp(1, film[k] - x0);
            (x0, w)
        };
        let ((x0, w), (y0, h)) = (at(0), at(1));
        let b = self.border.min((w - 1) / 2).min((h - 1) / 2);
        Rectangles {
            inner: ([x0 + b, y0 + b], [w - 2 * b, h - 2 * b]),
            outer: ([x0, y0], [w, h]),
        }
    }
}

/// An inset's place on the film ([`InsetSpec::pixels`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rectangles {
    /// Inside the border: top-left film pixel and size.
    pub inner: ([usize; 2], [usize; 2]),
    /// With the border.
    pub outer: ([usize; 2], [usize; 2]),
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
    /// How the PNG shows the render: `exposure` (stops) and `tonemap`.
    pub display: Display,
    /// Whether the image is denoised ([`crate::denoise`]) before it is written.
    pub denoise: bool,
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
        /// Where the OBJ text comes from.
        source: MeshSource,
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
    /// A microcylinder fabric (Sadeghi et al. 2013), the same at every point.
    Microcylinder(Box<woven::microcylinder::Microcylinder>),
    /// A rough dielectric coating over a diffuse base (Mitsuba 3's `roughplastic`).
    RoughPlastic(Box<woven::baseline::RoughPlastic>),
    /// The Charlie sheen over a Lambertian base.
    Sheen(Box<woven::baseline::Sheen>),
}

/// A parsed and checked scene file, before any table or geometry is built.
#[derive(Clone, Debug)]
pub struct SceneDescription {
    /// Where it came from (for messages).
    pub origin: String,
    /// The camera.
    pub camera: CameraSpec,
    /// A second view drawn over a rectangle of the film (a close-up), if any.
    pub inset: Option<InsetSpec>,
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
    /// A Preetham sun and sky, baked into a [`SKY_MAP_WIDTH`](crate::sky::SKY_MAP_WIDTH) ×
    /// [`SKY_MAP_HEIGHT`](crate::sky::SKY_MAP_HEIGHT) environment map.
    Sky {
        /// The sky's parameters (checked).
        params: SkyParams,
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

/// The largest yarn tilt `u_max_deg`, degrees, and the largest gap fraction: the library's
/// ([`woven::surface::SURFACE_KEYS`] holds every woven key's range).
pub use woven::surface::{MAX_GAP, MAX_U_MAX_DEG};

impl SceneDescription {
    /// Reads and checks a scene file: a regular file of at most [`MAX_SCENE_BYTES`] (checked
    /// before it is read).
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be read or is not UTF-8; [`Error::Scene`] naming the file when
    /// it is not a regular file or is too large, and naming the key and line otherwise.
    pub fn from_path(path: &Path) -> Result<SceneDescription> {
        let bytes =
            woven::fsutil::read_regular(path, MAX_SCENE_BYTES, "a scene file").map_err(|e| {
                Error::from_file(e, |message| Error::Scene {
                    path: path.display().to_string(),
                    key: "(file)".into(),
                    line: None,
                    message,
                })
            })?;
        let text = String::from_utf8(bytes).map_err(|_| Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                "not UTF-8 text, so not a scene file",
            ),
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::from_str(&text, &path.display().to_string(), base)
    }

    /// Parses and checks scene text (`parse.rs`, then `check.rs`); `origin` names it in
    /// messages, relative paths resolve against `base`.
    ///
    /// # Errors
    /// [`Error::Scene`] naming the key and line.
    pub fn from_str(text: &str, origin: &str, base: &Path) -> Result<SceneDescription> {
        let raw = parse::parse(text, origin)?;
        check::check(raw, text, origin, base)
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
    /// The inset's view, if any.
    pub inset: Option<Inset>,
    /// The lights.
    pub lights: Vec<Light>,
    /// Index of the environment light in `lights`, if any.
    pub environment: Option<usize>,
    /// Whether a ray can meet an emitter (an area light or the environment; point lights are
    /// deltas): if not, the path tracer makes no BSDF draw whose vertex could only add emission.
    pub emitters_can_be_hit: bool,
    /// How next-event estimation picks a light: in proportion to the lights' sampling weights.
    pub light_choice: Distribution1D,
    /// The geometry.
    pub accel: Accel,
    /// For each primitive: its material (index into `materials`), or `None` for a light's
    /// surface; and for a rectangle light's surface, the light's index.
    pub prim_info: Vec<PrimInfo>,
    /// The built materials.
    pub materials: Vec<Box<dyn SurfaceMaterial>>,
    /// Whether a material lets light through ([`SurfaceMaterial::transmits`]): shadow rays then
    /// carry the light the surfaces they meet pass, else they stop at the first.
    pub transmits: bool,
}

/// A built inset ([`InsetSpec`]).
#[derive(Clone, Debug)]
pub struct Inset {
    /// Its camera, over a film of the inset's inner size.
    pub camera: Camera,
    /// Where it lies on the film.
    pub at: Rectangles,
}

/// Which view a film pixel shows.
#[derive(Clone, Copy, Debug)]
pub enum View<'a> {
    /// The main camera, at the film pixel.
    Main,
    /// The inset's camera, at this pixel of the inset's own film.
    Inset(&'a Camera, [usize; 2]),
    /// The inset's border.
    Border,
}

impl Scene {
    /// The view film pixel `(x, y)` shows.
    pub fn view_at(&self, x: usize, y: usize) -> View<'_> {
        let Some(inset) = &self.inset else {
            return View::Main;
        };
        let inside = |([x0, y0], [w, h]): ([usize; 2], [usize; 2])| {
            (x0..x0 + w).contains(&x) && (y0..y0 + h).contains(&y)
        };
        let at = inset.at;
        if inside(at.inner) {
            View::Inset(&inset.camera, [x - at.inner.0[0], y - at.inner.0[1]])
        } else if inside(at.outer) {
            View::Border
        } else {
            View::Main
        }
    }
}

/// What a primitive is made of.
#[derive(Clone, Copy, Debug)]
pub struct PrimInfo {
    /// Its material, `None` for an emitter's (non-reflecting) surface.
    pub material: Option<usize>,
    /// The light whose surface it is.
    pub light: Option<usize>,
}
