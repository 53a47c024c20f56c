//! Directional albedo by quadrature, and the energy guard that keeps it at most 1
//! (docs/microcylinder.md §6).
//!
//! The printed normalization divides by `cos θ_i`, and where a tangent tilts toward grazing
//! light (velvet's upright pile, satin's tilted floats) the albedo of the shading model exceeds 1
//! at `θ_i ≳ 80°`. The guard scales the BRDF by a factor of `θ_i` alone,
//! `k(θ_i) = min(1, cos θ_i / ((1 + margin) h(θ_i)))`, with `h(θ_i) = cos θ_i · max_φi A(θ_i, φ_i)`
//! the largest channel's albedo times `cos θ_i` — bounded and smooth up to the horizon, unlike
//! the albedo — tabulated at build on a grid of `θ_i` and `φ_i` and interpolated conservatively
//! (the larger of the two neighbouring nodes).

use crate::color::Rgb;
use crate::math::quadrature::GaussLegendre;
use crate::math::Vec3;
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// The polar angles (degrees) at which the guard measures the albedo: sparse where every
/// preset's albedo is far below 1, dense toward grazing where it grows as `1/cos θ_i`.
pub const GUARD_THETA_DEG: [f64; 13] = [
    0.0, 40.0, 60.0, 70.0, 75.0, 79.0, 82.0, 84.0, 86.0, 87.5, 88.5, 89.3, 89.9,
];

/// Azimuths of light at which a fabric built from its threads measures its guard's albedo, every
/// 15° around the circle (a fraction of a second to a few seconds).
pub const GUARD_PHI_COUNT: usize = 24;

/// Headroom of that guard over the measured albedo: it covers the quadrature's error, the albedo
/// between the grid's azimuths (which varies sharply with azimuth at grazing light) and the
/// interpolation between its polar angles.
pub const GUARD_MARGIN: f64 = 0.25;

/// Azimuths of the presets' guards, measured once (`examples/microcylinder_guard`) and stored
/// with the presets: every 7.5°, so a small margin suffices.
pub const PRESET_GUARD_PHI_COUNT: usize = 48;

/// Headroom of the presets' guards.
pub const PRESET_GUARD_MARGIN: f64 = 0.08;

/// Panels of 8 Gauss–Legendre points in `θ_o` and in `φ_o` of [`albedo_quadrature`] for
/// [`Microcylinder::albedo`](super::Microcylinder::albedo).
pub const ALBEDO_PANELS: (usize, usize) = (8, 16);

/// `∫ f(ω_o) cos θ_o dω_o` over the upper hemisphere by a product Gauss–Legendre rule in
/// `(θ_o, φ_o)`, `panels.0` panels in `θ_o` and `panels.1` in `φ_o`, 8 points each.
pub fn albedo_quadrature(f: impl Fn(Vec3) -> Rgb, panels: (usize, usize)) -> Rgb {
    let gl = GaussLegendre::new(8);
    let mut sum = Rgb::BLACK;
    let (nt, np) = (panels.0.max(1), panels.1.max(1));
    let (ht, hp) = (FRAC_PI_2 / nt as f64, 2.0 * PI / np as f64);
    for a in 0..nt {
        for (x, wx) in gl.nodes().iter().zip(gl.weights()) {
            let theta = (a as f64 + 0.5 * (x + 1.0)) * ht;
            let (st, ct) = theta.sin_cos();
            let wt = 0.5 * ht * wx * st * ct;
            for b in 0..np {
                for (y, wy) in gl.nodes().iter().zip(gl.weights()) {
                    let phi = (b as f64 + 0.5 * (y + 1.0)) * hp;
                    let (sp, cp) = phi.sin_cos();
                    let wo = Vec3::new(st * cp, st * sp, ct);
                    sum += f(wo) * (wt * 0.5 * hp * wy);
                }
            }
        }
    }
    sum
}

/// `cos θ_i` times the largest channel of the albedo of `f` for light at `theta_deg` and the
/// `j`-th of `phi_count` azimuths: one entry of a guard's measurement, before the maximum over
/// azimuths.
pub fn h_at(
    f: &(impl Fn(Vec3, Vec3) -> Rgb + Sync),
    theta_deg: f64,
    j: usize,
    phi_count: usize,
) -> f64 {
    let theta = theta_deg.to_radians();
    let phi = 2.0 * PI * j as f64 / phi_count as f64;
    let wi = Vec3::from_spherical(theta, phi);
    albedo_quadrature(|wo| f(wi, wo), ALBEDO_PANELS).max() * theta.cos()
}

/// The energy guard: `k(θ_i)` tabulated at build.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyGuard {
    /// `h(θ_k) = cos θ_k · max_φ max_channel A(θ_k, φ)` at [`GUARD_THETA_DEG`].
    h: Vec<f64>,
    /// The headroom over `h`.
    margin: f64,
}

impl EnergyGuard {
    /// No guard (`k ≡ 1`).
    pub fn none() -> EnergyGuard {
        EnergyGuard {
            h: Vec::new(),
            margin: 0.0,
        }
    }

    /// A guard from a stored table `h` (at [`GUARD_THETA_DEG`]) and its `margin`.
    pub fn from_table(h: &[f64], margin: f64) -> EnergyGuard {
        EnergyGuard {
            h: h.to_vec(),
            margin,
        }
    }

    /// Measures `h` of the unguarded BRDF `f(wi, wo)` at `phi_count` azimuths of light (in
    /// parallel), with headroom `margin`.
    pub fn build(
        f: &(impl Fn(Vec3, Vec3) -> Rgb + Sync),
        phi_count: usize,
        margin: f64,
    ) -> EnergyGuard {
        let cases: Vec<(usize, usize)> = (0..GUARD_THETA_DEG.len())
            .flat_map(|k| (0..phi_count).map(move |j| (k, j)))
            .collect();
        let values: Vec<f64> = cases
            .par_iter()
            .map(|&(k, j)| h_at(f, GUARD_THETA_DEG[k], j, phi_count))
            .collect();
        let mut h = vec![0.0f64; GUARD_THETA_DEG.len()];
        for (&(k, _), v) in cases.iter().zip(&values) {
            h[k] = h[k].max(*v);
        }
        EnergyGuard { h, margin }
    }

    /// The tabulated `h(θ_k)` (empty for no guard).
    pub fn table(&self) -> &[f64] {
        &self.h
    }

    /// The factor `k(θ_i) ∈ (0, 1]` for light at `cos θ_i` (`> 0`).
    #[inline]
    pub fn factor(&self, cos_theta_i: f64) -> f64 {
        if self.h.is_empty() {
            return 1.0;
        }
        let theta = cos_theta_i.clamp(0.0, 1.0).acos().to_degrees();
        let k = GUARD_THETA_DEG.partition_point(|&t| t <= theta);
        // The larger h of the bracketing nodes (the last node's beyond the grid).
        let h = match k {
            0 => self.h[0],
            k if k >= self.h.len() => self.h[self.h.len() - 1],
            k => self.h[k - 1].max(self.h[k]),
        };
        let bound = (1.0 + self.margin) * h;
        if bound <= cos_theta_i {
            1.0
        } else {
            cos_theta_i / bound
        }
    }
}
