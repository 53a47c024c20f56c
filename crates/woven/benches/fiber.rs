//! Criterion benchmarks of the fiber BRDF (docs/spec.md §1): one evaluation, and the β table build.
// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use woven::fiber::{BetaTable, Fiber, FiberModel, FiberParams, Ior, Normalization};
use woven::Vec3;

fn fibers() -> Vec<(&'static str, Fiber)> {
    let rough = FiberParams::rough(1.55, 0.08, 0.15);
    let htsg = FiberParams {
        model: FiberModel::Htsg {
            sigma_h_um: 0.15,
            tau_um: 1.5,
        },
        eta: Ior::Constant(1.55),
        diffuse: 0.05,
        normalization: Normalization::Paper,
        body_gloss: 0.0,
        body_roughness: 0.0,
    };
    vec![
        ("rough", Fiber::new(&rough, 550.0).unwrap()),
        ("htsg", Fiber::new(&htsg, 550.0).unwrap()),
    ]
}

fn bench_eval(c: &mut Criterion) {
    // A fixed set of 64 direction pairs around the specular lobe and off it.
    let pairs: Vec<(Vec3, Vec3)> = (0..64)
        .map(|k| {
            let t = k as f64 / 64.0;
            (
                Vec3::from_spherical(0.2 + 1.2 * t, 0.3 * t),
                Vec3::from_spherical(1.3 - 1.1 * t, std::f64::consts::PI - 0.5 + t),
            )
        })
        .collect();
    let mut group = c.benchmark_group("fiber_eval");
    for (name, fiber) in fibers() {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for &(s, v) in &pairs {
                    acc += fiber.eval(black_box(s), black_box(v));
                }
                acc
            })
        });
    }
    group.finish();
}

fn bench_beta_table(c: &mut Criterion) {
    let mut group = c.benchmark_group("beta_table");
    group.sample_size(10);
    for (name, fiber) in fibers() {
        group.bench_function(name, |b| b.iter(|| BetaTable::build(black_box(&fiber))));
    }
    group.finish();
}

criterion_group!(benches, bench_eval, bench_beta_table);
criterion_main!(benches);
