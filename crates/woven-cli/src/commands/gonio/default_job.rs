//! The goniometer job: `woven gonio` without `--material` (bare `woven` did this before it rendered).
//!
//! The paper's virtual goniometer (§4, Fig. 8; docs/spec.md §4) for the `polyester-sateen` preset:
//! the readings as CSV (what `woven gonio --material polyester-sateen` prints) and Figure 8 as
//! SVG and PNG (what `woven plot fig8` draws), all under [`OUT_DIR`] in the current directory,
//! then a short summary for people: what was computed, where the files are, a few readings, and
//! the commands to try next. It takes well under a second.

use super::{AZIMUTHS, PAPER_TILTS, TILTS};
use crate::args::{parse_degrees_in, DEFAULT_WAVELENGTH_NM};
use crate::io;
use crate::plotting::figure::{self, DEFAULT_SIZE};
use crate::plotting::ImageFormat;
use anyhow::{Context, Result};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;
use woven::figures::FigureId;
use woven::gonio::{sweep, Reading};
use woven::material::Material;
use woven_fit::data::gonio::write as write_csv;

/// The folder the files go to, relative to the current directory.
pub const OUT_DIR: &str = "woven-out";
/// The material: the paper's Fig. 8 sample.
pub const PRESET: &str = "polyester-sateen";
/// The sample azimuths of the readings, degrees: weft, diagonal and warp in the plane of light
/// and sensor (the figure's three curves).
pub const SAMPLE_AZIMUTHS_DEG: [f64; 3] = [0.0, 45.0, 90.0];
/// The tilts the summary's little table shows, degrees (all on the paper's 3° grid).
pub const SHOWN_TILTS_DEG: [f64; 5] = [-30.0, -15.0, 0.0, 15.0, 30.0];

/// The files the job writes, in the order it writes them.
pub fn outputs() -> [PathBuf; 3] {
    let dir = Path::new(OUT_DIR);
    [
        dir.join(format!("gonio-{PRESET}.csv")),
        dir.join("fig8.svg"),
        dir.join("fig8.png"),
    ]
}

/// Runs the default job.
pub fn run() -> Result<()> {
    let start = Instant::now();
    std::fs::create_dir_all(OUT_DIR)
        .with_context(|| format!("cannot create the output folder `{OUT_DIR}`"))?;
    let [csv, svg, png] = outputs();

    // The goniometer readings on the paper's grid, as `woven gonio` writes them.
    let material = Material::preset(PRESET)?;
    let model = material
        .build(DEFAULT_WAVELENGTH_NM)
        .with_context(|| format!("cannot prepare the preset `{PRESET}`"))?;
    let tilts = parse_degrees_in("--tilt-deg", PAPER_TILTS, TILTS).map_err(anyhow::Error::msg)?;
    debug_assert!(SAMPLE_AZIMUTHS_DEG.iter().all(|&a| AZIMUTHS.contains(a)));
    let readings = sweep(&model, &SAMPLE_AZIMUTHS_DEG, &tilts, || {});
    io::write_atomically(&csv, |out| Ok(write_csv(&readings, out)?))?;

    // Figure 8, as `woven plot fig8` draws it.
    let fig8 = woven::figures::figure(FigureId::Fig8)?;
    for (path, format) in [(&svg, ImageFormat::Svg), (&png, ImageFormat::Png)] {
        let bytes = figure::render(&fig8, fig8.y_scale, format, DEFAULT_SIZE)
            .with_context(|| format!("drawing Fig. 8 for `{}`", path.display()))?;
        io::write_atomically(path, |out| Ok(out.write_all(&bytes)?))?;
    }

    print!(
        "{}",
        summary(&readings, tilts.len(), start.elapsed().as_secs_f64())
    );
    Ok(())
}

