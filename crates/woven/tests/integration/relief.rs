//! The resolved levels on the weave's relief (docs/model.md §8, "The relief"): fibres average to
//! the resolved yarn level, and the resolved yarn level to the macro BRDF scaled by the relief's
//! ratio, so `detail = "auto"` keeps its mean from close-up to far away.

use crate::common::Rng;
use std::sync::Arc;
use woven::bsdf::Bsdf;
use woven::material::Material;
use woven::surface::{Detail, SurfacePoint, SurfaceSpec, WovenSurface};
use woven::table::{Table, TableOptions};
use woven::Vec3;

/// A preset laid in its own weave at one cell a unit, at `detail`, on a table of its yarn.
pub fn surface(name: &str, detail: Detail, table: &Arc<Table>) -> WovenSurface {
    let spec = SurfaceSpec {
        detail,
        ..SurfaceSpec::new(Material::preset(name).unwrap())
    };
    WovenSurface::new(&spec, Arc::clone(table)).unwrap()
}

pub fn table(name: &str) -> Arc<Table> {
    let m = Material::preset(name).unwrap().yarn_family();
    let options = TableOptions {
        n_theta: 24,
        n_phi: 12,
        n_h: 61,
        colour: true,
        ..TableOptions::default()
    };
    Arc::new(Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap())
}

/// The mean (over channels and `n` points spread over `cells` × `cells` cells) of `f(s, v)` at
/// points with footprint `footprint` (uv per pixel).
pub fn area_mean(
    surface: &WovenSurface,
    (s, v): (Vec3, Vec3),
    cells: f64,
    n: usize,
    footprint: f64,
) -> f64 {
    let mut total = 0.0;
    for k in 0..n {
        let x = woven::yarn::point::golden_uniform(k as i64, 21);
        let y = (k as f64 + 0.5) / n as f64;
        let at = SurfacePoint {
            uv: [x * cells, y * cells],
            footprint: [[footprint, 0.0], [0.0, footprint]],
        };
        let f = surface.at(&at).eval(s, v).0;
        total += (f[0] + f[1] + f[2]) / 3.0;
    }
    total / n as f64
}

#[test]
#[ignore = "exploration"]
fn explore_relief_identities() {
    let mut rng = Rng(3);
    for name in ["satin-charmeuse"] {
        let t = table(name);
        let fib = surface(name, Detail::Fibers, &t);
        let auto = surface(name, Detail::Auto, &t);
        let paper = surface(name, Detail::Cloth, &t);
        for _ in 0..6 {
            let d = |rng: &mut Rng| {
                Vec3::from_spherical(
                    rng.uniform().sqrt().asin() * 0.98 + 0.0,
                    rng.range(0.0, 6.283),
                )
            };
            let (s, v) = (d(&mut rng), d(&mut rng));
            let f = area_mean(&fib, (s, v), 64.0, 40_000, 0.0);
            let y = area_mean(&auto, (s, v), 64.0, 40_000, 0.0);
            let m = area_mean(&auto, (s, v), 64.0, 200, 1e6);
            let p = area_mean(&paper, (s, v), 64.0, 200, 0.0);
            println!("{name}: θs {:.0} θv {:.0}: fibres {f:.4} yarns {y:.4} macro {m:.4} paper {p:.4}; fib/yarn {:+.1}% macro/yarn {:+.1}% paper/yarn {:+.1}%",
                s.z.acos().to_degrees(), v.z.acos().to_degrees(), 100.0*(f/y-1.0), 100.0*(m/y-1.0), 100.0*(p/y-1.0));
        }
    }
}

#[test]
#[ignore = "exploration"]
fn explore_local() {
    let name = "silk-shot";
    let t = table(name);
    let fib = surface(name, Detail::Fibers, &t);
    let auto = surface(name, Detail::Auto, &t);
    let s = Vec3::from_spherical(0.5, 0.3);
    let v = Vec3::from_spherical(0.7, 2.5);
    // Cell (0,1): which family? scan across y in the weft cell of row 0 col 0.
    for (x0, y0) in [(0.5, 0.5), (1.5, 0.5), (0.5, 0.3), (0.2, 0.5), (10.5, 20.5)] {
        let mut fm = 0.0;
        let n = 4000;
        for k in 0..n {
            let dy = (k as f64 + 0.5) / n as f64 * (2.0 / 16.0) - 1.0 / 16.0;
            let at = SurfacePoint {
                uv: [x0, y0 + dy],
                footprint: [[0.0; 2]; 2],
            };
            let f = fib.at(&at).eval(s, v).0;
            fm += f[1] / n as f64;
        }
        let at = SurfacePoint {
            uv: [x0, y0],
            footprint: [[0.0; 2]; 2],
        };
        let y = auto.at(&at).eval(s, v).0[1];
        let mix = fib.at(&at).mix_seen_from(v);
        println!(
            "({x0},{y0}): fibres {fm:.4} yarn {y:.4} ({:+.1}%) lobes {:?}",
            100.0 * (fm / y - 1.0),
            mix.lobes()
                .iter()
                .map(|l| (l.warp, l.tilt))
                .collect::<Vec<_>>()
        );
    }
}

