//! How a yarn's fibers are oriented about its axis, and the average of the single-orientation
//! BRDF over them (paper Eqs. (21)–(22); docs/spec.md §2.6). One home for the twist density and for
//! the orientation weights that the exact model, the albedo and the table build all use.
//!
//! A yarn whose axis has azimuth `φ_y` holds fibers of azimuth `φ_a`:
//!
//! - **aligned** (`twist_std = 0`, not isotropic): `φ_a = φ_y`;
//! - **twisted** (Eq. (21)): `φ_a − φ_y = δ` with the density `p(δ) ∝ exp(−δ²/2σ_t²)` on one
//!   period `δ ∈ [−π/2, π/2)` (a fiber's BRDF is π-periodic in `φ_a`), normalized there;
//! - **isotropic** (Eq. (22)): `φ_a` uniform over a period, density `1/π`.
//!
//! A weave mixes yarns of several axes with weights (Eq. (23): `[(0, γ), (π/2, 1 − γ)]`, see
//! [`crate::cloth::weave_axes`]); all of them average the same π-periodic function, so the mix is
//! one weighted average over fiber azimuths.

use super::window;
use super::YarnParams;
use crate::math::lanes::Lanes;
use crate::math::quadrature::{panel_edges, GaussLegendre};
use crate::math::special::exp_neg;
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI, SQRT_2};

/// Spreads at or above this (radians) are wide: the twist window needs no panels of its own.
const WIDE_TWIST: f64 = 0.3;

/// The twist density of Eq. (21): `p(δ) = c exp(−δ²/2σ_t²)` on `δ ∈ [−π/2, π/2)`, with `c`
/// normalizing it to 1 over that period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwistDensity {
    sigma: f64,
    /// `c = 1 / (σ √(2π) erf(π / (2√2 σ)))`, in closed form.
    norm: f64,
    /// `erf(π / (2√2 σ))`, the mass of the unnormalized Gaussian within one period.
    erf_half_period: f64,
}

impl TwistDensity {
    /// The density of spread `sigma > 0` (radians).
    pub fn new(sigma: f64) -> Self {
        debug_assert!(sigma > 0.0, "twist spread {sigma} must be positive");
        let erf_half_period = libm::erf(FRAC_PI_2 / (SQRT_2 * sigma));
        TwistDensity {
            sigma,
            norm: 1.0 / (sigma * (2.0 * PI).sqrt() * erf_half_period),
            erf_half_period,
        }
    }

    /// The spread `σ_t`, radians.
    pub fn std(&self) -> f64 {
        self.sigma
    }

    /// The offset `δ = φ_a − φ_y` of a fiber from its yarn axis, reduced to one period
    /// `[−π/2, π/2)`.
    #[inline]
    pub fn offset(phi_a: f64, phi_y: f64) -> f64 {
        (phi_a - phi_y + FRAC_PI_2).rem_euclid(PI) - FRAC_PI_2
    }

    /// `p(φ_a − φ_y)`, per radian: the density of fibers at azimuth `phi_a` in a yarn of axis
    /// `phi_y`.
    ///
    /// Implements Eq. (21) of the paper; docs/spec.md §2.6.
    #[inline]
    pub fn density(&self, phi_a: f64, phi_y: f64) -> f64 {
        let d = Self::offset(phi_a, phi_y);
        self.norm * exp_neg(d * d / (2.0 * self.sigma * self.sigma))
    }

    /// `∫_{−π/2}^{δ} p`, for `δ ∈ [−π/2, π/2]`: the distribution function on one period.
    fn cdf(&self, delta: f64) -> f64 {
        let e = libm::erf(delta / (SQRT_2 * self.sigma));
        (0.5 * (e + self.erf_half_period) / self.erf_half_period).clamp(0.0, 1.0)
    }

    /// The mass of the density between the fiber azimuths `a ≤ b` (`b − a ≤ π`), wrapping around
    /// the period.
    fn mass(&self, a: f64, b: f64, phi_y: f64) -> f64 {
        // The distribution function continued over the real line: +1 per period.
        let f = |phi: f64| {
            let k = ((phi - phi_y + FRAC_PI_2) / PI).floor();
            k + self.cdf(Self::offset(phi, phi_y))
        };
        f(b) - f(a)
    }
}

