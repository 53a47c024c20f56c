//! The cloth BRDF: fiber → yarn → weave (paper Eq. (23); docs/spec.md §2.7).

use crate::fiber::Fiber;
use crate::gaps::Cover;
use crate::math::Vec3;
use crate::yarn::Yarn;
use std::f64::consts::FRAC_PI_2;
use std::ops::{AddAssign, Mul};

/// The yarn axes of a weave and their weights, `[(φ_y, w)]`: the weft along `x` with weight `γ`
/// and the warp along `y` with weight `1 − γ` (Eq. (23)); where the yarns leave `gap` of their
/// pitch between them, each family's whole share of the cloth ([`Cover::total`]), which add
/// to `1 − gap²`.
#[inline]
pub fn weave_axes(weft_fraction: f64, gap: f64) -> [(f64, f64); 2] {
    let [weft, warp] = Cover::new(weft_fraction, gap).total();
    [(0.0, weft), (FRAC_PI_2, warp)]
}

/// Each family's BRDF on its tilted floats, `[weft, warp]` (the yarn's `u_max > 0`): `f(yarn,
/// s′, v′, weight)` evaluates the yarn along `x` with the family's weight (of `weights`) at
/// directions in a facet's frame, and [`FloatProfile::average`](crate::yarn::float::FloatProfile::average) takes the whole float's mean
/// over them, the warp's directions first turned so that its axis lies along `x`.
pub fn tilted_families<V>(
    yarn: &Yarn,
    weights: [f64; 2],
    s: Vec3,
    v: Vec3,
    mut f: impl FnMut(&Yarn, Vec3, Vec3, f64) -> V,
) -> [V; 2]
where
    V: Default + AddAssign + Mul<f64, Output = V>,
{
    let Some(float) = yarn.params().float_profile() else {
        return [V::default(), V::default()];
    };
    let to_warp = |d: Vec3| Vec3::new(d.y, -d.x, d.z);
    [
        float.average(s, v, |a, b| f(yarn, a, b, weights[0])),
        float.average(to_warp(s), to_warp(v), |a, b| f(yarn, a, b, weights[1])),
    ]
}

/// The structure a material's fiber surface is arranged in.
#[derive(Clone, Debug)]
pub enum Structure {
    /// A flat fiber surface (no `[yarn]` table).
    Flat(Fiber),
    /// Weft yarns along `x` (weight `γ`) and warp yarns along `y` (weight `1 − γ`).
    Woven {
        /// The yarn model (the same yarn for weft and warp), boxed: it is far larger than a fiber.
        yarn: Box<Yarn>,
        /// `γ`, the visible fraction of weft.
        weft_fraction: f64,
        /// The share of each cell's width between yarns (`[weave] gap`; 0: the paper's cloth,
        /// whose yarns fill their cells). Each family's weight is then its [`Cover`].
        gap: f64,
    },
}

impl Structure {
    /// `f_cloth(s, v) = γ f_yarn(s, v; 0) + (1 − γ) f_yarn(s, v; π/2)` (Eq. (23)), or the fiber BRDF.
    /// With a gap, each family weighs its [`Cover`]; with tilted floats, the share on top
    /// tilts and the share below lies flat.
    ///
    /// Implements Eq. (23) of the paper; docs/spec.md §2.7.
    #[inline]
    pub fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        match self {
            Structure::Flat(fiber) => fiber.eval(s, v),
            Structure::Woven {
                yarn,
                weft_fraction,
                gap,
            } if yarn.params().u_max > 0.0 => {
                let cover = Cover::new(*weft_fraction, *gap);
                let [weft, warp] = tilted_families(yarn, cover.top, s, v, |y, a, b, w| {
                    y.eval_mix(a, b, &[(0.0, w)])
                });
                let below = if *gap > 0.0 {
                    let [a, b] = cover.below;
                    yarn.eval_mix(s, v, &[(0.0, a), (FRAC_PI_2, b)])
                } else {
                    0.0
                };
                weft + warp + below
            }
            Structure::Woven {
                yarn,
                weft_fraction,
                gap,
            } => yarn.eval_mix(s, v, &weave_axes(*weft_fraction, *gap)),
        }
    }

    /// The yarn and its weave axes ([`weave_axes`]), or `None` for a flat fiber surface.
    pub fn yarns(&self) -> Option<(&Yarn, [(f64, f64); 2])> {
        match self {
            Structure::Flat(_) => None,
            Structure::Woven {
                yarn,
                weft_fraction,
                gap,
            } => Some((yarn, weave_axes(*weft_fraction, *gap))),
        }
    }

    /// The share of each cell's width between yarns (0 for a flat fiber surface).
    pub fn gap(&self) -> f64 {
        match self {
            Structure::Flat(_) => 0.0,
            Structure::Woven { gap, .. } => *gap,
        }
    }

    /// The fiber surface.
    pub fn fiber(&self) -> &Fiber {
        match self {
            Structure::Flat(f) => f,
            Structure::Woven { yarn, .. } => yarn.fiber(),
        }
    }
}
