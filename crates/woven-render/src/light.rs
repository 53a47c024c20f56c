//! Light sources: point lights, environments (constant or an equirectangular map) and
//! rectangular area lights, each an [`Emitter`]: what the path tracer asks of a light (pbrt-v4's
//! `Light` interface, Mitsuba 3's `Emitter`) — a direction drawn toward it for next-event
//! estimation ([`Emitter::sample_li`]), the density of that draw for a direction a BSDF-sampled
//! ray found it in ([`Emitter::pdf_li`]), and the radiance such a ray receives ([`Emitter::le`]).
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
use woven::math::sampling::{uniform_sphere, Distribution2D, UNIFORM_SPHERE_PDF};
use woven::Vec3;

/// The largest environment map file [`Environment::from_exr`] reads, in bytes (4 GiB): room for
/// an uncompressed 16384 × 8192 RGBA map in 32-bit floats (2 GiB) and more.
pub const MAX_EXR_BYTES: u64 = 4 << 30;

/// The most pixels a layer of an environment map may hold: 16384 × 8192, the largest maps
/// published. A map takes about 32 bytes a pixel once read (its radiance in `f64` and its
/// sampling CDF), 4 GiB at the limit; the limit is checked from the header, so a small file
/// that declares a huge image allocates nothing.
pub const MAX_ENVIRONMENT_PIXELS: usize = 16384 * 8192;

/// The most an EXR file's pixels can be compressed, as a ratio of their raw bytes to the
/// file's: 2048, above what any of the codecs the reader knows reaches on a constant image
/// (deflate, in ZIP, ZIPS and PXR24, tops out near 1032:1; RLE at 64:1; PIZ's Huffman runs
/// near 400:1; B44 at 32:3). A file smaller than its header's pixels, so compressed, cannot
/// hold them: it is refused before they are allocated.
pub const MAX_EXR_COMPRESSION: u64 = 2048;

/// What the path tracer asks of a light source.
pub trait Emitter {
    /// Draws a direction from the shading point `p` toward the light from two uniforms in
    /// `[0, 1)`; `None` when the draw gives nothing (a point on the light's back, or at `p`).
    fn sample_li(&self, p: Vec3, u: [f64; 2]) -> Option<LightSample>;

    /// The density per unit solid angle with which [`sample_li`](Self::sample_li), called at
    /// the ray's origin, draws the direction along which the ray `at` met the light; 0 for a
    /// delta light (never met).
    fn pdf_li(&self, at: &EmitterHit) -> f64;

    /// The radiance the ray `at` receives from the light, W m⁻² sr⁻¹ per channel.
    fn le(&self, at: &EmitterHit) -> Rgb;

    /// Whether the light is a delta in position or direction: no ray can meet it, and light
    /// samples of it take no MIS weight.
    fn is_delta(&self) -> bool;
}

/// Where a ray met an emitter: on an area light's surface, or escaping to the environment.
#[derive(Clone, Copy, Debug)]
pub struct EmitterHit {
    /// The ray's direction, unit, from its origin toward the light.
    pub d: Vec3,
    /// The distance from the ray's origin to the point met (infinite for the environment).
    pub distance: f64,
    /// The cosine between `-d` and the emitting surface's normal, > 0 on its emitting side
    /// (1 for the environment, which has no surface).
    pub cos_light: f64,
}

impl EmitterHit {
    /// A ray in direction `d` that met nothing and so receives the environment's light.
    pub fn escaped(d: Vec3) -> EmitterHit {
        EmitterHit {
            d,
            distance: f64::INFINITY,
            cos_light: 1.0,
        }
    }
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

/// A point light, radiating `intensity` equally in all directions.
#[derive(Clone, Copy, Debug)]
pub struct PointLight {
    /// Position.
    pub position: Vec3,
    /// Intensity, W sr⁻¹ per channel.
    pub intensity: Rgb,
}

impl Emitter for PointLight {
    fn sample_li(&self, p: Vec3, _: [f64; 2]) -> Option<LightSample> {
        let d = self.position - p;
        let r2 = d.dot(d);
        if r2 <= 0.0 {
            return None;
        }
        let r = r2.sqrt();
        Some(LightSample {
            wi: d * (1.0 / r),
            distance: r,
            radiance: self.intensity * (1.0 / r2),
            pdf: 1.0,
            delta: true,
        })
    }

