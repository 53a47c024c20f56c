//! Light sources: point lights, environments (constant or an equirectangular map) and
//! rectangular area lights.
//!
//! Units: point intensity in W sr⁻¹, radiance in W m⁻² sr⁻¹ (per RGB channel). A rectangle emits
//! from the side its normal `edge_u × edge_v` faces. An environment map is equirectangular with
//! `+z` up: column `x` covers azimuths `φ ∈ [x, x+1]·2π/W` measured from `+x` toward `+y`, row `y`
//! polar angles `θ ∈ [y, y+1]·π/H` from `+z` (row 0 at the zenith); it is sampled in proportion
//! to its luminance.

use crate::color::Rgb;
use crate::{Error, Result};
use std::f64::consts::PI;
use std::path::Path;
use woven::Vec3;

/// A piecewise-constant distribution on `[0, 1)`, for sampling tabulated functions.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// The cumulative weights, `cdf[0] = 0`, `cdf[n] = 1`.
    cdf: Vec<f64>,
    /// The total weight.
    total: f64,
}

impl Distribution1D {
    /// From non-negative weights; all-zero weights give a uniform distribution.
    pub fn new(weights: &[f64]) -> Distribution1D {
        let n = weights.len();
        let total: f64 = weights.iter().map(|w| w.max(0.0)).sum();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0);
        let mut acc = 0.0;
        for (i, w) in weights.iter().enumerate() {
            acc += if total > 0.0 {
                w.max(0.0) / total
            } else {
                1.0 / n as f64
            };
            cdf.push(if i + 1 == n { 1.0 } else { acc });
        }
        Distribution1D { cdf, total }
    }

    /// The number of bins.
    pub fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// Whether there are no bins.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The total weight.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The probability of bin `i`.
    pub fn probability(&self, i: usize) -> f64 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// Draws a bin from a uniform `u ∈ [0, 1)`: `(bin, the position in it in [0, 1))`.
    pub fn sample(&self, u: f64) -> (usize, f64) {
        let n = self.len();
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
        let p = self.probability(i);
        let t = if p > 0.0 {
            ((u - self.cdf[i]) / p).clamp(0.0, 1.0 - f64::EPSILON)
        } else {
            0.5
        };
        (i, t)
    }
}

/// An environment: radiance arriving from infinitely far away in every direction.
#[derive(Clone, Debug)]
pub struct Environment {
    kind: EnvKind,
    scale: f64,
}

#[derive(Clone, Debug)]
enum EnvKind {
    Constant(Rgb),
    Map {
        width: usize,
        height: usize,
        pixels: Vec<Rgb>,
        rows: Distribution1D,
        columns: Vec<Distribution1D>,
    },
}

impl Environment {
    /// A uniform environment of radiance `radiance × scale`.
    pub fn constant(radiance: Rgb, scale: f64) -> Environment {
        Environment {
            kind: EnvKind::Constant(radiance),
            scale,
        }
    }

    /// An equirectangular map (row-major, row 0 at the zenith), times `scale`.
    pub fn map(width: usize, height: usize, pixels: Vec<Rgb>, scale: f64) -> Environment {
        // Sample ∝ luminance × sin θ (the solid angle of a row).
        let mut columns = Vec::with_capacity(height);
        let mut row_weights = Vec::with_capacity(height);
        for y in 0..height {
            let sin = ((y as f64 + 0.5) * PI / height as f64).sin();
            let w: Vec<f64> = pixels[y * width..(y + 1) * width]
                .iter()
                .map(|p| p.luminance().max(0.0) * sin)
                .collect();
            let d = Distribution1D::new(&w);
            row_weights.push(d.total());
            columns.push(d);
        }
        Environment {
            kind: EnvKind::Map {
                width,
                height,
                rows: Distribution1D::new(&row_weights),
                columns,
                pixels,
            },
            scale,
        }
    }

