//! A render whose progress asks to stop returns `Error::Cancelled`, no image, within a tile per
//! worker; one that never asks renders the same image as `render`.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::SeqCst};
use woven::progress::Hooks;
use woven_render::render::{render, render_with_progress, RenderOptions, TILE};
use woven_render::scene::{Scene, SceneDescription};
use woven_render::Error;

/// A grey square under a point light, 64 × 64 pixels: 16 tiles.
const SQUARE: &str = r#"
[camera]
origin = [0, 0, 1]
target = [0, 0, 0]
up = [0, 1, 0]
fov_deg = 60
[film]
width = 64
height = 64
spp = 2
[[light]]
type = "point"
position = [0, 0, 1]
intensity = [1, 1, 1]
[[shape]]
type = "rectangle"
corner = [-1, -1, 0]
edge_u = [2, 0, 0]
edge_v = [0, 2, 0]
material = "grey"
[material.grey]
type = "diffuse"
reflectance = [0.5, 0.5, 0.5]
"#;

#[test]
fn a_render_told_to_stop_returns_cancelled_within_a_tile_per_worker() {
    let desc = SceneDescription::from_str(SQUARE, "<test>", std::path::Path::new(".")).unwrap();
    let scene = Scene::build(&desc, &crate::coarse_grid(), &|_| {}, &|_, _| {}).unwrap();
    let tile_samples = (TILE * TILE * desc.film.spp) as u64;
    let options = RenderOptions { threads: Some(2) };
    for tiles in [0, 3] {
        let (samples, asked) = (AtomicU64::new(0), AtomicUsize::new(0));
        let stop_after = Hooks {
            update: |done: u64, _: u64| {
                samples.fetch_max(done, SeqCst);
            },
            cancelled: || asked.fetch_add(1, SeqCst) >= tiles,
        };
        let got = render_with_progress(&scene, &options, &stop_after);
        assert!(matches!(got, Err(Error::Cancelled)), "{tiles} tiles");
        let rendered = samples.load(SeqCst) / tile_samples;
        assert!(
            rendered <= tiles as u64 + 2,
            "{tiles} tiles: {rendered} rendered"
        );
    }
    let never = Hooks {
        update: |_: u64, _: u64| {},
        cancelled: || false,
    };
    let whole = render_with_progress(&scene, &options, &never).unwrap();
    let plain = render(&scene, &options).unwrap();
    assert_eq!(whole.pixels, plain.pixels);
}
