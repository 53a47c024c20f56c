//! The golden values of `tests/data/vectors` (docs/spec.md §6.7) at the tolerances its README states.

use crate::common::{assert_close, dirs, vector_roots};
use woven::material::Material;

/// Tolerance for a vector set, from `vectors/README.md`.
fn tolerance(set: &str, material: &Material) -> Option<f64> {
    if set.starts_with("fiber-rough") {
        Some(match material.fiber.normalization {
            woven::fiber::Normalization::None => 1e-9,
            woven::fiber::Normalization::Paper => 2e-4,
        })
    } else if set.starts_with("fiber-htsg") {
        Some(1e-4)
    } else if set.starts_with("profile-") {
        Some(1e-6)
    } else if set.starts_with("cloth-") {
        Some(1e-3)
    } else {
        None
    }
}

fn check_sets(prefix: &str) {
    let mut checked = 0;
    for root in vector_roots() {
        let mut sets: Vec<_> = std::fs::read_dir(&root)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.path())
            .filter(|p| p.is_dir())
            .collect();
        sets.sort();
        for dir in sets {
            let set = dir.file_name().unwrap().to_string_lossy().to_string();
            if !set.starts_with(prefix) {
                continue;
            }
            let material = Material::from_path(dir.join("material.toml"))
                .unwrap_or_else(|e| panic!("{set}: {e}"));
            let Some(tol) = tolerance(&set, &material) else {
                continue;
            };
            let model = material.build(550.0).unwrap();
            let mut rdr = csv::Reader::from_path(dir.join("cases.csv")).unwrap();
            for (row, rec) in rdr.records().enumerate() {
                let rec = rec.unwrap();
                let x: Vec<f64> = rec.iter().map(|t| t.parse().unwrap()).collect();
                let (s, v) = dirs(x[0], x[1], x[2], x[3]);
                let got = model.eval(s, v);
                assert_close(
                    got,
                    x[4],
                    tol,
                    1e-9,
                    &format!("{} case {row} {x:?}", dir.display()),
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 0, "no golden cases found for {prefix}");
}

#[test]
fn golden_fiber_rough() {
    check_sets("fiber-rough");
}

#[test]
fn golden_fiber_htsg() {
    check_sets("fiber-htsg");
}

#[test]
fn golden_profile() {
    check_sets("profile-");
}

#[test]
fn golden_cloth() {
    check_sets("cloth-");
}