    fn pdf_li(&self, _: &EmitterHit) -> f64 {
        0.0
    }

    fn le(&self, _: &EmitterHit) -> Rgb {
        Rgb::BLACK
    }

    fn is_delta(&self) -> bool {
        true
    }
}

/// A one-sided parallelogram emitter, uniform radiance toward `edge_u × edge_v`; also geometry
/// (primitive `prim`, which reflects nothing).
#[derive(Clone, Copy, Debug)]
pub struct RectangleLight {
    /// A corner.
    pub corner: Vec3,
    /// First edge.
    pub edge_u: Vec3,
    /// Second edge.
    pub edge_v: Vec3,
    /// Radiance, W m⁻² sr⁻¹ per channel, toward `edge_u × edge_v`.
    pub radiance: Rgb,
    /// The primitive that is this light's surface.
    pub prim: usize,
    /// The unit normal of the emitting side, `edge_u × edge_v` normalized.
    normal: Vec3,
    /// The area, m².
    area: f64,
}

impl RectangleLight {
    /// The parallelogram at `corner` spanned by `edge_u` and `edge_v` (not parallel), emitting
    /// `radiance` toward `edge_u × edge_v`; its surface is primitive `prim`.
    pub fn new(corner: Vec3, edge_u: Vec3, edge_v: Vec3, radiance: Rgb, prim: usize) -> Self {
        let n = edge_u.cross(edge_v);
        let area = n.length();
        RectangleLight {
            corner,
            edge_u,
            edge_v,
            radiance,
            prim,
            normal: n * (1.0 / area),
            area,
        }
    }

    /// The area, m².
    pub fn area(&self) -> f64 {
        self.area
    }
}

impl Emitter for RectangleLight {
    /// A point drawn uniformly on the surface: density `r² / (cos θ_light · area)` per unit solid
    /// angle.
    fn sample_li(&self, p: Vec3, u: [f64; 2]) -> Option<LightSample> {
        let q = self.corner + self.edge_u * u[0] + self.edge_v * u[1];
        let d = q - p;
        let r2 = d.dot(d);
        let r = r2.sqrt();
        let wi = d * (1.0 / r);
        let cos_l = -wi.dot(self.normal);
        // The emitting side only; at grazing angles the density diverges.
        if cos_l <= 1e-12 || r <= 0.0 {
            return None;
        }
        Some(LightSample {
            wi,
            distance: r,
            radiance: self.radiance,
            pdf: r2 / (cos_l * self.area),
            delta: false,
        })
    }

    fn pdf_li(&self, at: &EmitterHit) -> f64 {
        at.distance * at.distance / (at.cos_light * self.area)
    }

    fn le(&self, at: &EmitterHit) -> Rgb {
        if at.cos_light > 0.0 {
            self.radiance
        } else {
            Rgb::BLACK
        }
    }

