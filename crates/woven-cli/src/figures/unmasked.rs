//! A reference for Fig. 8: the slope-averaged yarn BRDF with inter-facet masking and shadowing
//! switched off, so that a figure (and its tests) can measure how much masking the model applies.
//!
//! The library computes `f_θ = ∫ P(θa) f_p(θa) dθa` with the exact lit-and-visible indicator `V`
//! of Eq. (17) (docs/spec.md §2.2–2.4). Here `V` keeps only the local conditions `s·a > 0`, `v·a > 0`
//! (a facet facing away from the light or the viewer is dark either way); no facet hides
//! another. The integrals are brute-force midpoint rules built from the library's public pieces
//! (the fiber BRDF at a facet normal, the slope density), independent of the library's own
//! quadrature: `f_θ` with masking off equals the library's `f_θ` wherever nothing is masked
//! (e.g. light and viewer in the plane along the fibers, `ψ = 0`), which the tests check.
//!
//! Accuracy: the facet integral uses [`FACET_CELLS`] cells over `θ ∈ [−π/2, π/2]` (the fiber
//! lobe, `≈ α` wide, spans hundreds of cells for the presets' `α ≥ 0.1`) and the slope integral
//! [`SLOPE_CELLS`] cells; the result is good to about 1e-4 relative. This belongs in the library
//! (a `masking: off` switch of the profile integral); until then it lives here.

use std::f64::consts::{FRAC_PI_2, PI};
use woven::fiber::Fiber;
use woven::yarn::{SlopeDistribution, YarnParams};
use woven::Vec3;

/// Midpoint cells of the facet-normal integral over `θ ∈ [−π/2, π/2]`.
pub const FACET_CELLS: usize = 8192;
/// Midpoint cells of the slope integral over `θa ∈ [0, π/2]`.
pub const SLOPE_CELLS: usize = 2048;

/// `f_θ(s, v)` of fibers at azimuth `phi_a` (radians) with masking and shadowing between facets
/// switched off (see the module docs). `s`, `v` in the cloth frame, both above the surface.
pub fn slope_averaged_unmasked(
    fiber: &Fiber,
    yarn: &YarnParams,
    s: Vec3,
    v: Vec3,
    phi_a: f64,
) -> f64 {
    if s.z <= 0.0 || v.z <= 0.0 {
        return 0.0;
    }
    // The facet of normal angle θ in the cross-section: a = sin θ e_u + cos θ z, weighted by both
    // cosines (0 when it faces away from either direction).
    let e_u = Vec3::new(-phi_a.sin(), phi_a.cos(), 0.0);
    let g = |theta: f64| -> f64 {
        let a = e_u * theta.sin() + Vec3::Z * theta.cos();
        let (sa, va) = (s.dot(a), v.dot(a));
        if sa <= 0.0 || va <= 0.0 {
            0.0
        } else {
            fiber.eval_with_normal(s, v, a) * sa * va
        }
    };
    // Running integral G(θ) = ∫_{−π/2}^{θ} g, tabulated at the cell edges.
    let h = PI / FACET_CELLS as f64;
    let mut running = Vec::with_capacity(FACET_CELLS + 1);
    running.push(0.0);
    let mut sum = 0.0;
    for k in 0..FACET_CELLS {
        sum += g(-FRAC_PI_2 + (k as f64 + 0.5) * h) * h;
        running.push(sum);
    }
    let integral_to = |theta: f64| -> f64 {
        let x = ((theta + FRAC_PI_2) / h).clamp(0.0, FACET_CELLS as f64);
        let k = (x.floor() as usize).min(FACET_CELLS - 1);
        running[k] + (running[k + 1] - running[k]) * (x - k as f64)
    };

    // One profile (docs/spec.md §2.3 with V = 1 on facing facets): the arc [−θa, θa] and two
    // laterals of length L at normals ±θa, over the period P, per unit projected area.
    let length = yarn.lateral_length;
    let profile = |theta_a: f64| -> f64 {
        let period = 2.0 * (length * theta_a.cos() + theta_a.sin());
        // A profile of zero period (θa = 0, L = 0) is the flat surface.
        if period < 1e-12 {
            return fiber.eval(s, v);
        }
        let facets =
            integral_to(theta_a) - integral_to(-theta_a) + length * (g(theta_a) + g(-theta_a));
        facets / (period * s.z * v.z)
    };
    let slopes = SlopeDistribution::new(yarn.slope_mean, yarn.slope_std);
    if let Some(mu) = slopes.single() {
        return profile(mu);
    }
    let dh = FRAC_PI_2 / SLOPE_CELLS as f64;
    (0..SLOPE_CELLS)
        .map(|j| {
            let theta_a = (j as f64 + 0.5) * dh;
            slopes.density(theta_a) * profile(theta_a) * dh
        })
        .sum()
}
