//! Importance sampling of a [`Table`]: per incidence node, a piecewise-constant density over the
//! cells of the warped half-vector grid, drawn by marginal and conditional CDFs.
//!
//! For the node's light direction `s_k`, cell `(i_y, i_x)` gets the weight
//! `∫_cell f(s_k, v) cos θ_r |∂ω_r/∂t| dt`, where `|∂ω_r/∂t|` is the map's Jacobian
//! (see [`super::grid::jacobian`]), estimated from the cell's corners and centre, plus a defensive
//! 1 % spread uniformly over solid angle so no direction the table can reach has zero density.
//! An arbitrary `s` samples from the incidence node nearest it: in half-vector coordinates the
//! peaks stay put as the light moves, so the nearest node's density fits well, and reading one
//! node instead of mixing the four around `s` keeps a sample to three rounds of memory access
//! (marginal CDF, conditional CDF, the table's values) and a `pdf` to two CDF entries. The
//! density is read off the CDFs themselves (row probability × cell probability over the cell's
//! area), so it is exactly what the CDFs draw: `p(v) = p_k(t(v)) / |∂ω/∂t|`, with the Jacobian of
//! the actual `s`. The per-cell densities the CDFs are cumulated from are kept for the file
//! only. Directions a node's cells map below the horizon for the actual `s` are rejected
//! (`sample` returns `None`); that lost mass, significant only at grazing incidence, is the gap
//! between `∫ pdf dω` and 1.

use super::eval::{locate_axis, Incidence, Query};
use super::grid::{jacobian, jacobian_at_slopes, slope_of_t, t_of_slope};
use super::{Half, Table};
use crate::math::sampling::{cumulate, invert_cdf_scan, normalize_cdf, BinSample};
use crate::math::Vec3;

/// Fraction of each node's sampling mass spread uniformly over solid angle.
const DEFENSIVE: f64 = 0.01;

#[derive(Clone, Debug, Default)]
pub(crate) struct Sampler {
    /// Cells per axis, `n_h − 1`.
    nc: usize,
    /// Per node: CDF over rows, `nc + 1` entries from 0 to 1.
    marginal: Vec<f32>,
    /// Per node and row: CDF over the row's cells, `nc + 1` entries.
    conditional: Vec<f32>,
    /// Per node and cell: the density in `t` space (integrates to 1 over the square).
    cell_pdf: Vec<f32>,
}

impl Sampler {
    /// The sampler of a table whose per-cell densities were stored with it.
    pub(crate) fn from_cell_pdf(table: &Table, cell_pdf: Vec<f32>) -> Sampler {
        let nc = table.t.n - 1;
        let dt = (table.t.hi - table.t.lo) / nc as f64;
        let nodes = table.theta.n * table.phi.n;
        let mut out = Sampler {
            nc,
            marginal: vec![0.0; nodes * (nc + 1)],
            conditional: vec![0.0; nodes * nc * (nc + 1)],
            cell_pdf,
        };
        out.cumulate(dt);
        out
    }

    /// The marginal and conditional CDFs ([`super::Raw`]).
    pub(crate) fn cdfs(&self) -> (&[f32], &[f32]) {
        (&self.marginal, &self.conditional)
    }

    /// The per-cell densities (stored in table files).
    pub(crate) fn cell_pdf(&self) -> &[f32] {
        &self.cell_pdf
    }

    /// Builds the marginal and conditional CDFs from `cell_pdf`: per node, each row's CDF over its
    /// cells' masses, and the CDF over the rows' masses.
    fn cumulate(&mut self, dt: f64) {
        let nc = self.nc;
        let nodes = self.cell_pdf.len() / (nc * nc);
        let mut row_mass = vec![0.0; nc];
        for node in 0..nodes {
            for (iy, mass) in row_mass.iter_mut().enumerate() {
                let row = node * nc + iy;
                let cells = &self.cell_pdf[row * nc..(row + 1) * nc];
                let cdf = &mut self.conditional[row * (nc + 1)..(row + 1) * (nc + 1)];
                *mass = cumulate(cells.iter().map(|&p| p as f64 * dt * dt), cdf);
                // An empty row keeps a uniform CDF; it is never chosen.
                normalize_cdf(cdf, *mass);
            }
            let marginal = &mut self.marginal[node * (nc + 1)..(node + 1) * (nc + 1)];
            let total = cumulate(row_mass.iter().copied(), marginal);
            normalize_cdf(marginal, total);
        }
    }

