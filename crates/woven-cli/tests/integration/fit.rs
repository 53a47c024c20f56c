//! End-to-end tests of `woven fit`: a fit's files, and bad input met with clear errors.

use assert_cmd::Command;
use predicates::prelude::*;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn woven() -> Command {
    Command::cargo_bin("woven").unwrap()
}

/// A measurement CSV of a Lambertian surface of albedo `albedo` with a mild specular bump, in a
/// fresh directory (kept alive by the returned guard).
fn measurements(dir: &Path, name: &str, albedo: f64) -> PathBuf {
    let mut s = String::from("theta_i,phi_i,theta_r,phi_r,value\n");
    for i in 0..6 {
        for j in 0..6 {
            let (ti, tr) = (0.12 * i as f64 + 0.1, 0.13 * j as f64 + 0.05);
            let bump = 1.0 + 0.3 * (-((ti - tr) / 0.2).powi(2)).exp();
            s.push_str(&format!("{ti},0,{tr},{PI},{}\n", albedo / PI * bump));
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, s).unwrap();
    path
}

#[test]
fn a_fit_writes_its_material_report_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let data = measurements(dir.path(), "grey.csv", 0.5);
    let (out, report, plot) = (
        dir.path().join("fitted.toml"),
        dir.path().join("fit.md"),
        dir.path().join("fit.svg"),
    );
    woven()
        .args(["fit", "--model", "fiber", "--data"])
        .arg(&data)
        .arg("-o")
        .arg(&out)
        .arg("--report")
        .arg(&report)
        .arg("--plot")
        .arg(&plot)
        .assert()
        .success()
        .stderr(predicate::str::contains("RMS log error"));
    // The material file is one woven reads.
    let material = woven::material::Material::from_path(&out).unwrap();
    assert!(material.yarn.is_none());
    let text = std::fs::read_to_string(&report).unwrap();
    assert!(
        text.contains("fiber.roughness") && text.contains("standard error"),
        "{text}"
    );
    assert!(std::fs::read_to_string(&plot).unwrap().starts_with("<svg"));
    woven()
        .args(["eval", "--material"])
        .arg(&out)
        .args(["--input", "-"])
        .write_stdin("theta_i,phi_i,theta_r,phi_r\n0.3,0,0.4,3\n")
        .assert()
        .success();
}

#[test]
fn compare_prints_one_table() {
    let dir = tempfile::tempdir().unwrap();
    let a = measurements(dir.path(), "a.csv", 0.5);
    let b = measurements(dir.path(), "b.csv", 0.2);
    woven()
        .args(["fit", "--models", "lambert,microfacet", "--compare"])
        .arg(&a)
        .arg(&b)
        .assert()
        .success()
        .stdout(
            predicate::str::contains("| dataset | points | lambert | microfacet |")
                .and(predicate::str::contains("| a | 36 |"))
                .and(predicate::str::contains("| b | 36 |")),
        );
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let data = measurements(dir.path(), "grey.csv", 0.5);
    let run = |args: &[&str]| {
        let mut cmd = woven();
        cmd.args(["fit", "--data"]).arg(&data).args(args);
        cmd.assert()
    };
    run(&["--fix", "nonsense=1"]).failure().stderr(
        predicate::str::contains("nonsense").and(predicate::str::contains("fiber.roughness")),
    );
    run(&["--fix", "roughness=7"]).failure().stderr(
        predicate::str::contains("fiber.roughness").and(predicate::str::contains("[0.005, 2]")),
    );
    run(&["--fix", "roughness"])
        .failure()
        .stderr(predicate::str::contains("name=value"));
    run(&["--model", "phong"])
        .code(2)
        .stderr(predicate::str::contains("phong"));
    run(&["--model", "lambert", "--init", "silk"])
        .failure()
        .stderr(predicate::str::contains("--init"));
    run(&["--init", "no-such-preset"])
        .failure()
        .stderr(predicate::str::contains("no-such-preset"));
    run(&["--plot", "fit.jpg"])
        .failure()
        .stderr(predicate::str::contains(".svg or .png"));
    run(&["-o", "/no/such/dir/fitted.toml"])
        .failure()
        .stderr(predicate::str::contains("/no/such/dir"));
    woven()
        .args(["fit", "--data", "/no/such/file.csv"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("/no/such/file.csv"));
    woven().args(["fit"]).assert().code(2);
}

/// In-plane data cannot separate the microcylinder's second thread: the refusal's example of
/// `--fix` names that thread's parameter at its starting value, not another model's.
#[test]
fn a_refusal_suggests_fixing_a_parameter_of_the_model_fitted() {
    let dir = tempfile::tempdir().unwrap();
    let data = measurements(dir.path(), "a.csv", 0.5);
    woven()
        .args([
            "fit",
            "--model",
            "microcylinder",
            "--init",
            "microcylinder-silk-shot",
        ])
        .arg("--data")
        .arg(&data)
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("(e.g. --fix thread2.")
                .and(predicate::str::contains("fiber.roughness").not()),
        );
}

