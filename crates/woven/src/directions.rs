//! The direction-pair CSV that `woven eval` reads: a header `theta_i,phi_i,theta_r,phi_r`, then
//! one pair of directions a row, angles in radians.
//!
//! | column | meaning | unit | valid range |
//! |---|---|---|---|
//! | `theta_i` | polar angle of the direction toward the light | rad | `[0, π/2]` |
//! | `phi_i` | its azimuth | rad | any finite number |
//! | `theta_r` | polar angle of the direction toward the viewer | rad | `[0, π]` |
//! | `phi_r` | its azimuth | rad | any finite number |
//!
//! Both directions point away from the surface, in the cloth's local frame (`z` = macro normal).
//! A `theta_r` above `π/2` is a direction below the cloth: light transmitted through it (0 for
//! an opaque cloth).
//! Lines end in `\n` or `\r\n`; fields are separated by commas and may be surrounded by spaces
//! or enclosed in double quotes (`"0.5"`); blank lines are skipped; a UTF-8 byte-order mark before
//! the header is ignored.
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
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt;
use std::io::{self, BufRead, BufReader, Read};
use std::ops::Range;

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
pub struct DirectionRecord {
    /// 1-based line number.
    line: u64,
    /// The line's bytes, without its end.
    text: Vec<u8>,
    /// Each field's bytes in `text`: trimmed, quotes removed.
    fields: Vec<Range<usize>>,
}

impl DirectionRecord {
    /// An empty record, to be filled by [`DirectionReader::read_record`].
    pub fn new() -> Self {
        Self::default()
    }

    /// The fields exactly as read (surrounding spaces and quotes removed).
    pub fn fields(&self) -> impl Iterator<Item = &[u8]> {
        self.fields.iter().map(|r| &self.text[r.clone()])
    }

    /// The bytes of the line.
    pub fn byte_len(&self) -> usize {
        self.text.len()
    }

    /// The 1-based line of the record.
    pub fn line(&self) -> u64 {
        self.line
    }

    /// Splits `text` into fields.
    fn split(&mut self) {
        self.fields.clear();
        let mut start = 0;
        loop {
            let end = self.text[start..]
                .iter()
                .position(|&b| b == b',')
                .map_or(self.text.len(), |i| start + i);
            let mut field = start..end;
            // Surrounding spaces and tabs, then one pair of enclosing quotes.
            while field.start < field.end && matches!(self.text[field.start], b' ' | b'\t') {
                field.start += 1;
            }
            while field.end > field.start && matches!(self.text[field.end - 1], b' ' | b'\t') {
                field.end -= 1;
            }
            if field.len() >= 2
                && self.text[field.start] == b'"'
                && self.text[field.end - 1] == b'"'
            {
                field = field.start + 1..field.end - 1;
            }
            self.fields.push(field);
            if end == self.text.len() {
                break;
            }
            start = end + 1;
        }
    }