    /// Computes the per-cell densities of every node (the expensive part, in parallel over the
    /// nodes) and the CDFs.
    pub(crate) fn build(table: &Table) -> Sampler {
        use rayon::prelude::*;
        let n = table.t.n;
        let nc = n - 1;
        let dt = (table.t.hi - table.t.lo) / nc as f64;
        let nodes = table.theta.n * table.phi.n;
        let mut out = Sampler {
            nc,
            marginal: vec![0.0; nodes * (nc + 1)],
            conditional: vec![0.0; nodes * nc * (nc + 1)],
            cell_pdf: vec![0.0; nodes * nc * nc],
        };
        out.cell_pdf
            .par_chunks_mut(nc * nc)
            .enumerate()
            .for_each(|(node, cell_pdf)| node_density(table, node, dt, cell_pdf));
        out.cumulate(dt);
        out
    }

    /// The incidence node nearest folded `s` (in the axes' graded coordinates), whose density
    /// `sample` draws from and `pdf` reports, and the located `(iθ, wθ, iφ, wφ)` for evaluation.
    #[inline]
    fn node(table: &Table, s: Vec3) -> (usize, Incidence) {
        let (it, wt, ip, wp) = locate_axis(&table.theta, &table.phi, s);
        let np = table.phi.n;
        let dp = usize::from(np > 1 && wp >= 0.5);
        let dt = usize::from(wt >= 0.5);
        ((it + dt) * np + ip + dp, (it, wt, ip, wp))
    }

    /// The density in `t` space of cell `(iy, ix)` at `node`, exactly as the CDFs draw it: the
    /// row's and the cell's probabilities over the cell's area. Read from the CDFs rather than
    /// `cell_pdf` (which they round): `sample` has just read those entries, and `cell_pdf` stays
    /// out of the cache.
    #[inline]
    fn density(&self, node: usize, iy: usize, ix: usize, dt: f64) -> f64 {
        let nc = self.nc;
        let m = &self.marginal[node * (nc + 1) + iy..];
        let c = &self.conditional[(node * nc + iy) * (nc + 1) + ix..];
        (m[1] as f64 - m[0] as f64) * (c[1] as f64 - c[0] as f64) / (dt * dt)
    }

    /// Samples a folded `v` for folded `s`: `(v, pdf, f)`, with `f` the table's value there
    /// (computed from the sampled coordinates, without re-deriving them from `v`).
    pub(crate) fn sample<const WITH_F: bool>(
        &self,
        table: &Table,
        s: Vec3,
        u1: f64,
        u2: f64,
    ) -> Option<(Vec3, f64, f64)> {
        let nc = self.nc;
        let dt = (table.t.hi - table.t.lo) / nc as f64;
        let (node, located) = Self::node(table, s);
        let u = u1.clamp(0.0, 1.0 - f64::EPSILON);
        let marg = &self.marginal[node * (nc + 1)..(node + 1) * (nc + 1)];
        let BinSample {
            bin: iy,
            fraction: fy,
        } = invert_cdf_scan(marg, u)?;
        let cond = &self.conditional[(node * nc + iy) * (nc + 1)..(node * nc + iy + 1) * (nc + 1)];
        let BinSample {
            bin: ix,
            fraction: fx,
        } = invert_cdf_scan(cond, u2.clamp(0.0, 1.0 - f64::EPSILON))?;
        let tx = table.t.node(ix) + fx * dt;
        let ty = table.t.node(iy) + fy * dt;
        let (v, j) = jacobian(s, tx, ty)?;
        if j <= 0.0 {
            return None;
        }
        // The node's density in this cell over the map's Jacobian.
        let pdf = self.density(node, iy, ix, dt) / j;
        if !WITH_F {
            return (pdf > 0.0 && pdf.is_finite()).then_some((v, pdf, 0.0));
        }
        let f = if let Some(model) = table.exact_at(s, v) {
            model.eval(s, v)
        } else if Half::of(s, v) == Half::Light {
            table.eval_at(Half::Light, located, Query::new(s, v))
        } else {
            table.eval_folded(s, v)
        };
        (pdf > 0.0 && pdf.is_finite()).then_some((v, pdf, f))
    }

    /// The density (per unit solid angle) of a folded `v` for folded `s`.
    pub(crate) fn pdf(&self, table: &Table, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let h = s + v;
        let (px, py) = (h.x / h.z, h.y / h.z);
        let (tx, ty) = (t_of_slope(px), t_of_slope(py));
        // Past the grid's last slope `t` is clamped to ±1: the Jacobian there is the clamped
        // slope's (as the draw's would be).
        let at = |t: f64, p: f64| (t, if t.abs() < 1.0 { p } else { slope_of_t(t) });
        let Some(j) = jacobian_at_slopes(s, at(tx, px), at(ty, py)) else {
            return 0.0;
        };
        if j <= 0.0 {
            return 0.0;
        }
        let nc = self.nc;
        let (iy, _) = table.t.locate(ty);
        let (ix, _) = table.t.locate(tx);
        let (node, _) = Self::node(table, s);
        let dt = (table.t.hi - table.t.lo) / nc as f64;
        self.density(node, iy, ix, dt) / j
    }
}

