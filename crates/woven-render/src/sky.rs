//! A procedural daylight sky and sun: the analytic model of Preetham, Shirley and Smits, "A
//! Practical Analytic Model for Daylight" (SIGGRAPH 1999), baked into an equirectangular map
//! that [`Environment::map`] samples in proportion to its luminance, like an EXR sky.
//!
//! ```
//! use woven_render::sky::{Sky, SkyParams};
//! use woven::Vec3;
//!
//! // A clear sky (T = 2) with the sun 60° up: the zenith's luminance is the model's zenith
//! // luminance Y_z, about 5.9 kcd/m² (Preetham's Eq. for Y_z with θ_s = 30°).
//! let sky = Sky::new(&SkyParams {
//!     sun_elevation_deg: 60.0,
//!     turbidity: 2.0,
//!     ..SkyParams::default()
//! })?;
//! let zenith = sky.sky_radiance(Vec3::Z).luminance();
//! assert!((zenith - 5.88).abs() < 0.01, "{zenith}");
//! let image = sky.image(256, 128)?;
//! let env = image.into_environment();
//! # Ok::<(), woven_render::Error>(())
//! ```
//!
//! | parameter | meaning | unit | default | valid range |
//! |---|---|---|---|---|
//! | `sun_elevation_deg` | the sun centre's angle above the horizon | degrees | 45 | [0, 90] |
//! | `sun_azimuth_deg` | the sun's azimuth, from `+x` toward `+y` | degrees | 0 | finite (wrapped) |
//! | `turbidity` | Linke-like haze `T`: 2 clear, 3 clear and dry-warm, 6 warm and moist, 10 hazy | — | 3 | [2, 10] |
//! | `scale` | multiplies every radiance | — | 1 | finite, ≥ 0 |
//! | `sun` | whether the sun's disc is added to the sky | — | true | |
//!
//! **Frame and layout** (those of [`crate::light`]): `+z` is up; azimuth `φ` is measured from
//! `+x` toward `+y`. The map is row-major, row `y` covering polar angles `θ ∈ [y, y+1]·π/H`
//! from `+z` (row 0 at the zenith), column `x` covering `φ ∈ [x, x+1]·2π/W`.
//!
//! **Units**: the model's luminances are in kcd m⁻², and a pixel is the linear-sRGB colour whose
//! Rec. 709 luminance is that number (times `scale`). A clear noon zenith is ≈ 5–10, the sun's
//! disc ≈ 10⁶, and the integral of the map times `cos θ` over the upper hemisphere is the
//! horizontal illuminance in klx (≈ 100 in clear midday sun). A white diffuse plane under it is
//! ≈ 30 times brighter than under a unit [`Environment::constant`]; `scale = 1/30` brings it
//! near 1.
//!
//! **Below the horizon** the map is black (the ground is left to the scene's geometry), and the
//! part of the sun's disc below it is dropped.
//!
//! **Approximations** (each with its error):
//! - Each pixel is the sky's value at its centre (midpoint rule); the row that straddles the
//!   horizon (odd `H`) takes the value at the middle of its upper part, times that part's share
//!   of the row's solid angle, so that its energy is kept.
//! - Chromaticities outside the sRGB gamut (rare; low sun, high turbidity) lose their negative
//!   channels (set to 0).
//! - The sun is a uniform disc of angular radius [`SUN_ANGULAR_RADIUS`] (no limb darkening). Its
//!   radiance is the extraterrestrial sun's (the solar illuminance constant over the disc's
//!   solid angle, taken white: the real sun, ≈ 5800 K, is a few per cent warmer than D65)
//!   attenuated per channel by Rayleigh and aerosol extinction at one wavelength per channel
//!   ([`sun_transmittance`]); ozone and water-vapour absorption (a few per cent) are ignored.
//! - The disc is smaller than a pixel at ordinary resolutions: its power is spread over the
//!   pixels its points fall in (1024 equal-solid-angle points), so the disc looks a pixel or
//!   two wide but its irradiance, `L_sun Ω_sun cos θ_s`, is kept (to the share of its points
//!   above the horizon when it sets).

