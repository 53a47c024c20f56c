//! Benchmarks of the fitter: what one model preparation and one pass over a CUReT-sized dataset
//! cost (the units a fit is made of), and whole fits.

// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use woven::material::Material;
use woven::math::rng::SplitMix;
use woven_fit::evaluate::{FiberCache, Observation, Prepared};
use woven_fit::{ModelKind, ParamSet};

/// 205 random direction pairs up to 80° (a CUReT-sized dataset).
fn observations() -> Vec<Observation> {
    let mut rng = SplitMix(205);
    (0..205)
        .map(|_| Observation {
            s: rng.direction(80f64.to_radians()),
            v: rng.direction(80f64.to_radians()),
            value: [0.1; 3],
            weight: 1.0,
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let obs = observations();
    let mut group = c.benchmark_group("fit");
    group.sample_size(10);
    for preset in Material::preset_names() {
        let m = Material::preset(preset).unwrap();
        let set = ParamSet::new(ModelKind::Cloth, Some(&m), 1, false).unwrap();
        group.bench_function(format!("prepare/{preset}"), |b| {
            b.iter(|| black_box(Prepared::new(&set).unwrap()))
        });
        // A parameter vector differing from a cached one in anything but the roughness.
        let cache = FiberCache::default();
        Prepared::with_cache(&set, Some(&cache)).unwrap();
        let mut moved = set.clone();
        moved.fix("yarn.slope_std", 0.3).unwrap();
        group.bench_function(format!("prepare-cached/{preset}"), |b| {
            b.iter(|| black_box(Prepared::with_cache(&moved, Some(&cache)).unwrap()))
        });
        let prepared = Prepared::new(&set).unwrap();
        group.bench_function(format!("pass-205/{preset}"), |b| {
            b.iter(|| black_box(prepared.parts_all(&obs)))
        });
    }
    let fiber = ParamSet::new(ModelKind::Fiber, None, 1, false).unwrap();
    group.bench_function("prepare/fiber", |b| {
        b.iter(|| black_box(Prepared::new(&fiber).unwrap()))
    });
    let prepared = Prepared::new(&fiber).unwrap();
    group.bench_function("pass-205/fiber", |b| {
        b.iter(|| black_box(prepared.parts_all(&obs)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
