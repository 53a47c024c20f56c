//! What a surface lays at a point, as a mixture of lobes ([`LobeMix`]): the pattern cell and
//! the yarn on top there, its tilt along its float, the gaps between yarns (the yarn below, or
//! a hole), on a relief the yarn that the viewer's ray meets; the macro BRDF (the γ-mix) that
//! cells average to; and the footprint filter that blends from the one to the other (and from
//! fibres to yarns, [`Detail::Auto`]).

use super::{Detail, Layout, WovenSurface, YarnPoint};
use crate::relief::{Ground, Lean, Relief};
use crate::weave::{FloatPlace, Pattern};
use crate::Vec3;

/// Footprints (in pattern cells, the larger side of the pixel's footprint) from which the
/// footprint filter starts blending toward the macro BRDF, and at which it is the macro BRDF.
pub const FILTER_CELLS: [f64; 2] = [0.5, 2.0];

/// The most lobes mixed at a point: one cell's at fibre and at yarn level, and the macro BRDF's
/// (each family on top, a whole float when tilted, and flat where it shows in the other's
/// gaps).
pub const MAX_LOBES: usize = 6;

/// Footprints (in pattern cells) from which `detail = "auto"` starts blending from fibres to
/// yarns, and at which it shows yarns alone (the footprint filter then takes over at
/// [`FILTER_CELLS`]).
pub const FIBER_CELLS: [f64; 2] = [0.1, 0.35];

/// A point on a surface as a woven surface reads it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfacePoint {
    /// The surface parameters `(u, v)` at the point.
    pub uv: [f64; 2],
    /// The footprint of the pixel at the point, in uv: `[[∂u/∂x, ∂v/∂x], [∂u/∂y, ∂v/∂y]]`, the
    /// change of `(u, v)` from one film pixel to the next along `x` and along `y`. All zero: no
    /// footprint known (a path's later vertex, a renderer without ray differentials): no
    /// filtering, and [`Detail::Auto`] shades the point at yarn level; infinite entries: a
    /// footprint wider than any pattern.
    pub footprint: [[f64; 2]; 2],
}

/// One yarn family's BRDF, flat or on a tilted float, with a weight.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lobe {
    /// The warp (the table turned 90°), or the weft.
    pub warp: bool,
    /// Where the yarn lies along its float, when floats tilt.
    pub tilt: Tilt,
    /// The lobe's weight in the point's BRDF.
    pub weight: f64,
    /// A macro lobe scaled by the relief's ratio ([`WovenSurface::relief_ratio`]): the cloth's
    /// BRDF as its resolved points average.
    pub resolved: bool,
    /// Where on its yarn the point lies, at fibre level; `None`: the yarn's (or the cloth's)
    /// averaged BRDF.
    pub point: Option<YarnPoint>,
}

/// How a lobe's yarn tilts along its float ([`SurfaceSpec::u_max`](super::SurfaceSpec::u_max), [`FloatProfile`](crate::yarn::float::FloatProfile)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Tilt {
    /// Flat: the cloth's own frame.
    #[default]
    Flat,
    /// A point of a tilted float: the fraction along the float, in `[0, 1]`, at which the
    /// viewer's ray crosses the cloth plane. The point shades with the facet that ray meets
    /// ([`FloatProfile::seen_at`](crate::yarn::float::FloatProfile::seen_at)), lit or in a neighbouring float's shadow.
    Entering(f64),
    /// A whole tilted float, its points averaged: the macro BRDF's
    /// `(1/1) ∫ f′ cos θ′i cos θ′o / (cos θi cos θo cos ψ) dt` over the part both lit and seen.
    Float,
    /// A point of the weave's relief ([`Relief`]) that the viewer's ray met: its surface leans
    /// by `lean` (its float's tilt, its crown's roll), and it is lit where no yarn of the relief
    /// stands between it and the light.
    Relief {
        /// The lean of the surface there, in the lobe's frame.
        lean: Lean,
        /// Where the ray met the relief: `x`, `y` in cells and the height in `uv`.
        at: [f64; 3],
    },
}

