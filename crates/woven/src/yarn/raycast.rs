//! Brute-force 2D ray casting of the periodic profile: the reference implementation that the
//! closed-form intervals of [`Profile::lit`] are tested against (docs/spec.md §2.2 and §6, item 5).
//!
//! Nothing here uses the closed form or the argument behind it (which neighbour casts the
//! shadow, which point is the silhouette): [`is_lit`] intersects the ray with the arcs and
//! laterals of every period it passes over, until it has risen above the apexes. It is slow
//! (tens of nanoseconds per period crossed) and meant for tests, figures and checks.

use std::f64::consts::FRAC_PI_2;

use super::profile::{Piece, PieceIntervals, Profile};

/// Whether the profile point `point = (u, w)` with unit outward normal `normal = (a_u, a_w)` is lit
/// from projected angle `psi` (radians), by ray casting.
///
/// Lit means: `normal · (sin ψ, cos ψ) > 0`, and the ray `point + s (sin ψ, cos ψ)`, `s > 0`, meets
/// no arc and no lateral of any period of the profile (docs/spec.md §2.2). `point` must lie on the
/// profile (any period, to within ~1e-13 relative, i.e. as computed by [`Profile::point`]): the
/// curve it lies on is excluded from the intersection tests at `s = 0`, so rounding in `point`
/// cannot make it shadow itself. Returns `false` for `|ψ| ≥ π/2` or NaN.
///
/// # Panics
/// If the ray would have to cross more than 2²⁴ periods before rising above the apexes; valid
/// inputs stay far below this (a ray that is not blocked by the first neighbour rises above
/// the apexes within a few periods).
///
/// # Examples
/// ```
/// use woven::yarn::{profile::Profile, raycast::is_lit};
/// let p = Profile::new(std::f64::consts::FRAC_PI_2, 0.0)?; // touching cylinders
/// // The apex sees every direction above the surface...
/// assert!(is_lit(&p, (0.0, 0.0), (0.0, 1.0), 1.5));
/// // ...but at 60° from the right, the lower right of the cylinder is in its neighbour's shadow.
/// let theta: f64 = 1.2;
/// assert!(!is_lit(&p, (theta.sin(), theta.cos() - 1.0), (theta.sin(), theta.cos()), 1.047));
/// # Ok::<(), woven::Error>(())
/// ```
pub fn is_lit(profile: &Profile, point: (f64, f64), normal: (f64, f64), psi: f64) -> bool {
    // No direction above the surface.
    if psi.is_nan() || psi.abs() >= FRAC_PI_2 {
        return false;
    }
    let d = psi.sin_cos();
    if normal.0 * d.0 + normal.1 * d.1 <= 0.0 {
        return false;
    }
    let period = profile.period();
    if period <= 0.0 {
        // θ_a = 0 and L = 0: the profile is flat; nothing rises above the plane to block a ray.
        return true;
    }
    let (sin_a, cos_a) = profile.theta_a.sin_cos();
    let l = profile.lateral_length;
    // "On this curve" tolerances, ~500 times the rounding a computed profile point carries
    // (~2e-16 of its size): its distance to a lateral's line, and `|p − c|² − 1` for an arc's circle.
    let on_line = 1e-13 * (1.0 + point.0.abs() + point.1.abs());
    let on_circle = 1e-14 * (1.0 + point.0.abs());

    let step: i64 = if d.0 > 0.0 {
        1
    } else if d.0 < 0.0 {
        -1
    } else {
        0
    };
    let home = (point.0 / period).round() as i64;
    // One period behind the one holding the point, in case the point sits on a period boundary.
    let first = home - if step == 0 { 1 } else { step };
    let mut k = first;
    loop {
        let centre = k as f64 * period;
        let arc_hit = hits_arc(point, d, (centre, -1.0), cos_a, on_circle);
        let right_hit = hits_segment(
            point,
            d,
            (centre + sin_a, cos_a - 1.0),
            (cos_a, -sin_a),
            l,
            on_line,
        );
        let left_hit = hits_segment(
            point,
            d,
            (centre - sin_a, cos_a - 1.0),
            (-cos_a, -sin_a),
            l,
            on_line,
        );
        if arc_hit || right_hit || left_hit {
            return false;
        }
        if step == 0 {
            // A vertical ray stays over the point's own period (and the boundary neighbours).
            if k > home {
                return true;
            }
            k += 1;
            continue;
        }
        // Height of the ray over the far edge of period k; once above the apex height 0, no
        // further period can block it.
        let far_edge = centre + 0.5 * step as f64 * period;
        let ray_height = point.1 + (far_edge - point.0) * d.1 / d.0;
        if ray_height > 0.0 {
            return true;
        }
        assert!(
            (k - first).abs() < 1 << 24,
            "ray casting from {point:?} at ψ = {psi} crosses more than 2^24 periods of {profile:?}"
        );
        k += step;
    }
}

