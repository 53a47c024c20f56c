//! An anisotropic GGX (Trowbridge–Reitz) specular lobe on a dielectric, its roughness `α_x`
//! along the tangent `x` and `α_y` across it: the lobe every renderer carries (Cycles'
//! `microfacet("ggx", …)` with a tangent, OpenPBR's `specular_roughness_anisotropy`, glTF's
//! `KHR_materials_anisotropy`), which a woven yarn's sheen is projected onto, its tangent along
//! the yarn.
//!
//! ```text
//! D(m)  = 1 / (π α_x α_y (m_x²/α_x² + m_y²/α_y² + m_z²)²)          (∫ D cos θm dω = 1)
//! Λ(w)  = (√(1 + (α_x² w_x² + α_y² w_y²)/w_z²) − 1) / 2
//! f     = F(wi·h) D(h) / (4 cos θi cos θo (1 + Λ(wi) + Λ(wo)))   (height-correlated Smith)
//! ```
//!
//! `F` is the exact dielectric Fresnel of index `η`, `h` the half vector. With `α_x = α_y` it is
//! the isotropic GGX of [`Distribution::Ggx`](super::Distribution::Ggx).

use crate::error::{check_range, Result};
use crate::fiber::fresnel_dielectric;
use crate::math::Vec3;
use std::f64::consts::PI;

/// The smallest roughness `α` of an [`AnisotropicGgx`]: below it the lobe is a near-mirror that
/// a renderer samples as a delta.
pub const MIN_GGX_ALPHA: f64 = 1e-3;

/// An anisotropic GGX lobe (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnisotropicGgx {
    alpha: [f64; 2],
    eta: f64,
}

impl AnisotropicGgx {
    /// The lobe of roughness `alpha_x` along the tangent and `alpha_y` across it, each in
    /// `[MIN_GGX_ALPHA, 1]`, on a dielectric of index `eta` in `[1, 3]`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `alpha_x`, `alpha_y`
    /// or `eta` out of its range.
    ///
    /// ```
    /// use woven::baseline::AnisotropicGgx;
    /// use woven::Vec3;
    /// // Smooth along the tangent (x), rough across it.
    /// let lobe = AnisotropicGgx::new(0.1, 0.4, 1.5)?;
    /// let wi = Vec3::from_spherical(0.5, 0.0);
    /// let mirror = Vec3::from_spherical(0.5, std::f64::consts::PI);
    /// // Turned 0.15 rad off the mirror direction along x, and as far across it (y).
    /// let along = Vec3::from_spherical(0.65, std::f64::consts::PI);
    /// let across = (mirror + Vec3::new(0.0, 0.15, 0.0)).normalize();
    /// // The highlight stretches across the tangent.
    /// assert!(lobe.eval(wi, across) > 2.0 * lobe.eval(wi, along));
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn new(alpha_x: f64, alpha_y: f64, eta: f64) -> Result<AnisotropicGgx> {
        let alpha_x = check_range("alpha_x", alpha_x, MIN_GGX_ALPHA, 1.0)?;
        let alpha_y = check_range("alpha_y", alpha_y, MIN_GGX_ALPHA, 1.0)?;
        let eta = check_range("eta", eta, 1.0, 3.0)?;
        Ok(AnisotropicGgx {
            alpha: [alpha_x, alpha_y],
            eta,
        })
    }

    /// `(α_x, α_y)`.
    pub fn alpha(&self) -> [f64; 2] {
        self.alpha
    }

