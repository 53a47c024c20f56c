//! End-to-end tests of `woven fit --model microcylinder`: a fit from the default start writes a
//! microcylinder file, the file reads back through `woven eval` as the model the fit scored, and
//! starts of the wrong kind are clear errors. Tiny datasets, so each runs in seconds.

use assert_cmd::Command;
use predicates::prelude::*;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use woven::color::Rgb;
use woven::microcylinder::{default_rule, Microcylinder};
use woven::Vec3;

fn woven() -> Command {
    Command::cargo_bin("woven").unwrap()
}

/// Direction pairs: light at `theta_i_deg` and two azimuths, the viewer at three polar angles
/// and four azimuths, and at each light's mirror direction.
fn pairs(theta_i_deg: &[f64]) -> Vec<[f64; 4]> {
    let mut out = Vec::new();
    for &ti in theta_i_deg {
        for pi in [0.0f64, 60.0] {
            let (ti, pi) = (ti.to_radians(), pi.to_radians());
            for tr in [10.0f64, 35.0, 60.0] {
                for k in 0..4 {
                    out.push([ti, pi, tr.to_radians(), PI / 4.0 + PI / 2.0 * k as f64]);
                }
            }
            out.push([ti, pi, ti, pi + PI]);
        }
    }
    out
}

/// A fitter CSV (`value_r,value_g,value_b`) of `f` at `pairs`, written to `dir/name`.
fn measurements(
    dir: &Path,
    name: &str,
    pairs: &[[f64; 4]],
    f: &dyn Fn(Vec3, Vec3) -> Rgb,
) -> PathBuf {
    let mut s = String::from("theta_i,phi_i,theta_r,phi_r,value_r,value_g,value_b\n");
    for &[ti, pi, tr, pr] in pairs {
        let v = f(Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr)).0;
        s.push_str(&format!(
            "{ti:?},{pi:?},{tr:?},{pr:?},{:?},{:?},{:?}\n",
            v[0], v[1], v[2]
        ));
    }
    let path = dir.join(name);
    std::fs::write(&path, s).unwrap();
    path
}

/// The number after `RMS log error ` in a fit's standard error.
fn rms_log_of(stderr: &[u8]) -> f64 {
    let text = String::from_utf8_lossy(stderr);
    let at = text.find("RMS log error ").expect("the fit's summary line") + 14;
    text[at..]
        .split(|c: char| c == ',' || c.is_whitespace())
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn a_microcylinder_fit_from_the_default_start_writes_a_microcylinder_file() {
    let dir = tempfile::tempdir().unwrap();
    let shot = Microcylinder::preset("microcylinder-silk-shot").unwrap();
    let data = measurements(dir.path(), "shot.csv", &pairs(&[15.0, 35.0]), &|wi, wo| {
        shot.eval_rgb(wi, wo)
    });
    let (out, report) = (dir.path().join("fitted.toml"), dir.path().join("fit.md"));
    woven()
        .args(["fit", "--model", "microcylinder", "--data"])
        .arg(&data)
        .arg("-o")
        .arg(&out)
        .arg("--report")
        .arg(&report)
        .assert()
        .success()
        .stderr(
            predicate::str::contains("microcylinder fit to 52 measurements")
                .and(predicate::str::contains("thread1.gamma_s = ")),
        );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("model = \"microcylinder\"") && text.contains("microcylinder-linen-plain"),
        "{text}"
    );
    let (name, threads) = Microcylinder::threads_from_path(&out).unwrap();
    assert_eq!(name, "fit-shot");
    // The start's tangent curves (linen's: ±25°) are kept.
    assert_eq!(threads[0].tangents.offsets().len(), 2);
    assert!(threads[0].coverage + threads[1].coverage <= 1.0);
    let report = std::fs::read_to_string(&report).unwrap();
    assert!(report.contains("thread1.coverage_share"), "{report}");
}

