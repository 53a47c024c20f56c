//! The yarn resolved in space: the BRDF at one point across a yarn (docs/spec.md §2.3 read
//! point by point; docs/model.md §8).
//!
//! The profile BRDF (17') integrates, over the lit-and-visible facets of one period, the fiber
//! BRDF at each facet's normal weighted by both its cosines:
//! `f_p = (1/P) ∫ f_fiber(s, v; a) (s·a)(v·a) V_s V_v / (s_z v_z) dl`. A camera ray crosses the
//! yarn's top at a position `u` (uniform over the period, as pixels are) and meets the first
//! facet below it along `−v`: a facet element `dl` visible from `v` takes the entries of width
//! `(v·a) dl / v_z` ([`Profile::facet_seen`]). What the viewer sees there is that facet's
//! radiance, so the point's BRDF is
//!
//! ```text
//! f_point(u) = f_fiber(s, v; a(u, v)) (s·a) V_s(u, v) / s_z,
//! ```
//!
//! `a(u, v)` the facet the ray meets and `V_s` whether it is lit (the exact intervals of §2.2,
//! [`Profile::lit`]). Its mean over `u` is `f_p` exactly, and a furnace bounds it facet by facet:
//! `∫ f_point s_z dω_s = ∫ f_fiber (s·a) V_s dω_s`, at most the fibre's albedo at `v·a`. A
//! surface that shades each point of a yarn with `f_point` averages, over one yarn's width, to
//! the paper's profile BRDF, and over yarns whose slopes `θ_a` follow `P(θ_a)` (and whose fibres'
//! azimuths follow the twist density) to Eqs. (18)–(22).

use super::profile::{Piece, Profile};
use super::window::HALF_WIDTH;
use super::{FiberParts, Orientation, SlopeDistribution, Yarn};
use crate::fiber::FiberFrame;
use crate::math::quadrature::GaussLegendre;
use crate::math::sampling::Distribution1D;
use crate::math::Vec3;
use std::f64::consts::FRAC_PI_2;

/// The facet under a point of a profile's period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facet {
    /// The piece the point lies on.
    pub piece: Piece,
    /// Its parameter on the piece ([`Piece`]: the arc angle, or the distance along a lateral).
    pub param: f64,
    /// The facet normal's angle from `z` in the cross-section (towards `e_u`), radians.
    pub theta: f64,
}

impl Facet {
    /// The apex of the arc.
    pub const APEX: Facet = Facet {
        piece: Piece::Arc,
        param: 0.0,
        theta: 0.0,
    };
}

impl Profile {
    /// The facet that a ray toward a viewer at projected angle `psi_v` (as in [`Profile::lit`])
    /// meets, having crossed the apexes' line at `across ∈ [0, 1]` of one period (0 and 1 the
    /// valleys' abscissae, 1/2 the apex's). The hit may lie on a neighbouring prism, which
    /// repeats this one.
    ///
    /// Along the visible pieces, in order (left lateral outward-in, arc, right lateral), a point's
    /// "foot" `w = u cos ψ − w_z sin ψ` — where the ray through it crosses the apexes' line,
    /// scaled by `cos ψ` — increases by exactly `P cos ψ`: the visible parts tile the line. This
    /// inverts `w`, so uniform `across` falls on facets in proportion to their projected areas
    /// toward the viewer (docs/model.md §8). The apex for a flat profile (period 0) or `|ψ| ≥
    /// π/2`.
    pub fn facet_seen(&self, across: f64, psi_v: f64) -> Facet {
        if self.period() <= 0.0 || psi_v.is_nan() || psi_v.abs() >= FRAC_PI_2 {
            return Facet::APEX;
        }
        if psi_v < 0.0 {
            // Mirror u → −u.
            let f = self.facet_seen_from_right(1.0 - across, -psi_v);
            return Facet {
                piece: f.piece.mirrored(),
                param: if f.piece == Piece::Arc {
                    -f.param
                } else {
                    f.param
                },
                theta: -f.theta,
            };
        }
        self.facet_seen_from_right(across, psi_v)
    }

