//! Integration tests of `woven-serve` (one binary: each is a whole-program-optimized link under
//! `cargo test --release`, per STYLE.md).

mod api;
mod server;
