//! Yarn irregularity: each yarn's dye varies along its length.
//!
//! Real yarns are not uniform. A spun yarn thickens and thins (slubs), takes up dye unevenly
//! (ring-dyed indigo most of all), and neighbouring yarns come from different parts of a bobbin.
//! That is what gives denim its streaks and a heathered cloth its mottle. Here each yarn's albedos
//! (its dye, or its material's own) are scaled by a factor that varies smoothly along the yarn
//! and independently from yarn to yarn:
//!
//! ```text
//! m = exp(σ z − σ²/2),    z ~ N(0, 1) at every point,
//! z(t) = ((1 − s) z_k + s z_{k+1}) / √((1 − s)² + s²),   s = smoothstep(t/ℓ − k),
//! ```
//!
//! `σ` the family's [`Irregularity::spread`], `t` the position along the yarn in pattern cells,
//! `ℓ` the [`Irregularity::length`], `z_k`
//! independent standard normals at knots `ℓ` apart (Box–Muller from a hash of the yarn, its
//! family and the knot). Each `z(t)` is a unit normal, so `E[m] = 1` at every point: over many
//! yarns the cloth's mean albedo, and so its macro BRDF, is the uniform cloth's (up to the
//! albedos' caps, `ρ0 < 1`, `ρ ≤ 1`). The sheen is the fibres' surface and stays as it is.

use crate::error::{Error, Result};
use crate::material::{Material, Weave};
use crate::yarn::point::hash_uniform;
use std::f64::consts::TAU;

/// The largest [`Irregularity::spread`].
pub const MAX_SPREAD: f64 = 1.0;

/// The range of [`Irregularity::length`], in pattern cells.
pub const LENGTH_RANGE: [f64; 2] = [1.0, 1.0e6];

/// What [`Irregularity::spread`] must be, as an error states it.
pub(super) fn spread_valid() -> String {
    format!("a spread in [0, {MAX_SPREAD}] for the weft and for the warp")
}

/// What [`Irregularity::length`] must be, as an error states it.
pub(super) fn length_valid() -> String {
    let [lo, hi] = LENGTH_RANGE;
    format!("pattern cells in [{lo}, {hi:e}]")
}

/// How unevenly a surface's yarns are dyed along their length
/// ([`SurfaceSpec::irregularity`](crate::surface::SurfaceSpec::irregularity)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Irregularity {
    /// `σ` of the weft and of the warp, the spread of the log of each yarn's dye factor, each in
    /// `[0, MAX_SPREAD]`; 0 (the default): every yarn of the family dyed alike. (Denim's indigo
    /// warp streaks; its undyed weft hardly varies.)
    pub spread: [f64; 2],
    /// `ℓ`, the distance along a yarn over which its factor changes, in pattern cells, in
    /// [`LENGTH_RANGE`] (default 24).
    pub length: f64,
}

impl Default for Irregularity {
    fn default() -> Self {
        Irregularity {
            spread: [0.0; 2],
            length: 24.0,
        }
    }
}

impl Irregularity {
    /// Whether any yarn's dye varies.
    pub fn is_active(&self) -> bool {
        self.spread.iter().any(|s| *s > 0.0)
    }

    /// Checks both parameters.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `irregularity` or `irregularity_length`, its value and
    /// the valid range.
    pub fn validate(&self) -> Result<()> {
        if !self.spread.iter().all(|s| (0.0..=MAX_SPREAD).contains(s)) {
            return Err(Error::InvalidParameter {
                name: "irregularity".into(),
                value: format!("{:?}", self.spread),
                expected: spread_valid(),
            });
        }
        let [lo, hi] = LENGTH_RANGE;
        if !(lo..=hi).contains(&self.length) {
            return Err(Error::InvalidParameter {
                name: "irregularity_length".into(),
                value: self.length.to_string(),
                expected: length_valid(),
            });
        }
        Ok(())
    }

    /// [`validate`](Self::validate), and that `material` lays its yarns out on a weave pattern
    /// when any yarn varies (yarns vary one by one only there).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `irregularity` or `irregularity_length`.
    pub fn validate_for(&self, material: &Material) -> Result<()> {
        self.validate()?;
        if self.is_active() && !matches!(material.weave, Some(Weave::Pattern { .. })) {
            return Err(Error::InvalidParameter {
                name: "irregularity".into(),
                value: format!("{:?} without a weave pattern", self.spread),
                expected: "0: yarns are laid out (and can vary one by one) only on a pattern"
                    .into(),
            });
        }
        Ok(())
    }

    /// The dye factor `m` of yarn `index` of the weft (`warp = false`) or the warp at `along`
    /// pattern cells along it. 1 when inactive; finite and positive for every finite input.
    pub fn factor(&self, index: i64, warp: bool, along: f64) -> f64 {
        let sigma = self.spread[usize::from(warp)];
        if sigma <= 0.0 || !along.is_finite() {
            return 1.0;
        }
        let t = along / self.length;
        let k = t.floor();
        let w = t - k;
        let s = w * w * (3.0 - 2.0 * w);
        let knot = k as i64;
        let z0 = knot_normal(index, warp, knot);
        let z1 = knot_normal(index, warp, knot.wrapping_add(1));
        let z = ((1.0 - s) * z0 + s * z1) / ((1.0 - s).powi(2) + s * s).sqrt();
        (sigma * z - 0.5 * sigma * sigma).exp()
    }
}

