//! The weave's relief: both yarn families' tilted floats laid on the pattern as one height
//! field, so that a ray finds the yarn it meets first and a point knows whether a neighbouring
//! yarn shadows it (docs/model.md §8, "The relief").
//!
//! A yarn on top of a cell lies on its float's hill ([`FloatProfile`]): its crest at height 0,
//! its ends lower, the height in units of `uv` (the float's length in cells times a cell's
//! size along it, `uv` taken as isotropic). In a gap across the top yarn lies the crossing yarn,
//! at the relief's floor (the deepest end of any float); where both families leave a gap, a
//! hole, also at the floor. A float without ends (a row all weft) lies flat at 0.
//!
//! Coordinates: `(x, y)` in pattern cells (`u n_u`, `v n_v`), heights `z ≤ 0` in `uv` units,
//! directions in the cloth's frame (the weft along `x`).
//!
//! Rays are marched in steps of [`STEP`] cells and the crossing refined by bisection to
//! [`BISECTIONS`] halvings: the hill tops are smooth and the only sharp features are the walls
//! where one family's cell meets the other's, which a step cannot jump.

use crate::math::Vec3;
use crate::weave::{FloatPlace, Pattern};
use crate::yarn::float::{from_tilted, into_tilted, FloatProfile};

/// The march's step, in cells.
pub const STEP: f64 = 1.0 / 32.0;

/// Halvings of the step in which a ray crosses the relief.
pub const BISECTIONS: usize = 24;

/// The most steps one march takes (a ray within a hair of the horizon stops there, where it
/// is).
pub const MAX_STEPS: usize = 4096;

/// How a horizon's steps grow with the distance from its point, beyond [`STEP`] cells: each
/// this share of the distance already gone.
pub const HORIZON_GROWTH: f64 = 1.0 / 32.0;

/// What lies at a place of the relief.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ground {
    /// The yarn on top of its cell (`warp`: the warp, else the weft), at the fraction `t` along
    /// its float (`None`: a float without ends, flat).
    Top {
        /// The family.
        warp: bool,
        /// The fraction along the float, in `[0, 1]`.
        t: Option<f64>,
        /// The place across the yarn, in `[−1, 1]`: its edges at `±1` (`+1` toward `+y` for
        /// the weft, `+x` for the warp), its crown at 0.
        across: f64,
    },
    /// In the top yarn's gap: the crossing yarn below it, flat at the floor.
    Below {
        /// The family of the yarn below.
        warp: bool,
    },
    /// A gap of both families: nothing.
    Hole,
}

/// A point of the relief: where a ray met it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReliefPoint {
    /// The place in cells along `x`.
    pub x: f64,
    /// The place in cells along `y`.
    pub y: f64,
    /// The height, in `uv` units (`≤ 0`).
    pub z: f64,
    /// What lies there.
    pub ground: Ground,
}

impl ReliefPoint {
    /// `[x, y, z]`.
    pub fn place(&self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}

/// How a relief point's surface leans in its yarn's frame (the yarn along `x`): its float's
/// tilt (the axis turned toward `+z`, [`into_tilted`]), then its crown's roll about the axis (the
/// normal leaning toward `+y`), each as `(sin, cos)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lean {
    /// The float's tilt.
    pub tilt: (f64, f64),
    /// The crown's roll.
    pub roll: (f64, f64),
}

impl Lean {
    /// No lean: the yarn's own frame.
    pub const FLAT: Lean = Lean {
        tilt: (0.0, 1.0),
        roll: (0.0, 1.0),
    };

    /// A tilt alone.
    pub fn tilted(tilt: (f64, f64)) -> Lean {
        Lean {
            tilt,
            roll: (0.0, 1.0),
        }
    }

    /// `d` (in the yarn's frame) in the leaning surface's frame.
    #[inline]
    pub fn into_frame(&self, d: Vec3) -> Vec3 {
        let t = into_tilted(d, self.tilt);
        let (s, c) = self.roll;
        Vec3::new(t.x, c * t.y - s * t.z, s * t.y + c * t.z)
    }

