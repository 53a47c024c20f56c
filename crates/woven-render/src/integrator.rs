//! The path tracer: unidirectional, next-event estimation and BSDF sampling combined by
//! multiple importance sampling (power heuristic), Russian roulette — Mitsuba 3's `path`
//! integrator, transcribed to this renderer's types.
//!
//! **Depth** has Mitsuba's meaning: `max_depth = 1` shows emitters only, `2` direct lighting,
//! and so on; light sampling at a vertex happens only when a further vertex is allowed.
//! **Russian roulette** from depth `rr_depth` (5 by default) continues with probability
//! `min(max channel of the throughput, 0.95)`. **Emitters**: one light is chosen per light
//! sample, in proportion to the lights' `sampling_weight` (Mitsuba's; uniformly by default),
//! and asked only through [`Emitter`] (`sample_li`, `pdf_li`, `le`), whatever its kind;
//! point lights are deltas (no MIS, never hit); a rectangle light's surface reflects nothing;
//! surfaces are one-sided — a ray meeting a back face ends there, black.

use crate::camera::Camera;
use crate::color::Rgb;
use crate::geometry::{Frame, Hit, Ray};
use crate::light::{Emitter, EmitterHit};
use crate::material::{BsdfScratch, MaterialSample, ShadingPoint};
use crate::rng::Sampler;
use crate::scene::{Scene, Strategy};
use woven::bsdf::Transport;
use woven::math::sampling::power_heuristic as power;
use woven::Vec3;

/// The offset of a spawned ray's origin from its surface, relative to the point's magnitude
/// (with an absolute floor of the same value): enough to leave the surface after rounding.
const OFFSET: f64 = 1e-7;

/// A ray leaving `hit` in world direction `d`, its origin pushed off the surface to `d`'s side.
#[inline]
fn spawn(hit: &Hit, d: Vec3) -> Ray {
    let scale = OFFSET * (1.0 + hit.p.x.abs().max(hit.p.y.abs()).max(hit.p.z.abs()));
    let side = if d.dot(hit.ng) >= 0.0 { 1.0 } else { -1.0 };
    Ray {
        o: hit.p + hit.ng * (scale * side),
        d,
    }
}

/// The most surfaces a path or a shadow ray passes straight through before it is ended (a
/// bound on the work of a ray among many layers of sheer cloth).
const MAX_PASSES: u32 = 64;

/// The share of light that reaches `ray.o + t_max ray.d` from `ray.o`: 1 where nothing stands
/// between, 0 where an opaque surface does, and the product of what each surface met passes
/// straight through ([`SurfaceMaterial::pass_through`], at yarn level: no footprint) where the
/// scene has surfaces that let light through.
fn transmittance(scene: &Scene, mut ray: Ray, t_max: f64) -> f64 {
    if !scene.transmits {
        return if scene.accel.occluded(&ray, 0.0, t_max) {
            0.0
        } else {
            1.0
        };
    }
    let end = ray.o + ray.d * t_max;
    let mut passed = 1.0;
    for _ in 0..MAX_PASSES {
        let left = if t_max.is_finite() {
            (end - ray.o).dot(ray.d)
        } else {
            f64::INFINITY
        };
        let Some(hit) = scene.accel.intersect(&ray, 0.0, left) else {
            return passed;
        };
        let Some(material) = scene.prim_info[hit.prim]
            .material
            .map(|mi| &scene.materials[mi])
        else {
            return 0.0;
        };
        if !material.transmits() {
            return 0.0;
        }
        let at = ShadingPoint {
            uv: hit.uv(),
            footprint: [[0.0; 2]; 2],
        };
        passed *= material.pass_through(&at, Frame::from_hit(&hit).to_local(ray.d));
        if passed <= 0.0 {
            return 0.0;
        }
        ray = spawn(&hit, ray.d);
    }
    0.0
}