    /// Reads an equirectangular OpenEXR map (`+z` up).
    ///
    /// # Errors
    /// [`Error::Image`] when the file cannot be read as an RGB(A) EXR or holds a negative,
    /// infinite or NaN pixel.
    pub fn from_exr(path: &Path, scale: f64) -> Result<Environment> {
        use exr::prelude::read_first_rgba_layer_from_file;
        let image = read_first_rgba_layer_from_file(
            path,
            |resolution, _| {
                (
                    resolution.width(),
                    vec![Rgb::BLACK; resolution.width() * resolution.height()],
                )
            },
            |(w, pixels): &mut (usize, Vec<Rgb>), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                pixels[pos.y() * *w + pos.x()] = Rgb([r as f64, g as f64, b as f64]);
            },
        )
        .map_err(|e| Error::Image {
            path: path.to_path_buf(),
            message: format!("cannot read the environment map: {e}"),
        })?;
        let size = image.layer_data.size;
        let (_, pixels) = image.layer_data.channel_data.pixels;
        if let Some(i) = pixels.iter().position(|p| !p.is_valid()) {
            return Err(Error::Image {
                path: path.to_path_buf(),
                message: format!(
                    "pixel ({}, {}) is {:?}: an environment's radiance must be finite and >= 0",
                    i % size.width(),
                    i / size.width(),
                    pixels[i].0
                ),
            });
        }
        Ok(Environment::map(size.width(), size.height(), pixels, scale))
    }

    /// The radiance arriving from direction `d` (unit, pointing away from the scene).
    pub fn radiance(&self, d: Vec3) -> Rgb {
        match &self.kind {
            EnvKind::Constant(c) => *c * self.scale,
            EnvKind::Map {
                width,
                height,
                pixels,
                ..
            } => {
                let (x, y) = pixel_of(d, *width, *height);
                pixels[y * width + x] * self.scale
            }
        }
    }

    /// Draws a direction toward the environment: `(d, density per unit solid angle)`.
    pub fn sample(&self, u1: f64, u2: f64) -> Option<(Vec3, f64)> {
        match &self.kind {
            EnvKind::Constant(_) => {
                // Uniform on the sphere.
                let z = 1.0 - 2.0 * u1;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = 2.0 * PI * u2;
                Some((Vec3::new(r * phi.cos(), r * phi.sin(), z), 1.0 / (4.0 * PI)))
            }
            EnvKind::Map {
                width,
                height,
                rows,
                columns,
                ..
            } => {
                let (y, ty) = rows.sample(u1);
                let (x, tx) = columns[y].sample(u2);
                let theta = (y as f64 + ty) * PI / *height as f64;
                let phi = (x as f64 + tx) * 2.0 * PI / *width as f64;
                let d = Vec3::from_spherical(theta, phi);
                let pdf = self.pdf(d);
                (pdf > 0.0).then_some((d, pdf))
            }
        }
    }

    /// The density [`sample`](Self::sample) draws `d` with, per unit solid angle.
    pub fn pdf(&self, d: Vec3) -> f64 {
        match &self.kind {
            EnvKind::Constant(_) => 1.0 / (4.0 * PI),
            EnvKind::Map {
                width,
                height,
                rows,
                columns,
                ..
            } => {
                let (x, y) = pixel_of(d, *width, *height);
                let sin = (1.0 - d.z * d.z).max(0.0).sqrt();
                if sin <= 0.0 {
                    return 0.0;
                }
                let p = rows.probability(y) * columns[y].probability(x);
                // Per texel area in (θ, φ): (π/H)(2π/W); dω = sin θ dθ dφ.
                p * (*width * *height) as f64 / (2.0 * PI * PI * sin)
            }
        }
    }
}

/// The map pixel direction `d` falls in.
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

/// A light source.
#[derive(Clone, Debug)]
pub enum Light {
    /// A point light; never seen by camera rays, never hit by BSDF-sampled rays.
    Point {
        /// Position.
        position: Vec3,
        /// Intensity, W sr⁻¹ per channel.
        intensity: Rgb,
    },
    /// Light from infinitely far away.
    Environment(Environment),
    /// A one-sided parallelogram emitter (also geometry: primitive `prim`, which reflects
    /// nothing).
    Rectangle {
        /// A corner.
        corner: Vec3,
        /// First edge.
        edge_u: Vec3,
        /// Second edge.
        edge_v: Vec3,
        /// Radiance, W m⁻² sr⁻¹ per channel, toward `edge_u × edge_v`.
        radiance: Rgb,
        /// The primitive that is this light's surface.
        prim: usize,
    },
}

