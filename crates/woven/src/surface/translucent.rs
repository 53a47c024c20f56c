//! Light through the yarns ([`SurfaceSpec::transmission`](super::SurfaceSpec)): what enters
//! the yarns and leaves on the far side, a diffuse lobe that closes each direction's energy
//! (docs/model.md, "Light through the yarns").
//!
//! Of the light arriving along `w`, the cloth reflects its directional albedo `A(w)` (the
//! surface's own cloth-level BRDF, integrated) and passes `O(w)` through its gaps
//! ([`open_area`](crate::gaps::open_area)). The rest, `r(w) = 1 − O(w) − A(w)`, enters the yarns.
//! A share `τ` of it leaves on the far side; the rest the dye absorbs. It leaves diffusely, in
//! the symmetric form
//!
//! ```text
//! f_t(wi, wo) = τ r(wi) r(wo) / (π r̄),    r̄ = ∫ r(w) cos θ dω / π,
//! ```
//!
//! so the light transmitted from `wi` is exactly `τ r(wi)`, and `f_t(wi, wo) = f_t(wo, wi)`: a
//! thin sheet's reciprocity. Reflected, passed, transmitted and absorbed light add to what
//! arrives, and a white fibre that absorbs nothing (`τ = 1`) transmits all it neither reflects
//! nor passes.
//!
//! **The share `τ`** is a Kubelka–Munk slab's: a layer of fibres whose reflectance when
//! infinitely thick is the dyed body albedo `ρ0` (what the paper's `ρ0` is: the light a fibre
//! mass sends back), so its absorption over scattering is `K/S = (1 − ρ0)² / (2ρ0)`, at a
//! scattering depth `S X` of [`YARN_SCATTERING_DEPTH`]. Of what enters it the slab transmits `T`
//! and reflects `R`; `τ = T / (1 − R)` is the share of what it does not send back that leaves
//! on the far side. White fibres give `τ = 1`, black ones 0. Per channel, the two families'
//! dyes are mixed by their shares of the weave.
//!
//! **Departures.** The paper's cloth is opaque; this is an option beyond it. The transmitted
//! light is diffuse (no forward lobe about the yarn), the slab's depth a stated constant, not a
//! fitted one, and the reflection is the paper's, not the slab's (it stays what `woven eval`,
//! the tables and the fits are). At the yarn level a yarn transmits `1 / (1 − gap²)` of the
//! cloth's `f_t` and a hole nothing (it passes light straight through instead), so a cell
//! averages to the cloth's. The back of the cloth is its front turned over about the weft.

use super::{SurfacePoint, WovenSurface};
use crate::bsdf::Transport;
use crate::color::Rgb;
use crate::Vec3;
use std::f64::consts::PI;

/// The scattering depth `S X` of the Kubelka–Munk slab a yarn is taken to be (module docs):
/// white fibres at this depth reflect `SX / (1 + SX)` = 2/3 of what enters them as a slab.
pub const YARN_SCATTERING_DEPTH: f64 = 2.0;

/// The polar nodes of the albedo table: cosine-weighted midpoints (`cos² θ` evenly spaced).
const N_MU: usize = 16;
/// The azimuthal nodes of the albedo table, over the whole turn.
const N_PHI: usize = 24;
/// Stratified draws per node of the albedo table (the reflection's own sampling).
const DRAWS: usize = 256;

/// The cloth's reflection albedo `A(w)` per channel over the hemisphere, and what `f_t` needs
/// of it (module docs).
#[derive(Clone, Debug)]
pub struct Translucency {
    /// `r(w) = 1 − O(w) − A(w)` per channel at each node, `[mu][phi]`.
    rest: Vec<[f64; 3]>,
    /// `r̄` per channel.
    mean: [f64; 3],
}

/// A Kubelka–Munk slab's share of what it does not reflect that it transmits, for an infinite
/// reflectance `rho` and scattering depth `depth` (module docs): 1 for `rho` = 1, 0 for 0.
pub fn slab_transmitted_share(rho: f64, depth: f64) -> f64 {
    if rho <= 0.0 {
        return 0.0;
    }
    let ks = (1.0 - rho).powi(2) / (2.0 * rho);
    let a = 1.0 + ks;
    let b = (a * a - 1.0).max(0.0).sqrt();
    if b * depth < 1e-8 {
        // K → 0: R = SX / (1 + SX), T = 1 / (1 + SX), and T / (1 − R) = 1.
        return 1.0;
    }
    let (sh, ch) = ((b * depth).sinh(), (b * depth).cosh());
    let den = a * sh + b * ch;
    let (r, t) = (sh / den, b / den);
    (t / (1.0 - r)).clamp(0.0, 1.0)
}

