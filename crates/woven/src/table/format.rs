//! The `.wtab` file format (version 1).
//!
//! All integers and floats little-endian.
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `b"WOVENTAB"` |
//! | 8 | 4 | format version, `u32` = 1 |
//! | 12 | 4 | header length `H`, `u32` |
//! | 16 | `H` | header: UTF-8 TOML (`symmetry`, grid axes, wavelength, the material's TOML) |
//! | 16 + H | 8 | value count `N`, `u64` (= `n_theta · n_phi · n_h²`) |
//! | 24 + H | 4N | values, `f32`, index `((iθ·n_φ + iφ)·n_h + i_y)·n_h + i_x` |
//! | 24 + H + 4N | 8 | cell count `M`, `u64` (= `n_theta · n_phi · (n_h − 1)²`) |
//! | 32 + H + 4N | 4M | sampling densities per incidence node and half-vector cell, `f32` |
//! | 32 + H + 4N + 4M | 4 | CRC-32 (IEEE) of every byte before it |
//!
//! A truncated, corrupt (checksum), wrong-magic or wrong-version file, a header that does not parse
//! or disagrees with `N`, and trailing bytes are errors naming the file and what is wrong. The
//! sampling densities are stored (computing them takes longer than loading should); the CDFs are
//! their running sums, rebuilt on load.

use super::grid::Axis;
use super::{Symmetry, Table};
use crate::error::{Error, Result};
use std::io::{Read, Write};
use std::path::Path;

/// The file's magic bytes.
pub const MAGIC: &[u8; 8] = b"WOVENTAB";
/// The format version this build writes and reads.
pub const VERSION: u32 = 2;
use super::MAX_VALUES;

fn format_error(origin: &str, message: impl Into<String>) -> Error {
    Error::Parse {
        path: origin.to_string(),
        message: format!("not a valid woven table: {}", message.into()),
    }
}

impl Table {
    /// The table serialized in the `.wtab` format.
    pub fn to_bytes(&self) -> Vec<u8> {
        let header = format!(
            "symmetry = \"{}\"\nn_theta = {}\ntheta_max = {:?}\nn_phi = {}\nn_h = {}\nwavelength_nm = {:?}\nmaterial = {}\n",
            match self.symmetry {
                Symmetry::Isotropic => "isotropic",
                Symmetry::Mirror => "mirror",
            },
            self.theta.n,
            self.theta.hi,
            self.phi.n,
            self.t.n,
            self.wavelength_nm,
            toml_string(&self.material_toml),
        );
        let mut out = Vec::with_capacity(32 + header.len() + 4 * self.values.len());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
        out.extend_from_slice(header.as_bytes());
        out.extend_from_slice(&(self.values.len() as u64).to_le_bytes());
        for v in &self.values {
            out.extend_from_slice(&v.to_le_bytes());
        }
        let cells = self.sampler.cell_pdf();
        out.extend_from_slice(&(cells.len() as u64).to_le_bytes());
        for v in cells {
            out.extend_from_slice(&v.to_le_bytes());
        }
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// Writes the table to `w`.
    ///
    /// # Errors
    /// [`Error::Io`] if writing fails.
    pub fn write(&self, mut w: impl Write, origin: &Path) -> Result<()> {
        w.write_all(&self.to_bytes()).map_err(|source| Error::Io {
            path: origin.to_path_buf(),
            source,
        })
    }

    /// Saves the table to `path` atomically: a temporary file in the same folder, renamed over
    /// `path` only once complete (a device or pipe is written in place).
    ///
    /// # Errors
    /// [`Error::Io`] if the folder is not writable or the disk is full.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        crate::fsutil::atomic_write(path.as_ref(), |w| w.write_all(&self.to_bytes()))
    }

