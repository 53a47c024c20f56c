//! CUReT (Dana, van Ginneken, Nayar, Koenderink 1999): 61 real surfaces, each measured at the
//! same 205 light/view pairs; values averaged over the sample patch and over R, G and B.
//!
//! Two forms of the same data:
//! - `abrdf.dat` (one row per sample: its number, then the 205 values in measurement order) with
//!   `table.txt` beside it (205 rows `meas theta_v phi_v theta_i phi_i`, radians, view first);
//! - the long-format CSV `sample,name,meas,theta_v_rad,phi_v_rad,theta_i_rad,phi_i_rad,brdf_avg_rgb`
//!   (one row per measurement, the textile samples only).
//!
//! Both hold several materials: pick one with a selector, `abrdf.dat#44`, `abrdf.dat#linen`
//! ([`super::load`]), or read them all ([`super::load_all`]). Values are calibrated against a
//! reference card, so only up to a factor: every CUReT dataset has `relative = true`. The
//! azimuths are those of CUReT's sample frame; the weft's direction in it is not recorded, so a
//! fit frees the weave's in-plane rotation.

use super::rows::{format_error, parse_error, sample, Cell, Collector, CsvTable};
use super::{DataError, Dataset, Value};
use std::path::Path;

/// The CUReT textile samples: number and name. The names follow the CUReT sample list; sample 29
/// is sample 2 (polyester) imaged zoomed in.
pub const TEXTILES: [(u32, &str); 11] = [
    (1, "felt"),
    (2, "polyester"),
    (3, "terrycloth"),
    (7, "velvet"),
    (18, "rug_a"),
    (19, "rug_b"),
    (22, "lambswool"),
    (29, "polyester_zoomed"),
    (42, "corduroy"),
    (44, "linen"),
    (46, "cotton"),
];

/// The number of measurements per sample in CUReT.
pub const MEASUREMENTS: usize = 205;

/// The name of CUReT sample `number` when it is a textile.
pub fn textile_name(number: u32) -> Option<&'static str> {
    TEXTILES.iter().find(|t| t.0 == number).map(|t| t.1)
}

/// The dataset name of sample `number`: `curet-44-linen`, or `curet-04` for a non-textile.
pub fn dataset_name(number: u32) -> String {
    match textile_name(number) {
        Some(name) => format!("curet-{number:02}-{name}"),
        None => format!("curet-{number:02}"),
    }
}

/// Whether `selector` names sample `number` (whose name in the file, if any, is `file_name`):
/// its number (`44`, `044`), its name (`linen`, any case) or its dataset name (`curet-44-linen`).
fn matches(selector: &str, number: u32, file_name: Option<&str>) -> bool {
    let s = selector.trim().to_ascii_lowercase();
    if s.parse::<u32>().ok() == Some(number) {
        return true;
    }
    if s == dataset_name(number) {
        return true;
    }
    let names = [textile_name(number), file_name];
    names.iter().flatten().any(|n| n.to_ascii_lowercase() == s)
}

/// The sample number in the first field of a row of `abrdf.dat` or the long CSV.
fn sample_number(cell: Cell<'_>, text: &str) -> Result<u32, DataError> {
    let n = cell.number(text)?;
    if n.fract() != 0.0 || !(1.0..=1000.0).contains(&n) {
        return Err(cell.error(format!("sample number {n} is not an integer in [1, 1000]")));
    }
    Ok(n as u32)
}

/// The dataset names of the samples in `abrdf.dat` (contents `bytes`), in file order, without
/// reading their values.
///
/// # Errors
/// [`DataError::Parse`] for a bad sample number.
pub fn list_dat(path: &Path, bytes: &[u8]) -> Result<Vec<String>, DataError> {
    let text = String::from_utf8_lossy(bytes);
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        if let Some(first) = line.split_whitespace().next() {
            let cell = Cell {
                path,
                line: k as u64 + 1,
                column: "sample",
            };
            out.push(dataset_name(sample_number(cell, first)?));
        }
    }
    Ok(out)
}

