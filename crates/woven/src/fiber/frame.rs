//! The frame of a fiber lying in the cloth plane (docs/spec.md §0, §2.2).

use crate::math::Vec3;

/// The frame of fibers of azimuth `φ_a`: the fiber axis `e_f = (cos φ_a, sin φ_a, 0)`, the
/// in-plane direction across it `e_u = (−sin φ_a, cos φ_a, 0)`, and the macro normal `z`.
///
/// A cross-section of such fibers lies in the `(e_u, z)` plane: its facet at angle `θ` has the
/// normal `a(θ) = sin θ e_u + cos θ z`, and a direction `d` projects onto the plane at the angle
/// `ψ = atan2(d·e_u, d·z)`.
///
/// ```
/// use woven::fiber::FiberFrame;
/// let f = FiberFrame::new(std::f64::consts::FRAC_PI_2); // fibers along y (the warp)
/// assert!((f.e_f.y - 1.0).abs() < 1e-15 && (f.e_u.x + 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FiberFrame {
    /// The fiber axis `e_f`.
    pub e_f: Vec3,
    /// The in-plane direction across the fibers, `e_u = z × e_f`.
    pub e_u: Vec3,
}

impl FiberFrame {
    /// The frame of fibers of azimuth `phi_a` (radians, from `x`).
    #[inline]
    pub fn new(phi_a: f64) -> Self {
        let (sp, cp) = phi_a.sin_cos();
        FiberFrame {
            e_f: Vec3::new(cp, sp, 0.0),
            e_u: Vec3::new(-sp, cp, 0.0),
        }
    }

    /// The facet normal `a(θ) = sin θ e_u + cos θ z` of the cross-section at angle `theta`.
    #[inline]
    pub fn facet_normal(&self, theta: f64) -> Vec3 {
        let (st, ct) = theta.sin_cos();
        self.e_u * st + Vec3::Z * ct
    }

    /// The projected angle `ψ = atan2(d·e_u, d·z)` of `d` in the cross-section plane.
    #[inline]
    pub fn projected_angle(&self, d: Vec3) -> f64 {
        d.dot(self.e_u).atan2(d.z)
    }

    /// The fiber azimuth whose `e_u` is perpendicular to `d` (`d·e_u = 0`, so `ψ_d = 0`): the
    /// azimuth of `d` itself, in `(−π, π]` (π-periodic in meaning).
    #[inline]
    pub fn azimuth_across(d: Vec3) -> f64 {
        d.y.atan2(d.x)
    }
}
