//! The fiber-surface BRDF of the paper's §2 (docs/spec.md §1).
//!
//! | parameter | meaning | unit | default | valid range |
//! |---|---|---|---|---|
//! | `model` | `rough` (Eq. (16'), docs/spec.md §1.3) or `htsg` (Eqs. (9)–(13), §1.4) | — | `rough` | — |
//! | `eta` | refractive index `η`, constant or Cauchy `A + B/λ²` | — | — | `[1, 4]` over 380–780 nm |
//! | `roughness` | `σ_h/τ` (rough model); Beckmann `α = 2σ_h/τ` | — | — | `[0.005, 2]` |
//! | `sigma_h_um` | rms height `σ_h` (htsg) | µm | — | `(0, 10]` |
//! | `tau_um` | autocorrelation length `τ` (htsg) | µm | — | `(0, 100]`, with `σ_h/τ ∈ [0.005, 2]` |
//! | `diffuse` | uniform diffuse albedo `ρ0` | — | 0 | `[0, 1)` |
//! | `normalization` | `paper` (β of §1.5) or `none` (β = 1) | — | `paper` | — |
//! | `body_gloss` | share of the body's light `ρ0` leaving in a glossy lobe (an extension) | — | 0 | `[0, 1]` |
//! | `body_roughness` | that lobe's `σ_h/τ` | — | required with `body_gloss > 0` | `[0.005, 2]` |
//!
//! The BRDF is `β(θ_i) F(θ_d) D_B(h) S(s, v) / (4 cos θ_i cos θ_r) + ρ0/π` in the rough limit
//! (Torrance–Sparrow with a Beckmann distribution and the paper's Smith term), and
//! `β F S G D / (π cos θ_i cos θ_r) + ρ0/π` plus a specular spike `R_sp` in the full model.

mod frame;
mod fresnel;
mod htsg;
mod microfacet;
mod normalization;

pub use frame::FiberFrame;
pub use fresnel::{fresnel_dielectric, Ior};
pub use htsg::series as htsg_series;
pub use microfacet::{beckmann_d, smith_lambda, smith_s1};
pub(crate) use microfacet::{beckmann_reflection_pdf, sample_beckmann};
pub use normalization::{
    beta_direct, rough_single_scattering, single_scattering_adaptive, BetaTable,
};

use crate::error::{check_range, Error, Result};
use crate::math::hemisphere::reflected_hemisphere_integral;
use crate::math::special::exp_neg;
use crate::math::Vec3;
use std::f64::consts::{FRAC_1_PI, PI};
use std::sync::Arc;

/// The default evaluation wavelength, nm.
pub const DEFAULT_WAVELENGTH_NM: f64 = 550.0;

/// The wavelengths a fiber is prepared at ([`Fiber::new`]), nm: 380–780 nm is the visible range.
pub const WAVELENGTH_RANGE_NM: [f64; 2] = [200.0, 2500.0];

/// Which fiber model and its roughness parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FiberModel {
    /// The rough limit (16') — Torrance–Sparrow/Beckmann with Beckmann `α = 2 σ_h/τ`.
    Rough {
        /// `σ_h/τ`, dimensionless.
        roughness: f64,
    },
    /// The full physical-optics model of He et al. (§1.4).
    Htsg {
        /// rms height `σ_h`, µm.
        sigma_h_um: f64,
        /// autocorrelation length `τ`, µm.
        tau_um: f64,
    },
}

impl FiberModel {
    /// `σ_h/τ`.
    pub fn roughness(&self) -> f64 {
        match *self {
            FiberModel::Rough { roughness } => roughness,
            FiberModel::Htsg { sigma_h_um, tau_um } => sigma_h_um / tau_um,
        }
    }

    /// Beckmann slope parameter `α = 2 σ_h / τ` (docs/spec.md §1.1).
    pub fn alpha(&self) -> f64 {
        2.0 * self.roughness()
    }
}

