//! A rough dielectric coating over a diffuse base: Mitsuba 3's `roughplastic`, its formulation
//! and defaults.
//!
//! | parameter | meaning | unit | default | valid range |
//! |---|---|---|---|---|
//! | `distribution` | the coating's microfacet distribution | — | `Beckmann` | `Beckmann`, `Ggx` |
//! | `alpha` | the distribution's roughness `α` | — | 0.1 | `[0.001, 1]` |
//! | `int_ior` | refractive index of the coating | — | 1.49 (polypropylene) | `[1, 4]`, ≠ `ext_ior` |
//! | `ext_ior` | refractive index outside | — | 1.000277 (air) | `[1, 4]` |
//! | `diffuse_reflectance` | albedo of the base, per channel | — | 0.5 | `[0, 1]` each |
//! | `specular_reflectance` | factor on the specular lobe, per channel (1 for realism) | — | 1 | `[0, 1]` each |
//! | `nonlinear` | internal reflections tint the base (`ρ/(1 − ρ F̄)` instead of `ρ/(1 − F̄)`) | — | `false` | |
//!
//! The BRDF, per channel (sr⁻¹, without the cosine), with `η = int_ior / ext_ior` and
//! `h = (wi + wo)/|wi + wo|`:
//!
//! ```text
//! f = specular_reflectance · F(wi·h; η) D(h) G1(wi) G1(wo) / (4 cos θi cos θo)
//!   + ρ' · T(cos θi) T(cos θo) / (π η²)
//! ρ' = ρ / (1 − F̄_int)        (nonlinear = false: the base's albedo stays ρ)
//! ρ' = ρ / (1 − ρ F̄_int)      (nonlinear = true: the series of internal bounces, ρ = diffuse)
//! ```
//!
//! - `D` is Beckmann or GGX, normalized so that `∫ D cos θh dω = 1`; `G1 = 1/(1 + Λ)` is the
//!   separable Smith masking of each direction (Mitsuba's `G`), 0 where a direction sees the
//!   back of the microfacet; `F` the unpolarized dielectric Fresnel reflectance.
//! - `T(μ)` is the coating's directional transmittance from outside: the energy the rough
//!   interface refracts into the coating from `cos θ = μ`, Walter et al.'s BTDF integrated with
//!   the same `D`, `G1` and `F`. `F̄_int = 2∫ R_int(μ) μ dμ` is the cosine-weighted mean
//!   reflectance of the interface from inside (relative index `1/η`, total internal reflection
//!   included). Mitsuba tabulates the same two quantities; here both are computed at construction
//!   by Gauss–Legendre quadrature over microfacet normals drawn ∝ `D cos θm` (48 × 48 points;
//!   `T` on a `CosTable`), to about 10⁻⁴.
//! - **Energy.** The BTDF's reciprocity gives `T̄_ext / η² = T̄_int ≤ 1 − F̄_int`, so with `ρ ≤ 1`
//!   the base returns at most `T(μi)` and the albedo is at most `R(μi) + T(μi) ≤ 1` (masking
//!   loses the rest). Both terms are symmetric in `wi` and `wo`: `f` is reciprocal.
//!
//! Sampling, as Mitsuba: the specular lobe (microfacet normals ∝ `D cos θm`, reflected; Mitsuba
//! draws visible normals by default) with probability `(1 − T(μ)) w / ((1 − T(μ)) w + T(μ) (1 −
//! w))` at the known direction's `μ`, `w = s̄ / (d̄ + s̄)` from the channel means of
//! `specular_reflectance` and `diffuse_reflectance`; otherwise a cosine hemisphere.

use super::{check_reflectance, mean, reflect, CosTable};
use crate::bsdf::{complete_draw, known_and_drawn, Bsdf, BsdfSample, LobeFlags, Transport};
use crate::color::Rgb;
use crate::error::{check_range, Error, Result};
use crate::fiber::{beckmann_d, fresnel_dielectric, smith_lambda};
use crate::math::quadrature::GaussLegendre;
use crate::math::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use crate::math::Vec3;
use std::f64::consts::{FRAC_1_PI, PI};

/// Gauss–Legendre panels × points per panel of the tabulations, in each variable of the
/// microfacet draw (48 points each).
const PANELS: usize = 6;
const POINTS: usize = 8;

/// A microfacet distribution of normals (isotropic).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Distribution {
    /// Beckmann: `D = exp(−tan²θ/α²) / (π α² cos⁴θ)` (Mitsuba's default).
    #[default]
    Beckmann,
    /// GGX (Trowbridge–Reitz): `D = α² / (π cos⁴θ (α² + tan²θ)²)`.
    Ggx,
}

