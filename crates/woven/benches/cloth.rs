//! Criterion benchmarks of the cloth BRDF (docs/spec.md §2): one exact evaluation per preset, with the
// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]
//! flat fiber of the same material as the baseline measured in the same run.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use woven::material::Material;
use woven::Vec3;

/// 16 direction pairs spread over the hemisphere, specular and off-specular, some grazing.
fn pairs() -> Vec<(Vec3, Vec3)> {
    (0..16)
        .map(|k| {
            let t = k as f64 / 16.0;
            (
                Vec3::from_spherical(0.1 + 1.3 * t, 0.4 * k as f64),
                Vec3::from_spherical(1.4 - 1.2 * t, 2.5 + 0.3 * k as f64),
            )
        })
        .collect()
}

fn bench_presets(c: &mut Criterion) {
    let pairs = pairs();
    let mut group = c.benchmark_group("cloth_eval");
    for name in Material::preset_names() {
        let material = Material::preset(name).unwrap();
        let model = material.build(550.0).unwrap();
        let flat = Material::flat(material.fiber).build(550.0).unwrap();
        group.bench_function(format!("{name}/fiber_baseline"), |b| {
            b.iter(|| {
                pairs
                    .iter()
                    .map(|&(s, v)| flat.eval(black_box(s), black_box(v)))
                    .sum::<f64>()
            })
        });
        group.bench_function(format!("{name}/exact"), |b| {
            b.iter(|| {
                pairs
                    .iter()
                    .map(|&(s, v)| model.eval(black_box(s), black_box(v)))
                    .sum::<f64>()
            })
        });
        // The BRDF as an affine function of the albedos (one pass, both parts), for colour.
        group.bench_function(format!("{name}/exact_affine"), |b| {
            b.iter(|| {
                pairs
                    .iter()
                    .map(|&(s, v)| model.eval_affine(black_box(s), black_box(v)).fixed)
                    .sum::<f64>()
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench_presets
}
criterion_main!(benches);
