//! The table's parametrization: incidence `(θ_i, φ_i)` and the half vector's slopes.
//!
//! A cloth BRDF peaks where the half vector `h = (s + v)/|s + v|` meets a facet normal: for a flat
//! fiber at `h = z`, for yarns along the lines `h ⊥ e_f` — `h_x = 0` for the weft and `h_y = 0` for
//! the warp — with width `≈ α`. These features stay put as the light moves when `h` is written by
//! its slopes `p = (h_x/h_z, h_y/h_z)`: the Beckmann lobe is exactly `exp(−|p|²/α²)` there, and the
//! yarn ridges are the axes `p_x = 0`, `p_y = 0`. Every slope pair is a valid half vector, so the
//! grid has no edge inside the hemisphere. Each slope is warped as `p = tan(K·t|t|)`,
//! `t ∈ [−1, 1]`, `K = (π/2)(1 − 10⁻³)`: nodes crowd quadratically toward the axes (where the
//! peaks are) and are uniform in the slope angle near the horizon.

use crate::math::Vec3;
use std::f64::consts::FRAC_PI_2;

/// The slope-angle scale `K`: `t = ±1` is 0.09° short of a horizontal half vector.
pub(crate) const K: f64 = FRAC_PI_2 * (1.0 - 1e-3);

/// The slope `p` of a warped coordinate `t ∈ [−1, 1]`.
#[inline]
pub fn slope_of_t(t: f64) -> f64 {
    (K * t * t.abs()).tan()
}

/// The warped coordinate of a slope (clamped to `[−1, 1]`).
#[inline]
pub fn t_of_slope(p: f64) -> f64 {
    (p.abs().atan() / K).min(1.0).sqrt().copysign(p)
}

/// `dp/dt`.
#[inline]
pub fn dslope_dt(t: f64) -> f64 {
    dslope_dt_at(t, slope_of_t(t))
}

/// `dp/dt` given `p = slope_of_t(t)`: `2K|t| / cos²(K t|t|) = 2K|t| (1 + p²)`, no cosine.
#[inline]
fn dslope_dt_at(t: f64, p: f64) -> f64 {
    2.0 * K * t.abs() * (1.0 + p * p)
}

/// The half vector of slopes `(px, py)`.
#[inline]
pub fn h_of_slopes(px: f64, py: f64) -> Vec3 {
    Vec3::new(px, py, 1.0).normalize()
}

/// The viewer direction `v` for light from `s` and half-vector slopes `(px, py)`, with `h`, or
/// `None` when `v` falls below the horizon.
#[inline]
pub fn v_of_slopes(s: Vec3, px: f64, py: f64) -> Option<(Vec3, Vec3)> {
    let h = h_of_slopes(px, py);
    let sh = s.dot(h);
    if sh <= 0.0 {
        return None;
    }
    let v = h * (2.0 * sh) - s;
    (v.z > 0.0).then_some((v, h))
}

/// `|∂ω_r/∂(t_x, t_y)|` for light from `s`: `dω_r = 4 (s·h) dω_h`,
/// `dω_h = dp_x dp_y / (1 + |p|²)^{3/2}`, `dp = p'(t) dt`.
#[inline]
pub fn jacobian(s: Vec3, tx: f64, ty: f64) -> Option<(Vec3, f64)> {
    let (px, py) = (slope_of_t(tx), slope_of_t(ty));
    let (v, h) = v_of_slopes(s, px, py)?;
    Some((v, jacobian_factor(s, h, (tx, px), (ty, py))))
}

/// [`jacobian`] where the slopes are already known, `(t, p)` per axis with `p` the slope of
/// `t` (a density look-up has them from the pair's half vector: no tangents); `None` where `v`
/// falls below the horizon.
#[inline]
pub fn jacobian_at_slopes(s: Vec3, x: (f64, f64), y: (f64, f64)) -> Option<f64> {
    let (_, h) = v_of_slopes(s, x.1, y.1)?;
    Some(jacobian_factor(s, h, x, y))
}

/// `4 (s·h) / (1 + |p|²)^{3/2} · p′(t_x) p′(t_y)`.
#[inline]
fn jacobian_factor(s: Vec3, h: Vec3, (tx, px): (f64, f64), (ty, py): (f64, f64)) -> f64 {
    let q = 1.0 + px * px + py * py;
    4.0 * s.dot(h) / (q * q.sqrt()) * dslope_dt_at(tx, px) * dslope_dt_at(ty, py)
}

