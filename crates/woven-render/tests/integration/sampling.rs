//! The samplers: Sobol points render the same image as independent samples (no bias), with
//! less error for the same samples.

use crate::render_text;
use std::f64::consts::PI;
use woven::Vec3;
use woven_render::camera::Camera;

/// The irradiance at `p` (normal `n`) from a uniform polygon of unit radiance, all of it above
/// `p`'s horizon and unoccluded (Lambert's formula: half the sum over edges of the angle each
/// subtends times the cosine of its plane's normal with `n`).
fn polygon_irradiance(p: Vec3, n: Vec3, vertices: &[Vec3]) -> f64 {
    let mut sum = 0.0;
    for (k, a) in vertices.iter().enumerate() {
        let b = vertices[(k + 1) % vertices.len()];
        let (ua, ub) = ((*a - p).normalize(), (b - p).normalize());
        let angle = ua.dot(ub).clamp(-1.0, 1.0).acos();
        sum += angle * n.dot(ua.cross(ub).normalize());
    }
    0.5 * sum.abs()
}

/// A diffuse plane under a rectangular area light (direct lighting only), rendered with each
/// sampler at the same 64 spp, against the pixel averages of the analytic irradiance
/// (Lambert's polygon formula): both are unbiased, every Sobol pixel lies within five of the
/// independent render's standard errors, and the Sobol render's RMS error is under a quarter of
/// the independent one's (measured: 0.30 % against 2.9 %).
#[test]
fn sobol_points_render_an_area_light_without_bias_and_with_less_error() {
    let (w, h) = (24, 16);
    let (corner, edge_u, edge_v) = (
        Vec3::new(-0.3, -0.2, 1.2),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(0.6, 0.0, 0.0),
    );
    let (radiance, rho) = (4.0, 0.5);
    let scene = |sampler: &str| {
        format!(
            r#"
            [camera]
            origin = [0.3, -2.0, 2.2]
            target = [0.0, 0.0, 0.0]
            fov_deg = 45
            [film]
            width = {w}
            height = {h}
            spp = 64
            seed = 5
            sampler = "{sampler}"
            [integrator]
            max_depth = 2
            [[light]]
            type = "rectangle"
            corner = [{}, {}, {}]
            edge_u = [{}, {}, {}]
            edge_v = [{}, {}, {}]
            radiance = [{radiance}, {radiance}, {radiance}]
            [[shape]]
            type = "rectangle"
            corner = [-1, -1, 0]
            edge_u = [2, 0, 0]
            edge_v = [0, 2, 0]
            material = "plane"
            [material.plane]
            type = "diffuse"
            reflectance = [{rho}, {rho}, {rho}]
            "#,
            corner.x,
            corner.y,
            corner.z,
            edge_u.x,
            edge_u.y,
            edge_u.z,
            edge_v.x,
            edge_v.y,
            edge_v.z
        )
    };
    let sobol = render_text(&scene("sobol"));
    let independent = render_text(&scene("independent"));

    let camera = Camera::new(
        Vec3::new(0.3, -2.0, 2.2),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        45.0,
        w,
        h,
    );
    let light = [
        corner,
        corner + edge_u,
        corner + edge_u + edge_v,
        corner + edge_v,
    ];
    let n = 16; // the pixel integral by an n × n midpoint rule
    let (mut sq, mut bias, mut checked) = ([0.0; 2], [0.0; 2], 0);
    for y in 0..h {
        for x in 0..w {
            let mut expected = 0.0;
            let mut plane = 0;
            for a in 0..n {
                for b in 0..n {
                    let ray = camera.ray(
                        x as f64 + (a as f64 + 0.5) / n as f64,
                        y as f64 + (b as f64 + 0.5) / n as f64,
                    );
                    let t = -ray.o.z / ray.d.z;
                    let p = ray.o + ray.d * t;
                    // The light's back, seen from above, hides the plane: black there.
                    let tl = (corner.z - ray.o.z) / ray.d.z;
                    let q = ray.o + ray.d * tl - corner;
                    let (su, sv) = (
                        q.dot(edge_u) / edge_u.dot(edge_u),
                        q.dot(edge_v) / edge_v.dot(edge_v),
                    );
                    let behind_light = (0.0..=1.0).contains(&su) && (0.0..=1.0).contains(&sv);
                    if ray.d.z >= 0.0 || p.x.abs() > 1.0 || p.y.abs() > 1.0 || behind_light {
                        continue;
                    }
                    plane += 1;
                    let e = polygon_irradiance(p, Vec3::new(0.0, 0.0, 1.0), &light);
                    expected += rho / PI * radiance * e / (n * n) as f64;
                }
            }
            if plane != n * n {
                continue;
            }
            checked += 1;
            let se = independent.std_error[y * w + x].0[1];
            for (k, image) in [&sobol, &independent].into_iter().enumerate() {
                let got = image.at(x, y).0[1];
                let tol = 5.0 * se + 2e-3 * expected;
                assert!(
                    (got - expected).abs() <= tol,
                    "sampler {k}, pixel ({x}, {y}): rendered {got} vs analytic {expected} (tolerance {tol})"
                );
                sq[k] += ((got - expected) / expected).powi(2);
                bias[k] += (got - expected) / expected;
            }
        }
    }
    assert!(
        checked > w * h / 3,
        "the plane covers only {checked} pixels"
    );
    let rms = sq.map(|s| (s / checked as f64).sqrt());
    for k in 0..2 {
        let mean = bias[k] / checked as f64;
        assert!(
            mean.abs() <= 4.0 * rms[k] / (checked as f64).sqrt() + 2e-3,
            "sampler {k}: mean relative error {mean} (rms {})",
            rms[k]
        );
    }
    assert!(
        rms[0] < 0.25 * rms[1],
        "RMS relative error: Sobol {} vs independent {}",
        rms[0],
        rms[1]
    );
}

