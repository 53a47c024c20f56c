//! The warp by which RGL's `.bsdf` readers (Mitsuba 3's `measured`, pbrt-v4's `MeasuredBxDF`)
//! turn a uniform point of the unit square into a half vector, and back: a bilinear interpolant
//! on a regular grid, sampled continuously (the marginal's integral along `y`, then the
//! conditional's along `x`, each segment's inverse in closed form), multilinear in its
//! parameters (the incident direction). The fitter reads measured files through it
//! ([`invert`](Marginal2D::invert), [`eval`](Marginal2D::eval)); the exporter maps its sample
//! grid through it ([`sample`](Marginal2D::sample)) to know which half vector each node stands
//! for where a reader will look it up.

/// A tabulated function on the unit square (`nx × ny` nodes, bilinear), one slice per combination
/// of parameter values (multilinear between them): the continuous `Marginal2D` of Mitsuba 3 (and
/// pbrt-v4's `PiecewiseLinear2D`). With `cdf`, the slices are
/// normalised to integrate to 1 and carry the conditional and marginal CDFs that
/// [`Marginal2D::invert`] and [`Marginal2D::sample`] needs.
pub struct Marginal2D {
    nx: usize,
    ny: usize,
    /// The parameters' node values, outermost first.
    params: Vec<Vec<f64>>,
    /// Each parameter's stride in slices (0 for a single value).
    strides: Vec<usize>,
    data: Vec<f64>,
    /// Per slice, per row: the CDF along x (`nx` values).
    conditional: Vec<f64>,
    /// Per slice: the CDF along y (`ny` values).
    marginal: Vec<f64>,
}

/// The interval `[i, i + 1]` of sorted `values` that holds `x`, clamped to the ends (RGL's
/// `find_interval`): the last `i ≤ n − 2` with `values[i] ≤ x`, or 0.
fn find_interval(values: &[f64], x: f64) -> usize {
    let n = values.len();
    if n < 2 {
        return 0;
    }
    let mut i = 0;
    while i + 2 < n && values[i + 1] <= x {
        i += 1;
    }
    i
}

impl Marginal2D {
    /// A table of `data` (slices × `ny` × `nx`), parameters `params` (outermost first).
    pub fn new(
        nx: usize,
        ny: usize,
        data: Vec<f64>,
        params: Vec<Vec<f64>>,
        cdf: bool,
    ) -> Marginal2D {
        let mut strides = vec![0; params.len()];
        let mut slices = 1;
        for d in (0..params.len()).rev() {
            strides[d] = if params[d].len() > 1 { slices } else { 0 };
            slices *= params[d].len();
        }
        let mut t = Marginal2D {
            nx,
            ny,
            params,
            strides,
            data,
            conditional: Vec::new(),
            marginal: Vec::new(),
        };
        if cdf {
            let n = nx * ny;
            t.conditional = vec![0.0; slices * n];
            t.marginal = vec![0.0; slices * ny];
            for s in 0..slices {
                let data = &mut t.data[s * n..(s + 1) * n];
                let cond = &mut t.conditional[s * n..(s + 1) * n];
                let marg = &mut t.marginal[s * ny..(s + 1) * ny];
                for y in 0..ny {
                    for x in 0..nx - 1 {
                        let i = y * nx + x;
                        cond[i + 1] = cond[i] + 0.5 * (data[i] + data[i + 1]);
                    }
                }
                for y in 0..ny - 1 {
                    marg[y + 1] = marg[y] + 0.5 * (cond[(y + 1) * nx - 1] + cond[(y + 2) * nx - 1]);
                }
                // An all-zero slice stays zero rather than becoming NaN.
                let total = marg[ny - 1];
                let norm = if total > 0.0 { 1.0 / total } else { 0.0 };
                for v in cond
                    .iter_mut()
                    .chain(marg.iter_mut())
                    .chain(data.iter_mut())
                {
                    *v *= norm;
                }
            }
        }
        t
    }