/// A standard normal for the knot `knot` of yarn `index` (Box–Muller on two hashed uniforms).
fn knot_normal(index: i64, warp: bool, knot: i64) -> f64 {
    let family = if warp { 0x3A2F_0001 } else { 0x3A2F_0000 };
    let key = (index as u64).wrapping_mul(0x2545_F491_4F6C_DD1D) ^ family;
    let u1 = hash_uniform(key, knot as u64);
    let u2 = hash_uniform(key ^ 0xA5A5_5A5A, knot as u64);
    // 1 − u1 lies in (0, 1]: the log is finite.
    (-2.0 * (1.0 - u1).ln()).sqrt() * (TAU * u2).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    const ON: Irregularity = Irregularity {
        spread: [0.4, 0.4],
        length: 16.0,
    };

    /// Over many yarns the factor's mean is 1 and the spread of its log is `σ`, at a knot and
    /// between knots (the interpolation keeps `z` a unit normal).
    #[test]
    fn the_factor_has_mean_one_and_log_spread_sigma_everywhere_along_a_yarn() {
        let n = 40_000;
        for along in [0.0, 5.3, 8.0, 13.9] {
            let logs: Vec<f64> = (0..n)
                .map(|i| ON.factor(i, i % 2 == 0, along).ln())
                .collect();
            let m: Vec<f64> = logs.iter().map(|l| l.exp()).collect();
            let mean = m.iter().sum::<f64>() / n as f64;
            let sd_m = (m.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
            let se = sd_m / (n as f64).sqrt();
            assert!(
                (mean - 1.0).abs() < 4.0 * se,
                "at {along}: mean {mean} (SE {se})"
            );
            let mu = logs.iter().sum::<f64>() / n as f64;
            let sd = (logs.iter().map(|x| (x - mu).powi(2)).sum::<f64>() / n as f64).sqrt();
            assert!(
                (mu + 0.08).abs() < 0.01,
                "at {along}: mean log {mu}, expected −σ²/2"
            );
            assert!(
                (sd - 0.4).abs() < 0.01,
                "at {along}: log spread {sd}, expected 0.4"
            );
        }
    }

    /// Along one yarn the factor is continuous, and changes over `ℓ`: neighbouring points agree,
    /// points many lengths apart are unrelated; weft and warp yarns of one index differ.
    #[test]
    fn the_factor_is_smooth_along_a_yarn_and_independent_between_yarns() {
        for index in [-7, 0, 3, 1_000_000] {
            for k in 0..200 {
                let t = -50.0 + k as f64 * 0.5;
                let (a, b) = (
                    ON.factor(index, false, t),
                    ON.factor(index, false, t + 1e-6),
                );
                assert!(
                    (a / b - 1.0).abs() < 1e-5,
                    "yarn {index} at {t}: {a} then {b}"
                );
            }
        }
        let pairs = 20_000;
        let corr = |f: &dyn Fn(i64) -> (f64, f64)| {
            let v: Vec<(f64, f64)> = (0..pairs).map(f).collect();
            let (ma, mb) = v
                .iter()
                .fold((0.0, 0.0), |s, p| (s.0 + p.0.ln(), s.1 + p.1.ln()));
            let (ma, mb) = (ma / pairs as f64, mb / pairs as f64);
            let cov: f64 = v.iter().map(|p| (p.0.ln() - ma) * (p.1.ln() - mb)).sum();
            cov / pairs as f64 / 0.16
        };
        let near = corr(&|i| (ON.factor(i, true, 3.0), ON.factor(i, true, 4.0)));
        let far = corr(&|i| {
            (
                ON.factor(i, true, 3.0),
                ON.factor(i, true, 3.0 + 10.0 * 16.0),
            )
        });
        let across = corr(&|i| (ON.factor(i, true, 3.0), ON.factor(i + 1, true, 3.0)));
        let family = corr(&|i| (ON.factor(i, true, 3.0), ON.factor(i, false, 3.0)));
        assert!(near > 0.95, "one cell apart: correlation {near}");
        for (what, c) in [("far", far), ("across", across), ("families", family)] {
            assert!(c.abs() < 0.03, "{what}: correlation {c}");
        }
    }

    #[test]
    fn inactive_is_exactly_one_and_bad_parameters_are_refused() {
        let off = Irregularity::default();
        assert!(!off.is_active());
        assert_eq!(off.factor(12, true, 3.7), 1.0);
        assert!(off.validate().is_ok() && ON.validate().is_ok());
        let warp_only = Irregularity {
            spread: [0.0, 0.4],
            ..ON
        };
        assert!(warp_only.is_active());
        assert_eq!(warp_only.factor(12, false, 3.7), 1.0);
        assert_ne!(warp_only.factor(12, true, 3.7), 1.0);
        for (bad, name) in [
            (
                Irregularity {
                    spread: [0.2, -0.1],
                    ..ON
                },
                "irregularity",
            ),
            (
                Irregularity {
                    spread: [f64::NAN, 0.2],
                    ..ON
                },
                "irregularity",
            ),
            (
                Irregularity {
                    spread: [1.5, 0.0],
                    ..ON
                },
                "irregularity",
            ),
            (Irregularity { length: 0.5, ..ON }, "irregularity_length"),
            (
                Irregularity {
                    length: f64::INFINITY,
                    ..ON
                },
                "irregularity_length",
            ),
        ] {
            let e = bad.validate().unwrap_err().to_string();
            assert!(e.contains(name), "{bad:?}: {e}");
        }
        for along in [f64::MAX, -1e300, 1e15] {
            let m = ON.factor(i64::MAX, false, along);
            assert!(m.is_finite() && m > 0.0, "at {along}: {m}");
        }
    }
}
