//! # woven — the Yang–Ikeuchi woven-cloth reflectance model
//!
//! woven evaluates the physically based cloth BRDF of Yang & Ikeuchi, *A Rendering Method for
//! Woven Clothes Reflections*: a fiber-surface BRDF from rough-surface scattering, yarns as
//! arc-topped prisms with exact masking and shadowing, distributions of lateral slopes and fiber
//! twist, and a weave mix. It tabulates the model for renderers, with importance sampling.
//!
//! The workflow is **Material → Model → Table**: a [`Material`](material::Material) describes a
//! cloth (a TOML file or a built-in preset), [`Material::build`](material::Material::build)
//! prepares it at one wavelength as a [`Model`] that evaluates the exact BRDF, and a
//! [`Table`](table::Table) stores that model on a grid for fast evaluation and sampling through the
//! [`Bsdf`](bsdf::Bsdf) trait.
//!
//! ```
//! use woven::bsdf::{Bsdf, Transport};
//! use woven::material::Material;
//! use woven::table::{Table, TableOptions};
//! use woven::Vec3;
//!
//! // Material: the polyester sateen of the paper's Fig. 8 (or Material::from_path("cloth.toml")).
//! let material = Material::preset("polyester-sateen")?;
//!
//! // Model: the exact BRDF at 550 nm. Directions in the cloth's frame, pointing away from the
//! // surface: s toward the light, v toward the viewer; f in sr⁻¹, without the cosine.
//! let model = material.build(550.0)?;
//! let s = Vec3::from_spherical(0.6, 0.0);
//! let v = Vec3::from_spherical(0.5, 3.0);
//! let exact = model.eval(s, v);
//! assert!(exact > 0.0 && model.albedo(0.6, 0.0) <= 1.0);
//!
//! // Table: a (deliberately coarse) tabulation for a renderer; `woven tabulate` and
//! // TableOptions::for_model give the accurate default grid.
//! let options = TableOptions { n_theta: 6, n_phi: 4, n_h: 21, ..TableOptions::default() };
//! let table = Table::build(&model, &material, &options, &|_, _| {})?;
//! assert!(table.eval(s, v) > 0.0);
//! // A camera path knows the viewer (wo = v) and draws the light's direction (wi); `uc` picks
//! // a lobe, `u` draws within it.
//! if let Some(sample) = table.sample(v, 0.5, [0.3, 0.7], Transport::Radiance) {
//!     // wi drawn ∝ f cos θi; the density `pdf` reports is the one `sample` drew with.
//!     let pdf = table.pdf(sample.wi, v, Transport::Radiance);
//!     assert!(sample.pdf > 0.0 && (pdf - sample.pdf).abs() <= 1e-6 * sample.pdf);
//! }
//! # Ok::<(), woven::Error>(())
//! ```
//!
//! The crate implements the project's specification, `docs/spec.md` in the repository: every
//! equation with the paper's numbers and every correction of the printed paper; `docs/model.md`
//! maps each equation to the item that computes it. Frames and units are those of
//! `docs/conventions.md`: `z` is the macro normal, the weft runs along `x`, the warp along `y`;
//! `s` (a renderer's `wi`) points toward the light and `v` (`wo`) toward the viewer, both away
//! from the surface; angles are radians; wavelengths nanometres; BRDFs are in sr⁻¹ without the
//! cosine. Runnable examples are in `crates/woven/examples/`.
//!
//! ## Modules
//!
//! - [`material`]: material descriptions, their TOML files and the built-in presets.
//! - [`Model`]: a material prepared at one wavelength — the exact BRDF and its albedo.
//! - [`fiber`]: the fiber-surface BRDF of the paper's §2 (docs/spec.md §1).
//! - [`yarn`]: the yarn's profile, exact masking, slope and twist averages (docs/spec.md §2.1–§2.6).
//! - [`weave`]: weave patterns (named, matrices, WIF drafts) and their weft fraction.
//! - [`cloth`]: fiber → yarn → weave, the cloth BRDF (docs/spec.md §2.7).
//! - [`bsdf`]: the renderer-facing trait: evaluation, importance sampling, densities, in the
//!   renderer's naming (`wi` toward the light, `wo` toward the viewer) with a transport mode.
//! - [`surface`]: a woven surface — the weave pattern on a surface's uv, dyes, yarn tilt, gaps,
//!   the footprint filter — as the renderer, the Python package and the Mitsuba plugin share it.
//! - [`gaps`]: the light that passes between the yarns: the cloth's open area along a
//!   direction, from the yarns' cross-section.
//! - [`color`]: linear RGB.
//! - [`baseline`]: the baselines a cloth renderer reaches for beside the woven model — the
//!   Charlie sheen over a Lambertian base, and Mitsuba's rough plastic.
//! - [`catalog`]: every reflectance model a front end takes by name or file (woven materials and
//!   the microcylinder fabrics), in colour.
//! - [`table`]: tabulated BRDFs for renderers, their `.wtab` file format and accuracy reports.
//! - [`export`]: export to other programs' formats (MERL).
//! - [`math`]: vectors, special functions, quadrature and interpolation.
//! - [`microcylinder`]: the microcylinder cloth model of Sadeghi et al. 2013, its six fabrics
//!   and a [`Bsdf`](bsdf::Bsdf) for it.
//! - [`keys`]: values as front ends hand them over (a scene's table, a Python dict, Mitsuba's
//!   properties), which the library reads its keys from.
//! - [`error`]: the one error type, [`Error`].
//! - [`figures`]: the data of the paper's Figs. 3–5 and 8–10 (the command line draws them).
//! - [`fsutil`]: files written atomically (a temporary file renamed into place), and read only
//!   when they are regular files within a stated size, text with its lines bounded.

