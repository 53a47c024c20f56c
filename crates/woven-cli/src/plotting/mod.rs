//! Drawing for the commands that plot (`woven plot`, `woven gonio`'s job, `woven fit --plot`):
//! the image formats, SVG and PNG rendering of any [`Drawing`] with the embedded font, PNG
//! encoding, axis labels; the paper's curve figures are drawn by [`figure`].
//!
//! Text is laid out (and, for PNG, rasterized by [`glyphs`]) with the DejaVu Sans font embedded in
//! the binary, so plots render the same on a machine without any system fonts.

pub mod figure;
pub mod glyphs;

use anyhow::{anyhow, bail, Context, Result};
use glyphs::CrispText;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::Path;
use std::sync::OnceLock;

/// The image formats the plots are written in.
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

/// A picture that draws itself onto a drawing area of any plotters backend.
pub trait Drawing {
    /// Draws onto `root` (the whole picture).
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>;
}

/// Okabe–Ito colours: distinguishable with every common colour-vision deficiency.
pub const COLORS: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

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
