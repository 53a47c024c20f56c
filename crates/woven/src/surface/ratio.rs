//! The relief's ratio: how the cloth's macro BRDF changes when its points are resolved on the
//! weave's relief (docs/model.md §8, "The relief").
//!
//! Resolved, a point of the cloth shades as the relief point its viewer's ray meets: the yarn
//! that stands highest along the ray, its surface leaning with its float and its round crown,
//! lit where no yarn stands between it and the light. Averaged over a repeat, that is not the
//! paper's γ-mix: the family seen along the view covers more than its share γ, and yarns shadow
//! their neighbours. Far away, where a pixel covers cells, a resolving surface ([`Detail::Auto`])
//! shades with the paper's macro lobes of each family scaled by
//!
//! ```text
//! R_F(s, v) = M_F(s, v) / P_F(s, v),
//! ```
//!
//! `M_F` the mean over a repeat's entries of the yarn-level BRDF of the relief points of family
//! `F` met from `v` (each lit or not from `s`), `P_F` the paper's macro lobes of `F`, both for the
//! material's own albedos: the mean of what a close-up shows, so `auto` keeps its mean as it
//! blends from yarns to the macro BRDF. `R_F` varies with the geometry only (shares and shadows,
//! not the sheen's sharp lobes), so a coarse table of it serves: [`THETA_DEG`] × [`PHI`] nodes per
//! direction, interpolated linearly (bilinear in each direction's polar angle and azimuth).

use super::{Entry, LobeMix, Tilt, WovenSurface};
use crate::color::Rgb;
use crate::math::Vec3;
use crate::yarn::point::golden_uniform;
use rayon::prelude::*;
use std::f64::consts::PI;

/// The table's polar nodes, degrees.
pub const THETA_DEG: [f64; 9] = [0.0, 20.0, 35.0, 48.0, 59.0, 68.0, 76.0, 82.0, 87.0];

/// The table's azimuth nodes, over the whole circle.
pub const PHI: usize = 24;

/// Entries of a repeat averaged at each node: at least this many, and at least 9 per cell.
pub const ENTRIES: usize = 576;

/// The largest ratio kept (where the paper's lobes are all but black and the relief is not).
pub const MAX_RATIO: f64 = 8.0;

const NODES: usize = THETA_DEG.len() * PHI;

/// The relief's ratio table of a surface, per family (module docs).
#[derive(Debug)]
pub(super) struct ReliefRatio {
    /// Per family (weft, warp): `R_F` at light node `i` and view node `j`, at `i * NODES + j`.
    values: [Vec<f32>; 2],
}

/// Node `k`'s direction: polar node `k / PHI`, azimuth node `k % PHI`.
fn node(k: usize) -> Vec3 {
    let phi = 2.0 * PI * (k % PHI) as f64 / PHI as f64;
    Vec3::from_spherical(THETA_DEG[k / PHI].to_radians(), phi)
}

/// Node `k`'s azimuth, radians.
fn azimuth(k: usize) -> f64 {
    2.0 * PI * (k % PHI) as f64 / PHI as f64
}

/// `d` turned by `phi` about the normal.
fn turned(d: Vec3, phi: f64) -> Vec3 {
    let (s, c) = phi.sin_cos();
    Vec3::new(c * d.x - s * d.y, s * d.x + c * d.y, d.z)
}

/// The nodes about `d` and their weights: two polar nodes by two azimuth nodes.
fn corners(d: Vec3) -> [(usize, f64); 4] {
    let theta = d.z.clamp(-1.0, 1.0).acos().to_degrees();
    let last = THETA_DEG.len() - 1;
    let i = THETA_DEG[1..last].iter().take_while(|&&t| t <= theta).count();
    let ft = ((theta - THETA_DEG[i]) / (THETA_DEG[i + 1] - THETA_DEG[i])).clamp(0.0, 1.0);
    let p = d.y.atan2(d.x).rem_euclid(2.0 * PI) / (2.0 * PI) * PHI as f64;
    let j = (p.floor() as usize).min(PHI - 1);
    let fp = p - j as f64;
    let j1 = (j + 1) % PHI;
    [
        (i * PHI + j, (1.0 - ft) * (1.0 - fp)),
        (i * PHI + j1, (1.0 - ft) * fp),
        ((i + 1) * PHI + j, ft * (1.0 - fp)),
        ((i + 1) * PHI + j1, ft * fp),
    ]
}

