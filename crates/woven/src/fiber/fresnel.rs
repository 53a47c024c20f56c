//! Unpolarized dielectric Fresnel reflectance and the refractive index (docs/spec.md §1.1, §3).

use crate::error::{check_range, Error, Result};

/// Unpolarized reflectance `(r_s² + r_p²)/2` of a dielectric of relative index `eta` (> 0),
/// for light arriving at `cos_theta` (in `[0, 1]`) from the outside — the paper's `|F|²`.
///
/// Total internal reflection (possible only for `eta < 1`) returns 1.
///
/// ```
/// use woven::fiber::fresnel_dielectric;
/// // Normal incidence: ((η − 1)/(η + 1))² = 0.04 for η = 1.5.
/// assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-15);
/// ```
#[inline]
pub fn fresnel_dielectric(cos_theta: f64, eta: f64) -> f64 {
    let c = cos_theta.clamp(0.0, 1.0);
    // Snell: η² cos²θt = η² − sin²θi.
    let g2 = eta * eta - 1.0 + c * c;
    if g2 <= 0.0 {
        return 1.0;
    }
    let g = g2.sqrt();
    // r_s = (c − g)/(c + g); r_p = (η² c − g)/(η² c + g) (with g = η cos θt).
    let rs = (c - g) / (c + g);
    let e2c = eta * eta * c;
    let rp = (e2c - g) / (e2c + g);
    0.5 * (rs * rs + rp * rp)
}

/// The fiber's refractive index: a constant, or Cauchy's dispersion `η(λ) = A + B/λ²`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(untagged, deny_unknown_fields))]
pub enum Ior {
    /// A wavelength-independent index.
    Constant(f64),
    /// Cauchy's two-term dispersion; `λ` in nanometres.
    Cauchy {
        /// `A` (dimensionless).
        cauchy_a: f64,
        /// `B` in nm².
        cauchy_b_nm2: f64,
    },
}

impl Ior {
    /// The index at wavelength `lambda_nm`.
    ///
    /// ```
    /// use woven::fiber::Ior;
    /// let ior = Ior::Cauchy { cauchy_a: 1.5, cauchy_b_nm2: 5000.0 };
    /// assert!((ior.at(500.0) - 1.52).abs() < 1e-12);
    /// ```
    pub fn at(&self, lambda_nm: f64) -> f64 {
        match *self {
            Ior::Constant(eta) => eta,
            Ior::Cauchy {
                cauchy_a,
                cauchy_b_nm2,
            } => cauchy_a + cauchy_b_nm2 / (lambda_nm * lambda_nm),
        }
    }

    /// Checks that the index lies in `[1, 4]` over the visible range (380–780 nm).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `fiber.eta` (or its Cauchy coefficients).
    pub fn validate(&self) -> Result<()> {
        match *self {
            Ior::Constant(eta) => check_range("fiber.eta", eta, 1.0, 4.0).map(|_| ()),
            Ior::Cauchy {
                cauchy_a,
                cauchy_b_nm2,
            } => {
                check_range("fiber.eta.cauchy_a", cauchy_a, 1.0, 4.0)?;
                check_range("fiber.eta.cauchy_b_nm2", cauchy_b_nm2, 0.0, 1.0e6)?;
                for lambda in [380.0, 780.0] {
                    let eta = self.at(lambda);
                    if !(1.0..=4.0).contains(&eta) {
                        return Err(Error::invalid(
                            "fiber.eta",
                            format!("{eta} at {lambda} nm"),
                            "an index in [1, 4] over 380-780 nm",
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// The index at `lambda_nm`, checked to lie in `[1, 4]` there too: [`validate`](Self::validate)
    /// checks a Cauchy index over the visible range only, and `B/λ²` grows fast below it.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `fiber.eta`, the index and the wavelength.
    pub fn checked_at(&self, lambda_nm: f64) -> Result<f64> {
        let eta = self.at(lambda_nm);
        if eta.is_finite() && (1.0..=4.0).contains(&eta) {
            Ok(eta)
        } else {
            Err(Error::invalid(
                "fiber.eta",
                format!("{eta} at {lambda_nm} nm"),
                "an index in [1, 4] at the wavelength evaluated",
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_matches_closed_form() {
        for eta in [1.0, 1.33, 1.5, 1.6, 2.4] {
            let r = ((eta - 1.0) / (eta + 1.0)) * ((eta - 1.0) / (eta + 1.0));
            assert!(
                (fresnel_dielectric(1.0, eta) - r).abs() < 1e-15,
                "eta {eta}"
            );
        }
    }

    #[test]
    fn brewster_angle_leaves_only_s_polarization() {
        let eta: f64 = 1.55;
        let tb = eta.atan();
        let c = tb.cos();
        // At Brewster r_p = 0, so F = r_s²/2 with r_s = (cos θi − η cos θt)/(cos θi + η cos θt).
        let ct = (1.0 - (tb.sin() / eta).powi(2)).sqrt();
        let rs = (c - eta * ct) / (c + eta * ct);
        let f = fresnel_dielectric(c, eta);
        assert!(
            (f - 0.5 * rs * rs).abs() < 1e-14,
            "{f} vs {}",
            0.5 * rs * rs
        );
        // And F is 1 at grazing incidence.
        assert!((fresnel_dielectric(0.0, eta) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn total_internal_reflection_for_eta_below_one() {
        assert_eq!(fresnel_dielectric(0.1, 0.7), 1.0);
    }
}