    fn is_delta(&self) -> bool {
        false
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
        /// Over the pixels, in proportion to luminance × sin θ.
        distribution: Distribution2D,
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
        let weights: Vec<f64> = pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let theta = ((i / width) as f64 + 0.5) * PI / height as f64;
                p.luminance().max(0.0) * theta.sin()
            })
            .collect();
        Environment {
            kind: EnvKind::Map {
                width,
                height,
                distribution: Distribution2D::new(&weights, width, height),
                pixels,
            },
            scale,
        }
    }

    /// Reads an equirectangular OpenEXR map (`+z` up): a regular file of at most
    /// [`MAX_EXR_BYTES`] (checked before it is read) whose layers hold at most
    /// [`MAX_ENVIRONMENT_PIXELS`] each (checked from its header, before pixels are allocated).
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be opened; [`Error::Image`] when it is not a regular file, is
    /// too large, cannot be read as an RGB(A) EXR or holds a negative, infinite or NaN pixel.
    pub fn from_exr(path: &Path, scale: f64) -> Result<Environment> {
        let (file, _) = woven::fsutil::open_regular(path, MAX_EXR_BYTES, "an environment map")
            .map_err(|e| {
                Error::from_file(e, |message| Error::Image {
                    path: path.to_path_buf(),
                    message,
                })
            })?;
        Self::read_exr(std::io::BufReader::new(file), path, scale)
    }

    /// [`from_exr`](Self::from_exr) from a reader (`path` names it in messages).
    ///
    /// # Errors
    /// [`Error::Image`] when it cannot be read as an RGB(A) EXR, a layer holds more than
    /// [`MAX_ENVIRONMENT_PIXELS`], the file is too short to hold the pixels its header
    /// declares (their offset tables, and their bytes compressed [`MAX_EXR_COMPRESSION`]:1),
    /// or a pixel is negative, infinite or NaN.
    pub fn read_exr(
        mut reader: impl std::io::Read + std::io::Seek,
        path: &Path,
        scale: f64,
    ) -> Result<Environment> {
        use exr::prelude::{read, ReadChannels, ReadLayers};
        let image_error = |message: String| Error::Image {
            path: path.to_path_buf(),
            message,
        };
        // The header first: a few bytes may declare a layer of billions of pixels.
        let meta = exr::meta::MetaData::read_from_buffered(&mut reader, false)
            .map_err(|e| image_error(format!("cannot read the environment map: {e}")))?;
        for h in &meta.headers {
            let (w, ht) = (h.layer_size.0, h.layer_size.1);
            if w.checked_mul(ht).is_none_or(|n| n > MAX_ENVIRONMENT_PIXELS) {
                return Err(image_error(format!(
                    "a layer of {w} × {ht} pixels, more than the {MAX_ENVIRONMENT_PIXELS} \
                     (16384 × 8192) an environment map may hold"
                )));
            }
        }
        check_declared_size(&meta.headers, &mut reader).map_err(image_error)?;
        reader
            .seek(std::io::SeekFrom::Start(0))
            .map_err(|e| image_error(format!("cannot read the environment map: {e}")))?;
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .rgba_channels(
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
            .first_valid_layer()
            .all_attributes()
            .from_buffered(reader)
            .map_err(|e| image_error(format!("cannot read the environment map: {e}")))?;
        let size = image.layer_data.size;
        let (_, pixels) = image.layer_data.channel_data.pixels;
        if let Some(i) = pixels.iter().position(|p| !p.is_valid()) {
            return Err(image_error(format!(
                "pixel ({}, {}) is {:?}: an environment's radiance must be finite and >= 0",
                i % size.width(),
                i / size.width(),
                pixels[i].0
            )));
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

    /// Draws a direction toward the environment from two uniforms in `[0, 1)`: `(d, density
    /// per unit solid angle)`.
    pub fn sample(&self, u: [f64; 2]) -> Option<(Vec3, f64)> {
        match &self.kind {
            EnvKind::Constant(_) => Some((uniform_sphere(u[0], u[1]), UNIFORM_SPHERE_PDF)),
            EnvKind::Map { distribution, .. } => {
                // u[0] picks the row (θ), u[1] the pixel in it (φ).
                let s = distribution.sample([u[1], u[0]]);
                let d = Vec3::from_spherical(s.point[1] * PI, s.point[0] * 2.0 * PI);
                // The density of the pixel `d` falls in, as `pdf` reports it (rounding may carry
                // a point on a pixel's edge into its neighbour).
                let pdf = self.pdf(d);
                (pdf > 0.0).then_some((d, pdf))
            }
        }
    }

    /// The density [`sample`](Self::sample) draws `d` with, per unit solid angle.
    pub fn pdf(&self, d: Vec3) -> f64 {
        match &self.kind {
            EnvKind::Constant(_) => UNIFORM_SPHERE_PDF,
            EnvKind::Map {
                width,
                height,
                distribution,
                ..
            } => {
                let (x, y) = pixel_of(d, *width, *height);
                let sin = (1.0 - d.z * d.z).max(0.0).sqrt();
                if sin <= 0.0 {
                    return 0.0;
                }
                let p = distribution.probability(x, y);
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

/// Refuses an EXR whose `headers` declare more than the rest of the file can hold: each chunk
/// takes 8 bytes of the offset table, and the pixels (and any one tile) at least their raw
/// bytes over [`MAX_EXR_COMPRESSION`]. Deep layers, which the reader does not take, are refused here.
fn check_declared_size(
    headers: &[exr::meta::header::Header],
    reader: &mut impl std::io::Seek,
) -> std::result::Result<(), String> {
    let length = reader
        .seek(std::io::SeekFrom::End(0))
        .map_err(|e| format!("cannot read the environment map: {e}"))?;
    let mut need = 0u64;
    for h in headers {
        if h.deep {
            return Err("a deep-data layer: an environment map must be a flat image".into());
        }
        // The full-resolution level's samples (channels may be subsampled; a sampling of 0,
        // which the reader refuses later, counts as 1 here).
        let (w, ht) = (h.layer_size.0 as u64, h.layer_size.1 as u64);
        let raw: u64 = h
            .channels
            .list
            .iter()
            .map(|c| {
                let (sx, sy) = (c.sampling.0.max(1) as u64, c.sampling.1.max(1) as u64);
                (w / sx) * (ht / sy) * c.sample_type.bytes_per_sample() as u64
            })
            .fold(0u64, u64::saturating_add);
        need = need
            .saturating_add((h.chunk_count as u64).saturating_mul(8))
            .saturating_add(raw / MAX_EXR_COMPRESSION);
        // A tile is decoded whole, however little of it the image covers: it too must fit
        // in what the file could hold.
        if let exr::meta::BlockDescription::Tiles(t) = h.blocks {
            let tile = (t.tile_size.0 as u64)
                .saturating_mul(t.tile_size.1 as u64)
                .saturating_mul(h.channels.bytes_per_pixel as u64);
            if tile / MAX_EXR_COMPRESSION > length {
                return Err(format!(
                    "tiles of {} × {} pixels, which take at least {} bytes even compressed \
                     {MAX_EXR_COMPRESSION}:1, but the file has {length}",
                    t.tile_size.0,
                    t.tile_size.1,
                    tile / MAX_EXR_COMPRESSION
                ));
            }
        }
    }
    if length < need {
        let (w, ht) = (headers[0].layer_size.0, headers[0].layer_size.1);
        return Err(format!(
            "the header declares {w} × {ht} pixels, which take at least {need} bytes even \
             compressed {MAX_EXR_COMPRESSION}:1, but the file has {length}: it is truncated or \
             not what it claims"
        ));
    }
    Ok(())
}

impl Emitter for Environment {
    fn sample_li(&self, _: Vec3, u: [f64; 2]) -> Option<LightSample> {
        let (wi, pdf) = self.sample(u)?;
        Some(LightSample {
            wi,
            distance: f64::INFINITY,
            radiance: self.radiance(wi),
            pdf,
            delta: false,
        })
    }

    fn pdf_li(&self, at: &EmitterHit) -> f64 {
        self.pdf(at.d)
    }

    fn le(&self, at: &EmitterHit) -> Rgb {
        self.radiance(at.d)
    }

    fn is_delta(&self) -> bool {
        false
    }
}

/// A light source of a scene: one of the kinds above, each an [`Emitter`] (the enum dispatches
/// without a virtual call).
#[derive(Clone, Debug)]
pub enum Light {
    /// A point light; never seen by camera rays, never hit by BSDF-sampled rays.
    Point(PointLight),
    /// Light from infinitely far away.
    Environment(Environment),
    /// A one-sided parallelogram emitter.
    Rectangle(RectangleLight),
}

impl Emitter for Light {
    #[inline]
    fn sample_li(&self, p: Vec3, u: [f64; 2]) -> Option<LightSample> {
        match self {
            Light::Point(l) => l.sample_li(p, u),
            Light::Environment(l) => l.sample_li(p, u),
            Light::Rectangle(l) => l.sample_li(p, u),
        }
    }

    #[inline]
    fn pdf_li(&self, at: &EmitterHit) -> f64 {
        match self {
            Light::Point(l) => l.pdf_li(at),
            Light::Environment(l) => l.pdf_li(at),
            Light::Rectangle(l) => l.pdf_li(at),
        }
    }

    #[inline]
    fn le(&self, at: &EmitterHit) -> Rgb {
        match self {
            Light::Point(l) => l.le(at),
            Light::Environment(l) => l.le(at),
            Light::Rectangle(l) => l.le(at),
        }
    }

    fn is_delta(&self) -> bool {
        match self {
            Light::Point(l) => l.is_delta(),
            Light::Environment(l) => l.is_delta(),
            Light::Rectangle(l) => l.is_delta(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let (d, pdf) = env.sample([0.3, 0.8]).unwrap();
        assert!((env.pdf(d) - pdf).abs() < 1e-9 * pdf);
    }

    /// A ray that meets the rectangle where `sample_li` put its point is given the density and
    /// radiance of that sample; the back side receives nothing.
    #[test]
    fn rectangle_pdf_li_and_le_match_its_samples() {
        // edge_u × edge_v = −z: the light faces down, toward p.
        let light = RectangleLight::new(
            Vec3::new(-0.5, -0.25, 2.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Rgb::grey(3.0),
            0,
        );
        assert!((light.area() - 0.5).abs() < 1e-15);
        let p = Vec3::new(0.1, 0.2, 0.0);
        for u in [[0.1, 0.9], [0.5, 0.5], [0.97, 0.02]] {
            let s = light.sample_li(p, u).unwrap();
            let at = EmitterHit {
                d: s.wi,
                distance: s.distance,
                cos_light: s.wi.z,
            };
            assert!((light.pdf_li(&at) - s.pdf).abs() < 1e-12 * s.pdf);
            assert_eq!(light.le(&at), s.radiance);
            assert!(!s.delta && !light.is_delta());
            let back = EmitterHit {
                cos_light: -at.cos_light,
                ..at
            };
            assert!(light.le(&back).is_black());
        }
        // Seen from above, the light shows its back: no sample.
        assert!(light
            .sample_li(Vec3::new(0.0, 0.0, 3.0), [0.5, 0.5])
            .is_none());
    }

    /// Point lights are deltas: sampled with "density" 1 and the inverse-square falloff, never
    /// met by a ray.
    #[test]
    fn point_lights_are_deltas() {
        let light = Light::Point(PointLight {
            position: Vec3::new(0.0, 0.0, 2.0),
            intensity: Rgb::grey(8.0),
        });
        let s = light
            .sample_li(Vec3::new(0.0, 0.0, 0.0), [0.3, 0.6])
            .unwrap();
        assert!(s.delta && light.is_delta());
        assert_eq!((s.distance, s.pdf, s.radiance), (2.0, 1.0, Rgb::grey(2.0)));
        let at = EmitterHit::escaped(s.wi);
        assert_eq!((light.pdf_li(&at), light.le(&at)), (0.0, Rgb::BLACK));
    }

    /// The environment's `pdf_li` and `le` for an escaped ray are its map's density and
    /// radiance, and agree with its samples.
    #[test]
    fn environment_samples_agree_with_pdf_li() {
        let pixels: Vec<Rgb> = (0..8 * 4).map(|i| Rgb::grey(1.0 + i as f64)).collect();
        for env in [
            Environment::map(8, 4, pixels, 2.0),
            Environment::constant(Rgb::grey(0.5), 2.0),
        ] {
            let light = Light::Environment(env);
            for u in [[0.2, 0.7], [0.9, 0.1]] {
                let s = light.sample_li(Vec3::new(0.0, 0.0, 0.0), u).unwrap();
                let at = EmitterHit::escaped(s.wi);
                assert!((light.pdf_li(&at) - s.pdf).abs() < 1e-12 * s.pdf);
                assert_eq!(light.le(&at), s.radiance);
                assert!(s.distance.is_infinite() && !light.is_delta());
            }
        }
    }
}
