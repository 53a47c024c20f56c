//! One lobe ([`Lobe`]) in its own frame: the warp turned onto the weft, tilted with its float
//! or leaning with the relief; its BRDF, its density and its draws, from the yarn's table (the
//! crowned table for a resolved macro lobe, a whole float's own table for a whole tilted float)
//! or, at fibre level, from the point on its yarn.

use super::fibers::{point_eval, point_pdf, point_sample};
use super::{Lobe, Tilt, WovenSurface};
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
    /// `cos θ′o / (cos θo cos ψ)` per unit of cloth
    /// ([`FloatProfile::average`](crate::yarn::float::FloatProfile::average)), tabulated: one
    /// look-up in the float's table ([`Table::tilted`]). At
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
    /// floats; for a whole float, that table's average over the float, tabulated
    /// ([`tilted_table`](Self::tilted_table)).
    #[inline]
    fn lobe_with<V>(
        &self,
        lobe: &Lobe,
        wi: Vec3,
        wo: Vec3,
        read: impl Fn(&Table, Vec3, Vec3) -> V,
    ) -> V
    where
        V: Default + std::ops::AddAssign + std::ops::Mul<f64, Output = V>,
    {
        let (wi, wo) = into_lobe_frame(lobe, wi, wo);
        if lobe.tilt == Tilt::Float {
            return read(self.tilted_table(lobe.warp, lobe.resolved), wi, wo);
        }
        let (table, float) = match (&self.relief, lobe.resolved) {
            (Some(relief), true) => (self.crowned(), &relief.float(lobe.warp)),
            _ => (&*self.tables.yarn, &self.float),
        };
        let value = |a: Vec3, b: Vec3| read(table, a, b);
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
            Tilt::Float => unreachable!("a whole float reads its own table, above"),
        }
    }

    /// The tilt (sine, cosine) a draw for `known` (in the lobe's frame) uses: the facet that
    /// `known`'s ray meets for a point. `None` for a flat lobe and a whole float (drawn from its
    /// own table).
    #[inline]
    fn draw_tilt(&self, lobe: &Lobe, known: Vec3) -> Option<Lean> {
        let float = &self.float;
        match lobe.tilt {
            Tilt::Flat | Tilt::Float => None,
            Tilt::Entering(entry) => {
                let t = float.seen_at(entry, known);
                Some(Lean::tilted(float.tilt(t).sin_cos()))
            }
            Tilt::Relief { lean, .. } => Some(lean),
        }
    }

    /// The density of drawing `drawn` for `known` from one lobe (a rotation keeps densities per
    /// solid angle); for a whole float, its own table's.
    #[inline]
    pub(super) fn lobe_pdf(&self, lobe: &Lobe, known: Vec3, drawn: Vec3) -> f64 {
        let (k, d) = into_lobe_frame(lobe, known, drawn);
        if lobe.tilt == Tilt::Float {
            return self
                .tilted_table(lobe.warp, lobe.resolved)
                .pdf_direction(k, d);
        }
        let untilted = |k: Vec3, d: Vec3| match (&lobe.point, &self.fibers) {
            (Some(p), Some(f)) => point_pdf(f, p, k, d),
            _ => self.tables.yarn.pdf_direction(k, d),
        };
        let tilted = |lean: Lean| {
            let (k, d) = (lean.into_frame(k), lean.into_frame(d));
            if k.z <= 0.0 || d.z <= 0.0 {
                0.0
            } else {
                untilted(k, d)
            }
        };
        match self.draw_tilt(lobe, k) {
            None => untilted(k, d),
            Some(lean) => tilted(lean),
        }
    }

    /// Draws a direction for `known` from one lobe, with its density
    /// ([`lobe_pdf`](Self::lobe_pdf)).
    #[inline]
    pub(super) fn lobe_sample(&self, lobe: &Lobe, known: Vec3, u: [f64; 2]) -> Option<(Vec3, f64)> {
        let k0 = if lobe.warp { to_warp(known) } else { known };
        let lean = self.draw_tilt(lobe, k0);
        let k = match lean {
            Some(lean) => lean.into_frame(k0),
            None => k0,
        };
        if k.z <= 0.0 {
            return None;
        }
        let (mut d, pdf) = match (&lobe.point, &self.fibers) {
            (Some(p), Some(f)) => point_sample(f, p, k, u)?,
            _ if lobe.tilt == Tilt::Float => self
                .tilted_table(lobe.warp, lobe.resolved)
                .sample_direction(k, u[0], u[1])?,
            _ => self.tables.yarn.sample_direction(k, u[0], u[1])?,
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
