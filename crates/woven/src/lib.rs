//! # woven — the Yang–Ikeuchi woven-cloth reflectance model
//!
//! ```
//! use woven::{fiber::{Fiber, FiberParams}, Vec3};
//! // A polyester-like fiber surface: η = 1.6, σ_h/τ = 0.05, a little diffuse.
//! let fiber = Fiber::new(&FiberParams::rough(1.6, 0.05, 0.1), 550.0)?;
//! let s = Vec3::from_spherical(45f64.to_radians(), 0.0);
//! // The mirror direction carries the specular peak, ten times the retro-reflection direction;
//! // the directional albedo stays ≤ 1.
//! let mirror = Vec3::from_spherical(45f64.to_radians(), std::f64::consts::PI);
//! assert!(fiber.eval(s, mirror) > 10.0 * fiber.eval(s, s));
//! assert!(fiber.albedo(s.z) <= 1.0);
//! # Ok::<(), woven::Error>(())
//! ```
//!
//! The crate follows `MODEL.md` (the precise specification of the paper): frames and units are
//! those of `docs/conventions.md` — `z` is the macro normal, the weft runs along `x`, the warp
//! along `y`; `s` (a renderer's `wi`) points toward the light and `v` (`wo`) toward the viewer,
//! both away from the surface; angles are radians; BRDFs are in sr⁻¹ without the cosine.
//!
//! - [`fiber`]: the fiber-surface BRDF of the paper's §2 (MODEL.md §1).
//! - [`material`]: material descriptions and their TOML files.
//! - [`math`]: vectors, special functions, quadrature.

mod albedo;
pub mod bsdf;
pub mod cloth;
pub mod error;
pub mod export;
pub mod fiber;
mod fsutil;
pub mod gonio;
pub mod material;
pub mod math;
mod model;
#[cfg(feature = "serde")]
pub mod table;
pub mod weave;
pub mod yarn;

pub use error::{Error, Result};
pub use math::Vec3;
pub use model::Model;
