//! `woven tabulate`: builds a material's BRDF table (`.wtab`) for fast evaluation and sampling.

use crate::args::MaterialArgs;
use crate::io;
use crate::numbers::{group_digits, megabytes, percent, seconds};
use crate::progress::Progress;
use crate::tables::{build_table, Built};
use anyhow::{Context, Result};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use woven::figures::words::short;
use woven::material::Material;
use woven::table::report::{AccuracyReport, BANDS_DEG};
use woven::table::{Symmetry, Table, TableOptions, F0_PHI_NODES};
use woven::Model;

/// The long help of `woven tabulate`.
const LONG_ABOUT: &str = "Tabulate a material's BRDF at one wavelength into a table file \
(`.wtab`) that `woven eval --table`, `woven export --table` and the library's `Table` read: \
quadrilinear interpolation in the incidence (θi, φi) and the half vector, under a microsecond \
per evaluation, with importance sampling for renderers.

The grid exploits the material's symmetry. Isotropic materials (flat fiber surfaces, yarns with \
`isotropic = true`) need one incidence azimuth: --n-theta × --n-h-isotropic² nodes. All other \
woven materials are mirror-symmetric in x and y, so φi covers [0°, 90°]: --n-theta × --n-phi × \
--n-h² nodes. Flat fibers and single-orientation yarns are evaluated exactly at every node that \
a direction above the horizon can read. Twisted and isotropic yarns (about a millisecond per exact evaluation) first tabulate the yarn \
with its fibers along x exactly (--n-theta × 13 × --n-h² nodes), then average rotated look-ups \
of it over 180 fiber azimuths. Smooth fibers get a finer half-vector grid unless --n-h says \
otherwise: 81 nodes at roughness 0.05 and above (every preset), rising to 121 at 0.02, because \
the yarns' highlights are as narrow as the fiber's lobe. The build uses every core; a progress \
bar shows on standard \
error when it is a terminal and the build is long.

The table covers the whole hemisphere: it holds two halves, one indexed by the light \
direction and one by the viewer's, and each pair is read from the half whose direction is the \
more grazing, on polar nodes that crowd toward the horizon.

The table is written atomically (a failed build leaves no file) and records the material and \
the wavelength. A one-paragraph summary goes to standard output: symmetry, grid, file size, \
build time. --report adds the accuracy against the exact model over the whole hemisphere, in \
bands of θ = max(θi, θr): ≤ 80°, 80°–89° and 89°–90°, each with its own random direction \
pairs (uniform in solid angle, a fixed seed). Per band: the cosine-weighted relative RMS error, \
the 99th percentile and the largest relative error, and the largest error of f cos θi cos θr \
relative to the material's peak of f cos θi cos θr — what a renderer's estimate is off by. \
Exact values are computed in parallel; by default 2000 pairs per band, or 300 for twisted and \
isotropic yarns, whose exact evaluations are slow (--report-samples chooses).";

/// Arguments of `woven tabulate`.
#[derive(Args, Debug)]
#[command(
    about = "Tabulate a material's BRDF into a table file for fast evaluation and sampling",
    long_about = LONG_ABOUT,
    after_help = "Examples:
  woven tabulate --material polyester-sateen -o sateen.wtab
  woven tabulate -m silk -o silk.wtab --report
  woven tabulate -m my-cloth.toml -o my-cloth.wtab --wavelength-nm 450 --n-h 121 --report
  woven eval --table sateen.wtab --input dirs.csv --output brdf.csv"
)]
pub struct TabulateArgs {
    #[command(flatten)]
    pub material: MaterialArgs,

    /// The table file to write (conventionally `.wtab`), atomically.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// Polar nodes of each half's axis direction, from 0° to 89.9° (denser toward grazing)
    /// [default: 40; 60 for isotropic materials].
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u64).range(N_THETA.0..=N_THETA.1))]
    pub n_theta: Option<u64>,

    /// Azimuth nodes of each half's axis direction over [0°, 90°] (ignored for isotropic
    /// materials).
    #[arg(long, value_name = "N", default_value_t = TableOptions::default().n_phi as u64,
          value_parser = clap::value_parser!(u64).range(N_PHI.0..=N_PHI.1))]
    pub n_phi: u64,

    /// Nodes per half-vector axis for anisotropic materials, and for the intermediate table of
    /// twisted and isotropic yarns [default: 81, more for fibers smoother than roughness 0.05:
    /// up to 121 at 0.02].
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u64).range(N_H.0..=N_H.1))]
    pub n_h: Option<u64>,

    /// Nodes per half-vector axis for isotropic materials (one φi slice, so finer is cheap).
    #[arg(long, value_name = "N",
          default_value_t = TableOptions::default().n_h_isotropic as u64,
          value_parser = clap::value_parser!(u64).range(N_H.0..=N_H.1))]
    pub n_h_isotropic: u64,

    /// Also print the table's accuracy against the exact model.
    #[arg(long)]
    pub report: bool,

    /// Random direction pairs per band that the accuracy report compares [default: 2000; 300 for
    /// twisted or isotropic yarns].
    #[arg(long, value_name = "N", requires = "report",
          value_parser = clap::value_parser!(u64).range(REPORT_SAMPLES.0..=REPORT_SAMPLES.1))]
    pub report_samples: Option<u64>,
}