/// The lobes a point's BRDF mixes: `f = Σ weight · f_lobe`; the weights sum to at most 1, less
/// over the holes between gapped yarns.
#[derive(Clone, Copy, Debug)]
pub struct LobeMix {
    n: usize,
    lobes: [Lobe; MAX_LOBES],
}

impl Default for LobeMix {
    fn default() -> LobeMix {
        LobeMix {
            n: 0,
            lobes: [Lobe::default(); MAX_LOBES],
        }
    }
}

impl LobeMix {
    /// Adds `weight` of a lobe, to the same lobe's weight when it is already there (a cell's
    /// yarn blended into the γ-mix is one of the mix's two yarns: two look-ups, not three).
    #[inline]
    pub(super) fn push(&mut self, warp: bool, tilt: Tilt, weight: f64) {
        if weight > 0.0 {
            if let Some(l) = self.lobes[..self.n]
                .iter_mut()
                .find(|l| l.warp == warp && l.tilt == tilt && l.point.is_none() && !l.resolved)
            {
                l.weight += weight;
                return;
            }
            self.lobes[self.n] = Lobe {
                warp,
                tilt,
                weight,
                point: None,
                resolved: false,
            };
            self.n += 1;
        }
    }

    /// Adds a fibre-level lobe (never merged: its geometry is its own).
    #[inline]
    pub(super) fn push_point(&mut self, warp: bool, tilt: Tilt, weight: f64, point: YarnPoint) {
        if weight > 0.0 {
            self.lobes[self.n] = Lobe {
                warp,
                tilt,
                weight,
                point: Some(point),
                resolved: false,
            };
            self.n += 1;
        }
    }

    /// Empties the mix (its lobes' storage is kept, unread).
    #[inline]
    pub(super) fn clear(&mut self) {
        self.n = 0;
    }

    /// Marks every lobe from the `from`-th on as scaled by the relief's ratio.
    pub(super) fn resolve_from(&mut self, from: usize) {
        for l in &mut self.lobes[from..self.n] {
            l.resolved = true;
        }
    }

    /// The lobes, in the order they were added.
    pub fn lobes(&self) -> &[Lobe] {
        &self.lobes[..self.n]
    }

    /// The sum of the weights.
    pub fn total(&self) -> f64 {
        self.lobes().iter().map(|l| l.weight).sum()
    }
}

/// Where a viewer's ray enters a surface's relief, and the shares of the lobes it meets there.
#[derive(Clone, Copy, Debug)]
pub(super) struct Entry {
    /// The entry, in cells.
    pub(super) x: f64,
    pub(super) y: f64,
    /// The cell's share of the point's BRDF (the rest is the macro BRDF's).
    pub(super) weight: f64,
    /// The fibre level's share of the cell's.
    pub(super) fibers: f64,
}

impl WovenSurface {
    /// The lobes of the macro BRDF (weight 1 in all, less the holes): what every point blends
    /// toward under a wide footprint; the whole BRDF of a surface without a pattern.
    pub fn macro_lobes(&self) -> LobeMix {
        let mut mix = LobeMix::default();
        match &self.layout {
            Layout::Flat { .. } | Layout::Whole => mix.push(false, Tilt::Flat, 1.0),
            Layout::Macro { weft_fraction } | Layout::Pattern { weft_fraction, .. } => {
                self.push_macro(&mut mix, *weft_fraction, 1.0)
            }
        }
        mix
    }

    /// The weight of the macro BRDF at `at`: 0 while the pixel's footprint spans less than
    /// [`FILTER_CELLS`]`[0]` pattern cells, 1 from [`FILTER_CELLS`]`[1]` on, smooth between. The
    /// footprint's size is the longer side of its bounding box in uv, in cells.
    #[inline]
    pub fn macro_weight(&self, at: &SurfacePoint) -> f64 {
        match self.detail {
            Detail::Cloth => 1.0,
            Detail::Fibers => 0.0,
            Detail::Auto | Detail::Yarns => ramp(self.footprint_cells(at), FILTER_CELLS),
        }
    }

