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

/// Most knots a float's tilt curve has ([`FloatProfile::shaped`]).
const MAX_KNOTS: usize = 6;

/// A float's height along its length (module docs): its tilt `ψ(t)` is piecewise linear in `t`
/// through knots `(t_k, ψ_k)`, non-increasing from `+u_max` at `t = 0` to `−u_max` at `t = 1`
/// and odd about the crest `t = 1/2`, so that the height is a concave hill with its top at the
/// crest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatProfile {
    u_max: f64,
    /// The shares lying flat on top and at full tilt at each end ([`shaped`](Self::shaped)).
    shape: (f64, f64),
    /// `(t_k, ψ_k)`, `t` increasing from 0 to 1; the first `len` are used.
    knots: [(f64, f64); MAX_KNOTS],
    /// `∫₀^{t_k} tan ψ`, the height at each knot above the float's start.
    rise: [f64; MAX_KNOTS],
    len: usize,
    /// The crest's height above the float's start, `∫₀^{1/2} tan ψ`.
    top: f64,
}

impl FloatProfile {
    /// The same shape (crest and flanks) at the tilt `u_max`.
    pub fn with_u_max(&self, u_max: f64) -> FloatProfile {
        FloatProfile::shaped(u_max, self.shape.0, self.shape.1)
    }

    /// The float of tilt `u_max` (radians, in `(0, π/2)`; the surface allows up to 80°), its
    /// tilt falling linearly along it: `ψ(t) = u_max (1 − 2t)`.
    pub fn new(u_max: f64) -> FloatProfile {
        FloatProfile::shaped(u_max, 0.0, 0.0)
    }

    /// A float that keeps its full tilt `u_max` over the first and last `flank` of its length,
    /// lies flat over the middle `crest`, and turns linearly between (an option beyond Irawan &
    /// Marschner's linear tilt, [`new`](Self::new), which is `crest = flank = 0`): a float pressed
    /// flat on top, rising and dipping steeply at its ends. `crest, flank ≥ 0` with
    /// `crest + 2 flank < 1` ([`YarnParams::validate`](super::YarnParams::validate) checks them).
    pub fn shaped(u_max: f64, crest: f64, flank: f64) -> FloatProfile {
        debug_assert!(
            u_max > 0.0 && u_max < std::f64::consts::FRAC_PI_2,
            "u_max {u_max}"
        );
        debug_assert!(
            crest >= 0.0 && flank >= 0.0 && crest + 2.0 * flank < 1.0,
            "crest {crest} flank {flank}"
        );
        let (a, b) = (0.5 * (1.0 - crest), 0.5 * (1.0 + crest));
        let all = [
            (0.0, u_max),
            (flank, u_max),
            (a, 0.0),
            (b, 0.0),
            (1.0 - flank, -u_max),
            (1.0, -u_max),
        ];
        let mut f = FloatProfile {
            u_max,
            shape: (crest, flank),
            knots: [(0.0, 0.0); MAX_KNOTS],
            rise: [0.0; MAX_KNOTS],
            len: 0,
            top: 0.0,
        };
        for k in all {
            // Pieces of zero length are dropped, and a knot where the tilt does not turn (a
            // linear tilt is one piece).
            if f.len > 0 && k.0 <= f.knots[f.len - 1].0 {
                continue;
            }
            if f.len >= 2 {
                let ((t0, p0), (t1, p1)) = (f.knots[f.len - 2], f.knots[f.len - 1]);
                if ((p1 - p0) / (t1 - t0) - (k.1 - p1) / (k.0 - t1)).abs() <= 1e-12 * u_max {
                    f.len -= 1;
                }
            }
            f.knots[f.len] = k;
            if f.len > 0 {
                let (t0, _) = f.knots[f.len - 1];
                f.rise[f.len] = f.rise[f.len - 1] + f.rise_within(f.len - 1, k.0 - t0);
            }
            f.len += 1;
        }
        f.top = f.rise_to(0.5);
        f
    }

    /// The tilt at the float's ends, radians.
    pub fn u_max(&self) -> f64 {
        self.u_max
    }

    /// `(crest, flank)`: the shares of the float lying flat on top and at full tilt at each end
    /// (`(0, 0)` for a linear tilt).
    pub fn shape(&self) -> (f64, f64) {
        self.shape
    }

