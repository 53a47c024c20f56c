//! Sampling building blocks shared by the table sampler and renderers: piecewise-constant
//! distributions in one and two dimensions (CDFs built by [`cumulate`] and [`normalize_cdf`],
//! inverted by [`invert_cdf`]), the cosine-weighted hemisphere, the uniform sphere and the power
//! heuristic — pbrt-v4's `util/sampling.h`, in this crate's conventions.
//!
//! Every sampler takes explicit uniforms in `[0, 1)`; densities are per unit length (on
//! `[0, 1)`), per unit area (on `[0, 1)²`) or per unit solid angle, as each function says.
//!
//! ```
//! use woven::math::sampling::Distribution1D;
//!
//! // Weights 1 : 3: the second half of [0, 1) is drawn three times as often.
//! let d = Distribution1D::new(&[1.0, 3.0]);
//! assert_eq!(d.probability(1), 0.75);
//! assert_eq!(d.pdf(0.8), 1.5);
//! let s = d.sample(0.625);
//! assert_eq!((s.bin, s.fraction), (1, 0.5));
//! ```

use super::special::sin_cos;
use super::Vec3;
use std::f64::consts::{FRAC_1_PI, PI};

/// A number a CDF may be stored in: `f64`, or `f32` where memory matters (tables). Cumulation
/// runs in `f64` either way; only the stored entries are rounded.
pub trait CdfValue: Copy + private::Sealed {
    /// The value as `f64` (exact).
    fn to_f64(self) -> f64;
    /// `x` rounded to the nearest value of the type.
    fn from_f64(x: f64) -> Self;
}

impl CdfValue for f64 {
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn from_f64(x: f64) -> f64 {
        x
    }
}

impl CdfValue for f32 {
    #[inline]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn from_f64(x: f64) -> f32 {
        x as f32
    }
}

mod private {
    pub trait Sealed {}
    impl Sealed for f64 {}
    impl Sealed for f32 {}
}

/// Writes the running sums of `weights` into `cdf` (`cdf[0] = 0`, `cdf[k]` the sum of the first
/// `k` weights, accumulated in `f64` and each stored rounded to `T`) and returns the total, in
/// `f64`. `cdf` has one entry more than there are weights; negative weights are the caller's to
/// clamp.
///
/// # Panics
/// When `weights` yields more than `cdf.len() - 1` items.
pub fn cumulate<T: CdfValue>(weights: impl IntoIterator<Item = f64>, cdf: &mut [T]) -> f64 {
    cdf[0] = T::from_f64(0.0);
    let mut acc = 0.0;
    for (k, w) in weights.into_iter().enumerate() {
        acc += w;
        cdf[k + 1] = T::from_f64(acc);
    }
    acc
}

/// Divides a CDF of running sums (as [`cumulate`] leaves it) by their `total`; a total that is
/// not > 0 gives the uniform CDF (every bin equally likely).
pub fn normalize_cdf<T: CdfValue>(cdf: &mut [T], total: f64) {
    let n = cdf.len() - 1;
    for (k, c) in cdf.iter_mut().enumerate().skip(1) {
        *c = if total > 0.0 {
            T::from_f64(c.to_f64() / total)
        } else {
            // The uniform CDF, k / n. Rounding the f64 quotient to f32 gives the correctly
            // rounded f32 quotient (f64 has more than 2 × 24 + 2 bits), as `k as f32 / n as f32`.
            T::from_f64(k as f64 / n as f64)
        };
    }
}

/// A bin drawn from a CDF, and where in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BinSample {
    /// The bin `i`, with `cdf[i] ≤ u < cdf[i + 1]`.
    pub bin: usize,
    /// The position of `u` within the bin's CDF interval, in `[0, 1]`: the continuous offset
    /// within the bin for a piecewise-constant density.
    pub fraction: f64,
}

