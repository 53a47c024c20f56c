//! Evaluating a [`Table`]: folding a pair into the table's domain, locating it on the grid and
//! interpolating; the [`Bsdf`] implementation.

use super::grid::{t_of_slope, Axis};
use super::{Albedos, Half, Symmetry, Table, HORIZON_WEIGHT};
use crate::bsdf::{known_and_drawn, pair_of, Bsdf, BsdfSample, LobeFlags, Transport};
use crate::math::Vec3;

/// A located axis direction: `(iθ, wθ, iφ, wφ)`, each node index with the weight of the next node.
pub(crate) type Incidence = (usize, f64, usize, f64);

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
        if let Some(model) = self.exact_at(s, v) {
            return model.eval(s, v);
        }
        let half = Half::of(s, v);
        let (axis, other) = half.split(s, v);
        let fold = Fold::of(self.symmetry, axis);
        self.eval_half(half, fold.apply(axis), fold.apply(other))
    }

    /// The BRDF for other albedos, one per channel (`N` = 3 for RGB): `f` is affine in the
    /// fiber's diffuse albedo `ρ0` and the yarn's interreflection albedo `ρ` (docs/model.md §7),
    /// `f(ρ0, ρ) = f + (ρ0 − ρ0′) ∂f/∂ρ0 + (ρ − ρ′) ħ/π` with `ρ0′, ρ′` the material's
    /// own, so one table serves every dye. The table must be built with
    /// [`TableOptions::colour`](super::TableOptions::colour) ([`is_dyeable`](Self::is_dyeable));
    /// otherwise every channel is the material's own `f`. 0 below the horizon, never negative.
    #[inline]
    pub fn eval_dyed<const N: usize>(&self, s: Vec3, v: Vec3, albedos: &[Albedos; N]) -> [f64; N] {
        if s.z <= 0.0 || v.z <= 0.0 {
            return [0.0; N];
        }
        if let Some(model) = self.exact_at(s, v) {
            let affine = model.eval_affine(s, v);
            return albedos.map(|a| affine.at(a.diffuse, a.interreflection).max(0.0));
        }
        let Some(colour) = &self.colour else {
            return [self.eval(s, v); N];
        };
        let (f, body, g) = match &colour.crown {
            Some(g) => {
                let [f, body, g] = self.eval_arrays(s, v, [&self.values, &colour.body, g]);
                (f, body, g)
            }
            None => {
                let [f, body] = self.eval_arrays(s, v, [&self.values, &colour.body]);
                (f, body, 1.0)
            }
        };
        albedos.map(|a| {
            (f + (a.diffuse - colour.own.diffuse) * body
                + (a.interreflection - colour.own.interreflection) * colour.per_interreflection * g)
                .max(0.0)
        })
    }

    /// [`eval`](Self::eval) of `K` node arrays laid out as [`values`](Self::values), with the
    /// same weights; 0 below the horizon.
    #[inline]
    pub(crate) fn eval_arrays<const K: usize>(
        &self,
        s: Vec3,
        v: Vec3,
        arrays: [&[f32]; K],
    ) -> [f64; K] {
        if s.z <= 0.0 || v.z <= 0.0 {
            return [0.0; K];
        }
        let half = Half::of(s, v);
        let (axis, other) = half.split(s, v);
        let fold = Fold::of(self.symmetry, axis);
        let (axis, other) = (fold.apply(axis), fold.apply(other));
        let located = locate_axis(&self.theta, &self.phi, axis);
        self.interpolate(half, located, Query::new(axis, other), arrays)
    }

    /// The value of `half` at a folded `(axis, other)`.
    #[inline]
    pub(crate) fn eval_half(&self, half: Half, axis: Vec3, other: Vec3) -> f64 {
        let located = locate_axis(&self.theta, &self.phi, axis);
        self.eval_at(half, located, Query::new(axis, other))
    }

    /// The interpolated BRDF of `half` at a located axis direction `(iθ, wθ, iφ, wφ)` for the
    /// query `q`: the node values `f_k` averaged with the quadrilinear weights `w_k` times the
    /// nodes' cosine factors `c_k = cos θ_axis,k · max(cos θ_other,k, ε)`,
    /// `Σ w_k c_k f_k / Σ w_k c_k` (`ε` = [`HORIZON_WEIGHT`]).
    ///
    /// At each azimuth node the pair is first turned rigidly about `z` onto the node's azimuth
    /// (its half vector with it), so interpolating in azimuth never moves either direction's
    /// polar angle — at a fixed half vector, a grazing pair would swing across the horizon.
    ///
    /// Where `f` behaves like `1/(cos θ_i cos θ_r)` (near a highlight) this is the interpolation
    /// of the smooth `f cos θ_i cos θ_r` over the interpolated cosines; near the horizon it is a
    /// convex combination of node values, so it never exceeds the largest of them.
    #[inline]
    pub(crate) fn eval_at(&self, half: Half, located: Incidence, q: Query) -> f64 {
        self.interpolate(half, located, q, [&self.values])[0].max(0.0)
    }

    /// [`eval_at`](Self::eval_at) of `K` node arrays at once, with the same weights.
    #[inline]
    pub(crate) fn interpolate<const K: usize>(
        &self,
        half: Half,
        (it, wt, ip, wp): Incidence,
        q: Query,
        arrays: [&[f32]; K],
    ) -> [f64; K] {
        let n = self.t.n;
        let (mut num, mut den) = ([0.0; K], 0.0);
        let phi_nodes: &[(usize, f64)] = if self.phi.n > 1 {
            &[(0, 1.0 - wp), (1, wp)]
        } else {
            &[(0, 1.0)]
        };
        let turns = self.phi.n > 1 && q.turn > 0.0;
        let locate = |h: Vec3| {
            (
                self.t.locate(t_of_slope(h.y / h.z)),
                self.t.locate(t_of_slope(h.x / h.z)),
            )
        };
        // Without a turn both azimuth nodes read the query's own half vector: locate it once.
        let unturned = (!turns).then(|| locate(q.h));
        for &(b, fb) in phi_nodes {
            let ((iy, wy), (ix, wx)) = match unturned {
                Some(located) => located,
                None => {
                    // The pair turned (by `q.turn` of the way) onto azimuth node ip + b.
                    let (cb, sb) = self.phi_cs[ip + b];
                    let (c, sn) = (cb * q.cos + sb * q.sin, sb * q.cos - cb * q.sin);
                    let (c, sn) = if q.turn >= 1.0 {
                        (c, sn)
                    } else {
                        let (s2, c2) = (q.turn * sn.atan2(c)).sin_cos();
                        (c2, s2)
                    };
                    locate(Vec3::new(
                        c * q.h.x - sn * q.h.y,
                        sn * q.h.x + c * q.h.y,
                        q.h.z,
                    ))
                }
            };
            for (a, fa) in [(0, 1.0 - wt), (1, wt)] {
                let node = (it + a) * self.phi.n + ip + b;
                let d = self.axis_dirs[node];
                let base = self.index(half, it + a, ip + b, iy, ix);
                let wa = fa * fb * d.z;
                for (dy, fy) in [(0, 1.0 - wy), (1, wy)] {
                    let py = self.slopes[iy + dy];
                    for (dx, fx) in [(0, 1.0 - wx), (1, wx)] {
                        let px = self.slopes[ix + dx];
                        // The derived direction's cos θ = 2 (d·h) h_z − d_z at the node.
                        let cos_other =
                            2.0 * (d.x * px + d.y * py + d.z) / (1.0 + px * px + py * py) - d.z;
                        let wc = wa * fy * fx * cos_other.max(HORIZON_WEIGHT);
                        let at = base + dy * n + dx;
                        for (sum, array) in num.iter_mut().zip(arrays) {
                            *sum += wc * array[at] as f64;
                        }
                        den += wc;
                    }
                }
            }
        }
        if den > 0.0 {
            num.map(|x| x / den)
        } else {
            [0.0; K]
        }
    }

    /// [`eval`](Self::eval) for `s` already folded into the light half's domain.
    #[inline]
    pub(crate) fn eval_folded(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        if let Some(model) = self.exact_at(s, v) {
            return model.eval(s, v);
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

/// A folded query as [`Table::eval_at`] reads it: the (unnormalized) half vector and the axis
/// direction's azimuth.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Query {
    h: Vec3,
    cos: f64,
    sin: f64,
    /// How far the pair is turned onto each azimuth node: 0 (fixed half vector) while the other
    /// direction is clear of the horizon, 1 (a rigid turn) next to it.
    turn: f64,
}

impl Query {
    #[inline]
    pub(crate) fn new(axis: Vec3, other: Vec3) -> Query {
        let r = (axis.x * axis.x + axis.y * axis.y).sqrt();
        let (cos, sin) = if r > 0.0 {
            (axis.x / r, axis.y / r)
        } else {
            (1.0, 0.0)
        };
        let (lo, hi) = (
            TURN_FROM_DEG.to_radians().cos(),
            TURN_FULL_DEG.to_radians().cos(),
        );
        let x = ((lo - other.z) / (lo - hi)).clamp(0.0, 1.0);
        Query {
            h: axis + other,
            cos,
            sin,
            turn: x * x * (3.0 - 2.0 * x),
        }
    }
}

/// The other direction's polar angle from which azimuth interpolation starts turning the pair.
pub(crate) const TURN_FROM_DEG: f64 = 75.0;
/// The other direction's polar angle from which the pair is turned rigidly.
pub(crate) const TURN_FULL_DEG: f64 = 88.0;

/// The located axis direction `d` (folded).
#[inline]
pub(crate) fn locate_axis(theta: &Axis, phi: &Axis, d: Vec3) -> Incidence {
    let (it, wt) = theta.locate(d.z.clamp(-1.0, 1.0).acos());
    let (ip, wp) = phi.locate(d.y.atan2(d.x));
    (it, wt, ip, wp)
}

impl Table {
    /// [`sample`](Bsdf::sample) without the BRDF value: the drawn `v` and its density, for a
    /// caller that evaluates `f` itself (a renderer sampling `wi` for a given `wo` with the roles
    /// swapped, or with other albedos). Deterministic in `(u1, u2)`, the same draw as `sample`.
    #[inline]
    pub fn sample_direction(&self, s: Vec3, u1: f64, u2: f64) -> Option<(Vec3, f64)> {
        if s.z <= 0.0 {
            return None;
        }
        let fold = Fold::of(self.symmetry, s);
        let (vf, pdf, _) = self.sampler.sample::<false>(self, fold.apply(s), u1, u2)?;
        Some((fold.undo(vf), pdf))
    }
}

impl Table {
    /// The density with which the table's sampler draws `v` for light from `s`, per unit solid
    /// angle (the paper's naming; [`Bsdf::pdf`] names the pair the renderer's way).
    #[inline]
    pub fn pdf_direction(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let fold = Fold::of(self.symmetry, s);
        self.sampler.pdf(self, fold.apply(s), fold.apply(v))
    }
}

impl Bsdf for Table {
    type Value = f64;

    fn lobes(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::GLOSSY | LobeFlags::DIFFUSE | LobeFlags::ANISOTROPIC
    }

    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        Table::eval(self, wi, wo)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        self.pdf_direction(known, drawn)
    }

    #[inline]
    fn sample(&self, known: Vec3, _uc: f64, u: [f64; 2], mode: Transport) -> Option<BsdfSample> {
        if known.z <= 0.0 {
            return None;
        }
        let fold = Fold::of(self.symmetry, known);
        let (drawn, pdf, f) = match mode {
            // The sampler's own f is f(s = known, v = drawn): the pair the right way round.
            Transport::Importance => {
                let (d, pdf, f) =
                    self.sampler
                        .sample::<true>(self, fold.apply(known), u[0], u[1])?;
                (fold.undo(d), pdf, f)
            }
            Transport::Radiance => {
                let (d, pdf, _) =
                    self.sampler
                        .sample::<false>(self, fold.apply(known), u[0], u[1])?;
                let d = fold.undo(d);
                (d, pdf, Table::eval(self, d, known))
            }
        };
        let (wi, wo) = pair_of(known, drawn, mode);
        Some(BsdfSample {
            wo,
            wi,
            f,
            pdf,
            lobe: LobeFlags::REFLECTION | LobeFlags::GLOSSY,
        })
    }
}
