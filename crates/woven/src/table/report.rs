//! Accuracy of a table against the exact model (`woven tabulate --report`), over the whole
//! hemisphere in bands of the larger polar angle.

use super::Table;
use crate::math::Vec3;
use crate::progress::Progress;
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

/// `n` direction pairs `(s, v)`, each direction uniform in solid angle over the upper hemisphere
/// (no cosine weighting, no band selection), reproducible from `seed`: what "uniform random
/// pairs" means in the accuracy statements.
pub fn uniform_pairs(n: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut rng = SplitMix(seed);
    (0..n)
        .map(|_| {
            let s = rng.direction(std::f64::consts::FRAC_PI_2);
            let v = rng.direction(std::f64::consts::FRAC_PI_2);
            (s, v)
        })
        .collect()
}

/// The worst error of a table's `f cos θ_i cos θ_r` over uniform random pairs
/// ([`Table::peak_error`]), and where it occurred.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakError {
    /// Number of direction pairs.
    pub samples: usize,
    /// The material's peak of `f cos θ_i cos θ_r` (sr⁻¹), as in [`AccuracyReport::peak`].
    pub peak: f64,
    /// The largest `|f_table − f| cos θ_i cos θ_r` over the pairs, relative to [`peak`](Self::peak).
    pub max_peak_rel: f64,
    /// The light direction of the worst pair.
    pub s: Vec3,
    /// The view direction of the worst pair.
    pub v: Vec3,
    /// The table's value there (sr⁻¹).
    pub table: f64,
    /// The exact value there (sr⁻¹).
    pub exact: f64,
}

