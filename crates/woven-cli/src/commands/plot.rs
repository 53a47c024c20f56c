//! `woven plot`: draws the paper's figures, and BRDF hemisphere maps, as SVG or PNG.
//!
//! Curve data comes from [`crate::figures`]; this module only draws. The hemisphere map is in
//! [`super::plot_hemisphere`]. Text is laid out (and, for PNG, rasterized) with the DejaVu Sans
//! font embedded in the binary, so plots render the same on a machine without any system fonts.

use super::plot_hemisphere::{self, HemisphereArgs};
use crate::figures::{self, Figure, FigureId, LegendCorner, Series, YScale};
use crate::glyphs::CrispText;
use crate::io;
use anyhow::{anyhow, bail, Context, Result};
use clap::{Args, Subcommand};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

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
    #[command(long_about = plot_hemisphere::LONG_ABOUT)]
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

/// The curve figures' default image size in pixels, `(width, height)`.
pub const DEFAULT_SIZE: (u32, u32) = (1200, 800);

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

/// Image formats `woven plot` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// Scalable vector graphics.
    Svg,
    /// Portable network graphics, 8-bit RGB.
    Png,
}

impl ImageFormat {
    /// The format named by `path`'s extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("svg") => Ok(ImageFormat::Svg),
            Some("png") => Ok(ImageFormat::Png),
            _ => bail!(
                "--output `{}`: unknown image format; the file name must end in .svg or .png",
                path.display()
            ),
        }
    }
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
        PlotCommand::Hemisphere(a) => return plot_hemisphere::run(a),
    };
    run_curves(id, curve_args)
}

/// Checks that every output's folder exists, before a (slow) computation.
pub fn check_output_dirs(outputs: &[PathBuf]) -> Result<()> {
    for path in outputs {
        let dir = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        if !dir.is_dir() {
            bail!(
                "--output `{}`: directory `{}` does not exist",
                path.display(),
                dir.display()
            );
        }
    }
    Ok(())
}

/// Draws one of the curve figures.
fn run_curves(id: FigureId, args: &CurveArgs) -> Result<()> {
    // Check every output name before the (slow) computation.
    let formats = args
        .outputs
        .iter()
        .map(|path| ImageFormat::from_path(path))
        .collect::<Result<Vec<_>>>()?;
    check_output_dirs(&args.outputs)?;
    let figure = figures::figure(id)?;
    let scale = match args.y_scale {
        YScaleArg::Auto => figure.y_scale,
        YScaleArg::Linear => YScale::Linear,
        YScaleArg::Log => match figure.y_scale {
            YScale::Log { floor } => YScale::Log { floor },
            YScale::Linear => YScale::Log { floor: 1e-4 },
        },
    };
    for (path, format) in args.outputs.iter().zip(formats) {
        let bytes = render(&figure, scale, format, (args.width, args.height))
            .with_context(|| format!("drawing {id:?} for `{}`", path.display()))?;
        io::write_atomically(path, |out| Ok(out.write_all(&bytes)?))?;
    }
    Ok(())
}

/// Draws `figure` into an in-memory image file of the given format and size.
pub fn render(
    figure: &Figure,
    scale: YScale,
    format: ImageFormat,
    size: (u32, u32),
) -> Result<Vec<u8>> {
    struct Plot<'a>(&'a Figure, YScale);
    impl Drawing for Plot<'_> {
        fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
            draw(root, self.0, self.1)
        }
    }
    render_image(&Plot(figure, scale), format, size)
}

/// A picture that draws itself onto a drawing area of any plotters backend.
pub trait Drawing {
    /// Draws onto `root` (the whole picture).
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>;
}

/// Draws `picture` into an in-memory SVG or PNG file of `width × height` (PNG text in the
/// embedded font).
pub fn render_image(
    picture: &impl Drawing,
    format: ImageFormat,
    (width, height): (u32, u32),
) -> Result<Vec<u8>> {
    register_embedded_font()?;
    match format {
        ImageFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
                picture.draw_on(&root)?;
                root.present().map_err(plot_error)?;
            }
            Ok(svg.into_bytes())
        }
        ImageFormat::Png => {
            let mut rgb = vec![0u8; width as usize * height as usize * 3];
            {
                let backend = CrispText::new(
                    BitMapBackend::with_buffer(&mut rgb, (width, height)),
                    dejavu::sans::regular(),
                )
                .map_err(|_| anyhow!("the embedded DejaVu Sans font could not be loaded"))?;
                let root = backend.into_drawing_area();
                picture.draw_on(&root)?;
                root.present().map_err(plot_error)?;
            }
            encode_png(&rgb, width, height)
        }
    }
}