    /// The first slice and the interpolation weights `(w0, w1)` per parameter at `param`.
    fn weights(&self, param: &[f64]) -> (usize, Vec<(f64, f64)>) {
        let mut slice = 0;
        let mut w = Vec::with_capacity(self.params.len());
        for (d, values) in self.params.iter().enumerate() {
            if values.len() < 2 {
                w.push((1.0, 0.0));
                continue;
            }
            let i = find_interval(values, param[d]);
            let (p0, p1) = (values[i], values[i + 1]);
            // Repeated node values: take the lower node.
            let t = if p1 > p0 {
                ((param[d] - p0) / (p1 - p0)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            w.push((1.0 - t, t));
            slice += self.strides[d] * i;
        }
        (slice, w)
    }

    /// `array[index]` interpolated over the parameters (`size` = the length of one slice).
    fn lookup(&self, array: &[f64], index: usize, size: usize, w: &[(f64, f64)]) -> f64 {
        let dims = w.len();
        let mut sum = 0.0;
        for corner in 0..1usize << dims {
            let mut weight = 1.0;
            let mut i = index;
            for (d, &(w0, w1)) in w.iter().enumerate() {
                if corner >> d & 1 == 1 {
                    weight *= w1;
                    i += self.strides[d] * size;
                } else {
                    weight *= w0;
                }
            }
            if weight != 0.0 {
                sum += weight * array.get(i).copied().unwrap_or(0.0);
            }
        }
        sum
    }

    /// The bilinear cell of `pos` (in the unit square): its lower corner and the offsets in it.
    fn cell(&self, pos: [f64; 2]) -> ([usize; 2], [f64; 2]) {
        let scaled = [pos[0] * (self.nx - 1) as f64, pos[1] * (self.ny - 1) as f64];
        let ix = (scaled[0].max(0.0) as usize).min(self.nx - 2);
        let iy = (scaled[1].max(0.0) as usize).min(self.ny - 2);
        ([ix, iy], [scaled[0] - ix as f64, scaled[1] - iy as f64])
    }

    /// The tabulated function at `pos`, bilinear (as stored: unnormalised tables are the raw
    /// data).
    pub fn eval(&self, pos: [f64; 2], param: &[f64]) -> f64 {
        let (slice, w) = self.weights(param);
        let ([ix, iy], [fx, fy]) = self.cell(pos);
        let size = self.nx * self.ny;
        let i = ix + iy * self.nx + slice * size;
        let v = |k: usize| self.lookup(&self.data, i + k, size, &w);
        let (v00, v10, v01, v11) = (v(0), v(1), v(self.nx), v(self.nx + 1));
        (1.0 - fy) * ((1.0 - fx) * v00 + fx * v10) + fy * ((1.0 - fx) * v01 + fx * v11)
    }

    /// The inverse of the warp the table's distribution defines: the point of the unit square
    /// that the sample `u` came from.
    pub fn invert(&self, u: [f64; 2], param: &[f64]) -> [f64; 2] {
        let (slice, w) = self.weights(param);
        let ([ix, iy], [mut sx, mut sy]) = self.cell(u);
        let size = self.nx * self.ny;
        let offset = ix + iy * self.nx + slice * size;
        let v = |a: &[f64], k: usize| self.lookup(a, offset + k, size, &w);
        let (v00, v10, v01, v11) = (
            v(&self.data, 0),
            v(&self.data, 1),
            v(&self.data, self.nx),
            v(&self.data, self.nx + 1),
        );
        // Along x: the integral of the bilinear density up to sx, plus the row's CDF.
        let c0 = (1.0 - sy) * v00 + sy * v01;
        let c1 = (1.0 - sy) * v10 + sy * v11;
        sx *= c0 + 0.5 * sx * (c1 - c0);
        let (k0, k1) = (v(&self.conditional, 0), v(&self.conditional, self.nx));
        sx += (1.0 - sy) * k0 + sy * k1;
        let row = iy * self.nx + slice * size;
        let r = |k: usize| self.lookup(&self.conditional, row + k, size, &w);
        let (r0, r1) = (r(self.nx - 1), r(2 * self.nx - 1));
        let norm = (1.0 - sy) * r0 + sy * r1;
        sx = if norm > 0.0 { sx / norm } else { 0.0 };
        // Along y: the same with the marginal CDF.
        sy *= r0 + 0.5 * sy * (r1 - r0);
        sy += self.lookup(&self.marginal, iy + slice * self.ny, self.ny, &w);
        [sx, sy]
    }
    /// The point of the unit square that the uniform sample `u` maps to ([`invert`]'s inverse),
    /// and the density there over the unit square. Needs a table built with `cdf`.
    ///
    /// [`invert`]: Self::invert
    pub fn sample(&self, u: [f64; 2], param: &[f64]) -> ([f64; 2], f64) {
        let (slice, w) = self.weights(param);
        let size = self.nx * self.ny;
        let [mut sx, mut sy] = u.map(|v| v.clamp(EPS, 1.0 - EPS));
        let marg = |k: usize| self.lookup(&self.marginal, k + slice * self.ny, self.ny, &w);
        // The row: marginal[row] < sy ≤ marginal[row + 1].
        let row = (1..self.ny)
            .find(|&k| marg(k) >= sy)
            .map_or(self.ny - 2, |k| k - 1)
            .min(self.ny - 2);
        sy -= marg(row);
        let base = row * self.nx + slice * size;
        let cond = |k: usize| self.lookup(&self.conditional, base + k, size, &w);
        let (r0, r1) = (cond(self.nx - 1), cond(2 * self.nx - 1));
        let ty = segment(sy, r0, r1);
        // The column, along the conditional CDF interpolated between the two rows.
        let along = |k: usize| cond(k) + ty * (cond(self.nx + k) - cond(k));
        sx *= r0 + ty * (r1 - r0);
        let col = (1..self.nx)
            .find(|&k| along(k) >= sx)
            .map_or(self.nx - 2, |k| k - 1)
            .min(self.nx - 2);
        sx -= along(col);
        let v = |k: usize| self.lookup(&self.data, base + col + k, size, &w);
        let c0 = v(0) + ty * (v(self.nx) - v(0));
        let c1 = v(1) + ty * (v(self.nx + 1) - v(1));
        let tx = segment(sx, c0, c1);
        let point = [
            (col as f64 + tx) / (self.nx - 1) as f64,
            (row as f64 + ty) / (self.ny - 1) as f64,
        ];
        let cells = ((self.nx - 1) * (self.ny - 1)) as f64;
        (point, (c0 + tx * (c1 - c0)) * cells)
    }
}

/// The smallest and largest samples the readers use (single precision's `2⁻²⁴` from 0 and 1).
const EPS: f64 = 1.0 / 16_777_216.0;

/// Where in a segment one node long, whose density runs linearly from `v0` to `v1`, the integral
/// from its start reaches `s`: the root in `[0, 1]` of `v0·t + (v1 − v0)·t²/2 = s`.
fn segment(s: f64, v0: f64, v1: f64) -> f64 {
    let root = (v0 * v0 + 2.0 * (v1 - v0) * s).max(0.0).sqrt();
    if v0 + root > 0.0 {
        (2.0 * s / (v0 + root)).clamp(0.0, 1.0)
    } else {
        0.0
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

    fn lerp(a: f64, b: f64, t: f64) -> f64 {
        a + (b - a) * t
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
        let warp = Marginal2D::new(w, h, data.clone(), vec![], true);
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
            let (p, density) = warp.sample(u, &[]);
            assert!(p.iter().all(|v| (0.0..=1.0).contains(v)));
            let expected = bilinear(&data, w, h, p) / integral;
            assert!(
                (density - expected).abs() < 1e-6 * expected,
                "{density} {expected}"
            );
            let back = warp.invert(p, &[]);
            // Not exact where a segment's density is nearly constant: there the readers (and
            // `segment`) take the linear root, off by under 1e-4 of the segment's variation.
            assert!(
                (back[0] - u[0]).abs() < 1e-5 && (back[1] - u[1]).abs() < 1e-5,
                "{u:?} {back:?}"
            );
        }
    }

    #[test]
    fn samples_follow_the_density() {
        // The fraction of uniform points mapped into the left half is the interpolant's mass
        // there.
        let (w, h) = (5, 4);
        let data = bumpy(w, h);
        let warp = Marginal2D::new(w, h, data.clone(), vec![], true);
        let n = 200;
        let left = (0..n * n)
            .filter(|k| {
                let u = [(k % n) as f64 + 0.5, (k / n) as f64 + 0.5].map(|v| v / n as f64);
                warp.sample(u, &[]).0[0] < 0.5
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
        let warp = Marginal2D::new(4, 3, vec![2.0; 12], vec![], true);
        for u in [[0.1, 0.9], [0.5, 0.5], [0.77, 0.2]] {
            let (p, density) = warp.sample(u, &[]);
            assert!((p[0] - u[0]).abs() < 1e-12 && (p[1] - u[1]).abs() < 1e-12);
            assert!((density - 1.0).abs() < 1e-12);
        }
    }
}