    /// Back from the leaning surface's frame ([`into_frame`](Self::into_frame)'s inverse).
    #[inline]
    pub fn from_frame(&self, d: Vec3) -> Vec3 {
        let (s, c) = self.roll;
        from_tilted(
            Vec3::new(d.x, c * d.y + s * d.z, c * d.z - s * d.y),
            self.tilt,
        )
    }
}

/// The relief of a woven pattern (module docs).
#[derive(Clone, Debug)]
pub struct Relief {
    pattern: Pattern,
    floats: Vec<FloatPlace>,
    /// A cell's size in `uv` along `x` and `y`.
    cell: [f64; 2],
    gap: f64,
    floor: f64,
    /// The yarns' depth at their edges below their crown, in `uv`, per family (weft, warp).
    round: [f64; 2],
    /// Per family (weft, warp), its floats' profile: `float`, or the same shape tilted less where
    /// `float` would make its longest float dip deeper than the yarn it passes under is thick.
    floats_of: [FloatProfile; 2],
}

/// The half-angle of a yarn's crown, degrees: across its width the yarn's top is an arc whose
/// normal leans up to this far either way (its roll).
pub const CROWN_DEG: f64 = 30.0;

/// The crown's depth at the yarn's edges over its width, `(1 − cos α) / (2 sin α)` for the
/// half-angle `α` ([`CROWN_DEG`]).
pub const ROUND: f64 = 0.133_974_596_215_561_35;

/// A yarn's thickness over its width: a float dips at most this deep under the yarn it crosses.
pub const THICKNESS: f64 = 0.5;

