//! Every reflectance model a front end accepts by name or file: woven materials (the
//! Yang–Ikeuchi model, [`Material`]) and the microcylinder fabrics of Sadeghi et al. 2013
//! ([`Microcylinder`]), so that `woven eval`, the renderer and the fitter's references take
//! either the same way.

use crate::bsdf::{exact_draw, pair_of, Bsdf, BsdfSample, LobeFlags, Transport};
use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::material::{Dye, Material};
use crate::math::Vec3;
use crate::microcylinder::Microcylinder;
use crate::Model;
use std::path::Path;

/// A reflectance model by kind.
#[derive(Clone, Debug)]
pub enum AnyMaterial {
    /// A woven material (the paper's model), with its `[dye]`.
    Woven(Material),
    /// A microcylinder fabric.
    Microcylinder(Microcylinder),
}

impl AnyMaterial {
    /// Every built-in preset: the woven ones ([`Material::all_preset_names`]), then the
    /// microcylinder fabrics ([`Microcylinder::preset_names`]).
    pub fn preset_names() -> Vec<&'static str> {
        let mut names = Material::all_preset_names();
        names.extend_from_slice(Microcylinder::preset_names());
        names
    }

    /// Whether `name` is a built-in preset of either kind.
    pub fn is_preset(name: &str) -> bool {
        Self::preset_names().contains(&name)
    }

    /// A preset's name or a material file's path. A file is a microcylinder fabric when its
    /// first key is `model = "microcylinder"`, otherwise a woven material.
    ///
    /// # Errors
    /// As [`Material::from_preset_or_path`] and [`Microcylinder::from_path`]; an unknown name
    /// lists the presets of both kinds.
    pub fn from_preset_or_path(arg: &str) -> Result<AnyMaterial> {
        if Microcylinder::preset_names().contains(&arg) {
            return Microcylinder::preset(arg).map(AnyMaterial::Microcylinder);
        }
        if Material::preset_toml(arg).is_some() {
            return Material::preset(arg).map(AnyMaterial::Woven);
        }
        let path = Path::new(arg);
        if path.exists() || arg.contains('/') || arg.ends_with(".toml") {
            if is_microcylinder_file(path)? {
                return Microcylinder::from_path(path).map(AnyMaterial::Microcylinder);
            }
            return Material::from_path(path).map(AnyMaterial::Woven);
        }
        Err(Error::invalid(
            "material",
            format!("{arg:?}"),
            format!(
                "a material file or a preset: {}",
                Self::preset_names().join(", ")
            ),
        ))
    }

    /// The material's name, if it has one.
    pub fn name(&self) -> Option<&str> {
        match self {
            AnyMaterial::Woven(m) => m.name.as_deref(),
            AnyMaterial::Microcylinder(m) => Some(&m.name),
        }
    }

    /// The material as a BSDF in colour, prepared at `wavelength_nm` (a woven material's
    /// refractive index; the microcylinder fabrics have one per thread and ignore it).
    ///
    /// # Errors
    /// As [`Material::build`].
    pub fn build_rgb(&self, wavelength_nm: f64) -> Result<Box<dyn Bsdf<Value = Rgb>>> {
        Ok(match self {
            AnyMaterial::Woven(m) => Box::new(DyedModel {
                model: m.build(wavelength_nm)?,
                dye: m.dye,
            }),
            AnyMaterial::Microcylinder(m) => Box::new(m.clone()),
        })
    }
}

/// Whether the material file at `path` describes a microcylinder fabric: a top-level
/// `model = "microcylinder"` (a woven material file has no top-level `model`).
///
/// # Errors
/// As [`read_text_capped`](crate::fsutil::read_text_capped); a file that is not TOML is left
/// to the woven reader to report.
fn is_microcylinder_file(path: &Path) -> Result<bool> {
    let text =
        crate::fsutil::read_text_capped(path, crate::material::MAX_FILE_BYTES, "a material file")?;
    Ok(toml::from_str::<toml::Table>(&text)
        .ok()
        .and_then(|t| {
            t.get("model")
                .and_then(|m| m.as_str().map(|m| m == "microcylinder"))
        })
        .unwrap_or(false))
}

