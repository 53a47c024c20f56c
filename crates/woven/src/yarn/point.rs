//! The yarn resolved in space: the BRDF at one point across a yarn (docs/spec.md §2.3 read
//! point by point; docs/model.md §8).
//!
//! The profile BRDF (17') integrates, over the lit-and-visible facets of one period, the fiber
//! BRDF at each facet's normal weighted by both its cosines. Per unit of *projected* width
//! (`du = cos θ dl` on every piece: `θ` the facet normal's angle from `z`, `dl` its length), the
//! integrand at projected position `u` is
//!
//! ```text
//! f_point(u) = f_fiber(s, v; a(u)) (s·a)(v·a) V(u) / (s_z v_z cos θ(u)),
//! ```
//!
//! `V` the exact lit-and-visible indicator of §2.2 — the same intervals the profile BRDF
//! integrates ([`Profile::lit_and_visible`]) — so `(1/P) ∫_0^P f_point du = f_p` exactly: a
//! surface that shades each point of a yarn with `f_point` averages, over one yarn's width, to the
//! paper's profile BRDF, and over yarns whose slopes `θ_a` follow `P(θ_a)` (and whose fibres'
//! azimuths follow the twist density) to Eqs. (18)–(22).

use super::profile::{Piece, Profile};
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

impl Profile {
    /// The facet at `across ∈ [0, 1]` of one period, measured in the projection onto the cloth
    /// plane along `e_u`: 0 and 1 are the valleys between neighbouring yarns, 1/2 the apex.
    pub fn facet_at(&self, across: f64) -> Facet {
        let (s, c) = self.theta_a.sin_cos();
        let u = (across - 0.5) * self.period();
        if u.abs() <= s {
            // The arc point (sin θ, cos θ − 1): unit radius, so u = sin θ.
            let theta = u.clamp(-1.0, 1.0).asin();
            return Facet {
                piece: Piece::Arc,
                param: theta,
                theta,
            };
        }
        let t = ((u.abs() - s) / c.max(1e-300)).min(self.lateral_length);
        if u > 0.0 {
            Facet {
                piece: Piece::Right,
                param: t,
                theta: self.theta_a,
            }
        } else {
            Facet {
                piece: Piece::Left,
                param: t,
                theta: -self.theta_a,
            }
        }
    }
}

impl Yarn {
    /// The BRDF before interreflection at the point `across ∈ [0, 1]` of a yarn of slope
    /// `theta_a` whose fibres lie at azimuth `phi_a`, per unit of projected area, in the two
    /// parts the fiber BRDF is affine in ([`FiberParts`]): `f_point` of the module docs. 0 where
    /// the point is shadowed or masked. Its mean over `across` is the profile BRDF (17').
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
        let facet = profile.facet_at(across);
        let lit = profile.lit_and_visible(frame.projected_angle(s), frame.projected_angle(v));
        match lit.get(facet.piece) {
            Some((lo, hi)) if (lo..=hi).contains(&facet.param) => {}
            _ => return [0.0, 0.0],
        }
        let a = frame.facet_normal(facet.theta);
        let (sa, va, aw) = (s.dot(a), v.dot(a), facet.theta.cos());
        // A vertical facet (the rim of touching cylinders) has no projected width.
        if sa <= 0.0 || va <= 0.0 || aw < 1e-12 {
            return [0.0, 0.0];
        }
        let [p0, p1] = self.fiber.eval_parts_with_normal(s, v, a);
        let k = sa * va / (s.z * v.z * aw);
        [p0 * k, p1 * k]
    }

    /// The facet normal at the point `across` of a yarn of slope `theta_a`, fibres at `phi_a`.
    pub fn point_normal(&self, phi_a: f64, theta_a: f64, across: f64) -> Vec3 {
        let profile = Profile {
            theta_a,
            lateral_length: self.params.lateral_length,
        };
        FiberFrame::new(phi_a).facet_normal(profile.facet_at(across).theta)
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
        let slope = match slopes.single() {
            Some(theta_a) => Draw::Constant(theta_a),
            None => Draw::tabulated(0.0, FRAC_PI_2, |t| slopes.density(t)),
        };
        let twist = match yarn.orientation() {
            Orientation::Aligned => Draw::Constant(0.0),
            Orientation::Twisted(density) => {
                let d = *density;
                Draw::tabulated(-FRAC_PI_2, FRAC_PI_2, move |x| d.density(x, 0.0))
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
}

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
