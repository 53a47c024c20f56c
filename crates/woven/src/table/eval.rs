//! Evaluating a [`Table`]: folding a pair into the table's domain, locating it on the grid and
//! interpolating; the [`Bsdf`] implementation.

use super::grid::{t_of_slope, Axis};
use super::{Half, Symmetry, Table, HORIZON_WEIGHT};
use crate::bsdf::{Bsdf, BsdfSample};
use crate::math::Vec3;

/// A located axis direction: `(iθ, wθ, iφ, wφ)`, each node index with the weight of the next node.
pub(crate) type Incidence = (usize, f64, usize, f64);

/// A located coordinate on one axis: `(k, w)`.
pub(crate) type AxisPos = (usize, f64);

/// The symmetry fold that brings an axis direction into the table's domain, to apply to both
/// directions of a pair and to undo on a sampled one.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Fold {
    Mirror { flip_x: bool, flip_y: bool },
    Rotate { cos: f64, sin: f64 },
}

impl Fold {
    /// The fold that brings `d` into the domain of a table of `symmetry`.
    #[inline]
    pub(crate) fn of(symmetry: Symmetry, d: Vec3) -> Fold {
        match symmetry {
            Symmetry::Mirror => Fold::Mirror {
                flip_x: d.x < 0.0,
                flip_y: d.y < 0.0,
            },
            Symmetry::Isotropic => {
                let r = (d.x * d.x + d.y * d.y).sqrt();
                if r > 0.0 {
                    Fold::Rotate {
                        cos: d.x / r,
                        sin: d.y / r,
                    }
                } else {
                    Fold::Rotate { cos: 1.0, sin: 0.0 }
                }
            }
        }
    }

    #[inline]
    pub(crate) fn apply(&self, d: Vec3) -> Vec3 {
        match *self {
            Fold::Mirror { flip_x, flip_y } => Vec3::new(
                if flip_x { -d.x } else { d.x },
                if flip_y { -d.y } else { d.y },
                d.z,
            ),
            // Rotation by −φ about z.
            Fold::Rotate { cos, sin } => {
                Vec3::new(cos * d.x + sin * d.y, -sin * d.x + cos * d.y, d.z)
            }
        }
    }

    #[inline]
    pub(crate) fn undo(&self, d: Vec3) -> Vec3 {
        match *self {
            Fold::Mirror { .. } => self.apply(d),
            Fold::Rotate { cos, sin } => {
                Vec3::new(cos * d.x - sin * d.y, sin * d.x + cos * d.y, d.z)
            }
        }
    }
}

