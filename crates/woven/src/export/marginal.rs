//! The warp by which RGL's `.bsdf` readers turn a uniform point of the unit square into a half
//! vector: a bilinear interpolant on a regular grid, sampled continuously (the marginal's
//! integral along `y`, then the conditional's along `x`, each segment's inverse in closed form).
//!
//! The exporter ([`super::rgl`]) needs the same map the readers compute (Mitsuba 3's
//! `Marginal2D<…, Continuous = true>`, pbrt-v4's `PiecewiseLinear2D`) to know which half vector
//! each node of the file's sample grid stands for. Both readers evaluate one slice of it at a
//! table node, where their parameter weights are exactly 0 and 1; this is that slice.
//!
//! The grid has `w × h` nodes at `(i/(w−1), j/(h−1))`; `x` varies fastest in the data.

/// One slice of the continuous marginal warp, normalized to a density on the unit square.
#[derive(Clone, Debug)]
pub struct Marginal {
    w: usize,
    h: usize,
    /// The density at each node (normalized).
    data: Vec<f64>,
    /// Per row `y`, the integral of that row's interpolant from 0 to node `x + 1`.
    cond: Vec<f64>,
    /// The integral of the row integrals from 0 to row `y + 1`.
    marg: Vec<f64>,
}

/// The smallest and largest samples the readers use (single precision's `2⁻²⁴` from 0 and 1).
const EPS: f64 = 1.0 / 16_777_216.0;

impl Marginal {
    /// The warp of `data` (`w × h` values, non-negative, not all 0).
    ///
    /// # Panics
    /// When `w` or `h` is below 2 or `data` is not `w · h` long (a caller's bug).
    pub fn new(data: &[f64], w: usize, h: usize) -> Marginal {
        assert!(w >= 2 && h >= 2 && data.len() == w * h);
        let (half_dx, half_dy) = (0.5 / (w - 1) as f64, 0.5 / (h - 1) as f64);
        let mut cond = Vec::with_capacity(h * (w - 1));
        for row in data.chunks(w) {
            let mut sum = 0.0;
            for pair in row.windows(2) {
                sum += half_dx * (pair[0] + pair[1]);
                cond.push(sum);
            }
        }
        let total = |y: usize| cond[y * (w - 1) + w - 2];
        let mut marg = Vec::with_capacity(h - 1);
        let mut sum = 0.0;
        for y in 0..h - 1 {
            sum += half_dy * (total(y) + total(y + 1));
            marg.push(sum);
        }
        let norm = if sum > 0.0 { 1.0 / sum } else { 1.0 };
        let scale = |v: Vec<f64>| v.into_iter().map(|x| x * norm).collect();
        Marginal {
            w,
            h,
            data: scale(data.to_vec()),
            cond: scale(cond),
            marg: scale(marg),
        }
    }

    fn cond_at(&self, y: usize, x: usize) -> f64 {
        self.cond[y * (self.w - 1) + x]
    }

    fn row_total(&self, y: usize) -> f64 {
        self.cond_at(y, self.w - 2)
    }

    /// Row `row`'s and the next row's conditional integral to node `x + 1`, at `ty` between
    /// them; 0 before the first node.
    fn cond_lerp(&self, row: usize, x: Option<usize>, ty: f64) -> f64 {
        x.map_or(0.0, |x| {
            lerp(self.cond_at(row, x), self.cond_at(row + 1, x), ty)
        })
    }

    /// The point that the uniform point `u` maps to, and the density there.
    pub fn sample(&self, u: [f64; 2]) -> ([f64; 2], f64) {
        let [mut sx, mut sy] = u.map(|v| v.clamp(EPS, 1.0 - EPS));
        let row = first_not_below(&self.marg, sy).min(self.h - 2);
        sy -= if row > 0 { self.marg[row - 1] } else { 0.0 };
        let (r0, r1) = (self.row_total(row), self.row_total(row + 1));
        let ty = segment(sy, (self.h - 1) as f64, r0, r1);
        sx *= lerp(r0, r1, ty);
        let conds: Vec<f64> = (0..self.w - 1)
            .map(|x| self.cond_lerp(row, Some(x), ty))
            .collect();
        let col = first_not_below(&conds, sx).min(self.w - 2);
        sx -= self.cond_lerp(row, col.checked_sub(1), ty);
        let at = |x: usize, y: usize| self.data[y * self.w + x];
        let c0 = lerp(at(col, row), at(col, row + 1), ty);
        let c1 = lerp(at(col + 1, row), at(col + 1, row + 1), ty);
        let tx = segment(sx, (self.w - 1) as f64, c0, c1);
        let point = [
            (col as f64 + tx) / (self.w - 1) as f64,
            (row as f64 + ty) / (self.h - 1) as f64,
        ];
        (point, lerp(c0, c1, tx))
    }

    /// The uniform point that maps to `p` ([`sample`](Self::sample)'s inverse), and the
    /// density at `p`.
    pub fn invert(&self, p: [f64; 2]) -> ([f64; 2], f64) {
        let scaled = [
            p[0].clamp(0.0, 1.0) * (self.w - 1) as f64,
            p[1].clamp(0.0, 1.0) * (self.h - 1) as f64,
        ];
        let col = (scaled[0] as usize).min(self.w - 2);
        let row = (scaled[1] as usize).min(self.h - 2);
        let (fx, fy) = (scaled[0] - col as f64, scaled[1] - row as f64);
        let at = |x: usize, y: usize| self.data[y * self.w + x];
        let c0 = lerp(at(col, row), at(col, row + 1), fy);
        let c1 = lerp(at(col + 1, row), at(col + 1, row + 1), fy);
        let density = lerp(c0, c1, fx);
        let mut sx = fx * lerp(c0, c1, 0.5 * fx) / (self.w - 1) as f64;
        sx += self.cond_lerp(row, col.checked_sub(1), fy);
        let (r0, r1) = (self.row_total(row), self.row_total(row + 1));
        sx /= lerp(r0, r1, fy);
        let mut sy = fy * lerp(r0, r1, 0.5 * fy) / (self.h - 1) as f64;
        sy += if row > 0 { self.marg[row - 1] } else { 0.0 };
        ([sx, sy], density)
    }
}

fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a + (b - a) * t
}

/// The first index whose value is not below `x` (the last when all are).
fn first_not_below(values: &[f64], x: f64) -> usize {
    values.partition_point(|&v| v < x).min(values.len() - 1)
}

/// Where in a segment of width `1/inv_width`, whose density runs linearly from `v0` to `v1`,
/// the integral from its start reaches `s`: the root in `[0, 1]` of `v0·t + (v1 − v0)·t²/2 =
/// s·inv_width`.
fn segment(s: f64, inv_width: f64, v0: f64, v1: f64) -> f64 {
    let s = 2.0 * s * inv_width;
    if (v0 - v1).abs() > 1e-4 * (v0 + v1) {
        (v0 - (v0 * v0 + s * (v1 - v0)).max(0.0).sqrt()) / (v0 - v1)
    } else if v0 + v1 != 0.0 {
        s / (v0 + v1)
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::SplitMix;

    fn bumpy(w: usize, h: usize) -> Vec<f64> {
        (0..w * h)
            .map(|k| {
                let (x, y) = (
                    (k % w) as f64 / (w - 1) as f64,
                    (k / w) as f64 / (h - 1) as f64,
                );
                0.05 + (-((x - 0.3).powi(2) + (y - 0.7).powi(2)) / 0.02).exp() + x * y
            })
            .collect()
    }

    /// The bilinear interpolant of `data` at `p`, unnormalized.
    fn bilinear(data: &[f64], w: usize, h: usize, p: [f64; 2]) -> f64 {
        let (gx, gy) = (p[0] * (w - 1) as f64, p[1] * (h - 1) as f64);
        let (x, y) = ((gx as usize).min(w - 2), (gy as usize).min(h - 2));
        let (fx, fy) = (gx - x as f64, gy - y as f64);
        let at = |i: usize, j: usize| data[j * w + i];
        lerp(
            lerp(at(x, y), at(x + 1, y), fx),
            lerp(at(x, y + 1), at(x + 1, y + 1), fx),
            fy,
        )
    }

    #[test]
    fn sample_and_invert_are_inverses_and_the_density_is_the_normalized_interpolant() {
        let (w, h) = (9, 7);
        let data = bumpy(w, h);
        let warp = Marginal::new(&data, w, h);
        // The interpolant's integral by a midpoint rule whose cells split the grid's (exact for
        // a bilinear interpolant): the normalization.
        let n = 480;
        let integral = (0..n * n)
            .map(|k| {
                let p = [(k % n) as f64 + 0.5, (k / n) as f64 + 0.5].map(|v| v / n as f64);
                bilinear(&data, w, h, p)
            })
            .sum::<f64>()
            / (n * n) as f64;
        let mut rng = SplitMix(7);
        for _ in 0..2000 {
            let u = [rng.uniform(), rng.uniform()];
            let (p, density) = warp.sample(u);
            assert!(p.iter().all(|v| (0.0..=1.0).contains(v)));
            let expected = bilinear(&data, w, h, p) / integral;
            assert!(
                (density - expected).abs() < 1e-6 * expected,
                "{density} {expected}"
            );
            let (back, d2) = warp.invert(p);
            // Not exact where a segment's density is nearly constant: there the readers (and
            // `segment`) take the linear root, off by under 1e-4 of the segment's variation.
            assert!(
                (back[0] - u[0]).abs() < 1e-5 && (back[1] - u[1]).abs() < 1e-5,
                "{u:?} {back:?}"
            );
            assert!((d2 - density).abs() < 1e-9 * density);
        }
    }

    #[test]
    fn samples_follow_the_density() {
        // The fraction of uniform points mapped into the left half is the interpolant's mass
        // there.
        let (w, h) = (5, 4);
        let data = bumpy(w, h);
        let warp = Marginal::new(&data, w, h);
        let n = 200;
        let left = (0..n * n)
            .filter(|k| {
                let u = [(k % n) as f64 + 0.5, (k / n) as f64 + 0.5].map(|v| v / n as f64);
                warp.sample(u).0[0] < 0.5
            })
            .count() as f64
            / (n * n) as f64;
        let (mut mass_left, mut mass) = (0.0, 0.0);
        for k in 0..n * n {
            let p = [(k % n) as f64 + 0.5, (k / n) as f64 + 0.5].map(|v| v / n as f64);
            let v = bilinear(&data, w, h, p);
            mass += v;
            if p[0] < 0.5 {
                mass_left += v;
            }
        }
        assert!(
            (left - mass_left / mass).abs() < 0.01,
            "{left} {}",
            mass_left / mass
        );
    }

    #[test]
    fn a_constant_density_is_the_identity() {
        let warp = Marginal::new(&[2.0; 12], 4, 3);
        for u in [[0.1, 0.9], [0.5, 0.5], [0.77, 0.2]] {
            let (p, density) = warp.sample(u);
            assert!((p[0] - u[0]).abs() < 1e-12 && (p[1] - u[1]).abs() < 1e-12);
            assert!((density - 1.0).abs() < 1e-12);
        }
    }
}
