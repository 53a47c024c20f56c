//! Isotropic BRDFs in the binary layout of the MERL BRDF database.
//!
//! ```
//! use std::f64::consts::PI;
//! use woven::export::merl::{self, HalfDiff, MerlBrdf};
//! use woven::{material::Material, Vec3};
//!
//! // Mirror configuration: the half vector is the normal (θ_h = 0) and θ_d is the incidence angle.
//! let s = Vec3::from_spherical(0.5, 0.0);
//! let v = Vec3::from_spherical(0.5, PI);
//! let hd = HalfDiff::from_directions(s, v);
//! assert!(hd.theta_h.abs() < 1e-12 && (hd.theta_d - 0.5).abs() < 1e-12);
//!
//! // Silk's isotropic yarns can be exported; the twisted yarns of the belt cloth cannot.
//! merl::check_isotropic(&Material::preset("silk")?)?;
//! let err = merl::check_isotropic(&Material::preset("belt-cloth")?).unwrap_err();
//! assert!(err.to_string().contains("φ_h"));
//!
//! // A Lambertian surface of albedo 0.5, f = 0.5/π sr⁻¹, written and read back.
//! let brdf = MerlBrdf::from_fn(|_s, _v| 0.5 / PI)?;
//! let mut file = Vec::new();
//! brdf.write(&mut file)?;
//! assert_eq!(file.len(), merl::FILE_SIZE); // 12 + 3 · 1 458 000 · 8 bytes
//! let back = MerlBrdf::read(file.as_slice())?;
//! let rgb = back.lookup(Vec3::from_spherical(0.3, 0.0), Vec3::from_spherical(0.7, 2.0));
//! assert!(rgb.iter().all(|c| (c - 0.5 / PI).abs() < 1e-15));
//! # Ok::<(), woven::Error>(())
//! ```
//!
//! # The file
//!
//! Little-endian throughout, [`FILE_SIZE`] = 34 992 012 bytes:
//!
//! | offset | type | content |
//! |---|---|---|
//! | 0 | 3 × `i32` | dimensions `[90, 90, 180]`: bins in `θ_h`, `θ_d`, `φ_d` |
//! | 12 | [`MERL_BINS`] × `f64` | red block |
//! | 12 + 8·[`MERL_BINS`] | [`MERL_BINS`] × `f64` | green block |
//! | 12 + 16·[`MERL_BINS`] | [`MERL_BINS`] × `f64` | blue block |
//!
//! Within a block the bin `(i_h, i_d, i_φ)` sits at `i_φ + 180 (i_d + 90 i_h)` ([`Bin::index`]).
//! A reader multiplies a stored value by its channel's scale, [`CHANNEL_SCALES`] =
//! `[1/1500, 1.15/1500, 1.66/1500]`, to get the BRDF in sr⁻¹ (no cosine); the writer stores
//! `f · 1500`, `f · 1500/1.15`, `f · 1500/1.66`. [`MerlBrdf`] keeps the stored values, so that a
//! file read and written again is unchanged bit for bit, and reports BRDF values exactly as a
//! reader computes them (`stored · scale`). A monochrome export writes the same BRDF into all
//! three channels (a grey material).
//!
//! # Coordinates
//!
//! The half/difference coordinates of Rusinkiewicz, in the local frame of `docs/conventions.md`
//! (`z` the macro normal, weft along `x`), with `s` toward the light and `v` toward the viewer,
//! both unit vectors pointing away from the surface. `s` is the direction the MERL reader calls
//! "in" and the one rotated into the half-vector frame:
//!
//! - `h = (s + v)/|s + v|`, with polar angle `θ_h` and azimuth `φ_h`;
//! - `d = R_y(−θ_h) R_z(−φ_h) s`, the light direction in the frame whose pole is `h`, with polar
//!   angle `θ_d` (the angle between `s` and `h`) and azimuth `φ_d`.
//!
//! Back ([`HalfDiff::to_directions`]): `d = (sin θ_d cos φ_d, sin θ_d sin φ_d, cos θ_d)`,
//! `s = R_z(φ_h) R_y(θ_h) d` and `v = R_z(φ_h) R_y(θ_h) (−d_x, −d_y, d_z)` (the mirror image of
//! `s` about `h`). `R_y(α)` maps `(x, y, z)` to `(x cos α + z sin α, y, −x sin α + z cos α)` and
//! `R_z(α)` maps it to `(x cos α − y sin α, x sin α + y cos α, z)`.
//!
//! The format has no `φ_h`: it assumes an **isotropic** BRDF (independent of `φ_h`), and the
//! exporter samples at `φ_h = 0`. It stores `φ_d ∈ [0, π)` only: swapping `s` and `v` maps `φ_d`
//! to `φ_d + π`, so by **reciprocity** a reader folds `φ_d ≥ π` to `φ_d − π` (and `φ_d < 0` to
//! `φ_d + π`). A non-reciprocal BRDF — woven's `normalization = "paper"`, whose lobe scale
//! `β(θ_i)` depends on the light direction — is stored as `f(s, v)` for the bin's own `s`; a
//! reader looking up the other half of `φ_d` gets `f(v, s)`, which differs by the ratio of the
//! `β` of the two directions. [`check_isotropic`] rejects anisotropic materials.
//!
//! # Bins
//!
//! Bin indices, as the database's reader computes them (`floor`, clamped to the last bin):
//!
//! - `i_h = floor(√(θ_h/(π/2)) · 90)`: a square-root parametrization, fine near the specular peak
//!   (the first bin spans 0.011°, the last 2°);
//! - `i_d = floor(θ_d/(π/2) · 90)`: 1° bins;
//! - `i_φ = floor(φ_d/π · 180)` after folding `φ_d` into `[0, π)`: 1° bins.
//!
//! Each bin is sampled once, at its **centre** in its own parametrization
//! ([`Bin::center`]): `θ_h = ((i_h + ½)/90)² · π/2`, `θ_d = (i_d + ½)/90 · π/2`,
//! `φ_d = (i_φ + ½)/180 · π`, `φ_h = 0`. A bin whose centre puts `s` or `v` at or below the horizon
//! (`z ≤ 0`; 361 784 of the 1 458 000 bins) stores [`BELOW_HORIZON_VALUE`] = 0, never evaluated.
//! The database marks unmeasured bins with negative values (−1), but the reference reader and the
//! renderers' loaders multiply and return stored values without checking their sign, and a query
//! just above the horizon can land in such a bin: 0 is what the BRDF is below the horizon
//! (`Model::eval` returns 0 there), so it never makes negative radiance. Files with negative
//! values still read.
//!
//! Lookups ([`MerlBrdf::lookup`]) return the value of the bin that contains the query, without
//! interpolation, like the reference reader. For the smooth flat fiber of the integration tests
//! (η = 1.5, σ_h/τ = 0.3, ρ0 = 0.1, both polar angles ≤ 75°) the relative error against the model
//! is 0.3 % at the median, 2.6 % at the 99th percentile and 6 % at most; it grows with the lobe's
//! sharpness, which sets how much the BRDF changes across one bin.
//!
//! # Filling the table in parallel
//!
//! [`MerlBrdf::from_fn`] evaluates the bins one after the other, [`MerlBrdf::from_fn_threaded`]
//! on scoped threads. A caller with its own thread pool evaluates [`eval_bin`] over
//! `0..MERL_BINS` (with rayon, as `woven export` does) and hands the values to
//! [`MerlBrdf::from_values`] or [`MerlBrdf::from_rgb`]:
//!
//! ```text
//! let model = material.build(550.0)?;
//! let mono: Vec<f64> = (0..merl::MERL_BINS)
//!     .into_par_iter()
//!     .map(|i| merl::eval_bin(i, |s, v| model.eval(s, v)))
//!     .collect();
//! MerlBrdf::from_values(&mono)?.save(path)?;
//! ```