impl ReliefRatio {
    /// The table of `surface`, which has a relief and a pattern.
    pub(super) fn build(surface: &WovenSurface) -> ReliefRatio {
        let pattern = surface.pattern().expect("a relief lies on a pattern");
        let (cols, rows) = (pattern.cols(), pattern.rows());
        let per_side = ((ENTRIES as f64 / (cols * rows) as f64).sqrt().ceil() as usize).max(3);
        let n = per_side * per_side * cols * rows;
        // Stratified over each cell, jittered by golden-ratio points.
        let entries: Vec<Entry> = (0..n)
            .map(|k| {
                let (cell, sub) = (k / (per_side * per_side), k % (per_side * per_side));
                let (c, r) = ((cell % cols) as f64, (cell / cols) as f64);
                let jx = golden_uniform(k as i64, 11);
                let jy = golden_uniform(k as i64, 12);
                Entry {
                    x: c + ((sub % per_side) as f64 + jx) / per_side as f64,
                    y: r + ((sub / per_side) as f64 + jy) / per_side as f64,
                    weight: 1.0,
                    fibers: 0.0,
                }
            })
            .collect();
        let albedos = [surface.own; 3];
        // The denominator: the macro lobes of the crowned yarn on the relief's floats.
        let mut paper = surface.macro_lobes();
        paper.resolve_from(0);
        let relief = surface.relief.as_ref().expect("a ratio needs a relief");
        let mean = |f: Rgb, weight: f64| weight * (f.0[0] + f.0[1] + f.0[2]) / 3.0;
        // Per view node, every light node's pair of ratios.
        let columns: Vec<Vec<[f32; 2]>> = (0..NODES)
            .into_par_iter()
            .map(|j| {
                let v = node(j);
                // Each entry's relief point, and its horizon toward every azimuth node: a light
                // node is lit where it stands above it.
                let seen: Vec<(LobeMix, [f64; PHI])> = entries
                    .iter()
                    .map(|e| {
                        let mix = surface.with_relief(LobeMix::default(), e, v);
                        let mut horizon = [f64::NEG_INFINITY; PHI];
                        if let Some(Tilt::Relief { at, .. }) = mix.lobes().first().map(|l| l.tilt)
                        {
                            for (k, h) in horizon.iter_mut().enumerate() {
                                *h = relief.horizon(at, 2.0 * PI * k as f64 / PHI as f64);
                            }
                        }
                        (mix, horizon)
                    })
                    .collect();
                (0..NODES)
                    .map(|i| {
                        // Light node i is relative to the view's azimuth.
                        let s = turned(node(i), azimuth(j));
                        let toward = (i % PHI + j % PHI) % PHI;
                        let slope = s.z / s.x.hypot(s.y);
                        let mut m = [0.0; 2];
                        let mut p = [0.0; 2];
                        for (mix, horizon) in &seen {
                            if slope <= horizon[toward] {
                                continue;
                            }
                            for l in mix.lobes() {
                                let f = surface.lobe_value(l, &albedos, s, v);
                                m[usize::from(l.warp)] += mean(f, l.weight);
                            }
                        }
                        for l in paper.lobes() {
                            let f = surface.lobe_value(l, &albedos, s, v);
                            p[usize::from(l.warp)] += mean(f, l.weight);
                        }
                        [0, 1].map(|k| {
                            let m = m[k] / n as f64;
                            if p[k] > 1e-9 {
                                (m / p[k]).min(MAX_RATIO) as f32
                            } else {
                                1.0
                            }
                        })
                    })
                    .collect()
            })
            .collect();
        let values = [0, 1].map(|k| {
            let mut v = vec![0.0f32; NODES * NODES];
            for (j, column) in columns.iter().enumerate() {
                for (i, r) in column.iter().enumerate() {
                    v[i * NODES + j] = r[k];
                }
            }
            v
        });
        ReliefRatio { values }
    }

    /// `R_F(s, v)` for the family `warp`, interpolated.
    #[inline]
    pub(super) fn at(&self, warp: bool, s: Vec3, v: Vec3) -> f64 {
        let table = &self.values[usize::from(warp)];
        let mut r = 0.0;
        for (j, wj) in corners(v) {
            for (i, wi) in corners(turned(s, -azimuth(j))) {
                r += wi * wj * f64::from(table[i * NODES + j]);
            }
        }
        r
    }
}
