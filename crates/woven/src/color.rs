//! Linear RGB triples: radiance, throughput, reflectance, dyes — what a renderer's surface
//! returns per channel ([`surface`](crate::surface)).

use std::ops::{Add, AddAssign, Div, Mul, MulAssign};

/// A linear RGB value (linear sRGB primaries; see docs/render.md).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rgb(pub [f64; 3]);

impl Rgb {
    /// Black.
    pub const BLACK: Rgb = Rgb([0.0; 3]);
    /// White (1, 1, 1).
    pub const WHITE: Rgb = Rgb([1.0; 3]);

    /// A grey of value `v`.
    #[inline]
    pub const fn grey(v: f64) -> Rgb {
        Rgb([v, v, v])
    }

    /// The largest channel.
    #[inline]
    pub fn max(self) -> f64 {
        self.0[0].max(self.0[1]).max(self.0[2])
    }

    /// Rec. 709 luminance.
    #[inline]
    pub fn luminance(self) -> f64 {
        0.2126 * self.0[0] + 0.7152 * self.0[1] + 0.0722 * self.0[2]
    }

    /// Whether every channel is 0.
    #[inline]
    pub fn is_black(self) -> bool {
        self.0 == [0.0; 3]
    }

    /// Whether every channel is finite and non-negative.
    #[inline]
    pub fn is_valid(self) -> bool {
        // Each comparison is false for NaN; ∞ fails the bound.
        let ok = |c: f64| (0.0..f64::INFINITY).contains(&c);
        ok(self.0[0]) & ok(self.0[1]) & ok(self.0[2])
    }
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in `[0, 1]`: what an 8-bit
/// sRGB image stores (the renderer's PNGs, glTF's colour textures).
///
/// ```
/// use woven::color::srgb_encode;
/// // Middle grey (18 %) is stored near 46 % of full scale.
/// assert!((srgb_encode(0.18) - 0.4613).abs() < 1e-4);
/// assert_eq!(srgb_encode(0.0), 0.0);
/// assert!((srgb_encode(1.0) - 1.0).abs() < 1e-12);
/// ```
pub fn srgb_encode(x: f64) -> f64 {
    // The linear toe below 0.0031308 keeps the curve's slope finite at 0.
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

impl Add for Rgb {
    type Output = Rgb;
    #[inline]
    fn add(self, o: Rgb) -> Rgb {
        Rgb([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}

impl AddAssign for Rgb {
    #[inline]
    fn add_assign(&mut self, o: Rgb) {
        *self = *self + o;
    }
}

impl Mul for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, o: Rgb) -> Rgb {
        Rgb([self.0[0] * o.0[0], self.0[1] * o.0[1], self.0[2] * o.0[2]])
    }
}

impl MulAssign for Rgb {
    #[inline]
    fn mul_assign(&mut self, o: Rgb) {
        *self = *self * o;
    }
}

impl Mul<f64> for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, k: f64) -> Rgb {
        Rgb([self.0[0] * k, self.0[1] * k, self.0[2] * k])
    }
}

impl MulAssign<f64> for Rgb {
    #[inline]
    fn mul_assign(&mut self, k: f64) {
        *self = *self * k;
    }
}

impl Div<f64> for Rgb {
    type Output = Rgb;
    #[inline]
    fn div(self, k: f64) -> Rgb {
        self * (1.0 / k)
    }
}
