//! Rays, surface hits and the primitives: spheres, rectangles, cylinders and triangles.
//!
//! Every primitive is one-sided: its normal `ng` says which side reflects (and, for an emitter,
//! emits); a ray arriving from behind sees black. World space is right-handed, lengths in metres.

use std::f64::consts::PI;
use woven::Vec3;

/// A ray `o + t d`, `d` unit.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Origin.
    pub o: Vec3,
    /// Direction, unit.
    pub d: Vec3,
}

impl Ray {
    /// The point at distance `t`.
    #[inline]
    pub fn at(&self, t: f64) -> Vec3 {
        self.o + self.d * t
    }
}

/// Where a ray meets a surface, with the differential geometry a shading frame needs.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f64,
    /// The point.
    pub p: Vec3,
    /// Geometric normal, unit; the reflecting side.
    pub ng: Vec3,
    /// Shading normal, unit (interpolated on meshes; `ng` elsewhere), on `ng`'s side.
    pub ns: Vec3,
    /// Surface parameters `(u, v)`, [`Hit::uv`].
    uv: Uv,
    /// `∂p/∂u` (need not be unit or orthogonal to anything).
    pub dpdu: Vec3,
    /// `∂p/∂v`.
    pub dpdv: Vec3,
    /// Index of the primitive in the scene.
    pub prim: usize,
}

/// A hit's surface parameters: known, or a sphere's, worked out from its normal only when
/// asked (an arc tangent and an arc cosine that a material without a texture never reads).
#[derive(Clone, Copy, Debug)]
enum Uv {
    At([f64; 2]),
    Sphere,
}

impl Hit {
    /// Surface parameters `(u, v)`: a sphere's `(φ/2π, θ/π)` about its own `z` axis, a
    /// rectangle's and a cylinder's along their edge and axis, a mesh's interpolated.
    #[inline]
    pub fn uv(&self) -> [f64; 2] {
        match self.uv {
            Uv::At(uv) => uv,
            Uv::Sphere => {
                let n = self.ng;
                let theta = n.z.clamp(-1.0, 1.0).acos();
                [sphere_phi(n) / (2.0 * PI), theta / PI]
            }
        }
    }
}

/// The azimuth `φ ∈ [0, 2π)` of a sphere's unit normal `n`.
#[inline]
fn sphere_phi(n: Vec3) -> f64 {
    let a = n.y.atan2(n.x);
    if a < 0.0 {
        a + 2.0 * PI
    } else {
        a
    }
}

/// Where a ray crosses a primitive, before the hit's details: the distance, and a rectangle's
/// `(u, v)` or a triangle's barycentrics `(b1, b2)` (unused by spheres and cylinders).
#[derive(Clone, Copy, Debug)]
pub struct Crossing {
    /// Distance along the ray.
    pub t: f64,
    a: f64,
    b: f64,
}

/// A primitive's shape.
#[derive(Clone, Debug)]
pub enum Primitive {
    /// A sphere; normals outward; `u = φ/2π` around `+z`, `v = θ/π` from `+z`.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius, > 0.
        radius: f64,
    },
    /// The parallelogram `corner + a·edge_u + b·edge_v`, `a, b ∈ [0, 1]`; `uv = (a, b)`,
    /// normal `edge_u × edge_v`.
    Rectangle {
        /// A corner.
        corner: Vec3,
        /// First edge (the `u` direction).
        edge_u: Vec3,
        /// Second edge (the `v` direction).
        edge_v: Vec3,
    },
    /// An open cylinder tube around `axis` from `base`; normals outward; `u` around
    /// (`φ/2π` from `frame_x` toward `axis × frame_x`), `v` along (`0` at `base`, `1` at
    /// `base + axis`).
    Cylinder {
        /// Centre of the base circle.
        base: Vec3,
        /// From the base centre to the top centre.
        axis: Vec3,
        /// Radius, > 0.
        radius: f64,
    },
    /// Triangle `index` of mesh `mesh`.
    Triangle {
        /// Mesh index in the scene.
        mesh: usize,
        /// Triangle index in the mesh.
        index: usize,
    },
}

