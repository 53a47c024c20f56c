//! The light that passes between the yarns: the cloth's open area along a direction, from the
//! yarns' cross-section and spacing (docs/model.md, "The open area").
//!
//! Each family's yarns are straight prisms along their axis, one per pitch, each covering
//! `1 − gap` of its pitch (the surface's [`gap`](crate::surface::SurfaceSpec::gap)). A yarn's
//! cross-section is the relief's yarn made two-sided: its crown on top (an arc of half-angle
//! [`CROWN_DEG`] across its width), the same crown below, and [`THICKNESS`] of its width from
//! top to bottom, so the crowns meet the vertical edges at ±(`THICKNESS`/2 − [`ROUND`]) widths.
//!
//! A family's yarns run one way, so whether a ray passes between them depends on the ray's
//! slope across them alone: `t = d_across / d_z`. Their shadows on the cloth's plane are each
//! [`YarnSection::shadow`] wide, one per pitch, so the share of the plane no weft yarn shades is
//! `max(0, 1 − shadow(d_y / d_z))`, the warp's likewise with `d_x / d_z`. The weft's condition
//! is on a ray's `y` alone and the warp's on its `x` alone, and rays spread evenly over a tile
//! spread evenly in both, so the open area is the product of the two:
//!
//! ```text
//! O(d) = max(0, 1 − S(d_y / d_z)) · max(0, 1 − S(d_x / d_z)),   O(z) = gap².
//! ```
//!
//! The shadow is `S(t) = 2 h(1, |t|)`, `h` the section's support function. Up to `|t| = cot α`
//! (60° from the normal) its corners bound it, `S = w + 2 |t| z_e` (`w = 1 − gap`, `z_e` the
//! corners' height); beyond, its crowns, `S = 2 (|t| (T/2 − R) + R √(1 + t²))` (`T` the
//! thickness, `R = w / (2 sin α)` the crowns' radius). The open area is what the yarns leave of
//! a ray's way; the interlacing's crimp (yarns rising over and dipping under each other) is left
//! out, and so is light scattered through the yarns.

use crate::error::{check_range, Result};
use crate::math::Vec3;
use crate::relief::{CROWN_DEG, ROUND, THICKNESS};
/// The largest gap ([`SurfaceSpec::gap`](crate::surface::SurfaceSpec::gap)): yarns keep at
/// least 5 % of their pitch.
pub const MAX_GAP: f64 = 0.95;

/// A yarn's cross-section in units of its pitch (module docs): `|y| ≤ w/2` across its axis,
/// `|z| ≤` its crown's height at `y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct YarnSection {
    /// Its width `w = 1 − gap`, pitches.
    width: f64,
    /// Its thickness `T`, pitches: [`THICKNESS`] of its width.
    thickness: f64,
    /// Its crowns' radius `R = w / (2 sin α)`, pitches.
    radius: f64,
}

impl YarnSection {
    /// The section of yarns leaving `gap` of their pitch open.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `gap` unless it is in
    /// `[0, MAX_GAP]`.
    pub fn new(gap: f64) -> Result<YarnSection> {
        let gap = check_range("gap", gap, 0.0, MAX_GAP)?;
        let width = 1.0 - gap;
        Ok(YarnSection {
            width,
            thickness: THICKNESS * width,
            radius: width / (2.0 * CROWN_DEG.to_radians().sin()),
        })
    }

    /// Its width, pitches.
    pub fn width(&self) -> f64 {
        self.width
    }

    /// Its thickness, pitches.
    pub fn thickness(&self) -> f64 {
        self.thickness
    }

    /// The height of its top at `y` across it (`|y| ≤ w/2`), pitches from its middle plane:
    /// `T/2` at its axis, `T/2 − ROUND w` at its edges.
    pub fn top(&self, y: f64) -> f64 {
        let r = self.radius;
        0.5 * self.thickness - r + (r * r - y * y).max(0.0).sqrt()
    }

    /// Whether `(y, z)` (pitches, from its axis in its middle plane) lies in it.
    pub fn contains(&self, y: f64, z: f64) -> bool {
        y.abs() <= 0.5 * self.width && z.abs() <= self.top(y)
    }

    /// The width of its shadow on the cloth's plane under parallel rays of slope `t`
    /// (`d_across / d_z`), pitches (module docs).
    pub fn shadow(&self, t: f64) -> f64 {
        let s = t.abs();
        let alpha = CROWN_DEG.to_radians();
        let (w, r) = (self.width, self.radius);
        if s * alpha.tan() <= 1.0 {
            let corner = 0.5 * self.thickness - ROUND * w;
            w + 2.0 * s * corner
        } else {
            2.0 * (s * (0.5 * self.thickness - r) + r * (1.0 + s * s).sqrt())
        }
    }

    /// The share of the cloth's plane that rays of slope `t` across these yarns reach unshaded
    /// by them: `max(0, 1 − shadow(t))`.
    pub fn open(&self, t: f64) -> f64 {
        (1.0 - self.shadow(t)).max(0.0)
    }