/// How a yarn's fibers are oriented about its axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Orientation {
    /// Every fiber along the yarn axis (`twist_std = 0`).
    Aligned,
    /// Fibers twisted about the axis with the density of Eq. (21).
    Twisted(TwistDensity),
    /// Fibers uniformly in all azimuths (Eq. (22)).
    Isotropic,
}

impl Orientation {
    /// The orientation `params` describe (validated parameters).
    pub fn of(params: &YarnParams) -> Self {
        if params.isotropic {
            Orientation::Isotropic
        } else if params.twist_std > 0.0 {
            Orientation::Twisted(TwistDensity::new(params.twist_std))
        } else {
            Orientation::Aligned
        }
    }

    /// The weights of the fiber azimuths `φ_j = (j + ½)π/n`, `j < n`, for yarns of axes and
    /// weights `axes` (`(φ_y, w)`, e.g. [`crate::cloth::weave_axes`]): `Σ_j W_j F(φ_j)`
    /// approximates `Σ_k w_k ∫ p(φ_a − φ_k) F(φ_a) dφ_a` for a π-periodic `F`. Each yarn's weights
    /// sum to its `w`.
    ///
    /// Node `j` stands for the cell `[jπ/n, (j + 1)π/n]` and gets the yarn's mass in it (in closed
    /// form), so no spread is too narrow for the grid: as `σ_t → 0` the mass gathers in the cell
    /// holding the axis (split evenly when the axis lies on a cell edge, as `φ_y = 0` and `π/2` do
    /// for even `n`), which is what an aligned yarn gets. Isotropic yarns: `w/n` each.
    ///
    /// Implements Eqs. (21)–(23) of the paper on a grid of fiber azimuths; docs/spec.md §2.6–§2.7.
    pub fn midpoint_weights(&self, n: usize, axes: &[(f64, f64)]) -> Vec<f64> {
        let mut out = vec![0.0; n];
        let h = PI / n as f64;
        for &(phi_y, w) in axes {
            match self {
                Orientation::Isotropic => out.iter_mut().for_each(|x| *x += w / n as f64),
                Orientation::Twisted(t) => {
                    for (j, x) in out.iter_mut().enumerate() {
                        *x += w * t.mass(j as f64 * h, (j + 1) as f64 * h, phi_y);
                    }
                }
                Orientation::Aligned => {
                    // The cell of the axis, reduced to [0, π); half to each side on an edge.
                    let c = phi_y.rem_euclid(PI) / h;
                    // Within rounding of an edge (φ_y = π/2 lands a few ulp off one).
                    if (c - c.round()).abs() < 1e-9 {
                        let j = c.round() as usize % n;
                        out[j] += 0.5 * w;
                        out[(j + n - 1) % n] += 0.5 * w;
                    } else {
                        out[(c.floor() as usize).min(n - 1)] += w;
                    }
                }
            }
        }
        out
    }

