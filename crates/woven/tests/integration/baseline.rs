//! The baseline BSDFs (`woven::baseline`): sampling against the claimed densities by χ², white
//! furnaces by importance sampling and by quadrature, reciprocity, sample weights, refused
//! parameters.

use std::f64::consts::PI;
use woven::baseline::{Distribution, RoughPlastic, RoughPlasticParams, Sheen, SheenParams};
use woven::bsdf::{pair_of, Bsdf, Transport};
use woven::color::Rgb;
use woven::math::quadrature::GaussLegendre;
use woven::table::report::SplitMix;
use woven::Vec3;

fn sheen(diffuse: Rgb, sheen_color: Rgb, roughness: f64) -> Sheen {
    Sheen::new(&SheenParams {
        diffuse,
        sheen_color,
        roughness,
    })
    .unwrap()
}

fn plastic(distribution: Distribution, alpha: f64, diffuse: Rgb, nonlinear: bool) -> RoughPlastic {
    RoughPlastic::new(&RoughPlasticParams {
        distribution,
        alpha,
        diffuse_reflectance: diffuse,
        nonlinear,
        ..RoughPlasticParams::default()
    })
    .unwrap()
}

/// Parameter sets for the sampling tests: smooth and rough, pure lobes and mixtures, colours.
fn sheens() -> Vec<(&'static str, Sheen)> {
    vec![
        ("smooth sheen", sheen(Rgb::grey(0.5), Rgb::WHITE, 0.1)),
        (
            "tinted sheen",
            sheen(Rgb([0.8, 0.4, 0.1]), Rgb([1.0, 0.5, 0.2]), 0.4),
        ),
        ("sheen alone", sheen(Rgb::BLACK, Rgb::WHITE, 1.0)),
        ("base alone", sheen(Rgb::WHITE, Rgb::BLACK, 0.5)),
    ]
}

fn plastics() -> Vec<(&'static str, RoughPlastic)> {
    vec![
        (
            "beckmann 0.05",
            plastic(Distribution::Beckmann, 0.05, Rgb::grey(0.5), false),
        ),
        (
            "beckmann 0.3 nonlinear",
            plastic(Distribution::Beckmann, 0.3, Rgb([0.9, 0.3, 0.1]), true),
        ),
        (
            "ggx 0.1",
            plastic(Distribution::Ggx, 0.1, Rgb([0.2, 0.6, 0.9]), false),
        ),
        (
            "ggx 0.6 coating alone",
            plastic(Distribution::Ggx, 0.6, Rgb::BLACK, false),
        ),
    ]
}

/// χ² of `b`'s sampler against its density for a known direction at polar angle `theta_deg`.
fn chi2<B: Bsdf + ?Sized>(b: &B, theta_deg: f64, mode: Transport, seed: u64) -> (f64, f64, f64) {
    let known = Vec3::from_spherical(theta_deg.to_radians(), 0.4);
    crate::table::chi2_of(
        |rng| {
            b.sample(known, rng.uniform(), [rng.uniform(), rng.uniform()], mode)
                .map(|s| match mode {
                    Transport::Radiance => s.wi,
                    Transport::Importance => s.wo,
                })
        },
        |d| {
            let (wi, wo) = pair_of(known, d, mode);
            b.pdf(wi, wo, mode)
        },
        100_000,
        seed,
    )
}

const INCIDENCES_DEG: [f64; 3] = [15.0, 55.0, 82.0];

#[test]
fn sampling_passes_chi_square() {
    // 8 BSDFs × 3 incidences: Šidák-corrected significance 1 % overall.
    let tests = (8 * INCIDENCES_DEG.len()) as f64;
    let alpha = 1.0 - (1.0f64 - 0.01).powf(1.0 / tests);
    let check = |name: &str, theta: f64, (p, accepted, integral): (f64, f64, f64)| {
        assert!(
            p > alpha,
            "{name} at θ {theta}°: χ² p-value {p:.2e} < {alpha:.2e}"
        );
        // The density integrates to the fraction of draws that land above the horizon.
        assert!(
            (integral - accepted).abs() < 0.01,
            "{name} at θ {theta}°: ∫pdf {integral:.4} vs accepted fraction {accepted:.4}"
        );
    };
    let mut seed = 5;
    for (k, (name, b)) in sheens().iter().enumerate() {
        for theta in INCIDENCES_DEG {
            let mode = if k % 2 == 0 {
                Transport::Radiance
            } else {
                Transport::Importance
            };
            check(name, theta, chi2(b, theta, mode, seed));
            seed += 1;
        }
    }
    for (k, (name, b)) in plastics().iter().enumerate() {
        for theta in INCIDENCES_DEG {
            let mode = if k % 2 == 0 {
                Transport::Importance
            } else {
                Transport::Radiance
            };
            check(name, theta, chi2(b, theta, mode, seed));
            seed += 1;
        }
    }
}