/// The dataset names of the samples in the long-format CSV (contents `bytes`), in the order of
/// their first rows, without reading their values.
///
/// # Errors
/// As [`read_csv`], for the header and the `sample` column.
pub fn list_csv(path: &Path, bytes: &[u8]) -> Result<Vec<String>, DataError> {
    let mut table = CsvTable::new(path, bytes)?;
    let col = table.require("sample", "the CUReT long-format CSV has a `sample` column")?;
    let mut numbers: Vec<u32> = Vec::new();
    while let Some((line, record)) = table.next_record()? {
        let cell = Cell {
            path,
            line,
            column: "sample",
        };
        let n = sample_number(cell, record.get(col).unwrap_or(""))?;
        if !numbers.contains(&n) {
            numbers.push(n);
        }
    }
    Ok(numbers.into_iter().map(dataset_name).collect())
}

/// Reads `table.txt`: for each measurement, `(theta_v, phi_v, theta_i, phi_i)` in radians.
fn read_table(path: &Path, bytes: &[u8]) -> Result<Vec<[f64; 4]>, DataError> {
    const COLUMNS: [&str; 5] = ["meas", "theta_v", "phi_v", "theta_i", "phi_i"];
    let text = String::from_utf8_lossy(bytes);
    let mut rows = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line_no = k as u64 + 1;
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        if fields.len() != 5 {
            let column = COLUMNS.get(fields.len()).copied().unwrap_or("field 6");
            return Err(parse_error(
                path,
                line_no,
                column,
                format!(
                    "{} fields: CUReT's table.txt has 5 (meas theta_v phi_v theta_i phi_i)",
                    fields.len()
                ),
            ));
        }
        let cell = |c: usize| Cell {
            path,
            line: line_no,
            column: COLUMNS[c],
        };
        let meas = cell(0).number(fields[0])?;
        if meas != (rows.len() + 1) as f64 {
            return Err(cell(0).error(format!(
                "measurement {meas} where {} was expected (rows in order from 1)",
                rows.len() + 1
            )));
        }
        rows.push([
            cell(1).polar(fields[1])?,
            cell(2).azimuth(fields[2])?,
            cell(3).polar(fields[3])?,
            cell(4).azimuth(fields[4])?,
        ]);
    }
    if rows.is_empty() {
        return Err(format_error(
            path,
            "no measurements in the CUReT geometry table",
        ));
    }
    Ok(rows)
}

/// Reads the samples of `abrdf.dat` (contents `bytes`) that `selector` picks (all when `None`),
/// with the geometry of `table.txt` (`table_path`, contents `table_bytes`).
///
/// # Errors
/// [`DataError::Parse`] naming the file, line and column (`value 17` is the 17th measurement) of a
/// bad field, or a row whose number of values differs from the table's; [`DataError::Format`] when
/// the selector names no sample of the file.
pub fn read_dat(
    path: &Path,
    bytes: &[u8],
    table_path: &Path,
    table_bytes: &[u8],
    selector: Option<&str>,
) -> Result<Vec<Dataset>, DataError> {
    let geometry = read_table(table_path, table_bytes)?;
    let text = String::from_utf8_lossy(bytes);
    let mut out = Vec::new();
    let mut numbers = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line_no = k as u64 + 1;
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let first = Cell {
            path,
            line: line_no,
            column: "sample",
        };
        let number = sample_number(first, fields[0])?;
        if numbers.contains(&number) {
            return Err(first.error(format!("sample {number} appears twice")));
        }
        numbers.push(number);
        if fields.len() != geometry.len() + 1 {
            let column = if fields.len() > geometry.len() + 1 {
                format!("value {}", geometry.len() + 1)
            } else {
                format!("value {}", fields.len())
            };
            return Err(parse_error(
                path,
                line_no,
                column,
                format!(
                    "{} values where the geometry table ({}) has {} measurements",
                    fields.len() - 1,
                    table_path.display(),
                    geometry.len()
                ),
            ));
        }
        if selector.is_some_and(|s| !matches(s, number, None)) {
            continue;
        }
        let mut samples = Collector::new();
        for (m, (field, g)) in fields[1..].iter().zip(&geometry).enumerate() {
            let column = format!("value {}", m + 1);
            let value = Cell {
                path,
                line: line_no,
                column: &column,
            }
            .value(field)?;
            let [theta_v, phi_v, theta_i, phi_i] = *g;
            samples.push(sample(theta_i, phi_i, theta_v, phi_v, Value::Mono(value)));
        }
        out.push(samples.finish(path, dataset_name(number), true)?);
    }
    finish(path, out, selector, &numbers)
}

