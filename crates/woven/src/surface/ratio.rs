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
//! `F` met from `v` (each lit or not from `s`), `P_F` that family's whole-float average of the
//! crowned yarn (`Table::crowned`) on the relief's floats, both for the material's own albedos:
//! the mean of what a close-up shows, so `auto` keeps its mean as it blends from yarns to the
//! macro lobes. `P_F` carries the sheen's lobes, so `R_F` carries what varies slowly: the share of
//! each family seen along the view, and the shadowing and masking between neighbouring yarns. A
//! coarse table of it serves: [`THETA_DEG`] × [`PHI`] nodes per direction, the light's azimuth
//! taken relative to the view's node, interpolated linearly (bilinear in each direction's polar
//! angle and azimuth), over at least [`ENTRIES`] entries a repeat, stratified over its cells.
//! A build takes seconds per surface, so the table is kept on disk next to the yarn tables
//! ([`WovenSurface::prepare`]).

use super::{Entry, LobeMix, Tilt, WovenSurface};
use crate::math::Vec3;
use crate::yarn::point::golden_uniform;
use rayon::prelude::*;
use std::f64::consts::PI;
use std::path::Path;

/// The table's polar nodes, degrees.
pub const THETA_DEG: [f64; 9] = [0.0, 20.0, 35.0, 48.0, 59.0, 68.0, 76.0, 82.0, 87.0];

/// The table's azimuth nodes, over the whole circle.
pub const PHI: usize = 24;

/// Entries of a repeat averaged at each node: at least this many, and at least 4 per cell.
pub const ENTRIES: usize = 256;

/// The largest ratio kept (where the paper's lobes are all but black and the relief is not).
pub const MAX_RATIO: f64 = 8.0;

const NODES: usize = THETA_DEG.len() * PHI;

/// The first bytes of a cached ratio table.
const MAGIC: &[u8; 4] = b"WRAT";

/// What a build computes, beyond its inputs (part of the file and of its key): a change to the
/// relief, the crown, the sampling of entries or the macro lobes' evaluation bumps it (2: a
/// whole float read from its own table).
const REVISION: u32 = 2;

