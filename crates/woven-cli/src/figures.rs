//! The data behind the paper's figures: the library's ([`woven::figures`]); the command line
//! only draws them (`commands/plot.rs`).

pub use woven::figures::*;