/// A light sample for next-event estimation at a shading point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light.
    pub wi: Vec3,
    /// Distance to the light (infinite for the environment).
    pub distance: f64,
    /// The incident radiance (point lights: `I / r²`, the irradiance a delta contributes).
    pub radiance: Rgb,
    /// The density per unit solid angle of the draw; 1 for a point light (a delta).
    pub pdf: f64,
    /// Whether the light is a delta (no MIS: BSDF sampling cannot find it).
    pub delta: bool,
}

impl Light {
    /// Draws a point on the light as seen from `p`.
    pub fn sample(&self, p: Vec3, u1: f64, u2: f64) -> Option<LightSample> {
        match self {
            Light::Point {
                position,
                intensity,
            } => {
                let d = *position - p;
                let r2 = d.dot(d);
                if r2 <= 0.0 {
                    return None;
                }
                let r = r2.sqrt();
                Some(LightSample {
                    wi: d * (1.0 / r),
                    distance: r,
                    radiance: *intensity * (1.0 / r2),
                    pdf: 1.0,
                    delta: true,
                })
            }
            Light::Environment(env) => {
                let (wi, pdf) = env.sample(u1, u2)?;
                Some(LightSample {
                    wi,
                    distance: f64::INFINITY,
                    radiance: env.radiance(wi),
                    pdf,
                    delta: false,
                })
            }
            Light::Rectangle {
                corner,
                edge_u,
                edge_v,
                radiance,
                ..
            } => {
                let q = *corner + *edge_u * u1 + *edge_v * u2;
                let n = edge_u.cross(*edge_v);
                let area = n.length();
                let n = n * (1.0 / area);
                let d = q - p;
                let r2 = d.dot(d);
                let r = r2.sqrt();
                let wi = d * (1.0 / r);
                let cos_l = -wi.dot(n);
                // The emitting side only; at grazing angles the density diverges.
                if cos_l <= 1e-12 || r <= 0.0 {
                    return None;
                }
                Some(LightSample {
                    wi,
                    distance: r,
                    radiance: *radiance,
                    pdf: r2 / (cos_l * area),
                    delta: false,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distribution_samples_in_proportion() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]);
        assert_eq!(d.sample(0.1).0, 0);
        assert_eq!(d.sample(0.3).0, 2);
        assert!((d.probability(2) - 0.75).abs() < 1e-15);
        let (i, t) = d.sample(0.625);
        assert_eq!(i, 2);
        assert!((t - 0.5).abs() < 1e-12);
    }

    /// The map's density integrates to 1 over the sphere and matches its draws' bins.
    #[test]
    fn environment_map_density_is_normalized() {
        let (w, h) = (16, 8);
        let pixels: Vec<Rgb> = (0..w * h)
            .map(|i| Rgb::grey(1.0 + (i % 7) as f64 + if i == 20 { 50.0 } else { 0.0 }))
            .collect();
        let env = Environment::map(w, h, pixels, 1.0);
        // Midpoint quadrature in (θ, φ).
        let n = 400;
        let mut integral = 0.0;
        for i in 0..n {
            let theta = (i as f64 + 0.5) * PI / n as f64;
            for j in 0..2 * n {
                let phi = (j as f64 + 0.5) * PI / n as f64;
                integral += env.pdf(Vec3::from_spherical(theta, phi))
                    * theta.sin()
                    * (PI / n as f64).powi(2);
            }
        }
        assert!((integral - 1.0).abs() < 2e-3, "∫ pdf = {integral}");
        let (d, pdf) = env.sample(0.3, 0.8).unwrap();
        assert!((env.pdf(d) - pdf).abs() < 1e-9 * pdf);
    }
}
