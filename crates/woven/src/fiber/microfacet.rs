//! The Beckmann distribution and the corrected Smith shadowing term (paper Eq. (10); docs/spec.md §1.1–1.2),
//! and drawing Beckmann normals (with the density of the direction they reflect).

use crate::math::basis::orthonormal_basis;
use crate::math::special::{erfc, erfcx, exp_neg, exp_neg_sq, sin_cos, FRAC_1_SQRT_PI};
use crate::math::Vec3;
use std::f64::consts::PI;

/// Beckmann distribution `D_B(h) = exp(−tan²θ_h/α²) / (π α² cos⁴θ_h)` for `cos_theta_h > 0`,
/// else 0. Normalized so that `∫ D_B cos θ_h dω_h = 1`.
///
/// ```
/// use woven::fiber::beckmann_d;
/// // At the peak, D_B = 1/(π α²).
/// assert!((beckmann_d(1.0, 0.5) - 1.0 / (std::f64::consts::PI * 0.25)).abs() < 1e-15);
/// ```
#[inline]
pub fn beckmann_d(cos_theta_h: f64, alpha: f64) -> f64 {
    if cos_theta_h <= 0.0 {
        return 0.0;
    }
    let c2 = cos_theta_h * cos_theta_h;
    let tan2 = (1.0 - c2).max(0.0) / c2;
    let a2 = alpha * alpha;
    exp_neg(tan2 / a2) / (std::f64::consts::PI * a2 * c2 * c2)
}

/// Smith's `Λ(a) = ½ (exp(−a²)/(a√π) − erfc(a))` for a Gaussian (Beckmann) surface, `a > 0`.
///
/// Implements the corrected `Λ` of Eq. (10): the transcription drops `exp(−a²)` (docs/spec.md §1.2).
#[inline]
pub fn smith_lambda(a: f64) -> f64 {
    // Beyond a = 26 both terms underflow far below any use (exp(−676) ≈ 1e−294).
    if a >= 26.0 {
        return 0.0;
    }
    0.5 * ((-a * a).exp() * FRAC_1_SQRT_PI / a - erfc(a))
}

/// The per-direction shadowing factor `S1(θ) = (1 − ½ erfc(a)) / (1 + Λ(a))`, `a = cot θ / α`.
///
/// Implements Eq. (10) as corrected by docs/spec.md §1.2 (the paper's extra `(1 − ½ erfc a)`
/// factor is kept). Takes `cos θ ∈ [0, 1]`; `S1 = 1` at normal incidence and 0 at grazing, with
/// no NaN or infinity at either end.
///
/// ```
/// use woven::fiber::smith_s1;
/// assert_eq!(smith_s1(1.0, 0.3), 1.0);
/// assert_eq!(smith_s1(0.0, 0.3), 0.0);
/// ```
#[inline]
pub fn smith_s1(cos_theta: f64, alpha: f64) -> f64 {
    if cos_theta <= 0.0 {
        return 0.0;
    }
    // For a ≥ 6, ½ erfc(a) < 1.1e−17 and 0 ≤ Λ(a) < 1e−18 sit below half an ulp of 1, so the
    // quotient rounds to exactly 1: skip the two erfc and exp calls (most of a smooth fiber's
    // calls). a = cos θ/(α sin θ) ≥ 6 ⇔ cos²θ ≥ 36 α² sin²θ = 36 α² (1 − cos²θ), tested so, before
    // the square root and the division that make a (sin θ = 0 passes too).
    // (A NaN cosine takes the shortcut too, as it did when the test was a ≥ 6.)
    let c2 = cos_theta * cos_theta;
    let k = S1_SATURATES * S1_SATURATES * alpha * alpha;
    if c2 * (1.0 + k) >= k || c2.is_nan() {
        return 1.0;
    }
    let sin_theta = (1.0 - c2).max(0.0).sqrt();
    let a = cos_theta / (sin_theta * alpha);
    // erfc(a) = e^{−a²} erfcx(a) and Λ(a) = ½ e^{−a²} (1/(a√π) − erfcx(a)): one exponential and
    // one series for both (a ∈ (0, 6) here, the series' range).
    let e = exp_neg_sq(a);
    let q = erfcx(a);
    let lambda = 0.5 * e * (FRAC_1_SQRT_PI / a - q);
    (1.0 - 0.5 * e * q) / (1.0 + lambda)
}

