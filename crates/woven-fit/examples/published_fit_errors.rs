//! The published SGD and ABC fits' error on the bundled MERL grids, as the Markdown table of
//! docs/fitting.md ("Datasets"): the median of model / grid and the RMS of ln(model / grid), over
//! every grid point and channel where the grid exceeds 10⁻⁴ sr⁻¹.
//!
//! `cargo run --release -p woven-fit --example published_fit_errors`

use woven::Vec3;
use woven_fit::data::{bundled, published, Dataset, Family, Value};

/// The median over a grid of `ln(model / measured)` (all channels) and its RMS; `None` when no
/// value exceeds the floor.
fn log_error(d: &Dataset, eval: impl Fn(Vec3, Vec3) -> [f64; 3]) -> Option<(f64, f64)> {
    let mut logs = Vec::new();
    for s in &d.samples {
        let grid = match s.value {
            Value::Rgb(c) => c,
            Value::Mono(v) => [v; 3],
        };
        let wi = Vec3::from_spherical(s.theta_i, s.phi_i);
        let wo = Vec3::from_spherical(s.theta_r, s.phi_r);
        for (m, g) in eval(wi, wo).iter().zip(grid) {
            if g > 1e-4 {
                logs.push((m.max(1e-9) / g).ln());
            }
        }
    }
    if logs.is_empty() {
        return None;
    }
    let rms = (logs.iter().map(|x| x * x).sum::<f64>() / logs.len() as f64).sqrt();
    logs.sort_by(f64::total_cmp);
    Some((logs[logs.len() / 2], rms))
}

fn main() -> Result<(), woven_fit::data::DataError> {
    println!("| material | SGD median ratio | SGD RMS ln | ABC median ratio | ABC RMS ln |");
    println!("|---|---|---|---|---|");
    for b in bundled().into_iter().filter(|b| b.family == Family::Merl) {
        let d = b.load()?;
        let (sgd, abc) = published::for_material(&b.name)?;
        let (Some((med_s, rms_s)), Some((med_a, rms_a))) = (
            log_error(&d, |wi, wo| sgd.eval(wi, wo)),
            log_error(&d, |wi, wo| abc.eval(wi, wo)),
        ) else {
            println!("| {} | — | — | — | — |", b.name);
            continue;
        };
        println!(
            "| {} | {:.3} | {rms_s:.3} | {:.3} | {rms_a:.3} |",
            b.name,
            med_s.exp(),
            med_a.exp()
        );
    }
    Ok(())
}