use crate::error::{Error, Result};
use crate::material::Material;
use crate::math::Vec3;
use crate::progress::Progress;
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Number of `θ_h` bins.
pub const THETA_H_RES: usize = 90;
/// Number of `θ_d` bins.
pub const THETA_D_RES: usize = 90;
/// Number of `φ_d` bins, over `[0, π)`.
pub const PHI_D_RES: usize = 180;
/// Bins per channel: 90 · 90 · 180 = 1 458 000.
pub const MERL_BINS: usize = THETA_H_RES * THETA_D_RES * PHI_D_RES;
/// The header: `[θ_h, θ_d, φ_d]` bin counts, three little-endian `i32`.
pub const DIMS: [i32; 3] = [THETA_H_RES as i32, THETA_D_RES as i32, PHI_D_RES as i32];
/// Bytes in a file: the 12-byte header and three blocks of [`MERL_BINS`] `f64`.
pub const FILE_SIZE: usize = HEADER_SIZE + 3 * MERL_BINS * 8;
/// The factors a reader applies to the stored red, green and blue values to get sr⁻¹.
pub const CHANNEL_SCALES: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];
/// The value stored in bins whose sample directions lie at or below the horizon.
pub const BELOW_HORIZON_VALUE: f64 = 0.0;

const HEADER_SIZE: usize = 12;
const CHANNEL_NAMES: [&str; 3] = ["red", "green", "blue"];
/// Bins per θ_h slice: the unit of work of the threaded fill.
const SLICE: usize = THETA_D_RES * PHI_D_RES;

