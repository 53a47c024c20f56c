//! The cloth BRDF: fiber → yarn → weave (paper Eq. (23); docs/spec.md §2.7).

use crate::fiber::Fiber;
use crate::math::Vec3;
use crate::yarn::Yarn;
use std::f64::consts::FRAC_PI_2;

/// The yarn axes of a weave and their weights, `[(φ_y, w)]`: the weft along `x` with weight `γ`
/// and the warp along `y` with weight `1 − γ` (Eq. (23)).
#[inline]
pub fn weave_axes(weft_fraction: f64) -> [(f64, f64); 2] {
    [(0.0, weft_fraction), (FRAC_PI_2, 1.0 - weft_fraction)]
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