/// A primitive made ready for the crossing test: what the test works out from the shape alone
/// ([`Primitive::prepare`]), kept so that a ray pays only for what depends on it. A rectangle's
/// test is then one division; a cylinder's frame is not rebuilt for every ray.
#[derive(Clone, Copy, Debug)]
pub enum Prepared {
    /// A rectangle: its corner, its (unnormalized) normal `eu × ev`, and the vectors whose dot
    /// products with `p − corner` give its `(a, b)`.
    Rectangle {
        /// A corner.
        corner: Vec3,
        /// `edge_u × edge_v`.
        n: Vec3,
        /// `(edge_v × n) / |n|²`.
        to_a: Vec3,
        /// `(n × edge_u) / |n|²`.
        to_b: Vec3,
        /// The unit normal, as [`Primitive::hit`] works it out.
        unit_n: Vec3,
    },
    /// A cylinder: its base, its frame (`[x, y, axis]`, unit vectors) and its length.
    Cylinder {
        /// Centre of the base circle.
        base: Vec3,
        /// Two unit vectors across the axis, and the axis's unit vector.
        frame: [Vec3; 3],
        /// The axis's length.
        len: f64,
        /// Radius.
        radius: f64,
    },
    /// A sphere or a triangle: nothing to keep (a triangle reads its mesh).
    AsIs,
}

/// A rectangle's hit at crossing `c`: its unit normal `n`, its edges `[∂p/∂u, ∂p/∂v]`.
#[inline]
fn rectangle_hit(ray: &Ray, c: Crossing, n: Vec3, [dpdu, dpdv]: [Vec3; 2], prim: usize) -> Hit {
    Hit {
        t: c.t,
        p: ray.at(c.t),
        ng: n,
        ns: n,
        uv: Uv::At([c.a, c.b]),
        dpdu,
        dpdv,
        prim,
    }
}

impl Prepared {
    /// [`Primitive::hit`] of `prim`, which this was prepared from (a rectangle's normal is kept).
    #[inline]
    pub fn hit(
        &self,
        prim: &Primitive,
        ray: &Ray,
        c: Crossing,
        meshes: &[Mesh],
        index: usize,
    ) -> Hit {
        match (*self, prim) {
            (Prepared::Rectangle { unit_n, .. }, &Primitive::Rectangle { edge_u, edge_v, .. }) => {
                rectangle_hit(ray, c, unit_n, [edge_u, edge_v], index)
            }
            _ => prim.hit(ray, c, meshes, index),
        }
    }

