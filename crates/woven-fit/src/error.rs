//! The fitter's error type.

/// Everything that can stop a fit before it starts (a fit that runs never fails: it reports how
/// well it did).
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
    /// The initial material is not one the fitter can use, or does not build.
    #[error(transparent)]
    Material(#[from] woven::Error),
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
