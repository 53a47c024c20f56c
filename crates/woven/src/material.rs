//! Material descriptions and their TOML files (the project's material-file contract).
//!
//! ```toml
//! name = "my-fabric"            # optional
//! [fiber]
//! model = "rough"               # "rough" (MODEL.md §1.3, default) | "htsg" (§1.4)
//! eta = 1.6                     # or: eta = { cauchy_a = 1.55, cauchy_b_nm2 = 4000.0 }
//! roughness = 0.05              # σ_h/τ, for "rough"
//! sigma_h_um = 0.2              # for "htsg" (instead of roughness)
//! tau_um = 2.0                  # for "htsg"
//! diffuse = 0.1                 # ρ0, in [0, 1)
//! normalization = "paper"       # "paper" (default) | "none"
//! ```
//!
//! All angles in files are radians. Unknown keys, missing required keys, out-of-range values and
//! a key that does not belong to the chosen model are errors naming the key, the value and the
//! valid range.

use crate::error::{Error, Result};
use crate::fiber::{Fiber, FiberModel, FiberParams, Ior, Normalization};
use std::path::Path;

/// A complete material: a fiber surface (and, later, yarn and weave structure).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Optional human-readable name.
    pub name: Option<String>,
    /// The `[fiber]` table.
    pub fiber: FiberParams,
}

impl Material {
    /// A flat fiber surface.
    pub fn flat(fiber: FiberParams) -> Self {
        Material { name: None, fiber }
    }

    /// Validates every parameter.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first offending key.
    pub fn validate(&self) -> Result<()> {
        self.fiber.validate()
    }

    /// Prepares the material for evaluation at `wavelength_nm` (builds the β table).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an out-of-range parameter or wavelength.
    pub fn build(&self, wavelength_nm: f64) -> Result<crate::Model> {
        Ok(crate::Model {
            fiber: Fiber::new(&self.fiber, wavelength_nm)?,
        })
    }
}

#[cfg(feature = "serde")]
mod file {
    use super::*;
    use serde::{Deserialize, Serialize};

    #[derive(Deserialize, Serialize)]
    #[serde(deny_unknown_fields)]
    struct RawMaterial {
        #[serde(skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        fiber: RawFiber,
    }

    #[derive(Deserialize, Serialize, Default)]
    #[serde(deny_unknown_fields)]
    struct RawFiber {
        #[serde(skip_serializing_if = "Option::is_none")]
        model: Option<String>,
        #[serde(skip_serializing_if = "Option::is_none")]
        eta: Option<toml::Value>,
        #[serde(skip_serializing_if = "Option::is_none")]
        roughness: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        sigma_h_um: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        tau_um: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        diffuse: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        normalization: Option<String>,
    }

    fn missing(key: &str, why: &str) -> Error {
        Error::invalid(key, "(missing)", why)
    }

    fn not_for(key: &str, value: f64, model: &str, instead: &str) -> Error {
        Error::invalid(
            key,
            value,
            format!("no `{key}` with model = \"{model}\" (use {instead})"),
        )
    }

    fn parse_eta(v: &toml::Value) -> Result<Ior> {
        match v {
            toml::Value::Float(x) => Ok(Ior::Constant(*x)),
            toml::Value::Integer(i) => Ok(Ior::Constant(*i as f64)),
            toml::Value::Table(t) => {
                for k in t.keys() {
                    if k != "cauchy_a" && k != "cauchy_b_nm2" {
                        return Err(Error::invalid(
                            format!("fiber.eta.{k}"),
                            &t[k],
                            "only `cauchy_a` and `cauchy_b_nm2` in an eta table",
                        ));
                    }
                }
                let num = |k: &str| -> Result<f64> {
                    match t.get(k) {
                        Some(toml::Value::Float(x)) => Ok(*x),
                        Some(toml::Value::Integer(i)) => Ok(*i as f64),
                        Some(other) => Err(Error::invalid(format!("fiber.eta.{k}"), other, "a number")),
                        None => Err(missing(&format!("fiber.eta.{k}"), "a number (both Cauchy coefficients are required)")),
                    }
                };
                Ok(Ior::Cauchy {
                    cauchy_a: num("cauchy_a")?,
                    cauchy_b_nm2: num("cauchy_b_nm2")?,
                })
            }
            other => Err(Error::invalid(
                "fiber.eta",
                other,
                "a number, or { cauchy_a = A, cauchy_b_nm2 = B }",
            )),
        }
    }