impl Table {
    /// Compares the table with `model` at `samples_per_band` random pairs in each band of
    /// [`BANDS_DEG`] ([`band_pairs`] from `seed`), the exact values computed on all cores;
    /// `progress` hears `(done, total)` as they complete.
    pub fn accuracy(
        &self,
        model: &Model,
        samples_per_band: usize,
        seed: u64,
        progress: &dyn Progress,
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
                progress.update(k, pairs.len());
                f
            })
            .collect();
        self.accuracy_against(&pairs, &exact)
    }

    /// As [`accuracy`](Self::accuracy), with the pairs and their exact values supplied.
    pub fn accuracy_against(&self, pairs: &[(usize, Vec3, Vec3)], exact: &[f64]) -> AccuracyReport {
        let peak = self.peak_with(
            pairs
                .iter()
                .zip(exact)
                .map(|(&(_, s, v), &e)| e * s.z * v.z),
        );
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

    /// The worst `|f_table − f| cos θ_i cos θ_r` relative to the material's peak of
    /// `f cos θ_i cos θ_r` over `n` [`uniform_pairs`] from `seed` (both directions uniform in
    /// solid angle over their hemisphere, no band selection), the exact values computed on all
    /// cores; `progress` hears `(done, n)` as they complete. The peak is the one
    /// [`accuracy`](Self::accuracy) uses: the largest over the table's nodes and these pairs'
    /// exact values. This is the bound a statement "within x % of the peak everywhere" rests on.
    pub fn peak_error(
        &self,
        model: &Model,
        n: usize,
        seed: u64,
        progress: &dyn Progress,
    ) -> PeakError {
        let pairs = uniform_pairs(n, seed);
        let done = std::sync::atomic::AtomicUsize::new(0);
        let exact: Vec<f64> = pairs
            .par_iter()
            .with_max_len(64)
            .map(|&(s, v)| {
                let f = model.eval(s, v);
                let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress.update(k, pairs.len());
                f
            })
            .collect();
        self.peak_error_against(&pairs, &exact)
    }

    /// As [`peak_error`](Self::peak_error), with the pairs and their exact values supplied.
    pub fn peak_error_against(&self, pairs: &[(Vec3, Vec3)], exact: &[f64]) -> PeakError {
        assert_eq!(pairs.len(), exact.len(), "one exact value per pair");
        let peak = self.peak_with(pairs.iter().zip(exact).map(|(&(s, v), &e)| e * s.z * v.z));
        // (error · cosines, index); the first of equal errors wins, so the answer is the same
        // however the pairs are split over the cores.
        let (worst, at) = pairs
            .par_iter()
            .zip(exact)
            .enumerate()
            .map(|(k, (&(s, v), &e))| ((self.eval(s, v) - e).abs() * s.z * v.z, k))
            .reduce(
                || (0.0, usize::MAX),
                |a, b| match a.0.total_cmp(&b.0) {
                    std::cmp::Ordering::Greater => a,
                    std::cmp::Ordering::Less => b,
                    std::cmp::Ordering::Equal => (a.0, a.1.min(b.1)),
                },
            );
        let (s, v, table, exact) = match pairs.get(at) {
            Some(&(s, v)) => (s, v, self.eval(s, v), exact[at]),
            None => (Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 1.0), 0.0, 0.0),
        };
        PeakError {
            samples: pairs.len(),
            peak,
            max_peak_rel: if peak > 0.0 { worst / peak } else { 0.0 },
            s,
            v,
            table,
            exact,
        }
    }

    /// The material's peak of `f cos θ_i cos θ_r`: the largest of the table's nodes
    /// ([`peak_cosine_weighted`](Self::peak_cosine_weighted)) and the given exact values of it.
    fn peak_with(&self, exact_cosine_weighted: impl Iterator<Item = f64>) -> f64 {
        exact_cosine_weighted.fold(self.peak_cosine_weighted(), f64::max)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::TableOptions;

    /// The worst pair is found, measured against the peak the accuracy report uses, and located.
    #[test]
    fn peak_error_finds_the_worst_pair_against_the_peak() {
        let m = crate::material::Material::from_toml_str(
            "[fiber]\neta = 1.5\nroughness = 0.3\ndiffuse = 0.1\n",
            "test",
        )
        .unwrap();
        let model = m.build(550.0).unwrap();
        let options = TableOptions {
            n_theta: 6,
            n_phi: 3,
            n_h: 9,
            n_h_isotropic: 9,
            azimuth_nodes: 16,
            ..TableOptions::default()
        };
        let t = Table::build(&model, &m, &options, &|_, _| {}).unwrap();
        let pairs = uniform_pairs(2000, 5);
        assert_eq!(pairs, uniform_pairs(2000, 5));
        assert!(pairs.iter().all(|(s, v)| s.z >= 0.0 && v.z >= 0.0));
        // Exact values equal to the table's but at one pair, off by a known amount.
        let mut exact: Vec<f64> = pairs.iter().map(|&(s, v)| t.eval(s, v)).collect();
        let k = 1234;
        let (s, v) = pairs[k];
        let peak = t.peak_cosine_weighted();
        exact[k] += 0.03 * peak / (s.z * v.z);
        let r = t.peak_error_against(&pairs, &exact);
        // The peak: the nodes' and every supplied exact value's `f cos θ_i cos θ_r`.
        let all = pairs
            .iter()
            .zip(&exact)
            .map(|(&(s, v), &e)| e * s.z * v.z)
            .fold(peak, f64::max);
        assert!(all > peak, "the supplied values raise the peak");
        assert_eq!((r.s, r.v, r.samples), (s, v, 2000));
        assert!((r.peak - all).abs() <= 1e-12 * all, "{r:?}");
        assert!((r.max_peak_rel - 0.03 * peak / all).abs() < 1e-9, "{r:?}");
        assert_eq!(r.exact, exact[k]);
        // Against the exact model: this tiny grid misses by a fifth of the peak, found as the
        // largest error over the same pairs.
        let e = t.peak_error(&model, 2000, 5, &|_, _| {});
        assert_eq!(e.samples, 2000);
        assert!(e.max_peak_rel > 0.01 && e.max_peak_rel < 0.5, "{e:?}");
        let worst = pairs
            .iter()
            .map(|&(s, v)| (t.eval(s, v) - model.eval(s, v)).abs() * s.z * v.z)
            .fold(0.0, f64::max);
        assert!(
            (e.max_peak_rel * e.peak - worst).abs() <= 1e-12 * worst,
            "{e:?} {worst}"
        );
    }
}
