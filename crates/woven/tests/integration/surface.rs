//! The woven surface (`woven::surface`) and the `Bsdf` interface's transport modes: sampling
//! and densities agree in both modes, the pattern's layout is what its cells and floats say,
//! and parameters out of range are refused by name.

use crate::common::Rng;
use std::sync::{Arc, OnceLock};
use woven::bsdf::{Bsdf, Transport};
use woven::color::Rgb;
use woven::material::{Material, Weave};
use woven::surface::{Detail, Irregularity, SurfacePoint, SurfaceSpec, Tilt, WovenSurface};
use woven::table::{Table, TableOptions};
use woven::{Error, Vec3};

/// A small dyeable table of the sateen's yarn alone (built once).
fn yarn() -> Arc<Table> {
    static T: OnceLock<Arc<Table>> = OnceLock::new();
    Arc::clone(T.get_or_init(|| {
        let m = Material::preset("polyester-sateen").unwrap().yarn_family();
        let options = TableOptions {
            n_theta: 8,
            n_phi: 5,
            n_h: 21,
            colour: true,
            ..TableOptions::default()
        };
        Arc::new(Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap())
    }))
}

fn spec(pattern: &str, u_max_deg: f64, gap: f64) -> SurfaceSpec {
    let mut m = Material::preset("polyester-sateen").unwrap();
    m.weave = Some(Weave::named(pattern).unwrap());
    SurfaceSpec {
        yarns_per_unit: [6.0, 4.0],
        weft_color: Some(Rgb([0.7, 0.2, 0.1])),
        warp_color: Some(Rgb([0.1, 0.3, 0.6])),
        u_max: u_max_deg.to_radians(),
        gap,
        ..SurfaceSpec::new(m)
    }
}

fn direction(rng: &mut Rng, max_theta: f64) -> Vec3 {
    Vec3::from_spherical(
        (1.0 - rng.uniform() * (1.0 - max_theta.cos())).acos(),
        rng.range(0.0, 2.0 * std::f64::consts::PI),
    )
}

/// In both modes, a drawn pair's density is what `pdf` says for it, `f` is `eval`'s, and
/// `eval_pdf` gives both; for a table, for the exact model and for a surface's point.
#[test]
fn sampling_and_densities_agree_in_both_modes() {
    let table = yarn();
    let model = Material::preset("polyester-sateen")
        .unwrap()
        .build(550.0)
        .unwrap();
    let surface = WovenSurface::new(&spec("twill-2/1", 30.0, 0.3), Arc::clone(&table)).unwrap();
    let mut rng = Rng(11);
    let mut drawn = [0usize; 2];
    for (m, mode) in [Transport::Radiance, Transport::Importance]
        .into_iter()
        .enumerate()
    {
        for _ in 0..3000 {
            let known = direction(&mut rng, 1.45);
            let (uc, u) = (rng.uniform(), [rng.uniform(), rng.uniform()]);
            if let Some(s) = table.sample(known, uc, u, mode) {
                let (f, pdf) = table.eval_pdf(s.wi, s.wo, mode);
                // The sampler's own f (importance mode) is the same sum in its folded frame.
                assert!(
                    (f - s.f).abs() <= 1e-9 * f.max(1e-300),
                    "{mode:?}: {f} vs {}",
                    s.f
                );
                assert!(
                    (pdf - s.pdf).abs() <= 1e-5 * pdf,
                    "{mode:?}: {pdf} vs {}",
                    s.pdf
                );
                let known_is = if mode == Transport::Radiance {
                    s.wo
                } else {
                    s.wi
                };
                assert_eq!(known_is, known);
                drawn[m] += 1;
            }
            let s = model.sample(known, uc, u, mode).unwrap();
            assert!((model.pdf(s.wi, s.wo, mode) - s.pdf).abs() <= 1e-12);
            assert!((model.eval(s.wi, s.wo) - s.f).abs() <= 1e-12 * s.f.max(1.0));
            let at = SurfacePoint {
                uv: [rng.range(-1.0, 2.0), rng.range(-1.0, 2.0)],
                footprint: [[rng.range(0.0, 0.3), 0.0], [0.0, rng.range(0.0, 0.3)]],
            };
            let bsdf = surface.at(&at);
            if let Some(s) = bsdf.sample(known, uc, u, mode) {
                let (f, pdf) = bsdf.eval_pdf(s.wi, s.wo, mode);
                assert_eq!(f, s.f);
                assert!(
                    (pdf - s.pdf).abs() <= 1e-5 * pdf,
                    "{mode:?}: {pdf} vs {}",
                    s.pdf
                );
            }
        }
    }
    assert!(drawn.iter().all(|&n| n > 2500), "{drawn:?}");
}

