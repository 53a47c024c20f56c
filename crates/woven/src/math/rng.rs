//! A tiny deterministic generator for reproducible test cases, accuracy reports and benchmarks.
//!
//! The model itself never draws random numbers (sampling takes explicit uniforms); this is the
//! one generator the crate's reports, tests and benchmarks share, so that every run draws the
//! same cases.

use super::Vec3;

/// SplitMix64 (Steele, Lea & Flood 2014), seeded by its state.
///
/// ```
/// use woven::math::rng::SplitMix;
/// let (mut a, mut b) = (SplitMix(7), SplitMix(7));
/// assert_eq!(a.next_u64(), b.next_u64());
/// let u = a.uniform();
/// assert!((0.0..1.0).contains(&u));
/// ```
#[derive(Clone, Debug)]
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` (53 random bits).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }

    /// `10^x`, `x` uniform in `[lo, hi)`.
    pub fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        10f64.powf(self.range(lo, hi))
    }

    /// A direction uniform in solid angle with polar angle `θ ≤ theta_max` (radians).
    pub fn direction(&mut self, theta_max: f64) -> Vec3 {
        let cos_min = theta_max.cos();
        let z = cos_min + (1.0 - cos_min) * self.uniform();
        let phi = 2.0 * std::f64::consts::PI * self.uniform();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}
