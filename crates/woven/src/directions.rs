//! The direction-pair CSV that `woven eval` reads: a header `theta_i,phi_i,theta_r,phi_r`, then
//! one pair of directions a row, angles in radians.
//!
//! | column | meaning | unit | valid range |
//! |---|---|---|---|
//! | `theta_i` | polar angle of the direction toward the light | rad | `[0, π/2]` |
//! | `phi_i` | its azimuth | rad | any finite number |
//! | `theta_r` | polar angle of the direction toward the viewer | rad | `[0, π/2]` |
//! | `phi_r` | its azimuth | rad | any finite number |
//!
//! Both directions point away from the surface, in the cloth's local frame (`z` = macro normal).
//! Fields may be surrounded by spaces; a UTF-8 byte-order mark before the header is ignored.
//!
//! The input is a stream: [`DirectionReader`] reads one record at a time, so memory stays flat for
//! any number of rows, and no line may exceed [`MAX_LINE_BYTES`] (an endless line — `/dev/zero`,
//! a binary file — is refused instead of filling memory).
//!
//! # Examples
//! ```
//! use woven::directions::{DirectionReader, DirectionRecord};
//! let csv = "theta_i,phi_i,theta_r,phi_r\n0.5,0,0.5,3.14\n";
//! let mut reader = DirectionReader::new(csv.as_bytes(), "<doc>")?;
//! let mut record = DirectionRecord::new();
//! assert!(reader.read_record(&mut record)?);
//! assert_eq!(record.angles().unwrap(), [0.5, 0.0, 0.5, 3.14]);
//! assert!(!reader.read_record(&mut record)?);
//! # Ok::<(), woven::Error>(())
//! ```

use crate::error::{Error, Result};
use std::f64::consts::FRAC_PI_2;
use std::fmt;
use std::io::{self, Read};

/// The input columns, in order.
pub const COLUMNS: [&str; 4] = ["theta_i", "phi_i", "theta_r", "phi_r"];

/// The longest accepted line, in bytes (four angles need well under 100).
pub const MAX_LINE_BYTES: usize = 4096;

/// What is wrong with one data row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RowError {
    /// 1-based line number in the input.
    pub line: u64,
    /// 0-based column index, where one column is to blame.
    pub column: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for RowError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.column {
            Some(c) => write!(
                f,
                "line {}, column {} `{}`: {}",
                self.line,
                c + 1,
                COLUMNS[c],
                self.message
            ),
            None => write!(f, "line {}: {}", self.line, self.message),
        }
    }
}

impl std::error::Error for RowError {}

/// One data row as read: its fields' text, unparsed (see [`DirectionRecord::angles`]).
#[derive(Clone, Debug, Default)]
pub struct DirectionRecord(csv::ByteRecord);

impl DirectionRecord {
    /// An empty record, to be filled by [`DirectionReader::read_record`].
    pub fn new() -> Self {
        Self::default()
    }

    /// The fields exactly as read (surrounding spaces trimmed).
    pub fn fields(&self) -> impl Iterator<Item = &[u8]> {
        self.0.iter()
    }

    /// The 1-based line the record starts on.
    pub fn line(&self) -> u64 {
        self.0.position().map_or(0, |p| p.line())
    }

    /// The four angles `[theta_i, phi_i, theta_r, phi_r]`, in radians.
    ///
    /// # Errors
    /// A [`RowError`] naming the line (and the column, where one is to blame) for a wrong number
    /// of columns, text that is not a number, a non-finite number, or a polar angle outside
    /// `[0, π/2]`.
    pub fn angles(&self) -> Result<[f64; 4], RowError> {
        let line = self.line();
        let error = |column: Option<usize>, message: String| RowError {
            line,
            column,
            message,
        };
        let record = &self.0;
        if record.len() != COLUMNS.len() {
            let message = if record.len() < COLUMNS.len() {
                format!(
                    "expected 4 columns ({}), found {}: column `{}` is missing",
                    COLUMNS.join(","),
                    record.len(),
                    COLUMNS[record.len()]
                )
            } else {
                format!(
                    "expected 4 columns ({}), found {}: extra column {}",
                    COLUMNS.join(","),
                    record.len(),
                    COLUMNS.len() + 1
                )
            };
            return Err(error(None, message));
        }
        let mut angles = [0.0; 4];
        for (c, field) in record.iter().enumerate() {
            let text = std::str::from_utf8(field)
                .map_err(|_| error(Some(c), "not valid UTF-8 text".into()))?;
            if text.is_empty() {
                return Err(error(
                    Some(c),
                    "empty value: expected a number of radians".into(),
                ));
            }
            let x: f64 = text
                .parse()
                .map_err(|_| error(Some(c), format!("`{text}` is not a number")))?;
            if !x.is_finite() {
                return Err(error(
                    Some(c),
                    format!("`{text}` is not a finite number of radians"),
                ));
            }
            // Polar angles: the hemisphere above the surface.
            if (c == 0 || c == 2) && !(0.0..=FRAC_PI_2).contains(&x) {
                return Err(error(
                    Some(c),
                    format!(
                        "value {text} is outside the valid range [0, π/2] = [0, {FRAC_PI_2}] \
                         radians"
                    ),
                ));
            }
            angles[c] = x;
        }
        Ok(angles)
    }
}

/// A streaming reader of the direction CSV: checks the header on creation, then hands out one
/// record at a time.
pub struct DirectionReader<R: Read> {
    csv: csv::Reader<LineLimit<R>>,
    origin: String,
}

