//! An independent check of the light through the yarns (docs/model.md, "Light through the
//! yarns", "The explicit-yarn check"): light followed through a tile of explicit yarns, traced as
//! 3-D geometry, against the derivation's terms.
//!
//! **The tile.** Both families' yarns as `woven::gaps` lays them: straight prisms one per pitch,
//! each `1 − gap` wide, its cross-section [`YarnSection`] (crowns above and below, half as thick
//! as wide), the weft along `x` and the warp along `y`, crossing in one layer (no crimp), the
//! tile periodic in `x` and `y`.
//!
//! **Its transport.** Inside the yarns, a homogeneous medium that scatters isotropically (no
//! refracting boundary): extinction `σ` per pitch and single-scattering albedo `a`. Neither is
//! fitted to the model. Each is set by a property of a 1-D slab of the medium that the
//! derivation names, found by Monte Carlo (`slab`) rather than by the Kubelka–Munk formulas:
//! - `a`: a half-space of the medium under diffuse light reflects `ρ0` (what the paper's `ρ0` is:
//!   the light a thick fibre mass sends back);
//! - `σ`: a slab as thick as a yarn's middle, absorbing nothing, reflects `SX / (1 + SX)` = 2/3 of
//!   diffuse light, the reflectance of a Kubelka–Munk slab of the model's scattering depth
//!   ([`YARN_SCATTERING_DEPTH`]).
//!
//! Light arrives collimated from `w` at random points over the tile's top. A ray that never
//! enters a yarn has passed between them (`O`); one that does is followed, collision by
//! collision (free flights marched through the yarns in steps of 1/500 pitch), until it leaves
//! the tile above (`R`) or below (`T`), or is absorbed.
//!
//! **Against the derivation.** It claims `O(w)` is the open area ([`open_area`]), and that of what
//! is neither passed nor reflected, `1 − O − R`, the share `τ` leaves on the far side, `τ` a
//! Kubelka–Munk slab's `T / (1 − R)` ([`slab_transmitted_share`]), the same at every incidence,
//! and diffusely (the mean cosine of a Lambertian exit is 2/3). The tile's own `τ_tile = T / (1 −
//! O − R)` is printed beside the formula's and beside a 1-D slab's of the same medium by Monte
//! Carlo (which tells the formula's error from the geometry's).
//!
//! ```text
//! cargo run --release -p woven --example yarn_transport
//! ```
//! (about ten seconds on 2 cores.) It exits non-zero when the tile breaks energy (`R + T + O` with a
//! medium that absorbs nothing, off 1 by more than its noise), or its open share leaves the open
//! area by more than the marching step allows.

use rayon::prelude::*;
use woven::gaps::{open_area, YarnSection};
use woven::math::rng::SplitMix;
use woven::translucency::{slab_transmitted_share, YARN_OPTICAL_DEPTH, YARN_SCATTERING_DEPTH};
use woven::Vec3;

/// Walks per 1-D slab estimate.
const SLAB_WALKS: usize = 200_000;
/// Rays per tile case.
const TILE_RAYS: usize = 40_000;
/// The marching step through the tile, pitches.
const STEP: f64 = 0.002;
/// A walk's weight below which it ends (the bias it leaves is below this).
const CUTOFF: f64 = 1e-7;