/// The two modes draw different directions for the same uniforms — the known one is `wo` in
/// radiance mode and `wi` in importance mode — and weigh by the drawn direction's cosine.
#[test]
fn the_mode_says_which_direction_is_known() {
    let table = yarn();
    let known = Vec3::from_spherical(0.7, 0.4);
    let r = table
        .sample(known, 0.5, [0.3, 0.6], Transport::Radiance)
        .unwrap();
    let i = table
        .sample(known, 0.5, [0.3, 0.6], Transport::Importance)
        .unwrap();
    assert_eq!((r.wo, i.wi), (known, known));
    // The same table draw, named the other way round.
    assert_eq!(r.wi, i.wo);
    assert_eq!(r.f, table.eval(r.wi, known));
    assert_eq!(i.f, table.eval(known, i.wo));
    assert!((r.weight(Transport::Radiance) - r.f * r.wi.z / r.pdf).abs() < 1e-12);
    assert!((i.weight(Transport::Importance) - i.f * i.wo.z / i.pdf).abs() < 1e-12);
}

/// At the paper's yarn level, without tilt, gaps or a footprint, each point is its cell's yarn
/// alone: the weft where the pattern says weft, the warp (the table turned 90°) elsewhere, in
/// its dye.
#[test]
fn a_point_is_its_cells_yarn() {
    let table = yarn();
    let s = SurfaceSpec {
        detail: Detail::Yarns,
        ..spec("twill-2/1", 0.0, 0.0)
    };
    let surface = WovenSurface::new(&s, Arc::clone(&table)).unwrap();
    let pattern = surface.pattern().unwrap().clone();
    let mut rng = Rng(3);
    for _ in 0..500 {
        let uv = [rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)];
        let cell = pattern.cell_at(uv[0] * 6.0, uv[1] * 4.0);
        let mix = surface.lobes(&SurfacePoint {
            uv,
            footprint: [[0.0; 2]; 2],
        });
        assert_eq!(mix.lobes().len(), 1);
        assert_eq!(mix.lobes()[0].warp, !cell.weft);
        assert_eq!(
            (mix.lobes()[0].tilt, mix.lobes()[0].weight),
            (Tilt::Flat, 1.0)
        );
    }
    // A wide footprint is the macro BRDF: the γ-mix of weft and warp.
    let wide = SurfacePoint {
        uv: [0.3, 0.3],
        footprint: [[1.0, 0.0], [0.0, 1.0]],
    };
    let mix = surface.lobes(&wide);
    let weft: f64 = mix
        .lobes()
        .iter()
        .filter(|l| !l.warp)
        .map(|l| l.weight)
        .sum();
    assert!((weft - pattern.weft_fraction()).abs() < 1e-12);
    assert!((mix.total() - 1.0).abs() < 1e-12);
}

/// At the paper's yarn level with tilt, a point knows where along its float the viewer's ray
/// enters it, from 0 where the float comes up to 1 where it goes under; in a gap the crossing
/// yarn shows flat, and where both leave a gap, nothing.
#[test]
fn tilt_runs_along_floats_and_gaps_show_the_yarn_below() {
    let table = yarn();
    let s = SurfaceSpec {
        detail: Detail::Yarns,
        ..spec("satin-5", 40.0, 0.4)
    };
    let surface = WovenSurface::new(&s, Arc::clone(&table)).unwrap();
    let at = |x: f64, y: f64| {
        surface.lobes(&SurfacePoint {
            uv: [x / 6.0, y / 4.0],
            footprint: [[0.0; 2]; 2],
        })
    };
    // satin-5: the warp floats over four picks of five. Column 0's weft cell is at row 0; its
    // warp float runs over rows 1..=4.
    let pattern = surface.pattern().unwrap();
    assert!(pattern.is_weft(0, 0) && !pattern.is_weft(1, 0));
    let entering = |mix: woven::surface::LobeMix| match mix.lobes()[0].tilt {
        Tilt::Entering(t) if mix.lobes()[0].warp => t,
        other => panic!("{other:?}"),
    };
    assert!(entering(at(0.5, 1.0 + 1e-9)) < 1e-6);
    assert!((entering(at(0.5, 3.0)) - 0.5).abs() < 1e-9);
    assert!(entering(at(0.5, 5.0 - 1e-9)) > 1.0 - 1e-6);
    // Across the warp's gap (x near a cell's edge) the weft below shows, flat; at a cell's
    // corner both leave a gap: a hole.
    let below = at(0.05, 2.5);
    assert!(!below.lobes()[0].warp && below.lobes()[0].tilt == Tilt::Flat);
    assert_eq!(at(0.05, 2.05).lobes().len(), 0);
}

