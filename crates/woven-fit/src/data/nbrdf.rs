//! NBRDF neural fits of measured BRDFs (Sztrajman, Rainer, Ritschel, Weyrich, "Neural BRDF
//! Representation and Importance Sampling", CGF 2021): `*.nbrdf.json`, one small network per
//! material (MERL fabrics, RGL felts, DTU's green cloth; data/README.md).
//!
//! The network maps the Rusinkiewicz angles of a pair of directions to the BRDF: with the half
//! vector `h` (`θh`, `φh`) and the light's direction `d` in the half vector's frame (rotated by
//! `−φh` about z, then by `−θh` about y; `θd`, `φd`), the input is
//! `x = (sin θh, 0, cos θh, sin θd cos φd, sin θd sin φd, cos θd)` (isotropic: `φh` drops out) and
//! `f = max(exp(W3ᵀ a2 + b3) − 1, 0)` per channel with `a2 = relu(W2ᵀ a1 + b2)`,
//! `a1 = relu(W1ᵀ x + b1)` (6 → 21 → 21 → 3, the JSON's `W1, b1, W2, b2, W3, b3`, kernels stored
//! `[in][out]`). The output is f_r in sr⁻¹, RGB, in MERL's units, without the cosine.
//!
//! [`read`] evaluates a network on the grid of the `*.grid.csv` files (which were made from the
//! same networks, so a `.nbrdf.json` loads as the same dataset as its grid); [`Nbrdf::eval`]
//! evaluates it anywhere, e.g. at another dataset's directions ([`Nbrdf::dataset_at`]).

use super::rows::{format_error, on_grid, stem};
use super::{DataError, Dataset, Sample, Value};
use std::path::Path;
use woven::Vec3;

const INPUTS: usize = 6;
const HIDDEN: usize = 21;
const OUTPUTS: usize = 3;

/// One material's network.
#[derive(Clone, Debug, PartialEq)]
pub struct Nbrdf {
    /// The material's name (the JSON's `name`, else the file's stem).
    pub name: String,
    w1: Vec<[f64; HIDDEN]>,
    b1: [f64; HIDDEN],
    w2: Vec<[f64; HIDDEN]>,
    b2: [f64; HIDDEN],
    w3: Vec<[f64; OUTPUTS]>,
    b3: [f64; OUTPUTS],
}

/// A `[rows][N]` matrix of finite numbers from a JSON array of arrays.
fn matrix<const N: usize>(
    path: &Path,
    json: &serde_json::Value,
    key: &str,
    rows: usize,
) -> Result<Vec<[f64; N]>, DataError> {
    let bad = || {
        format_error(
            path,
            format!("NBRDF field `{key}` is not a {rows} × {N} array of finite numbers"),
        )
    };
    let outer = json.get(key).and_then(|v| v.as_array()).ok_or_else(bad)?;
    if outer.len() != rows {
        return Err(bad());
    }
    outer
        .iter()
        .map(|row| {
            let row = row.as_array().filter(|r| r.len() == N).ok_or_else(bad)?;
            let mut out = [0.0; N];
            for (o, v) in out.iter_mut().zip(row) {
                *o = v.as_f64().filter(|x| x.is_finite()).ok_or_else(bad)?;
            }
            Ok(out)
        })
        .collect()
}

/// A vector of `N` finite numbers from a JSON array.
fn vector<const N: usize>(
    path: &Path,
    json: &serde_json::Value,
    key: &str,
) -> Result<[f64; N], DataError> {
    let bad = || {
        format_error(
            path,
            format!("NBRDF field `{key}` is not {N} finite numbers"),
        )
    };
    let values = json
        .get(key)
        .and_then(|v| v.as_array())
        .filter(|a| a.len() == N)
        .ok_or_else(bad)?;
    let mut out = [0.0; N];
    for (o, v) in out.iter_mut().zip(values) {
        *o = v.as_f64().filter(|x| x.is_finite()).ok_or_else(bad)?;
    }
    Ok(out)
}

/// The rectified affine layer `relu(Wᵀ x + b)`.
fn layer<const N: usize>(x: &[f64], w: &[[f64; N]], b: &[f64; N]) -> [f64; N] {
    let mut out = *b;
    for (xi, row) in x.iter().zip(w) {
        for (o, wij) in out.iter_mut().zip(row) {
            *o += xi * wij;
        }
    }
    out
}