/// Directional albedo per channel for light from `theta` by importance sampling with `b`'s own
/// sampler: the weights `f cos / pdf` averaged over a grid of `u` (cell midpoints) and strata of
/// `uc` jittered within each stratum, so that each lobe is chosen with exactly its probability
/// (midpoints of `uc` would choose a lobe with a multiple of 1/8 instead, a bias).
fn albedo_sampled<B: Bsdf<Value = Rgb> + ?Sized>(b: &B, theta: f64) -> Rgb {
    let wi = Vec3::from_spherical(theta, 0.0);
    let (nc, nu) = (8, 96);
    let mut rng = SplitMix(29);
    let mut sum = Rgb::BLACK;
    for c in 0..nc {
        for i in 0..nu {
            for j in 0..nu {
                let uc = (c as f64 + rng.uniform()) / nc as f64;
                let u = [(i as f64 + 0.5) / nu as f64, (j as f64 + 0.5) / nu as f64];
                if let Some(s) = b.sample(wi, uc, u, Transport::Importance) {
                    sum += s.weight(Transport::Importance);
                }
            }
        }
    }
    sum / (nc * nu * nu) as f64
}

/// The same albedo by brute-force quadrature over the viewer's hemisphere (`√cos θo` and `φo`
/// panels); only for lobes broad enough to resolve.
fn albedo_quadrature<B: Bsdf<Value = Rgb> + ?Sized>(b: &B, theta: f64) -> Rgb {
    let wi = Vec3::from_spherical(theta, 0.0);
    let gl = GaussLegendre::new(12);
    let n = 24;
    let mut sum = Rgb::BLACK;
    for a in 0..n {
        for p in 0..n {
            let (t0, p0) = (a as f64 / n as f64, p as f64 / n as f64 * PI);
            let mut cell = Rgb::BLACK;
            for (x, wx) in gl.nodes().iter().zip(gl.weights()) {
                let t = t0 + (x + 1.0) * 0.5 / n as f64;
                let c = t * t;
                let s = (1.0 - c * c).max(0.0).sqrt();
                for (y, wy) in gl.nodes().iter().zip(gl.weights()) {
                    let phi = p0 + (y + 1.0) * 0.5 / n as f64 * PI;
                    let wo = Vec3::new(s * phi.cos(), s * phi.sin(), c);
                    // dω = dμ dφ = 2t dt dφ; the cosine is c.
                    cell += b.eval(wi, wo) * (wx * wy * 2.0 * t * c);
                }
            }
            sum += cell * (0.25 / n as f64 * PI / n as f64);
        }
    }
    sum * 2.0 // φo over half a turn: the lobes are even in azimuth about wi's plane
}

const FURNACE_DEG: [f64; 7] = [0.0, 30.0, 60.0, 75.0, 85.0, 88.0, 89.0];

#[test]
fn white_furnace_albedo_never_exceeds_one() {
    // Worst cases: a white base under a white sheen, smooth and rough; a white base under a
    // clear coating, nearly smooth to rough, both distributions, linear and nonlinear. Broad
    // lobes are integrated by quadrature (good to 10⁻⁴; the sampled estimate of a smooth sheen
    // at grazing is noisy to 10⁻²), the nearly smooth coating by its sampler (its weights are
    // smooth in the uniforms: good to 10⁻⁴).
    let mut cases: Vec<(String, Box<dyn Bsdf<Value = Rgb>>, bool)> = Vec::new();
    for r in [0.1, 0.2, 0.3, 0.6, 1.0] {
        cases.push((
            format!("sheen r {r}"),
            Box::new(sheen(Rgb::WHITE, Rgb::WHITE, r)),
            true,
        ));
    }
    for dist in [Distribution::Beckmann, Distribution::Ggx] {
        for alpha in [1e-3, 0.1, 0.5, 1.0] {
            for nonlinear in [false, true] {
                cases.push((
                    format!("{dist:?} α {alpha} nonlinear {nonlinear}"),
                    Box::new(plastic(dist, alpha, Rgb::WHITE, nonlinear)),
                    alpha >= 0.1,
                ));
            }
        }
    }
    for (name, b, broad) in &cases {
        for theta_deg in FURNACE_DEG {
            let theta = f64::to_radians(theta_deg);
            let a = if *broad {
                albedo_quadrature(b.as_ref(), theta)
            } else {
                albedo_sampled(b.as_ref(), theta)
            };
            // 10⁻³: the tabulations' error (module docs of each).
            assert!(
                a.0.iter().all(|&x| x <= 1.0 + 1e-3 && x > 0.0),
                "{name} at θ {theta_deg}°: albedo {:?}",
                a.0
            );
        }
    }
}

