//! Measured data laid over the model: the fitter's CSV (`theta_i,phi_i,theta_r,phi_r,value`,
//! radians, BRDF in sr⁻¹) and the model's values at the same directions, with the error.
//!
//! The reader here is a small stand-in: `woven_fit::data` is the project's home for measurement
//! readers. [`parse_csv`] is the one seam — replace its body with a call to the fitter's reader
//! (and map its error to [`ApiError`]) and the rest of the explorer follows.

use crate::error::{ApiError, ApiResult};
use serde::Serialize;
use std::f64::consts::FRAC_PI_2;

/// The header the CSV must start with.
pub const HEADER: [&str; 5] = ["theta_i", "phi_i", "theta_r", "phi_r", "value"];
/// The most rows read: enough for a goniometer's worth of data, bounded because a twisted or
/// isotropic yarn costs milliseconds per evaluation.
pub const MAX_ROWS: usize = 20_000;

/// One measurement.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Polar angle toward the light, radians.
    pub theta_i: f64,
    /// Azimuth toward the light, radians from the weft (x).
    pub phi_i: f64,
    /// Polar angle toward the viewer, radians.
    pub theta_r: f64,
    /// Azimuth toward the viewer, radians from the weft (x).
    pub phi_r: f64,
    /// The measured BRDF, sr⁻¹.
    pub value: f64,
}

/// Reads the fitter's CSV. Blank lines and lines starting with `#` are skipped.
///
/// # Errors
/// [`ApiError::Malformed`] (422) naming the line and column: a wrong header, a row without five
/// numbers, a polar angle outside `[0, π/2]`, a negative or non-finite value, more than
/// [`MAX_ROWS`] rows, or no rows at all.
pub fn parse_csv(text: &str, origin: &str) -> ApiResult<Vec<Sample>> {
    let bad = |line: usize, message: String| {
        ApiError::unprocessable(format!("{origin}:{line}: {message}"))
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let Some((n, header)) = lines.next() else {
        return Err(ApiError::unprocessable(format!(
            "{origin}: empty: expected the header {}",
            HEADER.join(",")
        )));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    if names != HEADER {
        return Err(bad(
            n,
            format!("header `{header}`: expected `{}`", HEADER.join(",")),
        ));
    }
    let mut samples = Vec::new();
    for (n, line) in lines {
        if samples.len() == MAX_ROWS {
            return Err(bad(n, format!("more than {MAX_ROWS} rows")));
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 5 {
            return Err(bad(n, format!("{} fields: expected 5", fields.len())));
        }
        let mut x = [0.0; 5];
        for (k, f) in fields.iter().enumerate() {
            x[k] = f
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    bad(
                        n,
                        format!("{} = `{f}`: expected a finite number", HEADER[k]),
                    )
                })?;
        }
        for k in [0, 2] {
            if !(0.0..=FRAC_PI_2).contains(&x[k]) {
                return Err(bad(
                    n,
                    format!("{} = {}: expected radians in [0, π/2]", HEADER[k], x[k]),
                ));
            }
        }
        if x[4] < 0.0 {
            return Err(bad(n, format!("value = {}: expected ≥ 0 (sr⁻¹)", x[4])));
        }
        samples.push(Sample {
            theta_i: x[0],
            phi_i: x[1],
            theta_r: x[2],
            phi_r: x[3],
            value: x[4],
        });
    }
    if samples.is_empty() {
        return Err(ApiError::unprocessable(format!("{origin}: no data rows")));
    }
    Ok(samples)
}

/// How far the model is from the data.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ErrorSummary {
    /// `sqrt(mean((model − measured)²)) / mean(measured)`: the RMS error relative to the
    /// data's mean.
    pub relative_rms: f64,
    /// `sqrt(mean(ln²(model / measured)))` over rows where both are positive: the typical
    /// factor between them, as a logarithm.
    pub log_rms: f64,
    /// Rows compared.
    pub rows: usize,
}

/// The error of `model` against `measured` (same order and length).
pub fn summarize(measured: &[f64], model: &[f64]) -> ErrorSummary {
    assert_eq!(measured.len(), model.len());
    let n = measured.len().max(1) as f64;
    let mse = measured
        .iter()
        .zip(model)
        .map(|(d, m)| (m - d) * (m - d))
        .sum::<f64>()
        / n;
    let mean = measured.iter().sum::<f64>() / n;
    let logs: Vec<f64> = measured
        .iter()
        .zip(model)
        .filter(|(d, m)| **d > 0.0 && **m > 0.0)
        .map(|(d, m)| (m / d).ln())
        .collect();
    let log_rms = if logs.is_empty() {
        f64::NAN
    } else {
        (logs.iter().map(|l| l * l).sum::<f64>() / logs.len() as f64).sqrt()
    };
    ErrorSummary {
        relative_rms: if mean > 0.0 {
            mse.sqrt() / mean
        } else {
            f64::NAN
        },
        log_rms,
        rows: measured.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_rows_and_refuses_bad_ones_by_line() {
        let ok = "theta_i,phi_i,theta_r,phi_r,value\n# a comment\n0.5,0,0.5,3.14159,0.8\n\n0.1, 1, 0.2, 2, 0\n";
        let s = parse_csv(ok, "m.csv").unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(s[1].phi_i, 1.0);
        for (text, needle) in [
            ("", "empty"),
            ("a,b\n1,2\n", "m.csv:1: header"),
            ("theta_i,phi_i,theta_r,phi_r,value\n", "no data rows"),
            (
                "theta_i,phi_i,theta_r,phi_r,value\n1,2,3\n",
                "m.csv:2: 3 fields",
            ),
            (
                "theta_i,phi_i,theta_r,phi_r,value\n0.1,0,x,0,1\n",
                "theta_r = `x`",
            ),
            (
                "theta_i,phi_i,theta_r,phi_r,value\n2.0,0,0.1,0,1\n",
                "theta_i = 2",
            ),
            (
                "theta_i,phi_i,theta_r,phi_r,value\n0.1,0,0.1,0,-1\n",
                "value = -1",
            ),
            (
                "theta_i,phi_i,theta_r,phi_r,value\n0.1,0,0.1,0,inf\n",
                "finite",
            ),
        ] {
            let e = parse_csv(text, "m.csv").unwrap_err().to_string();
            assert!(e.contains(needle), "{text:?}: {e}");
        }
    }

    #[test]
    fn errors_are_zero_for_a_perfect_model_and_scale_with_a_factor() {
        let d = [1.0, 2.0, 3.0];
        let e = summarize(&d, &d);
        assert_eq!((e.relative_rms, e.log_rms, e.rows), (0.0, 0.0, 3));
        let m: Vec<f64> = d.iter().map(|x| 2.0 * x).collect();
        let e = summarize(&d, &m);
        assert!((e.log_rms - 2f64.ln()).abs() < 1e-12);
        // RMS of (x) over mean 2: sqrt(14/3)/2.
        assert!((e.relative_rms - (14.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-12);
    }
}
