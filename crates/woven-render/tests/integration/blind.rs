//! Pixels that see nothing: a pixel whose every ray passes by the scene's boxes
//! (`Camera::pixel_misses`) is rendered without tracing its rays. That is only right if none of
//! them could have met anything: checked here against the scene's own intersection, for every
//! kind of shape, with few primitives (a box each) and many (one box around them all), and for
//! the inset's camera.

use crate::inset::{INSET, SCENE};
use std::path::Path;
use woven::math::rng::SplitMix;
use woven_render::camera::Camera;
use woven_render::scene::{Scene, SceneDescription};

/// The inset test's scene (a plane and a sphere) with a cylinder beside them, seen wider, so
/// that even one box around them all leaves pixels clear.
fn shapes() -> String {
    format!(
        "{}{}",
        SCENE.replace("fov_deg = 45", "fov_deg = 100"),
        r#"
[[shape]]
type = "cylinder"
base = [-1.6, 0.2, 0.0]
axis = [0.2, 0.3, 1.2]
radius = 0.1
material = "plane"
"#
    )
}

/// A draped cloth: thousands of triangles, so one box holds them all.
const CLOTH: &str = r#"
[[shape]]
type = "cloth"
corner = [-0.6, -0.4, 0.8]
edge_u = [1.2, 0, 0]
edge_v = [0, 0.8, 0]
amplitude = 0.1
resolution = [40, 20]
material = "plane"
"#;

fn build(text: &str) -> Scene {
    let desc = SceneDescription::from_str(text, "<test>", Path::new(".")).unwrap();
    Scene::build(&desc, &crate::coarse_grid(), &|_| {}, &|_, _| {}).unwrap()
}

/// Over every pixel of `camera`'s `width × height` film: the pixels it says see nothing, whose
/// rays (a 5 × 5 grid over the pixel, its edges included, and 16 random ones) must all meet
/// nothing in `scene`, and the others. Returns how many pixels were culled and kept.
fn check(scene: &Scene, camera: &Camera, width: usize, height: usize) -> (usize, usize) {
    let mut rng = SplitMix(3);
    let (mut culled, mut kept) = (0, 0);
    for (x, y) in (0..width).flat_map(|x| (0..height).map(move |y| (x, y))) {
        if !camera.pixel_misses(x, y, scene.accel.boxes()) {
            kept += 1;
            continue;
        }
        culled += 1;
        let grid = (0..25).map(|k| ((k % 5) as f64 / 4.0, (k / 5) as f64 / 4.0));
        let random: Vec<_> = (0..16).map(|_| (rng.uniform(), rng.uniform())).collect();
        for (dx, dy) in grid.chain(random) {
            let ray = camera.ray(x as f64 + dx, y as f64 + dy);
            let hit = scene.accel.intersect(&ray, 0.0, f64::INFINITY);
            assert!(
                hit.is_none(),
                "pixel ({x}, {y}) + ({dx}, {dy}) meets {hit:?}"
            );
        }
    }
    (culled, kept)
}

#[test]
fn pixels_said_to_see_nothing_meet_nothing() {
    for (name, text) in [
        ("three shapes", shapes()),
        ("with a cloth mesh", format!("{}{CLOTH}", shapes())),
    ] {
        let scene = build(&text);
        let (culled, kept) = check(&scene, &scene.camera, 40, 30);
        // Both kinds occur: the test would notice a cull that never happens or always does.
        assert!(
            culled > 300 && kept > 100,
            "{name}: {culled} culled, {kept} kept"
        );
    }
    // The inset's camera, over its own film, tilted up over the sphere's top.
    let inset = INSET.replace("target = [0.2, 0.1, 0.25]", "target = [0.2, 0.1, 0.8]");
    let scene = build(&shapes().replace("[film]", &format!("{inset}[film]")));
    let inset = scene.inset.as_ref().unwrap();
    let [w, h] = inset.at.inner.1;
    let (culled, kept) = check(&scene, &inset.camera, w, h);
    assert!(
        culled > 50 && kept > 30,
        "inset: {culled} culled, {kept} kept"
    );
}
