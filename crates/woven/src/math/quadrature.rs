//! Quadrature rules: Gauss–Legendre of any order and adaptive Gauss–Kronrod (7–15).
//!
//! The model's averages (docs/spec.md §1.5, §2.3–§2.6) all reduce to one-dimensional integrals of
//! smooth pieces with known breaks; these two rules, applied per piece, carry them.

use super::lanes::Lanes;

/// Sorts `breaks`, drops duplicates and points outside `[lo, hi]`, adds the ends, and splits any
/// panel wider than `max_width` into equal parts: the panel edges for a piecewise rule.
pub fn panel_edges(breaks: &mut Vec<f64>, lo: f64, hi: f64, max_width: f64) {
    breaks.retain(|&b| b > lo && b < hi);
    breaks.push(lo);
    breaks.push(hi);
    breaks.sort_by(f64::total_cmp);
    breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-12 * (1.0 + b.abs()));
    let mut k = 1;
    while k < breaks.len() {
        let w = breaks[k] - breaks[k - 1];
        if w > max_width {
            let n = (w / max_width).ceil() as usize;
            let a = breaks[k - 1];
            for j in 1..n {
                breaks.insert(k + j - 1, a + w * j as f64 / n as f64);
            }
            k += n;
        } else {
            k += 1;
        }
    }
}

