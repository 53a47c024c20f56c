//! Tables built by the commands (`woven tabulate`, and `woven export` for yarns too slow to
//! evaluate exactly): a size check that names the flags, a progress bar, the build time; and the
//! grid and cache of woven surfaces' tables (`woven render`, `woven export --format
//! openpbr|gltf`).

use crate::numbers::group_digits;
use crate::progress::Progress;
use anyhow::{bail, Context, Result};
use std::time::{Duration, Instant};
use woven::material::Material;
use woven::table::{grid_of, value_count, Symmetry, Table, TableOptions, MAX_VALUES};
use woven::Model;
use woven_render::woven_material::{TableCache, TableGrid};

/// Refuses a grid whose file could not be read back, naming the flags.
fn check_size(symmetry: Symmetry, options: &TableOptions) -> Result<()> {
    let (n_theta, n_phi, n_h) = grid_of(symmetry, options);
    let values = value_count(symmetry, options);
    if values > MAX_VALUES {
        let product = match symmetry {
            Symmetry::Isotropic => format!("2 × --n-theta {n_theta} × --n-h-isotropic {n_h}²"),
            Symmetry::Mirror => {
                format!("2 × --n-theta {n_theta} × --n-phi {n_phi} × --n-h {n_h}²")
            }
        };
        bail!(
            "{product} = {} values is more than a table file holds ({}); use fewer nodes",
            group_digits(values),
            group_digits(MAX_VALUES)
        );
    }
    Ok(())
}

/// A built table and how long the build took.
pub struct Built {
    /// The table.
    pub table: Table,
    /// Wall-clock build time.
    pub elapsed: Duration,
}

/// Builds the table of `model` (prepared from `material`) with a progress bar on standard error.
pub fn build_table(material: &Material, model: &Model, options: &TableOptions) -> Result<Built> {
    check_size(Symmetry::of(model), options)?;
    let bar = Progress::new(Some(0), "table rows", true);
    let start = Instant::now();
    let table = Table::build(model, material, options, &|done, total| {
        bar.set(done as u64, total as u64)
    })
    .context("cannot build the table")?;
    bar.finish();
    Ok(Built {
        table,
        elapsed: start.elapsed(),
    })
}

/// The woven-surface tables `--draft-tables` builds (`woven render`, `woven export --format
/// openpbr|gltf`): a coarse grid, seconds instead of tens of seconds per material, for previews
/// (highlights lose detail).
pub fn draft_grid() -> TableGrid {
    TableGrid::Custom(TableOptions {
        n_theta: 16,
        n_phi: 7,
        n_h: 31,
        n_h_isotropic: 61,
        azimuth_nodes: 60,
        ..TableOptions::default()
    })
}

/// The tables woven surfaces render from: none kept with `no_cache`, else the user's cache folder
/// (`$XDG_CACHE_HOME/woven` or `~/.cache/woven`), or none with a note where it cannot be had.
pub fn user_cache(no_cache: bool) -> TableCache {
    if no_cache {
        return TableCache::default();
    }
    match woven::table::cache::Cache::user() {
        Ok(disk) => TableCache::with_disk(disk).with_notes(|m| eprintln!("note: {m}")),
        Err(e) => {
            eprintln!("note: tables are not cached ({e})");
            TableCache::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn oversized_grids_are_refused_naming_the_flags() {
        let big = TableOptions {
            n_theta: 1024,
            n_phi: 1024,
            ..TableOptions::default()
        };
        let e = check_size(Symmetry::Mirror, &big).unwrap_err().to_string();
        assert!(e.contains("--n-phi 1024") && e.contains("--n-h 81²"), "{e}");
        // The library refuses what this check refuses.
        assert!(value_count(Symmetry::Mirror, &big) > MAX_VALUES);
        assert!(check_size(Symmetry::Isotropic, &big).is_ok());
        assert!(check_size(Symmetry::Mirror, &TableOptions::default()).is_ok());
    }
}
