//! The published analytic fits of the MERL materials, a baseline for the cloth model on the same
//! data: the Shifted Gamma Distribution model (SGD; Bagher, Soler, Holzschuch, "Accurate fitting
//! of measured reflectances using a Shifted Gamma micro-facet distribution", CGF 2012) and the
//! ABC model (Löw, Kronander, Ynnerman, Unger, "BRDF models for accurate and efficient rendering
//! of glossy surfaces", TOG 2012). The parameter tables (`data/published/merl_*_fits.csv`, one row
//! per MERL material, per-channel values `_r`, `_g`, `_b`) were distributed by Dupuy's public-domain
//! `dj_brdf`; the formulas below are the models as those papers define them, written from their
//! equations, and they evaluate the fits in MERL's physical units (the MERL scale factors are
//! part of the fitted values), comparable with the NBRDF grids of [`super::grid`].
//!
//! Both are microfacet models with the half vector `h = (wi + wo)/|wi + wo|`, `cos θh = h·z`,
//! `cos θd = wi·h`:
//!
//! - **SGD**, per channel: `f = (ρd + ρs F(θd) D(θh) G1(θi) G1(θo) / (cos θi cos θo)) / π` with
//!   - `D(θh) = K exp(−x) / (π x^p cos⁴θh)`, `x = α + tan²θh / α` (the shifted gamma
//!     distribution with its normalisation `K` = `kap` fitted);
//!   - `F(θd) = F0 − F1 cos θd + (1 − F0)(1 − cos θd)^5` (Schlick's form with a linear term);
//!   - `G1(θ) = clamp(1 + Λ(1 − exp(c (θ − θ0)₊^k)), 0, 1)` (the fitted shadowing, `lambda`,
//!     `c`, `k`, `theta0`).
//! - **ABC**: `f = kd/π + F(θd; η) D(θh) G / (π cos θi cos θo)` with `D(θh) = A / (1 + B(1 − cos θh))^C`
//!   (A per channel, B and C shared), `F` the unpolarised Fresnel reflectance of a dielectric of
//!   index `η` = `ior`, and `G = min(1, 2 cos θh cos θi / cos θd, 2 cos θh cos θo / cos θd)`
//!   (Cook–Torrance's V-groove shadowing).
//!
//! Both vanish when either direction is at or below the horizon.

use super::rows::{format_error, shorten, Cell, CsvTable};
use super::{data_dir, DataError};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use woven::fiber::fresnel_dielectric;
use woven::Vec3;

/// One material's SGD fit, per channel (red, green, blue).
#[derive(Clone, Debug, PartialEq)]
pub struct SgdFit {
    /// MERL's name of the material (`beige-fabric`).
    pub name: String,
    /// Whether the table flags it as a textile.
    pub is_textile: bool,
    /// Diffuse albedo `ρd`.
    pub rho_d: [f64; 3],
    /// Specular weight `ρs`.
    pub rho_s: [f64; 3],
    /// Shift `α` of the distribution.
    pub alpha: [f64; 3],
    /// Exponent `p`.
    pub p: [f64; 3],
    /// Fresnel `F0`.
    pub f0: [f64; 3],
    /// Fresnel linear term `F1`.
    pub f1: [f64; 3],
    /// Normalisation `K` of the distribution.
    pub kap: [f64; 3],
    /// Shadowing amplitude `Λ`.
    pub lambda: [f64; 3],
    /// Shadowing rate `c`.
    pub c: [f64; 3],
    /// Shadowing exponent `k`.
    pub k: [f64; 3],
    /// Shadowing onset `θ0`, radians.
    pub theta0: [f64; 3],
    /// The fit's error as published (per channel).
    pub error: [f64; 3],
}

/// One material's ABC fit.
#[derive(Clone, Debug, PartialEq)]
pub struct AbcFit {
    /// MERL's name of the material.
    pub name: String,
    /// Whether the table flags it as a textile.
    pub is_textile: bool,
    /// Diffuse albedo per channel.
    pub kd: [f64; 3],
    /// Specular amplitude `A` per channel.
    pub a: [f64; 3],
    /// Width `B` of the specular lobe.
    pub b: f64,
    /// Fall-off exponent `C` of the lobe.
    pub c: f64,
    /// Index of refraction `η` of the Fresnel term.
    pub ior: f64,
}

