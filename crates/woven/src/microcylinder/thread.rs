//! One thread type of a cloth (paper §4 and Table II): its optics, its share of the cloth's area
//! and its tangent curve.

use super::curve::TangentCurve;
use super::scattering::ScatteringParams;
use crate::color::Rgb;
use crate::error::{check_range, Error, Result};

/// One of a cloth's two threads (thread 1 runs along `x`, the weft; thread 2 along `y`).
///
/// | field | meaning | unit | valid range |
/// |---|---|---|---|
/// | `eta` | relative refractive index `η` | — | `[1, 3]` |
/// | `albedo` | volume albedo `A`, per channel | — | `[0, 1]` |
/// | `kd` | isotropic share `k_d` of the volume lobe | — | `[0, 1]` |
/// | `gamma_s` | surface lobe width `γ_s` | radians | `[0.1°, 60°]` |
/// | `gamma_v` | volume lobe width `γ_v` | radians | `[0.1°, 90°]` |
/// | `coverage` | area coverage `a` | — | `[0, 1]`, `a_1 + a_2 ≤ 1` |
/// | `tangents` | the tangent curve | radians | [`TangentCurve::new`] |
#[derive(Clone, Debug, PartialEq)]
pub struct Thread {
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
    /// The share `a` of the cloth's area this thread covers.
    pub coverage: f64,
    /// The tangent curve.
    pub tangents: TangentCurve,
}

const DEG: f64 = std::f64::consts::PI / 180.0;

impl Thread {
    /// Checks every parameter against the table above; `index` (0 or 1) names the thread in
    /// errors (`thread[0].kd`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first parameter out of range.
    pub fn validate(&self, index: usize) -> Result<()> {
        let name = |p: &str| format!("thread[{index}].{p}");
        check_range(&name("eta"), self.eta, 1.0, 3.0)?;
        for (c, &a) in self.albedo.0.iter().enumerate() {
            check_range(&name(&format!("albedo[{c}]")), a, 0.0, 1.0)?;
        }
        check_range(&name("kd"), self.kd, 0.0, 1.0)?;
        // Below 0.1° the Gaussians are needles no quadrature of the curve resolves.
        if !(self.gamma_s.is_finite() && (0.1 * DEG..=60.0 * DEG).contains(&self.gamma_s)) {
            return Err(Error::invalid(
                name("gamma_s"),
                self.gamma_s,
                "a width in [0.1°, 60°] (radians: [0.001745, 1.0472])",
            ));
        }
        if !(self.gamma_v.is_finite() && (0.1 * DEG..=90.0 * DEG).contains(&self.gamma_v)) {
            return Err(Error::invalid(
                name("gamma_v"),
                self.gamma_v,
                "a width in [0.1°, 90°] (radians: [0.001745, 1.5708])",
            ));
        }
        check_range(&name("coverage"), self.coverage, 0.0, 1.0)?;
        Ok(())
    }

    /// The parameters of the thread scattering function.
    pub fn scattering_params(&self) -> ScatteringParams {
        ScatteringParams {
            eta: self.eta,
            albedo: self.albedo,
            kd: self.kd,
            gamma_s: self.gamma_s,
            gamma_v: self.gamma_v,
        }
    }
}
