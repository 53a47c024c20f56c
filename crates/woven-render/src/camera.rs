//! The pinhole camera, with Mitsuba 3's conventions (`perspective`, `fov_axis = "x"`).
//!
//! Film pixel `(i, j)` covers `[i, i+1] × [j, j+1]` in film coordinates, row 0 at the top. A film
//! point `(x, y)` maps to the ray through the image plane at distance 1 with
//! `X = (2x/W − 1) tan(fov/2)` to the right and `Y = (1 − 2y/H) tan(fov/2) H/W` up, so the field
//! of view `fov_deg` spans the film's width. The camera looks from `origin` toward `target`; the
//! image's up is `up` made orthogonal to the view direction.

use crate::geometry::{Ray, RayFootprint};
use woven::Vec3;

/// How far, in pixels, [`Camera::pixel_misses`] widens a pixel: far below a pixel, and far
/// beyond the rounding of a ray's direction and of the side planes' normals (relative 10⁻¹⁶ of
/// a direction, against 10⁻³ of a pixel's angle: safe down to pixels of 10⁻¹² rad).
const PIXEL_MARGIN: f64 = 1e-3;

/// A pinhole camera.
#[derive(Clone, Debug)]
pub struct Camera {
    origin: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// `tan(fov/2)`: the image plane's half width at distance 1.
    half_width: f64,
    /// The half height at distance 1.
    half_height: f64,
    /// `2 tan(fov/2) / W` and `2 (H/W) tan(fov/2) / H`: the image plane's step per pixel (no
    /// division per ray).
    step: [f64; 2],
    width: usize,
    height: usize,
}

impl Camera {
    /// A camera at `origin` looking at `target`, `up` roughly up, horizontal field of view
    /// `fov_deg ∈ (0, 180)` degrees, a film of `width × height` pixels. The caller has checked
    /// that `target ≠ origin` and `up` is not parallel to the view direction.
    pub fn new(
        origin: Vec3,
        target: Vec3,
        up: Vec3,
        fov_deg: f64,
        width: usize,
        height: usize,
    ) -> Camera {
        let forward = (target - origin).normalize();
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        let half_width = (fov_deg.to_radians() / 2.0).tan();
        let half_height = half_width * height as f64 / width as f64;
        Camera {
            origin,
            forward,
            right,
            up,
            half_width,
            half_height,
            step: [
                2.0 * half_width / width as f64,
                2.0 * half_height / height as f64,
            ],
            width,
            height,
        }
    }

    /// The ray through film point `(x, y)` (pixels, `x ∈ [0, W]`, `y ∈ [0, H]`, `y` down).
    pub fn ray(&self, x: f64, y: f64) -> Ray {
        Ray {
            o: self.origin,
            d: self.through(x, y).normalize(),
        }
    }

    /// The direction, not normalized, through film point `(x, y)`: the image plane's point at
    /// distance 1.
    #[inline]
    fn through(&self, x: f64, y: f64) -> Vec3 {
        let sx = x * self.step[0] - self.half_width;
        let sy = self.half_height - y * self.step[1];
        self.forward + self.right * sx + self.up * sy
    }

    /// Whether every ray through film pixel `(x, y)` (film points in `[x, x + 1] × [y, y + 1]`)
    /// passes by every box `[min, max]` of `boxes`, so that none can meet what the boxes hold.
    /// Conservative: `false` whenever it cannot tell.
    ///
    /// The pixel's rays fill the pyramid from the origin through its square on the image plane
    /// (widened by a thousandth of a pixel against rounding); a box misses the pyramid when its
    /// corners all lie outside one of the pyramid's four side planes (the box's support along
    /// the plane's normal is negative).
    pub fn pixel_misses(&self, x: usize, y: usize, boxes: &[[Vec3; 2]]) -> bool {
        let (x0, x1) = (x as f64 - PIXEL_MARGIN, (x + 1) as f64 + PIXEL_MARGIN);
        let (y0, y1) = (y as f64 - PIXEL_MARGIN, (y + 1) as f64 + PIXEL_MARGIN);
        // The square's corners in turn around it, and the edges from each to the next, made
        // from the camera's axes (a difference of neighbouring corners would lose the digits
        // that tell them apart in a narrow field of view).
        let c = [
            self.through(x0, y0),
            self.through(x1, y0),
            self.through(x1, y1),
            self.through(x0, y1),
        ];
        let (across, down) = (
            self.right * ((x1 - x0) * self.step[0]),
            self.up * ((y1 - y0) * -self.step[1]),
        );
        let edges = [across, down, -across, -down];
        // The inward normals of the side planes through each corner and its edge.
        let centre = c[0] + c[1] + c[2] + c[3];
        let sides: [Vec3; 4] = std::array::from_fn(|k| {
            let n = c[k].cross(edges[k]);
            if n.dot(centre) < 0.0 {
                -n
            } else {
                n
            }
        });
        boxes.iter().all(|[lo, hi]| {
            let mid = (*lo + *hi) * 0.5 - self.origin;
            let half = (*hi - *lo) * 0.5;
            sides.iter().any(|n| {
                n.dot(mid) + n.x.abs() * half.x + n.y.abs() * half.y + n.z.abs() * half.z < 0.0
            })
        })
    }

