//! The Estevez–Kulla "Charlie" sheen over a Lambertian base: the sheen of glTF's
//! `KHR_materials_sheen` and Google Filament, with the base dimmed by the sheen's albedo.
//!
//! | parameter | meaning | unit | default | valid range |
//! |---|---|---|---|---|
//! | `diffuse` | albedo of the Lambertian base, per channel | — | 0.5 | `[0, 1]` each |
//! | `sheen_color` | the sheen's colour (glTF's `sheenColorFactor`), per channel | — | 1 | `[0, 1]` each |
//! | `roughness` | glTF's `sheenRoughness` `r`; the distribution's `α = r²` | — | 0.5 | `[0.1, 1]` |
//!
//! The BRDF, per channel (sr⁻¹, without the cosine):
//!
//! ```text
//! f(wi, wo) = diffuse/π · (1 − sheen_color · max(Ê(cos θi), Ê(cos θo)))
//!           + sheen_color · D(h) V(θi, θo) / N(θi, θo)
//! D(h)      = (2 + 1/α) sin^(1/α) θh / (2π)                      (Charlie; ∫ D cos θh dω = 1)
//! V         = 1 / (4 cos θi cos θo (1 + Λ(cos θi) + Λ(cos θo)))  (Estevez–Kulla's Smith form)
//! N         = max(1, E(cos θi), E(cos θo))
//! ```
//!
//! - **Visibility.** `Λ` is Estevez–Kulla's fit of the Charlie distribution's Smith `Λ`, as glTF's
//!   reference code writes it: `Λ(μ) = exp(L(μ))` for `μ < ½`, `exp(2 L(½) − L(1 − μ))` above,
//!   `L(x) = a/(1 + b x^c) + d x + e`, the five coefficients blended between their fits at `α = 1`
//!   and `α → 0` by `t = (1 − α)²`. Their terminator softening (`Λ^(1 + 2(1 − μ)^8)`) is not
//!   applied; Filament's cheaper Neubelt–Pettineo `V = 1/(4(μi + μo − μi μo))` is not used.
//! - **Energy.** The lobe's directional albedo `E(μ) = ∫ D V μo dωo` exceeds 1 toward grazing for
//!   smooth sheens (1.6 at θ = 89° for `r = 0.1`, 1.16 for `r = 0.2`; the fitted `Λ` is not the
//!   distribution's exact one). `N` scales the lobe down exactly there, so its albedo `Ê` never
//!   exceeds 1; `N` is symmetric, so `f` stays reciprocal, and `N = 1` wherever `E ≤ 1` on both
//!   sides (everywhere for `r ≥ 0.3` up to 89°). This is a departure from glTF, which lets a white
//!   sheen reflect more than it receives at grazing.
//! - **Base scaling.** glTF's albedo scaling, per channel instead of by `max3(sheen_color)`:
//!   `1 − sheen_color · max(Ê(μi), Ê(μo))` (glTF's `min(1 − c Ê(μv), 1 − c Ê(μl))`). With
//!   `diffuse ≤ 1` and `sheen_color ≤ 1` the albedo is at most `diffuse (1 − c Ê(μi)) + c Ê(μi) ≤ 1`.
//! - **Tabulation.** `E` and `Ê` are computed at construction on a `CosTable`
//!   (65 values of `cos θ`) by 24 × 24 Gauss–Legendre points over `(√cos θo, φo)` (under a
//!   millisecond); the quadrature is good to 10⁻⁵ and the interpolation between nodes to 10⁻³
//!   (tests against brute-force quadrature over `wo`).
//!
//! Sampling mixes half vectors drawn ∝ `D cos θh` (reflected about `h`) with a cosine
//! hemisphere, the sheen drawn with probability `c̄ Ê(μ) / (c̄ Ê(μ) + d̄ (1 − c̄ Ê(μ)))` at the known
//! direction's `μ` (`c̄`, `d̄` the channel means of `sheen_color` and `diffuse`).
//!
//! References: A. Conty Estevez and C. Kulla, *Production Friendly Microfacet Sheen BRDF*
//! (SIGGRAPH 2017 talk); the Khronos glTF `KHR_materials_sheen` specification.

use super::{check_reflectance, mean, reflect, CosTable};
use crate::bsdf::{complete_draw, known_and_drawn, Bsdf, BsdfSample, LobeFlags, Transport};
use crate::color::Rgb;
use crate::error::{check_range, Result};
use crate::math::quadrature::GaussLegendre;
use crate::math::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use crate::math::Vec3;
use std::f64::consts::{FRAC_1_PI, PI};

