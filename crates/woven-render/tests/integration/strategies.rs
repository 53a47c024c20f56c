//! BSDF sampling only, light sampling only and MIS converge to the same image.

use crate::render_text;
use woven_render::render::Image;

/// A diffuse floor, a sphere of `sphere_material`, a rectangle light and a uniform environment;
/// three bounces.
fn scene(strategy: &str, materials: &str, sphere_material: &str) -> String {
    format!(
        r#"
        [camera]
        origin = [0, -3, 1.5]
        target = [0, 0, 0.4]
        fov_deg = 50
        [film]
        width = 16
        height = 12
        spp = 256
        sampler = "independent"
        seed = 11
        [integrator]
        max_depth = 4
        strategy = "{strategy}"
        [[light]]
        type = "rectangle"
        corner = [-0.5, -0.5, 2.0]
        edge_u = [0, 1, 0]
        edge_v = [1, 0, 0]
        radiance = [4, 4, 4]
        [[light]]
        type = "environment"
        radiance = [0.3, 0.4, 0.5]
        [[shape]]
        type = "rectangle"
        corner = [-2, -2, 0]
        edge_u = [4, 0, 0]
        edge_v = [0, 4, 0]
        material = "floor"
        [[shape]]
        type = "sphere"
        center = [0, 0, 0.5]
        radius = 0.5
        material = "{sphere_material}"
        [material.floor]
        type = "diffuse"
        reflectance = [0.6, 0.5, 0.4]
        {materials}
        "#
    )
}

/// Compares 4 × 4-pixel blocks of two renders: each block mean agrees within `z_max` combined
/// standard errors.
fn assert_agree(a: &Image, b: &Image, what: &str, z_max: f64) {
    let mut worst = 0.0f64;
    for by in 0..a.height / 4 {
        for bx in 0..a.width / 4 {
            for c in 0..3 {
                let (mut ma, mut mb, mut va, mut vb) = (0.0, 0.0, 0.0, 0.0);
                for y in by * 4..by * 4 + 4 {
                    for x in bx * 4..bx * 4 + 4 {
                        let i = y * a.width + x;
                        ma += a.pixels[i].0[c] / 16.0;
                        mb += b.pixels[i].0[c] / 16.0;
                        va += (a.std_error[i].0[c] / 16.0).powi(2);
                        vb += (b.std_error[i].0[c] / 16.0).powi(2);
                    }
                }
                let z = (ma - mb).abs() / (va + vb).sqrt().max(1e-12);
                worst = worst.max(z);
                assert!(
                    z < z_max,
                    "{what}: block ({bx}, {by}) channel {c}: {ma} vs {mb}, z = {z:.2}"
                );
            }
        }
    }
    // Disagreements of a few standard errors happen; a test whose worst block is 0 compared
    // nothing.
    assert!(worst > 0.0, "{what}: identical images");
}

fn check(materials: &str, sphere: &str) {
    let mis = render_text(&scene("mis", materials, sphere));
    let bsdf = render_text(&scene("bsdf", materials, sphere));
    let light = render_text(&scene("light", materials, sphere));
    // 12 blocks × 3 channels × 2 comparisons: 4.5 standard errors keep false alarms < 1e-3.
    assert_agree(&mis, &bsdf, "MIS vs BSDF only", 4.5);
    assert_agree(&mis, &light, "MIS vs light only", 4.5);
}

#[test]
fn strategies_agree_on_diffuse_surfaces() {
    check("", "floor");
}

/// The woven material (a flat rough fiber surface, not reciprocal in paper normalization):
/// the swapped-role sampling and its density must make the three estimators agree.
#[test]
fn strategies_agree_on_a_woven_surface() {
    let materials = r#"
        [material.cloth]
        type = "woven"
        material = "fiber.toml"
        "#;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("fiber.toml"),
        "[fiber]\neta = 1.6\nroughness = 0.15\ndiffuse = 0.3\nnormalization = \"paper\"\n",
    )
    .unwrap();
    let run = |strategy: &str| {
        let text = scene(strategy, materials, "cloth");
        let desc =
            woven_render::scene::SceneDescription::from_str(&text, "<test>", dir.path()).unwrap();
        let scene =
            woven_render::scene::Scene::build(&desc, &crate::coarse_grid(), &|_| {}, &|_, _| {})
                .unwrap();
        let image = woven_render::render::render(&scene, &Default::default()).unwrap();
        assert_eq!(image.invalid_samples, 0);
        image
    };
    let (mis, bsdf, light) = (run("mis"), run("bsdf"), run("light"));
    assert_agree(&mis, &bsdf, "woven: MIS vs BSDF only", 4.5);
    assert_agree(&mis, &light, "woven: MIS vs light only", 4.5);
}

/// A patterned weave whose cells are about a pixel wide (the footprint filter blends each cell
/// with the γ-mix; reflected rays see the macro BRDF), with tilted yarns and gaps: every vertex
/// mixes several lobes, and the three estimators still agree.
#[test]
fn strategies_agree_on_a_filtered_tilted_gapped_weave() {
    check(
        r#"
        [material.cloth]
        type = "woven"
        material = "polyester-sateen"
        pattern = "twill-2/1"
        yarns_per_unit = 15
        u_max_deg = 25
        gap = 0.15
        "#,
        "cloth",
    );
}

/// Lights picked in proportion to unequal `sampling_weight`s (the rectangle ten times as often
/// as the environment) render the same image as a uniform choice, with MIS and with light
/// sampling alone (where the choice's probability is the whole light density).
#[test]
fn light_sampling_weights_change_the_noise_not_the_image() {
    let weighted = |strategy: &str| {
        scene(strategy, "", "floor")
            .replace(
                "radiance = [4, 4, 4]",
                "radiance = [4, 4, 4]\n        sampling_weight = 5",
            )
            .replace(
                "radiance = [0.3, 0.4, 0.5]",
                "radiance = [0.3, 0.4, 0.5]\n        sampling_weight = 0.5",
            )
    };
    assert!(weighted("mis").contains("sampling_weight = 5"));
    let uniform = render_text(&scene("mis", "", "floor"));
    for strategy in ["mis", "light"] {
        let image = render_text(&weighted(strategy));
        assert_agree(
            &uniform,
            &image,
            &format!("{strategy}: weighted vs uniform light choice"),
            4.5,
        );
    }
}
