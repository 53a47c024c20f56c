//! Measured reflectance: one type, [`Dataset`], whatever file it came from.
//!
//! Directions follow the rest of woven: `theta_i, phi_i` is the direction toward the light (the
//! paper's s), `theta_r, phi_r` the direction toward the viewer (v), polar angles from the macro
//! normal and azimuths from the weft (x) axis, in radians. Values are BRDFs in sr⁻¹ (f without the
//! cosine), or relatively calibrated ones when [`Dataset::relative`] says so.
//!
//! [`load`] reads any supported file, choosing the reader from the file's content:
//!
//! | format | reader | recognised by | values |
//! |---|---|---|---|
//! | the fitter CSV `theta_i,phi_i,theta_r,phi_r,value[,weight]` (or `value_r,value_g,value_b`) | [`fitcsv`] | its header | BRDF, sr⁻¹ (`# relative = true` marks relative ones) |
//! | the goniometer CSV of `woven gonio` | [`gonio`] | its header | radiance ÷ cos θi → BRDF |
//! | the grids `*.grid.csv` (RGL felts, NBRDF fits of MERL/RGL/DTU) | [`grid`] | its header | BRDF, RGB |
//! | CUReT `abrdf.dat` (+ `table.txt` beside it), CUReT long-format CSV | [`curet`] | the `.dat` name; the header | relative |
//! | RGL `.bsdf` (RGB tensor file) | [`rgl_bsdf`] | its magic bytes | evaluated on the grid of the `*.grid.csv` files, RGB |
//! | NBRDF network `*.nbrdf.json` (MERL, RGL, DTU) | [`nbrdf`] | the `.json` name | evaluated on the same grid, RGB |
//!
//! Rules common to every reader:
//! - a row whose light or view direction is at or below the horizon (`θ ≥ π/2`) is dropped and
//!   counted in [`Dataset::dropped_below_horizon`];
//! - a field that is not a finite number, a polar angle outside `[0, π]`, a negative value or
//!   weight is an error ([`DataError::Parse`]) naming the file, the line and the column — nothing
//!   is dropped silently, and no input makes a reader panic;
//! - files holding several materials (CUReT) take a selector after `#`:
//!   `data/curet/abrdf.dat#linen`; [`load_all`] reads every material of a file.
//!
//! [`bundled`] lists the real measurements copied into the repository's `data/` folder, and
//! [`published`] reads (and evaluates) the published SGD and ABC fits of the MERL materials.

mod bundled;
pub mod curet;
mod error;
pub mod fitcsv;
pub mod gonio;
pub mod grid;
pub mod nbrdf;
pub mod published;
pub mod rgl_bsdf;
mod rows;

pub use bundled::{bundled, data_dir, Bundled, Family};
pub use error::DataError;

use std::path::{Path, PathBuf};

/// A measured value: one channel, or red, green and blue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A single channel (a luminance or an average of channels).
    Mono(f64),
    /// Red, green and blue.
    Rgb([f64; 3]),
}

/// One measurement: a pair of directions, the value there and its weight in the fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Polar angle of the direction toward the light, radians.
    pub theta_i: f64,
    /// Azimuth of the direction toward the light, radians from the weft (x) axis.
    pub phi_i: f64,
    /// Polar angle of the direction toward the viewer, radians.
    pub theta_r: f64,
    /// Azimuth of the direction toward the viewer, radians from the weft (x) axis.
    pub phi_r: f64,
    /// The BRDF there, sr⁻¹ (or relative units; see [`Dataset::relative`]).
    pub value: Value,
    /// Weight of the sample in the objective (1 unless the file gives one).
    pub weight: f64,
}

/// A set of measurements of one material.
#[derive(Clone, Debug)]
pub struct Dataset {
    /// A short name (the file's stem unless the format names the material).
    pub name: String,
    /// Where it came from (the file).
    pub source: PathBuf,
    /// The measurements above the horizon, in file order.
    pub samples: Vec<Sample>,
    /// Rows dropped because a direction was at or below the horizon.
    pub dropped_below_horizon: usize,
    /// True when the values are calibrated only up to an unknown factor (a fit then frees an
    /// overall scale by default).
    pub relative: bool,
}

