//! The woven material's options beyond the paper (both off by default): yarns tilted along
//! their floats (`u_max`) and gaps between yarns (`gap`); and the footprint filter's blend.

use crate::footprint::tiny_grid;
use std::sync::Mutex;
use woven::material::{Material, PatternSpec, Weave};
use woven::math::rng::SplitMix;
use woven::surface::Detail;
use woven::weave::Pattern;
use woven::Vec3;
use woven_render::material::{BsdfScratch, ShadingPoint, SurfaceMaterial};
use woven_render::woven_material::{TableCache, WovenMaterial, WovenSpec};

/// The sateen's yarn woven in `pattern` (or a weft fraction), one cell per unit of uv.
fn material(pattern: Result<Pattern, f64>, u_max_deg: f64, gap: f64) -> WovenMaterial {
    let mut m = Material::preset("polyester-sateen").unwrap();
    m.weave = Some(match pattern {
        Ok(p) => Weave::Pattern {
            spec: PatternSpec::Matrix(p.to_matrix()),
            pattern: p,
        },
        Err(gamma) => Weave::WeftFraction(gamma),
    });
    let spec = WovenSpec {
        yarns_per_unit: [1.0, 1.0],
        u_max: u_max_deg.to_radians(),
        gap,
        detail: Detail::Yarns,
        ..WovenSpec::new(m)
    };
    // One table for every material here (they share the sateen's yarn).
    static CACHE: Mutex<Option<TableCache>> = Mutex::new(None);
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    let cache = cache.get_or_insert_with(TableCache::default);
    WovenMaterial::build(&spec, &tiny_grid(), cache, &|| {}, &|_, _| {}).unwrap()
}

fn at(u: f64, v: f64) -> ShadingPoint {
    ShadingPoint {
        uv: [u, v],
        ..ShadingPoint::default()
    }
}

/// A footprint of `cells` cells along both axes.
fn wide(u: f64, v: f64, cells: f64) -> ShadingPoint {
    ShadingPoint {
        uv: [u, v],
        footprint: [[cells, 0.0], [0.0, cells]],
    }
}

/// With no tilt and no gap a cell is exactly one yarn family's look-up: a weft cell is bit for
/// bit the all-weft macro BRDF, a warp cell the all-warp one (`f`, `pdf` and draws); a tilt of
/// 10⁻⁹ rad departs from it by no more than rounding.
#[test]
fn no_tilt_and_no_gap_is_the_plain_cell() {
    let twill = || Ok(Pattern::from_name("twill-2/1").unwrap());
    let flat = material(twill(), 0.0, 0.0);
    let tiny_tilt = material(twill(), 1e-9f64.to_degrees(), 0.0);
    let all_weft = material(Err(1.0), 0.0, 0.0);
    let all_warp = material(Err(0.0), 0.0, 0.0);
    let mut rng = SplitMix(4);
    // Twill-2/1 rows: `..#`, `#..`, `.#.` — cell (0, 2) weft, cell (0, 0) warp.
    let (weft, warp) = (at(2.5, 0.5), at(0.3, 0.7));
    for _ in 0..200 {
        let (wi, wo) = (rng.direction(1.5), rng.direction(1.5));
        for (p, reference) in [(&weft, &all_weft), (&warp, &all_warp)] {
            let none = ShadingPoint::default();
            assert_eq!(flat.eval(wi, wo, p), reference.eval(wi, wo, &none));
            assert_eq!(flat.pdf(wi, wo, p), reference.pdf(wi, wo, &none));
            let (u1, u2) = (rng.uniform(), rng.uniform());
            let (a, b) = (
                flat.sample(wo, p, 0.5, [u1, u2]),
                reference.sample(wo, &none, 0.5, [u1, u2]),
            );
            assert_eq!(a.map(|s| (s.wi, s.pdf)), b.map(|s| (s.wi, s.pdf)));
            let (f, g) = (flat.eval(wi, wo, p).0[0], tiny_tilt.eval(wi, wo, p).0[0]);
            assert!((f - g).abs() <= 1e-6 * f.max(1e-6), "{f} vs {g}");
        }
    }
}