use crate::color::Rgb;
use crate::light::Environment;
use crate::{Error, Result};
use std::f64::consts::PI;
use woven::Vec3;

/// The sun's mean angular radius seen from the Earth, radians (0.2666°; ±1.7% over the year).
pub const SUN_ANGULAR_RADIUS: f64 = 0.2666 * PI / 180.0;

/// The solar illuminance constant, klx: the illuminance of the sun outside the atmosphere at the
/// mean Sun–Earth distance (published values range over 127.5–133.8 klx; ±3% around this).
pub const SOLAR_ILLUMINANCE_CONSTANT: f64 = 128.0;

/// The width of the map a scene's `type = "sky"` light is baked into (0.35° per pixel).
pub const SKY_MAP_WIDTH: usize = 1024;

/// The height of the map a scene's `type = "sky"` light is baked into.
pub const SKY_MAP_HEIGHT: usize = 512;

/// The sky and sun parameters; see the [module](self)'s table for ranges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyParams {
    /// The sun centre's elevation above the horizon, degrees, in [0, 90].
    pub sun_elevation_deg: f64,
    /// The sun's azimuth from `+x` toward `+y`, degrees (any finite value).
    pub sun_azimuth_deg: f64,
    /// Atmospheric turbidity `T`, in [2, 10].
    pub turbidity: f64,
    /// A factor on every radiance, finite and ≥ 0.
    pub scale: f64,
    /// Whether the sun's disc is added to the sky.
    pub sun: bool,
}

impl Default for SkyParams {
    fn default() -> Self {
        SkyParams {
            sun_elevation_deg: 45.0,
            sun_azimuth_deg: 0.0,
            turbidity: 3.0,
            scale: 1.0,
            sun: true,
        }
    }
}

/// The five coefficients `A…E` of the Perez et al. (1993) distribution.
#[derive(Clone, Copy, Debug)]
struct Perez([f64; 5]);

impl Perez {
    /// The coefficients as linear functions of turbidity: `coef[i] = slope[i]·T + offset[i]`.
    fn of_turbidity(slope: [f64; 5], offset: [f64; 5], t: f64) -> Perez {
        Perez(std::array::from_fn(|i| slope[i] * t + offset[i]))
    }

    /// `F(θ, γ) = (1 + A e^{B / cos θ})(1 + C e^{D γ} + E cos² γ)` for a view direction at polar
    /// angle `θ` (given as `cos θ`, ≥ 0) and angle `γ` from the sun.
    ///
    /// Implements the Perez luminance distribution, Eq. (3) of Preetham et al. (1999).
    fn f(&self, cos_theta: f64, gamma: f64) -> f64 {
        let [a, b, c, d, e] = self.0;
        // At the horizon B / cos θ → −∞ (B < 0 for every T in [2, 10]), so the exponential → 0;
        // the floor keeps the division finite and of the right sign.
        let cos_theta = cos_theta.max(1e-9);
        let cos_gamma = gamma.cos();
        (1.0 + a * (b / cos_theta).exp())
            * (1.0 + c * (d * gamma).exp() + e * cos_gamma * cos_gamma)
    }
}

/// A Preetham sky for one sun position and turbidity, ready to evaluate in any direction.
#[derive(Clone, Debug)]
pub struct Sky {
    params: SkyParams,
    /// Unit direction toward the sun's centre.
    sun_dir: Vec3,
    /// Perez coefficients for luminance `Y` and chromaticities `x`, `y`.
    perez: [Perez; 3],
    /// `Y_z / F(0, θ_s)`, `x_z / F(0, θ_s)`, `y_z / F(0, θ_s)`: the zenith values over the
    /// distribution at the zenith, so that `value(θ, γ) = ratio · F(θ, γ)`.
    ratio: [f64; 3],
    /// The sun disc's radiance, kcd m⁻² per linear-sRGB channel, before `scale`.
    sun_radiance: Rgb,
}