/// Inverts a normalized CDF (`n + 1` non-decreasing entries from 0 to 1) at `u` by bisection:
/// the bin `i` with `cdf[i] ≤ u < cdf[i + 1]` (the last bin for `u ≥ 1`) and the fraction of the
/// way through it. `None` when `u < cdf[0]`, `u` is NaN, or the bin found is empty (only for
/// `u` outside `[0, 1)`).
#[inline]
pub fn invert_cdf<T: CdfValue>(cdf: &[T], u: f64) -> Option<BinSample> {
    let k = cdf.partition_point(|c| c.to_f64() <= u);
    bin_at(cdf, k, u)
}

/// [`invert_cdf`] by counting the entries `≤ u` instead of bisecting: the same result, faster for
/// short CDFs that are likely not in cache (the loads do not depend on one another, so their
/// cache lines arrive together rather than one miss after another).
#[inline]
pub fn invert_cdf_scan<T: CdfValue>(cdf: &[T], u: f64) -> Option<BinSample> {
    let k = cdf
        .iter()
        .fold(0usize, |k, &c| k + usize::from(c.to_f64() <= u));
    bin_at(cdf, k, u)
}

/// The bin below the first entry greater than `u` (`k` entries are `≤ u`).
#[inline]
fn bin_at<T: CdfValue>(cdf: &[T], k: usize, u: f64) -> Option<BinSample> {
    let n = cdf.len() - 1;
    let bin = k.checked_sub(1)?.min(n - 1);
    let (lo, hi) = (cdf[bin].to_f64(), cdf[bin + 1].to_f64());
    if hi <= lo {
        return None;
    }
    Some(BinSample {
        bin,
        fraction: ((u - lo) / (hi - lo)).clamp(0.0, 1.0),
    })
}

/// A piecewise-constant density on `[0, 1)` with `n` equal bins (pbrt's
/// `PiecewiseConstant1D`), for sampling tabulated functions and discrete choices.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// The normalized CDF, `n + 1` entries: `cdf[0] = 0`, `cdf[n] = 1`.
    cdf: Vec<f64>,
    /// The sum of the (clamped) weights.
    total: f64,
}

impl Distribution1D {
    /// From weights, one per bin (negative ones count as 0); all-zero weights give the uniform
    /// distribution.
    ///
    /// # Panics
    /// When `weights` is empty.
    pub fn new(weights: &[f64]) -> Distribution1D {
        assert!(!weights.is_empty(), "a distribution needs at least one bin");
        let mut cdf = vec![0.0; weights.len() + 1];
        let total = cumulate(weights.iter().map(|w| w.max(0.0)), &mut cdf);
        normalize_cdf(&mut cdf, total);
        Distribution1D { cdf, total }
    }

    /// The number of bins.
    pub fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// Whether there are no bins (never: [`new`](Self::new) needs one).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The sum of the weights.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The normalized CDF, `len() + 1` entries from 0 to 1.
    pub fn cdf(&self) -> &[f64] {
        &self.cdf
    }

    /// The probability of bin `i`.
    #[inline]
    pub fn probability(&self, i: usize) -> f64 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// The density at `x ∈ [0, 1)`, per unit length (0 outside `[0, 1]`).
    #[inline]
    pub fn pdf(&self, x: f64) -> f64 {
        if !(0.0..=1.0).contains(&x) {
            return 0.0;
        }
        let n = self.len();
        let i = ((x * n as f64) as usize).min(n - 1);
        self.probability(i) * n as f64
    }

    /// Draws a bin in proportion to its weight from `u ∈ [0, 1)` (clamped into it), and the
    /// offset within it in `[0, 1)`: the continuous sample is `(bin + fraction) / len()`, drawn
    /// with density [`pdf`](Self::pdf).
    #[inline]
    pub fn sample(&self, u: f64) -> BinSample {
        // A `u` rounded to 1 (or past it) draws the last non-empty bin, as one just below would.
        let u = u.clamp(0.0, 1.0 - f64::EPSILON);
        // cdf[0] = 0 ≤ u < 1 = cdf[n]: the bin found is never empty; the fallback only guards a
        // NaN `u`.
        match invert_cdf(&self.cdf, u) {
            // The fraction stays below 1 so that the sample stays in its bin after rounding.
            Some(s) => BinSample {
                bin: s.bin,
                fraction: s.fraction.min(1.0 - f64::EPSILON),
            },
            None => BinSample {
                bin: 0,
                fraction: 0.5,
            },
        }
    }
}