impl Translucency {
    /// `surface`'s table: its cloth-level BRDF's albedo by its own sampling, `DRAWS`
    /// stratified draws a node.
    pub fn of(surface: &WovenSurface) -> Translucency {
        let far = SurfacePoint {
            uv: [0.0; 2],
            footprint: [[1e6, 0.0], [0.0, 1e6]],
        };
        let bsdf = surface.at(&far);
        let mut rest = Vec::with_capacity(N_MU * N_PHI);
        let mut mean = [0.0; 3];
        let side = (DRAWS as f64).sqrt().ceil() as usize;
        let mut lobe = crate::math::rng::SplitMix(0x5eed);
        for k in 0..N_MU {
            for j in 0..N_PHI {
                let w = node(k, j);
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
                albedo *= 1.0 / (side * side) as f64;
                let open = surface.open_along(w);
                let r = albedo.0.map(|a| (1.0 - open - a).max(0.0));
                for c in 0..3 {
                    mean[c] += r[c] / (N_MU * N_PHI) as f64;
                }
                rest.push(r);
            }
        }
        Translucency { rest, mean }
    }

    /// `r(w)` per channel, `w` in the upper hemisphere: bilinear in `cos² θ` and `φ`.
    fn rest(&self, w: Vec3) -> [f64; 3] {
        let mu2 = (w.z * w.z).clamp(0.0, 1.0);
        let x = (mu2 * N_MU as f64 - 0.5).clamp(0.0, (N_MU - 1) as f64);
        let (k0, fx) = (x.floor() as usize, x.fract());
        let k1 = (k0 + 1).min(N_MU - 1);
        let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI) / (2.0 * PI) * N_PHI as f64 - 0.5;
        let phi = phi.rem_euclid(N_PHI as f64);
        let (j0, fy) = (phi.floor() as usize % N_PHI, phi.fract());
        let j1 = (j0 + 1) % N_PHI;
        let at = |k: usize, j: usize| self.rest[k * N_PHI + j];
        std::array::from_fn(|c| {
            let lo = at(k0, j0)[c] * (1.0 - fy) + at(k0, j1)[c] * fy;
            let hi = at(k1, j0)[c] * (1.0 - fy) + at(k1, j1)[c] * fy;
            lo * (1.0 - fx) + hi * fx
        })
    }

    /// `f_t(wi, wo)` per channel without `τ` (module docs), `wi` and `wo` on opposite sides: each
    /// taken to its own face's frame (the back's is the front's turned over about the weft).
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let (a, b) = (self.rest(face(wi)), self.rest(face(wo)));
        Rgb(std::array::from_fn(|c| {
            if self.mean[c] > 0.0 {
                a[c] * b[c] / (PI * self.mean[c])
            } else {
                0.0
            }
        }))
    }

    /// The light transmitted from `w` (without `τ`): `r(w)` per channel.
    pub fn transmitted(&self, w: Vec3) -> Rgb {
        Rgb(self.rest(face(w)))
    }
}

/// `w` in the frame of the face it lies on: itself above, and below the back's frame, the
/// front's turned over about the weft (`y` and `z` reversed).
fn face(w: Vec3) -> Vec3 {
    if w.z >= 0.0 {
        w
    } else {
        Vec3::new(w.x, -w.y, -w.z)
    }
}

/// The table's node `(k, j)`: `cos² θ` at the middle of its `k`-th of `N_MU` bins, `φ` at the
/// middle of its `j`-th of `N_PHI`.
fn node(k: usize, j: usize) -> Vec3 {
    let mu = ((k as f64 + 0.5) / N_MU as f64).sqrt();
    let phi = (j as f64 + 0.5) / N_PHI as f64 * 2.0 * PI;
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), mu)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::Bsdf;
    use crate::material::{Material, Weave};
    use crate::math::sampling::cosine_hemisphere;
    use crate::surface::SurfaceSpec;

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
        // Draws through the cloth report eval's f and pdf's density.
        let wo = Vec3::from_spherical(0.5, 0.8);
        let mut through = 0;
        for k in 0..400 {
            let u = [
                (k % 20) as f64 / 20.0 + 0.025,
                (k / 20) as f64 / 20.0 + 0.025,
            ];
            let uc = (k as f64 * 0.618_034) % 1.0;
            let d = bsdf.sample(wo, uc, u, Transport::Radiance).unwrap();
            let pdf = bsdf.pdf(d.wi, d.wo, Transport::Radiance);
            assert!((pdf - d.pdf).abs() < 1e-9 * pdf, "{pdf} {}", d.pdf);
            assert_eq!(bsdf.eval(d.wi, d.wo), d.f);
            through += usize::from(d.wi.z < 0.0);
        }
        assert!(through > 20 && through < 380, "{through}");
    }

    #[test]
    fn the_slab_passes_all_for_white_nothing_for_black_and_falls_between() {
        assert_eq!(slab_transmitted_share(1.0, 2.0), 1.0);
        assert_eq!(slab_transmitted_share(0.0, 2.0), 0.0);
        let mut last = 0.0;
        for k in 1..=20 {
            let t = slab_transmitted_share(k as f64 / 20.0, YARN_SCATTERING_DEPTH);
            assert!(t > last && t <= 1.0, "{k}: {t}");
            last = t;
        }
        // Kubelka–Munk at K = 0: T = 1 / (1 + SX) of all, R = SX / (1 + SX), so τ = 1 — and
        // just below, continuous.
        assert!((slab_transmitted_share(0.999_999, 2.0) - 1.0).abs() < 1e-3);
    }
}
