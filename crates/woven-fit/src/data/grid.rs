//! The dense grids of isotropic RGB BRDFs (`*.grid.csv`): the RGL felts evaluated with RGL's
//! reference loader, and the NBRDF fits of MERL, RGL and DTU materials (data/README.md).
//!
//! Header `theta_i_deg,theta_o_deg,phi_rel_deg,fr_r,fr_g,fr_b`: the light at `θi` in the x–z plane
//! (`φi = 0`), the viewer at `θo` and azimuth `φo = φ_rel` (180° is the forward, specular side),
//! angles in degrees, `f_r` in sr⁻¹ (linear RGB, without the cosine). The materials are isotropic,
//! so the azimuths are relative: a fit of an anisotropic model to them should free the weave's
//! in-plane rotation or average over it.
//!
//! The grids of the source run over `θi, θo ∈ {0, 5, …, 80}°` and `φ_rel ∈ {0, 15, …, 180}°`,
//! 3757 rows. At `θi = 0` or `θo = 0` the 13 azimuths name the same pair of directions: the
//! reader keeps every row as the file gives it (such pairs weigh 13 times in an unweighted fit).

use super::rows::{directives, stem, Cell, Collector, CsvTable};
use super::{DataError, Dataset, Value};
use std::path::Path;

/// The grid header.
pub const HEADER: &str = "theta_i_deg,theta_o_deg,phi_rel_deg,fr_r,fr_g,fr_b";

const EXPECTED: &str = "the grid CSV has theta_i_deg,theta_o_deg,phi_rel_deg,fr_r,fr_g,fr_b";

/// Reads a grid CSV in `bytes` (the contents of `path`). The name is the file's stem without
/// `.grid`; the values are absolute (`relative = false`) unless a `# relative = true` directive
/// says otherwise.
///
/// # Errors
/// [`DataError::Format`] for a missing column, [`DataError::Parse`] naming the line and column of
/// the first bad field.
pub fn read(path: &Path, bytes: &[u8]) -> Result<Dataset, DataError> {
    let text = String::from_utf8_lossy(bytes);
    let d = directives(path, &text)?;
    let mut table = CsvTable::new(path, bytes)?;
    let cols = [
        table.require("theta_i_deg", EXPECTED)?,
        table.require("theta_o_deg", EXPECTED)?,
        table.require("phi_rel_deg", EXPECTED)?,
        table.require("fr_r", EXPECTED)?,
        table.require("fr_g", EXPECTED)?,
        table.require("fr_b", EXPECTED)?,
    ];
    let headers = table.headers.clone();
    let mut out = Collector::new();
    while let Some((line, record)) = table.next_record()? {
        let cell = |k: usize| Cell {
            path,
            line,
            column: &headers[cols[k]],
        };
        let field = |k: usize| record.get(cols[k]).unwrap_or("");
        let theta_i = cell(0).polar_deg(field(0))?;
        let theta_r = cell(1).polar_deg(field(1))?;
        let phi_rel_deg = cell(2).number(field(2))?;
        if phi_rel_deg.abs() > 720.0 {
            return Err(cell(2).error(format!(
                "relative azimuth {phi_rel_deg}° outside [-720°, 720°]"
            )));
        }
        let rgb = [
            cell(3).value(field(3))?,
            cell(4).value(field(4))?,
            cell(5).value(field(5))?,
        ];
        out.push(super::rows::sample(
            theta_i,
            0.0,
            theta_r,
            phi_rel_deg.to_radians(),
            Value::Rgb(rgb),
        ));
    }
    let name = d.name.unwrap_or_else(|| {
        let s = stem(path);
        s.strip_suffix(".grid").map(str::to_string).unwrap_or(s)
    });
    out.finish(path, name, d.relative.unwrap_or(false))
}
