//! Integration tests of the renderer: analytic images, furnaces, sampling-strategy agreement,
//! image validity and scene-file errors. One binary (STYLE.md).

mod analytic;
mod blind;
mod cancel;
mod denoise;
mod detail;
mod files;
mod footprint;
mod furnace;
mod inset;
mod robustness;
mod sampling;
mod scene_file;
mod strategies;
mod transmission;
mod woven_surfaces;
mod yarn_options;

use std::path::Path;
use woven::table::TableOptions;
use woven_render::render::{render, Image, RenderOptions};
use woven_render::scene::{Scene, SceneDescription};
use woven_render::woven_material::TableGrid;

/// A coarse table grid: builds in about a second, accurate enough for agreement tests that
/// compare the renderer with itself.
pub fn coarse_grid() -> TableGrid {
    TableGrid::Custom(TableOptions {
        n_theta: 12,
        n_phi: 7,
        n_h: 31,
        n_h_isotropic: 61,
        ..TableOptions::default()
    })
}

/// Parses, builds and renders scene text.
pub fn render_text(text: &str) -> Image {
    let desc = SceneDescription::from_str(text, "<test>", Path::new(".")).unwrap();
    let scene = Scene::build(&desc, &coarse_grid(), &|_| {}, &|_, _| {}).unwrap();
    let image = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!(
        image.invalid_samples, 0,
        "NaN, infinite or negative samples"
    );
    assert!(image.pixels.iter().all(|p| p.is_valid()));
    image
}

/// `desc` built on the renderer's default table grid, with tables from the user's table cache
/// (built there if missing; in memory only when there is no cache folder): for tests that
/// render the showcase.
pub fn build_with_user_cache(desc: &SceneDescription) -> Scene {
    use woven::table::cache::Cache;
    use woven_render::woven_material::TableCache;
    let cache = match Cache::user() {
        Ok(c) => TableCache::with_disk(c),
        Err(_) => TableCache::default(),
    };
    Scene::build_with(desc, &TableGrid::Default, cache, &|_| {}, &|_, _| {}).unwrap()
}
