//! What every reader shares: reading a file with a size cap, CSV tables with their line numbers,
//! checked numbers (angles, values, weights), the horizon rule and the `# key = value` directives
//! at the top of a CSV file; and, for the writers, numbers as the shortest text that reads back.

use super::{DataError, Dataset, Sample, Value};
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};

/// The largest measurement file a reader accepts, bytes: far above any real one (the biggest
/// here, an RGL `.bsdf`, is 0.7 MB), small enough that a wrong path never fills memory.
pub(crate) const MAX_FILE_BYTES: u64 = 256 << 20;

/// The whole of `path`, a regular file of at most [`MAX_FILE_BYTES`] (read through
/// [`woven::fsutil::read_regular`]: a FIFO, a device or a folder is refused before it is opened,
/// so a wrong path never blocks or fills memory).
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, DataError> {
    woven::fsutil::read_regular(path, MAX_FILE_BYTES, "a measurement file").map_err(|e| match e {
        woven::Error::Io { source, .. } => DataError::Io {
            path: path.to_path_buf(),
            source,
        },
        woven::Error::Parse { message, .. } => format_error(path, message),
        other => format_error(path, other.to_string()),
    })
}

/// A [`DataError::Parse`].
pub(crate) fn parse_error(
    path: &Path,
    line: u64,
    column: impl Into<String>,
    message: impl Into<String>,
) -> DataError {
    DataError::Parse {
        path: path.to_path_buf(),
        line,
        column: column.into(),
        message: message.into(),
    }
}

/// A [`DataError::Format`].
pub(crate) fn format_error(path: &Path, message: impl Into<String>) -> DataError {
    DataError::Format {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Where a field is: the file, its line and its column's name.
#[derive(Clone, Copy)]
pub(crate) struct Cell<'a> {
    pub path: &'a Path,
    pub line: u64,
    pub column: &'a str,
}

impl Cell<'_> {
    /// An error at this cell.
    pub fn error(&self, message: impl Into<String>) -> DataError {
        parse_error(self.path, self.line, self.column, message)
    }

    /// The field as a finite number.
    pub fn number(&self, text: &str) -> Result<f64, DataError> {
        let shown = shorten(text);
        let x: f64 = text
            .trim()
            .parse()
            .map_err(|_| self.error(format!("`{shown}` is not a number")))?;
        if !x.is_finite() {
            return Err(self.error(format!("`{shown}` is not a finite number")));
        }
        Ok(x)
    }

    /// A polar angle in radians, in `[0, π]` (beyond `π/2` it is below the horizon, which the
    /// caller drops).
    pub fn polar(&self, text: &str) -> Result<f64, DataError> {
        let x = self.number(text)?;
        if !(0.0..=PI).contains(&x) {
            return Err(self.error(format!(
                "polar angle {x} outside [0, π] radians (0 = the normal, π/2 = the horizon)"
            )));
        }
        Ok(x)
    }

    /// A polar angle in degrees, in `[0, 180]`, returned in radians.
    pub fn polar_deg(&self, text: &str) -> Result<f64, DataError> {
        let x = self.number(text)?;
        if !(0.0..=180.0).contains(&x) {
            return Err(self.error(format!(
                "polar angle {x}° outside [0°, 180°] (0 = the normal, 90° = the horizon)"
            )));
        }
        Ok(x.to_radians())
    }

    /// An azimuth in radians: any finite number (it wraps), but at most a few turns, so that a
    /// value in degrees is caught.
    pub fn azimuth(&self, text: &str) -> Result<f64, DataError> {
        let x = self.number(text)?;
        if x.abs() > 4.0 * PI {
            return Err(self.error(format!(
                "azimuth {x} outside [-4π, 4π] radians (degrees by mistake?)"
            )));
        }
        Ok(x)
    }

    /// A BRDF value or radiance: finite and not negative.
    pub fn value(&self, text: &str) -> Result<f64, DataError> {
        let x = self.number(text)?;
        if x < 0.0 {
            return Err(self.error(format!(
                "{x} is negative: a BRDF is ≥ 0 (clip or drop such rows before fitting)"
            )));
        }
        Ok(x)
    }

    /// A weight: finite and not negative.
    pub fn weight(&self, text: &str) -> Result<f64, DataError> {
        let x = self.number(text)?;
        if x < 0.0 {
            return Err(self.error(format!("weight {x} is negative: expected ≥ 0")));
        }
        Ok(x)
    }
}

/// At most 40 characters of a field, for messages.
pub(crate) fn shorten(text: &str) -> String {
    let t = text.trim();
    if t.chars().count() <= 40 {
        t.to_string()
    } else {
        let head: String = t.chars().take(37).collect();
        format!("{head}...")
    }
}

/// True when both polar angles lie strictly above the horizon (`θ < π/2`): the rule every reader
/// applies before it keeps a row.
pub(crate) fn above_horizon(theta_i: f64, theta_r: f64) -> bool {
    theta_i < FRAC_PI_2 && theta_r < FRAC_PI_2
}

