//! The yarn: arc-topped prism cross-sections, their exact masking, and the distributions of
//! slopes and twist (paper §3; MODEL.md §2.1–§2.6).
//!
//! | parameter | symbol | meaning | unit | default | valid range |
//! |---|---|---|---|---|---|
//! | `lateral_length` | `L` | length of each lateral (arc radius 1) | — | required | `[0, 1e6]` |
//! | `slope_mean` | `μ` | mean lateral slope | rad | required | `[0, π/2]` |
//! | `slope_std` | `σ` | spread of slopes; 0 = the single profile `θ_a = μ` | rad | 0 | `[0, π]` |
//! | `interreflection` | `ħ` | weight of the interreflection term | — | 0 | `[0, 1]` |
//! | `interreflection_albedo` | `ρ` | its albedo (the term is `ħρ/π`) | — | 0 | `[0, 1]` |
//! | `twist_std` | `σ_t` | spread of fiber azimuths about the yarn axis | rad | 0 | `[0, π]` |
//! | `isotropic` | — | fibers in all azimuths, Eq. (22) | — | false | excludes `twist_std > 0` |

mod cross_section;
pub mod profile;
pub mod raycast;
mod slope;

pub use cross_section::CrossSection;
pub use slope::SlopeDistribution;

use crate::error::{check_range, Error, Result};
use crate::fiber::Fiber;
use crate::math::quadrature::adaptive;
use crate::math::Vec3;
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI};

/// Relative tolerance of the twist and isotropic averages over fiber azimuth.
const AZIMUTH_TOL: f64 = 1e-5;

/// The user-facing yarn parameters (the `[yarn]` table of a material file).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct YarnParams {
    /// `L`, lateral length in arc radii.
    pub lateral_length: f64,
    /// `μ`, mean lateral slope, radians.
    pub slope_mean: f64,
    /// `σ`, spread of lateral slopes, radians (0: one profile).
    pub slope_std: f64,
    /// `ħ ∈ [0, 1]`.
    pub interreflection: f64,
    /// `ρ ∈ [0, 1]`.
    pub interreflection_albedo: f64,
    /// `σ_t`, twist spread, radians.
    pub twist_std: f64,
    /// Eq. (22): fibers uniformly in all azimuths.
    pub isotropic: bool,
}

impl Default for YarnParams {
    fn default() -> Self {
        YarnParams {
            lateral_length: 0.0,
            slope_mean: 0.0,
            slope_std: 0.0,
            interreflection: 0.0,
            interreflection_albedo: 0.0,
            twist_std: 0.0,
            isotropic: false,
        }
    }
}

impl YarnParams {
    /// Checks every parameter against its valid range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first offending key.
    pub fn validate(&self) -> Result<()> {
        check_range("yarn.lateral_length", self.lateral_length, 0.0, 1e6)?;
        check_range("yarn.slope_mean", self.slope_mean, 0.0, FRAC_PI_2)?;
        check_range("yarn.slope_std", self.slope_std, 0.0, PI)?;
        check_range("yarn.interreflection", self.interreflection, 0.0, 1.0)?;
        check_range("yarn.interreflection_albedo", self.interreflection_albedo, 0.0, 1.0)?;
        check_range("yarn.twist_std", self.twist_std, 0.0, PI)?;
        if self.isotropic && self.twist_std > 0.0 {
            return Err(Error::invalid(
                "yarn.twist_std",
                self.twist_std,
                "no twist_std with isotropic = true (Eq. (22) already spreads fibers over all azimuths)",
            ));
        }
        if self.slope_std == 0.0 && self.slope_mean >= FRAC_PI_2 - 1e-12 && self.lateral_length > 0.0 {
            return Err(Error::invalid(
                "yarn.slope_mean",
                self.slope_mean,
                "a slope below π/2 when lateral_length > 0 (vertical laterals are slits of zero width; MODEL.md §2.1)",
            ));
        }
        Ok(())
    }
}

/// A yarn ready to evaluate: fiber, slope distribution and twist.
#[derive(Clone, Debug)]
pub struct Yarn {
    fiber: Fiber,
    params: YarnParams,
    slopes: SlopeDistribution,
    /// Normalization of the twist density on `[−π/2, π/2]` (0 without twist).
    twist_norm: f64,
}

