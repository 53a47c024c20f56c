//! The denoiser on a render whose every pixel is known: a diffuse sphere in a uniform sky.

use woven_render::render::{render, RenderOptions};
use woven_render::scene::{Scene, SceneDescription};

/// A Lambertian sphere (ρ = 0.5) in a uniform sky of radiance 1, direct light only, the sky
/// hidden: every pixel inside the disc is exactly 0.5 and every pixel outside it 0. At 4 spp the
/// denoised pixels inside the disc must be 4× closer to 0.5 (RMS) than the raw ones, with the
/// same mean within 1 %; the background, which has no noise, stays exactly black (the rim's
/// pixels, partly sky, give it nothing).
#[test]
fn denoising_a_furnace_sphere_leaves_its_exact_value() {
    let (w, h) = (64usize, 64usize);
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
        spp = 4
        sampler = "independent"
        denoise = true
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
        material = "white"
        [material.white]
        type = "diffuse"
        reflectance = [0.5, 0.5, 0.5]
        "#
    );
    let desc =
        SceneDescription::from_str(&text, "furnace.toml", std::path::Path::new(".")).unwrap();
    let scene = Scene::build(&desc, &Default::default(), &|_| {}, &|_, _| {}).unwrap();
    let image = render(&scene, &RenderOptions::default()).unwrap();
    let noisy = image.noisy.as_ref().expect("the raw means are kept");
    // The disc's radius on the film: the sphere subtends asin(1/4) of the 20° half-field.
    let radius = (0.25f64.asin().tan() / 20f64.to_radians().tan()) * w as f64 / 2.0;
    let (mut raw, mut denoised, mut mean, mut n) = (0.0, 0.0, 0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            let r =
                ((x as f64 + 0.5 - w as f64 / 2.0).hypot(y as f64 + 0.5 - h as f64 / 2.0)) / radius;
            let (a, b) = (noisy[y * w + x].luminance(), image.at(x, y).luminance());
            if r < 0.9 {
                raw += (a - 0.5).powi(2);
                denoised += (b - 0.5).powi(2);
                mean += b;
                n += 1.0;
            } else if r > 1.1 {
                assert_eq!(b, 0.0, "background pixel ({x}, {y})");
            }
        }
    }
    let (raw, denoised, mean) = ((raw / n).sqrt(), (denoised / n).sqrt(), mean / n);
    assert!(
        denoised < raw / 4.0,
        "RMS {raw:.4} raw, {denoised:.4} denoised"
    );
    assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
}
