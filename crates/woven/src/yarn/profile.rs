//! The arc-topped prism profile and its exact lit-and-visible intervals (docs/spec.md §2.1–§2.2).
//!
//! A yarn surface is an infinite row of parallel prisms; its cross-section, in coordinates
//! `(u, w)` (`u` across the fibers, `w` along the macro normal `z`), is one period made of an arc
//! of unit radius on top of two straight laterals tangent to it, repeated every
//! [`Profile::period`]. [`Profile::lit`] gives, in closed form, the part of each of the three
//! pieces that a direction of projected angle `ψ` lights (or, equivalently, sees); the derivation
//! of every interval end is in `docs/masking.md`, and [`crate::yarn::raycast`] is the brute-force
//! reference the closed form is tested against.
//!
//! | parameter | meaning | unit | default | valid range |
//! |---|---|---|---|---|
//! | `theta_a` (`θ_a`) | slope of the laterals = half-angle of the arc | rad | — | `[0, π/2]` |
//! | `lateral_length` (`L`) | length of each lateral | arc radii | — | `[0, 1e6]`; `0` when `θ_a = π/2` |
//!
//! Limits: `θ_a = π/2, L = 0` is a row of touching cylinders; `L → ∞` a row of V-grooves of slope
//! `θ_a` (Torrance–Sparrow's V-cavity); `θ_a = 0` a flat surface.

use std::f64::consts::FRAC_PI_2;

use crate::error::{check_range, Error, Result};

/// An arc-topped prism cross-section (docs/spec.md §2.1) with unit arc radius.
///
/// One period has its apex at the origin: the arc `(sin θ, cos θ − 1)`, `θ ∈ [−θ_a, θ_a]`, and two
/// laterals of length `L` tangent to it at its ends; copies sit at `u + kP` for every integer `k`.
/// Build it with [`Profile::new`], which validates the parameters; the methods assume valid
/// fields (checked by `debug_assert!` only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// Slope `θ_a` of the laterals (the angle of their normals from `z`), radians, in `[0, π/2]`.
    pub theta_a: f64,
    /// Length `L` of each lateral in units of the arc radius, in `[0, 1e6]`; `0` when `θ_a = π/2`.
    pub lateral_length: f64,
}

/// One of the three pieces of a period.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Piece {
    /// The arc, parametrized by its angle `θ ∈ [−θ_a, θ_a]` (radians, also its arc length).
    Arc,
    /// The right lateral (normal `(sin θ_a, cos θ_a)`), parametrized by the distance
    /// `t ∈ [0, L]` from the arc's right end `E = (sin θ_a, cos θ_a − 1)`.
    Right,
    /// The left lateral (normal `(−sin θ_a, cos θ_a)`), parametrized by the distance
    /// `t ∈ [0, L]` from the arc's left end `(−sin θ_a, cos θ_a − 1)`.
    Left,
}

impl Piece {
    /// The three pieces in a fixed order: arc, right, left.
    pub const ALL: [Piece; 3] = [Piece::Arc, Piece::Right, Piece::Left];

    /// The position of the piece in [`Piece::ALL`] (0, 1, 2).
    pub fn index(self) -> usize {
        match self {
            Piece::Arc => 0,
            Piece::Right => 1,
            Piece::Left => 2,
        }
    }

    /// The mirror image under `u → −u`: the arc stays, the laterals swap.
    pub fn mirrored(self) -> Piece {
        match self {
            Piece::Arc => Piece::Arc,
            Piece::Right => Piece::Left,
            Piece::Left => Piece::Right,
        }
    }
}

/// Parameter intervals on the three pieces of one period; `None` = empty.
///
/// Each interval `(lo, hi)` has `lo <= hi`; it may be a single point (`lo == hi`), e.g. on a piece
/// of zero length (`L = 0`, or the arc when `θ_a = 0`) whose point is lit. Parameters are those of
/// [`Piece`]: arc angle in radians (= arc length, the radius being 1), lateral distance in arc radii.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct PieceIntervals {
    /// Arc angles `θ ∈ [−θ_a, θ_a]`; the arc point is `(sin θ, cos θ − 1)`, its normal `(sin θ, cos θ)`.
    pub arc: Option<(f64, f64)>,
    /// Right lateral: distance `t ∈ [0, L]` from `E = (sin θ_a, cos θ_a − 1)` along
    /// `(cos θ_a, −sin θ_a)`; normal `(sin θ_a, cos θ_a)`.
    pub right: Option<(f64, f64)>,
    /// Left lateral: distance `t ∈ [0, L]` from `(−sin θ_a, cos θ_a − 1)` along
    /// `(−cos θ_a, −sin θ_a)`; normal `(−sin θ_a, cos θ_a)`.
    pub left: Option<(f64, f64)>,
}