impl Sky {
    /// The sky for `params`.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] naming the parameter, its value and its range when one is out
    /// of range or not finite.
    pub fn new(params: &SkyParams) -> Result<Sky> {
        check_range(
            "sun_elevation_deg",
            params.sun_elevation_deg,
            0.0,
            90.0,
            "in [0, 90]",
        )?;
        check_range(
            "sun_azimuth_deg",
            params.sun_azimuth_deg,
            f64::MIN,
            f64::MAX,
            "a finite angle",
        )?;
        check_range("turbidity", params.turbidity, 2.0, 10.0, "in [2, 10]")?;
        check_range("scale", params.scale, 0.0, f64::MAX, "a finite number >= 0")?;

        let t = params.turbidity;
        let theta_s = (90.0 - params.sun_elevation_deg).to_radians();
        let sun_dir = Vec3::from_spherical(theta_s, params.sun_azimuth_deg.to_radians());

        // Perez coefficients for Y, x and y; Preetham et al. (1999), Appendix A.2.
        let perez = [
            Perez::of_turbidity(
                [0.1787, -0.3554, -0.0227, 0.1206, -0.0670],
                [-1.4630, 0.4275, 5.3251, -2.5771, 0.3703],
                t,
            ),
            Perez::of_turbidity(
                [-0.0193, -0.0665, -0.0004, -0.0641, -0.0033],
                [-0.2592, 0.0008, 0.2125, -0.8989, 0.0452],
                t,
            ),
            Perez::of_turbidity(
                [-0.0167, -0.0950, -0.0079, -0.0441, -0.0109],
                [-0.2608, 0.0092, 0.2102, -1.6537, 0.0529],
                t,
            ),
        ];
        let zenith = zenith_values(t, theta_s);
        let ratio = std::array::from_fn(|i| zenith[i] / perez[i].f(1.0, theta_s));

        // The disc: the extraterrestrial sun's luminance, white, times the transmittance.
        let sun_luminance = SOLAR_ILLUMINANCE_CONSTANT / sun_solid_angle();
        let sun_radiance = sun_transmittance(t, theta_s) * sun_luminance;

        Ok(Sky {
            params: *params,
            sun_dir,
            perez,
            ratio,
            sun_radiance,
        })
    }

    /// The parameters this sky was built from.
    pub fn params(&self) -> &SkyParams {
        &self.params
    }

    /// The unit direction toward the sun's centre (`+z` up, azimuth from `+x` toward `+y`).
    pub fn sun_direction(&self) -> Vec3 {
        self.sun_dir
    }

    /// The sun disc's radiance, kcd m⁻² per linear-sRGB channel, times `scale` (whether or not
    /// `sun` is set).
    pub fn sun_radiance(&self) -> Rgb {
        self.sun_radiance * self.params.scale
    }

    /// The sky's radiance (without the sun's disc) arriving from the unit direction `d`,
    /// kcd m⁻² per linear-sRGB channel, times `scale`; black below the horizon (`d.z < 0`).
    ///
    /// Implements Eq. (4) of Preetham et al. (1999), `Y = Y_z F(θ, γ) / F(0, θ_s)` and the same
    /// for `x`, `y`, then xyY → XYZ → linear sRGB.
    pub fn sky_radiance(&self, d: Vec3) -> Rgb {
        if d.z < 0.0 {
            return Rgb::BLACK;
        }
        let gamma = d.dot(self.sun_dir).clamp(-1.0, 1.0).acos();
        let [lum, x, y] = std::array::from_fn(|i| self.ratio[i] * self.perez[i].f(d.z, gamma));
        xyy_to_linear_srgb(x, y, lum) * self.params.scale
    }