/// The smallest `roughness` (`α = 0.01`): below, the distribution approaches a ring of
/// horizontal normals that the tabulation's quadrature no longer resolves.
pub const MIN_SHEEN_ROUGHNESS: f64 = 0.1;

/// Gauss–Legendre panels × points per panel of the albedo tabulation, in each of `√cos θo` and
/// `φo` (24 points each).
const ALBEDO_PANELS: usize = 3;
const ALBEDO_POINTS: usize = 8;

/// The parameters of a [`Sheen`] (module docs' table).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheenParams {
    /// Albedo of the Lambertian base, per channel, in `[0, 1]`.
    pub diffuse: Rgb,
    /// The sheen's colour, per channel, in `[0, 1]`.
    pub sheen_color: Rgb,
    /// glTF's `sheenRoughness` in `[0.1, 1]`; `α = roughness²`.
    pub roughness: f64,
}

impl Default for SheenParams {
    fn default() -> Self {
        SheenParams {
            diffuse: Rgb::grey(0.5),
            sheen_color: Rgb::WHITE,
            roughness: 0.5,
        }
    }
}

/// The Charlie sheen lobe with a white colour: `D V / N` (module docs), with its albedo `Ê`.
#[derive(Clone, Debug, PartialEq)]
pub struct SheenLobe {
    roughness: f64,
    alpha: f64,
    /// `a, b, c, d, e` of `L(x)`, blended for this `α`.
    coeffs: [f64; 5],
    /// `E(μ)`: the albedo of `D V` (unnormalized).
    raw_albedo: CosTable,
    /// `Ê(μ)`: the albedo of `D V / N`.
    albedo: CosTable,
}

impl SheenLobe {
    /// The lobe for glTF's `sheenRoughness` `roughness` (`α = roughness²`); tabulates its
    /// albedos (a few milliseconds).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `roughness` outside
    /// `[0.1, 1]`.
    ///
    /// ```
    /// use woven::baseline::SheenLobe;
    /// let lobe = SheenLobe::new(0.5)?;
    /// // A sheen reflects toward grazing: little at normal incidence, much more at 80°.
    /// assert!(lobe.albedo(1.0) < 0.05 && lobe.albedo(80f64.to_radians().cos()) > 0.3);
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn new(roughness: f64) -> Result<SheenLobe> {
        check_range("roughness", roughness, MIN_SHEEN_ROUGHNESS, 1.0)?;
        let alpha = roughness * roughness;
        // Estevez–Kulla's fits at α = 1 and α → 0, blended by t = (1 − α)² (glTF's reference).
        let t = (1.0 - alpha) * (1.0 - alpha);
        let blend = |at_one: f64, at_zero: f64| (1.0 - t) * at_one + t * at_zero;
        let coeffs = [
            blend(21.5473, 25.3245),
            blend(3.82987, 3.32435),
            blend(0.19823, 0.16801),
            blend(-1.97760, -1.27393),
            blend(-4.32054, -4.85967),
        ];
        let mut lobe = SheenLobe {
            roughness,
            alpha,
            coeffs,
            raw_albedo: CosTable::build(|_| 0.0),
            albedo: CosTable::build(|_| 0.0),
        };
        let gl = GaussLegendre::new(ALBEDO_POINTS);
        lobe.raw_albedo =
            CosTable::build(|mu| lobe.albedo_by_quadrature(&gl, ALBEDO_PANELS, mu, |_, _| 1.0));
        lobe.albedo = CosTable::build(|mu| {
            lobe.albedo_by_quadrature(&gl, ALBEDO_PANELS, mu, |mi, mo| {
                1.0 / lobe.normalization(mi, mo)
            })
        });
        Ok(lobe)
    }

    /// glTF's `sheenRoughness`.
    pub fn roughness(&self) -> f64 {
        self.roughness
    }

    /// The distribution's `α = roughness²`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The Charlie distribution `D(h) = (2 + 1/α) sin^(1/α) θh / (2π)` for `cos θh` in `[0, 1]`
    /// (0 below), sr⁻¹; `∫ D cos θh dω = 1`.
    #[inline]
    pub fn d(&self, cos_theta_h: f64) -> f64 {
        if cos_theta_h < 0.0 {
            return 0.0;
        }
        let sin2 = (1.0 - cos_theta_h * cos_theta_h).max(0.0);
        (2.0 + 1.0 / self.alpha) * sin2.powf(0.5 / self.alpha) / (2.0 * PI)
    }