    /// `Σ_k w_k ∫ p_k(φ_a) f(φ_a) dφ_a` over one period for yarns of axes and weights `axes`, `p_k`
    /// this orientation's density about axis `φ_k` (a point mass for aligned fibers), `f`
    /// π-periodic (a number, or several parts averaged together).
    ///
    /// `breaks` are azimuths where `f` kinks or peaks; `rule` is applied on each panel between
    /// them. Twists narrower than [`window::NARROW_STD`] are integrated per yarn over their `±8σ_t`
    /// window in the standardized offset (a fixed number of panels for every `σ_t > 0`, tending
    /// to the aligned yarn's `f(φ_k)` as `σ_t → 0`); wider ones share one pass over `[0, π)`.
    ///
    /// Implements Eqs. (21)–(22) of the paper and the weave mix of Eq. (23); docs/spec.md §2.6.
    pub fn average<T: Lanes>(
        &self,
        axes: &[(f64, f64)],
        breaks: &[f64],
        rule: &GaussLegendre,
        f: impl Fn(f64) -> T,
    ) -> T {
        match self {
            Orientation::Aligned => axes
                .iter()
                .filter(|&&(_, w)| w != 0.0)
                .fold(T::ZERO, |acc, &(phi, w)| acc.add(f(phi).scale(w))),
            Orientation::Isotropic => {
                let total_weight: f64 = axes.iter().map(|&(_, w)| w).sum();
                period_integral(breaks, rule, |_| 1.0, &f).scale(total_weight * FRAC_1_PI)
            }
            Orientation::Twisted(t) if t.sigma < window::NARROW_STD => {
                axes.iter()
                    .filter(|&&(_, w)| w != 0.0)
                    .fold(T::ZERO, |acc, &(phi, w)| {
                        let sigma = t.sigma;
                        let extra = breaks.iter().map(|&b| TwistDensity::offset(b, phi) / sigma);
                        let edges = window::edges(
                            -window::HALF_WIDTH,
                            window::HALF_WIDTH,
                            rule.nodes().len(),
                            extra,
                        );
                        let (mut num, mut den) = (T::ZERO, 0.0);
                        for e in edges.windows(2) {
                            num = num.add(rule.integrate(e[0], e[1], |x| {
                                f(phi + sigma * x).scale(window::shape(x))
                            }));
                            den += rule.integrate(e[0], e[1], window::shape);
                        }
                        acc.add(num.scale(w / den))
                    })
            }
            Orientation::Twisted(t) => {
                let st = t.sigma;
                let mut all: Vec<f64> = breaks.to_vec();
                if st < WIDE_TWIST {
                    for &(c, _) in axes {
                        for k in [-4.0, -2.0, -1.0, 0.0, 1.0, 2.0, 4.0] {
                            all.push(c + k * st);
                        }
                    }
                }
                let weight = |phi_a: f64| -> f64 {
                    axes.iter()
                        .map(|&(phi, w)| {
                            let d = TwistDensity::offset(phi_a, phi);
                            w * t.norm * exp_neg(d * d / (2.0 * st * st))
                        })
                        .sum()
                };
                period_integral(&all, rule, weight, &f)
            }
        }
    }
}

