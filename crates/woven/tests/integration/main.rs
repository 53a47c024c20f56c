//! Integration tests of the `woven` library (one binary, per STYLE.md).

mod common;
mod export;
mod fiber;
mod golden;
mod masking;
mod material_files;
mod table;
mod weave;
