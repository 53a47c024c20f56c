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
//! **The forward lobe.** Part of that light crosses the yarns without scattering, and leaves
//! about the straight-through direction `−wi`, spread only by refraction at the fibres' surfaces
//! and by the fibres' slopes and twist. Its share of what enters is `e^{−δ/μ}` for a yarn of
//! optical thickness [`YARN_OPTICAL_DEPTH`] `δ` along a path of cosine `μ`, over the
//! `1/(1 + SX)` a white slab of the same depth transmits ([`forward_share`]: 0.229 along the
//! normal, 0.017 at 60°). It leaves in a lobe `K = exp(λ(−wi·wo − 1))` about `−wi`, `λ = 1/s²`
//! with [`forward_spread`] `s`, in the symmetric form
//!
//! ```text
//! f_F(wi, wo) = √(u(wi) u(wo) / (N(wi) N(wo))) K(wi, wo),   u = κ r,   N(w) = ∫ K |cos θo| dωo,
//! ```
//!
//! whose marginal is `u(wi)` where `u/N` varies little over the lobe. The diffuse part carries
//! what the forward part does not, `d = r − m_F` with `m_F` the forward part's own marginal
//! (worked out at the table's nodes), in the form above: each direction's total stays `r(wi)`
//! and `f_t` stays reciprocal.
//!
//! **The share `τ`** is a Kubelka–Munk slab's: a layer of fibres whose reflectance when
//! infinitely thick is the dyed body albedo `ρ0` (what the paper's `ρ0` is: the light a fibre
//! mass sends back), so its absorption over scattering is `K/S = (1 − ρ0)² / (2ρ0)`, at a
//! scattering depth `S X` of [`YARN_SCATTERING_DEPTH`]. Of what enters it the slab transmits `T`
//! and reflects `R`; `τ = T / (1 − R)` is the share of what it does not send back that leaves
//! on the far side. White fibres give `τ = 1`, black ones 0. Per channel, the two families'
//! dyes are mixed by their shares of the weave.
//!
//! **Departures.** The paper's cloth is opaque; this is an option beyond it. The forward lobe is
//! round (a fibre deflects light across its axis, not along it: Zhu et al. 2023's cross-shaped
//! highlights are not drawn), its share that of a white slab at every dye (a dark yarn's leans
//! further forward), the slab's depth a stated constant, not a fitted one, and the reflection
//! is the paper's, not the slab's (it stays what `woven eval`, the tables and the fits are). At
//! the yarn level a yarn transmits `1 / (1 − gap²)` of the cloth's `f_t` and a hole nothing (it
//! passes light straight through instead), so a cell averages to the cloth's. The table's back
//! side is its front turned over about the weft (the back's own reflection is its pattern's
//! complement, [`Material::back`](crate::material::Material::back)).
//! What these departures cost, light followed through explicit yarns measures (docs/model.md,
//! "The explicit-yarn check"): `τ` within 2–7 % for pale fibres, too small for dark ones, and
//! the exit's lean forward as the forward lobe gives it for white fibres.

use crate::color::Rgb;
use crate::Vec3;
use std::f64::consts::PI;

/// The scattering depth `S X` of the Kubelka–Munk slab a yarn is taken to be (module docs):
/// white fibres at this depth reflect `SX / (1 + SX)` = 2/3 of what enters them as a slab.
pub const YARN_SCATTERING_DEPTH: f64 = 2.0;

/// The optical thickness `δ` of a yarn's middle (module docs, "The forward lobe"): that of a
/// slab of a medium scattering isotropically and absorbing nothing that reflects `SX / (1 + SX)`
/// = 2/3 of diffuse light at the scattering depth [`YARN_SCATTERING_DEPTH`], found by Monte
/// Carlo in `examples/yarn_transport` (which checks it again when it runs).
pub const YARN_OPTICAL_DEPTH: f64 = 2.573;

/// The narrowest forward lobe, radians: a smooth fibre in a straight yarn (keeps the lobe's
/// quadratures resolved).
pub const MIN_FORWARD_SPREAD: f64 = 0.05;

/// Polar nodes of the forward lobe's normalization `N(μ)`, evenly spaced in `μ` over `[0, 1]`.
const N_NORM: usize = 65;
/// Each side of the lobe's quadrature grid (in `1 − cos γ`, importance-sampled, and azimuth).
const LOBE_QUADRATURE: usize = 40;

