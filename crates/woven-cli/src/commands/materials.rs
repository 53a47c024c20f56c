//! `woven materials`: the built-in presets, as a table or as their TOML text.

use anyhow::{Context, Result};
use clap::builder::PossibleValuesParser;
use clap::Args;
use std::io::Write;
use woven::figures::words::{description, Summary};
use woven::material::Material;
use woven::microcylinder::Microcylinder;

/// Arguments of `woven materials`.
#[derive(Args, Debug)]
#[command(
    about = "List the built-in material presets, or print one as TOML",
    long_about = "List the built-in material presets with their key parameters: fiber model, \
refractive index η, roughness σh/τ, lateral length L (arc radii), mean and spread of the lateral \
slopes μ and σ (radians), how the fibers of a yarn are oriented (one orientation, a twist of \
spread σt, or isotropic) and the visible weft fraction γ; then a one-line description.

Every command that takes --material accepts a preset's name in place of a file. \
`--show NAME` prints the preset's TOML exactly: save it to start a material file of your own.",
    after_help = "Examples:
  woven materials
  woven materials --show silk > my-silk.toml
  woven gonio --material belt-cloth"
)]
pub struct MaterialsArgs {
    /// Print this preset's TOML text instead of the table (woven presets; a microcylinder
    /// fabric's parameters are in docs/microcylinder.md).
    #[arg(long, value_name = "NAME",
          value_parser = PossibleValuesParser::new(Material::all_preset_names()))]
    pub show: Option<String>,
}

/// Runs `woven materials`.
pub fn run(args: &MaterialsArgs) -> Result<()> {
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    match &args.show {
        Some(name) => {
            let text =
                Material::preset_toml(name).with_context(|| format!("no preset named `{name}`"))?;
            out.write_all(text.as_bytes())?;
        }
        None => {
            out.write_all(table()?.as_bytes())?;
            out.write_all(b"\n")?;
            out.write_all(microcylinder_table()?.as_bytes())?;
        }
    }
    out.flush()?;
    Ok(())
}

/// The column titles of the table.
const HEADINGS: [&str; 10] = [
    "NAME",
    "FIBER",
    "η",
    "σh/τ",
    "L",
    "μ (rad)",
    "σ (rad)",
    "FIBERS",
    "γ (weft)",
    "DESCRIPTION",
];

/// The presets as an aligned text table, one line per preset under a heading line.
pub fn table() -> Result<String> {
    let mut rows: Vec<Vec<String>> = vec![HEADINGS.iter().map(|h| h.to_string()).collect()];
    for name in Material::all_preset_names() {
        let material =
            Material::preset(name).with_context(|| format!("loading the preset `{name}`"))?;
        let s = Summary::of(&material);
        let text = Material::preset_toml(name).unwrap_or_default();
        rows.push(vec![
            name.to_string(),
            s.fiber_model,
            s.eta,
            s.roughness,
            s.lateral_length,
            s.slope_mean,
            s.slope_std,
            s.fibers,
            s.weft_fraction,
            description(text),
        ]);
    }
    // Column widths in characters (η, σ, μ are one character each, several bytes).
    let widths: Vec<usize> = (0..HEADINGS.len())
        .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
        .collect();
    let mut out = String::new();
    for row in &rows {
        let mut line = String::new();
        for (c, cell) in row.iter().enumerate() {
            line.push_str(cell);
            if c + 1 < row.len() {
                let pad = widths[c] - cell.chars().count() + 2;
                line.extend(std::iter::repeat_n(' ', pad));
            }
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    Ok(out)
}

/// The microcylinder fabrics (Sadeghi et al. 2013, Table II): per thread its coverage `a`,
/// refractive index and the surface lobe's width `γs`, and the range of its tangent curve.
pub fn microcylinder_table() -> Result<String> {
    let mut out = String::from(
        "MICROCYLINDER FABRIC (Sadeghi et al. 2013, Table II; docs/microcylinder.md)  \
         THREAD 1 (along x): a, η, γs, tilts  /  THREAD 2 (along y)\n",
    );
    for name in Microcylinder::preset_names() {
        let m = Microcylinder::preset(name).with_context(|| format!("loading `{name}`"))?;
        let thread = |k: usize| {
            let t = &m.threads[k];
            let offsets = t.tangents.offsets();
            let (lo, hi) = offsets
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), o| (a.min(*o), b.max(*o)));
            format!(
                "a {:.2}, η {}, γs {:.1}°, tilts {:.0}°…{:.0}°",
                t.coverage,
                t.eta,
                t.gamma_s.to_degrees(),
                lo.to_degrees(),
                hi.to_degrees()
            )
        };
        out.push_str(&format!("{name:<36}  {}  /  {}\n", thread(0), thread(1)));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_has_a_row_per_preset_with_aligned_columns() {
        let t = table().unwrap();
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines.len(), 1 + Material::all_preset_names().len());
        assert!(lines[0].starts_with("NAME"));
        // The FIBERS column starts at the same character position on every line.
        let col = |l: &str, what: &str| l.find(what).map(|b| l[..b].chars().count());
        let fibers = col(lines[0], "FIBERS").unwrap();
        for (line, kind) in lines[1..]
            .iter()
            .zip(["one orientation", "twist", "isotropic"])
        {
            assert_eq!(col(line, kind), Some(fibers), "{line}");
        }
    }
}
