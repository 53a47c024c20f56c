//! Criterion benchmarks of the tabulated BRDF: evaluation against the exact model on the same
//! inputs (the baseline, measured in the same run), and batch throughput of `eval` and `sample`
//! on all cores.
// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rayon::prelude::*;
use woven::bsdf::{Bsdf, Transport};
use woven::material::Material;
use woven::table::report::SplitMix;
use woven::table::{Table, TableOptions};
use woven::Vec3;

const BATCH: usize = 1 << 20;

/// Sums `f` over `0..n` on all cores.
fn parallel_sum(n: usize, f: impl Fn(usize) -> f64 + Sync + Send) -> f64 {
    (0..n).into_par_iter().with_min_len(4096).map(f).sum()
}

fn bench_table(c: &mut Criterion) {
    let material = Material::preset("polyester-sateen").unwrap();
    let model = material.build(550.0).unwrap();
    let table = Table::build(&model, &material, &TableOptions::default(), &|_, _| {}).unwrap();
    let mut rng = SplitMix(1);
    let pairs: Vec<(Vec3, Vec3)> = (0..BATCH)
        .map(|_| (rng.direction(1.4), rng.direction(1.4)))
        .collect();
    let uniforms: Vec<(f64, f64)> = (0..BATCH).map(|_| (rng.uniform(), rng.uniform())).collect();

    let mut group = c.benchmark_group("sateen_one_core");
    group.sample_size(10);
    group.throughput(Throughput::Elements(64));
    group.bench_function("exact_eval", |b| {
        b.iter(|| {
            pairs[..64]
                .iter()
                .map(|&(s, v)| model.eval(black_box(s), black_box(v)))
                .sum::<f64>()
        })
    });
    group.bench_function("table_eval", |b| {
        b.iter(|| {
            pairs[..64]
                .iter()
                .map(|&(s, v)| table.eval(black_box(s), black_box(v)))
                .sum::<f64>()
        })
    });
    group.finish();

    let mut group = c.benchmark_group("sateen_all_cores");
    group.sample_size(10);
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function("table_eval", |b| {
        b.iter(|| parallel_sum(BATCH, |i| table.eval(pairs[i].0, pairs[i].1)))
    });
    group.bench_function("table_sample", |b| {
        b.iter(|| {
            parallel_sum(BATCH, |i| {
                let (u1, u2) = uniforms[i];
                table
                    .sample(pairs[i].0, 0.5, [u1, u2], Transport::Importance)
                    .map_or(0.0, |s| s.weight(Transport::Importance))
            })
        })
    });
    group.bench_function("table_pdf", |b| {
        b.iter(|| parallel_sum(BATCH, |i| table.pdf_direction(pairs[i].0, pairs[i].1)))
    });
    group.finish();
}

criterion_group!(benches, bench_table);
criterion_main!(benches);