/// The share of the light through the yarns along a direction of cosine `mu` (either side)
/// that crosses them unscattered (module docs): `(1 + SX) e^{−δ/|μ|}`, at most 1.
pub fn forward_share(mu: f64) -> f64 {
    let mu = mu.abs();
    if mu <= 0.0 {
        return 0.0;
    }
    ((1.0 + YARN_SCATTERING_DEPTH) * (-YARN_OPTICAL_DEPTH / mu).exp()).min(1.0)
}

/// The forward lobe's angular spread `s`, radians (module docs): refraction through the two
/// surfaces of a fibre of index `eta` whose microfacets tilt by Beckmann `alpha` deflects by
/// `(η − 1) α` (a thin prism's deviation), and the fibres' slopes across the yarn (`slope_std`)
/// and twist (`twist_std`) tilt their axes: `s² = ((η − 1) α)² + σ² + σ_t²`, at least
/// [`MIN_FORWARD_SPREAD`].
pub fn forward_spread(eta: f64, alpha: f64, yarn: Option<&crate::yarn::YarnParams>) -> f64 {
    let (slopes, twist) = yarn.map_or((0.0, 0.0), |y| (y.slope_std, y.twist_std));
    let s2 = ((eta - 1.0) * alpha).powi(2) + slopes * slopes + twist * twist;
    if s2.is_finite() {
        s2.sqrt().max(MIN_FORWARD_SPREAD)
    } else {
        MIN_FORWARD_SPREAD
    }
}

/// The forward lobe about `−w`: `K`'s concentration and its normalization (module docs).
#[derive(Clone, Debug)]
struct Forward {
    /// `λ = 1 / s²`.
    lambda: f64,
    /// `1 − e^{−2λ}`: `K`'s integral over the sphere is `2π` times it over `λ`.
    mass: f64,
    /// `N(μ)` at `μ = k / (N_NORM − 1)`.
    norm: Vec<f64>,
}

impl Forward {
    fn new(spread: f64) -> Forward {
        let lambda = 1.0 / (spread * spread);
        let mut lobe = Forward {
            lambda,
            mass: 1.0 - (-2.0 * lambda).exp(),
            norm: Vec::new(),
        };
        lobe.norm = (0..N_NORM)
            .map(|k| {
                let mu = k as f64 / (N_NORM - 1) as f64;
                let w = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
                lobe.integral(w, |d| [(-d.z).max(0.0)])[0]
            })
            .collect();
        lobe
    }

    /// `K(wi, wo)`: the lobe about `−wi` at `wo`.
    fn kernel(&self, wi: Vec3, wo: Vec3) -> f64 {
        (self.lambda * (-wi.dot(wo) - 1.0)).exp()
    }

    /// `N(μ)`, linear between its nodes.
    fn norm_at(&self, mu: f64) -> f64 {
        let x = mu.abs().clamp(0.0, 1.0) * (N_NORM - 1) as f64;
        let k = (x.floor() as usize).min(N_NORM - 2);
        let t = x - k as f64;
        self.norm[k] * (1.0 - t) + self.norm[k + 1] * t
    }

    /// The direction of the lobe about `−w` at `(x, y)` in `[0, 1)²` (importance-sampled in
    /// `K`, on the whole sphere).
    fn direction(&self, w: Vec3, x: f64, y: f64) -> Vec3 {
        let axis = -w;
        let u = -(1.0 - x * self.mass).ln() / self.lambda;
        let (cos, sin) = (1.0 - u, (u * (2.0 - u)).max(0.0).sqrt());
        let (t, b) = crate::math::basis::orthonormal_basis(axis);
        let psi = 2.0 * PI * y;
        axis * cos + (t * psi.cos() + b * psi.sin()) * sin
    }

    /// The lobe's density over the sphere at `d` for the lobe about `−w`.
    fn density(&self, w: Vec3, d: Vec3) -> f64 {
        self.lambda * self.kernel(w, d) / (2.0 * PI * self.mass)
    }