/// The file `-o` writes, evaluated by `woven eval`, scores on the data exactly the RMS log
/// error the fit printed: the fitted model is the one that renders, energy guard included (the
/// start is a cheap fabric of straight threads, whose guard measures in a fraction of a second,
/// and the light reaches 80°, where the guard acts).
#[test]
fn the_fitted_file_reads_back_through_woven_eval() {
    let dir = tempfile::tempdir().unwrap();
    let init = dir.path().join("straight.toml");
    std::fs::write(
        &init,
        "model = \"microcylinder\"\nname = \"straight\"\n\
         [[thread]]\neta = 1.5\nalbedo = [0.8, 0.6, 0.4]\nkd = 0.3\ngamma_s_deg = 20.0\n\
         gamma_v_deg = 40.0\ncoverage = 0.6\ntangent_offsets_deg = [-40.0]\n\
         [[thread]]\neta = 1.5\nalbedo = [0.3, 0.5, 0.8]\nkd = 0.5\ngamma_s_deg = 20.0\n\
         gamma_v_deg = 40.0\ncoverage = 0.4\ntangent_offsets_deg = [0.0]\n",
    )
    .unwrap();
    let (_, threads) = Microcylinder::threads_from_path(&init).unwrap();
    let truth = Microcylinder::with_options("truth", threads, &default_rule, false).unwrap();
    let geometry = pairs(&[20.0, 80.0]);
    let data = measurements(dir.path(), "straight.csv", &geometry, &|wi, wo| {
        truth.eval_unguarded(wi, wo)
    });
    let out = dir.path().join("fitted.toml");
    let fit = woven()
        .args(["fit", "--model", "microcylinder", "--starts", "4", "--init"])
        .arg(&init)
        .arg("--data")
        .arg(&data)
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
    let printed = rms_log_of(&fit.get_output().stderr);
    let mut dirs = String::from("theta_i,phi_i,theta_r,phi_r\n");
    for &[ti, pi, tr, pr] in &geometry {
        dirs.push_str(&format!("{ti:?},{pi:?},{tr:?},{pr:?}\n"));
    }
    let eval = woven()
        .args(["eval", "--rgb", "--input", "-", "--material"])
        .arg(&out)
        .write_stdin(dirs)
        .assert()
        .success();
    let evaluated: Vec<[f64; 3]> = String::from_utf8_lossy(&eval.get_output().stdout)
        .lines()
        .skip(1)
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            [v[4], v[5], v[6]]
        })
        .collect();
    // The fitter's statistic (woven_fit::report::statistics): RMS of ln(p + ε) − ln(m + ε), ε a
    // thousandth of the channel's median measurement.
    let measured: Vec<[f64; 3]> = geometry
        .iter()
        .map(|&[ti, pi, tr, pr]| {
            truth
                .eval_unguarded(Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr))
                .0
        })
        .collect();
    let mut sum = 0.0;
    for c in 0..3 {
        let mut positive: Vec<f64> = measured.iter().map(|m| m[c]).filter(|&x| x > 0.0).collect();
        positive.sort_by(f64::total_cmp);
        let eps = 1e-3 * positive[positive.len() / 2];
        for (m, p) in measured.iter().zip(&evaluated) {
            sum += ((p[c].max(0.0) + eps).ln() - (m[c] + eps).ln()).powi(2);
        }
    }
    let rms = (sum / (3 * measured.len()) as f64).sqrt();
    assert!(
        (rms - printed).abs() < 6e-5,
        "woven eval of the file: RMS log {rms}; the fit printed {printed}"
    );
}

#[test]
fn starts_of_the_wrong_kind_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let shot = Microcylinder::preset("microcylinder-silk-shot").unwrap();
    let data = measurements(dir.path(), "shot.csv", &pairs(&[30.0]), &|wi, wo| {
        shot.eval_rgb(wi, wo)
    });
    let run = |init: &str| {
        woven()
            .args(["fit", "--model", "microcylinder", "--init", init, "--data"])
            .arg(&data)
            .assert()
            .failure()
    };
    run("belt-cloth").stderr(
        predicate::str::contains("--init belt-cloth")
            .and(predicate::str::contains("woven material preset"))
            .and(predicate::str::contains("microcylinder-linen-plain")),
    );
    run("microcylinder-tweed").stderr(
        predicate::str::contains("microcylinder-tweed")
            .and(predicate::str::contains("no such preset or file")),
    );
    woven()
        .args([
            "fit",
            "--model",
            "microcylinder",
            "--fix",
            "thread1.kd=2",
            "--data",
        ])
        .arg(&data)
        .assert()
        .failure()
        .stderr(predicate::str::contains("thread1.kd").and(predicate::str::contains("[0, 1]")));
}

/// With --compare, --init is shared: each model starts from it where it is of that model's kind.
/// A microcylinder file starts the microcylinder, and the Lambert baseline, which takes no start,
/// ignores it; a single Lambert fit given it is an error naming both flags.
#[test]
fn compare_shares_init_with_the_models_of_its_kind() {
    let dir = tempfile::tempdir().unwrap();
    let shot = Microcylinder::preset("microcylinder-silk-shot").unwrap();
    let data = measurements(dir.path(), "shot.csv", &pairs(&[15.0, 35.0]), &|wi, wo| {
        shot.eval_rgb(wi, wo)
    });
    let init = dir.path().join("straight.toml");
    std::fs::write(
        &init,
        "model = \"microcylinder\"\nname = \"straight\"\n\
         [[thread]]\neta = 1.5\nalbedo = [0.8, 0.6, 0.4]\nkd = 0.3\ngamma_s_deg = 20.0\n\
         gamma_v_deg = 40.0\ncoverage = 0.6\ntangent_offsets_deg = [0.0]\n\
         [[thread]]\neta = 1.5\nalbedo = [0.3, 0.5, 0.8]\nkd = 0.5\ngamma_s_deg = 20.0\n\
         gamma_v_deg = 40.0\ncoverage = 0.4\ntangent_offsets_deg = [0.0]\n",
    )
    .unwrap();
    woven()
        .args([
            "fit",
            "--models",
            "lambert,microcylinder",
            "--starts",
            "2",
            "--init",
        ])
        .arg(&init)
        .arg("--compare")
        .arg(&data)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "| dataset | points | lambert | microcylinder |",
        ))
        .stderr(predicate::str::contains("failed").not());
    woven()
        .args(["fit", "--model", "lambert", "--init"])
        .arg(&init)
        .arg("--data")
        .arg(&data)
        .assert()
        .failure()
        .stderr(predicate::str::contains("--model lambert --init"));
}