    /// [`Primitive::crossing`] of `prim`, which this was prepared from.
    #[inline]
    pub fn crossing(
        &self,
        prim: &Primitive,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        meshes: &[Mesh],
    ) -> Option<Crossing> {
        match *self {
            Prepared::Rectangle {
                corner,
                n,
                to_a,
                to_b,
                ..
            } => {
                let denom = n.dot(ray.d);
                let num = n.dot(corner - ray.o);
                // t = num / denom, tested against (t_min, t_max) before dividing: most shadow
                // rays leave the plane they start on, and a division is the test's dearest step.
                let (num_pos, denom_pos) = if denom < 0.0 {
                    (-num, -denom)
                } else {
                    (num, denom)
                };
                if !(denom_pos > 0.0 && num_pos > t_min * denom_pos && num_pos < t_max * denom_pos)
                {
                    return None;
                }
                let t = num / denom;
                // The division's rounding can still land on an end of the range.
                if t <= t_min || t >= t_max {
                    return None;
                }
                let d = ray.at(t) - corner;
                let (a, b) = (d.dot(to_a), d.dot(to_b));
                ((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)).then_some(Crossing {
                    t,
                    a,
                    b,
                })
            }
            Prepared::Cylinder {
                base,
                frame: [fx, fy, w],
                len,
                radius,
            } => {
                // Local coordinates of the ray: (x, y) across the axis, z along it.
                let o = ray.o - base;
                let (ox, oy, oz) = (o.dot(fx), o.dot(fy), o.dot(w));
                let (dx, dy, dz) = (ray.d.dot(fx), ray.d.dot(fy), ray.d.dot(w));
                let a = dx * dx + dy * dy;
                if a == 0.0 {
                    return None;
                }
                let b = ox * dx + oy * dy;
                let c = ox * ox + oy * oy - radius * radius;
                let disc = b * b - a * c;
                if disc < 0.0 {
                    return None;
                }
                let sq = disc.sqrt();
                [(-b - sq) / a, (-b + sq) / a]
                    .into_iter()
                    .find(|&t| t > t_min && t < t_max && (0.0..=len).contains(&(oz + t * dz)))
                    .map(|t| Crossing { t, a: 0.0, b: 0.0 })
            }
            Prepared::AsIs => match *prim {
                Primitive::Sphere { center, radius } => {
                    let oc = ray.o - center;
                    let b = oc.dot(ray.d);
                    // From outside, moving away (a ray leaving the sphere's surface): nothing
                    // ahead, before any square root. Taken only where |oc|² − r² is clear of
                    // its rounding, so the answer is the full test's (both roots ≤ 0 ≤ t_min).
                    let oc2 = oc.dot(oc);
                    if b >= 0.0 && t_min >= 0.0 && oc2 - radius * radius > 1e-9 * oc2 {
                        return None;
                    }
                    // c computed as (|oc| − r)(|oc| + r) keeps precision for far origins.
                    let l = oc2.sqrt();
                    let c = (l - radius) * (l + radius);
                    let disc = b * b - c;
                    if disc < 0.0 {
                        return None;
                    }
                    let sq = disc.sqrt();
                    let mut t = -b - sq;
                    if t <= t_min {
                        t = -b + sq;
                    }
                    (t > t_min && t < t_max).then_some(Crossing { t, a: 0.0, b: 0.0 })
                }
                Primitive::Triangle { mesh, index } => {
                    let m = &meshes[mesh];
                    let [i0, i1, i2] = m.indices[index].map(|i| i as usize);
                    let (p0, p1, p2) = (m.positions[i0], m.positions[i1], m.positions[i2]);
                    // Möller–Trumbore.
                    let e1 = p1 - p0;
                    let e2 = p2 - p0;
                    let pv = ray.d.cross(e2);
                    let det = e1.dot(pv);
                    if det == 0.0 || !det.is_finite() {
                        return None;
                    }
                    let inv = 1.0 / det;
                    let tv = ray.o - p0;
                    let b1 = tv.dot(pv) * inv;
                    if !(0.0..=1.0).contains(&b1) {
                        return None;
                    }
                    let qv = tv.cross(e1);
                    let b2 = ray.d.dot(qv) * inv;
                    if b2 < 0.0 || b1 + b2 > 1.0 {
                        return None;
                    }
                    let t = e2.dot(qv) * inv;
                    (t > t_min && t < t_max).then_some(Crossing { t, a: b1, b: b2 })
                }
                // Prepared from another shape than `prim`: prepare `prim` itself.
                Primitive::Rectangle { .. } | Primitive::Cylinder { .. } => {
                    prim.prepare().crossing(prim, ray, t_min, t_max, meshes)
                }
            },
        }
    }
}

/// An indexed triangle mesh with per-vertex uv and (optional) normals.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (same length as `positions`), or empty for flat shading.
    pub normals: Vec<Vec3>,
    /// Per-vertex uv (same length as `positions`), or empty (uv = 0).
    pub uvs: Vec<[f64; 2]>,
    /// Triangles as vertex indices, counter-clockwise seen from the reflecting side.
    pub indices: Vec<[u32; 3]>,
}

/// Two unit vectors orthogonal to unit `n` and to each other (the library's, Duff et al. 2017).
pub use woven::math::basis::orthonormal_basis;

/// The cylinder's reference direction for `u = 0`: perpendicular to the axis.
pub fn cylinder_frame(axis: Vec3) -> (Vec3, Vec3) {
    orthonormal_basis(axis.normalize())
}

