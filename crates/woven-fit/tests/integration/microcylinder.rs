//! Fitting the microcylinder model: a fabric sampled as it renders is recovered from a
//! perturbed start, the written file reads back as the fitted model (its energy guard included),
//! and starts of the wrong kind are refused by name. Each test takes a few seconds at most: few
//! samples, incidences that keep the guard's measurement short.

use std::f64::consts::PI;
use std::path::PathBuf;
use std::time::Instant;
use woven::bsdf::Bsdf;
use woven::catalog::AnyMaterial;
use woven::color::Rgb;
use woven::microcylinder::Microcylinder;
use woven::Vec3;
use woven_fit::data::{Dataset, Sample, Value};
use woven_fit::microcylinder::Fabric;
use woven_fit::{fit, FitError, FitOptions, ModelKind, ParamSet};

/// Direction pairs: light at `theta_i_deg` and four azimuths of a quadrant, the viewer at four
/// polar angles and eight azimuths, and at each light's mirror direction.
fn geometry(theta_i_deg: &[f64]) -> Vec<(f64, f64, f64, f64)> {
    let mut out = Vec::new();
    for &ti in theta_i_deg {
        for pi in [0.0f64, 30.0, 60.0, 90.0] {
            let (ti, pi) = (ti.to_radians(), pi.to_radians());
            for tr in [10.0f64, 30.0, 50.0, 65.0] {
                for k in 0..8 {
                    out.push((ti, pi, tr.to_radians(), 2.0 * PI * k as f64 / 8.0));
                }
            }
            out.push((ti, pi, ti, pi + PI));
        }
    }
    out
}

/// A fresh folder of this process for one test.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "woven-fit-microcylinder-{}-{tag}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `f` at every pair, as an absolute colour dataset.
fn sample(f: &dyn Fn(Vec3, Vec3) -> Rgb, pairs: &[(f64, f64, f64, f64)]) -> Dataset {
    let samples = pairs
        .iter()
        .map(|&(theta_i, phi_i, theta_r, phi_r)| Sample {
            theta_i,
            phi_i,
            theta_r,
            phi_r,
            value: Value::Rgb(
                f(
                    Vec3::from_spherical(theta_i, phi_i),
                    Vec3::from_spherical(theta_r, phi_r),
                )
                .0,
            ),
            weight: 1.0,
        })
        .collect();
    Dataset {
        name: "sampled".into(),
        source: "<sampled>".into(),
        samples,
        dropped_below_horizon: 0,
        relative: false,
    }
}

/// The silk shot's BRDF as it renders (its preset guard), sampled with light up to 35°, is
/// recovered from a start off in every free parameter.
#[test]
fn silk_shot_is_recovered_from_a_perturbed_start() {
    let clock = Instant::now();
    let shot = Microcylinder::preset("microcylinder-silk-shot").unwrap();
    let data = sample(&|wi, wo| shot.eval_rgb(wi, wo), &geometry(&[15.0, 35.0]));
    let mut threads = shot.threads.clone();
    for (t, k) in threads.iter_mut().zip([1.3, 0.8]) {
        t.albedo = Rgb(t.albedo.0.map(|a| (a * k).min(0.95)));
        t.kd *= 1.6;
        t.gamma_s *= 1.25;
        t.gamma_v *= 0.8;
    }
    threads[0].coverage = 0.78;
    threads[1].coverage = 0.17;
    let start = Fabric::new("perturbed", threads).unwrap();
    let set = ParamSet::microcylinder(Some(&start), 3, false).unwrap();
    let options = FitOptions {
        starts: 8,
        ..FitOptions::default()
    };
    let result = fit(&data, &set, &options, &|_, _| {}).unwrap();
    println!("{}", result.to_markdown());
    println!("{:.2} s", clock.elapsed().as_secs_f64());
    assert_eq!(result.model, ModelKind::Microcylinder);
    assert!(result.rms_log < 0.02, "RMS log error {}", result.rms_log);
    let fitted = result.params.fabric_at_values().unwrap();
    let (a1, a2) = (fitted.threads[0].coverage, fitted.threads[1].coverage);
    assert!(a1 + a2 <= 1.0 && (a1 - 0.86).abs() < 0.05, "{a1}, {a2}");
    assert!(
        (fitted.threads[0].gamma_s.to_degrees() - 4.0).abs() < 0.4,
        "{}",
        fitted.threads[0].gamma_s.to_degrees()
    );
    // The tangent curves are the start's.
    assert_eq!(fitted.threads[0].tangents, shot.threads[0].tangents);
}

