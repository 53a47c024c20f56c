//! Every real dataset in `data/` loads and fits without error: the baselines on one dataset of
//! each family and the cloth model (few parameters free) on a CUReT sample by default, and the
//! cloth fit of MERL's light-brown fabric (once trapped worse than Lambert) in an ignored test of
//! its own, which CI runs. Every model on every dataset takes an hour on 2 cores: the
//! `every_dataset_fits` example, run by hand
//! (`cargo run --release -p woven-fit --example every_dataset_fits`).

use woven::material::Material;
use woven_fit::data::{bundled, Bundled, Family};
use woven_fit::{fit, FitOptions, FitResult, ModelKind, ParamSet};

fn channels(b: &Bundled) -> usize {
    if b.family == Family::Curet {
        1
    } else {
        3
    }
}

fn fit_bundled(
    b: &Bundled,
    model: ModelKind,
    init: Option<&Material>,
    options: &FitOptions,
) -> FitResult {
    let data = b.load().unwrap_or_else(|e| panic!("{}: {e}", b.name));
    let set = ParamSet::new(model, init, channels(b), data.relative).unwrap();
    let r = fit(&data, &set, options, &|_, _| {})
        .unwrap_or_else(|e| panic!("{} / {model}: {e}", b.name));
    assert!(
        r.rms_log.is_finite() && r.relative_rms.is_finite(),
        "{} / {model}: {} {}",
        b.name,
        r.rms_log,
        r.relative_rms
    );
    r
}

#[test]
fn one_dataset_of_each_family_fits_with_the_baselines() {
    let mut seen = Vec::new();
    for b in bundled() {
        if seen.contains(&b.family) {
            continue;
        }
        seen.push(b.family);
        let lambert = fit_bundled(&b, ModelKind::Lambert, None, &FitOptions::default());
        let microfacet = fit_bundled(&b, ModelKind::Microfacet, None, &FitOptions::default());
        // The microfacet model contains Lambert (specular → 0): its optimum is no worse.
        assert!(
            microfacet.rms_log <= lambert.rms_log + 1e-6,
            "{}: microfacet {} vs lambert {}",
            b.name,
            microfacet.rms_log,
            lambert.rms_log
        );
    }
    assert!(seen.len() >= 4, "{seen:?}");
}

/// The cloth model on CUReT's linen with a single-orientation yarn and four parameters free
/// (roughness, diffuse albedo, the weave's rotation, the scale of the relative data): it fits
/// better than Lambert.
#[test]
fn the_cloth_model_fits_curet_linen() {
    let b = bundled()
        .into_iter()
        .find(|b| b.name.contains("linen"))
        .unwrap();
    let sateen = Material::preset("polyester-sateen").unwrap();
    let data = b.load().unwrap();
    let mut set = ParamSet::new(ModelKind::Cloth, Some(&sateen), 1, data.relative).unwrap();
    for p in &mut set.params {
        p.free = false;
    }
    for name in ["roughness", "fiber.diffuse", "rotation", "scale"] {
        set.free(name).unwrap();
    }
    let options = FitOptions {
        starts: 8,
        max_iterations: 10,
        ..FitOptions::default()
    };
    let cloth = fit(&data, &set, &options, &|_, _| {}).unwrap();
    let lambert = fit_bundled(&b, ModelKind::Lambert, None, &FitOptions::default());
    println!("{}", cloth.to_markdown());
    assert!(
        cloth.rms_log < lambert.rms_log,
        "cloth {} vs lambert {}",
        cloth.rms_log,
        lambert.rms_log
    );
    assert!(Material::from_toml_str(&cloth.material_toml().unwrap(), "fitted.toml").is_ok());
}

/// The cloth model contains a Lambertian surface (`ħ → 1`), so its fit must not be worse than
/// the Lambert fit. On MERL's light-brown fabric the single-orientation start used to end at an
/// RMS log error of 0.86 (Lambert: 0.37): the start that ranked best on the 64-point subset led
/// into a very smooth fiber whose specular peaks that subset misses.
#[test]
#[ignore = "slow: a full cloth fit of a 3757-point colour grid (~15 s on 2 cores); CI runs it"]
fn the_cloth_fit_of_merl_light_brown_is_no_worse_than_lambert() {
    let b = bundled()
        .into_iter()
        .find(|b| b.name == "light-brown-fabric")
        .unwrap();
    let sateen = Material::preset("polyester-sateen").unwrap();
    let options = FitOptions::default();
    let cloth = fit_bundled(&b, ModelKind::Cloth, Some(&sateen), &options);
    let lambert = fit_bundled(&b, ModelKind::Lambert, None, &options);
    assert!(
        cloth.rms_log <= lambert.rms_log,
        "cloth {} vs lambert {}",
        cloth.rms_log,
        lambert.rms_log
    );
}
