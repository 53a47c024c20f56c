//! The presets grounded in measured fabrics ([`Material::grounded_preset_names`]): the woven
//! model fitted to the microcylinder fabrics, with shaped floats and glossy fibre bodies. Each
//! loads with its dyes and its figures, keeps the white furnace, and samples its own density,
//! at fibre level and as a whole cloth.

use std::sync::Arc;
use woven::bsdf::{Bsdf, Transport};
use woven::material::{Dye, Material};
use woven::surface::{Detail, SurfacePoint, SurfaceSpec, WovenSurface};
use woven::table::{Table, TableOptions};
use woven::Vec3;

#[test]
fn grounded_presets_load_with_their_dyes_figures_and_options() {
    for name in Material::grounded_preset_names() {
        let m = Material::preset(name).unwrap();
        assert!(m.dye.weft.is_some(), "{name}: no weft dye");
        assert!(!Material::preset_names().contains(name), "{name}");
        assert!(Material::all_preset_names().contains(name), "{name}");
        let text = Material::preset_toml(name).unwrap();
        for what in [
            "RMS log error",
            "Beckmann + Lambert",
            "microcylinder-",
            "Regenerate",
        ] {
            assert!(text.contains(what), "{name}: its header lacks {what:?}");
        }
        // Every fit uses the glossy body; the filament fabrics shape their floats.
        assert!(m.fiber.body_gloss > 0.0, "{name}");
        assert!(m.yarn.unwrap().u_max > 0.0, "{name}");
    }
}

/// The white furnace: each grounded preset with white fibres and white interreflection reflects
/// no more than it receives (its dyes are albedos in [0, 1], checked when it loads).
#[test]
fn a_white_grounded_preset_reflects_no_more_than_it_receives() {
    for name in Material::grounded_preset_names() {
        let mut m = Material::preset(name).unwrap();
        m.dye = Dye::default();
        m.fiber.diffuse = 0.999;
        if let Some(y) = &mut m.yarn {
            y.interreflection_albedo = 1.0;
        }
        let model = m.build(550.0).unwrap();
        for (theta, phi) in [(0.2, 0.4), (1.0, 1.3), (1.45, 0.4)] {
            let a = model.albedo(theta, phi);
            assert!(a <= 1.0 + 2e-3, "{name} at θ {theta} φ {phi}: albedo {a}");
            assert!(a > 0.3, "{name} at θ {theta} φ {phi}: albedo {a}");
        }
    }
}

/// χ² of a grounded preset's draws against its density, laid on a surface as a scene lays it
/// (its own weave, tilt, float shape, glossy body and dyes): a point of a float at fibre level
/// and the whole cloth, at two incidences each.
#[test]
fn grounded_presets_sample_their_density() {
    let mut k = 0;
    for name in Material::grounded_preset_names() {
        for detail in [Detail::Fibers, Detail::Cloth] {
            let spec = SurfaceSpec {
                yarns_per_unit: [1.0, 1.0],
                detail,
                ..SurfaceSpec::new(Material::preset(name).unwrap())
            };
            let m = spec.table_material();
            let options = TableOptions {
                n_theta: 4,
                n_phi: 3,
                n_h: 11,
                colour: true,
                ..TableOptions::default()
            };
            let table = Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap();
            let surface = WovenSurface::new(&spec, Arc::new(table)).unwrap();
            let at = SurfacePoint {
                uv: [0.5, 0.37],
                footprint: [[0.0; 2]; 2],
            };
            let bsdf = surface.at(&at);
            for theta_deg in [25.0, 70.0] {
                let wo = Vec3::from_spherical(f64::to_radians(theta_deg), 0.7);
                let (p, accepted, integral) = crate::table::chi2_of(
                    |rng| {
                        bsdf.sample(
                            wo,
                            rng.uniform(),
                            [rng.uniform(), rng.uniform()],
                            Transport::Radiance,
                        )
                        .map(|s| s.wi)
                    },
                    |wi| bsdf.pdf(wi, wo, Transport::Radiance),
                    50_000,
                    300 + k,
                );
                k += 1;
                // Sixteen tests: Bonferroni at 1 %.
                assert!(
                    p > 0.01 / 16.0,
                    "{name} {detail:?} at θo {theta_deg}°: p {p:.2e}"
                );
                assert!(
                    (integral - accepted).abs() < 0.01,
                    "{name} {detail:?}: ∫pdf {integral} vs accepted {accepted}"
                );
            }
        }
    }
}