/// Along a float the yarn tilts from `+u_max` where it comes up to `−u_max` where it goes
/// under, so a fiber highlight moves along it: light and view in the weft's plane with a half
/// vector `α` from the normal toward `+u` light the point where the tilt is `−α`, i.e. at
/// `s = (1 + α/u_max)/2` of the float. A float of four weft cells ([[1,1,1,1,0]]), u_max = 30°.
#[test]
fn the_highlight_moves_along_the_float_as_the_tilt_predicts() {
    let pattern = Pattern::from_matrix(vec![vec![1, 1, 1, 1, 0]]).unwrap();
    let m = material(Ok(pattern), 30.0, 0.0);
    let dir = |theta_deg: f64| {
        let t = theta_deg.to_radians();
        Vec3::new(t.sin(), 0.0, t.cos())
    };
    let mut checked = 0;
    for (ti, to) in [(40.0, -20.0), (30.0, -30.0), (50.0, -45.0), (20.0, -45.0)] {
        let (wi, wo) = (dir(ti), dir(to));
        let h = (wi + wo).normalize();
        let alpha = h.x.atan2(h.z).to_degrees();
        let predicted = 0.5 * (1.0 + alpha / 30.0);
        // Scan the float (u in [0, 4) cells).
        let n = 400;
        let (best, _) = (0..n)
            .map(|k| {
                let s = (k as f64 + 0.5) / n as f64;
                (s, m.eval(wi, wo, &at(4.0 * s, 0.5)).0[0])
            })
            .fold((0.0, f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
        println!(
            "θi {ti}°, θo {to}°: α {alpha:.1}°, peak at s = {best:.3}, predicted {predicted:.3}"
        );
        assert!(
            (best - predicted).abs() < 0.06,
            "θi {ti}, θo {to}: peak at {best}, predicted {predicted}"
        );
        checked += 1;
    }
    assert_eq!(checked, 4);
    // Without the tilt the float is uniform.
    let flat = material(
        Ok(Pattern::from_matrix(vec![vec![1, 1, 1, 1, 0]]).unwrap()),
        0.0,
        0.0,
    );
    let (wi, wo) = (dir(40.0), dir(-20.0));
    assert_eq!(
        flat.eval(wi, wo, &at(0.3, 0.5)),
        flat.eval(wi, wo, &at(3.7, 0.5))
    );
}

/// Gaps: a yarn covers the middle `1 − gap` of its cell across its axis; in its gap the crossing
/// yarn shows, and where both leave a gap nothing does (black). Over a repeat of a 2/1 twill
/// (γ = 1/3) with gap 0.3, the mean BRDF is `A_weft f_weft + A_warp f_warp` with
/// `A_weft = (1 − g)(γ + g(1 − γ))`, `A_warp = (1 − g)(1 − γ + gγ)`: darker by `g²` and shifted
/// toward the minority family. A wide footprint gives the same mean; the material's sampled
/// `f` and density are its `eval` and `pdf`.
#[test]
fn gaps_show_the_crossing_yarn_and_darken_by_the_holes() {
    let twill = Pattern::from_name("twill-2/1").unwrap();
    let (g, gamma) = (0.3, 1.0 / 3.0);
    let gapped = material(Ok(twill.clone()), 0.0, g);
    let all_weft = material(Err(1.0), 0.0, 0.0);
    let all_warp = material(Err(0.0), 0.0, 0.0);
    let (a_weft, a_warp) = (
        (1.0 - g) * (gamma + g * (1.0 - gamma)),
        (1.0 - g) * (1.0 - gamma + g * gamma),
    );
    assert!((a_weft + a_warp + g * g - 1.0).abs() < 1e-12);
    let mut rng = SplitMix(8);
    let none = ShadingPoint::default();
    for _ in 0..30 {
        let (wi, wo) = (rng.direction(1.4), rng.direction(1.4));
        // 20 points a cell along each axis: the bands' edges fall between them.
        let n = 60;
        let mut mean = 0.0;
        for i in 0..n {
            for j in 0..n {
                let p = at((i as f64 + 0.5) / 20.0, (j as f64 + 0.5) / 20.0);
                mean += gapped.eval(wi, wo, &p).0[0] / (n * n) as f64;
            }
        }
        let want =
            a_weft * all_weft.eval(wi, wo, &none).0[0] + a_warp * all_warp.eval(wi, wo, &none).0[0];
        assert!((mean - want).abs() <= 1e-9 * want, "{mean} vs {want}");
        let far = gapped.eval(wi, wo, &wide(0.4, 0.7, 50.0)).0[0];
        assert!((far - want).abs() <= 1e-9 * want, "far {far} vs {want}");
    }
    // A hole (the corner of a cell) is black and draws nothing.
    let hole = at(0.05, 0.05);
    let (wi, wo) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.3, 0.0, 0.954));
    assert!(gapped.eval(wi, wo, &hole).is_black());
    assert!(gapped.sample(wo, &hole, 0.5, [0.3, 0.6]).is_none());
    assert_eq!(gapped.pdf(wi, wo, &hole), 0.0);
    // Without gaps the pattern's mean is the γ-mix: the holes' share is what darkens.
    let plain_mean = gamma * all_weft.eval(wi, wo, &none).0[0]
        + (1.0 - gamma) * all_warp.eval(wi, wo, &none).0[0];
    let gapped_mean =
        a_weft * all_weft.eval(wi, wo, &none).0[0] + a_warp * all_warp.eval(wi, wo, &none).0[0];
    println!("normal light, 17° view: mean f without gaps {plain_mean:.4}, with gap 0.3 {gapped_mean:.4}");
}

