//! Orthonormal bases: the two unit vectors that complete a unit vector to a right-handed frame,
//! for drawing directions about a normal (a facet's, a microfacet's, a light's) and for the
//! frames a renderer builds at its shapes.

use super::Vec3;

/// Two unit vectors completing unit `n` to a right-handed orthonormal basis `(t, b, n)`
/// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited": branchless, discontinuous only
/// where `n.z` changes sign).
///
/// ```
/// use woven::math::basis::orthonormal_basis;
/// use woven::Vec3;
/// let n = Vec3::new(0.3, -0.4, 0.5).normalize();
/// let (t, b) = orthonormal_basis(n);
/// assert!(t.dot(n).abs() < 1e-15 && b.dot(n).abs() < 1e-15 && t.dot(b).abs() < 1e-15);
/// assert!((t.cross(b) - n).length() < 1e-15);
/// ```
#[inline]
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn completes_a_right_handed_frame_on_both_hemispheres() {
        for (theta, phi) in [
            (0.0, 0.0),
            (0.7, 2.0),
            (1.5, -1.0),
            (2.5, 0.3),
            (3.1, 1.0),
            (std::f64::consts::PI, 0.5),
        ] {
            let n = Vec3::from_spherical(theta, phi);
            let (t, b) = orthonormal_basis(n);
            for (x, y) in [(t, t), (b, b)] {
                assert!((x.dot(y) - 1.0).abs() < 1e-12, "{theta} {phi}");
            }
            for (x, y) in [(t, b), (t, n), (b, n)] {
                assert!(x.dot(y).abs() < 1e-12, "{theta} {phi}");
            }
            assert!((t.cross(b) - n).length() < 1e-12, "{theta} {phi}");
        }
    }
}
