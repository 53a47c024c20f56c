//! The weave relief's visible share of weft against the view, per preset with a pattern: the
//! share of a repeat's entries (96 × 96, stratified) whose ray toward the viewer meets a weft
//! yarn first (docs/model.md §8, "The relief").
//!
//! `cargo run --release -p woven --example relief_share`

use woven::material::{Material, Weave};
use woven::relief::{Ground, Relief};
use woven::surface::SurfaceSpec;
use woven::Vec3;

/// Entries per side of the repeat.
const N: usize = 96;

fn weft_share(relief: &Relief, (cols, rows): (f64, f64), v: Vec3) -> f64 {
    let mut weft = 0;
    for i in 0..N {
        for j in 0..N {
            let x = cols * (i as f64 + 0.5) / N as f64;
            let y = rows * (j as f64 + 0.5) / N as f64;
            if matches!(relief.hit(x, y, v).ground, Ground::Top { warp: false, .. }) {
                weft += 1;
            }
        }
    }
    weft as f64 / (N * N) as f64
}

fn main() -> Result<(), woven::Error> {
    let thetas = [0.0f64, 30.0, 50.0, 60.0, 70.0, 80.0, 85.0];
    println!(
        "weft share seen from θ (φ: the view's azimuth from the weft)\n| preset | φ | {} |",
        thetas.map(|t| format!("{t:.0}°")).join(" | ")
    );
    println!("|---|---|{}", "---|".repeat(thetas.len()));
    for name in ["satin-charmeuse", "linen-plain", "silk-shot", "belt-cloth"] {
        let spec = SurfaceSpec::new(Material::preset(name)?);
        let (Some(relief), Some(Weave::Pattern { pattern, .. })) =
            (spec.relief(), &spec.material.weave)
        else {
            continue;
        };
        let repeat = (pattern.cols() as f64, pattern.rows() as f64);
        for phi in [0.0f64, 45.0, 90.0] {
            let shares = thetas.map(|t| {
                let v = Vec3::from_spherical(t.to_radians(), phi.to_radians());
                format!("{:.3}", weft_share(&relief, repeat, v))
            });
            println!("| {name} | {phi:.0}° | {} |", shares.join(" | "));
        }
    }
    Ok(())
}