/// Half/difference (Rusinkiewicz) coordinates of a pair of directions, radians (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfDiff {
    /// Polar angle of the half vector, `[0, π/2]` for directions above the surface.
    pub theta_h: f64,
    /// Azimuth of the half vector from the weft (`x`), `(−π, π]`; 0 in the file's samples.
    pub phi_h: f64,
    /// Angle between the light direction and the half vector, `[0, π/2]`.
    pub theta_d: f64,
    /// Azimuth of the light direction about the half vector, `(−π, π]`.
    pub phi_d: f64,
}

/// A light direction `s` and a view direction `v`: unit vectors in the local frame, pointing away
/// from the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Directions {
    /// Toward the light (a renderer's `wi`).
    pub s: Vec3,
    /// Toward the viewer (a renderer's `wo`).
    pub v: Vec3,
}

/// Polar angle of a unit vector, accurate near the pole (unlike `acos(z)`).
fn polar(d: Vec3) -> f64 {
    d.x.hypot(d.y).atan2(d.z)
}

/// `R_z(φ_h) R_y(θ_h) d`: from the frame whose pole is the half vector back to the local frame.
fn from_half_frame(d: Vec3, theta_h: f64, phi_h: f64) -> Vec3 {
    let (st, ct) = theta_h.sin_cos();
    let (sp, cp) = phi_h.sin_cos();
    let x = d.x * ct + d.z * st;
    let z = -d.x * st + d.z * ct;
    Vec3::new(x * cp - d.y * sp, x * sp + d.y * cp, z)
}

impl HalfDiff {
    /// The coordinates of light direction `s` and view direction `v` (unit vectors in the local
    /// frame, pointing away from the surface).
    ///
    /// `h = (s + v)/|s + v|`; `d = R_y(−θ_h) R_z(−φ_h) s`. When `s = −v` (opposite grazing
    /// directions) there is no half vector and `h = z` is used. At `θ_h = 0` the azimuth `φ_h` is
    /// undefined — `atan2` of rounding noise in `h_x`, `h_y` — and `φ_d = φ_s − φ_h` with it; an
    /// isotropic BRDF does not depend on `φ_d` there.
    ///
    /// ```
    /// use woven::{export::merl::HalfDiff, Vec3};
    /// // Retro-reflection: h = s = v, so θ_h is the incidence angle and θ_d = 0.
    /// let s = Vec3::from_spherical(0.8, 1.0);
    /// let hd = HalfDiff::from_directions(s, s);
    /// assert!((hd.theta_h - 0.8).abs() < 1e-12 && hd.theta_d.abs() < 1e-12);
    /// ```
    pub fn from_directions(s: Vec3, v: Vec3) -> HalfDiff {
        let sum = s + v;
        let len = sum.length();
        // |s + v| = 0 only for exactly opposite directions; any pole serves there.
        let h = if len > 0.0 {
            sum * (1.0 / len)
        } else {
            Vec3::Z
        };
        let theta_h = polar(h);
        let phi_h = h.y.atan2(h.x);
        // R_z(−φ_h) then R_y(−θ_h): the half vector becomes the pole.
        let (sp, cp) = phi_h.sin_cos();
        let (st, ct) = theta_h.sin_cos();
        let x1 = s.x * cp + s.y * sp;
        let y1 = -s.x * sp + s.y * cp;
        let d = Vec3::new(x1 * ct - s.z * st, y1, x1 * st + s.z * ct);
        HalfDiff {
            theta_h,
            phi_h,
            theta_d: polar(d),
            phi_d: d.y.atan2(d.x),
        }
    }

