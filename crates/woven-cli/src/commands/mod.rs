//! One module per subcommand: its clap arguments and its `run`.

pub mod albedo;
pub mod convert;
pub mod default_job;
pub mod eval;
pub mod export;
pub mod fit;
pub mod gonio;
pub mod materials;
pub mod plot;
pub mod plot_hemisphere;
pub mod render;
pub mod serve;
pub mod tabulate;
