//! Per-sample random numbers: deterministic for `(seed, pixel, sample)`.
//!
//! Two kinds ([`SamplerKind`]): independent uniforms (Mitsuba's `independent` sampler), and
//! Owen-scrambled Sobol points (the `sobol_burley` crate), which spread a pixel's samples
//! evenly over the pixel, over the light and over each BSDF draw. On the showcase the Sobol
//! points at 16 samples per pixel are as noisy as independent ones at 64 (docs/render.md).
//!
//! **Sobol dimensions.** The uniforms of one camera sample are taken in order, four at a time
//! from the first four dimensions of a Sobol sequence scrambled and shuffled by a seed of their
//! own (Burley's padding: each set of four is stratified in itself and randomly paired with the
//! others). A pair ([`Sampler::next2`]) never straddles two sets, so the pixel position, a point
//! on a light and a BSDF draw are each stratified in two dimensions. The sequence has 2¹⁶
//! points: samples from the 65 537th on are independent uniforms.

use serde::Deserialize;
use woven::math::rng::SplitMix;

/// How a pixel's samples are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SamplerKind {
    /// Owen-scrambled Sobol points, shuffled per pixel: less noise for the same samples.
    #[default]
    Sobol,
    /// Independent uniforms per sample (Mitsuba's `independent`): each sample is independent
    /// of the others, so a pixel's sample variance estimates its error exactly (statistical
    /// tests use it).
    Independent,
}

/// The most samples per pixel the Sobol points cover.
const SOBOL_POINTS: u64 = 1 << 16;

/// The uniforms one camera sample draws, from a stream seeded by the render seed, the pixel and
/// the sample index, so a render is the same for a seed whatever the threads or tile order.
#[derive(Clone, Debug)]
pub struct Sampler {
    /// Independent uniforms (the whole stream for [`SamplerKind::Independent`]).
    stream: SplitMix,
    /// Sobol points: the sample's index in the pixel's sequence and the pixel's seed; `None`
    /// for independent uniforms.
    sobol: Option<(u32, u64)>,
    /// The current set of four Sobol uniforms.
    set: [f32; 4],
    /// The set's number (its seed follows from it).
    set_index: u64,
    /// How many of the set are used.
    used: usize,
}

impl Sampler {
    /// The stream of sample `sample` of pixel `pixel` (row-major index) in a render with `seed`.
    pub fn new(kind: SamplerKind, seed: u64, pixel: u64, sample: u64) -> Sampler {
        // Each key is mixed through SplitMix's finalizer before the next is added, so nearby
        // (pixel, sample) pairs start uncorrelated streams.
        let mut h = SplitMix(seed ^ 0x005E_ED0F_C10C);
        let a = h.next_u64();
        let mut h = SplitMix(a ^ pixel);
        let pixel_seed = h.next_u64();
        let sobol = (kind == SamplerKind::Sobol && sample < SOBOL_POINTS)
            .then_some((sample as u32, pixel_seed));
        Sampler {
            stream: SplitMix(pixel_seed ^ sample.wrapping_mul(0xD1B5_4A32_D192_ED03)),
            sobol,
            set: [0.0; 4],
            set_index: 0,
            used: 4,
        }
    }

    /// The next Sobol uniform, starting a new set of four when this one is used up or when
    /// `need` more must come from one set.
    #[inline]
    fn sobol(&mut self, index: u32, pixel_seed: u64, need: usize) -> f64 {
        if self.used + need > 4 {
            let seed = SplitMix(pixel_seed ^ self.set_index.wrapping_mul(0x9E37_79B9_7F4A_7C15))
                .next_u64();
            self.set = sobol_burley::sample_4d(index, 0, seed as u32);
            self.set_index += 1;
            self.used = 0;
        }
        let x = self.set[self.used];
        self.used += 1;
        x as f64
    }

    /// A uniform in `[0, 1)`.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        match self.sobol {
            Some((index, seed)) => self.sobol(index, seed, 1),
            None => self.stream.uniform(),
        }
    }

    /// Two uniforms in `[0, 1)`, from one set of Sobol points (stratified together).
    #[inline]
    pub fn next2(&mut self) -> (f64, f64) {
        match self.sobol {
            Some((index, seed)) => {
                let a = self.sobol(index, seed, 2);
                (a, self.sobol(index, seed, 1))
            }
            None => (self.stream.uniform(), self.stream.uniform()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean over a pixel's samples of a smooth integrand in each pair of uniforms: the Sobol
    /// points' error is far below independent uniforms' at 256 samples, and both are unbiased
    /// (their means over many pixels agree with the integral).
    #[test]
    fn sobol_pairs_are_stratified_and_unbiased() {
        // ∫∫ (x + y²) dx dy = 1/2 + 1/3.
        let exact = 0.5 + 1.0 / 3.0;
        let spp = 256;
        let pixels = 200;
        let mut sq = [0.0; 2];
        let mut mean = [0.0; 2];
        for (k, kind) in [SamplerKind::Sobol, SamplerKind::Independent]
            .into_iter()
            .enumerate()
        {
            for pixel in 0..pixels {
                let mut sum = 0.0;
                for s in 0..spp {
                    let mut sampler = Sampler::new(kind, 7, pixel, s);
                    // A uniform first, so the pair starts inside a set; then the pair.
                    let _ = sampler.uniform();
                    let (x, y) = sampler.next2();
                    let (_, _) = sampler.next2();
                    assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
                    sum += x + y * y;
                }
                let e = sum / spp as f64 - exact;
                sq[k] += e * e;
                mean[k] += e;
            }
        }
        let rms = sq.map(|s| (s / pixels as f64).sqrt());
        // Independent: σ/√spp with σ² = Var(x + y²) ≈ 0.172, so ≈ 0.026.
        assert!(
            rms[1] > 0.015 && rms[1] < 0.04,
            "independent rms {}",
            rms[1]
        );
        assert!(rms[0] < rms[1] / 10.0, "sobol rms {} vs {}", rms[0], rms[1]);
        for (k, m) in mean.iter().enumerate() {
            let m = m / pixels as f64;
            assert!(
                m.abs() < 4.0 * rms[k] / (pixels as f64).sqrt() + 1e-6,
                "bias {m}"
            );
        }
    }

    /// A render is the same for a seed: a sample's uniforms depend on (seed, pixel, sample)
    /// alone, and differ between pixels.
    #[test]
    fn streams_are_deterministic_and_differ_between_pixels() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let draw = |pixel| {
                let mut s = Sampler::new(kind, 3, pixel, 5);
                (0..12).map(|_| s.uniform()).collect::<Vec<_>>()
            };
            assert_eq!(draw(9), draw(9));
            assert_ne!(draw(9), draw(10));
        }
        // Past the Sobol points: independent uniforms, still deterministic.
        let mut a = Sampler::new(SamplerKind::Sobol, 3, 1, SOBOL_POINTS + 2);
        let mut b = Sampler::new(SamplerKind::Independent, 3, 1, SOBOL_POINTS + 2);
        assert_eq!(a.uniform(), b.uniform());
    }
}
