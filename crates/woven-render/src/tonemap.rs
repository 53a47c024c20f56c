//! Display transforms: how a linear render becomes an 8-bit PNG (`[film] tonemap`, `exposure`).
//! The EXR output stays linear; only the PNG passes through here.
//!
//! - [`ToneMap::Clamp`]: scale by `2^exposure`, clip each channel to `[0, 1]`, sRGB-encode.
//!   Anything brighter than white clips flat, and a saturated highlight clips one channel
//!   before the others, so it shifts hue (a yellow sun on red satin turns orange, then white at
//!   the edges only).
//! - [`ToneMap::Filmic`] (the default): a log-domain sigmoid in the manner of film and of
//!   Blender's AgX. Each channel is taken to stops about middle grey, `log2(x / 0.18)`, over the
//!   range [`FILMIC_STOPS`] (−10 to +6.5 EV), mapped to `[0, 1]`, and passed through a logistic
//!   curve normalised to run from 0 to 1 across that range. The curve is fixed by two
//!   conditions: middle grey lands where the sRGB curve puts it (`0.18 → 0.461`), and its
//!   contrast there is the sRGB curve's (0.149 per stop), so a well-exposed diffuse scene looks
//!   as it does clipped. Above grey it rolls off instead of clipping: diffuse white (1.0) shows
//!   at 0.80, and 16× grey at 0.98, so a satin's highlight keeps its shape and its colour.
//!   Before the curve each colour is drawn 15 % toward its own luminance ([`FILMIC_INSET`]), and
//!   after it pushed back out by the same share about the result's luminance: mid-tones keep
//!   their saturation, and a highlight bright enough to reach the top of the curve in every
//!   channel goes white rather than to a clipped primary.

use crate::color::Rgb;
use serde::Deserialize;

/// How the PNG maps linear values to display values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToneMap {
    /// A log-domain sigmoid that rolls highlights off to white (module docs).
    #[default]
    Filmic,
    /// Clip each channel at 1, then the sRGB curve.
    Clamp,
}

/// The range of the filmic curve, in stops about middle grey: below it black, above it white.
pub const FILMIC_STOPS: (f64, f64) = (-10.0, 6.5);
/// The share by which the filmic map draws colours toward their luminance before its curve.
pub const FILMIC_INSET: f64 = 0.15;
/// The logistic's steepness and centre in the curve's `[0, 1]` log domain, solved (and tested)
/// so that middle grey maps to its sRGB value with the sRGB curve's slope there.
const FILMIC_STEEPNESS: f64 = 9.653_591_5;
const FILMIC_CENTRE: f64 = 0.626_680_77;
/// Middle grey, linear.
const MIDDLE_GREY: f64 = 0.18;

impl ToneMap {
    /// The names a scene file or a command line uses, in order.
    pub const NAMES: [&'static str; 2] = ["filmic", "clamp"];

    /// The tone map named `name` ([`NAMES`](Self::NAMES)); `None` for another name.
    pub fn parse(name: &str) -> Option<ToneMap> {
        match name {
            "filmic" => Some(ToneMap::Filmic),
            "clamp" => Some(ToneMap::Clamp),
            _ => None,
        }
    }

    /// The name of this tone map.
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Filmic => "filmic",
            ToneMap::Clamp => "clamp",
        }
    }

    /// The display value in `[0, 1]` (sRGB-encoded) of a linear colour already scaled by the
    /// exposure. Non-finite or negative channels count as 0.
    pub fn apply(self, linear: Rgb) -> [f64; 3] {
        let c = linear
            .0
            .map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        match self {
            ToneMap::Clamp => c.map(|v| srgb_encode(v.min(1.0))),
            ToneMap::Filmic => filmic(c),
        }
    }
}

/// How a render is shown in a PNG: its exposure and tone map (`[film] exposure`, `tonemap`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Display {
    /// Stops: linear values are scaled by `2^exposure` before the tone map.
    pub exposure: f64,
    /// The tone map.
    pub tonemap: ToneMap,
}

impl Display {
    /// The 8-bit display value of a linear colour.
    pub fn encode(&self, linear: Rgb) -> [u8; 3] {
        let gain = self.exposure.exp2();
        self.tonemap
            .apply(Rgb(linear.0.map(|v| v * gain)))
            .map(|v| (v * 255.0 + 0.5) as u8)
    }
}

/// The sRGB transfer function of a linear value in `[0, 1]` (the library's one home of it).
pub use woven::color::srgb_encode;

