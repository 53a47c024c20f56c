//! Energy: in a white furnace no point of a woven surface reflects more than it receives, at
//! every level of detail, with and without tilt and gaps, for every preset (docs/model.md §8,
//! "Energy"); and the levels agree on average over the whole hemisphere of light and view
//! directions, not at one pair: fibres with yarns, a tilted float's points with the float.

use crate::common::Rng;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};
use woven::bsdf::{Bsdf, Transport};
use woven::color::Rgb;
use woven::material::{Material, Weave};
use woven::math::sampling::cosine_hemisphere;
use woven::surface::{Detail, SurfacePoint, SurfaceSpec, Tilt, WovenSurface};
use woven::table::{Table, TableOptions};
use woven::Vec3;

/// A small dyeable table of a preset's yarn alone, built once per preset.
pub fn yarn_table(name: &str) -> Arc<Table> {
    static TABLES: OnceLock<Mutex<HashMap<String, Arc<Table>>>> = OnceLock::new();
    let tables = TABLES.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(t) = tables.lock().unwrap().get(name) {
        return Arc::clone(t);
    }
    let m = Material::preset(name).unwrap().yarn_family();
    let options = TableOptions {
        n_theta: 6,
        n_phi: 4,
        n_h: 15,
        colour: true,
        ..TableOptions::default()
    };
    let t = Arc::new(Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap());
    tables
        .lock()
        .unwrap()
        .insert(name.to_string(), Arc::clone(&t));
    t
}

/// The white (0.999) dye of the furnace.
const WHITE: Rgb = Rgb([0.999; 3]);

/// A preset laid as `pattern` at 4 cells a unit, white, at a level of detail, tilt and gap.
pub fn white_surface(
    name: &str,
    pattern: &str,
    detail: Detail,
    u_max_deg: f64,
    gap: f64,
) -> WovenSurface {
    let mut material = Material::preset(name).unwrap();
    material.weave = Some(Weave::named(pattern).unwrap());
    let spec = SurfaceSpec {
        yarns_per_unit: [4.0, 4.0],
        weft_color: Some(WHITE),
        warp_color: Some(WHITE),
        u_max: u_max_deg.to_radians(),
        gap,
        detail,
        ..SurfaceSpec::new(material)
    };
    WovenSurface::new(&spec, yarn_table(name)).unwrap()
}

/// `∫ f(wi, wo) cos θi dωi` by an `n × n` stratified cosine-weighted grid (midpoints), the
/// largest channel.
fn furnace_by_quadrature(bsdf: &impl Bsdf<Value = Rgb>, wo: Vec3, n: usize) -> f64 {
    let mut sum = Rgb::BLACK;
    for j in 0..n {
        for k in 0..n {
            let wi = cosine_hemisphere((j as f64 + 0.5) / n as f64, (k as f64 + 0.5) / n as f64);
            sum += bsdf.eval(wi, wo);
        }
    }
    sum.max() * std::f64::consts::PI / (n * n) as f64
}

/// The same by the surface's own importance sampling (`wo` known, `wi` drawn), `n` draws, with
/// its standard error.
fn furnace_by_sampling(
    bsdf: &impl Bsdf<Value = Rgb>,
    wo: Vec3,
    n: usize,
    rng: &mut Rng,
) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let x = bsdf
            .sample(
                wo,
                rng.uniform(),
                [rng.uniform(), rng.uniform()],
                Transport::Radiance,
            )
            .map_or(0.0, |s| s.f.max() * s.wi.z / s.pdf);
        sum += x;
        sum2 += x * x;
    }
    let mean = sum / n as f64;
    let var = (sum2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt())
}

/// A direction with `θ` uniform in `cos θ` up to `max_deg`, any azimuth.
fn view(rng: &mut Rng, max_deg: f64) -> Vec3 {
    let c = 1.0 - rng.uniform() * (1.0 - max_deg.to_radians().cos());
    Vec3::from_spherical(c.acos(), rng.range(0.0, 2.0 * std::f64::consts::PI))
}

