//! One module per subcommand: its clap arguments and its `run`.

pub mod albedo;
pub mod eval;
pub mod plot;