/// The text printed after the job.
fn summary(readings: &[Reading], n_tilts: usize, seconds: f64) -> String {
    let [csv, svg, png] = outputs();
    let mut out = String::new();
    // Writing into a String cannot fail.
    let _ = writeln!(
        out,
        "woven — the Yang–Ikeuchi woven-cloth BRDF. `woven gonio` without --material: the \
         goniometer job ran on the built-in `{PRESET}` preset at {DEFAULT_WAVELENGTH_NM} nm: the paper's virtual \
         goniometer (§4, Fig. 8), light and sensor 90° apart, the sample tilted by t (light at \
         θi = 45° + t, sensor at θr = 45° − t) with the weft, the diagonal or the warp in the \
         plane of light and sensor. Done in {seconds:.1} s.\n"
    );
    let _ = writeln!(
        out,
        "  {}  {} readings: 3 sample azimuths × {n_tilts} tilts (−42° … 42°, the paper's grid)",
        csv.display(),
        readings.len()
    );
    let _ = writeln!(
        out,
        "  {}, {}  the paper's Figure 8 drawn from the model\n",
        svg.display(),
        png.display()
    );
    let _ = writeln!(
        out,
        "Reflected radiance for unit irradiance, f·cos θi (sr⁻¹):\n"
    );
    let _ = writeln!(
        out,
        "  {:>6}  {:>9}  {:>9}  {:>9}",
        "tilt", "weft", "45°", "warp"
    );
    for &t in &SHOWN_TILTS_DEG {
        let at = |a: f64| {
            readings
                .iter()
                .find(|r| r.azimuth_deg == a && r.tilt_deg == t)
                .map_or(f64::NAN, |r| r.radiance)
        };
        let _ = writeln!(
            out,
            "  {:>6}  {:>9.4}  {:>9.4}  {:>9.4}",
            if t == 0.0 {
                "0°".to_string()
            } else {
                format!("{t:+}°")
            },
            at(0.0),
            at(45.0),
            at(90.0)
        );
    }
    let _ = writeln!(
        out,
        "\nWith the weft in the plane, masking and shadowing cut the curve down at large tilts; \
         with the warp in the plane they remove nothing (the figure's caption has the numbers).\n"
    );
    let _ = writeln!(out, "Next:");
    for (command, what) in [
        ("woven --help", "every command"),
        (
            "woven materials",
            "the built-in presets and their parameters",
        ),
        (
            "woven plot hemisphere --material silk -o silk.png",
            "a BRDF over the view hemisphere",
        ),
        (
            "woven gonio --material belt-cloth -o belt.csv",
            "the goniometer for another preset",
        ),
        (
            "woven tabulate --material belt-cloth -o belt.wtab --report",
            "a table for renderers",
        ),
    ] {
        let _ = writeln!(out, "  {command:<60} {what}");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use woven::figures::cloth;

    #[test]
    fn summary_shows_the_readings_asked_for() {
        let model = Material::preset(PRESET).unwrap().build(550.0).unwrap();
        let tilts: Vec<f64> = SHOWN_TILTS_DEG.to_vec();
        let readings = sweep(&model, &SAMPLE_AZIMUTHS_DEG, &tilts, || {});
        let text = summary(&readings, tilts.len(), 0.1);
        assert!(!text.contains("NaN"), "{text}");
        let row = text.lines().find(|l| l.trim_start().starts_with("+15°"));
        let row = row.unwrap_or_else(|| panic!("no +15° row in\n{text}"));
        let want = woven::gonio::read(&model, 90.0, 15.0).radiance;
        let got: f64 = row.split_whitespace().last().unwrap().parse().unwrap();
        assert!((got - want).abs() < 1e-4, "{got} vs {want}");
        for path in outputs() {
            assert!(text.contains(&path.display().to_string()), "{text}");
        }
        // The shown tilts lie on the paper's grid, so the CSV holds them.
        let grid = parse_degrees_in("--tilt-deg", PAPER_TILTS, TILTS).unwrap();
        assert!(SHOWN_TILTS_DEG.iter().all(|t| grid.contains(t)));
        assert_eq!(cloth::AZIMUTHS.map(|(a, _)| a), SAMPLE_AZIMUTHS_DEG);
    }
}