impl Nbrdf {
    /// Reads a network from `bytes` (the contents of `path`, JSON).
    ///
    /// # Errors
    /// [`DataError::Format`] for text that is not JSON, or a weight array of the wrong shape or
    /// with a non-finite entry.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Nbrdf, DataError> {
        let json: serde_json::Value = serde_json::from_slice(bytes)
            .map_err(|e| format_error(path, format!("not NBRDF JSON: {e}")))?;
        Ok(Nbrdf {
            name: json
                .get("name")
                .and_then(|n| n.as_str())
                .map(str::to_string)
                .unwrap_or_else(|| {
                    let s = stem(path);
                    s.strip_suffix(".nbrdf").map(str::to_string).unwrap_or(s)
                }),
            w1: matrix::<HIDDEN>(path, &json, "W1", INPUTS)?,
            b1: vector::<HIDDEN>(path, &json, "b1")?,
            w2: matrix::<HIDDEN>(path, &json, "W2", HIDDEN)?,
            b2: vector::<HIDDEN>(path, &json, "b2")?,
            w3: matrix::<OUTPUTS>(path, &json, "W3", HIDDEN)?,
            b3: vector::<OUTPUTS>(path, &json, "b3")?,
        })
    }

    /// The network at the Rusinkiewicz angles `θh`, `θd`, `φd` (radians): f_r per channel, sr⁻¹.
    pub fn eval_hd(&self, theta_h: f64, theta_d: f64, phi_d: f64) -> [f64; 3] {
        let x = [
            theta_h.sin(),
            0.0,
            theta_h.cos(),
            theta_d.sin() * phi_d.cos(),
            theta_d.sin() * phi_d.sin(),
            theta_d.cos(),
        ];
        let a1 = layer(&x, &self.w1, &self.b1).map(|v| v.max(0.0));
        let a2 = layer(&a1, &self.w2, &self.b2).map(|v| v.max(0.0));
        let y = layer(&a2, &self.w3, &self.b3);
        // The network's output transform; a huge pre-activation would overflow exp: capped.
        y.map(|v| (v.min(700.0).exp() - 1.0).max(0.0))
    }

    /// The BRDF `f(wi, wo)` per channel, sr⁻¹ (unit vectors in the local frame, `wi` toward the
    /// light); zero when either direction is at or below the horizon.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        let sum = wi + wo;
        let h = sum * (1.0 / sum.length());
        let theta_h = h.z.clamp(-1.0, 1.0).acos();
        let phi_h = h.y.atan2(h.x);
        // The light's direction in the half vector's frame: rotate by −φh about z, −θh about y.
        let (s, c) = (-phi_h).sin_cos();
        let d = Vec3::new(c * wi.x - s * wi.y, s * wi.x + c * wi.y, wi.z);
        let (s, c) = (-theta_h).sin_cos();
        let d = Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
        let theta_d = d.z.clamp(-1.0, 1.0).acos();
        let phi_d = d.y.atan2(d.x);
        self.eval_hd(theta_h, theta_d, phi_d)
    }

    /// The network evaluated at the directions of `geometry` (for example CUReT's 205 pairs): a
    /// dataset named after the network, RGB, absolute, with the samples' weights kept.
    pub fn dataset_at(&self, geometry: &Dataset) -> Dataset {
        Dataset {
            name: self.name.clone(),
            source: geometry.source.clone(),
            samples: geometry
                .samples
                .iter()
                .map(|s| Sample {
                    value: Value::Rgb(self.eval(
                        Vec3::from_spherical(s.theta_i, s.phi_i),
                        Vec3::from_spherical(s.theta_r, s.phi_r),
                    )),
                    ..*s
                })
                .collect(),
            dropped_below_horizon: geometry.dropped_below_horizon,
            relative: false,
        }
    }
}

/// Reads a `.nbrdf.json` network and evaluates it on the grid of the `*.grid.csv` files
/// (θi, θo ∈ {0, 5, …, 80}°, φo − φi ∈ {0, 15, …, 180}°, the light at φi = 0).
///
/// # Errors
/// As [`Nbrdf::parse`].
pub fn read(path: &Path, bytes: &[u8]) -> Result<Dataset, DataError> {
    let net = Nbrdf::parse(path, bytes)?;
    on_grid(path, net.name.clone(), |wi, wo| net.eval(wi, wo))
}