/// The kinds of file [`load`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Format {
    /// The fitter CSV ([`fitcsv`]).
    FitCsv,
    /// The goniometer CSV of `woven gonio` ([`gonio`]).
    Gonio,
    /// An isotropic RGB grid, `*.grid.csv` ([`grid`]).
    Grid,
    /// CUReT `abrdf.dat` with `table.txt` beside it ([`curet::read_dat`]).
    CuretDat,
    /// The CUReT long-format CSV ([`curet::read_csv`]).
    CuretCsv,
    /// An RGL `.bsdf` tensor file ([`rgl_bsdf`]).
    RglBsdf,
    /// An NBRDF network, `*.nbrdf.json` ([`nbrdf`]).
    Nbrdf,
}

impl Format {
    /// A short name for messages and listings.
    pub fn name(self) -> &'static str {
        match self {
            Format::FitCsv => "fitter CSV",
            Format::Gonio => "goniometer CSV",
            Format::Grid => "BRDF grid CSV",
            Format::CuretDat => "CUReT abrdf.dat",
            Format::CuretCsv => "CUReT long-format CSV",
            Format::RglBsdf => "RGL .bsdf",
            Format::Nbrdf => "NBRDF network",
        }
    }
}

/// Splits `FILE#SELECTOR` when `path` itself does not exist and its file name holds a `#`.
fn split_selector(path: &Path) -> (PathBuf, Option<String>) {
    if path.exists() {
        return (path.to_path_buf(), None);
    }
    let text = path.to_string_lossy();
    match text.rsplit_once('#') {
        Some((file, selector)) if !file.is_empty() && !selector.contains('/') => {
            (PathBuf::from(file), Some(selector.to_string()))
        }
        _ => (path.to_path_buf(), None),
    }
}

/// The format of `bytes`, the contents of `path`: by its magic bytes, its name, then its CSV
/// header.
fn detect(path: &Path, bytes: &[u8]) -> Result<Format, DataError> {
    if bytes.starts_with(rgl_bsdf::MAGIC) {
        return Ok(Format::RglBsdf);
    }
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if name.ends_with(".dat") {
        return Ok(Format::CuretDat);
    }
    if name.ends_with(".bsdf") {
        return Ok(Format::RglBsdf);
    }
    if name.ends_with(".json") {
        return Ok(Format::Nbrdf);
    }
    if name == "table.txt" {
        return Err(rows::format_error(
            path,
            "the CUReT geometry table: load the values, `abrdf.dat#SAMPLE`, with table.txt beside it",
        ));
    }
    // The header: the first line that is neither empty nor a comment.
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(1 << 16)]);
    let header = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap_or("");
    let columns: Vec<&str> = header.split(',').map(str::trim).collect();
    let has = |c: &str| columns.contains(&c);
    Ok(if has("radiance") && has("azimuth_deg") {
        Format::Gonio
    } else if has("theta_i_deg") && has("phi_rel_deg") {
        Format::Grid
    } else if has("brdf_avg_rgb") {
        Format::CuretCsv
    } else if has("rhoD_r") || has("kD_r") {
        return Err(rows::format_error(
            path,
            "a table of published SGD/ABC fits, not measurements (read it with \
             woven_fit::data::published)",
        ));
    } else {
        Format::FitCsv
    })
}

/// The datasets in `path` (all, or the one `selector` picks), and the file's format.
fn read_any(path: &Path, selector: Option<&str>) -> Result<(Vec<Dataset>, Format), DataError> {
    let bytes = rows::read_file(path)?;
    let format = detect(path, &bytes)?;
    let single = |d: Dataset| -> Result<Vec<Dataset>, DataError> {
        match selector {
            Some(s) if s != d.name => Err(rows::format_error(
                path,
                format!(
                    "selector `#{}`, but a {} holds one material, `{}`",
                    rows::shorten(s),
                    format.name(),
                    d.name
                ),
            )),
            _ => Ok(vec![d]),
        }
    };
    let sets = match format {
        Format::FitCsv => single(fitcsv::read(path, &bytes)?)?,
        Format::Gonio => single(gonio::read(path, &bytes)?)?,
        Format::Grid => single(grid::read(path, &bytes)?)?,
        Format::RglBsdf => single(rgl_bsdf::read(path, &bytes)?)?,
        Format::Nbrdf => single(nbrdf::read(path, &bytes)?)?,
        Format::CuretCsv => curet::read_csv(path, &bytes, selector)?,
        Format::CuretDat => {
            let table = path.with_file_name("table.txt");
            let table_bytes = rows::read_file(&table)?;
            curet::read_dat(path, &bytes, &table, &table_bytes, selector)?
        }
    };
    Ok((sets, format))
}