impl Primitive {
    /// The axis-aligned bounds `(min, max)`.
    pub fn bounds(&self, meshes: &[Mesh]) -> (Vec3, Vec3) {
        let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut hi = lo * -1.0;
        let mut grow = |p: Vec3| {
            lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        };
        match *self {
            Primitive::Sphere { center, radius } => {
                let r = Vec3::new(radius, radius, radius);
                grow(center - r);
                grow(center + r);
            }
            Primitive::Rectangle {
                corner,
                edge_u,
                edge_v,
            } => {
                for p in [
                    corner,
                    corner + edge_u,
                    corner + edge_v,
                    corner + edge_u + edge_v,
                ] {
                    grow(p);
                }
            }
            Primitive::Cylinder { base, axis, radius } => {
                // The bounds of the two end discs (a loose but safe box).
                let r = Vec3::new(radius, radius, radius);
                for c in [base, base + axis] {
                    grow(c - r);
                    grow(c + r);
                }
            }
            Primitive::Triangle { mesh, index } => {
                let m = &meshes[mesh];
                for &i in &m.indices[index] {
                    grow(m.positions[i as usize]);
                }
            }
        }
        (lo, hi)
    }

    /// The nearest hit with `t ∈ (t_min, t_max)`, from either side (the caller decides what the
    /// back side means): [`crossing`](Self::crossing), then [`hit`](Self::hit).
    pub fn intersect(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        meshes: &[Mesh],
        prim: usize,
    ) -> Option<Hit> {
        self.crossing(ray, t_min, t_max, meshes)
            .map(|c| self.hit(ray, c, meshes, prim))
    }

