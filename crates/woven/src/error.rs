//! The one error type of the `woven` library.

use std::path::PathBuf;

/// Everything that can go wrong when building a model from user parameters or files.
///
/// Hot paths (`eval`, `pdf`, `sample`) never return errors: parameters are validated once,
/// when a model is constructed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its valid range.
    #[error("invalid parameter `{name}` = {value}: expected {expected}")]
    InvalidParameter {
        /// The parameter's name as it appears in material files (`fiber.roughness`).
        name: String,
        /// The offending value, formatted.
        value: String,
        /// The valid range or set, in words.
        expected: String,
    },
    /// A file or string could not be parsed.
    #[error("{path}: {message}")]
    Parse {
        /// Where the text came from (a path, or `<string>`).
        path: String,
        /// What is wrong, with the line where known.
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An [`Error::InvalidParameter`] from displayable parts.
    pub fn invalid(
        name: impl Into<String>,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Error::InvalidParameter {
            name: name.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }
}

/// Checks `lo <= x <= hi` (and finiteness), naming the parameter on failure.
pub(crate) fn check_range(name: &str, x: f64, lo: f64, hi: f64) -> Result<f64> {
    if x.is_finite() && x >= lo && x <= hi {
        Ok(x)
    } else {
        Err(Error::invalid(name, x, format!("a number in [{lo}, {hi}]")))
    }
}
