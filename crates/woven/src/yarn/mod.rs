//! The yarn: arc-topped prism cross-sections, their exact masking, and the distributions of
//! slopes and twist (paper §3; docs/spec.md §2.1–§2.6).
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
pub mod float;
mod orientation;
pub mod point;
pub mod profile;
pub mod raycast;
mod slope;
mod window;

pub use cross_section::{CrossSection, FiberParts, Masking};
pub use orientation::{Orientation, TwistDensity};
pub use slope::SlopeDistribution;
pub use window::NARROW_STD;

use crate::error::{check_range, Error, Result};
use crate::fiber::Fiber;
use crate::fiber::FiberFrame;
use crate::math::quadrature::GaussLegendre;
use crate::math::Vec3;
use crate::model::AffineBrdf;
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI};

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
    /// An extension beyond the paper (docs/model.md §8, "Tilt"): the tilt of each float's axis
    /// out of the cloth plane where it rises and dips, radians in `[0, 80°]`. The cloth's BRDF is
    /// then each family's whole-float average ([`FloatProfile::average`](float::FloatProfile::average));
    /// 0 (the default): flat floats, the paper's model exactly.
    pub u_max: f64,
    /// With [`u_max`](Self::u_max) `> 0`, the share of each float's length lying flat on top
    /// (another extension, [`FloatProfile::shaped`](float::FloatProfile::shaped)); 0: the tilt
    /// falls linearly along the whole float.
    pub float_crest: f64,
    /// With [`u_max`](Self::u_max) `> 0`, the share of each float's length at its full tilt, at
    /// each end ([`FloatProfile::shaped`](float::FloatProfile::shaped)).
    pub float_flank: f64,
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
            u_max: 0.0,
            float_crest: 0.0,
            float_flank: 0.0,
        }
    }
}

/// The largest [`YarnParams::float_crest`] `+ 2` [`YarnParams::float_flank`]: the float turns
/// over at least a tenth of its length.
pub const MAX_FLOAT_SHAPE: f64 = 0.9;

impl YarnParams {
    /// The floats' profile along their length, `None` for the paper's flat floats (`u_max = 0`).
    pub fn float_profile(&self) -> Option<float::FloatProfile> {
        (self.u_max > 0.0)
            .then(|| float::FloatProfile::shaped(self.u_max, self.float_crest, self.float_flank))
    }

    /// Checks every parameter against its valid range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first offending key.
    pub fn validate(&self) -> Result<()> {
        check_range("yarn.lateral_length", self.lateral_length, 0.0, 1e6)?;
        check_range("yarn.slope_mean", self.slope_mean, 0.0, FRAC_PI_2)?;
        check_range("yarn.slope_std", self.slope_std, 0.0, PI)?;
        check_range("yarn.interreflection", self.interreflection, 0.0, 1.0)?;
        check_range(
            "yarn.interreflection_albedo",
            self.interreflection_albedo,
            0.0,
            1.0,
        )?;
        check_range("yarn.twist_std", self.twist_std, 0.0, PI)?;
        check_range(
            "yarn.u_max_deg",
            self.u_max.to_degrees(),
            0.0,
            crate::surface::MAX_U_MAX_DEG,
        )?;
        check_range("yarn.float_crest", self.float_crest, 0.0, MAX_FLOAT_SHAPE)?;
        check_range(
            "yarn.float_flank",
            self.float_flank,
            0.0,
            MAX_FLOAT_SHAPE / 2.0,
        )?;
        if self.float_crest + 2.0 * self.float_flank > MAX_FLOAT_SHAPE {
            return Err(Error::invalid(
                "yarn.float_flank",
                self.float_flank,
                format!(
                    "float_crest + 2 float_flank ≤ {MAX_FLOAT_SHAPE} (float_crest is {})",
                    self.float_crest
                ),
            ));
        }
        if self.u_max == 0.0 && (self.float_crest > 0.0 || self.float_flank > 0.0) {
            let (key, value) = if self.float_crest > 0.0 {
                ("yarn.float_crest", self.float_crest)
            } else {
                ("yarn.float_flank", self.float_flank)
            };
            return Err(Error::invalid(
                key,
                value,
                "0 unless the floats are tilted (u_max_deg > 0): a flat float has no shape",
            ));
        }
        if self.isotropic && self.twist_std > 0.0 {
            return Err(Error::invalid(
                "yarn.twist_std",
                self.twist_std,
                "no twist_std with isotropic = true (Eq. (22) already spreads fibers over all azimuths)",
            ));
        }
        if self.slope_std == 0.0
            && self.slope_mean >= FRAC_PI_2 - 1e-12
            && self.lateral_length > 0.0
        {
            return Err(Error::invalid(
                "yarn.slope_mean",
                self.slope_mean,
                "a slope below π/2 when lateral_length > 0 (vertical laterals are slits of zero width; docs/spec.md §2.1)",
            ));
        }
        Ok(())
    }
}

