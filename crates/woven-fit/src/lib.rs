//! Fitting the Yang–Ikeuchi woven-cloth BRDF, and the usual analytic baselines, to measured
//! reflectance.
//!
//! ```
//! use woven_fit::data::{Dataset, Sample, Value};
//! use woven_fit::{fit, FitOptions, ModelKind, ParamSet};
//!
//! // A Lambertian surface of albedo 0.4 seen at a few angles...
//! let samples = (0..12)
//!     .map(|k| Sample {
//!         theta_i: 0.1 * k as f64,
//!         phi_i: 0.0,
//!         theta_r: 0.5,
//!         phi_r: 3.0,
//!         value: Value::Mono(0.4 / std::f64::consts::PI),
//!         weight: 1.0,
//!     })
//!     .collect();
//! let data = Dataset {
//!     name: "grey".into(),
//!     source: "grey.csv".into(),
//!     samples,
//!     dropped_below_horizon: 0,
//!     relative: false,
//! };
//! // ... fitted by the Lambert baseline.
//! let set = ParamSet::new(ModelKind::Lambert, None, 1, false)?;
//! let result = fit(&data, &set, &FitOptions::default(), &|_, _| {})?;
//! assert!((result.estimates[0].value - 0.4).abs() < 1e-6);
//! assert!(result.rms_log < 1e-6);
//! # Ok::<(), woven_fit::FitError>(())
//! ```
//!
//! - [`data`]: measurements (one type for every source) and the readers that produce them.
//! - [`params`]: the parameter registry of each model: names, bounds, transforms, which are free.
//! - [`evaluate`]: a parameter set made ready to evaluate at every measurement (the woven model,
//!   the microcylinder fabric, the Lambert, microfacet and sheen baselines).
//! - [`microcylinder`]: fitting the microcylinder cloth model (Sadeghi et al. 2013): its
//!   parameters, its starting fabric, its energy guard, the fitted fabric as a file.
//! - [`fit`](mod@fit): the objective (log or relative residuals) and the optimizer (quasi-random
//!   multi-start, then bounded Levenberg–Marquardt).
//! - [`reference`](mod@reference): fitting to a reference model sampled over the hemisphere (the microcylinder
//!   fabrics): the samples, dyes per yarn family, the scaled log error, the satin ridge ratio.
//! - [`projection`]: a woven BRDF projected onto the standard lobes renderers carry (a sheen
//!   over a Lambertian lobe and an anisotropic GGX along the yarn), beside the best isotropic
//!   GGX + Lambert.
//! - [`request`]: a fit described as plain data (model, start, held and freed parameters,
//!   options), as `woven fit --data` and the Python bindings run it.
//! - [`report`]: standard errors, warnings, statistics, the Markdown report, plot data and the
//!   comparison table.

pub mod data;
pub mod error;
pub mod evaluate;
pub mod fit;
pub mod microcylinder;
pub mod params;
pub mod projection;
pub mod reference;
pub mod report;
pub mod request;
pub mod standard;

pub use error::FitError;
pub use fit::{fit, FitOptions, ProgressFn, Residual, MAX_ITERATIONS, MAX_STARTS};
pub use params::{ModelKind, ParamSet, Quantity};
pub use report::{Comparison, FitResult};
