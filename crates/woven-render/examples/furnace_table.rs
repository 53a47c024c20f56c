//! The white furnace table of docs/render.md ("Levels of detail"): a white-dyed plain weave of
//! the polyester sateen's yarn, 16 cells across a 4 × 4 plane, seen from `(0, −1, 1)` at 30° in a
//! uniform sky of radiance 1 (hidden), one bounce, 128 × 128 pixels at 256 independent samples,
//! at fibre, auto, yarn and cloth level, flat and tilted 60° with gaps of 0.3, without the relief
//! and with it. Prints a Markdown row
//! per case: the brightest pixel (its largest channel), the share of pixels above 1.05, the
//! image's mean (green) and the largest excess over 1 in the pixel's own standard errors. Tables
//! on a coarse grid (12 × 7 directions, 31 and 61 slopes), as the furnace test renders them
//! (`a_white_woven_plane_is_nowhere_brighter_than_the_furnace` in
//! crates/woven-render/tests/integration/furnace.rs, which CI runs at 24 × 24 pixels). About
//! six minutes on two cores.
//!
//! `cargo run --release -p woven-render --example furnace_table`

use std::path::Path;
use woven::table::TableOptions;
use woven_render::render::{render, Image, RenderOptions};
use woven_render::scene::{Scene, SceneDescription};
use woven_render::woven_material::TableGrid;

#[path = "../tests/support/white_plane.rs"]
mod white_plane_scene;
use white_plane_scene::{furnace_figures, white_plane};

/// Builds the scene on the coarse grid and renders it.
fn render_text(text: &str) -> Image {
    let grid = TableGrid::Custom(TableOptions {
        n_theta: 12,
        n_phi: 7,
        n_h: 31,
        n_h_isotropic: 61,
        ..TableOptions::default()
    });
    let desc = SceneDescription::from_str(text, "<furnace>", Path::new(".")).unwrap();
    let scene = Scene::build(&desc, &grid, &|_| {}, &|_, _| {}).unwrap();
    let image = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!(
        image.invalid_samples, 0,
        "NaN, infinite or negative samples"
    );
    image
}

fn main() {
    println!("| (detail, relief, tilt °, gap) | brightest | above 1.05 | mean | most above 1 (standard errors) |");
    println!("|---|---|---|---|---|");
    for config in [
        ("fibers", false, 0.0, 0.0),
        ("auto", false, 0.0, 0.0),
        ("yarns", false, 0.0, 0.0),
        ("cloth", false, 0.0, 0.0),
        ("yarns", false, 60.0, 0.3),
        ("fibers", false, 60.0, 0.3),
        ("fibers", true, 0.0, 0.0),
        ("auto", true, 0.0, 0.0),
        ("fibers", true, 60.0, 0.3),
    ] {
        let image = render_text(&white_plane("polyester-sateen", config, 16, 128, 256));
        let (brightest, above, mean, excess, _) = furnace_figures(&image);
        println!(
            "| {config:?} | {brightest:.3} | {:.2} % | {mean:.4} | {excess:.1} |",
            100.0 * above
        );
    }
}
