//! A minimal 3-vector for directions in the local shading frame (docs/spec.md §0).

use std::ops::{Add, Mul, Neg, Sub};

/// A 3-vector of `f64`. Directions in the cloth's local frame: `z` is the macro normal, the
/// weft runs along `x` and the warp along `y` (docs/spec.md §0).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Vec3 {
    /// Component along the weft.
    pub x: f64,
    /// Component along the warp.
    pub y: f64,
    /// Component along the macro normal.
    pub z: f64,
}

impl Vec3 {
    /// The macro normal.
    pub const Z: Vec3 = Vec3::new(0.0, 0.0, 1.0);

    /// A vector from components.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Vec3 { x, y, z }
    }

    /// The unit vector with polar angle `theta` from `z` and azimuth `phi` from `x` (radians).
    ///
    /// ```
    /// let d = woven::Vec3::from_spherical(0.0, 1.0);
    /// assert!((d.z - 1.0).abs() < 1e-15);
    /// ```
    pub fn from_spherical(theta: f64, phi: f64) -> Self {
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        Vec3::new(st * cp, st * sp, ct)
    }

    /// `(theta, phi)` of this vector, `phi` in `(-π, π]`.
    pub fn to_spherical(self) -> (f64, f64) {
        let n = self.length();
        ((self.z / n).clamp(-1.0, 1.0).acos(), self.y.atan2(self.x))
    }

    /// Dot product.
    #[inline]
    pub fn dot(self, o: Vec3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    #[inline]
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Euclidean length.
    #[inline]
    pub fn length(self) -> f64 {
        self.dot(self).sqrt()
    }

    /// This vector scaled to unit length (NaN for the zero vector).
    #[inline]
    pub fn normalize(self) -> Vec3 {
        self * (1.0 / self.length())
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    #[inline]
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Vec3 {
    type Output = Vec3;
    #[inline]
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Mul<f64> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn mul(self, k: f64) -> Vec3 {
        Vec3::new(self.x * k, self.y * k, self.z * k)
    }
}

impl Neg for Vec3 {
    type Output = Vec3;
    #[inline]
    fn neg(self) -> Vec3 {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}
