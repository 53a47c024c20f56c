//! Counts the fireflies of a rendered EXR (`woven_render::fireflies`: a pixel's luminance above
//! 10× the median of its 5 × 5 neighbourhood and above the image's 99th percentile).
//!
//! `cargo run --release -p woven-render --example fireflies -- woven-out/showcase.exr`

use exr::prelude::read_first_rgba_layer_from_file;
use woven::color::Rgb;

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: fireflies IMAGE.exr");
        std::process::exit(2);
    };
    let image = read_first_rgba_layer_from_file(
        &path,
        |size, _| (size.width(), vec![0.0f64; size.width() * size.height()]),
        |(width, values), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            values[pos.y() * *width + pos.x()] =
                Rgb([f64::from(r), f64::from(g), f64::from(b)]).luminance();
        },
    );
    let (width, values) = match image {
        Ok(image) => image.layer_data.channel_data.pixels,
        Err(e) => {
            eprintln!("fireflies: cannot read {path}: {e}");
            std::process::exit(1);
        }
    };
    let height = values.len() / width.max(1);
    let found = woven_render::fireflies::fireflies(width, height, &values);
    println!("{path}: {width} × {height}, {} fireflies", found.len());
    for (x, y) in found.iter().take(20) {
        println!("  ({x}, {y}): {:.4}", values[y * width + x]);
    }
}