/// The configurations of the furnace: every level that shades points, with and without tilt
/// and gaps.
const CONFIGS: [(Detail, f64, f64); 5] = [
    (Detail::Fibers, 0.0, 0.0),
    (Detail::Fibers, 60.0, 0.3),
    (Detail::Yarns, 0.0, 0.0),
    (Detail::Yarns, 60.0, 0.3),
    (Detail::Yarns, 80.0, 0.5),
];

/// `cases` random points and views (up to 89°) per preset and configuration: the worst
/// furnace value by quadrature (48 × 48) and by sampling (1 000 draws, less 4.5 standard
/// errors: over 10⁴ cases a skewed estimate passes 3 now and then — one did, at 1.021 ± 0.006
/// where 4 · 10⁵ draws and a 400 × 400 quadrature agree on 0.9991).
fn worst_point_furnace(cases: usize, seed: u64) -> Vec<(String, f64, f64)> {
    let mut out = Vec::new();
    let mut rng = Rng(seed);
    for name in Material::preset_names().iter().copied() {
        for (detail, u_max, gap) in CONFIGS {
            let surface = white_surface(name, "satin-5", detail, u_max, gap);
            let (mut worst_q, mut worst_s) = (0.0f64, 0.0f64);
            for _ in 0..cases {
                let at = SurfacePoint {
                    uv: [rng.uniform(), rng.uniform()],
                    footprint: [[0.0; 2]; 2],
                };
                let bsdf = surface.at(&at);
                let wo = view(&mut rng, 89.0);
                worst_q = worst_q.max(furnace_by_quadrature(&bsdf, wo, 48));
                let (m, se) = furnace_by_sampling(&bsdf, wo, 1000, &mut rng);
                worst_s = worst_s.max(m - 4.5 * se);
            }
            let what = format!("{name} {detail:?} u_max {u_max}° gap {gap}");
            eprintln!("furnace: {what}: worst quadrature {worst_q:.4}, sampling {worst_s:.4}");
            out.push((what, worst_q, worst_s));
        }
    }
    out
}

/// Point by point, a white surface reflects at most what it receives, for a fixed viewer:
/// `∫ f cos θi dωi ≤ 1` by quadrature (within its error, 2 %) and by importance sampling.
#[test]
fn no_point_reflects_more_than_it_receives() {
    for (what, q, s) in worst_point_furnace(30, 2024) {
        assert!(q <= 1.02, "{what}: furnace by quadrature {q}");
        assert!(s <= 1.0, "{what}: furnace by sampling {s}");
    }
}

/// The same over 10⁴ random cases in all (500 per preset and configuration).
#[test]
#[ignore = "exhaustive: about a minute"]
fn no_point_reflects_more_than_it_receives_exhaustive() {
    for (what, q, s) in worst_point_furnace(500, 77) {
        assert!(q <= 1.02, "{what}: furnace by quadrature {q}");
        assert!(s <= 1.0, "{what}: furnace by sampling {s}");
    }
}

/// A weft-only weave (every cell the weft) of a preset at one cell a unit, at `detail`, in the
/// material's own colour, on the shared table.
pub fn weft_only(name: &str, detail: Detail) -> WovenSurface {
    WovenSurface::new(&weft_only_spec(name, detail), yarn_table(name)).unwrap()
}

/// The layout of [`weft_only`].
fn weft_only_spec(name: &str, detail: Detail) -> SurfaceSpec {
    let mut material = Material::preset(name).unwrap();
    material.weave = Some(Weave::Pattern {
        spec: woven::material::PatternSpec::Matrix(vec![vec![1]]),
        pattern: woven::weave::Pattern::from_matrix(vec![vec![1]]).unwrap(),
    });
    // The yarn alone: no gaps between, nothing through.
    material.openness = woven::material::Openness::default();
    // One cell per unit of uv; undyed: the exact yarn it is held to has the material's own
    // albedos.
    SurfaceSpec {
        yarns_per_unit: [1.0, 1.0],
        detail,
        relief: true,
        weft_color: None,
        warp_color: None,
        ..SurfaceSpec::new(material)
    }
}

