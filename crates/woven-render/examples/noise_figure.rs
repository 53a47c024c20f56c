//! The showcase's noise at its own budget, raw and denoised, against a 1024-spp reference.
//!
//! Renders the built-in showcase at `SCALE` of its size (default 0.5: 480 × 270) with its own
//! samples per pixel, once, and measures its error against a reference of the same scene at
//! `REFERENCE_SPP` (default 1024) samples: the raw means and the denoised image
//! ([`woven_render::denoise`]). The reference is rendered once per version of the scene and
//! kept under `target/noise-figure/`.
//!
//! Two errors are printed, each an RMS over the image, over the main camera's view and over the
//! inset (with its border):
//! - **linear**: of the luminance, relative to the reference's mean luminance;
//! - **display**: of the PNG's 8-bit sRGB values after the showcase's tone map, in levels.
//!
//! `cargo run --release -p woven-render --example noise_figure -- [SCALE] [REFERENCE_SPP]`

use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use woven::color::Rgb;
use woven::table::cache::Cache;
use woven_render::render::{render, Image, RenderOptions};
use woven_render::scene::{Scene, SceneDescription, View, SHOWCASE_SCENE};
use woven_render::shapes::BUILTIN_MESHES;
use woven_render::tonemap::Display;
use woven_render::woven_material::{TableCache, TableGrid};

fn main() {
    let arg = |k: usize, default: f64| {
        std::env::args().nth(k).map_or(default, |a| {
            a.parse().unwrap_or_else(|_| {
                eprintln!("usage: noise_figure [SCALE in (0, 1]] [REFERENCE_SPP]");
                std::process::exit(2)
            })
        })
    };
    let (scale, reference_spp) = (arg(1, 0.5), arg(2, 1024.0) as usize);
    if !(scale > 0.0 && scale <= 1.0) || reference_spp < 2 {
        eprintln!("noise_figure: SCALE {scale} must be in (0, 1], REFERENCE_SPP {reference_spp} at least 2");
        std::process::exit(2);
    }
    let mut desc =
        SceneDescription::from_str(SHOWCASE_SCENE, "<built-in showcase>", Path::new(".")).unwrap();
    desc.film.width = ((desc.film.width as f64 * scale).round() as usize).max(1);
    desc.film.height = ((desc.film.height as f64 * scale).round() as usize).max(1);
    let display = desc.film.display;
    let budget = desc.film.spp;

    let reference = reference(&desc, reference_spp);
    desc.film.denoise = true;
    let scene = build(&desc);
    let image = render(&scene, &RenderOptions::default()).unwrap();
    let noisy = image.noisy.as_deref().expect("denoised");
    // Which pixels show the inset (with its border): reported apart from the main view.
    let in_inset: Vec<bool> = (0..image.width * image.height)
        .map(|p| !matches!(scene.view_at(p % image.width, p / image.width), View::Main))
        .collect();
    println!(
        "showcase at {} × {}, {budget} spp, {:.1} s (denoiser included); reference {reference_spp} spp",
        image.width, image.height, image.seconds
    );
    let own = reference_noise(&reference);
    println!("reference's own noise: linear {:.4}", own);
    println!("            whole image         main view           inset");
    println!("            linear  display     linear  display     linear  display");
    for (name, pixels) in [("raw", noisy), ("denoised", &image.pixels[..])] {
        let mut line = format!("{name:>10}:");
        for keep in [|_: bool| true, |inset: bool| !inset, |inset: bool| inset] {
            let pick = |v: &[Rgb]| -> Vec<Rgb> {
                v.iter()
                    .zip(&in_inset)
                    .filter(|(_, &i)| keep(i))
                    .map(|(p, _)| *p)
                    .collect()
            };
            let (linear, levels) = errors(&pick(pixels), &pick(&reference.pixels), &display);
            line += &format!("  {linear:.4}  {levels:5.2}    ");
        }
        println!("{}", line.trim_end());
    }
}