    /// The index of refraction.
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// `D(m)` for a unit normal `m` (0 at or below the horizon), sr⁻¹.
    #[inline]
    pub fn d(&self, m: Vec3) -> f64 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let [ax, ay] = self.alpha;
        let k = (m.x / ax).powi(2) + (m.y / ay).powi(2) + m.z * m.z;
        1.0 / (PI * ax * ay * k * k)
    }

    /// Smith's `Λ` of a unit direction `w` above the horizon.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f64 {
        let [ax, ay] = self.alpha;
        let t2 = ((ax * w.x).powi(2) + (ay * w.y).powi(2)) / (w.z * w.z);
        0.5 * ((1.0 + t2).sqrt() - 1.0)
    }

    /// `f(wi, wo)`, sr⁻¹ without the cosine; 0 where either is at or below the horizon.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let h = (wi + wo).normalize();
        let g2 = 1.0 / (1.0 + self.lambda(wi) + self.lambda(wo));
        fresnel_dielectric(wi.dot(h), self.eta) * self.d(h) * g2 / (4.0 * wi.z * wo.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::baseline::Distribution;

    /// `∫ g(θ, φ) sin θ dθ dφ` over the hemisphere by a midpoint rule in `cos θ` and `φ`.
    fn hemisphere(n: usize, g: impl Fn(Vec3) -> f64) -> f64 {
        let mut sum = 0.0;
        for i in 0..n {
            let mu = (i as f64 + 0.5) / n as f64;
            for j in 0..2 * n {
                let phi = PI * (j as f64 + 0.5) / n as f64;
                sum += g(Vec3::from_spherical(mu.acos(), phi));
            }
        }
        sum * 2.0 * PI / (2 * n * n) as f64
    }

    #[test]
    fn the_distribution_is_normalized_and_masks_as_smith_says() {
        for (ax, ay) in [(0.3, 0.3), (0.2, 0.6), (0.8, 0.25)] {
            let lobe = AnisotropicGgx::new(ax, ay, 1.5).unwrap();
            let norm = hemisphere(800, |m| lobe.d(m) * m.z);
            assert!((norm - 1.0).abs() < 2e-3, "α {ax}, {ay}: ∫ D cos = {norm}");
            // Smith's identity: the projected area of the visible facets is the macro area's,
            // ∫ G1(w) ⟨w·m⟩ D(m) dm = cos θw, G1 = 1/(1 + Λ(w)).
            for w in [
                Vec3::from_spherical(0.4, 0.3),
                Vec3::from_spherical(1.2, 2.0),
            ] {
                let g1 = 1.0 / (1.0 + lobe.lambda(w));
                let seen = hemisphere(800, |m| g1 * w.dot(m).max(0.0) * lobe.d(m));
                assert!(
                    (seen - w.z).abs() < 3e-3 * w.z.max(0.1),
                    "{w:?}: {seen} vs {}",
                    w.z
                );
            }
        }
    }

    #[test]
    fn equal_roughnesses_are_the_isotropic_ggx_and_the_lobe_is_reciprocal() {
        let lobe = AnisotropicGgx::new(0.35, 0.35, 1.5).unwrap();
        for (a, b) in [((0.3, 0.2), (0.9, 2.5)), ((1.2, 4.0), (0.1, 1.0))] {
            let (wi, wo) = (
                Vec3::from_spherical(a.0, a.1),
                Vec3::from_spherical(b.0, b.1),
            );
            let h = (wi + wo).normalize();
            let iso = Distribution::Ggx.d(h.z, 0.35);
            assert!((lobe.d(h) - iso).abs() <= 1e-12 * iso, "{h:?}");
            let lambda = Distribution::Ggx.lambda(wi.z, 0.35);
            assert!((lobe.lambda(wi) - lambda).abs() <= 1e-12 * lambda.max(1.0));
            let f = lobe.eval(wi, wo);
            assert!(f > 0.0 && (f - lobe.eval(wo, wi)).abs() <= 1e-12 * f);
        }
        let turned = AnisotropicGgx::new(0.1, 0.5, 1.5).unwrap();
        let across = AnisotropicGgx::new(0.5, 0.1, 1.5).unwrap();
        let turn = |d: Vec3| Vec3::new(d.y, -d.x, d.z);
        let (wi, wo) = (
            Vec3::from_spherical(0.6, 0.4),
            Vec3::from_spherical(0.3, 2.0),
        );
        let f = turned.eval(wi, wo);
        assert!((f - across.eval(turn(wi), turn(wo))).abs() <= 1e-12 * f);
    }

    #[test]
    fn bad_parameters_are_refused_by_name() {
        for (ax, ay, eta, name) in [
            (0.0, 0.3, 1.5, "alpha_x"),
            (0.3, 1.5, 1.5, "alpha_y"),
            (0.3, 0.3, 0.5, "eta"),
            (f64::NAN, 0.3, 1.5, "alpha_x"),
        ] {
            let err = AnisotropicGgx::new(ax, ay, eta).unwrap_err().to_string();
            assert!(err.contains(name), "{err}");
        }
    }
}
