//! The crate's one error type.

use std::path::PathBuf;

/// Everything that can go wrong loading a scene or writing an image.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene file is malformed or holds an invalid value.
    #[error("{path}{}: `{key}`: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Scene {
        /// The scene file (or `<string>`).
        path: String,
        /// The offending key, dotted (`shape[2].radius`); `(file)` for syntax errors.
        key: String,
        /// The 1-based line, where TOML gives it.
        line: Option<usize>,
        /// What is wrong and what is valid.
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
    /// An image could not be read or written.
    #[error("{}: {message}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The model library refused a material or table.
    #[error(transparent)]
    Woven(#[from] woven::Error),
    /// An input within its ranges that would take more than a budget allows (memory, above
    /// all), refused before anything is allocated.
    #[error("over the {budget} budget: {message}")]
    OverBudget {
        /// Which budget: `film`, `triangles`.
        budget: String,
        /// What the input would take, the budget, and what fits.
        message: String,
    },
    /// The render was told to stop (its progress's
    /// [`cancelled`](woven::progress::Progress::cancelled) answered `true`) before it finished;
    /// no image is returned.
    #[error("the render was cancelled before it finished")]
    Cancelled,
    /// An invalid render setting (from the command line or a caller).
    #[error("invalid setting `{name}` = {value}: expected {expected}")]
    InvalidSetting {
        /// The setting.
        name: String,
        /// Its value, formatted.
        value: String,
        /// The valid range or set.
        expected: String,
    },
}

impl Error {
    /// A file refused by `woven::fsutil` (not a regular file, too large) as this crate's error:
    /// `refused` makes it from the message, which names the limit; I/O errors stay I/O errors.
    pub(crate) fn from_file(e: woven::Error, refused: impl FnOnce(String) -> Error) -> Error {
        match e {
            woven::Error::Parse { message, .. } => refused(message),
            woven::Error::Io { path, source } => Error::Io { path, source },
            e => Error::Woven(e),
        }
    }
}

/// The crate's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