    /// The cloth's open area along `d` (either side) between yarns of this section in both
    /// families (module docs): `O(d)`, 0 in the cloth's plane.
    pub fn open_along(&self, d: Vec3) -> f64 {
        if d.z == 0.0 {
            return 0.0;
        }
        self.open(d.y / d.z) * self.open(d.x / d.z)
    }
}

/// Where each yarn family shows from above, as shares of the cloth's area, `[weft, warp]`: a
/// cloth of weft fraction `g` whose yarns leave `gap` of their pitch between them. A family lies
/// on top over `1 − gap` of its cells' width (`top`), and shows below in the crossing family's
/// gaps where it leaves none itself (`below`, seen flat); the rest, `gap²`, is open. With no
/// gap, `top` is the paper's `[γ, 1 − γ]` exactly and `below` is 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cover {
    /// Each family's share on top.
    pub top: [f64; 2],
    /// Each family's share seen below the other's gaps.
    pub below: [f64; 2],
}

impl Cover {
    /// The cover of weft fraction `g` and `gap` (type docs).
    pub fn new(g: f64, gap: f64) -> Cover {
        let w = 1.0 - gap;
        Cover {
            top: [w * g, w * (1.0 - g)],
            below: [gap * w * (1.0 - g), gap * w * g],
        }
    }

    /// Each family's whole share, on top and below.
    pub fn total(&self) -> [f64; 2] {
        [self.top[0] + self.below[0], self.top[1] + self.below[1]]
    }
}

/// The share of light along `d` (either way through the cloth) that passes between the yarns of
/// both families, each leaving `gap` of its pitch open (module docs): `gap²` along the normal,
/// falling as `d` tilts across either family, 0 in the cloth's plane.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `gap` unless it is in
/// `[0, MAX_GAP]`, or `d` unless it is a finite non-zero vector.
pub fn open_area(gap: f64, d: Vec3) -> Result<f64> {
    let section = YarnSection::new(gap)?;
    if !(d.x.is_finite() && d.y.is_finite() && d.z.is_finite()) || d.length() == 0.0 {
        return Err(crate::Error::invalid(
            "d",
            format!("({}, {}, {})", d.x, d.y, d.z),
            "a finite, non-zero direction",
        ));
    }
    Ok(section.open_along(d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cover_leaves_the_gaps_square_open_and_is_the_papers_mix_without_gaps() {
        for (g, gap) in [(0.5, 0.3), (0.2, 0.6), (1.0, 0.1)] {
            let [a, b] = Cover::new(g, gap).total();
            assert!((a + b - (1.0 - gap * gap)).abs() < 1e-15);
        }
        let c = Cover::new(0.3, 0.0);
        assert_eq!((c.top, c.below), ([0.3, 1.0 - 0.3], [0.0, 0.0]));
    }

    #[test]
    fn the_shadow_is_continuous_where_the_crowns_take_over_from_the_corners() {
        let s = YarnSection::new(0.3).unwrap();
        let knee = 1.0 / CROWN_DEG.to_radians().tan();
        let (below, above) = (
            s.shadow(knee * (1.0 - 1e-12)),
            s.shadow(knee * (1.0 + 1e-12)),
        );
        assert!((below - above).abs() < 1e-10, "{below} {above}");
        // Along the normal the shadow is the yarn's width, and the crowns meet its edges.
        assert!((s.shadow(0.0) - 0.7).abs() < 1e-15);
        assert!((s.top(0.35) - (0.5 * s.thickness() - ROUND * 0.7)).abs() < 1e-12);
        assert!((s.top(0.0) - 0.5 * s.thickness()).abs() < 1e-15);
    }

    #[test]
    fn the_open_area_is_the_gaps_square_along_the_normal_and_shuts_toward_the_plane() {
        for gap in [0.0, 0.1, 0.5, MAX_GAP] {
            let normal = open_area(gap, Vec3::new(0.0, 0.0, 1.0)).unwrap();
            assert!((normal - gap * gap).abs() < 1e-15, "{gap}");
            let below = open_area(gap, Vec3::new(0.0, 0.0, -1.0)).unwrap();
            assert_eq!(normal, below);
            assert_eq!(open_area(gap, Vec3::new(1.0, 0.2, 0.0)).unwrap(), 0.0);
            let mut last = normal;
            for k in 1..90 {
                let d = Vec3::from_spherical(f64::from(k).to_radians(), 0.7);
                let o = open_area(gap, d).unwrap();
                assert!(o <= last + 1e-15 && o >= 0.0, "{gap} {k}: {o} > {last}");
                last = o;
            }
        }
        for (gap, d) in [
            (-0.1, Vec3::new(0.0, 0.0, 1.0)),
            (0.99, Vec3::new(0.0, 0.0, 1.0)),
        ] {
            assert!(open_area(gap, d).unwrap_err().to_string().contains("gap"));
        }
        let e = open_area(0.2, Vec3::new(f64::NAN, 0.0, 1.0)).unwrap_err();
        assert!(
            e.to_string().contains("`d`") || e.to_string().contains("d"),
            "{e}"
        );
    }
}
