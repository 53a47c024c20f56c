//! A tilted float: a yarn's height along the stretch where it lies on top (docs/model.md §8,
//! "Tilt").
//!
//! A float rises from under one crossing yarn and dips under the next. Its axis tilts out of the
//! cloth plane by `ψ(t) = u_max (1 − 2t)` at the fraction `t ∈ [0, 1]` of its length (measured in
//! the cloth plane): `+u_max` where it comes up, `−u_max` where it goes under (Irawan &
//! Marschner's `u_max`). Its height, in float lengths, is therefore
//!
//! ```text
//! h(t) = ln cos ψ(t) / (2 u_max)      (h′ = tan ψ; 0 at the crest t = 1/2, concave)
//! ```
//!
//! and floats repeat along the yarn, every float length: a row of identical hills meeting in
//! kinks, a heightfield that varies along the yarn's axis only. A direction `d` (in the yarn's
//! frame: the axis along `x`) meets it in the `(x, z)` plane at slope `m = d_z / |d_x|`.
//!
//! **Exact masking.** From `+x`, a point of a hill faces `d` iff `tan ψ(t) < m`, i.e.
//! `t > t* = (1 − atan m / u_max) / 2`; a facing point is never shadowed by its own (concave)
//! hill, and it is lit iff the ray clears the next hill, whose highest point above the ray's
//! line is its point of tangency `t*`: lit iff `h(t) − m t ≥ h(t*) − m t* − m`. The lit set is one
//! interval `[t*, t_e]` ([`FloatProfile::lit`]), the same from `−x` mirrored.
//!
//! **The point a ray meets.** A camera ray crossing the cloth plane (the crests' height) at `t₀`
//! descends along `−v` to the first hill point it meets. Along the visible set `[t*, t_e]` the
//! point's "foot" `w(t) = t − h(t)/m` (where the ray through it crosses the plane) increases
//! from `w(t*)` to exactly `w(t*) + 1`: the visible parts of the hills tile the plane, each
//! seen over its projected length `w′(t) dt = (1 − tan ψ / m) dt`. [`FloatProfile::seen_at`]
//! inverts `w`, so uniform entry points fall on facets in proportion to their projected areas
//! toward the viewer — which is what makes a point's BRDF that of the facet it lands on, and
//! their mean the float's masked average.

use crate::math::quadrature::GaussLegendre;
use crate::math::roots::monotone_root;
use crate::math::Vec3;
use std::ops::{AddAssign, Mul};

/// Gauss–Legendre nodes over the part of a float both lit and seen ([`FloatProfile::average`]).
pub const TILT_NODES: usize = 8;

/// The rule of [`FloatProfile::average`], built once.
pub(crate) fn tilt_rule() -> &'static GaussLegendre {
    static RULE: std::sync::OnceLock<GaussLegendre> = std::sync::OnceLock::new();
    RULE.get_or_init(|| GaussLegendre::new(TILT_NODES))
}

/// A direction in the frame of a yarn tilted by `(sin, cos)` of its tilt: the axis `x` turned
/// toward `+z`.
#[inline]
pub fn into_tilted(d: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(c * d.x + s * d.z, d.y, c * d.z - s * d.x)
}

/// Back from a tilted yarn's frame ([`into_tilted`]'s inverse).
#[inline]
pub fn from_tilted(d: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z)
}

/// The tolerance of the interval ends and of the point a ray meets, in float lengths.
const TOL: f64 = 1e-12;

/// A float's height along its length for a tilt `u_max` at its ends (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatProfile {
    u_max: f64,
}

impl FloatProfile {
    /// The float of tilt `u_max` (radians, in `(0, π/2)`; the surface allows up to 80°).
    pub fn new(u_max: f64) -> FloatProfile {
        debug_assert!(
            u_max > 0.0 && u_max < std::f64::consts::FRAC_PI_2,
            "u_max {u_max}"
        );
        FloatProfile { u_max }
    }

    /// The axis's tilt at the fraction `t` of the float, radians.
    #[inline]
    pub fn tilt(&self, t: f64) -> f64 {
        self.u_max * (1.0 - 2.0 * t)
    }

    /// The height at `t`, in float lengths below the crest (`≤ 0`).
    #[inline]
    pub fn height(&self, t: f64) -> f64 {
        self.tilt(t).cos().ln() / (2.0 * self.u_max)
    }

