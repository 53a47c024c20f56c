//! Monotone cubic interpolation on a uniform grid (Fritsch–Carlson), used for the β table.

/// A monotone piecewise-cubic Hermite interpolant of samples on a uniform grid over `[x0, x1]`.
///
/// Between nodes it never overshoots the data, so a positive table stays positive.
#[derive(Clone, Debug)]
pub struct MonotoneCubic {
    x0: f64,
    inv_h: f64,
    /// Per interval `k`, the cubic in the local `u ∈ [0, 1]`: `c0 + c1 u + c2 u² + c3 u³` (the
    /// Hermite form expanded once here, so that a look-up is one row and three products).
    cubics: Vec<[f64; 4]>,
    /// The last sample (returned as is at and beyond the last node).
    last: f64,
}

impl MonotoneCubic {
    /// Builds the interpolant of `y[k]` at `x0 + k (x1 − x0)/(n − 1)`; needs `n ≥ 2`.
    pub fn new(x0: f64, x1: f64, y: Vec<f64>) -> Self {
        let n = y.len();
        assert!(n >= 2, "need at least two samples");
        let h = (x1 - x0) / (n - 1) as f64;
        let d: Vec<f64> = y.windows(2).map(|w| (w[1] - w[0]) / h).collect();
        let mut m = vec![0.0; n];
        // End slopes by the one-sided three-point formula (exact for quadratics), kept monotone.
        m[0] = end_slope(d[0], *d.get(1).unwrap_or(&d[0]));
        m[n - 1] = end_slope(d[n - 2], if n >= 3 { d[n - 3] } else { d[n - 2] });
        for k in 1..n - 1 {
            m[k] = if d[k - 1] * d[k] <= 0.0 {
                0.0
            } else {
                // Three-point (centred) slope, limited below to keep monotonicity.
                0.5 * (d[k - 1] + d[k])
            };
        }
        // Fritsch–Carlson limiter: keep (α, β) inside the circle of radius 3.
        for k in 0..n - 1 {
            if d[k] == 0.0 {
                m[k] = 0.0;
                m[k + 1] = 0.0;
                continue;
            }
            let a = m[k] / d[k];
            let b = m[k + 1] / d[k];
            let r = a * a + b * b;
            if r > 9.0 {
                let t = 3.0 / r.sqrt();
                m[k] = t * a * d[k];
                m[k + 1] = t * b * d[k];
            }
        }
        let cubics = (0..n - 1)
            .map(|k| {
                let (y0, y1) = (y[k], y[k + 1]);
                let (m0, m1) = (m[k] * h, m[k + 1] * h);
                // (2u³ − 3u² + 1) y0 + (u³ − 2u² + u) m0 + (−2u³ + 3u²) y1 + (u³ − u²) m1.
                [
                    y0,
                    m0,
                    -3.0 * y0 - 2.0 * m0 + 3.0 * y1 - m1,
                    2.0 * y0 + m0 - 2.0 * y1 + m1,
                ]
            })
            .collect();
        MonotoneCubic {
            x0,
            inv_h: 1.0 / h,
            cubics,
            last: y[n - 1],
        }
    }

    /// The interpolated value at `x` (clamped to the grid's range).
    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        let intervals = self.cubics.len();
        let t = ((x - self.x0) * self.inv_h).clamp(0.0, intervals as f64);
        let k = t as usize;
        if k >= intervals {
            return self.last;
        }
        let u = t - k as f64;
        let [c0, c1, c2, c3] = self.cubics[k];
        ((c3 * u + c2) * u + c1) * u + c0
    }
}

/// The PCHIP end condition: `(3 d0 − d1)/2`, zeroed if it turns against `d0` and limited to
/// `3 d0` when the data turns.
fn end_slope(d0: f64, d1: f64) -> f64 {
    let m = 0.5 * (3.0 * d0 - d1);
    if m * d0 <= 0.0 {
        0.0
    } else if d0 * d1 <= 0.0 && m.abs() > 3.0 * d0.abs() {
        3.0 * d0
    } else {
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_nodes_and_a_smooth_function() {
        let n = 65;
        let y: Vec<f64> = (0..n).map(|k| (k as f64 / 64.0).exp()).collect();
        let c = MonotoneCubic::new(0.0, 1.0, y.clone());
        for k in 0..n {
            assert!((c.eval(k as f64 / 64.0) - y[k]).abs() < 1e-15);
        }
        for k in 0..1000 {
            let x = k as f64 / 999.0;
            assert!((c.eval(x) - x.exp()).abs() < 1e-6, "at {x}");
        }
    }

    #[test]
    fn end_slope_is_exact_for_a_quadratic() {
        // y = x² on [0, 1]: the end slope at 0 must be 0, so values near 0 stay accurate.
        let y: Vec<f64> = (0..11).map(|k| (k as f64 / 10.0).powi(2)).collect();
        let c = MonotoneCubic::new(0.0, 1.0, y);
        assert!((c.eval(0.05) - 0.0025).abs() < 1e-12, "{}", c.eval(0.05));
    }

    #[test]
    fn never_overshoots_a_step() {
        let y = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        let c = MonotoneCubic::new(0.0, 5.0, y);
        for k in 0..=500 {
            let v = c.eval(k as f64 / 100.0);
            assert!((0.0..=1.0).contains(&v), "{v}");
        }
    }
}