    impl RawFiber {
        fn into_params(self) -> Result<FiberParams> {
            let model_name = self.model.as_deref().unwrap_or("rough");
            let model = match model_name {
                "rough" => {
                    if let Some(x) = self.sigma_h_um {
                        return Err(not_for("fiber.sigma_h_um", x, "rough", "`roughness`, or model = \"htsg\""));
                    }
                    if let Some(x) = self.tau_um {
                        return Err(not_for("fiber.tau_um", x, "rough", "`roughness`, or model = \"htsg\""));
                    }
                    let roughness = self
                        .roughness
                        .ok_or_else(|| missing("fiber.roughness", "σ_h/τ in [0.005, 2] (required for model = \"rough\")"))?;
                    FiberModel::Rough { roughness }
                }
                "htsg" => {
                    if let Some(x) = self.roughness {
                        return Err(not_for("fiber.roughness", x, "htsg", "`sigma_h_um` and `tau_um`"));
                    }
                    let sigma_h_um = self
                        .sigma_h_um
                        .ok_or_else(|| missing("fiber.sigma_h_um", "σ_h in µm, (0, 10] (required for model = \"htsg\")"))?;
                    let tau_um = self
                        .tau_um
                        .ok_or_else(|| missing("fiber.tau_um", "τ in µm, (0, 100] (required for model = \"htsg\")"))?;
                    FiberModel::Htsg { sigma_h_um, tau_um }
                }
                other => {
                    return Err(Error::invalid("fiber.model", format!("{other:?}"), "\"rough\" or \"htsg\""))
                }
            };
            let eta = parse_eta(
                self.eta
                    .as_ref()
                    .ok_or_else(|| missing("fiber.eta", "a refractive index in [1, 4] (required)"))?,
            )?;
            let normalization = match self.normalization.as_deref().unwrap_or("paper") {
                "paper" => Normalization::Paper,
                "none" => Normalization::None,
                other => {
                    return Err(Error::invalid(
                        "fiber.normalization",
                        format!("{other:?}"),
                        "\"paper\" or \"none\"",
                    ))
                }
            };
            let params = FiberParams {
                model,
                eta,
                diffuse: self.diffuse.unwrap_or(0.0),
                normalization,
            };
            params.validate()?;
            Ok(params)
        }

        fn from_params(p: &FiberParams) -> Self {
            let mut raw = RawFiber::default();
            match p.model {
                FiberModel::Rough { roughness } => {
                    raw.model = Some("rough".into());
                    raw.roughness = Some(roughness);
                }
                FiberModel::Htsg { sigma_h_um, tau_um } => {
                    raw.model = Some("htsg".into());
                    raw.sigma_h_um = Some(sigma_h_um);
                    raw.tau_um = Some(tau_um);
                }
            }
            raw.eta = Some(match p.eta {
                Ior::Constant(x) => toml::Value::Float(x),
                Ior::Cauchy { cauchy_a, cauchy_b_nm2 } => {
                    let mut t = toml::map::Map::new();
                    t.insert("cauchy_a".into(), toml::Value::Float(cauchy_a));
                    t.insert("cauchy_b_nm2".into(), toml::Value::Float(cauchy_b_nm2));
                    toml::Value::Table(t)
                }
            });
            raw.diffuse = Some(p.diffuse);
            raw.normalization = Some(
                match p.normalization {
                    Normalization::Paper => "paper",
                    Normalization::None => "none",
                }
                .into(),
            );
            raw
        }
    }

    impl Material {
        /// Parses a material from TOML text; `origin` names the source in errors.
        ///
        /// # Errors
        /// [`Error::Parse`] for malformed TOML, unknown or mistyped keys (with the line);
        /// [`Error::InvalidParameter`] for missing keys and out-of-range values.
        ///
        /// ```
        /// let m = woven::material::Material::from_toml_str(
        ///     "[fiber]\neta = 1.6\nroughness = 0.05\ndiffuse = 0.1\n", "<doc>")?;
        /// assert_eq!(m.fiber.diffuse, 0.1);
        /// let err = woven::material::Material::from_toml_str(
        ///     "[fiber]\neta = 1.6\nroughness = 7.0\n", "<doc>").unwrap_err();
        /// assert!(err.to_string().contains("fiber.roughness"));
        /// # Ok::<(), woven::Error>(())
        /// ```
        pub fn from_toml_str(text: &str, origin: &str) -> Result<Self> {
            let raw: RawMaterial = toml::from_str(text).map_err(|e| Error::Parse {
                path: origin.to_string(),
                message: e.to_string().trim_end().to_string(),
            })?;
            let material = Material {
                name: raw.name,
                fiber: raw.fiber.into_params()?,
            };
            material.validate()?;
            Ok(material)
        }

        /// Reads and parses a material file.
        ///
        /// # Errors
        /// [`Error::Io`] if the file cannot be read; otherwise as [`from_toml_str`](Self::from_toml_str).
        pub fn from_path(path: impl AsRef<Path>) -> Result<Self> {
            let path = path.as_ref();
            let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
            Self::from_toml_str(&text, &path.display().to_string())
        }

        /// The material as TOML text that [`from_toml_str`](Self::from_toml_str) reads back
        /// unchanged.
        pub fn to_toml_string(&self) -> String {
            let raw = RawMaterial {
                name: self.name.clone(),
                fiber: RawFiber::from_params(&self.fiber),
            };
            toml::to_string_pretty(&raw).expect("a material always serializes")
        }
    }
}
