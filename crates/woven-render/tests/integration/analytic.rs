//! Images with known answers.

use crate::render_text;
use std::f64::consts::PI;
use woven::Vec3;
use woven_render::camera::Camera;

/// A diffuse rectangle under a point light: every pixel is `ρ/π · I cos θ / r²` averaged over
/// the pixel's area, within a small multiple of its standard error.
#[test]
fn diffuse_rectangle_under_a_point_light_is_analytic() {
    let (w, h) = (24, 16);
    let text = format!(
        r#"
        [camera]
        origin = [0.3, -2.0, 2.2]
        target = [0.0, 0.0, 0.0]
        up = [0, 0, 1]
        fov_deg = 45
        [film]
        width = {w}
        height = {h}
        spp = 64
        sampler = "independent"
        seed = 3
        [integrator]
        max_depth = 2
        [[light]]
        type = "point"
        position = [0.4, 0.5, 1.5]
        intensity = [10, 5, 2]
        [[shape]]
        type = "rectangle"
        corner = [-1, -1, 0]
        edge_u = [2, 0, 0]
        edge_v = [0, 2, 0]
        material = "plane"
        [material.plane]
        type = "diffuse"
        reflectance = [0.5, 0.8, 0.2]
        "#
    );
    let image = render_text(&text);
    let camera = Camera::new(
        Vec3::new(0.3, -2.0, 2.2),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        45.0,
        w,
        h,
    );
    let light = Vec3::new(0.4, 0.5, 1.5);
    let (rho, intensity) = ([0.5, 0.8, 0.2], [10.0, 5.0, 2.0]);
    let n = 32; // the pixel integral by an n × n midpoint rule
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let mut expected = [0.0; 3];
            let mut covered = 0;
            for a in 0..n {
                for b in 0..n {
                    let ray = camera.ray(
                        x as f64 + (a as f64 + 0.5) / n as f64,
                        y as f64 + (b as f64 + 0.5) / n as f64,
                    );
                    if ray.d.z >= 0.0 {
                        continue;
                    }
                    let t = -ray.o.z / ray.d.z;
                    let p = ray.o + ray.d * t;
                    if p.x.abs() > 1.0 || p.y.abs() > 1.0 {
                        continue;
                    }
                    covered += 1;
                    let d = light - p;
                    let r2 = d.dot(d);
                    let cos = d.z / r2.sqrt();
                    for c in 0..3 {
                        expected[c] += rho[c] / PI * intensity[c] * cos / r2 / (n * n) as f64;
                    }
                }
            }
            if covered != 0 && covered != n * n {
                // On the rectangle's edge: the random samples cover it differently.
                continue;
            }
            let got = image.at(x, y).0;
            let se = image.std_error[y * w + x].0;
            for c in 0..3 {
                let tol = 5.0 * se[c] + 2e-3 * expected[c] + 1e-9;
                assert!(
                    (got[c] - expected[c]).abs() <= tol,
                    "pixel ({x}, {y}) channel {c}: rendered {} vs analytic {} (tolerance {tol})",
                    got[c],
                    expected[c]
                );
            }
            checked += (expected[0] > 0.0) as usize;
        }
    }
    assert!(
        checked > w * h / 3,
        "the plane covers only {checked} pixels"
    );
}

