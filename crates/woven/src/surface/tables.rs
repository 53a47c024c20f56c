//! The resolved levels' tables: the yarn's table averaged over its crown, and the relief's
//! ratio ([`ReliefRatio`]), each built on first use or prepared ahead (from a renderer's table
//! cache and its folder).

use super::{Layout, ReliefRatio, WovenSurface};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::progress::Progress;
use crate::table::{Table, TableOptions};
use crate::yarn::float::FloatProfile;
use crate::Vec3;
use std::sync::Arc;

/// The tables a [`WovenSurface`] renders from: its yarn's, and those built from it on first use
/// (or prepared ahead, [`WovenSurface::prepare`]).
#[derive(Clone, Debug)]
pub(super) struct SurfaceTables {
    /// The yarn's table.
    pub(super) yarn: Arc<Table>,
    /// The relief's ratio table ([`WovenSurface::relief_ratio`]).
    pub(super) ratio: std::sync::OnceLock<Arc<ReliefRatio>>,
    /// The yarn's table averaged over its crown ([`Table::crowned`]): the resolved macro lobes'
    /// BRDF before the ratio.
    pub(super) crowned: std::sync::OnceLock<Arc<Table>>,
    /// Whole tilted floats' tables ([`Table::tilted`]): the yarn's on the surface's floats, and
    /// the crowned yarn's on the relief's weft and warp floats.
    pub(super) tilted: [std::sync::OnceLock<Arc<Table>>; 3],
}

impl SurfaceTables {
    /// `yarn`'s, the others not built yet.
    pub(super) fn new(yarn: Arc<Table>) -> SurfaceTables {
        SurfaceTables {
            yarn,
            ratio: std::sync::OnceLock::new(),
            crowned: std::sync::OnceLock::new(),
            tilted: Default::default(),
        }
    }
}

impl WovenSurface {
    /// Builds now what a relief's levels would build on first use: the crowned yarn table and,
    /// at every level but `"fibers"` (which never blends to the macro lobes the ratio scales),
    /// the relief's ratio table, read from `dir` when it was stored there before (and stored
    /// there when built). Nothing to do without a relief ([`SurfaceSpec::relief`](super::SurfaceSpec::relief) off, or no
    /// pattern). `note` hears why a stored ratio was not used, or why a built one could not be
    /// stored (the surface works either way).
    pub fn prepare(&self, dir: Option<&std::path::Path>, note: &dyn Fn(&str)) {
        self.prepare_tilted(dir, note);
        if self.relief.is_none() {
            return;
        }
        let _ = self.crowned();
        if self.detail == super::Detail::Fibers {
            return;
        }
        self.tables.ratio.get_or_init(|| {
            Arc::new(match dir {
                Some(dir) => ReliefRatio::load_or_build(self, dir, note),
                None => ReliefRatio::build(self),
            })
        });
    }

    /// This surface ready for its resolved levels, from `tables`: its yarn's crowned table
    /// (`options` crowned at [`CROWN_DEG`](crate::relief::CROWN_DEG): from memory, from disk, or
    /// built from the yarn's table on `options`) and the relief's ratio, kept in the tables'
    /// folder ([`prepare`](Self::prepare)). A surface that does not resolve the relief is
    /// returned as it is. `material` is the yarn tabulated ([`SurfaceSpec::table_material`](super::SurfaceSpec::table_material)),
    /// `on_build` and `progress` as [`Tables::table`](crate::table::cache::Tables::table) has
    /// them; the tables' notes hear why a stored file was not used.
    ///
    /// # Errors
    /// An invalid material or options.
    pub fn prepared_from(
        self,
        tables: &mut crate::table::cache::Tables,
        material: &Material,
        wavelength_nm: f64,
        options: &TableOptions,
        on_build: &dyn Fn(Option<&std::path::Path>),
        progress: &dyn Progress,
    ) -> Result<WovenSurface> {
        if !self.resolves_relief() {
            let dir = tables.disk().map(|d| d.dir().to_path_buf());
            self.prepare_tilted(dir.as_deref(), &|m| tables.note(m));
            return Ok(self);
        }
        let crowned = TableOptions {
            crown_deg: crate::relief::CROWN_DEG,
            ..*options
        };
        let crowned = tables.table(material, wavelength_nm, &crowned, on_build, progress)?;
        let surface = self.with_crowned(crowned)?;
        let dir = tables.disk().map(|d| d.dir().to_path_buf());
        surface.prepare(dir.as_deref(), &|m| tables.note(m));
        Ok(surface)
    }

    /// Whether the surface lays its weave's relief ([`SurfaceSpec::relief`](super::SurfaceSpec::relief) on a pattern):
    /// then it reads a crowned yarn table ([`with_crowned`](Self::with_crowned)) and
    /// the relief's ratio ([`prepare`](Self::prepare)).
    pub fn resolves_relief(&self) -> bool {
        self.relief.is_some()
    }