    /// Where `ray` first meets the primitive with `t ∈ (t_min, t_max)`, from either side: the
    /// distance alone (with what [`hit`](Self::hit) needs to finish), so a traversal that meets
    /// several candidates, or only asks whether anything is there, works out no more. A scene
    /// asks its [`Prepared`] form, which holds what this works out from the shape alone.
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_min: f64, t_max: f64, meshes: &[Mesh]) -> Option<Crossing> {
        self.prepare().crossing(self, ray, t_min, t_max, meshes)
    }

    /// What [`crossing`](Self::crossing) needs of the shape alone, worked out once.
    pub fn prepare(&self) -> Prepared {
        match *self {
            Primitive::Rectangle {
                corner,
                edge_u,
                edge_v,
            } => {
                let n = edge_u.cross(edge_v);
                let nn = n.dot(n);
                // With d = p − corner = a·eu + b·ev: a = (d × ev)·n / |n|² = d·(ev × n) / |n|²,
                // and b = (eu × d)·n / |n|² = d·(n × eu) / |n|² (Cramer's rule with the normal).
                Prepared::Rectangle {
                    corner,
                    n,
                    to_a: edge_v.cross(n) * (1.0 / nn),
                    to_b: n.cross(edge_u) * (1.0 / nn),
                    unit_n: n.normalize(),
                }
            }
            Primitive::Cylinder { base, axis, radius } => {
                let len = axis.length();
                let w = axis * (1.0 / len);
                let (fx, fy) = orthonormal_basis(w);
                Prepared::Cylinder {
                    base,
                    frame: [fx, fy, w],
                    len,
                    radius,
                }
            }
            Primitive::Sphere { .. } | Primitive::Triangle { .. } => Prepared::AsIs,
        }
    }
    /// The hit of `ray` at a [`crossing`](Self::crossing) of this primitive (index `prim`).
    pub fn hit(&self, ray: &Ray, c: Crossing, meshes: &[Mesh], prim: usize) -> Hit {
        let t = c.t;
        let p = ray.at(t);
        match *self {
            Primitive::Sphere { center, radius } => {
                let n = (p - center).normalize();
                // The angles' sines and cosines from the normal itself, not from the angles:
                // (sin θ cos φ, sin θ sin φ, cos θ) = n; at a pole φ's own (0 or π).
                let st = (n.x * n.x + n.y * n.y).sqrt();
                let ct = n.z;
                let (sp, cp) = if st > 0.0 {
                    (n.y / st, n.x / st)
                } else {
                    sphere_phi(n).sin_cos()
                };
                let dpdu = Vec3::new(-2.0 * PI * radius * n.y, 2.0 * PI * radius * n.x, 0.0);
                let dpdv = Vec3::new(
                    PI * radius * ct * cp,
                    PI * radius * ct * sp,
                    -PI * radius * st,
                );
                Hit {
                    t,
                    p,
                    ng: n,
                    ns: n,
                    uv: Uv::Sphere,
                    dpdu,
                    dpdv,
                    prim,
                }
            }
            Primitive::Rectangle { edge_u, edge_v, .. } => rectangle_hit(
                ray,
                c,
                edge_u.cross(edge_v).normalize(),
                [edge_u, edge_v],
                prim,
            ),
            Primitive::Cylinder { base, axis, radius } => {
                let len = axis.length();
                let w = axis * (1.0 / len);
                let (fx, fy) = orthonormal_basis(w);
                let o = p - base;
                let (x, y, z) = (o.dot(fx), o.dot(fy), o.dot(w).clamp(0.0, len));
                let mut phi = y.atan2(x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                let n = ((fx * x + fy * y) * (1.0 / radius)).normalize();
                let dpdu = (fx * -y + fy * x) * (2.0 * PI);
                Hit {
                    t,
                    p,
                    ng: n,
                    ns: n,
                    uv: Uv::At([phi / (2.0 * PI), z / len]),
                    dpdu,
                    dpdv: axis,
                    prim,
                }
            }
            Primitive::Triangle { mesh, index } => {
                let m = &meshes[mesh];
                let [i0, i1, i2] = m.indices[index].map(|i| i as usize);
                let (p0, p1, p2) = (m.positions[i0], m.positions[i1], m.positions[i2]);
                let (e1, e2) = (p1 - p0, p2 - p0);
                let (b1, b2) = (c.a, c.b);
                let b0 = 1.0 - b1 - b2;
                let ng = e1.cross(e2).normalize();
                let (uv0, uv1, uv2) = if m.uvs.is_empty() {
                    ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0])
                } else {
                    (m.uvs[i0], m.uvs[i1], m.uvs[i2])
                };
                let uv = [
                    b0 * uv0[0] + b1 * uv1[0] + b2 * uv2[0],
                    b0 * uv0[1] + b1 * uv1[1] + b2 * uv2[1],
                ];
                // ∂p/∂u, ∂p/∂v from the uv differences (pbrt's construction).
                let (du1, dv1) = (uv1[0] - uv0[0], uv1[1] - uv0[1]);
                let (du2, dv2) = (uv2[0] - uv0[0], uv2[1] - uv0[1]);
                let d = du1 * dv2 - dv1 * du2;
                let (dpdu, dpdv) = if d.abs() < 1e-12 {
                    // Degenerate uv: any frame in the plane.
                    orthonormal_basis(ng)
                } else {
                    let r = 1.0 / d;
                    ((e1 * dv2 - e2 * dv1) * r, (e2 * du1 - e1 * du2) * r)
                };
                let ns = if m.normals.is_empty() {
                    ng
                } else {
                    let n = m.normals[i0] * b0 + m.normals[i1] * b1 + m.normals[i2] * b2;
                    let l = n.length();
                    if l > 0.0 && l.is_finite() {
                        // The shading normal stays on the reflecting side of the geometry.
                        let n = n * (1.0 / l);
                        if n.dot(ng) > 0.0 {
                            n
                        } else {
                            ng
                        }
                    } else {
                        ng
                    }
                };
                Hit {
                    t,
                    p,
                    ng,
                    ns,
                    uv: Uv::At(uv),
                    dpdu,
                    dpdv,
                    prim,
                }
            }
        }
    }
}

/// The local shading frame at a hit: tangent `x` along `∂p/∂u` (the weft), `z` the shading
/// normal, `y = z × x` (along `∂p/∂v` for a right-handed parameterization).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Tangent (weft, `u`).
    pub x: Vec3,
    /// Bitangent (warp, `v`).
    pub y: Vec3,
    /// Shading normal.
    pub z: Vec3,
}

impl Frame {
    /// The frame of a hit: `∂p/∂u` made orthogonal to the shading normal (Gram–Schmidt); an
    /// arbitrary tangent where `∂p/∂u` vanishes (a sphere's poles).
    pub fn from_hit(hit: &Hit) -> Frame {
        let z = hit.ns;
        let t = hit.dpdu - z * z.dot(hit.dpdu);
        // |t| > 10⁻¹² |∂p/∂u|, squared (one square root fewer on every hit).
        let l2 = t.dot(t);
        let x = if l2 > 1e-24 * hit.dpdu.dot(hit.dpdu).max(f64::MIN_POSITIVE) && l2.is_finite() {
            t * (1.0 / l2.sqrt())
        } else {
            // ∂p/∂u vanishes: fall back on ∂p/∂v, else any tangent.
            let t2 = hit.dpdv - z * z.dot(hit.dpdv);
            let l2 = t2.length();
            if l2 > 0.0 && l2.is_finite() {
                (t2 * (1.0 / l2)).cross(z)
            } else {
                orthonormal_basis(z).0
            }
        };
        Frame {
            x,
            y: z.cross(x),
            z,
        }
    }