/// What a camera ray first meets, for the denoiser ([`crate::denoise`]): one sample's
/// features, averaged over a pixel's samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstHit {
    /// The shading normal (world), facing the camera; zero where the ray escapes.
    pub normal: Vec3,
    /// The distance along the ray; [`FirstHit::MISS_DISTANCE`] where it escapes.
    pub distance: f64,
    /// The first vertex's BSDF weight `f cos θ / pdf` (each channel at most 1): a one-sample
    /// estimate of its albedo, so a texture or a weave shows in it. White where no direction is
    /// drawn there (an emitter, or a path too short to reflect), black where the draw fails.
    pub albedo: Rgb,
    /// The warp's share of the BRDF there, seen along the camera ray
    /// ([`Bsdf::warp_share`](woven::bsdf::Bsdf::warp_share)): which yarn the ray met, without
    /// noise.
    pub warp_share: f64,
}

impl FirstHit {
    /// The distance given to rays that escape: far beyond any scene's extent, so escaped and
    /// surface pixels never mix.
    pub const MISS_DISTANCE: f64 = 1e30;

    /// An escaped ray.
    pub const MISS: FirstHit = FirstHit {
        normal: Vec3::new(0.0, 0.0, 0.0),
        distance: Self::MISS_DISTANCE,
        albedo: Rgb::BLACK,
        warp_share: 0.0,
    };
}

/// What a path tracer keeps from one path to the next so that no vertex allocates or moves
/// much: where its vertices build their material's BSDF ([`BsdfScratch`]). One per thread;
/// `'a` is the scene's lifetime.
#[derive(Default)]
pub struct Scratch<'a> {
    bsdf: BsdfScratch<'a>,
}

/// What is known of a camera ray before it is traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aim {
    /// It may meet the scene: trace it.
    Unknown,
    /// It meets nothing (its pixel passes by the scene's boxes, [`Camera::pixel_misses`]): it
    /// escapes at once, untraced.
    Clear,
}

/// The radiance arriving at `camera` (the scene's, or its inset's) along `ray`.
pub fn radiance<'a>(
    scene: &'a Scene,
    camera: &Camera,
    ray: Ray,
    aim: Aim,
    sampler: &mut Sampler,
    scratch: &mut Scratch<'a>,
) -> Rgb {
    trace(scene, camera, ray, aim, sampler, &mut None, scratch)
}

/// [`radiance`], and what the ray first meets.
pub fn radiance_and_first_hit<'a>(
    scene: &'a Scene,
    camera: &Camera,
    ray: Ray,
    aim: Aim,
    sampler: &mut Sampler,
    scratch: &mut Scratch<'a>,
) -> (Rgb, FirstHit) {
    let mut first = Some(FirstHit::MISS);
    let l = trace(scene, camera, ray, aim, sampler, &mut first, scratch);
    (l, first.unwrap_or(FirstHit::MISS))
}

