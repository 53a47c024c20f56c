//! Light straight through a surface ([`SurfaceSpec::transmission`](super::SurfaceSpec)): the
//! share of the light along a direction that passes between the yarns unscattered, a delta lobe
//! a renderer follows by continuing the ray.
//!
//! At the cloth level it is the open area [`open_area`](crate::gaps::open_area) `O(d)`
//! everywhere. At the yarn and fibre levels the gaps are where it goes through: a hole between
//! gapped yarns (where the layout puts no yarn, [`WovenSurface::texel`]) passes `O(d) / gap²`
//! and a yarn nothing, which averages to `O(d)` over a cell. Between the levels the two blend
//! by the footprint's weight, as the lobes do. Where the reflection is the cloth's average the
//! passing share is too, so reflected and passed light never exceed what arrives.

use super::{SurfacePoint, WovenSurface};
use crate::Vec3;

/// Where a point lies for the light through it: the cloth level's share of its shading (the
/// footprint's weight), and whether at the yarn level it is a hole between gapped yarns.
#[derive(Clone, Copy, Debug)]
pub(super) struct Through {
    pub(super) cloth: f64,
    pub(super) hole: bool,
}

impl WovenSurface {
    /// Whether light may pass through the surface (its `transmission` is on): between the yarns
    /// where they leave gaps ([`pass_through`](Self::pass_through)), and through the yarns
    /// ([`Translucency`](super::translucent::Translucency)).
    pub fn transmits(&self) -> bool {
        self.open.is_some()
    }

    /// The light through the surface's yarns ([`Translucency`](super::translucent::Translucency)),
    /// worked out on first use (a fraction of a second).
    pub fn translucency(&self) -> &super::translucent::Translucency {
        self.translucency
            .get_or_init(|| super::translucent::of(self))
    }

    /// The cloth level's open area along `d` (either side): `O(d)`, 0 where the surface does
    /// not transmit.
    pub fn open_along(&self, d: Vec3) -> f64 {
        match &self.open {
            Some(section) if self.gap > 0.0 && d.z.is_finite() => section.open_along(d),
            _ => 0.0,
        }
    }

    /// Where `at` lies for the light through it ([`Through`]); a surface without a pattern is
    /// its cloth level everywhere.
    pub(super) fn through(&self, at: &SurfacePoint) -> Through {
        if self.pattern().is_none() {
            return Through {
                cloth: 1.0,
                hole: false,
            };
        }
        let cloth = self.macro_weight(at);
        let hole = cloth < 1.0 && self.gap > 0.0 && {
            let t = self.texel(at.uv);
            t.weft + t.warp == 0.0
        };
        Through { cloth, hole }
    }

    /// The share of the light along `d` (the surface's frame, either side) that passes straight
    /// through at `at`, in `[0, 1]` (module docs); 0 where the surface does not transmit.
    pub fn pass_through(&self, at: &SurfacePoint, d: Vec3) -> f64 {
        let open = self.open_along(d);
        if open == 0.0 {
            return 0.0;
        }
        self.share(self.through(at), open)
    }

    /// The share passed along `d` at a point that lies as `t` says (module docs).
    pub(super) fn passed(&self, t: Through, d: Vec3) -> f64 {
        let open = self.open_along(d);
        if open == 0.0 {
            return 0.0;
        }
        self.share(t, open)
    }

    /// What a point that lies as `t` says passes where the cloth's open area is `open`.
    fn share(&self, t: Through, open: f64) -> f64 {
        let resolved = if t.hole {
            (open / (self.gap * self.gap)).min(1.0)
        } else {
            0.0
        };
        t.cloth * open + (1.0 - t.cloth) * resolved
    }
}

#[cfg(test)]
mod tests {
    use crate::gaps::open_area;
    use crate::material::{Material, Weave};
    use crate::surface::{SurfacePoint, SurfaceSpec, WovenSurface};
    use crate::Vec3;

    fn surface(gap: f64, transmission: bool) -> WovenSurface {
        let mut material = Material::preset("linen-plain").unwrap();
        material.weave = Some(Weave::named("plain").unwrap());
        let spec = SurfaceSpec {
            yarns_per_unit: [10.0, 10.0],
            gap,
            transmission,
            ..SurfaceSpec::new(material)
        };
        crate::surface::test_surface(&spec, [3, 2, 5])
    }

    #[test]
    fn the_holes_pass_what_the_open_area_says_on_average_and_the_cloth_level_passes_it_everywhere()
    {
        let gap = 0.3;
        let s = surface(gap, true);
        assert!(s.transmits());
        for d in [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::from_spherical(0.5, 0.3),
            Vec3::from_spherical(0.9, 1.2),
            Vec3::new(0.1, -0.2, -0.97).normalize(),
        ] {
            let want = open_area(gap, d).unwrap();
            // Yarn level (no footprint): the mean over a cell's points.
            let n = 200;
            let mut sum = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let uv = [
                        (i as f64 + 0.5) / (10.0 * n as f64),
                        (j as f64 + 0.5) / (10.0 * n as f64),
                    ];
                    let p = s.pass_through(
                        &SurfacePoint {
                            uv,
                            footprint: [[0.0; 2]; 2],
                        },
                        d,
                    );
                    assert!((0.0..=1.0).contains(&p));
                    sum += p;
                }
            }
            let mean = sum / (n * n) as f64;
            assert!(
                (mean - want).abs() < 1e-3 * want.max(1e-3),
                "{d:?}: {mean} {want}"
            );
            // Cloth level (a footprint of many cells): the open area at every point.
            let far = SurfacePoint {
                uv: [0.01, 0.02],
                footprint: [[1.0, 0.0], [0.0, 1.0]],
            };
            assert!((s.pass_through(&far, d) - want).abs() < 1e-15);
        }
        // Off, or without gaps, nothing passes.
        let at = SurfacePoint {
            uv: [0.095, 0.095],
            footprint: [[0.0; 2]; 2],
        };
        assert_eq!(
            surface(gap, false).pass_through(&at, Vec3::new(0.0, 0.0, 1.0)),
            0.0
        );
        let closed = surface(0.0, true);
        assert!(closed.transmits() && closed.pass_through(&at, Vec3::new(0.0, 0.0, 1.0)) == 0.0);
    }
}