    /// The knots `(t_k, ψ_k)` of the tilt, `t` increasing from 0 to 1, between which `ψ` is
    /// linear (two for a linear tilt; up to six for a crest and flanks).
    pub fn knots(&self) -> &[(f64, f64)] {
        &self.knots[..self.len]
    }

    /// The height at each knot above the float's start, `∫₀^{t_k} tan ψ`: the height at `t` in
    /// piece `k` is this knot's rise, plus the piece's own up to `t`, less [`top`](Self::top).
    pub fn rises(&self) -> &[f64] {
        &self.rise[..self.len]
    }

    /// The crest's height above the float's start, `∫₀^{1/2} tan ψ`.
    pub fn top(&self) -> f64 {
        self.top
    }

    /// `∫ tan ψ` over the first `dt` of piece `i` (from knot `i` toward knot `i + 1`).
    #[inline]
    fn rise_within(&self, i: usize, dt: f64) -> f64 {
        let ((t0, p0), (t1, p1)) = (self.knots[i], self.knots[i + 1]);
        let k = (p1 - p0) / (t1 - t0);
        if k == 0.0 {
            p0.tan() * dt
        } else {
            (p0.cos().ln() - (p0 + k * dt).cos().ln()) / k
        }
    }

    /// The piece holding `t` (clamped to the float).
    #[inline]
    fn piece(&self, t: f64) -> usize {
        let mut i = 0;
        while i + 2 < self.len && t >= self.knots[i + 1].0 {
            i += 1;
        }
        i
    }

    /// The height at `t` above the float's start.
    #[inline]
    fn rise_to(&self, t: f64) -> f64 {
        let i = self.piece(t);
        self.rise[i] + self.rise_within(i, t - self.knots[i].0)
    }

    /// The axis's tilt at the fraction `t` of the float, radians.
    #[inline]
    pub fn tilt(&self, t: f64) -> f64 {
        let i = self.piece(t);
        let ((t0, p0), (t1, p1)) = (self.knots[i], self.knots[i + 1]);
        p0 + (p1 - p0) * ((t - t0) / (t1 - t0))
    }

    /// The height at `t`, in float lengths below the crest (`≤ 0`).
    #[inline]
    pub fn height(&self, t: f64) -> f64 {
        self.rise_to(t) - self.top
    }

    /// The first `t` past which the tilt is below `a` (`tan ψ(t) < tan a`): where a direction
    /// from `+x` at elevation `a` starts to face the float.
    fn facing_from(&self, a: f64) -> f64 {
        for i in 0..self.len - 1 {
            let ((t0, p0), (t1, p1)) = (self.knots[i], self.knots[i + 1]);
            if p1 < a {
                return if p0 <= a {
                    t0
                } else {
                    t0 + (t1 - t0) * (p0 - a) / (p0 - p1)
                };
            }
        }
        1.0
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
        let mut piece = |lo: f64, hi: f64, flat: bool| {
            let mut add = |t: f64, w: f64| {
                let sc = self.tilt(t).sin_cos();
                let (ts, tv) = (into_tilted(s, sc), into_tilted(v, sc));
                if ts.z > 0.0 && tv.z > 0.0 {
                    let k = ts.z * tv.z / (s.z * v.z * sc.1);
                    sum += f(ts, tv) * (w * k);
                }
            };
            if flat {
                // A piece of constant tilt: the integrand is constant along it.
                add(0.5 * (lo + hi), hi - lo);
            } else {
                for (x, w) in rule.nodes().iter().zip(rule.weights()) {
                    add(0.5 * (lo + hi) + 0.5 * (hi - lo) * x, 0.5 * (hi - lo) * w);
                }
            }
        };
        for i in 0..self.len - 1 {
            let ((t0, p0), (t1, p1)) = (self.knots[i], self.knots[i + 1]);
            let (a, b) = (t0.max(lo), t1.min(hi));
            if a < b {
                piece(a, b, p0 == p1);
            }
        }
        sum
    }

