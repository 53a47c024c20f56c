//! Argument types shared by several subcommands.

use anyhow::{Context, Result};
use clap::Args;
use std::path::Path;
use woven::bsdf::Bsdf;
use woven::catalog::{AnyMaterial, Luminance};
use woven::color::Rgb;
use woven::material::Material;
use woven::table::Table;
use woven::Model;

/// The wavelength a material is evaluated at when `--wavelength-nm` is not given, nm.
pub const DEFAULT_WAVELENGTH_NM: f64 = 550.0;

/// A `--material` value: a preset name or the path of a TOML material file.
///
/// Resolution is [`Material::from_preset_or_path`]'s: a preset name wins, then anything that
/// exists as a file or looks like a path (contains `/`, ends in `.toml`).
#[derive(Clone, Debug)]
pub struct MaterialSource(String);

impl MaterialSource {
    /// Parses a command-line value (clap value parser).
    pub fn parse(value: &str) -> Result<Self, String> {
        if value.trim().is_empty() {
            return Err(format!(
                "expected a preset name ({}) or the path of a TOML material file",
                Material::all_preset_names().join(", ")
            ));
        }
        Ok(MaterialSource(value.to_string()))
    }

    /// Reads the material and prepares it for evaluation at `wavelength_nm` (named
    /// `--wavelength-nm` in messages).
    ///
    /// # Errors
    /// As [`load`](Self::load), and for a wavelength the material's refractive index does not
    /// cover.
    pub fn load_and_build(&self, wavelength_nm: f64) -> Result<(Material, Model)> {
        let material = self.load()?;
        let model = material.build(wavelength_nm).with_context(|| {
            format!("cannot prepare material `{self}` at --wavelength-nm {wavelength_nm}")
        })?;
        Ok((material, model))
    }

    /// A short name for the material: its `name`, else the `--material` value.
    pub fn display_name(&self, material: &Material) -> String {
        material.name.clone().unwrap_or_else(|| self.0.clone())
    }

    /// Reads the material of either kind: a woven material or a microcylinder fabric.
    ///
    /// # Errors
    /// When the value is neither a preset nor a readable, valid material file of either kind.
    pub fn load_any(&self) -> Result<AnyMaterial> {
        let arg = &self.0;
        AnyMaterial::from_preset_or_path(arg).with_context(|| {
            if AnyMaterial::is_preset(arg) {
                format!("cannot load the preset `{arg}`")
            } else if Path::new(arg).exists() {
                format!("cannot load material file `{arg}`")
            } else {
                format!(
                    "cannot load --material `{arg}`: neither a preset (see `woven materials`) \
                     nor a readable material file"
                )
            }
        })
    }

    /// `material` (read by [`load_any`](Self::load_any)) as a colour BSDF at `wavelength_nm`.
    pub fn build_rgb(
        &self,
        material: &AnyMaterial,
        wavelength_nm: f64,
    ) -> Result<Box<dyn Bsdf<Value = Rgb>>> {
        material.build_rgb(wavelength_nm).with_context(|| {
            format!("cannot prepare material `{self}` at --wavelength-nm {wavelength_nm}")
        })
    }

    /// The material of either kind as one value per pair, for the commands that plot or tabulate
    /// a single channel (`woven plot hemisphere`, `woven gonio`): a woven material's exact model
    /// at `wavelength_nm` (undyed, as before the microcylinder fabrics came), a microcylinder
    /// fabric's Rec. 709 luminance (its own refractive indices: the wavelength does not apply).
    ///
    /// # Errors
    /// As [`load_any`](Self::load_any) and [`load_and_build`](Self::load_and_build).
    pub fn load_mono(&self, wavelength_nm: f64) -> Result<MonoBrdf> {
        Ok(match self.load_any()? {
            AnyMaterial::Woven(material) => {
                let model = material.build(wavelength_nm).with_context(|| {
                    format!("cannot prepare material `{self}` at --wavelength-nm {wavelength_nm}")
                })?;
                MonoBrdf {
                    name: self.display_name(&material),
                    brdf: Box::new(model),
                    kind: MaterialKind::Woven,
                }
            }
            AnyMaterial::Microcylinder(fabric) => MonoBrdf {
                name: fabric.name.clone(),
                brdf: Box::new(Luminance(fabric)),
                kind: MaterialKind::Microcylinder,
            },
        })
    }

    /// Reads and validates the material.
    ///
    /// # Errors
    /// When the value is neither a preset nor a readable, valid material file; the message lists
    /// the presets when the value names no existing file.
    pub fn load(&self) -> Result<Material> {
        let arg = &self.0;
        Material::from_preset_or_path(arg).with_context(|| {
            if Material::preset_toml(arg).is_some() {
                format!("cannot load the preset `{arg}`")
            } else if Path::new(arg).exists() {
                format!("cannot load material file `{arg}`")
            } else {
                format!(
                    "cannot load --material `{arg}`: neither a preset ({}; see `woven \
                     materials`) nor a readable material file",
                    Material::all_preset_names().join(", ")
                )
            }
        })
    }
}

/// Which model a material is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialKind {
    /// A woven material (the Yang–Ikeuchi model).
    Woven,
    /// A microcylinder fabric (Sadeghi et al. 2013), in colour.
    Microcylinder,
}

/// A material of either kind seen in one channel ([`MaterialSource::load_mono`]).
pub struct MonoBrdf {
    /// The material's name: its `name`, else the `--material` value.
    pub name: String,
    /// Its BRDF, sr⁻¹: the woven model, or a colour BRDF's luminance.
    pub brdf: Box<dyn Bsdf<Value = f64>>,
    /// Which model it is.
    pub kind: MaterialKind,
}

