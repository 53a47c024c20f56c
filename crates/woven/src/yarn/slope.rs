//! The distribution of lateral slopes `P(θ_a)` (paper Eq. (19); docs/spec.md §2.4).

use crate::math::quadrature::adaptive;
use std::f64::consts::FRAC_PI_2;

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
        let shape = |t: f64| (-(t - mu) * (t - mu) / (2.0 * sigma * sigma)).exp() * t.cos();
        // Split at μ so a narrow peak is seen.
        let m = mu.clamp(0.0, FRAC_PI_2);
        let z =
            adaptive(0.0, m, 1e-13, 0.0, 40, shape) + adaptive(m, FRAC_PI_2, 1e-13, 0.0, 40, shape);
        SlopeDistribution {
            mu,
            sigma,
            c: 1.0 / z,
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
    #[inline]
    pub fn density(&self, theta_a: f64) -> f64 {
        if !(0.0..=FRAC_PI_2).contains(&theta_a) {
            return 0.0;
        }
        let d = theta_a - self.mu;
        self.c * (-d * d / (2.0 * self.sigma * self.sigma)).exp() * theta_a.cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn density_integrates_to_one() {
        for (mu, sigma) in [(0.0, 1.2), (0.4, 0.05), (1.5, 0.3), (0.7, 5.0)] {
            let d = SlopeDistribution::new(mu, sigma);
            let i = adaptive(0.0, mu, 1e-12, 0.0, 40, |t| d.density(t))
                + adaptive(mu, FRAC_PI_2, 1e-12, 0.0, 40, |t| d.density(t));
            assert!((i - 1.0).abs() < 1e-10, "μ {mu} σ {sigma}: {i}");
        }
    }
}
