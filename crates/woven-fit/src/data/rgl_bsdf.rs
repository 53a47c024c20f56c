//! RGL's measured `.bsdf` files (Dupuy & Jakob 2018): Mitsuba's little-endian "tensor file".
//!
//! Layout: the 12 bytes `tensor_file\0`, a version (two `u8`, 1.0), a `u32` field count, then per
//! field its name (`u16` length + bytes), its rank (`u16`), its type (`u8`: 1 u8, 2 i8, 3 u16,
//! 4 i16, 5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64), the byte offset of its data (`u64`)
//! and its shape (`u64` per dimension). [`TensorFile::parse`] (woven's, [`woven::tensor`]) reads
//! and checks all of it: every field's data lies inside the file.
//!
//! **Evaluation** ([`RglBsdf::eval`]) follows the paper's parameterisation as RGL's reference
//! loader implements it: with the half vector `m`, the light's `u_wi = (√(2θi/π), (φi + π)/2π)`
//! and `u_m = (√(2θm/π), frac((φm − φi + π)/2π))` (isotropic files), the point `u_m` is mapped
//! back through the warp of the visible-normal distribution (`vndf`, a marginal-conditional
//! bilinear warp, multilinear over the tabulated incidences) to the unit square where `rgb` is
//! tabulated, and `f · cos θo = rgb · ndf(u_m) / (4 σ(u_wi))`. [`read`] evaluates a file on the
//! grid of the `*.grid.csv` files (θi, θo ∈ {0, 5, …, 80}°, φo − φi ∈ {0, 15, …, 180}°), dividing
//! by `cos θo` and clipping negative channels (out-of-gamut spectra) at 0 as RGL's loader does,
//! so a `.bsdf` loads as the same dataset as its grid.

use super::rows::format_error;
use super::{DataError, Dataset};
use std::path::Path;
use woven::math::marginal::Marginal2D;
pub use woven::tensor::{Field, TensorFile, MAGIC};
use woven::Vec3;

/// An RGL measured BRDF, ready to evaluate.
pub struct RglBsdf {
    /// The file's description.
    pub description: String,
    ndf: Marginal2D,
    sigma: Marginal2D,
    vndf: Marginal2D,
    rgb: Marginal2D,
}

impl std::fmt::Debug for RglBsdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RglBsdf")
            .field("description", &self.description)
            .finish_non_exhaustive()
    }
}

impl RglBsdf {
    /// Reads an RGL `.bsdf` (RGB) file's tables from `bytes` (the contents of `path`).
    ///
    /// # Errors
    /// [`DataError::Format`] for a malformed tensor file, a missing field, a field of the wrong
    /// type or shape, an anisotropic or spectral file (not supported).
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<RglBsdf, DataError> {
        let file = TensorFile::parse(path, bytes).map_err(|e| match e {
            woven::Error::Parse { message, .. } => format_error(path, message),
            other => format_error(path, other.to_string()),
        })?;
        let bad = |what: String| format_error(path, format!("not an RGL RGB BSDF: {what}"));
        let field = |name: &str, ndim: usize| -> Result<(Vec<u64>, Vec<f64>), DataError> {
            let f = file
                .field(name)
                .ok_or_else(|| bad(format!("no field `{name}`")))?;
            if f.shape.len() != ndim {
                return Err(bad(format!(
                    "field `{name}` has {} dimensions, expected {ndim}",
                    f.shape.len()
                )));
            }
            let data = file
                .f32s(bytes, name)
                .ok_or_else(|| bad(format!("field `{name}` is not f32")))?;
            if data.iter().any(|v| !v.is_finite()) {
                return Err(bad(format!("field `{name}` holds a non-finite value")));
            }
            Ok((f.shape.clone(), data))
        };
        if file.field("spectra").is_some() && file.field("rgb").is_none() {
            return Err(bad(
                "a spectral file (`spectra`): only RGB files are supported".into(),
            ));
        }
        let (_, theta_i) = field("theta_i", 1)?;
        let (_, phi_i) = field("phi_i", 1)?;
        if phi_i.len() > 2 {
            return Err(bad("an anisotropic file (several φi): not supported".into()));
        }
        let (ndf_shape, ndf) = field("ndf", 2)?;
        let (sigma_shape, sigma) = field("sigma", 2)?;
        let (vndf_shape, vndf) = field("vndf", 4)?;
        let (rgb_shape, rgb) = field("rgb", 5)?;
        let (np, nt) = (phi_i.len() as u64, theta_i.len() as u64);
        let at_least_2 = |s: &[u64]| s.iter().rev().take(2).all(|&n| n >= 2);
        let ok = nt >= 1
            && np >= 1
            && at_least_2(&ndf_shape)
            && at_least_2(&sigma_shape)
            && at_least_2(&vndf_shape)
            && at_least_2(&rgb_shape)
            && vndf_shape[..2] == [np, nt]
            && rgb_shape[..3] == [np, nt, 3];
        if !ok {
            return Err(bad(format!(
                "inconsistent shapes: theta_i {nt}, phi_i {np}, ndf {ndf_shape:?}, sigma \
                 {sigma_shape:?}, vndf {vndf_shape:?}, rgb {rgb_shape:?}"
            )));
        }
        let dims = |s: &[u64]| (s[s.len() - 1] as usize, s[s.len() - 2] as usize);
        let (nx, ny) = dims(&ndf_shape);
        let ndf = Marginal2D::new(nx, ny, ndf, vec![], false);
        let (nx, ny) = dims(&sigma_shape);
        let sigma = Marginal2D::new(nx, ny, sigma, vec![], false);
        let (nx, ny) = dims(&vndf_shape);
        let vndf = Marginal2D::new(nx, ny, vndf, vec![phi_i.clone(), theta_i.clone()], true);
        let (nx, ny) = dims(&rgb_shape);
        let rgb = Marginal2D::new(
            nx,
            ny,
            rgb,
            vec![phi_i, theta_i, vec![0.0, 1.0, 2.0]],
            false,
        );
        Ok(RglBsdf {
            description: file.description(bytes).unwrap_or_default(),
            ndf,
            sigma,
            vndf,
            rgb,
        })
    }