impl<R: Read> fmt::Debug for DirectionReader<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("DirectionReader")
            .field("origin", &self.origin)
            .finish_non_exhaustive()
    }
}

impl<R: Read> DirectionReader<R> {
    /// Reads and checks the header of `input`; `origin` names the input in errors.
    ///
    /// # Errors
    /// [`Error::Parse`] naming `origin` for an empty input, a header other than
    /// `theta_i,phi_i,theta_r,phi_r`, or a line longer than [`MAX_LINE_BYTES`]; [`Error::Io`] if
    /// reading fails.
    pub fn new(input: R, origin: &str) -> Result<Self> {
        let csv = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(LineLimit {
                inner: input,
                line: 1,
                column: 0,
            });
        let mut reader = DirectionReader {
            csv,
            origin: origin.to_string(),
        };
        let mut header = DirectionRecord::new();
        if !reader.read_record(&mut header)? {
            return Err(reader.parse_error(format!(
                "the input is empty: expected the header `{}`",
                COLUMNS.join(",")
            )));
        }
        let fields: Vec<String> = header
            .fields()
            .enumerate()
            .map(|(i, f)| {
                let s = String::from_utf8_lossy(f);
                // A UTF-8 byte-order mark from spreadsheet exports is not part of the name.
                let s = if i == 0 {
                    s.trim_start_matches('\u{feff}')
                } else {
                    &s
                };
                s.to_string()
            })
            .collect();
        if fields != COLUMNS {
            return Err(reader.parse_error(format!(
                "line {}: expected the header `{}`, found `{}`",
                header.line().max(1),
                COLUMNS.join(","),
                // What the file holds is only echoed when it is short text.
                abbreviate(&fields.join(","))
            )));
        }
        Ok(reader)
    }

    /// Reads the next data row into `record` (reusing its buffers); `false` at the end.
    ///
    /// # Errors
    /// [`Error::Parse`] naming the input and the line for a line longer than [`MAX_LINE_BYTES`]
    /// or malformed CSV; [`Error::Io`] if reading fails.
    pub fn read_record(&mut self, record: &mut DirectionRecord) -> Result<bool> {
        let line = self.csv.position().line();
        self.csv.read_byte_record(&mut record.0).map_err(|e| {
            let message = match e.into_kind() {
                csv::ErrorKind::Io(e) if e.kind() == io::ErrorKind::InvalidData => e.to_string(),
                csv::ErrorKind::Io(e) => {
                    return Error::Io {
                        path: self.origin.clone().into(),
                        source: e,
                    }
                }
                other => format!("line {line}: malformed CSV: {other:?}"),
            };
            self.parse_error(message)
        })
    }

    fn parse_error(&self, message: String) -> Error {
        Error::Parse {
            path: self.origin.clone(),
            message,
        }
    }
}

/// At most 60 characters of `s`, marked with `…` where cut.
fn abbreviate(s: &str) -> String {
    match s.char_indices().nth(60) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// A reader that fails with [`io::ErrorKind::InvalidData`] once a line exceeds
/// [`MAX_LINE_BYTES`], so that an endless line cannot fill memory.
struct LineLimit<R> {
    inner: R,
    /// 1-based line of the next byte.
    line: u64,
    /// Bytes of the current line so far.
    column: usize,
}

impl<R: Read> Read for LineLimit<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        for &b in &buf[..n] {
            if b == b'\n' {
                self.line += 1;
                self.column = 0;
            } else {
                self.column += 1;
                if self.column > MAX_LINE_BYTES {
                    return Err(io::Error::new(
                        io::ErrorKind::InvalidData,
                        format!(
                            "line {} is longer than {MAX_LINE_BYTES} bytes: not a direction CSV",
                            self.line
                        ),
                    ));
                }
            }
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(text: &[u8]) -> Result<Vec<Result<[f64; 4], RowError>>> {
        let mut reader = DirectionReader::new(text, "<test>")?;
        let mut record = DirectionRecord::new();
        let mut out = Vec::new();
        while reader.read_record(&mut record)? {
            out.push(record.angles());
        }
        Ok(out)
    }

    #[test]
    fn an_endless_line_is_refused_in_bounded_memory() {
        // /dev/zero as an input: zero bytes, never a newline.
        let zeros = io::repeat(0).take(1 << 30);
        let e = DirectionReader::new(zeros, "/dev/zero")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/dev/zero") && e.contains("longer than 4096 bytes"),
            "{e}"
        );
        let mut text = b"theta_i,phi_i,theta_r,phi_r\n0,0,0,0\n".to_vec();
        text.extend(std::iter::repeat_n(b'1', 5000));
        let e = rows(&text).unwrap_err().to_string();
        assert!(e.contains("line 3 is longer"), "{e}");
    }

    #[test]
    fn non_finite_values_name_line_and_column() {
        let r = rows(b"theta_i,phi_i,theta_r,phi_r\n0.1,0,0.1,0\n0.1,NaN,0.1,0\n0.1,0,inf,0\n")
            .unwrap();
        assert!(r[0].is_ok());
        let e = r[1].as_ref().unwrap_err().to_string();
        assert!(e.starts_with("line 3, column 2 `phi_i`"), "{e}");
        let e = r[2].as_ref().unwrap_err().to_string();
        assert!(e.starts_with("line 4, column 3 `theta_r`"), "{e}");
        assert!(e.contains("not a finite number"), "{e}");
    }

    #[test]
    fn a_wrong_header_is_abbreviated() {
        let long = format!("{}\n", "x".repeat(1000));
        let e = rows(long.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("expected the header") && e.len() < 300, "{e}");
    }
}
