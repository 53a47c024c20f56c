//! The key parameters of a material in words: for figure titles and the command line's material
//! listings.

use crate::fiber::{FiberModel, Ior};
use crate::material::{Material, PatternSpec, Weave};

/// The key parameters of a material, each already formatted for people.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// The material's name (the preset name for presets), or `-`.
    pub name: String,
    /// Fiber model: `rough` (Eq. (16')) or `htsg` (Eqs. (9)–(13)).
    pub fiber_model: String,
    /// Refractive index `η` (constant, or the Cauchy law).
    pub eta: String,
    /// Roughness `σ_h/τ`.
    pub roughness: String,
    /// Lateral length `L` (arc radii), or `-` for a flat fiber surface.
    pub lateral_length: String,
    /// Mean lateral slope `μ`, radians, or `-`.
    pub slope_mean: String,
    /// Spread of lateral slopes `σ`, radians, or `-`.
    pub slope_std: String,
    /// How the fibers of a yarn are oriented: `one orientation`, `twist σt = …`, `isotropic`, or
    /// `flat surface`.
    pub fibers: String,
    /// Visible weft fraction `γ`, with the weave pattern's name when a pattern gives it.
    pub weft_fraction: String,
}

/// A number in its shortest form, at most four significant digits (`0.3333`, `20`, `1.57`).
pub fn short(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let s = if x.abs() < 0.01 {
        format!("{x:.2e}")
    } else {
        let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    };
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

impl Summary {
    /// Summarizes `material`.
    pub fn of(material: &Material) -> Self {
        let fiber = &material.fiber;
        let fiber_model = match fiber.model {
            FiberModel::Rough { .. } => "rough".to_string(),
            FiberModel::Htsg { sigma_h_um, tau_um } => {
                format!(
                    "htsg (σh = {} µm, τ = {} µm)",
                    short(sigma_h_um),
                    short(tau_um)
                )
            }
        };
        let eta = match fiber.eta {
            Ior::Constant(eta) => short(eta),
            Ior::Cauchy {
                cauchy_a,
                cauchy_b_nm2,
            } => format!("{} + {} nm²/λ²", short(cauchy_a), short(cauchy_b_nm2)),
        };
        let dash = || "-".to_string();
        let (lateral_length, slope_mean, slope_std, fibers) = match &material.yarn {
            None => (dash(), dash(), dash(), "flat surface".to_string()),
            Some(y) => (
                short(y.lateral_length),
                short(y.slope_mean),
                short(y.slope_std),
                if y.isotropic {
                    "isotropic".to_string()
                } else if y.twist_std > 0.0 {
                    format!("twist σt = {}", short(y.twist_std))
                } else {
                    "one orientation".to_string()
                },
            ),
        };
        let weft_fraction = match (&material.yarn, &material.weave) {
            (None, _) => dash(),
            (Some(_), None) => "1".to_string(),
            (Some(_), Some(w @ Weave::Pattern { spec, .. })) => match spec {
                PatternSpec::Name(name) => format!("{} ({name})", short(w.weft_fraction())),
                _ => format!("{} (pattern)", short(w.weft_fraction())),
            },
            (Some(_), Some(w)) => short(w.weft_fraction()),
        };
        Summary {
            name: material.name.clone().unwrap_or_else(dash),
            fiber_model,
            eta,
            roughness: short(fiber.model.roughness()),
            lateral_length,
            slope_mean,
            slope_std,
            fibers,
            weft_fraction,
        }
    }

    /// The parameters in one line, for a figure title: `σh/τ = 0.05, L = 20, μ = 0, σ = 1.2, …`.
    pub fn one_line(&self) -> String {
        let mut parts = vec![
            format!("η = {}", self.eta),
            format!("σh/τ = {}", self.roughness),
        ];
        if self.lateral_length != "-" {
            parts.push(format!("L = {}", self.lateral_length));
            parts.push(format!("μ = {}", self.slope_mean));
            parts.push(format!("σ = {}", self.slope_std));
            parts.push(self.fibers.clone());
            parts.push(format!("γ = {}", self.weft_fraction));
        }
        parts.join(", ")
    }
}

/// The first line of the leading comment of a material file's text (`# Silk, the paper's …`), or
/// an empty string.
pub fn description(toml_text: &str) -> String {
    toml_text
        .lines()
        .map(str::trim)
        .take_while(|l| l.starts_with('#'))
        .map(|l| l.trim_start_matches('#').trim())
        .find(|l| !l.is_empty())
        .unwrap_or_default()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short() {
        assert_eq!(short(0.05), "0.05");
        assert_eq!(short(20.0), "20");
        assert_eq!(short(1.0 / 3.0), "0.3333");
        assert_eq!(short(1.57), "1.57");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(1234.5), "1234");
        assert_eq!(short(0.005), "5.00e-3");
    }

    #[test]
    fn presets_are_summarized() {
        let sateen = Summary::of(&Material::preset("polyester-sateen").unwrap());
        assert_eq!(sateen.name, "polyester-sateen");
        assert_eq!(sateen.roughness, "0.05");
        assert_eq!(sateen.lateral_length, "20");
        assert_eq!(sateen.slope_std, "1.2");
        assert_eq!(sateen.fibers, "one orientation");
        assert_eq!(sateen.weft_fraction, "0");
        let belt = Summary::of(&Material::preset("belt-cloth").unwrap());
        assert_eq!(belt.fibers, "twist σt = 0.35");
        assert_eq!(belt.weft_fraction, "0.3333 (twill-2/1)");
        let silk = Summary::of(&Material::preset("silk").unwrap());
        assert_eq!(silk.fibers, "isotropic");
        assert!(
            silk.one_line().contains("σh/τ = 0.1"),
            "{}",
            silk.one_line()
        );
        for name in Material::preset_names() {
            let d = description(Material::preset_toml(name).unwrap());
            assert!(d.len() > 10 && !d.starts_with('#'), "{name}: {d}");
        }
        assert_eq!(description("name = \"x\"\n"), "");
    }
}
