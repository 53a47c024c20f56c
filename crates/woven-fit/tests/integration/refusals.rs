//! The fitter refuses what it cannot fit instead of writing a result: data that is all zero or
//! too large to reach in floating point, parameters held where the model vanishes or
//! overflows, a parameter named twice, and budgets beyond what a fit can hold.

use woven_fit::data::{Dataset, Sample, Value};
use woven_fit::request::FitRequest;
use woven_fit::{FitError, FitOptions, ModelKind, MAX_STARTS};

/// A mono dataset of 40 direction pairs, every value `value`.
fn flat(value: f64) -> Dataset {
    let samples = (0..40)
        .map(|k| Sample {
            theta_i: 0.02 * k as f64,
            phi_i: 0.1 * k as f64,
            theta_r: 0.6 - 0.01 * k as f64,
            phi_r: 2.0,
            value: Value::Mono(value),
            weight: 1.0,
        })
        .collect();
    Dataset {
        name: "flat".into(),
        source: "flat.csv".into(),
        samples,
        dropped_below_horizon: 0,
        relative: false,
    }
}

/// A quick fit of `model` with `fix` held.
fn request(model: ModelKind, fix: &[&str], free: &[&str]) -> FitRequest {
    FitRequest {
        fix: fix.iter().map(|s| s.to_string()).collect(),
        free: free.iter().map(|s| s.to_string()).collect(),
        options: FitOptions {
            starts: 4,
            max_iterations: 5,
            ..FitOptions::default()
        },
        ..FitRequest::new(model)
    }
}

fn message(e: FitError) -> String {
    e.to_string()
}

#[test]
fn all_zero_data_is_refused() {
    let e = request(ModelKind::Lambert, &[], &[])
        .run(&flat(0.0), &|_, _| {})
        .unwrap_err();
    assert!(message(e).contains("all 40 usable measurements are 0"));
}

#[test]
fn a_scale_held_at_zero_is_refused_naming_it() {
    let e = request(ModelKind::Cloth, &["scale=0"], &[])
        .run(&flat(0.1), &|_, _| {})
        .unwrap_err();
    let m = message(e);
    assert!(m.contains("scale") && m.contains("(0, inf]"), "{m}");
}

#[test]
fn values_beyond_floating_point_are_refused_not_written() {
    let e = request(ModelKind::Lambert, &[], &[])
        .run(&flat(1e300), &|_, _| {})
        .unwrap_err();
    let m = message(e);
    assert!(m.contains("not finite"), "{m}");
    let e = request(ModelKind::Cloth, &["scale=1e308"], &[])
        .run(&flat(0.1), &|_, _| {})
        .unwrap_err();
    let m = message(e);
    assert!(m.contains("not finite"), "{m}");
}

#[test]
fn a_parameter_named_twice_is_refused() {
    for (fix, free, twice) in [
        (&["scale=2", "scale=3"][..], &[][..], "fix"),
        (&["scale=2"][..], &["scale"][..], "free"),
        (&[][..], &["scale", " scale"][..], "free"),
    ] {
        let e = request(ModelKind::Cloth, fix, free)
            .run(&flat(0.1), &|_, _| {})
            .unwrap_err();
        let m = message(e);
        assert!(m.contains(twice) && m.contains("named once"), "{m}");
    }
}

#[test]
fn budgets_beyond_the_fits_are_refused_before_anything_is_allocated() {
    let mut r = request(ModelKind::Lambert, &[], &[]);
    r.options.starts = 100_000_000;
    let m = message(r.run(&flat(0.1), &|_, _| {}).unwrap_err());
    assert!(
        m.contains("starts") && m.contains(&MAX_STARTS.to_string()) && m.contains("1000x"),
        "{m}"
    );
}