    /// The share of the fibre level in a cell's BRDF at `at`: 1 at [`Detail::Fibers`], 0 at
    /// yarns and cloth; under [`Detail::Auto`] 1 while the footprint spans less than
    /// [`FIBER_CELLS`]`[0]` cells, 0 from [`FIBER_CELLS`]`[1]`, smooth between — and 0 without a
    /// footprint (all zero): a path's later vertices average their light over many paths, and
    /// the yarn level is that average (docs/model.md §8) at a fraction of the fibre level's
    /// variance.
    #[inline]
    pub fn fiber_weight(&self, at: &SurfacePoint) -> f64 {
        match (self.detail, &self.fibers) {
            (_, None) => 0.0,
            (Detail::Fibers, _) => 1.0,
            (Detail::Auto, _) => {
                let cells = self.footprint_cells(at);
                if cells > 0.0 {
                    1.0 - ramp(cells, FIBER_CELLS)
                } else {
                    0.0
                }
            }
            _ => 0.0,
        }
    }

    /// The footprint's size at `at`: the longer side of its bounding box in uv, in cells.
    #[inline]
    fn footprint_cells(&self, at: &SurfacePoint) -> f64 {
        let [a, b] = at.footprint;
        (self.yarns_per_unit[0] * (a[0].abs() + b[0].abs()))
            .max(self.yarns_per_unit[1] * (a[1].abs() + b[1].abs()))
    }

    /// The lobes mixed at `at`. A flat fiber surface has one (its table, for sampling).
    pub fn lobes(&self, at: &SurfacePoint) -> LobeMix {
        let mut mix = LobeMix::default();
        match self.split_into(at, &mut mix) {
            Some(e) => self.with_relief(mix, &e, Vec3::new(0.0, 0.0, 1.0)),
            None => mix,
        }
    }

    /// Adds to `mix` (empty) the lobes at `at` that do not depend on the view, and returns, on a
    /// relief, where the viewer's ray enters it (the rest of the point's lobes:
    /// [`with_relief`](Self::with_relief)). It fills a mix in place: a mix is over half a
    /// kilobyte, and moving it was a tenth of a plane's render time.
    #[inline]
    pub(super) fn split_into(&self, at: &SurfacePoint, mix: &mut LobeMix) -> Option<Entry> {
        let mut entry = None;
        match &self.layout {
            Layout::Flat { .. } | Layout::Whole => mix.push(false, Tilt::Flat, 1.0),
            Layout::Macro { weft_fraction } => self.push_macro(mix, *weft_fraction, 1.0),
            Layout::Pattern {
                pattern,
                weft_fraction,
                floats,
            } => {
                let w = self.macro_weight(at);
                let (x, y) = (
                    at.uv[0] * self.yarns_per_unit[0],
                    at.uv[1] * self.yarns_per_unit[1],
                );
                if w < 1.0 {
                    if self.relief.is_some() && x.is_finite() && y.is_finite() {
                        entry = Some(Entry {
                            x,
                            y,
                            weight: 1.0 - w,
                            fibers: self.fiber_weight(at),
                        });
                    } else {
                        self.push_cell(mix, pattern, floats, at, 1.0 - w);
                    }
                }
                if w > 0.0 {
                    let from = mix.n;
                    self.push_macro(mix, *weft_fraction, w);
                    if self.relief.is_some() {
                        mix.resolve_from(from);
                    }
                }
            }
        }
        entry
    }

    /// `mix` with the lobes of the relief point that a ray toward `view` entering at `e` meets:
    /// its yarn (at fibre level with the share `e.fibers`, at yarn level with the rest), or the
    /// yarn below in a gap, or nothing in a hole.
    pub(super) fn with_relief(&self, mut mix: LobeMix, e: &Entry, view: Vec3) -> LobeMix {
        let (Some(relief), Some(pattern)) = (&self.relief, self.pattern()) else {
            return mix;
        };
        let hit = relief.hit(e.x, e.y, view);
        let at = [hit.x, hit.y, hit.z];
        let cell = pattern.cell_at(hit.x, hit.y);
        let (warp, lean) = match hit.ground {
            Ground::Top { warp, t, across } => {
                let tilt = match t {
                    Some(t) if self.u_max > 0.0 => relief.tilt(warp, t),
                    _ => 0.0,
                };
                // In the warp's frame (y turned to x) its +y is the cloth's −x.
                let roll = Relief::roll(if warp { -across } else { across });
                let lean = Lean {
                    tilt: tilt.sin_cos(),
                    roll: roll.sin_cos(),
                };
                (warp, lean)
            }
            Ground::Below { warp } => (warp, Lean::FLAT),
            Ground::Hole => return mix,
        };
        let tilt = Tilt::Relief { lean, at };
        self.push_yarn(
            &mut mix,
            warp,
            tilt,
            e.weight,
            e.fibers,
            (hit.x, hit.y, &cell),
        );
        mix
    }