    /// The equirectangular map, `width × height` pixels (layout in the [module](self) docs):
    /// the sky at each pixel, plus the sun's disc when `sun` is set.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] when `width` is not in [1, 16384] or `height` not in [1, 8192].
    pub fn image(&self, width: usize, height: usize) -> Result<SkyImage> {
        check_range("width", width as f64, 1.0, 16384.0, "in [1, 16384]")?;
        check_range("height", height as f64, 1.0, 8192.0, "in [1, 8192]")?;
        let d_theta = PI / height as f64;
        let d_phi = 2.0 * PI / width as f64;
        let mut pixels = vec![Rgb::BLACK; width * height];

        // The sky at each pixel's centre; rows wholly below the horizon stay black.
        for y in 0..height {
            let theta0 = y as f64 * d_theta;
            if theta0 >= PI / 2.0 {
                break;
            }
            let theta1 = (y + 1) as f64 * d_theta;
            // A row straddling the horizon: its upper part's middle, weighted by that part's
            // share of the row's solid angle.
            let (theta, share) = if theta1 > PI / 2.0 {
                let share = theta0.cos() / (theta0.cos() - theta1.cos());
                (0.5 * (theta0 + PI / 2.0), share)
            } else {
                (0.5 * (theta0 + theta1), 1.0)
            };
            for x in 0..width {
                let phi = (x as f64 + 0.5) * d_phi;
                pixels[y * width + x] = self.sky_radiance(Vec3::from_spherical(theta, phi)) * share;
            }
        }

        if self.params.sun {
            self.add_sun_disc(&mut pixels, width, height);
        }
        Ok(SkyImage {
            width,
            height,
            pixels,
        })
    }

    /// Adds the disc's power to the pixels its points fall in: `SUN_POINTS²` points of equal
    /// solid angle over the disc, each carrying `L_sun Ω_sun / n` of radiant intensity, spread
    /// over its pixel's solid angle. Points below the horizon are dropped.
    fn add_sun_disc(&self, pixels: &mut [Rgb], width: usize, height: usize) {
        const SUN_POINTS: usize = 32;
        let cos_r = SUN_ANGULAR_RADIUS.cos();
        let point_solid_angle = sun_solid_angle() / (SUN_POINTS * SUN_POINTS) as f64;
        let radiance = self.sun_radiance();
        // An orthonormal frame (t1, t2, sun) around the sun's direction.
        let s = self.sun_dir;
        let helper = if s.z.abs() < 0.9 {
            Vec3::Z
        } else {
            Vec3::new(1.0, 0.0, 0.0)
        };
        let t1 = helper.cross(s).normalize();
        let t2 = s.cross(t1);
        let d_phi = 2.0 * PI / width as f64;
        let d_theta = PI / height as f64;
        for i in 0..SUN_POINTS {
            // Uniform in solid angle over the cap: cos α uniform in [cos r, 1].
            let cos_a = 1.0 - (i as f64 + 0.5) / SUN_POINTS as f64 * (1.0 - cos_r);
            let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
            for j in 0..SUN_POINTS {
                let beta = (j as f64 + 0.5) / SUN_POINTS as f64 * 2.0 * PI;
                let d = t1 * (sin_a * beta.cos()) + t2 * (sin_a * beta.sin()) + s * cos_a;
                if d.z < 0.0 {
                    continue;
                }
                let (x, y) = pixel_of(d, width, height);
                let theta0 = y as f64 * d_theta;
                let pixel_solid_angle = d_phi * (theta0.cos() - (theta0 + d_theta).cos());
                pixels[y * width + x] += radiance * (point_solid_angle / pixel_solid_angle);
            }
        }
    }
}

/// A sky baked into an equirectangular map, linear sRGB, kcd m⁻² per channel times `scale`.
#[derive(Clone, Debug)]
pub struct SkyImage {
    /// Columns (azimuth).
    pub width: usize,
    /// Rows (polar angle; row 0 at the zenith).
    pub height: usize,
    /// Row-major pixels.
    pub pixels: Vec<Rgb>,
}

impl SkyImage {
    /// The environment light of this map (scale 1: the sky's `scale` is already in the pixels),
    /// importance sampled like an EXR map.
    pub fn into_environment(self) -> Environment {
        Environment::map(self.width, self.height, self.pixels, 1.0)
    }

    /// The pixel direction `d` (unit) falls in.
    pub fn at(&self, d: Vec3) -> Rgb {
        let (x, y) = pixel_of(d, self.width, self.height);
        self.pixels[y * self.width + x]
    }
}

