//! `woven`: evaluate and plot the Yang–Ikeuchi woven-cloth reflectance model.
//!
//! This file only declares the command line and dispatches; each subcommand lives in
//! [`commands`]; bare `woven` renders the built-in showcase ([`commands::render`]), and
//! `woven gonio` without `--material` runs the goniometer job of
//! [`commands::gonio::default_job`]. Exit status: 0 on success, 2 for usage errors (reported by
//! clap), 1 for any other error.

mod args;
mod commands;
mod io;
mod numbers;
mod plotting;
mod progress;
mod tables;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Evaluate and plot the Yang–Ikeuchi woven-cloth reflectance model.
#[derive(Parser, Debug)]
#[command(
    name = "woven",
    version,
    about = "Evaluate, plot, tabulate and export the Yang–Ikeuchi woven-cloth reflectance model",
    long_about = "Evaluate, plot, tabulate and export the Yang–Ikeuchi woven-cloth reflectance model.

Run without a command, woven renders its built-in showcase (four fabrics in plain, twill and \
satin weaves under a sun and sky, yarns resolved up close; what `woven render` does without a \
scene file) to woven-out/ as \
showcase.exr and showcase.png. `woven gonio` without --material runs the paper's virtual \
goniometer on the polyester-sateen preset, written to woven-out/ as CSV \
(gonio-polyester-sateen.csv) and as the paper's Figure 8 (fig8.svg, fig8.png), with a short \
summary.

Materials are built-in presets (list them with `woven materials`) or TOML files (see the \
`woven` library's `material` module); --material takes either. Angles in files are radians; options that take degrees end in `-deg`. Directions use the cloth's local frame: z is \
the macro normal, the weft runs along x and the warp along y; theta is the polar angle from z, \
phi the azimuth from x; i is the light, r the viewer.

Exit status: 0 on success, 1 on an error, 2 on a command-line usage error.",
    after_help = "Examples:
  woven materials
  woven eval --material polyester.toml --input dirs.csv --output brdf.csv
  woven albedo --material silk --theta-deg 0:80:20
  woven gonio
  woven gonio --material belt-cloth -o belt.csv
  woven render --example > scene.toml && woven render scene.toml --spp 16
  woven tabulate --material belt-cloth -o belt.wtab --report
  woven eval --table belt.wtab --input dirs.csv --output brdf.csv
  woven export --material silk --format merl -o silk.binary
  woven plot fig3 -o fig3.svg
  woven plot hemisphere --material polyester-sateen -o sateen.png
  woven serve

Run `woven help <COMMAND>` for a command's options and examples.",
    propagate_version = true
)]
struct Cli {
    /// The command; none runs the main job (see above).
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    Eval(commands::eval::EvalArgs),
    Albedo(commands::albedo::AlbedoArgs),
    Gonio(commands::gonio::GonioArgs),
    Materials(commands::materials::MaterialsArgs),
    Plot(commands::plot::PlotArgs),
    Tabulate(commands::tabulate::TabulateArgs),
    Export(commands::export::ExportArgs),
    Render(commands::render::RenderArgs),
    Convert(commands::convert::ConvertArgs),
    Serve(commands::serve::ServeArgs),
    Fit(commands::fit::FitArgs),
}

fn main() -> ExitCode {
    // Usage errors print clap's message and exit with status 2; --help and --version exit 0.
    let cli = Cli::parse();
    let result = match &cli.command {
        None => commands::render::run(&commands::render::RenderArgs::default()),
        Some(Command::Eval(args)) => commands::eval::run(args),
        Some(Command::Albedo(args)) => commands::albedo::run(args),
        Some(Command::Gonio(args)) => commands::gonio::run(args),
        Some(Command::Materials(args)) => commands::materials::run(args),
        Some(Command::Plot(args)) => commands::plot::run(args),
        Some(Command::Tabulate(args)) => commands::tabulate::run(args),
        Some(Command::Export(args)) => commands::export::run(args),
        Some(Command::Render(args)) => commands::render::run(args),
        Some(Command::Convert(args)) => commands::convert::run(args),
        Some(Command::Serve(args)) => commands::serve::run(args),
        Some(Command::Fit(args)) => commands::fit::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // A closed pipe (`woven eval … | head`) means the reader has all it wants.
        Err(err) if is_broken_pipe(&err) => ExitCode::SUCCESS,
        Err(err) => {
            // A key or a name of megabytes, echoed from the input, is shown cut.
            let clip = |text: &str| woven::error::clip_words(text).into_owned();
            eprintln!("error: {}", clip(&err.to_string()));
            let mut previous = err.to_string();
            for cause in err.chain().skip(1) {
                let text = cause.to_string();
                // The library's I/O errors print their source after the path: say it once.
                if !previous.ends_with(&text) {
                    eprintln!("  caused by: {}", clip(&text));
                }
                previous = text;
            }
            ExitCode::FAILURE
        }
    }
}

fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
            || cause
                .downcast_ref::<csv::Error>()
                .is_some_and(|e| matches!(e.kind(), csv::ErrorKind::Io(io) if io.kind() == std::io::ErrorKind::BrokenPipe))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn command_line_is_consistent() {
        Cli::command().debug_assert();
    }
}
