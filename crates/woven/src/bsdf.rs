//! The renderer-facing interface: evaluation, importance sampling and densities, as the BSDFs
//! of pbrt-v4 (`BxDF`) and Mitsuba 3 (`BSDF`) have it.
//!
//! Directions live in the cloth's local frame (docs/spec.md §0; `docs/conventions.md`): `z` is the
//! macro normal, the weft runs along `x`. They are named the renderer's way: `wo` points toward
//! the viewer (the paper's `v`), `wi` toward the light (the paper's `s`), both away from the
//! surface, and every call takes them in the paper's order, `(wi, wo)` as `(s, v)`, as the
//! renderer's materials do. [`Bsdf::eval`] is the BRDF `f(s = wi, v = wo)` in sr⁻¹ without the
//! cosine, whoever asks; a density is per unit solid angle.
//!
//! **Transport mode.** With `normalization = "paper"` the model is not reciprocal
//! (`f(s, v) ≠ f(v, s)` by `β(θ_i)`), so which of the two directions is known matters when one
//! is drawn. A camera path ([`Transport::Radiance`]) knows `wo` and draws `wi`; a light path
//! ([`Transport::Importance`]) knows `wi` and draws `wo`. [`Bsdf::sample`] draws the unknown
//! direction for the known one; [`Bsdf::pdf`] is the density of that draw; the value is always
//! the true `f(wi, wo)`, so the estimate stays unbiased in either mode. Tables sample `v` for
//! a given `s` (∝ `f(s, v) cos θ_v`); in radiance mode they draw with the roles swapped —
//! `wi` as the `v` of `s = wo` — which is exact where the model is reciprocal and a close
//! importance function where it is not.

use crate::math::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use crate::math::Vec3;
use crate::Model;
use std::f64::consts::FRAC_1_PI;
use std::ops::{BitOr, Mul};
use std::sync::Arc;

/// Which direction a path knows when it samples a BSDF.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Transport {
    /// A camera path: `wo` (toward the viewer) is known, `wi` (toward the light) is drawn.
    #[default]
    Radiance,
    /// A light path: `wi` (toward the light) is known, `wo` (toward the viewer) is drawn.
    Importance,
}

/// What kinds of scattering a BSDF (or one drawn lobe) has: a set of bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LobeFlags(u8);

impl LobeFlags {
    /// No scattering.
    pub const NONE: LobeFlags = LobeFlags(0);
    /// Reflection.
    pub const REFLECTION: LobeFlags = LobeFlags(1);
    /// A glossy lobe (the fibers' specular highlights).
    pub const GLOSSY: LobeFlags = LobeFlags(1 << 1);
    /// A diffuse lobe (the fibers' body).
    pub const DIFFUSE: LobeFlags = LobeFlags(1 << 2);
    /// The BSDF changes when turned about the normal (oriented fibers).
    pub const ANISOTROPIC: LobeFlags = LobeFlags(1 << 3);
    /// The BSDF changes across the surface (a weave pattern, textured dyes).
    pub const SPATIALLY_VARYING: LobeFlags = LobeFlags(1 << 4);
    /// Transmission to the far side (a woven surface with `transmission` on: the light through
    /// its yarns).
    pub const TRANSMISSION: LobeFlags = LobeFlags(1 << 5);

    /// Whether every bit of `other` is set here.
    pub fn contains(self, other: LobeFlags) -> bool {
        self.0 & other.0 == other.0
    }
}

impl BitOr for LobeFlags {
    type Output = LobeFlags;
    fn bitor(self, o: LobeFlags) -> LobeFlags {
        LobeFlags(self.0 | o.0)
    }
}

/// A direction drawn by [`Bsdf::sample`], with both directions of the pair named.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample<V = f64> {
    /// Toward the viewer, unit, `z > 0` (drawn in [`Transport::Importance`]; `z < 0` when
    /// drawn through a transmitting surface).
    pub wo: Vec3,
    /// Toward the light, unit, `z > 0` (drawn in [`Transport::Radiance`]; `z < 0` when drawn
    /// through a transmitting surface).
    pub wi: Vec3,
    /// `f(wi, wo)`, sr⁻¹ (per channel for a coloured surface).
    pub f: V,
    /// The density the drawn direction was drawn with, per unit solid angle, > 0.
    pub pdf: f64,
    /// The kind of lobe that was drawn.
    pub lobe: LobeFlags,
}