/// The resolved yarn level of [`weft_only`]`(name)` from the exact yarn, not a table: at each
/// point the yarn the viewer's ray meets on the relief, its BRDF in the frame leaning there
/// times its incident cosine over the cloth's, where the relief lets the light in.
pub struct ExactResolved {
    surface: WovenSurface,
    relief: woven::relief::Relief,
    yarn: woven::Model,
}

impl ExactResolved {
    pub fn new(name: &str) -> ExactResolved {
        let spec = weft_only_spec(name, Detail::Auto);
        ExactResolved {
            relief: spec
                .relief_geometry()
                .expect("a weft-only weave has a relief"),
            surface: WovenSurface::new(&spec, yarn_table(name)).unwrap(),
            yarn: crate::surface::exact_yarn(name),
        }
    }

    /// The value at `at` for the light `s` and the viewer `v`.
    pub fn eval(&self, at: &SurfacePoint, s: Vec3, v: Vec3) -> f64 {
        let mix = self.surface.at(at).mix_seen_from(v).into_owned();
        mix.lobes()
            .iter()
            .map(|lobe| match lobe.tilt {
                woven::surface::Tilt::Relief { lean, at } => {
                    assert!(!lobe.warp, "a weft-only weave");
                    let (ts, tv) = (lean.into_frame(s), lean.into_frame(v));
                    if ts.z <= 0.0 || tv.z <= 0.0 || !self.relief.sees(at, s) {
                        return 0.0;
                    }
                    lobe.weight * self.yarn.eval(ts, tv) * ts.z / s.z
                }
                other => panic!("a resolved point without a footprint: {other:?}"),
            })
            .sum()
    }
}

/// The fibre level's mean over `yarns` picks × `across` points across each (green channel),
/// with its standard error over the picks; pick `y`'s points at `(k + offset(y)) / across`.
pub fn fibre_mean(
    surface: &WovenSurface,
    (s, v): (Vec3, Vec3),
    (yarns, across): (usize, usize),
    offset: impl Fn(usize) -> f64,
) -> (f64, f64) {
    points_mean(|at| surface.at(at).eval(s, v).0[1], (yarns, across), offset)
}

/// [`fibre_mean`] of any value at the points.
pub fn points_mean(
    value: impl Fn(&SurfacePoint) -> f64,
    (yarns, across): (usize, usize),
    offset: impl Fn(usize) -> f64,
) -> (f64, f64) {
    let means: Vec<f64> = (0..yarns)
        .map(|y| {
            let offset = offset(y);
            (0..across)
                .map(|k| {
                    let at = SurfacePoint {
                        uv: [0.37, y as f64 + (k as f64 + offset) / across as f64],
                        footprint: [[0.0; 2]; 2],
                    };
                    value(&at)
                })
                .sum::<f64>()
                / across as f64
        })
        .collect();
    let mean = means.iter().sum::<f64>() / yarns as f64;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (yarns - 1) as f64;
    (mean, (var / yarns as f64).sqrt())
}