/// A white furnace with a grey sphere: a convex diffuse sphere of ρ = 0.5 in a uniform
/// environment of radiance 1 reflects exactly 0.5 everywhere (nothing it reflects returns to
/// it), whatever the depth; the background is the environment, 1.
#[test]
fn diffuse_sphere_in_a_furnace_is_half_grey() {
    let text = r#"
        [camera]
        origin = [0, 0, 4]
        target = [0, 0, 0]
        up = [0, 1, 0]
        fov_deg = 40
        [film]
        width = 16
        height = 16
        spp = 32
        sampler = "independent"
        [integrator]
        max_depth = -1
        [[light]]
        type = "environment"
        radiance = [1, 1, 1]
        [[shape]]
        type = "sphere"
        center = [0, 0, 0]
        radius = 1
        material = "grey"
        [material.grey]
        type = "diffuse"
        reflectance = [0.5, 0.5, 0.5]
    "#;
    let image = render_text(text);
    // Pixels within 0.6 of the disc's radius: on the sphere whatever the sample position.
    let half = (20f64).to_radians().tan() * 4.0; // the film's half width at the sphere's centre
    let disc = (1.0f64 / (16.0 - 1.0)).sqrt() * 4.0 / half * 8.0; // silhouette radius, pixels
    let (mut inside, mut mean, mut var) = (0, 0.0, 0.0);
    for y in 0..16 {
        for x in 0..16 {
            let r = ((x as f64 + 0.5 - 8.0).powi(2) + (y as f64 + 0.5 - 8.0).powi(2)).sqrt();
            let p = image.at(x, y).0[1];
            if r < 0.6 * disc {
                inside += 1;
                mean += p;
                var += image.std_error[y * 16 + x].0[1].powi(2);
            } else if r > disc + 1.5 {
                assert!((p - 1.0).abs() < 1e-12, "background ({x}, {y}) = {p}");
            }
        }
    }
    assert!(inside > 20);
    let mean = mean / inside as f64;
    let se = var.sqrt() / inside as f64;
    assert!(
        (mean - 0.5).abs() < 5.0 * se + 1e-6,
        "furnace mean {mean} vs 0.5 (standard error {se})"
    );
}

/// Mitsuba's depth: `max_depth = 1` shows emitters only (the sphere is black, the sky 1);
/// `hide_emitters` blacks out the directly seen sky but keeps its light on the sphere (0.5).
#[test]
fn depth_one_shows_emitters_only_and_hide_emitters_hides_them() {
    let scene = |integrator: &str| {
        format!(
            r#"
            [camera]
            origin = [0, 0, 4]
            target = [0, 0, 0]
            up = [0, 1, 0]
            fov_deg = 40
            [film]
            width = 8
            height = 8
            spp = 16
            sampler = "independent"
            [integrator]
            {integrator}
            [[light]]
            type = "environment"
            radiance = [1, 1, 1]
            [[shape]]
            type = "sphere"
            center = [0, 0, 0]
            radius = 1
            material = "grey"
            [material.grey]
            type = "diffuse"
            reflectance = [0.5, 0.5, 0.5]
            "#
        )
    };
    let emitters_only = render_text(&scene("max_depth = 1"));
    assert_eq!(emitters_only.at(4, 4).0, [0.0; 3]);
    assert_eq!(emitters_only.at(0, 0).0, [1.0; 3]);
    let hidden = render_text(&scene("max_depth = 2\nhide_emitters = true"));
    assert_eq!(hidden.at(0, 0).0, [0.0; 3]);
    let centre = hidden.at(4, 4).0[0];
    let se = hidden.std_error[4 * 8 + 4].0[0];
    assert!((centre - 0.5).abs() < 5.0 * se + 1e-6, "{centre} ± {se}");
}

/// A render depends on the seed only: one thread or two give the same image bit for bit; another
/// seed gives another image.
#[test]
fn renders_are_deterministic_for_a_seed() {
    use std::path::Path;
    use woven_render::render::{render, RenderOptions};
    use woven_render::scene::{Scene, SceneDescription};
    let text = |seed: u64| {
        format!(
            r#"
            [camera]
            origin = [0, -3, 2]
            target = [0, 0, 0]
            fov_deg = 50
            [film]
            width = 20
            height = 20
            spp = 4
            sampler = "independent"
            seed = {seed}
            [[light]]
            type = "environment"
            radiance = [1, 1, 1]
            [[shape]]
            type = "sphere"
            center = [0, 0, 0.5]
            radius = 0.5
            material = "grey"
            [[shape]]
            type = "rectangle"
            corner = [-2, -2, 0]
            edge_u = [4, 0, 0]
            edge_v = [0, 4, 0]
            material = "grey"
            [material.grey]
            type = "diffuse"
            reflectance = [0.7, 0.7, 0.7]
            "#
        )
    };
    let run = |seed: u64, threads: usize| {
        let desc = SceneDescription::from_str(&text(seed), "<test>", Path::new(".")).unwrap();
        let scene = Scene::build(&desc, &crate::coarse_grid(), &|_| {}, &|_, _| {}).unwrap();
        let options = RenderOptions {
            threads: Some(threads),
        };
        render(&scene, &options).unwrap().pixels
    };
    assert_eq!(run(1, 1), run(1, 2));
    assert_ne!(run(1, 2), run(2, 2));
}