impl PieceIntervals {
    /// The interval on `piece`.
    pub fn get(&self, piece: Piece) -> Option<(f64, f64)> {
        match piece {
            Piece::Arc => self.arc,
            Piece::Right => self.right,
            Piece::Left => self.left,
        }
    }

    /// The length of the interval on `piece` (radians on the arc, arc radii on a lateral); 0 when empty.
    pub fn length(&self, piece: Piece) -> f64 {
        self.get(piece).map_or(0.0, |(lo, hi)| hi - lo)
    }

    /// The mirror image under `u → −u`: the arc's `(lo, hi)` becomes `(−hi, −lo)`, left and right swap
    /// (their parameter `t` is measured from the arc outward on both sides, so it is unchanged).
    pub fn mirrored(&self) -> PieceIntervals {
        PieceIntervals {
            arc: self.arc.map(|(lo, hi)| (-hi, -lo)),
            right: self.left,
            left: self.right,
        }
    }

    /// The per-piece intersection; a piece is `None` where either is `None` or they do not meet.
    pub fn intersect(&self, other: &PieceIntervals) -> PieceIntervals {
        fn meet(a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
            let ((a0, a1), (b0, b1)) = (a?, b?);
            let (lo, hi) = (a0.max(b0), a1.min(b1));
            (lo <= hi).then_some((lo, hi))
        }
        PieceIntervals {
            arc: meet(self.arc, other.arc),
            right: meet(self.right, other.right),
            left: meet(self.left, other.left),
        }
    }
}

impl Profile {
    /// The largest accepted lateral length (arc radii); far beyond the V-groove limit, which
    /// [`Profile::lit`] reaches to ~`1/L`.
    pub const MAX_LATERAL_LENGTH: f64 = 1e6;

    /// A validated profile.
    ///
    /// `theta_a` (radians) in `[0, π/2]`; `lateral_length` (`L`, arc radii) in `[0, 1e6]`.
    /// `θ_a = π/2` (to within 1e-12) requires `L = 0` (touching cylinders): with `L > 0` the
    /// laterals would be vertical slits of zero width (docs/spec.md §2.1). `θ_a = 0, L = 0` is accepted
    /// (it is the flat limit) but has period 0; callers dividing by [`Profile::period`] must take
    /// that limit themselves.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `theta_a` or `yarn.lateral_length`.
    ///
    /// # Examples
    /// ```
    /// use woven::yarn::profile::Profile;
    /// assert!(Profile::new(0.5, 20.0).is_ok());
    /// assert!(Profile::new(std::f64::consts::FRAC_PI_2, 0.0).is_ok()); // touching cylinders
    /// assert!(Profile::new(std::f64::consts::FRAC_PI_2, 1.0).is_err());
    /// ```
    pub fn new(theta_a: f64, lateral_length: f64) -> Result<Self> {
        let theta_a = check_range("theta_a", theta_a, 0.0, FRAC_PI_2)?;
        let lateral_length = check_range(
            "yarn.lateral_length",
            lateral_length,
            0.0,
            Self::MAX_LATERAL_LENGTH,
        )?;
        // 1e-12: the caller's π/2 may come from a different rounding path (e.g. degrees).
        if FRAC_PI_2 - theta_a <= 1e-12 && lateral_length != 0.0 {
            return Err(Error::invalid(
                "yarn.lateral_length",
                lateral_length,
                "0 when theta_a = π/2 (touching cylinders)",
            ));
        }
        Ok(Profile {
            theta_a,
            lateral_length,
        })
    }

    /// The period `P = 2 (L cos θ_a + sin θ_a)` in arc radii: the width of one prism.
    ///
    /// ```
    /// use woven::yarn::profile::Profile;
    /// // Touching cylinders of unit radius repeat every diameter.
    /// let p = Profile::new(std::f64::consts::FRAC_PI_2, 0.0)?;
    /// assert!((p.period() - 2.0).abs() < 1e-15);
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn period(&self) -> f64 {
        2.0 * (self.lateral_length * self.theta_a.cos() + self.theta_a.sin())
    }