    /// `f(wi, wo) · cos θo` per channel (what RGL's loader returns), unit vectors in the local
    /// frame; zero when either direction is at or below the horizon. Channels may be negative
    /// (out-of-gamut spectra).
    pub fn eval_cos(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        let sum = wi + wo;
        let m = sum * (1.0 / sum.length());
        let theta_i = wi.z.clamp(-1.0, 1.0).acos();
        let phi_i = wi.y.atan2(wi.x);
        let theta_m = m.z.clamp(-1.0, 1.0).acos();
        let phi_m = m.y.atan2(m.x);
        let to_u = |theta: f64| (theta * 2.0 / std::f64::consts::PI).sqrt();
        let to_v = |phi: f64| (phi + std::f64::consts::PI) / (2.0 * std::f64::consts::PI);
        let u_wi = [to_u(theta_i), to_v(phi_i)];
        let v_m = to_v(phi_m - phi_i);
        let u_m = [to_u(theta_m), v_m - v_m.floor()];
        let params = [phi_i, theta_i];
        let sample = self.vndf.invert(u_m, &params);
        let scale = self.ndf.eval(u_m, &[]) / (4.0 * self.sigma.eval(u_wi, &[]));
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            *o = self.rgb.eval(sample, &[phi_i, theta_i, c as f64]) * scale;
        }
        out
    }

    /// The BRDF `f(wi, wo)` per channel, sr⁻¹ (without the cosine), negative channels clipped
    /// at 0 as RGL's loader does.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        let c = self.eval_cos(wi, wo);
        if wo.z <= 0.0 {
            return [0.0; 3];
        }
        c.map(|v| (v / wo.z).max(0.0))
    }
}

/// Reads a `.bsdf` file ([`RglBsdf::parse`]) and evaluates it on the grid of the `*.grid.csv`
/// files: θi, θo ∈ {0, 5, …, 80}°, φo − φi ∈ {0, 15, …, 180}° (θi outermost, the relative
/// azimuth innermost), the light at φi = 0. Absolute, RGB; named after the file's stem.
///
/// # Errors
/// As [`RglBsdf::parse`]; [`DataError::Format`] if an evaluation is not finite.
pub fn read(path: &Path, bytes: &[u8]) -> Result<Dataset, DataError> {
    let brdf = RglBsdf::parse(path, bytes)?;
    super::rows::on_grid(path, super::rows::stem(path), |wi, wo| brdf.eval(wi, wo))
}