/// Collects samples, dropping (and counting) those at or below the horizon.
pub(crate) struct Collector {
    pub samples: Vec<Sample>,
    pub dropped_below_horizon: usize,
}

impl Collector {
    pub fn new() -> Self {
        Collector {
            samples: Vec::new(),
            dropped_below_horizon: 0,
        }
    }

    /// Keeps the sample, or counts it as dropped when a direction is at or below the horizon.
    pub fn push(&mut self, sample: Sample) {
        if above_horizon(sample.theta_i, sample.theta_r) {
            self.samples.push(sample);
        } else {
            self.dropped_below_horizon += 1;
        }
    }

    /// The dataset, or an error when no row was read at all.
    pub fn finish(self, path: &Path, name: String, relative: bool) -> Result<Dataset, DataError> {
        if self.samples.is_empty() && self.dropped_below_horizon == 0 {
            return Err(format_error(path, "no measurements (a header and no rows)"));
        }
        Ok(Dataset {
            name,
            source: path.to_path_buf(),
            samples: self.samples,
            dropped_below_horizon: self.dropped_below_horizon,
            relative,
        })
    }
}

/// A sample from its four angles (radians) and value, weight 1.
pub(crate) fn sample(theta_i: f64, phi_i: f64, theta_r: f64, phi_r: f64, value: Value) -> Sample {
    Sample {
        theta_i,
        phi_i,
        theta_r,
        phi_r,
        value,
        weight: 1.0,
    }
}

/// The polar angles of the standard grid, degrees: 0, 5, …, 80.
pub(crate) const GRID_THETA_DEG: std::ops::RangeInclusive<u32> = 0..=16;
/// The relative azimuths of the standard grid, in steps of 15°: 0, 15, …, 180.
pub(crate) const GRID_PHI_STEPS: std::ops::RangeInclusive<u32> = 0..=12;

/// `eval(wi, wo)` (RGB, sr⁻¹) on the grid of the `*.grid.csv` files: θi, θo ∈ {0, 5, …, 80}°,
/// φo − φi ∈ {0, 15, …, 180}° (θi outermost, the azimuth innermost), the light at φi = 0; an
/// absolute RGB dataset.
///
/// # Errors
/// [`DataError::Format`] when an evaluation is not finite or is negative.
pub(crate) fn on_grid(
    path: &Path,
    name: String,
    eval: impl Fn(woven::Vec3, woven::Vec3) -> [f64; 3],
) -> Result<Dataset, DataError> {
    let mut samples = Vec::with_capacity(17 * 17 * 13);
    for ti in GRID_THETA_DEG {
        for to in GRID_THETA_DEG {
            for p in GRID_PHI_STEPS {
                let theta_i = (5.0 * ti as f64).to_radians();
                let theta_r = (5.0 * to as f64).to_radians();
                let phi_r = (15.0 * p as f64).to_radians();
                let f = eval(
                    woven::Vec3::from_spherical(theta_i, 0.0),
                    woven::Vec3::from_spherical(theta_r, phi_r),
                );
                if f.iter().any(|v| !v.is_finite() || *v < 0.0) {
                    return Err(format_error(
                        path,
                        format!(
                            "the BRDF evaluates to {f:?} at θi = {}°, θo = {}°, φ = {}°: not a \
                             finite value ≥ 0",
                            5 * ti,
                            5 * to,
                            15 * p
                        ),
                    ));
                }
                samples.push(sample(theta_i, 0.0, theta_r, phi_r, Value::Rgb(f)));
            }
        }
    }
    Ok(Dataset {
        name,
        source: path.to_path_buf(),
        samples,
        dropped_below_horizon: 0,
        relative: false,
    })
}

/// The file's stem (`felt.grid.csv` → `felt.grid`), or `measurements`.
pub(crate) fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "measurements".to_string())
}

/// The settings a CSV file may give in comment lines at its top, `# key = value`.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Directives {
    /// `# name = …`: the dataset's name.
    pub name: Option<String>,
    /// `# relative = true|false`: whether the values are relatively calibrated.
    pub relative: Option<bool>,
}

/// Reads the `# key = value` lines at the top of a CSV file (before its header). Other comment
/// lines, and unknown keys, are comments.
pub(crate) fn directives(path: &Path, text: &str) -> Result<Directives, DataError> {
    let mut d = Directives::default();
    for (k, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() {
            continue;
        }
        let Some(body) = line.strip_prefix('#') else {
            break;
        };
        let Some((key, value)) = body.split_once('=') else {
            continue;
        };
        let (key, value) = (key.trim(), value.trim());
        match key {
            "name" if !value.is_empty() => d.name = Some(value.to_string()),
            "relative" => {
                d.relative = Some(match value {
                    "true" => true,
                    "false" => false,
                    _ => {
                        return Err(parse_error(
                            path,
                            k as u64 + 1,
                            "relative",
                            format!("`{}` is not true or false", shorten(value)),
                        ))
                    }
                })
            }
            _ => {}
        }
    }
    Ok(d)
}