    /// `∫ K(w, d) g(d) dω` over the sphere for each of `g`'s `C` values, by the lobe's own
    /// importance sampling on a midpoint grid.
    fn integral<const C: usize>(&self, w: Vec3, g: impl Fn(Vec3) -> [f64; C]) -> [f64; C] {
        let n = LOBE_QUADRATURE;
        let mut sum = [0.0; C];
        for i in 0..n {
            for j in 0..n {
                let d = self.direction(w, (i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                for (s, v) in sum.iter_mut().zip(g(d)) {
                    *s += v;
                }
            }
        }
        sum.map(|s| s / (n * n) as f64 * 2.0 * PI * self.mass / self.lambda)
    }
}

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
    /// The diffuse part's `d(w) = r(w) − m_F(w)` per channel at each node.
    diffuse: Vec<[f64; 3]>,
    /// `d̄` per channel.
    mean: [f64; 3],
    /// The forward lobe.
    forward: Forward,
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
    /// paper's do), so only the nodes of the first quarter turn are worked out. `spread`: the
    /// forward lobe's ([`forward_spread`]).
    pub fn from_albedo(
        albedo: impl Fn(usize, Vec3) -> [f64; 3] + Sync,
        open: impl Fn(Vec3) -> f64 + Sync,
        mirrored: bool,
        spread: f64,
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
        let mut table = Translucency {
            diffuse: Vec::new(),
            rest,
            mean: [0.0; 3],
            forward: Forward::new(spread.max(MIN_FORWARD_SPREAD)),
        };
        // The diffuse part carries what the forward lobe does not, node by node.
        let diffuse: Vec<[f64; 3]> = (0..N_MU * N_PHI)
            .map(|i| {
                let w = node(i / N_PHI, i % N_PHI);
                let carried = table.forward_marginal(w);
                std::array::from_fn(|c| (table.rest[i][c] - carried[c]).max(0.0))
            })
            .collect();
        for d in &diffuse {
            for c in 0..3 {
                table.mean[c] += d[c] / (N_MU * N_PHI) as f64;
            }
        }
        table.diffuse = diffuse;
        table
    }

    /// The forward lobe's marginal `m_F(w) = ∫ f_F(w, wo) |cos θo| dωo` per channel, `w` above.
    fn forward_marginal(&self, w: Vec3) -> [f64; 3] {
        self.forward.integral(w, |d| {
            self.forward_factor(w, d).map(|f| f * (-d.z).max(0.0))
        })
    }

    /// `√(u(wi) u(wo) / (N(wi) N(wo)))` per channel, `wi` and `wo` on opposite sides: the
    /// forward part over `K` (module docs).
    fn forward_factor(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        let (a, b) = (face(wi), face(wo));
        self.forward_factor_in(a.z, b.z, Cell::of(a), Cell::of(b))
    }

    /// [`forward_factor`](Self::forward_factor) for faces of cosines `mu_a`, `mu_b` in the cells
    /// `ca`, `cb`.
    fn forward_factor_in(&self, mu_a: f64, mu_b: f64, ca: Cell, cb: Cell) -> [f64; 3] {
        let (ka, kb) = (forward_share(mu_a), forward_share(mu_b));
        if ka * kb <= 0.0 {
            return [0.0; 3];
        }
        let n = self.forward.norm_at(mu_a) * self.forward.norm_at(mu_b);
        if n <= 0.0 {
            return [0.0; 3];
        }
        let (ra, rb) = (ca.read(&self.rest), cb.read(&self.rest));
        std::array::from_fn(|c| (ka * ra[c] * kb * rb[c] / n).max(0.0).sqrt())
    }

    /// `r(w)` per channel, `w` in the upper hemisphere: bilinear in `cos² θ` and `φ`.
    fn rest(&self, w: Vec3) -> [f64; 3] {
        Cell::of(w).read(&self.rest)
    }
}

/// Where a direction in the upper hemisphere falls among the table's nodes: its two polar and two
/// azimuthal neighbours and its place between them, bilinear in `cos² θ` and `φ` (worked out
/// once, read from any table of per-channel node values).
#[derive(Clone, Copy, Debug)]
struct Cell {
    k: [usize; 2],
    fx: f64,
    j: [usize; 2],
    fy: f64,
}

impl Cell {
    fn of(w: Vec3) -> Cell {
        let mu2 = (w.z * w.z).clamp(0.0, 1.0);
        let x = (mu2 * N_MU as f64 - 0.5).clamp(0.0, (N_MU - 1) as f64);
        let (k0, fx) = (x.floor() as usize, x.fract());
        let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI) / (2.0 * PI) * N_PHI as f64 - 0.5;
        let phi = phi.rem_euclid(N_PHI as f64);
        let (j0, fy) = (phi.floor() as usize % N_PHI, phi.fract());
        Cell {
            k: [k0, (k0 + 1).min(N_MU - 1)],
            fx,
            j: [j0, (j0 + 1) % N_PHI],
            fy,
        }
    }

