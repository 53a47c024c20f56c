//! `woven eval`: the BRDF for a CSV file of direction pairs.

use crate::args::{self, material_help, parse_finite, MaterialSource, DEFAULT_WAVELENGTH_NM};
use crate::io::{self, InputSource};
use crate::progress::{self, Progress};
use anyhow::{Context, Result};
use clap::{ArgGroup, Args};
use rayon::prelude::*;
use std::f64::consts::FRAC_PI_2;
use std::io::{IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use woven::bsdf::{Bsdf, LobeFlags};
use woven::catalog::{AnyMaterial, Grey, Luminance};
use woven::color::Rgb;
use woven::directions::{DirectionReader, DirectionRecord, RowError, COLUMNS};
use woven::Vec3;

/// Arguments of `woven eval`.
#[derive(Args, Debug)]
#[command(
    about = "Evaluate the BRDF for direction pairs read from a CSV file",
    long_about = "Evaluate the BRDF (sr⁻¹, without the cosine factor) for direction pairs read \
from a CSV file.

The input has the header `theta_i,phi_i,theta_r,phi_r`: polar and azimuthal angles in radians of \
the direction toward the light (theta_i, phi_i) and toward the viewer (theta_r, phi_r), both \
pointing away from the surface, in the cloth's local frame (z = macro normal, weft along x, warp \
along y). theta_i must lie in [0, π/2] and theta_r in [0, π]; azimuths may be any finite number. \
A theta_r above π/2 is a direction below the cloth: a material that lets light through \
(`[weave] transmission = true`, as the preset `cotton-voile`) gives its transmission there (the \
diffuse part through the yarns; what passes straight between them is a delta, printed by \
`woven albedo`), any other 0. theta = π/2 (grazing) gives 0.

The output repeats the four input columns exactly as read and appends `brdf`. Rows are processed \
in chunks, in parallel on all cores, and written in input order. A malformed row stops the run \
with an error naming its line and column; with --output no file is created then.

The BRDF comes from exactly one of --material (the exact model) and --table (a table built by \
`woven tabulate`, interpolated). Any material evaluates: a flat fiber surface takes \
microseconds a row, a woven cloth (the belt-cloth and silk presets) about a millisecond; a \
table takes well under a microsecond a row for any material, within the accuracy `woven \
tabulate --report` states. A table holds the one wavelength it was built at. When standard \
error is a terminal and the run lasts, a progress bar shows there (never when the output goes \
to the same terminal).",
    after_help = "Examples:
  woven eval --material polyester.toml --input dirs.csv --output brdf.csv
  woven eval --material belt-cloth --input dirs.csv --output brdf.csv
  woven eval --table belt-cloth.wtab --input dirs.csv --output brdf.csv
  woven eval -m polyester.toml --input dirs.csv --wavelength-nm 650 > brdf.csv
  cat dirs.csv | woven eval -m polyester.toml --input - > brdf.csv"
)]
#[command(group(ArgGroup::new("brdf").args(["material", "table"]).required(true)))]
pub struct EvalArgs {
    #[arg(short, long, value_name = "PRESET|FILE", value_parser = MaterialSource::parse,
          help = material_help())]
    pub material: Option<MaterialSource>,

    /// A table built by `woven tabulate` (`.wtab`), evaluated in place of a material.
    #[arg(long, value_name = "FILE")]
    pub table: Option<PathBuf>,

    /// Wavelength, in nanometres, at which --material is evaluated [default: 550]. With --table
    /// it may only repeat the table's own wavelength.
    #[arg(long, value_name = "NM", value_parser = parse_finite)]
    pub wavelength_nm: Option<f64>,

    /// Input CSV with header `theta_i,phi_i,theta_r,phi_r` (radians); `-` reads standard input.
    #[arg(short, long, value_name = "FILE", value_parser = InputSource::parse)]
    pub input: InputSource,

    /// Output CSV (written atomically); standard output when absent.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// Write the BRDF in colour, as `brdf_r,brdf_g,brdf_b` (linear sRGB): a dyed woven material
    /// or a microcylinder fabric in its colours; an undyed woven material (and a table) writes its
    /// one value three times. Without it, a coloured material writes its Rec. 709 luminance.
    #[arg(long)]
    pub rgb: bool,
}

