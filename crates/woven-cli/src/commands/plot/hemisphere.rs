//! `woven plot hemisphere`: a material's BRDF over the whole view hemisphere as a false-colour
//! disc (data in [`woven::figures::hemisphere`]).

use crate::args::{
    any_material_help, parse_degrees, parse_finite, MaterialKind, MaterialSource,
    DEFAULT_WAVELENGTH_NM,
};
use crate::io;
use crate::plotting::glyphs::CrispText;
use crate::plotting::{
    encode_png, plot_error, register_embedded_font, tick_label, ImageFormat, FONT,
};
use crate::progress::Progress;
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontTransform;
use std::f64::consts::FRAC_1_SQRT_2;
use std::path::PathBuf;
use woven::figures::hemisphere::{self, Grid};
use woven::figures::words::short;
use woven::Vec3;

/// The long help of `woven plot hemisphere` (also set on its `plot` subcommand entry, whose doc
/// comment would otherwise replace it).
pub const LONG_ABOUT: &str =
    "Draw a material's BRDF f(s, v) (sr⁻¹, without the cosine) for one light \
direction over the whole hemisphere of view directions, as a false-colour disc (PNG).

The disc is the hemisphere seen from above in orthographic projection: a view direction at \
polar angle θr and azimuth φr sits at x = sin θr cos φr, y = sin θr sin φr, the normal in the \
centre, the horizon on the rim, the weft (x) to the right and the warp (y) up. Rings mark \
θr = 30° and 60°; a filled dot the light's own direction, a ring the mirror direction. Colours \
follow the viridis map, linear from 0 (or logarithmic over three decades with --log), with a \
colour bar in sr⁻¹.

With --side below the disc shows the view directions below the cloth instead, seen from above \
through it (x = sin θr cos φr, y = sin θr sin φr, θr measured from the normal below): what a \
material that lets light through (`[weave] transmission = true`, as the preset `cotton-voile`) \
transmits diffusely through its yarns. The light straight through the gaps is a delta, not \
drawn; an opaque material's disc is 0 there.

The material is a woven material (a preset or file) or a microcylinder fabric (Sadeghi et al. \
2013: the microcylinder-* presets, or a file with `model = \"microcylinder\"`). A microcylinder \
fabric is coloured: the disc shows the luminance (Rec. 709) of its RGB BRDF, as `woven eval` \
without --rgb writes it, and --wavelength-nm does not apply to it.

The BRDF is evaluated on a grid of --grid × --grid view directions (in parallel) and upsampled \
bilinearly to the image. The default grid, 128, costs about 13,000 evaluations: about a second \
for a flat surface or the sateen preset, 5–15 s for the belt-cloth and silk presets on two \
cores (view directions off the plane of incidence cost a cloth up to 2 ms each). Raise it (up \
to the disc's size in pixels) for sharper highlights of fast materials. A progress bar shows on \
standard error when it is a terminal and the job is long.";

/// Arguments of `woven plot hemisphere`.
#[derive(Args, Debug)]
#[command(
    long_about = LONG_ABOUT,
    after_help = "Examples:
  woven plot hemisphere --material silk -o silk.png
  woven plot hemisphere -m polyester-sateen --theta-i-deg 60 --phi-i-deg 90 -o sateen.png --log
  woven plot hemisphere -m my-cloth.toml --size 1024 --grid 400 -o big.png
  woven plot hemisphere -m microcylinder-satin-charmeuse --theta-i-deg 30 -o charmeuse.png
  woven plot hemisphere -m cotton-voile --side below -o voile-through.png"
)]
pub struct HemisphereArgs {
    #[arg(short, long, value_name = "PRESET|FILE", value_parser = MaterialSource::parse,
          help = any_material_help())]
    pub material: MaterialSource,

    /// Wavelength at which a woven material is evaluated, in nanometres (a microcylinder fabric
    /// has its own refractive indices and ignores it).
    #[arg(long, value_name = "NM", default_value_t = DEFAULT_WAVELENGTH_NM,
          value_parser = parse_finite)]
    pub wavelength_nm: f64,

    /// Polar angle θi of the light, degrees, in [0, 90).
    #[arg(long, value_name = "DEGREES", default_value_t = 45.0, allow_hyphen_values = true,
          value_parser = parse_theta_i)]
    pub theta_i_deg: f64,

    /// Azimuth φi of the light, degrees (0: along the weft, x; 90: along the warp, y).
    #[arg(long, value_name = "DEGREES", default_value_t = 0.0, allow_hyphen_values = true,
          value_parser = parse_finite)]
    pub phi_i_deg: f64,

    /// Output image (.png), written atomically.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// Image height in pixels; the image is 5/4 as wide (disc, labels and colour bar).
    #[arg(long, value_name = "PX", default_value_t = 512,
          value_parser = clap::value_parser!(u32).range(256..=4096))]
    pub size: u32,

    /// Evaluation grid: N × N view directions over the disc (clamped to the disc's diameter in
    /// pixels), bilinearly upsampled to the image.
    #[arg(long, value_name = "N", default_value_t = 128,
          value_parser = clap::value_parser!(u32).range(8..=4096))]
    pub grid: u32,

    /// Logarithmic colour scale over the three decades below the maximum (linear from 0 otherwise).
    #[arg(long)]
    pub log: bool,

    /// Which view hemisphere: `above` the cloth (what it reflects) or `below` it (what a material
    /// that lets light through transmits).
    #[arg(long, value_enum, default_value_t = SideArg::Above)]
    pub side: SideArg,
}

