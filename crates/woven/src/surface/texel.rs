//! What a surface lays at one point of its uv, as a renderer without woven's BSDF carries it in
//! textures ([`Texel`]): which yarn family is on top (or a hole) and each family's dye factor;
//! and each family's BRDF as the cloth shows it ([`WovenSurface::family_brdf`]), what those
//! renderers' lobes are fitted to. Blender, OpenPBR and glTF read a woven material as these
//! textures over its families' standard lobes (`woven_fit::standard`): the layout is the
//! library's, never rewritten in their languages. The float's tilt is in the families' BRDFs,
//! with the masking between facets that a normal map could not carry.

use super::{Tilt, WovenSurface};
use crate::Vec3;

/// One point of a surface's layout at yarn level, seen along the normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texel {
    /// The weft's share of the point (1 where it is on top; the weft fraction γ on a surface
    /// without a pattern).
    pub weft: f64,
    /// The warp's share; `1 − weft − warp` is the hole between gapped yarns.
    pub warp: f64,
    /// The weft's and the warp's dye factors there ([`WovenSurface::dye_factors`]).
    pub factors: [f64; 2],
}

impl WovenSurface {
    /// The surface at `uv` as textures carry it ([`Texel`]): the pattern cell's yarn at yarn
    /// level (fibres averaged: no footprint), on a relief the yarn a viewer above meets.
    pub fn texel(&self, uv: [f64; 2]) -> Texel {
        let at = super::SurfacePoint {
            uv,
            footprint: [[0.0; 2]; 2],
        };
        let mut mix = super::LobeMix::default();
        if let Some(entry) = self.split_into(&at, &mut mix) {
            mix = self.with_relief(mix, &entry, Vec3::new(0.0, 0.0, 1.0));
        }
        let mut shares = [0.0; 2];
        for lobe in mix.lobes() {
            shares[usize::from(lobe.warp)] += lobe.weight;
        }
        Texel {
            weft: shares[0],
            warp: shares[1],
            factors: self.dye_factors(&at),
        }
    }

    /// One family's BRDF as the cloth shows it from a pattern cell's distance and beyond, per
    /// channel, in the family's own frame (its yarn along `x`): the whole float where floats
    /// tilt (its lit and seen facets averaged, [`Tilt::Float`]), else the flat yarn; in the
    /// family's dye; on a relief, scaled by the relief's ratio as the macro BRDF's lobes are.
    /// What a renderer without woven's BSDF fits its lobes to: the float's tilt and the masking
    /// between floats are in it, which a normal map over standard lobes cannot carry.
    pub fn family_brdf(&self, warp: bool, wi: Vec3, wo: Vec3) -> crate::color::Rgb {
        // The lobe turns the warp's directions into its own frame: hand it the cloth's.
        let back = |d: Vec3| if warp { Vec3::new(-d.y, d.x, d.z) } else { d };
        let (wi, wo) = (back(wi), back(wo));
        let lobe = super::Lobe {
            warp,
            tilt: if self.u_max > 0.0 {
                Tilt::Float
            } else {
                Tilt::Flat
            },
            weight: 1.0,
            resolved: self.relief.is_some(),
            point: None,
        };
        let ratio = lobe.resolved.then(|| self.relief_ratio(warp, wi, wo));
        self.lobe_eval(&lobe, self.albedos(warp), wi, wo, ratio)
    }

    /// The cells of one repeat of the surface's layout, `[along u, along v]`: the pattern's
    /// columns and rows; `[1, 1]` without a pattern (the same everywhere).
    pub fn repeat_cells(&self) -> [usize; 2] {
        self.pattern().map_or([1, 1], |p| [p.cols(), p.rows()])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, Weave};
    use crate::surface::{SurfacePoint, SurfaceSpec};

    fn surface(pattern: &str, u_max_deg: f64, gap: f64) -> WovenSurface {
        woven_with(Weave::named(pattern).unwrap(), u_max_deg, gap)
    }