    /// The light and view directions of these coordinates (the inverse of
    /// [`from_directions`](Self::from_directions)).
    ///
    /// Either direction may come out below the horizon (`z < 0`): not every triple of angles in
    /// `[0, π/2]² × [0, π)` is a pair of directions above the surface.
    pub fn to_directions(&self) -> Directions {
        let (st, ct) = self.theta_d.sin_cos();
        let (sp, cp) = self.phi_d.sin_cos();
        let d = Vec3::new(st * cp, st * sp, ct);
        // v is s mirrored about h: in the half-vector frame, (−d_x, −d_y, d_z).
        let d_v = Vec3::new(-d.x, -d.y, d.z);
        Directions {
            s: from_half_frame(d, self.theta_h, self.phi_h),
            v: from_half_frame(d_v, self.theta_h, self.phi_h),
        }
    }
}

/// One bin of the table: its index in each coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Bin {
    /// `θ_h` bin, `0..90`, in the square-root parametrization.
    pub theta_h: usize,
    /// `θ_d` bin, `0..90`.
    pub theta_d: usize,
    /// `φ_d` bin, `0..180`, after folding `φ_d` into `[0, π)`.
    pub phi_d: usize,
}

impl Bin {
    /// The bin that contains `hd`, as the database's reader computes it (`φ_h` is ignored;
    /// out-of-range angles fall into the first or last bin).
    pub fn containing(hd: &HalfDiff) -> Bin {
        // `as usize` truncates toward zero (= floor for x ≥ 0) and maps NaN and negatives to 0;
        // `min` keeps θ = π/2 and φ = π in the last bin, as the reader's clamp does.
        let theta_h = (hd.theta_h.max(0.0) / FRAC_PI_2).sqrt() * THETA_H_RES as f64;
        let theta_d = hd.theta_d.max(0.0) / FRAC_PI_2 * THETA_D_RES as f64;
        // Reciprocity: φ_d and φ_d + π are the same bin (rem_euclid may round up to π itself).
        let phi_d = hd.phi_d.rem_euclid(PI) / PI * PHI_D_RES as f64;
        Bin {
            theta_h: (theta_h as usize).min(THETA_H_RES - 1),
            theta_d: (theta_d as usize).min(THETA_D_RES - 1),
            phi_d: (phi_d as usize).min(PHI_D_RES - 1),
        }
    }

    /// The bin at position `index` of a channel block.
    ///
    /// # Panics
    /// If `index >= MERL_BINS`.
    pub fn from_index(index: usize) -> Bin {
        assert!(
            index < MERL_BINS,
            "MERL bin index {index} out of range 0..{MERL_BINS}"
        );
        Bin {
            theta_h: index / SLICE,
            theta_d: index / PHI_D_RES % THETA_D_RES,
            phi_d: index % PHI_D_RES,
        }
    }

    /// The position of this bin in a channel block: `φ_d + 180 (θ_d + 90 θ_h)`.
    pub fn index(self) -> usize {
        debug_assert!(
            self.theta_h < THETA_H_RES && self.theta_d < THETA_D_RES && self.phi_d < PHI_D_RES
        );
        self.phi_d + PHI_D_RES * (self.theta_d + THETA_D_RES * self.theta_h)
    }

