//! Importance sampling of the microcylinder cloth and its [`Bsdf`] implementation
//! (docs/microcylinder.md §7).
//!
//! The unknown direction is drawn from a mixture: with probability [`COSINE_SHARE`] a
//! cosine-weighted hemisphere; otherwise a thread by its coverage, a tangent of its curve by
//! length (the quadrature's nodes and weights), and a direction near that tangent's specular
//! cone: `θ_h` from a logistic density of the surface lobe's width (truncated to the directions
//! that exist) and `φ_d` with density `cos(φ_d/2)/4`. The density [`Bsdf::pdf`] reports is the
//! mixture's, summed over every tangent.

use super::frame::{wrap_pi, TangentFrame, ThreadAngles};
use super::Microcylinder;
use crate::bsdf::{known_and_drawn, pair_of, Bsdf, BsdfSample, LobeFlags, Transport};
use crate::color::Rgb;
use crate::math::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use crate::math::Vec3;
use std::f64::consts::FRAC_PI_2;

/// The share of draws from the cosine-weighted hemisphere (the rest go to the specular cones).
pub const COSINE_SHARE: f64 = 0.5;

/// `√3/π`: a logistic density of scale `γ √3/π` has standard deviation `γ`.
const LOGISTIC_SCALE: f64 = 0.551_328_895_421_792_1;

/// The logistic CDF of scale `s`, `1/(1 + e^{−x/s})`, written with `tanh` (no overflow).
#[inline]
fn logistic_cdf(x: f64, s: f64) -> f64 {
    0.5 * (1.0 + (0.5 * x / s).tanh())
}

/// The range of `θ_h` whose drawn `θ = 2θ_h − θ_known` lies in `[−π/2, π/2]`.
#[inline]
fn theta_h_range(theta_known: f64) -> (f64, f64) {
    (
        0.5 * (theta_known - FRAC_PI_2),
        0.5 * (theta_known + FRAC_PI_2),
    )
}

/// Draws a direction near one tangent's specular cone for the known direction's angles `k`.
fn draw_cone(frame: &TangentFrame, k: &ThreadAngles, gamma: f64, u: [f64; 2]) -> Vec3 {
    let s = gamma * LOGISTIC_SCALE;
    let k_theta = k.theta();
    let (lo, hi) = theta_h_range(k_theta);
    let (c_lo, c_hi) = (logistic_cdf(lo, s), logistic_cdf(hi, s));
    // Inverse CDF, kept inside (0, 1) so the logarithm stays finite.
    let p = (c_lo + u[0] * (c_hi - c_lo)).clamp(1e-300, 1.0 - 1e-16);
    let theta_h = (s * (p / (1.0 - p)).ln()).clamp(lo, hi);
    let theta = 2.0 * theta_h - k_theta;
    // φ_d with density cos(φ_d/2)/4 on [−π, π]: CDF (1 + sin(φ_d/2))/2.
    let phi_d = 2.0 * (2.0 * u[1] - 1.0).clamp(-1.0, 1.0).asin();
    let phi = k.phi() + phi_d;
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    (frame.t * st + (frame.n * cp + frame.b * sp) * ct).normalize()
}

/// The density per unit solid angle of [`draw_cone`] at `d` (angles `a`) for the known `k`.
#[inline]
fn cone_pdf(k: &ThreadAngles, a: &ThreadAngles, gamma: f64) -> f64 {
    if a.cos_theta <= 0.0 {
        return 0.0; // along the tangent: a set of measure zero
    }
    let s = gamma * LOGISTIC_SCALE;
    let k_theta = k.theta();
    let (lo, hi) = theta_h_range(k_theta);
    let mass = logistic_cdf(hi, s) - logistic_cdf(lo, s);
    let theta_h = 0.5 * (a.theta() + k_theta);
    let c = logistic_cdf(theta_h, s);
    // Logistic density F(1 − F)/s in θ_h; θ = 2θ_h − θ_k halves it.
    let pdf_theta = 0.5 * c * (1.0 - c) / (s * mass);
    let pdf_phi = 0.25 * (0.5 * wrap_pi(a.phi() - k.phi())).cos().max(0.0);
    pdf_theta * pdf_phi / a.cos_theta
}