/// `--side`: the hemisphere of view directions drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SideArg {
    /// Above the cloth: its reflection.
    Above,
    /// Below it, seen through it from above: its transmission.
    Below,
}

fn parse_theta_i(value: &str) -> Result<f64, String> {
    // 90° is excluded: light at the horizon delivers no irradiance.
    let angles = parse_degrees("--theta-i-deg", value, 0.0, 90.0, true)?;
    match angles[..] {
        [theta] => Ok(theta),
        _ => Err(format!("--theta-i-deg `{value}`: expected one angle")),
    }
}

/// How BRDF values map to colours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorScale {
    /// `[0, max]` linearly.
    Linear {
        /// The top of the scale, sr⁻¹.
        max: f64,
    },
    /// `[floor, max]` logarithmically; values below the floor take its colour.
    Log {
        /// The bottom of the scale, sr⁻¹.
        floor: f64,
        /// The top of the scale, sr⁻¹.
        max: f64,
    },
}

/// Decades a logarithmic scale spans below its maximum.
pub const LOG_DECADES: f64 = 3.0;

impl ColorScale {
    /// The scale for values up to `max`.
    pub fn new(max: f64, log: bool) -> Self {
        // An all-black BRDF still needs a non-empty range.
        let max = if max > 0.0 { max } else { 1.0 };
        if log {
            ColorScale::Log {
                floor: max * 10f64.powf(-LOG_DECADES),
                max,
            }
        } else {
            ColorScale::Linear { max }
        }
    }

    /// The position of `f` on the scale, in `[0, 1]`.
    pub fn position(&self, f: f64) -> f64 {
        let t = match *self {
            ColorScale::Linear { max } => f / max,
            ColorScale::Log { floor, max } => {
                (f.max(floor) / floor).log10() / (max / floor).log10()
            }
        };
        if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// The colour of `f`.
    pub fn color(&self, f: f64) -> RGBColor {
        ViridisRGB.get_color(self.position(f))
    }

    /// Tick values for the colour bar: 0 and round steps (linear), or the decades (log).
    pub fn ticks(&self) -> Vec<f64> {
        match *self {
            ColorScale::Linear { max } => {
                let step = nice_step(max / 5.0);
                (0..)
                    .map(|k| k as f64 * step)
                    .take_while(|&t| t <= max * (1.0 + 1e-9))
                    .collect()
            }
            ColorScale::Log { floor, max } => {
                let (lo, hi) = (floor.log10().ceil() as i32, max.log10().floor() as i32);
                (lo..=hi).map(|e| 10f64.powi(e)).collect()
            }
        }
    }
}

/// The smallest of 1, 2, 2.5, 5 × 10^k at or above `x > 0`.
fn nice_step(x: f64) -> f64 {
    let decade = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= x * (1.0 - 1e-9))
        .unwrap_or(10.0 * decade)
}

