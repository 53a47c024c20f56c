//! Integration tests of the `woven` library (one binary, per STYLE.md).

mod baseline;
mod cloth;
mod cloth_files;
mod common;
mod dye_and_tilt;
mod energy;
mod export;
mod fiber;
mod gaps;
mod golden;
mod grounded;
mod levels;
mod masking;
mod material_files;
mod microcylinder;
mod relief;
mod robustness;
mod sheer;
mod surface;
mod surface_keys;
mod table;
mod weave;
