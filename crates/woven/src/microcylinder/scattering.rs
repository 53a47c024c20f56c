//! The thread scattering function (paper §4.1, Eqs. (3)–(5)): a surface lobe reflected at the
//! fiber's surface and a volume lobe scattered inside it, both Gaussian in the half angle `θ_h`.

use super::frame::{PairAngles, ThreadAngles};
use crate::color::Rgb;
use crate::fiber::fresnel_dielectric;
use crate::math::special::exp_neg;
use std::f64::consts::PI;

/// The scattering parameters of one thread (a subset of [`Thread`](super::Thread)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScatteringParams {
    /// Relative refractive index `η`.
    pub eta: f64,
    /// The volume lobe's RGB albedo `A`.
    pub albedo: Rgb,
    /// The isotropic share `k_d` of the volume lobe.
    pub kd: f64,
    /// The surface lobe's width `γ_s`, radians.
    pub gamma_s: f64,
    /// The volume lobe's width `γ_v`, radians.
    pub gamma_v: f64,
}

/// The normalized zero-mean Gaussian `g(γ, x) = exp(−x²/(2γ²)) / (γ √(2π))` of the paper's
/// Eqs. (4)–(5) (`γ` the standard deviation, radians).
///
/// ```
/// use woven::microcylinder::gaussian;
/// let peak = 1.0 / (0.1 * (2.0 * std::f64::consts::PI).sqrt());
/// assert!((gaussian(0.1, 0.0) - peak).abs() < 1e-12);
/// ```
#[inline]
pub fn gaussian(gamma: f64, x: f64) -> f64 {
    let z = x / gamma;
    exp_neg(0.5 * z * z) / (gamma * (2.0 * PI).sqrt())
}

/// The surface lobe `f_r,s = F_r(η, ω_i) cos(φ_d/2) g(γ_s, θ_h)`.
///
/// Implements Eq. (4) of the paper. The Fresnel reflectance is taken at the angle of incidence
/// on the reflecting fiber surface, whose cosine is `cos θ_d cos(φ_d/2)` (the paper's note under
/// Eq. (4); as for Marschner et al.'s R lobe). `cos(φ_d/2) ≥ 0` for `φ_d ∈ [−π, π]`.
#[inline]
pub fn surface_lobe(p: &ScatteringParams, pair: &PairAngles) -> f64 {
    let cos_half_phi = pair.cos_half_phi_d;
    let cos_incidence = pair.cos_theta_d * cos_half_phi;
    fresnel_dielectric(cos_incidence, p.eta) * cos_half_phi * gaussian(p.gamma_s, pair.theta_h)
}

/// The volume lobe `f_r,v = F ((1 − k_d) g(γ_v, θ_h) + k_d) / (cos θ_i + cos θ_r) · A`.
///
/// Implements Eq. (5) of the paper, with `F = F_t(η, θ_i) F_t(η, θ_r)` the Fresnel
/// transmittances `1 − F_r` into and out of the fiber, each taken at its direction's longitudinal
/// angle (the incidence on the part of the fiber's surface that faces the direction; see
/// docs/microcylinder.md §2). 0 where both directions lie along the tangent (a set of measure
/// zero, where `cos θ_i + cos θ_r = 0`).
#[inline]
pub fn volume_lobe(
    p: &ScatteringParams,
    i: &ThreadAngles,
    r: &ThreadAngles,
    pair: &PairAngles,
) -> Rgb {
    let denom = i.cos_theta + r.cos_theta;
    if denom <= 0.0 {
        return Rgb::BLACK;
    }
    let transmit = (1.0 - fresnel_dielectric(i.cos_theta, p.eta))
        * (1.0 - fresnel_dielectric(r.cos_theta, p.eta));
    let lobe = (1.0 - p.kd) * gaussian(p.gamma_v, pair.theta_h) + p.kd;
    p.albedo * (transmit * lobe / denom)
}

/// The thread scattering function `f_s = (f_r,s + f_r,v) / cos² θ_d`, per unit length of thread
/// (the curve scattering function of the paper's Eq. (2)).
///
/// Implements Eq. (3) of the paper.
///
/// ```
/// use woven::color::Rgb;
/// use woven::microcylinder::{scattering, PairAngles, ScatteringParams, TangentFrame};
/// let p = ScatteringParams { eta: 1.46, albedo: Rgb::grey(0.3), kd: 0.3,
///     gamma_s: 0.2, gamma_v: 0.4 };
/// let f = TangentFrame::new(0, 0.0);
/// let (i, r) = (f.angles(woven::Vec3::new(0.6, 0.0, 0.8)), f.angles(woven::Vec3::new(-0.6, 0.0, 0.8)));
/// assert!(scattering(&p, &i, &r, &PairAngles::new(&i, &r)).is_valid());
/// ```
#[inline]
pub fn scattering(
    p: &ScatteringParams,
    i: &ThreadAngles,
    r: &ThreadAngles,
    pair: &PairAngles,
) -> Rgb {
    let cos_d = pair.cos_theta_d;
    // θ_d ∈ [−π/2, π/2]: cos θ_d = 0 only when ω_i = ±t and ω_r = ∓t (a set of measure zero).
    if cos_d <= 0.0 {
        return Rgb::BLACK;
    }
    (Rgb::grey(surface_lobe(p, pair)) + volume_lobe(p, i, r, pair)) * (1.0 / (cos_d * cos_d))
}
