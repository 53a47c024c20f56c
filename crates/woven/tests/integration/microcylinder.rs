//! The microcylinder cloth model (Sadeghi et al. 2013; docs/microcylinder.md): the curve
//! quadrature against brute force, the sampler (χ², weights), energy (albedo ≤ 1 of the guarded
//! BSDF), the thread layout's mirror symmetries, and parameter errors.

use std::f64::consts::PI;
use std::sync::OnceLock;
use woven::bsdf::{Bsdf, Transport};
use woven::microcylinder::{CurveRule, Microcylinder, TangentCurve, Thread};
use woven::Vec3;

/// Every preset, built once per test binary.
fn presets() -> &'static Vec<Microcylinder> {
    static P: OnceLock<Vec<Microcylinder>> = OnceLock::new();
    P.get_or_init(|| {
        Microcylinder::preset_names()
            .iter()
            .map(|n| Microcylinder::preset(n).unwrap())
            .collect()
    })
}

fn unguarded(name: &str, rule: &dyn Fn(&Thread) -> CurveRule) -> Microcylinder {
    Microcylinder::with_options(
        name,
        Microcylinder::preset_threads(name).unwrap(),
        rule,
        false,
    )
    .unwrap()
}

/// Directions spread over the hemisphere (deterministic), with the mirror pairs and grazing
/// light where the lobes are sharpest.
fn directions() -> Vec<(Vec3, Vec3)> {
    let mut out = Vec::new();
    let mut rng = woven::math::rng::SplitMix(11);
    for _ in 0..40 {
        let ti = rng.range(0.0, 1.45);
        let pi = rng.range(0.0, 2.0 * PI);
        let to = rng.range(0.0, 1.45);
        let po = rng.range(0.0, 2.0 * PI);
        out.push((Vec3::from_spherical(ti, pi), Vec3::from_spherical(to, po)));
        out.push((
            Vec3::from_spherical(ti, pi),
            Vec3::from_spherical(ti, pi + PI),
        ));
    }
    out
}

/// The default Gauss–Legendre rule of each curve matches a brute-force midpoint rule of 20 000
/// points along the thread's length, for every preset (docs/microcylinder.md §5).
#[test]
fn curve_quadrature_matches_brute_force() {
    for name in Microcylinder::preset_names() {
        let gauss = unguarded(name, &woven::microcylinder::default_rule);
        let brute = unguarded(name, &|_| CurveRule::Midpoint { n: 20_000 });
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for (wi, wo) in directions() {
            let (a, b) = (gauss.eval_unguarded(wi, wo), brute.eval_unguarded(wi, wo));
            for c in 0..3 {
                worst = worst.max((a.0[c] - b.0[c]).abs());
                scale = scale.max(b.0[c]);
            }
        }
        println!("{name}: worst |gauss − brute| = {worst:.3e} (peak {scale:.3e})");
        assert!(worst <= 2e-3 * scale, "{name}: {worst} vs peak {scale}");
    }
}

/// Averaging over the table's control points instead of along the length is a different model:
/// the test above must be able to tell (here it changes values by far more than its tolerance).
#[test]
fn control_point_average_differs() {
    let name = "microcylinder-satin-charmeuse";
    let brute = unguarded(name, &|_| CurveRule::Midpoint { n: 20_000 });
    let offsets: Vec<f64> = brute.threads[0].tangents.offsets().to_vec();
    let w = 1.0 / offsets.len() as f64;
    let mut threads = Microcylinder::preset_threads(name).unwrap();
    // Control points as equal-weight straight threads: one segment of each constant tilt.
    let pts: Vec<f64> = offsets.iter().flat_map(|a| [*a, *a]).collect();
    let lens: Vec<f64> = (0..pts.len() - 1)
        .map(|k| if k % 2 == 0 { w } else { 0.0 })
        .collect();
    threads[0].tangents = TangentCurve::new(&pts, &lens).unwrap();
    let cp = Microcylinder::with_options(name, threads, &woven::microcylinder::default_rule, false)
        .unwrap();
    // Over the test directions, the largest ratio between the two readings (green channel).
    let mut ratio = 1.0f64;
    for (wi, wo) in directions() {
        let (a, b) = (
            cp.eval_unguarded(wi, wo).0[1],
            brute.eval_unguarded(wi, wo).0[1],
        );
        if a > 1e-3 && b > 1e-3 {
            ratio = ratio.max(a / b).max(b / a);
        }
    }
    println!("largest ratio control points / along the length: {ratio:.2}");
    assert!(ratio > 2.0, "ratio {ratio}");
}

