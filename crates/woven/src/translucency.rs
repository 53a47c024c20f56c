//! Light through the yarns (`[weave] transmission`, [`Openness`](crate::material::Openness); a
//! surface's [`transmission`](crate::surface::SurfaceSpec::transmission)): what enters the yarns
//! and leaves on the far side, a diffuse lobe that closes each direction's energy (docs/model.md,
//! "Light through the yarns").
//!
//! Of the light arriving along `w`, the cloth reflects its directional albedo `A(w)` (its own
//! cloth-level BRDF, integrated: exactly for a [`Model`](crate::Model), by the BRDF's own
//! sampling for a [`WovenSurface`](crate::surface::WovenSurface)) and passes `O(w)` through its gaps
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
//! averages to the cloth's. The table's back side is its front turned over about the weft (the
//! back's own reflection is its pattern's complement, [`Material::back`](crate::material::Material::back)).
//! What these departures cost, light followed through explicit yarns measures (docs/model.md,
//! "The explicit-yarn check"): `τ` within 2–7 % for pale fibres, too small for dark ones, and
//! the exit leaning forward.

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
    /// The table of a cloth whose reflection albedo along `w` is `albedo(node, w)` per channel
    /// (`node` numbers the table's nodes, for a sampled albedo's seeds) and whose open area is
    /// `open(w)`. The nodes are worked out on every core. `mirrored`: the albedo is the same
    /// at `φ`, `−φ` and `π − φ` (a cloth whose yarns each mirror about their axis, as the
    /// paper's do), so only the nodes of the first quarter turn are worked out.
    pub fn from_albedo(
        albedo: impl Fn(usize, Vec3) -> [f64; 3] + Sync,
        open: impl Fn(Vec3) -> f64 + Sync,
        mirrored: bool,
    ) -> Translucency {
        let own = |j: usize| !mirrored || j < N_PHI / 4;
        let todo: Vec<usize> = (0..N_MU * N_PHI).filter(|i| own(i % N_PHI)).collect();
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut rest = vec![[0.0; 3]; N_MU * N_PHI];
        let work = |k: usize| {
            let i = todo[k];
            let w = node(i / N_PHI, i % N_PHI);
            let (a, o) = (albedo(i, w), open(w));
            (i, a.map(|a| (1.0 - o - a).max(0.0)))
        };
        // Plain scoped threads (not the rayon pool): a caller may build the table from inside
        // a rayon task that other tasks wait on.
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads)
                .map(|t| {
                    let work = &work;
                    let n = todo.len();
                    scope.spawn(move || (t..n).step_by(threads).map(work).collect::<Vec<_>>())
                })
                .collect();
            for h in handles {
                for (i, r) in h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)) {
                    rest[i] = r;
                }
            }
        });
        if mirrored {
            for i in 0..N_MU * N_PHI {
                let (k, j) = (i / N_PHI, i % N_PHI);
                let q = N_PHI / 4;
                let source = match j / q {
                    0 => j,
                    1 => 2 * q - 1 - j,
                    2 => j - 2 * q,
                    _ => N_PHI - 1 - j,
                };
                rest[i] = rest[k * N_PHI + source];
            }
        }
        let mut mean = [0.0; 3];
        for r in &rest {
            for c in 0..3 {
                mean[c] += r[c] / (N_MU * N_PHI) as f64;
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
pub fn face(w: Vec3) -> Vec3 {
    if w.z >= 0.0 {
        w
    } else {
        Vec3::new(w.x, -w.y, -w.z)
    }
}

/// The table's node `(k, j)`: `cos² θ` at the middle of its `k`-th of `N_MU` bins, `φ` at the
/// middle of its `j`-th of `N_PHI`.
pub(crate) fn node(k: usize, j: usize) -> Vec3 {
    let mu = ((k as f64 + 0.5) / N_MU as f64).sqrt();
    let phi = (j as f64 + 0.5) / N_PHI as f64 * 2.0 * PI;
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), mu)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mirrored_table_equals_the_whole_one_for_a_mirrored_albedo() {
        let albedo =
            |_: usize, w: Vec3| [0.3 + 0.2 * w.z + 0.1 * (2.0 * w.x * w.x - 1.0) * (1.0 - w.z); 3];
        let open = |w: Vec3| 0.1 * w.z * w.z;
        let (whole, folded) = (
            Translucency::from_albedo(albedo, open, false),
            Translucency::from_albedo(albedo, open, true),
        );
        // Equal but for the nodes' own rounding (cos(π − φ) is −cos φ to an ulp).
        for (a, b) in whole
            .rest
            .iter()
            .zip(&folded.rest)
            .chain([(&whole.mean, &folded.mean)])
        {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() < 1e-12, "{a:?} {b:?}");
            }
        }
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
