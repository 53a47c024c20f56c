//! The acceleration structure: a bounding volume hierarchy (the `bvh` crate, SAH build) over
//! every primitive of a scene.

use crate::geometry::{Hit, Mesh, Primitive, Ray};
use bvh::aabb::{Aabb, Bounded, IntersectsAabb};
use bvh::bounding_hierarchy::BHShape;
use bvh::bvh::Bvh;
use nalgebra::Point3;
use std::cell::Cell;

/// A primitive as the BVH stores it: its bounds and its node.
struct Leaf {
    aabb: Aabb<f64, 3>,
    node: usize,
    /// Index of the primitive.
    index: usize,
}

impl Bounded<f64, 3> for Leaf {
    fn aabb(&self) -> Aabb<f64, 3> {
        self.aabb
    }
}

impl BHShape<f64, 3> for Leaf {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node = index;
    }
    fn bh_node_index(&self) -> usize {
        self.node
    }
}

/// A ray query that shrinks as hits are found: boxes beyond the nearest hit so far are skipped.
struct Query {
    o: [f64; 3],
    inv_d: [f64; 3],
    t_min: f64,
    t_max: Cell<f64>,
}

impl IntersectsAabb<f64, 3> for Query {
    fn intersects_aabb(&self, aabb: &Aabb<f64, 3>) -> bool {
        // The slab test; NaN from 0·∞ (a ray in a box's face plane) fails safe via max/min.
        let mut t0 = self.t_min;
        let mut t1 = self.t_max.get();
        for k in 0..3 {
            let a = (aabb.min[k] - self.o[k]) * self.inv_d[k];
            let b = (aabb.max[k] - self.o[k]) * self.inv_d[k];
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            t0 = if lo > t0 { lo } else { t0 };
            // Widened by a few ulps so that a hit on a box face is never culled.
            t1 = if hi * (1.0 + 4.0 * f64::EPSILON) < t1 {
                hi * (1.0 + 4.0 * f64::EPSILON)
            } else {
                t1
            };
            if t0 > t1 {
                return false;
            }
        }
        true
    }
}

/// The scene's geometry: primitives, meshes and their BVH.
pub struct Accel {
    prims: Vec<Primitive>,
    meshes: Vec<Mesh>,
    leaves: Vec<Leaf>,
    bvh: Bvh<f64, 3>,
}

impl Accel {
    /// Builds the hierarchy over `prims` (triangles refer to `meshes`).
    pub fn new(prims: Vec<Primitive>, meshes: Vec<Mesh>) -> Accel {
        let mut leaves: Vec<Leaf> = prims
            .iter()
            .enumerate()
            .map(|(index, p)| {
                let (lo, hi) = p.bounds(&meshes);
                // A flat primitive's box gets a little thickness so the slab test sees it.
                let pad = 1e-9 * (1.0 + lo.x.abs().max(lo.y.abs()).max(lo.z.abs()));
                Leaf {
                    aabb: Aabb::with_bounds(
                        Point3::new(lo.x - pad, lo.y - pad, lo.z - pad),
                        Point3::new(hi.x + pad, hi.y + pad, hi.z + pad),
                    ),
                    node: 0,
                    index,
                }
            })
            .collect();
        let bvh = Bvh::build(&mut leaves);
        Accel {
            prims,
            meshes,
            leaves,
            bvh,
        }
    }

    /// The primitives, in scene order.
    pub fn primitives(&self) -> &[Primitive] {
        &self.prims
    }

    /// The meshes triangles refer to.
    pub fn meshes(&self) -> &[Mesh] {
        &self.meshes
    }

    /// The nearest hit with `t ∈ (t_min, t_max)`, from either side.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        if self.prims.is_empty() {
            return None;
        }
        let query = Query {
            o: [ray.o.x, ray.o.y, ray.o.z],
            inv_d: [1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z],
            t_min,
            t_max: Cell::new(t_max),
        };
        let mut best: Option<Hit> = None;
        for leaf in self.bvh.traverse_iterator(&query, &self.leaves) {
            let index = leaf.index;
            if let Some(hit) =
                self.prims[index].intersect(ray, t_min, query.t_max.get(), &self.meshes, index)
            {
                query.t_max.set(hit.t);
                best = Some(hit);
            }
        }
        best
    }

    /// Whether anything lies on the ray strictly between `t_min` and `t_max`.
    pub fn occluded(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        if self.prims.is_empty() {
            return false;
        }
        let query = Query {
            o: [ray.o.x, ray.o.y, ray.o.z],
            inv_d: [1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z],
            t_min,
            t_max: Cell::new(t_max),
        };
        self.bvh
            .traverse_iterator(&query, &self.leaves)
            .any(|leaf| {
                let index = leaf.index;
                self.prims[index]
                    .intersect(ray, t_min, t_max, &self.meshes, index)
                    .is_some()
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
