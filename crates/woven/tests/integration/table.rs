//! Tabulated BRDFs: sampling against the density (χ²), densities that integrate to the accepted
//! fraction, weights consistent with `eval`, determinism, the file format's errors, and accuracy
//! against the exact model (STYLE.md's canon; issue "fast evaluation and importance sampling").

use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;
use woven::bsdf::Bsdf;
use woven::bsdf::Transport::Importance;
use woven::material::Material;
use woven::math::quadrature::GaussLegendre;
use woven::table::report::SplitMix;
use woven::table::{Table, TableOptions};
use woven::{Model, Vec3};

/// Small grids keep the tests fast; accuracy at the default grid is the ignored test below.
fn small() -> TableOptions {
    TableOptions {
        n_theta: 16,
        n_phi: 5,
        n_h: 33,
        n_h_isotropic: 49,
        azimuth_nodes: 48,
        ..TableOptions::default()
    }
}

fn material(name: &str) -> Material {
    crate::common::table_material(name)
}

/// One small table per material, built once per test binary.
fn table(name: &str) -> &'static (Model, Table) {
    type Cache = std::sync::Mutex<Vec<(String, &'static (Model, Table))>>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    if let Some((_, t)) = cache.lock().unwrap().iter().find(|(n, _)| n == name) {
        return t;
    }
    let m = material(name);
    let model = m.build(550.0).unwrap();
    let t = Table::build(&model, &m, &small(), &|_, _| {}).unwrap();
    let leaked: &'static (Model, Table) = Box::leak(Box::new((model, t)));
    cache.lock().unwrap().push((name.to_string(), leaked));
    leaked
}

/// χ² goodness of fit of `sample` against `pdf` on a (cos θ, φ) histogram, cells with expected
/// counts below 5 pooled (pbrt's and Mitsuba's test). Returns (p-value, accepted fraction, ∫pdf).
fn chi2(t: &Table, s: Vec3, n: usize, seed: u64) -> (f64, f64, f64) {
    chi2_of(
        |rng| {
            t.sample(s, 0.5, [rng.uniform(), rng.uniform()], Importance)
                .map(|smp| smp.wo)
        },
        |d| t.pdf_direction(s, d),
        n,
        seed,
    )
}

/// [`chi2`] of any sampler: `sample` draws a direction (or fails) with uniforms from the given
/// generator, `pdf` is the density it claims.
pub fn chi2_of(
    sample: impl FnMut(&mut SplitMix) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    n: usize,
    seed: u64,
) -> (f64, f64, f64) {
    chi2_with(sample, pdf, n, seed, 4, 0.0)
}

/// [`chi2_of`] over the whole sphere (`cos θ` in `[−1, 1]`): a BSDF that also transmits.
pub fn chi2_of_sphere(
    sample: impl FnMut(&mut SplitMix) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    n: usize,
    seed: u64,
) -> (f64, f64, f64) {
    chi2_with(sample, pdf, n, seed, 4, -1.0)
}

/// [`chi2_of`] for a density that is smooth within a cell (an analytic lobe, not a table's
/// bilinear pieces): its cells are first integrated on 2×2 sub-cells, a quarter of the cost.
pub fn chi2_of_smooth(
    sample: impl FnMut(&mut SplitMix) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    n: usize,
    seed: u64,
) -> (f64, f64, f64) {
    chi2_with(sample, pdf, n, seed, 2, 0.0)
}