/// How the single-scattering lobe is scaled (docs/spec.md §1.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Normalization {
    /// `β = 1`: pure Torrance–Sparrow, reciprocal.
    None,
    /// `β(θ_i)` of Eq. (15) made precise: the lobe carries `1 − ρ0` of the energy before Fresnel.
    /// Not reciprocal.
    #[default]
    Paper,
}

/// The user-facing fiber parameters (the `[fiber]` table of a material file).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FiberParams {
    /// Model and roughness.
    pub model: FiberModel,
    /// Refractive index.
    pub eta: Ior,
    /// Uniform diffuse albedo `ρ0 ∈ [0, 1)`.
    pub diffuse: f64,
    /// Normalization mode.
    pub normalization: Normalization,
    /// An extension beyond the paper (docs/model.md §9, "Body gloss"): the share `g ∈ [0, 1]` of
    /// the body's light (the `ρ0` that enters the fiber and comes back out, dyed) that leaves in
    /// a glossy lobe about the mirror direction instead of diffusely, as light refracted through
    /// a smooth transparent filament does. 0 (the default): the paper's Lambertian body exactly.
    pub body_gloss: f64,
    /// The glossy body lobe's `σ_h/τ` (in `[0.005, 2]` when [`body_gloss`](Self::body_gloss)
    /// `> 0`; unused, and 0, otherwise).
    pub body_roughness: f64,
}

impl FiberParams {
    /// A rough-limit fiber with index `eta`, roughness `σ_h/τ`, diffuse albedo `ρ0`, `paper` mode.
    pub fn rough(eta: f64, roughness: f64, diffuse: f64) -> Self {
        FiberParams {
            model: FiberModel::Rough { roughness },
            eta: Ior::Constant(eta),
            diffuse,
            normalization: Normalization::Paper,
            body_gloss: 0.0,
            body_roughness: 0.0,
        }
    }

    /// The same parameters with another normalization mode.
    pub fn with_normalization(mut self, normalization: Normalization) -> Self {
        self.normalization = normalization;
        self
    }

