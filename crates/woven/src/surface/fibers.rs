//! The fibre level ([`Detail::Fibers`](super::Detail::Fibers)): what resolving fibres needs (the yarn's exact model
//! and its draws), each yarn's draws at a point (its slope per float, its strands' azimuths),
//! and a point's BRDF, density and draws on its yarn's profile.

use super::{LobeMix, Tilt, WovenSurface};
use crate::cloth::Structure;
use crate::color::Rgb;
use crate::fiber::{beckmann_reflection_pdf, sample_beckmann, Normalization};
use crate::math::basis::orthonormal_basis;
use crate::math::sampling::cosine_hemisphere;
use crate::table::Albedos;
use crate::weave::{CellPoint, FloatPlace};
use crate::yarn::point::{golden_uniform, hash_uniform, YarnDraws};
use crate::yarn::Yarn;
use crate::{Model, Vec3};
use std::f64::consts::FRAC_1_PI;
use std::sync::Arc;

/// Strands of fibres across one yarn, each with its own azimuth offset (twisted and isotropic
/// yarns).
pub const STRANDS: u64 = 16;

/// A point on a yarn, resolved to its fibres ([`Detail::Fibers`](super::Detail::Fibers)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct YarnPoint {
    /// The position across its strand (one period of the yarn's profile), in `[0, 1]`: 0 and 1
    /// its edges, 1/2 its crest.
    pub across: f64,
    /// The yarn's lateral slope `θ_a` (drawn per yarn from `P(θ_a)`), radians.
    pub theta_a: f64,
    /// The fibres' azimuth offset from the yarn's axis (drawn per strand), radians.
    pub phi: f64,
    /// The probabilities with which a draw here follows the facet's microfacet lobe and the
    /// facet's cosine (the rest: the cloth normal's cosine), in proportion to the reflectance
    /// of the fibre's sheen, body colour and interreflection (each at least 5 %).
    pub draws: [f64; 2],
}

/// What resolving fibres needs: the exact model of the yarn alone, and its draws.
#[derive(Clone, Debug)]
pub(super) struct Fibers {
    pub(super) model: Arc<Model>,
    pub(super) draws: YarnDraws,
    /// [`Pattern::floats`](crate::weave::Pattern::floats) and the pattern's columns: where each float starts, for the slope
    /// drawn per float.
    pub(super) floats: Vec<FloatPlace>,
    pub(super) cols: usize,
    /// How far the strands shift across the weft's and the warp's yarn per cell along it, in
    /// yarn widths: `tan α` times the cell's length over the yarn's width, `α` the helix angle
    /// ([`YarnDraws::helix_angle`]), `uv` taken as isotropic.
    pub(super) helix: [f64; 2],
}

impl Fibers {
    fn yarn(&self) -> &Yarn {
        match self.model.structure() {
            Structure::Woven { yarn, .. } => yarn,
            Structure::Flat(_) => unreachable!("fibres are resolved on yarns only"),
        }
    }

    /// The uniform number of the slope of the float of yarn `index` (of family `warp`) over the
    /// cell at `(x, y)` (in cells): the yarn's golden-ratio point, rotated by a hash of where
    /// along the yarn the float starts (the cell itself where the yarn is not on top).
    fn slope_uniform(&self, index: i64, warp: bool, (x, y, cell): (f64, f64, &CellPoint)) -> f64 {
        let along = (if warp { y } else { x }).floor() as i64;
        let place = self.floats.get(cell.row * self.cols + cell.col);
        let start = match place {
            Some(f) if cell.weft != warp && f.len > 0 => along - i64::from(f.before),
            _ => along,
        };
        let family = u64::from(warp);
        let rotation = hash_uniform(start as u64, 0xF10A7 + family);
        (golden_uniform(index, family) + rotation).fract()
    }

    /// [`YarnPoint::draws`] for a yarn dyed `albedos`: the sheen's, the body's and the
    /// interreflection's reflectance (channel means), each at least 5 % of the draws.
    fn draw_shares(&self, albedos: &[Albedos; 3]) -> [f64; 2] {
        let yarn = self.yarn();
        let h = yarn.params().interreflection;
        let rho0 = albedos.iter().map(|a| a.diffuse).sum::<f64>() / 3.0;
        let rho = albedos.iter().map(|a| a.interreflection).sum::<f64>() / 3.0;
        let sheen = match yarn.fiber().params().normalization {
            Normalization::Paper => 1.0 - rho0,
            Normalization::None => 1.0,
        };
        let raw = [(1.0 - h) * sheen, (1.0 - h) * rho0, h * rho].map(|x| x.max(0.0));
        let total: f64 = raw.iter().sum::<f64>().max(1e-12);
        let floored = raw.map(|x| (x / total).max(0.05));
        let total: f64 = floored.iter().sum();
        [floored[0] / total, floored[1] / total]
    }
}