/// Encodes an 8-bit RGB buffer of `width × height` pixels as PNG.
pub fn encode_png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>> {
    let mut png_bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut png_bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Best);
    encoder
        .write_header()
        .and_then(|mut w| w.write_image_data(rgb))
        .context("encoding PNG")?;
    Ok(png_bytes)
}

/// The family name under which the embedded font is registered and requested.
pub const FONT: &str = "sans-serif";

/// Registers the embedded DejaVu Sans with plotters (once per process).
pub fn register_embedded_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok());
    if ok {
        Ok(())
    } else {
        Err(anyhow!("the embedded DejaVu Sans font could not be loaded"))
    }
}

/// A drawing error as an `anyhow` error.
pub fn plot_error(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("plotting failed: {e}")
}

/// Okabe–Ito colours: distinguishable with every common colour-vision deficiency.
const COLORS: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// Font sizes and line widths, scaled with the image size (tuned at 1200 × 800).
struct Sizes {
    title: f64,
    axis: f64,
    ticks: f64,
    legend: f64,
    caption: f64,
    line: u32,
}

impl Sizes {
    fn for_size(width: u32, height: u32) -> Self {
        // Text grows more slowly than the image: a small image keeps readable labels, a large
        // one gains room for the curves.
        let k = (width as f64 / 1200.0).min(height as f64 / 800.0).sqrt();
        Sizes {
            title: 26.0 * k,
            axis: 19.0 * k,
            ticks: 16.0 * k,
            legend: 17.0 * k,
            caption: 15.0 * k,
            line: (2.5 * k).round().max(1.0) as u32,
        }
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
    scale: YScale,
) -> Result<()> {
    let (width, height) = root.dim_in_pixel();
    let sizes = Sizes::for_size(width, height);
    root.fill(&WHITE).map_err(plot_error)?;

    // The caption lines go under the chart.
    let line_height = (sizes.caption * 1.35).ceil() as u32;
    let caption_height = line_height * figure.caption.len() as u32 + line_height / 2;
    let (chart_area, caption_area) = root.split_vertically(height.saturating_sub(caption_height));
    let caption_style = (FONT, sizes.caption).into_font().color(&BLACK.mix(0.8));
    for (k, line) in figure.caption.iter().enumerate() {
        caption_area
            .draw_text(
                line,
                &caption_style,
                (
                    (sizes.caption * 1.2) as i32,
                    (k as u32 * line_height) as i32,
                ),
            )
            .map_err(plot_error)?;
    }

    // The y range follows the model curves; reference curves are cut where they leave it.
    let y_max = figure
        .series
        .iter()
        .filter(|s| !s.reference)
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0f64, f64::max);
    match scale {
        YScale::Linear => {
            let top = if y_max > 0.0 { y_max * 1.08 } else { 1.0 };
            chart(&chart_area, figure, &sizes, 0.0..top, None, top)
        }
        YScale::Log { floor } => {
            // Headroom above the highest peak for the legend: one decade.
            let top = (y_max.max(floor) * 10.0).log10().ceil();
            // Just below the floor, so that its own decade gets a tick label.
            let range = ((floor * (1.0 - 1e-9))..10f64.powf(top)).log_scale();
            chart(
                &chart_area,
                figure,
                &sizes,
                range,
                Some(floor),
                10f64.powf(top),
            )
        }
    }
}

