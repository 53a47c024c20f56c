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
    /// The work was told to stop ([`Progress::cancelled`](crate::progress::Progress::cancelled))
    /// and stopped before it finished; nothing it would have made is returned.
    #[error("cancelled before it finished")]
    Cancelled,
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

/// The longest run of non-blank characters a message shows whole: a long path fits; a key or a
/// name of a megabyte, echoed back from hostile input, does not.
pub const MAX_WORD_CHARS: usize = 256;

/// `message` with each run of non-blank characters longer than [`MAX_WORD_CHARS`] cut to its
/// first 120 and last 40 characters around a note of how many were left out: what front ends
/// (the CLI, Python, the server) show of an error, so that a 10 MB name is not echoed whole.
///
/// ```
/// let key = "k".repeat(1_000_000);
/// let message = format!("unknown field `{key}`, expected `a`");
/// let shown = woven::error::clip_words(&message);
/// assert!(shown.len() < 300);
/// assert!(shown.contains("…(999843 characters left out)…"));
/// assert!(shown.ends_with("`, expected `a`"));
/// assert_eq!(woven::error::clip_words("short words"), "short words");
/// ```
pub fn clip_words(message: &str) -> std::borrow::Cow<'_, str> {
    const HEAD: usize = 120;
    const TAIL: usize = 40;
    let long = |w: &str| w.chars().nth(MAX_WORD_CHARS).is_some();
    if !message.split_whitespace().any(long) {
        return message.into();
    }
    let mut out = String::new();
    let mut rest = message;
    while !rest.is_empty() {
        let blank = rest
            .find(|c: char| !c.is_whitespace())
            .unwrap_or(rest.len());
        out.push_str(&rest[..blank]);
        rest = &rest[blank..];
        let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
        let word = &rest[..end];
        if long(word) {
            let n = word.chars().count();
            let head: String = word.chars().take(HEAD).collect();
            let tail: String = word.chars().skip(n - TAIL).collect();
            out.push_str(&format!(
                "{head}…({} characters left out)…{tail}",
                n - HEAD - TAIL
            ));
        } else {
            out.push_str(word);
        }
        rest = &rest[end..];
    }
    out.into()
}