/// A cheap fabric (straight threads, one tangent each, so that its guard measures in a second): the fit, written as a
/// file, reads back through the catalogue `woven eval` uses as the model the fit predicted with,
/// energy guard included, at light up to 80° where the guard acts.
#[test]
fn the_fitted_file_reads_back_as_the_fitted_model() {
    let clock = Instant::now();
    let dir = temp_dir("round-trip");
    let init = dir.join("cheap.toml");
    std::fs::write(
        &init,
        "model = \"microcylinder\"\nname = \"cheap\"\n\
         [[thread]]\neta = 1.5\nalbedo = [0.9, 0.7, 0.5]\nkd = 0.3\ngamma_s_deg = 30.0\n\
         gamma_v_deg = 50.0\ncoverage = 0.6\ntangent_offsets_deg = [-50.0]\n\
         [[thread]]\neta = 1.5\nalbedo = [0.3, 0.5, 0.9]\nkd = 0.5\ngamma_s_deg = 30.0\n\
         gamma_v_deg = 50.0\ncoverage = 0.4\ntangent_offsets_deg = [0.0]\n",
    )
    .unwrap();
    let start = Fabric::from_preset_or_path(init.to_str().unwrap()).unwrap();
    let truth = Microcylinder::with_options(
        "truth",
        start.threads.clone(),
        &woven::microcylinder::default_rule,
        false,
    )
    .unwrap();
    // The unguarded model, brightened: a target the guard must hold down at grazing light.
    let data = sample(
        &|wi, wo| truth.eval_unguarded(wi, wo) * 1.2,
        &geometry(&[20.0, 80.0]),
    );
    let set = ParamSet::microcylinder(Some(&start), 3, false).unwrap();
    let options = FitOptions {
        starts: 4,
        max_iterations: 8,
        ..FitOptions::default()
    };
    let result = fit(&data, &set, &options, &|_, _| {}).unwrap();
    let text = result.material_toml().unwrap();
    assert!(text.contains("model = \"microcylinder\""), "{text}");
    let path = dir.join("fitted.toml");
    std::fs::write(&path, &text).unwrap();
    let AnyMaterial::Microcylinder(back) =
        AnyMaterial::from_preset_or_path(path.to_str().unwrap()).unwrap()
    else {
        panic!("not read as a microcylinder fabric");
    };
    assert_eq!(back.name, "cheap");
    // The guard acts at 80° (the test's point), and the file's model is the fit's, guard
    // included.
    assert!(back.guard().factor(80f64.to_radians().cos()) < 0.99);
    let bsdf = AnyMaterial::Microcylinder(back).build_rgb(550.0).unwrap();
    for (o, p) in result.observations.iter().zip(&result.predicted) {
        let f = bsdf.eval(o.s, o.v);
        for c in 0..3 {
            assert!(
                (f.0[c] - p[c]).abs() <= 1e-9 * p[c].max(1e-12),
                "{:?} {:?}: file {} vs fit {}",
                o.s,
                o.v,
                f.0[c],
                p[c]
            );
        }
    }
    println!(
        "RMS log {:.4}; {}; {:.2} s",
        result.rms_log,
        result.termination,
        clock.elapsed().as_secs_f64()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A woven material, an unknown name or a woven material file cannot start a microcylinder
/// fit; each error names the parameter, the value and what is expected.
#[test]
fn starts_of_the_wrong_kind_are_refused() {
    let silk = woven::material::Material::preset("silk").unwrap();
    let e = ParamSet::new(ModelKind::Microcylinder, Some(&silk), 3, false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("init") && e.contains("microcylinder"), "{e}");
    for arg in ["silk", "microcylinder-tweed"] {
        let e = Fabric::from_preset_or_path(arg).unwrap_err();
        assert!(matches!(e, FitError::InvalidParameter { .. }));
        let e = e.to_string();
        assert!(
            e.contains(arg) && e.contains("microcylinder-silk-shot"),
            "{e}"
        );
    }
    let dir = temp_dir("wrong-kind");
    let woven_file = dir.join("woven.toml");
    std::fs::write(
        &woven_file,
        woven::material::Material::preset_toml("silk").unwrap(),
    )
    .unwrap();
    let e = Fabric::from_preset_or_path(woven_file.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("woven material file"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    // Out of range: named with its value and range.
    let mut set = ParamSet::microcylinder(None, 3, false).unwrap();
    let e = set.fix_arg("thread2.kd=1.5").unwrap_err().to_string();
    assert!(
        e.contains("thread2.kd") && e.contains("1.5") && e.contains("[0, 1]"),
        "{e}"
    );
    let e = set.fix_arg("kd=0.5").unwrap_err().to_string();
    assert!(e.contains("thread1.kd"), "{e}");
}