    /// Checks every parameter against its valid range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first offending key.
    pub fn validate(&self) -> Result<()> {
        self.eta.validate()?;
        check_range("fiber.diffuse", self.diffuse, 0.0, 1.0 - 1e-12)
            .map_err(|_| Error::invalid("fiber.diffuse", self.diffuse, "a number in [0, 1)"))?;
        check_range("fiber.body_gloss", self.body_gloss, 0.0, 1.0)?;
        if self.body_gloss > 0.0 {
            check_range(
                "fiber.body_roughness",
                self.body_roughness,
                ROUGHNESS_MIN,
                ROUGHNESS_MAX,
            )?;
        } else if self.body_roughness != 0.0 {
            return Err(Error::invalid(
                "fiber.body_roughness",
                self.body_roughness,
                "0 (unused) unless body_gloss > 0",
            ));
        }
        match self.model {
            FiberModel::Rough { roughness } => {
                check_range("fiber.roughness", roughness, ROUGHNESS_MIN, ROUGHNESS_MAX)?;
            }
            FiberModel::Htsg { sigma_h_um, tau_um } => {
                if !(sigma_h_um > 0.0 && sigma_h_um <= 10.0) {
                    return Err(Error::invalid(
                        "fiber.sigma_h_um",
                        sigma_h_um,
                        "a length in µm in (0, 10]",
                    ));
                }
                if !(tau_um > 0.0 && tau_um <= 100.0) {
                    return Err(Error::invalid(
                        "fiber.tau_um",
                        tau_um,
                        "a length in µm in (0, 100]",
                    ));
                }
                let r = sigma_h_um / tau_um;
                if !(ROUGHNESS_MIN..=ROUGHNESS_MAX).contains(&r) {
                    return Err(Error::invalid(
                        "fiber.sigma_h_um / fiber.tau_um",
                        r,
                        format!("a ratio in [{ROUGHNESS_MIN}, {ROUGHNESS_MAX}]"),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Smallest supported `σ_h/τ`: below it the lobe is narrower than the quadratures resolve cheaply.
pub const ROUGHNESS_MIN: f64 = 0.005;
/// Largest supported `σ_h/τ` (`α = 4`: a nearly uniform lobe).
pub const ROUGHNESS_MAX: f64 = 2.0;

/// A fiber BRDF ready to evaluate at one wavelength: parameters validated, `η(λ)` resolved and the
/// β table built. Cheap to clone (the table is shared).
#[derive(Clone, Debug)]
pub struct Fiber {
    params: FiberParams,
    lambda_nm: f64,
    eta: f64,
    alpha: f64,
    /// `k = 2π/λ` in µm⁻¹, `σ_h`, `τ` in µm (htsg only).
    k: f64,
    sigma_h: f64,
    tau: f64,
    unit_fresnel: bool,
    beta: Option<Arc<BetaTable>>,
    /// The glossy body lobe ([`FiberParams::body_gloss`]` > 0`): a rough fiber of the body's
    /// roughness with unit Fresnel and no diffuse part, normalised as this fiber is.
    body: Option<Arc<Fiber>>,
}

impl Fiber {
    /// Prepares the fiber for evaluation at `wavelength_nm` (380–780 nm is the visible range;
    /// [`WAVELENGTH_RANGE_NM`] is accepted).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for any parameter out of range.
    ///
    /// ```
    /// use woven::{fiber::{Fiber, FiberParams}, Vec3};
    /// let f = Fiber::new(&FiberParams::rough(1.5, 0.1, 0.0), 550.0)?;
    /// let v = Vec3::from_spherical(0.5, std::f64::consts::PI);
    /// let s = Vec3::from_spherical(0.5, 0.0);
    /// // The mirror direction holds the peak of a smooth fiber: f = β F D_B S / (4 cos² θ) ≈ 0.1.
    /// assert!(f.eval(s, v) > 0.09 && f.eval(s, v) > 20.0 * f.eval(s, s));
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn new(params: &FiberParams, wavelength_nm: f64) -> Result<Self> {
        params.validate()?;
        let [lo, hi] = WAVELENGTH_RANGE_NM;
        check_range("wavelength_nm", wavelength_nm, lo, hi)?;
        params.eta.checked_at(wavelength_nm)?;
        let mut fiber = Self::unnormalized(params, wavelength_nm);
        if params.normalization == Normalization::Paper {
            // The table holds β for ζ = 1 (ρ0 = 0); `beta` scales it by ζ = 1 − ρ0, so that fibers
            // differing only in ρ0 share it exactly and the BRDF is affine in ρ0
            // (`eval_parts_with_normal`).
            let mut unit = fiber.clone();
            unit.params.diffuse = 0.0;
            fiber.beta = Some(BetaTable::shared(&unit));
        }
        fiber.body = Self::body_lobe(params, wavelength_nm)?;
        Ok(fiber)
    }

    /// The glossy body lobe of `params`, if it has one: the paper's lobe at the body's roughness
    /// with `F = 1` and `ρ0 = 0`, so that with the `paper` normalization it returns all the body
    /// light it is given (`β` makes its albedo exactly 1).
    fn body_lobe(params: &FiberParams, wavelength_nm: f64) -> Result<Option<Arc<Fiber>>> {
        if params.body_gloss == 0.0 {
            return Ok(None);
        }
        let lobe = FiberParams {
            model: FiberModel::Rough {
                roughness: params.body_roughness,
            },
            eta: Ior::Constant(1.5),
            diffuse: 0.0,
            normalization: params.normalization,
            body_gloss: 0.0,
            body_roughness: 0.0,
        };
        Ok(Some(Arc::new(
            Fiber::new(&lobe, wavelength_nm)?.with_unit_fresnel(),
        )))
    }

    /// A fiber with other parameters at this fiber's wavelength, sharing this fiber's β table
    /// when the new parameters need the same one: in the rough limit β depends only on the
    /// roughness (docs/spec.md §1.5: `Ω₁` has `F = 1` and `ρ0 = 0`), so fibers that differ only
    /// in `η` or `ρ0` share it exactly. Otherwise the same as [`Fiber::new`]. For fitters, which
    /// build many fibers differing in one parameter; building a table costs ~0.2 s.
    ///
    /// # Errors
    /// As [`Fiber::new`].
    ///
    /// ```
    /// use woven::{fiber::{Fiber, FiberParams}, Vec3};
    /// let a = Fiber::new(&FiberParams::rough(1.5, 0.1, 0.0), 550.0)?;
    /// let b = a.with_params(&FiberParams::rough(1.6, 0.1, 0.2))?; // shares a's table
    /// let c = Fiber::new(&FiberParams::rough(1.6, 0.1, 0.2), 550.0)?;
    /// let (s, v) = (Vec3::from_spherical(0.5, 0.0), Vec3::from_spherical(0.6, 3.0));
    /// assert_eq!(b.eval(s, v), c.eval(s, v));
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn with_params(&self, params: &FiberParams) -> Result<Self> {
        let same_table = matches!(
            (self.params.model, params.model),
            (FiberModel::Rough { roughness: a }, FiberModel::Rough { roughness: b }) if a == b
        ) && self.params.normalization == params.normalization
            && !self.unit_fresnel;
        if !same_table {
            return Fiber::new(params, self.lambda_nm);
        }
        params.validate()?;
        params.eta.checked_at(self.lambda_nm)?;
        let mut fiber = Self::unnormalized(params, self.lambda_nm);
        fiber.beta = self.beta.clone();
        fiber.body = if (params.body_gloss > 0.0) == self.body.is_some()
            && params.body_roughness == self.params.body_roughness
        {
            self.body.clone()
        } else {
            Self::body_lobe(params, self.lambda_nm)?
        };
        Ok(fiber)
    }

    fn unnormalized(params: &FiberParams, wavelength_nm: f64) -> Self {
        let lambda_um = wavelength_nm * 1e-3;
        let (sigma_h, tau) = match params.model {
            FiberModel::Htsg { sigma_h_um, tau_um } => (sigma_h_um, tau_um),
            FiberModel::Rough { .. } => (0.0, 0.0),
        };
        Fiber {
            params: *params,
            lambda_nm: wavelength_nm,
            eta: params.eta.at(wavelength_nm),
            alpha: params.model.alpha(),
            k: 2.0 * PI / lambda_um,
            sigma_h,
            tau,
            unit_fresnel: false,
            beta: None,
            body: None,
        }
    }

    /// The same fiber with Fresnel reflectance replaced by 1 — the "white furnace" used to check
    /// that the `paper` normalization conserves energy exactly (docs/spec.md §6.2).
    pub fn with_unit_fresnel(mut self) -> Self {
        self.unit_fresnel = true;
        self
    }

    /// The parameters this fiber was built from.
    pub fn params(&self) -> &FiberParams {
        &self.params
    }

    /// The wavelength, nm.
    pub fn wavelength_nm(&self) -> f64 {
        self.lambda_nm
    }

    /// The refractive index at this wavelength.
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// Beckmann `α = 2 σ_h/τ`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// `β(θ_i)` (1 in `none` mode), from the table.
    #[inline]
    pub fn beta(&self, cos_theta_i: f64) -> f64 {
        match &self.beta {
            Some(t) => self.lobe_weight() * t.eval(cos_theta_i),
            None => 1.0,
        }
    }

    /// `β / ζ` (`ζ = 1 − ρ0`, docs/spec.md §1.5): the normalization of a fiber without diffuse
    /// albedo, which `β` scales by ζ; 1 without normalization.
    #[inline]
    fn beta_unit(&self, cos_theta_i: f64) -> f64 {
        match &self.beta {
            Some(t) => t.eval(cos_theta_i),
            None => 1.0,
        }
    }

    /// The factor of the normalized lobe in [`eval_parts_with_normal`](Self::eval_parts_with_normal):
    /// `ζ = 1 − ρ0` with the `paper` normalization (β carries it, docs/spec.md §1.5), 1 without.
    #[inline]
    pub fn lobe_weight(&self) -> f64 {
        match self.params.normalization {
            Normalization::Paper => 1.0 - self.params.diffuse,
            Normalization::None => 1.0,
        }
    }

    #[inline]
    fn fresnel(&self, cos_theta: f64) -> f64 {
        if self.unit_fresnel {
            1.0
        } else {
            fresnel_dielectric(cos_theta, self.eta)
        }
    }

    /// The BRDF (sr⁻¹) for light from `s` toward a viewer at `v`, both unit vectors pointing away
    /// from a fiber surface whose normal is `z`. 0 below the horizon. The specular spike of the
    /// full model is not included (see [`specular_reflectance`](Self::specular_reflectance)).
    ///
    /// Implements Eq. (16) as (16') of docs/spec.md §1.3, or Eqs. (9), (13), (14) (§1.4).
    #[inline]
    pub fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        self.eval_with_normal(s, v, Vec3::Z)
    }

    /// The BRDF at a surface point whose unit normal is `a` (docs/spec.md §2.3): the fiber is isotropic,
    /// so only `a` matters. `β` is taken at the local incidence `s·a`.
    #[inline]
    pub fn eval_with_normal(&self, s: Vec3, v: Vec3, a: Vec3) -> f64 {
        self.combine_parts(self.eval_parts_with_normal(s, v, a))
    }

    /// The value of [`eval_parts_with_normal`](Self::eval_parts_with_normal)'s parts (or of any
    /// linear average of them): `ζ·parts[0] + ρ0·parts[1]`.
    #[inline]
    pub fn combine_parts(&self, parts: [f64; 2]) -> f64 {
        self.lobe_weight() * parts[0] + self.params.diffuse * parts[1]
    }

    /// `(fixed, per_diffuse)` of the parts: their value is `fixed + ρ0·per_diffuse` as a function
    /// of the diffuse albedo `ρ0` (β carries `ζ = 1 − ρ0` with the `paper` normalization, so
    /// `per_diffuse = parts[1] − parts[0]` there; `parts[1]` without normalization).
    #[inline]
    pub fn affine_in_diffuse(&self, parts: [f64; 2]) -> (f64, f64) {
        match self.params.normalization {
            Normalization::Paper => (parts[0], parts[1] - parts[0]),
            Normalization::None => (parts[0], parts[1]),
        }
    }

    /// The BRDF at normal `a` in the two parts it is affine in (docs/spec.md §1.5):
    /// `[β/ζ · lobe, body]`, the body `1/π` (with a glossy body, `(1 − g)/π + g·f_gloss`,
    /// [`FiberParams::body_gloss`]), so that `f = ζ·parts[0] + ρ0·parts[1]` with `ζ` the
    /// [`lobe_weight`](Self::lobe_weight) (`1 − ρ0` for the `paper` normalization, else 1). Both
    /// parts are non-negative and independent of `ρ0`; `[0, 0]` when `s` or `v` is below `a`.
    #[inline]
    pub fn eval_parts_with_normal(&self, s: Vec3, v: Vec3, a: Vec3) -> [f64; 2] {
        let ci = s.dot(a);
        let cr = v.dot(a);
        if ci <= 0.0 || cr <= 0.0 {
            return [0.0, 0.0];
        }
        let body = match &self.body {
            None => FRAC_1_PI,
            Some(lobe) => {
                let g = self.params.body_gloss;
                (1.0 - g) * FRAC_1_PI + g * lobe.beta(ci) * lobe.lobe(s, v, a, ci, cr)
            }
        };
        [self.beta_unit(ci) * self.lobe(s, v, a, ci, cr), body]
    }

    /// The single-scattering lobe with `β = 1` (Fresnel included, `ρ0` excluded).
    #[inline]
    fn lobe(&self, s: Vec3, v: Vec3, a: Vec3, ci: f64, cr: f64) -> f64 {
        let w = s + v;
        let w2 = w.dot(w);
        if w2 <= 0.0 {
            return 0.0;
        }
        let wa = w.dot(a);
        let cos_d = s.dot(w) / w2.sqrt();
        let shadow = smith_s1(ci, self.alpha) * smith_s1(cr, self.alpha);
        match self.params.model {
            FiberModel::Rough { .. } => {
                // Eq. (16'): F D_B S / (4 cos θi cos θr), with tan²θ_h = |w_⊥|²/(w·a)² (exact to an
                // ulp, where 1/cos² − 1 would lose ε/α² near the peak).
                let cos2_h = wa * wa / w2;
                let tan2_h = (w2 - wa * wa).max(0.0) / (wa * wa);
                let a2 = self.alpha * self.alpha;
                let d = if wa > 0.0 {
                    exp_neg(tan2_h / a2) / (PI * a2 * cos2_h * cos2_h)
                } else {
                    0.0
                };
                self.fresnel(cos_d) * d * shadow / (4.0 * ci * cr)
            }
            FiberModel::Htsg { .. } => {
                // Eqs. (9), (13): F S G D / (π cos θi cos θr).
                let lambda_um = self.lambda_nm * 1e-3;
                let kr = self.k * self.sigma_h * (ci + cr);
                let g = kr * kr;
                let wxy2 = (w2 - wa * wa).max(0.0);
                let k_big = self.k * self.k * wxy2 * self.tau * self.tau / 4.0;
                let d = PI * PI * self.tau * self.tau / (4.0 * lambda_um * lambda_um)
                    * htsg::series(g, k_big);
                let geo = (w2 / wa) * (w2 / wa);
                self.fresnel(cos_d) * shadow * geo * d / (PI * ci * cr)
            }
        }
    }

    /// The reflectance of the full model's mirror spike, `R_sp(θ_i) = β F(θ_i) e^{−g(θ_i,θ_i)} S1(θ_i)²`
    /// (Eq. (12); docs/spec.md §1.4). 0 for the rough model. A Dirac lobe: never part of [`eval`](Self::eval).
    pub fn specular_reflectance(&self, cos_theta_i: f64) -> f64 {
        if cos_theta_i <= 0.0 {
            return 0.0;
        }
        self.beta(cos_theta_i) * self.fresnel(cos_theta_i) * self.specular_unnormalized(cos_theta_i)
    }

    /// `e^{−g(θ_i,θ_i)} S1(θ_i)²` (0 for the rough model).
    fn specular_unnormalized(&self, ci: f64) -> f64 {
        match self.params.model {
            FiberModel::Rough { .. } => 0.0,
            FiberModel::Htsg { .. } => {
                let kr = 2.0 * self.k * self.sigma_h * ci;
                let s1 = smith_s1(ci, self.alpha);
                (-kr * kr).exp() * s1 * s1
            }
        }
    }

    /// The directional albedo `∫ f cos θ_r dω_r + R_sp(θ_i)`: all light reflected for unit
    /// irradiance from `θ_i` (`cos_theta_i ∈ (0, 1]`), by adaptive half-vector quadrature.
    /// `≤ 1` in `paper` mode; exactly 1 with unit Fresnel.
    pub fn albedo(&self, cos_theta_i: f64) -> f64 {
        let ci = cos_theta_i.clamp(1e-9, 1.0);
        let lobe = reflected_hemisphere_integral(ci, self.lobe_width(ci), 1e-8, |s, v, _| {
            let cr = v.z;
            self.beta(ci) * self.lobe(s, v, Vec3::Z, ci, cr)
        });
        let body = match &self.body {
            None => 1.0,
            Some(lobe) => {
                let g = self.params.body_gloss;
                1.0 - g + g * lobe.albedo(ci)
            }
        };
        lobe + self.params.diffuse * body + self.specular_reflectance(ci)
    }

    /// The half-vector width of the lobe at incidence `ci`: `α`, or for the full model at low `g`
    /// the wider diffraction lobe `~2/(kτ)`.
    pub(crate) fn lobe_width(&self, _ci: f64) -> f64 {
        match self.params.model {
            FiberModel::Rough { .. } => self.alpha,
            // The m-th series term has width 2√m/(kτ) in |w_xy|; m ≥ 1.
            FiberModel::Htsg { .. } => self.alpha.max(2.0 / (self.k * self.tau)),
        }
    }
}