#[test]
fn importance_sampled_and_quadrature_albedos_agree() {
    let cases: Vec<(&str, Box<dyn Bsdf<Value = Rgb>>)> = vec![
        ("sheen r 0.3", Box::new(sheen(Rgb::WHITE, Rgb::WHITE, 0.3))),
        (
            "sheen r 0.8 tinted",
            Box::new(sheen(Rgb([0.2, 0.5, 0.9]), Rgb([0.9, 0.6, 0.3]), 0.8)),
        ),
        (
            "beckmann 0.3",
            Box::new(plastic(Distribution::Beckmann, 0.3, Rgb::WHITE, false)),
        ),
        (
            "ggx 0.5 nonlinear",
            Box::new(plastic(Distribution::Ggx, 0.5, Rgb([0.7, 0.2, 0.4]), true)),
        ),
    ];
    for (name, b) in &cases {
        for theta_deg in [0.0, 45.0, 80.0] {
            let theta = f64::to_radians(theta_deg);
            let (s, q) = (
                albedo_sampled(b.as_ref(), theta),
                albedo_quadrature(b.as_ref(), theta),
            );
            for c in 0..3 {
                assert!(
                    (s.0[c] - q.0[c]).abs() < 3e-3,
                    "{name} at θ {theta_deg}°, channel {c}: sampled {} vs quadrature {}",
                    s.0[c],
                    q.0[c]
                );
            }
        }
    }
}

/// Random direction pairs above the horizon (some near grazing).
fn pairs(n: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut rng = SplitMix(seed);
    (0..n)
        .map(|_| {
            let a = Vec3::from_spherical(rng.range(0.0, 1.56), rng.range(0.0, 2.0 * PI));
            let b = Vec3::from_spherical(rng.range(0.0, 1.56), rng.range(0.0, 2.0 * PI));
            (a, b)
        })
        .collect()
}

