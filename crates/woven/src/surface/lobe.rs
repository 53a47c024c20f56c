//! One lobe ([`Lobe`]) in its own frame: the warp turned onto the weft, tilted with its float
//! or leaning with the relief; its BRDF, its density and its draws, from the yarn's table (the
//! crowned table for a resolved macro lobe) or, at fibre level, from the point on its yarn.

use super::fibers::{point_eval, point_pdf, point_sample};
use super::{Lobe, Tilt, WovenSurface, TILT_NODES};
use crate::color::Rgb;
use crate::relief::Lean;
use crate::table::{Albedos, Table};
use crate::Vec3;

impl WovenSurface {
    /// One lobe's BRDF per channel: the weft, or the warp (turned), flat or on its float.
    ///
    /// On a tilted float a point shades as the facet the viewer's ray meets
    /// ([`FloatProfile::seen_at`](crate::yarn::float::FloatProfile::seen_at)), if lit: `f′(ti, to) cos θ′i / cos θi` — the facet's radiance
    /// for unit irradiance on the cloth, its own incident cosine over the cloth's — so no point
    /// is brighter than its facet. The whole float ([`Tilt::Float`]) is those points' mean: the
    /// facets both lit and seen, each over its projected area toward the viewer,
    /// `cos θ′o / (cos θo cos ψ)` per unit of cloth ([`TILT_NODES`] Gauss–Legendre nodes). At
    /// fibre level the same holds for the point's BRDF, whose profile lies in the tilted frame
    /// (the tilt turns the yarn about its cross axis; the profile runs across it).
    #[inline]
    pub(super) fn lobe_eval(
        &self,
        lobe: &Lobe,
        albedos: &[Albedos; 3],
        wi: Vec3,
        wo: Vec3,
        ratio: Option<f64>,
    ) -> Rgb {
        if let (Tilt::Relief { at, .. }, Some(relief)) = (lobe.tilt, &self.relief) {
            if !relief.sees(at, wi) {
                return Rgb::BLACK;
            }
        }
        if let Some(ratio) = ratio {
            return self.lobe_value(lobe, albedos, wi, wo) * ratio;
        }
        self.lobe_value(lobe, albedos, wi, wo)
    }

    /// [`lobe_eval`](Self::lobe_eval) before the relief: a relief point as if lit, a macro lobe
    /// unscaled.
    #[inline]
    fn lobe_value(&self, lobe: &Lobe, albedos: &[Albedos; 3], wi: Vec3, wo: Vec3) -> Rgb {
        self.lobe_with(lobe, wi, wo, |table, a, b| {
            match (&lobe.point, &self.fibers) {
                (Some(p), Some(f)) => point_eval(f, p, albedos, a, b),
                _ => Rgb(table.eval_dyed(a, b, albedos)),
            }
        })
    }

    /// [`lobe_value`](Self::lobe_value) of an averaged lobe (not a fibre point) at the
    /// material's own albedos, one value (what the relief's ratio is built from).
    #[inline]
    pub(super) fn lobe_value_own(&self, lobe: &Lobe, wi: Vec3, wo: Vec3) -> f64 {
        debug_assert!(lobe.point.is_none());
        self.lobe_with(lobe, wi, wo, |table, a, b| table.eval(a, b))
    }

    /// A lobe's value from `value(table, s′, v′)`, the BRDF of a facet in its own frame read
    /// from `table`: the yarn's, or for a resolved macro lobe the crowned yarn's on the relief's
    /// floats.
    #[inline]
    fn lobe_with<V>(
        &self,
        lobe: &Lobe,
        wi: Vec3,
        wo: Vec3,
        value: impl Fn(&Table, Vec3, Vec3) -> V,
    ) -> V
    where
        V: Default + std::ops::AddAssign + std::ops::Mul<f64, Output = V>,
    {
        let (wi, wo) = into_lobe_frame(lobe, wi, wo);
        let (table, float) = match (&self.relief, lobe.resolved) {
            (Some(relief), true) => (self.crowned(), &relief.float(lobe.warp)),
            _ => (&*self.yarn, &self.float),
        };
        let value = |a: Vec3, b: Vec3| value(table, a, b);
        // A leaning facet's radiance for unit irradiance on the cloth: its BRDF in its own
        // frame, times its incident cosine over the cloth's.
        let leaning = |lean: Lean| {
            let (ti, to) = (lean.into_frame(wi), lean.into_frame(wo));
            if ti.z <= 0.0 || to.z <= 0.0 {
                return V::default();
            }
            value(ti, to) * (ti.z / wi.z)
        };
        match lobe.tilt {
            Tilt::Flat => value(wi, wo),
            Tilt::Entering(entry) => {
                let t = float.seen_at(entry, wo);
                match float.lit(wi) {
                    Some((lo, hi)) if (lo..=hi).contains(&t) => {}
                    _ => return V::default(),
                }
                leaning(Lean::tilted(float.tilt(t).sin_cos()))
            }
            Tilt::Relief { lean, .. } => leaning(lean),
            Tilt::Float => float.average(wi, wo, value),
        }
    }

