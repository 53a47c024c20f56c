//! The fitter's error type.

/// Everything that can stop a fit before it starts (a fit that runs never fails: it reports how
/// well it did), and a fit cancelled while it runs.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// A parameter's value (given to `fix`, or an initial material's) is out of range or
    /// malformed, or a parameter is not one the model can take.
    #[error("invalid parameter `{name}` = {value}: expected {expected}")]
    InvalidParameter {
        /// The parameter as the user named it.
        name: String,
        /// The offending value, formatted.
        value: String,
        /// The valid range or set, in words.
        expected: String,
    },
    /// A parameter name that the chosen model does not have.
    #[error("unknown parameter `{name}` for model {model}: its parameters are {known}")]
    UnknownParameter {
        /// The name given.
        name: String,
        /// The model.
        model: String,
        /// The model's parameter names, comma-separated.
        known: String,
    },
    /// The dataset cannot be fitted (empty, mixed channels, nothing left after filtering).
    #[error("dataset `{name}`: {message}")]
    Data {
        /// The dataset's name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The data cannot determine the free parameters, so the fit is refused rather than run:
    /// fewer measured values than free parameters, or a Jacobian at the initial values whose rank
    /// on the measurements is below its rank on a reference geometry (some combination of the
    /// parameters changes no prediction where the data was measured; `crate::fit`'s module docs).
    /// Holding some parameters at a value ([`ParamSet::fix`](crate::ParamSet::fix)) or measuring
    /// at more geometries makes a fit possible; a fit that is only ill-conditioned runs, with
    /// warnings.
    #[error(
        "dataset `{name}`: {measurements} measurement(s) × {channels} channel(s) = {values} \
         value(s) cannot determine {free} free parameter(s) (the Jacobian at the initial values \
         has rank {rank}): {detail}; hold some at a value (fixed parameters, `ParamSet::fix`) or \
         add measurements at other geometries"
    )]
    Underdetermined {
        /// The dataset's name.
        name: String,
        /// The usable measurements (after the ones dropped).
        measurements: usize,
        /// Colour channels per measurement (1 or 3).
        channels: usize,
        /// Measured values: `measurements × channels`, the residuals a fit has.
        values: usize,
        /// The free parameters.
        free: usize,
        /// The rank of the Jacobian at the initial values on the measurements (columns scaled to
        /// unit length).
        rank: usize,
        /// Its rank on the reference geometry: what measurements spread over the hemisphere
        /// would determine.
        reference_rank: usize,
        /// The parameters the data leaves undetermined (beyond what the model itself does), the
        /// most involved first.
        undetermined: Vec<String>,
        /// What is wrong, in words, naming them.
        detail: String,
    },
    /// The initial material is not one the fitter can use, or does not build.
    #[error(transparent)]
    Material(#[from] woven::Error),
    /// The fit was told to stop (its progress's
    /// [`cancelled`](woven::progress::Progress::cancelled) answered `true`) before it finished;
    /// it returns no partial result.
    #[error("the fit was cancelled before it finished")]
    Cancelled,
}

impl FitError {
    /// A [`FitError::InvalidParameter`] from displayable parts.
    pub fn invalid(
        name: impl Into<String>,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        FitError::InvalidParameter {
            name: name.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }
}
