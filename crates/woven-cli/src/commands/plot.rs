//! `woven plot`: draws the paper's figures as SVG or PNG.
//!
//! Curve data comes from [`crate::figures`]; this module only draws. Text is laid out (and, for
//! PNG, rasterized) with the DejaVu Sans font embedded in the binary, so plots render the same on
//! a machine without any system fonts.

use crate::figures::{self, Figure, FigureId, YScale};
use crate::glyphs::CrispText;
use crate::io;
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Arguments of `woven plot`.
#[derive(Args, Debug)]
#[command(
    about = "Draw one of the paper's figures from the model (SVG or PNG)",
    long_about = "Draw one of the paper's figures, computed from the model, as SVG or PNG (chosen \
by the output file's extension).

fig3, fig4, fig5: planar fiber surfaces (the rough limit, Eq. (16')) as in the paper's \
Figures 3–5, the viewer moving in a vertical plane (the plane of incidence for fig3 and fig4). The y axis is the reflected radiance for unit irradiance, \
L/I0 = f·cos θi, in sr⁻¹; the x axis the signed view angle in degrees (negative on the light's \
side). The paper gives no refractive index or diffuse albedo: the figures use η = 1.6 \
(polyester), ρ0 = 0 and the `paper` normalization, and say so in their caption.

  fig3  θi = π/6, π/4, π/3 (σh/τ = 0.05): reflection rises with the angle of incidence
  fig4  σh/τ = 0.5 … 0.05 (θi = π/4), log axis: rougher surfaces reflect more toward the light
  fig5  viewer azimuth φr − φi = π, 15π/16, 11π/12 (θi = π/4): reflection falls off-plane",
    after_help = "Examples:
  woven plot fig3 -o fig3.svg -o fig3.png
  woven plot fig4 -o fig4.png --width 1600 --height 1000
  woven plot fig4 -o fig4-linear.svg --y-scale linear"
)]
pub struct PlotArgs {
    /// Which figure to draw.
    #[arg(value_enum)]
    pub figure: FigureId,

    /// Output image; the extension chooses the format: `.svg` or `.png`. Written atomically.
    /// Repeat to write several files from one computation (`-o fig.svg -o fig.png`).
    #[arg(short, long = "output", value_name = "FILE", required = true)]
    pub outputs: Vec<PathBuf>,

    /// Image width in pixels.
    #[arg(long, value_name = "PX", default_value_t = 1200,
          value_parser = clap::value_parser!(u32).range(320..=8000))]
    pub width: u32,

    /// Image height in pixels.
    #[arg(long, value_name = "PX", default_value_t = 800,
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
    // Check every output name before the (slow) computation.
    let formats = args
        .outputs
        .iter()
        .map(|path| ImageFormat::from_path(path))
        .collect::<Result<Vec<_>>>()?;
    for path in &args.outputs {
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
    let figure = figures::figure(args.figure)?;
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
            .with_context(|| format!("drawing {:?} for `{}`", args.figure, path.display()))?;
        io::write_atomically(path, |out| Ok(out.write_all(&bytes)?))?;
    }
    Ok(())
}

/// Draws `figure` into an in-memory image file of the given format and size.
pub fn render(
    figure: &Figure,
    scale: YScale,
    format: ImageFormat,
    (width, height): (u32, u32),
) -> Result<Vec<u8>> {
    register_embedded_font()?;
    match format {
        ImageFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
                draw(&root, figure, scale)?;
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
                draw(&root, figure, scale)?;
                root.present().map_err(plot_error)?;
            }
            let mut png_bytes = Vec::new();
            let mut encoder = png::Encoder::new(&mut png_bytes, width, height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_compression(png::Compression::Best);
            encoder
                .write_header()
                .and_then(|mut w| w.write_image_data(&rgb))
                .context("encoding PNG")?;
            Ok(png_bytes)
        }
    }
}

/// The family name under which the embedded font is registered and requested.
const FONT: &str = "sans-serif";

/// Registers the embedded DejaVu Sans with plotters (once per process).
fn register_embedded_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok());
    if ok {
        Ok(())
    } else {
        Err(anyhow!("the embedded DejaVu Sans font could not be loaded"))
    }
}

fn plot_error(e: impl std::fmt::Display) -> anyhow::Error {
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

    let y_max = figure
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0f64, f64::max);
    match scale {
        YScale::Linear => {
            let top = if y_max > 0.0 { y_max * 1.08 } else { 1.0 };
            chart(&chart_area, figure, &sizes, 0.0..top, None)
        }
        YScale::Log { floor } => {
            // Headroom above the highest peak for the legend: one decade.
            let top = (y_max.max(floor) * 10.0).log10().ceil();
            // Just below the floor, so that its own decade gets a tick label.
            let range = ((floor * (1.0 - 1e-9))..10f64.powf(top)).log_scale();
            chart(&chart_area, figure, &sizes, range, Some(floor))
        }
    }
}

fn chart<DB, Y>(
    area: &DrawingArea<DB, Shift>,
    figure: &Figure,
    sizes: &Sizes,
    y_range: Y,
    floor: Option<f64>,
) -> Result<()>
where
    DB: DrawingBackend,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .caption(&figure.title, (FONT, sizes.title))
        .margin((sizes.ticks * 1.2) as u32)
        .x_label_area_size((sizes.ticks * 2.0 + sizes.axis * 1.6) as u32)
        .y_label_area_size((sizes.ticks * 4.2 + sizes.axis * 1.6) as u32)
        .build_cartesian_2d(-90.0..90.0, y_range)
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
        .x_labels(13)
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

    let line = sizes.line;
    let swatch = (sizes.legend * 1.6) as i32;
    for (k, series) in figure.series.iter().enumerate() {
        let color = color_of(k);
        let mut runs = visible_runs(&series.points, floor).into_iter();
        // The first run carries the legend entry (an empty one when nothing is visible).
        chart
            .draw_series(LineSeries::new(
                runs.next().unwrap_or_default(),
                color.stroke_width(line),
            ))
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
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
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
fn tick_label(y: f64) -> String {
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