fn chart<DB, Y>(
    area: &DrawingArea<DB, Shift>,
    figure: &Figure,
    sizes: &Sizes,
    y_range: Y,
    floor: Option<f64>,
    top: f64,
) -> Result<()>
where
    DB: DrawingBackend,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    // A title no wider than the image: shrink the font when it would be.
    let margin = (sizes.ticks * 1.2) as u32;
    let (area_w, _) = area.dim_in_pixel();
    let (title_w, _) = area
        .estimate_text_size(
            &figure.title,
            &TextStyle::from((FONT, sizes.title).into_font()),
        )
        .map_err(plot_error)?;
    let room = area_w.saturating_sub(2 * margin) as f64;
    let title_size = sizes.title * (room / title_w.max(1) as f64).min(1.0);
    let (x_lo, x_hi) = figure.x_range;
    let mut chart = ChartBuilder::on(area)
        .caption(&figure.title, (FONT, title_size))
        .margin(margin)
        .x_label_area_size((sizes.ticks * 2.0 + sizes.axis * 1.6) as u32)
        .y_label_area_size((sizes.ticks * 4.2 + sizes.axis * 1.6) as u32)
        .build_cartesian_2d(x_lo..x_hi, y_range)
        .map_err(plot_error)?;

    // Axis descriptions no longer than the axes they label: shrink the font when they would be.
    let (plot_w, plot_h) = chart.plotting_area().dim_in_pixel();
    let desc_font = TextStyle::from((FONT, sizes.axis).into_font());
    let (x_w, _) = area
        .estimate_text_size(&figure.x_label, &desc_font)
        .map_err(plot_error)?;
    let (y_w, _) = area
        .estimate_text_size(&figure.y_label, &desc_font)
        .map_err(plot_error)?;
    let fit = [
        plot_w as f64 / x_w.max(1) as f64,
        plot_h as f64 / y_w.max(1) as f64,
    ]
    .into_iter()
    .fold(1.0, f64::min);
    let axis_size = sizes.axis * fit;

    let x_fmt = |x: &f64| format!("{x:.0}");
    let y_fmt = |y: &f64| tick_label(*y);
    chart
        .configure_mesh()
        .x_labels(figure.x_ticks)
        .y_labels(10)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .x_desc(&figure.x_label)
        .y_desc(&figure.y_label)
        .axis_desc_style((FONT, axis_size))
        .label_style((FONT, sizes.ticks))
        .light_line_style(BLACK.mix(0.06))
        .bold_line_style(BLACK.mix(0.18))
        .draw()
        .map_err(plot_error)?;

    let swatch = (sizes.legend * 1.6) as i32;
    let (dash, gap) = ((sizes.legend * 0.6) as i32, (sizes.legend * 0.4) as i32);
    for (k, series) in figure.series.iter().enumerate() {
        let color = color_of(series.color.unwrap_or(k));
        let line = ((sizes.line as f64) * series.width).round().max(1.0) as u32;
        let mut runs = series_runs(series, floor, top).into_iter();
        let first = runs.next().unwrap_or_default();
        // The first run carries the legend entry (an empty one when nothing is visible).
        if series.reference {
            let style = color.stroke_width(line);
            chart
                .draw_series(DashedLineSeries::new(first, dash, gap, style))
                .map_err(plot_error)?
                .label(&series.label)
                .legend(move |(x, y)| {
                    DashedPathElement::new(vec![(x, y), (x + swatch, y)], dash, gap, style)
                });
            for run in runs {
                chart
                    .draw_series(DashedLineSeries::new(run, dash, gap, style))
                    .map_err(plot_error)?;
            }
        } else {
            chart
                .draw_series(LineSeries::new(first, color.stroke_width(line)))
                .map_err(plot_error)?
                .label(&series.label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + swatch, y)], color.stroke_width(line + 1))
                });
            for run in runs {
                chart
                    .draw_series(LineSeries::new(run, color.stroke_width(line)))
                    .map_err(plot_error)?;
            }
        }
    }
    chart
        .configure_series_labels()
        .position(match figure.legend {
            LegendCorner::UpperLeft => SeriesLabelPosition::UpperLeft,
            LegendCorner::UpperRight => SeriesLabelPosition::UpperRight,
        })
        .margin((sizes.legend * 0.8) as u32)
        .legend_area_size(swatch as u32 + (sizes.legend * 0.6) as u32)
        .label_font((FONT, sizes.legend))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.4))
        .draw()
        .map_err(plot_error)?;
    Ok(())
}