impl WovenSurface {
    /// The lobes of the yarn of family `warp` at a point of a cell (`(x, y)` in cells): at fibre
    /// level with weight `scale · fibers`, at yarn level with the rest.
    pub(super) fn push_yarn(
        &self,
        mix: &mut LobeMix,
        warp: bool,
        tilt: Tilt,
        scale: f64,
        fibers: f64,
        (x, y, cell): (f64, f64, &CellPoint),
    ) {
        if let Some(f) = self.fibers.as_ref().filter(|_| fibers > 0.0) {
            // Across the yarn: the weft spans y, the warp x (its frame turns y to x, so its
            // profile's e_u runs along −x); a gap's share of the cell is not yarn.
            let g = self.gap;
            let frac = if warp { cell.x } else { cell.y };
            let mut across = ((frac - 0.5 * g) / (1.0 - g)).clamp(0.0, 1.0);
            if warp {
                across = 1.0 - across;
            }
            // Each float of each yarn (a pick for the weft, an end for the warp, counted over
            // the whole surface; a float from where it comes up) draws its slope, each strand
            // of fibres its azimuth: golden-ratio points by the yarn's index, rotated per float
            // by a hash, so neighbours differ, a yarn's cross-section varies along it, and a
            // patch of a few dozen yarns averages to the model.
            let index = (if warp { x } else { y }).floor() as i64;
            let family = u64::from(warp);
            let theta_a = f.draws.slope(f.slope_uniform(index, warp, (x, y, cell)));
            // The yarn is STRANDS strands side by side, each one period of the yarn's profile
            // (its fibres' prism). Strands wind about the yarn at its helix angle: across the
            // yarn they shift by `helix` yarn widths per cell along it (wrapping round), so they
            // show as diagonal stripes, and every place along the yarn still holds each strand.
            let along = if warp { y } else { x };
            let wound = (across + along * f.helix[usize::from(warp)]) * STRANDS as f64;
            let strand = (wound.floor() as i64).rem_euclid(STRANDS as i64);
            let phi = if f.draws.varies_in_azimuth() {
                let fibre = index.wrapping_mul(STRANDS as i64).wrapping_add(strand);
                f.draws.twist(golden_uniform(fibre, 2 + family))
            } else {
                0.0
            };
            let point = YarnPoint {
                across: wound - wound.floor(),
                theta_a,
                phi,
                draws: f.draw_shares(self.dyes.albedos(warp)),
            };
            mix.push_point(warp, tilt, scale * fibers, point);
        }
        mix.push(warp, tilt, scale * (1.0 - fibers));
    }
}

/// The BRDF per channel at a point on a yarn (in its lobe's frame: the yarn along `x`):
/// `(1 − ħ) f_point + ħ ρ/π` ([`Yarn::point_parts`], Eq. (20')), dyed as the table is.
#[inline]
pub(super) fn point_eval(
    f: &Fibers,
    p: &YarnPoint,
    albedos: &[Albedos; 3],
    s: Vec3,
    v: Vec3,
) -> Rgb {
    let yarn = f.yarn();
    let parts = yarn.point_parts(s, v, p.phi, p.theta_a, p.across);
    let (fixed, per_diffuse) = yarn.fiber().affine_in_diffuse(parts);
    let h = yarn.params().interreflection;
    Rgb(albedos.map(|a| {
        ((1.0 - h) * (fixed + a.diffuse * per_diffuse) + h * a.interreflection * FRAC_1_PI).max(0.0)
    }))
}

/// The density of a fibre-level draw: the facet's Beckmann lobe (the fiber's roughness) about
/// its normal with probability [`YarnPoint::draws`]`[0]`, cosine-weighted about the facet's
/// normal with [`YarnPoint::draws`]`[1]` (the facet's body colour, `∝ s·a`: a lit facet's diffuse light is
/// then drawn with a bounded weight), else cosine-weighted about the cloth's normal (the
/// interreflection). The facet is the one `known`'s ray meets.
#[inline]
pub(super) fn point_pdf(f: &Fibers, p: &YarnPoint, known: Vec3, drawn: Vec3) -> f64 {
    if known.z <= 0.0 || drawn.z <= 0.0 {
        return 0.0;
    }
    let a = f.yarn().point_normal(known, p.phi, p.theta_a, p.across);
    point_pdf_about(f, p, a, known, drawn)
}

/// [`point_pdf`] about the facet normal `a` that `known`'s ray meets (found once by the caller).
#[inline]
fn point_pdf_about(f: &Fibers, p: &YarnPoint, a: Vec3, known: Vec3, drawn: Vec3) -> f64 {
    let glossy = beckmann_reflection_pdf(known, drawn, a, f.yarn().fiber().alpha());
    let [g, c] = p.draws;
    g * glossy + c * drawn.dot(a).max(0.0) * FRAC_1_PI + (1.0 - g - c) * drawn.z * FRAC_1_PI
}

/// A fibre-level draw for `known` and its density ([`point_pdf`]).
#[inline]
pub(super) fn point_sample(
    f: &Fibers,
    p: &YarnPoint,
    known: Vec3,
    u: [f64; 2],
) -> Option<(Vec3, f64)> {
    let [g, c] = p.draws;
    let yarn = f.yarn();
    let a = yarn.point_normal(known, p.phi, p.theta_a, p.across);
    let drawn = if u[0] < g {
        let h = sample_beckmann(a, yarn.fiber().alpha(), [u[0] / g, u[1]]);
        let kh = known.dot(h);
        if kh <= 0.0 {
            return None;
        }
        h * (2.0 * kh) - known
    } else if u[0] < g + c {
        let d = cosine_hemisphere(((u[0] - g) / c).min(1.0), u[1]);
        let (t, b) = orthonormal_basis(a);
        (t * d.x + b * d.y + a * d.z).normalize()
    } else {
        // Horizon draws are rejected below.
        cosine_hemisphere(((u[0] - g - c) / (1.0 - g - c)).min(1.0), u[1])
    };
    if drawn.z <= 0.0 {
        return None;
    }
    let pdf = point_pdf_about(f, p, a, known, drawn);
    (pdf > 0.0 && pdf.is_finite()).then_some((drawn, pdf))
}
