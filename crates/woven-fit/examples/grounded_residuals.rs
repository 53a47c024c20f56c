//! Where a grounded preset misses its microcylinder reference: the log residuals of its
//! luminance (best scale removed) over the 1620 reference pairs, grouped by the half vector's
//! angles along and across the floats (`atan(h_x/h_z)`, `atan(h_y/h_z)`, 15° and 30° bins) and by
//! the polar angles of light and viewer (20° bins). Each row: the bin, the mean residual (> 0:
//! the preset too bright), its RMS, the pairs in it, and its share of the total squared error
//! (docs/microcylinder.md §11).
//!
//! ```text
//! cargo run --release -p woven-fit --example grounded_residuals [PRESET|FILE] [REFERENCE]
//! ```
//! (default `satin-charmeuse` against `microcylinder-satin-charmeuse`).

use std::collections::BTreeMap;
use woven::catalog::AnyMaterial;
use woven::microcylinder::Microcylinder;
use woven::Vec3;
use woven_fit::data::Sample;
use woven_fit::reference::{luminances, predict_luminances, sample};

/// Sums per bin: residual, its square, count.
type Bins = BTreeMap<(i32, i32), (f64, f64, usize)>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let preset = args.first().map_or("satin-charmeuse", String::as_str);
    let reference_name = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| format!("microcylinder-{preset}"));
    let reference = Microcylinder::preset(&reference_name)?;
    let data = sample(&reference, &reference_name);
    let bsdf = AnyMaterial::from_preset_or_path(preset)?.build_rgb(550.0)?;
    let (m, p) = (luminances(&data), predict_luminances(&*bsdf, &data));
    let logs: Vec<f64> = m
        .iter()
        .zip(&p)
        .map(|(a, b)| (b.max(1e-300) / a.max(1e-300)).ln())
        .collect();
    let mean = logs.iter().sum::<f64>() / logs.len() as f64;
    let total: f64 = logs.iter().map(|x| (x - mean).powi(2)).sum();
    println!(
        "{preset} against {reference_name}: RMS log {:.3} over {} pairs (scale {:.3} removed)",
        (total / logs.len() as f64).sqrt(),
        logs.len(),
        (-mean).exp()
    );
    let (mut by_half, mut by_theta) = (Bins::new(), Bins::new());
    for (s, r) in data.samples.iter().zip(&logs) {
        let (wi, wo) = directions(s);
        let h = (wi + wo).normalize();
        let along = (h.x / h.z).atan().to_degrees();
        let across = (h.y / h.z).atan().to_degrees();
        add(
            &mut by_half,
            (bin(along, 15.0), bin(across, 30.0)),
            r - mean,
        );
        let polar = |t: f64| (t.to_degrees() / 20.0) as i32 * 20;
        add(
            &mut by_theta,
            (polar(s.theta_i), polar(s.theta_r)),
            r - mean,
        );
    }
    print(
        "half vector along, across the floats (deg)",
        &by_half,
        total,
    );
    print("θi, θr (deg, bins from)", &by_theta, total);
    Ok(())
}

fn directions(s: &Sample) -> (Vec3, Vec3) {
    let d = |t: f64, p: f64| Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
    (d(s.theta_i, s.phi_i), d(s.theta_r, s.phi_r))
}

fn bin(x: f64, width: f64) -> i32 {
    (x / width).round() as i32 * width as i32
}

fn add(bins: &mut Bins, key: (i32, i32), r: f64) {
    let e = bins.entry(key).or_default();
    (e.0, e.1, e.2) = (e.0 + r, e.1 + r * r, e.2 + 1);
}

fn print(title: &str, bins: &Bins, total: f64) {
    println!("\n{title}: mean residual, RMS, pairs, share of the squared error");
    for ((a, b), (sum, sq, n)) in bins {
        let n_f = *n as f64;
        println!(
            "{a:4} {b:4}: {:+.2} {:.2} {n:4} {:.3}",
            sum / n_f,
            (sq / n_f).sqrt(),
            sq / total
        );
    }
}
