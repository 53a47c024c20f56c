//! Measured reflectance: one type, [`Dataset`], whatever file it came from.
//!
//! Directions follow the rest of woven: `theta_i, phi_i` is the direction toward the light (the
//! paper's s), `theta_r, phi_r` the direction toward the viewer (v), polar angles from the macro
//! normal and azimuths from the weft (x) axis, in radians. Values are BRDFs in sr⁻¹ (f without the
//! cosine), or relatively calibrated ones when [`Dataset::relative`] says so.

use std::path::PathBuf;

/// A measured value: one channel, or red, green and blue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A single channel (a luminance or an average of channels).
    Mono(f64),
    /// Red, green and blue.
    Rgb([f64; 3]),
}

/// One measurement: a pair of directions, the value there and its weight in the fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Polar angle of the direction toward the light, radians.
    pub theta_i: f64,
    /// Azimuth of the direction toward the light, radians from the weft (x) axis.
    pub phi_i: f64,
    /// Polar angle of the direction toward the viewer, radians.
    pub theta_r: f64,
    /// Azimuth of the direction toward the viewer, radians from the weft (x) axis.
    pub phi_r: f64,
    /// The BRDF there, sr⁻¹ (or relative units; see [`Dataset::relative`]).
    pub value: Value,
    /// Weight of the sample in the objective (1 unless the file gives one).
    pub weight: f64,
}

/// A set of measurements of one material.
#[derive(Clone, Debug)]
pub struct Dataset {
    /// A short name (the file's stem unless the format names the material).
    pub name: String,
    /// Where it came from (the file).
    pub source: PathBuf,
    /// The measurements above the horizon, in file order.
    pub samples: Vec<Sample>,
    /// Rows dropped because a direction was at or below the horizon.
    pub dropped_below_horizon: usize,
    /// True when the values are calibrated only up to an unknown factor (a fit then frees an
    /// overall scale by default).
    pub relative: bool,
}