    /// Estevez–Kulla's fitted Smith `Λ(μ)` for `μ = cos θ` in `[0, 1]`.
    #[inline]
    pub fn lambda(&self, cos_theta: f64) -> f64 {
        let mu = cos_theta.clamp(0.0, 1.0);
        if mu < 0.5 {
            self.l(mu).exp()
        } else {
            (2.0 * self.l(0.5) - self.l(1.0 - mu)).exp()
        }
    }

    /// `L(x) = a/(1 + b x^c) + d x + e`.
    #[inline]
    fn l(&self, x: f64) -> f64 {
        let [a, b, c, d, e] = self.coeffs;
        a / (1.0 + b * x.powf(c)) + d * x + e
    }

    /// `N(μi, μo) = max(1, E(μi), E(μo))`.
    #[inline]
    fn normalization(&self, mu_i: f64, mu_o: f64) -> f64 {
        self.raw_albedo
            .eval(mu_i)
            .max(self.raw_albedo.eval(mu_o))
            .max(1.0)
    }

    /// The lobe `D V / N` with a white colour, sr⁻¹, without the cosine; 0 when either direction
    /// is at or below the horizon. Symmetric in its arguments.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let h = (wi + wo).normalize();
        let v = 1.0 / (4.0 * wi.z * wo.z * (1.0 + self.lambda(wi.z) + self.lambda(wo.z)));
        self.d(h.z) * v / self.normalization(wi.z, wo.z)
    }

    /// The lobe's directional albedo `Ê(μ) = ∫ (D V / N) cos θo dωo` at `μ = cos θi`
    /// (tabulated; at most 1).
    #[inline]
    pub fn albedo(&self, cos_theta: f64) -> f64 {
        self.albedo.eval(cos_theta)
    }

    /// The albedo of the unnormalized `D V` at `μ` (tabulated), which exceeds 1 toward grazing
    /// for smooth sheens (module docs).
    pub fn unnormalized_albedo(&self, cos_theta: f64) -> f64 {
        self.raw_albedo.eval(cos_theta)
    }

    /// The base's attenuation per unit sheen colour, `max(Ê(μi), Ê(μo))`: the base is scaled by
    /// `1 − sheen_color · base_attenuation`.
    #[inline]
    pub fn base_attenuation(&self, cos_theta_i: f64, cos_theta_o: f64) -> f64 {
        self.albedo(cos_theta_i).max(self.albedo(cos_theta_o))
    }

    /// A half vector drawn with density `D(h) cos θh` per unit solid angle: `sin θh = u1^(1/(2 +
    /// 1/α))` (the inverse of its distribution function `sin^(2 + 1/α)`), `φh = 2π u2`.
    #[inline]
    pub fn sample_h(&self, u: [f64; 2]) -> Vec3 {
        let k = 1.0 / (2.0 + 1.0 / self.alpha);
        // ln u1 · 2k: sin²θh = u1^(2k); 1 − sin² by expm1 keeps cos θh accurate near grazing.
        // max(MIN_POSITIVE): u1 = 0 would give ln 0; the smallest positive is the same draw.
        let log_sin2 = u[0].max(f64::MIN_POSITIVE).ln() * 2.0 * k;
        let sin2 = log_sin2.exp();
        let cos = (-log_sin2.exp_m1()).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        let s = sin2.sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), cos)
    }

    /// The density per unit solid angle of `drawn` by reflecting `known` about a half vector
    /// from [`sample_h`](Self::sample_h): `D(h) cos θh / (4 known·h)`.
    #[inline]
    pub fn pdf_reflected(&self, known: Vec3, drawn: Vec3) -> f64 {
        if known.z <= 0.0 || drawn.z <= 0.0 {
            return 0.0;
        }
        let h = (known + drawn).normalize();
        self.d(h.z) * h.z / (4.0 * known.dot(h))
    }

    /// Draws the other direction for `known` by [`sample_h`](Self::sample_h); `None` when the
    /// reflection falls at or below the horizon (or `h` faces away from `known`).
    #[inline]
    pub fn sample_reflected(&self, known: Vec3, u: [f64; 2]) -> Option<Vec3> {
        let h = self.sample_h(u);
        if known.dot(h) <= 0.0 {
            return None;
        }
        let d = reflect(known, h);
        (d.z > 0.0).then_some(d)
    }

    /// `∫ weight · D V cos θo dωo` at `μi = mu` by Gauss–Legendre over `t = √μo` and `φo`
    /// (panels of [`ALBEDO_POINTS`] points), `φo` over half a turn (the lobe is even in azimuth)
    /// and doubled; `weight(μi, μo)` is `1/N` or 1. `μo = t²` crowds the nodes toward the horizon,
    /// where the lobe of a smooth sheen lives and the fitted `Λ` turns steeply: 3 × 3 panels agree
    /// with 32 × 32 to 10⁻⁵ at θ = 89° and `r = 0.1`.
    fn albedo_by_quadrature(
        &self,
        gl: &GaussLegendre,
        panels: usize,
        mu: f64,
        weight: impl Fn(f64, f64) -> f64,
    ) -> f64 {
        if mu <= 0.0 {
            return 0.0; // the limit: Λ(0) = e^(a + e) is finite, the factor 1/μi is not
        }
        let wi = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
        let width = 1.0 / panels as f64;
        let mut sum = 0.0;
        for a in 0..panels {
            for b in 0..panels {
                let (t0, p0) = (a as f64 * width, b as f64 * width * PI);
                sum += gl.integrate(t0, t0 + width, |t| {
                    let mu_o = t * t;
                    let s = (1.0 - mu_o * mu_o).max(0.0).sqrt();
                    // dμo = 2t dt.
                    2.0 * t
                        * gl.integrate(p0, p0 + width * PI, |phi| {
                            let wo = Vec3::new(s * phi.cos(), s * phi.sin(), mu_o);
                            let h = (wi + wo).normalize();
                            let v = 1.0 / (4.0 * mu * (1.0 + self.lambda(mu) + self.lambda(mu_o)));
                            // f cos θo = D V μo = D / (4 μi (1 + Λi + Λo)).
                            weight(mu, mu_o) * self.d(h.z) * v
                        })
                });
            }
        }
        2.0 * sum
    }
}

