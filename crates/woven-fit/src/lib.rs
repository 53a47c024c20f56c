//! Fitting the Yang–Ikeuchi woven-cloth BRDF, and the usual analytic baselines, to measured
//! reflectance.
//!
//! - [`data`]: measurements (one type for every source) and the readers that produce them.

pub mod data;
