//! The cloth BRDF: fiber → yarn → weave (paper Eq. (23); docs/spec.md §2.7).

use crate::fiber::Fiber;
use crate::math::Vec3;
use crate::yarn::Yarn;
use std::f64::consts::FRAC_PI_2;
use std::ops::{AddAssign, Mul};

/// The yarn axes of a weave and their weights, `[(φ_y, w)]`: the weft along `x` with weight `γ`
/// and the warp along `y` with weight `1 − γ` (Eq. (23)).
#[inline]
pub fn weave_axes(weft_fraction: f64) -> [(f64, f64); 2] {
    [(0.0, weft_fraction), (FRAC_PI_2, 1.0 - weft_fraction)]
}

/// Each family's BRDF on its tilted floats, `[weft, warp]` (the yarn's `u_max > 0`): `f(yarn,
/// s′, v′, weight)` evaluates the yarn along `x` with the family's weight (`γ` or `1 − γ`) at
/// directions in a facet's frame, and [`FloatProfile::average`](crate::yarn::float::FloatProfile::average) takes the whole float's mean
/// over them, the warp's directions first turned so that its axis lies along `x`.
pub fn tilted_families<V>(
    yarn: &Yarn,
    weft_fraction: f64,
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
        float.average(s, v, |a, b| f(yarn, a, b, weft_fraction)),
        float.average(to_warp(s), to_warp(v), |a, b| {
            f(yarn, a, b, 1.0 - weft_fraction)
        }),
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
    },
}

impl Structure {
    /// `f_cloth(s, v) = γ f_yarn(s, v; 0) + (1 − γ) f_yarn(s, v; π/2)` (Eq. (23)), or the fiber BRDF.
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
            } if yarn.params().u_max > 0.0 => {
                let [weft, warp] = tilted_families(yarn, *weft_fraction, s, v, |y, a, b, w| {
                    y.eval_mix(a, b, &[(0.0, w)])
                });
                weft + warp
            }
            Structure::Woven {
                yarn,
                weft_fraction,
            } => yarn.eval_mix(s, v, &weave_axes(*weft_fraction)),
        }
    }

    /// The yarn and its weave axes ([`weave_axes`]), or `None` for a flat fiber surface.
    pub fn yarns(&self) -> Option<(&Yarn, [(f64, f64); 2])> {
        match self {
            Structure::Flat(_) => None,
            Structure::Woven {
                yarn,
                weft_fraction,
            } => Some((yarn, weave_axes(*weft_fraction))),
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