impl Microcylinder {
    /// The probability of each thread's cone lobe, given that a cone lobe is drawn.
    fn thread_shares(&self) -> [f64; 2] {
        let (a1, a2) = (self.prepared[0].coverage, self.prepared[1].coverage);
        let total = a1 + a2;
        if total > 0.0 {
            [a1 / total, a2 / total]
        } else {
            [0.0, 0.0]
        }
    }

    /// The density of [`Bsdf::sample`] drawing `drawn` for `known` (both unit), per unit solid
    /// angle; 0 when either is below the horizon.
    pub fn sample_pdf(&self, known: Vec3, drawn: Vec3) -> f64 {
        if known.z <= 0.0 || drawn.z <= 0.0 {
            return 0.0;
        }
        let shares = self.thread_shares();
        let cone_share = if shares[0] + shares[1] > 0.0 {
            1.0 - COSINE_SHARE
        } else {
            0.0
        };
        let mut cones = 0.0;
        for (thread, share) in self.prepared.iter().zip(shares) {
            if share == 0.0 {
                continue;
            }
            let mut sum = 0.0;
            for (frame, w) in thread.frames.iter().zip(&thread.weights) {
                sum += w * cone_pdf(
                    &frame.angles(known),
                    &frame.angles(drawn),
                    thread.params.gamma_s,
                );
            }
            cones += share * sum;
        }
        (1.0 - cone_share) * cosine_hemisphere_pdf(drawn.z) + cone_share * cones
    }

    /// Draws the unknown direction for `known` (see [`Bsdf::sample`]).
    fn draw(&self, known: Vec3, uc: f64, u: [f64; 2]) -> Option<(Vec3, LobeFlags)> {
        let shares = self.thread_shares();
        if uc < COSINE_SHARE || shares[0] + shares[1] == 0.0 {
            let d = cosine_hemisphere(u[0], u[1]);
            return Some((d, LobeFlags::REFLECTION | LobeFlags::DIFFUSE));
        }
        // Reuse uc: which thread, then which tangent by length.
        let mut v = (uc - COSINE_SHARE) / (1.0 - COSINE_SHARE);
        let j = usize::from(v >= shares[0]);
        v = if j == 0 {
            v / shares[0]
        } else {
            (v - shares[0]) / shares[1]
        };
        let thread = &self.prepared[j];
        let total = *thread.cdf.last()?;
        let n = thread
            .cdf
            .partition_point(|&c| c <= v.clamp(0.0, 1.0) * total)
            .min(thread.frames.len() - 1);
        let frame = &thread.frames[n];
        let d = draw_cone(frame, &frame.angles(known), thread.params.gamma_s, u);
        Some((d, LobeFlags::REFLECTION | LobeFlags::GLOSSY))
    }
}

/// The microcylinder cloth as a renderer's BSDF: [`eval`](Bsdf::eval) is the energy-guarded
/// BRDF [`Microcylinder::eval_rgb`]; the model is not reciprocal (the normalization divides by
/// `cos θ_i` and its gap term by `cos θ_r`), so the transport mode decides which direction is
/// drawn, and the value is always `f(wi, wo)`.
impl Bsdf for Microcylinder {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::GLOSSY | LobeFlags::DIFFUSE | LobeFlags::ANISOTROPIC
    }

    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        self.eval_rgb(wi, wo)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        self.sample_pdf(known, drawn)
    }

    fn sample(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Rgb>> {
        if known.z <= 0.0 {
            return None;
        }
        let (drawn, lobe) = self.draw(known, uc, u)?;
        if drawn.z <= 0.0 {
            return None; // a cone below the horizon: the draw is rejected
        }
        let pdf = self.sample_pdf(known, drawn);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let (wi, wo) = pair_of(known, drawn, mode);
        Some(BsdfSample {
            wo,
            wi,
            f: self.eval_rgb(wi, wo),
            pdf,
            lobe,
        })
    }
}