/// Parameters out of range are refused, by name, with the valid range.
#[test]
fn bad_parameters_are_refused_by_name() {
    let table = yarn();
    type Change = Box<dyn Fn(&mut SurfaceSpec)>;
    let irregular = |spread, length| Irregularity {
        spread: [spread; 2],
        length,
    };
    let cases: [(&str, Change); 7] = [
        (
            "yarns_per_unit",
            Box::new(|s| s.yarns_per_unit = [0.0, 4.0]),
        ),
        (
            "weft_color",
            Box::new(|s| s.weft_color = Some(Rgb([1.2, 0.0, 0.0]))),
        ),
        (
            "warp_color",
            Box::new(|s| s.warp_color = Some(Rgb([f64::NAN; 3]))),
        ),
        ("u_max", Box::new(|s| s.u_max = 1.5)),
        ("gap", Box::new(|s| s.gap = 0.99)),
        (
            "irregularity",
            Box::new(move |s| s.irregularity = irregular(1.5, 24.0)),
        ),
        (
            "irregularity_length",
            Box::new(move |s| s.irregularity = irregular(0.3, 0.0)),
        ),
    ];
    for (name, change) in cases {
        let mut s = spec("plain", 0.0, 0.0);
        change(&mut s);
        match WovenSurface::new(&s, Arc::clone(&table)) {
            Err(Error::InvalidParameter {
                name: n, expected, ..
            }) => {
                assert_eq!(n, name);
                assert!(!expected.is_empty());
            }
            other => panic!("{name}: {:?}", other.map(|_| ())),
        }
    }
    // A dye needs a dyeable table.
    let m = Material::preset("polyester-sateen").unwrap().yarn_family();
    let options = TableOptions {
        n_theta: 4,
        n_phi: 3,
        n_h: 11,
        ..TableOptions::default()
    };
    let plain = Arc::new(Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap());
    let err = WovenSurface::new(&spec("plain", 0.0, 0.0), plain).unwrap_err();
    assert!(err.to_string().contains("weft_color"), "{err}");
    // Yarns vary one by one only on a pattern.
    let mut s = spec("plain", 0.0, 0.0);
    s.material.weave = Some(Weave::WeftFraction(0.5));
    s.irregularity = irregular(0.3, 24.0);
    let err = WovenSurface::new(&s, Arc::clone(&table)).unwrap_err();
    assert!(err.to_string().contains("irregularity"), "{err}");
    // Light through a flat fiber surface (no yarns) has nothing to pass through.
    let flat = SurfaceSpec {
        transmission: true,
        ..SurfaceSpec::new(crate::common::table_material("rough"))
    };
    let err = flat.validate().unwrap_err().to_string();
    assert!(
        err.contains("transmission") && err.contains("flat fiber"),
        "{err}"
    );
}

