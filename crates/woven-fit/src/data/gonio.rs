//! The goniometer CSV that `woven gonio` writes ([`write()`]; the readings of `woven::gonio`;
//! docs/spec.md §4).
//!
//! Header `azimuth_deg,tilt_deg,theta_i,theta_r,radiance`. Light and sensor lie in one vertical
//! plane through the normal: the light at `θi`, azimuth `φi = A` (the sample azimuth), the sensor
//! at `θr`, azimuth `φr = A + 180°`. `theta_i` and `theta_r` are radians; `radiance` is
//! `f(s, v) · cos θi` for unit irradiance, sr⁻¹.
//!
//! **Conversion.** The reader divides by `cos θi`, so each sample holds the BRDF `f = L / cos θi`
//! in sr⁻¹, exactly what `woven eval` computes at those directions. `woven gonio` reports for unit
//! irradiance, so its files are absolutely calibrated (`relative = false`). Readings of a real
//! instrument in arbitrary units (an unknown irradiance or sensor gain) are relative: put
//! `# relative = true` above the header (the directive of the fitter CSV) and the fitter frees
//! an overall scale. Rows with `|t| ≥ 45°` put the light or the sensor on or below the horizon
//! and are dropped and counted.

use super::rows::{directives, stem, Cell, Collector, CsvTable, Num};
use super::{DataError, Dataset, Value};
use std::io::{self, Write};
use std::path::Path;
use woven::gonio::Reading;

/// The header `woven gonio` writes.
pub const HEADER: &str = "azimuth_deg,tilt_deg,theta_i,theta_r,radiance";

const EXPECTED: &str = "the goniometer CSV has azimuth_deg,tilt_deg,theta_i,theta_r,radiance";

/// Reads a goniometer CSV in `bytes` (the contents of `path`), converting radiance to BRDF.
///
/// # Errors
/// [`DataError::Format`] for a missing column, [`DataError::Parse`] naming the line and column of
/// the first bad field.
pub fn read(path: &Path, bytes: &[u8]) -> Result<Dataset, DataError> {
    let text = String::from_utf8_lossy(bytes);
    let d = directives(path, &text)?;
    let mut table = CsvTable::new(path, bytes)?;
    let cols = [
        table.require("azimuth_deg", EXPECTED)?,
        table.require("tilt_deg", EXPECTED)?,
        table.require("theta_i", EXPECTED)?,
        table.require("theta_r", EXPECTED)?,
        table.require("radiance", EXPECTED)?,
    ];
    let headers = table.headers.clone();
    let mut out = Collector::new();
    while let Some((line, record)) = table.next_record()? {
        let cell = |k: usize| Cell {
            path,
            line,
            column: &headers[cols[k]],
        };
        let field = |k: usize| record.get(cols[k]).unwrap_or("");
        let azimuth_deg = cell(0).number(field(0))?;
        if azimuth_deg.abs() > 720.0 {
            return Err(cell(0).error(format!("azimuth {azimuth_deg}° outside [-720°, 720°]")));
        }
        // The tilt is implied by the polar angles; it is checked only for being a number.
        cell(1).number(field(1))?;
        let theta_i = cell(2).polar(field(2))?;
        let theta_r = cell(3).polar(field(3))?;
        let radiance = cell(4).value(field(4))?;
        let phi_i = azimuth_deg.to_radians();
        // Below the horizon cos θi ≤ 0: the row is dropped by the collector, and the division
        // (which would give a negative or infinite value) is not made.
        let value = if theta_i < std::f64::consts::FRAC_PI_2 {
            radiance / theta_i.cos()
        } else {
            0.0
        };
        out.push(super::rows::sample(
            theta_i,
            phi_i,
            theta_r,
            phi_i + std::f64::consts::PI,
            Value::Mono(value),
        ));
    }
    out.finish(
        path,
        d.name.unwrap_or_else(|| stem(path)),
        d.relative.unwrap_or(false),
    )
}

/// Writes `readings` as the goniometer CSV: [`HEADER`], then one row per reading, numbers in
/// Rust's shortest round-trip form (what `woven gonio` prints; [`read()`] reads it back).
///
/// # Errors
/// The writer's.
pub fn write(readings: &[Reading], out: &mut dyn Write) -> io::Result<()> {
    writeln!(out, "{HEADER}")?;
    for r in readings {
        writeln!(
            out,
            "{},{},{},{},{}",
            Num(r.azimuth_deg),
            Num(r.tilt_deg),
            Num(r.theta_i),
            Num(r.theta_r),
            Num(r.radiance)
        )?;
    }
    Ok(())
}