    /// The bin's sample point: its centre in each coordinate's own parametrization, with
    /// `φ_h = 0`: `θ_h = ((i_h + ½)/90)² π/2`, `θ_d = (i_d + ½)/90 · π/2`, `φ_d = (i_φ + ½)/180 · π`.
    pub fn center(self) -> HalfDiff {
        let u = (self.theta_h as f64 + 0.5) / THETA_H_RES as f64;
        HalfDiff {
            theta_h: u * u * FRAC_PI_2,
            phi_h: 0.0,
            theta_d: (self.theta_d as f64 + 0.5) / THETA_D_RES as f64 * FRAC_PI_2,
            phi_d: (self.phi_d as f64 + 0.5) / PHI_D_RES as f64 * PI,
        }
    }

    /// The directions of the bin's centre, or `None` when either lies at or below the horizon
    /// (such bins store [`BELOW_HORIZON_VALUE`]).
    pub fn directions(self) -> Option<Directions> {
        let d = self.center().to_directions();
        (d.s.z > 0.0 && d.v.z > 0.0).then_some(d)
    }
}

/// The sample directions of bin `index` (see [`Bin::directions`]); what a caller filling the table
/// in parallel evaluates.
///
/// # Panics
/// If `index >= MERL_BINS`.
pub fn bin_directions(index: usize) -> Option<Directions> {
    Bin::from_index(index).directions()
}

/// The value to store for bin `index`: `f(s, v)` (sr⁻¹) at the bin's sample directions, or
/// [`BELOW_HORIZON_VALUE`] without calling `f` when they are below the horizon.
///
/// # Panics
/// If `index >= MERL_BINS`.
pub fn eval_bin(index: usize, f: impl Fn(Vec3, Vec3) -> f64) -> f64 {
    bin_directions(index).map_or(BELOW_HORIZON_VALUE, |d| f(d.s, d.v))
}

/// Checks that `material` is isotropic, as the MERL layout requires.
///
/// Isotropic: a flat fiber surface (no `[yarn]` table) or yarns with `isotropic = true`
/// (Eq. (22)). Single-orientation yarns, twisted or not, are anisotropic.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `yarn.isotropic`, explaining why and what to do instead.
pub fn check_isotropic(material: &Material) -> Result<()> {
    let Some(yarn) = &material.yarn else {
        return Ok(());
    };
    if yarn.isotropic {
        return Ok(());
    }
    let which = match &material.name {
        Some(name) => format!("material {name:?}"),
        None => "the material".to_string(),
    };
    let why = if yarn.twist_std > 0.0 {
        format!(
            "its fibers spread only twist_std = {} rad about yarn axes that run along the weft and \
             the warp",
            yarn.twist_std
        )
    } else {
        "its fibers run along its yarns, that is along the weft and the warp".to_string()
    };
    Err(Error::invalid(
        "yarn.isotropic",
        false,
        format!(
            "an isotropic material for MERL export: a MERL file has no half-vector azimuth (its \
             bins are θ_h, θ_d, φ_d), so only isotropic BRDFs, the same at every azimuth, fit in \
             it; {which} is anisotropic because {why}, so its highlights move with the azimuth φ_h \
             of the half vector relative to the weft; instead, build a table with `woven \
             tabulate` (woven::table::Table in code: it keeps the azimuth, and renderers can \
             sample it), or make the yarns isotropic with `isotropic = true` in [yarn] (fibers in \
             every azimuth, as in the silk preset); a flat fiber surface, without [yarn], is \
             isotropic too"
        ),
    ))
}

/// An isotropic BRDF in the MERL layout: three channels of [`MERL_BINS`] values.
///
/// Holds the values as stored in the file (BRDF / channel scale), so that reading and writing
/// are exact; [`value`](Self::value) and [`lookup`](Self::lookup) return sr⁻¹ as a reader computes
/// them. Every stored value is finite.
#[derive(Clone, PartialEq)]
pub struct MerlBrdf {
    /// Red, green and blue blocks one after the other, in file order.
    stored: Vec<f64>,
}

impl fmt::Debug for MerlBrdf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MerlBrdf")
            .field("bins", &MERL_BINS)
            .finish_non_exhaustive()
    }
}

impl MerlBrdf {
    /// A grey table from a BRDF `f(s, v)` (sr⁻¹, no cosine), evaluated at each bin's sample
    /// directions one after the other (see [`eval_bin`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if `f` returns a non-finite value, naming the bin.
    pub fn from_fn(f: impl Fn(Vec3, Vec3) -> f64) -> Result<Self> {
        let mono: Vec<f64> = (0..MERL_BINS).map(|i| eval_bin(i, &f)).collect();
        Self::from_values(&mono)
    }

