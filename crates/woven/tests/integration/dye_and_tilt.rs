//! Options beyond the paper that a material file may carry: `[dye]` (the weft's and the warp's
//! colours), `[yarn] u_max_deg` (floats tilted along their length) with `float_crest` and
//! `float_flank` (their shape), and `[fiber] body_gloss` (a glossy body). Off, the material is
//! the paper's model exactly; on, the BRDF stays consistent with its parts and with energy.

use std::f64::consts::FRAC_PI_2;
use woven::color::Rgb;
use woven::material::{Dye, Material};
use woven::math::rng::SplitMix;
use woven::surface::SurfaceSpec;
use woven::Vec3;

fn tilted(name: &str, deg: f64) -> Material {
    let mut m = Material::preset(name).unwrap();
    m.yarn.as_mut().unwrap().u_max = deg.to_radians();
    m
}

fn shaped(name: &str, deg: f64, crest: f64, flank: f64) -> Material {
    let mut m = tilted(name, deg);
    let y = m.yarn.as_mut().unwrap();
    (y.float_crest, y.float_flank) = (crest, flank);
    m
}

#[test]
fn float_shape_and_body_gloss_round_trip_and_are_validated() {
    let mut m = shaped("belt-cloth", 25.0, 0.4, 0.2);
    (m.fiber.body_gloss, m.fiber.body_roughness) = (0.7, 0.12);
    let text = m.to_toml_string();
    let back = Material::from_toml_str(&text, "<test>").unwrap();
    assert_eq!(back.yarn, m.yarn);
    assert_eq!(back.fiber, m.fiber);
    let paper = Material::preset("belt-cloth").unwrap().to_toml_string();
    for key in ["float_crest", "float_flank", "body_gloss", "body_roughness"] {
        assert!(text.contains(key) && !paper.contains(key), "{key}: {text}");
    }
    for (from, to, key) in [
        ("float_flank = 0.2", "float_flank = 0.3", "yarn.float_flank"),
        (
            "float_crest = 0.4",
            "float_crest = 0.95",
            "yarn.float_crest",
        ),
        ("u_max_deg = 25", "u_max_deg = 0", "yarn.float_crest"),
        ("body_gloss = 0.7", "body_gloss = 1.2", "fiber.body_gloss"),
        (
            "body_roughness = 0.12",
            "body_roughness = 0.001",
            "fiber.body_roughness",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let e = Material::from_toml_str(&text.replace(from, to), "<test>")
            .unwrap_err()
            .to_string();
        assert!(e.contains(key), "{to}: {e}");
    }
}

/// A float pressed flat on top keeps more of the flat floats' mirror peak than a linear tilt to
/// the same angle, which spreads its facets evenly.
#[test]
fn a_pressed_float_keeps_the_mirror_peak() {
    let t = 30f64.to_radians();
    let (s, c) = t.sin_cos();
    // filament-satin is warp-faced: its floats run along y; light in the xz plane.
    let (wi, mirror) = (Vec3::new(s, 0.0, c), Vec3::new(-s, 0.0, c));
    let linear = tilted("filament-satin", 30.0).build(550.0).unwrap();
    let pressed = shaped("filament-satin", 30.0, 0.6, 0.1)
        .build(550.0)
        .unwrap();
    let (a, b) = (linear.eval(wi, mirror), pressed.eval(wi, mirror));
    assert!(b > 1.5 * a, "pressed {b} vs linear {a}");
}

#[test]
fn dye_and_tilt_round_trip_through_toml_and_are_validated() {
    let mut m = tilted("belt-cloth", 25.0);
    m.dye = Dye {
        weft: Some(Rgb([0.5, 0.1, 0.05])),
        warp: Some(Rgb([0.02, 0.3, 0.6])),
    };
    let text = m.to_toml_string();
    assert!(
        text.contains("u_max_deg") && text.contains("[dye]"),
        "{text}"
    );
    let back = Material::from_toml_str(&text, "<test>").unwrap();
    assert_eq!(back.dye, m.dye);
    assert!((back.yarn.unwrap().u_max - m.yarn.unwrap().u_max).abs() < 1e-15);
    // Off, neither is written: a paper preset's file is unchanged.
    let paper = Material::preset("belt-cloth").unwrap().to_toml_string();
    assert!(
        !paper.contains("u_max_deg") && !paper.contains("[dye]"),
        "{paper}"
    );

    let bad = text.replace("0.5,", "1.5,");
    let e = Material::from_toml_str(&bad, "<test>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("dye.weft") && e.contains("[0, 1]"), "{e}");
    let steep = text.replace("u_max_deg = 25", "u_max_deg = 85");
    let e = Material::from_toml_str(&steep, "<test>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("yarn.u_max_deg") && e.contains("80"), "{e}");
    let flat = "[fiber]\nmodel = \"rough\"\neta = 1.5\nroughness = 0.1\ndiffuse = 0.2\n\
                [dye]\nwarp = [0.1, 0.2, 0.3]\n";
    let e = Material::from_toml_str(flat, "<test>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("dye.warp"), "{e}");
}

/// A surface laid from a material takes its dye and its tilt unless told otherwise, and renders
/// the yarn's table flat (the surface tilts the yarn itself).
#[test]
fn a_surface_takes_the_material_s_dye_and_tilt() {
    let mut m = tilted("filament-satin", 30.0);
    m.dye.weft = Some(Rgb([0.4, 0.2, 0.1]));
    let spec = SurfaceSpec::new(m.clone());
    assert_eq!(spec.weft_color, m.dye.weft);
    assert_eq!(spec.warp_color, None);
    assert!((spec.u_max - 30f64.to_radians()).abs() < 1e-15);
    assert_eq!(spec.table_material().yarn.unwrap().u_max, 0.0);
}

/// A float tilted by a vanishing angle is the flat yarn: the whole-float average tends to the
/// paper's Eq. (23).
#[test]
fn a_barely_tilted_float_is_the_flat_cloth() {
    for name in ["filament-satin", "belt-cloth", "silk"] {
        let flat = Material::preset(name).unwrap().build(550.0).unwrap();
        // 12 pairs: a twisted or isotropic yarn's tilted evaluation costs 16 flat ones.
        let tilt = tilted(name, 1e-4).build(550.0).unwrap();
        let mut rng = SplitMix(3);
        for _ in 0..12 {
            let (s, v) = (rng.direction(1.3), rng.direction(1.3));
            let (a, b) = (flat.eval(s, v), tilt.eval(s, v));
            assert!(
                (a - b).abs() <= 1e-3 * a + 1e-9,
                "{name} {s:?} {v:?}: {a} vs {b}"
            );
        }
    }
}

/// Tilting floats spreads a satin's highlight along them: light across the floats, the viewer
/// tilted 30° along them sees more of it than on flat floats, and the mirror direction less.
#[test]
fn tilted_floats_spread_the_sheen_along_them() {
    let t = 30f64.to_radians();
    let (s, c) = t.sin_cos();
    // filament-satin is warp-faced: its floats run along y; light in the xz plane.
    let wi = Vec3::new(s, 0.0, c);
    let (mirror, off) = (Vec3::new(-s, 0.0, c), Vec3::new(-s * c, s, c * c));
    let flat = Material::preset("filament-satin")
        .unwrap()
        .build(550.0)
        .unwrap();
    let tilt = tilted("filament-satin", 30.0).build(550.0).unwrap();
    let ratio = |m: &woven::Model| m.eval(wi, mirror) / m.eval(wi, off);
    assert!(
        ratio(&tilt) < 0.8 * ratio(&flat),
        "{} vs {}",
        ratio(&tilt),
        ratio(&flat)
    );
}

/// The white furnace: a tilted cloth of white fibres reflects no more than it receives, for
/// light from anywhere (the whole-float average weights facets by their lit and seen areas).
/// Yarns of one orientation (an exact tilted evaluation of a twisted or isotropic yarn costs
/// 16 of theirs, too slow for a hemisphere of them here; the surface's tilted lobes over every
/// preset are in energy.rs).
#[test]
fn a_tilted_cloth_reflects_no_more_than_it_receives() {
    // Shaped floats and glossy bodies: the grounded presets' furnace (grounded.rs).
    for (name, deg) in [
        ("filament-satin", 40.0),
        ("filament-satin", 75.0),
        ("polyester-sateen", 25.0),
    ] {
        let mut m = tilted(name, deg);
        m.fiber.diffuse = 0.999;
        if let Some(y) = &mut m.yarn {
            y.interreflection_albedo = 1.0;
        }
        let model = m.build(550.0).unwrap();
        for theta in [0.0, 0.9, 1.4] {
            for phi in [0.3, FRAC_PI_2] {
                let a = model.albedo(theta, phi);
                assert!(a <= 1.0 + 2e-3, "{name} at θ {theta} φ {phi}: albedo {a}");
            }
        }
    }
}

/// The dye rule on colours out of range: a NaN channel (a bad texel) is black, an infinite or
/// large one is kept below 1, a negative one is 0; every albedo it gives is finite and in range.
#[test]
fn the_dye_rule_keeps_bad_colours_in_range() {
    use woven::table::Albedos;
    let own = Albedos::of(&Material::preset("polyester-sateen").unwrap());
    let dyed = own.dyed(Some(Rgb([f64::NAN, f64::INFINITY, -2.0])));
    assert_eq!(dyed.map(|a| a.diffuse), [0.0, 0.999, 0.0]);
    for a in dyed {
        assert!((0.0..=1.0).contains(&a.interreflection), "{a:?}");
    }
    assert_eq!(dyed[0].interreflection, 0.0);
}
