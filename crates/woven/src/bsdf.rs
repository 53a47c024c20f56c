//! The renderer-facing interface: evaluation, importance sampling and densities.
//!
//! Directions live in the cloth's local frame (docs/spec.md §0; `docs/conventions.md`): `z` is the
//! macro normal, the weft runs along `x`. `s` points toward the light (a renderer's `wi`), `v`
//! toward the viewer (`wo`), both away from the surface. `eval` is the BRDF in sr⁻¹ without the
//! cosine; `pdf` is a density per unit solid angle.
//!
//! Sampling draws `v` for a given `s`, proportionally to `f(s, v) cos θ_r` (as the tabulated
//! sampler does). In `normalization = "none"` the model is reciprocal, so the same call samples
//! `wi` for a given `wo` by swapping the roles; in `paper` mode the asymmetry is `β(θ_i)` only.

use crate::math::Vec3;
use crate::Model;
use std::f64::consts::{FRAC_1_PI, PI};

/// A sampled direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The sampled direction (toward the viewer), unit, `v_z > 0`.
    pub v: Vec3,
    /// `f(s, v)`, sr⁻¹.
    pub f: f64,
    /// The density of `v`, per unit solid angle.
    pub pdf: f64,
    /// `f(s, v) cos θ_r / pdf`.
    pub weight: f64,
}

/// A BSDF as a renderer uses it. Implementations are `Send + Sync` and allocate nothing per call.
pub trait Bsdf: Send + Sync {
    /// The BRDF `f(s, v)`, sr⁻¹, 0 below the horizon.
    fn eval(&self, s: Vec3, v: Vec3) -> f64;

    /// Draws `v` for light from `s` from two uniforms in `[0, 1)`; deterministic in `(u1, u2)`.
    /// `None` when no direction results (light below the horizon, or a rejected draw).
    fn sample(&self, s: Vec3, u1: f64, u2: f64) -> Option<BsdfSample>;

    /// The density [`sample`](Bsdf::sample) draws `v` with, per unit solid angle.
    fn pdf(&self, s: Vec3, v: Vec3) -> f64;
}

/// The exact model samples a cosine-weighted hemisphere: correct for any material, with a density
/// that ignores the highlights. Renderers should sample a [`Table`](crate::table::Table).
impl Bsdf for Model {
    #[inline]
    fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        Model::eval(self, s, v)
    }

    fn sample(&self, s: Vec3, u1: f64, u2: f64) -> Option<BsdfSample> {
        if s.z <= 0.0 {
            return None;
        }
        // Malley's method: a uniform point on the disc lifted to the hemisphere.
        let r = u1.clamp(0.0, 1.0).sqrt();
        let phi = 2.0 * PI * u2;
        let z = (1.0 - r * r).max(0.0).sqrt();
        if z <= 0.0 {
            return None;
        }
        let v = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        let f = Model::eval(self, s, v);
        let pdf = z * FRAC_1_PI;
        Some(BsdfSample {
            v,
            f,
            pdf,
            weight: f * z / pdf,
        })
    }

    #[inline]
    fn pdf(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            0.0
        } else {
            v.z * FRAC_1_PI
        }
    }
}