/// The path tracer's loop; `first`, when `Some`, receives what the camera ray meets.
fn trace<'a>(
    scene: &'a Scene,
    camera: &Camera,
    mut ray: Ray,
    aim: Aim,
    sampler: &mut Sampler,
    first: &mut Option<FirstHit>,
    scratch: &mut Scratch<'a>,
) -> Rgb {
    let settings = &scene.integrator;
    let max_depth = settings.max_depth.unwrap_or(u32::MAX);
    let n_lights = scene.lights.len();
    // The probability that light sampling picks light `k` (in proportion to its weight).
    let pick = |k: usize| scene.light_choice.probability(k);
    let use_lights = settings.strategy != Strategy::Bsdf && n_lights > 0;

    let mut l = Rgb::BLACK;
    let mut beta = Rgb::WHITE;
    // The density of the BSDF draw that produced `ray` (∞ for the camera ray: its emitter hits
    // count in full).
    let mut prev_pdf = f64::INFINITY;
    let mut depth: u32 = 0;
    // The pixel's footprint at the camera vertex, for filtering fine weaves (None: the filter is
    // off, and past the first vertex).
    let mut footprint = settings.footprint_filter.then(|| camera.footprint());

    let mut clear = aim == Aim::Clear;
    // Surfaces passed straight through so far, and (while the camera ray goes on) the distance
    // it has gone: footprints are measured along the whole camera ray.
    let (mut passes, mut travelled, camera_ray) = (0u32, 0.0, ray);
    loop {
        let hit = if std::mem::take(&mut clear) {
            None
        } else {
            scene.accel.intersect(&ray, 0.0, f64::INFINITY)
        };
        // Emission found along the ray, weighted against light sampling.
        let emitted = |le: Rgb, light_pdf: f64| -> Rgb {
            if depth == 0 {
                // Hidden where the camera sees it directly, not through a surface it passed.
                if settings.hide_emitters && passes == 0 {
                    Rgb::BLACK
                } else {
                    le
                }
            } else {
                match settings.strategy {
                    Strategy::Bsdf => le,
                    Strategy::Light => Rgb::BLACK,
                    Strategy::Mis => le * power(prev_pdf, light_pdf),
                }
            }
        };
        let Some(hit) = hit else {
            if let Some(e) = scene.environment {
                let light = &scene.lights[e];
                let met = EmitterHit::escaped(ray.d);
                let le = light.le(&met);
                if !le.is_black() {
                    l += beta * emitted(le, pick(e) * light.pdf_li(&met));
                }
            }
            break;
        };
        let info = scene.prim_info[hit.prim];
        let mut material = info.material.map(|mi| scene.materials[mi].as_ref());
        let mut hit = hit;
        // One-sided surfaces: the back side is black and ends the path. A surface that lets
        // light through is two-sided: met from behind, it is shaded turned over, as its back.
        let two_sided = material.is_some_and(|m| m.transmits());
        let mut cos_front = -ray.d.dot(hit.ng);
        if cos_front < 0.0 && two_sided {
            (hit.ng, hit.ns, cos_front) = (-hit.ng, -hit.ns, -cos_front);
            material = material.map(|m| m.back().unwrap_or(m));
        }
        if cos_front <= 0.0 {
            break;
        }
        if depth == 0 && passes == 0 {
            if let Some(f) = first {
                *f = FirstHit {
                    normal: hit.ns,
                    distance: hit.t,
                    albedo: Rgb::WHITE,
                    warp_share: 0.0,
                };
            }
        }
        if let Some(li) = info.light {
            let light = &scene.lights[li];
            let met = EmitterHit {
                d: ray.d,
                distance: hit.t,
                cos_light: cos_front,
            };
            l += beta * emitted(light.le(&met), pick(li) * light.pdf_li(&met));
        }
        let Some(material) = material else {
            break;
        };
        let frame = Frame::from_hit(&hit);
        let wo = frame.to_local(-ray.d);
        if wo.z <= 0.0 {
            // Seen below the shading normal's horizon: nothing reflects toward the viewer.
            break;
        }
        let at = ShadingPoint {
            uv: if material.uses_uv() {
                hit.uv()
            } else {
                [0.0; 2]
            },
            // Measured from the camera, through the surfaces the ray passed.
            footprint: footprint.map_or([[0.0; 2]; 2], |f| {
                let mut from_camera = hit;
                from_camera.t += travelled;
                f.uv(&camera_ray, &from_camera)
            }),
        };
        // At the last vertex an opaque surface is not shaded (nothing further is allowed); one
        // that transmits may still pass the path on, so its BSDF is built first.
        if !two_sided && depth + 1 >= max_depth {
            break;
        }
        // The material's BSDF here, built once for every question below.
        let bsdf = material.bsdf(&at, &mut scratch.bsdf);
        if two_sided {
            // Light straight through (a delta lobe): followed with its share's probability,
            // the throughput unchanged (its weight over its probability is 1); the rest of the
            // vertex (light sampling and the next draw) carries what is not passed.
            let pass = bsdf.pass_through(wo).min(1.0);
            if pass > 0.0 {
                if sampler.uniform() < pass {
                    passes += 1;
                    if passes > MAX_PASSES {
                        break;
                    }
                    travelled += hit.t;
                    ray = spawn(&hit, ray.d);
                    continue;
                }
                beta *= 1.0 / (1.0 - pass);
            }
            if depth + 1 >= max_depth {
                break;
            }
        }

        // Next-event estimation.
        if use_lights {
            let k = scene.light_choice.sample(sampler.uniform()).bin;
            let (u1, u2) = sampler.next2();
            if let Some(ls) = scene.lights[k].sample_li(hit.p, [u1, u2]) {
                let wi = frame.to_local(ls.wi);
                // A light on the surface's side, or (through a surface that transmits) behind it.
                let side = ls.wi.dot(hit.ng);
                let seen = (wi.z > 0.0 && side > 0.0) || (two_sided && wi.z < 0.0 && side < 0.0);
                if seen && !ls.radiance.is_black() {
                    let f = bsdf.eval(wi, wo);
                    if !f.is_black() {
                        let shadow = spawn(&hit, ls.wi);
                        let t_max = if ls.distance.is_finite() {
                            // Stop short of the light's own surface.
                            (ls.distance - shadow.o.dot(ls.wi) + hit.p.dot(ls.wi)) * (1.0 - 1e-7)
                        } else {
                            f64::INFINITY
                        };
                        let passed = transmittance(scene, shadow, t_max);
                        if passed > 0.0 {
                            let light_pdf = pick(k) * ls.pdf;
                            let w = if ls.delta || settings.strategy == Strategy::Light {
                                1.0
                            } else {
                                power(light_pdf, bsdf.pdf(wi, wo, Transport::Radiance))
                            };
                            l += beta * f * ls.radiance * (passed * wi.z.abs() * w / light_pdf);
                        }
                    }
                }
            }
        }

        // BSDF sampling: the next direction. At the last vertex it can only find emission.
        if depth + 2 >= max_depth && !scene.emitters_can_be_hit {
            break;
        }
        // The lobe choice has a dimension of its own (stratified points stay stratified).
        let uc = sampler.uniform();
        let (u1, u2) = sampler.next2();
        // A draw of density 0 (or not a number) is no draw.
        let drawn = bsdf.sample(wo, uc, [u1, u2], Transport::Radiance);
        let Some(s) = drawn.filter(|s| s.pdf > 0.0) else {
            if let (0, Some(f)) = (depth, first.as_mut()) {
                f.albedo = Rgb::BLACK;
            }
            break;
        };
        if let (0, Some(f)) = (depth, first.as_mut()) {
            f.warp_share = bsdf.warp_share(wo);
            f.albedo = albedo_estimate(&s);
        }
        let wi = frame.to_world(s.wi);
        let side = wi.dot(hit.ng);
        if !(s.wi.z > 0.0 && side > 0.0 || two_sided && s.wi.z < 0.0 && side < 0.0) {
            // Through the geometric surface, or off its side: a one-sided surface transmits
            // nothing.
            break;
        }
        beta *= s.f * (s.wi.z.abs() / s.pdf);
        prev_pdf = s.pdf;
        depth += 1;

        // Russian roulette.
        if depth >= settings.rr_depth {
            let q = beta.max().min(0.95);
            if sampler.uniform() >= q {
                break;
            }
            beta *= 1.0 / q;
        }
        if beta.is_black() || !beta.is_valid() {
            break;
        }
        // The filter is for what the camera sees: later vertices shade with their cell's yarn.
        footprint = None;
        ray = spawn(&hit, wi);
    }
    l
}

/// A one-sample estimate of the albedo at a vertex from its draw `s`: its weight `f cos θ / pdf`,
/// each channel clamped to `[0, 1]` (0 where it is not finite), for the denoiser's guide.
#[inline]
fn albedo_estimate(s: &MaterialSample) -> Rgb {
    let w = s.f * (s.wi.z.abs() / s.pdf);
    Rgb(w.0.map(|c| {
        if c.is_finite() {
            c.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }))
}
