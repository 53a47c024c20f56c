//! The virtual goniometer's sweeps, in parallel over the readings; the geometry and a reading are
//! the library's ([`woven::gonio`]).

use rayon::prelude::*;
pub use woven::gonio::{directions, read, Reading, HALF_ANGLE_DEG};
use woven::Model;

/// The paper's tilt steps as a `--tilt-deg` range: −42° to 42° by 3° (§4;
/// [`woven::gonio::paper_tilts_deg`]).
pub const PAPER_TILTS: &str = "-42:42:3";

/// Readings for every azimuth (outer loop) and tilt (inner loop), in that order, computed in
/// parallel; `progress` is told of each reading done.
pub fn sweep(
    model: &Model,
    azimuths_deg: &[f64],
    tilts_deg: &[f64],
    progress: impl Fn() + Sync,
) -> Vec<Reading> {
    woven::gonio::sweep_grid(azimuths_deg, tilts_deg)
        .par_iter()
        // One reading costs up to a few milliseconds for cloth: small tasks balance the cores.
        .with_max_len(4)
        .map(|&(a, t)| {
            let r = read(model, a, t);
            progress();
            r
        })
        .collect()
}
