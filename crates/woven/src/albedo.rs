//! Directional albedo of woven materials: `∫ f(s, v) cos θ_r dω_r` over the hemisphere
//! (docs/spec.md §6.2).
//!
//! The cloth BRDF is linear in its parts (Eqs. (18)–(23)), so the albedo is the same mix of the
//! albedos of single fiber orientations. For fibers along `e_f`, the reflected light gathers on
//! the specular cone `v·e_f = −s·e_f`, a ridge of width `≈ α`; the hemisphere is parametrized
//! around `e_f`, `v = cos χ e_f + sin χ (cos ω e_u + sin ω z)` (`v_z > 0` ⇔ `ω ∈ (0, π)`), with
//! `dω_r = sin χ dχ dω`, so the ridge is the line `χ = χ₀` and panels in `χ` resolve it.

use crate::fiber::FiberFrame;
use crate::math::quadrature::{adaptive, GaussLegendre};
use crate::math::Vec3;
use crate::yarn::Yarn;
use crate::Model;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;

fn rules() -> &'static (GaussLegendre, GaussLegendre) {
    static R: OnceLock<(GaussLegendre, GaussLegendre)> = OnceLock::new();
    R.get_or_init(|| (GaussLegendre::new(8), GaussLegendre::new(16)))
}

/// The directional albedo of `model` for light from `(theta_i, phi_i)`.
pub fn hemisphere_albedo(model: &Model, theta_i: f64, phi_i: f64) -> f64 {
    let s = Vec3::from_spherical(theta_i.min(FRAC_PI_2 - 1e-9), phi_i);
    match model.structure().yarns() {
        None => model.fiber().albedo(s.z),
        Some((yarn, axes)) => {
            // The weave mix (Eq. (23)) over fiber azimuths (Eqs. (21)–(22)), as the BRDF takes
            // it, with the fiber albedo in place of the fiber BRDF; then Eq. (20).
            let (_, gl) = rules();
            let oriented = yarn
                .orientation()
                .average(&axes, &[], gl, |phi_a| oriented_albedo(yarn, s, phi_a));
            let total_weight: f64 = axes.iter().map(|&(_, w)| w).sum();
            yarn.interreflection_mix_albedo(oriented, total_weight)
        }
    }
}

/// `∫ f_θ(s, v; φ_a) cos θ_r dω_r` for fibers at azimuth `phi_a`.
fn oriented_albedo(yarn: &Yarn, s: Vec3, phi_a: f64) -> f64 {
    let (gl_chi, _) = rules();
    let FiberFrame { e_f, e_u } = FiberFrame::new(phi_a);
    let chi0 = (-s.dot(e_f)).clamp(-1.0, 1.0).acos();
    let w = yarn.fiber().alpha().clamp(1e-3, 0.5);
    let mut edges = vec![0.0, PI];
    for k in [-16.0, -8.0, -4.0, -2.0, -1.0, 0.0, 1.0, 2.0, 4.0, 8.0, 16.0] {
        let e = chi0 + k * w;
        if e > 0.0 && e < PI {
            edges.push(e);
        }
    }
    edges.sort_by(f64::total_cmp);
    // In the cross-section the facet of angle θ mirrors s into ψ_v = 2θ − ψ_s, i.e.
    // ω = π/2 − 2θ + ψ_s: split there for the arc top (θ = 0) and the mean lateral slopes (±μ),
    // and integrate each ω panel adaptively (single profiles have sharp lateral highlights).
    let psi_s = FiberFrame::new(phi_a).projected_angle(s);
    let mu = yarn.params().slope_mean;
    let mut omega_breaks = vec![0.0, PI];
    for theta in [0.0, mu, -mu] {
        let w = FRAC_PI_2 - 2.0 * theta + psi_s;
        if w > 0.0 && w < PI {
            omega_breaks.push(w);
        }
    }
    omega_breaks.sort_by(f64::total_cmp);
    let mut total = 0.0;
    for e in edges.windows(2) {
        total += gl_chi.integrate(e[0], e[1], |chi| {
            let (sc, cc) = chi.sin_cos();
            let inner = |omega: f64| {
                let (so, co) = omega.sin_cos();
                let v = e_f * cc + (e_u * co + Vec3::Z * so) * sc;
                if v.z <= 0.0 {
                    return 0.0;
                }
                yarn.slope_averaged(s, v, phi_a) * v.z
            };
            let mut acc = 0.0;
            for b in omega_breaks.windows(2) {
                acc += adaptive(b[0], b[1], 1e-5, 1e-9, 12, inner);
            }
            sc * acc
        });
    }
    total
}
