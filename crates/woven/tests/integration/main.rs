//! Integration tests of the `woven` library (one binary, per STYLE.md).

mod cloth;
mod cloth_files;
mod common;
mod energy;
mod export;
mod fiber;
mod golden;
mod masking;
mod material_files;
mod robustness;
mod surface;
mod table;
mod weave;