/// Builds the map of the sky for `params`: [`Sky::new`] then [`Sky::image`].
///
/// # Errors
/// As those two.
pub fn sky_image(params: &SkyParams, width: usize, height: usize) -> Result<SkyImage> {
    Sky::new(params)?.image(width, height)
}

/// The solid angle of the sun's disc, sr (≈ 6.80 × 10⁻⁵).
pub fn sun_solid_angle() -> f64 {
    2.0 * PI * (1.0 - SUN_ANGULAR_RADIUS.cos())
}

/// The fraction of the sun's light that crosses the atmosphere to the ground, per linear-sRGB
/// channel, for turbidity `t` and the sun at polar angle `theta_s` (radians, in [0, π/2]).
///
/// Rayleigh and aerosol (Ångström) extinction, `exp(−m (0.008735 λ^−4.08 + β λ^−α))` with `λ`
/// in µm, `α = 1.3`, `β = 0.04608 T − 0.04586`, and Kasten's relative optical mass `m` (the
/// forms Preetham et al. (1999) use in their Appendix A.1), evaluated at one wavelength per
/// channel (610, 550 and 465 nm) rather than integrated over the spectrum: a few per cent of
/// colour error; ozone and water-vapour absorption are ignored (they would take a few per cent
/// more).
pub fn sun_transmittance(t: f64, theta_s: f64) -> Rgb {
    let theta_deg = theta_s.to_degrees();
    // Kasten (1966); finite at the horizon (m ≈ 38 at θ_s = 90°).
    let m = 1.0 / (theta_s.cos() + 0.15 * (93.885 - theta_deg).powf(-1.253));
    let beta = 0.04608 * t - 0.04586;
    let alpha = 1.3;
    let tau = |lambda_um: f64| {
        let depth = 0.008735 * lambda_um.powf(-4.08) + beta * lambda_um.powf(-alpha);
        (-m * depth).exp()
    };
    Rgb([tau(0.610), tau(0.550), tau(0.465)])
}

/// The zenith's luminance `Y_z` (kcd m⁻²) and chromaticity `x_z`, `y_z` for turbidity `t` and
/// the sun at polar angle `theta_s` (radians).
///
/// Implements the zenith formulas of Preetham et al. (1999), Appendix A.2.
fn zenith_values(t: f64, theta_s: f64) -> [f64; 3] {
    let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * theta_s);
    let y_lum = (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192;
    // [T², T, 1] · M · [θ³, θ², θ, 1].
    let chroma = |m: [[f64; 4]; 3]| {
        let th = [theta_s.powi(3), theta_s.powi(2), theta_s, 1.0];
        let tt = [t * t, t, 1.0];
        (0..3)
            .map(|i| tt[i] * (0..4).map(|j| m[i][j] * th[j]).sum::<f64>())
            .sum::<f64>()
    };
    let x = chroma([
        [0.00166, -0.00375, 0.00209, 0.0],
        [-0.02903, 0.06377, -0.03202, 0.00394],
        [0.11693, -0.21196, 0.06052, 0.25886],
    ]);
    let y = chroma([
        [0.00275, -0.00610, 0.00317, 0.0],
        [-0.04214, 0.08970, -0.04153, 0.00516],
        [0.15346, -0.26756, 0.06670, 0.26688],
    ]);
    [y_lum, x, y]
}

/// CIE xyY → XYZ → linear sRGB (IEC 61966-2-1 matrix, D65); negative channels (outside the
/// gamut) are set to 0.
fn xyy_to_linear_srgb(x: f64, y: f64, lum: f64) -> Rgb {
    // y > 0 for every chromaticity the model gives (≈ 0.25–0.45); the guard keeps a
    // degenerate input from dividing by zero.
    if y <= 1e-12 || lum <= 0.0 {
        return Rgb::BLACK;
    }
    let cx = x / y * lum;
    let cz = (1.0 - x - y) / y * lum;
    let r = 3.2404542 * cx - 1.5371385 * lum - 0.4985314 * cz;
    let g = -0.9692660 * cx + 1.8760108 * lum + 0.0415560 * cz;
    let b = 0.0556434 * cx - 0.2040259 * lum + 1.0572252 * cz;
    Rgb([r.max(0.0), g.max(0.0), b.max(0.0)])
}

