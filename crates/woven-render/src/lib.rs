//! # woven-render — a path tracer for woven cloth
//!
//! Renders scenes described in TOML (see `docs/render.md` and [`scene::EXAMPLE_SCENE`]) with the
//! Yang–Ikeuchi cloth BRDF of the `woven` crate on real geometry: the weave pattern decides, at
//! every surface point, whether the weft or the warp is on top, and the yarn's BRDF follows the
//! surface's uv directions.
//!
//! ```
//! use woven_render::render::{render, RenderOptions};
//! use woven_render::scene::{Scene, SceneDescription};
//! use woven_render::woven_material::TableGrid;
//!
//! // A diffuse square (ρ = 0.5) lit from straight above by a point light of 1 W/sr at 1 m:
//! // radiance ρ/π · I cos θ / r² = 0.5/π at the centre.
//! let text = r#"
//!     [camera]
//!     origin = [0, 0, 1]
//!     target = [0, 0, 0]
//!     up = [0, 1, 0]
//!     fov_deg = 10
//!     [film]
//!     width = 4
//!     height = 4
//!     spp = 4
//!     [[light]]
//!     type = "point"
//!     position = [0, 0, 1]
//!     intensity = [1, 1, 1]
//!     [[shape]]
//!     type = "rectangle"
//!     corner = [-1, -1, 0]
//!     edge_u = [2, 0, 0]
//!     edge_v = [0, 2, 0]
//!     material = "grey"
//!     [material.grey]
//!     type = "diffuse"
//!     reflectance = [0.5, 0.5, 0.5]
//! "#;
//! let desc = SceneDescription::from_str(text, "<doc>", std::path::Path::new("."))?;
//! let scene = Scene::build(&desc, &TableGrid::Default, &|_| {}, &|_, _| {})?;
//! let image = render(&scene, &RenderOptions::default())?;
//! let centre = image.at(2, 2).0[0];
//! assert!((centre - 0.5 / std::f64::consts::PI).abs() < 2e-3);
//! # Ok::<(), woven_render::Error>(())
//! ```
//!
//! ## Modules
//! - [`scene`]: the scene file: parsing, checks, building (a file each).
//! - [`render`]: tiles over all cores, per-pixel means, progress reported to a callback.
//! - [`integrator`]: the path tracer (NEE + MIS, Russian roulette, Mitsuba's depth).
//! - [`material`]: the [`SurfaceMaterial`](material::SurfaceMaterial) trait (one door: a
//!   material's BSDF at a point, built once per path vertex into a
//!   [`BsdfScratch`](material::BsdfScratch)) and the diffuse material;
//!   [`woven_material`]: the woven cloth.
//! - [`light`]: the [`Emitter`](light::Emitter) interface (`sample_li`, `pdf_li`, `le`) and
//!   the point, environment and rectangle lights; [`camera`], [`geometry`], [`shapes`],
//!   [`accel`]: the rest of what a scene is made of.
//! - [`output`]: OpenEXR and PNG files.

pub mod accel;
pub mod camera;
pub mod denoise;
pub mod error;
pub mod fireflies;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod material;
pub mod output;
pub mod render;
pub mod rng;
pub mod scene;
pub mod shapes;
pub mod sky;
pub mod tonemap;
pub mod woven_material;

/// Linear RGB: the library's ([`woven::color`]), which woven surfaces return.
pub use woven::color;

pub use color::Rgb;
pub use error::{Error, Result};
