//! The showcase's noise per sampler (docs/render.md, "Samplers"): the built-in showcase at
//! 480 × 270, raw means, rendered with two seeds; its noise is the RMS difference of the two
//! images' luminance over √2. For independent samples at 16 (the showcase as it is) and 32 spp
//! and for Sobol points at 16 and 32 spp, prints the mean luminance, the noise and the time a
//! render. Exits with status 1 unless the Sobol points are the less noisy at both budgets and
//! every case renders the same image (means within 0.3 %). Tables come from the user's cache.
//! Eight renders: about four minutes on two cores.
//!
//! `cargo run --release -p woven-render --example sampler_noise`

use std::path::Path;
use woven::table::cache::Cache;
use woven_render::render::{render, RenderOptions};
use woven_render::rng::SamplerKind;
use woven_render::scene::{Scene, SceneDescription, SHOWCASE_SCENE};
use woven_render::woven_material::{TableCache, TableGrid};

/// `desc` on the default table grid, with tables from the user's cache (built there if missing).
fn build(desc: &SceneDescription) -> Scene {
    let cache = match Cache::user() {
        Ok(c) => TableCache::with_disk(c),
        Err(_) => TableCache::default(),
    };
    Scene::build_with(desc, &TableGrid::Default, cache, &|_| {}, &|_, _| {}).unwrap()
}

/// The noise's variance and the mean luminance of the showcase with `sampler` at `spp`.
fn noise(sampler: SamplerKind, spp: usize) -> (f64, f64) {
    let images: Vec<_> = (0..2)
        .map(|seed| {
            let mut desc =
                SceneDescription::from_str(SHOWCASE_SCENE, "<showcase>", Path::new(".")).unwrap();
            desc.film.width = 480;
            desc.film.height = 270;
            desc.film.spp = spp;
            desc.film.seed = seed;
            desc.film.sampler = sampler;
            // The raw means: their noise is what is measured.
            desc.film.denoise = false;
            let image = render(&build(&desc), &RenderOptions::default()).unwrap();
            assert_eq!(image.invalid_samples, 0);
            image
        })
        .collect();
    let n = images[0].pixels.len() as f64;
    let (a, b) = (&images[0].pixels, &images[1].pixels);
    let var = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p.luminance() - q.luminance()).powi(2) / 2.0)
        .sum::<f64>()
        / n;
    let mean = a.iter().chain(b).map(|p| p.luminance()).sum::<f64>() / (2.0 * n);
    let seconds = images.iter().map(|i| i.seconds).sum::<f64>() / 2.0;
    println!(
        "{sampler:?} {spp:3} spp: mean luminance {mean:.4}, RMS noise {:.5} (variance \
         {var:.3e}), {seconds:.2} s a render",
        var.sqrt(),
    );
    (var, mean)
}

fn main() {
    let (ind16, mean16) = noise(SamplerKind::Independent, 16);
    let (ind32, mean32) = noise(SamplerKind::Independent, 32);
    let (sob16, mean_now) = noise(SamplerKind::Sobol, 16);
    let (sob32, _) = noise(SamplerKind::Sobol, 32);
    let mut failed = false;
    if !(sob16 < ind16 && sob32 < ind32) {
        eprintln!(
            "Sobol points not less noisy: {sob16} vs {ind16} (16 spp), {sob32} vs {ind32} (32 spp)"
        );
        failed = true;
    }
    // The same image: the means agree to well within the noise.
    for mean in [mean16, mean32] {
        if (mean_now - mean).abs() >= 3e-3 * mean {
            eprintln!("not the same image: mean luminance {mean_now} vs {mean}");
            failed = true;
        }
    }
    if failed {
        std::process::exit(1);
    }
}
