//! A material prepared for evaluation at one wavelength.

use crate::fiber::Fiber;
use crate::math::Vec3;

/// A material ready to evaluate: the result of [`Material::build`](crate::material::Material::build).
#[derive(Clone, Debug)]
pub struct Model {
    pub(crate) fiber: Fiber,
}

impl Model {
    /// The BRDF (sr⁻¹, no cosine) for light from `s` seen from `v`, in the cloth's local frame.
    #[inline]
    pub fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        self.fiber.eval(s, v)
    }

    /// The fiber surface of this material.
    pub fn fiber(&self) -> &Fiber {
        &self.fiber
    }

    /// Directional albedo for light from polar angle `theta_i` and azimuth `phi_i` (radians).
    pub fn albedo(&self, theta_i: f64, _phi_i: f64) -> f64 {
        self.fiber.albedo(theta_i.cos())
    }
}