/// Whether the ray `p + s d`, `s > 0`, meets the arc of the circle of unit radius about `c`
/// with `w − c_w ≥ cos θ_a`.
fn hits_arc(p: (f64, f64), d: (f64, f64), c: (f64, f64), cos_a: f64, on_curve: f64) -> bool {
    let f = (p.0 - c.0, p.1 - c.1);
    let b = f.0 * d.0 + f.1 * d.1;
    let cc = f.0 * f.0 + f.1 * f.1 - 1.0;
    // Roots of s² + 2 b s + cc = 0; none when the ray passes the circle by.
    let disc = b * b - cc;
    if disc < 0.0 {
        return false;
    }
    let on_arc = |s: f64| s > 0.0 && p.1 + s * d.1 - c.1 >= cos_a;
    // The stable pair: q = −(b + sign(b)√disc), then the roots are q and cc/q, |cc/q| ≤ |q|.
    let q = -(b + b.signum() * disc.sqrt());
    if q == 0.0 {
        // b = 0 and cc = 0: the ray is tangent at the point itself.
        return false;
    }
    if cc.abs() <= on_curve {
        // The point is on this circle: the smaller root, cc/q ≈ 0, is the point itself.
        return on_arc(q);
    }
    on_arc(q) || on_arc(cc / q)
}

/// Whether the ray `p + s d`, `s > 0`, meets the segment `a + t e`, `t ∈ [0, len]` (`e` a unit vector).
fn hits_segment(
    p: (f64, f64),
    d: (f64, f64),
    a: (f64, f64),
    e: (f64, f64),
    len: f64,
    on_curve: f64,
) -> bool {
    let cross = |x: (f64, f64), y: (f64, f64)| x.0 * y.1 - x.1 * y.0;
    let ap = (a.0 - p.0, a.1 - p.1);
    if cross(ap, e).abs() <= on_curve {
        // The point is on this line: a ray leaving the line meets it only at s = 0.
        return false;
    }
    let denom = cross(d, e);
    if denom == 0.0 {
        // Parallel to the segment and off its line: no meeting.
        return false;
    }
    let s = cross(ap, e) / denom;
    let t = cross(ap, d) / denom;
    // The 1e-12 slack covers rounding at the segment's ends; each end is shared with the arc or
    // the neighbour's lateral, which are tested too.
    let slack = 1e-12 * (1.0 + len);
    s > 0.0 && t >= -slack && t <= len + slack
}

/// The outcome of sampling every piece of a profile with a predicate (e.g. "lit").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledPieces {
    /// Per piece, the hull of the samples for which the predicate held, widened by half a sample
    /// spacing on each side and clipped to the piece; `None` if it held nowhere. Its ends are within
    /// half a spacing (`length / (2n)`) of the true set's ends when that set is one interval.
    pub intervals: PieceIntervals,
    /// Per piece, in the order of [`Piece::ALL`], the number of maximal runs of consecutive samples
    /// for which the predicate held: 1 (or 0) when the sampled set is one interval.
    pub runs: [usize; 3],
    /// The number of samples per piece.
    pub samples: usize,
}

/// Samples `n` points per piece (cell midpoints, so no sample sits on a piece's end) and records
/// where `predicate(point, normal)` holds.
///
/// `point` and `normal` are as in [`Profile::point`] and [`Profile::normal`].
///
/// # Panics
/// If `n == 0`.
pub fn sample_pieces(
    profile: &Profile,
    n: usize,
    mut predicate: impl FnMut((f64, f64), (f64, f64)) -> bool,
) -> SampledPieces {
    assert!(n > 0, "need at least one sample per piece");
    let mut out = SampledPieces {
        intervals: PieceIntervals::default(),
        runs: [0; 3],
        samples: n,
    };
    for piece in Piece::ALL {
        let (a, b) = profile.parameter_range(piece);
        let h = (b - a) / n as f64;
        let mut first: Option<f64> = None;
        let mut last = a;
        let mut runs = 0;
        let mut previous = false;
        for i in 0..n {
            let x = a + (i as f64 + 0.5) * h;
            let lit = predicate(profile.point(piece, x), profile.normal(piece, x));
            if lit {
                first.get_or_insert(x);
                last = x;
                if !previous {
                    runs += 1;
                }
            }
            previous = lit;
        }
        let interval = first.map(|x0| ((x0 - 0.5 * h).max(a), (last + 0.5 * h).min(b)));
        match piece {
            Piece::Arc => out.intervals.arc = interval,
            Piece::Right => out.intervals.right = interval,
            Piece::Left => out.intervals.left = interval,
        }
        out.runs[piece.index()] = runs;
    }
    out
}