/// Over `pairs` random pairs of light and view (each up to `max_deg`), per preset: the fibre
/// level's mean over many yarns against the resolved yarn level at the same points (the exact
/// yarn's BRDF leaning with the relief: [`ExactResolved`]); returns the worst deviation in
/// standard errors and relative to the value, per preset.
fn fibre_identity(pairs: usize, max_deg: f64, seed: u64) -> Vec<(String, f64, f64)> {
    use rayon::prelude::*;
    let mut rng = Rng(seed);
    let mut out = Vec::new();
    // The opaque presets: an open one's yarn is an ordinary spun yarn, and the default run's
    // longest test need not take a ninth more for it (its gaps: sheer.rs, gaps.rs).
    let open = Material::open_preset_names();
    for name in Material::all_preset_names()
        .into_iter()
        .filter(|n| !open.contains(n))
    {
        let surface = weft_only(name, Detail::Fibers);
        let resolved = ExactResolved::new(name);
        let (mut worst_z, mut worst_rel) = (0.0f64, 0.0f64);
        let drawn: Vec<(Vec3, Vec3)> = (0..pairs)
            .map(|_| (view(&mut rng, max_deg), view(&mut rng, max_deg)))
            .collect();
        // The pairs in parallel (this is the default run's longest test), drawn in order above.
        let means: Vec<_> = drawn
            .par_iter()
            .map(|&(s, v)| {
                // Each pick's points shifted by its own random offset: stratified, and unbiased
                // over picks where a fixed midpoint rule would miss narrow lit bands (a hash,
                // not the golden-ratio steps the picks' slopes are drawn with, which it would
                // follow).
                let offset = |y: usize| woven::yarn::point::hash_uniform(y as u64, 0xA11CE);
                let (mean, se) = fibre_mean(&surface, (s, v), (1000, 32), offset);
                // The exact yarn costs ~25 µs a look-up and varies smoothly across the yarn: 8
                // points a pick serve.
                let (want, _) = points_mean(|at| resolved.eval(at, s, v), (1000, 8), offset);
                (mean, se, want)
            })
            .collect();
        for (&(s, v), &(mean, se, want)) in drawn.iter().zip(&means) {
            // Yarns differ (each draws its slope): the level is the fibres', not the table's.
            // (The shot silk's slopes spread by 3e-9 rad: its yarns differ by their twist.)
            assert!(
                se > 1e-4 * want || want < 1e-9,
                "{name} s {s:?} v {v:?}: no spread between yarns ({se} of {want})"
            );
            // 0.5 %: the midpoint rules across a pick, 32 points for the fibres, 8 for the
            // reference (the shot silk, whose yarns hardly differ, is 1.1 % apart at one pair).
            let z = (mean - want).abs() / (se + 5e-3 * want + 1e-9);
            assert!(
                z <= 4.0,
                "{name} s {s:?} v {v:?}: fibres {mean} ± {se} vs yarn {want}"
            );
            worst_z = worst_z.max((mean - want).abs() / se.max(1e-12));
            worst_rel = worst_rel.max((mean - want).abs() / want.max(1e-12));
        }
        eprintln!(
            "identity: {name}: fibres vs yarn over {pairs} pairs to {max_deg}°: worst {worst_z:.2} \
             standard errors, {:.2} % of the value",
            100.0 * worst_rel
        );
        out.push((name.to_string(), worst_z, worst_rel));
    }
    out
}

/// The fibre level averages to the yarn level over the whole hemisphere (8 random pairs up to
/// 85° per preset, the grounded presets too), not at one pair. (The shot silk's slopes, spread
/// by 3e-9 rad, were once drawn from bins 8e-4 rad wide that missed their density: 15 % off.)
#[test]
fn fibres_average_to_yarns_over_the_hemisphere() {
    fibre_identity(8, 85.0, 5);
}

/// The macro BRDF of `surface` (not resolving its relief) at `(s, v)`, the weft's first
/// channel, with each whole float's mean taken from the yarn's table
/// ([`FloatProfile::average`](woven::yarn::float::FloatProfile::average): 8 look-ups a float,
/// 16 for both families), not from the float's own table: what that table tabulates.
pub fn macro_by_float_means(surface: &WovenSurface, s: Vec3, v: Vec3) -> f64 {
    let (table, float) = (surface.table(), surface.float_profile());
    let turn = |d: Vec3| Vec3::new(d.y, -d.x, d.z);
    let mut f = 0.0;
    for lobe in surface.macro_lobes().lobes() {
        let albedos = [surface.albedos(lobe.warp)[0]];
        let (a, b) = if lobe.warp {
            (turn(s), turn(v))
        } else {
            (s, v)
        };
        let value = |a: Vec3, b: Vec3| table.eval_dyed(a, b, &albedos)[0];
        f += lobe.weight
            * match lobe.tilt {
                Tilt::Flat => value(a, b),
                Tilt::Float => float.average(a, b, value),
                other => panic!("a macro lobe is flat or a whole float, not {other:?}"),
            };
    }
    f
}