/// [`chi2_of`] with each cell first integrated on `base × base` sub-cells, `cos θ` binned over
/// `[lowest, 1]`.
fn chi2_with(
    mut sample: impl FnMut(&mut SplitMix) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    n: usize,
    seed: u64,
    base: usize,
    lowest: f64,
) -> (f64, f64, f64) {
    let span = 1.0 - lowest;
    let (nc, np) = (16usize, 32usize);
    let mut observed = vec![0f64; nc * np];
    let mut rng = SplitMix(seed);
    let mut accepted = 0usize;
    for _ in 0..n {
        if let Some(d) = sample(&mut rng) {
            accepted += 1;
            let (ct, phi) = (d.z, d.y.atan2(d.x).rem_euclid(2.0 * PI));
            let i = (((ct - lowest) / span * nc as f64).max(0.0) as usize).min(nc - 1);
            let j = ((phi / (2.0 * PI) * np as f64) as usize).min(np - 1);
            observed[i * np + j] += 1.0;
        }
    }
    // Expected counts: ∫ pdf over each cell (dω = d cos θ dφ), 8×8 Gauss–Legendre on `base`²
    // sub-cells. A cell holding more than 0.5 % of the mass is integrated again on (2 base)²
    // sub-cells, and where the two differ by more than 1e-4 of that (a smooth fiber's
    // needle-like density) on 32×32, so quadrature error stays below sampling noise (a cell of
    // 0.5 % of 10⁵ draws has a noise of 1.4 %). Most cells of a smooth lobe stop at (2 base)².
    let gl = GaussLegendre::new(8);
    let cell_integral = |i: usize, j: usize, sub: usize| {
        let mut e = 0.0;
        for a in 0..sub {
            for b in 0..sub {
                let c0 = lowest + (i as f64 + a as f64 / sub as f64) / nc as f64 * span;
                let p0 = (j as f64 + b as f64 / sub as f64) / np as f64 * 2.0 * PI;
                e += gl.integrate(c0, c0 + span / (sub * nc) as f64, |ct| {
                    gl.integrate(p0, p0 + 2.0 * PI / (sub * np) as f64, |phi| {
                        let st = (1.0 - ct * ct).max(0.0).sqrt();
                        pdf(Vec3::new(st * phi.cos(), st * phi.sin(), ct))
                    })
                });
            }
        }
        e
    };
    let mut expected = vec![0f64; nc * np];
    for i in 0..nc {
        for j in 0..np {
            let mut e = cell_integral(i, j, base);
            if e > 0.005 {
                let finer = cell_integral(i, j, 2 * base);
                e = if (finer - e).abs() > 1e-4 * finer {
                    cell_integral(i, j, 32)
                } else {
                    finer
                };
            }
            expected[i * np + j] = e * n as f64;
        }
    }
    let integral: f64 = expected.iter().sum::<f64>() / n as f64;
    // Pool cells with expected < 5 into one.
    let (mut stat, mut dof) = (0.0, 0usize);
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (o, e) in observed.iter().zip(&expected) {
        if *e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            stat += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pool_e > 0.0 {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e.max(1.0);
        dof += 1;
    }
    let p = 1.0 - ChiSquared::new((dof - 1) as f64).unwrap().cdf(stat);
    if std::env::var("CHI2_DEBUG").is_ok() {
        let mut worst: Vec<(f64, usize)> = observed
            .iter()
            .zip(&expected)
            .enumerate()
            .filter(|(_, (_, e))| **e >= 5.0)
            .map(|(k, (o, e))| ((o - e) * (o - e) / e, k))
            .collect();
        worst.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (c, k) in worst.iter().take(6) {
            eprintln!(
                "cell {k} (cos {}, phi {}): o {} e {:.1} contrib {c:.1}",
                k / np,
                k % np,
                observed[*k],
                expected[*k]
            );
        }
        eprintln!("stat {stat:.1} dof {dof} pooled o {pool_o} e {pool_e:.1}");
    }
    (p, accepted as f64 / n as f64, integral)
}

const MATERIALS: [&str; 5] = ["rough", "smooth", "polyester-sateen", "belt-cloth", "silk"];
const INCIDENCES_DEG: [(f64, f64); 3] = [(10.0, 20.0), (45.0, 60.0), (70.0, 135.0)];

#[test]
fn sampling_passes_chi_square_for_every_preset_and_incidence() {
    // 5 materials × 3 incidences: Šidák-corrected significance 1 % overall.
    let tests = (MATERIALS.len() * INCIDENCES_DEG.len()) as f64;
    let alpha = 1.0 - (1.0f64 - 0.01).powf(1.0 / tests);
    for name in MATERIALS {
        let (_, t) = table(name);
        for (k, (ti, pi)) in INCIDENCES_DEG.iter().enumerate() {
            let s = Vec3::from_spherical(ti.to_radians(), pi.to_radians());
            let (p, accepted, integral) = chi2(t, s, 200_000, 17 + k as u64);
            assert!(
                p > alpha,
                "{name} at θi {ti}°, φi {pi}°: χ² p-value {p:.2e} < {alpha:.2e}"
            );
            // ∫ pdf over the hemisphere is the accepted fraction (the rest maps below the horizon);
            // the quadrature of the smooth fiber's needle-like density is good to ~1 %.
            let tol = if name == "smooth" { 0.02 } else { 0.01 };
            assert!(
                (integral - accepted).abs() < tol,
                "{name} θi {ti}°: ∫pdf {integral:.4} vs accepted fraction {accepted:.4}"
            );
        }
    }
}

#[test]
fn pdf_integrates_to_one_away_from_grazing() {
    // Lost mass (cells a neighbouring node maps below the horizon) is small for θi ≤ 60°.
    let gl = GaussLegendre::new(24);
    for name in ["rough", "polyester-sateen", "silk"] {
        let (_, t) = table(name);
        for ti in [0.0f64, 30.0, 60.0] {
            let s = Vec3::from_spherical(ti.to_radians(), 0.4);
            // ∫ pdf dω on 48 × 96 panels in (cos θ, φ).
            let mut total = 0.0;
            for a in 0..48 {
                let c0 = a as f64 / 48.0;
                for b in 0..96 {
                    let p0 = b as f64 / 96.0 * 2.0 * PI;
                    total += gl.integrate(c0, c0 + 1.0 / 48.0, |ct| {
                        gl.integrate(p0, p0 + 2.0 * PI / 96.0, |phi| {
                            let st = (1.0 - ct * ct).max(0.0).sqrt();
                            t.pdf_direction(s, Vec3::new(st * phi.cos(), st * phi.sin(), ct))
                        })
                    });
                }
            }
            assert!(
                total > 0.97 && total < 1.0 + 5e-3,
                "{name} θi {ti}°: ∫ pdf dω = {total}"
            );
        }
    }
}

#[test]
fn sample_weight_and_pdf_agree_with_eval_and_are_deterministic() {
    let mut rng = SplitMix(99);
    for name in MATERIALS {
        let (_, t) = table(name);
        for _ in 0..2000 {
            let s = rng.direction(85f64.to_radians());
            let (u1, u2) = (rng.uniform(), rng.uniform());
            let Some(a) = t.sample(s, 0.5, [u1, u2], Importance) else {
                continue;
            };
            let b = t.sample(s, 0.5, [u1, u2], Importance).unwrap();
            assert_eq!(a, b, "{name}: sampling is not deterministic");
            assert!(a.wo.z > 0.0 && (a.wo.length() - 1.0).abs() < 1e-12 && a.wi == s);
            let f = t.eval(s, a.wo);
            let pdf = t.pdf(s, a.wo, Importance);
            assert!(
                (a.f - f).abs() <= 1e-9 * f.max(1e-300),
                "{name}: f {} vs eval {f}",
                a.f
            );
            // The same density up to rounding in re-deriving the cell from v.
            assert!(
                (a.pdf - pdf).abs() <= 1e-5 * pdf,
                "{name}: pdf {} vs pdf() {pdf}",
                a.pdf
            );
            let w = f * a.wo.z / pdf;
            assert!(
                (a.weight(Importance) - w).abs() <= 1e-5 * w.max(1e-300),
                "{name}: weight {} vs {w}",
                a.weight(Importance)
            );
        }
    }
}

#[test]
fn exact_model_sampling_is_consistent() {
    let model = material("rough").build(550.0).unwrap();
    let mut rng = SplitMix(5);
    for _ in 0..500 {
        let s = rng.direction(1.4);
        let smp = Bsdf::sample(&model, s, 0.5, [rng.uniform(), rng.uniform()], Importance).unwrap();
        assert!((smp.pdf - Bsdf::pdf(&model, s, smp.wo, Importance)).abs() < 1e-12);
        assert!((smp.f - model.eval(s, smp.wo)).abs() < 1e-12);
    }
}

#[test]
fn table_matches_the_exact_model_on_small_grids() {
    // The rough flat fiber is smooth enough for the small test grid; the presets' figures at the
    // default grid are the ignored test below.
    let (model, t) = table("rough");
    let r = t.accuracy(model, 1500, 3, &|_, _| {});
    assert!(r.bands[0].weighted_rel_rms < 0.02, "rough: {r:?}");
}

#[test]
fn table_files_round_trip_and_reject_damage() {
    let (_, t) = table("polyester-sateen");
    let bytes = t.to_bytes();
    let back = Table::from_bytes(&bytes, "mem").unwrap();
    assert_eq!(back.values(), t.values());
    assert_eq!(back.to_bytes(), bytes);
    let s = Vec3::from_spherical(0.5, 0.2);
    let v = Vec3::from_spherical(0.6, 2.9);
    assert_eq!(back.eval(s, v), t.eval(s, v));
    assert_eq!(back.pdf_direction(s, v), t.pdf_direction(s, v));
    // Truncations anywhere, a flipped byte, a wrong version, trailing bytes: errors, no panic.
    for cut in [
        0,
        4,
        8,
        15,
        40,
        bytes.len() / 2,
        bytes.len() - 5,
        bytes.len() - 1,
    ] {
        let e = Table::from_bytes(&bytes[..cut], "cut")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cut") && e.contains("not a valid woven table"),
            "{cut}: {e}"
        );
    }
    let mut flipped = bytes.clone();
    let k = bytes.len() / 3;
    flipped[k] ^= 0x10;
    assert!(Table::from_bytes(&flipped, "f")
        .unwrap_err()
        .to_string()
        .contains("checksum"));
    let mut version = bytes.clone();
    version[8] = 9;
    assert!(Table::from_bytes(&version, "v")
        .unwrap_err()
        .to_string()
        .contains("version 9"));
    let mut trailing = bytes.clone();
    trailing.push(0);
    assert!(Table::from_bytes(&trailing, "t")
        .unwrap_err()
        .to_string()
        .contains("trailing"));
    assert!(Table::from_bytes(b"hello world, not a table", "h").is_err());
    // Saving is atomic: the file appears complete, and no temporary is left behind.
    let dir = std::env::temp_dir().join(format!("woven-table-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("sateen.wtab");
    t.save(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), bytes);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    let loaded = Table::load(&path).unwrap();
    assert_eq!(loaded.values(), t.values());
    assert!(matches!(
        Table::load(dir.join("missing.wtab")),
        Err(woven::Error::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tables_fold_symmetric_directions_onto_one_another() {
    // Mirror symmetry x → −x, y → −y (every woven preset) and rotation (isotropic).
    let mut rng = SplitMix(8);
    let (_, sateen) = table("polyester-sateen");
    let (_, silk) = table("silk");
    for _ in 0..200 {
        let s = rng.direction(1.3);
        let v = rng.direction(1.3);
        let m = |d: Vec3| Vec3::new(-d.x, d.y, d.z);
        assert!(
            (sateen.eval(s, v) - sateen.eval(m(s), m(v))).abs()
                <= 1e-9 * sateen.eval(s, v).max(1e-9)
        );
        let r = |d: Vec3| {
            let (c, sn) = (0.7f64.cos(), 0.7f64.sin());
            Vec3::new(c * d.x - sn * d.y, sn * d.x + c * d.y, d.z)
        };
        assert!(
            (silk.eval(s, v) - silk.eval(r(s), r(v))).abs() <= 1e-6 * silk.eval(s, v).max(1e-9)
        );
    }
    let _ = FRAC_PI_2;
}

/// What a default-grid table must achieve, band by band of `θ = max(θ_i, θ_r)`: the largest
/// cosine-weighted relative RMS error and 99th percentile up to 80° and in 80°–89°, the largest
/// `|f_table − f| cos θ_i cos θ_r` relative to the material's peak of `f cos θ_i cos θ_r` up to
/// 89° and in the last degree, and the largest sampling weight `f cos θ_r / pdf` relative to its
/// median at incidences up to 89.9°.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    bulk: (f64, f64),
    grazing: (f64, f64),
    peak_rel: f64,
    peak_rel_last_degree: f64,
    weight_spread: f64,
}

/// The targets of the issue "tables right to the horizon": ≤ 1 % and ≤ 3 % up to 80°, ≤ 2 % and
/// ≤ 10 % in 80°–89°, 1 % of the peak over the test's pairs (seed 11; the true bound over 10⁶
/// random pairs is up to 2.05 % for the sateen: `examples/table_peak_bound`, docs/model.md §6),
/// weights within 10× their median.
const TARGETS: Bounds = Bounds {
    bulk: (0.01, 0.03),
    grazing: (0.02, 0.10),
    peak_rel: 0.01,
    peak_rel_last_degree: 0.01,
    weight_spread: 10.0,
};

/// The bounds each material is held to: the targets. (Before the exact regions
/// `FORWARD_EXACT` and `GRAZING_HALF_EXACT`, the sateens missed them where light and view run
/// opposite each other at grazing angles: 80°–89° RMS 2.1 % and 8.2 %, up to 15 % and 19 % of the
/// peak in the last degree; and the smooth sateen's sampling weights reached 12× their median at
/// θi 89.5°.)
fn bounds(_name: &str) -> Bounds {
    TARGETS
}

/// Checks a default-grid table against [`bounds`], printing every figure.
fn assert_bounds(name: &str, model: &Model, t: &Table, per_band: usize) {
    let b = bounds(name);
    let r = t.accuracy(model, per_band, 11, &|_, _| {});
    println!("{name}: peak {:.4}", r.peak);
    for band in &r.bands {
        println!(
            "  [{}°, {}°]: rms {:.3} % p99 {:.3} % max {:.2} % peak-rel {:.3} %",
            band.lo_deg,
            band.hi_deg,
            100.0 * band.weighted_rel_rms,
            100.0 * band.p99_rel,
            100.0 * band.max_rel,
            100.0 * band.max_peak_rel
        );
    }
    let spread = sampling_weight_spread(t, 4000);
    println!("  sampling: largest weight / median weight {spread:.2}");
    let (bulk, grazing) = (r.bands[0], r.bands[1]);
    assert!(
        bulk.weighted_rel_rms <= b.bulk.0 && bulk.p99_rel <= b.bulk.1,
        "{name}: {bulk:?} against {b:?}"
    );
    assert!(
        grazing.weighted_rel_rms <= b.grazing.0 && grazing.p99_rel <= b.grazing.1,
        "{name}: {grazing:?} against {b:?}"
    );
    assert!(
        r.bands[..2]
            .iter()
            .all(|band| band.max_peak_rel <= b.peak_rel)
            && r.bands[2].max_peak_rel <= b.peak_rel_last_degree,
        "{name}: {r:?} against {b:?}"
    );
    assert!(
        spread <= b.weight_spread,
        "{name}: a sampling weight {spread:.1}× its median"
    );
}

/// The largest ratio, over incidences from normal to 89.9° (10 polar angles × 5 azimuths), of
/// the largest sampling weight `f cos θ_r / pdf` to the median weight, `n` draws each.
fn sampling_weight_spread(t: &Table, n: usize) -> f64 {
    let mut rng = SplitMix(23);
    let mut worst = 0.0f64;
    for ti in [0.0f64, 20.0, 45.0, 65.0, 80.0, 85.0, 88.0, 89.0, 89.5, 89.9] {
        for pi in [0.0f64, 20.0, 45.0, 70.0, 90.0] {
            let s = Vec3::from_spherical(ti.to_radians(), pi.to_radians());
            let mut w: Vec<f64> = (0..n)
                .filter_map(|_| t.sample(s, 0.5, [rng.uniform(), rng.uniform()], Importance))
                .map(|smp| smp.weight(Importance))
                .collect();
            if w.is_empty() {
                continue;
            }
            w.sort_by(f64::total_cmp);
            let ratio = w[w.len() - 1] / w[w.len() / 2];
            if ratio > worst {
                println!("  θi {ti}° φi {pi}°: max/median weight {ratio:.2}");
            }
            worst = worst.max(ratio);
        }
    }
    worst
}

/// [`assert_bounds`] for every preset, a rough and a very smooth flat fiber, and the sateen at the
/// smooth fiber's roughness 0.02 (which gets [`TableOptions::for_model`]'s finer half-vector grid).
/// Builds full tables (tens of seconds each):
/// `cargo test --release -p woven --test integration table_accuracy_at_default_grid -- --ignored --nocapture`
/// (`WOVEN_TABLE_MATERIALS=silk,belt-cloth` checks only those).
#[test]
#[ignore = "slow: builds full-resolution tables"]
fn table_accuracy_at_default_grid() {
    let only = std::env::var("WOVEN_TABLE_MATERIALS").ok();
    for name in MATERIALS.iter().copied().chain(["smooth-sateen"]) {
        if only
            .as_ref()
            .is_some_and(|o| !o.split(',').any(|x| x == name))
        {
            continue;
        }
        let (model, t) = crate::common::default_table(name);
        let n = if name == "belt-cloth" || name == "silk" {
            300
        } else {
            2000
        };
        assert_bounds(name, model, t, n);
    }
}

/// Next to the horizon a table never amplifies: its value is a weighted mean of node values, so
/// it stays within the range of the exact BRDF around it — the old division of interpolated
/// `f cos θ_i cos θ_r` by vanishing cosines gave up to 8 000× the exact value next to the horizon.
#[test]
fn grazing_pairs_are_never_amplified() {
    let mut rng = SplitMix(41);
    for name in ["rough", "polyester-sateen", "silk"] {
        let (model, t) = table(name);
        let largest = t.values().iter().fold(0.0f32, |a, &b| a.max(b)) as f64;
        let pairs = woven::table::report::band_pairs(300, rng.0);
        rng.uniform();
        for &(band, s, v) in pairs.iter().filter(|p| p.0 > 0) {
            let (f, e) = (t.eval(s, v), model.eval(s, v));
            assert!(
                f.is_finite() && f >= 0.0 && f <= largest * (1.0 + 1e-6),
                "{name}: {f}"
            );
            // Small grids are coarse, but never far off where it matters.
            let c = s.z * v.z;
            assert!(
                (f - e).abs() * c <= 0.2 * t.peak_cosine_weighted(),
                "{name} band {band}: s {s:?} v {v:?}: table {f} exact {e}"
            );
        }
    }
}

/// A material with other albedos.
fn dyed(m: &Material, diffuse: f64, interreflection: f64) -> Material {
    let mut m = m.clone();
    m.fiber.diffuse = diffuse;
    if let Some(y) = m.yarn.as_mut() {
        y.interreflection_albedo = interreflection;
    }
    m
}

/// The BRDF is affine in the albedos (docs/model.md §7), exactly, in the exact model: the
/// interreflection albedo `ρ` enters as `ħρ/π`, and three diffuse albedos determine the rest.
#[test]
fn the_exact_model_is_affine_in_the_albedos() {
    let mut rng = SplitMix(17);
    for name in ["rough", "polyester-sateen", "belt-cloth"] {
        let m = material(name);
        let at = |d: f64, r: f64| dyed(&m, d, r).build(550.0).unwrap();
        let (m00, m50, m90, m01) = (at(0.0, 0.0), at(0.5, 0.0), at(0.9, 0.0), at(0.0, 1.0));
        let hbar = m.yarn.as_ref().map_or(0.0, |y| y.interreflection);
        for _ in 0..40 {
            let mut pick = || {
                let z = rng.uniform().max(1e-3);
                let ph = 2.0 * PI * rng.uniform();
                let r = (1.0 - z * z).sqrt();
                Vec3::new(r * ph.cos(), r * ph.sin(), z)
            };
            let (s, v) = (pick(), pick());
            let (f00, f50, f90) = (m00.eval(s, v), m50.eval(s, v), m90.eval(s, v));
            // Collinear in ρ0: f(0.9) on the line through f(0) and f(0.5).
            let line = f00 + 1.8 * (f50 - f00);
            assert!(
                (f90 - line).abs() <= 1e-6 * f90.abs().max(1e-3),
                "{name}: f(ρ0 = 0.9) = {f90}, the line gives {line}"
            );
            let per_rho = m01.eval(s, v) - f00;
            assert!(
                (per_rho - hbar / PI).abs() <= 1e-9,
                "{name}: ∂f/∂ρ = {per_rho}, ħ/π = {}",
                hbar / PI
            );
        }
    }
}

/// A dyeable table gives the material's own BRDF at its own albedos, and at other albedos what a
/// table built for those albedos gives, on the same grid, in every band; it survives a file
/// round trip.
#[test]
fn dyed_tables_agree_with_tables_of_the_dyed_material() {
    // The agreement does not depend on the grid: a tiny one keeps the test fast.
    let tiny = TableOptions {
        n_theta: 8,
        n_phi: 4,
        n_h: 17,
        n_h_isotropic: 25,
        azimuth_nodes: 24,
        ..TableOptions::default()
    };
    let options = TableOptions {
        colour: true,
        ..tiny
    };
    let mut rng = SplitMix(23);
    for name in ["rough", "polyester-sateen", "silk"] {
        let m = material(name);
        let model = m.build(550.0).unwrap();
        let t = Table::build(&model, &m, &options, &|_, _| {}).unwrap();
        assert!(t.is_dyeable());
        let plain = Table::build(&model, &m, &tiny, &|_, _| {}).unwrap();
        let dyes = [(0.02, 0.9), (0.95, 0.0)];
        let other: Vec<Table> = dyes
            .iter()
            .map(|&(d, r)| {
                let dm = dyed(&m, d, r);
                Table::build(&dm.build(550.0).unwrap(), &dm, &tiny, &|_, _| {}).unwrap()
            })
            .collect();
        let albedos = dyes.map(|(d, r)| woven::table::Albedos {
            diffuse: d,
            interreflection: r,
        });
        let loaded = Table::from_bytes(&t.to_bytes(), "memory").unwrap();
        assert!(loaded.is_dyeable());
        for k in 0..3000 {
            let lim = [1.0, 0.17, 0.02][k % 3];
            let mut pick = |lim: f64| {
                let z = lim * rng.uniform().max(1e-6);
                let ph = 2.0 * PI * rng.uniform();
                let r = (1.0 - z * z).sqrt();
                Vec3::new(r * ph.cos(), r * ph.sin(), z)
            };
            let (s, v) = (pick(lim), pick(1.0));
            let own = t.eval_dyed(s, v, &[woven::table::Albedos::of(&m)])[0];
            let want = plain.eval(s, v);
            assert!(
                (own - want).abs() <= 1e-4 * want.max(1e-2),
                "{name}: own albedos give {own}, the plain table {want} at s {s:?} v {v:?}"
            );
            let got = t.eval_dyed(s, v, &albedos);
            assert_eq!(got, loaded.eval_dyed(s, v, &albedos));
            for (j, o) in other.iter().enumerate() {
                let want = o.eval(s, v);
                assert!(
                    (got[j] - want).abs() <= 1e-4 * want.max(1e-2),
                    "{name} dyed {:?}: {} vs a table of the dyed material {want} at s {s:?} v {v:?}",
                    dyes[j],
                    got[j]
                );
            }
        }
    }
}

/// Tables of single-orientation yarns evaluate near-forward pairs (`|s + v| < FORWARD_EXACT`) and
/// pairs whose half vector is within 5° of the horizon (`GRAZING_HALF_EXACT`) with the exact
/// model, also after a file round trip, in `eval`, `eval_dyed` and `sample`; twisted yarns
/// interpolate there.
#[test]
fn near_forward_pairs_of_aligned_yarns_are_exact() {
    use woven::table::{Albedos, FORWARD_EXACT, GRAZING_HALF_EXACT};
    let exact_region = |s: Vec3, v: Vec3| {
        let h = s + v;
        (
            h.dot(h) < FORWARD_EXACT * FORWARD_EXACT,
            h.z < GRAZING_HALF_EXACT * h.length(),
        )
    };
    let mut rng = SplitMix(31);
    let (model, t) = table("polyester-sateen");
    let loaded = Table::from_bytes(&t.to_bytes(), "memory").unwrap();
    let (belt_model, belt) = table("belt-cloth");
    let own = [Albedos::of(&material("polyester-sateen"))];
    let (mut forward, mut grazing, mut belt_differs) = (0, 0, 0);
    for k in 0..6000 {
        // Both directions within 15° of the horizon, roughly opposite; or, every third pair,
        // both within 6° of it at any azimuths.
        let (zmax, spread) = if k % 3 == 2 {
            (0.1, 2.0 * PI)
        } else {
            (0.26, 0.6)
        };
        let z = zmax * rng.uniform().max(1e-6);
        let ph = 2.0 * PI * rng.uniform();
        let s = Vec3::new(
            (1.0 - z * z).sqrt() * ph.cos(),
            (1.0 - z * z).sqrt() * ph.sin(),
            z,
        );
        let z2 = zmax * rng.uniform().max(1e-6);
        let ph2 = ph + PI + spread * (rng.uniform() - 0.5);
        let v = Vec3::new(
            (1.0 - z2 * z2).sqrt() * ph2.cos(),
            (1.0 - z2 * z2).sqrt() * ph2.sin(),
            z2,
        );
        let (near_forward, grazing_half) = exact_region(s, v);
        let (e, f) = (model.eval(s, v), t.eval(s, v));
        if near_forward || grazing_half {
            forward += usize::from(near_forward);
            grazing += usize::from(grazing_half && !near_forward);
            assert_eq!(f, e, "s {s:?} v {v:?}");
            assert_eq!(loaded.eval(s, v), e);
            assert!((t.eval_dyed(s, v, &own)[0] - e).abs() <= 1e-12 * e.max(1.0));
            if belt.eval(s, v) != belt_model.eval(s, v) {
                belt_differs += 1;
            }
        } else {
            assert_ne!(f, e, "s {s:?} v {v:?} interpolated");
        }
    }
    assert!(grazing > 500, "{grazing} pairs with a grazing half vector");
    assert!(forward > 500, "{forward} near-forward pairs");
    assert!(
        belt_differs > (forward + grazing) / 2,
        "the belt cloth's table is exact at {belt_differs}"
    );
    // A sampled direction near forward carries the exact value too.
    let s = Vec3::from_spherical(85f64.to_radians(), 0.3);
    let mut hits = 0;
    for _ in 0..20_000 {
        if let Some(smp) = t.sample(s, 0.5, [rng.uniform(), rng.uniform()], Importance) {
            if exact_region(s, smp.wo).0 {
                hits += 1;
                assert_eq!(smp.f, model.eval(s, smp.wo));
            }
        }
    }
    assert!(hits > 0, "no near-forward draw from θi 85°");
}

/// `exact_regions = false` (a renderer's tables) interpolates everywhere, also after a file
/// round trip, and agrees with the table that keeps the exact model outside its regions.
#[test]
fn tables_without_exact_regions_interpolate_everywhere() {
    let (model, with) = table("polyester-sateen");
    let m = material("polyester-sateen");
    let options = TableOptions {
        exact_regions: false,
        ..small()
    };
    let without = Table::build(model, &m, &options, &|_, _| {}).unwrap();
    let loaded = Table::from_bytes(&without.to_bytes(), "memory").unwrap();
    let s = Vec3::from_spherical(85f64.to_radians(), 0.2);
    let forward = Vec3::from_spherical(84f64.to_radians(), 0.2 + PI);
    assert_eq!(with.eval(s, forward), model.eval(s, forward));
    assert_ne!(without.eval(s, forward), model.eval(s, forward));
    assert_eq!(loaded.eval(s, forward), without.eval(s, forward));
    let v = Vec3::from_spherical(30f64.to_radians(), 1.0);
    assert_eq!(without.eval(s, v), with.eval(s, v));
}