/// What `woven eval` evaluates: one value per row, or three.
#[derive(Clone, Copy)]
pub enum Brdf<'a> {
    /// One value per row (`brdf`).
    Mono(&'a dyn Bsdf<Value = f64>),
    /// Linear RGB per row (`brdf_r,brdf_g,brdf_b`).
    Rgb(&'a dyn Bsdf<Value = Rgb>),
}

/// What [`Brdf`] borrows.
enum Owned {
    Mono(Box<dyn Bsdf<Value = f64>>),
    Rgb(Box<dyn Bsdf<Value = Rgb>>),
}

impl Brdf<'_> {
    /// The output's value columns.
    /// Whether the BSDF transmits (a viewer below the cloth sees light through it): asked once
    /// a block, not once a row.
    fn transmits(self) -> bool {
        match self {
            Brdf::Mono(b) => b.lobes(),
            Brdf::Rgb(b) => b.lobes(),
        }
        .contains(LobeFlags::TRANSMISSION)
    }

    fn columns(self) -> &'static str {
        match self {
            Brdf::Mono(_) => "brdf",
            Brdf::Rgb(_) => "brdf_r,brdf_g,brdf_b",
        }
    }
}

/// Runs `woven eval`.
pub fn run(args: &EvalArgs) -> Result<()> {
    let owned = match (&args.material, &args.table) {
        (None, Some(path)) => {
            let table = args::load_table(path, args.wavelength_nm)?;
            if args.rgb {
                Owned::Rgb(Box::new(Grey(table)))
            } else {
                Owned::Mono(Box::new(table))
            }
        }
        (Some(material), None) => {
            let nm = args.wavelength_nm.unwrap_or(DEFAULT_WAVELENGTH_NM);
            let any = material.load_any()?;
            match (&any, args.rgb) {
                (AnyMaterial::Woven(m), false) if m.dye.is_none() => {
                    Owned::Mono(Box::new(m.build(nm).with_context(|| {
                        format!("cannot prepare material `{material}` at --wavelength-nm {nm}")
                    })?))
                }
                (_, false) => Owned::Mono(Box::new(Luminance(material.build_rgb(&any, nm)?))),
                (_, true) => Owned::Rgb(material.build_rgb(&any, nm)?),
            }
        }
        // clap's group "brdf" admits exactly one of the two.
        _ => anyhow::bail!("give exactly one of --material and --table"),
    };
    let brdf = match &owned {
        Owned::Mono(b) => Brdf::Mono(&**b),
        Owned::Rgb(b) => Brdf::Rgb(&**b),
    };
    let input = args.input.open()?;
    // A bar only when the data does not go to the same terminal; it appears once the run has
    // proved long (cloth materials take about a millisecond a row).
    let show = args.output.is_some() || !std::io::stdout().is_terminal();
    let total = match &args.input {
        InputSource::File(path) if show && progress::stderr_is_terminal() => count_rows(path).ok(),
        _ => None,
    };
    let bar = Progress::new(total, "rows", show);
    let rows = io::write_output(args.output.as_deref(), |out| {
        eval_csv(brdf, input, &args.input.to_string(), out, |n| bar.inc(n))
    })
    .with_context(|| format!("evaluating `{}`", args.input))?;
    bar.finish();
    if let Some(path) = &args.output {
        if progress::stderr_is_terminal() {
            eprintln!("wrote {rows} rows to {}", path.display());
        }
    }
    Ok(())
}