/// The node counts `--n-theta` accepts (those of [`TableOptions::validate`]).
pub const N_THETA: (u64, u64) = (2, 1024);
/// The node counts `--n-phi` accepts (those of [`TableOptions::validate`]).
pub const N_PHI: (u64, u64) = (2, 1024);
/// The node counts `--n-h` and `--n-h-isotropic` accept (those of [`TableOptions::validate`]).
pub const N_H: (u64, u64) = (3, 4097);
/// The pair counts `--report-samples` accepts: enough for a 99th percentile, few enough to end.
pub const REPORT_SAMPLES: (u64, u64) = (100, 10_000_000);

/// Report pairs per band for materials whose exact evaluation takes tens of microseconds.
pub const REPORT_SAMPLES_FAST: usize = 2000;
/// Report pairs per band for twisted and isotropic yarns, about a millisecond per exact evaluation.
pub const REPORT_SAMPLES_SLOW: usize = 300;
/// The seed of the report's direction pairs: the same pairs on every run.
pub const REPORT_SEED: u64 = 1;

/// Whether `material` has twisted or isotropic yarns: about a millisecond per exact evaluation
/// (the other materials take microseconds to tens of microseconds).
pub fn has_slow_yarns(material: &Material) -> bool {
    material
        .yarn
        .is_some_and(|y| y.isotropic || y.twist_std > 0.0)
}

/// The table options of the parsed arguments for `model` (already within
/// [`TableOptions::validate`]'s ranges: clap checks them); `--n-h` defaults to
/// [`TableOptions::for_model`]'s.
fn options(args: &TabulateArgs, model: &Model) -> TableOptions {
    let auto = TableOptions::for_model(model);
    TableOptions {
        n_theta: args.n_theta.map_or(auto.n_theta, |n| n as usize),
        n_phi: args.n_phi as usize,
        n_h: args.n_h.map_or(auto.n_h, |n| n as usize),
        n_h_isotropic: args.n_h_isotropic as usize,
        ..auto
    }
}

/// Runs `woven tabulate`.
pub fn run(args: &TabulateArgs) -> Result<()> {
    io::check_output_dirs(std::slice::from_ref(&args.output))?;
    let (material, model) = args.material.load_and_build()?;
    let options = options(args, &model);
    let built = build_table(&material, &model, &options)?;
    // The CLI's atomic writer rather than `Table::save`: the same temporary file and rename, and
    // a device such as /dev/null is written, not replaced.
    let bytes = built.table.to_bytes();
    io::write_atomically(&args.output, |out| Ok(out.write_all(&bytes)?))
        .with_context(|| format!("cannot write the table to `{}`", args.output.display()))?;
    let bytes = bytes.len() as u64;
    println!(
        "{}",
        summary(
            &args.material.display_name(&material),
            &material,
            &built,
            &options,
            &args.output,
            bytes
        )
    );
    if args.report {
        let slow = has_slow_yarns(&material);
        let samples = args.report_samples.map_or(
            if slow {
                REPORT_SAMPLES_SLOW
            } else {
                REPORT_SAMPLES_FAST
            },
            |n| n as usize,
        );
        let start = Instant::now();
        let report = accuracy(&built.table, &model, samples);
        println!();
        println!(
            "{}",
            report_paragraph(
                &report,
                start.elapsed(),
                slow && args.report_samples.is_none()
            )
        );
    }
    Ok(())
}

/// The accuracy of `table` against the exact `model` at `samples` direction pairs per band,
/// drawn from [`REPORT_SEED`], with a progress bar (twisted and isotropic yarns take about a
/// millisecond per exact evaluation).
pub fn accuracy(table: &Table, model: &Model, samples: usize) -> AccuracyReport {
    let total = (samples * BANDS_DEG.len()) as u64;
    let bar = Progress::new(Some(total), "exact evaluations", true);
    let report = table.accuracy(model, samples, REPORT_SEED, &|done, _| {
        bar.set(done as u64, total)
    });
    bar.finish();
    report
}