fn color_of(k: usize) -> RGBColor {
    COLORS[k % COLORS.len()]
}

/// The drawable runs of a series: a reference curve cut where it rises above `top` (the axis'
/// top), then every curve cut at the log axis' `floor`.
fn series_runs(series: &Series, floor: Option<f64>, top: f64) -> Vec<Vec<(f64, f64)>> {
    let pieces = if series.reference {
        below(&series.points, top)
    } else {
        vec![series.points.clone()]
    };
    pieces
        .iter()
        .flat_map(|piece| visible_runs(piece, floor))
        .collect()
}

/// The parts of a curve at or below `top`, each ending where the curve crosses it (linear
/// interpolation), so that a curve leaving the plot is cut at its edge.
fn below(points: &[(f64, f64)], top: f64) -> Vec<Vec<(f64, f64)>> {
    let crossing = |a: (f64, f64), b: (f64, f64)| {
        let t = (top - a.1) / (b.1 - a.1);
        (a.0 + t * (b.0 - a.0), top)
    };
    let mut runs = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    for (k, &p) in points.iter().enumerate() {
        if p.1 <= top {
            if run.is_empty() && k > 0 {
                run.push(crossing(points[k - 1], p));
            }
            run.push(p);
        } else if !run.is_empty() {
            run.push(crossing(points[k - 1], p));
            runs.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// The parts of a curve at or above `floor` (all of it without one), each run starting and
/// ending on the floor where the curve crosses it, so that a log axis shows curves entering from
/// the bottom instead of a line drawn along it.
fn visible_runs(points: &[(f64, f64)], floor: Option<f64>) -> Vec<Vec<(f64, f64)>> {
    let Some(floor) = floor else {
        return vec![points.to_vec()];
    };
    let mut runs = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    for (k, &(x, y)) in points.iter().enumerate() {
        if y >= floor {
            if run.is_empty() && k > 0 {
                run.push((points[k - 1].0, floor));
            }
            run.push((x, y));
        } else if !run.is_empty() {
            run.push((x, floor));
            runs.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// A short axis label: plain decimals in `[1e-3, 1e4)`, scientific notation outside.
pub fn tick_label(y: f64) -> String {
    let a = y.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&a) {
        // Up to four significant digits, trailing zeros removed.
        let digits = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{y:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{y:.0e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(0.25), "0.25");
        assert_eq!(tick_label(1.0), "1");
        assert_eq!(tick_label(0.001), "0.001");
        assert_eq!(tick_label(1e-4), "1e-4");
        assert_eq!(tick_label(12.5), "12.5");
    }

    #[test]
    fn curves_are_cut_at_the_log_floor() {
        let pts = [(0.0, 1e-6), (1.0, 1.0), (2.0, 2.0), (3.0, 0.0), (4.0, 5.0)];
        let runs = visible_runs(&pts, Some(1e-3));
        assert_eq!(
            runs,
            vec![
                vec![(0.0, 1e-3), (1.0, 1.0), (2.0, 2.0), (3.0, 1e-3)],
                vec![(3.0, 1e-3), (4.0, 5.0)]
            ]
        );
        assert_eq!(visible_runs(&pts, None), vec![pts.to_vec()]);
        assert!(visible_runs(&pts[..1], Some(1.0)).is_empty());
    }

    #[test]
    fn reference_curves_are_cut_at_the_top() {
        let pts = [(0.0, 1.0), (1.0, 3.0), (2.0, 1.0), (3.0, 0.5)];
        assert_eq!(
            below(&pts, 2.0),
            vec![
                vec![(0.0, 1.0), (0.5, 2.0)],
                vec![(1.5, 2.0), (2.0, 1.0), (3.0, 0.5)]
            ]
        );
        assert_eq!(below(&pts, 5.0), vec![pts.to_vec()]);
        assert!(below(&pts, 0.1).is_empty());
    }

    #[test]
    fn formats_follow_the_extension() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a/b.SVG")).unwrap(),
            ImageFormat::Svg
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("b.png")).unwrap(),
            ImageFormat::Png
        );
        let err = ImageFormat::from_path(Path::new("b.jpg")).unwrap_err();
        assert!(err.to_string().contains(".svg or .png"));
    }
}
