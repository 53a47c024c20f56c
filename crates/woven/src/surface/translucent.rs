//! The light through a surface's yarns ([`SurfaceSpec::transmission`](super::SurfaceSpec)): the
//! cloth's [`Translucency`] with the albedo `A(w)` of the surface's own cloth-level BRDF, by its
//! own sampling (docs/model.md, "Light through the yarns"). At the yarn level a yarn transmits
//! `1 / (1 − gap²)` of the cloth's `f_t` and a hole nothing (it passes light straight through
//! instead), so a cell averages to the cloth's.

use super::{SurfacePoint, WovenSurface};
use crate::bsdf::Transport;
use crate::color::Rgb;
pub use crate::translucency::{slab_transmitted_share, Translucency, YARN_SCATTERING_DEPTH};

/// Stratified draws per node of the albedo table (the reflection's own sampling).
const DRAWS: usize = 256;

/// `surface`'s table: its cloth-level BRDF's albedo by its own sampling, `DRAWS` stratified
/// draws a node, the lobe's choice from a stream of its own per node.
pub(super) fn of(surface: &WovenSurface) -> Translucency {
    let far = SurfacePoint {
        uv: [0.0; 2],
        footprint: [[1e6, 0.0], [0.0, 1e6]],
    };
    let bsdf = surface.at(&far);
    let side = (DRAWS as f64).sqrt().ceil() as usize;
    let albedo = |node: usize, w: crate::Vec3| {
        let mut lobe = crate::math::rng::SplitMix(0x5eed ^ (node as u64).wrapping_mul(0x9e37_79b9));
        let mut albedo = Rgb::BLACK;
        for s in 0..side * side {
            let u = [
                ((s % side) as f64 + 0.5) / side as f64,
                ((s / side) as f64 + 0.5) / side as f64,
            ];
            // The lobe's choice independent of the direction's stratum.
            let uc = lobe.uniform();
            if let Some(d) = bsdf.sample_reflection(w, uc, u, Transport::Importance) {
                albedo += d.f * (d.wo.z / d.pdf);
            }
        }
        (albedo * (1.0 / (side * side) as f64)).0
    };
    Translucency::from_albedo(albedo, |w| surface.open_along(w), false, surface.spread)
}