    /// This surface with `crowned` as its crowned yarn table, the yarn's table built with
    /// [`TableOptions::crown_deg`] = [`CROWN_DEG`](crate::relief::CROWN_DEG) (a renderer keeps it
    /// in its table cache; without it, the surface builds it from the yarn's table on first use).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `crowned` for a table of another crown.
    pub fn with_crowned(self, crowned: Arc<Table>) -> Result<WovenSurface> {
        if crowned.crown_deg() != crate::relief::CROWN_DEG {
            return Err(Error::InvalidParameter {
                name: "crowned".into(),
                value: format!("a table crowned at {}°", crowned.crown_deg()),
                expected: format!("a table crowned at {}°", crate::relief::CROWN_DEG),
            });
        }
        let _ = self.tables.crowned.set(crowned);
        Ok(self)
    }

    /// The yarn's table averaged over its crown (built on first use).
    pub(super) fn crowned(&self) -> &Table {
        self.tables.crowned.get_or_init(|| {
            // On the yarn table's grid (an isotropic yarn's: the renderer's azimuths).
            let (n_theta, n_phi, n_h) = self.tables.yarn.dims();
            let options = TableOptions {
                n_theta,
                n_phi: if n_phi > 1 {
                    n_phi
                } else {
                    crate::table::N_PHI_RENDER
                },
                n_h,
                ..TableOptions::default()
            };
            Arc::new(self.tables.yarn.crowned(crate::relief::CROWN_DEG, &options))
        })
    }

    /// Builds now the tables of whole tilted floats the surface's macro lobes read
    /// ([`tilted_table`](Self::tilted_table)), read from `dir` when stored there before (and
    /// stored there when built, [`Table::tilted_in`]): none without a tilt.
    fn prepare_tilted(&self, dir: Option<&std::path::Path>, note: &dyn Fn(&str)) {
        if self.u_max == 0.0
            || !matches!(self.layout, Layout::Macro { .. } | Layout::Pattern { .. })
        {
            return;
        }
        let build = |base: &Table, float: &FloatProfile| {
            Arc::new(match dir {
                Some(dir) => base.tilted_in(float, dir, note),
                None => base.tilted(float),
            })
        };
        match &self.relief {
            Some(relief) => {
                let [weft, warp] = [false, true].map(|warp| relief.float(warp));
                let first = self.tables.tilted[1].get_or_init(|| build(self.crowned(), &weft));
                self.tables.tilted[2].get_or_init(|| match warp == weft {
                    true => Arc::clone(first),
                    false => build(self.crowned(), &warp),
                });
            }
            None => {
                self.tables.tilted[0].get_or_init(|| build(&self.tables.yarn, &self.float));
            }
        }
    }

    /// The table a whole tilted float ([`Tilt::Float`](super::Tilt::Float)) of the family
    /// `warp` reads, in that family's frame ([`Table::tilted`], built on first use): for a
    /// resolved macro lobe the crowned yarn's table on the relief's float of that family (one
    /// table when both families' floats are the same), else the yarn's table on the surface's
    /// floats (the same for both families).
    #[inline]
    pub(super) fn tilted_table(&self, warp: bool, resolved: bool) -> &Arc<Table> {
        match (&self.relief, resolved) {
            (Some(relief), true) => self.tables.tilted[1 + usize::from(warp)].get_or_init(|| {
                let float = relief.float(warp);
                match warp && float == relief.float(false) {
                    true => Arc::clone(self.tilted_table(false, true)),
                    false => Arc::new(self.crowned().tilted(&float)),
                }
            }),
            _ => {
                self.tables.tilted[0].get_or_init(|| Arc::new(self.tables.yarn.tilted(&self.float)))
            }
        }
    }

    /// The yarn's table averaged over a whole float of the surface ([`Table::tilted`], built on
    /// first use): what a whole tilted float reads in its family's frame, outside the resolved
    /// levels. `None` without a tilt (a flat surface, a whole table, `u_max` 0).
    pub fn float_table(&self) -> Option<&Arc<Table>> {
        (self.u_max > 0.0 && matches!(self.layout, Layout::Macro { .. } | Layout::Pattern { .. }))
            .then(|| self.tilted_table(false, false))
    }

    /// Both families' relief ratios `[R_weft, R_warp]` at `(s, v)` ([`relief_ratio`](Self::relief_ratio)).
    pub(super) fn relief_ratios(&self, s: Vec3, v: Vec3) -> [f64; 2] {
        if self.relief.is_none() {
            return [1.0; 2];
        }
        self.tables
            .ratio
            .get_or_init(|| Arc::new(ReliefRatio::build(self)))
            .pair(s, v)
    }

    /// The relief's ratio `R_F(s, v)` for the family `warp` (the module `ratio`'s table, built
    /// on first use): what scales the macro lobes of a resolving surface. 1 without a relief.
    pub fn relief_ratio(&self, warp: bool, s: Vec3, v: Vec3) -> f64 {
        if self.relief.is_none() {
            return 1.0;
        }
        self.tables
            .ratio
            .get_or_init(|| Arc::new(ReliefRatio::build(self)))
            .at(warp, s, v)
    }
}