impl Relief {
    /// The relief of `pattern` laid at `yarns_per_unit` cells per unit of `u` and `v`, its floats
    /// shaped by `float`, each yarn covering `1 − gap` of its cells' width. The inputs are those
    /// of a checked [`SurfaceSpec`](crate::surface::SurfaceSpec).
    pub fn new(
        pattern: &Pattern,
        yarns_per_unit: [f64; 2],
        float: FloatProfile,
        gap: f64,
    ) -> Relief {
        let floats = pattern.floats();
        let cell = [1.0 / yarns_per_unit[0], 1.0 / yarns_per_unit[1]];
        let mut relief = Relief {
            pattern: pattern.clone(),
            floats,
            cell,
            gap,
            floor: 0.0,
            round: [ROUND * (1.0 - gap) * cell[1], ROUND * (1.0 - gap) * cell[0]],
            floats_of: [float; 2],
        };
        // A float passes under a crossing yarn THICKNESS of its width thick; its hill may dip
        // no deeper: the longest float's tilt is lowered until it fits (by bisection).
        let cols = pattern.cols();
        for warp in [false, true] {
            let deepest = |relief: &Relief| {
                (0..pattern.rows() * cols)
                    .filter(|&i| pattern.is_weft(i / cols, i % cols) != warp)
                    .map(|i| -relief.hill(warp, relief.floats[i], 0.0))
                    .fold(0.0, f64::max)
            };
            let crossing = THICKNESS * (1.0 - gap) * cell[usize::from(warp)];
            if deepest(&relief) > crossing {
                let (mut lo, mut hi) = (0.0, float.u_max());
                for _ in 0..50 {
                    let mid = 0.5 * (lo + hi);
                    relief.floats_of[usize::from(warp)] = float.with_u_max(mid);
                    if deepest(&relief) > crossing {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                relief.floats_of[usize::from(warp)] = float.with_u_max(lo.max(f64::MIN_POSITIVE));
            }
        }
        relief.floor = (0..pattern.rows() * cols)
            .map(|i| {
                let warp = !pattern.is_weft(i / cols, i % cols);
                relief.hill(warp, relief.floats[i], 0.0)
            })
            .fold(0.0, f64::min)
            - relief.round[0].max(relief.round[1]);
        relief
    }

    /// The floor: the height of the gaps and holes, the lowest of the relief, `uv` units.
    pub fn floor(&self) -> f64 {
        self.floor
    }

    /// The height of family `warp`'s float `place` at the fraction `t` along it.
    #[inline]
    fn hill(&self, warp: bool, place: FloatPlace, t: f64) -> f64 {
        if place.len == 0 {
            return 0.0;
        }
        let i = usize::from(warp);
        self.floats_of[i].height(t) * f64::from(place.len) * self.cell[1 - i]
    }

    /// The tilt of family `warp`'s surface at the fraction `t` along its float, radians: the
    /// slope of its hill ([`float`](Self::float)), so the yarn shades as the relief stands.
    #[inline]
    pub fn tilt(&self, warp: bool, t: f64) -> f64 {
        self.floats_of[usize::from(warp)].tilt(t)
    }

    /// Family `warp`'s float profile: the surface's, or the same shape tilted less where the
    /// surface's would dip a long float deeper than [`THICKNESS`].
    pub fn float(&self, warp: bool) -> FloatProfile {
        self.floats_of[usize::from(warp)]
    }

    /// The roll of a yarn's surface about its axis at `across ∈ [−1, 1]` ([`Ground::Top`]):
    /// the angle by which its normal leans toward `+across`, radians (`±`[`CROWN_DEG`] at the
    /// edges): on the arc, `sin θ = a sin α`.
    #[inline]
    pub fn roll(across: f64) -> f64 {
        (across.clamp(-1.0, 1.0) * CROWN_DEG.to_radians().sin()).asin()
    }

    /// The crown's height at `across ∈ [−1, 1]` below its top, in units of its depth at the
    /// edges: `(1 − cos θ) / (1 − cos α)`, `θ` the roll there.
    #[inline]
    fn crown(across: f64) -> f64 {
        let alpha = CROWN_DEG.to_radians();
        (Relief::roll(across).cos() - 1.0) / (1.0 - alpha.cos())
    }

    /// The height and ground at `(x, y)` (cells).
    #[inline]
    pub fn at(&self, x: f64, y: f64) -> (f64, Ground) {
        let cell = self.pattern.cell_at(x, y);
        let top = !cell.weft;
        let half = 0.5 * (1.0 - self.gap);
        let covers = |warp: bool| ((if warp { cell.x } else { cell.y }) - 0.5).abs() < half;
        if self.gap == 0.0 || covers(top) {
            let place = self.floats[cell.row * self.pattern.cols() + cell.col];
            let (along, across) = if top {
                (cell.y, cell.x)
            } else {
                (cell.x, cell.y)
            };
            let a = (2.0 * (across - 0.5) / (1.0 - self.gap)).clamp(-1.0, 1.0);
            let crown = self.round[usize::from(top)] * Relief::crown(a);
            if place.len == 0 {
                let ground = Ground::Top {
                    warp: top,
                    t: None,
                    across: a,
                };
                return (crown, ground);
            }
            let t = ((f64::from(place.before) + along) / f64::from(place.len)).clamp(0.0, 1.0);
            (
                self.hill(top, place, t) + crown,
                Ground::Top {
                    warp: top,
                    t: Some(t),
                    across: a,
                },
            )
        } else if covers(!top) {
            (self.floor, Ground::Below { warp: !top })
        } else {
            (self.floor, Ground::Hole)
        }
    }

    /// The point that a ray toward the viewer `v` meets, having crossed the crests' plane
    /// (`z = 0`) at `(x, y)`: the first place below it along `−v`. `v` at or below the horizon
    /// meets the relief where it enters.
    pub fn hit(&self, x: f64, y: f64, v: Vec3) -> ReliefPoint {
        let point = |s: f64| {
            let (px, py) = (x - s * v.x / self.cell[0], y - s * v.y / self.cell[1]);
            (px, py, -s * v.z)
        };
        let below = |s: f64| {
            let (px, py, z) = point(s);
            z <= self.at(px, py).0
        };
        let s = if v.z > 0.0 && self.floor < 0.0 {
            let end = -self.floor / v.z;
            march(below, end, self.step(v)).unwrap_or(end)
        } else {
            0.0
        };
        let (px, py, z) = point(s);
        let (h, ground) = self.at(px, py);
        ReliefPoint {
            x: px,
            y: py,
            z: z.max(h),
            ground,
        }
    }

    /// Whether the ray from `p` toward `d` leaves the relief without meeting it (a light there
    /// lights `p`; a viewer there sees it). `false` at or below the horizon.
    pub fn sees(&self, [x, y, z]: [f64; 3], d: Vec3) -> bool {
        let p = ReliefPoint {
            x,
            y,
            z,
            ground: Ground::Hole,
        };
        if d.z <= 0.0 || d.z.is_nan() {
            return false;
        }
        if p.z >= 0.0 {
            return true;
        }
        let end = -p.z / d.z;
        let step = self.step(d);
        // Leave the start's own surface before testing: a hair along the ray.
        let below = |s: f64| {
            let (qx, qy) = (p.x + s * d.x / self.cell[0], p.y + s * d.y / self.cell[1]);
            p.z + s * d.z < self.at(qx, qy).0 - 1e-12
        };
        march(below, end, step).is_none()
    }

    /// The relief's horizon from `at` toward the azimuth `phi` (radians, from `+x`): the
    /// largest `(h − z) / r` over the places at horizontal distance `r` (in `uv`) along it, `h`
    /// their height and `z` that of `at`. A direction of that azimuth is blocked unless its
    /// slope `d_z / |d_xy|` exceeds it ([`sees`](Self::sees) in one march for every elevation).
    /// `−∞` from the crests' height, where nothing stands higher.
    pub fn horizon(&self, [x, y, z]: [f64; 3], phi: f64) -> f64 {
        let mut best = f64::NEG_INFINITY;
        if z >= 0.0 {
            return best;
        }
        let (s, c) = phi.sin_cos();
        let step = self.step(Vec3::new(c, s, 0.0));
        let mut r = 0.0;
        for _ in 0..MAX_STEPS {
            // Steps of STEP cells near the point, beyond a cell a fixed share of the distance
            // ([`HORIZON_GROWTH`]): a distant rise subtends less, and is sampled as coarsely.
            r += step.max(r * HORIZON_GROWTH);
            // Nothing farther can stand higher than the crests.
            if -z / r <= best {
                break;
            }
            let h = self
                .at(x + r * c / self.cell[0], y + r * s / self.cell[1])
                .0;
            best = best.max((h - z) / r);
        }
        best
    }

    /// The march's step along a ray toward `d`, in its length: [`STEP`] cells across, or the
    /// ray's whole depth when it runs straight down.
    #[inline]
    fn step(&self, d: Vec3) -> f64 {
        let across = (d.x / self.cell[0]).hypot(d.y / self.cell[1]);
        STEP / across.max(1e-300)
    }
}

/// The first `s ∈ (0, end]` with `below(s)`, by steps of `step` (at most [`MAX_STEPS`]) and
/// bisection of the step that crosses; `None` when none does.
fn march(below: impl Fn(f64) -> bool, end: f64, step: f64) -> Option<f64> {
    if below(0.0) {
        return Some(0.0);
    }
    let n = ((end / step).ceil() as usize).clamp(1, MAX_STEPS);
    let h = end / n as f64;
    let mut lo = 0.0;
    for i in 1..=n {
        let s = if i == n { end } else { i as f64 * h };
        if below(s) {
            let mut hi = s;
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (lo + hi);
                if below(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        lo = s;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The relief of `pattern` at one cell per unit, linear floats tilted `u_max_deg`.
    fn relief(pattern: &str, u_max_deg: f64, gap: f64) -> Relief {
        let p = Pattern::from_name(pattern).unwrap();
        Relief::new(
            &p,
            [1.0, 1.0],
            FloatProfile::new(u_max_deg.to_radians()),
            gap,
        )
    }

    /// The first place below the relief along `−v` from `(x, y, 0)`, by steps of 1e-5 cells.
    fn brute_hit(r: &Relief, x: f64, y: f64, v: Vec3) -> f64 {
        let step = 1e-5 / v.x.hypot(v.y);
        let mut s = 0.0;
        while -s * v.z > r.at(x - s * v.x, y - s * v.y).0 {
            s += step;
        }
        s
    }

    fn dir(theta_deg: f64, phi_deg: f64) -> Vec3 {
        Vec3::from_spherical(theta_deg.to_radians(), phi_deg.to_radians())
    }

    #[test]
    fn floats_are_hills_with_their_crests_at_zero() {
        let r = relief("satin-5", 30.0, 0.0);
        // A warp float of 4 cells in a 5-satin: its crest at its middle, its ends lowest (the
        // tilt would dip it 4 × 0.29 cells: capped at the crossing yarn's thickness), less the
        // round yarn's depth at its edges.
        let natural = FloatProfile::new(30f64.to_radians()).height(0.0) * 4.0;
        assert!(natural < -THICKNESS);
        let depth = -THICKNESS - ROUND;
        assert!(
            (r.floor() - depth).abs() < 1e-12,
            "{} vs {depth}",
            r.floor()
        );
        let mut top = f64::NEG_INFINITY;
        for i in 0..500 {
            for j in 0..500 {
                let (h, g) = r.at(i as f64 / 100.0, j as f64 / 100.0);
                assert!(h <= 0.0 && h >= r.floor() - 1e-12);
                assert!(matches!(g, Ground::Top { t: Some(_), .. }));
                top = top.max(h);
            }
        }
        assert!(top > -1e-3, "{top}");
    }

    #[test]
    fn yarns_are_round_across_and_a_crown_is_met_where_it_is_entered() {
        // Rows all weft: floats without ends, so only the yarns' round crowns stand out.
        let p = Pattern::from_matrix(vec![vec![1, 1]]).unwrap();
        let r = Relief::new(&p, [3.0, 5.0], FloatProfile::new(0.5), 0.2);
        // The floor: the deeper of the two families' edges (the warp's, across wider cells).
        let depth = ROUND * 0.8 / 3.0;
        assert!((r.floor() + depth).abs() < 1e-15, "{}", r.floor());
        assert_eq!(r.at(0.3, 0.5).0, 0.0);
        let (h, g) = r.at(0.3, 0.5 + 0.4 * 0.6);
        let weft_depth = ROUND * 0.8 / 5.0;
        let want = weft_depth * (1.0 - (1.0 - 0.36 * 0.25f64).sqrt()) / (1.0 - 0.75f64.sqrt());
        assert!((h + want).abs() < 1e-15, "{h} vs {want}");
        assert_eq!(
            g,
            Ground::Top {
                warp: false,
                t: None,
                across: 0.6
            }
        );
        assert_eq!(r.at(0.3, 0.95).1, Ground::Below { warp: true });
        assert_eq!(r.at(0.05, 0.95).1, Ground::Hole);
        let hit = r.hit(0.3, 0.5, dir(70.0, 20.0));
        assert_eq!((hit.x, hit.y, hit.z), (0.3, 0.5, 0.0));
        assert!(r.sees(hit.place(), dir(85.0, 200.0)));
        assert!(!r.sees(hit.place(), dir(90.5, 0.0)));
        // Low on the yarn's flank: in the next yarn's shadow (or its own crown's) under grazing light,
        // lit from higher up.
        let flank = r.hit(0.3, 0.5 + 0.39, dir(0.0, 0.0));
        assert!(
            !r.sees(flank.place(), dir(80.0, 90.0)) && !r.sees(flank.place(), dir(80.0, 270.0))
        );
        assert!(r.sees(flank.place(), dir(30.0, 90.0)));
    }

    #[test]
    fn rays_meet_the_first_place_below_the_relief() {
        let r = relief("twill-2/1", 35.0, 0.0);
        let (mut agree, mut grazes) = (0, 0);
        for k in 0..400 {
            let (x, y) = (0.37 + 0.173 * k as f64, 0.11 + 0.291 * k as f64);
            let v = dir(20.0 + 0.17 * k as f64, 37.0 * k as f64);
            let h = r.hit(x, y, v);
            assert!((h.z - r.at(h.x, h.y).0).abs() < 1e-9);
            let s = brute_hit(&r, x, y, v);
            let along = (h.x - x).hypot(h.y - y) / v.x.hypot(v.y);
            // Never short of the first place below; past it only where the ray skims a
            // corner thinner than a step: the relief stands less than a hundredth of a cell
            // above the ray over what the march stepped past.
            assert!(along > s - 1e-4, "{k}: met at {along}, first below at {s}");
            if along < s + 1e-4 {
                agree += 1;
                continue;
            }
            grazes += 1;
            let n = ((along - s) / 1e-5) as usize + 1;
            let skimmed = (0..=n)
                .map(|i| {
                    let t = s + (along - s) * i as f64 / n as f64;
                    r.at(x - t * v.x, y - t * v.y).0 + t * v.z
                })
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(skimmed < 0.01, "{k}: stepped past {skimmed} of relief");
        }
        assert!(
            grazes * 50 < agree,
            "{grazes} rays skim a corner, {agree} agree"
        );
    }

    #[test]
    fn a_point_is_lit_unless_the_relief_stands_in_the_way() {
        let r = relief("plain", 30.0, 0.1);
        let (mut lit, mut shadowed) = (0, 0);
        for k in 0..400 {
            let (x, y) = (0.37 + 0.173 * k as f64, 0.11 + 0.291 * k as f64);
            let p = r.hit(x, y, dir(30.0, 11.0 * k as f64));
            let d = dir(40.0 + 0.12 * k as f64, 29.0 * k as f64);
            // Brute force: the ray's height against the relief's, every 1e-4 cells.
            let n = ((-p.z / d.z) * d.x.hypot(d.y) / 1e-4).ceil() as usize;
            // How far the relief rises above the ray at most (a graze: a hair).
            let intrusion = (1..=n)
                .map(|i| {
                    let s = (-p.z / d.z) * i as f64 / n as f64;
                    r.at(p.x + s * d.x, p.y + s * d.y).0 - (p.z + s * d.z)
                })
                .fold(0.0, f64::max);
            if r.sees(p.place(), d) {
                lit += 1;
                // A blocker thinner than a step can be stepped over only where the ray grazes
                // it.
                assert!(
                    intrusion < 1e-3,
                    "{k}: the march misses a blocker {intrusion} deep"
                );
            } else {
                shadowed += 1;
            }
        }
        assert!(lit > 50 && shadowed > 50, "{lit} lit, {shadowed} shadowed");
    }

    /// A horizon tells what [`Relief::sees`] would for every elevation of its azimuth: above
    /// it the way is clear, below it blocked (except within 5 % of its slope).
    #[test]
    fn a_horizon_is_where_the_way_out_is_blocked() {
        let r = relief("twill-2/1", 30.0, 0.1);
        let (mut clear, mut blocked) = (0, 0);
        for k in 0..300 {
            let (x, y) = (0.37 + 0.173 * k as f64, 0.11 + 0.291 * k as f64);
            let p = r.hit(x, y, dir(35.0, 13.0 * k as f64));
            let phi = (31.0 * k as f64).to_radians();
            let h = r.horizon(p.place(), phi);
            for e in [2.0, 5.0, 10.0, 20.0, 35.0, 60.0] {
                let slope = f64::to_radians(e).tan();
                // A wall's top is found to within a step, so the horizon's slope to within a
                // step over the distance (a few per cent at a few cells).
                if (slope - h).abs() <= 0.05 * slope {
                    continue;
                }
                let d = Vec3::new(
                    phi.cos() * e.to_radians().cos(),
                    phi.sin() * e.to_radians().cos(),
                    e.to_radians().sin(),
                );
                assert_eq!(
                    r.sees(p.place(), d),
                    slope > h,
                    "{k}: elevation {e}°, horizon slope {h}"
                );
                if slope > h {
                    clear += 1
                } else {
                    blocked += 1
                }
            }
        }
        assert!(
            clear > 100 && blocked > 100,
            "{clear} clear, {blocked} blocked"
        );
    }

    /// The share of the weft among `n × n` entries of one repeat seen from `v`.
    fn weft_share(r: &Relief, v: Vec3, n: usize) -> f64 {
        let mut weft = 0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (
                    2.0 * (i as f64 + 0.5) / n as f64,
                    2.0 * (j as f64 + 0.5) / n as f64,
                );
                if matches!(r.hit(x, y, v).ground, Ground::Top { warp: false, .. }) {
                    weft += 1;
                }
            }
        }
        weft as f64 / (n * n) as f64
    }

    #[test]
    fn a_plain_weave_shows_more_of_the_yarn_it_is_seen_along() {
        let r = relief("plain", 25.0, 0.0);
        let normal = weft_share(&r, dir(0.0, 0.0), 64);
        let along_weft = weft_share(&r, dir(60.0, 0.0), 64);
        let along_warp = weft_share(&r, dir(60.0, 90.0), 64);
        assert!((normal - 0.5).abs() < 1e-9, "{normal}");
        assert!(along_weft > 0.505, "{along_weft}");
        assert!(
            (along_weft + along_warp - 1.0).abs() < 0.02,
            "{along_weft} {along_warp}"
        );
    }
}