impl WovenSurface {
    /// What a point on a yarn transmits through its fibres of light along the normal, per
    /// channel, at the surface's own dyes: `τ r(n) / (1 − gap²)` (module docs), in `[0, 1]`;
    /// `None` where the surface does not transmit or has no yarns. The figure a renderer that
    /// carries only a Lambertian translucency and holes open at every angle (Cycles' Translucent
    /// and Transparent BSDFs) gives its yarns: with the holes it transmits what the cloth does
    /// along the normal, and toward grazing, where the cloth's gaps close and its yarns take the
    /// light they passed, the holes' excess stands for the yarns' (the voile: 0.433 at every
    /// angle against the cloth's 0.433, 0.428, 0.416 and 0.389 at 0°, 30°, 60° and 80°).
    pub fn yarn_transmittance(&self) -> Option<Rgb> {
        if !self.transmits() || matches!(self.layout, super::Layout::Flat { .. }) {
            return None;
        }
        let tau = super::point::tau(self.weft_fraction(), &self.dyes.weft, &self.dyes.warp);
        let normal = self
            .translucency()
            .transmitted(crate::Vec3::new(0.0, 0.0, 1.0));
        let yarn = 1.0 / (1.0 - self.gap * self.gap);
        Some(Rgb(std::array::from_fn(|c| {
            (tau[c] * normal.0[c] * yarn).clamp(0.0, 1.0)
        })))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::Bsdf;
    use crate::material::{Material, Weave};
    use crate::math::sampling::cosine_hemisphere;
    use crate::surface::SurfaceSpec;
    use crate::Vec3;
    use std::f64::consts::PI;

    /// A plain linen of `gap`, dyed `dye`, transmission on.
    fn surface(gap: f64, dye: f64) -> WovenSurface {
        let mut material = Material::preset("linen-plain").unwrap();
        material.weave = Some(Weave::named("plain").unwrap());
        let spec = SurfaceSpec {
            yarns_per_unit: [10.0, 10.0],
            gap,
            transmission: true,
            weft_color: Some(Rgb([dye; 3])),
            warp_color: Some(Rgb([dye; 3])),
            ..SurfaceSpec::new(material)
        };
        crate::surface::test_surface(&spec, [12, 7, 31])
    }

    const FAR: SurfacePoint = SurfacePoint {
        uv: [0.0; 2],
        footprint: [[1e6, 0.0], [0.0, 1e6]],
    };

    /// Reflected, transmitted (the cosine-weighted mean of `π f`, `n²` stratified directions on
    /// each side) and passed light for light from `w`, per channel's mean.
    fn budget(s: &WovenSurface, w: Vec3, n: usize) -> (f64, f64, f64) {
        let bsdf = s.at(&FAR);
        let (mut r, mut t) = (0.0, 0.0);
        for a in 0..n {
            for b in 0..n {
                let d = cosine_hemisphere((a as f64 + 0.5) / n as f64, (b as f64 + 0.5) / n as f64);
                let m = |f: Rgb| (f.0[0] + f.0[1] + f.0[2]) / 3.0 * PI / (n * n) as f64;
                r += m(bsdf.eval(w, d));
                t += m(bsdf.eval(w, Vec3::new(d.x, d.y, -d.z)));
            }
        }
        (r, t, s.open_along(w))
    }

    /// A yarn point's transmittance for a Lambertian translucency is the light the cloth
    /// transmits through its yarns along the normal (by 96² stratified directions on the far
    /// side), spread over the yarns' share `1 − gap²`, within 1 %; black fibres pass nothing
    /// through themselves, and an opaque cloth has none.
    #[test]
    fn a_yarns_transmittance_is_the_cloths_along_the_normal_over_its_yarns() {
        for dye in [1.0, 0.5] {
            let (gap, s) = (0.3, surface(0.3, dye));
            let through = budget(&s, Vec3::new(0.0, 0.0, 1.0), 96).1;
            let yarn = s.yarn_transmittance().unwrap();
            let got = (yarn.0[0] + yarn.0[1] + yarn.0[2]) / 3.0 * (1.0 - gap * gap);
            assert!(
                (got / through - 1.0).abs() < 0.01,
                "dye {dye}: {got} against {through}"
            );
        }
        assert_eq!(surface(0.3, 0.0).yarn_transmittance(), Some(Rgb::BLACK));
        let mut material = Material::preset("linen-plain").unwrap();
        material.weave = Some(Weave::named("plain").unwrap());
        let opaque = crate::surface::test_surface(&SurfaceSpec::new(material), [4, 4, 4]);
        assert_eq!(opaque.yarn_transmittance(), None);
    }

    #[test]
    fn a_white_fibre_reflects_transmits_and_passes_all_it_is_given() {
        let s = surface(0.3, 1.0);
        for (theta, phi) in [(0.1, 0.2), (0.7, 0.5), (1.1, 2.0), (1.35, 4.0)] {
            let w = Vec3::from_spherical(theta, phi);
            let (r, t, o) = budget(&s, w, 160);
            println!(
                "θ {theta}: R {r:.4} T {t:.4} O {o:.4}, sum {:.4}",
                r + t + o
            );
            assert!(t > 0.05, "θ {theta}: nothing transmitted");
            assert!(
                (r + t + o - 1.0).abs() < 0.02,
                "θ {theta}: R {r} + T {t} + O {o} = {}",
                r + t + o
            );
        }
        // A black dye absorbs what enters the yarns: no glow, and R + T + O well below 1.
        let black = surface(0.3, 0.0);
        let (r, t, o) = budget(&black, Vec3::from_spherical(0.4, 0.3), 80);
        assert!(t < 1e-9 && r + o < 0.9, "{r} {t} {o}");
    }

    #[test]
    fn the_transmission_is_reciprocal_through_the_sheet_and_sampled_with_its_density() {
        let s = surface(0.2, 0.7);
        let bsdf = s.at(&FAR);
        let back = |w: Vec3| Vec3::new(w.x, -w.y, -w.z);
        for (a, b) in [((0.3, 0.4), (2.1, 1.0)), ((1.2, 5.0), (2.8, 2.2))] {
            let (wo, wi) = (
                Vec3::from_spherical(a.0, a.1),
                Vec3::from_spherical(b.0, b.1),
            );
            assert!(wo.z > 0.0 && wi.z < 0.0);
            let (f, g) = (bsdf.eval(wi, wo), bsdf.eval(back(wo), back(wi)));
            for c in 0..3 {
                assert!(f.0[c] > 0.0 && (f.0[c] - g.0[c]).abs() < 1e-12 * f.0[c]);
            }
        }
        // Draws through the cloth report eval's f and pdf's density; a draw of the forward lobe
        // that lands back on the viewer's side fails (its density leaves that out).
        let wo = Vec3::from_spherical(0.5, 0.8);
        let (mut through, mut failed) = (0, 0);
        for k in 0..400 {
            let u = [
                (k % 20) as f64 / 20.0 + 0.025,
                (k / 20) as f64 / 20.0 + 0.025,
            ];
            let uc = (k as f64 * 0.618_034) % 1.0;
            let Some(d) = bsdf.sample(wo, uc, u, Transport::Radiance) else {
                failed += 1;
                continue;
            };
            let pdf = bsdf.pdf(d.wi, d.wo, Transport::Radiance);
            assert!((pdf - d.pdf).abs() < 1e-9 * pdf, "{pdf} {}", d.pdf);
            assert_eq!(bsdf.eval(d.wi, d.wo), d.f);
            through += usize::from(d.wi.z < 0.0);
        }
        assert!(through > 20 && through < 380, "{through}");
        assert!(failed < 20, "{failed} of 400 draws failed");
    }
}
