//! Writing images: linear OpenEXR (float32 RGB) and sRGB PNG (through a [`Display`]: exposure
//! and tone map), each atomically (a temporary file
//! in the same folder, renamed into place), so a reader never sees half a file.

use crate::render::Image;
use crate::tonemap::Display;
use crate::{Error, Result};
use std::path::{Path, PathBuf};

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

/// A temporary path beside `path` (same folder, so the rename is atomic) with the same
/// extension (the EXR writer checks nothing by it, but tools watching the folder might).
fn temp_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "image".into());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// Writes the finished temporary file into place, or removes it on failure.
fn finish(tmp: &Path, path: &Path, written: std::result::Result<(), String>) -> Result<()> {
    match written {
        Ok(()) => std::fs::rename(tmp, path).map_err(|source| {
            let _ = std::fs::remove_file(tmp);
            Error::Io {
                path: path.to_path_buf(),
                source,
            }
        }),
        Err(message) => {
            let _ = std::fs::remove_file(tmp);
            Err(Error::Image {
                path: path.to_path_buf(),
                message,
            })
        }
    }
}

/// Writes `image` as linear float32 RGB OpenEXR.
///
/// # Errors
/// [`Error::Image`]/[`Error::Io`] when the file cannot be written.
pub fn write_exr(image: &Image, path: &Path) -> Result<()> {
    let tmp = temp_beside(path);
    let written = exr::prelude::write_rgb_file(&tmp, image.width, image.height, |x, y| {
        let p = image.at(x, y).0;
        (p[0] as f32, p[1] as f32, p[2] as f32)
    })
    .map_err(|e| format!("cannot write the EXR file: {e}"));
    finish(&tmp, path, written)
}

/// Writes `image` as an 8-bit sRGB PNG through `display` (exposure, then tone map).
///
/// # Errors
/// [`Error::Image`]/[`Error::Io`] when the file cannot be written.
pub fn write_png(image: &Image, path: &Path, display: &Display) -> Result<()> {
    let bytes: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|p| display.encode(*p))
        .collect();
    let tmp = temp_beside(path);
    let buffer = image::RgbImage::from_raw(image.width as u32, image.height as u32, bytes)
        .expect("the buffer holds width × height RGB pixels");
    let written = buffer
        .save_with_format(&tmp, image::ImageFormat::Png)
        .map_err(|e| format!("cannot write the PNG file: {e}"));
    finish(&tmp, path, written)
}

/// Writes `image` in the format `path`'s extension names.
///
/// # Errors
/// [`Error::InvalidSetting`] for an extension other than `.exr` or `.png`; as the writers.
pub fn write(image: &Image, path: &Path, display: &Display) -> Result<()> {
    match Format::of(path) {
        Some(Format::Exr) => write_exr(image, path),
        Some(Format::Png) => write_png(image, path, display),
        None => Err(Error::InvalidSetting {
            name: "output".into(),
            value: path.display().to_string(),
            expected: "a file name ending in .exr or .png".into(),
        }),
    }
}
