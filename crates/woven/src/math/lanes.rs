//! Values the quadrature rules can integrate: a number, or a few numbers integrated together
//! (the parts a BRDF is affine in, docs/spec.md §1.5, share every node of one pass).

/// A value of a linear space the rules sum: `f64`, or `[f64; N]` lane by lane.
pub trait Lanes: Copy {
    /// The zero value.
    const ZERO: Self;
    /// `self + other`.
    fn add(self, other: Self) -> Self;
    /// `k · self`.
    fn scale(self, k: f64) -> Self;
    /// `max(self, 0)`, lane by lane.
    fn clamp_non_negative(self) -> Self;
}

impl Lanes for f64 {
    const ZERO: Self = 0.0;
    #[inline]
    fn add(self, other: Self) -> Self {
        self + other
    }
    #[inline]
    fn scale(self, k: f64) -> Self {
        k * self
    }
    #[inline]
    fn clamp_non_negative(self) -> Self {
        self.max(0.0)
    }
}

impl<const N: usize> Lanes for [f64; N] {
    const ZERO: Self = [0.0; N];
    #[inline]
    fn add(self, other: Self) -> Self {
        std::array::from_fn(|i| self[i] + other[i])
    }
    #[inline]
    fn scale(self, k: f64) -> Self {
        self.map(|x| k * x)
    }
    #[inline]
    fn clamp_non_negative(self) -> Self {
        self.map(|x| x.max(0.0))
    }
}