    fn read(&self, values: &[[f64; 3]]) -> [f64; 3] {
        let at = |k: usize, j: usize| values[self.k[k] * N_PHI + self.j[j]];
        std::array::from_fn(|c| {
            let lo = at(0, 0)[c] * (1.0 - self.fy) + at(0, 1)[c] * self.fy;
            let hi = at(1, 0)[c] * (1.0 - self.fy) + at(1, 1)[c] * self.fy;
            lo * (1.0 - self.fx) + hi * self.fx
        })
    }
}

impl Translucency {
    /// `f_t(wi, wo)` per channel without `τ` (module docs), `wi` and `wo` on opposite sides: the
    /// diffuse part with each taken to its own face's frame (the back's is the front's turned
    /// over about the weft), and the forward lobe about the straight-through direction.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z * wo.z >= 0.0 {
            return Rgb::BLACK;
        }
        let (fa, fb) = (face(wi), face(wo));
        let (ca, cb) = (Cell::of(fa), Cell::of(fb));
        let (a, b) = (ca.read(&self.diffuse), cb.read(&self.diffuse));
        let k = self.forward.kernel(wi, wo);
        // Beyond e⁻³⁰ of its peak the lobe adds nothing a float holds.
        let forward = if k > 1e-13 {
            self.forward_factor_in(fa.z, fb.z, ca, cb)
        } else {
            [0.0; 3]
        };
        Rgb(std::array::from_fn(|c| {
            let diffuse = if self.mean[c] > 0.0 {
                a[c] * b[c] / (PI * self.mean[c])
            } else {
                0.0
            };
            diffuse + forward[c] * k
        }))
    }

    /// Draws a direction on the far side of `known` (either side) for the light through the
    /// yarns: `uc` picks the forward lobe with the probability [`forward_share`] along `known`
    /// (at most 0.95), else a cosine lobe; `None` where the lobe's draw lands on `known`'s side.
    pub fn sample(&self, known: Vec3, uc: f64, u: [f64; 2]) -> Option<Vec3> {
        let side = if known.z > 0.0 { -1.0 } else { 1.0 };
        let drawn = if uc < self.forward_choice(known) {
            self.forward.direction(known, u[0], u[1])
        } else {
            let d = crate::math::sampling::cosine_hemisphere(u[0], u[1]);
            Vec3::new(d.x, d.y, side * d.z)
        };
        (drawn.z * side > 0.0).then_some(drawn)
    }

    /// The density of [`sample`](Self::sample)'s draw of `drawn` for `known` (0 on `known`'s
    /// side).
    pub fn pdf(&self, known: Vec3, drawn: Vec3) -> f64 {
        if known.z * drawn.z >= 0.0 {
            return 0.0;
        }
        let p = self.forward_choice(known);
        (1.0 - p) * drawn.z.abs() / PI + p * self.forward.density(known, drawn)
    }

    /// The probability that [`sample`](Self::sample) draws from the forward lobe.
    fn forward_choice(&self, known: Vec3) -> f64 {
        forward_share(known.z).min(0.95)
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
            Translucency::from_albedo(albedo, open, false, 0.5),
            Translucency::from_albedo(albedo, open, true, 0.5),
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

    /// A table of a cloth reflecting about half, open a little along the normal.
    fn half(spread: f64) -> Translucency {
        let albedo = |_: usize, w: Vec3| {
            let a = 0.45 + 0.1 * w.z + 0.05 * (2.0 * w.x * w.x - 1.0);
            [a, 0.8 * a, 0.6 * a]
        };
        Translucency::from_albedo(albedo, |w| 0.04 * w.z * w.z, true, spread)
    }

    /// `∫ f_t(w, wo) |cos θo| dωo` and `∫ f_t |cos θo|² dωo` per channel, by the table's own
    /// sampling on a stratified grid (`side²` draws for each of `picks` choices of the lobe).
    fn moments(t: &Translucency, w: Vec3, side: usize, picks: usize) -> ([f64; 3], f64) {
        let (mut m0, mut m1) = ([0.0; 3], 0.0);
        let n = (side * side * picks) as f64;
        for k in 0..picks {
            let uc = (k as f64 + 0.5) / picks as f64;
            for i in 0..side * side {
                let u = [
                    ((i % side) as f64 + 0.5) / side as f64,
                    ((i / side) as f64 + 0.5) / side as f64,
                ];
                let Some(d) = t.sample(w, uc, u) else {
                    continue;
                };
                let (f, p) = (t.eval(w, d), t.pdf(w, d));
                assert!(p > 0.0 && f.0.iter().all(|x| x.is_finite() && *x >= 0.0));
                for c in 0..3 {
                    m0[c] += f.0[c] * d.z.abs() / p / n;
                }
                m1 += f.0[0] * d.z * d.z / p / n;
            }
        }
        (m0, m1)
    }

    /// The light through the yarns is reciprocal (a thin sheet's: `f_t(wi, wo) = f_t(wo, wi)`,
    /// the back's directions turned over) and carries exactly `r(wi)` of each direction, the
    /// forward lobe included, narrow or wide, to the horizon: within 1.5 % by the table's own
    /// sampling (whose draws and density agree, so its weights average to the integral).
    #[test]
    fn the_light_through_is_reciprocal_and_carries_what_enters() {
        for spread in [MIN_FORWARD_SPREAD, 0.15, 0.45, 0.9] {
            let t = half(spread);
            let mut rng = crate::math::rng::SplitMix(7);
            for _ in 0..200 {
                let wi = crate::math::sampling::uniform_sphere(rng.uniform(), rng.uniform());
                let wo = crate::math::sampling::uniform_sphere(rng.uniform(), rng.uniform());
                let (a, b) = (t.eval(wi, wo), t.eval(wo, wi));
                for c in 0..3 {
                    assert!(
                        (a.0[c] - b.0[c]).abs() <= 1e-12 * a.0[c].max(1e-12),
                        "{a:?} {b:?}"
                    );
                }
            }
            for theta in [0.0f64, 30.0, 60.0, 80.0, 88.0] {
                for side in [1.0, -1.0] {
                    let (s, c) = theta.to_radians().sin_cos();
                    let w = Vec3::new(s * 0.6, s * 0.8, side * c);
                    let (m0, _) = moments(&t, w, 96, 8);
                    let r = t.transmitted(w).0;
                    for ch in 0..3 {
                        let rel = m0[ch] / r[ch] - 1.0;
                        assert!(
                            rel.abs() < 0.015,
                            "spread {spread} θ {theta} side {side}: {rel}"
                        );
                    }
                }
            }
        }
    }

    /// The forward lobe's share falls from 0.229 along the normal to 0.017 at 60°, so light
    /// from straight above leaves leaning forward and slanting light about as diffusely as a
    /// Lambertian exit: the mean cosine of the exit is what light followed through explicit
    /// yarns gives for white fibres (docs/model.md, "The explicit-yarn check": 0.744–0.763 at
    /// 0°, 0.631–0.674 at 60°), within 0.03, with the narrowest lobe: those yarns' medium
    /// neither refracts nor tilts the light it does not scatter.
    #[test]
    fn the_exit_leans_forward_as_through_explicit_yarns() {
        assert!(
            (forward_share(1.0) - 0.229).abs() < 0.001,
            "{}",
            forward_share(1.0)
        );
        assert!((forward_share(0.5) - 0.0174).abs() < 0.001);
        let t = half(MIN_FORWARD_SPREAD);
        for (theta, lo, hi) in [(0.0f64, 0.744, 0.763), (60.0, 0.631, 0.674)] {
            let (s, c) = theta.to_radians().sin_cos();
            let (m0, m1) = moments(&t, Vec3::new(s, 0.0, c), 96, 8);
            let mean_cos = m1 / m0[0];
            println!("θ {theta}°: the exit's mean cosine {mean_cos:.3}");
            assert!(
                mean_cos > lo - 0.03 && mean_cos < hi + 0.03,
                "θ {theta}: mean cosine {mean_cos}"
            );
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
