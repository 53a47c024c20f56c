//! Every model on every bundled dataset: each of `ModelKind::ALL` fitted with its defaults to
//! each dataset in `data/`, printing the fit's RMS log error, its relative RMS error and how long
//! it took. A fit that fails, or whose errors are not finite, is reported and makes the run exit
//! with status 1. About an hour on two cores, so not in CI: its tests fit the baselines to one
//! dataset of each family, the cloth model to CUReT's linen and to MERL's light-brown fabric
//! (crates/woven-fit/tests/integration/fit_real.rs).
//!
//! ```text
//! cargo run --release -p woven-fit --example every_dataset_fits [DATASET…]
//! ```
//! (names as `woven convert --bundled` lists them, e.g. `curet-44-linen`; default every dataset).

use woven_fit::data::{bundled, Family};
use woven_fit::{fit, FitOptions, ModelKind, ParamSet};

fn main() {
    let only: Vec<String> = std::env::args().skip(1).collect();
    let mut failures = 0;
    for b in bundled() {
        if !only.is_empty() && !only.contains(&b.name) {
            continue;
        }
        let channels = if b.family == Family::Curet { 1 } else { 3 };
        for model in ModelKind::ALL {
            let start = std::time::Instant::now();
            let result = b.load().map_err(|e| e.to_string()).and_then(|data| {
                let set = ParamSet::new(model, None, channels, data.relative)
                    .map_err(|e| e.to_string())?;
                fit(&data, &set, &FitOptions::default(), &|_, _| {}).map_err(|e| e.to_string())
            });
            let seconds = start.elapsed().as_secs_f64();
            match result {
                Ok(r) if r.rms_log.is_finite() && r.relative_rms.is_finite() => println!(
                    "{} / {model}: RMS log {:.4}, relative RMS {:.4} ({seconds:.1} s)",
                    b.name, r.rms_log, r.relative_rms
                ),
                Ok(r) => {
                    failures += 1;
                    println!(
                        "{} / {model}: FAILED, errors not finite: RMS log {}, relative RMS {}",
                        b.name, r.rms_log, r.relative_rms
                    );
                }
                Err(e) => {
                    failures += 1;
                    println!("{} / {model}: FAILED: {e}", b.name);
                }
            }
        }
    }
    if failures > 0 {
        eprintln!("{failures} fit(s) failed");
        std::process::exit(1);
    }
}