impl<V> BsdfSample<V> {
    /// The same draw with the value `f` in place of its own (another view of the same BSDF: a
    /// colour, its luminance).
    pub fn with_f<W>(self, f: W) -> BsdfSample<W> {
        BsdfSample {
            wo: self.wo,
            wi: self.wi,
            f,
            pdf: self.pdf,
            lobe: self.lobe,
        }
    }
}

/// Completes a direction `drawn` for `known` into a sample of `bsdf`: the pair named for `mode`,
/// its value and the density [`Bsdf::pdf`] gives; `None` below the horizon or at density 0.
pub fn complete_draw<B: Bsdf + ?Sized>(
    bsdf: &B,
    known: Vec3,
    drawn: Vec3,
    lobe: LobeFlags,
    mode: Transport,
) -> Option<BsdfSample<B::Value>> {
    if drawn.z <= 0.0 {
        return None;
    }
    let (wi, wo) = pair_of(known, drawn, mode);
    let pdf = bsdf.pdf(wi, wo, mode);
    (pdf > 0.0).then(|| BsdfSample {
        wo,
        wi,
        f: bsdf.eval(wi, wo),
        pdf,
        lobe,
    })
}

impl<V: Copy + Mul<f64, Output = V>> BsdfSample<V> {
    /// The Monte Carlo weight `f |cos θ| / pdf`, `θ` the drawn direction's polar angle (on
    /// either side: a transmitted direction's cosine is negative).
    pub fn weight(&self, mode: Transport) -> V {
        let cos = match mode {
            Transport::Radiance => self.wi.z,
            Transport::Importance => self.wo.z,
        };
        self.f * (cos.abs() / self.pdf)
    }
}

/// A BSDF as a renderer uses it. Implementations are `Send + Sync` and allocate nothing per call.
pub trait Bsdf: Send + Sync {
    /// What [`eval`](Bsdf::eval) returns: `f64` for one channel, [`Rgb`](crate::color::Rgb) for
    /// a dyed surface.
    type Value: Copy;

    /// The kinds of scattering this BSDF has.
    fn lobes(&self) -> LobeFlags;

    /// The BRDF `f(s = wi, v = wo)`, sr⁻¹, without the cosine; 0 when either direction is below
    /// the horizon.
    fn eval(&self, wi: Vec3, wo: Vec3) -> Self::Value;

    /// The density per unit solid angle with which [`sample`](Bsdf::sample) in `mode` draws the
    /// unknown direction of the pair for the known one.
    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64;

    /// [`eval`](Bsdf::eval) and [`pdf`](Bsdf::pdf) in one call (implementations share the
    /// work where they can).
    fn eval_pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> (Self::Value, f64) {
        (self.eval(wi, wo), self.pdf(wi, wo, mode))
    }

    /// Draws the unknown direction of the pair for `known` (`wo` in [`Transport::Radiance`],
    /// `wi` in [`Transport::Importance`]). `uc` in `[0, 1)` chooses among lobes (a BSDF of one
    /// lobe ignores it) and `u` in `[0, 1)²` draws within the lobe, so stratified points stay
    /// stratified; deterministic in `(uc, u)`. `None` when no direction results (`known` below
    /// the horizon, or a rejected draw).
    fn sample(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Self::Value>>;

    /// The warp's share of the BSDF for a viewer toward `wo`, in `[0, 1]`: which yarn family
    /// the view meets (on a relief, the yarn its ray meets first). 0 without yarns. It tells a
    /// weave's families apart without noise (a denoiser's guide).
    fn warp_share(&self, _wo: Vec3) -> f64 {
        0.0
    }

    /// The share of the light along `d` (either side) that passes straight through, in `[0,
    /// 1]`: a delta lobe beside `eval`'s, which a renderer follows by continuing the ray. 0 for
    /// every BSDF but a woven surface's with `transmission` on.
    fn pass_through(&self, _d: Vec3) -> f64 {
        0.0
    }
}

/// Splits a pair `(wi, wo)` into `(known, drawn)` for `mode`: the known direction is the `s` a
/// table's sampler draws `v` for.
#[inline]
pub fn known_and_drawn(wi: Vec3, wo: Vec3, mode: Transport) -> (Vec3, Vec3) {
    match mode {
        Transport::Radiance => (wo, wi),
        Transport::Importance => (wi, wo),
    }
}

/// Names a drawn pair: `(known, drawn)` back as `(wi, wo)`.
#[inline]
pub fn pair_of(known: Vec3, drawn: Vec3, mode: Transport) -> (Vec3, Vec3) {
    match mode {
        Transport::Radiance => (drawn, known),
        Transport::Importance => (known, drawn),
    }
}

/// The exact model samples a cosine-weighted hemisphere: correct for any material, with a density
/// that ignores the highlights. Renderers should sample a [`Table`](crate::table::Table).
impl Bsdf for Model {
    type Value = f64;

