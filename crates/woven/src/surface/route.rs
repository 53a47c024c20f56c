//! Which of a surface's values a JIT renderer traces itself, and which it asks the library for
//! ([`WovenSurface::route`]): the Mitsuba plugin's llvm and cuda variants trace a surface's
//! table look-ups and its lobes' mix in Dr.Jit where the layout is only gathered and
//! interpolated, and hand every other surface to the library lane by lane. The rule lives here,
//! once; the plugin asks it.

use super::{Detail, Irregularity, Tilt, WovenSurface, FILTER_CELLS};
use crate::table::{Albedos, DyeRule};
use crate::weave::FloatPlace;
use std::fmt;

/// The version of [`JitLayout`]: raised whenever a field is added or changes its meaning, so
/// that a JIT front end written for another refuses the layout by name instead of misreading
/// it.
pub const JIT_LAYOUT_VERSION: u32 = 2;

/// What a JIT renderer gathers to trace a surface ([`WovenSurface::jit_layout`]): arrays and
/// constants, every rule (which lobes the macro BRDF has and their weights, the dyes and their
/// rule, what a pattern at `"cloth"` traces) evaluated here. The renderer indexes the cells and
/// floats, blends by the footprint and interpolates the tables; it decides nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct JitLayout {
    /// [`JIT_LAYOUT_VERSION`].
    pub version: u32,
    /// What each point traces: a pattern at `detail = "cloth"` is the macro BRDF everywhere
    /// ([`LayoutKind::Macro`]).
    pub kind: LayoutKind,
    /// The surface's level of detail.
    pub detail: Detail,
    /// Pattern cells per unit of `u` and of `v`.
    pub yarns_per_unit: [f64; 2],
    /// The floats' tilt at their ends, radians (0: flat).
    pub u_max: f64,
    /// The floats' profile where they tilt (`u_max > 0`), else `None`.
    pub float: Option<JitFloat>,
    /// The fraction of a cell's width between yarns.
    pub gap: f64,
    /// The macro BRDF's weft fraction γ.
    pub weft_fraction: f64,
    /// The footprint filter's start and end, in cells ([`FILTER_CELLS`]).
    pub filter_cells: [f64; 2],
    /// The macro BRDF's lobes, weight 1 in all (less the holes).
    pub macro_lobes: Vec<MacroLobe>,
    /// The weft's and the warp's dyed albedos per channel.
    pub albedos: [[Albedos; 3]; 2],
    /// The dye rule for a colour read per point ([`WovenSurface::dye_rule`]); its cap also
    /// bounds a diffuse albedo the irregularity scales.
    pub dye_rule: DyeRule,
    /// How each yarn's dye varies along it, where it does (an active irregularity on a
    /// pattern, at every level), else `None`.
    pub irregularity: Option<Irregularity>,
    /// A pattern's cells, row by row, 1 where the weft is on top; empty without one.
    pub cells: Vec<Vec<u8>>,
    /// Each cell's place in its float ([`Pattern::floats`](crate::weave::Pattern::floats)), row by row; empty without a tilt.
    pub floats: Vec<FloatPlace>,
}

/// A tilted float's profile as a JIT renderer traces it
/// ([`FloatProfile`](crate::yarn::float::FloatProfile)): the tilt `ψ` is linear between
/// knots, and the height at `t` in the piece from knot `k` is
/// `rises[k] + ∫_{t_k}^t tan ψ − top`, that integral `tan ψ_k (t − t_k)` on a piece of constant
/// tilt, else `(ln cos ψ_k − ln cos ψ(t)) / ψ′`.
#[derive(Clone, Debug, PartialEq)]
pub struct JitFloat {
    /// `(t_k, ψ_k)`, `t` increasing from 0 to 1, `ψ` in radians.
    pub knots: Vec<(f64, f64)>,
    /// The height at each knot above the float's start.
    pub rises: Vec<f64>,
    /// The crest's height above the float's start.
    pub top: f64,
}

/// One lobe of the macro BRDF, as a JIT renderer traces it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MacroLobe {
    /// The warp (the table turned 90°), or the weft.
    pub warp: bool,
    /// A whole tilted float (its own table's look-up), or flat.
    pub whole_float: bool,
    /// The lobe's weight.
    pub weight: f64,
}