impl Distribution {
    /// What [`parse`](Self::parse) accepts, for error messages.
    pub const NAMES: &'static str = "\"beckmann\" or \"ggx\"";

    /// The distribution Mitsuba names `name` (`"beckmann"`, `"ggx"`), or `None`.
    pub fn parse(name: &str) -> Option<Distribution> {
        match name {
            "beckmann" => Some(Distribution::Beckmann),
            "ggx" => Some(Distribution::Ggx),
            _ => None,
        }
    }

    /// `D(m)` for `cos θm` (0 at or below the horizon), sr⁻¹; `∫ D cos θm dω = 1`.
    #[inline]
    pub fn d(self, cos_theta: f64, alpha: f64) -> f64 {
        if cos_theta <= 0.0 {
            return 0.0;
        }
        match self {
            Distribution::Beckmann => beckmann_d(cos_theta, alpha),
            Distribution::Ggx => {
                let c2 = cos_theta * cos_theta;
                let a2 = alpha * alpha;
                let k = c2 * (a2 - 1.0) + 1.0;
                a2 / (PI * k * k)
            }
        }
    }

    /// Smith's `Λ` for a direction at `cos θ` in `(0, 1]`.
    #[inline]
    pub fn lambda(self, cos_theta: f64, alpha: f64) -> f64 {
        let c = cos_theta.clamp(0.0, 1.0);
        let s = (1.0 - c * c).max(0.0).sqrt();
        if s == 0.0 {
            return 0.0;
        }
        match self {
            // a = cot θ / α; the library's Beckmann Λ (docs/spec.md §1.2).
            Distribution::Beckmann => smith_lambda(c / (s * alpha)),
            Distribution::Ggx => {
                let t = alpha * s / c;
                0.5 * ((1.0 + t * t).sqrt() - 1.0)
            }
        }
    }

    /// The masking of direction `w` by a facet of normal `m`: `1/(1 + Λ)`, 0 where `w` sees
    /// the facet's back (`w·m` and `w·z` of opposite signs).
    #[inline]
    pub fn g1(self, w: Vec3, m: Vec3, alpha: f64) -> f64 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w.z.abs(), alpha))
    }

    /// A normal drawn with density `D(m) cos θm` per unit solid angle: `tan²θ = −α² ln(1 − u1)`
    /// (Beckmann) or `α² u1 / (1 − u1)` (GGX), `φ = 2π u2`.
    #[inline]
    pub fn sample_m(self, u: [f64; 2], alpha: f64) -> Vec3 {
        // min: u1 → 1 sends θ to the horizon; 1 − 2⁻⁵³ keeps tan² finite.
        let u1 = u[0].min(1.0 - f64::EPSILON / 2.0);
        let tan2 = match self {
            Distribution::Beckmann => -alpha * alpha * (-u1).ln_1p(),
            Distribution::Ggx => alpha * alpha * u1 / (1.0 - u1),
        };
        let cos = 1.0 / (1.0 + tan2).sqrt();
        let sin = (tan2 / (1.0 + tan2)).sqrt();
        let phi = 2.0 * PI * u[1];
        Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
    }
}

/// The parameters of a [`RoughPlastic`] (module docs' table; defaults are Mitsuba 3's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughPlasticParams {
    /// The coating's microfacet distribution.
    pub distribution: Distribution,
    /// Its roughness `α` in `[0.001, 1]`.
    pub alpha: f64,
    /// Refractive index of the coating, `[1, 4]`.
    pub int_ior: f64,
    /// Refractive index outside, `[1, 4]`, different from `int_ior`.
    pub ext_ior: f64,
    /// Albedo of the diffuse base, per channel in `[0, 1]`.
    pub diffuse_reflectance: Rgb,
    /// Factor on the specular lobe, per channel in `[0, 1]`.
    pub specular_reflectance: Rgb,
    /// Whether internal reflections tint the base (`ρ/(1 − ρ F̄_int)`).
    pub nonlinear: bool,
}

impl Default for RoughPlasticParams {
    fn default() -> Self {
        RoughPlasticParams {
            distribution: Distribution::Beckmann,
            alpha: 0.1,
            int_ior: 1.49,
            ext_ior: 1.000277,
            diffuse_reflectance: Rgb::grey(0.5),
            specular_reflectance: Rgb::WHITE,
            nonlinear: false,
        }
    }
}