    /// A world direction in the local frame.
    #[inline]
    pub fn to_local(&self, d: Vec3) -> Vec3 {
        Vec3::new(d.dot(self.x), d.dot(self.y), d.dot(self.z))
    }

    /// A local direction in world space.
    #[inline]
    pub fn to_world(&self, d: Vec3) -> Vec3 {
        self.x * d.x + self.y * d.y + self.z * d.z
    }
}

/// How wide a pixel is where its camera ray meets a surface: ray differentials (exact for the
/// pinhole, anisotropic).
/// A camera ray is `o + s·D` with `D = d/(d·forward)`; the footprint holds `∂D/∂x` and
/// `∂D/∂y` per film pixel.
#[derive(Clone, Copy, Debug)]
pub struct RayFootprint {
    /// The camera's view direction.
    pub forward: Vec3,
    /// `∂D/∂x`, per pixel.
    pub dd_dx: Vec3,
    /// `∂D/∂y`, per pixel.
    pub dd_dy: Vec3,
}

impl RayFootprint {
    /// The footprint at `hit` of `ray` in world space: the change of the hit point from one
    /// pixel to the next along `x` and `y`, both in the tangent plane.
    pub fn world(&self, ray: &Ray, hit: &Hit) -> [Vec3; 2] {
        let n = hit.ng;
        // p = o + s D with s = t (d·forward); moving D by dD keeps p on the tangent plane:
        // dp = s (dD − D (n·dD)/(n·D)).
        let f = ray.d.dot(self.forward);
        let big_d = ray.d * (1.0 / f);
        let s = hit.t * f;
        let nd = n.dot(big_d);
        [self.dd_dx, self.dd_dy].map(|dd| (dd - big_d * (n.dot(dd) / nd)) * s)
    }