/// `∫_0^π w(φ) f(φ) dφ` on panels split at `breaks` (reduced into the period) and at most π/4
/// wide; `f` is not called where `w` is 0.
fn period_integral<T: Lanes>(
    breaks: &[f64],
    rule: &GaussLegendre,
    weight: impl Fn(f64) -> f64,
    f: &impl Fn(f64) -> T,
) -> T {
    let mut edges: Vec<f64> = breaks
        .iter()
        .filter(|b| b.is_finite())
        .map(|b| b.rem_euclid(PI))
        .collect();
    panel_edges(&mut edges, 0.0, PI, 0.25 * PI);
    let mut total = T::ZERO;
    for e in edges.windows(2) {
        total = total.add(rule.integrate(e[0], e[1], |phi_a| {
            let wt = weight(phi_a);
            if wt == 0.0 {
                return T::ZERO;
            }
            f(phi_a).scale(wt)
        }));
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::adaptive;

    /// Eq. (21): the closed-form normalization makes the twist density integrate to 1 over one
    /// period, checked by adaptive quadrature split at the peak, for wide and narrow spreads.
    #[test]
    fn twist_density_integrates_to_one_over_a_period() {
        for sigma in [2.0, 0.35, 0.05, 1e-3] {
            let t = TwistDensity::new(sigma);
            let phi_y = 0.7;
            let p = |d: f64| t.density(phi_y + d, phi_y);
            // Split at ±σ, ±8σ so that the adaptive rule sees the peak.
            let mut e = vec![-FRAC_PI_2, 0.0, FRAC_PI_2];
            for k in [-8.0, -1.0, 1.0, 8.0] {
                if (k * sigma).abs() < FRAC_PI_2 {
                    e.push(k * sigma);
                }
            }
            e.sort_by(f64::total_cmp);
            let i: f64 = e
                .windows(2)
                .map(|w| adaptive(w[0], w[1], 1e-13, 1e-15, 30, p))
                .sum();
            assert!((i - 1.0).abs() < 1e-10, "σ_t {sigma}: ∫p = {i}");
            // One period's mass, in closed form, is 1 wherever the period starts.
            let m = t.mass(0.3, 0.3 + PI, phi_y);
            assert!((m - 1.0).abs() < 1e-14, "σ_t {sigma}: mass {m}");
        }
    }

    /// Eqs. (21)–(23) on a grid: each yarn's weights sum to its weight, they are the density's
    /// cell masses (≈ density × cell width when the twist is resolved), and a vanishing twist
    /// puts them where an aligned yarn's are.
    #[test]
    fn midpoint_weights_are_cell_masses_that_tend_to_the_aligned_yarn() {
        let axes = [(0.0, 0.3), (FRAC_PI_2, 0.7)];
        let n = 180;
        let h = PI / n as f64;
        for o in [
            Orientation::Isotropic,
            Orientation::Aligned,
            Orientation::Twisted(TwistDensity::new(0.35)),
            Orientation::Twisted(TwistDensity::new(1e-9)),
        ] {
            let w = o.midpoint_weights(n, &axes);
            let sum: f64 = w.iter().sum();
            assert!((sum - 1.0).abs() < 1e-13, "{o:?}: Σ = {sum}");
            assert!(w.iter().all(|&x| x >= 0.0 && x.is_finite()), "{o:?}");
        }
        let t = TwistDensity::new(0.35);
        let w = Orientation::Twisted(t).midpoint_weights(n, &axes);
        for (j, &x) in w.iter().enumerate().step_by(17) {
            let phi = (j as f64 + 0.5) * h;
            let want = h * (0.3 * t.density(phi, 0.0) + 0.7 * t.density(phi, FRAC_PI_2));
            // Cell mass − midpoint rule = h³p''/24 + …, and p''/p = (δ² − σ²)/σ⁴.
            let curvature = [0.0, FRAC_PI_2]
                .map(|c| {
                    let d = TwistDensity::offset(phi, c);
                    (d * d - 0.35 * 0.35).abs() / 0.35f64.powi(4)
                })
                .into_iter()
                .fold(0.0, f64::max);
            let tol = 2.0 * h * h / 24.0 * curvature;
            assert!(
                (x - want).abs() <= tol * want,
                "node {j}: {x} vs {want} (tol {tol:.1e})"
            );
        }
        // A vanishing twist, like an aligned yarn, puts each yarn's weight on the nodes within
        // one cell of its axis.
        for o in [
            Orientation::Aligned,
            Orientation::Twisted(TwistDensity::new(1e-9)),
        ] {
            let w = o.midpoint_weights(n, &axes);
            for &(phi_y, wy) in &axes {
                let near: f64 = w
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| {
                        let phi = (j as f64 + 0.5) * h;
                        TwistDensity::offset(phi, phi_y).abs() < h
                    })
                    .map(|(_, x)| x)
                    .sum();
                assert!(
                    (near - wy).abs() < 1e-12,
                    "{o:?}, axis {phi_y}: {near} vs {wy}"
                );
            }
        }
    }

    /// The continuous average: a constant averages to the sum of the weights in every case, a
    /// smooth periodic function to its closed-form average, and narrow twists to `f(φ_y)`.
    #[test]
    fn average_of_known_functions() {
        let rule = GaussLegendre::new(6);
        let axes = [(0.0, 0.25), (FRAC_PI_2, 0.75)];
        // f(φ) = 1 + cos 2φ: aligned ⇒ Σ w (1 + cos 2φ_k); isotropic ⇒ Σ w; a twist of spread
        // σ multiplies cos 2φ by E[cos 2δ] = e^{−2σ²} (up to its truncation at ±π/2).
        let f = |phi: f64| 1.0 + (2.0 * phi).cos();
        let exact_aligned = 0.25 * 2.0 + 0.75 * 0.0;
        let cases = [
            (Orientation::Aligned, exact_aligned),
            (Orientation::Isotropic, 1.0),
            (
                Orientation::Twisted(TwistDensity::new(0.05)),
                1.0 + (0.25 - 0.75) * (-2.0 * 0.05f64 * 0.05).exp(),
            ),
            (
                Orientation::Twisted(TwistDensity::new(1e-200)),
                exact_aligned,
            ),
        ];
        for (o, want) in cases {
            let got = o.average(&axes, &[], &rule, f);
            assert!((got - want).abs() < 1e-9, "{o:?}: {got} vs {want}");
            let one = o.average(&axes, &[], &rule, |_| 1.0);
            assert!((one - 1.0).abs() < 1e-12, "{o:?}: average of 1 = {one}");
        }
    }
}
