//! Accuracy of a table against the exact model (`woven tabulate --report`), over the whole
//! hemisphere in bands of the larger polar angle.

use super::Table;
use crate::math::Vec3;
use crate::Model;
use rayon::prelude::*;

/// The generator of the reports' random directions (re-exported from its home).
pub use crate::math::rng::SplitMix;

/// The bands of `θ = max(θ_i, θ_r)` the report covers, degrees: the bulk, the grazing band, and
/// the last degree before the horizon.
pub const BANDS_DEG: [(f64, f64); 3] = [(0.0, 80.0), (80.0, 89.0), (89.0, 90.0)];

/// Agreement in one band of `θ = max(θ_i, θ_r)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandAccuracy {
    /// The band's lower end, degrees.
    pub lo_deg: f64,
    /// The band's upper end, degrees.
    pub hi_deg: f64,
    /// Number of direction pairs.
    pub samples: usize,
    /// `√(Σ c (f_table − f)² / Σ c f²)` with `c = cos θ_i cos θ_r`: the cosine-weighted relative
    /// RMS error.
    pub weighted_rel_rms: f64,
    /// 99th percentile of `|f_table − f| / f` (pairs with `f` below 1e-6 sr⁻¹ compare absolutely).
    pub p99_rel: f64,
    /// Largest relative error seen.
    pub max_rel: f64,
    /// Largest `|f_table − f| cos θ_i cos θ_r` relative to the material's peak of
    /// `f cos θ_i cos θ_r` ([`AccuracyReport::peak`]): what a renderer's estimate is off by.
    pub max_peak_rel: f64,
}

/// Agreement of a table with the exact model over random direction pairs, band by band.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyReport {
    /// One entry per band of [`BANDS_DEG`].
    pub bands: Vec<BandAccuracy>,
    /// The material's peak of `f cos θ_i cos θ_r` (sr⁻¹): the largest over the table's nodes and
    /// the report's exact values.
    pub peak: f64,
}

impl AccuracyReport {
    /// The band `[lo_deg, hi_deg]`, if the report has it.
    pub fn band(&self, lo_deg: f64) -> Option<&BandAccuracy> {
        self.bands.iter().find(|b| b.lo_deg == lo_deg)
    }

    /// The largest [`BandAccuracy::max_peak_rel`] over all bands.
    pub fn max_peak_rel(&self) -> f64 {
        self.bands
            .iter()
            .map(|b| b.max_peak_rel)
            .fold(0.0, f64::max)
    }

    /// Direction pairs in total.
    pub fn samples(&self) -> usize {
        self.bands.iter().map(|b| b.samples).sum()
    }
}

/// `samples_per_band` direction pairs in each band of [`BANDS_DEG`], uniform in solid angle
/// within it (each direction uniform over the hemisphere, kept when `max(θ_i, θ_r)` falls in the
/// band), reproducible from `seed`: `(band, s, v)`.
pub fn band_pairs(samples_per_band: usize, seed: u64) -> Vec<(usize, Vec3, Vec3)> {
    let mut rng = SplitMix(seed);
    let mut out = Vec::with_capacity(BANDS_DEG.len() * samples_per_band);
    for (band, &(lo, hi)) in BANDS_DEG.iter().enumerate() {
        let (z_hi, z_lo) = (lo.to_radians().cos(), hi.to_radians().cos());
        let mut kept = 0;
        while kept < samples_per_band {
            let s = rng.direction(std::f64::consts::FRAC_PI_2);
            let v = rng.direction(std::f64::consts::FRAC_PI_2);
            // max θ ∈ [lo, hi) ⇔ min cos θ ∈ (cos hi, cos lo].
            let z = s.z.min(v.z);
            if z > z_lo && z <= z_hi {
                out.push((band, s, v));
                kept += 1;
            }
        }
    }
    out
}

impl Table {
    /// Compares the table with `model` at `samples_per_band` random pairs in each band of
    /// [`BANDS_DEG`] ([`band_pairs`] from `seed`), the exact values computed on all cores;
    /// `progress(done, total)` is called as they complete.
    pub fn accuracy(
        &self,
        model: &Model,
        samples_per_band: usize,
        seed: u64,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> AccuracyReport {
        let pairs = band_pairs(samples_per_band, seed);
        let done = std::sync::atomic::AtomicUsize::new(0);
        let exact: Vec<f64> = pairs
            .par_iter()
            // Up to a few milliseconds a pair for cloth: small tasks balance the cores.
            .with_max_len(8)
            .map(|&(_, s, v)| {
                let f = model.eval(s, v);
                let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress(k, pairs.len());
                f
            })
            .collect();
        self.accuracy_against(&pairs, &exact)
    }

    /// As [`accuracy`](Self::accuracy), with the pairs and their exact values supplied.
    pub fn accuracy_against(&self, pairs: &[(usize, Vec3, Vec3)], exact: &[f64]) -> AccuracyReport {
        let peak = pairs
            .iter()
            .zip(exact)
            .map(|(&(_, s, v), &e)| e * s.z * v.z)
            .fold(self.peak_cosine_weighted(), f64::max);
        let bands = BANDS_DEG
            .iter()
            .enumerate()
            .map(|(band, &(lo_deg, hi_deg))| {
                let (mut num, mut den, mut worst) = (0.0, 0.0, 0.0f64);
                let mut rel = Vec::new();
                for (&(_, s, v), &e) in pairs.iter().zip(exact).filter(|(p, _)| p.0 == band) {
                    let t = self.eval(s, v);
                    let c = s.z * v.z;
                    num += c * (t - e) * (t - e);
                    den += c * e * e;
                    rel.push((t - e).abs() / e.max(1e-6));
                    worst = worst.max((t - e).abs() * c);
                }
                rel.sort_by(f64::total_cmp);
                let p99 = rel
                    .get(((rel.len() as f64) * 0.99) as usize)
                    .copied()
                    .unwrap_or(0.0);
                BandAccuracy {
                    lo_deg,
                    hi_deg,
                    samples: rel.len(),
                    weighted_rel_rms: if den > 0.0 { (num / den).sqrt() } else { 0.0 },
                    p99_rel: p99,
                    max_rel: rel.last().copied().unwrap_or(0.0),
                    max_peak_rel: if peak > 0.0 { worst / peak } else { 0.0 },
                }
            })
            .collect();
        AccuracyReport { bands, peak }
    }

    /// The largest `f cos θ_i cos θ_r` over the table's nodes above the horizon (sr⁻¹).
    pub fn peak_cosine_weighted(&self) -> f64 {
        let n = self.t.n;
        let per_half = self.values.len() / 2;
        let mut peak = 0.0f64;
        for half in 0..2 {
            for (node, a) in self.axis_dirs.iter().enumerate() {
                for iy in 0..n {
                    for ix in 0..n {
                        let (px, py) = (self.slopes[ix], self.slopes[iy]);
                        let cos_o =
                            2.0 * (a.x * px + a.y * py + a.z) / (1.0 + px * px + py * py) - a.z;
                        if cos_o > 0.0 {
                            let f = self.values[half * per_half + (node * n + iy) * n + ix] as f64;
                            peak = peak.max(f * a.z * cos_o);
                        }
                    }
                }
            }
        }
        peak
    }
}
