//! The one error type of the measurement readers.

use std::path::PathBuf;

/// Why a measurement file could not be read.
///
/// Every variant names the file; a bad row also names its line (1-based, as an editor counts)
/// and its column (the header's name for it, or the field's position where the format has no
/// header).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// Reading the file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A row holds a value that cannot be used.
    #[error("{}: line {line}, column `{column}`: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The line, 1-based.
        line: u64,
        /// The column: its header name, or its position (`field 7`) in formats without a header.
        column: String,
        /// What is wrong, with the offending text and the valid range.
        message: String,
    },
    /// The file as a whole is not what the reader expects (an unknown header, a missing column,
    /// no measurements, an unknown sample name).
    #[error("{}: {message}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl DataError {
    /// The line of a [`DataError::Parse`], `None` for the other variants.
    pub fn line(&self) -> Option<u64> {
        match self {
            DataError::Parse { line, .. } => Some(*line),
            _ => None,
        }
    }

    /// The column of a [`DataError::Parse`], `None` for the other variants.
    pub fn column(&self) -> Option<&str> {
        match self {
            DataError::Parse { column, .. } => Some(column),
            _ => None,
        }
    }
}