/// A woven material's exact model in colour: [`Model::eval_rgb`] with its dye. Like the exact
/// [`Model`], it draws directions from a cosine-weighted hemisphere.
#[derive(Clone, Debug)]
pub struct DyedModel {
    /// The model.
    pub model: Model,
    /// The colours of its yarns.
    pub dye: Dye,
}

impl Bsdf for DyedModel {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        self.model.lobes()
    }

    #[inline]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if (wi.z > 0.0 && wo.z > 0.0) || !self.model.transmits() {
            return self.model.eval_rgb(wi, wo, &self.dye);
        }
        self.model.eval_rgb_beyond(wi, wo, &self.dye)
    }

    /// The exact model's density (a cosine-weighted hemisphere on each side it scatters to).
    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        Bsdf::pdf(&self.model, wi, wo, mode)
    }

    /// The exact model's draw (a cosine-weighted hemisphere on each side), valued in colour.
    fn sample(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Rgb>> {
        let (drawn, lobe) = exact_draw(self.model.transmits(), known, uc, u)?;
        let (wi, wo) = pair_of(known, drawn, mode);
        let pdf = Bsdf::pdf(&self.model, wi, wo, mode);
        (pdf > 0.0).then(|| BsdfSample {
            wo,
            wi,
            f: self.eval(wi, wo),
            pdf,
            lobe,
        })
    }

    fn pass_through(&self, d: Vec3) -> f64 {
        self.model.open_along(d)
    }
}

/// Any colour BSDF seen in one channel, its Rec. 709 luminance: what a single-valued front end
/// (`woven eval` without `--rgb`) writes for a coloured material.
pub struct Luminance<B>(pub B);

impl<B: Bsdf<Value = Rgb>> Bsdf for Luminance<B> {
    type Value = f64;

    fn lobes(&self) -> LobeFlags {
        self.0.lobes()
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        self.0.eval(wi, wo).luminance()
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        self.0.pdf(wi, wo, mode)
    }

    fn sample(&self, known: Vec3, uc: f64, u: [f64; 2], mode: Transport) -> Option<BsdfSample> {
        self.0
            .sample(known, uc, u, mode)
            .map(|s| s.with_f(s.f.luminance()))
    }
}

/// A single-valued BSDF (a table, an undyed model) in colour: its value in every channel.
pub struct Grey<B>(pub B);

impl<B: Bsdf<Value = f64>> Bsdf for Grey<B> {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        self.0.lobes()
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        Rgb::grey(self.0.eval(wi, wo))
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        self.0.pdf(wi, wo, mode)
    }

    fn sample(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Rgb>> {
        self.0
            .sample(known, uc, u, mode)
            .map(|s| s.with_f(Rgb::grey(s.f)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An undyed woven material's colour BSDF is its model in every channel; a dyed one differs
    /// per channel and stays within the undyed value's white sheen plus its dyed body.
    #[test]
    fn an_undyed_material_is_grey_and_a_dye_colours_it() {
        let m = Material::preset("silk").unwrap();
        let model = m.build(550.0).unwrap();
        let bsdf = AnyMaterial::Woven(m.clone()).build_rgb(550.0).unwrap();
        let (s, v) = (
            Vec3::from_spherical(0.4, 0.2),
            Vec3::from_spherical(0.7, 2.9),
        );
        let grey = bsdf.eval(s, v);
        let f = model.eval(s, v);
        for c in grey.0 {
            assert!((c - f).abs() <= 1e-12 * f, "{c} vs {f}");
        }
        let mut dyed = m;
        dyed.dye = Dye {
            weft: Some(Rgb([0.8, 0.1, 0.1])),
            warp: Some(Rgb([0.1, 0.1, 0.8])),
        };
        let rgb = AnyMaterial::Woven(dyed)
            .build_rgb(550.0)
            .unwrap()
            .eval(s, v);
        assert!(rgb.0[1] < rgb.0[0] && rgb.0[1] < rgb.0[2], "{rgb:?}");
    }

    #[test]
    fn names_of_both_kinds_resolve_and_unknown_ones_list_them() {
        for name in AnyMaterial::preset_names() {
            assert!(AnyMaterial::from_preset_or_path(name).is_ok(), "{name}");
        }
        let e = AnyMaterial::from_preset_or_path("satin-nope")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("microcylinder-velvet") && e.contains("silk"),
            "{e}"
        );
    }
}
