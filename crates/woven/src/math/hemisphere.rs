//! Integrals over the reflected hemisphere in half-vector coordinates (docs/spec.md §1.5).
//!
//! For a lobe of width `α` around the mirror direction, integrating over `v` directly misses the
//! peak when `α` is small. With the half vector `h` of `s` and `v`, `dω_r = 4 (s·h) dω_h`, and the
//! lobe becomes a bump of width `α` around `h = z`. The valid `h` are those whose mirror image
//! `v = 2(s·h)h − s` lies above the surface: for azimuth `φ_h` (relative to `s`) they are
//! `θ_h < θ_max(φ_h) = (π/2 + atan2(sin θ_i cos φ_h, cos θ_i)) / 2` (derived from
//! `v_z = cos θ_i cos 2θ_h + sin θ_i cos φ_h sin 2θ_h > 0`). At grazing incidence `θ_max`
//! switches from `π/2` to near 0 over a width `~cot θ_i` around `φ_h = π/2`; the `φ_h` integral is
//! split there and adaptive.

use super::quadrature::adaptive;
use super::Vec3;
use std::f64::consts::{FRAC_PI_2, PI};

/// `∫_{H²} f(v) cos θ_r dω_r` for light from `s = (sin θ_i, 0, cos θ_i)`, `cos_theta_i ∈ (0, 1]`.
///
/// `width` is the lobe's half-vector width (Beckmann `α`); `f` receives `(s, v, h)`.
/// `f` must be even in `v_y` (isotropic about the normal, as every fiber BRDF is): only
/// `φ_h ∈ [0, π]` is integrated, then doubled. Relative accuracy about `rel_tol`.
pub fn reflected_hemisphere_integral(
    cos_theta_i: f64,
    width: f64,
    rel_tol: f64,
    f: impl Fn(Vec3, Vec3, Vec3) -> f64,
) -> f64 {
    let ci = cos_theta_i.clamp(1e-12, 1.0);
    let si = (1.0 - ci * ci).max(0.0).sqrt();
    let s = Vec3::new(si, 0.0, ci);
    // Panel edges in x = tan θ_h: geometric around the lobe width, to resolve the peak.
    let edges = |x_max: f64| {
        let mut e = vec![0.0];
        let mut x = 0.25 * width;
        while x < x_max {
            e.push(x);
            x *= 2.0;
        }
        e.push(x_max);
        e
    };
    let inner = |phi: f64| -> f64 {
        let (sp, cp) = phi.sin_cos();
        let theta_max = 0.5 * (FRAC_PI_2 + (si * cp).atan2(ci));
        // θ_max = π/2 only when φ = 0 at exact grazing; stop just short (x is finite).
        let x_max = theta_max.min(FRAC_PI_2 - 1e-9).tan();
        if x_max <= 0.0 {
            return 0.0;
        }
        // Panels run outward from the peak; once the peak is summed, later panels (the tail)
        // need only an absolute accuracy relative to that sum, not to their own tiny values.
        let mut sum: f64 = 0.0;
        for w in edges(x_max).windows(2) {
            sum += adaptive(
                w[0],
                w[1],
                rel_tol * 0.1,
                rel_tol * 0.1 * sum.abs(),
                30,
                |x: f64| {
                    // dω_h = sin θ_h dθ_h dφ = x/(1+x²)^{3/2} dx dφ.
                    let c = 1.0 / (1.0 + x * x).sqrt();
                    let st = x * c;
                    let h = Vec3::new(st * cp, st * sp, c);
                    let sh = s.dot(h);
                    let v = h * (2.0 * sh) - s;
                    if v.z <= 0.0 || sh <= 0.0 {
                        return 0.0;
                    }
                    f(s, v, h) * v.z * 4.0 * sh * x * c * c * c
                },
            );
        }
        sum
    };
    // The φ_h boundary switch sits at π/2 with width ~cot θ_i: split there and grade around it.
    let w = (ci / si.max(1e-300)).clamp(1e-6, 0.5);
    // Clamping keeps the list sorted; empty panels are skipped.
    let breaks = [f64::NEG_INFINITY, -4.0, -1.0, 0.0, 1.0, 4.0, f64::INFINITY]
        .map(|k: f64| (FRAC_PI_2 + k * w).clamp(0.0, PI));
    let mut total = 0.0;
    for b in breaks.windows(2) {
        if b[1] > b[0] {
            total += adaptive(b[0], b[1], rel_tol, 0.0, 30, inner);
        }
    }
    2.0 * total
}
