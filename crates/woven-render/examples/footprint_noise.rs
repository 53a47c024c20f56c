//! The showcase's noise with and without the footprint filter (docs/render.md, "Fine weaves"):
//! the built-in showcase at 320 × 180 and 16 independent samples a pixel, raw means, default
//! tables (the user's table cache), rendered once unfiltered and once filtered. For each
//! material the camera sees, prints its pixels' mean standard error relative to their mean, and
//! the two render times. About 25 s on two cores with the showcase's tables in the cache, a
//! minute more to build them.
//!
//! `cargo run --release -p woven-render --example footprint_noise`

use std::path::Path;
use woven::table::cache::Cache;
use woven_render::render::{render, Image, RenderOptions};
use woven_render::rng::SamplerKind;
use woven_render::scene::{Scene, SceneDescription, SHOWCASE_SCENE};
use woven_render::woven_material::{TableCache, TableGrid};

const WIDTH: usize = 320;
const HEIGHT: usize = 180;

/// `desc` on the default table grid, with tables from the user's cache (built there if missing).
fn build(desc: &SceneDescription) -> Scene {
    let cache = match Cache::user() {
        Ok(c) => TableCache::with_disk(c),
        Err(_) => TableCache::default(),
    };
    Scene::build_with(desc, &TableGrid::Default, cache, &|_| {}, &|_, _| {}).unwrap()
}

fn main() {
    let mut images = Vec::new();
    let mut names: Vec<String> = Vec::new();
    let mut owner = Vec::new();
    for filter in [false, true] {
        let text = SHOWCASE_SCENE.replace(
            "[integrator]\n",
            &format!("[integrator]\nfootprint_filter = {filter}\n"),
        );
        let mut desc = SceneDescription::from_str(&text, "<showcase>", Path::new(".")).unwrap();
        assert_eq!(desc.integrator.footprint_filter, filter);
        desc.film.width = WIDTH;
        desc.film.height = HEIGHT;
        desc.film.spp = 16;
        // Independent samples: the standard errors below are then the pixels' true errors.
        desc.film.sampler = SamplerKind::Independent;
        // The raw means: their noise is what is measured.
        desc.film.denoise = false;
        let scene = build(&desc);
        let image = render(&scene, &RenderOptions::default()).unwrap();
        assert_eq!(image.invalid_samples, 0);
        // Which material each pixel's centre sees.
        names = desc
            .materials
            .keys()
            .filter(|n| desc.shapes.iter().any(|(_, m)| m == *n))
            .cloned()
            .collect();
        owner = (0..WIDTH * HEIGHT)
            .map(|i| {
                let ray = scene
                    .camera
                    .ray((i % WIDTH) as f64 + 0.5, (i / WIDTH) as f64 + 0.5);
                scene
                    .accel
                    .intersect(&ray, 0.0, f64::INFINITY)
                    .and_then(|h| scene.prim_info[h.prim].material)
            })
            .collect();
        println!("filter {filter}: {:.2} s", image.seconds);
        images.push(image);
    }
    for (k, name) in names.iter().enumerate() {
        let px: Vec<usize> = (0..WIDTH * HEIGHT)
            .filter(|&i| owner[i] == Some(k))
            .collect();
        let rel = |img: &Image| {
            let mean = px.iter().map(|&i| img.pixels[i].luminance()).sum::<f64>();
            px.iter()
                .map(|&i| img.std_error[i].luminance())
                .sum::<f64>()
                / mean
        };
        println!(
            "{name:10} {:6} pixels: relative standard error {:.4} unfiltered, {:.4} filtered",
            px.len(),
            rel(&images[0]),
            rel(&images[1])
        );
    }
}