/// One measurement cannot decide the cloth model's parameters: the fit is refused with the
/// counts and the flag that helps, and nothing is written.
#[test]
fn a_fit_the_data_cannot_decide_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("one.csv");
    std::fs::write(
        &data,
        "theta_i,phi_i,theta_r,phi_r,value\n0.3,0,0.4,3.1,0.1\n",
    )
    .unwrap();
    let out = dir.path().join("fitted.toml");
    woven()
        .args(["fit", "--model", "cloth", "--data"])
        .arg(&data)
        .arg("-o")
        .arg(&out)
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("--fix name=value")
                .and(predicate::str::contains(
                    "1 measurement(s) × 1 channel(s) = 1 value(s) cannot determine",
                ))
                .and(predicate::str::contains("has rank 1"))
                .and(predicate::str::contains("warning").not()),
        );
    assert!(!out.exists());
}

/// A plot that cannot be written (a full disk: `/dev/full` behind the plot's name) fails the
/// fit's outputs all together: the material and the report are not left behind.
#[cfg(unix)]
#[test]
fn a_plot_on_a_full_disk_leaves_no_output() {
    assert!(Path::new("/dev/full").exists(), "no /dev/full");
    let dir = tempfile::tempdir().unwrap();
    let data = measurements(dir.path(), "grey.csv", 0.5);
    let (out, report, plot) = (
        dir.path().join("fitted.toml"),
        dir.path().join("fit.md"),
        dir.path().join("fit.svg"),
    );
    std::os::unix::fs::symlink("/dev/full", &plot).unwrap();
    woven()
        .args(["fit", "--model", "fiber", "--starts", "2", "--data"])
        .arg(&data)
        .arg("-o")
        .arg(&out)
        .arg("--report")
        .arg(&report)
        .arg("--plot")
        .arg(&plot)
        .assert()
        .failure()
        .stderr(predicate::str::contains("cannot write `"))
        .stderr(predicate::str::contains("fit.svg`"));
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    let mut left = left;
    left.sort();
    assert_eq!(
        left,
        ["fit.svg", "grey.csv"],
        "only the data and the link remain"
    );
}

/// A sheer's measurements with transmitted rows (`theta_r` above π/2, as `woven eval` takes
/// them): the fit keeps the init material's openness (its gap and transmission) in the file it
/// writes, fits the reflected rows, and says how many transmitted ones it left out.
#[test]
fn a_sheer_fits_its_reflection_and_says_what_it_left_out() {
    let dir = tempfile::tempdir().unwrap();
    let mut rows = String::from("theta_i,phi_i,theta_r,phi_r\n");
    for k in 0..30 {
        let t = k as f64 / 30.0;
        let theta_r = if k % 3 == 0 { PI - 0.3 - t } else { 0.2 + t };
        rows.push_str(&format!(
            "{},{},{theta_r},{}\n",
            0.1 + t,
            0.2 * k as f64,
            3.0 - t
        ));
    }
    let eval = woven()
        .args(["eval", "-m", "cotton-voile", "--input", "-"])
        .write_stdin(rows)
        .output()
        .unwrap();
    assert!(eval.status.success());
    let data = dir.path().join("voile.csv");
    let text = String::from_utf8(eval.stdout)
        .unwrap()
        .replacen("brdf", "value", 1);
    std::fs::write(&data, text).unwrap();
    let out = dir.path().join("fitted.toml");
    woven()
        .args([
            "fit",
            "--init",
            "cotton-voile",
            "--starts",
            "1",
            "--max-iterations",
            "5",
        ])
        .arg("--data")
        .arg(&data)
        .arg("-o")
        .arg(&out)
        .assert()
        .success()
        .stderr(predicate::str::contains("fit to 20 measurements"))
        .stderr(predicate::str::contains(
            "10 rows with a direction at or below the horizon",
        ));
    let fitted = woven::material::Material::from_path(&out).unwrap();
    assert_eq!(fitted.openness.gap, 0.5);
    assert!(fitted.openness.transmission);
}
