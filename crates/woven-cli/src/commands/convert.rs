//! `woven convert`: any measurement file the fitter reads, written as the fitter's own CSV.

use crate::io;
use anyhow::{bail, Context, Result};
use clap::Args;
use std::path::PathBuf;
use woven_fit::data::{self, fitcsv, Value};

/// The long help of `woven convert`.
const LONG_ABOUT: &str = "Read a measurement file in any format `woven fit` accepts and write it \
as the fitter's CSV: `theta_i,phi_i,theta_r,phi_r,value,weight` (or value_r,value_g,value_b), \
radians, the BRDF in sr⁻¹, with `# name = …` and `# relative = true|false` above the header.

Formats, recognised by content: the fitter CSV itself; the goniometer CSV of `woven gonio` \
(radiance, divided by cos θi into the BRDF); the BRDF grids `*.grid.csv` (RGL felts, NBRDF fits \
of MERL/RGL/DTU materials; RGB); CUReT `abrdf.dat` (with table.txt beside it) and CUReT's \
long-format CSV (relative values; pick a sample with FILE#NUMBER or FILE#NAME); RGL's measured \
`.bsdf` files (RGB, isotropic) and NBRDF networks `*.nbrdf.json`, both evaluated on the grid of \
the `*.grid.csv` files.

Rows with a direction at or below the horizon are dropped, and the count is reported on standard \
error. A bad row is an error naming the file, its line and its column. --list prints what a file \
holds (one line per material) instead of converting it; --bundled lists the real measurements \
of the repository's data/ folder.";

/// Arguments of `woven convert`.
#[derive(Args, Debug)]
#[command(
    about = "Convert a measurement file (CUReT, RGL/MERL grid, goniometer CSV) to the fitter's CSV",
    long_about = LONG_ABOUT,
    after_help = "Examples:
  woven convert data/curet/abrdf.dat#linen -o linen.csv
  woven convert data/merl/beige-fabric.grid.csv -o beige.csv
  woven convert gonio-polyester-sateen.csv
  woven convert --list data/curet/abrdf.dat
  woven convert --bundled"
)]
pub struct ConvertArgs {
    /// The measurement file; FILE#SAMPLE picks one material of a file that holds several (CUReT).
    #[arg(value_name = "FILE", required_unless_present = "bundled")]
    pub input: Option<PathBuf>,

    /// Output CSV (written atomically); standard output when absent.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// List the materials in FILE (name, samples, rows dropped, calibration) instead of converting.
    #[arg(long, conflicts_with = "output")]
    pub list: bool,

    /// List the real datasets bundled in the repository's data/ folder (name, family, path).
    #[arg(long, conflicts_with_all = ["output", "list", "input"])]
    pub bundled: bool,
}

/// Runs `woven convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    if args.bundled {
        return io::write_output(None, |out| {
            writeln!(out, "name,family,textile,relative,samples,path")?;
            for b in data::bundled() {
                writeln!(
                    out,
                    "{},{},{},{},{},{}",
                    b.name,
                    b.family.name(),
                    b.textile,
                    b.relative,
                    b.samples,
                    b.spec().display()
                )?;
            }
            Ok(())
        });
    }
    let Some(input) = &args.input else {
        bail!("no input file (give FILE, or --bundled)");
    };
    if args.list {
        // Each material on its own: one that cannot be read is reported on its line.
        let (names, format) = (data::materials(input)?, data::format_of(input)?);
        let several = names.len() > 1;
        return io::write_output(None, |out| {
            writeln!(out, "# {}: {}", input.display(), format.name())?;
            writeln!(
                out,
                "name,samples,dropped_below_horizon,channels,relative,error"
            )?;
            for name in &names {
                let spec = if several {
                    PathBuf::from(format!("{}#{name}", input.display()))
                } else {
                    input.clone()
                };
                match data::load(&spec) {
                    Ok(d) => {
                        let channels = match d.samples.first().map(|s| s.value) {
                            Some(Value::Rgb(_)) => 3,
                            _ => 1,
                        };
                        writeln!(
                            out,
                            "{},{},{},{channels},{},",
                            d.name,
                            d.samples.len(),
                            d.dropped_below_horizon,
                            d.relative
                        )?;
                    }
                    Err(e) => writeln!(out, "{name},,,,,\"{}\"", e.to_string().replace('"', "'"))?,
                }
            }
            Ok(())
        });
    }
    let dataset = data::load(input)?;
    if dataset.samples.is_empty() {
        bail!(
            "{}: every row ({}) lies at or below the horizon: nothing to convert",
            input.display(),
            dataset.dropped_below_horizon
        );
    }
    io::write_output(args.output.as_deref(), |out| {
        fitcsv::write(&dataset, out).context("writing the fitter CSV")
    })?;
    eprintln!(
        "{}: {} samples{}{}",
        dataset.name,
        dataset.samples.len(),
        if dataset.dropped_below_horizon > 0 {
            format!(
                ", {} rows at or below the horizon dropped",
                dataset.dropped_below_horizon
            )
        } else {
            String::new()
        },
        if dataset.relative {
            " (relatively calibrated)"
        } else {
            ""
        }
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converts_a_bundled_dataset_to_a_file_that_loads_back_the_same() {
        let dir = tempfile::tempdir().unwrap();
        let linen = data::bundled()
            .into_iter()
            .find(|b| b.name == "curet-44-linen")
            .unwrap();
        let output = dir.path().join("linen.csv");
        run(&ConvertArgs {
            input: Some(linen.spec()),
            output: Some(output.clone()),
            list: false,
            bundled: false,
        })
        .unwrap();
        let back = data::load(&output).unwrap();
        let want = linen.load().unwrap();
        assert_eq!(back.samples, want.samples);
        assert_eq!((back.name, back.relative), (want.name, true));
    }

    #[test]
    fn the_goniometer_csv_loads_as_the_model_brdf() {
        // What `woven gonio` writes, read back: radiance / cos θi is the model's BRDF there.
        let material = woven::material::Material::from_preset_or_path("belt-cloth").unwrap();
        let model = material.build(550.0).unwrap();
        let readings = woven::gonio::sweep(&model, &[0.0, 90.0], &[-44.0, -15.0, 0.0, 30.0], || {});
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("gonio.csv");
        crate::io::write_atomically(&path, |out| Ok(data::gonio::write(&readings, out)?)).unwrap();
        let d = data::load(&path).unwrap();
        assert_eq!(
            (d.samples.len(), d.dropped_below_horizon, d.relative),
            (8, 0, false)
        );
        for (s, r) in d.samples.iter().zip(&readings) {
            let (wi, wo) = woven::gonio::directions(r.azimuth_deg, r.tilt_deg);
            let want = model.eval(wi, wo);
            let Value::Mono(got) = s.value else {
                panic!("one channel expected")
            };
            assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
        }
    }

    #[test]
    fn a_bad_file_is_an_error_naming_line_and_column_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("bad.csv");
        std::fs::write(
            &input,
            "theta_i,phi_i,theta_r,phi_r,value\n0.1,0,0.2,0,oops\n",
        )
        .unwrap();
        let output = dir.path().join("out.csv");
        let e = run(&ConvertArgs {
            input: Some(input),
            output: Some(output.clone()),
            list: false,
            bundled: false,
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("line 2, column `value`"), "{e}");
        assert!(!output.exists());
    }
}