/// The uniform materials a scene names beside woven cloth (a microcylinder fabric, Mitsuba's
/// rough plastic, the Charlie sheen) on a plane under a point light: the image is the library's
/// BSDF times the light's irradiance, pixel by pixel, within the noise of the draws (direct
/// light only: the light is a point, and nothing else is in view of the plane).
#[test]
fn uniform_materials_on_a_plane_under_a_point_light_are_their_library_bsdfs() {
    use woven::bsdf::Bsdf;
    use woven::color::Rgb;
    let (w, h) = (16, 12);
    let cases: [(&str, Box<dyn Bsdf<Value = Rgb>>); 3] = [
        (
            "type = \"microcylinder\"\nmaterial = \"microcylinder-silk-shot\"",
            Box::new(
                woven::microcylinder::Microcylinder::preset("microcylinder-silk-shot").unwrap(),
            ),
        ),
        (
            "type = \"roughplastic\"\nalpha = 0.3\ndiffuse_reflectance = [0.6, 0.3, 0.1]",
            Box::new(
                woven::baseline::RoughPlastic::new(&woven::baseline::RoughPlasticParams {
                    alpha: 0.3,
                    diffuse_reflectance: Rgb([0.6, 0.3, 0.1]),
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
        (
            "type = \"sheen\"\nroughness = 0.4\nsheen_color = [0.9, 0.8, 0.7]",
            Box::new(
                woven::baseline::Sheen::new(&woven::baseline::SheenParams {
                    roughness: 0.4,
                    sheen_color: Rgb([0.9, 0.8, 0.7]),
                    ..Default::default()
                })
                .unwrap(),
            ),
        ),
    ];
    let (origin, light) = (Vec3::new(0.3, -2.0, 2.2), Vec3::new(-0.6, 0.9, 1.2));
    for (material, bsdf) in cases {
        let text = format!(
            "[camera]\norigin = [0.3, -2.0, 2.2]\ntarget = [0, 0, 0]\nup = [0, 0, 1]\nfov_deg = 45\n\
             [film]\nwidth = {w}\nheight = {h}\nspp = 16\n[integrator]\nmax_depth = 2\n\
             [[light]]\ntype = \"point\"\nposition = [-0.6, 0.9, 1.2]\nintensity = [4, 4, 4]\n\
             [[shape]]\ntype = \"rectangle\"\ncorner = [-4, -4, 0]\nedge_u = [8, 0, 0]\n\
             edge_v = [0, 8, 0]\nmaterial = \"m\"\n[material.m]\n{material}\n"
        );
        let image = render_text(&text);
        let camera = Camera::new(origin, Vec3::new(0.0, 0.0, 0.0), Vec3::Z, 45.0, w, h);
        let n = 6;
        let (mut got, mut want) = (0.0, 0.0);
        for y in 0..h {
            for x in 0..w {
                let mut e = 0.0;
                for a in 0..n {
                    for b in 0..n {
                        let ray = camera.ray(
                            x as f64 + (a as f64 + 0.5) / n as f64,
                            y as f64 + (b as f64 + 0.5) / n as f64,
                        );
                        let p = ray.o + ray.d * (-ray.o.z / ray.d.z);
                        let d = light - p;
                        let r2 = d.dot(d);
                        let (wi, wo) = (d.normalize(), (origin - p).normalize());
                        e += bsdf.eval(wi, wo).luminance() * 4.0 * wi.z / r2 / (n * n) as f64;
                    }
                }
                want += e;
                got += image.at(x, y).luminance();
            }
        }
        assert!(
            (got - want).abs() <= 0.01 * want,
            "{material}: image {got} vs the library's BSDF {want}"
        );
    }
}