impl Yarn {
    /// Builds a yarn of `fiber` with `params`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an out-of-range parameter.
    pub fn new(fiber: Fiber, params: YarnParams) -> Result<Self> {
        params.validate()?;
        let slopes = SlopeDistribution::new(params.slope_mean, params.slope_std);
        let twist_norm = if params.twist_std > 0.0 {
            let st = params.twist_std;
            let shape = |d: f64| (-d * d / (2.0 * st * st)).exp();
            1.0 / (2.0 * adaptive(0.0, FRAC_PI_2, 1e-13, 0.0, 40, shape))
        } else {
            0.0
        };
        Ok(Yarn {
            fiber,
            params,
            slopes,
            twist_norm,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &YarnParams {
        &self.params
    }

    /// The fiber.
    pub fn fiber(&self) -> &Fiber {
        &self.fiber
    }

    /// The profile BRDF `f_p` (Eq. (17), exact masking; MODEL.md §2.3) of the single profile of
    /// slope `theta_a` with this yarn's lateral length, fibers at azimuth `phi_a`.
    pub fn profile_brdf(&self, s: Vec3, v: Vec3, phi_a: f64, theta_a: f64) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        CrossSection::new(&self.fiber, s, v, phi_a).profile_brdf(&profile::Profile {
            theta_a,
            lateral_length: self.params.lateral_length,
        })
    }

    /// `f_θ` (Eq. (18)): the slope-averaged BRDF of fibers at azimuth `phi_a`, before
    /// interreflection.
    pub fn slope_averaged(&self, s: Vec3, v: Vec3, phi_a: f64) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        CrossSection::new(&self.fiber, s, v, phi_a).slope_average(&self.slopes, self.params.lateral_length)
    }

    /// `f_ir` (Eq. (20); MODEL.md §2.5) for fibers at azimuth `phi_a`:
    /// `(1 − ħ) f_θ + ħ ρ / π`.
    pub fn eval_oriented(&self, s: Vec3, v: Vec3, phi_a: f64) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let p = &self.params;
        (1.0 - p.interreflection) * self.slope_averaged(s, v, phi_a)
            + p.interreflection * p.interreflection_albedo * FRAC_1_PI
    }

    /// The yarn BRDF for a yarn whose axis has azimuth `phi_y` (Eqs. (20)–(22); MODEL.md §2.6):
    /// one orientation, the twist average, or the isotropic average.
    pub fn eval(&self, s: Vec3, v: Vec3, phi_y: f64) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let p = &self.params;
        let f_theta = if p.isotropic {
            // (1/π) ∫ over one period of φ_a (f is π-periodic in φ_a).
            self.azimuth_average(s, v, phi_y - FRAC_PI_2, |_| FRAC_1_PI)
        } else if p.twist_std > 0.0 {
            let (st, norm) = (p.twist_std, self.twist_norm);
            self.azimuth_average(s, v, phi_y - FRAC_PI_2, move |phi_a: f64| {
                let d = phi_a - phi_y;
                norm * (-d * d / (2.0 * st * st)).exp()
            })
        } else {
            self.slope_averaged(s, v, phi_y)
        };
        (1.0 - p.interreflection) * f_theta + p.interreflection * p.interreflection_albedo * FRAC_1_PI
    }

    /// `∫_{start}^{start+π} w(φ_a) f_θ(φ_a) dφ_a`, split where `f_θ` kinks or peaks in `φ_a`
    /// (MODEL.md §2.4): where `ψ_s = 0`, `ψ_v = 0`, `ψ_s = ±ψ_v`, and around the orientation whose
    /// cross-section contains the half vector (the highlight, of width `≈ α/|ĥ_xy|`).
    fn azimuth_average(&self, s: Vec3, v: Vec3, start: f64, weight: impl Fn(f64) -> f64) -> f64 {
        // An azimuth where e_u ⊥ d (d horizontal): φ_a = azimuth(d) (e_u = (−sin φ_a, cos φ_a)).
        let perp = |d: Vec3| d.y.atan2(d.x);
        let mut breaks = vec![
            perp(s),
            perp(v),
            perp(s * (1.0 / s.z) - v * (1.0 / v.z)),
            perp(s * (1.0 / s.z) + v * (1.0 / v.z)),
        ];
        let h = (s + v).normalize();
        let hxy = (h.x * h.x + h.y * h.y).sqrt();
        if hxy > 1e-9 {
            // The highlight: e_f ⊥ h, i.e. e_u ∥ h_xy: φ_a = azimuth(h) − π/2.
            let c = h.y.atan2(h.x) - FRAC_PI_2;
            let w = (self.fiber.lobe_width(0.0) / hxy).min(0.5);
            for k in [-6.0, -3.0, -1.5, 0.0, 1.5, 3.0, 6.0] {
                breaks.push(c + k * w);
            }
        }
        if !self.params.isotropic && self.params.twist_std > 0.0 && self.params.twist_std < 0.3 {
            let c = start + FRAC_PI_2;
            for k in [-3.0, -1.0, 1.0, 3.0] {
                breaks.push(c + k * self.params.twist_std);
            }
        }
        // Reduce every break into [start, start + π) (f is π-periodic in φ_a).
        let mut edges: Vec<f64> = breaks
            .into_iter()
            .filter(|b| b.is_finite())
            .map(|b| start + (b - start).rem_euclid(PI))
            .collect();
        edges.push(start);
        edges.push(start + PI);
        edges.sort_by(f64::total_cmp);
        edges.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        let mut total = 0.0;
        for e in edges.windows(2) {
            total += adaptive(e[0], e[1], AZIMUTH_TOL, 1e-12, 16, |phi_a| {
                weight(phi_a) * self.slope_averaged(s, v, phi_a)
            });
        }
        total
    }
}