/// A piecewise-constant density on `[0, 1)²` over a `width × height` grid of cells (pbrt's
/// `PiecewiseConstant2D`): rows drawn from their marginal, then a cell from its row's
/// conditional distribution.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    /// Over the rows, weighted by the rows' totals.
    marginal: Distribution1D,
    /// Per row, over its cells.
    conditional: Vec<Distribution1D>,
}

/// A point drawn by [`Distribution2D::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample2D {
    /// The point in `[0, 1)²`: `(x, y)`, `x` along a row (the column), `y` across rows.
    pub point: [f64; 2],
    /// The cell `(column, row)` it lies in.
    pub cell: [usize; 2],
    /// The density it was drawn with, per unit area of the square.
    pub pdf: f64,
}

impl Distribution2D {
    /// From row-major weights (`weights[row * width + column]`; negative ones count as 0). A row
    /// of zero weight is never drawn; all-zero weights give the uniform distribution.
    ///
    /// # Panics
    /// When `weights.len() != width * height` or either side is 0.
    pub fn new(weights: &[f64], width: usize, height: usize) -> Distribution2D {
        assert!(width > 0 && height > 0 && weights.len() == width * height);
        let conditional: Vec<Distribution1D> = weights
            .chunks_exact(width)
            .map(Distribution1D::new)
            .collect();
        let row_totals: Vec<f64> = conditional.iter().map(Distribution1D::total).collect();
        Distribution2D {
            marginal: Distribution1D::new(&row_totals),
            conditional,
        }
    }

    /// Cells per row.
    pub fn width(&self) -> usize {
        self.conditional[0].len()
    }

    /// Rows.
    pub fn height(&self) -> usize {
        self.conditional.len()
    }

    /// The probability of cell `(column, row)`.
    #[inline]
    pub fn probability(&self, column: usize, row: usize) -> f64 {
        self.marginal.probability(row) * self.conditional[row].probability(column)
    }

    /// The density at `(x, y) ∈ [0, 1)²`, per unit area (0 outside `[0, 1]²`).
    #[inline]
    pub fn pdf(&self, point: [f64; 2]) -> f64 {
        let [x, y] = point;
        if !(0.0..=1.0).contains(&x) || !(0.0..=1.0).contains(&y) {
            return 0.0;
        }
        let (w, h) = (self.width(), self.height());
        let column = ((x * w as f64) as usize).min(w - 1);
        let row = ((y * h as f64) as usize).min(h - 1);
        self.probability(column, row) * (w * h) as f64
    }

    /// Draws a point: `u[1]` picks the row from the marginal, `u[0]` the cell within it (each
    /// in `[0, 1)`).
    #[inline]
    pub fn sample(&self, u: [f64; 2]) -> Sample2D {
        let row = self.marginal.sample(u[1]);
        let column = self.conditional[row.bin].sample(u[0]);
        let (w, h) = (self.width(), self.height());
        Sample2D {
            point: [
                (column.bin as f64 + column.fraction) / w as f64,
                (row.bin as f64 + row.fraction) / h as f64,
            ],
            cell: [column.bin, row.bin],
            pdf: self.probability(column.bin, row.bin) * (w * h) as f64,
        }
    }
}

/// A cosine-weighted direction on the upper hemisphere (`z > 0` but for `u1 = 1`), by Malley's
/// method: a uniform point on the unit disk (polar mapping, `r = √u1`, `φ = 2π u2`) lifted to
/// the hemisphere. Its density is [`cosine_hemisphere_pdf`]`(z)`.
#[inline]
pub fn cosine_hemisphere(u1: f64, u2: f64) -> Vec3 {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    // max(0): 1 − u1 is ≥ 0 for u1 ∈ [0, 1]; the guard keeps a u1 rounded past 1 from a NaN.
    let z = (1.0 - u1).max(0.0).sqrt();
    let (s, c) = sin_cos(phi);
    Vec3::new(r * c, r * s, z)
}