/// The Charlie sheen over a Lambertian base (module docs): an RGB [`Bsdf`].
///
/// ```
/// use woven::baseline::{Sheen, SheenParams};
/// use woven::bsdf::Bsdf;
/// use woven::color::Rgb;
/// use woven::Vec3;
/// let sheen = Sheen::new(&SheenParams { sheen_color: Rgb::BLACK, ..SheenParams::default() })?;
/// // With no sheen it is the Lambertian base: 0.5/π.
/// let f = sheen.eval(Vec3::from_spherical(0.3, 0.0), Vec3::from_spherical(1.2, 2.0));
/// assert!((f.0[0] - 0.5 / std::f64::consts::PI).abs() < 1e-15);
/// # Ok::<(), woven::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Sheen {
    params: SheenParams,
    lobe: SheenLobe,
}

impl Sheen {
    /// Validates `params` and tabulates the lobe's albedos.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `diffuse`,
    /// `sheen_color` (a channel outside `[0, 1]`) or `roughness` (outside `[0.1, 1]`).
    pub fn new(params: &SheenParams) -> Result<Sheen> {
        check_reflectance("diffuse", params.diffuse)?;
        check_reflectance("sheen_color", params.sheen_color)?;
        Ok(Sheen {
            params: *params,
            lobe: SheenLobe::new(params.roughness)?,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &SheenParams {
        &self.params
    }

    /// The sheen lobe (white).
    pub fn lobe(&self) -> &SheenLobe {
        &self.lobe
    }

    /// The probability of drawing the sheen lobe for a known direction at `cos θ` (module docs).
    fn sheen_probability(&self, cos_theta: f64) -> f64 {
        let s = mean(self.params.sheen_color) * self.lobe.albedo(cos_theta);
        let d = mean(self.params.diffuse) * (1.0 - s);
        if s + d > 0.0 {
            s / (s + d)
        } else {
            0.0 // a black surface: any draw will do
        }
    }
}

impl Bsdf for Sheen {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::GLOSSY | LobeFlags::DIFFUSE
    }

    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::BLACK;
        }
        let c = self.params.sheen_color;
        let loss = self.lobe.base_attenuation(wi.z, wo.z);
        let lobe = self.lobe.eval(wi, wo);
        let mut f = [0.0; 3];
        for (k, f) in f.iter_mut().enumerate() {
            *f = self.params.diffuse.0[k] * FRAC_1_PI * (1.0 - c.0[k] * loss) + c.0[k] * lobe;
        }
        Rgb(f)
    }