/// Passes continue one sequence: four one-sample passes at `first_sample` 0, 1, 2, 3 average to
/// the four-sample render, for both samplers (how the explorer's preview refines).
#[test]
fn passes_at_successive_first_samples_make_one_render() {
    use std::path::Path;
    use woven_render::render::{render, RenderOptions};
    use woven_render::rng::SamplerKind;
    use woven_render::scene::{Scene, SceneDescription};

    let text = r#"
        [camera]
        origin = [0, -3, 1.5]
        target = [0, 0, 0.4]
        fov_deg = 50
        [film]
        width = 12
        height = 8
        spp = 4
        [integrator]
        max_depth = 3
        [[light]]
        type = "rectangle"
        corner = [-0.5, -0.5, 2.0]
        edge_u = [0, 1, 0]
        edge_v = [1, 0, 0]
        radiance = [4, 4, 4]
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
        reflectance = [0.5, 0.5, 0.5]
        "#;
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
        let mut desc = SceneDescription::from_str(text, "<test>", Path::new(".")).unwrap();
        desc.film.sampler = sampler;
        let mut scene = Scene::build(&desc, &crate::coarse_grid(), &|_| {}, &|_, _| {}).unwrap();
        let whole = render(&scene, &RenderOptions::default()).unwrap();
        scene.film.spp = 1;
        let mut sum = vec![[0.0; 3]; whole.pixels.len()];
        for pass in 0..4 {
            scene.film.first_sample = pass;
            let image = render(&scene, &RenderOptions::default()).unwrap();
            for (acc, px) in sum.iter_mut().zip(&image.pixels) {
                for c in 0..3 {
                    acc[c] += px.0[c];
                }
            }
        }
        for (acc, px) in sum.iter().zip(&whole.pixels) {
            for c in 0..3 {
                assert!(
                    (acc[c] / 4.0 - px.0[c]).abs() <= 1e-12 * px.0[c].abs().max(1.0),
                    "{sampler:?}: {} vs {}",
                    acc[c] / 4.0,
                    px.0[c]
                );
            }
        }
        assert!(whole.pixels.iter().any(|p| p.0[0] > 0.0));
    }
}