#[test]
#[ignore = "exploration"]
fn explore_micro() {
    let name = "silk-shot";
    let t = table(name);
    let fib = surface(name, Detail::Fibers, &t);
    let auto = surface(name, Detail::Auto, &t);
    let s = Vec3::from_spherical(0.5, 0.3);
    let v = Vec3::from_spherical(0.7, 2.5);
    let (x0, y0) = (1.5, 0.5);
    let n = 64;
    for k in 0..n {
        let dy = (k as f64 + 0.5) / n as f64 * (1.0 / 16.0);
        let at = SurfacePoint {
            uv: [x0, y0 + dy],
            footprint: [[0.0; 2]; 2],
        };
        let b = fib.at(&at);
        let f = b.eval(s, v).0[1];
        let mix = b.mix_seen_from(v);
        let l = mix.lobes()[0];
        if k % 8 == 0 {
            println!(
                "dy {dy:.4}: f {f:.4} across {:?} tilt {:?}",
                l.point.map(|p| (p.across, p.theta_a, p.phi)),
                l.tilt
            );
        }
    }
    let at = SurfacePoint {
        uv: [x0, y0],
        footprint: [[0.0; 2]; 2],
    };
    println!("yarn {:.4}", auto.at(&at).eval(s, v).0[1]);
    let model = crate::surface::exact_yarn(name);
    let yarn = match model.structure() {
        woven::cloth::Structure::Woven { yarn, .. } => yarn,
        _ => panic!(),
    };
    let theta_a = yarn.slopes().mean();
    let m: f64 = (0..4000)
        .map(|k| {
            let p = yarn.point_parts(s, v, 0.0, theta_a, (k as f64 + 0.5) / 4000.0);
            p[0] + p[1] * 0.3
        })
        .sum::<f64>()
        / 4000.0;
    println!(
        "micro mean of parts (ρ0 0.3) {m:.4}; exact yarn {:.4}; profile {:?}",
        model.eval(s, v),
        yarn.profile_brdf(s, v, 0.0, theta_a)
    );
}

#[test]
#[ignore = "exploration"]
fn explore_nodes() {
    let name = "satin-charmeuse";
    let t = table(name);
    let auto = surface(name, Detail::Auto, &t);
    let node = |it: usize, ip: usize| {
        Vec3::from_spherical(
            woven::surface::RATIO_THETA_DEG[it].to_radians(),
            2.0 * std::f64::consts::PI * ip as f64 / 12.0,
        )
    };
    for (a, b, c, d) in [
        (4, 0, 3, 6),
        (4, 3, 4, 9),
        (3, 1, 5, 7),
        (5, 2, 2, 8),
        (4, 0, 4, 6),
        (4, 6, 4, 0),
    ] {
        let (s, v) = (node(a, b), node(c, d));
        let y = area_mean(&auto, (s, v), 64.0, 160_000, 0.0);
        let m = area_mean(&auto, (s, v), 64.0, 200, 1e6);
        let half = std::f64::consts::PI / woven::surface::RATIO_PHI as f64;
        let sm = Vec3::from_spherical(s.z.acos(), s.y.atan2(s.x) + half);
        let vm = Vec3::from_spherical(v.z.acos(), v.y.atan2(v.x) + half);
        let y2 = area_mean(&auto, (sm, vm), 64.0, 160_000, 0.0);
        let m2 = area_mean(&auto, (sm, vm), 64.0, 200, 1e6);
        let r = |s: Vec3, v: Vec3| {
            (
                auto.relief_ratio(false, s, v),
                auto.relief_ratio(true, s, v),
            )
        };
        println!("  R node {:?} shifted {:?}", r(s, v), r(sm, vm));
        println!("node s({a},{b}) v({c},{d}): yarns {y:.4} macro {m:.4} ({:+.1}%); between nodes: yarns {y2:.4} macro {m2:.4} ({:+.1}%)", 100.0 * (m / y - 1.0), 100.0 * (m2 / y2 - 1.0));
    }
}