/// The per-cell densities in `t` space of incidence node `node` (see the module's description).
fn node_density(table: &Table, node: usize, dt: f64, cell_pdf: &mut [f32]) {
    let nc = table.t.n - 1;
    let (it, ip) = (node / table.phi.n, node % table.phi.n);
    let s = Vec3::from_spherical(table.theta.node(it), table.phi.node(ip));
    // f cos θ_r at a node above the horizon (0 below it: no mass to sample there), from whichever
    // half answers for the pair, or from the exact model where the table answers with it.
    let value = |v: Vec3| (table.eval_folded(s, v) * v.z).max(0.0);
    let mut weights = vec![0.0f64; nc * nc];
    let mut spread = vec![0.0f64; nc * nc];
    for iy in 0..nc {
        for ix in 0..nc {
            let (t0y, t0x) = (table.t.node(iy), table.t.node(ix));
            let mut acc = 0.0;
            let mut valid = 0usize;
            let mut corner_sum = 0.0;
            for (a, b) in [(0.0, 0.0), (0.0, dt), (dt, 0.0), (dt, dt)] {
                if let Some((v, j)) = jacobian(s, t0x + b, t0y + a) {
                    let fc = value(v);
                    acc += fc * j;
                    corner_sum += fc;
                    valid += 1;
                }
            }
            let centre = jacobian(s, t0x + 0.5 * dt, t0y + 0.5 * dt);
            let mut norm = valid as f64;
            if let Some((vc, j)) = centre {
                // The centre counts four times, with the corners' mean value (an evaluation
                // fewer), or its own where no corner is valid.
                let fc = if valid > 0 {
                    corner_sum / valid as f64
                } else {
                    value(vc)
                };
                acc += 4.0 * fc * j;
                norm += 4.0;
            }
            // The mean over the cell's valid points times the area of its valid part: a cell
            // the horizon cuts keeps the density of its valid part. Its valid fraction is
            // counted on a 4 × 4 grid, not read off the five points, whose count diluted the
            // density (weights 7× their median next to the horizon) or, taking the whole cell,
            // spent mass on rejected draws (6 % of them at 40° on a coarse grid).
            let fraction = if valid == 4 && centre.is_some() {
                1.0
            } else if norm > 0.0 {
                let inside = (0..16)
                    .filter(|k| {
                        let (a, b) = ((k / 4) as f64 + 0.5, (k % 4) as f64 + 0.5);
                        jacobian(s, t0x + b * dt / 4.0, t0y + a * dt / 4.0).is_some()
                    })
                    .count();
                inside.max(1) as f64 / 16.0
            } else {
                0.0
            };
            weights[iy * nc + ix] = if norm > 0.0 {
                acc / norm * fraction * dt * dt
            } else {
                0.0
            };
            // Solid angle of the cell (for the defensive part), if any of it is valid.
            spread[iy * nc + ix] = if norm > 0.0 {
                centre.map_or_else(|| jacobian_abs_mean(s, t0x, t0y, dt), |(_, j)| j) * dt * dt
            } else {
                0.0
            };
        }
    }
    let total: f64 = weights.iter().sum();
    let total_spread: f64 = spread.iter().sum();
    let (wf, ws) = if total > 0.0 && total_spread > 0.0 {
        ((1.0 - DEFENSIVE) / total, DEFENSIVE / total_spread)
    } else if total_spread > 0.0 {
        (0.0, 1.0 / total_spread)
    } else {
        (0.0, 0.0)
    };
    for (k, p) in cell_pdf.iter_mut().enumerate() {
        *p = ((wf * weights[k] + ws * spread[k]) / (dt * dt)) as f32;
    }
}

/// Mean `|∂ω/∂t|` over the valid corners of a cell whose centre maps below the horizon.
fn jacobian_abs_mean(s: Vec3, t0x: f64, t0y: f64, dt: f64) -> f64 {
    let mut acc = 0.0;
    let mut k = 0;
    for (a, b) in [(0.0, 0.0), (0.0, dt), (dt, 0.0), (dt, dt)] {
        if let Some((_, j)) = jacobian(s, t0x + b, t0y + a) {
            acc += j;
            k += 1;
        }
    }
    if k == 0 {
        0.0
    } else {
        acc / k as f64
    }
}
