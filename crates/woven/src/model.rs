//! A material prepared for evaluation at one wavelength.

use crate::cloth::Structure;
use crate::fiber::Fiber;
use crate::math::Vec3;

/// A material ready to evaluate: the result of [`Material::build`](crate::material::Material::build).
/// `Send + Sync`; cheap to clone.
#[derive(Clone, Debug)]
pub struct Model {
    structure: Structure,
}

impl Model {
    /// A model of the given structure.
    pub fn new(structure: Structure) -> Self {
        Model { structure }
    }

    /// The BRDF (sr⁻¹, no cosine) for light from `s` seen from `v`, in the cloth's local frame
    /// (docs/spec.md §0); 0 when either is below the surface.
    #[inline]
    pub fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        self.structure.eval(s, v)
    }

    /// The structure (flat fiber surface or woven yarns).
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// The fiber surface of this material.
    pub fn fiber(&self) -> &Fiber {
        self.structure.fiber()
    }

    /// Directional albedo `∫ f cos θ_r dω_r` (plus the full model's specular spike) for light from
    /// polar angle `theta_i` and azimuth `phi_i` (radians).
    pub fn albedo(&self, theta_i: f64, phi_i: f64) -> f64 {
        match &self.structure {
            Structure::Flat(fiber) => fiber.albedo(theta_i.cos()),
            Structure::Woven { .. } => crate::albedo::hemisphere_albedo(self, theta_i, phi_i),
        }
    }
}
