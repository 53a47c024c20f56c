//! The `.wtab` file format (version 3; version 2, without `parts`, still reads).
//!
//! All integers and floats little-endian.
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `b"WOVENTAB"` |
//! | 8 | 4 | format version, `u32` = 3 |
//! | 12 | 4 | header length `H`, `u32` |
//! | 16 | `H` | header: UTF-8 TOML (`symmetry`, grid axes, wavelength, `parts`, `exact_regions` (absent: true), the material's TOML) |
//! | 16 + H | 8 | value count `N`, `u64` (= `parts · 2 · n_theta · n_phi · n_h²`) |
//! | 24 + H | 4N | values, `f32`: `f` at every node as [`Table::values`], then with `parts = 2` `∂f/∂ρ0` ([`Table::body_values`]) |
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
use crate::fiber::WAVELENGTH_RANGE_NM;
use std::io::{Read, Write};
use std::path::Path;

/// The file's magic bytes.
pub const MAGIC: &[u8; 8] = b"WOVENTAB";
/// The format version this build writes and reads.
pub const VERSION: u32 = 3;
/// The oldest format version this build reads.
pub const OLDEST_VERSION: u32 = 2;
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
            "symmetry = \"{}\"\nn_theta = {}\ntheta_max = {:?}\nn_phi = {}\nn_h = {}\nwavelength_nm = {:?}\nparts = {}\nexact_regions = {}\ncrown_deg = {:?}\nmaterial = {}\n",
            match self.symmetry {
                Symmetry::Isotropic => "isotropic",
                Symmetry::Mirror => "mirror",
            },
            self.theta.n,
            self.theta.hi,
            self.phi.n,
            self.t.n,
            self.wavelength_nm,
            match (&self.colour, self.crown_values()) {
                (None, _) => 1,
                (Some(_), None) => 2,
                (Some(_), Some(_)) => 3,
            },
            self.exact.is_some(),
            self.crown_deg,
            toml_string(
                &self
                    .material()
                    .map_or_else(String::new, |m| m.to_self_contained_toml_string())
            ),
        );
        let mut out = Vec::with_capacity(32 + header.len() + 4 * self.values.len());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
        out.extend_from_slice(header.as_bytes());
        let body = self.body_values().unwrap_or(&[]);
        let crown = self.crown_values().unwrap_or(&[]);
        let count = self.values.len() + body.len() + crown.len();
        out.extend_from_slice(&(count as u64).to_le_bytes());
        for v in self.values.iter().chain(body).chain(crown) {
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
    /// [`Error::Parse`] for anything but a complete, intact table of a version this build reads.
    pub fn from_bytes(bytes: &[u8], origin: &str) -> Result<Table> {
        let err = |m: &str| format_error(origin, m);
        if bytes.len() < 8 || &bytes[..8] != MAGIC {
            return Err(err("wrong magic bytes (expected WOVENTAB)"));
        }
        if bytes.len() < 16 {
            return Err(err("truncated header"));
        }
        let version = u32::from_le_bytes(bytes[8..12].try_into().unwrap());
        if !(OLDEST_VERSION..=VERSION).contains(&version) {
            return Err(err(&format!(
                "format version {version}, this build reads version {VERSION}{}",
                if version < OLDEST_VERSION {
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
        let toml_header: toml::Table = header.parse().map_err(|e| err(&format!("header: {e}")))?;
        let header = check_header(&toml_header, count, cell_count).map_err(|m| err(&m))?;
        let Header {
            symmetry,
            n_theta,
            n_phi,
            n_h,
            theta_max,
            wavelength_nm,
            parts,
            exact_regions,
            crown_deg,
        } = header;
        let cell_pdf: Vec<f32> = bytes[values_end + 8..payload_end]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        if cell_pdf.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(err("negative or non-finite sampling densities"));
        }
        if cell_pdf.iter().all(|&v| v == 0.0) {
            return Err(err(
                "every sampling density is zero (a built table has positive densities)",
            ));
        }
        let mut values: Vec<f32> = bytes[after_header + 8..values_end]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        let mut body = values.split_off(values.len() / parts);
        let crown = (parts == 3).then(|| body.split_off(body.len() / 2));
        if values.iter().any(|v| !v.is_finite()) {
            return Err(err("non-finite values"));
        }
        let text = toml_header
            .get("material")
            .and_then(|v| v.as_str())
            .unwrap_or("");
        let material = crate::material::Material::from_toml_str(text, origin)
            .map_err(|e| err(&format!("its recorded material does not parse: {e}")))?;
        let colour = (parts >= 2).then(|| super::Colour {
            crown,
            ..super::Colour::new(&material, body)
        });
        // Single-orientation yarns keep the exact model for near-forward pairs
        // (`FORWARD_EXACT`); the material was checked as it parsed, so it builds.
        let model = material
            .build(wavelength_nm)
            .map_err(|e| err(&format!("its recorded material does not build: {e}")))?;
        let mut table = Table::assemble(
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
            Some(super::Provenance {
                material,
                wavelength_nm,
            }),
            wavelength_nm,
            Some(cell_pdf),
            colour,
            exact_regions.then_some(&model),
        );
        table.crown_deg = crown_deg;
        Ok(table)
    }

    /// Loads a table file.
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be read; [`Error::Parse`] if it is not a regular file (a
    /// folder, a device, a pipe), or as [`from_bytes`](Self::from_bytes).
    pub fn load(path: impl AsRef<Path>) -> Result<Table> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        // A regular file only (a pipe with no writer would block the open); its length is
        // bounded by its own counts as it is read.
        let (file, _) = crate::fsutil::open_regular(path, u64::MAX, "a table")?;
        let bytes = read_bounded(file, &origin).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Table::from_bytes(&bytes?, &origin)
    }
}

/// The longest header accepted, in bytes: the material's TOML with a full-size WIF pattern
/// written out as a matrix stays below it.
const MAX_HEADER_BYTES: u64 = 64 << 20;

/// Reads one table file from `r`, section by section, never more than its own counts announce
/// (each bounded by [`MAX_HEADER_BYTES`] or `MAX_VALUES`), and at most one byte past its end:
/// an endless stream (`/dev/zero`, a pipe) is refused at its first wrong field, not read to the
/// end. The outer error is an I/O failure; the inner one a format error for
/// [`Table::from_bytes`]'s messages, with the bytes read so far when the stream ends early.
fn read_bounded(mut r: impl Read, origin: &str) -> std::io::Result<Result<Vec<u8>>> {
    let mut bytes = Vec::new();
    // Appends up to `n` more bytes; false when the stream ended first.
    let mut more = |bytes: &mut Vec<u8>, n: u64| -> std::io::Result<bool> {
        let want = bytes.len() + n as usize;
        (&mut r).take(n).read_to_end(bytes)?;
        Ok(bytes.len() == want)
    };
    let u64_at =
        |bytes: &[u8], at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
    if !more(&mut bytes, 16)? || &bytes[..8] != MAGIC {
        // Short or foreign: from_bytes names what is wrong.
        return Ok(Ok(bytes));
    }
    let hlen = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as u64;
    if hlen > MAX_HEADER_BYTES {
        return Ok(Err(format_error(
            origin,
            format!("header of {hlen} bytes, more than the {MAX_HEADER_BYTES} accepted"),
        )));
    }
    if !more(&mut bytes, hlen + 8)? {
        return Ok(Ok(bytes));
    }
    let count = u64_at(&bytes, bytes.len() - 8);
    if count > MAX_VALUES {
        return Ok(Err(format_error(
            origin,
            format!("implausible value count {count}"),
        )));
    }
    if !more(&mut bytes, 4 * count + 8)? {
        return Ok(Ok(bytes));
    }
    let cells = u64_at(&bytes, bytes.len() - 8);
    if cells > MAX_VALUES {
        return Ok(Err(format_error(
            origin,
            format!("implausible cell count {cells}"),
        )));
    }
    // The densities, the CRC, and one byte more to tell trailing bytes from the end.
    more(&mut bytes, 4 * cells + 4 + 1)?;
    Ok(Ok(bytes))
}

/// The checked header of a table file.
#[derive(Debug)]
struct Header {
    symmetry: Symmetry,
    n_theta: usize,
    n_phi: usize,
    n_h: usize,
    theta_max: f64,
    wavelength_nm: f64,
    parts: usize,
    exact_regions: bool,
    crown_deg: f64,
}

/// The wavelengths a table may hold, nm: those a fiber can be prepared at (`Fiber::new`).
const WAVELENGTH_NM: (f64, f64) = (WAVELENGTH_RANGE_NM[0], WAVELENGTH_RANGE_NM[1]);
/// The smallest `theta_max`, degrees: that of `TableOptions::validate`.
const MIN_THETA_MAX_DEG: f64 = 1.0;

/// Checks a table's header against itself and against the stored value and cell counts; the
/// message says which key is wrong, its value and what it must be.
///
/// A file whose checksum is right can still hold a header no build writes (edited, or from a
/// buggy writer): every key is checked here, so that a loaded table evaluates finite numbers.
fn check_header(header: &toml::Table, count: u64, cell_count: u64) -> Result<Header, String> {
    let int = |k: &str, lo: usize, hi: usize| -> Result<usize, String> {
        match header.get(k) {
            None => Err(format!("header key `{k}` is missing")),
            Some(v) => match v.as_integer() {
                Some(x) if (lo as i64..=hi as i64).contains(&x) => Ok(x as usize),
                _ => Err(format!(
                    "header key `{k}` = {v}: expected an integer in [{lo}, {hi}]"
                )),
            },
        }
    };
    let float = |k: &str, lo: f64, hi: f64| -> Result<f64, String> {
        match header.get(k) {
            None => Err(format!("header key `{k}` is missing")),
            Some(v) => match v.as_float() {
                Some(x) if x.is_finite() && x >= lo && x <= hi => Ok(x),
                _ => Err(format!(
                    "header key `{k}` = {v}: expected a number in [{lo}, {hi}]"
                )),
            },
        }
    };
    let symmetry = match header.get("symmetry").and_then(|v| v.as_str()) {
        Some("isotropic") => Symmetry::Isotropic,
        Some("mirror") => Symmetry::Mirror,
        _ => return Err("header key `symmetry` must be \"isotropic\" or \"mirror\"".into()),
    };
    // The ranges `TableOptions::validate` admits (n_h up to 4097 for either symmetry).
    let n_theta = int("n_theta", 2, 1024)?;
    let n_phi = match symmetry {
        Symmetry::Isotropic => int("n_phi", 1, 1)?,
        Symmetry::Mirror => int("n_phi", 2, 1024)?,
    };
    let n_h = int("n_h", 3, 4097)?;
    // Strictly below π/2: the grid's last node must stay above the horizon.
    let theta_max = float(
        "theta_max",
        MIN_THETA_MAX_DEG.to_radians(),
        std::f64::consts::FRAC_PI_2,
    )?;
    if theta_max >= std::f64::consts::FRAC_PI_2 {
        return Err(format!(
            "header key `theta_max` = {theta_max}: expected less than π/2"
        ));
    }
    let wavelength_nm = float("wavelength_nm", WAVELENGTH_NM.0, WAVELENGTH_NM.1)?;
    // Absent in version 2: `f` only.
    let parts = match header.get("parts") {
        None => 1,
        Some(_) => int("parts", 1, 3)?,
    };
    // Absent before crowned tables: none.
    let crown_deg = match header.get("crown_deg") {
        None => 0.0,
        Some(_) => float("crown_deg", 0.0, super::options::MAX_CROWN_DEG)?,
    };
    // `parts` = 3 holds an interreflection factor per node: a crowned table's (`crown_deg` > 0)
    // or a tilted float's (`Table::tilted`, of a plain table or a crowned one).
    // Absent before it was an option: kept (a single-orientation yarn's table then keeps it).
    let exact_regions = match header.get("exact_regions") {
        None => true,
        Some(toml::Value::Boolean(b)) => *b,
        Some(v) => {
            return Err(format!(
                "header key `exact_regions` = {v}: expected true or false"
            ))
        }
    };
    match header.get("material").map(|v| v.as_str()) {
        None => return Err("header key `material` is missing".into()),
        Some(None) => return Err("header key `material` is not a string".into()),
        Some(Some(m)) if m.trim().is_empty() => {
            return Err("header key `material` is empty: a table records its material".into())
        }
        Some(Some(_)) => {}
    }
    // The counts, in u64 (each factor is at most 4097, so no product overflows); the values
    // fill two halves (light and view).
    let incidences = (n_theta * n_phi) as u64;
    let expected = parts as u64 * 2 * incidences * (n_h * n_h) as u64;
    if expected != count {
        return Err(format!("{count} values, but the grid needs {expected}"));
    }
    let expected_cells = incidences * ((n_h - 1) * (n_h - 1)) as u64;
    if expected_cells != cell_count {
        return Err(format!(
            "{cell_count} cells, but the grid needs {expected_cells}"
        ));
    }
    Ok(Header {
        symmetry,
        n_theta,
        n_phi,
        n_h,
        theta_max,
        wavelength_nm,
        parts,
        exact_regions,
        crown_deg,
    })
}

/// A TOML basic string literal of `s`.
fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}