    /// The depth of the valleys below the apex, `1 − cos θ_a + L sin θ_a`, in arc radii.
    pub fn depth(&self) -> f64 {
        (1.0 - self.theta_a.cos()) + self.lateral_length * self.theta_a.sin()
    }

    /// The masking onset `π/2 − θ_a` (radians): for `|ψ|` up to it every facing point is lit;
    /// beyond it the neighbouring prism casts a shadow. A break point for integrals over `θ_a` or
    /// `ψ` (docs/spec.md §2.4).
    pub fn masking_onset(&self) -> f64 {
        FRAC_PI_2 - self.theta_a
    }

    /// The length of `piece`: `2 θ_a` for the arc (radians = arc radii), `L` for a lateral.
    pub fn piece_length(&self, piece: Piece) -> f64 {
        match piece {
            Piece::Arc => 2.0 * self.theta_a,
            Piece::Right | Piece::Left => self.lateral_length,
        }
    }

    /// The parameter range of `piece`: `(−θ_a, θ_a)` for the arc, `(0, L)` for a lateral.
    pub fn parameter_range(&self, piece: Piece) -> (f64, f64) {
        match piece {
            Piece::Arc => (-self.theta_a, self.theta_a),
            Piece::Right | Piece::Left => (0.0, self.lateral_length),
        }
    }

    /// The point `(u, w)` of `piece` at parameter `x` (see [`Piece`]), in the period whose apex is
    /// the origin.
    pub fn point(&self, piece: Piece, x: f64) -> (f64, f64) {
        let (s, c) = self.theta_a.sin_cos();
        match piece {
            Piece::Arc => (x.sin(), x.cos() - 1.0),
            Piece::Right => (s + x * c, (c - 1.0) - x * s),
            Piece::Left => (-s - x * c, (c - 1.0) - x * s),
        }
    }

    /// The unit outward normal `(a_u, a_w)` of `piece` at parameter `x`.
    pub fn normal(&self, piece: Piece, x: f64) -> (f64, f64) {
        let (s, c) = self.theta_a.sin_cos();
        match piece {
            Piece::Arc => x.sin_cos(),
            Piece::Right => (s, c),
            Piece::Left => (-s, c),
        }
    }

    /// The part of each piece lit from projected angle `psi` (radians) — equally, the part visible
    /// from it.
    ///
    /// Implements the paper's `η_n`, `θ_n` after Eq. (17), exactly; docs/spec.md §2.2, docs/masking.md.
    ///
    /// A point is lit iff its normal `a` has `a·(sin ψ, cos ψ) > 0` and the ray from it toward
    /// `(sin ψ, cos ψ)` meets no other part of the periodic profile (docs/spec.md §2.2). `ψ` is the
    /// direction's projected angle `atan2(d·e_u, d·z)` in `(−π/2, π/2)`; positive `ψ` comes from
    /// `+u`. The sets are exact (closed form, derived in `docs/masking.md`); each is one interval.
    /// This computes the quantity the paper's `η_n`, `θ_n` after Eq. (17) describe (their
    /// transcription is garbled).
    ///
    /// For `|ψ| < π/2 − θ_a` every piece is lit whole. A lateral the light grazes (`a·d = 0`: the
    /// one facing away at `|ψ| = π/2 − θ_a` exactly, or both on touching cylinders at `ψ = 0`)
    /// is not lit; its weight `a·d` is 0 anyway, so integrals are continuous there. For
    /// `|ψ| ≥ π/2` or a NaN `ψ` nothing is lit (all `None`). Never returns NaN.
    ///
    /// # Examples
    /// ```
    /// use woven::yarn::profile::Profile;
    /// let p = Profile::new(0.8, 3.0)?;
    /// // Light from straight above lights every piece whole.
    /// let lit = p.lit(0.0);
    /// assert_eq!(lit.arc, Some((-0.8, 0.8)));
    /// assert_eq!(lit.right, Some((0.0, 3.0)));
    /// assert_eq!(lit.left, Some((0.0, 3.0)));
    /// // Near-grazing light from +u (ψ = 1.5, 86°): the left lateral faces away, and the
    /// // neighbour's arc shadows all but the top 0.054 of the right lateral (of length 3).
    /// let lit = p.lit(1.5);
    /// assert_eq!(lit.left, None);
    /// let (t0, t1) = lit.right.unwrap();
    /// assert!(t0 == 0.0 && (t1 - 0.0541).abs() < 1e-4);
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn lit(&self, psi: f64) -> PieceIntervals {
        debug_assert!(
            (0.0..=FRAC_PI_2).contains(&self.theta_a) && self.lateral_length >= 0.0,
            "invalid profile {self:?}"
        );
        // No direction above the surface: nothing lit.
        if psi.is_nan() || psi.abs() >= FRAC_PI_2 {
            return PieceIntervals::default();
        }
        if psi >= 0.0 {
            self.lit_from_right(psi)
        } else {
            // Mirror u → −u: the profile is symmetric, so lit(−ψ) is lit(ψ) mirrored.
            self.lit_from_right(-psi).mirrored()
        }
    }