mod albedo;
pub mod baseline;
pub mod bsdf;
#[cfg(feature = "serde")]
pub mod catalog;
pub mod cloth;
pub mod color;
pub mod directions;
pub mod error;
pub mod export;
pub mod fiber;
#[cfg(feature = "serde")]
pub mod figures;
pub mod fsutil;
pub mod gaps;
pub mod gonio;
pub mod keys;
pub mod material;
pub mod math;
pub mod microcylinder;
mod model;
pub mod progress;
pub mod relief;
#[cfg(feature = "serde")]
pub mod surface;
#[cfg(feature = "serde")]
pub mod table;
pub mod tensor;
pub mod translucency;
pub mod weave;
pub mod yarn;

pub use error::{Error, Result};
pub use math::Vec3;
pub use model::{AffineBrdf, Budget, Model};

/// The README shows the examples whole: every `examples/*.rs` must appear in it verbatim.
#[cfg(test)]
mod readme {
    #[test]
    fn readme_shows_every_example_verbatim() {
        let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let readme = std::fs::read_to_string(crate_dir.join("../../README.md")).unwrap();
        let mut names = Vec::new();
        for entry in std::fs::read_dir(crate_dir.join("examples")).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                assert!(
                    readme.contains(&format!("```rust\n{text}```")),
                    "README.md does not show {} verbatim in a ```rust block",
                    path.display()
                );
                names.push(path);
            }
        }
        assert!(names.len() >= 2, "expected the examples, found {names:?}");
    }

    /// The README's material file (its ```toml block) parses and builds.
    #[cfg(feature = "serde")]
    #[test]
    fn readme_material_file_parses() {
        let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let readme = std::fs::read_to_string(crate_dir.join("../../README.md")).unwrap();
        let start = readme
            .find("```toml\n")
            .expect("a ```toml block in README.md")
            + 8;
        let len = readme[start..].find("```").unwrap();
        let material =
            crate::material::Material::from_toml_str(&readme[start..start + len], "README.md")
                .unwrap_or_else(|e| panic!("README.md's material file: {e}"));
        material.build(550.0).unwrap();
    }
}
