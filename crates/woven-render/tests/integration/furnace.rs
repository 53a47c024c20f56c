//! Furnaces: a woven sphere renders, pixel by pixel, to its directional albedo; a white woven
//! plane is nowhere brighter than the sky at any level of detail.

use crate::coarse_grid;
use woven::material::Material;
use woven::math::rng::SplitMix;
use woven::Vec3;
use woven_render::geometry::Frame;
use woven_render::material::ShadingPoint;
use woven_render::render::{render, RenderOptions};
use woven_render::scene::{Scene, SceneDescription};

/// Polyester sateen's yarn in the reciprocal normalization, all weft (`pattern = [[1]]`), on a
/// sphere of radius 1 in a uniform sky of radiance 1, one bounce (`max_depth = 2`), the sky
/// hidden. With `f` reciprocal, a pixel whose view direction is `v` (local frame) sees
/// `∫ f(s, v) cos θs dωs = ∫ f(v, s) cos θs dωs`: the directional albedo `A(v)` for light from
/// `v`, what `woven albedo` states. Each pixel well inside the disc must equal `A` averaged
/// over the pixel (4 × 4 positions, each `A` estimated by the material's own BSDF sampling,
/// 512 draws — a strategy independent of the render's light sampling), within 5 combined
/// standard errors and 0.3 %, and their mean within 4 standard errors; and the table's `A` must agree with the exact model's albedo
/// (`Model::albedo`) to the coarse test grid's accuracy.
#[test]
fn a_woven_sphere_in_a_furnace_renders_its_directional_albedo() {
    let dir = tempfile::tempdir().unwrap();
    let mut sateen = Material::preset("polyester-sateen").unwrap();
    sateen.fiber.normalization = woven::fiber::Normalization::None;
    std::fs::write(dir.path().join("sateen.toml"), sateen.to_toml_string()).unwrap();
    let (w, h) = (24usize, 24usize);
    let text = format!(
        r#"
        [camera]
        origin = [0, -4, 0]
        target = [0, 0, 0]
        up = [0, 0, 1]
        fov_deg = 40
        [film]
        width = {w}
        height = {h}
        spp = 512
        sampler = "independent"
        [integrator]
        max_depth = 2
        hide_emitters = true
        [[light]]
        type = "environment"
        radiance = [1, 1, 1]
        [[shape]]
        type = "sphere"
        center = [0, 0, 0]
        radius = 1
        material = "sateen"
        [material.sateen]
        type = "woven"
        material = "sateen.toml"
        pattern = [[1]]
        yarns_per_unit = 10.0
        # Each pixel against the yarn's directional albedo: the yarn's BRDF at every point (fibres
        # average to it over a yarn's width, not per pixel).
        detail = "yarns"
        "#
    );
    let desc = SceneDescription::from_str(&text, "<furnace>", dir.path()).unwrap();
    let scene = Scene::build(&desc, &coarse_grid(), &|_| {}, &|_, _| {}).unwrap();
    let image = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!(
        image.invalid_samples, 0,
        "NaN, infinite or negative samples"
    );
    let material = &scene.materials[0];

    // A(v) by the material's own sampling: the mean of f cos θ / p over stratified draws.
    let albedo_at = |v: Vec3, rng: &mut SplitMix| -> (f64, f64) {
        let n = 512usize;
        let (mut sum, mut sum2) = (0.0, 0.0);
        for k in 0..n {
            let u1 = ((k / 16) as f64 + rng.uniform()) / 32.0;
            let u2 = ((k % 16) as f64 + rng.uniform()) / 16.0;
            let at = ShadingPoint::default();
            let x = match material.sample(v, &at, 0.5, [u1, u2]) {
                Some(s) => s.f.0[1] * s.wi.z / s.pdf,
                None => 0.0,
            };
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / n as f64;
        (
            mean,
            ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
        )
    };

    let mut rng = SplitMix(11);
    let centre = [w as f64 / 2.0, h as f64 / 2.0];
    // The disc's radius in pixels: sin of the half angle the sphere subtends over the film's
    // half-width tangent.
    let disc = (1.0f64 / 15.0).sqrt() / (20f64).to_radians().tan() * w as f64 / 2.0;
    let (mut checked, mut worst) = (0, 0.0f64);
    // The sum of the differences and of their variances: the mean must hold far tighter.
    let (mut diff, mut diff_var, mut total) = (0.0, 0.0, 0.0);
    let mut views = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let r = ((x as f64 + 0.5 - centre[0]).powi(2) + (y as f64 + 0.5 - centre[1]).powi(2))
                .sqrt();
            if r > 0.75 * disc {
                continue;
            }
            let (mut want, mut var) = (0.0, 0.0);
            for j in 0..4 {
                for i in 0..4 {
                    let ray = scene.camera.ray(
                        x as f64 + (i as f64 + 0.5) / 4.0,
                        y as f64 + (j as f64 + 0.5) / 4.0,
                    );
                    let hit = scene.accel.intersect(&ray, 0.0, f64::INFINITY).unwrap();
                    let v = Frame::from_hit(&hit).to_local(ray.d * -1.0);
                    let (a, se) = albedo_at(v, &mut rng);
                    want += a / 16.0;
                    var += (se / 16.0).powi(2);
                    if i == 0 && j == 0 && views.len() < 400 {
                        views.push((v, a, se));
                    }
                }
            }
            let got = image.at(x, y).0[1];
            let se = (image.std_error[y * w + x].0[1].powi(2) + var).sqrt();
            let z = (got - want).abs() / se;
            worst = worst.max(z);
            assert!(
                (got - want).abs() <= 5.0 * se + 3e-3 * want,
                "pixel ({x}, {y}): render {got}, albedo {want} (combined standard error {se})"
            );
            checked += 1;
            diff += got - want;
            diff_var += se * se;
            total += want;
        }
    }
    assert!(checked > 100, "only {checked} pixels checked");
    let (bias, bias_se) = (diff / total, diff_var.sqrt() / total);
    println!("{checked} pixels, largest |z| {worst:.2}, mean difference {bias:+.5} ± {bias_se:.5}");
    assert!(
        bias.abs() <= 4.0 * bias_se,
        "the render is {bias:+.5} (relative, ± {bias_se:.5}) off the albedo on average"
    );

    // The table's A against the exact model's albedo at three of the pixels' view directions.
    let model = sateen.build(550.0).unwrap();
    for &(v, a, se) in [views[0], views[views.len() / 2], views[views.len() - 1]].iter() {
        let exact = model.albedo(v.z.acos(), v.y.atan2(v.x));
        println!("A({v:?}): table {a} ± {se}, exact {exact}");
        assert!(
            (a - exact).abs() <= 5.0 * se + 0.03 * exact,
            "A at {v:?}: table {a} ± {se}, exact {exact}"
        );
    }
}

