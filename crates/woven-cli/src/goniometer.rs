//! The virtual goniometer: the geometry, a reading and the parallel sweep are the library's
//! ([`woven::gonio`]).

#[cfg(test)]
pub use woven::gonio::read;
pub use woven::gonio::{sweep, Reading, HALF_ANGLE_DEG};

/// The paper's tilt steps as a `--tilt-deg` range: −42° to 42° by 3° (§4;
/// [`woven::gonio::paper_tilts_deg`]).
pub const PAPER_TILTS: &str = "-42:42:3";