impl std::fmt::Display for MaterialSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The help line of `--material`, naming the presets the library has.
pub fn material_help() -> String {
    format!(
        "A preset ({}; list them with `woven materials`) or a material file (TOML; see the \
         `woven` library's `material` module for its keys)",
        Material::all_preset_names().join(", ")
    )
}

/// The help line of a `--material` that takes either model: the woven presets, the
/// microcylinder fabrics, and files of both kinds.
pub fn any_material_help() -> String {
    format!(
        "A preset ({}; or a microcylinder fabric: {}; list them with `woven materials`) or a \
         material file (TOML: a woven material, or a microcylinder fabric with `model = \
         \"microcylinder\"`)",
        Material::all_preset_names().join(", "),
        woven::microcylinder::Microcylinder::preset_names().join(", ")
    )
}

/// `--material` and `--wavelength-nm`: what every model-evaluating command needs.
#[derive(Args, Clone, Debug)]
pub struct MaterialArgs {
    #[arg(short, long, value_name = "PRESET|FILE", value_parser = MaterialSource::parse,
          help = material_help())]
    pub material: MaterialSource,

    /// Wavelength at which the material is evaluated, in nanometres.
    #[arg(long, value_name = "NM", default_value_t = DEFAULT_WAVELENGTH_NM,
          value_parser = parse_finite)]
    pub wavelength_nm: f64,
}

impl MaterialArgs {
    /// Loads the material and prepares it for evaluation at the requested wavelength.
    pub fn build(&self) -> Result<Model> {
        Ok(self.load_and_build()?.1)
    }

    /// The material as loaded, and prepared for evaluation at the requested wavelength.
    pub fn load_and_build(&self) -> Result<(Material, Model)> {
        self.material.load_and_build(self.wavelength_nm)
    }

    /// A short name for the material: its `name`, else the `--material` value.
    pub fn display_name(&self, material: &Material) -> String {
        self.material.display_name(material)
    }
}

/// Loads a table built by `woven tabulate` (`--table FILE`).
///
/// A table holds one wavelength: `wavelength_nm`, when the user gave `--wavelength-nm`, must be
/// the table's.
///
/// # Errors
/// When the file cannot be read or is not an intact table (the library's message says what is
/// wrong: truncated, checksum, version, …), or when `wavelength_nm` differs from the table's.
pub fn load_table(path: &Path, wavelength_nm: Option<f64>) -> Result<Table> {
    let table =
        Table::load(path).with_context(|| format!("cannot load --table `{}`", path.display()))?;
    if let Some(nm) = wavelength_nm {
        check_table_wavelength(path, &table, nm)?;
    }
    Ok(table)
}

/// Checks that `--wavelength-nm` `nm` is the wavelength `table` (read from `path`) was built at.
fn check_table_wavelength(path: &Path, table: &Table, nm: f64) -> Result<()> {
    let built = table.wavelength_nm();
    // The file stores the wavelength exactly; the slack only forgives a value typed with more
    // digits than it was built with.
    if (nm - built).abs() > 1e-9 * built.abs().max(1.0) {
        anyhow::bail!(
            "--wavelength-nm {nm} differs from the wavelength of --table `{}`, built at {built} \
             nm: a table holds one wavelength; leave --wavelength-nm out, or build a table at \
             {nm} nm with `woven tabulate --wavelength-nm {nm}`",
            path.display()
        );
    }
    Ok(())
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

/// The interval an angle option accepts, in degrees; either end open or closed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower end.
    pub lo: f64,
    /// Whether `lo` itself is excluded.
    pub lo_open: bool,
    /// Upper end.
    pub hi: f64,
    /// Whether `hi` itself is excluded.
    pub hi_open: bool,
}

impl Interval {
    /// Whether `x` lies in the interval.
    pub fn contains(&self, x: f64) -> bool {
        let above = if self.lo_open {
            x > self.lo
        } else {
            x >= self.lo
        };
        let below = if self.hi_open {
            x < self.hi
        } else {
            x <= self.hi
        };
        above && below
    }
}

impl std::fmt::Display for Interval {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}{}, {}{}",
            if self.lo_open { '(' } else { '[' },
            self.lo,
            self.hi,
            if self.hi_open { ')' } else { ']' }
        )
    }
}

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
    let valid = Interval {
        lo,
        lo_open: false,
        hi,
        hi_open,
    };
    parse_degrees_in(flag, value, valid)
}

/// [`parse_degrees`] for any [`Interval`].
pub fn parse_degrees_in(flag: &str, value: &str, valid: Interval) -> Result<Vec<f64>, String> {
    let number = |part: &str, what: &str| -> Result<f64, String> {
        match part.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!(
                "{flag} `{value}`: {what} `{}` is not a finite number",
                part.trim()
            )),
        }
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
    if let Some(bad) = angles.iter().find(|&&x| !valid.contains(x)) {
        return Err(format!(
            "{flag} `{value}`: angle {bad}° is outside the valid range {valid} degrees"
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

    #[test]
    fn open_intervals_exclude_their_ends() {
        let tilt = Interval {
            lo: -45.0,
            lo_open: true,
            hi: 45.0,
            hi_open: true,
        };
        let p = |s: &str| parse_degrees_in("--tilt-deg", s, tilt);
        assert_eq!(p("-42:42:3").unwrap().len(), 29);
        assert_eq!(p("-44.9,0,44.9").unwrap(), vec![-44.9, 0.0, 44.9]);
        let e = p("-45:45:15").unwrap_err();
        assert!(e.contains("angle -45°") && e.contains("(-45, 45)"), "{e}");
        assert!(p("45").unwrap_err().contains("angle 45°"));
    }
}
