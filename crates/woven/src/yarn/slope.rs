//! The distribution of lateral slopes `P(θ_a)` (paper Eq. (19); docs/spec.md §2.4).

use super::window;
use crate::math::quadrature::{panel_edges, GaussLegendre};
use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

fn rule20() -> &'static GaussLegendre {
    static R: OnceLock<GaussLegendre> = OnceLock::new();
    R.get_or_init(|| GaussLegendre::new(20))
}

/// The standardized window `[lo, hi]` of `x = (θ − μ)/σ` for slopes in `[0, top]`, within ±8
/// (`σ > 0`; empty, `hi ≤ lo`, only when `μ` lies above `top` by more than `8σ`).
pub(crate) fn x_window(mu: f64, sigma: f64, top: f64) -> (f64, f64) {
    let lo = (-mu / sigma).max(-window::HALF_WIDTH);
    let hi = ((top - mu) / sigma).min(window::HALF_WIDTH);
    (lo, hi)
}

/// `P(θ_a) = c · exp(−(θ_a − μ)²/(2σ²)) · cos θ_a` on `[0, π/2]`, normalized to 1; `σ = 0` is the
/// single slope `θ_a = μ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlopeDistribution {
    mu: f64,
    sigma: f64,
    /// The normalization `c` (0 when `σ = 0`).
    c: f64,
}

impl SlopeDistribution {
    /// The distribution of mean `mu ∈ [0, π/2]` and spread `sigma ≥ 0` (radians; validated by
    /// the caller).
    pub fn new(mu: f64, sigma: f64) -> Self {
        if sigma == 0.0 {
            return SlopeDistribution { mu, sigma, c: 0.0 };
        }
        // c⁻¹ = ∫_0^{π/2} exp(−(t − μ)²/2σ²) cos t dt = σ ∫ exp(−x²/2) cos(μ + σx) dx over the
        // window of x = (t − μ)/σ (Gaussian mass beyond ±8σ: 1.2e-15): a fixed number of panels
        // for every σ, each integrated by 20-point Gauss–Legendre to rounding.
        let (lo, hi) = x_window(mu, sigma, FRAC_PI_2);
        let mut edges = window::edges(lo, hi, 20, []);
        panel_edges(&mut edges, lo, hi, 1.0);
        let rule = rule20();
        let z: f64 = edges
            .windows(2)
            .map(|e| rule.integrate(e[0], e[1], |x| window::shape(x) * (mu + sigma * x).cos()))
            .sum();
        SlopeDistribution {
            mu,
            sigma,
            c: 1.0 / (sigma * z),
        }
    }

    /// `Some(μ)` when the distribution is the single slope `μ` (`σ = 0`).
    pub fn single(&self) -> Option<f64> {
        (self.sigma == 0.0).then_some(self.mu)
    }

    /// Mean parameter `μ`.
    pub fn mean(&self) -> f64 {
        self.mu
    }

    /// Spread parameter `σ`.
    pub fn std(&self) -> f64 {
        self.sigma
    }

    /// `P(θ_a)` (0 outside `[0, π/2]`; meaningless when `σ = 0`).
    ///
    /// Implements Eq. (19) of the paper; docs/spec.md §2.4.
    #[inline]
    pub fn density(&self, theta_a: f64) -> f64 {
        if !(0.0..=FRAC_PI_2).contains(&theta_a) {
            return 0.0;
        }
        let x = (theta_a - self.mu) / self.sigma;
        self.c * window::shape(x) * theta_a.cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::adaptive;

    #[test]
    fn density_integrates_to_one() {
        for (mu, sigma) in [(0.0, 1.2), (0.4, 0.05), (1.5, 0.3), (0.7, 5.0)] {
            let d = SlopeDistribution::new(mu, sigma);
            let i = adaptive(0.0, mu, 1e-12, 0.0, 40, |t| d.density(t))
                + adaptive(mu, FRAC_PI_2, 1e-12, 0.0, 40, |t| d.density(t));
            assert!((i - 1.0).abs() < 1e-10, "μ {mu} σ {sigma}: {i}");
        }
    }

    /// Narrow spreads (which once took an adaptive rule minutes, or gave c = ∞): the density
    /// integrates to 1 over its ±8σ window, at the mean, near either end of the range.
    #[test]
    fn narrow_density_integrates_to_one() {
        for (mu, sigma) in [
            (0.4, 1e-3),
            (0.4, 1e-6),
            (0.0, 1e-5),
            (1.5, 1e-4),
            (1.0, 1e-9),
        ] {
            let d = SlopeDistribution::new(mu, sigma);
            assert!(
                d.c.is_finite() && d.c > 0.0,
                "μ {mu} σ {sigma}: c = {}",
                d.c
            );
            let (lo, hi) = (
                (mu - 8.0 * sigma).max(0.0),
                (mu + 8.0 * sigma).min(FRAC_PI_2),
            );
            let i = adaptive(lo, mu, 1e-12, 0.0, 40, |t| d.density(t))
                + adaptive(mu, hi, 1e-12, 0.0, 40, |t| d.density(t));
            assert!((i - 1.0).abs() < 1e-9, "μ {mu} σ {sigma}: {i}");
        }
    }
}