/// Tilted yarns far away: the macro BRDF (each family at tilts spread over ±u_max) is the mean
/// of the tilted cells over a repeat, within the tilt quadrature's error.
#[test]
fn the_macro_brdf_of_tilted_yarns_is_the_mean_of_the_cells() {
    let twill = Pattern::from_name("twill-2/1").unwrap();
    let m = material(Ok(twill), 12.0, 0.0);
    let mut rng = SplitMix(21);
    let mut worst: f64 = 0.0;
    for _ in 0..25 {
        let (wi, wo) = (rng.direction(1.2), rng.direction(1.2));
        let n = 120;
        let mut mean = 0.0;
        for i in 0..n {
            for j in 0..n {
                let p = at(
                    3.0 * (i as f64 + 0.5) / n as f64,
                    3.0 * (j as f64 + 0.5) / n as f64,
                );
                mean += m.eval(wi, wo, &p).0[0] / (n * n) as f64;
            }
        }
        let far = m.eval(wi, wo, &wide(0.2, 0.9, 50.0)).0[0];
        let err = (far - mean).abs() / mean.max(0.05);
        worst = worst.max(err);
        assert!(
            err < 0.03,
            "wi {wi:?} wo {wo:?}: macro {far} vs cells' mean {mean}"
        );
    }
    println!("tilted macro vs the cells' mean: worst relative difference {worst:.4}");
}

/// A point whose footprint is between half a cell and two cells mixes its cell's yarn with the
/// macro BRDF (with tilt and gaps): draws report `eval` and `pdf`, and the density is the one
/// sampled with: `E[f cos/pdf]` over draws equals `∫ f cos dω` by uniform sampling.
#[test]
fn blended_tilted_gapped_points_sample_with_their_density() {
    let twill = Pattern::from_name("twill-2/1").unwrap();
    let m = material(Ok(twill), 20.0, 0.2);
    let p = wide(1.55, 0.5, 1.1);
    let mut rng = SplitMix(33);
    let wo = Vec3::new(0.35, -0.2, 0.915).normalize();
    let n = 40_000;
    let (mut by_draws, mut by_draws_sq) = (0.0, 0.0);
    for _ in 0..n {
        let x = match m.sample(wo, &p, rng.uniform(), [rng.uniform(), rng.uniform()]) {
            Some(s) => {
                let f = m.eval(s.wi, wo, &p).0[0];
                assert!((s.f.0[0] - f).abs() <= 1e-12 * f.max(1e-12));
                let pdf = m.pdf(s.wi, wo, &p);
                assert!((s.pdf - pdf).abs() <= 1e-9 * pdf, "{} vs {pdf}", s.pdf);
                f * s.wi.z / s.pdf
            }
            None => 0.0,
        };
        by_draws += x / n as f64;
        by_draws_sq += x * x / n as f64;
    }
    let (mut uniform, mut uniform_sq) = (0.0, 0.0);
    let two_pi = 2.0 * std::f64::consts::PI;
    for _ in 0..n {
        let z: f64 = rng.uniform();
        let phi = two_pi * rng.uniform();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let wi = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        let x = m.eval(wi, wo, &p).0[0] * z * two_pi;
        uniform += x / n as f64;
        uniform_sq += x * x / n as f64;
    }
    let se = ((by_draws_sq - by_draws * by_draws) / n as f64
        + (uniform_sq - uniform * uniform) / n as f64)
        .sqrt();
    println!("albedo by draws {by_draws:.4}, by uniform directions {uniform:.4} (se {se:.4})");
    assert!(
        (by_draws - uniform).abs() < 4.5 * se,
        "{by_draws} vs {uniform} (se {se})"
    );
}

/// The denoiser's guide `warp_share` (the BSDF's at the point, seen from straight above): at the
/// yarn level each point lies on one family (0 or 1)
/// and a 2/1 twill's points are a third one family, two thirds the other; a macro BRDF of weft
/// fraction 0.7 is 0.3 warp everywhere.
#[test]
fn the_warp_share_tells_the_yarn_families_apart() {
    let twill = material(Ok(Pattern::from_name("twill-2/1").unwrap()), 0.0, 0.0);
    let share = |m: &WovenMaterial, uv: [f64; 2]| {
        m.bsdf(&at(uv[0], uv[1]), &mut BsdfScratch::default())
            .warp_share(Vec3::new(0.0, 0.0, 1.0))
    };
    // Over the pattern's repeat, 3 × 3 yarns (one a unit of uv).
    let n = 30;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let uv = [i, j].map(|k| 3.0 * (k as f64 + 0.5) / n as f64);
            let s = share(&twill, uv);
            assert!(s == 0.0 || s == 1.0, "share {s}");
            sum += s;
        }
    }
    let mean = sum / (n * n) as f64;
    assert!(
        (mean - 1.0 / 3.0).abs() < 0.02 || (mean - 2.0 / 3.0).abs() < 0.02,
        "mean share {mean}"
    );
    let macro_cloth = material(Err(0.7), 0.0, 0.0);
    for uv in [[0.1, 0.2], [0.55, 0.9]] {
        let s = share(&macro_cloth, uv);
        assert!((s - 0.3).abs() < 1e-12, "share {s}");
    }
}
