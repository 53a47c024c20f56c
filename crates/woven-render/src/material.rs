//! Surface materials: what a renderer asks of a BRDF at a shading point.
//!
//! Directions are unit vectors in the local shading frame ([`Frame`](crate::geometry::Frame)):
//! `z` the shading normal, `x` along `∂p/∂u` (the weft), `y` along `∂p/∂v` (the warp), both
//! pointing away from the surface. `wi` points toward the light (the paper's `s`), `wo` toward
//! the viewer (`v`). A BSDF's `eval` is `f(wi, wo)` per channel in sr⁻¹, *without* the cosine.
//! Camera paths know `wo` and draw `wi` ([`Transport::Radiance`]).
//!
//! A material has one door, [`SurfaceMaterial::bsdf`]: its BSDF at a point, built once per path
//! vertex (into a [`BsdfScratch`] the path keeps, where building it costs more than a call) and
//! asked there for eval, sample, pdf and the warp's share, as pbrt's materials answer
//! `GetBSDF`.

use crate::color::Rgb;
use std::f64::consts::FRAC_1_PI;
use woven::bsdf::{known_and_drawn, pair_of, Bsdf, BsdfSample, LobeFlags, Transport};
use woven::math::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use woven::surface::{PointBsdf, WovenSurface};
use woven::Vec3;

/// What a material may read at a shading point besides the directions: its uv and the pixel's
/// footprint there (the library's [`SurfacePoint`](woven::surface::SurfacePoint), which woven
/// surfaces read).
pub use woven::surface::SurfacePoint as ShadingPoint;

/// A direction drawn by a material's BSDF: `wi` drawn for the given `wo`, `f(wi, wo)` and the
/// density `wi` was drawn with.
pub type MaterialSample = BsdfSample<Rgb>;

/// A material's BSDF at a point, as the path tracer asks it (per channel).
pub type MaterialBsdf<'a> = dyn Bsdf<Value = Rgb> + 'a;

/// Where materials build their BSDF at a point when it depends on the point (a woven surface's
/// lobes there: over a kilobyte, built in place, since building it anew and moving it was a
/// tenth of a plane's render time). A path keeps one and its vertices build over it; `'a` is
/// the materials' lifetime.
#[derive(Default)]
pub struct BsdfScratch<'a> {
    woven: Option<PointBsdf<'a>>,
}

impl<'a> BsdfScratch<'a> {
    /// `surface`'s BSDF at `at`, built over what an earlier vertex left here.
    #[inline]
    pub fn woven(&mut self, surface: &'a WovenSurface, at: &ShadingPoint) -> &PointBsdf<'a> {
        surface.at_into(at, &mut self.woven);
        self.woven
            .as_ref()
            .expect("WovenSurface::at_into fills the slot")
    }
}

/// A reflecting surface as the path tracer uses it. Implementations are `Send + Sync` and
/// allocate nothing per call.
pub trait SurfaceMaterial: Send + Sync {
    /// The material's BSDF at `at`: the one door a renderer asks a material through, once per
    /// path vertex. A material the same everywhere is its own BSDF; one that varies builds it
    /// into `scratch`.
    fn bsdf<'a, 's>(
        &'a self,
        at: &ShadingPoint,
        scratch: &'s mut BsdfScratch<'a>,
    ) -> &'s MaterialBsdf<'a>;

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

    /// Whether light may pass straight through the material ([`pass_through`](Self::pass_through)
    /// is not always 0). Such a surface is two-sided: met from behind, it is shaded turned over.
    fn transmits(&self) -> bool {
        false
    }

    /// The material met from behind, where it [`transmits`](Self::transmits) (shaded turned
    /// over): its back, where that differs from its front (a woven cloth's is its pattern's
    /// complement: a satin's back is its sateen). `None`: the same material.
    fn back(&self) -> Option<&dyn SurfaceMaterial> {
        None
    }

    /// The share of the light along `d` (the local frame, either side) that passes straight
    /// through at `at`, in `[0, 1]`: a delta lobe, which shadow rays carry (a path asks the
    /// BSDF it built at its vertex, [`Bsdf::pass_through`]).
    fn pass_through(&self, _at: &ShadingPoint, _d: Vec3) -> f64 {
        0.0
    }

    /// `f(wi, wo)` at `at`: [`bsdf`](Self::bsdf)'s, built for this one question (for tests and
    /// tools; a renderer asks the BSDF it built once per vertex).
    fn eval(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> Rgb {
        self.bsdf(at, &mut BsdfScratch::default()).eval(wi, wo)
    }

    /// A draw of `wi` for `wo` at `at` ([`Transport::Radiance`]): [`bsdf`](Self::bsdf)'s, for
    /// this one question.
    fn sample(&self, wo: Vec3, at: &ShadingPoint, uc: f64, u: [f64; 2]) -> Option<MaterialSample> {
        self.bsdf(at, &mut BsdfScratch::default())
            .sample(wo, uc, u, Transport::Radiance)
    }

    /// The density of [`sample`](Self::sample)'s draw: [`bsdf`](Self::bsdf)'s, for this one
    /// question.
    fn pdf(&self, wi: Vec3, wo: Vec3, at: &ShadingPoint) -> f64 {
        self.bsdf(at, &mut BsdfScratch::default())
            .pdf(wi, wo, Transport::Radiance)
    }
}

/// A Lambertian reflector: `f = ρ/π`.
#[derive(Clone, Copy, Debug)]
pub struct Diffuse {
    /// The reflectance `ρ` per channel, each in `[0, 1]`.
    pub reflectance: Rgb,
}

impl Bsdf for Diffuse {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::DIFFUSE
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            Rgb::BLACK
        } else {
            self.reflectance * FRAC_1_PI
        }
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        let (_, drawn) = known_and_drawn(wi, wo, mode);
        if wi.z <= 0.0 || wo.z <= 0.0 {
            0.0
        } else {
            drawn.z * FRAC_1_PI
        }
    }

    fn sample(
        &self,
        known: Vec3,
        _uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<MaterialSample> {
        if known.z <= 0.0 {
            return None;
        }
        let drawn = cosine_hemisphere(u[0], u[1]);
        let pdf = cosine_hemisphere_pdf(drawn.z);
        let (wi, wo) = pair_of(known, drawn, mode);
        // A draw on the horizon has density 0: reject it rather than divide by it.
        (pdf > 0.0).then_some(MaterialSample {
            wi,
            wo,
            f: self.reflectance * FRAC_1_PI,
            pdf,
            lobe: LobeFlags::REFLECTION | LobeFlags::DIFFUSE,
        })
    }
}

impl SurfaceMaterial for Diffuse {
    fn bsdf<'a, 's>(
        &'a self,
        _: &ShadingPoint,
        _: &'s mut BsdfScratch<'a>,
    ) -> &'s MaterialBsdf<'a> {
        self
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
    fn bsdf<'a, 's>(
        &'a self,
        _: &ShadingPoint,
        _: &'s mut BsdfScratch<'a>,
    ) -> &'s MaterialBsdf<'a> {
        &self.0
    }
}