#[test]
#[ignore = "exploration"]
fn explore_mirror() {
    let name = "satin-charmeuse";
    let t = table(name);
    let auto = surface(name, Detail::Auto, &t);
    let th = 59f64.to_radians();
    let v = Vec3::from_spherical(th, 270f64.to_radians());
    for ds in [90.0, 97.5, 105.0, 112.5, 120.0, 135.0, 150.0] {
        let s = Vec3::from_spherical(th, f64::to_radians(ds));
        let y = area_mean(&auto, (s, v), 64.0, 160_000, 0.0);
        let m = area_mean(&auto, (s, v), 64.0, 200, 1e6);
        let r = (
            auto.relief_ratio(false, s, v),
            auto.relief_ratio(true, s, v),
        );
        println!("φs {ds}: yarns {y:.4} macro {m:.4} R {:.3} {:.3}", r.0, r.1);
    }
}

#[test]
#[ignore = "exploration"]
fn explore_mirror_weft_only() {
    let name = "satin-charmeuse";
    let t = table(name);
    let mut material = woven::material::Material::preset(name).unwrap();
    material.weave = Some(woven::material::Weave::Pattern {
        spec: woven::material::PatternSpec::Matrix(vec![vec![1]]),
        pattern: woven::weave::Pattern::from_matrix(vec![vec![1]]).unwrap(),
    });
    let spec = SurfaceSpec {
        detail: Detail::Auto,
        u_max: 0.0,
        ..SurfaceSpec::new(material)
    };
    let auto = WovenSurface::new(&spec, Arc::clone(&t)).unwrap();
    let th = 59f64.to_radians();
    let v = Vec3::from_spherical(th, 270f64.to_radians());
    for ds in [90.0, 97.5, 105.0, 112.5, 120.0, 135.0, 150.0, 0.0, 45.0] {
        let s = Vec3::from_spherical(th, f64::to_radians(ds));
        let y = area_mean(&auto, (s, v), 64.0, 40_000, 0.0);
        let m = area_mean(&auto, (s, v), 64.0, 200, 1e6);
        let r = auto.relief_ratio(false, s, v);
        println!("weft-only φs {ds}: yarns {y:.4} macro {m:.4} R {r:.3}");
    }
}

/// A resolving surface's ratio table is stored in the folder it is prepared with, read back by
/// the next surface of the same kind (the same values), and rebuilt, with a note, when the
/// file is damaged.
#[test]
fn the_relief_ratio_is_kept_on_disk() {
    let name = "belt-cloth";
    let t = table(name);
    let dir = std::env::temp_dir().join(format!("woven-ratio-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let notes = std::sync::Mutex::new(Vec::<String>::new());
    let note = |m: &str| notes.lock().unwrap().push(m.to_string());
    let first = surface(name, Detail::Auto, &t);
    first.prepare(Some(&dir), &note);
    let files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(files.len(), 1, "{files:?}");
    assert!(files[0].extension().is_some_and(|e| e == "wrat"));
    let pairs = [
        (0.3, 0.2, 0.9, 2.5),
        (1.1, 4.0, 0.4, 0.7),
        (1.4, 1.0, 1.3, 4.4),
    ];
    let ratios = |s: &WovenSurface| {
        pairs
            .iter()
            .map(|&(a, b, c, d)| {
                let (wi, wo) = (Vec3::from_spherical(a, b), Vec3::from_spherical(c, d));
                (s.relief_ratio(false, wi, wo), s.relief_ratio(true, wi, wo))
            })
            .collect::<Vec<_>>()
    };
    let second = surface(name, Detail::Auto, &t);
    let started = std::time::Instant::now();
    second.prepare(Some(&dir), &note);
    let loaded = started.elapsed();
    assert_eq!(ratios(&first), ratios(&second));
    assert!(
        notes.lock().unwrap().is_empty(),
        "{:?}",
        notes.lock().unwrap()
    );
    // Damaged: rebuilt (the same values), with a note saying why.
    let mut bytes = std::fs::read(&files[0]).unwrap();
    bytes[100] ^= 0xff;
    std::fs::write(&files[0], bytes).unwrap();
    let third = surface(name, Detail::Auto, &t);
    third.prepare(Some(&dir), &note);
    assert_eq!(ratios(&first), ratios(&third));
    let notes = notes.lock().unwrap();
    assert!(
        notes.len() == 1 && notes[0].contains("checksum"),
        "{notes:?}"
    );
    eprintln!("ratio read back in {:.3} s", loaded.as_secs_f64());
    std::fs::remove_dir_all(&dir).unwrap();
}
