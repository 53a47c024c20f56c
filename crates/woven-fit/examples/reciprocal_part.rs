//! The grounded presets against the reciprocal part of their references. The microcylinder
//! model is not reciprocal (docs/microcylinder.md §4), and no reciprocal BRDF can follow its
//! antisymmetric part. For each grounded preset this prints:
//! - that part's size, the reciprocity floor (`reciprocity_floor`);
//! - the preset's RMS log error against its reference and against the reference's reciprocal
//!   part (`sample_reciprocal`);
//! - the best Beckmann + Lambert (`microfacet`) fit's errors, fitted to each;
//! - the preset's error over the microfacet fit's, for each.
//!
//! ```text
//! cargo run --release -p woven-fit --example reciprocal_part
//! ```
use woven::catalog::AnyMaterial;
use woven::material::Material;
use woven::microcylinder::Microcylinder;
use woven_fit::data::Dataset;
use woven_fit::fit::{fit, FitOptions};
use woven_fit::params::{ModelKind, ParamSet};
use woven_fit::reference::{
    luminances, predict_luminances, reciprocity_floor, rms_log_scaled, sample, sample_reciprocal,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "| preset | reciprocity floor | woven | best microfacet | woven / microfacet \
         | woven, reciprocal part | best microfacet, reciprocal part | woven / microfacet |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for name in Material::grounded_preset_names() {
        let reference_name = format!("microcylinder-{name}");
        let reference = Microcylinder::preset(&reference_name)?;
        let floor = reciprocity_floor(&reference);
        let bsdf = AnyMaterial::from_preset_or_path(name)?.build_rgb(550.0)?;
        let mut row = format!("| `{name}` | {floor:.3} |");
        for data in [
            sample(&reference, &reference_name),
            sample_reciprocal(&reference, &reference_name),
        ] {
            let woven = rms_log_scaled(&predict_luminances(&*bsdf, &data), &luminances(&data));
            let microfacet = microfacet_error(&data)?;
            row += &format!(
                " {woven:.3} | {microfacet:.3} | {:.2} |",
                woven / microfacet
            );
        }
        println!("{row}");
    }
    Ok(())
}

/// The best Beckmann + Lambert fit's RMS log error on luminance (best scale removed).
fn microfacet_error(data: &Dataset) -> Result<f64, Box<dyn std::error::Error>> {
    let set = ParamSet::new(ModelKind::Microfacet, None, 3, false)?;
    let r = fit(data, &set, &FitOptions::default(), &|_, _| {})?;
    let lum = |c: [f64; 3]| woven::color::Rgb(c).luminance();
    let measured: Vec<f64> = r.observations.iter().map(|o| lum(o.value)).collect();
    let predicted: Vec<f64> = r.predicted.iter().map(|p| lum(*p)).collect();
    Ok(rms_log_scaled(&predicted, &measured))
}