/// χ² of the sampler against its density, for every preset at three incident directions, in
/// both transport modes.
#[test]
fn sampler_chi2() {
    let tests = presets().len() * 3 * 2;
    for cloth in presets() {
        for (k, theta) in [0.3f64, 0.9, 1.3].into_iter().enumerate() {
            let known = Vec3::from_spherical(theta, 0.4 + k as f64);
            for mode in [Transport::Radiance, Transport::Importance] {
                // The microcylinder's density is analytic: smooth within a cell.
                let (p, accepted, integral) = crate::table::chi2_of_smooth(
                    |rng| {
                        let uc = rng.uniform();
                        cloth
                            .sample(known, uc, [rng.uniform(), rng.uniform()], mode)
                            .map(|s| match mode {
                                Transport::Radiance => s.wi,
                                Transport::Importance => s.wo,
                            })
                    },
                    |d| cloth.sample_pdf(known, d),
                    100_000,
                    7 + k as u64,
                );
                println!(
                    "{} θ={theta} {mode:?}: p = {p:.3e}, accepted {accepted:.4}, ∫pdf {integral:.4}",
                    cloth.name
                );
                assert!(p > 0.01 / tests as f64, "{}: p = {p}", cloth.name);
                assert!(
                    (accepted - integral).abs() < 0.01,
                    "{accepted} vs {integral}"
                );
            }
        }
    }
}

/// `sample`'s value and density are `eval`'s and `pdf`'s, and its weight is `f cos / pdf`.
#[test]
fn sample_agrees_with_eval_and_pdf() {
    let mut rng = woven::math::rng::SplitMix(3);
    for cloth in presets() {
        for mode in [Transport::Radiance, Transport::Importance] {
            for _ in 0..200 {
                let known = Vec3::from_spherical(rng.range(0.0, 1.5), rng.range(0.0, 2.0 * PI));
                let u = [rng.uniform(), rng.uniform()];
                let Some(s) = cloth.sample(known, rng.uniform(), u, mode) else {
                    continue;
                };
                let f = cloth.eval(s.wi, s.wo);
                let pdf = cloth.pdf(s.wi, s.wo, mode);
                assert_eq!(f, s.f);
                assert!((pdf - s.pdf).abs() <= 1e-12 * pdf, "{pdf} vs {}", s.pdf);
                let cos = if mode == Transport::Radiance {
                    s.wi.z
                } else {
                    s.wo.z
                };
                let w = s.weight(mode);
                for c in 0..3 {
                    let want = f.0[c] * cos / pdf;
                    assert!((w.0[c] - want).abs() <= 1e-12 * want.max(1e-300));
                }
            }
        }
    }
}

/// White furnace: the guarded BSDF's directional albedo is at most 1 for every preset, light
/// up to 89° and azimuths on and between the guard's grid.
#[test]
fn albedo_at_most_one() {
    for cloth in presets() {
        let mut worst = 0.0f64;
        for theta_deg in [0.0, 45.0, 70.0, 80.0, 85.0, 88.0, 89.0] {
            for phi_deg in [0.0, 22.5, 90.0, 157.5, 200.0] {
                let a = cloth.albedo(f64::to_radians(theta_deg), f64::to_radians(phi_deg));
                assert!(a.is_valid());
                worst = worst.max(a.max());
                assert!(
                    a.max() <= 1.0,
                    "{}: albedo {a:?} at θi = {theta_deg}°, φi = {phi_deg}°",
                    cloth.name
                );
            }
        }
        println!("{}: largest albedo {worst:.3}", cloth.name);
    }
}

/// The printed model's albedo exceeds 1 at grazing light (why the guard exists); the guard
/// leaves the BRDF untouched where the albedo is well below 1.
#[test]
fn guard_is_needed_and_local() {
    let silk = presets()
        .iter()
        .find(|c| c.name.contains("silk-shot"))
        .unwrap();
    assert!(silk.albedo_unguarded(88f64.to_radians(), 0.0).max() > 1.0);
    for cloth in presets() {
        assert_eq!(cloth.guard().factor(0.5f64.cos()), 1.0, "{}", cloth.name);
    }
}

