//! One module per subcommand: its clap arguments and its `run` (a subcommand's own parts, such as
//! `plot hemisphere` or the goniometer job, are submodules of it). Commands do not import from
//! each other: what several use lives in the crate's shared modules ([`crate::io`],
//! [`crate::numbers`], [`crate::plotting`], [`crate::tables`], [`crate::args`],
//! [`crate::progress`]).

pub mod albedo;
pub mod convert;
pub mod eval;
pub mod export;
pub mod fit;
pub mod gonio;
pub mod materials;
pub mod plot;
pub mod render;
pub mod serve;
pub mod tabulate;