/// Runs `woven plot hemisphere`.
pub fn run(args: &HemisphereArgs) -> Result<()> {
    if ImageFormat::from_path(&args.output)? != ImageFormat::Png {
        bail!(
            "--output `{}`: the hemisphere plot is written as PNG; use a name ending in .png",
            args.output.display()
        );
    }
    io::check_output_dirs(std::slice::from_ref(&args.output))?;
    let material = args.material.load_mono(args.wavelength_nm)?;
    let layout = Layout::new(args.size);
    let n = (args.grid as usize).min(layout.diameter as usize).max(8);
    let s = Vec3::from_spherical(args.theta_i_deg.to_radians(), args.phi_i_deg.to_radians());
    let bar = Progress::new(Some(hemisphere::nodes_needed(n)), "directions", true);
    let side = match args.side {
        SideArg::Above => hemisphere::Side::Above,
        SideArg::Below => hemisphere::Side::Below,
    };
    let grid = hemisphere::evaluate(&*material.brdf, s, n, side, |k| bar.inc(k));
    bar.finish();
    let words = Words {
        title: match side {
            hemisphere::Side::Above => format!("BRDF over the view hemisphere — {}", material.name),
            hemisphere::Side::Below => format!(
                "transmission below the cloth, seen through it — {}",
                material.name
            ),
        },
        setting: format!(
            "light at θi = {}°, φi = {}° (dot); {} direction (ring); {}",
            short(args.theta_i_deg),
            short(args.phi_i_deg),
            ring(side),
            match material.kind {
                MaterialKind::Woven => format!("λ = {} nm", short(args.wavelength_nm)),
                MaterialKind::Microcylinder => "luminance (Rec. 709) of its RGB BRDF".into(),
            }
        ),
        method: format!(
            "seen from above: x = sin θr cos φr, y = sin θr sin φr; rings at θr = 30°, 60°; \
             {n} × {n} grid, bilinear; {} colour scale",
            if args.log { "logarithmic" } else { "linear" }
        ),
        ring: ring(side),
        quantity: match side {
            hemisphere::Side::Above => "BRDF f(s, v)",
            hemisphere::Side::Below => "BTDF f(s, v)",
        },
    };
    let scale = ColorScale::new(grid.max_in_disc(), args.log);
    let bytes = render(&grid, scale, s, &layout, &words)
        .with_context(|| format!("drawing `{}`", args.output.display()))?;
    io::write_atomically(&args.output, |out| Ok(out.write_all(&bytes)?))
}

/// The name of the ring on `side`: where light from the dot leaves as from a mirror above, and
/// straight on below.
fn ring(side: hemisphere::Side) -> &'static str {
    match side {
        hemisphere::Side::Above => "mirror",
        hemisphere::Side::Below => "straight through",
    }
}

/// The texts of the image.
pub struct Words {
    /// Title line.
    pub title: String,
    /// Second line: the light and the wavelength.
    pub setting: String,
    /// Third line: the projection and the grid.
    pub method: String,
    /// The ring's name: the mirror direction above, the direction straight through below.
    pub ring: &'static str,
    /// What the colour bar measures: a BRDF above, a BTDF below.
    pub quantity: &'static str,
}

/// Where everything goes in an image of a given height (tuned at 512 px, scaled with it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    /// Image width and height, px.
    pub width: u32,
    /// Image height, px.
    pub height: u32,
    /// Scale of fonts and margins relative to a 512 px image.
    pub k: f64,
    /// The disc's top-left corner and diameter, px.
    pub disc_x: i32,
    /// The disc's top edge, px.
    pub disc_y: i32,
    /// The disc's diameter, px.
    pub diameter: u32,
    /// The colour bar's left edge, px (top and bottom match the disc).
    pub bar_x: i32,
    /// The colour bar's width, px.
    pub bar_width: u32,
}