/// The number of data rows of a CSV file (lines after the header), for the progress bar's length.
/// Only regular files are counted: a device or a pipe (`/dev/zero`) may never end.
fn count_rows(path: &Path) -> std::io::Result<u64> {
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    let mut file = std::fs::File::open(path)?;
    let mut buf = vec![0u8; 1 << 16];
    let (mut lines, mut last) = (0u64, b'\n');
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            break;
        }
        lines += buf[..n].iter().filter(|&&b| b == b'\n').count() as u64;
        last = buf[n - 1];
    }
    // A last line without its newline still counts; the header does not.
    Ok((lines + u64::from(last != b'\n')).saturating_sub(1))
}

/// Rows evaluated per parallel batch: large enough to keep every core busy, small enough that
/// memory stays flat for any input size.
const CHUNK_ROWS: usize = 1 << 16;

/// Reads direction pairs from `input` (named `origin` in errors) and writes them with the BRDF
/// `brdf` gives to `output`. `progress` is told, from the worker threads, the number of rows of
/// each block evaluated. Returns the number of rows.
pub fn eval_csv(
    brdf: Brdf<'_>,
    input: impl Read + Send,
    origin: &str,
    output: &mut dyn Write,
    progress: impl Fn(u64) + Sync,
) -> Result<u64> {
    let mut reader = DirectionReader::new(input, origin)?;
    writeln!(output, "{},{}", COLUMNS.join(","), brdf.columns())?;

    // Two buffers of records: one is evaluated while the other is read, so reading (one thread)
    // overlaps the parallel evaluation.
    let mut current: Vec<DirectionRecord> = Vec::new();
    let mut next: Vec<DirectionRecord> = Vec::new();
    let mut more = fill_chunk(&mut reader, &mut current)?;
    let mut rows = 0u64;
    while !current.is_empty() {
        let (blocks, read) = rayon::join(
            || evaluate_chunk(brdf, &current, &progress),
            || {
                if more {
                    fill_chunk(&mut reader, &mut next)
                } else {
                    next.clear();
                    Ok(false)
                }
            },
        );
        for block in blocks {
            output.write_all(&block?)?;
        }
        rows += current.len() as u64;
        more = read?;
        std::mem::swap(&mut current, &mut next);
    }
    output.flush()?;
    Ok(rows)
}

/// The most bytes of fields per batch: with lines of up to 4 KiB
/// ([`woven::directions::MAX_LINE_BYTES`]), a batch of long lines ends before [`CHUNK_ROWS`].
const CHUNK_BYTES: usize = 8 << 20;
/// A record buffer that held more than this is dropped rather than kept for reuse, so that a few
/// long lines do not leave every buffer large.
const KEEP_RECORD_BYTES: usize = 256;

/// Reads up to [`CHUNK_ROWS`] records (and about [`CHUNK_BYTES`]) into `chunk`, reusing its
/// buffers; returns whether the input may hold more. Two chunks are alive at a time, so memory
/// stays within a few tens of MiB for any input.
fn fill_chunk(
    reader: &mut DirectionReader<impl Read + Send>,
    chunk: &mut Vec<DirectionRecord>,
) -> Result<bool> {
    let (mut n, mut bytes) = (0, 0);
    loop {
        if n == CHUNK_ROWS || bytes >= CHUNK_BYTES {
            chunk.truncate(n);
            return Ok(true);
        }
        if n == chunk.len() {
            chunk.push(DirectionRecord::new());
        } else if chunk[n].byte_len() > KEEP_RECORD_BYTES {
            chunk[n] = DirectionRecord::new();
        }
        if !reader.read_record(&mut chunk[n])? {
            chunk.truncate(n);
            return Ok(false);
        }
        bytes += chunk[n].byte_len();
        n += 1;
    }
}

/// The most rows per parallel task: enough to amortize scheduling for fast materials, few enough
/// that a cloth material (about 1 ms a row) reports progress every second or two.
const BLOCK_ROWS: usize = 2048;
/// The fewest rows per parallel task.
const MIN_BLOCK_ROWS: usize = 16;