/// Over `pairs` random pairs (up to `max_deg`) per preset, tilt and gap: a tilted surface's
/// points at yarn level, averaged over its pattern (a stratified `n × n` grid of one repeat),
/// against its macro BRDF with each float's mean taken from the yarn's table
/// ([`macro_by_float_means`]); the worst relative deviation. With `tables`, also how far the
/// macro BRDF the surface renders (`detail = "cloth"`, whole floats read from their own tables,
/// [`Table::tilted`]) is from that mean, the tilted tables' interpolation error: held within 2 %
/// of the largest `f cos θs cos θv` over the pairs where it counts (measured ≤ 1.36 %, the
/// sateen at 60°; relative to `f` alone it reaches 45 % at grazing pairs of small value, which
/// are printed). Building those tables is most of the cost: the exhaustive run alone does.
fn tilt_identity(pairs: usize, max_deg: f64, n: usize, seed: u64, tables: bool) -> f64 {
    let mut rng = Rng(seed);
    let mut worst = 0.0f64;
    for name in Material::preset_names().iter().copied() {
        for (u_max, gap) in [(30.0, 0.0), (60.0, 0.3), (80.0, 0.5)] {
            let points = white_surface(name, "satin-5", Detail::Yarns, u_max, gap);
            let whole = white_surface(name, "satin-5", Detail::Cloth, u_max, gap);
            let (mut worst_here, mut table_worst) = (0.0f64, 0.0f64);
            // The tilted table's errors weighted by the cosines, and the largest f cos cos.
            let (mut table_weighted, mut peak) = (0.0f64, 0.0f64);
            for _ in 0..pairs {
                let (s, v) = (view(&mut rng, max_deg), view(&mut rng, max_deg));
                // One repeat of satin-5 at 4 cells a unit: 5/4 of a unit each way.
                let mut sum = 0.0;
                for j in 0..n {
                    for k in 0..n {
                        let at = SurfacePoint {
                            uv: [
                                1.25 * (j as f64 + 0.5) / n as f64,
                                1.25 * (k as f64 + 0.5) / n as f64,
                            ],
                            footprint: [[0.0; 2]; 2],
                        };
                        sum += points.at(&at).eval(s, v).0[1];
                    }
                }
                let mean = sum / (n * n) as f64;
                let want = macro_by_float_means(&whole, s, v);
                let rel = (mean - want).abs() / want.max(1e-3);
                assert!(
                    rel <= 0.03,
                    "{name} u_max {u_max}° gap {gap} s {s:?} v {v:?}: points {mean} vs float {want}"
                );
                worst_here = worst_here.max(rel);
                if tables {
                    let tabulated = whole.at(&SurfacePoint::default()).eval(s, v).0[1];
                    table_worst = table_worst.max((tabulated - want).abs() / want.max(1e-3));
                    table_weighted = table_weighted.max((tabulated - want).abs() * s.z * v.z);
                    peak = peak.max(want * s.z * v.z);
                }
            }
            let table_note = if tables {
                let weighted = table_weighted / peak;
                assert!(
                    weighted <= 0.02,
                    "{name} u_max {u_max}° gap {gap}: the float's table is off its mean by \
                     {:.2} % of the peak of f cos θs cos θv",
                    100.0 * weighted
                );
                format!(
                    " (the float's table against its mean: worst {:.2} %, {:.2} % of the peak \
                     of f cos θs cos θv)",
                    100.0 * table_worst,
                    100.0 * weighted
                )
            } else {
                String::new()
            };
            eprintln!(
                "identity: {name} u_max {u_max}° gap {gap}: points vs float over {pairs} pairs to \
                 {max_deg}°: worst {:.2} %{table_note}",
                100.0 * worst_here,
            );
            worst = worst.max(worst_here);
        }
    }
    worst
}

/// A tilted float's points average to the float's macro BRDF over the whole hemisphere.
#[test]
fn tilted_points_average_to_their_float_over_the_hemisphere() {
    tilt_identity(8, 85.0, 200, 9, false);
}

/// The same over 60 pairs per preset and tilt, up to 89°, with the float tables' error.
#[test]
#[ignore = "exhaustive: about five minutes"]
fn tilted_points_average_to_their_float_over_the_hemisphere_exhaustive() {
    tilt_identity(60, 89.0, 300, 99, true);
}