/// What a surface lays on its uv, as a front end names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayoutKind {
    /// A flat fiber surface: the exact model.
    Flat,
    /// A table as it is: the BRDF it was built for, everywhere.
    Whole,
    /// The macro BRDF, the γ-mix, everywhere.
    Macro,
    /// One yarn family per pattern cell.
    Pattern,
}

impl LayoutKind {
    /// `"flat"`, `"whole"`, `"macro"` or `"pattern"`.
    pub fn name(self) -> &'static str {
        match self {
            LayoutKind::Flat => "flat",
            LayoutKind::Whole => "whole",
            LayoutKind::Macro => "macro",
            LayoutKind::Pattern => "pattern",
        }
    }
}

/// Where a JIT renderer takes a surface's values from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Route {
    /// Traced: table look-ups at the lobes of each lane's cell, float and gap.
    Traced,
    /// Evaluated by the library, lane by lane, for the reason given.
    Library(LibraryReason),
}

/// Why a JIT renderer hands a surface to the library.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LibraryReason {
    /// `detail` "fibers" or "auto" on a pattern: the yarns' fibres.
    Resolved(Detail),
    /// `relief` on a pattern: the weave's relief (ray-marched) at every level.
    Relief,
    /// `transmission`: light through the gaps and the yarns, and the back face.
    Transmission,
}

impl fmt::Display for LibraryReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LibraryReason::Resolved(d) => {
                write!(f, "`detail` = {:?} resolves the yarns' fibres", d.name())
            }
            LibraryReason::Relief => {
                f.write_str("`relief` = true lays the weave's relief, ray-marched at every level")
            }
            LibraryReason::Transmission => f.write_str(
                "`transmission` = true lets light through the gaps and the yarns, and shows the back face from behind",
            ),
        }
    }
}

impl WovenSurface {
    /// What a JIT renderer gathers to trace this surface ([`JitLayout`]); meaningful where
    /// [`route`](Self::route) says [`Route::Traced`], and filled for every surface (a front end
    /// reads its constants, the cells and floats, whatever the route).
    pub fn jit_layout(&self) -> JitLayout {
        let kind = match self.kind() {
            LayoutKind::Pattern if self.detail == Detail::Cloth => LayoutKind::Macro,
            kind => kind,
        };
        JitLayout {
            version: JIT_LAYOUT_VERSION,
            kind,
            detail: self.detail,
            yarns_per_unit: self.yarns_per_unit,
            u_max: self.u_max,
            float: (self.u_max > 0.0).then(|| JitFloat {
                knots: self.float.knots().to_vec(),
                rises: self.float.rises().to_vec(),
                top: self.float.top(),
            }),
            gap: self.gap,
            weft_fraction: self.weft_fraction(),
            filter_cells: FILTER_CELLS,
            macro_lobes: self
                .macro_lobes()
                .lobes()
                .iter()
                .map(|l| MacroLobe {
                    warp: l.warp,
                    whole_float: l.tilt == Tilt::Float,
                    weight: l.weight,
                })
                .collect(),
            albedos: [self.dyes.weft, self.dyes.warp],
            dye_rule: self.dye_rule(),
            irregularity: self.varying_dyes().copied(),
            cells: self.pattern().map_or_else(Vec::new, |p| p.to_matrix()),
            floats: self.floats().to_vec(),
        }
    }

    /// What the surface lays on its uv.
    pub fn kind(&self) -> LayoutKind {
        match &self.layout {
            super::Layout::Flat { .. } => LayoutKind::Flat,
            super::Layout::Whole => LayoutKind::Whole,
            super::Layout::Macro { .. } => LayoutKind::Macro,
            super::Layout::Pattern { .. } => LayoutKind::Pattern,
        }
    }

    /// Where a JIT renderer takes this surface's values from: traced where it only gathers,
    /// interpolates and follows a float's profile (a flat or whole table, the macro BRDF, a
    /// pattern at `detail` "yarns" or "cloth", its floats flat, tilted or shaped, its dyes even
    /// or irregular), else the library, with the reason: light through the cloth, the fibres,
    /// or the relief.
    pub fn route(&self) -> Route {
        if self.transmits() {
            return Route::Library(LibraryReason::Transmission);
        }
        if matches!(self.layout, super::Layout::Pattern { .. }) {
            if self.relief.is_some() {
                return Route::Library(LibraryReason::Relief);
            }
            if matches!(self.detail, Detail::Fibers | Detail::Auto) {
                return Route::Library(LibraryReason::Resolved(self.detail));
            }
        }
        Route::Traced
    }
}
