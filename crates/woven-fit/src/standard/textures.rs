//! A woven surface's layout as textures ([`LayoutImages`]), baked from the library's own
//! reading of each point ([`WovenSurface::texel`]), for renderers that lay the standard lobes of
//! each family out on the uv (Blender, OpenPBR, glTF). Two 16-bit RGB images of one tile:
//! - **layout**: the weft's share (R) and the warp's (G) of each texel; where both are 0, a hole
//!   between gapped yarns;
//! - **factors**: the weft's dye factor (R) and the warp's (G), each divided by
//!   [`FACTOR_RANGE`].
//!
//! The image's first row is the tile's top (`v` at its largest), as image files are read. A tile
//! spans [`LayoutImages::cells`] pattern cells: one repeat of the pattern, or, where the dyes vary
//! along the yarns, enough repeats that the variation does not visibly repeat
//! ([`IRREGULAR_TILE_CELLS`]).

use crate::error::FitError;
use std::path::{Path, PathBuf};
use woven::surface::WovenSurface;

/// A dye factor's texture value is the factor over this (factors above it are clipped).
pub const FACTOR_RANGE: f64 = 4.0;

/// The least cells a tile spans along each side where the dyes vary along the yarns: the
/// pattern repeated until it is at least this long.
pub const IRREGULAR_TILE_CELLS: usize = 128;

/// The most texels along a tile's side.
pub const MAX_TILE_TEXELS: usize = 2048;

/// A layout baked into images (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutImages {
    /// Pattern cells the tile spans, `[along u, along v]`.
    pub cells: [usize; 2],
    /// Texels per cell along each side.
    pub texels_per_cell: usize,
    /// The weft's and the warp's share, row-major from the top row.
    pub layout: Vec<[u16; 3]>,
    /// The encoded dye factors, likewise.
    pub factors: Vec<[u16; 3]>,
}

/// The paths [`LayoutImages::write`] writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LayoutFiles {
    /// The layout image.
    pub layout: PathBuf,
    /// The dye factors.
    pub factors: PathBuf,
}

fn unit16(x: f64) -> u16 {
    (x.clamp(0.0, 1.0) * 65535.0).round() as u16
}

impl LayoutImages {
    /// `surface`'s layout over one tile with `texels_per_cell` texels along each cell's side
    /// (fewer where the tile would exceed [`MAX_TILE_TEXELS`]), each texel read at its centre.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming `texels_per_cell` outside `[1, 64]`.
    pub fn bake(surface: &WovenSurface, texels_per_cell: usize) -> Result<LayoutImages, FitError> {
        use rayon::prelude::*;
        if !(1..=64).contains(&texels_per_cell) {
            return Err(FitError::invalid(
                "texels_per_cell",
                texels_per_cell,
                "an integer in [1, 64]",
            ));
        }
        let repeat = surface.repeat_cells();
        let cells = if surface.varying_dyes().is_some() {
            repeat.map(|r| r * IRREGULAR_TILE_CELLS.div_ceil(r))
        } else {
            repeat
        };
        let n = texels_per_cell
            .min(MAX_TILE_TEXELS / cells[0].max(cells[1]))
            .max(1);
        let [w, h] = [cells[0] * n, cells[1] * n];
        let per_unit = surface.yarns_per_unit();
        let texels: Vec<_> = (0..w * h)
            .into_par_iter()
            .map(|k| {
                let (i, row) = (k % w, k / w);
                let j = h - 1 - row;
                let uv = [
                    (i as f64 + 0.5) / (n as f64 * per_unit[0]),
                    (j as f64 + 0.5) / (n as f64 * per_unit[1]),
                ];
                surface.texel(uv)
            })
            .collect();
        Ok(LayoutImages {
            cells,
            texels_per_cell: n,
            layout: texels
                .iter()
                .map(|t| [unit16(t.weft), unit16(t.warp), 0])
                .collect(),
            factors: texels
                .iter()
                .map(|t| {
                    [
                        unit16(t.factors[0] / FACTOR_RANGE),
                        unit16(t.factors[1] / FACTOR_RANGE),
                        0,
                    ]
                })
                .collect(),
        })
    }

    /// The tile's size in texels, `[width, height]`.
    pub fn size(&self) -> [usize; 2] {
        self.cells.map(|c| c * self.texels_per_cell)
    }

    /// Writes the two images as 16-bit PNGs `STEM-layout.png` and `STEM-factors.png` in
    /// `folder`, each whole or not at all.
    ///
    /// # Errors
    /// [`FitError::Material`] holding the I/O error that names a file that cannot be written.
    pub fn write(&self, folder: &Path, stem: &str) -> Result<LayoutFiles, FitError> {
        let files = LayoutFiles {
            layout: folder.join(format!("{stem}-layout.png")),
            factors: folder.join(format!("{stem}-factors.png")),
        };
        for (path, pixels) in [
            (&files.layout, &self.layout),
            (&files.factors, &self.factors),
        ] {
            write_png16(path, self.size(), pixels)?;
        }
        Ok(files)
    }
}

/// A 16-bit RGB PNG written atomically.
fn write_png16(path: &Path, [w, h]: [usize; 2], pixels: &[[u16; 3]]) -> Result<(), FitError> {
    // The encoder takes 16-bit samples in the machine's byte order (it writes PNG's big-endian).
    let mut bytes = Vec::with_capacity(pixels.len() * 6);
    for p in pixels {
        for c in p {
            bytes.extend_from_slice(&c.to_ne_bytes());
        }
    }
    write_png(path, [w, h], &bytes, image::ColorType::Rgb16)
}

/// A PNG of `colour` samples `bytes` (row-major from the top row, 16-bit samples in the
/// machine's byte order), encoded whole and written atomically: the one encoder of the
/// standard-lobe writers' textures (these layouts, glTF's 8-bit textures).
pub(super) fn write_png(
    path: &Path,
    [w, h]: [usize; 2],
    bytes: &[u8],
    colour: image::ColorType,
) -> Result<(), FitError> {
    use image::ImageEncoder;
    let mut png = Vec::new();
    let size = |x: usize| u32::try_from(x).unwrap_or(u32::MAX);
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(bytes, size(w), size(h), colour)
        .map_err(|e| woven::Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other(e.to_string()),
        })?;
    Ok(woven::fsutil::atomic_write(path, |out| {
        out.write_all(&png)
    })?)
}
