//! Argument types shared by several subcommands.

use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use woven::material::Material;
use woven::Model;

/// Where a material comes from.
///
/// Today every value is a path to a TOML material file. The type exists so that named presets
/// (`--material sateen`) can be added later without touching the commands that take one.
#[derive(Clone, Debug)]
pub enum MaterialSource {
    /// A TOML material file (see `woven::material`).
    File(PathBuf),
}

impl MaterialSource {
    /// Parses a command-line value.
    pub fn parse(value: &str) -> Result<Self, String> {
        if value.trim().is_empty() {
            return Err("expected the path of a TOML material file".into());
        }
        Ok(MaterialSource::File(PathBuf::from(value)))
    }

    /// Reads and validates the material.
    pub fn load(&self) -> Result<Material> {
        match self {
            MaterialSource::File(path) => Material::from_path(path)
                .with_context(|| format!("cannot load material file `{}`", path.display())),
        }
    }
}

impl std::fmt::Display for MaterialSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MaterialSource::File(path) => write!(f, "{}", path.display()),
        }
    }
}

/// `--material` and `--wavelength-nm`: what every model-evaluating command needs.
#[derive(Args, Clone, Debug)]
pub struct MaterialArgs {
    /// Material file (TOML; see the `woven` library's `material` module for its keys).
    #[arg(short, long, value_name = "FILE", value_parser = MaterialSource::parse)]
    pub material: MaterialSource,

    /// Wavelength at which the material is evaluated, in nanometres.
    #[arg(long, value_name = "NM", default_value_t = 550.0, value_parser = parse_finite)]
    pub wavelength_nm: f64,
}

impl MaterialArgs {
    /// Loads the material and prepares it for evaluation at the requested wavelength.
    pub fn build(&self) -> Result<Model> {
        let material = self.material.load()?;
        material.build(self.wavelength_nm).with_context(|| {
            format!(
                "cannot prepare material `{}` at --wavelength-nm {}",
                self.material, self.wavelength_nm
            )
        })
    }
}

/// A finite number (clap value parser).
pub fn parse_finite(value: &str) -> Result<f64, String> {
    match value.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(x) => Err(format!("expected a finite number, found {x}")),
        Err(_) => Err(format!("expected a number, found `{value}`")),
    }
}

/// The most angles a degree list or range may expand to (a guard against `0:90:1e-9`).
pub const MAX_ANGLES: usize = 100_000;

/// Parses a list of angles in degrees: `START:STOP:STEP` (inclusive of `STOP` when the steps land
/// on it), a comma list `0,15,30`, or one value; every angle must lie in `[lo, hi]` (or
/// `[lo, hi)` when `hi_open`). `flag` names the option in messages.
pub fn parse_degrees(
    flag: &str,
    value: &str,
    lo: f64,
    hi: f64,
    hi_open: bool,
) -> Result<Vec<f64>, String> {
    let number = |part: &str, what: &str| -> Result<f64, String> {
        match part.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!(
                "{flag} `{value}`: {what} `{}` is not a finite number",
                part.trim()
            )),
        }
    };
    let in_range = |x: f64| x >= lo && (if hi_open { x < hi } else { x <= hi });
    let range_text = if hi_open {
        format!("[{lo}, {hi})")
    } else {
        format!("[{lo}, {hi}]")
    };

    let angles: Vec<f64> = if value.contains(':') {
        let parts: Vec<&str> = value.split(':').collect();
        if parts.len() != 3 {
            return Err(format!(
                "{flag} `{value}`: a range is START:STOP:STEP (three numbers), found {} parts",
                parts.len()
            ));
        }
        let start = number(parts[0], "START")?;
        let stop = number(parts[1], "STOP")?;
        let step = number(parts[2], "STEP")?;
        if step <= 0.0 {
            return Err(format!(
                "{flag} `{value}`: STEP = {step} must be greater than 0"
            ));
        }
        if stop < start {
            return Err(format!(
                "{flag} `{value}`: STOP = {stop} is below START = {start}"
            ));
        }
        // Tolerate rounding so that 0:1:0.1 ends at 1.
        let count = ((stop - start) / step + 1e-9).floor() + 1.0;
        if count > MAX_ANGLES as f64 {
            return Err(format!(
                "{flag} `{value}`: {count} angles is too many (at most {MAX_ANGLES})"
            ));
        }
        (0..count as usize)
            .map(|k| tidy(start + k as f64 * step))
            .collect()
    } else {
        let items: Vec<f64> = value
            .split(',')
            .map(|part| number(part, "angle"))
            .collect::<Result<_, _>>()?;
        if items.len() > MAX_ANGLES {
            return Err(format!("{flag}: at most {MAX_ANGLES} angles"));
        }
        items
    };
    if let Some(bad) = angles.iter().find(|&&x| !in_range(x)) {
        return Err(format!(
            "{flag} `{value}`: angle {bad}° is outside the valid range {range_text} degrees"
        ));
    }
    Ok(angles)
}

/// Rounds away the last-bit noise of `start + k·step` (0.30000000000000004 → 0.3), keeping nine
/// decimals: far below any meaningful angle resolution.
fn tidy(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degree_ranges_and_lists() {
        let p = |s: &str| parse_degrees("--theta-deg", s, 0.0, 90.0, true);
        assert_eq!(p("0:85:5").unwrap().len(), 18);
        assert_eq!(p("0:1:0.1").unwrap().last().copied(), Some(1.0));
        assert_eq!(p("0:1:0.1").unwrap()[3], 0.3);
        assert_eq!(p("10, 20,30").unwrap(), vec![10.0, 20.0, 30.0]);
        assert_eq!(p("45").unwrap(), vec![45.0]);
        assert!(p("0:90:5").unwrap_err().contains("angle 90°"));
        assert!(p("0:80:0").unwrap_err().contains("STEP"));
        assert!(p("50:10:5").unwrap_err().contains("STOP"));
        assert!(p("0:10").unwrap_err().contains("START:STOP:STEP"));
        assert!(p("a,b").unwrap_err().contains("`a`"));
        assert!(p("-5").unwrap_err().contains("[0, 90)"));
        assert!(p("0:80:1e-9").unwrap_err().contains("too many"));
        assert!(p("nan").is_err());
    }
}