    /// The part of each piece both lit from `psi_s` and visible from `psi_v` (projected angles,
    /// radians, as in [`Profile::lit`]): the per-piece intersection of `lit(psi_s)` and
    /// `lit(psi_v)`. Each piece's result is one interval, being the meet of two intervals.
    ///
    /// ```
    /// use woven::yarn::profile::Profile;
    /// let p = Profile::new(1.0, 2.0)?;
    /// // Light and viewer on opposite grazing sides: only the top of the arc is both lit and seen.
    /// let both = p.lit_and_visible(1.4, -1.4);
    /// assert!(both.right.is_none() && both.left.is_none());
    /// let (lo, hi) = both.arc.unwrap();
    /// assert!(lo < 0.0 && 0.0 < hi && hi - lo < 0.35);
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn lit_and_visible(&self, psi_s: f64, psi_v: f64) -> PieceIntervals {
        self.lit(psi_s).intersect(&self.lit(psi_v))
    }

    /// [`Profile::lit`] for `ψ ∈ [0, π/2)`: light from the `+u` side.
    fn lit_from_right(&self, psi: f64) -> PieceIntervals {
        let (theta_a, l) = (self.theta_a, self.lateral_length);

        // Case 1, |ψ| ≤ π/2 − θ_a: the ray is at least as steep as any slope of the profile, so
        // nothing is shadowed and every piece faces the light (docs/masking.md §3).
        if psi <= FRAC_PI_2 - theta_a {
            return PieceIntervals {
                arc: Some((-theta_a, theta_a)),
                // A lateral the light grazes (a·d = 0) is not lit: the right one only when
                // θ_a = π/2 and ψ = 0, the left one at ψ = π/2 − θ_a exactly.
                right: (theta_a - psi < FRAC_PI_2).then_some((0.0, l)),
                left: (psi < FRAC_PI_2 - theta_a).then_some((0.0, l)),
            };
        }

        // Case 2, ψ > π/2 − θ_a (so θ_a > 0, ψ > 0): the shadow line runs through the silhouette
        // point S = (P − cos ψ, sin ψ − 1) of the right neighbour's arc; a facing point is lit iff
        // it lies above that line (docs/masking.md §4).
        let cos_psi = psi.cos();
        let p = self.period();

        // Arc: facing iff θ > ψ − π/2; above the shadow line iff sin(ψ − θ) > 1 − P cos ψ, i.e.
        // θ < ψ − π/2 + acos(1 − P cos ψ) = ψ − π/2 + 2 asin(√(P cos ψ / 2)) (the asin form keeps
        // full precision at grazing, where P cos ψ → 0).
        // The max: ψ − π/2 > −θ_a in exact arithmetic here; rounding must not push it past the end.
        let arc_lo = (psi - FRAC_PI_2).max(-theta_a);
        // The min(1): P cos ψ ≥ 2 puts the shadow line below the whole arc (no arc shadow).
        let arc_width = 2.0 * (0.5 * p * cos_psi).sqrt().min(1.0).asin();
        let arc_hi = (arc_lo + arc_width).min(theta_a);

        // Right lateral (faces the light): above the shadow line iff t < t*, with
        //   t* = (2 L cos θ_a cos ψ + sin(ψ + θ_a) − 1) / cos(ψ − θ_a),
        // the paper's η_n·L; sin(ψ + θ_a) − 1 = −2 sin²(δ/2), δ = ψ + θ_a − π/2 > 0, avoids the
        // cancellation at the onset.
        let delta = (psi - FRAC_PI_2) + theta_a;
        let half = (0.5 * delta).sin();
        let numerator = 2.0 * l * theta_a.cos() * cos_psi - 2.0 * half * half;
        // cos(ψ − θ_a) > 0 since |ψ − θ_a| < π/2 here; the floor only keeps a rounding-level
        // zero from dividing (numerator/floor is then finite and clamped to [0, L] below).
        let denominator = (psi - theta_a).cos().max(f64::MIN_POSITIVE);
        let t_star = numerator / denominator;
        let right = (t_star >= 0.0).then_some((0.0, t_star.min(l)));

        // Left lateral: its normal (−sin θ_a, cos θ_a) faces away once ψ > π/2 − θ_a.
        PieceIntervals {
            arc: Some((arc_lo, arc_hi)),
            right,
            left: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_3, FRAC_PI_4, FRAC_PI_6};

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn validation_names_the_parameter() {
        for (ta, l, name) in [
            (-0.1, 1.0, "theta_a"),
            (1.6, 0.0, "theta_a"),
            (f64::NAN, 0.0, "theta_a"),
            (0.5, -1.0, "yarn.lateral_length"),
            (0.5, 2e6, "yarn.lateral_length"),
            (0.5, f64::INFINITY, "yarn.lateral_length"),
            (FRAC_PI_2, 1e-3, "yarn.lateral_length"),
            (FRAC_PI_2 - 1e-13, 1.0, "yarn.lateral_length"),
        ] {
            match Profile::new(ta, l) {
                Err(Error::InvalidParameter { name: got, .. }) => {
                    assert_eq!(got, name, "Profile::new({ta}, {l})")
                }
                other => panic!("Profile::new({ta}, {l}) = {other:?}, want an error on {name}"),
            }
        }
        for (ta, l) in [
            (0.0, 0.0),
            (0.0, 1e6),
            (FRAC_PI_2, 0.0),
            (FRAC_PI_2 - 1e-9, 5.0),
        ] {
            assert!(Profile::new(ta, l).is_ok(), "Profile::new({ta}, {l})");
        }
    }

    #[test]
    fn period_and_pieces_close_up() {
        let p = Profile::new(0.7, 2.5).unwrap();
        // The right lateral's far end meets the next period's left lateral's far end at u = P/2.
        let r = p.point(Piece::Right, 2.5);
        let l = p.point(Piece::Left, 2.5);
        assert!(
            close(r.0, p.period() / 2.0, 1e-14),
            "{r:?} vs P/2 {}",
            p.period() / 2.0
        );
        assert!(close(l.0, -p.period() / 2.0, 1e-14) && close(l.1, r.1, 1e-15));
        assert!(close(-r.1, p.depth(), 1e-14), "{r:?} depth {}", p.depth());
        // The laterals are tangent to the arc at its ends.
        assert_eq!(p.point(Piece::Right, 0.0), p.point(Piece::Arc, 0.7));
        assert_eq!(p.normal(Piece::Right, 0.0), p.normal(Piece::Arc, 0.7));
    }

    #[test]
    fn touching_cylinders_hand_values() {
        // θ_a = π/2, L = 0, ψ = π/3: facing from θ = −π/6; the neighbour's silhouette
        // S = (1.5, √3/2 − 1) casts the line through (sin π/3, cos π/3 − 1), i.e. θ = π/3.
        let p = Profile::new(FRAC_PI_2, 0.0).unwrap();
        let lit = p.lit(FRAC_PI_3);
        let (lo, hi) = lit.arc.unwrap();
        assert!(close(lo, -FRAC_PI_6, 1e-15), "lo {lo}");
        assert!(close(hi, FRAC_PI_3, 1e-15), "hi {hi}");
        assert_eq!(lit.right, None);
        assert_eq!(lit.left, None);
        // Straight above: the whole half-circle; the zero-length laterals at the equator are grazed.
        let lit = p.lit(0.0);
        assert_eq!(lit.arc, Some((-FRAC_PI_2, FRAC_PI_2)));
        assert_eq!((lit.right, lit.left), (None, None));
    }

    #[test]
    fn right_lateral_matches_paper_eta() {
        // The paper's third η_n case, (2 cos θa cos ψ + [sin(θa + ψ) − 1]/L) / cos(θa − ψ).
        let (ta, l, psi): (f64, f64, f64) = (FRAC_PI_4, 4.0, 1.2);
        let p = Profile::new(ta, l).unwrap();
        let eta = (2.0 * ta.cos() * psi.cos() + ((ta + psi).sin() - 1.0) / l) / (ta - psi).cos();
        let (t0, t1) = p.lit(psi).right.unwrap();
        assert_eq!(t0, 0.0);
        assert!(close(t1 / l, eta, 1e-14), "t*/L {} vs η {eta}", t1 / l);
        // And the paper's third θ_n case, ψ + asin(2(L cos θa + sin θa) cos ψ − 1), is 1 − ...:
        let p = Profile::new(1.2, 0.1).unwrap();
        let psi: f64 = 1.45;
        let theta_n = psi + (p.period() * psi.cos() - 1.0).asin();
        let (_, hi) = p.lit(psi).arc.unwrap();
        assert!(close(hi, theta_n, 1e-13), "arc hi {hi} vs θ_n {theta_n}");
    }

    #[test]
    fn continuous_at_the_masking_onset() {
        for (ta, l) in [
            (0.3, 0.0),
            (0.3, 5.0),
            (1.2, 0.01),
            (1.5, 40.0),
            (1e-6, 2.0),
        ] {
            let p = Profile::new(ta, l).unwrap();
            let onset = p.masking_onset();
            let before = p.lit(onset);
            let after = p.lit(onset + 1e-12);
            // The arc and the lateral facing the light change continuously (the one facing away
            // drops out, but it is grazed at the onset and carries no weight).
            let arc = (before.arc.unwrap(), after.arc.unwrap());
            assert!(
                close(arc.0 .0, arc.1 .0, 1e-9) && close(arc.0 .1, arc.1 .1, 1e-9),
                "θa {ta} L {l}: arc at onset {:?}, just past {:?}",
                arc.0,
                arc.1
            );
            let (b, a) = (before.length(Piece::Right), after.length(Piece::Right));
            // The lit length falls at rate ~L/(2θ_a) just past the onset (the V-groove fraction
            // is 1 − ε/(2θ_a) there): steep for small θ_a, but continuous.
            assert!(
                close(a, b, 1e-9 * (1.0 + l) * (1.0 + 1.0 / ta)),
                "θa {ta} L {l}: right lateral lit length at onset {b}, just past {a}"
            );
        }
    }

    #[test]
    fn grazing_and_invalid_directions_light_nothing() {
        let p = Profile::new(0.9, 3.0).unwrap();
        for psi in [FRAC_PI_2, -FRAC_PI_2, 2.0, -3.0, f64::NAN, f64::INFINITY] {
            assert_eq!(p.lit(psi), PieceIntervals::default(), "ψ = {psi}");
        }
        // Just inside grazing: finite, ordered, inside the pieces.
        for psi in [FRAC_PI_2 - 1e-15, -(FRAC_PI_2 - 1e-15), FRAC_PI_2 - 1e-300] {
            let lit = p.lit(psi);
            for piece in Piece::ALL {
                if let Some((lo, hi)) = lit.get(piece) {
                    let (a, b) = p.parameter_range(piece);
                    assert!(
                        a <= lo && lo <= hi && hi <= b,
                        "ψ {psi} {piece:?} {lo} {hi}"
                    );
                }
            }
        }
    }

    #[test]
    fn mirror_and_intersect() {
        let a = PieceIntervals {
            arc: Some((-0.2, 0.5)),
            right: Some((0.0, 1.0)),
            left: None,
        };
        let m = a.mirrored();
        assert_eq!(m.arc, Some((-0.5, 0.2)));
        assert_eq!((m.right, m.left), (None, Some((0.0, 1.0))));
        let b = PieceIntervals {
            arc: Some((0.1, 0.9)),
            right: Some((2.0, 3.0)),
            left: Some((0.0, 1.0)),
        };
        let c = a.intersect(&b);
        assert_eq!(c.arc, Some((0.1, 0.5)));
        assert_eq!((c.right, c.left), (None, None));
        assert!(close(c.length(Piece::Arc), 0.4, 1e-15));
    }
}