    /// The footprint at `hit` in uv: `[[∂u/∂x, ∂v/∂x], [∂u/∂y, ∂v/∂y]]` (least squares through
    /// `∂p/∂u`, `∂p/∂v`; infinite where the parameterization degenerates).
    pub fn uv(&self, ray: &Ray, hit: &Hit) -> [[f64; 2]; 2] {
        let (pu, pv) = (hit.dpdu, hit.dpdv);
        let (uu, uv, vv) = (pu.dot(pu), pu.dot(pv), pv.dot(pv));
        let det = uu * vv - uv * uv;
        self.world(ray, hit).map(|dp| {
            let (bu, bv) = (pu.dot(dp), pv.dot(dp));
            let d = [(vv * bu - uv * bv) / det, (uu * bv - uv * bu) / det];
            if d[0].is_finite() && d[1].is_finite() {
                d
            } else {
                [f64::INFINITY; 2]
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f64; 3], d: [f64; 3]) -> Ray {
        Ray {
            o: Vec3::new(o[0], o[1], o[2]),
            d: Vec3::new(d[0], d[1], d[2]).normalize(),
        }
    }

    #[test]
    fn sphere_hit_from_outside_has_outward_normal_and_uv() {
        let s = Primitive::Sphere {
            center: Vec3::new(0.0, 0.0, 0.0),
            radius: 2.0,
        };
        let h = s
            .intersect(
                &ray([5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
                0.0,
                f64::INFINITY,
                &[],
                0,
            )
            .unwrap();
        assert!((h.t - 3.0).abs() < 1e-12 && (h.ng.x - 1.0).abs() < 1e-12);
        assert!((h.uv()[0] - 0.0).abs() < 1e-12 && (h.uv()[1] - 0.5).abs() < 1e-12);
        // ∂p/∂u points along +y at φ = 0 (counter-clockwise about +z), length 2π r.
        assert!((h.dpdu.y - 4.0 * PI).abs() < 1e-9);
    }

    /// A sphere hit's ∂p/∂u and ∂p/∂v are the derivatives of its parameterization p(u, v)
    /// (φ = 2πu, θ = πv), by central differences, all over the sphere.
    #[test]
    fn sphere_derivatives_are_those_of_its_parameterization() {
        let (center, radius) = (Vec3::new(0.3, -0.2, 0.5), 1.5);
        let s = Primitive::Sphere { center, radius };
        let p = |u: f64, v: f64| {
            let (phi, theta) = (2.0 * PI * u, PI * v);
            center
                + Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ) * radius
        };
        let mut rng = woven::math::rng::SplitMix(11);
        for _ in 0..200 {
            let d = rng.direction(PI);
            let r = Ray {
                o: center + d * 5.0,
                d: -d,
            };
            let h = s.intersect(&r, 0.0, f64::INFINITY, &[], 0).unwrap();
            let [u, v] = h.uv();
            let e = 1e-6;
            let du = (p(u + e, v) - p(u - e, v)) * (0.5 / e);
            let dv = (p(u, v + e) - p(u, v - e)) * (0.5 / e);
            assert!(
                (h.p - p(u, v)).length() < 1e-9,
                "uv does not map back to the hit"
            );
            assert!(
                (h.dpdu - du).length() < 1e-6 * radius,
                "dpdu {:?} vs {du:?}",
                h.dpdu
            );
            assert!(
                (h.dpdv - dv).length() < 1e-6 * radius,
                "dpdv {:?} vs {dv:?}",
                h.dpdv
            );
        }
    }

    #[test]
    fn rectangle_uv_and_bounds() {
        let r = Primitive::Rectangle {
            corner: Vec3::new(-1.0, -1.0, 0.0),
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 2.0, 0.0),
        };
        let h = r
            .intersect(
                &ray([0.5, 0.0, 3.0], [0.0, 0.0, -1.0]),
                0.0,
                f64::INFINITY,
                &[],
                0,
            )
            .unwrap();
        assert!((h.uv()[0] - 0.75).abs() < 1e-12 && (h.uv()[1] - 0.5).abs() < 1e-12);
        assert!((h.ng.z - 1.0).abs() < 1e-12);
        assert!(r
            .intersect(
                &ray([1.5, 0.0, 3.0], [0.0, 0.0, -1.0]),
                0.0,
                f64::INFINITY,
                &[],
                0
            )
            .is_none());
    }

    #[test]
    fn cylinder_hit_and_frame() {
        let c = Primitive::Cylinder {
            base: Vec3::new(0.0, 0.0, 0.0),
            axis: Vec3::new(0.0, 0.0, 2.0),
            radius: 0.5,
        };
        let h = c
            .intersect(
                &ray([3.0, 0.1, 1.0], [-1.0, 0.0, 0.0]),
                0.0,
                f64::INFINITY,
                &[],
                0,
            )
            .unwrap();
        assert!((h.p.x * h.p.x + h.p.y * h.p.y - 0.25).abs() < 1e-9);
        assert!(h.ng.dot(Vec3::new(h.p.x, h.p.y, 0.0)) > 0.0);
        assert!((h.uv()[1] - 0.5).abs() < 1e-12);
        let f = Frame::from_hit(&h);
        // The frame is orthonormal and right-handed; y runs along the axis here.
        assert!((f.x.cross(f.y).dot(f.z) - 1.0).abs() < 1e-12);
        assert!(f.y.z.abs() > 0.999);
    }

    #[test]
    fn triangle_barycentric_uv() {
        let mesh = Mesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: vec![],
            uvs: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            indices: vec![[0, 1, 2]],
        };
        let t = Primitive::Triangle { mesh: 0, index: 0 };
        let h = t
            .intersect(
                &ray([0.25, 0.5, 1.0], [0.0, 0.0, -1.0]),
                0.0,
                f64::INFINITY,
                &[mesh],
                0,
            )
            .unwrap();
        assert!((h.uv()[0] - 0.25).abs() < 1e-12 && (h.uv()[1] - 0.5).abs() < 1e-12);
        assert!((h.dpdu.x - 1.0).abs() < 1e-12 && (h.dpdv.y - 1.0).abs() < 1e-12);
    }
}
