//! Export of woven BRDFs to file formats that other programs read.
//!
//! - [`merl`]: the binary layout of the MERL BRDF database (isotropic BRDFs only), read by BRDF
//!   viewers and by renderers' measured-BRDF loaders.
//! - [`rgl`]: RGL's `.bsdf` format (anisotropic, RGB or spectral), which Mitsuba 3's `measured`
//!   plugin and pbrt-v4's `MeasuredBxDF` read; [`crate::tensor`] is its container and
//!   [`crate::math::marginal`] the warp its readers draw half vectors with.
//!
//! Export functions take the BRDF as a closure `f(s, v)` (sr⁻¹, no cosine, `s` toward the light,
//! `v` toward the viewer, local frame of `docs/conventions.md`), so that any [`Model`](crate::Model)
//! or a tabulated BRDF can be exported, and a caller can evaluate the bins in parallel itself.

pub mod merl;
pub mod rgl;

pub use merl::{check_isotropic, MerlBrdf};
pub use rgl::{Channels, RglFile, RglOptions};
