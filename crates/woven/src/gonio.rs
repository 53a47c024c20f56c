//! The paper's virtual goniometer (§4, Fig. 7; docs/spec.md §4): the geometry of light, sensor and
//! sample, shared by the command-line tool, fitters and renderers.
//!
//! Light and sensor are fixed 90° apart. The sample turns about its normal to the sample azimuth
//! `A` and tilts by `t` in the plane of light and sensor, so that in the cloth's frame
//!
//! - `θi = 45° + t`, `θr = 45° − t`,
//! - `φi = A`, `φr = A + 180°` (light and sensor in one plane through the normal),
//!
//! `A = 0` putting the weft (`x`) in that plane, `A = 90°` the warp (`y`). The sensor records the
//! radiance `L = f(s, v) · I0 cos θi`; we report it for unit irradiance `I0 = 1`, in sr⁻¹.
//! `t` must lie in `(−45°, 45°)`: at ±45° light or sensor grazes the sample.

use crate::bsdf::Bsdf;
use crate::Vec3;

/// The half-angle between light and sensor, degrees: they are 90° apart.
pub const HALF_ANGLE_DEG: f64 = 45.0;

/// The paper's tilt steps, degrees: −42° to 42° by 3° (§4).
pub fn paper_tilts_deg() -> Vec<f64> {
    (-14..=14).map(|k| 3.0 * k as f64).collect()
}

/// One goniometer reading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// Sample azimuth `A`, degrees (as given).
    pub azimuth_deg: f64,
    /// Sample tilt `t`, degrees (as given).
    pub tilt_deg: f64,
    /// Polar angle of the light in the cloth frame, radians: `45° + t`.
    pub theta_i: f64,
    /// Polar angle of the sensor in the cloth frame, radians: `45° − t`.
    pub theta_r: f64,
    /// `f(s, v) cos θi`, sr⁻¹: the radiance for unit irradiance.
    pub radiance: f64,
}

/// The directions `(s, v)` toward the light and the sensor, in the cloth frame, for sample
/// azimuth `azimuth_deg` and tilt `tilt_deg` (degrees, `|t| < 45°`).
pub fn directions(azimuth_deg: f64, tilt_deg: f64) -> (Vec3, Vec3) {
    debug_assert!(tilt_deg.abs() < HALF_ANGLE_DEG, "tilt {tilt_deg}° grazes");
    let phi_i = azimuth_deg.to_radians();
    let s = Vec3::from_spherical((HALF_ANGLE_DEG + tilt_deg).to_radians(), phi_i);
    let v = Vec3::from_spherical(
        (HALF_ANGLE_DEG - tilt_deg).to_radians(),
        phi_i + std::f64::consts::PI,
    );
    (s, v)
}

/// The reading of `model` at sample azimuth `azimuth_deg` and tilt `tilt_deg` (degrees). Any
/// single-valued BSDF reads: a woven [`Model`](crate::Model), a table, or a colour BSDF (a
/// microcylinder fabric) as its [`Luminance`](crate::catalog::Luminance).
pub fn read<B: Bsdf<Value = f64> + ?Sized>(model: &B, azimuth_deg: f64, tilt_deg: f64) -> Reading {
    let (s, v) = directions(azimuth_deg, tilt_deg);
    let theta_i = (HALF_ANGLE_DEG + tilt_deg).to_radians();
    Reading {
        azimuth_deg,
        tilt_deg,
        theta_i,
        theta_r: (HALF_ANGLE_DEG - tilt_deg).to_radians(),
        radiance: model.eval(s, v) * theta_i.cos(),
    }
}

/// The `(azimuth, tilt)` pairs of a sweep, degrees: every azimuth (outer loop) with every tilt
/// (inner loop), the order in which a sweep reports its readings.
pub fn sweep_grid(azimuths_deg: &[f64], tilts_deg: &[f64]) -> Vec<(f64, f64)> {
    azimuths_deg
        .iter()
        .flat_map(|&a| tilts_deg.iter().map(move |&t| (a, t)))
        .collect()
}

/// The readings of `model` over [`sweep_grid`]`(azimuths_deg, tilts_deg)`, in that order,
/// computed over all cores (rayon); `progress` is called once per reading, from any thread.
pub fn sweep<B: Bsdf<Value = f64> + ?Sized>(
    model: &B,
    azimuths_deg: &[f64],
    tilts_deg: &[f64],
    progress: impl Fn() + Sync,
) -> Vec<Reading> {
    use rayon::prelude::*;
    sweep_grid(azimuths_deg, tilts_deg)
        .par_iter()
        // One reading costs up to a few milliseconds for cloth: small tasks balance the cores.
        .with_max_len(4)
        .map(|&(a, t)| {
            let r = read(model, a, t);
            progress();
            r
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn geometry_matches_the_paper() {
        // Light and sensor are 90° apart whatever the tilt and azimuth.
        for (a, t) in [(0.0, 0.0), (45.0, -30.0), (90.0, 42.0), (-20.0, 10.0)] {
            let (s, v) = directions(a, t);
            assert!(s.dot(v).abs() < 1e-12, "A {a} t {t}: s·v = {}", s.dot(v));
            let (ti, pi) = s.to_spherical();
            let (tr, pr) = v.to_spherical();
            assert!((ti - (45.0 + t).to_radians()).abs() < 1e-12);
            assert!((tr - (45.0 - t).to_radians()).abs() < 1e-12);
            // Opposite azimuths: one plane through the normal.
            let dphi = (pr - pi).rem_euclid(2.0 * PI);
            assert!((dphi - PI).abs() < 1e-9, "Δφ = {dphi}");
        }
        // A = 0: the plane holds the weft (x); A = 90°: the warp (y).
        let (s, v) = directions(0.0, 10.0);
        assert!(s.y.abs() < 1e-15 && v.y.abs() < 1e-15 && s.x > 0.0);
        let (s, v) = directions(90.0, 10.0);
        assert!(s.x.abs() < 1e-15 && v.x.abs() < 1e-15 && s.y > 0.0);
    }
}