/// Rows per parallel task for a chunk of `rows`: at least eight tasks per thread, so that a short
/// input of slow rows still uses every core, within [`MIN_BLOCK_ROWS`, `BLOCK_ROWS`].
fn block_rows(rows: usize) -> usize {
    (rows / (8 * rayon::current_num_threads())).clamp(MIN_BLOCK_ROWS, BLOCK_ROWS)
}

/// Parses and evaluates every record of a chunk in parallel, formatting the output lines there
/// too (validated numbers need no CSV quoting): one buffer of lines per block, in input order, or
/// the first bad row of the block. `progress` is told each block's row count when it is done.
fn evaluate_chunk(
    brdf: Brdf<'_>,
    chunk: &[DirectionRecord],
    progress: &(impl Fn(u64) + Sync),
) -> Vec<Result<Vec<u8>, RowError>> {
    chunk
        .par_chunks(block_rows(chunk.len()))
        .map(|block| {
            // ~100 bytes a row: four echoed angles of up to 20 characters, the BRDF, commas.
            let mut out = Vec::with_capacity(block.len() * 100);
            let mut number = String::new();
            let transmits = brdf.transmits();
            for record in block {
                let [theta_i, phi_i, theta_r, phi_r] = record.angles()?;
                for field in record.fields() {
                    out.extend_from_slice(field);
                    out.push(b',');
                }
                number.clear();
                let (values, n) = eval_row(brdf, transmits, theta_i, phi_i, theta_r, phi_r);
                for (k, v) in values[..n].iter().enumerate() {
                    if k > 0 {
                        number.push(',');
                    }
                    io::push_f64(&mut number, *v);
                }
                out.extend_from_slice(number.as_bytes());
                out.push(b'\n');
            }
            progress(block.len() as u64);
            Ok(out)
        })
        .collect()
}