    /// The lobes of a macro BRDF with weft fraction `g`, scaled by `scale`: each family on top
    /// over `(1 − gap)` of its cells' width (a whole float when floats tilt), and seen flat in
    /// the other family's gaps where it is not itself in a gap.
    fn push_macro(&self, mix: &mut LobeMix, g: f64, scale: f64) {
        let cover = crate::gaps::Cover::new(g, self.gap);
        if self.gap == 0.0 && self.u_max == 0.0 {
            mix.push(false, Tilt::Flat, scale * cover.top[0]);
            mix.push(true, Tilt::Flat, scale * cover.top[1]);
            return;
        }
        let total = cover.total();
        for (k, warp) in [false, true].into_iter().enumerate() {
            if self.u_max == 0.0 {
                mix.push(warp, Tilt::Flat, scale * total[k]);
            } else {
                mix.push(warp, Tilt::Float, scale * cover.top[k]);
                mix.push(warp, Tilt::Flat, scale * cover.below[k]);
            }
        }
    }

    /// The lobes of the pattern cell at `at`, with weight `scale`: the yarn on top, tilted by
    /// its place along its float; in a gap across it, the crossing yarn below (flat); in a
    /// gap of both, nothing. Each at fibre level (its share [`fiber_weight`](Self::fiber_weight))
    /// and at yarn level. A non-finite uv shades as the weft.
    fn push_cell(
        &self,
        mix: &mut LobeMix,
        pattern: &Pattern,
        floats: &[FloatPlace],
        at: &SurfacePoint,
        scale: f64,
    ) {
        let (x, y) = (
            at.uv[0] * self.yarns_per_unit[0],
            at.uv[1] * self.yarns_per_unit[1],
        );
        if !(x.is_finite() && y.is_finite()) {
            mix.push(false, Tilt::Flat, scale);
            return;
        }
        let cell = pattern.cell_at(x, y);
        let top = !cell.weft;
        let fibers = self.fiber_weight(at);
        if self.gap == 0.0 && self.u_max == 0.0 {
            self.push_yarn(mix, top, Tilt::Flat, scale, fibers, (x, y, &cell));
            return;
        }
        // A yarn covers the middle (1 − gap) of the cell across its axis: the weft spans y,
        // the warp spans x.
        let half = 0.5 * (1.0 - self.gap);
        let covers = |warp: bool| ((if warp { cell.x } else { cell.y }) - 0.5).abs() < half;
        if covers(top) {
            let tilt = match floats.get(cell.row * pattern.cols() + cell.col) {
                Some(f) if f.len > 0 => {
                    let along = if top { cell.y } else { cell.x };
                    Tilt::Entering((f64::from(f.before) + along) / f64::from(f.len))
                }
                _ => Tilt::Flat,
            };
            self.push_yarn(mix, top, tilt, scale, fibers, (x, y, &cell));
        } else if covers(!top) {
            self.push_yarn(mix, !top, Tilt::Flat, scale, fibers, (x, y, &cell));
        }
    }
}

/// 0 up to `edges[0]`, 1 from `edges[1]`, [`smoothstep`] between.
#[inline]
fn ramp(x: f64, edges: [f64; 2]) -> f64 {
    if x > edges[0] {
        smoothstep((x - edges[0]) / (edges[1] - edges[0]))
    } else {
        0.0
    }
}

/// `x ↦ 3x² − 2x³` on `[0, 1]`, clamped.
#[inline]
fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}