/// Gauss–Legendre nodes and weights on `[-1, 1]`.
#[derive(Clone, Debug)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// The `n`-point rule (`n ≥ 1`), exact for polynomials of degree `2n − 1`.
    ///
    /// Nodes are the roots of `P_n`, found by Newton's method from Tricomi's initial guess;
    /// weights `2 / ((1 − x²) P_n'(x)²)`. Accurate to a few ulp for `n` up to several hundred.
    ///
    /// ```
    /// use woven::math::quadrature::GaussLegendre;
    /// let gl = GaussLegendre::new(3);
    /// // ∫_0^1 x^5 dx = 1/6, exact for 3 points.
    /// assert!((gl.integrate(0.0, 1.0, |x| x.powi(5)) - 1.0 / 6.0).abs() < 1e-15);
    /// ```
    pub fn new(n: usize) -> Self {
        assert!(n >= 1, "Gauss–Legendre order must be at least 1");
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for i in 0..n.div_ceil(2) {
            // Tricomi's approximation of the i-th root (descending order).
            let k = i as f64 + 1.0;
            let mut x = (std::f64::consts::PI * (k - 0.25) / (nf + 0.5)).cos()
                * (1.0 - (nf - 1.0) / (8.0 * nf * nf * nf));
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre_and_derivative(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre_and_derivative(n, x);
            if d.is_finite() {
                dp = d;
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            weights[i] = w;
            nodes[n - 1 - i] = x;
            weights[n - 1 - i] = w;
        }
        if n % 2 == 1 {
            nodes[n / 2] = 0.0;
        }
        GaussLegendre { nodes, weights }
    }

    /// The nodes on `[-1, 1]`, ascending.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// The weights, matching [`nodes`](Self::nodes); they sum to 2.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// `∫_a^b f(x) dx` by this rule (`f` a number, or several integrated together).
    #[inline]
    pub fn integrate<T: Lanes>(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> T) -> T {
        let h = 0.5 * (b - a);
        let c = 0.5 * (b + a);
        let mut s = T::ZERO;
        for (x, w) in self.nodes.iter().zip(&self.weights) {
            s = s.add(f(c + h * x).scale(*w));
        }
        s.scale(h)
    }
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let mut p0 = 1.0;
    let mut p1 = x;
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let nf = n as f64;
    (p1, nf * (x * p1 - p0) / (x * x - 1.0))
}

// Kronrod 15-point abscissae and weights with the embedded 7-point Gauss rule (published constants).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One Gauss–Kronrod 7–15 panel: `(K15 estimate, |K15 − G7|)`.
#[inline]
pub fn gauss_kronrod_15(a: f64, b: f64, f: &mut impl FnMut(f64) -> f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = WGK[7] * fc;
    let mut g = WG[3] * fc;
    for j in 0..7 {
        let dx = h * XGK[j];
        let s = f(c - dx) + f(c + dx);
        k += WGK[j] * s;
        if j % 2 == 1 {
            g += WG[j / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// Adaptive Gauss–Kronrod integration of `f` over `[a, b]`.
///
/// Bisects panels until each panel's error estimate is below its share of
/// `max(abs_tol, rel_tol · |I|)`, or the depth limit (`2^max_depth` panels) is reached.
/// Returns the integral estimate.
///
/// ```
/// use woven::math::quadrature::adaptive;
/// let i = adaptive(0.0, 1.0, 1e-12, 0.0, 30, |x: f64| x.sqrt());
/// assert!((i - 2.0 / 3.0).abs() < 1e-10);
/// ```
pub fn adaptive(
    a: f64,
    b: f64,
    rel_tol: f64,
    abs_tol: f64,
    max_depth: u32,
    mut f: impl FnMut(f64) -> f64,
) -> f64 {
    if a == b {
        return 0.0;
    }
    let (whole, err) = gauss_kronrod_15(a, b, &mut f);
    if err <= abs_tol.max(rel_tol * whole.abs()) {
        return whole;
    }
    // Global tolerance fixed from the first estimate; each panel gets its length's share.
    let tol = abs_tol.max(rel_tol * whole.abs());
    recurse(a, b, whole, err, tol / (b - a).abs(), max_depth, &mut f)
}

fn recurse(
    a: f64,
    b: f64,
    est: f64,
    err: f64,
    tol_density: f64,
    depth: u32,
    f: &mut impl FnMut(f64) -> f64,
) -> f64 {
    if depth == 0 || err <= tol_density * (b - a).abs() {
        return est;
    }
    let m = 0.5 * (a + b);
    let (l, el) = gauss_kronrod_15(a, m, f);
    let (r, er) = gauss_kronrod_15(m, b, f);
    // Stop refining once the two halves agree with the parent to the tolerance.
    if el + er <= tol_density * (b - a).abs() {
        return l + r;
    }
    recurse(a, m, l, el, tol_density, depth - 1, f)
        + recurse(m, b, r, er, tol_density, depth - 1, f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_weights_sum_to_two_and_integrate_polynomials_exactly() {
        for n in [1, 2, 5, 16, 33, 64, 200] {
            let gl = GaussLegendre::new(n);
            let s: f64 = gl.weights().iter().sum();
            assert!((s - 2.0).abs() < 1e-13, "n = {n}: sum of weights {s}");
            // Degree 2n-1 monomial on [0, 2]: ∫ x^d = 2^(d+1)/(d+1).
            let d = (2 * n - 1).min(60) as i32;
            let exact = 2f64.powi(d + 1) / (d as f64 + 1.0);
            let got = gl.integrate(0.0, 2.0, |x| x.powi(d));
            assert!(
                ((got - exact) / exact).abs() < 1e-12,
                "n = {n}: {got} vs {exact}"
            );
        }
    }

    #[test]
    fn panel_edges_sorts_clips_and_splits() {
        let mut b = vec![0.9, -1.0, 0.3, 0.3, 5.0];
        panel_edges(&mut b, 0.0, 2.0, 0.5);
        let want = [0.0, 0.3, 0.6, 0.9, 1.9 / 1.5, 2.45 / 1.5, 2.0];
        assert_eq!(b.len(), want.len(), "{b:?}");
        for (x, y) in b.iter().zip(want) {
            assert!((x - y).abs() < 1e-12, "{b:?}");
        }
    }

    #[test]
    fn gauss_legendre_nodes_are_sorted_and_symmetric() {
        let gl = GaussLegendre::new(17);
        for w in gl.nodes().windows(2) {
            assert!(w[0] < w[1]);
        }
        for i in 0..17 {
            assert!((gl.nodes()[i] + gl.nodes()[16 - i]).abs() < 1e-15);
        }
    }

    #[test]
    fn adaptive_handles_a_narrow_peak_split_at_its_centre_and_a_kink() {
        // A Gaussian of width 1e-3 centred off the midpoint: found once the peak is a break
        // (a 15-point first look cannot see it otherwise — hence the model splits at its peaks).
        let w = 1e-3;
        let g = |x: f64| (-((x - 0.123) / w).powi(2)).exp();
        let i = adaptive(-1.0, 0.123, 1e-10, 0.0, 40, g) + adaptive(0.123, 1.0, 1e-10, 0.0, 40, g);
        let exact = w * std::f64::consts::PI.sqrt();
        assert!(((i - exact) / exact).abs() < 1e-8, "{i} vs {exact}");
        let k = adaptive(-1.0, 2.0, 1e-12, 0.0, 40, |x: f64| x.abs());
        assert!((k - 2.5).abs() < 1e-10, "{k}");
    }
}