    /// polyester-sateen woven as `weave` on a small table, 10 cells a unit.
    fn woven_with(weave: Weave, u_max_deg: f64, gap: f64) -> WovenSurface {
        let mut material = Material::preset("polyester-sateen").unwrap();
        material.weave = Some(weave);
        let spec = SurfaceSpec {
            yarns_per_unit: [10.0, 10.0],
            u_max: u_max_deg.to_radians(),
            gap,
            ..SurfaceSpec::new(material)
        };
        crate::surface::test_surface(&spec, [3, 2, 5])
    }

    #[test]
    fn a_texel_is_the_family_the_surface_shades_and_its_cells_average_to_the_macro_shares() {
        let s = surface("satin-5", 20.0, 0.1);
        let (mut weft, mut warp, mut holes) = (0, 0, 0);
        for i in 0..50 {
            for j in 0..50 {
                let uv = [(i as f64 + 0.5) / 100.0, (j as f64 + 0.5) / 100.0];
                let t = s.texel(uv);
                let mix = s.lobes(&SurfacePoint {
                    uv,
                    footprint: [[0.0; 2]; 2],
                });
                let on_top: f64 = mix
                    .lobes()
                    .iter()
                    .filter(|l| !l.warp)
                    .map(|l| l.weight)
                    .sum();
                assert!((t.weft - on_top).abs() < 1e-12, "{uv:?}");
                // At yarn level a point is one family's, or a hole.
                match (t.weft, t.warp) {
                    (1.0, 0.0) => weft += 1,
                    (0.0, 1.0) => warp += 1,
                    (0.0, 0.0) => holes += 1,
                    other => panic!("{uv:?}: shares {other:?}"),
                }
            }
        }
        // The cells average to the macro BRDF's shares: each family on top over 1 − gap of its
        // cells, and below in the other's gaps; gaps of 0.1 leave 1 % holes.
        let (n, g, gap) = (f64::from(weft + warp + holes), s.weft_fraction(), 0.1);
        let share = (1.0 - gap) * g + gap * (1.0 - gap) * (1.0 - g);
        assert!(
            (f64::from(weft) / n - share).abs() < 0.02,
            "{weft} of {n}, γ {g}"
        );
        assert!(holes > 0 && f64::from(holes) / n < 0.03, "{holes}");
        assert_eq!(s.repeat_cells(), [5, 5]);
    }

    #[test]
    fn a_tight_weave_has_no_holes_and_even_dyes_unit_factors() {
        let s = surface("plain", 0.0, 0.0);
        for k in 0..40 {
            let t = s.texel([k as f64 * 0.0123, k as f64 * 0.0371]);
            assert_eq!(t.weft + t.warp, 1.0);
            assert_eq!(t.factors, [1.0, 1.0]);
        }
    }

    #[test]
    fn a_family_s_brdf_is_the_cloth_of_that_family_alone_in_its_own_frame() {
        use crate::bsdf::Bsdf;
        // γ = 1 is the weft alone, γ = 0 the warp alone (the macro BRDF, whole tilted floats).
        let alone = |gamma: f64| woven_with(Weave::WeftFraction(gamma), 15.0, 0.0);
        let (weft, warp) = (alone(1.0), alone(0.0));
        let at = SurfacePoint::default();
        // The warp's own frame: the cloth's y is its x.
        let own = |d: Vec3| Vec3::new(d.y, -d.x, d.z);
        let mut seen = 0.0;
        for k in 0..30 {
            let wi = Vec3::from_spherical(0.05 * f64::from(k), 0.7 * f64::from(k));
            let wo = Vec3::from_spherical(1.3 - 0.04 * f64::from(k), 2.0 + 0.5 * f64::from(k));
            let a = weft.at(&at).eval(wi, wo).0;
            let b = weft.family_brdf(false, wi, wo).0;
            let c = warp.at(&at).eval(wi, wo).0;
            let d = warp.family_brdf(true, own(wi), own(wo)).0;
            for ch in 0..3 {
                assert!((a[ch] - b[ch]).abs() <= 1e-12 * a[ch].abs().max(1.0), "{k}");
                assert!((c[ch] - d[ch]).abs() <= 1e-12 * c[ch].abs().max(1.0), "{k}");
            }
            seen += a[1] + c[1];
        }
        assert!(seen > 0.0);
    }
}
