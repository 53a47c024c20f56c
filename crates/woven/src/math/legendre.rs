//! Piecewise Legendre interpolants: a function sampled at Gauss–Legendre nodes on panels, with
//! exact integrals of the interpolant between any two points.
//!
//! The cross-section integrals of the yarn (docs/spec.md §2.3–§2.4) integrate one function of the
//! facet angle — the fiber BRDF at normal `a(θ)` times the two cosines — over many different
//! intervals (one per slope `θ_a`, cut by masking). Sampling it once on lobe-resolving panels and
//! integrating the interpolant over each interval turns a nested integral into one sampling pass.
//! On a panel with `n` nodes the interpolant is the degree-`n − 1` polynomial through the samples;
//! its integral over the whole panel equals the `n`-point Gauss–Legendre rule.

use super::lanes::Lanes;
use super::quadrature::GaussLegendre;

/// Nodes per panel.
pub const PANEL_NODES: usize = 10;

/// The fixed `PANEL_NODES`-point rule and `P_k(x_i)` for `k < PANEL_NODES`.
struct Basis {
    gl: GaussLegendre,
    /// `(2k+1)/2 · w_i · P_k(x_i)`: row `k` maps samples to the `k`-th Legendre coefficient.
    analysis: [[f64; PANEL_NODES]; PANEL_NODES],
}

fn basis() -> &'static Basis {
    static B: std::sync::OnceLock<Basis> = std::sync::OnceLock::new();
    B.get_or_init(|| {
        let gl = GaussLegendre::new(PANEL_NODES);
        let mut analysis = [[0.0; PANEL_NODES]; PANEL_NODES];
        for (i, (&x, &w)) in gl.nodes().iter().zip(gl.weights()).enumerate() {
            let p = legendre_all(x);
            for k in 0..PANEL_NODES {
                analysis[k][i] = (2 * k + 1) as f64 / 2.0 * w * p[k];
            }
        }
        Basis { gl, analysis }
    })
}

/// The `PANEL_NODES`-point Gauss–Legendre rule the panels use.
pub fn panel_rule() -> &'static GaussLegendre {
    &basis().gl
}

/// `P_0(x) … P_{N}(x)` by the three-term recurrence (one more than the panel degree, for the
/// antiderivative).
#[inline]
fn legendre_all(x: f64) -> [f64; PANEL_NODES + 1] {
    let mut p = [0.0; PANEL_NODES + 1];
    p[0] = 1.0;
    p[1] = x;
    for k in 1..PANEL_NODES {
        // (k + 1) P_{k+1} = (2k + 1) x P_k − k P_{k−1}, with the quotients precomputed.
        p[k + 1] = RECURRENCE_A[k] * x * p[k] - RECURRENCE_B[k] * p[k - 1];
    }
    p
}

/// `(2k + 1)/(k + 1)` and `k/(k + 1)`: the Legendre recurrence without divisions.
const RECURRENCE_A: [f64; PANEL_NODES] = recurrence(1);
const RECURRENCE_B: [f64; PANEL_NODES] = recurrence(0);

/// `1/(2k + 1)`, the factor of `∫ P_k = (P_{k+1} − P_{k−1})/(2k + 1)`.
const INV_2K_PLUS_1: [f64; PANEL_NODES] = {
    let mut r = [0.0; PANEL_NODES];
    let mut k = 0;
    while k < PANEL_NODES {
        r[k] = 1.0 / (2 * k + 1) as f64;
        k += 1;
    }
    r
};

/// `(2k + 1)/(k + 1)` (`a = 1`) or `k/(k + 1)` (`a = 0`) for `k < PANEL_NODES`.
const fn recurrence(a: usize) -> [f64; PANEL_NODES] {
    let mut r = [0.0; PANEL_NODES];
    let mut k = 0;
    while k < PANEL_NODES {
        r[k] = ((1 + a) * k + a) as f64 / (k + 1) as f64;
        k += 1;
    }
    r
}

#[derive(Clone, Copy, Debug)]
struct Panel<T> {
    a: f64,
    b: f64,
    /// Legendre coefficients of the interpolant in the panel's local variable `x ∈ [−1, 1]`.
    coeffs: [T; PANEL_NODES],
    /// `∫` of the interpolant from the first panel's start to this panel's start.
    cumulative: T,
}

/// A function represented on `[edges[0], edges[last]]` by one polynomial per panel; its values
/// are numbers (`T = f64`) or several functions sampled together (`T = [f64; N]`).
#[derive(Clone, Debug)]
pub struct PiecewiseLegendre<T = f64> {
    panels: Vec<Panel<T>>,
}

impl<T> Default for PiecewiseLegendre<T> {
    fn default() -> Self {
        PiecewiseLegendre { panels: Vec::new() }
    }
}

impl<T: Lanes> PiecewiseLegendre<T> {
    /// Samples `f` at `PANEL_NODES` Gauss–Legendre nodes on each panel between consecutive
    /// `edges` (ascending; empty panels are skipped).
    pub fn sample(edges: &[f64], mut f: impl FnMut(f64) -> T) -> Self {
        let mut out = PiecewiseLegendre::default();
        out.resample(edges, &mut f);
        out
    }

