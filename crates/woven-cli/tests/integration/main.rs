//! Integration tests of `woven-cli` (one binary: each is a whole-program-optimized link under
//! `cargo test --release`, per STYLE.md).

mod cli;
mod export_standard;
mod fit;
mod fit_microcylinder;
mod serve;
