//! Which of a surface's values a JIT renderer traces itself, and which it asks the library for
//! ([`WovenSurface::route`]): the Mitsuba plugin's llvm and cuda variants trace a surface's
//! table look-ups and its lobes' mix in Dr.Jit where the layout is only gathered and
//! interpolated, and hand every other surface to the library lane by lane. The rule lives here,
//! once; the plugin asks it.

use super::{Detail, WovenSurface};
use std::fmt;

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
    /// Floats shaped by `float_crest` and `float_flank` (their crest and flanks).
    ShapedFloats {
        /// `float_crest`.
        crest: f64,
        /// `float_flank`.
        flank: f64,
    },
    /// `irregularity`: each yarn dyed unevenly along its length.
    Irregular,
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
            LibraryReason::ShapedFloats { crest, flank } => write!(
                f,
                "floats shaped by `float_crest` = {crest} and `float_flank` = {flank}"
            ),
            LibraryReason::Irregular => {
                f.write_str("`irregularity` dyes each yarn unevenly along its length")
            }
        }
    }
}

impl WovenSurface {
    /// What the surface lays on its uv.
    pub fn kind(&self) -> LayoutKind {
        match &self.layout {
            super::Layout::Flat { .. } => LayoutKind::Flat,
            super::Layout::Whole => LayoutKind::Whole,
            super::Layout::Macro { .. } => LayoutKind::Macro,
            super::Layout::Pattern { .. } => LayoutKind::Pattern,
        }
    }

    /// Where a JIT renderer takes this surface's values from: traced where it only gathers and
    /// interpolates (a flat or whole table, the macro BRDF, a pattern at `detail` "yarns" or
    /// "cloth" with flat or linearly tilted floats and no relief), else the library, with the reason. Shaped
    /// floats go to the library whatever lays them (a pattern or a weft fraction).
    pub fn route(&self) -> Route {
        let (crest, flank) = self.float.shape();
        if self.u_max > 0.0 && (crest, flank) != (0.0, 0.0) {
            return Route::Library(LibraryReason::ShapedFloats { crest, flank });
        }
        if matches!(self.layout, super::Layout::Pattern { .. }) {
            if self.relief.is_some() {
                return Route::Library(LibraryReason::Relief);
            }
            if matches!(self.detail, Detail::Fibers | Detail::Auto) {
                return Route::Library(LibraryReason::Resolved(self.detail));
            }
            if self.irregularity.is_active() {
                return Route::Library(LibraryReason::Irregular);
            }
        }
        Route::Traced
    }
}
