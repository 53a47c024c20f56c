//! The fitter's own CSV: one measurement per row, angles in radians, the BRDF in sr⁻¹.
//!
//! ```text
//! # name = linen          (optional directives, before the header)
//! # relative = true
//! theta_i,phi_i,theta_r,phi_r,value,weight
//! 0.5,0,0.5,3.14159,0.31,1
//! ```
//!
//! | column | meaning | range |
//! |---|---|---|
//! | `theta_i`, `theta_r` | polar angles of the directions toward the light and the viewer, radians | `[0, π]`; rows at or beyond `π/2` are dropped and counted |
//! | `phi_i`, `phi_r` | their azimuths from the weft (x) axis, radians | `[-4π, 4π]` |
//! | `value` | the BRDF, sr⁻¹ (f without the cosine) | finite, ≥ 0 |
//! | `value_r`, `value_g`, `value_b` | the same per channel, instead of `value` | finite, ≥ 0 |
//! | `weight` (optional) | the sample's weight in the fit (1 when absent) | finite, ≥ 0 |
//!
//! Columns may come in any order; any other column is an error (a misspelt `weight` must not be
//! ignored). Lines starting with `#` are comments; before the header, `# name = …` names the
//! dataset (default: the file's stem) and `# relative = true` marks relatively calibrated values.

use super::rows::{directives, shorten, stem, Cell, Collector, CsvTable, Num};
use super::{DataError, Dataset, Sample, Value};
use std::io::{self, Write};
use std::path::Path;

/// The header of a single-channel file (with weights).
pub const HEADER_MONO: &str = "theta_i,phi_i,theta_r,phi_r,value,weight";
/// The header of an RGB file (with weights).
pub const HEADER_RGB: &str = "theta_i,phi_i,theta_r,phi_r,value_r,value_g,value_b,weight";

const COLUMNS: [&str; 9] = [
    "theta_i", "phi_i", "theta_r", "phi_r", "value", "value_r", "value_g", "value_b", "weight",
];

const EXPECTED: &str = "the fitter CSV needs theta_i,phi_i,theta_r,phi_r and value (or \
                        value_r,value_g,value_b), optionally weight";

/// Reads the fitter CSV in `bytes` (the contents of `path`).
///
/// # Errors
/// [`DataError::Format`] for a header that lacks a column or has an unknown or repeated one;
/// [`DataError::Parse`] naming the line and the column of the first bad field.
pub fn read(path: &Path, bytes: &[u8]) -> Result<Dataset, DataError> {
    let text = String::from_utf8_lossy(bytes);
    let d = directives(path, &text)?;
    let mut table = CsvTable::new(path, bytes)?;
    for (k, h) in table.headers.iter().enumerate() {
        if !COLUMNS.contains(&h.as_str()) {
            return Err(super::rows::format_error(
                path,
                format!("unknown column `{}`; {EXPECTED}", shorten(h)),
            ));
        }
        if table.headers[..k].contains(h) {
            return Err(super::rows::format_error(
                path,
                format!("column `{h}` appears twice"),
            ));
        }
    }
    let angles = [
        table.require("theta_i", EXPECTED)?,
        table.require("phi_i", EXPECTED)?,
        table.require("theta_r", EXPECTED)?,
        table.require("phi_r", EXPECTED)?,
    ];
    let channels: Vec<usize> = match table.column("value") {
        Some(v) => {
            if let Some(c) = ["value_r", "value_g", "value_b"]
                .into_iter()
                .find(|c| table.column(c).is_some())
            {
                return Err(super::rows::format_error(
                    path,
                    format!("both `value` and `{c}`: give one value or three channels"),
                ));
            }
            vec![v]
        }
        None => vec![
            table.require("value_r", EXPECTED)?,
            table.require("value_g", EXPECTED)?,
            table.require("value_b", EXPECTED)?,
        ],
    };
    let weight = table.column("weight");
    let headers = table.headers.clone();
    let mut out = Collector::new();
    while let Some((line, record)) = table.next_record()? {
        let cell = |k: usize| Cell {
            path,
            line,
            column: &headers[k],
        };
        let field = |k: usize| record.get(k).unwrap_or("");
        let theta_i = cell(angles[0]).polar(field(angles[0]))?;
        let phi_i = cell(angles[1]).azimuth(field(angles[1]))?;
        let theta_r = cell(angles[2]).polar(field(angles[2]))?;
        let phi_r = cell(angles[3]).azimuth(field(angles[3]))?;
        let value = if channels.len() == 1 {
            Value::Mono(cell(channels[0]).value(field(channels[0]))?)
        } else {
            let mut rgb = [0.0; 3];
            for (c, &k) in channels.iter().enumerate() {
                rgb[c] = cell(k).value(field(k))?;
            }
            Value::Rgb(rgb)
        };
        let weight = match weight {
            Some(k) => cell(k).weight(field(k))?,
            None => 1.0,
        };
        out.push(Sample {
            theta_i,
            phi_i,
            theta_r,
            phi_r,
            value,
            weight,
        });
    }
    out.finish(
        path,
        d.name.unwrap_or_else(|| stem(path)),
        d.relative.unwrap_or(false),
    )
}

