//! Criterion benchmark of `woven eval` end to end on 10⁵ random directions (CSV in, CSV out, all
//! cores), for a flat fiber (the baseline) and the polyester-sateen preset, in the same run.
// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::io::Write;
use std::path::PathBuf;
use std::process::Command;

const ROWS: usize = 100_000;

/// Writes `ROWS` random direction pairs (θ ≤ 85°) as the `eval` input CSV.
fn input_csv() -> PathBuf {
    let path = std::env::temp_dir().join(format!("woven-bench-eval-{}.csv", std::process::id()));
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    writeln!(f, "theta_i,phi_i,theta_r,phi_r").unwrap();
    // Reproducible uniforms.
    let mut rng = woven::math::rng::SplitMix(7);
    let mut uniform = move || rng.uniform();
    for _ in 0..ROWS {
        let t = 85f64.to_radians();
        writeln!(
            f,
            "{},{},{},{}",
            t * uniform(),
            std::f64::consts::TAU * uniform(),
            t * uniform(),
            std::f64::consts::TAU * uniform()
        )
        .unwrap();
    }
    path
}

fn bench_eval(c: &mut Criterion) {
    let input = input_csv();
    let output = input.with_extension("out.csv");
    let dir = std::env::temp_dir();
    let flat = dir.join(format!("woven-bench-flat-{}.toml", std::process::id()));
    std::fs::write(
        &flat,
        "[fiber]\neta = 1.6\nroughness = 0.05\ndiffuse = 0.08\n",
    )
    .unwrap();
    let mut group = c.benchmark_group("woven_eval_1e5");
    group.sample_size(10);
    group.throughput(Throughput::Elements(ROWS as u64));
    for (name, material) in [
        ("flat_fiber_baseline", flat.to_string_lossy().to_string()),
        ("polyester-sateen", "polyester-sateen".to_string()),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let status = Command::new(env!("CARGO_BIN_EXE_woven"))
                    .args(["eval", "--material", &material, "--input"])
                    .arg(&input)
                    .arg("--output")
                    .arg(&output)
                    .status()
                    .unwrap();
                assert!(status.success());
            })
        });
    }
    group.finish();
    for p in [&input, &output, &flat] {
        let _ = std::fs::remove_file(p);
    }
}

criterion_group!(benches, bench_eval);
criterion_main!(benches);
