//! Surface materials: what a renderer asks of a BRDF at a shading point.
//!
//! Directions are unit vectors in the local shading frame ([`Frame`](crate::geometry::Frame)):
//! `z` the shading normal, `x` along `∂p/∂u` (the weft), `y` along `∂p/∂v` (the warp), both
//! pointing away from the surface. `wi` points toward the light (the paper's `s`), `wo` toward
//! the viewer (`v`). [`SurfaceMaterial::eval`] is the BRDF `f(wi, wo)` per channel in sr⁻¹,
//! *without* the cosine. Camera paths know `wo` and draw `wi`, so [`SurfaceMaterial::sample`]
//! draws `wi` for a given `wo`, and [`SurfaceMaterial::pdf`] is the density of that draw.
//!
//! A path tracer asks a material at each vertex through a [`MaterialAt`]: the material's BSDF
//! at the point ([`SurfaceMaterial::point_bsdf`]) is built there once, in place, and answers the
//! vertex's eval, sample and pdf.

use crate::color::Rgb;
use std::f64::consts::FRAC_1_PI;
use woven::bsdf::{Bsdf, BsdfSample, LobeFlags, Transport};
use woven::math::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use woven::surface::PointBsdf;
use woven::Vec3;

/// What a material may read at a shading point besides the directions: its uv and the pixel's
/// footprint there (the library's [`SurfacePoint`](woven::surface::SurfacePoint), which woven
/// surfaces read).
pub use woven::surface::SurfacePoint as ShadingPoint;

/// A direction drawn by [`SurfaceMaterial::sample`] (the library's sample type, per channel):
/// `wi` drawn for the given `wo`, `f(wi, wo)` and the density `wi` was drawn with (> 0).
pub type MaterialSample = BsdfSample<Rgb>;

/// A reflecting surface as the path tracer uses it. Implementations are `Send + Sync` and
/// allocate nothing per call.
pub trait SurfaceMaterial: Send + Sync {
    /// The BRDF `f(wi, wo)`, sr⁻¹ per channel, without the cosine; 0 when either direction is
    /// below the surface.
    fn eval(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> Rgb;

    /// Draws `wi` for the viewer direction `wo` (a camera path:
    /// [`Transport::Radiance`]): `uc` in `[0, 1)` picks a lobe,
    /// `u` in `[0, 1)²` draws within it. `None` when no direction results (`wo` below the
    /// surface, or a rejected draw).
    fn sample(&self, wo: Vec3, at: &ShadingPoint, uc: f64, u: [f64; 2]) -> Option<MaterialSample>;

    /// The density per unit solid angle with which [`sample`](Self::sample) draws `wi` for `wo`.
    fn pdf(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> f64;

    /// Whether the material reads [`ShadingPoint::uv`] (one that does not is handed `[0, 0]`,
    /// and a sphere's uv, two inverse trigonometric functions, is not worked out).
    fn uses_uv(&self) -> bool {
        true
    }

    /// Whether the material reads [`ShadingPoint::footprint`] (a scene whose materials do not
    /// skips computing it).
    fn uses_footprint(&self) -> bool {
        false
    }

    /// The warp's share of the BRDF at `at`, in `[0, 1]`; 0 for a material without yarns. It
    /// tells a weave's yarn families apart without noise (the denoiser's guide).
    fn warp_share(&self, _at: &ShadingPoint) -> f64 {
        0.0
    }

    /// The material's BSDF at `at`, where building it costs more than a call: a woven
    /// surface's lobes at the point (and on a relief, the yarn the viewer's ray meets), built
    /// into `slot` (over what a previous vertex left there: a path keeps one slot). A
    /// [`MaterialAt`] builds it once per path vertex and asks it what it would ask
    /// [`eval`](Self::eval), [`sample`](Self::sample) and [`pdf`](Self::pdf), which must answer
    /// as it does ([`Transport::Radiance`]). Returns whether it built one; `false` (the
    /// default): the vertex asks those.
    fn point_bsdf<'a>(&'a self, _at: &ShadingPoint, _slot: &mut Option<PointBsdf<'a>>) -> bool {
        false
    }
}

/// A material at one path vertex: what a path tracer asks there. The material's BSDF at the
/// point ([`SurfaceMaterial::point_bsdf`]) is built with it and answers every question, as the
/// material's own methods would, bit for bit.
///
/// It is built eagerly, into a slot the path keeps (`'s`): a vertex that reaches its material
/// always asks it something, and building a point's BSDF (over a kilobyte of lobes) anew and
/// moving it into place was a tenth of a plane's render time.
pub struct MaterialAt<'a, 's> {
    material: &'a dyn SurfaceMaterial,
    at: ShadingPoint,
    bsdf: Option<&'s PointBsdf<'a>>,
}

impl<'a, 's> MaterialAt<'a, 's> {
    /// `material` at `at`, its BSDF there built into `slot` (one per path; whatever an earlier
    /// vertex left there is overwritten).
    #[inline]
    pub fn new(
        material: &'a dyn SurfaceMaterial,
        at: ShadingPoint,
        slot: &'s mut Option<PointBsdf<'a>>,
    ) -> MaterialAt<'a, 's> {
        let built = material.point_bsdf(&at, slot);
        let slot: &'s Option<PointBsdf<'a>> = slot;
        MaterialAt {
            material,
            at,
            bsdf: if built { slot.as_ref() } else { None },
        }
    }