    /// As [`sample`](Self::sample), reusing this value's storage.
    pub fn resample(&mut self, edges: &[f64], mut f: impl FnMut(f64) -> T) {
        let b = basis();
        self.panels.clear();
        let mut cumulative = T::ZERO;
        for e in edges.windows(2) {
            let (a, bb) = (e[0], e[1]);
            if bb <= a {
                continue;
            }
            let h = 0.5 * (bb - a);
            let c = 0.5 * (bb + a);
            let mut y = [T::ZERO; PANEL_NODES];
            for (yi, &x) in y.iter_mut().zip(b.gl.nodes()) {
                *yi = f(c + h * x);
            }
            let mut coeffs = [T::ZERO; PANEL_NODES];
            for k in 0..PANEL_NODES {
                coeffs[k] = b.analysis[k]
                    .iter()
                    .zip(&y)
                    .fold(T::ZERO, |acc, (m, v)| acc.add(v.scale(*m)));
            }
            self.panels.push(Panel {
                a,
                b: bb,
                coeffs,
                cumulative,
            });
            // ∫_{−1}^{1} of the series is 2 c_0.
            cumulative = cumulative.add(coeffs[0].scale(2.0 * h));
        }
    }

    /// `∫` of the interpolant over the whole domain.
    pub fn total(&self) -> T {
        self.panels
            .last()
            .map_or(T::ZERO, |p| p.cumulative.add(p.coeffs[0].scale(p.b - p.a)))
    }

    /// `∫` of the interpolant from the domain's start to `x` (clamped to the domain).
    pub fn cumulative(&self, x: f64) -> T {
        let Some(first) = self.panels.first() else {
            return T::ZERO;
        };
        if x <= first.a {
            return T::ZERO;
        }
        // Panels are few (tens): a binary search on their starts.
        let k = self.panels.partition_point(|p| p.a <= x) - 1;
        let p = &self.panels[k];
        if x >= p.b {
            return p.cumulative.add(p.coeffs[0].scale(p.b - p.a));
        }
        let h = 0.5 * (p.b - p.a);
        let t = (x - 0.5 * (p.a + p.b)) / h;
        let pl = legendre_all(t);
        // ∫_{−1}^{t} P_0 = t + 1; ∫_{−1}^{t} P_k = (P_{k+1}(t) − P_{k−1}(t)) / (2k + 1), k ≥ 1.
        let mut s = p.coeffs[0].scale(t + 1.0);
        for k in 1..PANEL_NODES {
            s = s.add(p.coeffs[k].scale((pl[k + 1] - pl[k - 1]) * INV_2K_PLUS_1[k]));
        }
        p.cumulative.add(s.scale(h))
    }

    /// The interpolant's value at `x` (0 outside the domain).
    pub fn value(&self, x: f64) -> T {
        let Some(first) = self.panels.first() else {
            return T::ZERO;
        };
        let last = self.panels[self.panels.len() - 1].b;
        if x < first.a || x > last {
            return T::ZERO;
        }
        let k = (self.panels.partition_point(|p| p.a <= x).max(1)) - 1;
        let p = &self.panels[k];
        let t = ((x - 0.5 * (p.a + p.b)) / (0.5 * (p.b - p.a))).clamp(-1.0, 1.0);
        let pl = legendre_all(t);
        p.coeffs
            .iter()
            .zip(&pl)
            .fold(T::ZERO, |acc, (c, l)| acc.add(c.scale(*l)))
    }

    /// `∫_lo^hi` of the interpolant (0 if `hi ≤ lo`).
    #[inline]
    pub fn integral(&self, lo: f64, hi: f64) -> T {
        if hi <= lo {
            return T::ZERO;
        }
        self.cumulative(hi).add(self.cumulative(lo).scale(-1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly_between_any_points() {
        let f = |x: f64| 3.0 * x.powi(7) - x.powi(4) + 2.0 * x - 1.0;
        let big_f = |x: f64| 3.0 / 8.0 * x.powi(8) - x.powi(5) / 5.0 + x * x - x;
        let pl = PiecewiseLegendre::sample(&[-1.0, -0.3, 0.4, 1.2], f);
        for (lo, hi) in [(-1.0, 1.2), (-0.7, 0.1), (0.5, 0.9), (-0.2, -0.1)] {
            let want = big_f(hi) - big_f(lo);
            let got = pl.integral(lo, hi);
            assert!((got - want).abs() < 1e-13, "[{lo}, {hi}]: {got} vs {want}");
        }
        assert!((pl.total() - (big_f(1.2) - big_f(-1.0))).abs() < 1e-13);
        for x in [-1.0, -0.3, 0.0, 0.77, 1.2] {
            assert!((pl.value(x) - f(x)).abs() < 1e-12, "value at {x}");
        }
        assert_eq!(pl.value(1.3), 0.0);
    }

    #[test]
    fn resolves_a_gaussian_on_fine_panels() {
        let w = 0.01;
        let f = |x: f64| (-(x / w).powi(2)).exp();
        let edges: Vec<f64> = (-10..=10).map(|k| k as f64 * w).collect();
        let pl = PiecewiseLegendre::sample(&edges, f);
        // ∫_0^x of the Gaussian = w √π/2 erf(x/w).
        for x in [0.003, 0.0123, 0.05] {
            let want = w * std::f64::consts::PI.sqrt() / 2.0 * libm::erf(x / w);
            let got = pl.integral(0.0, x);
            assert!((got - want).abs() < 1e-11, "x {x}: {got} vs {want}");
        }
    }
}
