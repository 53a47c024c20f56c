//! Special functions, from `libm`.

/// The complementary error function `erfc(x) = 1 − erf(x)`, accurate in its tail.
#[inline]
pub fn erfc(x: f64) -> f64 {
    libm::erfc(x)
}

/// `ln Γ(x)` for `x > 0`.
#[inline]
pub fn ln_gamma(x: f64) -> f64 {
    libm::lgamma(x)
}

/// `1/√π`.
pub const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;