    /// [`Profile::facet_seen`] for `ψ ∈ [0, π/2)`.
    fn facet_seen_from_right(&self, across: f64, psi: f64) -> Facet {
        let (sp, cp) = psi.sin_cos();
        let theta_a = self.theta_a;
        let seen = self.lit(psi);
        // Each visible piece as (piece, w at its first point, w per unit of parameter, its
        // first parameter, its last), in the order of increasing w; w less the common sin ψ.
        let (cl, cr) = ((theta_a + psi).cos(), (theta_a - psi).cos());
        let mut segments: [(Piece, f64, f64); 3] = [(Piece::Arc, 0.0, 0.0); 3];
        let mut n = 0;
        if let Some((lo, hi)) = seen.left {
            // w = −sin(θ_a + ψ) − t cos(θ_a + ψ), decreasing in t: from hi down to lo.
            segments[n] = (Piece::Left, hi, lo);
            n += 1;
        }
        if let Some((lo, hi)) = seen.arc {
            segments[n] = (Piece::Arc, lo, hi);
            n += 1;
        }
        if let Some((lo, hi)) = seen.right {
            segments[n] = (Piece::Right, lo, hi);
            n += 1;
        }
        let w_of = |piece: Piece, x: f64| match piece {
            Piece::Arc => (x - psi).sin(),
            Piece::Right => (theta_a - psi).sin() + x * cr,
            Piece::Left => -(theta_a + psi).sin() - x * cl,
        };
        let segments = &segments[..n];
        let Some(&(first, first_param, _)) = segments.first() else {
            return Facet::APEX;
        };
        let start = w_of(first, first_param);
        let width = self.period() * cp;
        let entry = (across - 0.5) * self.period() * cp - sp;
        let w = entry - ((entry - start) / width).floor() * width;
        for (k, &(piece, a, b)) in segments.iter().enumerate() {
            if w <= w_of(piece, b) || k + 1 == n {
                let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
                let param = match piece {
                    Piece::Arc => psi + w.clamp(-1.0, 1.0).asin(),
                    Piece::Right => (w - (theta_a - psi).sin()) / cr,
                    Piece::Left => -(w + (theta_a + psi).sin()) / cl,
                };
                let param = if param.is_finite() {
                    param.clamp(lo, hi)
                } else {
                    a
                };
                let theta = match piece {
                    Piece::Arc => param,
                    Piece::Right => theta_a,
                    Piece::Left => -theta_a,
                };
                return Facet {
                    piece,
                    param,
                    theta,
                };
            }
        }
        unreachable!("the last segment takes what the others leave")
    }
}

impl Yarn {
    /// The BRDF before interreflection at the point `across ∈ [0, 1]` of a yarn of slope
    /// `theta_a` whose fibres lie at azimuth `phi_a`, in the two parts the fiber BRDF is affine
    /// in ([`FiberParts`]): `f_point` of the module docs, the BRDF of the facet that the
    /// viewer's ray entering at `across` meets ([`Profile::facet_seen`]), 0 where that facet is
    /// shadowed. Its mean over `across` is the profile BRDF (17').
    pub fn point_parts(
        &self,
        s: Vec3,
        v: Vec3,
        phi_a: f64,
        theta_a: f64,
        across: f64,
    ) -> FiberParts {
        if s.z <= 0.0 || v.z <= 0.0 {
            return [0.0, 0.0];
        }
        let profile = Profile {
            theta_a,
            lateral_length: self.params.lateral_length,
        };
        let frame = FiberFrame::new(phi_a);
        let facet = profile.facet_seen(across, frame.projected_angle(v));
        match profile.lit(frame.projected_angle(s)).get(facet.piece) {
            Some((lo, hi)) if (lo..=hi).contains(&facet.param) => {}
            _ => return [0.0, 0.0],
        }
        let a = frame.facet_normal(facet.theta);
        let sa = s.dot(a);
        if sa <= 0.0 {
            return [0.0, 0.0];
        }
        let [p0, p1] = self.fiber.eval_parts_with_normal(s, v, a);
        let k = sa / s.z;
        [p0 * k, p1 * k]
    }

    /// The normal of the facet that a ray toward `v` entering at `across` meets, on a yarn of
    /// slope `theta_a` whose fibres lie at `phi_a` ([`Profile::facet_seen`]).
    pub fn point_normal(&self, v: Vec3, phi_a: f64, theta_a: f64, across: f64) -> Vec3 {
        let profile = Profile {
            theta_a,
            lateral_length: self.params.lateral_length,
        };
        let frame = FiberFrame::new(phi_a);
        frame.facet_normal(profile.facet_seen(across, frame.projected_angle(v)).theta)
    }
}

/// Bins of the tabulated inverse distribution functions.
const QUANTILE_BINS: usize = 2048;

/// The yarn-to-yarn and fibre-to-fibre variation the model averages over, as draws: a yarn's
/// lateral slope `θ_a` from `P(θ_a)` (Eqs. (18)–(19)), a fibre's azimuth offset from its yarn's
/// axis from the twist density (Eq. (21)) or uniformly (Eq. (22)). Each maps a uniform number in
/// `[0, 1)` to a value, so that uniform (hashed) numbers give the model's distributions.
#[derive(Clone, Debug)]
pub struct YarnDraws {
    slope: Draw,
    twist: Draw,
}

/// One drawn quantity: a constant, or a tabulated inverse distribution function on `[lo, hi]`.
#[derive(Clone, Debug)]
enum Draw {
    Constant(f64),
    Table {
        lo: f64,
        hi: f64,
        distribution: Distribution1D,
    },
}