/// The half vector's `cos θh` and `cos θd = wi·h`, or `None` when a direction is at or below the
/// horizon (or the two are opposite).
fn half_angles(wi: Vec3, wo: Vec3) -> Option<(f64, f64)> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return None;
    }
    let sum = wi + wo;
    let len = sum.length();
    // Opposite directions have no half vector; above the horizon they cannot occur, but a
    // rounding-level sum is guarded anyway.
    if len < 1e-12 {
        return None;
    }
    let h = sum * (1.0 / len);
    Some((h.z.clamp(0.0, 1.0), wi.dot(h).clamp(0.0, 1.0)))
}

impl SgdFit {
    /// The BRDF `f(wi, wo)`, sr⁻¹, per channel (unit vectors in the local frame, `z` the normal;
    /// the model is isotropic). Zero when either direction is at or below the horizon.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        let Some((cos_h, cos_d)) = half_angles(wi, wo) else {
            return [0.0; 3];
        };
        let theta_i = wi.z.clamp(-1.0, 1.0).acos();
        let theta_o = wo.z.clamp(-1.0, 1.0).acos();
        let c2 = cos_h * cos_h;
        let tan2 = (1.0 - c2) / c2;
        let mut out = [0.0; 3];
        for ch in 0..3 {
            // The shifted gamma distribution D(θh).
            let x = self.alpha[ch] + tan2 / self.alpha[ch];
            let d = self.kap[ch] * (-x).exp() / (PI * x.powf(self.p[ch]) * c2 * c2);
            // The fitted Fresnel curve.
            let f = self.f0[ch] - self.f1[ch] * cos_d + (1.0 - self.f0[ch]) * (1.0 - cos_d).powi(5);
            // The fitted shadowing, one factor per direction.
            let g1 = |theta: f64| {
                let t = (theta - self.theta0[ch]).max(0.0);
                (1.0 + self.lambda[ch] * (1.0 - (self.c[ch] * t.powf(self.k[ch])).exp()))
                    .clamp(0.0, 1.0)
            };
            let g = g1(theta_i) * g1(theta_o);
            let v = (self.rho_d[ch] + self.rho_s[ch] * f * d * g / (wi.z * wo.z)) / PI;
            // A tan²θh overflow at grazing half vectors gives 0·∞: the lobe is zero there.
            out[ch] = if v.is_finite() {
                v
            } else {
                self.rho_d[ch] / PI
            };
        }
        out
    }
}

impl AbcFit {
    /// The BRDF `f(wi, wo)`, sr⁻¹, per channel; zero when either direction is at or below the
    /// horizon.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        let Some((cos_h, cos_d)) = half_angles(wi, wo) else {
            return [0.0; 3];
        };
        let f = fresnel_dielectric(cos_d, self.ior);
        let g = if cos_d > 0.0 {
            (2.0 * cos_h * wi.z / cos_d)
                .min(2.0 * cos_h * wo.z / cos_d)
                .min(1.0)
        } else {
            0.0
        };
        let lobe = 1.0 / (1.0 + self.b * (1.0 - cos_h)).powf(self.c);
        let mut out = [0.0; 3];
        for ch in 0..3 {
            let d = self.a[ch] * lobe;
            out[ch] = self.kd[ch] / PI + f * d * g / (PI * wi.z * wo.z);
        }
        out
    }
}

/// Reads a row's `NAME_r`, `NAME_g`, `NAME_b` columns.
fn rgb(
    table: &CsvTable<'_>,
    record: &csv::StringRecord,
    line: u64,
    name: &str,
) -> Result<[f64; 3], DataError> {
    let mut out = [0.0; 3];
    for (k, suffix) in ["r", "g", "b"].iter().enumerate() {
        out[k] = scalar(table, record, line, &format!("{name}_{suffix}"))?;
    }
    Ok(out)
}

/// Reads a row's column `name` as a finite number.
fn scalar(
    table: &CsvTable<'_>,
    record: &csv::StringRecord,
    line: u64,
    name: &str,
) -> Result<f64, DataError> {
    let k = table.require(name, "a published-fits table")?;
    Cell {
        path: table.path,
        line,
        column: name,
    }
    .number(record.get(k).unwrap_or(""))
}