/// Quadrature orders of the yarn averages (docs/spec.md §2.4, §2.6): Gauss–Legendre nodes per panel
/// of the slope integral and of the fiber-azimuth integral. The defaults converge every average
/// to ≤ 1e-4 relative (tested by doubling them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Quadrature {
    /// Nodes per panel in `θ_a` (Eq. (18)).
    pub slope_nodes: usize,
    /// Nodes per panel in `φ_a` (Eqs. (21)–(22)).
    pub azimuth_nodes: usize,
    /// Nodes per panel in `φ_a` when light or viewer is beyond [`GRAZING_THETA`] (masking makes
    /// `f_θ(φ_a)` steeper there).
    pub azimuth_nodes_grazing: usize,
}

/// Polar angle (80°) beyond which the azimuth average uses
/// [`Quadrature::azimuth_nodes_grazing`].
pub const GRAZING_THETA: f64 = 80.0 * std::f64::consts::PI / 180.0;

/// Light or viewer this close to the horizon (`cos θ ≤ 1e-6`, θ > 89.99994°) gives a yarn BRDF
/// of 0: the profile BRDF divides by `s_z v_z`, which would amplify rounding without bound, and
/// the reflected radiance `f cos θ_i` is 0 to that precision anyway.
pub const HORIZON_COS: f64 = 1e-6;

impl Default for Quadrature {
    fn default() -> Self {
        Quadrature {
            slope_nodes: 6,
            azimuth_nodes: 6,
            azimuth_nodes_grazing: 10,
        }
    }
}

/// A yarn ready to evaluate: fiber, slope distribution and twist.
#[derive(Clone, Debug)]
pub struct Yarn {
    fiber: Fiber,
    params: YarnParams,
    slopes: SlopeDistribution,
    orientation: Orientation,
    quadrature: Quadrature,
    slope_rule: GaussLegendre,
    azimuth_rule: GaussLegendre,
    azimuth_rule_grazing: GaussLegendre,
}

impl Yarn {
    /// Builds a yarn of `fiber` with `params`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an out-of-range parameter.
    pub fn new(fiber: Fiber, params: YarnParams) -> Result<Self> {
        params.validate()?;
        let slopes = SlopeDistribution::new(params.slope_mean, params.slope_std);
        let orientation = Orientation::of(&params);
        let q = Quadrature::default();
        Ok(Yarn {
            fiber,
            params,
            slopes,
            orientation,
            quadrature: q,
            slope_rule: GaussLegendre::new(q.slope_nodes),
            azimuth_rule: GaussLegendre::new(q.azimuth_nodes),
            azimuth_rule_grazing: GaussLegendre::new(q.azimuth_nodes_grazing),
        })
    }

    /// The same yarn with other quadrature orders (for convergence studies).
    pub fn with_quadrature(mut self, q: Quadrature) -> Self {
        self.quadrature = q;
        self.slope_rule = GaussLegendre::new(q.slope_nodes.max(1));
        self.azimuth_rule = GaussLegendre::new(q.azimuth_nodes.max(1));
        self.azimuth_rule_grazing = GaussLegendre::new(q.azimuth_nodes_grazing.max(1));
        self
    }

    /// The quadrature orders in use.
    pub fn quadrature(&self) -> Quadrature {
        self.quadrature
    }

    /// The parameters.
    pub fn params(&self) -> &YarnParams {
        &self.params
    }

    /// The fiber.
    pub fn fiber(&self) -> &Fiber {
        &self.fiber
    }

    /// Whether the fibers of a yarn all share its axis (no twist, not isotropic).
    pub fn is_single_orientation(&self) -> bool {
        self.orientation == Orientation::Aligned
    }

    /// How the fibers are oriented about the yarn axis (Eqs. (21)–(22)).
    pub fn orientation(&self) -> &Orientation {
        &self.orientation
    }

    /// The distribution of lateral slopes (Eq. (19)).
    pub fn slopes(&self) -> &SlopeDistribution {
        &self.slopes
    }

