//! `woven gonio`: the paper's virtual goniometer (docs/spec.md §4) as a CSV table. The geometry,
//! a reading and the parallel sweep are the library's ([`woven::gonio`]), the CSV the fitter's
//! ([`woven_fit::data::gonio`], which reads it back); without `--material`, [`default_job`].

pub mod default_job;

use crate::args::{
    any_material_help, parse_degrees_in, parse_finite, Interval, MaterialSource,
    DEFAULT_WAVELENGTH_NM,
};
use crate::io;
use crate::progress::Progress;
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use woven::gonio::{sweep, HALF_ANGLE_DEG};
use woven_fit::data::gonio::write as write_csv;

/// Arguments of `woven gonio`.
#[derive(Args, Debug)]
#[command(
    about = "Virtual goniometer: radiance against sample tilt, as in the paper's Figs. 8–10",
    long_about = "The paper's measurement (§4, Fig. 7), computed from the model. Light and sensor \
are fixed 90° apart; the sample turns about its normal to the sample azimuth A and tilts by t in \
the plane of light and sensor. In the cloth's frame the light is at θi = 45° + t, the sensor at \
θr = 45° − t, both in one vertical plane (φi = A, φr = A + 180°); A = 0 puts the weft (x) in that \
plane, A = 90° the warp (y).

Prints CSV with the header `azimuth_deg,tilt_deg,theta_i,theta_r,radiance`: A and t in degrees \
as given, θi and θr in radians, and the radiance f(s, v)·cos θi (sr⁻¹) for unit irradiance. \
Rows run over the tilts for each azimuth in turn, computed in parallel.

--material takes a woven material or a microcylinder fabric (the microcylinder-* presets, or a \
file with `model = \"microcylinder\"`); a microcylinder fabric is coloured, and its radiance is \
the luminance (Rec. 709) of its RGB BRDF, as `woven eval` without --rgb writes it \
(--wavelength-nm does not apply to it).

Without --material (and without -o) it runs the main goniometer job: the polyester-sateen \
preset on the paper's grid, written to woven-out/ as CSV (gonio-polyester-sateen.csv) and as \
the paper's Figure 8 (fig8.svg, fig8.png), with a short summary; --azimuth-deg and --tilt-deg \
then keep their defaults.",
    after_help = "Examples:
  woven gonio
  woven gonio --material polyester-sateen
  woven gonio -m belt-cloth --azimuth-deg 0,45,90 --tilt-deg -42:42:3 -o belt.csv
  woven gonio -m my-cloth.toml --azimuth-deg 30 --tilt-deg -44:44:0.5 --wavelength-nm 450
  woven gonio -m microcylinder-silk-shot --azimuth-deg 0,90 -o shot.csv"
)]
pub struct GonioArgs {
    /// Absent: the main job (see above).
    #[arg(short, long, value_name = "PRESET|FILE", value_parser = MaterialSource::parse,
          help = any_material_help())]
    pub material: Option<MaterialSource>,

    /// Wavelength at which a woven material is evaluated, in nanometres (a microcylinder fabric
    /// has its own refractive indices and ignores it).
    #[arg(long, value_name = "NM", default_value_t = DEFAULT_WAVELENGTH_NM,
          value_parser = parse_finite)]
    pub wavelength_nm: f64,

    /// Sample azimuths A in degrees, each in [-360, 360]: a comma list, one angle, or a range
    /// START:STOP:STEP. 0 = the weft (x) in the plane of light and sensor, 90 = the warp (y).
    #[arg(long, value_name = "DEGREES", default_value = "0,45,90", allow_hyphen_values = true,
          value_parser = parse_azimuths)]
    pub azimuth_deg: DegreeList,

    /// Sample tilts t in degrees, each in (-45, 45) (±45° is grazing): a range START:STOP:STEP
    /// (STOP included when the steps land on it), a comma list, or one angle. The default is the
    /// paper's grid.
    #[arg(long, value_name = "DEGREES", default_value = PAPER_TILTS,
          allow_hyphen_values = true, value_parser = parse_tilts)]
    pub tilt_deg: DegreeList,

    /// Output CSV (written atomically); standard output when absent.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// Parsed angles, in degrees.
#[derive(Clone, Debug)]
pub struct DegreeList(pub Vec<f64>);

/// The paper's tilt steps as a `--tilt-deg` range: −42° to 42° by 3° (§4;
/// [`woven::gonio::paper_tilts_deg`]).
pub const PAPER_TILTS: &str = "-42:42:3";

/// The sample azimuths `--azimuth-deg` accepts: one turn either way.
pub const AZIMUTHS: Interval = Interval {
    lo: -360.0,
    lo_open: false,
    hi: 360.0,
    hi_open: false,
};

/// The tilts `--tilt-deg` accepts: short of grazing on both sides.
pub const TILTS: Interval = Interval {
    lo: -HALF_ANGLE_DEG,
    lo_open: true,
    hi: HALF_ANGLE_DEG,
    hi_open: true,
};

fn parse_azimuths(value: &str) -> Result<DegreeList, String> {
    parse_degrees_in("--azimuth-deg", value, AZIMUTHS).map(DegreeList)
}

fn parse_tilts(value: &str) -> Result<DegreeList, String> {
    parse_degrees_in("--tilt-deg", value, TILTS).map(DegreeList)
}

/// Runs `woven gonio`.
pub fn run(args: &GonioArgs) -> Result<()> {
    let Some(material) = &args.material else {
        if args.output.is_some() {
            anyhow::bail!(
                "-o needs --material: without it, `woven gonio` runs the main job, which writes \
                 its files to {}/",
                default_job::OUT_DIR
            );
        }
        return default_job::run();
    };
    let material = material.load_mono(args.wavelength_nm)?;
    let (azimuths, tilts) = (&args.azimuth_deg.0, &args.tilt_deg.0);
    let bar = Progress::new(
        Some((azimuths.len() * tilts.len()) as u64),
        "readings",
        args.output.is_some() || !std::io::IsTerminal::is_terminal(&std::io::stdout()),
    );
    let readings = sweep(&*material.brdf, azimuths, tilts, || bar.inc(1));
    bar.finish();
    io::write_output(args.output.as_deref(), |out| Ok(write_csv(&readings, out)?))
        .context("writing the goniometer table")
}