    /// The four angles `[theta_i, phi_i, theta_r, phi_r]`, in radians.
    ///
    /// # Errors
    /// A [`RowError`] naming the line (and the column, where one is to blame) for a wrong number
    /// of columns, text that is not a number, a non-finite number, a `theta_i` outside `[0, π/2]`
    /// or a `theta_r` outside `[0, π]`.
    pub fn angles(&self) -> Result<[f64; 4], RowError> {
        let line = self.line;
        let error = |column: Option<usize>, message: String| RowError {
            line,
            column,
            message,
        };
        let n = self.fields.len();
        if n != COLUMNS.len() {
            let message = if n < COLUMNS.len() {
                format!(
                    "expected 4 columns ({}), found {n}: column `{}` is missing",
                    COLUMNS.join(","),
                    COLUMNS[n]
                )
            } else {
                format!(
                    "expected 4 columns ({}), found {n}: extra column {}",
                    COLUMNS.join(","),
                    COLUMNS.len() + 1
                )
            };
            return Err(error(None, message));
        }
        let mut angles = [0.0; 4];
        for (c, field) in self.fields().enumerate() {
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
                .map_err(|_| error(Some(c), format!("`{}` is not a number", abbreviate(text))))?;
            if !x.is_finite() {
                return Err(error(
                    Some(c),
                    format!("`{text}` is not a finite number of radians"),
                ));
            }
            // Polar angles: the light above the surface, the viewer on either side of it.
            let (top, top_name) = if c == 2 {
                (PI, "π")
            } else {
                (FRAC_PI_2, "π/2")
            };
            if (c == 0 || c == 2) && !(0.0..=top).contains(&x) {
                return Err(error(
                    Some(c),
                    format!(
                        "value {text} is outside the valid range [0, {top_name}] = [0, {top}] \
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
    input: BufReader<R>,
    /// Lines read so far.
    line: u64,
    origin: String,
}

impl<R: Read> fmt::Debug for DirectionReader<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("DirectionReader")
            .field("origin", &self.origin)
            .field("line", &self.line)
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
        let mut reader = DirectionReader {
            input: BufReader::with_capacity(1 << 16, input),
            line: 0,
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
                header.line(),
                COLUMNS.join(","),
                // What the file holds is only echoed when it is short text.
                abbreviate(&fields.join(","))
            )));
        }
        Ok(reader)
    }

    /// Reads the next non-blank line into `record` (reusing its buffers); `false` at the end.
    ///
    /// # Errors
    /// [`Error::Parse`] naming the input and the line for a line longer than
    /// [`MAX_LINE_BYTES`]; [`Error::Io`] if reading fails.
    pub fn read_record(&mut self, record: &mut DirectionRecord) -> Result<bool> {
        loop {
            record.text.clear();
            if !self.read_line(&mut record.text)? {
                return Ok(false);
            }
            if record.text.last() == Some(&b'\r') {
                record.text.pop();
            }
            if record.text.iter().all(|b| b.is_ascii_whitespace()) {
                continue;
            }
            record.line = self.line;
            record.split();
            return Ok(true);
        }
    }

    /// Appends the next line, without its `\n`, to `text`; `false` at the end of the input.
    /// Never holds more than [`MAX_LINE_BYTES`] of one line.
    fn read_line(&mut self, text: &mut Vec<u8>) -> Result<bool> {
        let mut any = false;
        loop {
            let buf = match self.input.fill_buf() {
                Ok(buf) => buf,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => {
                    return Err(Error::Io {
                        path: self.origin.clone().into(),
                        source: e,
                    })
                }
            };
            if buf.is_empty() {
                if any {
                    self.line += 1;
                }
                return Ok(any);
            }
            any = true;
            let (take, done) = match buf.iter().position(|&b| b == b'\n') {
                Some(i) => (i, true),
                None => (buf.len(), false),
            };
            if text.len() + take > MAX_LINE_BYTES {
                return Err(self.parse_error(format!(
                    "line {} is longer than {MAX_LINE_BYTES} bytes: not a direction CSV",
                    self.line + 1
                )));
            }
            text.extend_from_slice(&buf[..take]);
            self.input.consume(take + usize::from(done));
            if done {
                self.line += 1;
                return Ok(true);
            }
        }
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
    fn fields_are_trimmed_unquoted_and_blank_lines_skipped() {
        let r = rows(b"\xef\xbb\xbftheta_i, phi_i ,theta_r,\"phi_r\"\r\n\n \"0.5\" ,\t1,0.25,-3\r\n\n\n1,2,1,2")
            .unwrap();
        assert_eq!(r[0], Ok([0.5, 1.0, 0.25, -3.0]));
        assert_eq!(r[1], Ok([1.0, 2.0, 1.0, 2.0]));
        let r = rows(b"theta_i,phi_i,theta_r,phi_r\n\n0,0,0\n0,0,0,0,\n").unwrap();
        assert_eq!(r[0].as_ref().unwrap_err().line, 3);
        assert!(r[0]
            .as_ref()
            .unwrap_err()
            .to_string()
            .contains("`phi_r` is missing"));
        assert!(r[1]
            .as_ref()
            .unwrap_err()
            .to_string()
            .contains("extra column 5"));
    }

    #[test]
    fn a_wrong_header_is_abbreviated() {
        let long = format!("{}\n", "x".repeat(1000));
        let e = rows(long.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("expected the header") && e.len() < 300, "{e}");
    }
}