    /// As [`from_fn`](Self::from_fn), on `threads` worker threads (0: one per available core).
    /// `progress` hears `(done, total)` slices of constant θh and is asked before each row of φd
    /// bins whether to stop.
    ///
    /// # Errors
    /// As [`from_fn`](Self::from_fn), [`Error::InvalidParameter`] if no thread pool of that
    /// size can be made, or [`Error::Cancelled`] when `progress` asked to stop.
    ///
    /// # Panics
    /// If `f` panics.
    pub fn from_fn_threaded(
        f: impl Fn(Vec3, Vec3) -> f64 + Sync,
        threads: usize,
        progress: &dyn Progress,
    ) -> Result<Self> {
        use rayon::prelude::*;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::invalid("threads", threads, format!("a usable count ({e})")))?;
        let mut mono = vec![BELOW_HORIZON_VALUE; MERL_BINS];
        // θ_h slices, one task each: their costs differ (more bins lie below the horizon at
        // large θ_h), so rayon balances them.
        let (done, total) = (AtomicUsize::new(0), MERL_BINS / SLICE);
        pool.install(|| {
            mono.par_chunks_mut(SLICE)
                .enumerate()
                .for_each(|(k, slice)| {
                    // Asked once per row of φd bins: an exact model's row takes milliseconds.
                    for (r, row) in slice.chunks_mut(PHI_D_RES).enumerate() {
                        if progress.cancelled() {
                            return;
                        }
                        let first = k * SLICE + r * PHI_D_RES;
                        for (j, out) in row.iter_mut().enumerate() {
                            *out = eval_bin(first + j, &f);
                        }
                    }
                    progress.update(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                })
        });
        if progress.cancelled() {
            return Err(Error::Cancelled);
        }
        Self::from_values(&mono)
    }

    /// A grey table from BRDF values (sr⁻¹) in bin order ([`Bin::index`]), e.g. computed in
    /// parallel with [`eval_bin`]. The same value goes into the three channels.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if `mono` does not hold [`MERL_BINS`] values or one is not
    /// finite.
    pub fn from_values(mono: &[f64]) -> Result<Self> {
        Self::from_rgb(mono, mono, mono)
    }

    /// A table from red, green and blue BRDF values (sr⁻¹) in bin order ([`Bin::index`]).
    /// Negative values are kept (the database marks unmeasured bins with −1).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if a channel does not hold [`MERL_BINS`] values or a value is
    /// not finite (or overflows once divided by its channel scale).
    pub fn from_rgb(red: &[f64], green: &[f64], blue: &[f64]) -> Result<Self> {
        let mut stored = Vec::with_capacity(3 * MERL_BINS);
        for (c, values) in [red, green, blue].into_iter().enumerate() {
            if values.len() != MERL_BINS {
                return Err(Error::invalid(
                    format!("{} values", CHANNEL_NAMES[c]),
                    format!("{} values", values.len()),
                    format!("{MERL_BINS} values, one per MERL bin (90 θ_h × 90 θ_d × 180 φ_d)"),
                ));
            }
            let to_file = 1.0 / CHANNEL_SCALES[c];
            for (i, &x) in values.iter().enumerate() {
                let y = x * to_file;
                if !y.is_finite() {
                    return Err(Error::invalid(
                        format!(
                            "{} value of MERL bin {i} ({})",
                            CHANNEL_NAMES[c],
                            describe(i)
                        ),
                        x,
                        "a finite BRDF value in sr⁻¹",
                    ));
                }
                stored.push(y);
            }
        }
        Ok(MerlBrdf { stored })
    }

    /// The red, green and blue BRDF (sr⁻¹) of bin `index`: stored value × channel scale.
    ///
    /// # Panics
    /// If `index >= MERL_BINS`.
    #[inline]
    pub fn value(&self, index: usize) -> [f64; 3] {
        assert!(
            index < MERL_BINS,
            "MERL bin index {index} out of range 0..{MERL_BINS}"
        );
        [0, 1, 2].map(|c| self.stored[c * MERL_BINS + index] * CHANNEL_SCALES[c])
    }