/// The density of [`cosine_hemisphere`] at a direction with `cos θ = cos_theta`, per unit solid
/// angle: `cos θ / π` (0 below the horizon).
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f64) -> f64 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// A uniformly distributed direction on the unit sphere; its density is
/// [`UNIFORM_SPHERE_PDF`].
#[inline]
pub fn uniform_sphere(u1: f64, u2: f64) -> Vec3 {
    let z = 1.0 - 2.0 * u1;
    // max(0): rounding may leave 1 − z² just below 0 at the poles.
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    let (s, c) = sin_cos(phi);
    Vec3::new(r * c, r * s, z)
}

/// The density of [`uniform_sphere`], `1 / 4π` per unit solid angle.
pub const UNIFORM_SPHERE_PDF: f64 = 0.25 * FRAC_1_PI;

/// The power heuristic (β = 2) weight of a strategy that drew a sample with density `pdf` against
/// one other strategy whose density there is `other` (one sample each): `pdf² / (pdf² + other²)`.
/// An infinite `pdf` (a delta, or a sample no other strategy can draw) weighs 1; a sample that
/// neither strategy can draw weighs 0.
///
/// ```
/// use woven::math::sampling::power_heuristic;
/// assert_eq!(power_heuristic(3.0, 1.0), 0.9);
/// assert_eq!(power_heuristic(f64::INFINITY, 2.0), 1.0);
/// ```
#[inline]
pub fn power_heuristic(pdf: f64, other: f64) -> f64 {
    let (a2, b2) = (pdf * pdf, other * other);
    if a2 + b2 > 0.0 && (a2 + b2).is_finite() {
        a2 / (a2 + b2)
    } else if pdf.is_infinite() {
        1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::SplitMix;

    fn uniforms(seed: u64) -> impl FnMut() -> f64 {
        let mut rng = SplitMix(seed);
        move || rng.uniform()
    }

    #[test]
    fn distribution_1d_samples_in_proportion() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]);
        assert_eq!(d.sample(0.1).bin, 0);
        assert_eq!(d.sample(0.3).bin, 2);
        assert!((d.probability(2) - 0.75).abs() < 1e-15);
        let s = d.sample(0.625);
        assert_eq!(s.bin, 2);
        assert!((s.fraction - 0.5).abs() < 1e-12);
        assert_eq!(d.total(), 4.0);
    }

    /// The density integrates to 1, and all-zero or negative weights give the uniform one.
    #[test]
    fn distribution_1d_pdf_integrates_to_one() {
        for weights in [
            vec![1.0, 0.0, 3.0, 0.5, 7.0],
            vec![0.0; 4],
            vec![-1.0, -2.0],
            vec![2.5],
        ] {
            let d = Distribution1D::new(&weights);
            let n = 10_000;
            let integral: f64 = (0..n)
                .map(|k| d.pdf((k as f64 + 0.5) / n as f64) / n as f64)
                .sum();
            assert!(
                (integral - 1.0).abs() < 1e-12,
                "{weights:?}: ∫ pdf = {integral}"
            );
            assert_eq!(d.cdf()[0], 0.0);
            assert_eq!(d.cdf()[d.len()], 1.0);
        }
        let uniform = Distribution1D::new(&[0.0; 4]);
        assert!((0..4).all(|i| uniform.probability(i) == 0.25));
        assert_eq!(uniform.pdf(0.3), 1.0);
    }

    /// The drawn `x` lies in its bin and has the density `pdf` reports; the empirical bin
    /// frequencies match the probabilities.
    #[test]
    fn distribution_1d_sample_and_pdf_agree() {
        let weights = [0.2, 5.0, 0.0, 1.0, 3.3, 0.01];
        let d = Distribution1D::new(&weights);
        let mut u = uniforms(7);
        let n = 200_000;
        let mut counts = [0usize; 6];
        for _ in 0..n {
            let s = d.sample(u());
            assert!((0.0..1.0).contains(&s.fraction));
            let x = (s.bin as f64 + s.fraction) / 6.0;
            assert_eq!((x * 6.0) as usize, s.bin);
            assert!(d.pdf(x) > 0.0);
            assert!((d.pdf(x) - d.probability(s.bin) * 6.0).abs() < 1e-15);
            counts[s.bin] += 1;
        }
        assert_eq!(counts[2], 0, "an empty bin was drawn");
        for (i, &c) in counts.iter().enumerate() {
            let p = d.probability(i);
            let sigma = (n as f64 * p * (1.0 - p)).sqrt().max(1.0);
            let dev = (c as f64 - n as f64 * p).abs();
            assert!(
                dev < 5.0 * sigma,
                "bin {i}: {c} draws, expected {}",
                n as f64 * p
            );
        }
    }

    /// The ends: u = 0 draws the first non-empty bin at its start, u just below 1 the last
    /// non-empty bin at its end; `u ≥ 1` past an empty last bin, and `u < 0`, find nothing.
    #[test]
    fn inversion_at_the_ends() {
        let cdf = [0.0, 0.0, 0.25, 0.25, 1.0];
        for invert in [invert_cdf::<f64>, invert_cdf_scan::<f64>] {
            assert_eq!(
                invert(&cdf, 0.0),
                Some(BinSample {
                    bin: 1,
                    fraction: 0.0
                })
            );
            let top = invert(&cdf, 1.0 - f64::EPSILON).unwrap();
            assert_eq!(top.bin, 3);
            assert!(top.fraction > 1.0 - 1e-15 && top.fraction <= 1.0);
            assert_eq!(invert(&cdf, 1.0).map(|s| s.bin), Some(3));
            assert_eq!(invert(&cdf, -0.1), None);
            assert_eq!(invert(&cdf, f64::NAN), None);
            assert_eq!(invert(&[0.0, 0.5, 1.0, 1.0], 1.0), None);
        }
        let d = Distribution1D::new(&[0.0, 1.0, 1.0, 0.0]);
        assert_eq!(d.sample(0.0).bin, 1);
        for u in [1.0 - f64::EPSILON, 1.0, 1.5] {
            let last = d.sample(u);
            assert_eq!(last.bin, 2, "u = {u}");
            assert!(last.fraction < 1.0);
        }
        assert_eq!(d.sample(-0.5).bin, 1);
    }

    /// Bisection and counting find the same bin, in f32 and f64, for every u.
    #[test]
    fn bisection_and_scan_agree() {
        let mut u = uniforms(3);
        let weights: Vec<f64> = (0..37)
            .map(|k| if k % 5 == 0 { 0.0 } else { u() })
            .collect();
        let mut cdf64 = vec![0.0f64; 38];
        let mut cdf32 = vec![0.0f32; 38];
        let t64 = cumulate(weights.iter().copied(), &mut cdf64);
        let t32 = cumulate(weights.iter().copied(), &mut cdf32);
        assert_eq!(t64, t32);
        normalize_cdf(&mut cdf64, t64);
        normalize_cdf(&mut cdf32, t32);
        for _ in 0..10_000 {
            let x = u();
            assert_eq!(invert_cdf(&cdf64, x), invert_cdf_scan(&cdf64, x));
            assert_eq!(invert_cdf(&cdf32, x), invert_cdf_scan(&cdf32, x));
        }
    }

    /// f32 CDFs: running sums are accumulated in f64 and rounded once per entry; a zero total
    /// gives k / n rounded to f32.
    #[test]
    fn f32_cdfs_round_each_entry_once() {
        let mut cdf = [0.0f32; 4];
        let total = cumulate([0.1, 0.2, 0.3], &mut cdf);
        assert_eq!(
            cdf,
            [0.0, 0.1f64 as f32, (0.1f64 + 0.2) as f32, total as f32]
        );
        normalize_cdf(&mut cdf, 0.0);
        assert_eq!(cdf, [0.0, 1.0f32 / 3.0, 2.0f32 / 3.0, 1.0]);
    }

    /// The 2-D density integrates to 1 and its draws carry the density `pdf` reports.
    #[test]
    fn distribution_2d_pdf_and_samples_agree() {
        let (w, h) = (7, 5);
        let weights: Vec<f64> = (0..w * h)
            .map(|i| {
                if i / w == 2 {
                    0.0
                } else {
                    1.0 + (i % 4) as f64
                }
            })
            .collect();
        let d = Distribution2D::new(&weights, w, h);
        // Midpoints of a grid that refines the cells: the rule is exact.
        let n = 7 * 5 * 10;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let p = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                integral += d.pdf(p) / (n * n) as f64;
            }
        }
        // Exact but for the rounding of 122 500 terms.
        assert!((integral - 1.0).abs() < 1e-9, "∫ pdf = {integral}");
        let mut u = uniforms(11);
        for _ in 0..10_000 {
            let s = d.sample([u(), u()]);
            assert_ne!(s.cell[1], 2, "a zero row was drawn");
            assert!((d.pdf(s.point) - s.pdf).abs() < 1e-12 * s.pdf);
            let cell = [
                (s.point[0] * w as f64) as usize,
                (s.point[1] * h as f64) as usize,
            ];
            assert_eq!(cell, s.cell);
        }
    }

    /// Cosine-weighted directions: unit, upper hemisphere, mean cos θ of 2/3, and a density
    /// that integrates to 1.
    #[test]
    fn cosine_hemisphere_is_normalized() {
        let mut u = uniforms(5);
        let n = 100_000;
        let mut mean_z = 0.0;
        for _ in 0..n {
            let d = cosine_hemisphere(u(), u());
            assert!((d.length() - 1.0).abs() < 1e-12 && d.z >= 0.0);
            mean_z += d.z / n as f64;
        }
        assert!((mean_z - 2.0 / 3.0).abs() < 5e-3, "E[cos θ] = {mean_z}");
        // ∫ cos θ / π dω = ∫₀¹ 2 μ dμ = 1 (midpoint rule in μ = cos θ, exact for a linear
        // integrand).
        let m = 1000;
        let integral: f64 = (0..m)
            .map(|k| cosine_hemisphere_pdf((k as f64 + 0.5) / m as f64) * 2.0 * PI / m as f64)
            .sum();
        assert!((integral - 1.0).abs() < 1e-12);
        assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
        // The endpoints: u1 = 0 the pole, u1 → 1 the horizon.
        assert_eq!(cosine_hemisphere(0.0, 0.3).z, 1.0);
        assert_eq!(cosine_hemisphere(1.0, 0.3).z, 0.0);
    }

    #[test]
    fn uniform_sphere_is_uniform() {
        let mut u = uniforms(9);
        let n = 100_000;
        let (mut mean, mut upper) = (Vec3::new(0.0, 0.0, 0.0), 0usize);
        for _ in 0..n {
            let d = uniform_sphere(u(), u());
            assert!((d.length() - 1.0).abs() < 1e-12);
            mean = mean + d * (1.0 / n as f64);
            upper += usize::from(d.z > 0.0);
        }
        assert!(mean.length() < 1e-2, "mean direction {mean:?}");
        assert!((upper as f64 / n as f64 - 0.5).abs() < 1e-2);
        assert!((UNIFORM_SPHERE_PDF * 4.0 * PI - 1.0).abs() < 1e-15);
    }

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 1.0), (0.3, 7.0), (1e-100, 1e-100), (5.0, 0.0)] {
            let sum = power_heuristic(a, b) + power_heuristic(b, a);
            assert!((sum - 1.0).abs() < 1e-12, "({a}, {b}): {sum}");
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(f64::INFINITY, f64::INFINITY), 1.0);
        assert_eq!(power_heuristic(2.0, f64::INFINITY), 0.0);
    }
}