/// Mitsuba 3's rough plastic (module docs): an RGB [`Bsdf`].
///
/// ```
/// use woven::baseline::{RoughPlastic, RoughPlasticParams};
/// use woven::bsdf::Bsdf;
/// use woven::Vec3;
/// let plastic = RoughPlastic::new(&RoughPlasticParams::default())?;
/// // The coating reflects ((η − 1)/(η + 1))² ≈ 3.9 % at normal incidence; the rest enters.
/// let t = plastic.transmittance(1.0);
/// assert!(t > 0.95 && t < 0.962);
/// let f = plastic.eval(Vec3::from_spherical(0.4, 0.0), Vec3::from_spherical(0.4, 3.14159));
/// assert!(f.is_valid() && f.0[0] > 0.0);
/// # Ok::<(), woven::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RoughPlastic {
    params: RoughPlasticParams,
    /// `η = int_ior / ext_ior`.
    eta: f64,
    /// `T(μ)`, the transmittance into the coating.
    transmittance: CosTable,
    /// `F̄_int`, the mean internal reflectance.
    internal_reflectance: f64,
    /// `w = s̄ / (d̄ + s̄)`.
    specular_weight: f64,
}

impl RoughPlastic {
    /// Validates `params` and tabulates the coating's transmittance and internal reflectance
    /// (a few milliseconds).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `alpha`, `int_ior`, `ext_ior` (outside their ranges,
    /// or equal), `diffuse_reflectance` or `specular_reflectance` (a channel outside `[0, 1]`).
    pub fn new(params: &RoughPlasticParams) -> Result<RoughPlastic> {
        check_range("alpha", params.alpha, 1e-3, 1.0)?;
        check_range("int_ior", params.int_ior, 1.0, 4.0)?;
        check_range("ext_ior", params.ext_ior, 1.0, 4.0)?;
        if params.int_ior == params.ext_ior {
            return Err(Error::invalid(
                "int_ior",
                params.int_ior,
                format!("an index different from ext_ior = {}", params.ext_ior),
            ));
        }
        check_reflectance("diffuse_reflectance", params.diffuse_reflectance)?;
        check_reflectance("specular_reflectance", params.specular_reflectance)?;
        let eta = params.int_ior / params.ext_ior;
        let (dist, alpha) = (params.distribution, params.alpha);
        let gl = GaussLegendre::new(POINTS);
        let transmittance = CosTable::build(|mu| transmittance(&gl, PANELS, dist, alpha, eta, mu));
        let internal_reflectance = internal_reflectance(&gl, dist, alpha, eta);
        let (s, d) = (
            mean(params.specular_reflectance),
            mean(params.diffuse_reflectance),
        );
        let specular_weight = if s + d > 0.0 { s / (s + d) } else { 1.0 };
        Ok(RoughPlastic {
            params: *params,
            eta,
            transmittance,
            internal_reflectance,
            specular_weight,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &RoughPlasticParams {
        &self.params
    }

    /// `η = int_ior / ext_ior`.
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// `T(μ)`: the coating's directional transmittance from outside at `cos θ = μ` (tabulated).
    pub fn transmittance(&self, cos_theta: f64) -> f64 {
        self.transmittance.eval(cos_theta)
    }

    /// `F̄_int`: the cosine-weighted mean reflectance of the interface from inside.
    pub fn internal_reflectance(&self) -> f64 {
        self.internal_reflectance
    }

    /// The specular lobe alone (per unit `specular_reflectance`), sr⁻¹.
    #[inline]
    pub fn specular(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let (dist, alpha) = (self.params.distribution, self.params.alpha);
        let h = (wi + wo).normalize();
        fresnel_dielectric(wi.dot(h), self.eta)
            * dist.d(h.z, alpha)
            * dist.g1(wi, h, alpha)
            * dist.g1(wo, h, alpha)
            / (4.0 * wi.z * wo.z)
    }

    /// The probability of drawing the specular lobe for a known direction at `cos θ`.
    fn specular_probability(&self, cos_theta: f64) -> f64 {
        let t = self.transmittance(cos_theta);
        let w = self.specular_weight;
        let (s, d) = ((1.0 - t) * w, t * (1.0 - w));
        if s + d > 0.0 {
            s / (s + d)
        } else {
            1.0 // nothing enters the base: only the coating reflects
        }
    }

    /// The density of reflecting `known` about a normal drawn ∝ `D cos θm`:
    /// `D(h) cos θh / (4 known·h)`.
    fn specular_pdf(&self, known: Vec3, drawn: Vec3) -> f64 {
        let h = (known + drawn).normalize();
        self.params.distribution.d(h.z, self.params.alpha) * h.z / (4.0 * known.dot(h))
    }
}

/// `F̄_int = 2∫ R_int(μ) μ dμ`, `R_int` the reflectance from inside (relative index `1/η`), by
/// Gauss–Legendre panels split at the critical angle, where `R_int` has a kink (`F` rises to 1
/// with an infinite slope; roughness only blurs it over about `α`).
fn internal_reflectance(gl: &GaussLegendre, dist: Distribution, alpha: f64, eta: f64) -> f64 {
    // Total internal reflection for sin θ > 1/η, i.e. cos θ < √(1 − 1/η²) (none for η < 1).
    let mu_c = (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt();
    let mut sum = 0.0;
    for (lo, hi) in [(0.0, mu_c), (mu_c, 1.0)] {
        let n = 3;
        for k in 0..n {
            let a = lo + (hi - lo) * k as f64 / n as f64;
            let b = lo + (hi - lo) * (k + 1) as f64 / n as f64;
            sum += gl.integrate(a, b, |mu| {
                reflectance(gl, PANELS, dist, alpha, 1.0 / eta, mu) * mu
            });
        }
    }
    2.0 * sum
}

/// `T(μ)`: `∫ (1 − F(i·m; η)) G1(i) G1(t) (i·m) D(m) / μ dωm` over normals with `i·m > 0`, `t`
/// the refracted direction (Walter et al.'s BTDF times `|cos θt|`, integrated over `t`).
fn transmittance(
    gl: &GaussLegendre,
    panels: usize,
    dist: Distribution,
    alpha: f64,
    eta: f64,
    mu: f64,
) -> f64 {
    over_normals(gl, panels, dist, alpha, mu, |i, m| {
        let c = i.dot(m);
        let f = fresnel_dielectric(c, eta);
        if f >= 1.0 {
            return 0.0; // total internal reflection
        }
        // Snell: cos θt = √(1 − (1 − c²)/η²); t = −i/η + (c/η − cos θt) m points into the coating.
        let cos_t = (1.0 - (1.0 - c * c) / (eta * eta)).max(0.0).sqrt();
        let t = i * (-1.0 / eta) + m * (c / eta - cos_t);
        (1.0 - f) * dist.g1(i, m, alpha) * dist.g1(t, m, alpha)
    })
}

/// `R(μ)`: `∫ F(i·m; η) G1(i) G1(r) (i·m) D(m) / μ dωm`, `r` the mirror direction (above the
/// horizon): the specular lobe's directional albedo.
fn reflectance(
    gl: &GaussLegendre,
    panels: usize,
    dist: Distribution,
    alpha: f64,
    eta: f64,
    mu: f64,
) -> f64 {
    over_normals(gl, panels, dist, alpha, mu, |i, m| {
        let r = reflect(i, m);
        if r.z <= 0.0 {
            return 0.0;
        }
        fresnel_dielectric(i.dot(m), eta) * dist.g1(i, m, alpha) * dist.g1(r, m, alpha)
    })
}

/// `∫ g(i, m) (i·m) D(m) / μ dωm` over normals with `i·m > 0`, `i` at `cos θ = μ`, by
/// Gauss–Legendre over the draw [`Distribution::sample_m`]: `D cos θm dωm = du`, so the integrand
/// is `g (i·m) / (μ cos θm)`. `u1 = 1 − (1 − v)²` removes the draw's `1/√(1 − u1)` growth of
/// `tan θm` at the horizon; `u2` covers half a turn (`i` lies in the `xz` plane) and is doubled.
fn over_normals(
    gl: &GaussLegendre,
    panels: usize,
    dist: Distribution,
    alpha: f64,
    mu: f64,
    g: impl Fn(Vec3, Vec3) -> f64,
) -> f64 {
    if mu <= 0.0 {
        return 0.0; // the limit: G1(i) → 0 at grazing
    }
    let i = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let panel = 1.0 / panels as f64;
    let mut sum = 0.0;
    for p1 in 0..panels {
        for p2 in 0..panels {
            let (a1, a2) = (p1 as f64 * panel, p2 as f64 * panel * 0.5);
            sum += gl.integrate(a1, a1 + panel, |v| {
                let u1 = 1.0 - (1.0 - v) * (1.0 - v);
                let jac = 2.0 * (1.0 - v);
                jac * gl.integrate(a2, a2 + 0.5 * panel, |u2| {
                    let m = dist.sample_m([u1, u2], alpha);
                    let c = i.dot(m);
                    if c <= 0.0 {
                        return 0.0;
                    }
                    g(i, m) * c / (mu * m.z)
                })
            });
        }
    }
    2.0 * sum
}

impl Bsdf for RoughPlastic {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::GLOSSY | LobeFlags::DIFFUSE
    }

    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::BLACK;
        }
        let spec = self.specular(wi, wo);
        let base =
            self.transmittance(wi.z) * self.transmittance(wo.z) * FRAC_1_PI / (self.eta * self.eta);
        let mut f = [0.0; 3];
        for (k, f) in f.iter_mut().enumerate() {
            let rho = self.params.diffuse_reflectance.0[k];
            let internal = if self.params.nonlinear {
                rho * self.internal_reflectance
            } else {
                self.internal_reflectance
            };
            *f = self.params.specular_reflectance.0[k] * spec + rho / (1.0 - internal) * base;
        }
        Rgb(f)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        if known.z <= 0.0 || drawn.z <= 0.0 {
            return 0.0;
        }
        let p = self.specular_probability(known.z);
        p * self.specular_pdf(known, drawn) + (1.0 - p) * cosine_hemisphere_pdf(drawn.z)
    }

    fn sample(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Rgb>> {
        if known.z <= 0.0 {
            return None;
        }
        let p = self.specular_probability(known.z);
        let (drawn, lobe) = if uc < p {
            let m = self.params.distribution.sample_m(u, self.params.alpha);
            if known.dot(m) <= 0.0 {
                return None;
            }
            (reflect(known, m), LobeFlags::GLOSSY)
        } else {
            (cosine_hemisphere(u[0], u[1]), LobeFlags::DIFFUSE)
        };
        complete_draw(self, known, drawn, LobeFlags::REFLECTION | lobe, mode)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::adaptive;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn distributions_have_unit_projected_area() {
        for dist in [Distribution::Beckmann, Distribution::Ggx] {
            for alpha in [0.05, 0.3, 1.0] {
                let i = adaptive(0.0, FRAC_PI_2, 1e-12, 0.0, 40, |t: f64| {
                    dist.d(t.cos(), alpha) * t.cos() * t.sin()
                }) * 2.0
                    * PI;
                assert!((i - 1.0).abs() < 1e-8, "{dist:?} α {alpha}: {i}");
            }
        }
    }

    #[test]
    fn smooth_coating_reflects_fresnel_and_transmits_the_rest() {
        // Golden: at normal incidence a nearly smooth interface reflects ((η − 1)/(η + 1))².
        let p = RoughPlastic::new(&RoughPlasticParams {
            alpha: 1e-3,
            int_ior: 1.5,
            ext_ior: 1.0,
            ..RoughPlasticParams::default()
        })
        .unwrap();
        let gl = GaussLegendre::new(POINTS);
        let r = reflectance(&gl, PANELS, Distribution::Beckmann, 1e-3, 1.5, 1.0);
        assert!((r - 0.04).abs() < 1e-5, "{r}");
        assert!(
            (p.transmittance(1.0) - 0.96).abs() < 1e-5,
            "{}",
            p.transmittance(1.0)
        );
        // From inside, the mean reflectance of a smooth interface is 1 − (1 − F̄_ext)/η², with
        // F̄_ext = 2∫ F(μ; η) μ dμ (the two sides' transmittances are reciprocal).
        let f_ext = 2.0
            * adaptive(0.0, 1.0, 1e-12, 0.0, 40, |mu: f64| {
                fresnel_dielectric(mu, 1.5) * mu
            });
        let want = 1.0 - (1.0 - f_ext) / 2.25;
        assert!(
            (p.internal_reflectance() - want).abs() < 2e-3,
            "{} vs {want}",
            p.internal_reflectance()
        );
    }

    #[test]
    fn parameters_out_of_range_are_refused_by_name() {
        let base = RoughPlasticParams::default();
        let cases = [
            (RoughPlasticParams { alpha: 0.0, ..base }, "alpha"),
            (RoughPlasticParams { alpha: 2.0, ..base }, "alpha"),
            (
                RoughPlasticParams {
                    int_ior: 0.5,
                    ..base
                },
                "int_ior",
            ),
            (
                RoughPlasticParams {
                    ext_ior: f64::NAN,
                    ..base
                },
                "ext_ior",
            ),
            (
                RoughPlasticParams {
                    int_ior: 1.3,
                    ext_ior: 1.3,
                    ..base
                },
                "int_ior",
            ),
            (
                RoughPlasticParams {
                    diffuse_reflectance: Rgb([0.1, 0.2, 1.2]),
                    ..base
                },
                "diffuse_reflectance",
            ),
        ];
        for (params, name) in cases {
            let e = RoughPlastic::new(&params).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains("expected"), "{name}: {e}");
        }
    }
}
