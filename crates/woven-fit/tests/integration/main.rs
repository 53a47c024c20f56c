//! Integration tests of `woven-fit` (one binary: each is a whole-program-optimized link under
//! `cargo test --release`, per STYLE.md).

mod data;
mod exports;
mod fit;
mod fit_real;
mod grounded;
mod microcylinder;
mod projection;
mod refusals;
