//! The acceleration structure: a compressed 8-wide bounding volume hierarchy (the `obvhs`
//! crate: PLOC build, SIMD traversal) over every primitive of a scene.
//!
//! The hierarchy is single precision; the primitives are intersected in double precision. Each
//! primitive's box is padded outward (by 10⁻⁵ of its distance from the origin, at least 10⁻⁶ m)
//! so that rounding the ray and the boxes to `f32` can never cull a primitive the ray reaches,
//! and the distance handed back for culling is rounded up. The `bvh` crate's double-precision
//! hierarchy was 2.3× slower on the showcase (its traversal iterator was a quarter of the
//! render's time).

use crate::geometry::{Crossing, Hit, Mesh, Prepared, Primitive, Ray};
use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray as RayF32, RayHit};
use obvhs::{Boundable, BvhBuildParams};
use woven::Vec3;

/// A primitive's padded bounds, as the builder takes them.
struct Bounds(Aabb);

impl Boundable for Bounds {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// The scene's primitives and their hierarchy.
pub struct Accel {
    prims: Vec<Primitive>,
    /// Each primitive's [`Prepared`] form, in the same order.
    prepared: Vec<Prepared>,
    meshes: Vec<Mesh>,
    bvh: CwBvh,
    /// Primitives whose padded boxes are identical share one leaf of the hierarchy: the
    /// builder's nearest-neighbour merging (PLOC) finds no pair to merge among equal boxes
    /// and goes quadratic (30 000 coincident triangles took 27 s). `None` when every box is
    /// distinct; otherwise leaf `i` holds `order[starts[i]..starts[i + 1]]`.
    groups: Option<Groups>,
    /// Boxes, `[min, max]`, that hold every point a ray can meet: each primitive's padded box
    /// in a scene of at most [`BRUTE_FORCE_MAX`] primitives, else their union (none when the
    /// scene is empty).
    boxes: Vec<[Vec3; 2]>,
}

/// The primitives of each distinct box, in compressed rows.
struct Groups {
    starts: Vec<u32>,
    order: Vec<u32>,
}

impl Groups {
    /// Groups equal boxes; `None` when all are distinct. The kept boxes are each group's, in
    /// group order.
    fn of(bounds: &mut Vec<Bounds>) -> Option<Groups> {
        let key = |b: &Bounds| {
            let (lo, hi) = (b.0.min, b.0.max);
            [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z].map(f32::to_bits)
        };
        let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
        order.sort_unstable_by_key(|&i| key(&bounds[i as usize]));
        let mut starts = Vec::new();
        let mut unique = Vec::new();
        for (k, &i) in order.iter().enumerate() {
            if k == 0 || key(&bounds[i as usize]) != key(&bounds[order[k - 1] as usize]) {
                starts.push(k as u32);
                unique.push(Bounds(bounds[i as usize].0));
            }
        }
        if unique.len() == bounds.len() {
            return None;
        }
        starts.push(order.len() as u32);
        *bounds = unique;
        Some(Groups { starts, order })
    }
}

/// Scenes of at most this many primitives are intersected by a loop over all of them: a
/// hierarchy's traversal costs more than a few sphere or rectangle tests (the one-rectangle
/// comparison scene ran at half the speed through it).
const BRUTE_FORCE_MAX: usize = 8;

/// The smallest `f32` at least `x` (for `x ≥ 0`), so culling by it is conservative.
#[inline]
fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        y.next_up()
    } else {
        y
    }
}

impl Accel {
    /// Builds the hierarchy over `prims` (triangles index into `meshes`).
    pub fn new(prims: Vec<Primitive>, meshes: Vec<Mesh>) -> Accel {
        let bounds: Vec<Bounds> = prims
            .iter()
            .map(|p| {
                let (lo, hi) = p.bounds(&meshes);
                let size =
                    lo.x.abs()
                        .max(lo.y.abs())
                        .max(lo.z.abs())
                        .max(hi.x.abs().max(hi.y.abs()).max(hi.z.abs()));
                let pad = (1e-5 * size).max(1e-6);
                let down = |x: f64| ((x - pad) as f32).next_down();
                let up = |x: f64| ((x + pad) as f32).next_up();
                Bounds(Aabb::new(
                    Vec3A::new(down(lo.x), down(lo.y), down(lo.z)),
                    Vec3A::new(up(hi.x), up(hi.y), up(hi.z)),
                ))
            })
            .collect();
        let mut bounds = bounds;
        let boxes = Self::enclosing(&bounds);
        let groups = Groups::of(&mut bounds);
        let bvh = if prims.len() <= BRUTE_FORCE_MAX {
            CwBvh::default()
        } else {
            obvhs::cwbvh::builder::build_cwbvh(
                &bounds,
                BvhBuildParams::medium_build(),
                &mut std::time::Duration::default(),
            )
        };
        let prepared = prims.iter().map(Primitive::prepare).collect();
        Accel {
            prims,
            prepared,
            meshes,
            bvh,
            groups,
            boxes,
        }
    }

    /// [`Accel::boxes`] from the primitives' padded boxes.
    fn enclosing(bounds: &[Bounds]) -> Vec<[Vec3; 2]> {
        let corners = |b: &Bounds| {
            let v = |p: Vec3A| Vec3::new(p.x as f64, p.y as f64, p.z as f64);
            [v(b.0.min), v(b.0.max)]
        };
        if bounds.len() <= BRUTE_FORCE_MAX {
            return bounds.iter().map(corners).collect();
        }
        let union = bounds.iter().map(corners).reduce(|[lo, hi], [a, b]| {
            [
                Vec3::new(lo.x.min(a.x), lo.y.min(a.y), lo.z.min(a.z)),
                Vec3::new(hi.x.max(b.x), hi.y.max(b.y), hi.z.max(b.z)),
            ]
        });
        union.into_iter().collect()
    }

