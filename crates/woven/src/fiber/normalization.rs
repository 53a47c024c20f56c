//! The normalization `β(θ_i)` of Eq. (15), made precise by MODEL.md §1.5, tabulated once per fiber.

use super::Fiber;
use crate::math::hemisphere::reflected_hemisphere_integral;
use crate::math::interp::MonotoneCubic;
use crate::math::Vec3;

/// Number of nodes in `cos θ_i` (uniform on `[0, 1]`).
pub const BETA_NODES: usize = 256;

/// Relative accuracy of each node's hemisphere integral.
const NODE_TOL: f64 = 1e-9;

/// `β(cos θ_i)` sampled at [`BETA_NODES`] uniform nodes in `cos θ_i` and interpolated by a
/// monotone cubic. Interpolation error ≤ 1e-4 relative over `(0, 1]` (tested against direct
/// evaluation between the nodes for smooth and rough fibers).
#[derive(Clone, Debug)]
pub struct BetaTable {
    interp: MonotoneCubic,
}

impl BetaTable {
    /// Builds the table for `fiber` (its normalization mode is ignored: this is the `paper` β).
    pub fn build(fiber: &Fiber) -> Self {
        let values = (0..BETA_NODES)
            .map(|k| beta_direct(fiber, k as f64 / (BETA_NODES - 1) as f64))
            .collect();
        BetaTable {
            interp: MonotoneCubic::new(0.0, 1.0, values),
        }
    }

    /// `β` at `cos_theta_i` (clamped to `[0, 1]`).
    #[inline]
    pub fn eval(&self, cos_theta_i: f64) -> f64 {
        self.interp.eval(cos_theta_i)
    }
}

/// `β(θ_i) = (1 − ρ0) / (∫ Ω₁ cos θ_r dω_r [+ e^{−g} S1²])`, computed directly (MODEL.md §1.5).
///
/// `Ω₁` is the fiber's lobe with `β = 1`, `F = 1`, `ρ0 = 0`. At `cos θ_i = 0` the limit is taken
/// at `cos θ_i = 1e-7` (β is finite there: `S1(θ_i)/cos θ_i → √π/α`).
pub fn beta_direct(fiber: &Fiber, cos_theta_i: f64) -> f64 {
    let mut white = fiber.clone();
    white.unit_fresnel = true;
    white.beta = None;
    let ci = cos_theta_i.clamp(1e-7, 1.0);
    let single = reflected_hemisphere_integral(ci, white.lobe_width(ci), NODE_TOL, |s, v, _| {
        white.lobe(s, v, Vec3::Z, ci, v.z)
    });
    (1.0 - fiber.params.diffuse) / (single + white.specular_unnormalized(ci))
}