    /// The interreflection mix of Eq. (20), `(1 − ħ) f_θ + weight · ħ ρ / π`: the yarn BRDF from
    /// its slope-averaged BRDF `f_theta` (already averaged over fiber azimuths and weighted by
    /// yarn weights summing to `weight`).
    ///
    /// Implements Eq. (20) of the paper; docs/spec.md §2.5.
    #[inline]
    pub fn interreflection_mix(&self, f_theta: f64, weight: f64) -> f64 {
        let p = &self.params;
        (1.0 - p.interreflection) * f_theta
            + weight * p.interreflection * p.interreflection_albedo * FRAC_1_PI
    }

    /// The directional albedo of Eq. (20)'s mix, `(1 − ħ) A_θ + weight · ħ ρ`, from the albedo
    /// `a_theta` of the slope-averaged BRDF (the Lambertian term `ρ/π` reflects `ρ`).
    ///
    /// Implements Eq. (20) of the paper integrated over the hemisphere; docs/spec.md §2.5, §6.2.
    #[inline]
    pub fn interreflection_mix_albedo(&self, a_theta: f64, weight: f64) -> f64 {
        let p = &self.params;
        (1.0 - p.interreflection) * a_theta + weight * p.interreflection * p.interreflection_albedo
    }

    /// The profile BRDF `f_p` (Eq. (17), exact masking; docs/spec.md §2.3) of the single profile of
    /// slope `theta_a` with this yarn's lateral length, fibers at azimuth `phi_a`.
    pub fn profile_brdf(&self, s: Vec3, v: Vec3, phi_a: f64, theta_a: f64) -> f64 {
        if s.z <= HORIZON_COS || v.z <= HORIZON_COS {
            return 0.0;
        }
        CrossSection::new(&self.fiber, s, v, phi_a, cross_section::FINE_PANELS).profile_brdf(
            &profile::Profile {
                theta_a,
                lateral_length: self.params.lateral_length,
            },
        )
    }

    /// `f_θ` (Eq. (18)): the slope-averaged BRDF of fibers at azimuth `phi_a`, before
    /// interreflection.
    ///
    /// Implements Eqs. (17)–(19) of the paper; docs/spec.md §2.3–§2.4.
    pub fn slope_averaged(&self, s: Vec3, v: Vec3, phi_a: f64) -> f64 {
        self.fiber
            .combine_parts(self.slope_averaged_parts(s, v, phi_a, Masking::Exact))
    }

    /// [`slope_averaged`](Self::slope_averaged) with masking and shadowing between facets switched
    /// off ([`Masking::Off`]): not the model, but the reference that measures how much masking it
    /// applies (the paper's Fig. 8). Equal to `slope_averaged` wherever nothing is masked.
    pub fn slope_averaged_unmasked(&self, s: Vec3, v: Vec3, phi_a: f64) -> f64 {
        self.fiber
            .combine_parts(self.slope_averaged_parts(s, v, phi_a, Masking::Off))
    }

    /// [`slope_averaged`](Self::slope_averaged) in the two parts the fiber BRDF is affine in
    /// ([`FiberParts`]; [`Fiber::combine_parts`] gives the value, [`Fiber::affine_in_diffuse`]
    /// the dependence on `ρ0`).
    pub fn slope_averaged_parts(
        &self,
        s: Vec3,
        v: Vec3,
        phi_a: f64,
        masking: Masking,
    ) -> FiberParts {
        if s.z <= HORIZON_COS || v.z <= HORIZON_COS {
            return [0.0, 0.0];
        }
        // Narrow slope distributions read the exact facet lobe near their mean (cross_section.rs),
        // so they sample it as finely as a single profile does.
        let panels = if self.slopes.single().is_some() || self.slopes.std() < NARROW_STD {
            cross_section::FINE_PANELS
        } else {
            cross_section::COARSE_PANELS
        };
        CrossSection::new(&self.fiber, s, v, phi_a, panels)
            .with_masking(masking)
            .slope_average(&self.slopes, self.params.lateral_length, &self.slope_rule)
    }

    /// `f_ir` (Eq. (20); docs/spec.md §2.5) for fibers at azimuth `phi_a`:
    /// `(1 − ħ) f_θ + ħ ρ / π`.
    pub fn eval_oriented(&self, s: Vec3, v: Vec3, phi_a: f64) -> f64 {
        if s.z <= HORIZON_COS || v.z <= HORIZON_COS {
            return 0.0;
        }
        self.interreflection_mix(self.slope_averaged(s, v, phi_a), 1.0)
    }

    /// The yarn BRDF for a yarn whose axis has azimuth `phi_y` (Eqs. (20)–(22); docs/spec.md §2.6):
    /// one orientation, the twist average, or the isotropic average.
    pub fn eval(&self, s: Vec3, v: Vec3, phi_y: f64) -> f64 {
        self.eval_mix(s, v, &[(phi_y, 1.0)])
    }