    /// The red, green and blue BRDF (sr⁻¹, no cosine) for light from `s` seen from `v` (unit
    /// vectors in the local frame): the value of the bin that contains their coordinates, without
    /// interpolation, as the database's reader looks it up. 0 when either direction is at or
    /// below the horizon.
    pub fn lookup(&self, s: Vec3, v: Vec3) -> [f64; 3] {
        debug_assert!((s.length() - 1.0).abs() < 1e-6 && (v.length() - 1.0).abs() < 1e-6);
        if s.z <= 0.0 || v.z <= 0.0 {
            return [0.0; 3];
        }
        self.value(Bin::containing(&HalfDiff::from_directions(s, v)).index())
    }

    /// Writes the file (header and three blocks, [`FILE_SIZE`] bytes) to `w`.
    ///
    /// # Errors
    /// [`Error::Io`] (path `<writer>`) if writing fails.
    pub fn write(&self, w: impl Write) -> Result<()> {
        self.write_raw(w).map_err(|source| Error::Io {
            path: PathBuf::from("<writer>"),
            source,
        })
    }

    fn write_raw(&self, mut w: impl Write) -> io::Result<()> {
        // Encode in 64 KiB pieces: few write calls without a second copy of the table.
        const CHUNK: usize = 8192;
        let mut buf = Vec::with_capacity(8 * CHUNK);
        for d in DIMS {
            buf.extend_from_slice(&d.to_le_bytes());
        }
        for chunk in self.stored.chunks(CHUNK) {
            for x in chunk {
                buf.extend_from_slice(&x.to_le_bytes());
            }
            w.write_all(&buf)?;
            buf.clear();
        }
        w.flush()
    }

    /// Writes the file to `path` atomically: to a temporary file in the same folder, synced, then
    /// renamed over `path`, so `path` never holds a partial file.
    ///
    /// # Errors
    /// [`Error::Io`] naming `path` if the folder is not writable, writing fails or the rename
    /// fails; the temporary file is removed.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        crate::fsutil::atomic_write(path.as_ref(), |w| self.write_raw(w))
    }

    /// Reads a file from `r`.
    ///
    /// # Errors
    /// [`Error::Parse`] (path `<reader>`) for wrong dimensions, a truncated file, bytes after the
    /// blue block or a non-finite value; [`Error::Io`] if reading fails.
    pub fn read(r: impl Read) -> Result<Self> {
        Self::read_named(r, Path::new("<reader>"))
    }

    /// Reads the file at `path`.
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be opened or read; otherwise as [`read`](Self::read),
    /// naming `path`.
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        // A regular file only (a pipe with no writer would block the open); the reader
        // bounds what it reads by the header's counts.
        let (file, _) = crate::fsutil::open_regular(path, u64::MAX, "a MERL BRDF file")?;
        Self::read_named(file, path)
    }

    fn read_named(mut r: impl Read, name: &Path) -> Result<Self> {
        let io_error = |source| Error::Io {
            path: name.to_path_buf(),
            source,
        };
        let parse = |message: String| Error::Parse {
            path: name.display().to_string(),
            message,
        };

        // Header: three i32 dimensions.
        let mut header = Vec::with_capacity(HEADER_SIZE);
        (&mut r)
            .take(HEADER_SIZE as u64)
            .read_to_end(&mut header)
            .map_err(io_error)?;
        if header.len() < HEADER_SIZE {
            return Err(parse(format!(
                "truncated MERL BRDF file: {} bytes, shorter than the {HEADER_SIZE}-byte header",
                header.len()
            )));
        }
        let dims: [i32; 3] = [0, 1, 2]
            .map(|k| i32::from_le_bytes(header[4 * k..4 * k + 4].try_into().expect("4 bytes")));
        if dims != DIMS {
            return Err(parse(format!(
                "not a MERL BRDF file of the standard resolution: header dimensions {dims:?}, \
                 expected {DIMS:?} (θ_h, θ_d, φ_d bins, little-endian i32)"
            )));
        }

        // Three blocks of f64, then nothing.
        let body_size = FILE_SIZE - HEADER_SIZE;
        let mut body = Vec::with_capacity(body_size);
        (&mut r)
            .take(body_size as u64)
            .read_to_end(&mut body)
            .map_err(io_error)?;
        if body.len() < body_size {
            let values = body.len() / 8;
            return Err(parse(format!(
                "truncated MERL BRDF file: {} bytes, expected {FILE_SIZE}; it ends in the {} \
                 block at bin {}",
                HEADER_SIZE + body.len(),
                CHANNEL_NAMES[values / MERL_BINS],
                values % MERL_BINS
            )));
        }
        let mut extra = [0u8; 1];
        let more = loop {
            match r.read(&mut extra) {
                Ok(n) => break n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(io_error(e)),
            }
        };
        if more > 0 {
            return Err(parse(format!(
                "trailing bytes after the blue block: a MERL BRDF file is exactly {FILE_SIZE} bytes"
            )));
        }

        let mut stored = Vec::with_capacity(3 * MERL_BINS);
        for (k, bytes) in body.chunks_exact(8).enumerate() {
            let x = f64::from_le_bytes(bytes.try_into().expect("8 bytes"));
            if !x.is_finite() {
                let (c, i) = (k / MERL_BINS, k % MERL_BINS);
                return Err(parse(format!(
                    "non-finite value {x} in the {} block at bin {i} ({})",
                    CHANNEL_NAMES[c],
                    describe(i)
                )));
            }
            stored.push(x);
        }
        Ok(MerlBrdf { stored })
    }
}