/// The BSDF for one direction pair (validated angles): its values and how many there are (1 or
/// 3). Exactly 0 at grazing `θ = π/2`, where `cos θ` is not exactly 0 in floating point, and
/// for a viewer below a material that does not transmit.
fn eval_row(
    brdf: Brdf<'_>,
    transmits: bool,
    theta_i: f64,
    phi_i: f64,
    theta_r: f64,
    phi_r: f64,
) -> ([f64; 3], usize) {
    let n = match brdf {
        Brdf::Mono(_) => 1,
        Brdf::Rgb(_) => 3,
    };
    if theta_i >= FRAC_PI_2 || theta_r == FRAC_PI_2 || (theta_r > FRAC_PI_2 && !transmits) {
        return ([0.0; 3], n);
    }
    let (wi, wo) = (
        Vec3::from_spherical(theta_i, phi_i),
        Vec3::from_spherical(theta_r, phi_r),
    );
    match brdf {
        Brdf::Mono(b) => ([b.eval(wi, wo), 0.0, 0.0], 1),
        Brdf::Rgb(b) => (b.eval(wi, wo).0, 3),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use woven::fiber::FiberParams;
    use woven::material::Material;
    use woven::Model;

    fn model() -> Model {
        Material::flat(FiberParams::rough(1.5, 0.1, 0.1))
            .build(550.0)
            .unwrap()
    }

    fn run(input: &str) -> Result<String> {
        let mut out = Vec::new();
        eval_csv(
            Brdf::Mono(&model()),
            input.as_bytes(),
            "<test>",
            &mut out,
            |_| {},
        )?;
        Ok(String::from_utf8(out).unwrap())
    }

    #[test]
    fn evaluates_rows_and_keeps_input_text() {
        let out =
            run("theta_i,phi_i,theta_r,phi_r\n0.5,0,0.5,2.5\n 0.1 , 1e-3 ,1.5707963267948966,-7\n")
                .unwrap();
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], "theta_i,phi_i,theta_r,phi_r,brdf");
        assert!(lines[1].starts_with("0.5,0,0.5,2.5,"));
        assert_eq!(lines[2], "0.1,1e-3,1.5707963267948966,-7,0");
        let f: f64 = lines[1].rsplit(',').next().unwrap().parse().unwrap();
        let m = model();
        let want = m.eval(
            Vec3::from_spherical(0.5, 0.0),
            Vec3::from_spherical(0.5, 2.5),
        );
        assert_eq!(f, want);
    }

    #[test]
    fn many_chunks_stay_in_order() {
        let n = CHUNK_ROWS * 2 + 17;
        let mut input = String::from("theta_i,phi_i,theta_r,phi_r\n");
        for k in 0..n {
            input.push_str(&format!("{},0,0.3,{}\n", (k % 100) as f64 * 0.01, k));
        }
        let out = run(&input).unwrap();
        assert_eq!(out.lines().count(), n + 1);
        // Progress is reported for every row, block by block, whatever the order of the blocks.
        let done = std::sync::atomic::AtomicU64::new(0);
        eval_csv(
            Brdf::Mono(&model()),
            input.as_bytes(),
            "<test>",
            &mut Vec::new(),
            |k| {
                done.fetch_add(k, std::sync::atomic::Ordering::Relaxed);
            },
        )
        .unwrap();
        assert_eq!(done.into_inner(), n as u64);
        for (k, line) in out.lines().skip(1).enumerate().step_by(9973) {
            assert!(line.starts_with(&format!("{},0,0.3,{k},", (k % 100) as f64 * 0.01)));
        }
    }

    #[test]
    fn bad_rows_name_line_and_column() {
        let h = "theta_i,phi_i,theta_r,phi_r\n";
        let e = |body: &str| format!("{:#}", run(&format!("{h}{body}")).unwrap_err());
        assert!(e("0.1,0,0.1,0\n0.1,x,0.2,0\n").contains("line 3, column 2 `phi_i`"));
        assert!(e("0.1,0,0.1,NaN\n").contains("line 2, column 4 `phi_r`"));
        assert!(e("0.1,0,inf,0\n").contains("column 3 `theta_r`"));
        assert!(e("0.1,0,0.1\n").contains("column `phi_r` is missing"));
        assert!(e("0.1,0,0.1,0,9\n").contains("extra column 5"));
        assert!(e("0.1,,0.1,0\n").contains("empty value"));
        let msg = e("1.6,0,0.1,0\n");
        assert!(msg.contains("line 2, column 1 `theta_i`"), "{msg}");
        assert!(msg.contains("1.6") && msg.contains("[0, π/2]"), "{msg}");
        assert!(e("-0.1,0,0.1,0\n").contains("outside the valid range"));
        let header = format!("{:#}", run("theta_i,phi_i,theta_o,phi_o\n").unwrap_err());
        assert!(
            header.contains("line 1") && header.contains("theta_o"),
            "{header}"
        );
        assert!(format!("{:#}", run("").unwrap_err()).contains("empty"));
    }

    #[test]
    fn rows_are_counted_for_the_bar() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.csv");
        std::fs::write(&path, "theta_i,phi_i,theta_r,phi_r\n1,2,3,4\n5,6,7,8").unwrap();
        assert_eq!(count_rows(&path).unwrap(), 2);
        std::fs::write(&path, "theta_i,phi_i,theta_r,phi_r\n1,2,3,4\n").unwrap();
        assert_eq!(count_rows(&path).unwrap(), 1);
        // An endless device is not counted (it would never end).
        #[cfg(unix)]
        assert!(count_rows(Path::new("/dev/zero")).is_err());
        assert_eq!(block_rows(10), MIN_BLOCK_ROWS);
        assert_eq!(block_rows(10_000_000), BLOCK_ROWS);
    }

    #[test]
    fn header_only_gives_header_only() {
        assert_eq!(
            run("\u{feff}theta_i,phi_i,theta_r,phi_r\n").unwrap(),
            "theta_i,phi_i,theta_r,phi_r,brdf\n"
        );
    }
}