/// A direction uniform over the sphere, isotropic scattering's.
fn isotropic(rng: &mut SplitMix) -> Vec3 {
    let z = 2.0 * rng.uniform() - 1.0;
    let phi = 2.0 * std::f64::consts::PI * rng.uniform();
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// `(R, T)` of a slab of optical thickness `depth` (infinite: a half-space) and single-scattering
/// albedo `a` under diffuse (cosine-weighted) light, by Monte Carlo with survival weights; the
/// same random numbers for every call, so estimates move smoothly with the parameters.
fn slab(depth: f64, a: f64) -> (f64, f64) {
    let (r, t) = (0..SLAB_WALKS)
        .into_par_iter()
        .map(|k| {
            let mut rng = SplitMix(0x51ab ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
            let (mut z, mut mu, mut weight) = (0.0, rng.uniform().sqrt(), 1.0);
            loop {
                z += mu * -(1.0 - rng.uniform()).ln();
                if z < 0.0 {
                    return (weight, 0.0);
                }
                if z > depth {
                    return (0.0, weight);
                }
                weight *= a;
                if weight < CUTOFF {
                    return (0.0, 0.0);
                }
                mu = 2.0 * rng.uniform() - 1.0;
            }
        })
        .reduce(|| (0.0, 0.0), |x, y| (x.0 + y.0, x.1 + y.1));
    (r / SLAB_WALKS as f64, t / SLAB_WALKS as f64)
}

/// The root of an increasing `f` on `[lo, hi]`, by bisection.
fn bisect(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> f64 {
    for _ in 0..24 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The explicit tile of `gap`: whether `p` lies in a yarn of either family.
struct Tile {
    section: YarnSection,
}

impl Tile {
    fn inside(&self, p: Vec3) -> bool {
        let across = |c: f64| c - c.floor() - 0.5;
        self.section.contains(across(p.y), p.z) || self.section.contains(across(p.x), p.z)
    }

    /// Half the tile's thickness: above and below it there are no yarns.
    fn half(&self) -> f64 {
        0.5 * self.section.thickness()
    }
}

/// Where a ray of light from `w` goes in the tile with a medium of extinction `sigma` and
/// albedo `a`: `[O, R, T]` and the transmitted light's weighted mean exit cosine.
fn tile(gap: f64, w: Vec3, sigma: f64, a: f64) -> ([f64; 3], f64) {
    let tile = Tile {
        section: YarnSection::new(gap).expect("a valid gap"),
    };
    let top = tile.half() + 1e-9;
    let (sums, cos_sum) = (0..TILE_RAYS)
        .into_par_iter()
        .map(|k| {
            let mut rng = SplitMix(0x7113 ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
            let mut p = Vec3::new(rng.uniform(), rng.uniform(), top);
            let mut d = Vec3::new(-w.x, -w.y, -w.z);
            let (mut weight, mut entered) = (1.0, false);
            loop {
                // A free flight: optical depth −ln u, spent inside yarns only.
                let mut left = -(1.0 - rng.uniform()).ln();
                let mut travelled = 0.0;
                let collided = loop {
                    let mid = p + d * (0.5 * STEP);
                    if tile.inside(mid) {
                        entered = true;
                        let cost = sigma * STEP;
                        if cost >= left {
                            p = p + d * (left / sigma);
                            break true;
                        }
                        left -= cost;
                    }
                    p = p + d * STEP;
                    travelled += STEP;
                    if p.z.abs() > top || travelled > 50.0 {
                        break false;
                    }
                };
                if !collided {
                    let out = [
                        if entered { 0.0 } else { weight },
                        if entered && p.z > 0.0 { weight } else { 0.0 },
                        if entered && p.z < 0.0 { weight } else { 0.0 },
                    ];
                    let cos = if out[2] > 0.0 { weight * -d.z } else { 0.0 };
                    return (out, cos);
                }
                weight *= a;
                if weight < CUTOFF {
                    return ([0.0; 3], 0.0);
                }
                d = isotropic(&mut rng);
            }
        })
        .reduce(
            || ([0.0; 3], 0.0),
            |x, y| {
                (
                    [x.0[0] + y.0[0], x.0[1] + y.0[1], x.0[2] + y.0[2]],
                    x.1 + y.1,
                )
            },
        );
    let n = TILE_RAYS as f64;
    (sums.map(|s| s / n), cos_sum / sums[2].max(1e-300))
}

fn main() {
    let depth = YARN_SCATTERING_DEPTH;
    // σ: a yarn-thick slab that absorbs nothing reflects SX / (1 + SX).
    let want = depth / (1.0 + depth);
    let thickness_optical = bisect(0.05, 30.0, |t| slab(t, 1.0).0 - want);
    println!(
        "a slab that absorbs nothing reflects {want:.4} of diffuse light at optical thickness \
         {thickness_optical:.3} (the library's YARN_OPTICAL_DEPTH: {YARN_OPTICAL_DEPTH})"
    );
    let mut failures = 0;
    // The forward lobe's share (translucency::forward_share) rests on this thickness.
    if (thickness_optical / YARN_OPTICAL_DEPTH - 1.0).abs() > 0.01 {
        println!("  the optical thickness leaves YARN_OPTICAL_DEPTH by more than 1 %");
        failures += 1;
    }
    println!(
        "\n| ρ0 | a | gap | θi | O (open area) | R | T | τ_tile | τ 1-D slab | τ formula | exit cos |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for rho0 in [1.0, 0.8, 0.4] {
        // a: a half-space of the medium reflects ρ0 of diffuse light (all of it: a = 1).
        let a = if rho0 == 1.0 {
            1.0
        } else {
            bisect(0.0, 1.0, |a| slab(f64::INFINITY, a).0 - rho0)
        };
        let (r1, t1) = slab(thickness_optical, a);
        let tau_slab = t1 / (1.0 - r1);
        let tau_formula = slab_transmitted_share(rho0, depth);
        for gap in [0.2, 0.5] {
            let section = YarnSection::new(gap).expect("a valid gap");
            let sigma = thickness_optical / section.thickness();
            for theta_deg in [0.0f64, 30.0, 60.0] {
                let w = Vec3::from_spherical(theta_deg.to_radians(), 0.3);
                let ([o, r, t], cos) = tile(gap, w, sigma, a);
                let tau_tile = t / (1.0 - o - r);
                let open = open_area(gap, w).expect("a valid direction");
                println!(
                    "| {rho0} | {a:.5} | {gap} | {theta_deg}° | {o:.4} ({open:.4}) | {r:.4} | {t:.4} \
                     | {tau_tile:.3} | {tau_slab:.3} | {tau_formula:.3} | {cos:.3} |"
                );
                // The open share is the open area within the marching's reach.
                if (o - open).abs() > 0.01 {
                    println!("  the open share leaves the open area");
                    failures += 1;
                }
                // A medium that absorbs nothing conserves the light.
                if a == 1.0 && (o + r + t - 1.0).abs() > 0.01 {
                    println!("  R + T + O = {} with no absorption", o + r + t);
                    failures += 1;
                }
            }
        }
    }
    if failures > 0 {
        eprintln!("{failures} check(s) failed");
        std::process::exit(1);
    }
}