/// A bin's indices, for error messages.
fn describe(index: usize) -> String {
    let b = Bin::from_index(index);
    format!(
        "θ_h bin {}, θ_d bin {}, φ_d bin {}",
        b.theta_h, b.theta_d, b.phi_d
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every bin's centre lies in its own bin, through the indices and through the directions.
    #[test]
    fn export_bin_centres_fall_in_their_bins() {
        let mut valid = 0;
        for i in 0..MERL_BINS {
            let bin = Bin::from_index(i);
            assert_eq!(bin.index(), i);
            assert_eq!(Bin::containing(&bin.center()), bin, "bin {i}");
            if let Some(d) = bin.directions() {
                valid += 1;
                let hd = HalfDiff::from_directions(d.s, d.v);
                assert_eq!(Bin::containing(&hd), bin, "bin {i} through its directions");
            }
        }
        assert_eq!(valid, MERL_BINS - 361_784, "valid bins");
    }

    /// The first and last bins of each coordinate, and the fold of φ_d.
    #[test]
    fn export_bin_edges() {
        let bin = |theta_h, theta_d, phi_d| {
            Bin::containing(&HalfDiff {
                theta_h,
                phi_h: 0.0,
                theta_d,
                phi_d,
            })
        };
        let b = bin(0.0, 0.0, 0.0);
        assert_eq!((b.theta_h, b.theta_d, b.phi_d), (0, 0, 0));
        let b = bin(FRAC_PI_2, FRAC_PI_2, PI);
        assert_eq!((b.theta_h, b.theta_d, b.phi_d), (89, 89, 0));
        // θ_h = (1/90)² π/2 starts bin 1; just below it is bin 0.
        let edge = FRAC_PI_2 / 8100.0;
        assert_eq!(bin(edge * 1.000001, 0.0, 0.0).theta_h, 1);
        assert_eq!(bin(edge * 0.999999, 0.0, 0.0).theta_h, 0);
        // φ_d + π and φ_d − π share φ_d's bin.
        let phi = 0.3;
        let want = bin(0.1, 0.1, phi).phi_d;
        assert_eq!(want, (0.3 / PI * 180.0) as usize);
        assert_eq!(bin(0.1, 0.1, phi + PI).phi_d, want);
        assert_eq!(bin(0.1, 0.1, phi - PI).phi_d, want);
        assert_eq!(bin(0.1, 0.1, -1e-300).phi_d, 179);
    }

    #[test]
    #[should_panic(expected = "out of range")]
    fn export_bin_index_out_of_range_panics() {
        Bin::from_index(MERL_BINS);
    }
}