/// Writes `dataset` as the fitter CSV: the `# name` and `# relative` directives, then
/// [`HEADER_MONO`] or [`HEADER_RGB`] and one row per sample. Numbers are written in Rust's
/// shortest round-trip form, so [`read()`] gives back exactly the same samples.
///
/// # Errors
/// The writer's errors; [`io::ErrorKind::InvalidInput`] when the dataset mixes single-channel and
/// RGB samples.
pub fn write(dataset: &Dataset, out: &mut dyn Write) -> io::Result<()> {
    let rgb = match dataset.samples.first().map(|s| s.value) {
        Some(Value::Rgb(_)) => true,
        Some(Value::Mono(_)) | None => false,
    };
    if dataset
        .samples
        .iter()
        .any(|s| matches!(s.value, Value::Rgb(_)) != rgb)
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the dataset mixes single-channel and RGB values",
        ));
    }
    // A name on one line, so that it stays one directive.
    let name: String = dataset
        .name
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    writeln!(out, "# name = {}", name.trim())?;
    writeln!(out, "# relative = {}", dataset.relative)?;
    if dataset.dropped_below_horizon > 0 {
        writeln!(
            out,
            "# {} rows at or below the horizon were dropped when the source was read",
            dataset.dropped_below_horizon
        )?;
    }
    writeln!(out, "{}", if rgb { HEADER_RGB } else { HEADER_MONO })?;
    for s in &dataset.samples {
        let (a, b, c, d) = (s.theta_i, s.phi_i, s.theta_r, s.phi_r);
        write!(out, "{},{},{},{},", Num(a), Num(b), Num(c), Num(d))?;
        match s.value {
            Value::Mono(v) => write!(out, "{}", Num(v))?,
            Value::Rgb([r, g, b]) => write!(out, "{},{},{}", Num(r), Num(g), Num(b))?,
        }
        writeln!(out, ",{}", Num(s.weight))?;
    }
    Ok(())
}

/// Writes `dataset` to `path` as the fitter CSV ([`write()`]), atomically: a reader never sees half
/// a file, and on failure an existing `path` is untouched.
///
/// # Errors
/// [`DataError::Io`] naming `path`.
pub fn save(dataset: &Dataset, path: &Path) -> Result<(), DataError> {
    woven::fsutil::atomic_write_with(path, |_| (), |out| write(dataset, out)).map_err(|e| {
        let source = match e {
            woven::fsutil::AtomicWriteError::NotAFile => {
                io::Error::new(io::ErrorKind::InvalidInput, "not a file path")
            }
            woven::fsutil::AtomicWriteError::ReadOnly => io::Error::new(
                io::ErrorKind::PermissionDenied,
                "the file is read-only: refusing to replace it",
            ),
            woven::fsutil::AtomicWriteError::Io { source, .. }
            | woven::fsutil::AtomicWriteError::Write(source) => source,
        };
        DataError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}
