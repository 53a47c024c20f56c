//! Benchmarks of the fitter: what one model preparation and one pass over a CUReT-sized dataset
//! cost (the units a fit is made of), and whole fits, reduced to a few seconds each
//! (`cargo bench -p woven-fit --bench fit -- fit/whole`; see [`whole_fits`]).

// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, SamplingMode};
use std::cell::Cell;
use std::hint::black_box;
use std::time::Duration;
use woven::material::Material;
use woven::math::rng::SplitMix;
use woven_fit::data::{self, Dataset};
use woven_fit::evaluate::{FiberCache, Observation, Prepared};
use woven_fit::request::FitRequest;
use woven_fit::{FitOptions, ModelKind, ParamSet};

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
    whole_fits(&mut group);
    group.finish();
}

/// Every `step`-th sample of `dataset`, from the first (a fixed, even subset).
fn every(mut dataset: Dataset, step: usize) -> Dataset {
    dataset.samples = dataset.samples.into_iter().step_by(step).collect();
    dataset
}

/// Whole fits through the library's own entry ([`FitRequest::run`], what `woven fit --data`
/// runs), each small enough to take a few seconds. The two ways a whole fit can slow down both
/// show:
///
/// - a dearer evaluation (the model, its preparation, the fitter's bookkeeping) in
///   `whole/curet-linen-belt-cloth` (the twisted yarn, 1.5–3 ms a pair) and
///   `whole/merl-white-fabric-sateen` (colour data and a large dataset's subset-then-polish
///   path), both on a fixed budget of starts and iterations: their time is the evaluations
///   they make times what those cost;
/// - a longer convergence path (start ranges, bounds, transforms, seeds, the optimizer's
///   stopping) in `whole/curet-linen-sateen`, a default fit run to convergence (`woven fit
///   --data 'data/curet/abrdf.dat#linen' --init polyester-sateen`, 205 measurements): the
///   one-orientation yarn is cheap to evaluate and dear to prepare (each roughness the
///   optimizer visits builds a β table), so its time follows the number of steps taken.
///
/// After each bench its last fit's model evaluations are printed: a count that, unlike a time,
/// does not move with the machine's load, and that changes when the path does.
fn whole_fits(group: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>) {
    // Seconds an iteration: every sample one or two fits (criterion's default, linear sampling,
    // would take 55 fits at least).
    group.sampling_mode(SamplingMode::Flat);
    group.measurement_time(Duration::from_secs(20));
    let linen = data::load(&data::data_dir().join("curet/abrdf.dat#linen")).expect("data/curet");
    // Every 8th of linen's 205 measurements (26), from the twisted belt cloth (the slow
    // case, `--init belt-cloth`), with 1 quasi-random start besides the initial values, 1
    // refinement of 1 iteration and a final run of at most 2 iterations; the rank check, the
    // Lambert-like guard and the standard errors' Jacobian as in a full fit.
    let request = FitRequest {
        init: Some("belt-cloth".into()),
        options: FitOptions {
            starts: 1,
            refine: 1,
            refine_iterations: 1,
            max_iterations: 2,
            ..FitOptions::default()
        },
        ..FitRequest::new(ModelKind::Cloth)
    };
    bench_fit(
        group,
        "whole/curet-linen-belt-cloth",
        &request,
        &every(linen.clone(), 8),
    );

    // The MERL white-fabric grid (3757 directions × RGB), every 16th direction (235), from the
    // one-orientation polyester sateen, with the same fixed budget and a final subset of 128:
    // the final run on 128 directions, then one polishing iteration on all 235. Its multi-start
    // lands worse than the Lambert-like limit, so the final run is repeated from that limit (the
    // guard's path is measured too).
    let grid = data::load(&data::data_dir().join("merl/white-fabric.grid.csv")).expect("data/merl");
    let request = FitRequest {
        init: Some("polyester-sateen".into()),
        options: FitOptions {
            starts: 1,
            refine: 1,
            refine_iterations: 1,
            max_iterations: 2,
            final_subset: 128,
            ..FitOptions::default()
        },
        ..FitRequest::new(ModelKind::Cloth)
    };
    bench_fit(
        group,
        "whole/merl-white-fabric-sateen",
        &request,
        &every(grid, 16),
    );

    // Linen whole, from the polyester sateen, with the default options: to convergence.
    let request = FitRequest {
        init: Some("polyester-sateen".into()),
        ..FitRequest::new(ModelKind::Cloth)
    };
    bench_fit(group, "whole/curet-linen-sateen", &request, &linen);
}

/// Benchmarks `request` on `dataset`, then prints what the last fit did (nothing when the
/// bench was filtered out).
fn bench_fit(
    group: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    request: &FitRequest,
    dataset: &Dataset,
) {
    let last = Cell::new(None);
    group.bench_function(name, |b| {
        b.iter(|| {
            let result = request.run(dataset, &|_, _| {}).expect("the fit runs");
            last.set(Some((
                result.evaluations,
                result.rms_log,
                result.termination.clone(),
            )));
            black_box(result)
        })
    });
    if let Some((evaluations, rms_log, termination)) = last.take() {
        println!(
            "fit/{name}: {} measurements, {evaluations} model evaluations, RMS log error \
             {rms_log:.4}; {termination}",
            dataset.samples.len()
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