    fn lobes(&self) -> LobeFlags {
        let lobes =
            LobeFlags::REFLECTION | LobeFlags::GLOSSY | LobeFlags::DIFFUSE | LobeFlags::ANISOTROPIC;
        if self.transmits() {
            lobes | LobeFlags::TRANSMISSION
        } else {
            lobes
        }
    }

    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        Model::eval(self, wi, wo)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        exact_pdf(self.transmits(), known, drawn)
    }

    fn sample(&self, known: Vec3, uc: f64, u: [f64; 2], mode: Transport) -> Option<BsdfSample> {
        let (drawn, lobe) = exact_draw(self.transmits(), known, uc, u)?;
        let (wi, wo) = pair_of(known, drawn, mode);
        Some(BsdfSample {
            wo,
            wi,
            f: Model::eval(self, wi, wo),
            pdf: exact_pdf(self.transmits(), known, drawn),
            lobe,
        })
    }

    fn pass_through(&self, d: Vec3) -> f64 {
        self.open_along(d)
    }
}

/// The share of an exact transmitting model's draws that cross the cloth.
pub const EXACT_THROUGH_SHARE: f64 = 0.5;

/// The exact model's density of `drawn` for `known`: a cosine-weighted hemisphere on the known
/// direction's side, and for a cloth that `transmits`, [`EXACT_THROUGH_SHARE`] of the draws in
/// the same on the far side.
pub fn exact_pdf(transmits: bool, known: Vec3, drawn: Vec3) -> f64 {
    if !transmits {
        return if known.z <= 0.0 {
            0.0
        } else {
            cosine_hemisphere_pdf(drawn.z)
        };
    }
    if known.z == 0.0 || drawn.z == 0.0 {
        return 0.0;
    }
    let share = if (known.z > 0.0) == (drawn.z > 0.0) {
        1.0 - EXACT_THROUGH_SHARE
    } else {
        EXACT_THROUGH_SHARE
    };
    share * drawn.z.abs() * FRAC_1_PI
}

/// The exact model's draw for `known` ([`exact_pdf`]'s density) and its lobe: `uc` picks the
/// side for a cloth that `transmits`.
pub fn exact_draw(transmits: bool, known: Vec3, uc: f64, u: [f64; 2]) -> Option<(Vec3, LobeFlags)> {
    if known.z == 0.0 || (known.z < 0.0 && !transmits) {
        return None;
    }
    let d = cosine_hemisphere(u[0], u[1]);
    if d.z <= 0.0 {
        return None;
    }
    let through = transmits && uc < EXACT_THROUGH_SHARE;
    let side = if (known.z > 0.0) != through {
        1.0
    } else {
        -1.0
    };
    let lobe = if through {
        LobeFlags::TRANSMISSION
    } else {
        LobeFlags::REFLECTION
    };
    Some((Vec3::new(d.x, d.y, side * d.z), lobe | LobeFlags::DIFFUSE))
}

/// A boxed or shared BSDF is a BSDF (front ends choose the material at run time).
macro_rules! forward_bsdf {
    ($($pointer:ident),*) => {$(
        impl<B: Bsdf + ?Sized> Bsdf for $pointer<B> {
            type Value = B::Value;

            fn lobes(&self) -> LobeFlags {
                (**self).lobes()
            }

            #[inline]
            fn eval(&self, wi: Vec3, wo: Vec3) -> B::Value {
                (**self).eval(wi, wo)
            }

            #[inline]
            fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
                (**self).pdf(wi, wo, mode)
            }

            fn eval_pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> (B::Value, f64) {
                (**self).eval_pdf(wi, wo, mode)
            }

            fn sample(
                &self,
                known: Vec3,
                uc: f64,
                u: [f64; 2],
                mode: Transport,
            ) -> Option<BsdfSample<B::Value>> {
                (**self).sample(known, uc, u, mode)
            }

            fn warp_share(&self, wo: Vec3) -> f64 {
                (**self).warp_share(wo)
            }

            fn pass_through(&self, d: Vec3) -> f64 {
                (**self).pass_through(d)
            }
        }
    )*};
}

forward_bsdf!(Box, Arc);
