//! Baseline BSDFs a cloth renderer reaches for beside the woven model: a sheen over a diffuse
//! base, and a rough dielectric coating over a diffuse base, and the lobes a renderer of standard
//! lobes carries. The two baselines are RGB [`Bsdf`]s, and every lobe here follows the
//! crate's conventions (docs/conventions.md): `wi` toward the light, `wo` toward the viewer,
//! `z` the normal, `f` in sr⁻¹ without the cosine and 0 below the horizon.
//!
//! - [`Sheen`]: the Estevez–Kulla "Charlie" sheen (glTF `KHR_materials_sheen`, Filament) over a
//!   Lambertian base scaled by the sheen's albedo; [`SheenLobe`] is its lobe alone (the fitter's
//!   `sheen` model evaluates it).
//! - [`AnisotropicGgx`]: an anisotropic GGX specular lobe on a dielectric, its tangent along
//!   `x` (the lobe a woven yarn's sheen is projected onto for renderers that carry only
//!   standard lobes).
//! - [`RoughPlastic`]: Mitsuba 3's `roughplastic` — a Beckmann or GGX dielectric coating over a
//!   diffuse base with the coating's transmittance in and out and internal reflections.
//!
//! Each baseline samples a mixture of its specular lobe's own distribution and a cosine hemisphere, and
//! reports the mixture's exact density. The quantities a constructor tabulates (directional
//! albedos, transmittances) are functions of `cos θ` on `CosTable`'s grid.
//!
//! [`Bsdf`]: crate::bsdf::Bsdf

mod ggx;
mod plastic;
mod sheen;

pub use ggx::{AnisotropicGgx, MIN_GGX_ALPHA};
pub use plastic::{Distribution, RoughPlastic, RoughPlasticParams};
pub use sheen::{Sheen, SheenLobe, SheenParams, MIN_SHEEN_ROUGHNESS};

use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::math::Vec3;

/// A function of `cos θ ∈ [0, 1]` tabulated at `μ_k = (k/(n−1))²` and interpolated linearly in
/// `√μ`: nodes crowd toward grazing (the first above 0 sits at θ = 89.986° for `n = 65`), where
/// the tabulated albedos and transmittances change fastest.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CosTable {
    values: Vec<f64>,
}

/// Nodes of every `CosTable`: linear interpolation in `√μ` on 65 nodes keeps the tabulation
/// error of the albedos below 10⁻³ (pinned by the tests' furnaces against direct quadrature).
pub(crate) const COS_TABLE_NODES: usize = 65;

impl CosTable {
    /// Tabulates `f(μ)` on the grid.
    pub(crate) fn build(mut f: impl FnMut(f64) -> f64) -> CosTable {
        let n = COS_TABLE_NODES;
        let values = (0..n)
            .map(|k| {
                let t = k as f64 / (n - 1) as f64;
                f(t * t)
            })
            .collect();
        CosTable { values }
    }

    /// The interpolated value at `cos_theta` (clamped to `[0, 1]`).
    #[inline]
    pub(crate) fn eval(&self, cos_theta: f64) -> f64 {
        let n = self.values.len();
        let x = cos_theta.clamp(0.0, 1.0).sqrt() * (n - 1) as f64;
        // min: x = n − 1 exactly at normal incidence; the last interval then takes weight 1.
        let i = (x as usize).min(n - 2);
        let w = x - i as f64;
        self.values[i] * (1.0 - w) + self.values[i + 1] * w
    }
}

/// The mirror direction of `d` about the unit normal `m`: `2 (d·m) m − d`.
#[inline]
pub(crate) fn reflect(d: Vec3, m: Vec3) -> Vec3 {
    m * (2.0 * d.dot(m)) - d
}

/// Checks that every channel of `c` lies in `[0, 1]`, naming the parameter on failure.
pub(crate) fn check_reflectance(name: &str, c: Rgb) -> Result<Rgb> {
    if c.0.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)) {
        Ok(c)
    } else {
        Err(Error::invalid(
            name,
            format!("[{}, {}, {}]", c.0[0], c.0[1], c.0[2]),
            "a colour with every channel in [0, 1]",
        ))
    }
}

/// The mean of the three channels.
#[inline]
pub(crate) fn mean(c: Rgb) -> f64 {
    (c.0[0] + c.0[1] + c.0[2]) / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cos_table_is_exact_at_nodes_and_linear_in_sqrt_mu_between() {
        let t = CosTable::build(|mu| mu.sqrt());
        for c in [0.0, 1e-4, 0.1, 0.37, 0.99, 1.0] {
            assert!((t.eval(c) - c.sqrt()).abs() < 1e-14, "{c}");
        }
        assert_eq!(t.eval(-1.0), 0.0);
        assert_eq!(t.eval(2.0), 1.0);
    }

    #[test]
    fn reflection_keeps_the_angle_to_the_normal() {
        let d = Vec3::from_spherical(0.7, 0.3);
        let m = Vec3::from_spherical(0.2, 2.0);
        let r = reflect(d, m);
        assert!((r.length() - 1.0).abs() < 1e-14);
        assert!((r.dot(m) - d.dot(m)).abs() < 1e-14);
        assert!(((d + r).normalize().dot(m) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn reflectances_outside_zero_one_are_refused_by_name() {
        assert!(check_reflectance("diffuse", Rgb([0.0, 0.5, 1.0])).is_ok());
        let e = check_reflectance("diffuse", Rgb([0.2, 1.5, 0.1]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("diffuse") && e.contains("1.5") && e.contains("[0, 1]"),
            "{e}"
        );
        assert!(check_reflectance("sheen_color", Rgb([f64::NAN, 0.0, 0.0])).is_err());
    }
}