/// The one-paragraph summary of a build.
fn summary(
    name: &str,
    material: &Material,
    built: &Built,
    options: &TableOptions,
    path: &Path,
    bytes: u64,
) -> String {
    let table = &built.table;
    let (n_theta, n_phi, n_h) = table.dims();
    let values = table.values().len() as u64;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let symmetry = match table.symmetry() {
        Symmetry::Isotropic => format!(
            "isotropic (the BRDF depends on φr − φi only), so one azimuth: two halves (indexed \
             by the light and by the viewer, each pair read from its more grazing direction's) \
             of {n_theta} polar × {n_h}² half-vector nodes"
        ),
        Symmetry::Mirror => format!(
            "mirror (x → −x and y → −y), so azimuths over [0°, 90°]: two halves (indexed by \
             the light and by the viewer, each pair read from its more grazing direction's) of \
             {n_theta} polar × {n_phi} azimuth × {n_h}² half-vector nodes"
        ),
    };
    let method = match &material.yarn {
        Some(y) if y.isotropic || y.twist_std > 0.0 => format!(
            " The {} yarns were tabulated with their fibers along x first (two halves of \
             {n_theta} polar × {} azimuth × {}² nodes, exact), then averaged over {} fiber \
             azimuths.",
            if y.isotropic { "isotropic" } else { "twisted" },
            F0_PHI_NODES,
            options.n_h,
            options.azimuth_nodes
        ),
        _ => String::new(),
    };
    format!(
        "Tabulated `{name}` at {} nm into {} ({}) in {} on {threads} thread{}. Symmetry: \
         {symmetry} = {} values (f32).{method} Evaluate it with `woven eval --table {}`.",
        short(table.wavelength_nm()),
        path.display(),
        megabytes(bytes),
        seconds(built.elapsed),
        if threads == 1 { "" } else { "s" },
        group_digits(values),
        path.display(),
    )
}

/// The paragraph and table of `--report`. `reduced`: the default pair count was lowered for
/// slow yarns.
fn report_paragraph(report: &AccuracyReport, elapsed: Duration, reduced: bool) -> String {
    let per_band = report.bands.first().map_or(0, |b| b.samples);
    let note = if reduced {
        format!(
            " {} pairs per band rather than {}: an exact evaluation of twisted or isotropic \
             yarns takes about a millisecond (--report-samples sets the count).",
            group_digits(per_band as u64),
            group_digits(REPORT_SAMPLES_FAST as u64)
        )
    } else {
        String::new()
    };
    let mut out = format!(
        "Accuracy against the exact model over the whole hemisphere, {} random direction pairs \
         in each band of θ = max(θi, θr) (uniform in solid angle, seed {REPORT_SEED}); the \
         material's peak of f cos θi cos θr is {} sr⁻¹. The exact values took {}.{note}\n\n",
        group_digits(per_band as u64),
        short(report.peak),
        seconds(elapsed),
    );
    out.push_str(
        "  band       rel. RMS (cos-weighted)  99th pct.  largest  largest |Δf| cos θi cos θr / peak\n",
    );
    for b in &report.bands {
        let band = if b.lo_deg == 0.0 {
            format!("≤ {}°", short(b.hi_deg))
        } else {
            format!("{}°–{}°", short(b.lo_deg), short(b.hi_deg))
        };
        out.push_str(&format!(
            "  {band:<9}  {:>23}  {:>9}  {:>7}  {:>8}\n",
            percent(b.weighted_rel_rms),
            percent(b.p99_rel),
            percent(b.max_rel),
            percent(b.max_peak_rel)
        ));
    }
    out.trim_end().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flag_ranges_are_the_library_ranges() {
        // Each flag's ends pass TableOptions::validate and one beyond them fails, so the usage
        // errors clap gives (naming the flag) and the library's checks cannot drift apart.
        type Set = fn(&mut TableOptions, usize);
        let flags: [(&str, (u64, u64), Set); 4] = [
            ("n_theta", N_THETA, |o, n| o.n_theta = n),
            ("n_phi", N_PHI, |o, n| o.n_phi = n),
            ("n_h", N_H, |o, n| o.n_h = n),
            ("n_h_isotropic", N_H, |o, n| o.n_h_isotropic = n),
        ];
        for (name, (lo, hi), set) in flags {
            for (n, ok) in [(lo - 1, false), (lo, true), (hi, true), (hi + 1, false)] {
                let mut o = TableOptions::default();
                set(&mut o, n as usize);
                assert_eq!(o.validate().is_ok(), ok, "{name} = {n}");
            }
        }
    }

    #[test]
    fn speed_follows_the_yarns() {
        let preset = |name| Material::preset(name).unwrap();
        assert!(has_slow_yarns(&preset("silk")) && has_slow_yarns(&preset("belt-cloth")));
        assert!(!has_slow_yarns(&preset("polyester-sateen")));
        let flat = Material::flat(woven::fiber::FiberParams::rough(1.5, 0.1, 0.1));
        assert!(!has_slow_yarns(&flat));
    }
}