#[path = "../support/white_plane.rs"]
mod white_plane_scene;
pub use white_plane_scene::{furnace_figures, white_plane};

/// Renders the white plane of every preset at each level, without the relief (fibres, auto,
/// yarns, cloth) and with it (fibres, auto), flat and tilted with gaps, at 16 cells and at 128
/// (many yarns, whose drawn slopes average out); asserts no pixel above 1 by more than its
/// noise and, at 128 cells, the levels' means within 1 % of the cloth level's without the relief
/// (one macro BRDF: the paper's), the fibres' within 2 % of `auto` far away with it (the
/// ratio-scaled macro lobes); prints the figures.
fn white_planes(presets: &[&str], px: usize, spp: usize) {
    const LEVELS: [(&str, bool); 6] = [
        ("fibers", false),
        ("auto", false),
        ("yarns", false),
        ("cloth", false),
        ("fibers", true),
        ("auto", true),
    ];
    for preset in presets.iter().copied() {
        for (u_max, gap) in [(0.0, 0.0), (60.0, 0.3)] {
            for cells in [16, 128] {
                let (mut means, mut noise) = (Vec::new(), Vec::new());
                for (detail, relief) in LEVELS {
                    let text = white_plane(preset, (detail, relief, u_max, gap), cells, px, spp);
                    let image = crate::render_text(&text);
                    let (brightest, above, mean, excess, mean_se) = furnace_figures(&image);
                    let what = format!(
                        "{preset} {detail} relief {relief} u_max {u_max}° gap {gap}, {cells} cells"
                    );
                    eprintln!(
                        "white furnace: {what}: brightest {brightest:.3}, above 1.05 {:.1} %, \
                         mean {mean:.4}, most above 1: {excess:.1} standard errors",
                        100.0 * above
                    );
                    // Independent samples: a pixel above 1 by more than 5 of its standard
                    // errors is no noise (1 in 10⁶ per pixel for a normal mean).
                    assert!(
                        excess <= 5.0,
                        "{what}: a pixel {excess} standard errors above 1"
                    );
                    means.push(mean);
                    noise.push(mean_se);
                }
                if cells < 128 {
                    continue;
                }
                // Within 1 % (2 % on the relief) and the two means' noise (3 standard errors
                // of their difference).
                let agree = |a: usize, b: usize, within: f64| {
                    let se = noise[a].hypot(noise[b]);
                    assert!(
                        (means[a] - means[b]).abs() <= within * means[b] + 3.0 * se,
                        "{preset} u_max {u_max}° gap {gap}: {:?} mean {} vs {:?} {} (± {se:.4})",
                        LEVELS[a],
                        means[a],
                        LEVELS[b],
                        means[b]
                    );
                };
                for level in 0..3 {
                    agree(level, 3, 0.01);
                }
                agree(4, 5, 0.02);
            }
        }
    }
}

/// A white woven plane in a furnace is nowhere brighter than the sky, at every level of detail,
/// with and without tilt and gaps, with and without the relief (the sateen); the levels keep one
/// mean. The same plane at 128 × 128 pixels and 256 samples, docs/render.md's table, takes
/// minutes: `cargo run --release -p woven-render --example furnace_table`.
#[test]
fn a_white_woven_plane_is_nowhere_brighter_than_the_furnace() {
    white_planes(&["polyester-sateen"], 24, 64);
}