/// A CSV file: its header and its records, each with the line it starts on.
pub(crate) struct CsvTable<'a> {
    pub path: &'a Path,
    pub headers: Vec<String>,
    bytes: &'a [u8],
    reader: csv::Reader<&'a [u8]>,
    record: csv::StringRecord,
    /// A byte offset and the line it lies on, where the next line count resumes (the `csv`
    /// crate's own line numbers skip blank lines, so lines are counted here from byte offsets).
    mark: (usize, u64),
}

impl<'a> CsvTable<'a> {
    /// Opens `bytes` (the contents of `path`) as CSV: `#` lines are comments, fields are trimmed,
    /// every row must have as many fields as the header.
    pub fn new(path: &'a Path, bytes: &'a [u8]) -> Result<Self, DataError> {
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .flexible(false)
            .from_reader(bytes);
        let headers = reader
            .headers()
            .map_err(|e| {
                let line = e.position().map(|p| {
                    let end = (p.byte() as usize).min(bytes.len());
                    1 + bytes[..end].iter().filter(|&&b| b == b'\n').count() as u64
                });
                csv_error(path, &[], e, line)
            })?
            .iter()
            .map(str::to_string)
            .collect::<Vec<_>>();
        if headers.iter().all(String::is_empty) {
            return Err(format_error(path, "empty: no CSV header"));
        }
        Ok(CsvTable {
            path,
            headers,
            bytes,
            reader,
            record: csv::StringRecord::new(),
            mark: (0, 1),
        })
    }

    /// The index of the column `name`, if the header has it.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.headers.iter().position(|h| h == name)
    }

    /// The index of the column `name`, or an error naming what the format needs.
    pub fn require(&self, name: &str, format: &str) -> Result<usize, DataError> {
        self.column(name).ok_or_else(|| {
            format_error(
                self.path,
                format!(
                    "no column `{name}` in the header ({}); {format}",
                    shorten(&self.headers.join(","))
                ),
            )
        })
    }

    /// The line (1-based) of byte offset `byte`, counted on from the last one asked for.
    fn line_at(&mut self, byte: usize) -> u64 {
        let mut byte = byte.min(self.bytes.len());
        // A record's position may be where the reader resumed: before the blank and comment
        // lines it skipped. The record starts after them.
        while let Some(&b) = self.bytes.get(byte) {
            match b {
                b'\n' | b'\r' => byte += 1,
                b'#' => {
                    byte += self.bytes[byte..]
                        .iter()
                        .position(|&b| b == b'\n')
                        .map_or(self.bytes.len() - byte, |k| k + 1)
                }
                _ => break,
            }
        }
        let (from, line) = if byte >= self.mark.0 {
            self.mark
        } else {
            (0, 1)
        };
        let line = line
            + self.bytes[from..byte]
                .iter()
                .filter(|&&b| b == b'\n')
                .count() as u64;
        self.mark = (byte, line);
        line
    }

    /// The next record and its line, `None` at the end.
    pub fn next_record(&mut self) -> Result<Option<(u64, &csv::StringRecord)>, DataError> {
        match self.reader.read_record(&mut self.record) {
            Ok(false) => Ok(None),
            Ok(true) => {
                let byte = self.record.position().map_or(0, |p| p.byte() as usize);
                let line = self.line_at(byte);
                Ok(Some((line, &self.record)))
            }
            Err(e) => {
                let line = e.position().map(|p| self.line_at(p.byte() as usize));
                Err(csv_error(self.path, &self.headers, e, line))
            }
        }
    }
}

/// A [`DataError`] from the `csv` crate's error, with the line and the column where it knows them.
fn csv_error(path: &Path, headers: &[String], e: csv::Error, line: Option<u64>) -> DataError {
    let line = line.unwrap_or(0);
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => {
            let column = if *len > *expected_len {
                format!("field {}", expected_len + 1)
            } else {
                headers
                    .get(*len as usize)
                    .cloned()
                    .unwrap_or_else(|| format!("field {}", len + 1))
            };
            parse_error(
                path,
                line,
                column,
                format!("{len} fields where the header has {expected_len}"),
            )
        }
        csv::ErrorKind::Utf8 { err, .. } => {
            let column = headers
                .get(err.field())
                .cloned()
                .unwrap_or_else(|| format!("field {}", err.field() + 1));
            parse_error(path, line, column, "not valid UTF-8 text")
        }
        csv::ErrorKind::Io(io) => DataError::Io {
            path: PathBuf::from(path),
            source: std::io::Error::new(io.kind(), io.to_string()),
        },
        _ => format_error(path, format!("not CSV: {e}")),
    }
}

/// A number in the shortest text that reads back as the same `f64`: plain for magnitudes in
/// `[1e-5, 1e16)` and 0, scientific otherwise (Rust's `{}` never switches to an exponent and
/// would spell 1e-300 with 300 zeros).
pub(crate) struct Num(pub(crate) f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}