/// Irregular yarns ([`Irregularity`]) vary the cloth from point to point, but over many yarns
/// the cloth is the uniform one: the mean BRDF over random points of a wide patch is the
/// uniform surface's at the same points (paired, within 4 standard errors), at yarn level and
/// at fibre level, while single points differ by the spread asked for. (Dyes whose factor
/// reaches the albedos' caps, `ρ0 < 1` and `ρ ≤ 1`, lose a little on average.)
#[test]
fn irregular_yarns_average_to_the_uniform_cloth() {
    let table = yarn();
    let (wi, wo) = (
        Vec3::from_spherical(0.5, 0.3),
        Vec3::from_spherical(0.7, 2.4),
    );
    for detail in [Detail::Yarns, Detail::Fibers] {
        // Dyes dark enough that no factor within 3σ reaches the albedos' caps (the sateen's
        // `ρ` is 7.5 times its `ρ0`).
        let uniform = SurfaceSpec {
            detail,
            weft_color: Some(Rgb([0.05, 0.025, 0.01])),
            warp_color: Some(Rgb([0.01, 0.025, 0.05])),
            ..spec("twill-2/1", 20.0, 0.1)
        };
        let irregular = SurfaceSpec {
            irregularity: Irregularity {
                spread: [0.3, 0.3],
                length: 8.0,
            },
            ..uniform.clone()
        };
        let a = WovenSurface::new(&uniform, Arc::clone(&table)).unwrap();
        let b = WovenSurface::new(&irregular, Arc::clone(&table)).unwrap();
        let mut rng = Rng(29);
        let n = 20_000;
        let (mut sum, mut sum2, mut spread) = ([0.0; 3], [0.0; 3], 0.0);
        for _ in 0..n {
            let at = SurfacePoint {
                uv: [rng.range(-40.0, 40.0), rng.range(-40.0, 40.0)],
                footprint: [[0.0; 2]; 2],
            };
            let (fa, fb) = (a.at(&at).eval(wi, wo), b.at(&at).eval(wi, wo));
            for k in 0..3 {
                let d = fb.0[k] - fa.0[k];
                sum[k] += d;
                sum2[k] += d * d;
            }
            let m = b.dye_factors(&at);
            spread += m[0].ln().powi(2) + m[1].ln().powi(2);
        }
        for k in 0..3 {
            let mean = sum[k] / n as f64;
            let se = ((sum2[k] / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                mean.abs() < 4.0 * se,
                "{detail:?}, channel {k}: mean difference {mean:.3e} (SE {se:.3e})"
            );
            assert!(se > 0.0, "{detail:?}: the points do not vary");
        }
        let rms_log = (spread / (2 * n) as f64).sqrt();
        // The log factor's RMS: `σ` and `σ²/2` in quadrature.
        let expected = (0.09f64 + 0.0225f64.powi(2)).sqrt();
        assert!(
            (rms_log - expected).abs() < 0.02,
            "{detail:?}: RMS log factor {rms_log}"
        );
    }
}

/// The exact yarn of a preset's material (its yarn alone).
pub fn exact_yarn(name: &str) -> woven::Model {
    Material::preset(name)
        .unwrap()
        .yarn_family()
        .build(550.0)
        .unwrap()
}

fn yarn_of(model: &woven::Model) -> &woven::yarn::Yarn {
    match model.structure() {
        woven::cloth::Structure::Woven { yarn, .. } => yarn,
        woven::cloth::Structure::Flat(_) => panic!("a preset with yarns"),
    }
}

/// Directions of the identity tests: near normal, oblique, grazing, across and along the yarn,
/// forward and backward.
fn identity_pairs() -> Vec<(Vec3, Vec3)> {
    let d = |t: f64, p: f64| Vec3::from_spherical(t.to_radians(), p.to_radians());
    vec![
        (d(20.0, 10.0), d(35.0, 200.0)),
        (d(60.0, 90.0), d(50.0, 260.0)),
        (d(75.0, 30.0), d(40.0, 150.0)),
        (d(45.0, 0.0), d(45.0, 180.0)),
        (d(80.0, 100.0), d(70.0, 100.0)),
    ]
}

/// Resolved in space, a yarn's points average over its width to the paper's profile BRDF
/// (17'): for every preset's yarn, several directions, slopes and fibre azimuths, the mean of
/// `Yarn::point_parts` over the projected width equals `Yarn::profile_brdf` to 1e-3.
#[test]
fn fibre_points_average_to_the_profile_brdf() {
    let n = 40_000;
    for name in Material::preset_names().iter().copied() {
        let model = exact_yarn(name);
        let yarn = yarn_of(&model);
        for (s, v) in identity_pairs() {
            for (theta_a, phi_a) in [(0.3, 0.0), (0.9, 0.4), (1.4, -1.2), (0.05, 2.0)] {
                let mut parts = [0.0; 2];
                for k in 0..n {
                    let p = yarn.point_parts(s, v, phi_a, theta_a, (k as f64 + 0.5) / n as f64);
                    parts[0] += p[0] / n as f64;
                    parts[1] += p[1] / n as f64;
                }
                let mean = yarn.fiber().combine_parts(parts);
                let want = yarn.profile_brdf(s, v, phi_a, theta_a);
                assert!(
                    (mean - want).abs() <= 1e-3 * want + 1e-6,
                    "{name} θa {theta_a} φa {phi_a} s {s:?} v {v:?}: points {mean} vs f_p {want}"
                );
            }
        }
    }
}

/// The draws of slopes and fibre azimuths follow the model's distributions: averaged over
/// uniform numbers, the profile BRDF of drawn slopes is the slope average (18) and the yarn's
/// BRDF at drawn fibre azimuths is the twist (21) or isotropic (22) average, to 1e-3.
#[test]
fn yarn_draws_average_to_the_models_integrals() {
    let n = 1_500;
    for name in Material::preset_names().iter().copied() {
        let model = exact_yarn(name);
        let yarn = yarn_of(&model);
        let draws = woven::yarn::point::YarnDraws::new(yarn);
        for (s, v) in identity_pairs().into_iter().take(3) {
            let mean: f64 = (0..n)
                .map(|k| yarn.profile_brdf(s, v, 0.3, draws.slope((k as f64 + 0.5) / n as f64)))
                .sum::<f64>()
                / n as f64;
            let want = yarn.slope_averaged(s, v, 0.3);
            assert!(
                (mean - want).abs() <= 1e-3 * want + 1e-6,
                "{name}: slopes drawn {mean} vs Eq. (18) {want}"
            );
            if draws.varies_in_azimuth() {
                let m = 400;
                let mean: f64 = (0..m)
                    .map(|k| yarn.eval_oriented(s, v, draws.twist((k as f64 + 0.5) / m as f64)))
                    .sum::<f64>()
                    / m as f64;
                let want = yarn.eval(s, v, 0.0);
                assert!(
                    (mean - want).abs() <= 2e-3 * want + 1e-6,
                    "{name}: azimuths drawn {mean} vs Eqs. (21)/(22) {want}"
                );
            }
        }
    }
}

/// The preset `name` in its own weave as a relief at fibre level, one cell a unit, on the shared table of
/// its yarn.
fn at_fibre_level(name: &str) -> WovenSurface {
    let spec = SurfaceSpec {
        yarns_per_unit: [1.0, 1.0],
        detail: Detail::Fibers,
        relief: true,
        ..SurfaceSpec::new(Material::preset(name).unwrap())
    };
    WovenSurface::new(&spec, crate::energy::yarn_table(name)).unwrap()
}

/// χ² of a BSDF's draws for a viewer at `theta_deg` (azimuth 0.7) against its density in
/// radiance mode: `(p, share of draws accepted, ∫ pdf)` ([`crate::table::chi2_of`]).
pub fn radiance_chi2<B: Bsdf + ?Sized>(
    bsdf: &B,
    theta_deg: f64,
    n: usize,
    seed: u64,
) -> (f64, f64, f64) {
    let wo = Vec3::from_spherical(f64::to_radians(theta_deg), 0.7);
    crate::table::chi2_of(
        |rng| {
            bsdf.sample(
                wo,
                rng.uniform(),
                [rng.uniform(), rng.uniform()],
                Transport::Radiance,
            )
            .map(|s| s.wi)
        },
        |wi| bsdf.pdf(wi, wo, Transport::Radiance),
        n,
        seed,
    )
}

/// χ² of a transmitting surface's draws over the whole sphere (reflection and the light through
/// the yarns together) against its density, in radiance mode: a gapped, tilted twill with
/// transmission on, at the cloth level and on a yarn at the yarn level, three views each
/// (Bonferroni at 1 % over the six).
#[test]
fn transmitting_surfaces_sample_both_sides_by_chi_square() {
    let spec = SurfaceSpec {
        transmission: true,
        ..spec("twill-2/1", 20.0, 0.25)
    };
    let surface = WovenSurface::new(&spec, yarn()).unwrap();
    let points = [
        SurfacePoint {
            uv: [0.0; 2],
            footprint: [[1e3, 0.0], [0.0, 1e3]],
        },
        // Cell (0, 0), the middle of its top yarn (gap 0.25: a yarn covers the middle 0.75).
        SurfacePoint {
            uv: [0.5 / 6.0, 0.5 / 4.0],
            footprint: [[0.0; 2]; 2],
        },
    ];
    let mut k = 0;
    for at in &points {
        let bsdf = surface.at(at);
        for theta_deg in [15.0, 50.0, 75.0] {
            let wo = Vec3::from_spherical(f64::to_radians(theta_deg), 0.7);
            let (p, accepted, integral) = crate::table::chi2_of_sphere(
                |rng| {
                    bsdf.sample(
                        wo,
                        rng.uniform(),
                        [rng.uniform(), rng.uniform()],
                        Transport::Radiance,
                    )
                    .map(|s| s.wi)
                },
                |wi| bsdf.pdf(wi, wo, Transport::Radiance),
                100_000,
                301 + k,
            );
            k += 1;
            println!(
                "{at:?} θo {theta_deg}°: p {p:.3}, accepted {accepted:.4}, ∫pdf {integral:.4}"
            );
            assert!(p > 0.01 / 6.0, "θo {theta_deg}° at {at:?}: p {p:.2e}");
            assert!(
                (integral - accepted).abs() < 0.01,
                "∫pdf {integral} vs accepted {accepted}"
            );
            // Some draws cross the cloth.
            let through = (0..2000)
                .filter_map(|i| {
                    let u = [(i % 40) as f64 / 40.0 + 0.01, (i / 40) as f64 / 50.0 + 0.01];
                    bsdf.sample(wo, (i as f64 * 0.618) % 1.0, u, Transport::Radiance)
                })
                .filter(|s| s.wi.z < 0.0)
                .count();
            assert!(through > 50, "{through} of 2000 draws through the cloth");
        }
    }
}

/// χ² of the fibre-level sampling (the facet's Beckmann lobe and the cosine lobe, mixed) against
/// its density, at three incidences for every preset's yarn, in radiance mode: a pattern point at
/// `detail = "fibers"` on the crest, on a flank and near the edge of a yarn.
#[test]
fn fibre_level_sampling_passes_chi2() {
    let mut k = 0;
    for name in Material::preset_names().iter().copied() {
        let mut material = Material::preset(name).unwrap();
        material.weave = Some(Weave::named("plain").unwrap());
        let spec = SurfaceSpec {
            yarns_per_unit: [1.0, 1.0],
            detail: woven::surface::Detail::Fibers,
            ..SurfaceSpec::new(material)
        };
        let m = spec.table_material();
        let options = TableOptions {
            n_theta: 4,
            n_phi: 3,
            n_h: 11,
            colour: true,
            ..TableOptions::default()
        };
        let table = Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap();
        let surface = WovenSurface::new(&spec, Arc::new(table)).unwrap();
        for (theta_deg, across) in [(10.0, 0.5), (50.0, 0.3), (80.0, 0.9)] {
            // Cell (0, 1) of the plain weave: the weft on top, across its width along v.
            let at = SurfacePoint {
                uv: [1.5, across],
                footprint: [[0.0; 2]; 2],
            };
            let bsdf = surface.at(&at);
            assert!(bsdf.mix().lobes()[0].point.is_some());
            let (p, accepted, integral) = radiance_chi2(&bsdf, theta_deg, 100_000, 91 + k);
            k += 1;
            // Nine tests: Bonferroni at 1 %.
            assert!(
                p > 0.01 / 9.0,
                "{name} at θo {theta_deg}°, across {across}: p {p:.2e}"
            );
            // The density integrates to the fraction of draws that land above the horizon.
            assert!(
                (integral - accepted).abs() < 0.01,
                "{name}: ∫pdf {integral} vs accepted {accepted}"
            );
        }
    }
}

/// The mean absolute change of a weft-only surface's BRDF (channel 1, summed over `pairs`)
/// between points a tenth of a cell apart along the yarn and `k` times that across it, over `n × n` points of
/// one cell.
fn striation_change(surface: &WovenSurface, pairs: &[(Vec3, Vec3)], k: f64, n: usize) -> f64 {
    let f = |x: f64, y: f64| -> f64 {
        let at = SurfacePoint {
            uv: [x, y],
            footprint: [[0.0; 2]; 2],
        };
        let b = surface.at(&at);
        pairs.iter().map(|&(s, v)| b.eval(s, v).0[1]).sum()
    };
    let d = 0.1;
    let mut total = 0.0;
    for i in 0..n {
        for j in 0..n {
            // Away from the yarn's edges and ends, so the step stays on one float (slopes are
            // drawn per float).
            let (x, y) = (
                0.85 * (i as f64 + 0.5) / n as f64,
                0.2 + 0.6 * (j as f64 + 0.5) / n as f64,
            );
            total += (f(x + d, y + k * d) - f(x, y)).abs();
        }
    }
    total / (n * n) as f64
}

/// Fibres of a twisted yarn follow a helix: at fibre level its strands run diagonally at the
/// yarn's helix angle (the mean |φ| of its twist density), so the BRDF changes least along that
/// diagonal and far more along the yarn's axis — fine diagonal stripes, the striation of spun
/// yarn. Measured on the belt cloth's weft (twist σ_t = 0.35 rad) by scanning the direction.
///
/// `cargo test --release -p woven --test integration striation -- --nocapture`
#[test]
fn twisted_strands_run_diagonally_at_the_helix_angle() {
    let surface = crate::energy::weft_only("belt-cloth", Detail::Fibers);
    let model = exact_yarn("belt-cloth");
    let helix = woven::yarn::point::YarnDraws::new(yarn_of(&model)).helix_angle();
    // Oblique light and view across the yarn: the fibres' azimuths matter most.
    let pairs = [identity_pairs()[2]];
    let n = 48;
    let along_axis = striation_change(&surface, &pairs, 0.0, n);
    let (best_k, best) = (-60..=60)
        .map(|i| {
            let k = i as f64 * 0.01;
            (k, striation_change(&surface, &pairs, k, n))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    let mean: f64 = pairs.iter().map(|&(s, v)| model.eval(s, v)).sum::<f64>();
    // The striation's contrast: how much neighbouring strands differ, as a share of the mean.
    let f = |y: f64| {
        let at = SurfacePoint {
            uv: [0.4, y],
            footprint: [[0.0; 2]; 2],
        };
        surface.at(&at).eval(pairs[0].0, pairs[0].1).0[1]
    };
    let strand = 1.0 / woven::surface::STRANDS as f64;
    let contrast = (0..256)
        .map(|j| (f(0.2 + 0.6 * j as f64 / 256.0 + strand) - f(0.2 + 0.6 * j as f64 / 256.0)).abs())
        .sum::<f64>()
        / 256.0
        / mean;
    println!(
        "helix angle {:.1}°; stripes found at {:.1}° from the axis; change per step along them \
         {best:.4}, along the axis {along_axis:.4} ({:.1}×), of a mean {mean:.4}; neighbouring \
         strands differ by {:.1} % of it",
        helix.to_degrees(),
        best_k.abs().atan().to_degrees(),
        along_axis / best,
        100.0 * contrast
    );
    assert!(
        (best_k.abs() - helix.tan()).abs() < 0.03,
        "stripes at slope {best_k}, helix tan {}",
        helix.tan()
    );
    assert!(along_axis > 1.6 * best, "{along_axis} vs {best}");
}

/// The mean of channel 1 of `f(s, v)` over the points of weft floats whose place along their
/// float `t` lies in each of `bins` equal bins, over a stratified grid of `n × n` points a cell
/// on `cells × cells` cells.
fn along_float_profile(
    surface: &WovenSurface,
    (s, v): (Vec3, Vec3),
    cells: usize,
    n: usize,
    bins: usize,
) -> Vec<f64> {
    let pattern = surface.pattern().unwrap();
    let floats = surface.floats();
    let (mut sum, mut count) = (vec![0.0; bins], vec![0usize; bins]);
    for i in 0..cells * n {
        for j in 0..cells * n {
            let (x, y) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            let cell = pattern.cell_at(x, y);
            let place = floats[cell.row * pattern.cols() + cell.col];
            if !cell.weft || place.len == 0 {
                continue;
            }
            let t = (f64::from(place.before) + cell.x) / f64::from(place.len);
            let b = ((t * bins as f64) as usize).min(bins - 1);
            let at = SurfacePoint {
                uv: [x, y],
                footprint: [[0.0; 2]; 2],
            };
            sum[b] += surface.at(&at).eval(s, v).0[1];
            count[b] += 1;
        }
    }
    sum.iter()
        .zip(&count)
        .map(|(s, &c)| s / c.max(1) as f64)
        .collect()
}

/// Where a float dips under the crossing yarn, under a raking light along it, both its ends lie
/// in shadow: the end facing away from the light in its own hill's, the end facing the light in
/// the crossing yarn's, which stands up between them. The satin charmeuse's 7-cell floats at
/// fibre level, seen from above, lit 70° from the normal along the weft: the first and last
/// tenths of the float under half of mid-float, while its lit slope is brighter than mid-float.
///
/// `cargo test --release -p woven --test integration crossings -- --nocapture`
#[test]
fn crossings_are_shadowed_under_a_raking_light() {
    let surface = at_fibre_level("satin-charmeuse");
    let d = |t: f64, p: f64| Vec3::from_spherical(t.to_radians(), p.to_radians());
    let bins = 10;
    let mut report = Vec::new();
    for (light, name) in [(d(70.0, 0.0), "from +x"), (d(70.0, 180.0), "from −x")] {
        let profile = along_float_profile(&surface, (light, d(0.0, 0.0)), 16, 24, bins);
        let mid = 0.5 * (profile[bins / 2 - 1] + profile[bins / 2]);
        let (start, end) = (profile[0] / mid, profile[bins - 1] / mid);
        let brightest = profile.iter().copied().fold(0.0, f64::max) / mid;
        report.push(format!(
            "light {name}: float start {start:.2}, end {end:.2}, brightest {brightest:.2} of \
             mid-float ({mid:.4})"
        ));
        assert!(start.max(end) < 0.5, "{name}: {profile:?}");
        assert!(brightest > 1.2, "{name}: {profile:?}");
    }
    println!("crossings: {}", report.join("; "));
}

/// A JIT renderer traces shaped floats and irregular dyes (only the fibres and the relief go to
/// the library), and the layout it gathers holds the float's profile exactly: the height that
/// [`JitFloat`]'s documented rule rebuilds from its knots, rises and top is
/// [`FloatProfile::height`](woven::yarn::float::FloatProfile::height), and its tilt the
/// profile's.
#[test]
fn a_jit_layout_traces_shaped_floats_and_irregular_dyes() {
    use woven::surface::{JitFloat, LibraryReason, Route};
    let table = yarn();
    let mut shaped = spec("satin-5", 30.0, 0.1);
    let yarn_params = shaped.material.yarn.as_mut().unwrap();
    (yarn_params.float_crest, yarn_params.float_flank) = (0.2, 0.13);
    shaped.irregularity = Irregularity {
        spread: [0.2, 0.4],
        length: 6.0,
    };
    for detail in [Detail::Yarns, Detail::Cloth] {
        let s = SurfaceSpec {
            detail,
            ..shaped.clone()
        };
        let surface = WovenSurface::new(&s, Arc::clone(&table)).unwrap();
        assert_eq!(surface.route(), Route::Traced, "{detail:?}");
        let lay = surface.jit_layout();
        assert_eq!(lay.irregularity, Some(s.irregularity), "{detail:?}");
        let JitFloat { knots, rises, top } = lay.float.expect("a tilted float's profile");
        assert_eq!(knots.len(), 6, "a crest and two flanks: five pieces");
        let profile = surface.float_profile();
        for k in 0..=400 {
            let t = k as f64 / 400.0;
            let i = (1..knots.len() - 1).filter(|&j| t >= knots[j].0).count();
            let ((t0, p0), (t1, p1)) = (knots[i], knots[i + 1]);
            let slope = (p1 - p0) / (t1 - t0);
            let psi = p0 + slope * (t - t0);
            let within = if slope == 0.0 {
                p0.tan() * (t - t0)
            } else {
                (p0.cos().ln() - psi.cos().ln()) / slope
            };
            let height = rises[i] + within - top;
            assert!((psi - profile.tilt(t)).abs() < 1e-14, "t {t}");
            assert!((height - profile.height(t)).abs() < 1e-14, "t {t}");
        }
    }
    // A weft fraction's floats tilt too, and its yarns cannot vary one by one.
    let mut fraction = shaped.clone();
    fraction.material.weave = Some(Weave::WeftFraction(0.3));
    fraction.irregularity = Irregularity::default();
    let surface = WovenSurface::new(&fraction, Arc::clone(&table)).unwrap();
    assert_eq!(surface.route(), Route::Traced);
    assert!(surface.jit_layout().float.is_some());
    assert_eq!(surface.jit_layout().irregularity, None);
    // What goes to the library, and why.
    for (detail, relief, why) in [
        (
            Detail::Fibers,
            false,
            LibraryReason::Resolved(Detail::Fibers),
        ),
        (Detail::Auto, false, LibraryReason::Resolved(Detail::Auto)),
        (Detail::Yarns, true, LibraryReason::Relief),
    ] {
        let s = SurfaceSpec {
            detail,
            relief,
            ..shaped.clone()
        };
        let surface = WovenSurface::new(&s, Arc::clone(&table)).unwrap();
        assert_eq!(
            surface.route(),
            Route::Library(why),
            "{detail:?}, relief {relief}"
        );
    }
    // Light through the cloth, and its back face, at every level (even the cloth's average).
    for detail in [Detail::Cloth, Detail::Yarns, Detail::Fibers] {
        let s = SurfaceSpec {
            detail,
            transmission: true,
            ..shaped.clone()
        };
        let surface = WovenSurface::new(&s, Arc::clone(&table)).unwrap();
        assert_eq!(
            surface.route(),
            Route::Library(LibraryReason::Transmission),
            "{detail:?}"
        );
    }
}
