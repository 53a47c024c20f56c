//! Accuracy of a table against the exact model (`woven tabulate --report`).

use super::Table;
use crate::math::Vec3;
use crate::Model;

/// Agreement of a table with the exact model over random direction pairs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccuracyReport {
    /// Number of direction pairs.
    pub samples: usize,
    /// `√(Σ c (f_table − f)² / Σ c f²)` with `c = cos θ_i cos θ_r`: the cosine-weighted relative RMS error.
    pub weighted_rel_rms: f64,
    /// 99th percentile of `|f_table − f| / f` (pairs with `f` below 1e-6 sr⁻¹ compare absolutely).
    pub p99_rel: f64,
    /// Largest relative error seen.
    pub max_rel: f64,
}

/// The generator of the reports' random directions (re-exported from its home).
pub use crate::math::rng::SplitMix;

impl Table {
    /// Compares the table with `model` at `n` random pairs with `θ_i, θ_r ≤ theta_max` (radians),
    /// drawn uniformly in solid angle from `seed`. `eval` is the exact model's cost per pair.
    pub fn accuracy(&self, model: &Model, n: usize, theta_max: f64, seed: u64) -> AccuracyReport {
        let mut rng = SplitMix(seed);
        let pairs: Vec<(Vec3, Vec3)> = (0..n)
            .map(|_| (rng.direction(theta_max), rng.direction(theta_max)))
            .collect();
        let exact: Vec<f64> = pairs.iter().map(|&(s, v)| model.eval(s, v)).collect();
        self.accuracy_against(&pairs, &exact)
    }

    /// As [`accuracy`](Self::accuracy), with the exact values supplied (e.g. computed in parallel).
    pub fn accuracy_against(&self, pairs: &[(Vec3, Vec3)], exact: &[f64]) -> AccuracyReport {
        let (mut num, mut den) = (0.0, 0.0);
        let mut rel = Vec::with_capacity(pairs.len());
        for (&(s, v), &e) in pairs.iter().zip(exact) {
            let t = self.eval(s, v);
            let c = s.z * v.z;
            num += c * (t - e) * (t - e);
            den += c * e * e;
            rel.push(if e > 1e-6 {
                (t - e).abs() / e
            } else {
                (t - e).abs() / 1e-6
            });
        }
        rel.sort_by(f64::total_cmp);
        let p99 = rel
            .get(((rel.len() as f64) * 0.99) as usize)
            .copied()
            .unwrap_or(0.0);
        AccuracyReport {
            samples: pairs.len(),
            weighted_rel_rms: if den > 0.0 { (num / den).sqrt() } else { 0.0 },
            p99_rel: p99,
            max_rel: rel.last().copied().unwrap_or(0.0),
        }
    }
}
