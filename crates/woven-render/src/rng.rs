//! Per-sample random numbers: deterministic for `(seed, pixel, sample)`.

use woven::math::rng::SplitMix;

/// The uniforms one camera sample draws, from a stream seeded by the render seed, the pixel and
/// the sample index, so a render is the same for a seed whatever the threads or tile order.
#[derive(Clone, Debug)]
pub struct Sampler(SplitMix);

impl Sampler {
    /// The stream of sample `sample` of pixel `pixel` (row-major index) in a render with `seed`.
    pub fn new(seed: u64, pixel: u64, sample: u64) -> Sampler {
        // Each key is mixed through SplitMix's finalizer before the next is added, so nearby
        // (pixel, sample) pairs start uncorrelated streams.
        let mut h = SplitMix(seed ^ 0x005E_ED0F_C10C);
        let a = h.next_u64();
        let mut h = SplitMix(a ^ pixel);
        let b = h.next_u64();
        Sampler(SplitMix(b ^ sample.wrapping_mul(0xD1B5_4A32_D192_ED03)))
    }

    /// A uniform in `[0, 1)`.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        self.0.uniform()
    }

    /// Two uniforms in `[0, 1)`.
    #[inline]
    pub fn next2(&mut self) -> (f64, f64) {
        (self.uniform(), self.uniform())
    }
}