    /// The material's BSDF here; `None` for a material without one.
    #[inline]
    fn bsdf(&self) -> Option<&'s PointBsdf<'a>> {
        self.bsdf
    }

    /// [`SurfaceMaterial::eval`] here.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        match self.bsdf() {
            Some(b) => b.eval(wi, wo),
            None => self.material.eval(wi, wo, &self.at),
        }
    }

    /// [`SurfaceMaterial::sample`] here.
    #[inline]
    pub fn sample(&self, wo: Vec3, uc: f64, u: [f64; 2]) -> Option<MaterialSample> {
        match self.bsdf() {
            Some(b) => b.sample(wo, uc, u, Transport::Radiance),
            None => self.material.sample(wo, &self.at, uc, u),
        }
    }

    /// [`SurfaceMaterial::pdf`] here.
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f64 {
        match self.bsdf() {
            Some(b) => b.pdf(wi, wo, Transport::Radiance),
            None => self.material.pdf(wi, wo, &self.at),
        }
    }

    /// [`SurfaceMaterial::warp_share`] here.
    pub fn warp_share(&self) -> f64 {
        self.material.warp_share(&self.at)
    }
}

/// A Lambertian reflector: `f = ρ/π`.
#[derive(Clone, Copy, Debug)]
pub struct Diffuse {
    /// The reflectance `ρ` per channel, each in `[0, 1]`.
    pub reflectance: Rgb,
}

impl SurfaceMaterial for Diffuse {
    fn eval(&self, wi: Vec3, wo: Vec3, _: &ShadingPoint) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            Rgb::BLACK
        } else {
            self.reflectance * FRAC_1_PI
        }
    }

    fn sample(&self, wo: Vec3, _: &ShadingPoint, _uc: f64, u: [f64; 2]) -> Option<MaterialSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = cosine_hemisphere(u[0], u[1]);
        let pdf = cosine_hemisphere_pdf(wi.z);
        // A draw on the horizon has density 0: reject it rather than divide by it.
        (pdf > 0.0).then_some(MaterialSample {
            wi,
            wo,
            f: self.reflectance * FRAC_1_PI,
            pdf,
            lobe: LobeFlags::REFLECTION | LobeFlags::DIFFUSE,
        })
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, _: &ShadingPoint) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            0.0
        } else {
            wi.z * FRAC_1_PI
        }
    }

    fn uses_uv(&self) -> bool {
        false
    }
}

/// Any of the library's colour BSDFs that is the same at every point (a microcylinder fabric, a
/// rough plastic, a sheen), as the path tracer uses it: a camera path draws `wi` for `wo`
/// ([`Transport::Radiance`]).
pub struct Uniform<B>(pub B);

impl<B: Bsdf<Value = Rgb>> SurfaceMaterial for Uniform<B> {
    fn eval(&self, wi: Vec3, wo: Vec3, _: &ShadingPoint) -> Rgb {
        self.0.eval(wi, wo)
    }

    fn sample(&self, wo: Vec3, _: &ShadingPoint, uc: f64, u: [f64; 2]) -> Option<MaterialSample> {
        self.0
            .sample(wo, uc, u, Transport::Radiance)
            .filter(|s| s.pdf > 0.0)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, _: &ShadingPoint) -> f64 {
        self.0.pdf(wi, wo, Transport::Radiance)
    }
}
