//! Scenes that read files: OBJ meshes and EXR environment maps.

use crate::coarse_grid;
use woven_render::render::{render, Image, RenderOptions};
use woven_render::scene::{Scene, SceneDescription};

fn render_in(dir: &std::path::Path, text: &str) -> Image {
    let desc = SceneDescription::from_str(text, "<test>", dir).unwrap();
    let scene = Scene::build(&desc, &coarse_grid(), &|_| {}, &|_, _| {}).unwrap();
    let image = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!(image.invalid_samples, 0);
    image
}

/// Writes an equirectangular EXR map: `value(x, y)` per pixel.
fn write_map(
    path: &std::path::Path,
    w: usize,
    h: usize,
    value: impl Fn(usize, usize) -> f32 + Sync,
) {
    exr::prelude::write_rgb_file(path, w, h, |x, y| {
        let v = value(x, y);
        (v, v, v)
    })
    .unwrap();
}

const CAMERA: &str = r#"
    [camera]
    origin = [0.2, -2.2, 2.0]
    target = [0, 0, 0]
    fov_deg = 45
    [film]
    width = 16
    height = 12
    spp = 64
"#;

/// An OBJ quad (two triangles with uv and normals) renders as the same rectangle does.
#[test]
fn obj_quad_renders_like_the_rectangle() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("quad.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
         f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n",
    )
    .unwrap();
    let lights = r#"
        [integrator]
        max_depth = 2
        [[light]]
        type = "point"
        position = [0.4, 0.5, 1.5]
        intensity = [10, 10, 10]
        [material.m]
        type = "diffuse"
        reflectance = [0.5, 0.5, 0.5]
    "#;
    let mesh = render_in(
        dir.path(),
        &format!(
            "{CAMERA}{lights}[[shape]]\ntype = \"mesh\"\nfile = \"quad.obj\"\nmaterial = \"m\"\n"
        ),
    );
    let rect = render_in(
        dir.path(),
        &format!(
            "{CAMERA}{lights}[[shape]]\ntype = \"rectangle\"\ncorner = [-1, -1, 0]\n\
             edge_u = [2, 0, 0]\nedge_v = [0, 2, 0]\nmaterial = \"m\"\n"
        ),
    );
    // The same sample positions and the same geometry: equal up to rounding.
    for (a, b) in mesh.pixels.iter().zip(&rect.pixels) {
        assert!(
            (a.0[0] - b.0[0]).abs() < 1e-9 * (1.0 + b.0[0]),
            "{a:?} vs {b:?}"
        );
    }
    assert!(rect.pixels.iter().any(|p| p.0[0] > 0.1));
    // A missing file is an error naming the key.
    let desc = SceneDescription::from_str(
        &format!(
            "{CAMERA}{lights}[[shape]]\ntype = \"mesh\"\nfile = \"nope.obj\"\nmaterial = \"m\"\n"
        ),
        "<test>",
        dir.path(),
    )
    .unwrap();
    let err = Scene::build(&desc, &coarse_grid(), &|_| {}, &|_, _| {})
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("shape[0].file") && err.contains("nope.obj"),
        "{err}"
    );
}

/// A constant EXR map renders the furnace's 0.5 on a ρ = 0.5 sphere; a map with a bright sun
/// gives the same image by light sampling, BSDF sampling and MIS (the map's importance sampling
/// and its density agree).
#[test]
fn environment_maps_light_the_scene_consistently() {
    let dir = tempfile::tempdir().unwrap();
    write_map(&dir.path().join("grey.exr"), 16, 8, |_, _| 1.0);
    write_map(&dir.path().join("sun.exr"), 32, 16, |x, y| {
        if (5..7).contains(&x) && (3..5).contains(&y) {
            200.0
        } else {
            0.5 + 0.05 * y as f32
        }
    });
    let sphere = r#"
        [[shape]]
        type = "sphere"
        center = [0, 0, 0]
        radius = 0.8
        material = "m"
        [material.m]
        type = "diffuse"
        reflectance = [0.5, 0.5, 0.5]
    "#;
    let furnace = render_in(
        dir.path(),
        &format!(
            "{CAMERA}[integrator]\nmax_depth = -1\n[[light]]\ntype = \"environment\"\n\
             file = \"grey.exr\"\n{sphere}"
        ),
    );
    // The centre pixels see the sphere only.
    for (x, y) in [(7, 5), (8, 6), (8, 5), (7, 6)] {
        let p = furnace.at(x, y).0[0];
        let se = furnace.std_error[y * 16 + x].0[0];
        assert!((p - 0.5).abs() < 5.0 * se + 1e-6, "({x}, {y}) = {p} ± {se}");
    }
    let run = |strategy: &str| {
        render_in(
            dir.path(),
            &format!(
                "{CAMERA}[integrator]\nmax_depth = 3\nstrategy = \"{strategy}\"\n[[light]]\n\
                 type = \"environment\"\nfile = \"sun.exr\"\n{sphere}\
                 [[shape]]\ntype = \"rectangle\"\ncorner = [-2, -2, -0.8]\nedge_u = [4, 0, 0]\n\
                 edge_v = [0, 4, 0]\nmaterial = \"m\"\n"
            ),
        )
    };
    let (mis, light, bsdf) = (run("mis"), run("light"), run("bsdf"));
    let mean = |im: &Image| {
        let n = im.pixels.len() as f64;
        let m: f64 = im.pixels.iter().map(|p| p.0[0]).sum::<f64>() / n;
        let se = im
            .std_error
            .iter()
            .map(|s| s.0[0].powi(2))
            .sum::<f64>()
            .sqrt()
            / n;
        (m, se)
    };
    let (m0, s0) = mean(&mis);
    for (name, im) in [("light", &light), ("bsdf", &bsdf)] {
        let (m, s) = mean(im);
        let z = (m - m0).abs() / (s * s + s0 * s0).sqrt();
        assert!(z < 4.5, "MIS {m0} ± {s0} vs {name} {m} ± {s}: z = {z:.2}");
    }
}
