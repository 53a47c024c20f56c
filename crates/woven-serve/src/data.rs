//! Measured data laid over the model: the fitter's CSV (`theta_i,phi_i,theta_r,phi_r,value`,
//! radians, BRDF in sr⁻¹) and the model's values at the same directions, with the error.
//!
//! The CSV is read by the fitter's reader (`woven_fit::data::fitcsv`), the project's one home
//! for measurement files.

use crate::error::{ApiError, ApiResult};
use serde::Serialize;
use std::path::Path;
use woven_fit::data::{Dataset, Value};

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

/// Reads the fitter's CSV with the fitter's own reader ([`woven_fit::data::fitcsv`]: the
/// header `theta_i,phi_i,theta_r,phi_r,value` or `value_r,value_g,value_b`, an optional
/// `weight`; blank and `#` lines skipped; rows at or below the horizon dropped).
///
/// # Errors
/// [`ApiError::Malformed`] (422) with the reader's message (it names the line and the column),
/// more than [`MAX_ROWS`] rows, or no rows at all.
pub fn read_csv(text: &str, origin: &str) -> ApiResult<Dataset> {
    let dataset = woven_fit::data::fitcsv::read(Path::new(origin), text.as_bytes())
        .map_err(|e| ApiError::unprocessable(e.to_string()))?;
    if dataset.samples.len() > MAX_ROWS {
        return Err(ApiError::unprocessable(format!(
            "{origin}: {} rows: at most {MAX_ROWS}",
            dataset.samples.len()
        )));
    }
    if dataset.samples.is_empty() {
        return Err(ApiError::unprocessable(format!("{origin}: no data rows")));
    }
    Ok(dataset)
}

/// The measurements a request names: its CSV text (`csv`, shown as `name`) or a bundled
/// dataset (`dataset`), exactly one of them.
///
/// # Errors
/// [`ApiError::Malformed`] (422): neither or both given, or as [`read_csv`] and
/// [`load_bundled`].
pub fn source(csv: Option<&str>, name: Option<&str>, dataset: Option<&str>) -> ApiResult<Dataset> {
    match (csv, dataset) {
        (Some(csv), None) => read_csv(csv, name.unwrap_or("<upload>.csv")),
        (None, Some(dataset)) => load_bundled(dataset),
        _ => Err(ApiError::unprocessable(
            "give either `csv` (the fitter's CSV) or `dataset` (a bundled dataset's name)",
        )),
    }
}

/// One channel: a colour dataset's rows as the mean of their channels (the page compares and
/// fits one value per direction).
pub fn mono(mut dataset: Dataset) -> Dataset {
    for m in &mut dataset.samples {
        if let Value::Rgb(c) = m.value {
            m.value = Value::Mono((c[0] + c[1] + c[2]) / 3.0);
        }
    }
    dataset
}

/// The real measurements bundled in the repository's `data/` (`woven_fit::data::bundled`) that
/// the page offers: name, family, rows, whether relatively calibrated. Those of more than
/// [`MAX_ROWS`] rows are left out.
pub fn bundled() -> Vec<woven_fit::data::Bundled> {
    woven_fit::data::bundled()
        .into_iter()
        .filter(|b| b.samples <= MAX_ROWS)
        .collect()
}

/// The bundled dataset `name` (one of [`bundled`]), read from `data/`.
///
/// # Errors
/// [`ApiError::Malformed`] (422) for a name not in the list (no path is ever taken from the
/// request), or when `data/` is not where the binary was built from.
pub fn load_bundled(name: &str) -> ApiResult<Dataset> {
    let Some(b) = bundled().into_iter().find(|b| b.name == name) else {
        return Err(ApiError::unprocessable(format!(
            "dataset = `{name}`: not a bundled dataset (GET /api/datasets lists them)"
        )));
    };
    b.load().map_err(|e| {
        ApiError::unprocessable(format!(
            "dataset `{name}` could not be read from {} ({e}): the bundled data lives in the \
             repository the binary was built from",
            woven_fit::data::data_dir().display()
        ))
    })
}

/// The explorer's rows of a dataset; a colour row as the mean of its channels.
pub fn samples_of(dataset: &woven_fit::data::Dataset) -> Vec<Sample> {
    dataset
        .samples
        .iter()
        .map(|m| Sample {
            theta_i: m.theta_i,
            phi_i: m.phi_i,
            theta_r: m.theta_r,
            phi_r: m.phi_r,
            value: match m.value {
                Value::Mono(v) => v,
                Value::Rgb(c) => (c[0] + c[1] + c[2]) / 3.0,
            },
        })
        .collect()
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
        let s = samples_of(&read_csv(ok, "m.csv").unwrap());
        assert_eq!(s.len(), 2);
        assert_eq!(s[1].phi_i, 1.0);
        // The fitter's reader words the errors (its own tests pin them); here: they come
        // through naming the file, and the line where there is one.
        for (text, needle) in [
            ("", "m.csv"),
            ("a,b\n1,2\n", "unknown column `a`"),
            ("theta_i,phi_i,theta_r,phi_r,value\n", "no measurements"),
            ("theta_i,phi_i,theta_r,phi_r,value\n1,2,3\n", "line 2"),
            ("theta_i,phi_i,theta_r,phi_r,value\n0.1,0,x,0,1\n", "line 2"),
            (
                "theta_i,phi_i,theta_r,phi_r,value\n0.1,0,0.1,0,-1\n",
                "value",
            ),
            (
                "theta_i,phi_i,theta_r,phi_r,value\n0.1,0,0.1,0,inf\n",
                "value",
            ),
        ] {
            let e = read_csv(text, "m.csv").unwrap_err().to_string();
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
