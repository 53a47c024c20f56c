//! `woven plot`: draws the paper's figures, and BRDF hemisphere maps, as SVG or PNG.
//!
//! Curve data comes from [`woven::figures`] and is drawn by [`crate::plotting::figure`]; this
//! module parses the arguments and writes the files. The hemisphere map is [`hemisphere`].

pub mod hemisphere;

use crate::io;
use crate::plotting::figure::{self, DEFAULT_SIZE};
use crate::plotting::ImageFormat;
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use hemisphere::HemisphereArgs;
use std::path::PathBuf;
use woven::figures::{FigureId, YScale};

/// Arguments of `woven plot`.
#[derive(Args, Debug)]
#[command(
    about = "Draw one of the paper's figures, or a material's BRDF over the hemisphere",
    long_about = "Draw one of the paper's figures, computed from the model, as SVG or PNG (chosen \
by the output file's extension), or a material's BRDF over the whole view hemisphere (PNG).

fig3, fig4, fig5: planar fiber surfaces (the rough limit, Eq. (16')) as in the paper's \
Figures 3–5, the viewer moving in a vertical plane (the plane of incidence for fig3 and fig4). \
The y axis is the reflected radiance for unit irradiance, L/I0 = f·cos θi, in sr⁻¹; the x axis \
the signed view angle in degrees (negative on the light's side). The paper gives no refractive \
index or diffuse albedo: the figures use η = 1.6 (polyester), ρ0 = 0 and the `paper` \
normalization, and say so in their caption.

fig8, fig9, fig10: the paper's cloth samples (the presets polyester-sateen, belt-cloth, silk) on \
the virtual goniometer of `woven gonio`: radiance against sample tilt with the weft, the \
diagonal and the warp in the plane of light and sensor.

  fig3        θi = π/6, π/4, π/3 (σh/τ = 0.05): reflection rises with the angle of incidence
  fig4        σh/τ = 0.5 … 0.05 (θi = π/4), log axis: rougher surfaces reflect more toward the light
  fig5        viewer azimuth φr − φi = π, 15π/16, 11π/12 (θi = π/4): reflection falls off-plane
  fig8        polyester sateen: masking strong along the weft, nil along the warp
  fig9        belt cloth (twisted fibers)
  fig10       silk (isotropic yarns): the same in every direction
  hemisphere  any material: the BRDF over the view hemisphere as a false-colour disc",
    after_help = "Examples:
  woven plot fig3 -o fig3.svg -o fig3.png
  woven plot fig4 -o fig4.png --width 1600 --height 1000
  woven plot fig8 -o fig8.png
  woven plot hemisphere --material silk --theta-i-deg 45 -o silk.png

Run `woven plot <FIGURE> --help` for a figure's options."
)]
pub struct PlotArgs {
    /// Which figure to draw.
    #[command(subcommand)]
    pub figure: PlotCommand,
}

/// The figures `woven plot` draws.
#[derive(Subcommand, Debug)]
pub enum PlotCommand {
    /// Fig. 3: θi = π/6, π/4, π/3 on a planar fiber surface (σh/τ = 0.05)
    Fig3(CurveArgs),
    /// Fig. 4: σh/τ from 0.5 to 0.05 on a planar fiber surface (θi = π/4)
    Fig4(CurveArgs),
    /// Fig. 5: viewer azimuths φr − φi = π, 15π/16, 11π/12 (θi = π/4)
    Fig5(CurveArgs),
    /// Fig. 8: polyester sateen on the virtual goniometer (weft, 45°, warp)
    Fig8(CurveArgs),
    /// Fig. 9: belt cloth on the virtual goniometer (weft, 45°, warp)
    Fig9(CurveArgs),
    /// Fig. 10: silk on the virtual goniometer (weft, 45°, warp)
    Fig10(CurveArgs),
    /// A material's BRDF over the view hemisphere, as a false-colour disc (PNG)
    #[command(long_about = hemisphere::LONG_ABOUT)]
    Hemisphere(HemisphereArgs),
}

/// Options of the curve figures (fig3 … fig10).
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  woven plot fig3 -o fig3.svg -o fig3.png
  woven plot fig8 -o fig8.png --width 1600 --height 1000
  woven plot fig4 -o fig4-linear.svg --y-scale linear")]
pub struct CurveArgs {
    /// Output image; the extension chooses the format: `.svg` or `.png`. Written atomically.
    /// Repeat to write several files from one computation (`-o fig.svg -o fig.png`).
    #[arg(short, long = "output", value_name = "FILE", required = true)]
    pub outputs: Vec<PathBuf>,

    /// Image width in pixels.
    #[arg(long, value_name = "PX", default_value_t = DEFAULT_SIZE.0,
          value_parser = clap::value_parser!(u32).range(320..=8000))]
    pub width: u32,

    /// Image height in pixels.
    #[arg(long, value_name = "PX", default_value_t = DEFAULT_SIZE.1,
          value_parser = clap::value_parser!(u32).range(240..=8000))]
    pub height: u32,

    /// y-axis scale; `auto` is each figure's own (logarithmic for fig4, linear otherwise).
    #[arg(long, value_enum, default_value_t = YScaleArg::Auto)]
    pub y_scale: YScaleArg,
}

/// `--y-scale` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum YScaleArg {
    /// The figure's own choice.
    Auto,
    /// Linear from 0.
    Linear,
    /// Logarithmic.
    Log,
}

/// Runs `woven plot`.
pub fn run(args: &PlotArgs) -> Result<()> {
    let (id, curve_args) = match &args.figure {
        PlotCommand::Fig3(a) => (FigureId::Fig3, a),
        PlotCommand::Fig4(a) => (FigureId::Fig4, a),
        PlotCommand::Fig5(a) => (FigureId::Fig5, a),
        PlotCommand::Fig8(a) => (FigureId::Fig8, a),
        PlotCommand::Fig9(a) => (FigureId::Fig9, a),
        PlotCommand::Fig10(a) => (FigureId::Fig10, a),
        PlotCommand::Hemisphere(a) => return hemisphere::run(a),
    };
    run_curves(id, curve_args)
}

/// Draws one of the curve figures.
fn run_curves(id: FigureId, args: &CurveArgs) -> Result<()> {
    // Check every output name before the (slow) computation.
    let formats = args
        .outputs
        .iter()
        .map(|path| ImageFormat::from_path(path))
        .collect::<Result<Vec<_>>>()?;
    io::check_output_dirs(&args.outputs)?;
    let data = woven::figures::figure(id)?;
    let scale = match args.y_scale {
        YScaleArg::Auto => data.y_scale,
        YScaleArg::Linear => YScale::Linear,
        YScaleArg::Log => match data.y_scale {
            YScale::Log { floor } => YScale::Log { floor },
            YScale::Linear => YScale::Log { floor: 1e-4 },
        },
    };
    for (path, format) in args.outputs.iter().zip(formats) {
        let bytes = figure::render(&data, scale, format, (args.width, args.height))
            .with_context(|| format!("drawing {id:?} for `{}`", path.display()))?;
        io::write_atomically(path, |out| Ok(out.write_all(&bytes)?))?;
    }
    Ok(())
}