/// The cache key of `surface`'s ratio table: an FNV-1a hash of everything that decides it — the
/// yarn table's values (and dye derivatives), the pattern, the cells' aspect (the relief scales
/// with the cells), the gap, the floats' profile and the table's constants.
fn key(surface: &WovenSurface) -> String {
    use crate::table::cache::{fnv1a, FNV_BASIS};
    let mut h = FNV_BASIS;
    let mut eat = |bytes: &[u8]| h = fnv1a(h, bytes);
    let table = &surface.tables.yarn;
    for x in table.values() {
        eat(&x.to_le_bytes());
    }
    for x in table.body_values().unwrap_or_default() {
        eat(&x.to_le_bytes());
    }
    let pattern = surface.pattern().expect("a relief lies on a pattern");
    eat(format!(
        "{:?}|{}|{}|{:?}|{}|{:?}|{:?}|{}|{}|{}|{}",
        pattern,
        surface.yarns_per_unit[1] / surface.yarns_per_unit[0],
        surface.gap,
        surface.float,
        crate::relief::CROWN_DEG,
        THETA_DEG,
        PHI,
        ENTRIES,
        crate::table::crown::CROWN_NODES,
        REVISION,
        surface.dyes.own.diffuse,
    )
    .as_bytes());
    format!("{h:016x}")
}

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
    let i = THETA_DEG[1..last]
        .iter()
        .take_while(|&&t| t <= theta)
        .count();
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
        let per_side = ((ENTRIES as f64 / (cols * rows) as f64).sqrt().ceil() as usize).max(2);
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
        // The denominator: the macro lobes of the crowned yarn on the relief's floats.
        let mut paper = surface.macro_lobes();
        paper.resolve_from(0);
        let relief = surface.relief.as_ref().expect("a ratio needs a relief");
        // Per view node, every light node's pair of ratios.
        // The view nodes straight up (the first PHI) are one direction: its column is built once
        // (below, each is the first turned by its azimuth).
        let mut columns: Vec<Vec<[f32; 2]>> = (0..NODES)
            .into_par_iter()
            .map(|j| {
                if (1..PHI).contains(&j) {
                    return Vec::new();
                }
                let v = node(j);
                // Each entry's relief point, and its horizon toward every azimuth node: a light
                // node is lit where it stands above it.
                let seen: Vec<(LobeMix, [f64; PHI])> = entries
                    .iter()
                    .map(|e| {
                        let mix = surface.with_relief(LobeMix::default(), e, v);
                        let mut horizon = [f64::NEG_INFINITY; PHI];
                        if let Some(Tilt::Relief { at, .. }) = mix.lobes().first().map(|l| l.tilt) {
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
                                m[usize::from(l.warp)] +=
                                    l.weight * surface.lobe_value_own(l, s, v);
                            }
                        }
                        for l in paper.lobes() {
                            p[usize::from(l.warp)] += l.weight * surface.lobe_value_own(l, s, v);
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
        for j in 1..PHI {
            // Light node (a, k) relative to azimuth j is node (a, k + j) relative to azimuth 0.
            columns[j] = (0..NODES)
                .map(|i| columns[0][i - i % PHI + (i % PHI + j) % PHI])
                .collect();
        }
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

    /// The table as bytes: a magic, the revision and node counts, both families' values, a
    /// CRC-32 of what precedes it.
    fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(20 + 8 * NODES * NODES);
        out.extend_from_slice(MAGIC);
        for n in [REVISION, THETA_DEG.len() as u32, PHI as u32] {
            out.extend_from_slice(&n.to_le_bytes());
        }
        for family in &self.values {
            for x in family {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// The table [`to_bytes`](Self::to_bytes) wrote, or why `bytes` are not one of this build's.
    fn from_bytes(bytes: &[u8]) -> std::result::Result<ReliefRatio, &'static str> {
        let want = 16 + 8 * NODES * NODES + 4;
        if bytes.len() != want || &bytes[..4] != MAGIC {
            return Err("not a ratio table of this build's size");
        }
        let (body, crc) = bytes.split_at(want - 4);
        if crc32fast::hash(body).to_le_bytes() != crc {
            return Err("checksum mismatch");
        }
        let word = |i: usize| u32::from_le_bytes(body[4 + 4 * i..8 + 4 * i].try_into().unwrap());
        if [word(0), word(1), word(2)] != [REVISION, THETA_DEG.len() as u32, PHI as u32] {
            return Err("another revision or grid");
        }
        let floats: Vec<f32> = body[16..]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        if !floats.iter().all(|x| x.is_finite() && *x >= 0.0) {
            return Err("values not finite and non-negative");
        }
        let (weft, warp) = floats.split_at(NODES * NODES);
        Ok(ReliefRatio {
            values: [weft.to_vec(), warp.to_vec()],
        })
    }

    /// The table of `surface` from `dir` (a file named by its key), or built and stored there.
    /// `note` hears why a file was not used or could not be written (the table is then built, or
    /// kept in memory only).
    pub(super) fn load_or_build(
        surface: &WovenSurface,
        dir: &Path,
        note: &dyn Fn(&str),
    ) -> ReliefRatio {
        let path = dir.join(format!("ratio-{}.wrat", key(surface)));
        match crate::fsutil::read_regular(&path, (32 + 8 * NODES * NODES) as u64, "ratio table") {
            Ok(bytes) => match ReliefRatio::from_bytes(&bytes) {
                Ok(table) => return table,
                Err(why) => note(&format!(
                    "not using {} ({why}): rebuilding it",
                    path.display()
                )),
            },
            Err(_) if !path.exists() => {}
            Err(e) => note(&format!(
                "not using {} ({e}): rebuilding it",
                path.display()
            )),
        }
        let table = ReliefRatio::build(surface);
        let stored = std::fs::create_dir_all(dir)
            .map_err(|e| e.to_string())
            .and_then(|()| {
                crate::fsutil::atomic_write(&path, |w| w.write_all(&table.to_bytes()))
                    .map_err(|e| e.to_string())
            });
        if let Err(e) = stored {
            note(&format!("the ratio table could not be cached ({e})"));
        }
        table
    }

    /// `R_F(s, v)` for the family `warp`, interpolated.
    #[inline]
    pub(super) fn at(&self, warp: bool, s: Vec3, v: Vec3) -> f64 {
        self.pair(s, v)[usize::from(warp)]
    }

    /// `[R_weft, R_warp]` at `(s, v)`, interpolated (one location of the nodes for both).
    #[inline]
    pub(super) fn pair(&self, s: Vec3, v: Vec3) -> [f64; 2] {
        // The light's nodes once: turning it back by a view node's azimuth shifts its azimuth
        // index by that node's.
        let light = corners(s);
        let mut r = [0.0; 2];
        for (j, wj) in corners(v) {
            let back = PHI - j % PHI;
            for &(i, wi) in &light {
                let k = (i - i % PHI + (i % PHI + back) % PHI) * NODES + j;
                for (r, table) in r.iter_mut().zip(&self.values) {
                    *r += wi * wj * f64::from(table[k]);
                }
            }
        }
        r
    }
}