/// Reads a row's `is_textile` flag (0 or 1).
fn flag(table: &CsvTable<'_>, record: &csv::StringRecord, line: u64) -> Result<bool, DataError> {
    let x = scalar(table, record, line, "is_textile")?;
    if x == 0.0 || x == 1.0 {
        Ok(x == 1.0)
    } else {
        Err(Cell {
            path: table.path,
            line,
            column: "is_textile",
        }
        .error(format!("{x} is not 0 or 1")))
    }
}

/// Reads a table of SGD fits (`merl_sgd_fits.csv`).
///
/// # Errors
/// [`DataError::Io`], [`DataError::Format`] for a missing column, [`DataError::Parse`] naming the
/// line and column of a bad number.
pub fn read_sgd(path: &Path) -> Result<Vec<SgdFit>, DataError> {
    let bytes = super::rows::read_file(path)?;
    let mut table = CsvTable::new(path, &bytes)?;
    let name_col = table.require("name", "a table of SGD fits")?;
    let mut out = Vec::new();
    while let Some((line, record)) = table.next_record()? {
        let record = record.clone();
        let t = &table;
        let r = &record;
        out.push(SgdFit {
            name: r.get(name_col).unwrap_or("").to_string(),
            is_textile: flag(t, r, line)?,
            rho_d: rgb(t, r, line, "rhoD")?,
            rho_s: rgb(t, r, line, "rhoS")?,
            alpha: rgb(t, r, line, "alpha")?,
            p: rgb(t, r, line, "p")?,
            f0: rgb(t, r, line, "f0")?,
            f1: rgb(t, r, line, "f1")?,
            kap: rgb(t, r, line, "kap")?,
            lambda: rgb(t, r, line, "lambda")?,
            c: rgb(t, r, line, "c")?,
            k: rgb(t, r, line, "k")?,
            theta0: rgb(t, r, line, "theta0")?,
            error: rgb(t, r, line, "error")?,
        });
        if out
            .last()
            .is_some_and(|f| f.alpha.iter().any(|&a| a <= 0.0))
        {
            return Err(Cell {
                path,
                line,
                column: "alpha",
            }
            .error("the shift α must be > 0"));
        }
    }
    if out.is_empty() {
        return Err(format_error(path, "no fits in the table"));
    }
    Ok(out)
}

/// Reads a table of ABC fits (`merl_abc_fits.csv`).
///
/// # Errors
/// As [`read_sgd`].
pub fn read_abc(path: &Path) -> Result<Vec<AbcFit>, DataError> {
    let bytes = super::rows::read_file(path)?;
    let mut table = CsvTable::new(path, &bytes)?;
    let name_col = table.require("name", "a table of ABC fits")?;
    let mut out = Vec::new();
    while let Some((line, record)) = table.next_record()? {
        let record = record.clone();
        let t = &table;
        let r = &record;
        out.push(AbcFit {
            name: r.get(name_col).unwrap_or("").to_string(),
            is_textile: flag(t, r, line)?,
            kd: rgb(t, r, line, "kD")?,
            a: rgb(t, r, line, "A")?,
            b: scalar(t, r, line, "B")?,
            c: scalar(t, r, line, "C")?,
            ior: scalar(t, r, line, "ior")?,
        });
    }
    if out.is_empty() {
        return Err(format_error(path, "no fits in the table"));
    }
    Ok(out)
}

/// The bundled table of SGD fits, `data/published/merl_sgd_fits.csv`.
pub fn sgd_table() -> PathBuf {
    data_dir().join("published/merl_sgd_fits.csv")
}

/// The bundled table of ABC fits, `data/published/merl_abc_fits.csv`.
pub fn abc_table() -> PathBuf {
    data_dir().join("published/merl_abc_fits.csv")
}

/// The published SGD and ABC fits of the MERL material `name` (`beige-fabric`), from the bundled
/// tables.
///
/// # Errors
/// [`DataError::Format`] when the tables have no such material; errors of [`read_sgd`] and
/// [`read_abc`].
pub fn for_material(name: &str) -> Result<(SgdFit, AbcFit), DataError> {
    let missing =
        |path: &Path| format_error(path, format!("no published fit of `{}`", shorten(name)));
    let sgd = read_sgd(&sgd_table())?
        .into_iter()
        .find(|f| f.name == name)
        .ok_or_else(|| missing(&sgd_table()))?;
    let abc = read_abc(&abc_table())?
        .into_iter()
        .find(|f| f.name == name)
        .ok_or_else(|| missing(&abc_table()))?;
    Ok((sgd, abc))
}