/// The map pixel direction `d` falls in: the same mapping as [`Environment`]'s.
fn pixel_of(d: Vec3, width: usize, height: usize) -> (usize, usize) {
    let theta = d.z.clamp(-1.0, 1.0).acos();
    let mut phi = d.y.atan2(d.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let x = ((phi / (2.0 * PI) * width as f64) as usize).min(width - 1);
    let y = ((theta / PI * height as f64) as usize).min(height - 1);
    (x, y)
}

/// `Ok` when `value` is finite and in `[lo, hi]`, else [`Error::InvalidSetting`] naming it.
fn check_range(name: &str, value: f64, lo: f64, hi: f64, expected: &str) -> Result<()> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(Error::InvalidSetting {
            name: name.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(elevation: f64, azimuth: f64, t: f64, sun: bool) -> Sky {
        Sky::new(&SkyParams {
            sun_elevation_deg: elevation,
            sun_azimuth_deg: azimuth,
            turbidity: t,
            scale: 1.0,
            sun,
        })
        .unwrap()
    }

    /// The direction at elevation `el` and azimuth `az`, degrees.
    fn dir(el: f64, az: f64) -> Vec3 {
        Vec3::from_spherical((90.0 - el).to_radians(), az.to_radians())
    }

    /// Horizontal illuminance of a map, klx: Σ L cos θ ΔΩ over the pixels.
    fn horizontal_illuminance(img: &SkyImage) -> f64 {
        let (w, h) = (img.width, img.height);
        let d_theta = PI / h as f64;
        let mut sum = 0.0;
        for y in 0..h {
            let (t0, t1) = (y as f64 * d_theta, (y + 1) as f64 * d_theta);
            // ∫ cos θ sin θ dθ over the row, times the column's Δφ.
            let weight = 0.5 * (t1.sin().powi(2) - t0.sin().powi(2)) * 2.0 * PI / w as f64;
            let row: f64 = (0..w).map(|x| img.pixels[y * w + x].luminance()).sum();
            sum += row * weight;
        }
        sum
    }

    /// Preetham's clear skies brighten toward the horizon away from the sun: at 10° elevation,
    /// at 90° and 180° in azimuth from the sun, the sky is > 1.3× the zenith for T = 2 with the
    /// sun up to 70° (higher, the zenith is near the sun) and for T = 3 with the sun below 30°.
    /// (At higher turbidity and sun the model's zenith outgrows its horizon, a known trait of
    /// its zenith formula.)
    #[test]
    fn clear_sky_horizon_is_brighter_than_zenith_away_from_the_sun() {
        let cases = [(2.0, 5.0), (2.0, 20.0), (2.0, 45.0), (2.0, 70.0)];
        for (t, elevation) in cases.into_iter().chain([(3.0, 10.0), (3.0, 25.0)]) {
            let s = sky(elevation, 30.0, t, false);
            let zenith = s.sky_radiance(Vec3::Z).luminance();
            for az in [30.0 + 90.0, 30.0 + 180.0] {
                let horizon = s.sky_radiance(dir(10.0, az)).luminance();
                assert!(
                    horizon > 1.3 * zenith,
                    "T = {t}, sun at {elevation}°: horizon at azimuth {az}° {horizon} \
                     vs zenith {zenith} (want > 1.3×)"
                );
            }
        }
    }

    /// The sky is bluer at the zenith than at the horizon (clear, high sun).
    #[test]
    fn clear_zenith_is_blue() {
        let s = sky(60.0, 0.0, 2.5, false);
        let z = s.sky_radiance(Vec3::Z).0;
        assert!(z[2] > z[0], "zenith {z:?}: blue should exceed red");
        let h = s.sky_radiance(dir(2.0, 180.0)).0;
        assert!(z[2] / z[0] > h[2] / h[0], "zenith {z:?} horizon {h:?}");
    }

    /// The brightest pixel holds the sun, and `Environment` finds it looking toward the sun
    /// (the layouts agree); without the disc the brightest sky is circumsolar.
    #[test]
    fn the_sun_region_is_brightest_and_where_the_environment_expects_it() {
        let (w, h) = (512, 256);
        let centre = |i: usize| {
            let theta = ((i / w) as f64 + 0.5) * PI / h as f64;
            let phi = ((i % w) as f64 + 0.5) * 2.0 * PI / w as f64;
            Vec3::from_spherical(theta, phi)
        };
        let brightest = |img: &SkyImage| {
            let (i, p) = img
                .pixels
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.luminance().total_cmp(&b.1.luminance()))
                .unwrap();
            (i, p.luminance())
        };
        for (el, az) in [(30.0, 0.0), (45.0, 100.0), (10.0, 250.0), (85.0, -40.0)] {
            let s = sky(el, az, 3.0, true);
            let img = s.image(w, h).unwrap();
            let sky_img = sky(el, az, 3.0, false).image(w, h).unwrap();
            let (i, peak) = brightest(&img);
            let (j, sky_peak) = brightest(&sky_img);
            // The sun's pixel: within the disc's radius plus a pixel's diagonal of its centre.
            let gamma = centre(i).dot(s.sun_direction()).acos();
            let reach = SUN_ANGULAR_RADIUS + PI / h as f64 + 2.0 * PI / w as f64;
            assert!(
                gamma < reach,
                "sun at ({el}°, {az}°): peak {gamma} rad away"
            );
            let env = img.into_environment();
            let toward_sun = env.radiance(s.sun_direction()).luminance();
            assert!(
                toward_sun > 1e3 * sky_peak && toward_sun > 0.2 * peak,
                "sun at ({el}°, {az}°): toward the sun {toward_sun}, peak {peak}, sky {sky_peak}"
            );
            // Sky only: the brightest pixel lies within 10° of the sun.
            let gamma = centre(j).dot(s.sun_direction()).acos().to_degrees();
            assert!(
                gamma < 10.0,
                "sun at ({el}°, {az}°): sky peak {gamma}° away"
            );
        }
    }

    /// Horizontal illuminance, sun at 60°, T = 3: the disc gives `L_sun Ω_sun cos θ_s` (the
    /// splat keeps it to 0.1%), ≈ 79 klx of direct light (clear-day beam illuminance on the
    /// ground at that height is 70–100 klx) and the sky ≈ 32 klx of diffuse light; measured
    /// clear skies give 15–30 klx there, and Preetham's model is known to run bright as the
    /// turbidity grows (Zotti, Wilkie and Purgathofer 2007), hence 15–40. Global ≈ 110 klx.
    #[test]
    fn energy_is_plausible_and_the_disc_keeps_its_power() {
        let s = sky(60.0, 45.0, 3.0, true);
        let with_sun = horizontal_illuminance(&s.image(1024, 512).unwrap());
        let sky_only =
            horizontal_illuminance(&sky(60.0, 45.0, 3.0, false).image(1024, 512).unwrap());
        let direct = with_sun - sky_only;
        let expected = s.sun_radiance().luminance() * sun_solid_angle() * 30f64.to_radians().cos();
        assert!(
            (direct - expected).abs() < 1e-3 * expected,
            "direct {direct} klx vs L Ω cos θ = {expected} (tolerance 0.1%)"
        );
        assert!(
            (70.0..100.0).contains(&direct),
            "direct {direct} klx, want 70–100"
        );
        assert!(
            (15.0..40.0).contains(&sky_only),
            "diffuse {sky_only} klx, want 15–40"
        );
        assert!(
            (90.0..130.0).contains(&with_sun),
            "global {with_sun} klx, want 90–130"
        );
        // Haze moves light from the beam to the sky.
        let hazy = sky(60.0, 45.0, 8.0, false).image(256, 128).unwrap();
        assert!(horizontal_illuminance(&hazy) > sky_only);
        assert!(
            sky(60.0, 45.0, 8.0, true).sun_radiance().luminance() < s.sun_radiance().luminance()
        );
    }

    /// Over the whole parameter range no pixel is NaN, infinite or negative, the rows below
    /// the horizon are black, and `scale` multiplies everything.
    #[test]
    fn images_are_valid_and_black_below_the_horizon() {
        for t in [2.0, 2.5, 4.0, 6.0, 8.0, 10.0] {
            for el in [0.0, 0.5, 5.0, 20.0, 45.0, 70.0, 89.9, 90.0] {
                for sun in [false, true] {
                    let s = sky(el, 123.0, t, sun);
                    // Odd height: one row straddles the horizon.
                    for (w, h) in [(64, 32), (33, 17), (4, 1)] {
                        let img = s.image(w, h).unwrap();
                        for (i, p) in img.pixels.iter().enumerate() {
                            assert!(p.is_valid(), "T {t} el {el}: pixel {i} = {:?}", p.0);
                            let theta0 = (i / w) as f64 * PI / h as f64;
                            if theta0 >= PI / 2.0 {
                                assert!(p.is_black(), "T {t} el {el}: pixel {i} below horizon");
                            }
                        }
                    }
                }
            }
        }
        let one = sky(30.0, 0.0, 3.0, true).image(32, 16).unwrap();
        let mut params = *sky(30.0, 0.0, 3.0, true).params();
        params.scale = 0.25;
        let quarter = sky_image(&params, 32, 16).unwrap();
        for (a, b) in one.pixels.iter().zip(&quarter.pixels) {
            for c in 0..3 {
                assert!((a.0[c] * 0.25 - b.0[c]).abs() <= 1e-12 * a.0[c]);
            }
        }
    }

    /// The sun reddens toward the horizon and dims with haze.
    #[test]
    fn sun_transmittance_reddens_low_suns() {
        let high = sun_transmittance(3.0, 0.0);
        let low = sun_transmittance(3.0, 85f64.to_radians());
        assert!(high.0[0] > high.0[2] && low.0[0] / low.0[2] > high.0[0] / high.0[2]);
        assert!(
            (0.6..0.85).contains(&high.0[1]),
            "zenith-sun green transmittance {:?}",
            high.0
        );
        assert!(sun_transmittance(10.0, 0.0).0[1] < high.0[1]);
    }

    /// Out-of-range parameters are refused with their name, value and range.
    #[test]
    fn bad_parameters_are_named() {
        let cases = [
            (
                SkyParams {
                    sun_elevation_deg: -5.0,
                    ..SkyParams::default()
                },
                "sun_elevation_deg",
                "in [0, 90]",
            ),
            (
                SkyParams {
                    sun_elevation_deg: 91.0,
                    ..SkyParams::default()
                },
                "sun_elevation_deg",
                "in [0, 90]",
            ),
            (
                SkyParams {
                    sun_azimuth_deg: f64::NAN,
                    ..SkyParams::default()
                },
                "sun_azimuth_deg",
                "finite",
            ),
            (
                SkyParams {
                    turbidity: 1.5,
                    ..SkyParams::default()
                },
                "turbidity",
                "in [2, 10]",
            ),
            (
                SkyParams {
                    turbidity: 12.0,
                    ..SkyParams::default()
                },
                "turbidity",
                "in [2, 10]",
            ),
            (
                SkyParams {
                    scale: -1.0,
                    ..SkyParams::default()
                },
                "scale",
                ">= 0",
            ),
            (
                SkyParams {
                    scale: f64::INFINITY,
                    ..SkyParams::default()
                },
                "scale",
                ">= 0",
            ),
        ];
        for (params, name, range) in cases {
            let message = Sky::new(&params).unwrap_err().to_string();
            assert!(
                message.contains(name) && message.contains(range),
                "{params:?}: {message}"
            );
        }
        let message = sky_image(&SkyParams::default(), 0, 8)
            .unwrap_err()
            .to_string();
        assert_eq!(
            message,
            "invalid setting `width` = 0: expected in [1, 16384]"
        );
        let message = sky_image(
            &SkyParams {
                turbidity: 1.5,
                ..SkyParams::default()
            },
            8,
            4,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            message,
            "invalid setting `turbidity` = 1.5: expected in [2, 10]"
        );
    }
}