    /// The lit interval for a direction from `+x` at slope `m > 0`.
    fn lit_from_plus_x(&self, m: f64) -> (f64, f64) {
        let a = m.atan();
        if a >= self.u_max {
            return (0.0, 1.0);
        }
        let t_star = self.facing_from(a);
        let g = self.height(t_star) - m * t_star;
        // H(t) = h(t) − m t − (g − m): m at t*, h(1) − g < 0 at 1, decreasing between.
        let t_end = monotone_root(
            |t| (self.height(t) - m * t - g + m, self.tilt(t).tan() - m),
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

    /// Linear tilts and shaped ones (a flat crest, flanks at full tilt, both).
    fn profiles(u_degs: &[f64]) -> Vec<FloatProfile> {
        let mut out = Vec::new();
        for &u in u_degs {
            let u = u.to_radians();
            for (crest, flank) in [(0.0, 0.0), (0.3, 0.0), (0.0, 0.25), (0.2, 0.13)] {
                out.push(FloatProfile::shaped(u, crest, flank));
            }
        }
        out
    }

    #[test]
    fn the_height_rises_as_the_tilt_and_tops_out_at_the_crest() {
        for f in profiles(&[10.0, 45.0, 80.0]) {
            assert!(f.height(0.5).abs() < 1e-15, "{f:?}");
            for k in 1..200 {
                let t = k as f64 / 200.0;
                let dt = 1e-6;
                let slope = (f.height(t + dt) - f.height(t - dt)) / (2.0 * dt);
                // h′ = tan ψ away from the kinks; h ≤ 0 everywhere.
                assert!(
                    (slope - f.tilt(t).tan()).abs() < 1e-4 * (1.0 + slope.abs()) || kink(&f, t),
                    "{f:?} t {t}: h′ {slope} tan ψ {}",
                    f.tilt(t).tan()
                );
                assert!(f.height(t) <= 1e-15, "{f:?} t {t}");
            }
        }
    }

    fn kink(f: &FloatProfile, t: f64) -> bool {
        f.knots[..f.len].iter().any(|k| (k.0 - t).abs() < 1e-5)
    }

    #[test]
    fn a_shaped_float_is_its_linear_float_without_crest_or_flanks() {
        let (a, b) = (FloatProfile::new(0.5), FloatProfile::shaped(0.5, 0.0, 0.0));
        assert_eq!(a, b);
        assert_eq!(a.len, 2);
        // A pressed float: flat over its crest, at full tilt over its flanks.
        let f = FloatProfile::shaped(0.5, 0.2, 0.1);
        assert_eq!(f.tilt(0.45), 0.0);
        assert_eq!(f.tilt(0.05), 0.5);
        assert_eq!(f.tilt(0.97), -0.5);
        assert!((f.tilt(0.25) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn the_whole_float_average_is_a_fine_riemann_sum() {
        // f ≡ 1: the mean of cos θ′s cos θ′v / (cos θs cos θv cos ψ) over the lit-and-seen part.
        for f in profiles(&[20.0, 60.0]) {
            for (s, v) in [
                (dir(1.0, 0.7), dir(-0.6, 1.0)),
                (dir(0.3, 1.0), dir(2.0, 0.5)),
            ] {
                let got = f.average(s, v, |_, _| 1.0);
                let (lo, hi) = f.lit_and_visible(s, v).unwrap();
                let n = 200_000;
                let want: f64 = (0..n)
                    .map(|k| {
                        let t = lo + (hi - lo) * (k as f64 + 0.5) / n as f64;
                        let sc = f.tilt(t).sin_cos();
                        let (ts, tv) = (into_tilted(s, sc), into_tilted(v, sc));
                        (ts.z * tv.z).max(0.0) / (s.z * v.z * sc.1)
                    })
                    .sum::<f64>()
                    * (hi - lo)
                    / n as f64;
                assert!((got - want).abs() < 1e-6 * want, "{f:?}: {got} vs {want}");
            }
        }
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
        for f in profiles(&[10.0, 40.0, 80.0]) {
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
                            "{f:?} d {d:?} t {t}: interval ({lo}, {hi})"
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
        for f in profiles(&[5.0, 45.0, 80.0]) {
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
                assert!((sum - 1.0).abs() < 1e-6, "{f:?} d {d:?}: {sum}");
            }
        }
    }

    #[test]
    fn a_ray_meets_a_visible_point_on_its_own_line() {
        for f in profiles(&[60.0]) {
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
    }

    #[test]
    fn tiny_and_steep_tilts_and_grazing_directions_stay_finite() {
        for u in [1e-9, 1e-4, f64::to_radians(80.0)] {
            for f in [FloatProfile::new(u), FloatProfile::shaped(u, 0.5, 0.2)] {
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
}