/// The selected datasets, or an error naming the samples the file has.
fn finish(
    path: &Path,
    out: Vec<Dataset>,
    selector: Option<&str>,
    numbers: &[u32],
) -> Result<Vec<Dataset>, DataError> {
    if out.is_empty() {
        let have: Vec<String> = numbers.iter().map(|&n| dataset_name(n)).collect();
        return Err(format_error(
            path,
            match selector {
                Some(s) => format!(
                    "no CUReT sample `{}` (by number or name); the file has {}",
                    super::rows::shorten(s),
                    summarize(&have)
                ),
                None => "no CUReT samples".to_string(),
            },
        ));
    }
    Ok(out)
}

/// A list of names, shortened to the first ten.
fn summarize(names: &[String]) -> String {
    if names.len() <= 10 {
        names.join(", ")
    } else {
        format!("{}, … ({} in all)", names[..10].join(", "), names.len())
    }
}

/// Reads the long-format CUReT CSV (contents `bytes`), the samples `selector` picks (all when
/// `None`), in the order of their first rows.
///
/// # Errors
/// As [`read_dat`].
pub fn read_csv(
    path: &Path,
    bytes: &[u8],
    selector: Option<&str>,
) -> Result<Vec<Dataset>, DataError> {
    const EXPECTED: &str = "the CUReT long-format CSV has sample,name,meas,theta_v_rad,\
                            phi_v_rad,theta_i_rad,phi_i_rad,brdf_avg_rgb";
    let mut table = CsvTable::new(path, bytes)?;
    let cols = [
        table.require("sample", EXPECTED)?,
        table.column("name").unwrap_or(usize::MAX),
        table.require("theta_v_rad", EXPECTED)?,
        table.require("phi_v_rad", EXPECTED)?,
        table.require("theta_i_rad", EXPECTED)?,
        table.require("phi_i_rad", EXPECTED)?,
        table.require("brdf_avg_rgb", EXPECTED)?,
    ];
    let headers = table.headers.clone();
    let mut groups: Vec<(u32, Collector)> = Vec::new();
    let mut numbers: Vec<u32> = Vec::new();
    while let Some((line, record)) = table.next_record()? {
        let cell = |k: usize| Cell {
            path,
            line,
            column: &headers[cols[k]],
        };
        let field = |k: usize| record.get(cols[k]).unwrap_or("");
        let number = sample_number(cell(0), field(0))?;
        if !numbers.contains(&number) {
            numbers.push(number);
        }
        let name = record.get(cols[1]);
        if selector.is_some_and(|s| !matches(s, number, name)) {
            continue;
        }
        let theta_v = cell(2).polar(field(2))?;
        let phi_v = cell(3).azimuth(field(3))?;
        let theta_i = cell(4).polar(field(4))?;
        let phi_i = cell(5).azimuth(field(5))?;
        let value = cell(6).value(field(6))?;
        let k = match groups.iter().position(|g| g.0 == number) {
            Some(k) => k,
            None => {
                groups.push((number, Collector::new()));
                groups.len() - 1
            }
        };
        groups[k]
            .1
            .push(sample(theta_i, phi_i, theta_v, phi_v, Value::Mono(value)));
    }
    let out = groups
        .into_iter()
        .map(|(number, c)| c.finish(path, dataset_name(number), true))
        .collect::<Result<Vec<_>, _>>()?;
    finish(path, out, selector, &numbers)
}