    /// The part `[t0, t1]` of a float lit from `d` (equally, visible from it), in the yarn's
    /// frame (axis along `x`); `None` for a direction at or below the horizon.
    pub fn lit(&self, d: Vec3) -> Option<(f64, f64)> {
        if d.z <= 0.0 || d.z.is_nan() || d.x.is_nan() {
            return None;
        }
        if d.x == 0.0 {
            return Some((0.0, 1.0));
        }
        let (lo, hi) = self.lit_from_plus_x(d.z / d.x.abs());
        Some(if d.x > 0.0 {
            (lo, hi)
        } else {
            (1.0 - hi, 1.0 - lo)
        })
    }

    /// The part both lit from `s` and visible from `v`: one interval, or `None`.
    pub fn lit_and_visible(&self, s: Vec3, v: Vec3) -> Option<(f64, f64)> {
        let (a, b) = (self.lit(s)?, self.lit(v)?);
        let (lo, hi) = (a.0.max(b.0), a.1.min(b.1));
        (lo < hi).then_some((lo, hi))
    }

    /// The BRDF of the whole float for light from `s` seen from `v` (both in the yarn's frame,
    /// the axis along `x`), from `f`, the BRDF of a facet in its own tilted frame: the mean over
    /// the facets both lit and seen, each over its projected area toward the viewer,
    ///
    /// ```text
    /// f_float(s, v) = ∫ f(s′, v′) cos θ′s cos θ′v / (cos θs cos θv cos ψ) dt   over [t_lo, t_hi]
    /// ```
    ///
    /// (`s′, v′` turned into the facet's frame by its tilt `ψ(t)`; per unit of cloth, a facet of
    /// length `dt` has area `dt / cos ψ` and irradiance `cos θ′s / cos θs` relative to the
    /// cloth's), by [`TILT_NODES`]-point Gauss–Legendre. 0 when no part is both lit and seen.
    pub fn average<V>(&self, s: Vec3, v: Vec3, mut f: impl FnMut(Vec3, Vec3) -> V) -> V
    where
        V: Default + AddAssign + Mul<f64, Output = V>,
    {
        let mut sum = V::default();
        let Some((lo, hi)) = self.lit_and_visible(s, v) else {
            return sum;
        };
        let rule = tilt_rule();
        for (x, w) in rule.nodes().iter().zip(rule.weights()) {
            let t = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
            let sc = self.tilt(t).sin_cos();
            let (ts, tv) = (into_tilted(s, sc), into_tilted(v, sc));
            if ts.z > 0.0 && tv.z > 0.0 {
                let k = ts.z * tv.z / (s.z * v.z * sc.1);
                sum += f(ts, tv) * (0.5 * (hi - lo) * w * k);
            }
        }
        sum
    }

    /// The lit interval for a direction from `+x` at slope `m > 0`.
    fn lit_from_plus_x(&self, m: f64) -> (f64, f64) {
        let u = self.u_max;
        let a = m.atan();
        if a >= u {
            return (0.0, 1.0);
        }
        let t_star = 0.5 * (1.0 - a / u);
        let g = self.height(t_star) - m * t_star;
        // H(t) = h(t) − m t − (g − m): m at t*, h(1) − g < 0 at 1, decreasing between.
        let t_end = monotone_root(
            |t| {
                let psi = self.tilt(t);
                (psi.cos().ln() / (2.0 * u) - m * t - g + m, psi.tan() - m)
            },
            t_star,
            1.0,
            TOL,
        );
        (t_star, t_end)
    }

    /// The fraction along the float of the point that a ray toward the viewer `v` (in the yarn's
    /// frame) meets, having crossed the crests' plane at `entry ∈ [0, 1)`; the hit may lie on a
    /// neighbouring float, which repeats this one. Uniform entries give points distributed as
    /// the visible facets' projected areas (module docs). `entry` itself when `v` is at or
    /// below the horizon, or has no component along the axis.
    pub fn seen_at(&self, entry: f64, v: Vec3) -> f64 {
        if v.z <= 0.0 || v.x == 0.0 || !(v.x.is_finite() && v.z.is_finite()) {
            return entry.clamp(0.0, 1.0);
        }
        if v.x < 0.0 {
            return 1.0 - self.seen_from_plus_x(1.0 - entry, v.z / -v.x);
        }
        self.seen_from_plus_x(entry, v.z / v.x)
    }