    /// Reads a table from bytes; `origin` names the source in errors.
    ///
    /// # Errors
    /// [`Error::Parse`] for anything but a complete, intact version-1 table.
    pub fn from_bytes(bytes: &[u8], origin: &str) -> Result<Table> {
        let err = |m: &str| format_error(origin, m);
        if bytes.len() < 8 || &bytes[..8] != MAGIC {
            return Err(err("wrong magic bytes (expected WOVENTAB)"));
        }
        if bytes.len() < 16 {
            return Err(err("truncated header"));
        }
        let version = u32::from_le_bytes(bytes[8..12].try_into().unwrap());
        if version != VERSION {
            return Err(err(&format!(
                "format version {version}, this build reads version {VERSION}{}",
                if version < VERSION {
                    " (the file was written by an earlier woven; build it again with \
                     `woven tabulate`)"
                } else {
                    ""
                }
            )));
        }
        let hlen = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let after_header = 16usize
            .checked_add(hlen)
            .ok_or_else(|| err("header length overflows"))?;
        if bytes.len() < after_header + 8 + 4 {
            return Err(err("truncated (header or value count missing)"));
        }
        let count = u64::from_le_bytes(bytes[after_header..after_header + 8].try_into().unwrap());
        if count > MAX_VALUES {
            return Err(err(&format!("implausible value count {count}")));
        }
        let values_end = after_header + 8 + 4 * count as usize;
        if bytes.len() < values_end + 8 + 4 {
            return Err(err("truncated (values or cell count missing)"));
        }
        let cell_count = u64::from_le_bytes(bytes[values_end..values_end + 8].try_into().unwrap());
        if cell_count > MAX_VALUES {
            return Err(err(&format!("implausible cell count {cell_count}")));
        }
        let payload_end = values_end + 8 + 4 * cell_count as usize;
        if bytes.len() < payload_end + 4 {
            return Err(err(&format!(
                "truncated: {} bytes, expected {}",
                bytes.len(),
                payload_end + 4
            )));
        }
        if bytes.len() > payload_end + 4 {
            return Err(err(&format!(
                "{} trailing bytes",
                bytes.len() - payload_end - 4
            )));
        }
        let stored = u32::from_le_bytes(bytes[payload_end..payload_end + 4].try_into().unwrap());
        if crc32fast::hash(&bytes[..payload_end]) != stored {
            return Err(err("checksum mismatch (the file is corrupt)"));
        }
        let header = std::str::from_utf8(&bytes[16..after_header])
            .map_err(|_| err("header is not UTF-8"))?;
        let header: toml::Table = header.parse().map_err(|e| err(&format!("header: {e}")))?;
        let int = |k: &str| -> Result<usize> {
            header
                .get(k)
                .and_then(|v| v.as_integer())
                .filter(|&x| (1..=1 << 20).contains(&x))
                .map(|x| x as usize)
                .ok_or_else(|| err(&format!("header key `{k}` missing or out of range")))
        };
        let float = |k: &str| -> Result<f64> {
            header
                .get(k)
                .and_then(|v| v.as_float())
                .filter(|x| x.is_finite())
                .ok_or_else(|| err(&format!("header key `{k}` missing or not a number")))
        };
        let symmetry = match header.get("symmetry").and_then(|v| v.as_str()) {
            Some("isotropic") => Symmetry::Isotropic,
            Some("mirror") => Symmetry::Mirror,
            _ => {
                return Err(err(
                    "header key `symmetry` must be \"isotropic\" or \"mirror\"",
                ))
            }
        };
        let (n_theta, n_phi, n_h) = (int("n_theta")?, int("n_phi")?, int("n_h")?);
        let theta_max = float("theta_max")?;
        if n_theta < 2
            || n_h < 3
            || (symmetry == Symmetry::Mirror && n_phi < 2)
            || (symmetry == Symmetry::Isotropic && n_phi != 1)
        {
            return Err(err("grid dimensions are inconsistent with the symmetry"));
        }
        if !(0.0..std::f64::consts::FRAC_PI_2).contains(&theta_max) {
            return Err(err("theta_max out of range"));
        }
        // Two halves (light and view).
        let expected = 2 * (n_theta * n_phi * n_h * n_h) as u64;
        if expected != count {
            return Err(err(&format!(
                "{count} values, but the grid needs {expected}"
            )));
        }
        let expected_cells = (n_theta * n_phi * (n_h - 1) * (n_h - 1)) as u64;
        if expected_cells != cell_count {
            return Err(err(&format!(
                "{cell_count} cells, but the grid needs {expected_cells}"
            )));
        }
        let cell_pdf: Vec<f32> = bytes[values_end + 8..payload_end]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        if cell_pdf.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(err("negative or non-finite sampling densities"));
        }
        let values: Vec<f32> = bytes[after_header + 8..values_end]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        if values.iter().any(|v| !v.is_finite()) {
            return Err(err("non-finite values"));
        }
        let material = header
            .get("material")
            .and_then(|v| v.as_str())
            .unwrap_or("")
            .to_string();
        let wavelength_nm = float("wavelength_nm")?;
        Ok(Table::assemble(
            symmetry,
            Axis {
                lo: 0.0,
                hi: theta_max,
                n: n_theta,
                grading: super::THETA_GRADING,
            },
            Axis::uniform(0.0, std::f64::consts::FRAC_PI_2, n_phi),
            Axis::uniform(-1.0, 1.0, n_h),
            values,
            material,
            wavelength_nm,
            Some(cell_pdf),
        ))
    }

    /// Loads a table file.
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be read; [`Error::Parse`] as [`from_bytes`](Self::from_bytes).
    pub fn load(path: impl AsRef<Path>) -> Result<Table> {
        let path = path.as_ref();
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|mut f| f.read_to_end(&mut bytes))
            .map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        Table::from_bytes(&bytes, &path.display().to_string())
    }
}

/// A TOML basic string literal of `s`.
fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}