/// The lit part of each piece from projected angle `psi` (radians), by ray casting `n` samples per
/// piece: the brute-force counterpart of [`Profile::lit`].
///
/// # Examples
/// ```
/// use woven::yarn::{profile::{Piece, Profile}, raycast::sample_lit};
/// let p = Profile::new(0.8, 3.0)?;
/// let brute = sample_lit(&p, 1.2, 10_000);
/// let exact = p.lit(1.2);
/// let (_, t_brute) = brute.intervals.right.unwrap();
/// let (_, t_exact) = exact.right.unwrap();
/// assert!((t_brute - t_exact).abs() <= 3.0 / 10_000.0);
/// assert_eq!(brute.runs[Piece::Right.index()], 1);
/// # Ok::<(), woven::Error>(())
/// ```
pub fn sample_lit(profile: &Profile, psi: f64, n: usize) -> SampledPieces {
    sample_pieces(profile, n, |p, a| is_lit(profile, p, a, psi))
}

/// The part of each piece both lit from `psi_s` and visible from `psi_v` (radians), by ray casting
/// `n` samples per piece: the brute-force counterpart of [`Profile::lit_and_visible`].
pub fn sample_lit_and_visible(
    profile: &Profile,
    psi_s: f64,
    psi_v: f64,
    n: usize,
) -> SampledPieces {
    sample_pieces(profile, n, |p, a| {
        is_lit(profile, p, a, psi_s) && is_lit(profile, p, a, psi_v)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apex_sees_everything_above() {
        for (ta, l) in [
            (0.0, 0.0),
            (0.0, 3.0),
            (0.5, 2.0),
            (FRAC_PI_2, 0.0),
            (1.5, 50.0),
        ] {
            let p = Profile::new(ta, l).unwrap();
            for psi in [-(FRAC_PI_2 - 1e-6), -1.0, 0.0, 0.3, FRAC_PI_2 - 1e-9] {
                assert!(
                    is_lit(&p, (0.0, 0.0), (0.0, 1.0), psi),
                    "θa {ta} L {l} ψ {psi}"
                );
                // The same apex one and five periods away.
                for k in [1.0, -5.0] {
                    let u = k * p.period();
                    assert!(
                        is_lit(&p, (u, 0.0), (0.0, 1.0), psi),
                        "θa {ta} L {l} ψ {psi} u {u}"
                    );
                }
            }
            assert!(!is_lit(&p, (0.0, 0.0), (0.0, 1.0), FRAC_PI_2));
            assert!(!is_lit(&p, (0.0, 0.0), (0.0, 1.0), f64::NAN));
        }
    }

    #[test]
    fn deep_in_a_groove_the_neighbour_shadows() {
        // A V-groove-like profile: slope 45°, long laterals. Near the valley, light at 60° from
        // the right is blocked by the neighbour's left lateral; from straight above it is not.
        let p = Profile::new(std::f64::consts::FRAC_PI_4, 10.0).unwrap();
        let x = 9.5;
        let (pt, n) = (p.point(Piece::Right, x), p.normal(Piece::Right, x));
        assert!(!is_lit(&p, pt, n, 1.047));
        assert!(is_lit(&p, pt, n, 0.0));
        assert!(is_lit(&p, pt, n, 0.7));
        // Facing away from the left lateral's normal: not lit whatever the geometry.
        assert!(!is_lit(&p, pt, n, -1.0));
    }

    #[test]
    fn sampling_counts_runs() {
        let p = Profile::new(0.6, 1.0).unwrap();
        // A predicate true on two separate stretches of the right lateral.
        let s = sample_pieces(&p, 100, |pt, _| {
            let t = (pt.0 - 0.6f64.sin()) / 0.6f64.cos();
            !(0.2..=0.8).contains(&t)
        });
        assert_eq!(s.runs[Piece::Right.index()], 2);
        assert_eq!(s.intervals.right, Some((0.0, 1.0)));
    }
}