    fn seen_from_plus_x(&self, entry: f64, m: f64) -> f64 {
        let (lo, hi) = self.lit_from_plus_x(m);
        let foot = |t: f64| t - self.height(t) / m;
        let start = foot(lo);
        let target = entry - (entry - start).floor();
        monotone_root(
            |t| (foot(t) - target, 1.0 - self.tilt(t).tan() / m),
            lo,
            hi,
            TOL,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(x: f64, z: f64) -> Vec3 {
        Vec3::new(x, 0.3, z).normalize()
    }

    /// Brute force: whether the point at `t` (float 0) is seen from `d` (yarn frame), by
    /// marching the ray over the next floats.
    fn lit_by_marching(f: &FloatProfile, t: f64, d: Vec3) -> bool {
        let psi = f.tilt(t);
        if -psi.sin() * d.x + psi.cos() * d.z <= 0.0 {
            return false;
        }
        let (step, m) = (d.x.signum(), d.z / d.x.abs());
        let h0 = f.height(t);
        for k in 1..100_000 {
            let x = t + step * k as f64 * 5e-4;
            let ray = h0 + m * (x - t).abs();
            if ray > 0.0 {
                return true;
            }
            if f.height(x.rem_euclid(1.0)) > ray + 1e-12 {
                return false;
            }
        }
        true
    }

    #[test]
    fn the_lit_interval_is_what_a_marched_ray_sees() {
        for u_deg in [10.0, 40.0, 80.0] {
            let f = FloatProfile::new(f64::to_radians(u_deg));
            for d in [dir(1.0, 0.2), dir(-1.0, 0.6), dir(0.4, 1.0), dir(-3.0, 0.1)] {
                let (lo, hi) = f.lit(d).unwrap();
                for k in 0..100 {
                    let t = (k as f64 + 0.5) / 100.0;
                    let inside = t > lo + 2e-3 && t < hi - 2e-3;
                    let outside = t < lo - 2e-3 || t > hi + 2e-3;
                    if inside || outside {
                        assert_eq!(
                            lit_by_marching(&f, t, d),
                            inside,
                            "u {u_deg}° d {d:?} t {t}: interval ({lo}, {hi})"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_visible_parts_tile_the_plane() {
        // ∫ over the visible part of w′(t) = 1 − tan ψ / m is one float length, so the
        // projected lengths seen from any direction add up to the cloth's.
        for u_deg in [5.0, 45.0, 80.0] {
            let f = FloatProfile::new(f64::to_radians(u_deg));
            for d in [dir(1.0, 0.05), dir(-1.0, 1.0), dir(2.0, 1.0)] {
                let (lo, hi) = f.lit(d).unwrap();
                let m = d.z / d.x.abs();
                let n = 20_000;
                let sum: f64 = (0..n)
                    .map(|k| {
                        let t = lo + (hi - lo) * (k as f64 + 0.5) / n as f64;
                        let psi = f.tilt(if d.x > 0.0 { t } else { 1.0 - t });
                        1.0 - psi.tan() / m
                    })
                    .sum::<f64>()
                    * (hi - lo)
                    / n as f64;
                assert!((sum - 1.0).abs() < 1e-6, "u {u_deg}° d {d:?}: {sum}");
            }
        }
    }

    #[test]
    fn a_ray_meets_a_visible_point_on_its_own_line() {
        let f = FloatProfile::new(f64::to_radians(60.0));
        for v in [dir(1.0, 0.3), dir(-0.5, 1.0), dir(4.0, 0.2)] {
            let (lo, hi) = f.lit(v).unwrap();
            for k in 0..100 {
                let entry = (k as f64 + 0.25) / 100.0;
                let t = f.seen_at(entry, v);
                assert!(
                    t >= lo - 1e-9 && t <= hi + 1e-9,
                    "v {v:?} entry {entry}: t {t}"
                );
                // The ray through the point reaches the crests' plane at the entry (mod 1).
                let foot = t - f.height(t) * v.x / v.z;
                let off = foot - entry;
                assert!(
                    (off - off.round()).abs() < 1e-9,
                    "v {v:?} entry {entry}: foot {foot}"
                );
            }
        }
        // Straight down the axis' normal plane, the point below the entry.
        assert_eq!(f.seen_at(0.3, Vec3::new(0.0, 0.6, 0.8)), 0.3);
    }

    #[test]
    fn tiny_and_steep_tilts_and_grazing_directions_stay_finite() {
        for u in [1e-9, 1e-4, f64::to_radians(80.0)] {
            let f = FloatProfile::new(u);
            for d in [
                dir(1.0, 1e-9),
                dir(-1.0, 1e-6),
                dir(1e-12, 1.0),
                dir(3.0, 0.02),
            ] {
                let (lo, hi) = f.lit(d).unwrap();
                assert!(
                    (0.0..=hi).contains(&lo) && hi <= 1.0,
                    "u {u} d {d:?}: ({lo}, {hi})"
                );
                for entry in [0.0, 0.3, 0.999_999] {
                    let t = f.seen_at(entry, d);
                    assert!((0.0..=1.0).contains(&t), "u {u} d {d:?} entry {entry}: {t}");
                }
            }
        }
    }
}
