//! The presets grounded in measured fabrics ([`Material::grounded_preset_names`]): the woven
//! model fitted to the microcylinder fabrics, with shaped floats and glossy fibre bodies. Each
//! loads with its dyes and its figures, keeps the white furnace, and samples its own density,
//! at fibre level and as a whole cloth.

use std::sync::Arc;
use woven::material::{Dye, Material};
use woven::surface::{Detail, SurfacePoint, SurfaceSpec, WovenSurface};
use woven::table::{Table, TableOptions};

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
    // One direction each (an exact tilted albedo costs seconds), grazing for the two satin-like
    // filaments, where a glossy lobe's energy is hardest to keep.
    let directions = [(1.45, 0.4), (0.6, 1.3), (1.0, 0.4), (1.45, 1.3)];
    for (name, (theta, phi)) in Material::grounded_preset_names().iter().zip(directions) {
        let mut m = Material::preset(name).unwrap();
        m.dye = Dye::default();
        m.fiber.diffuse = 0.999;
        if let Some(y) = &mut m.yarn {
            y.interreflection_albedo = 1.0;
        }
        let a = m.build(550.0).unwrap().albedo(theta, phi);
        assert!(a <= 1.0 + 2e-3, "{name} at θ {theta} φ {phi}: albedo {a}");
        assert!(a > 0.3, "{name} at θ {theta} φ {phi}: albedo {a}");
    }
}

/// χ² of a grounded preset's draws against its density, laid on a surface as a scene lays it
/// (its own weave, tilt, float shape, glossy body and dyes): a point of a float at fibre level
/// at 25° and the whole cloth at 70°.
#[test]
fn grounded_presets_sample_their_density() {
    let mut k = 0;
    for name in Material::grounded_preset_names() {
        let material = Material::preset(name).unwrap();
        let m = SurfaceSpec::new(material.clone()).table_material();
        let options = TableOptions {
            n_theta: 4,
            n_phi: 3,
            n_h: 11,
            colour: true,
            ..TableOptions::default()
        };
        let table =
            Arc::new(Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap());
        for (detail, theta_deg) in [(Detail::Fibers, 25.0), (Detail::Cloth, 70.0)] {
            let spec = SurfaceSpec {
                yarns_per_unit: [1.0, 1.0],
                detail,
                ..SurfaceSpec::new(material.clone())
            };
            let surface = WovenSurface::new(&spec, table.clone()).unwrap();
            let at = SurfacePoint {
                uv: [0.5, 0.37],
                footprint: [[0.0; 2]; 2],
            };
            let bsdf = surface.at(&at);
            {
                let (p, accepted, integral) =
                    crate::surface::radiance_chi2(&bsdf, theta_deg, 40_000, 300 + k);
                k += 1;
                // Eight tests: Bonferroni at 1 %.
                assert!(
                    p > 0.01 / 8.0,
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