/// An axis of `n ≥ 1` nodes on `[lo, hi]`, at `lo + (hi − lo) g(k/(n−1))` with the grading
/// `g(u) = u (1 + a (1 − u))`: uniform for `a = 0`; for `a > 0` spacing shrinks toward `hi` by
/// the factor `(1 − a)/(1 + a)` (the polar axis uses `a = 1`, [`super::THETA_GRADING`]: masking and Fresnel change fastest
/// at grazing incidence).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    /// First node.
    pub lo: f64,
    /// Last node.
    pub hi: f64,
    /// Number of nodes.
    pub n: usize,
    /// Grading `a ∈ [0, 1)`.
    pub grading: f64,
}

impl Axis {
    /// A uniform axis.
    pub fn uniform(lo: f64, hi: f64, n: usize) -> Axis {
        Axis {
            lo,
            hi,
            n,
            grading: 0.0,
        }
    }

    /// The `k`-th node.
    #[inline]
    pub fn node(&self, k: usize) -> f64 {
        if self.n == 1 {
            return self.lo;
        }
        let u = k as f64 / (self.n - 1) as f64;
        self.lo + (self.hi - self.lo) * u * (1.0 + self.grading * (1.0 - u))
    }

    /// `(k, w)`: `x` lies between nodes `k` and `k + 1` with weight `w` on `k + 1`, linear in the
    /// graded coordinate (clamped to the axis; a single-node axis gives `(0, 0)`).
    #[inline]
    pub fn locate(&self, x: f64) -> (usize, f64) {
        if self.n == 1 {
            return (0, 0.0);
        }
        let y = ((x - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0);
        let a = self.grading;
        // Invert y = u + a u (1 − u): a u² − (1 + a) u + y = 0, the root in [0, 1].
        let u = if a == 0.0 {
            y
        } else {
            let b = 1.0 + a;
            2.0 * y / (b + (b * b - 4.0 * a * y).max(0.0).sqrt())
        };
        let v = u * (self.n - 1) as f64;
        let k = (v as usize).min(self.n - 2);
        (k, (v - k as f64).clamp(0.0, 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warp_round_trips_and_its_derivative_matches() {
        for k in 0..=200 {
            let t = -1.0 + k as f64 / 100.0;
            let p = slope_of_t(t);
            assert!((t_of_slope(p) - t).abs() < 1e-12, "t {t}");
            if t.abs() < 0.99 {
                let d = 1e-6;
                let fd = (slope_of_t(t + d) - slope_of_t(t - d)) / (2.0 * d);
                assert!(
                    (fd - dslope_dt(t)).abs() <= 1e-5 * fd.abs().max(1.0),
                    "t {t}: {fd} vs {}",
                    dslope_dt(t)
                );
            }
        }
    }

    #[test]
    fn graded_axis_locates_its_own_nodes() {
        let ax = Axis {
            lo: 0.0,
            hi: 1.5,
            n: 30,
            grading: 0.6,
        };
        for k in 0..30 {
            let x = ax.node(k);
            let (i, w) = ax.locate(x);
            let back = ax.node(i) + w * (ax.node(i + 1) - ax.node(i));
            assert!((back - x).abs() < 1e-12, "k {k}: {back} vs {x}");
        }
        // Spacing shrinks toward the end by (1 − a)/(1 + a).
        let first = ax.node(1) - ax.node(0);
        let last = ax.node(29) - ax.node(28);
        assert!((last / first - 0.25).abs() < 0.03, "{}", last / first);
    }

    #[test]
    fn jacobian_integrates_to_the_hemisphere() {
        // ∫ |∂ω/∂t| over the valid square is the solid angle of the hemisphere, 2π.
        let s = Vec3::from_spherical(0.7, 0.3);
        let gl = crate::math::quadrature::GaussLegendre::new(40);
        let mut edges = vec![-1.0, 1.0];
        for k in 1..40 {
            edges.push(-1.0 + k as f64 / 20.0);
        }
        edges.sort_by(f64::total_cmp);
        let mut total = 0.0;
        for ey in edges.windows(2) {
            for ex in edges.windows(2) {
                total += gl.integrate(ey[0], ey[1], |ty| {
                    gl.integrate(ex[0], ex[1], |tx| {
                        jacobian(s, tx, ty).map_or(0.0, |(_, j)| j)
                    })
                });
            }
        }
        assert!((total - 2.0 * std::f64::consts::PI).abs() < 2e-3, "{total}");
    }
}