/// The filmic curve of one channel: linear in, display-encoded out, both in `[0, 1]`.
pub fn filmic_curve(x: f64) -> f64 {
    let (lo, hi) = FILMIC_STOPS;
    let stops = (x.max(1e-30) / MIDDLE_GREY).log2();
    let e = ((stops - lo) / (hi - lo)).clamp(0.0, 1.0);
    let logistic = |t: f64| 1.0 / (1.0 + (-FILMIC_STEEPNESS * (t - FILMIC_CENTRE)).exp());
    let (bottom, top) = (logistic(0.0), logistic(1.0));
    ((logistic(e) - bottom) / (top - bottom)).clamp(0.0, 1.0)
}

/// The filmic map of a colour: inset toward its luminance, the curve per channel, outset.
fn filmic(c: [f64; 3]) -> [f64; 3] {
    let y = Rgb(c).luminance();
    let inset = c.map(|v| v + FILMIC_INSET * (y - v));
    let d = inset.map(filmic_curve);
    let dy = Rgb(d).luminance();
    d.map(|v| (dy + (v - dy) / (1.0 - FILMIC_INSET)).clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filmic_curve_keeps_middle_grey_and_its_contrast() {
        let grey = filmic_curve(MIDDLE_GREY);
        assert!((grey - srgb_encode(MIDDLE_GREY)).abs() < 2e-4, "{grey}");
        // Contrast per stop at grey against the sRGB curve's.
        let h: f64 = 1e-3;
        let per_stop = |f: &dyn Fn(f64) -> f64| {
            (f(MIDDLE_GREY * h.exp2()) - f(MIDDLE_GREY * (-h).exp2())) / (2.0 * h)
        };
        let (ours, srgb) = (per_stop(&filmic_curve), per_stop(&srgb_encode));
        assert!((ours / srgb - 1.0).abs() < 5e-3, "{ours} vs {srgb}");
    }

    #[test]
    fn the_filmic_curve_is_monotone_from_black_to_white() {
        assert_eq!(filmic_curve(0.0), 0.0);
        assert!(filmic_curve(MIDDLE_GREY * FILMIC_STOPS.1.exp2()) > 0.999);
        let mut last = 0.0;
        for k in -400..=200 {
            let v = filmic_curve((k as f64 * 0.05).exp2());
            assert!(v >= last, "falls at 2^{}", k as f64 * 0.05);
            last = v;
        }
        // Highlights roll off instead of clipping: white and 4× white stay apart.
        assert!(filmic_curve(4.0) - filmic_curve(1.0) > 0.1);
    }

    #[test]
    fn greys_stay_grey_and_bright_colours_go_white() {
        for v in [0.01, 0.18, 1.0, 10.0] {
            let d = ToneMap::Filmic.apply(Rgb([v; 3]));
            assert!((d[0] - d[1]).abs() < 1e-12 && (d[1] - d[2]).abs() < 1e-12);
            assert!((d[0] - filmic_curve(v)).abs() < 1e-12);
        }
        // A pure red far over white: clamp keeps it a pure primary at any brightness, filmic
        // takes it toward white.
        let red = |k: f64| Rgb([k, 0.1 * k, 0.05 * k]);
        let (clamped, filmic) = (
            ToneMap::Clamp.apply(Rgb([100.0, 0.0, 0.0])),
            ToneMap::Filmic.apply(Rgb([100.0, 0.0, 0.0])),
        );
        assert!(clamped[0] > 0.999_999 && clamped[1] == 0.0);
        assert!(filmic[1] > 0.5 && filmic[2] > 0.5, "{filmic:?}");
        // A mid-tone keeps its hue order and most of its saturation.
        let mid = ToneMap::Filmic.apply(red(0.3));
        assert!(mid[0] > mid[1] && mid[1] > mid[2]);
    }

    #[test]
    fn bad_values_are_black_and_names_round_trip() {
        for map in [ToneMap::Filmic, ToneMap::Clamp] {
            assert_eq!(
                map.apply(Rgb([f64::NAN, -1.0, f64::NEG_INFINITY])),
                [0.0; 3]
            );
            assert_eq!(ToneMap::parse(map.name()), Some(map));
        }
        assert_eq!(ToneMap::parse("aces"), None);
        assert_eq!(
            ToneMap::NAMES.map(|n| ToneMap::parse(n).unwrap().name()),
            ToneMap::NAMES
        );
    }
}