fn all() -> Vec<(&'static str, Box<dyn Bsdf<Value = Rgb>>)> {
    let mut v: Vec<(&'static str, Box<dyn Bsdf<Value = Rgb>>)> = Vec::new();
    for (name, b) in sheens() {
        v.push((name, Box::new(b)));
    }
    for (name, b) in plastics() {
        v.push((name, Box::new(b)));
    }
    v
}

#[test]
fn both_are_reciprocal() {
    for (name, b) in all() {
        for (wi, wo) in pairs(500, 3) {
            let (f, g) = (b.eval(wi, wo), b.eval(wo, wi));
            for c in 0..3 {
                assert!(
                    (f.0[c] - g.0[c]).abs() <= 1e-12 * f.0[c].abs().max(1e-300),
                    "{name}: f(wi, wo) {:?} vs f(wo, wi) {:?}",
                    f.0,
                    g.0
                );
            }
            assert!(f.is_valid(), "{name}: {:?}", f.0);
        }
        // Below the horizon: nothing.
        let up = Vec3::from_spherical(0.3, 0.0);
        let down = Vec3::new(0.3, 0.0, -0.95);
        assert!(
            b.eval(up, down).is_black() && b.eval(down, up).is_black(),
            "{name}"
        );
        assert_eq!(b.pdf(up, down, Transport::Radiance), 0.0, "{name}");
        assert!(b
            .sample(down, 0.5, [0.3, 0.3], Transport::Radiance)
            .is_none());
    }
}

#[test]
fn samples_carry_eval_pdf_and_their_weight() {
    let mut rng = SplitMix(11);
    for (name, b) in all() {
        for mode in [Transport::Radiance, Transport::Importance] {
            for _ in 0..400 {
                let known = Vec3::from_spherical(rng.range(0.0, 1.55), rng.range(0.0, 2.0 * PI));
                let (uc, u) = (rng.uniform(), [rng.uniform(), rng.uniform()]);
                let Some(s) = b.sample(known, uc, u, mode) else {
                    continue;
                };
                let f = b.eval(s.wi, s.wo);
                let pdf = b.pdf(s.wi, s.wo, mode);
                assert!(s.pdf > 0.0 && (s.pdf - pdf).abs() <= 1e-12 * pdf, "{name}");
                assert_eq!(s.f, f, "{name}");
                let cos = match mode {
                    Transport::Radiance => s.wi.z,
                    Transport::Importance => s.wo.z,
                };
                let w = s.weight(mode);
                for c in 0..3 {
                    let want = f.0[c] * cos / pdf;
                    assert!(
                        (w.0[c] - want).abs() <= 1e-12 * want.abs().max(1e-300),
                        "{name}: weight {:?} vs f cos/pdf {want}",
                        w.0
                    );
                }
                let drawn = match mode {
                    Transport::Radiance => s.wi,
                    Transport::Importance => s.wo,
                };
                assert!((drawn.length() - 1.0).abs() < 1e-12 && drawn.z > 0.0);
                assert_eq!(
                    if mode == Transport::Radiance {
                        s.wo
                    } else {
                        s.wi
                    },
                    known
                );
            }
        }
    }
}

#[test]
fn golden_limits() {
    // No sheen: the Lambertian base, diffuse/π, everywhere.
    let base = sheen(Rgb([0.3, 0.6, 0.9]), Rgb::BLACK, 0.5);
    for (wi, wo) in pairs(50, 7) {
        let f = base.eval(wi, wo);
        for c in 0..3 {
            assert!((f.0[c] - [0.3, 0.6, 0.9][c] / PI).abs() < 1e-15);
        }
    }
    // A nearly smooth clear coating reflects ((η − 1)/(η + 1))² at normal incidence: the
    // specular part of the albedo of a black base.
    let eta: f64 = 1.49 / 1.000277;
    let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    let coat = plastic(Distribution::Beckmann, 1e-3, Rgb::BLACK, false);
    let a = albedo_sampled(&coat, 0.0);
    assert!((a.0[0] - f0).abs() < 1e-4, "{} vs {f0}", a.0[0]);
    assert!((coat.transmittance(1.0) - (1.0 - f0)).abs() < 1e-4);
    // Linear and nonlinear agree for a white base and differ (darker) for a grey one.
    let (lin, non) = (
        plastic(Distribution::Beckmann, 0.1, Rgb::grey(0.5), false),
        plastic(Distribution::Beckmann, 0.1, Rgb::grey(0.5), true),
    );
    let (wi, wo) = (
        Vec3::from_spherical(0.2, 0.0),
        Vec3::from_spherical(1.0, 1.0),
    );
    assert!(non.eval(wi, wo).0[0] < lin.eval(wi, wo).0[0]);
    let (lw, nw) = (
        plastic(Distribution::Beckmann, 0.1, Rgb::WHITE, false),
        plastic(Distribution::Beckmann, 0.1, Rgb::WHITE, true),
    );
    assert_eq!(lw.eval(wi, wo), nw.eval(wi, wo));
}

#[test]
fn bad_parameters_are_refused_naming_parameter_value_and_range() {
    let e = Sheen::new(&SheenParams {
        roughness: 0.01,
        ..SheenParams::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("roughness") && e.contains("0.01") && e.contains("[0.1, 1]"),
        "{e}"
    );
    let e = Sheen::new(&SheenParams {
        diffuse: Rgb([0.5, 0.5, 2.0]),
        ..SheenParams::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("diffuse") && e.contains('2') && e.contains("[0, 1]"),
        "{e}"
    );
    let e = RoughPlastic::new(&RoughPlasticParams {
        alpha: -0.1,
        ..RoughPlasticParams::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("alpha") && e.contains("-0.1") && e.contains("[0.001, 1]"),
        "{e}"
    );
    let e = RoughPlastic::new(&RoughPlasticParams {
        int_ior: 1.000277,
        ..RoughPlasticParams::default()
    })
    .unwrap_err()
    .to_string();
    assert!(e.contains("int_ior") && e.contains("ext_ior"), "{e}");
    let e = RoughPlastic::new(&RoughPlasticParams {
        specular_reflectance: Rgb([1.0, f64::INFINITY, 1.0]),
        ..RoughPlasticParams::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("specular_reflectance") && e.contains("inf"),
        "{e}"
    );
    // The defaults build and are Mitsuba 3's.
    let d = RoughPlasticParams::default();
    assert_eq!(
        (d.distribution, d.alpha, d.int_ior, d.ext_ior, d.nonlinear),
        (Distribution::Beckmann, 0.1, 1.49, 1.000277, false)
    );
    RoughPlastic::new(&d).unwrap();
    Sheen::new(&SheenParams::default()).unwrap();
}