impl Draw {
    /// A density on `[lo, hi]`, tabulated on [`QUANTILE_BINS`] bins (each bin's mass by
    /// 4-point Gauss–Legendre), inverted linearly within a bin.
    fn tabulated(lo: f64, hi: f64, density: impl Fn(f64) -> f64) -> Draw {
        let rule = GaussLegendre::new(4);
        let h = (hi - lo) / QUANTILE_BINS as f64;
        let masses: Vec<f64> = (0..QUANTILE_BINS)
            .map(|i| {
                let a = lo + i as f64 * h;
                rule.integrate(a, a + h, &density)
            })
            .collect();
        Draw::Table {
            lo,
            hi,
            distribution: Distribution1D::new(&masses),
        }
    }

    #[inline]
    fn at(&self, u: f64) -> f64 {
        match self {
            Draw::Constant(x) => *x,
            Draw::Table {
                lo,
                hi,
                distribution,
            } => {
                let b = distribution.sample(u);
                lo + (hi - lo) * (b.bin as f64 + b.fraction) / distribution.len() as f64
            }
        }
    }
}

impl YarnDraws {
    /// The draws of `yarn`'s slope distribution and fibre orientation.
    pub fn new(yarn: &Yarn) -> YarnDraws {
        let slopes: &SlopeDistribution = yarn.slopes();
        // A narrow density is tabulated over its ±8σ window (its mass to rounding), so that
        // its bins resolve it however small σ is.
        let slope = match slopes.single() {
            Some(theta_a) => Draw::Constant(theta_a),
            None => {
                let (mu, reach) = (slopes.mean(), HALF_WIDTH * slopes.std());
                let (lo, hi) = ((mu - reach).max(0.0), (mu + reach).min(FRAC_PI_2));
                Draw::tabulated(lo, hi, |t| slopes.density(t))
            }
        };
        let twist = match yarn.orientation() {
            Orientation::Aligned => Draw::Constant(0.0),
            Orientation::Twisted(density) => {
                let d = *density;
                let reach = (HALF_WIDTH * d.std()).min(FRAC_PI_2);
                Draw::tabulated(-reach, reach, move |x| d.density(x, 0.0))
            }
            Orientation::Isotropic => Draw::Table {
                lo: -FRAC_PI_2,
                hi: FRAC_PI_2,
                distribution: Distribution1D::new(&[1.0]),
            },
        };
        YarnDraws { slope, twist }
    }

    /// The lateral slope `θ_a` for a uniform `u ∈ [0, 1)`: distributed as `P(θ_a)` for uniform
    /// `u`.
    #[inline]
    pub fn slope(&self, u: f64) -> f64 {
        self.slope.at(u)
    }

    /// A fibre's azimuth offset from its yarn's axis for a uniform `u ∈ [0, 1)`: distributed as
    /// the twist density (a period of `π` for isotropic yarns; 0 for aligned fibres).
    #[inline]
    pub fn twist(&self, u: f64) -> f64 {
        self.twist.at(u)
    }

    /// Whether fibres vary in azimuth (twisted or isotropic yarns).
    pub fn varies_in_azimuth(&self) -> bool {
        !matches!(self.twist, Draw::Constant(_))
    }

    /// The yarn's helix angle, radians: the mean `|φ|` of the fibres' azimuth offsets (the
    /// twist density's, or `π/4` for isotropic fibres; 0 for aligned ones), by the midpoint rule
    /// over [`HELIX_NODES`] quantiles. Strands of fibres wind about the yarn at this angle, so a
    /// close-up shows them as diagonal stripes.
    pub fn helix_angle(&self) -> f64 {
        let n = HELIX_NODES as f64;
        (0..HELIX_NODES)
            .map(|i| self.twist((i as f64 + 0.5) / n).abs())
            .sum::<f64>()
            / n
    }
}

/// Quantiles over which [`YarnDraws::helix_angle`] averages.
pub const HELIX_NODES: usize = 4096;

/// The `index`-th point of the golden-ratio (R1) sequence in `[0, 1)`, offset by `seed`: the
/// values of consecutive indices spread evenly over `[0, 1)`, so the mean of a function over
/// the first `N` converges like `1/N` rather than Monte Carlo's `1/√N` — yarn after yarn looks
/// varied, and a patch of cloth averages to the model's integrals after a few hundred yarns.
#[inline]
pub fn golden_uniform(index: i64, seed: u64) -> f64 {
    // 1/φ in 2⁻⁶⁴ units: integer arithmetic keeps every index exact.
    const INV_PHI: u64 = 0x9E37_79B9_7F4A_7C15;
    let offset = (hash_uniform(seed, 0x5EED) * (1u64 << 53) as f64) as u64;
    let x = (index as u64)
        .wrapping_mul(INV_PHI)
        .wrapping_add(offset << 11);
    (x >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform number in `[0, 1)` from integers (a 64-bit finaliser, SplitMix64's): the same
/// inputs always give the same number, neighbouring inputs unrelated ones.
#[inline]
pub fn hash_uniform(a: u64, b: u64) -> f64 {
    let mut z = a
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(b.wrapping_mul(0xD1B5_4A32_D192_ED03))
        .wrapping_add(0x632B_E59B_D9B4_E019);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}