impl Table {
    /// The BRDF (sr⁻¹), interpolated in the half whose axis is the pair's more grazing direction;
    /// 0 below the horizon.
    #[inline]
    pub fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let half = Half::of(s, v);
        let (axis, other) = half.split(s, v);
        let fold = Fold::of(self.symmetry, axis);
        self.eval_half(half, fold.apply(axis), fold.apply(other))
    }

    /// The value of `half` at a folded `(axis, other)`.
    #[inline]
    pub(crate) fn eval_half(&self, half: Half, axis: Vec3, other: Vec3) -> f64 {
        let located = locate_axis(&self.theta, &self.phi, axis);
        let (y, x) = locate_half_vector(&self.t, axis, other);
        self.eval_at(half, located, y, x)
    }

    /// The interpolated BRDF of `half` at located coordinates `(iθ, wθ, iφ, wφ)`, `(i_y, w_y)`,
    /// `(i_x, w_x)`: the node values `f_k` averaged with the quadrilinear weights `w_k` times the
    /// nodes' cosine factors `c_k = cos θ_axis,k · max(cos θ_other,k, ε)`,
    /// `Σ w_k c_k f_k / Σ w_k c_k` (`ε` = [`HORIZON_WEIGHT`]).
    ///
    /// Where `f` behaves like `1/(cos θ_i cos θ_r)` (near a highlight) this is the interpolation
    /// of the smooth `f cos θ_i cos θ_r` over the interpolated cosines; near the horizon it is a
    /// convex combination of node values, so it never exceeds the largest of them.
    #[inline]
    pub(crate) fn eval_at(
        &self,
        half: Half,
        (it, wt, ip, wp): Incidence,
        (iy, wy): AxisPos,
        (ix, wx): AxisPos,
    ) -> f64 {
        let dp = usize::from(self.phi.n > 1);
        let n = self.t.n;
        let (px0, px1) = (self.slopes[ix], self.slopes[ix + 1]);
        let (py0, py1) = (self.slopes[iy], self.slopes[iy + 1]);
        // The half-vector corners: slopes, bilinear weight and 1/(1 + |p|²), for the derived
        // direction's cos θ = 2 (a·h) h_z − a_z = 2 (a_x p_x + a_y p_y + a_z)/(1 + |p|²) − a_z.
        let corners = [
            (px0, py0, (1.0 - wy) * (1.0 - wx)),
            (px1, py0, (1.0 - wy) * wx),
            (px0, py1, wy * (1.0 - wx)),
            (px1, py1, wy * wx),
        ]
        .map(|(px, py, w)| (px, py, w, 1.0 / (1.0 + px * px + py * py)));
        let (mut num, mut den) = (0.0, 0.0);
        for (a, fa) in [(0, 1.0 - wt), (1, wt)] {
            for (b, fb) in [(0, 1.0 - wp), (dp, wp)] {
                let node = (it + a) * self.phi.n + ip + b;
                let d = self.axis_dirs[node];
                let base = self.index(half, it + a, ip + b, iy, ix);
                let vals = [
                    self.values[base],
                    self.values[base + 1],
                    self.values[base + n],
                    self.values[base + n + 1],
                ];
                let wa = fa * fb * d.z;
                for ((px, py, w, q), f) in corners.into_iter().zip(vals) {
                    let cos_other = 2.0 * (d.x * px + d.y * py + d.z) * q - d.z;
                    let wc = wa * w * cos_other.max(HORIZON_WEIGHT);
                    num += wc * f as f64;
                    den += wc;
                }
            }
        }
        if den > 0.0 {
            (num / den).max(0.0)
        } else {
            0.0
        }
    }

    /// [`eval`](Self::eval) for `s` already folded into the light half's domain.
    #[inline]
    pub(crate) fn eval_folded(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        match Half::of(s, v) {
            Half::Light => self.eval_half(Half::Light, s, v),
            Half::View => {
                let fold = Fold::of(self.symmetry, v);
                self.eval_half(Half::View, fold.apply(v), fold.apply(s))
            }
        }
    }
}

/// The located axis direction `d` (folded).
#[inline]
pub(crate) fn locate_axis(theta: &Axis, phi: &Axis, d: Vec3) -> Incidence {
    let (it, wt) = theta.locate(d.z.clamp(-1.0, 1.0).acos());
    let (ip, wp) = phi.locate(d.y.atan2(d.x));
    (it, wt, ip, wp)
}

/// The located half-vector slopes `(t_y, t_x)` of a pair.
#[inline]
pub(crate) fn locate_half_vector(t: &Axis, a: Vec3, b: Vec3) -> (AxisPos, AxisPos) {
    let h = a + b;
    (
        t.locate(t_of_slope(h.y / h.z)),
        t.locate(t_of_slope(h.x / h.z)),
    )
}

impl Bsdf for Table {
    #[inline]
    fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        Table::eval(self, s, v)
    }

    #[inline]
    fn pdf(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let fold = Fold::of(self.symmetry, s);
        self.sampler.pdf(self, fold.apply(s), fold.apply(v))
    }

    #[inline]
    fn sample(&self, s: Vec3, u1: f64, u2: f64) -> Option<BsdfSample> {
        if s.z <= 0.0 {
            return None;
        }
        let fold = Fold::of(self.symmetry, s);
        let sf = fold.apply(s);
        let (vf, pdf, f) = self.sampler.sample(self, sf, u1, u2)?;
        let v = fold.undo(vf);
        Some(BsdfSample {
            v,
            f,
            pdf,
            weight: f * v.z / pdf,
        })
    }
}
