//! The paper's curve figures (Figs. 3–5 and 8–10; their data is [`woven::figures`]'s) drawn as
//! SVG or PNG: the curves, a legend, the caption under the chart, a linear or logarithmic y axis.

use super::{plot_error, render_image, tick_label, Drawing, ImageFormat, COLORS, FONT};
use anyhow::Result;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use woven::figures::{Figure, LegendCorner, Series, YScale};

/// The curve figures' default image size in pixels, `(width, height)`.
pub const DEFAULT_SIZE: (u32, u32) = (1200, 800);

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