    /// The tilt (sine, cosine) a draw for `known` (in the lobe's frame) uses, drawing a tilt
    /// node of a whole float with `u` (returned stretched back to `[0, 1)`): the facet that
    /// `known`'s ray meets for a point, the [`TILT_NODES`] midpoints of a whole float. `None`
    /// for a flat lobe.
    #[inline]
    fn draw_tilt(&self, lobe: &Lobe, known: Vec3, u: f64) -> (Option<Lean>, f64) {
        let float = &self.float;
        match lobe.tilt {
            Tilt::Flat => (None, u),
            Tilt::Entering(entry) => {
                let t = float.seen_at(entry, known);
                (Some(Lean::tilted(float.tilt(t).sin_cos())), u)
            }
            Tilt::Relief { lean, .. } => (Some(lean), u),
            Tilt::Float => {
                let x = u * TILT_NODES as f64;
                let i = (x as usize).min(TILT_NODES - 1);
                let t = (i as f64 + 0.5) / TILT_NODES as f64;
                (
                    Some(Lean::tilted(float.tilt(t).sin_cos())),
                    (x - i as f64).clamp(0.0, 1.0 - f64::EPSILON),
                )
            }
        }
    }

    /// The density of drawing `drawn` for `known` from one lobe (a rotation keeps densities per
    /// solid angle); for a whole float, the mean over its tilt nodes.
    #[inline]
    pub(super) fn lobe_pdf(&self, lobe: &Lobe, known: Vec3, drawn: Vec3) -> f64 {
        let (k, d) = into_lobe_frame(lobe, known, drawn);
        let untilted = |k: Vec3, d: Vec3| match (&lobe.point, &self.fibers) {
            (Some(p), Some(f)) => point_pdf(f, p, k, d),
            _ => self.yarn.pdf_direction(k, d),
        };
        let tilted = |lean: Lean| {
            let (k, d) = (lean.into_frame(k), lean.into_frame(d));
            if k.z <= 0.0 || d.z <= 0.0 {
                0.0
            } else {
                untilted(k, d)
            }
        };
        match lobe.tilt {
            Tilt::Flat => untilted(k, d),
            Tilt::Entering(_) | Tilt::Relief { .. } => {
                tilted(self.draw_tilt(lobe, k, 0.0).0.unwrap_or(Lean::FLAT))
            }
            Tilt::Float => {
                let float = &self.float;
                (0..TILT_NODES)
                    .map(|i| {
                        let t = (i as f64 + 0.5) / TILT_NODES as f64;
                        tilted(Lean::tilted(float.tilt(t).sin_cos()))
                    })
                    .sum::<f64>()
                    / TILT_NODES as f64
            }
        }
    }

    /// Draws a direction for `known` from one lobe, with its density
    /// ([`lobe_pdf`](Self::lobe_pdf)); for a whole float, the density of the tilt node it was
    /// drawn from (the lobe's is the nodes' mean, which [`PointBsdf`](super::PointBsdf)'s `sample` takes).
    #[inline]
    pub(super) fn lobe_sample(&self, lobe: &Lobe, known: Vec3, u: [f64; 2]) -> Option<(Vec3, f64)> {
        let k0 = if lobe.warp { to_warp(known) } else { known };
        let (lean, u0) = self.draw_tilt(lobe, k0, u[0]);
        let k = match lean {
            Some(lean) => lean.into_frame(k0),
            None => k0,
        };
        if k.z <= 0.0 {
            return None;
        }
        let (mut d, pdf) = match (&lobe.point, &self.fibers) {
            (Some(p), Some(f)) => point_sample(f, p, k, [u0, u[1]])?,
            _ => self.yarn.sample_direction(k, u0, u[1])?,
        };
        if d.z <= 0.0 || pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        if let Some(lean) = lean {
            d = lean.from_frame(d);
        }
        if lobe.warp {
            d = from_warp(d);
        }
        if d.z <= 0.0 {
            return None;
        }
        Some((d, pdf))
    }
}

/// A pair of directions in the frame of a lobe's family (turned for the warp; not yet tilted).
#[inline]
fn into_lobe_frame(lobe: &Lobe, a: Vec3, b: Vec3) -> (Vec3, Vec3) {
    if lobe.warp {
        (to_warp(a), to_warp(b))
    } else {
        (a, b)
    }
}

/// Into the frame of a warp yarn: a 90° turn about `z` taking `y` (the warp) to `x`.
#[inline]
fn to_warp(d: Vec3) -> Vec3 {
    Vec3::new(d.y, -d.x, d.z)
}

/// Back from the warp yarn's frame.
#[inline]
fn from_warp(d: Vec3) -> Vec3 {
    Vec3::new(-d.y, d.x, d.z)
}