/// Mirror symmetries of the thread layout: `y → −y` for every preset (thread 1 lies in the xz
/// plane; thread 2's curves are symmetric in the tilt), and `x → −x` for every preset whose
/// thread-1 curve is symmetric (all but velvet, whose pile leans one way).
#[test]
fn mirror_symmetries() {
    let my = |v: Vec3| Vec3::new(v.x, -v.y, v.z);
    let mx = |v: Vec3| Vec3::new(-v.x, v.y, v.z);
    for cloth in presets() {
        let velvet = cloth.name.contains("velvet");
        for (wi, wo) in directions() {
            let f = cloth.eval_rgb(wi, wo);
            let tol = 1e-9 * f.max().max(1e-12);
            let g = cloth.eval_rgb(my(wi), my(wo));
            for c in 0..3 {
                assert!((f.0[c] - g.0[c]).abs() <= tol, "{} y-mirror", cloth.name);
            }
            if !velvet {
                let h = cloth.eval_rgb(mx(wi), mx(wo));
                for c in 0..3 {
                    assert!((f.0[c] - h.0[c]).abs() <= tol, "{} x-mirror", cloth.name);
                }
            }
        }
    }
    // Velvet's lean is visible: the x mirror changes it somewhere.
    let velvet = presets()
        .iter()
        .find(|c| c.name.contains("velvet"))
        .unwrap();
    let (wi, wo) = (
        Vec3::from_spherical(1.2, 0.0),
        Vec3::from_spherical(0.3, 2.0),
    );
    let (a, b) = (velvet.eval_rgb(wi, wo), velvet.eval_rgb(mx(wi), mx(wo)));
    assert!((a.max() - b.max()).abs() > 1e-3 * a.max().max(b.max()));
}

/// The model is not reciprocal (the normalization divides by cos θ_i): the transport mode
/// matters, and swapping the directions changes the value.
#[test]
fn not_reciprocal() {
    let cloth = &presets()[0];
    let (wi, wo) = (
        Vec3::from_spherical(1.2, 0.3),
        Vec3::from_spherical(0.2, 2.0),
    );
    let (a, b) = (cloth.eval_rgb(wi, wo).max(), cloth.eval_rgb(wo, wi).max());
    assert!((a - b).abs() > 1e-3 * a.max(b), "{a} {b}");
}

/// Invalid parameters are named, with their value and the valid range.
#[test]
fn invalid_parameters() {
    let d = PI / 180.0;
    let e = TangentCurve::new(&[-25.0 * d, 95.0 * d], &[1.0])
        .unwrap_err()
        .to_string();
    assert!(e.contains("tangent_offsets[1]") && e.contains("π/2"), "{e}");
    let e = TangentCurve::new(&[0.0, 0.1], &[-1.0])
        .unwrap_err()
        .to_string();
    assert!(e.contains("tangent_lengths[0]") && e.contains("-1"), "{e}");
    let e = TangentCurve::new(&[0.0, 0.1, 0.2], &[1.0])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("tangent_lengths") && e.contains("2 lengths"),
        "{e}"
    );
    let e = TangentCurve::new(&[0.0, 0.1], &[0.0])
        .unwrap_err()
        .to_string();
    assert!(e.contains("nonzero"), "{e}");
    let mut threads = Microcylinder::preset_threads("microcylinder-linen-plain").unwrap();
    threads[1].kd = 1.5;
    let e = Microcylinder::new("x", threads.clone())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("thread[1].kd") && e.contains("1.5") && e.contains("[0, 1]"),
        "{e}"
    );
    threads[1].kd = 0.3;
    threads[0].coverage = 0.8;
    let e = Microcylinder::new("x", threads.clone())
        .unwrap_err()
        .to_string();
    assert!(e.contains("coverage"), "{e}");
    threads[0].coverage = 0.3;
    threads[0].gamma_s = 0.0;
    let e = Microcylinder::new("x", threads).unwrap_err().to_string();
    assert!(e.contains("thread[0].gamma_s"), "{e}");
    let e = Microcylinder::preset("microcylinder-tweed")
        .unwrap_err()
        .to_string();
    assert!(e.contains("microcylinder-velvet"), "{e}");
}

/// The presets' stored energy guards are what measuring them again gives, at three of the
/// guard's polar angles (60°, 84°, 89.9°: a quarter of the whole measurement, a minute on two
/// cores; the measurement is deterministic).
#[test]
#[ignore = "a minute: CI's slow step"]
fn stored_preset_guards_are_measured_again() {
    use rayon::prelude::*;
    use woven::microcylinder::{
        default_rule, h_at, GUARD_THETA_DEG, PRESET_GUARDS, PRESET_GUARD_PHI_COUNT,
    };
    for (name, stored) in Microcylinder::preset_names().iter().zip(PRESET_GUARDS) {
        let threads = Microcylinder::preset_threads(name).unwrap();
        let cloth = Microcylinder::with_options(*name, threads, &default_rule, false).unwrap();
        for k in [2, 7, 12] {
            let f = |wi, wo| cloth.eval_unguarded(wi, wo);
            let h = (0..PRESET_GUARD_PHI_COUNT)
                .into_par_iter()
                .map(|j| h_at(&f, GUARD_THETA_DEG[k], j, PRESET_GUARD_PHI_COUNT))
                .reduce(|| 0.0, f64::max);
            let want = stored[k];
            assert!(
                (h - want).abs() <= 1e-12 * want,
                "{name} at θ node {k}: {h} vs {want}"
            );
        }
    }
}