    /// The footprint of camera rays (ray differentials): how the ray moves from one film pixel
    /// to the next.
    pub fn footprint(&self) -> RayFootprint {
        RayFootprint {
            forward: self.forward,
            dd_dx: self.right * self.step[0],
            dd_dy: self.up * -self.step[1],
        }
    }

    /// Film width, pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Film height, pixels.
    pub fn height(&self) -> usize {
        self.height
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn film_edges_span_the_horizontal_fov() {
        let cam = Camera::new(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            90.0,
            200,
            100,
        );
        // The left edge is 45° to the left (−x when looking along +y with +z up), the centre
        // straight ahead, the top edge up by atan(tan 45° · 1/2).
        let left = cam.ray(0.0, 50.0).d;
        assert!((left.x + 0.5f64.sqrt()).abs() < 1e-12 && (left.y - 0.5f64.sqrt()).abs() < 1e-12);
        let c = cam.ray(100.0, 50.0).d;
        assert!((c.y - 1.0).abs() < 1e-12);
        let top = cam.ray(100.0, 0.0).d;
        assert!((top.z / top.y - 0.5).abs() < 1e-12);
    }

    /// Whether the ray meets the box `[lo, hi]` ahead of its origin (slabs).
    fn meets(ray: &Ray, [lo, hi]: [Vec3; 2]) -> bool {
        let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
        for (o, d, a, b) in [
            (ray.o.x, ray.d.x, lo.x, hi.x),
            (ray.o.y, ray.d.y, lo.y, hi.y),
            (ray.o.z, ray.d.z, lo.z, hi.z),
        ] {
            let (ta, tb) = ((a - o) / d, (b - o) / d);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        t0 <= t1
    }

    /// A pixel said to miss a box has no ray that meets it: film points all over the pixel,
    /// its edges and corners included, against random cameras and boxes (some around the
    /// camera, some behind it). And the test does cull: most pixels far from a small box are
    /// said to miss it, and no pixel whose centre ray meets a box is.
    #[test]
    fn a_pixel_said_to_miss_the_boxes_has_no_ray_that_meets_them() {
        let mut rng = woven::math::rng::SplitMix(17);
        let (mut culled, mut kept, mut far) = (0, 0, 0);
        for _ in 0..200 {
            let mut v = |k: f64| Vec3::new(rng.range(-k, k), rng.range(-k, k), rng.range(-k, k));
            let origin = v(3.0);
            let target = v(1.0);
            let centre = v(2.0);
            let h = v(0.3);
            let half = Vec3::new(0.05 + h.x.abs(), 0.05 + h.y.abs(), 0.05 + h.z.abs());
            let boxes = [[centre - half, centre + half]];
            let cam = Camera::new(origin, target, Vec3::new(0.0, 0.0, 1.0), 50.0, 24, 16);
            for (x, y) in (0..24).flat_map(|x| (0..16).map(move |y| (x, y))) {
                let misses = cam.pixel_misses(x, y, &boxes);
                let centre_ray = cam.ray(x as f64 + 0.5, y as f64 + 0.5);
                assert!(!(misses && meets(&centre_ray, boxes[0])));
                if misses {
                    culled += 1;
                    for (fx, fy) in (0..=6).flat_map(|i| (0..=6).map(move |j| (i, j))) {
                        let ray = cam.ray(x as f64 + fx as f64 / 6.0, y as f64 + fy as f64 / 6.0);
                        assert!(!meets(&ray, boxes[0]), "pixel ({x}, {y}) of {cam:?}");
                    }
                } else {
                    kept += 1;
                    // Pixels whose every probe ray misses by far: most of them are culled.
                    if !meets(&centre_ray, [centre - half * 4.0, centre + half * 4.0]) {
                        far += 1;
                    }
                }
            }
        }
        assert!(
            culled > 10 * far,
            "culled {culled}, kept {kept} of which far {far}"
        );
        assert!(kept > 0);
    }

    /// In a narrow field of view (a pixel 10⁻⁷ rad across, where neighbouring corners agree to
    /// nine digits) a box that a ray of the pixel meets, a hundredth of a pixel inside its
    /// edge, keeps the pixel; a box a pixel outside it is culled.
    #[test]
    fn narrow_pixels_keep_the_boxes_their_rays_meet() {
        let mut rng = woven::math::rng::SplitMix(29);
        let (mut kept, mut culled) = (0, 0);
        for _ in 0..4000 {
            let mut v = |k: f64| Vec3::new(rng.range(-k, k), rng.range(-k, k), rng.range(-k, k));
            let (origin, target) = (v(50.0), v(1.0));
            let cam = Camera::new(origin, target, Vec3::new(0.0, 0.0, 1.0), 0.01, 2048, 1024);
            let (x, y) = (
                (rng.uniform() * 2048.0) as usize,
                (rng.uniform() * 1024.0) as usize,
            );
            // A film point near one of the pixel's four edges, just inside it.
            let inside = 0.01 * rng.uniform();
            let along = rng.uniform();
            let edge = (rng.uniform() * 4.0) as usize;
            let (fx, fy) = match edge {
                0 => (inside, along),
                1 => (1.0 - inside, along),
                2 => (along, inside),
                _ => (along, 1.0 - inside),
            };
            let distance = rng.range(1.0, 200.0);
            let at = |fx: f64, fy: f64| {
                let ray = cam.ray(x as f64 + fx, y as f64 + fy);
                ray.o + ray.d * distance
            };
            let tiny = Vec3::new(1e-12, 1e-12, 1e-12) * distance;
            let p = at(fx, fy);
            assert!(!cam.pixel_misses(x, y, &[[p - tiny, p + tiny]]));
            kept += 1;
            // A pixel beyond the same edge: outside by a pixel's width.
            let q = match edge {
                0 => at(-1.0, fy),
                1 => at(2.0, fy),
                2 => at(fx, -1.0),
                _ => at(fx, 2.0),
            };
            culled += usize::from(cam.pixel_misses(x, y, &[[q - tiny, q + tiny]]));
        }
        assert!(culled > kept * 9 / 10, "{culled} of {kept} culled");
    }

    /// The ray differentials' uv footprint on a tilted rectangle equals the uv step between the
    /// hits of neighbouring pixels' rays (finite differences, to second order).
    #[test]
    fn footprint_is_the_uv_step_between_pixels() {
        use crate::geometry::Primitive;
        let cam = Camera::new(
            Vec3::new(0.3, -2.0, 1.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            40.0,
            320,
            200,
        );
        let rect = Primitive::Rectangle {
            corner: Vec3::new(-3.0, -1.0, 0.0),
            edge_u: Vec3::new(6.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 3.0, 0.4),
        };
        let hit = |x: f64, y: f64| {
            let r = cam.ray(x, y);
            (r, rect.intersect(&r, 0.0, f64::INFINITY, &[], 0).unwrap())
        };
        let mut checked = 0;
        for (x, y) in [
            (160.0, 150.0),
            (20.5, 190.2),
            (300.0, 120.0),
            (100.0, 110.0),
        ] {
            let (ray, h) = hit(x, y);
            let fp = cam.footprint().uv(&ray, &h);
            // Central differences over ±1/8 pixel, scaled to one pixel.
            let e = 0.125;
            for (k, (dx, dy)) in [(e, 0.0), (0.0, e)].into_iter().enumerate() {
                let (_, a) = hit(x + dx, y + dy);
                let (_, b) = hit(x - dx, y - dy);
                for c in 0..2 {
                    let fd = (a.uv()[c] - b.uv()[c]) / (2.0 * e);
                    assert!(
                        (fp[k][c] - fd).abs() <= 1e-3 * fd.abs() + 1e-9,
                        "pixel ({x}, {y}), d{}/d{}: {} vs {fd}",
                        ["u", "v"][c],
                        ["x", "y"][k],
                        fp[k][c]
                    );
                }
            }
            checked += 1;
        }
        assert_eq!(checked, 4);
    }
}
