//! A fit described as plain data — a model, a starting material by name, parameters held or
//! freed by name, and [`FitOptions`] — made into its [`ParamSet`] for a dataset and run.
//!
//! This is what `woven fit --data` does with its flags, for front ends that receive the fit as
//! values rather than as a command line (the Python bindings' `woven.fit`, which
//! `woven.batch.fit_many` sends to workers as plain data).
//!
//! ```
//! use woven_fit::data::{Dataset, Sample, Value};
//! use woven_fit::request::FitRequest;
//! use woven_fit::ModelKind;
//!
//! // A grey Lambertian surface of albedo 0.3, fitted by the Lambert baseline.
//! let samples = (0..10)
//!     .map(|k| Sample {
//!         theta_i: 0.1 * k as f64,
//!         phi_i: 0.0,
//!         theta_r: 0.4,
//!         phi_r: 2.0,
//!         value: Value::Mono(0.3 / std::f64::consts::PI),
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
//! let request = FitRequest::new(ModelKind::Lambert);
//! let result = request.run(&data, &|_, _| {})?;
//! assert!((result.estimates[0].value - 0.3).abs() < 1e-6);
//! # Ok::<(), woven_fit::FitError>(())
//! ```

use crate::data::{Dataset, Value};
use crate::fit::ProgressFn;
use crate::microcylinder::Fabric;
use crate::{fit, FitError, FitOptions, FitResult, ModelKind, ParamSet};
use woven::material::Material;

/// One fit, as values: what `woven fit --data FILE --model … --init … --fix … --free …` asks.
#[derive(Clone, Debug, PartialEq)]
pub struct FitRequest {
    /// The model fitted.
    pub model: ModelKind,
    /// The starting material: for `cloth` and `fiber` a woven preset name or material file
    /// (`None`: belt-cloth); for `microcylinder` a microcylinder preset or file (`None`:
    /// microcylinder-linen-plain); the baselines take none.
    pub init: Option<String>,
    /// Parameters held at a value, each `name=value` (as `--fix`).
    pub fix: Vec<String>,
    /// Parameters let vary, by name (as `--free`).
    pub free: Vec<String>,
    /// How the fit runs (seed, starts, iterations, residual, saturation).
    pub options: FitOptions,
}

impl FitRequest {
    /// A fit of `model` from its default start with the default options.
    pub fn new(model: ModelKind) -> FitRequest {
        FitRequest {
            model,
            init: None,
            fix: Vec::new(),
            free: Vec::new(),
            options: FitOptions::default(),
        }
    }

    /// The parameter set this request fits to `dataset`: the model's parameters for the data's
    /// channels and calibration, started at `init`, with `fix` and `free` applied in order.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming `init` for a starting material that cannot be read
    /// or is of the wrong kind, naming `fix` for a malformed `name=value`, or for a value out of
    /// range; [`FitError::UnknownParameter`] for a name the model does not have;
    /// [`FitError::Material`] for a material file that does not parse.
    pub fn param_set(&self, dataset: &Dataset) -> Result<ParamSet, FitError> {
        let channels = match dataset.samples.first().map(|s| s.value) {
            Some(Value::Rgb(_)) => 3,
            _ => 1,
        };
        let relative = dataset.relative;
        let mut set = match (self.model, &self.init) {
            (ModelKind::Microcylinder, Some(arg)) => {
                let fabric = Fabric::from_preset_or_path(arg)?;
                ParamSet::microcylinder(Some(&fabric), channels, relative)?
            }
            (model, Some(arg)) => {
                let material = Material::from_preset_or_path(arg).map_err(|e| {
                    FitError::invalid(
                        "init",
                        format!("{arg:?}"),
                        format!("a woven preset or material file ({e})"),
                    )
                })?;
                ParamSet::new(model, Some(&material), channels, relative)?
            }
            (model, None) => ParamSet::new(model, None, channels, relative)?,
        };
        self.check_named_once()?;
        for f in &self.fix {
            set.fix_arg(f)?;
        }
        for f in &self.free {
            set.free(f.trim())?;
        }
        Ok(set)
    }

    /// Refuses a parameter named twice across `fix` and `free`: held twice, freed twice, or held
    /// and freed at once (which wins would depend on the order).
    fn check_named_once(&self) -> Result<(), FitError> {
        let fixed = self
            .fix
            .iter()
            .map(|f| ("fix", f.split_once('=').map_or(f.as_str(), |(n, _)| n)));
        let freed = self.free.iter().map(|f| ("free", f.as_str()));
        let mut seen: Vec<(&str, &str)> = Vec::new();
        for (key, name) in fixed.chain(freed) {
            let name = name.trim();
            if let Some((first, _)) = seen.iter().find(|(_, n)| *n == name) {
                return Err(FitError::invalid(
                    key,
                    name,
                    format!("each parameter named once across fix and free (already in {first})"),
                ));
            }
            seen.push((key, name));
        }
        Ok(())
    }

    /// Fits `dataset`: [`param_set`](Self::param_set), then [`fit`](crate::fit()) with
    /// `options`, reporting `(done, total)` steps to `progress`. Deterministic for a seed.
    ///
    /// # Errors
    /// As [`param_set`](Self::param_set) and [`fit`](crate::fit()).
    pub fn run(&self, dataset: &Dataset, progress: ProgressFn<'_>) -> Result<FitResult, FitError> {
        let set = self.param_set(dataset)?;
        fit(dataset, &set, &self.options, progress)
    }
}