impl Layout {
    /// The layout of an image `size` pixels high.
    pub fn new(size: u32) -> Self {
        let k = size as f64 / 512.0;
        let px = |x: f64| (x * k).round() as i32;
        let height = size;
        let width = size * 5 / 4;
        let diameter = (size as i32 - px(96.0)).max(16) as u32;
        Layout {
            width,
            height,
            k,
            disc_x: px(16.0),
            disc_y: px(82.0),
            diameter,
            bar_x: width as i32 - px(110.0),
            bar_width: px(18.0) as u32,
        }
    }
}

/// The colour of text and frames: near-black.
const INK: RGBColor = RGBColor(20, 20, 20);

/// Draws the hemisphere image and encodes it as PNG.
pub fn render(
    grid: &Grid,
    scale: ColorScale,
    light: Vec3,
    layout: &Layout,
    words: &Words,
) -> Result<Vec<u8>> {
    register_embedded_font()?;
    let (w, h) = (layout.width as usize, layout.height as usize);
    let mut rgb = vec![255u8; w * h * 3];
    let mut put = |x: i32, y: i32, c: RGBColor| {
        if x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h {
            let at = (y as usize * w + x as usize) * 3;
            rgb[at..at + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    };
    // The disc, pixel by pixel.
    let d = layout.diameter as usize;
    for (k, pixel) in grid.upsample(d).into_iter().enumerate() {
        if let Some(f) = pixel {
            put(
                layout.disc_x + (k % d) as i32,
                layout.disc_y + (k / d) as i32,
                scale.color(f),
            );
        }
    }
    // The colour bar's gradient, top = the scale's maximum.
    for row in 0..d {
        let t = 1.0 - row as f64 / (d - 1) as f64;
        let c = ViridisRGB.get_color(t);
        for col in 0..layout.bar_width as i32 {
            put(layout.bar_x + col, layout.disc_y + row as i32, c);
        }
    }
    // Guides over the disc, anti-aliased: rings at θr = 30° and 60°, the x and y axes, the rim.
    let r = layout.diameter as f64 / 2.0;
    let (cx, cy) = (layout.disc_x as f64 + r, layout.disc_y as f64 + r);
    let mut canvas = Canvas {
        rgb: &mut rgb,
        width: w,
        height: h,
    };
    let thin = layout.k.max(1.0);
    for theta_deg in [30.0f64, 60.0] {
        let rr = theta_deg.to_radians().sin() * r;
        canvas.stroke(cx, cy, r, thin, WHITE, 0.55, |x, y| (x.hypot(y) - rr).abs());
    }
    canvas.stroke(cx, cy, r, thin, WHITE, 0.55, |x, y| {
        if x.hypot(y) <= r {
            x.abs().min(y.abs())
        } else {
            f64::INFINITY
        }
    });
    canvas.stroke(cx, cy, r + 2.0 * thin, 1.5 * thin, INK, 1.0, |x, y| {
        (x.hypot(y) - r).abs()
    });
    {
        let backend = CrispText::new(
            BitMapBackend::with_buffer(&mut rgb, (layout.width, layout.height)),
            dejavu::sans::regular(),
        )
        .map_err(|_| anyhow!("the embedded DejaVu Sans font could not be loaded"))?;
        let root = backend.into_drawing_area();
        decorate(&root, scale, light, layout, words)?;
        root.present().map_err(plot_error)?;
    }
    encode_png(&rgb, layout.width, layout.height)
}

/// An RGB buffer to paint anti-aliased strokes into.
struct Canvas<'a> {
    rgb: &'a mut [u8],
    width: usize,
    height: usize,
}

impl Canvas<'_> {
    /// Blends `color` at opacity `alpha` into every pixel within `width / 2` of a curve given by
    /// its distance function `distance(x, y)` (pixels, relative to the centre `(cx, cy)`), over
    /// the square of half-side `reach` around the centre; coverage falls off linearly over one
    /// pixel at the stroke's edges.
    fn stroke(
        &mut self,
        cx: f64,
        cy: f64,
        reach: f64,
        width: f64,
        color: RGBColor,
        alpha: f64,
        distance: impl Fn(f64, f64) -> f64,
    ) {
        let lo_x = (cx - reach - width).floor().max(0.0) as usize;
        let hi_x = ((cx + reach + width).ceil() as usize).min(self.width);
        let lo_y = (cy - reach - width).floor().max(0.0) as usize;
        let hi_y = ((cy + reach + width).ceil() as usize).min(self.height);
        for py in lo_y..hi_y {
            for px in lo_x..hi_x {
                // Pixel centres sit at half-integer coordinates.
                let d = distance(px as f64 + 0.5 - cx, py as f64 + 0.5 - cy);
                let coverage = (0.5 * width + 0.5 - d).clamp(0.0, 1.0) * alpha;
                if coverage > 0.0 {
                    let at = (py * self.width + px) * 3;
                    for (channel, target) in [color.0, color.1, color.2].into_iter().enumerate() {
                        let old = self.rgb[at + channel] as f64;
                        self.rgb[at + channel] =
                            (old + (target as f64 - old) * coverage).round() as u8;
                    }
                }
            }
        }
    }
}