    /// Boxes `[min, max]` that together hold every point a ray can meet, padded like the
    /// hierarchy's (empty for an empty scene): a ray, or a bundle of rays, that passes by all of
    /// them meets nothing.
    pub fn boxes(&self) -> &[[Vec3; 2]] {
        &self.boxes
    }

    /// The primitives of the hierarchy's primitive `id`: one, or a group of coincident ones.
    #[inline]
    fn members(&self, id: u32) -> impl Iterator<Item = usize> + '_ {
        let leaf = self.bvh.primitive_indices[id as usize];
        let (range, order) = match &self.groups {
            None => (leaf..leaf + 1, None),
            Some(g) => (
                g.starts[leaf as usize]..g.starts[leaf as usize + 1],
                Some(&g.order),
            ),
        };
        range.map(move |k| order.map_or(k as usize, |o| o[k as usize] as usize))
    }

    /// Every primitive, in scene order.
    pub fn primitives(&self) -> &[Primitive] {
        &self.prims
    }

    /// The triangle meshes the primitives index into.
    pub fn meshes(&self) -> &[Mesh] {
        &self.meshes
    }

    /// Where `ray` crosses primitive `index` ([`Primitive::crossing`], through its prepared form).
    #[inline]
    fn crossing(&self, index: usize, ray: &Ray, t_min: f64, t_max: f64) -> Option<Crossing> {
        self.prepared[index].crossing(&self.prims[index], ray, t_min, t_max, &self.meshes)
    }

    /// The ray in single precision, over `[0, t_max]` (rounded up): `t_min` is applied to the
    /// primitives, in double precision.
    #[inline]
    fn ray_f32(ray: &Ray, t_max: f64) -> RayF32 {
        RayF32::new(
            Vec3A::new(ray.o.x as f32, ray.o.y as f32, ray.o.z as f32),
            Vec3A::new(ray.d.x as f32, ray.d.y as f32, ray.d.z as f32),
            0.0,
            f32_up(t_max),
        )
    }

    /// The nearest hit with `t` in `(t_min, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        if self.prims.is_empty() {
            return None;
        }
        // The nearest crossing so far; the hit's details are worked out for it alone.
        let mut best: Option<(usize, Crossing)> = None;
        let mut best_t = t_max;
        if self.prims.len() <= BRUTE_FORCE_MAX {
            for index in 0..self.prims.len() {
                if let Some(c) = self.crossing(index, ray, t_min, best_t) {
                    best_t = c.t;
                    best = Some((index, c));
                }
            }
        } else {
            let mut hit = RayHit::none();
            self.bvh
                .ray_traverse(Self::ray_f32(ray, t_max), &mut hit, |_, id| {
                    let mut found = false;
                    for index in self.members(id as u32) {
                        if let Some(c) = self.crossing(index, ray, t_min, best_t) {
                            best_t = c.t;
                            best = Some((index, c));
                            found = true;
                        }
                    }
                    if found {
                        f32_up(best_t)
                    } else {
                        f32::INFINITY
                    }
                });
        }
        best.map(|(index, c)| {
            self.prepared[index].hit(&self.prims[index], ray, c, &self.meshes, index)
        })
    }

    /// Whether anything lies on the ray with `t` in `(t_min, t_max)` (stops at the first hit).
    pub fn occluded(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        if self.prims.len() <= BRUTE_FORCE_MAX {
            return (0..self.prims.len()).any(|i| self.crossing(i, ray, t_min, t_max).is_some());
        }
        !self
            .bvh
            .ray_traverse_miss(Self::ray_f32(ray, t_max), |_, id| {
                let hit = self
                    .members(id as u32)
                    .any(|index| self.crossing(index, ray, t_min, t_max).is_some());
                if hit {
                    0.0
                } else {
                    f32::INFINITY
                }
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use woven::math::rng::SplitMix;
    use woven::Vec3;

    /// The BVH finds exactly the hits a brute-force loop over all primitives finds.
    #[test]
    fn bvh_agrees_with_brute_force() {
        let mut rng = SplitMix(3);
        let mut prims = Vec::new();
        for _ in 0..60 {
            let c = Vec3::new(
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
            );
            prims.push(Primitive::Sphere {
                center: c,
                radius: rng.range(0.1, 1.0),
            });
            prims.push(Primitive::Rectangle {
                corner: c,
                edge_u: Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0),
                edge_v: Vec3::new(0.0, rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
            });
        }
        let accel = Accel::new(prims.clone(), vec![]);
        let mut hits = 0;
        for _ in 0..2000 {
            let o = Vec3::new(
                rng.range(-8.0, 8.0),
                rng.range(-8.0, 8.0),
                rng.range(-8.0, 8.0),
            );
            let ray = Ray {
                o,
                d: rng.direction(std::f64::consts::PI),
            };
            let brute = prims
                .iter()
                .enumerate()
                .filter_map(|(i, p)| p.intersect(&ray, 0.0, f64::INFINITY, &[], i))
                .min_by(|a, b| a.t.total_cmp(&b.t));
            let fast = accel.intersect(&ray, 0.0, f64::INFINITY);
            match (brute, fast) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert_eq!(a.prim, b.prim);
                    assert!((a.t - b.t).abs() < 1e-12);
                }
                (a, b) => panic!("brute {:?} vs bvh {:?}", a.map(|h| h.t), b.map(|h| h.t)),
            }
            assert_eq!(
                accel.occluded(&ray, 0.0, f64::INFINITY),
                accel.intersect(&ray, 0.0, f64::INFINITY).is_some()
            );
        }
        assert!(
            hits > 200,
            "only {hits} hits: the test shoots too few rays at the shapes"
        );
    }
}
