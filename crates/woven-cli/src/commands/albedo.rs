//! `woven albedo`: the directional albedo over a range of incidence angles.

use crate::args::{parse_degrees, parse_finite, MaterialArgs};
use crate::io;
use crate::progress::Progress;
use anyhow::{Context, Result};
use clap::Args;
use rayon::prelude::*;
use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

/// Arguments of `woven albedo`.
#[derive(Args, Debug)]
#[command(
    about = "Tabulate the directional albedo against the angle of incidence",
    long_about = "Tabulate the directional albedo ∫ f(s, v) cos θr dω_r over the reflected \
hemisphere — the fraction of the light arriving from polar angle θi that the surface reflects — \
for a list of incidence angles.

Prints CSV with the header `theta_i_deg,albedo` (standard output unless --output is given); a \
material that lets light through (`[weave] transmission = true`, as the preset `cotton-voile`) \
adds a column `transmittance`: all the light that reaches the far side, what passes straight \
between the yarns included. In the `paper` normalization the albedo never exceeds 1. Twisted and isotropic yarns take a \
second or more per angle; a progress bar then shows on standard error when it is a terminal.",
    after_help = "Examples:
  woven albedo --material polyester.toml
  woven albedo -m polyester.toml --theta-deg 0:89:1 --output albedo.csv
  woven albedo -m polyester.toml --theta-deg 0,30,60,80 --wavelength-nm 450
  woven albedo -m cotton-voile --theta-deg 0:80:20"
)]
pub struct AlbedoArgs {
    #[command(flatten)]
    pub material: MaterialArgs,

    /// Incidence angles θi in degrees, each in [0, 90): a range START:STOP:STEP (STOP included
    /// when the steps land on it), a comma list, or one angle.
    #[arg(
        long,
        value_name = "DEGREES",
        default_value = "0:85:5",
        allow_hyphen_values = true,
        value_parser = parse_theta_list
    )]
    pub theta_deg: ThetaList,

    /// Azimuth φi of the incident light in degrees (matters for anisotropic cloth).
    #[arg(long, value_name = "DEGREES", default_value_t = 0.0, allow_hyphen_values = true,
          value_parser = parse_finite)]
    pub phi_deg: f64,

    /// Output CSV (written atomically); standard output when absent.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// Parsed `--theta-deg` angles, in degrees.
#[derive(Clone, Debug)]
pub struct ThetaList(pub Vec<f64>);

fn parse_theta_list(value: &str) -> Result<ThetaList, String> {
    // 90° is excluded: light at the horizon delivers no irradiance, so no albedo is defined.
    parse_degrees("--theta-deg", value, 0.0, 90.0, true).map(ThetaList)
}

/// Runs `woven albedo`.
pub fn run(args: &AlbedoArgs) -> Result<()> {
    let model = args.material.build()?;
    let phi_i = args.phi_deg.to_radians();
    // One tick per finished angle: a twisted or isotropic yarn takes a second or more each. The
    // calling thread only watches the clock, so that the bar (with its elapsed time) appears once
    // the job turns out to be long, even before the first angle is done.
    let bar = Progress::new(Some(args.theta_deg.0.len() as u64), "angles", true);
    let watcher = std::thread::current();
    let transmits = model.transmits();
    let albedos: Vec<[f64; 2]> = std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            let albedos = args
                .theta_deg
                .0
                .par_iter()
                .map(|theta_deg| {
                    let budget = model.budget(theta_deg.to_radians(), phi_i);
                    bar.inc(1);
                    [budget.reflected, budget.transmittance()]
                })
                .collect::<Vec<[f64; 2]>>();
            watcher.unpark();
            albedos
        });
        while !worker.is_finished() {
            std::thread::park_timeout(Duration::from_millis(100));
            bar.inc(0);
        }
        worker
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    });
    bar.finish();
    io::write_output(args.output.as_deref(), |out| {
        write_table(out, &args.theta_deg.0, &albedos, transmits)
    })
    .context("writing the albedo table")
}

/// The CSV: each angle's albedo, and its transmittance where the material `transmits`.
fn write_table(
    out: &mut dyn Write,
    thetas_deg: &[f64],
    rows: &[[f64; 2]],
    transmits: bool,
) -> Result<()> {
    let mut line = String::new();
    let header = if transmits {
        "theta_i_deg,albedo,transmittance"
    } else {
        "theta_i_deg,albedo"
    };
    writeln!(out, "{header}")?;
    for (&theta, &[albedo, through]) in thetas_deg.iter().zip(rows) {
        line.clear();
        io::push_f64(&mut line, theta);
        line.push(',');
        io::push_f64(&mut line, albedo);
        if transmits {
            line.push(',');
            io::push_f64(&mut line, through);
        }
        writeln!(out, "{line}")?;
    }
    Ok(())
}