    /// `Σ_k w_k f_yarn(s, v; φ_k)` for yarn axes `φ_k` with weights `w_k` — the weave mix of
    /// Eq. (23) is `[(0, γ), (π/2, 1 − γ)]`. Twisted and isotropic yarns share one pass over the
    /// fiber azimuths: `f_θ(φ_a)` is π-periodic, and each yarn's twist window `φ_k ± π/2` is one
    /// whole period, so all the yarns' weights are applied to the same samples.
    pub fn eval_mix(&self, s: Vec3, v: Vec3, yarns: &[(f64, f64)]) -> f64 {
        self.eval_mix_with(s, v, yarns, Masking::Exact)
    }

    /// [`eval_mix`](Self::eval_mix) with masking and shadowing between facets switched off
    /// ([`Masking::Off`]; see [`slope_averaged_unmasked`](Self::slope_averaged_unmasked)).
    pub fn eval_mix_unmasked(&self, s: Vec3, v: Vec3, yarns: &[(f64, f64)]) -> f64 {
        self.eval_mix_with(s, v, yarns, Masking::Off)
    }

    fn eval_mix_with(&self, s: Vec3, v: Vec3, yarns: &[(f64, f64)], masking: Masking) -> f64 {
        let p = &self.params;
        self.eval_mix_affine(s, v, yarns, masking)
            .at(self.fiber.params().diffuse, p.interreflection_albedo)
    }

    /// [`eval_mix`](Self::eval_mix) (with `masking`) as the affine function of the fiber's
    /// diffuse albedo `ρ0` and the interreflection albedo `ρ` that it is (docs/spec.md §1.5,
    /// §2.5): one pass through the quadrature, each node carrying both parts of the fiber BRDF.
    ///
    /// Implements Eqs. (17)–(23) of the paper with the albedos left free.
    pub fn eval_mix_affine(
        &self,
        s: Vec3,
        v: Vec3,
        yarns: &[(f64, f64)],
        masking: Masking,
    ) -> AffineBrdf {
        if s.z <= HORIZON_COS || v.z <= HORIZON_COS {
            return AffineBrdf::default();
        }
        let total_weight: f64 = yarns.iter().map(|&(_, w)| w).sum();
        let f = |phi_a: f64| self.slope_averaged_parts(s, v, phi_a, masking);
        let f_theta: FiberParts = if self.is_single_orientation() {
            self.orientation.average(yarns, &[], &self.slope_rule, f)
        } else {
            let rule = if s.z.min(v.z) < GRAZING_THETA.cos() {
                &self.azimuth_rule_grazing
            } else {
                &self.azimuth_rule
            };
            self.orientation
                .average(yarns, &self.azimuth_breaks(s, v), rule, f)
        };
        // Eq. (20), (1 − ħ) f_θ + weight·ħ ρ/π, term by term.
        let (fixed, per_diffuse) = self.fiber.affine_in_diffuse(f_theta);
        let k = 1.0 - self.params.interreflection;
        AffineBrdf {
            fixed: k * fixed,
            per_diffuse: k * per_diffuse,
            per_interreflection: total_weight * self.params.interreflection * FRAC_1_PI,
        }
    }

    /// The fiber azimuths where `f_θ(φ_a)` kinks or peaks (docs/spec.md §2.4): where `ψ_s = 0`,
    /// `ψ_v = 0`, `ψ_s = ±ψ_v`, and around the orientation whose cross-section contains the half
    /// vector (the highlight, of width `≈ α/|ĥ_xy|`).
    fn azimuth_breaks(&self, s: Vec3, v: Vec3) -> Vec<f64> {
        let perp = FiberFrame::azimuth_across;
        let mut breaks: Vec<f64> = Vec::with_capacity(32);
        breaks.extend([
            perp(s),
            perp(v),
            perp(s * (1.0 / s.z) - v * (1.0 / v.z)),
            perp(s * (1.0 / s.z) + v * (1.0 / v.z)),
        ]);
        let h = (s + v).normalize();
        let hxy = (h.x * h.x + h.y * h.y).sqrt();
        let w = self.fiber.lobe_width(0.0) / hxy.max(1e-12);
        if w < 0.3 {
            // The highlight: e_f ⊥ h, i.e. e_u ∥ h_xy: φ_a = azimuth(h) − π/2.
            let c = h.y.atan2(h.x) - FRAC_PI_2;
            for k in [-6.0, -3.0, -1.5, 0.0, 1.5, 3.0, 6.0] {
                breaks.push(c + k * w);
            }
        }
        breaks
    }
}