/// `a` beyond which [`smith_s1`] is exactly 1 in `f64`.
const S1_SATURATES: f64 = 6.0;

/// A Beckmann microfacet normal of width `alpha` about `n`, drawn ∝ `D(h) (h·n)`.
#[inline]
pub(crate) fn sample_beckmann(n: Vec3, alpha: f64, [u1, u2]: [f64; 2]) -> Vec3 {
    let tan2 = -alpha * alpha * (1.0 - u1).max(1e-300).ln();
    let cos = 1.0 / (1.0 + tan2).sqrt();
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    let (t, b) = orthonormal_basis(n);
    let (sp, cp) = sin_cos(phi);
    (t * (sin * cp) + b * (sin * sp) + n * cos).normalize()
}

/// The density of the direction `drawn` reflected from `known` about a Beckmann normal of width
/// `alpha` about `n` (drawn by [`sample_beckmann`]): `D(h) (h·n) / (4 |drawn·h|)`.
#[inline]
pub(crate) fn beckmann_reflection_pdf(known: Vec3, drawn: Vec3, n: Vec3, alpha: f64) -> f64 {
    let h = (known + drawn).normalize();
    let (cos, dh) = (h.dot(n), drawn.dot(h));
    if cos <= 0.0 || dh <= 0.0 || !cos.is_finite() {
        return 0.0;
    }
    let c2 = cos * cos;
    let tan2 = (1.0 - c2) / c2;
    let d = exp_neg(tan2 / (alpha * alpha)) / (PI * alpha * alpha * c2 * c2);
    d * cos / (4.0 * dh)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `smith_s1` is exactly 1 where `a = cot θ / α ≥ 6` (its shortcut, taken without forming
    /// `a`), and below it is the series written out, to an ulp: a shortcut firing anywhere
    /// below `a` = 6 by more than rounding (where ½ erfc(a) > 1e−16) would fail.
    #[test]
    fn smith_shortcut_matches_its_threshold() {
        let series = |a: f64| {
            let (e, q) = (exp_neg_sq(a), erfcx(a));
            (1.0 - 0.5 * e * q) / (1.0 + 0.5 * e * (FRAC_1_SQRT_PI / a - q))
        };
        for alpha in [0.01, 0.1, 0.577, 2.0] {
            for k in 1..20_000 {
                let c = k as f64 / 20_000.0;
                let a = c / ((1.0 - c * c).sqrt() * alpha);
                let s = smith_s1(c, alpha);
                if a >= 6.0 * (1.0 + 1e-12) {
                    assert_eq!(s, 1.0, "alpha {alpha} cos {c}: a = {a}");
                } else {
                    let want = series(a);
                    assert!(
                        (s - want).abs() <= 2.3e-16,
                        "alpha {alpha} cos {c}: {s} vs {want}"
                    );
                }
            }
            assert_eq!(smith_s1(1.0, alpha), 1.0);
            assert_eq!(smith_s1(1.0 + 1e-12, alpha), 1.0);
            assert_eq!(smith_s1(f64::NAN, alpha), 1.0);
        }
    }

    #[test]
    fn beckmann_projected_area_is_one() {
        // ∫ D cosθh dω = 2π ∫_0^{π/2} D cos sin dθ.
        for alpha in [0.05, 0.2, 0.7] {
            let i = crate::math::quadrature::adaptive(
                0.0,
                std::f64::consts::FRAC_PI_2,
                1e-12,
                0.0,
                40,
                |t: f64| beckmann_d(t.cos(), alpha) * t.cos() * t.sin(),
            ) * 2.0
                * std::f64::consts::PI;
            assert!((i - 1.0).abs() < 1e-9, "alpha {alpha}: {i}");
        }
    }

    #[test]
    fn reflected_beckmann_density_integrates_to_one() {
        // Seen along the normal every drawn normal reflects the view to some direction, and the
        // reflection's Jacobian is exact: over the whole sphere the density integrates to 1.
        let n = Vec3::new(0.0, 0.0, 1.0);
        for alpha in [0.05, 0.2, 0.7] {
            let i = crate::math::quadrature::adaptive(0.0, PI, 1e-12, 0.0, 40, |t: f64| {
                beckmann_reflection_pdf(n, Vec3::from_spherical(t, 0.3), n, alpha) * t.sin()
            }) * 2.0
                * PI;
            assert!((i - 1.0).abs() < 1e-6, "alpha {alpha}: {i}");
        }
    }

    #[test]
    fn drawn_normals_are_unit_and_about_n() {
        let n = Vec3::new(0.3, -0.2, 0.9).normalize();
        for k in 0..256 {
            let u = [
                (k as f64 + 0.5) / 256.0,
                ((k * 97 % 256) as f64 + 0.5) / 256.0,
            ];
            let h = sample_beckmann(n, 0.3, u);
            assert!(
                (h.length() - 1.0).abs() < 1e-12 && h.dot(n) > 0.0,
                "{u:?}: {h:?}"
            );
        }
    }

    #[test]
    fn s1_is_monotone_and_bounded() {
        let alpha = 0.2;
        let mut prev = 1.0;
        for k in 0..=1000 {
            let theta = k as f64 / 1000.0 * std::f64::consts::FRAC_PI_2;
            let s = smith_s1(theta.cos(), alpha);
            assert!(s.is_finite() && (0.0..=1.0).contains(&s), "{theta}: {s}");
            assert!(s <= prev + 1e-15, "not monotone at {theta}");
            prev = s;
        }
    }

    #[test]
    fn s1_short_cut_changes_no_bit() {
        // The formula itself already rounds to 1 from a = 6 on, so skipping it changes nothing.
        for k in 0..=2000 {
            let a = S1_SATURATES + k as f64 * 0.01;
            assert_eq!(
                (1.0 - 0.5 * erfc(a)) / (1.0 + smith_lambda(a)),
                1.0,
                "a {a}"
            );
        }
        // ...and just below the cut it is not yet 1, so the cut is not hiding a real drop.
        let a = 5.5;
        assert!((1.0 - 0.5 * erfc(a)) / (1.0 + smith_lambda(a)) < 1.0);
    }

    /// The shared-exponential form equals Eq. (10) written with `libm`'s `erfc` and `exp` to a
    /// few ulp, from grazing to the saturation cut.
    #[test]
    fn s1_matches_the_formula_with_libm() {
        for alpha in [0.01, 0.1, 0.4, 4.0] {
            for k in 1..=4000 {
                let c = k as f64 / 4000.0;
                let s = (1.0 - c * c).sqrt();
                if s == 0.0 {
                    continue;
                }
                let a = c / (s * alpha);
                let lambda = 0.5 * ((-a * a).exp() * FRAC_1_SQRT_PI / a - libm::erfc(a));
                let want = (1.0 - 0.5 * libm::erfc(a)) / (1.0 + lambda);
                let got = smith_s1(c, alpha);
                assert!(
                    (got - want).abs() <= 4e-15 * want,
                    "α {alpha} cos θ {c}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn s1_near_grazing_is_linear_in_cot() {
        // For a → 0, Λ ≈ 1/(2a√π), so S1 ≈ a√π.
        let alpha = 0.3;
        let c = 1e-7;
        let a = c / alpha;
        let s = smith_s1(c, alpha);
        assert!(
            (s / (a * std::f64::consts::PI.sqrt()) - 1.0).abs() < 1e-5,
            "{s}"
        );
    }

    #[test]
    fn lambda_matches_walter_form() {
        // Walter et al. (2007) eq. 27: Λ(a) = (erf(a) − 1)/2 + exp(−a²)/(2a√π).
        for a in [0.01, 0.3, 1.0, 2.5, 6.0] {
            let w = (libm::erf(a) - 1.0) / 2.0
                + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt());
            assert!((smith_lambda(a) - w).abs() < 1e-14, "a {a}");
        }
    }
}
