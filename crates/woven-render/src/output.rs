//! Writing images: linear OpenEXR (float32 RGB) and sRGB PNG (through a [`Display`]: exposure
//! and tone map), encoded in memory and written atomically by the library's one atomic writer (a
//! temporary file in the same folder, renamed into place), so a reader never sees half a file.

use crate::render::Image;
use crate::tonemap::Display;
use crate::{Error, Result};
use std::path::Path;

/// An output format, chosen by a file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// OpenEXR, linear float32 RGB.
    Exr,
    /// PNG, 8-bit sRGB after the exposure and tone map ([`Display`]).
    Png,
}

impl Format {
    /// The format of `path` by its extension (`.exr`, `.png`, any case).
    pub fn of(path: &Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "exr" => Some(Format::Exr),
            "png" => Some(Format::Png),
            _ => None,
        }
    }
}

/// `image` encoded as `format` (a PNG through `display`: exposure, then tone map), the bytes of
/// its file: linear float32 RGB OpenEXR, or 8-bit sRGB PNG.
///
/// # Errors
/// [`Error::Image`] naming `path` (what the bytes are for) when the encoder fails.
pub fn encode(image: &Image, format: Format, display: &Display, path: &Path) -> Result<Vec<u8>> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    let failed = |message: String| Error::Image {
        path: path.to_path_buf(),
        message,
    };
    match format {
        Format::Exr => {
            use exr::prelude::{Image as ExrImage, SpecificChannels, WritableImage};
            let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
                let c = image.at(p.x(), p.y()).0;
                (c[0] as f32, c[1] as f32, c[2] as f32)
            });
            ExrImage::from_channels((image.width, image.height), channels)
                .write()
                .to_buffered(&mut bytes)
                .map_err(|e| failed(format!("cannot encode the EXR file: {e}")))?;
        }
        Format::Png => {
            let pixels: Vec<u8> = image
                .pixels
                .iter()
                .flat_map(|p| display.encode(*p))
                .collect();
            image::RgbImage::from_raw(image.width as u32, image.height as u32, pixels)
                .expect("the buffer holds width × height RGB pixels")
                .write_to(&mut bytes, image::ImageFormat::Png)
                .map_err(|e| failed(format!("cannot encode the PNG file: {e}")))?;
        }
    }
    Ok(bytes.into_inner())
}

/// Writes `image` as linear float32 RGB OpenEXR ([`write`](fn@write)).
///
/// # Errors
/// As [`write`](fn@write).
pub fn write_exr(image: &Image, path: &Path) -> Result<()> {
    write_as(image, Format::Exr, &Display::default(), path)
}

/// Writes `image` as an 8-bit sRGB PNG through `display` ([`write`](fn@write)).
///
/// # Errors
/// As [`write`](fn@write).
pub fn write_png(image: &Image, path: &Path, display: &Display) -> Result<()> {
    write_as(image, Format::Png, display, path)
}

/// Writes `image` in the format `path`'s extension names, atomically: the library's one atomic
/// writer ([`woven::fsutil::atomic_write`]: a temporary file beside `path`, renamed into place;
/// a special file such as `/dev/null` written in place; a read-only `path` refused). A front end
/// that catches signals writes [`encode`]'s bytes through its own registration instead (the
/// command line's removes the temporary file when interrupted).
///
/// # Errors
/// [`Error::InvalidSetting`] for an extension other than `.exr` or `.png`; [`Error::Image`]
/// when encoding fails; [`Error::Io`] naming `path` when it cannot be written.
pub fn write(image: &Image, path: &Path, display: &Display) -> Result<()> {
    write_as(image, format_of(path)?, display, path)
}

/// The format `path`'s extension names.
///
/// # Errors
/// [`Error::InvalidSetting`] naming `output` for an extension other than `.exr` or `.png`.
pub fn format_of(path: &Path) -> Result<Format> {
    Format::of(path).ok_or_else(|| Error::InvalidSetting {
        name: "output".into(),
        value: path.display().to_string(),
        expected: "a file name ending in .exr or .png".into(),
    })
}

fn write_as(image: &Image, format: Format, display: &Display, path: &Path) -> Result<()> {
    let bytes = encode(image, format, display, path)?;
    woven::fsutil::atomic_write(path, |w| w.write_all(&bytes)).map_err(|e| match e {
        woven::Error::Io { path, source } => Error::Io { path, source },
        e => Error::Woven(e),
    })
}
