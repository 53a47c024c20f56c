//! The bundled datasets at a glance, as the Markdown table of docs/fitting.md ("Datasets"):
//! samples, angle ranges, values (the mean of the channels) and calibration of every dataset in
//! `data/`.
//!
//! `cargo run --release -p woven-fit --example bundled_summary`

use woven_fit::data::{bundled, Sample, Value};

fn main() -> Result<(), woven_fit::data::DataError> {
    println!(
        "| dataset | family | samples | max θi, θr | values (sr⁻¹): min / median / max | calibration |"
    );
    println!("|---|---|---|---|---|---|");
    for b in bundled() {
        let d = b.load()?;
        let mut v: Vec<f64> = d
            .samples
            .iter()
            .map(|s| match s.value {
                Value::Mono(v) => v,
                Value::Rgb(c) => (c[0] + c[1] + c[2]) / 3.0,
            })
            .collect();
        if v.is_empty() {
            println!("| {} | {} | 0 | | | |", b.name, b.family.name());
            continue;
        }
        v.sort_by(f64::total_cmp);
        let max_t =
            |f: fn(&Sample) -> f64| d.samples.iter().map(f).fold(0.0, f64::max).to_degrees();
        println!(
            "| {} | {} | {} | {:.1}°, {:.1}° | {:.3} / {:.3} / {:.3} | {} |",
            b.name,
            b.family.name(),
            d.samples.len(),
            max_t(|s| s.theta_i),
            max_t(|s| s.theta_r),
            v[0],
            v[v.len() / 2],
            v[v.len() - 1],
            if d.relative {
                "relative, grey"
            } else {
                "absolute, RGB"
            }
        );
    }
    Ok(())
}