/// The scene, its woven tables from the user's cache.
fn build(desc: &SceneDescription) -> Scene {
    let cache = match Cache::user() {
        Ok(c) => TableCache::with_disk(c),
        Err(_) => TableCache::default(),
    };
    Scene::build_with(desc, &TableGrid::Default, cache, &|_| {}, &|_, _| {}).unwrap()
}

/// The reference at `spp` samples: read from `target/noise-figure/`, or rendered and kept there.
fn reference(desc: &SceneDescription, spp: usize) -> Image {
    // Named by the scene it shows (its text and the built-in meshes), so an edited showcase
    // never meets a stale reference.
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (SHOWCASE_SCENE, BUILTIN_MESHES).hash(&mut hasher);
    let name = format!(
        "reference-{}x{}-{spp}-{:016x}",
        desc.film.width,
        desc.film.height,
        hasher.finish()
    );
    let dir = PathBuf::from("target/noise-figure");
    let path = dir.join(format!("{name}.exr"));
    let errors = dir.join(format!("{name}-error.exr"));
    if let (Some(pixels), Some(std_error)) = (read_exr(&path), read_exr(&errors)) {
        eprintln!("reference: {}", path.display());
        return Image {
            width: desc.film.width,
            height: desc.film.height,
            pixels,
            std_error,
            invalid_samples: 0,
            spp,
            seconds: 0.0,
            noisy: None,
        };
    }
    eprintln!("rendering the reference at {spp} spp (minutes)…");
    let mut desc = desc.clone();
    desc.film.spp = spp;
    desc.film.denoise = false;
    desc.film.seed = 1;
    let image = render(&build(&desc), &RenderOptions::default()).unwrap();
    std::fs::create_dir_all(&dir).unwrap();
    woven_render::output::write_exr(&image, &path).unwrap();
    let errors_image = Image {
        pixels: image.std_error.clone(),
        ..image.clone()
    };
    woven_render::output::write_exr(&errors_image, &errors).unwrap();
    eprintln!(
        "reference rendered in {:.0} s: {}",
        image.seconds,
        path.display()
    );
    image
}

fn read_exr(path: &Path) -> Option<Vec<Rgb>> {
    use exr::prelude::read_first_rgba_layer_from_file;
    let image = read_first_rgba_layer_from_file(
        path,
        |size, _| (size.width(), vec![Rgb::BLACK; size.width() * size.height()]),
        |(width, values), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            values[pos.y() * *width + pos.x()] = Rgb([r, g, b].map(f64::from));
        },
    )
    .ok()?;
    Some(image.layer_data.channel_data.pixels.1)
}

/// The reference's own RMS error (its standard errors), linear, relative to its mean.
fn reference_noise(reference: &Image) -> f64 {
    let n = reference.pixels.len() as f64;
    let mean = reference.pixels.iter().map(|p| p.luminance()).sum::<f64>() / n;
    let ms = reference
        .std_error
        .iter()
        .map(|e| e.luminance().powi(2))
        .sum::<f64>()
        / n;
    ms.sqrt() / mean
}

/// RMS errors of `pixels` against `reference`: linear luminance relative to the reference's
/// mean, and display values in 8-bit levels.
fn errors(pixels: &[Rgb], reference: &[Rgb], display: &Display) -> (f64, f64) {
    let n = pixels.len() as f64;
    let mean = reference.iter().map(|p| p.luminance()).sum::<f64>() / n;
    let linear = pixels
        .iter()
        .zip(reference)
        .map(|(p, r)| (p.luminance() - r.luminance()).powi(2))
        .sum::<f64>()
        / n;
    let levels = pixels
        .iter()
        .zip(reference)
        .map(|(p, r)| {
            let (a, b) = (display.encode(*p), display.encode(*r));
            (0..3)
                .map(|c| (f64::from(a[c]) - f64::from(b[c])).powi(2))
                .sum::<f64>()
                / 3.0
        })
        .sum::<f64>()
        / n;
    (linear.sqrt() / mean, levels.sqrt())
}