/// Text in `FONT` at `size` px, anchored at `(h, v)`, shrunk to fit `max_width` px.
fn text_style<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: f64,
    max_width: f64,
    anchor: (HPos, VPos),
    color: &'static RGBColor,
) -> Result<TextStyle<'static>> {
    let (tw, _) = area
        .estimate_text_size(text, &TextStyle::from((FONT, size).into_font()))
        .map_err(plot_error)?;
    let size = size * (max_width / tw.max(1) as f64).min(1.0);
    Ok(TextStyle::from((FONT, size).into_font())
        .color(color)
        .pos(Pos::new(anchor.0, anchor.1)))
}

/// Everything but the pixels: titles, guides, markers, axis names, colour-bar ticks.
fn decorate<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    scale: ColorScale,
    light: Vec3,
    layout: &Layout,
    words: &Words,
) -> Result<()> {
    let k = layout.k;
    let px = |x: f64| (x * k).round() as i32;
    let room = layout.width as f64 - 2.0 * px(12.0) as f64;
    let draw_text = |text: &str,
                     at: (i32, i32),
                     size: f64,
                     anchor: (HPos, VPos),
                     color: &'static RGBColor|
     -> Result<()> {
        let style = text_style(root, text, size * k, room, anchor, color)?;
        root.draw(&Text::new(text.to_string(), at, style))
            .map_err(plot_error)
    };
    let ink = INK;
    let left_top = (HPos::Left, VPos::Top);
    draw_text(&words.title, (px(12.0), px(6.0)), 18.0, left_top, &INK)?;
    draw_text(&words.setting, (px(12.0), px(31.0)), 12.5, left_top, &INK)?;
    draw_text(&words.method, (px(12.0), px(48.0)), 12.5, left_top, &INK)?;

    // The disc's frame: centre, radius, and a map from projected (x, y) to pixels.
    let r = layout.diameter as f64 / 2.0;
    let (cx, cy) = (layout.disc_x as f64 + r, layout.disc_y as f64 + r);
    let to_px = |x: f64, y: f64| ((cx + x * r).round() as i32, (cy - y * r).round() as i32);
    for theta_deg in [30.0f64, 60.0] {
        // The ring's label, down and to the left, where highlights rarely are.
        let rr = theta_deg.to_radians().sin();
        let (lx, ly) = to_px(-rr * FRAC_1_SQRT_2, -rr * FRAC_1_SQRT_2);
        draw_text(
            &format!("{theta_deg:.0}°"),
            (lx - px(2.0), ly + px(2.0)),
            10.5,
            (HPos::Right, VPos::Top),
            &WHITE,
        )?;
    }

    // The light's direction (a filled dot) and the mirror direction (a ring).
    let marker = px(6.0).max(3);
    let light_px = to_px(light.x, light.y);
    let mirror_px = to_px(-light.x, -light.y);
    root.draw(&Circle::new(light_px, marker + 1, ink.filled()))
        .map_err(plot_error)?;
    root.draw(&Circle::new(light_px, marker - 1, WHITE.filled()))
        .map_err(plot_error)?;
    root.draw(&Circle::new(
        mirror_px,
        marker + 1,
        ink.stroke_width(px(1.0).max(1) as u32),
    ))
    .map_err(plot_error)?;
    root.draw(&Circle::new(
        mirror_px,
        marker,
        WHITE.stroke_width(px(2.0).max(1) as u32),
    ))
    .map_err(plot_error)?;
    for (at, x, name) in [
        (light_px, light.x, "light"),
        (mirror_px, -light.x, words.ring),
    ] {
        // Outlined white text, toward the centre (clear of the axis names outside the rim).
        let (pos, h) = if x > 0.3 {
            (
                (at.0 - marker - px(3.0), at.1 - marker - px(1.0)),
                HPos::Right,
            )
        } else {
            (
                (at.0 + marker + px(3.0), at.1 - marker - px(1.0)),
                HPos::Left,
            )
        };
        for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
            draw_text(
                name,
                (pos.0 + dx, pos.1 + dy),
                12.0,
                (h, VPos::Bottom),
                &INK,
            )?;
        }
        draw_text(name, pos, 12.0, (h, VPos::Bottom), &WHITE)?;
    }

    // Axis names: the weft (x) to the right, the warp (y) up.
    let (right, _) = to_px(1.0, 0.0);
    let (_, top) = to_px(0.0, 1.0);
    draw_text(
        "→ x (weft)",
        (right + px(6.0), cy.round() as i32),
        13.0,
        (HPos::Left, VPos::Center),
        &INK,
    )?;
    draw_text(
        "↑ y (warp)",
        (cx.round() as i32, top - px(4.0)),
        13.0,
        (HPos::Center, VPos::Bottom),
        &INK,
    )?;

    // The colour bar: frame, ticks, labels and unit.
    let (bx, bw) = (layout.bar_x, layout.bar_width as i32);
    let (by, bh) = (layout.disc_y, layout.diameter as i32);
    root.draw(&Rectangle::new(
        [(bx, by), (bx + bw, by + bh)],
        ink.stroke_width(1),
    ))
    .map_err(plot_error)?;
    for value in scale.ticks() {
        let y = by + ((1.0 - scale.position(value)) * (bh - 1) as f64).round() as i32;
        root.draw(&PathElement::new(
            vec![(bx + bw, y), (bx + bw + px(5.0), y)],
            ink.stroke_width(1),
        ))
        .map_err(plot_error)?;
        draw_text(
            &tick_label(value),
            (bx + bw + px(8.0), y),
            11.5,
            (HPos::Left, VPos::Center),
            &INK,
        )?;
    }
    let unit = match scale {
        ColorScale::Linear { .. } => format!("{}  (sr⁻¹)", words.quantity),
        ColorScale::Log { .. } => format!("{}  (sr⁻¹, log scale)", words.quantity),
    };
    let style = TextStyle::from(
        (FONT, 13.0 * k)
            .into_font()
            .transform(FontTransform::Rotate270),
    )
    .color(&ink)
    .pos(Pos::new(HPos::Center, VPos::Center));
    root.draw(&Text::new(
        unit.to_string(),
        (layout.width as i32 - px(16.0), by + bh / 2),
        style,
    ))
    .map_err(plot_error)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_map_values_to_the_unit_interval() {
        let lin = ColorScale::new(2.0, false);
        assert_eq!(lin.position(1.0), 0.5);
        assert_eq!(lin.position(5.0), 1.0);
        assert_eq!(lin.position(f64::NAN), 0.0);
        assert_eq!(lin.ticks(), vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        let log = ColorScale::new(10.0, true);
        assert!((log.position(0.1) - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(log.position(1e-9), 0.0);
        assert_eq!(log.ticks(), vec![0.01, 0.1, 1.0, 10.0]);
        assert_eq!(ColorScale::new(0.0, false), ColorScale::Linear { max: 1.0 });
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(0.021), 0.025);
        assert_eq!(nice_step(1.0), 1.0);
    }

    #[test]
    fn the_layout_fits_the_image() {
        for size in [256, 512, 1000, 4096] {
            let l = Layout::new(size);
            assert_eq!(l.height, size);
            assert!(l.disc_y as u32 + l.diameter < size, "{l:?}");
            // The colour bar starts right of the disc and its weft label.
            assert!(
                l.disc_x + l.diameter as i32 + (70.0 * l.k) as i32 <= l.bar_x,
                "{l:?}"
            );
        }
    }
}