    #[inline]
    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        if known.z <= 0.0 || drawn.z <= 0.0 {
            return 0.0;
        }
        let p = self.sheen_probability(known.z);
        p * self.lobe.pdf_reflected(known, drawn) + (1.0 - p) * cosine_hemisphere_pdf(drawn.z)
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
        let p = self.sheen_probability(known.z);
        let (drawn, lobe) = if uc < p {
            (self.lobe.sample_reflected(known, u)?, LobeFlags::GLOSSY)
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
    fn charlie_projected_area_is_one() {
        // ∫ D cos θh dω = 2π ∫ D cos sin dθ = 1 for every α (a golden value by adaptive quadrature).
        for r in [0.1, 0.3, 0.6, 1.0] {
            let lobe = SheenLobe::new(r).unwrap();
            let i = adaptive(0.0, FRAC_PI_2, 1e-12, 0.0, 40, |t: f64| {
                lobe.d(t.cos()) * t.cos() * t.sin()
            }) * 2.0
                * PI;
            assert!((i - 1.0).abs() < 1e-9, "r {r}: {i}");
        }
    }

    #[test]
    fn charlie_peak_and_lambda_match_the_formulas() {
        let lobe = SheenLobe::new(1.0).unwrap();
        // α = 1: D = 3 sin θh / 2π; at a horizontal half vector 3/2π.
        assert!((lobe.d(0.0) - 3.0 / (2.0 * PI)).abs() < 1e-15);
        // Λ is continuous at μ = ½ (both branches give exp(L(½))) and falls toward the normal.
        let smooth = SheenLobe::new(0.2).unwrap();
        for l in [&lobe, &smooth] {
            let (a, b) = (l.lambda(0.5 - 1e-12), l.lambda(0.5));
            assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
            assert!(l.lambda(0.1) > l.lambda(0.5) && l.lambda(0.5) > l.lambda(0.9));
        }
        // At α = 1 the blend takes the α = 1 fit alone: L(0) = a + e.
        assert!((lobe.l(0.0) - (21.5473 - 4.32054)).abs() < 1e-12);
    }

    /// `∫ f cos θo dωo` over the viewer's hemisphere by brute force (θo in `cos` panels, φo in
    /// panels), independent of the tabulation's half-vector variables.
    fn brute_albedo(f: impl Fn(Vec3) -> f64) -> f64 {
        let gl = GaussLegendre::new(16);
        let mut sum = 0.0;
        let (nc, np) = (64, 32);
        for i in 0..nc {
            let (c0, c1) = (i as f64 / nc as f64, (i + 1) as f64 / nc as f64);
            for j in 0..np {
                let (p0, p1) = (j as f64 / np as f64 * PI, (j + 1) as f64 / np as f64 * PI);
                sum += gl.integrate(c0, c1, |c| {
                    gl.integrate(p0, p1, |p| {
                        let s = (1.0 - c * c).max(0.0).sqrt();
                        f(Vec3::new(s * p.cos(), s * p.sin(), c)) * c
                    })
                });
            }
        }
        2.0 * sum
    }

    #[test]
    fn tabulated_albedos_match_brute_force() {
        for r in [0.1, 0.35, 1.0] {
            let lobe = SheenLobe::new(r).unwrap();
            for theta_deg in [0.0, 40.0, 70.0, 85.0, 89.0] {
                let mu = f64::cos(theta_deg * PI / 180.0);
                let wi = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let norm = brute_albedo(|wo| lobe.eval(wi, wo));
                let raw = brute_albedo(|wo| lobe.eval(wi, wo) * lobe.normalization(mu, wo.z));
                let (a, b) = (lobe.albedo(mu), lobe.unnormalized_albedo(mu));
                assert!(
                    (a - norm).abs() < 2e-3 && (b - raw).abs() < 2e-3 * raw.max(1.0),
                    "r {r} θ {theta_deg}: Ê {a} vs {norm}, E {b} vs {raw}"
                );
                assert!(a <= 1.0 + 1e-3, "r {r} θ {theta_deg}: Ê {a}");
            }
        }
        // The unnormalized lobe does exceed 1 at grazing for a smooth sheen (why N exists).
        let smooth = SheenLobe::new(0.1).unwrap();
        assert!(smooth.unnormalized_albedo(89f64.to_radians().cos()) > 1.2);
    }

    #[test]
    fn parameters_out_of_range_are_refused_by_name() {
        for r in [0.0, 0.05, 1.5, f64::NAN] {
            let e = SheenLobe::new(r).unwrap_err().to_string();
            assert!(e.contains("roughness") && e.contains("[0.1, 1]"), "{e}");
        }
        let bad = SheenParams {
            sheen_color: Rgb([0.5, -0.1, 0.5]),
            ..SheenParams::default()
        };
        let e = Sheen::new(&bad).unwrap_err().to_string();
        assert!(e.contains("sheen_color") && e.contains("-0.1"), "{e}");
    }
}
