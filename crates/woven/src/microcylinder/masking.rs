//! Shadowing and masking (paper §5.1, Eqs. (10)–(11)) and the reweighting by apparent length
//! (§5.2, Eqs. (12)–(13)): both blend an uncorrelated product with a correlated bound, weighted
//! by a unit-height Gaussian of the angle between the two directions.

use super::frame::{psi_difference, ThreadAngles};

/// The standard deviation of the correlation weight `u`, 20° (the paper: "between 15° and 25°";
/// it uses 20°).
pub const CORRELATION_SIGMA: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// The unit-height Gaussian `u(x) = exp(−x²/(2σ²))`, `σ` = [`CORRELATION_SIGMA`]: 1 when the two
/// directions coincide (fully correlated), → 0 when they part.
///
/// ```
/// assert_eq!(woven::microcylinder::correlation(0.0), 1.0);
/// ```
#[inline]
pub fn correlation(x: f64) -> f64 {
    let z = x / CORRELATION_SIGMA;
    // Beyond 9σ, u < 3e-18: below f64's resolution of 1 − u.
    if z.abs() > 9.0 {
        return 0.0;
    }
    (-0.5 * z * z).exp()
}

/// The masking (or shadowing) of one direction by the neighbouring threads,
/// `M(t, ω) = max(cos φ, 0)`.
///
/// Implements Eq. (10) of the paper.
#[inline]
pub fn masking_one(w: &ThreadAngles) -> f64 {
    // cos φ = (ω·n_t)/cos θ; cos θ = 0 (ω along the tangent) is the limit cos φ → its sign.
    if w.cos_theta <= 0.0 {
        return 0.0;
    }
    (w.cos_n / w.cos_theta).clamp(0.0, 1.0)
}

/// The blend of an uncorrelated product and the perfectly correlated bound:
/// `(1 − u(x)) a b + u(x) min(a, b)`.
///
/// `min` is the Fréchet upper bound of the joint probability of two events of probabilities `a`
/// and `b`: perfectly correlated visibility from both directions (light and viewer at the same
/// place) is visible-and-lit exactly where the less visible of the two is visible
/// (Ashikhmin et al. 2000, whom the paper follows; docs/microcylinder.md §3 argues against `max`).
#[inline]
pub fn blend_correlated(a: f64, b: f64, x: f64) -> f64 {
    let u = correlation(x);
    (1.0 - u) * a * b + u * a.min(b)
}

/// The shadowing–masking of a pair, `M(t, ω_i, ω_r) = (1 − u(φ_d)) M(t, ω_i) M(t, ω_r)
/// + u(φ_d) min(M(t, ω_i), M(t, ω_r))`.
///
/// Implements Eq. (11) of the paper.
#[inline]
pub fn masking(i: &ThreadAngles, r: &ThreadAngles, phi_d: f64) -> f64 {
    blend_correlated(masking_one(i), masking_one(r), phi_d)
}

/// The apparent length of a tangent's stretch of thread seen from `ω`, `P(t, ω) = max(cos ψ, 0)`.
///
/// Implements Eq. (12) of the paper.
#[inline]
pub fn reweight_one(w: &ThreadAngles) -> f64 {
    w.cos_psi().max(0.0)
}

/// The reweighting of a pair, `P(t, ω_i, ω_r) = (1 − u(ψ_d)) P(t, ω_i) P(t, ω_r)
/// + u(ψ_d) min(P(t, ω_i), P(t, ω_r))`, the same blend as the masking.
///
/// Implements Eq. (13) of the paper.
#[inline]
pub fn reweight(i: &ThreadAngles, r: &ThreadAngles) -> f64 {
    let (a, b) = (reweight_one(i), reweight_one(r));
    if a == 0.0 || b == 0.0 {
        return 0.0; // both terms of the blend vanish
    }
    blend_correlated(a, b, psi_difference(i, r))
}