/// Reads the measurements of one material from `path`, whatever its format (see the module's
/// table). A file that holds several materials (CUReT) needs a selector: `abrdf.dat#44`,
/// `abrdf.dat#linen`.
///
/// ```
/// use woven_fit::data::{self, Value};
///
/// // CUReT's linen (sample 44) in the repository's data/ folder: 205 measurements, relative.
/// let path = data::data_dir().join("curet/abrdf.dat#linen");
/// let linen = data::load(&path)?;
/// assert_eq!((linen.name.as_str(), linen.samples.len()), ("curet-44-linen", 205));
/// assert!(linen.relative);
/// // The first measurement: light at θi = 78.75°, viewer at θr = 79.6°, BRDF 0.156 (relative).
/// let s = linen.samples[0];
/// assert!((s.theta_i.to_degrees() - 78.75).abs() < 0.01);
/// assert_eq!(s.value, Value::Mono(0.156));
/// # Ok::<(), woven_fit::data::DataError>(())
/// ```
///
/// # Errors
/// [`DataError::Io`] when the file cannot be read; [`DataError::Format`] when it is not a
/// measurement file, or holds several materials and no selector picks one;
/// [`DataError::Parse`] naming the line and the column of a bad row.
pub fn load(path: &Path) -> Result<Dataset, DataError> {
    let (file, selector) = split_selector(path);
    if selector.is_none() {
        // A file of several materials is refused before its values are read.
        let names = materials(&file)?;
        if names.len() > 1 {
            let format = format_of(&file)?;
            let shown: Vec<&str> = names.iter().take(12).map(String::as_str).collect();
            return Err(rows::format_error(
                &file,
                format!(
                    "a {} with {} materials: pick one with FILE#NUMBER or FILE#NAME ({}{})",
                    format.name(),
                    names.len(),
                    shown.join(", "),
                    if names.len() > 12 { ", …" } else { "" }
                ),
            ));
        }
    }
    let (mut sets, _) = read_any(&file, selector.as_deref())?;
    Ok(sets.remove(0))
}

/// The names of the materials in `path` ([`Dataset::name`] of each), without reading the values
/// of a file of several (CUReT); a file of one material is read whole.
///
/// # Errors
/// As [`load`].
pub fn materials(path: &Path) -> Result<Vec<String>, DataError> {
    let (file, selector) = split_selector(path);
    let bytes = rows::read_file(&file)?;
    match (detect(&file, &bytes)?, selector) {
        (Format::CuretDat, None) => curet::list_dat(&file, &bytes),
        (Format::CuretCsv, None) => curet::list_csv(&file, &bytes),
        (_, selector) => Ok(read_any(&file, selector.as_deref())?
            .0
            .into_iter()
            .map(|d| d.name)
            .collect()),
    }
}

/// Reads every material in `path` (one for most formats; each sample of a CUReT file), or the one
/// a `#SELECTOR` picks.
///
/// # Errors
/// As [`load`].
pub fn load_all(path: &Path) -> Result<Vec<Dataset>, DataError> {
    let (file, selector) = split_selector(path);
    read_any(&file, selector.as_deref()).map(|(sets, _)| sets)
}

/// The format [`load`] would read `path` as (after a `#SELECTOR` is split off).
///
/// # Errors
/// [`DataError::Io`] when the file cannot be read, [`DataError::Format`] for a file no reader
/// takes.
pub fn format_of(path: &Path) -> Result<Format, DataError> {
    let (file, _) = split_selector(path);
    let bytes = rows::read_file(&file)?;
    detect(&file, &bytes)
}
