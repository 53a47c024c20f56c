//! One module per subcommand: its clap arguments and its `run`.

pub mod albedo;
pub mod eval;
pub mod gonio;
pub mod materials;
pub mod plot;
pub mod plot_hemisphere;
