//! Woven surfaces: the rendered image against the table it renders, and the pattern's cells
//! averaging to the macro BRDF.

use std::path::Path;
use woven::bsdf::Transport;
use woven::material::{Material, Weave};
use woven::surface::Detail;
use woven::table::{Table, TableOptions};
use woven::Vec3;
use woven_render::camera::Camera;
use woven_render::material::{BsdfScratch, ShadingPoint, SurfaceMaterial};
use woven_render::render::{render, RenderOptions};
use woven_render::scene::{Scene, SceneDescription};
use woven_render::woven_material::{TableCache, TableGrid, WovenMaterial, WovenSpec};

/// A very coarse grid (about a second per table for a single-orientation yarn): the tests here
/// compare the renderer with the same tables, so the grid's accuracy does not matter.
/// `spec` built on the [`tiny`] grid, in a cache of its own.
fn build_tiny(spec: &WovenSpec) -> WovenMaterial {
    WovenMaterial::build(
        spec,
        &TableGrid::Custom(tiny()),
        &mut TableCache::default(),
        &|| {},
        &|_, _| {},
    )
    .unwrap()
}

fn tiny() -> TableOptions {
    TableOptions {
        n_theta: 8,
        n_phi: 5,
        n_h: 17,
        n_h_isotropic: 33,
        ..TableOptions::default()
    }
}

/// A sateen rectangle (all warp, strongly anisotropic) under a point light with no environment:
/// every pixel equals the table's `f(s, v) · I cos θ_i / r²` averaged over the pixel, with the
/// weft along the rectangle's `edge_u` (world `x`) — the frame convention end to end.
#[test]
fn woven_rectangle_pixels_equal_the_table_times_the_irradiance() {
    let (w, h) = (16, 12);
    let origin = Vec3::new(0.3, -2.0, 1.6);
    let light = Vec3::new(-0.6, 0.8, 1.2);
    let text = format!(
        r#"
        [camera]
        origin = [{}, {}, {}]
        target = [0, 0, 0]
        fov_deg = 50
        [film]
        width = {w}
        height = {h}
        spp = 64
        [integrator]
        max_depth = 2
        [[light]]
        type = "point"
        position = [{}, {}, {}]
        intensity = [3, 3, 3]
        [[shape]]
        type = "rectangle"
        corner = [-1, -1, 0]
        edge_u = [2, 0, 0]
        edge_v = [0, 2, 0]
        material = "cloth"
        [material.cloth]
        type = "woven"
        material = "polyester-sateen"
        "#,
        origin.x, origin.y, origin.z, light.x, light.y, light.z
    );
    let desc = SceneDescription::from_str(&text, "<test>", Path::new(".")).unwrap();
    let scene = Scene::build(&desc, &TableGrid::Custom(tiny()), &|_| {}, &|_, _| {}).unwrap();
    let image = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!(image.invalid_samples, 0);

    let material = Material::preset("polyester-sateen").unwrap();
    let model = material.build(550.0).unwrap();
    let table = Table::build(&model, &material, &tiny(), &|_, _| {}).unwrap();
    let camera = Camera::new(origin, Vec3::new(0.0, 0.0, 0.0), Vec3::Z, 50.0, w, h);
    let n = 24;
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let (mut expected, mut covered) = (0.0, 0);
            for a in 0..n {
                for b in 0..n {
                    let ray = camera.ray(
                        x as f64 + (a as f64 + 0.5) / n as f64,
                        y as f64 + (b as f64 + 0.5) / n as f64,
                    );
                    let t = -ray.o.z / ray.d.z;
                    let p = ray.o + ray.d * t;
                    if ray.d.z >= 0.0 || p.x.abs() > 1.0 || p.y.abs() > 1.0 {
                        continue;
                    }
                    covered += 1;
                    let d = light - p;
                    let r2 = d.dot(d);
                    let s = d * (1.0 / r2.sqrt());
                    let v = ray.d * -1.0;
                    expected += table.eval(s, v) * 3.0 * s.z / r2 / (n * n) as f64;
                }
            }
            if covered != n * n {
                continue;
            }
            let got = image.at(x, y).0[0];
            let se = image.std_error[y * w + x].0[0];
            let tol = 5.0 * se + 0.02 * expected + 1e-6;
            assert!(
                (got - expected).abs() <= tol,
                "pixel ({x}, {y}): rendered {got} vs table {expected} (tolerance {tol})"
            );
            checked += 1;
        }
    }
    assert!(checked > w * h / 3, "only {checked} pixels checked");
}

/// Far away, the pattern's cells average to the macro BRDF: a 2/1 twill (γ = 1/3) of the
/// sateen's yarn, evaluated over whole pattern repeats, equals the material with
/// `weft_fraction = 1/3` (the paper's γ-mix) within the two tables' interpolation error.
#[test]
fn pattern_cells_average_to_the_macro_brdf() {
    let mut twill = Material::preset("polyester-sateen").unwrap();
    twill.weave = Some(Weave::Pattern {
        spec: woven::material::PatternSpec::Name("twill-2/1".into()),
        pattern: woven::weave::Pattern::from_name("twill-2/1").unwrap(),
    });
    let mut mixed = Material::preset("polyester-sateen").unwrap();
    mixed.weave = Some(Weave::WeftFraction(1.0 / 3.0));
    let grid = TableGrid::Custom(tiny());
    let mut cache = TableCache::default();
    let build = |m: Material, cache: &mut TableCache| {
        let spec = WovenSpec {
            detail: Detail::Yarns,
            material: m,
            yarns_per_unit: [3.0, 3.0],
            weft_color: None,
            warp_color: None,
            u_max: 0.0,
            gap: 0.0,
            irregularity: Default::default(),
            relief: false,
            transmission: false,
        };
        WovenMaterial::build(&spec, &grid, cache, &|| {}, &|_, _| {}).unwrap()
    };
    let pattern = build(twill, &mut cache);
    let macro_brdf = build(mixed, &mut cache);
    let mut rng = woven::math::rng::SplitMix(5);
    let mut worst: f64 = 0.0;
    for _ in 0..40 {
        let wi = rng.direction(1.2);
        let wo = rng.direction(1.2);
        // One pattern repeat is 1 × 1 in uv here (3 cells per unit, a 3 × 3 pattern): cell
        // centres sample each cell once.
        let mut mean = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                let at = ShadingPoint {
                    uv: [(i as f64 + 0.5) / 3.0, (j as f64 + 0.5) / 3.0],
                    ..ShadingPoint::default()
                };
                mean += pattern.eval(wi, wo, &at).0[0] / 9.0;
            }
        }
        let want = macro_brdf.eval(wi, wo, &ShadingPoint::default()).0[0];
        let err = (mean - want).abs() / want.max(0.05);
        worst = worst.max(err);
        assert!(
            err < 0.08,
            "wi {wi:?} wo {wo:?}: cell average {mean} vs macro {want}"
        );
    }
    assert!(worst > 0.0);
}

/// `sample`, `eval` and `pdf` of a patterned woven material agree in weft and warp cells: the
/// drawn `f` is `eval(wi, wo)` and the drawn density is `pdf(wi, wo)`; the warp cell is the
/// weft cell turned 90° about the normal.
#[test]
fn woven_sample_eval_and_pdf_agree_in_both_yarn_families() {
    let spec = WovenSpec {
        detail: Detail::Yarns,
        material: Material::preset("polyester-sateen").unwrap(),
        yarns_per_unit: [2.0, 2.0],
        weft_color: None,
        warp_color: None,
        u_max: 0.0,
        gap: 0.0,
        irregularity: Default::default(),
        relief: false,
        transmission: false,
    };
    let mut spec = spec;
    spec.material.weave = Some(Weave::Pattern {
        spec: woven::material::PatternSpec::Name("plain".into()),
        pattern: woven::weave::Pattern::plain().unwrap(),
    });
    let m = build_tiny(&spec);
    // Plain weave, 2 cells per unit: cell (0, 0) is warp, cell (0, 1) weft.
    let warp = ShadingPoint {
        uv: [0.25, 0.25],
        ..ShadingPoint::default()
    };
    let weft = ShadingPoint {
        uv: [0.75, 0.25],
        ..ShadingPoint::default()
    };
    let turn = |d: Vec3| Vec3::new(-d.y, d.x, d.z);
    let mut rng = woven::math::rng::SplitMix(9);
    let mut drawn = 0;
    for _ in 0..200 {
        let wo = rng.direction(1.4);
        for at in [&warp, &weft] {
            let Some(s) = m.sample(wo, at, rng.uniform(), [rng.uniform(), rng.uniform()]) else {
                continue;
            };
            drawn += 1;
            let f = m.eval(s.wi, wo, at).0[0];
            let pdf = m.pdf(s.wi, wo, at);
            assert!(
                (s.f.0[0] - f).abs() <= 1e-9 * f.max(1e-9),
                "{} vs {f}",
                s.f.0[0]
            );
            assert!((s.pdf - pdf).abs() <= 1e-6 * pdf, "{} vs {pdf}", s.pdf);
        }
        // A warp cell sees the weft cell's BRDF turned by 90°.
        let wi = rng.direction(1.4);
        let a = m.eval(turn(wi), turn(wo), &warp).0[0];
        let b = m.eval(wi, wo, &weft).0[0];
        assert!((a - b).abs() <= 1e-9 * b.max(1e-9), "warp {a} vs weft {b}");
    }
    assert!(drawn > 300, "only {drawn} draws succeeded");
}

/// A flat woven rectangle seen from afar (about 40 pattern cells per pixel), with the footprint
/// filter off (every sample sees its cell's yarn), renders as the macro BRDF of the same material: 4 × 4-pixel blocks agree within the noise plus the two
/// tables' interpolation error, and random sample positions leave no moiré (a structured
/// difference would break the per-block bound).
#[test]
fn a_distant_patterned_rectangle_renders_as_the_macro_brdf() {
    let dir = tempfile::tempdir().unwrap();
    let scene = |pattern: &str| {
        format!(
            r#"
            [camera]
            origin = [0, -2.5, 2.5]
            target = [0, 0, 0]
            fov_deg = 45
            [film]
            width = 16
            height = 16
            spp = 256
            [integrator]
            max_depth = 2
            footprint_filter = false
            [[light]]
            type = "point"
            position = [0.4, 0.5, 1.5]
            intensity = [10, 10, 10]
            [[shape]]
            type = "rectangle"
            corner = [-1, -1, 0]
            edge_u = [2, 0, 0]
            edge_v = [0, 2, 0]
            material = "cloth"
            [material.cloth]
            type = "woven"
            material = "{pattern}"
            yarns_per_unit = 500
            "#
        )
    };
    let mut twill = Material::preset("polyester-sateen").unwrap();
    twill.weave = Some(Weave::Pattern {
        spec: woven::material::PatternSpec::Name("twill-2/1".into()),
        pattern: woven::weave::Pattern::from_name("twill-2/1").unwrap(),
    });
    let mut mixed = Material::preset("polyester-sateen").unwrap();
    mixed.weave = Some(Weave::WeftFraction(1.0 / 3.0));
    let images: Vec<_> = [("twill.toml", twill), ("mixed.toml", mixed)]
        .into_iter()
        .map(|(file, m)| {
            std::fs::write(dir.path().join(file), m.to_toml_string()).unwrap();
            let desc = SceneDescription::from_str(&scene(file), "<test>", dir.path()).unwrap();
            let scene =
                Scene::build(&desc, &TableGrid::Custom(tiny()), &|_| {}, &|_, _| {}).unwrap();
            render(&scene, &RenderOptions::default()).unwrap()
        })
        .collect();
    let (a, b) = (&images[0], &images[1]);
    let mut compared = 0;
    for by in 0..4 {
        for bx in 0..4 {
            let (mut ma, mut mb, mut var) = (0.0, 0.0, 0.0);
            for y in by * 4..by * 4 + 4 {
                for x in bx * 4..bx * 4 + 4 {
                    let i = y * 16 + x;
                    ma += a.pixels[i].0[0] / 16.0;
                    mb += b.pixels[i].0[0] / 16.0;
                    var += (a.std_error[i].0[0].powi(2) + b.std_error[i].0[0].powi(2)) / 256.0;
                }
            }
            let tol = 4.5 * var.sqrt() + 0.03 * mb;
            assert!(
                (ma - mb).abs() <= tol,
                "block ({bx}, {by}): pattern {ma} vs macro {mb} (tolerance {tol})"
            );
            compared += (mb > 0.0) as usize;
        }
    }
    assert!(compared >= 6, "only {compared} lit blocks");
}

/// Shot cloth: the weft and the warp each render in their own dye. Each channel of a dyed woven
/// material is the BRDF of the material with that channel's albedos (ρ0 = the dye, ρ in
/// proportion), evaluated by a table built for the dyed material on the same grid; the white
/// sheen is not tinted.
#[test]
fn dyed_weft_and_warp_are_the_dyed_materials() {
    let mut plain = Material::preset("polyester-sateen").unwrap();
    plain.weave = Some(Weave::Pattern {
        spec: woven::material::PatternSpec::Name("plain".into()),
        pattern: woven::weave::Pattern::plain().unwrap(),
    });
    let (red, blue) = ([0.7, 0.1, 0.02], [0.03, 0.2, 0.6]);
    let spec = WovenSpec {
        detail: Detail::Yarns,
        material: plain.clone(),
        yarns_per_unit: [2.0, 2.0],
        weft_color: Some(woven_render::color::Rgb(red)),
        warp_color: Some(woven_render::color::Rgb(blue)),
        u_max: 0.0,
        gap: 0.0,
        irregularity: Default::default(),
        relief: false,
        transmission: false,
    };
    let m = build_tiny(&spec);
    let own = woven::table::Albedos::of(&plain);
    // The yarn alone, dyed with one channel's albedos: the reference table.
    let reference = |c: f64| {
        let mut d = plain.yarn_family();
        d.fiber.diffuse = c;
        d.yarn.as_mut().unwrap().interreflection_albedo =
            (own.interreflection * c / own.diffuse).min(1.0);
        Table::build(&d.build(550.0).unwrap(), &d, &tiny(), &|_, _| {}).unwrap()
    };
    let weft_refs = red.map(reference);
    let warp_refs = blue.map(reference);
    let warp = ShadingPoint {
        uv: [0.25, 0.25],
        ..ShadingPoint::default()
    };
    let weft = ShadingPoint {
        uv: [0.75, 0.25],
        ..ShadingPoint::default()
    };
    let turn = |d: Vec3| Vec3::new(d.y, -d.x, d.z);
    let mut rng = woven::math::rng::SplitMix(12);
    for _ in 0..300 {
        let (wi, wo) = (rng.direction(1.45), rng.direction(1.45));
        let (fw, fv) = (m.eval(wi, wo, &weft), m.eval(wi, wo, &warp));
        for k in 0..3 {
            let want_w = weft_refs[k].eval(wi, wo);
            let want_v = warp_refs[k].eval(turn(wi), turn(wo));
            assert!(
                (fw.0[k] - want_w).abs() <= 1e-4 * want_w.max(1e-2),
                "weft channel {k}: {} vs {want_w}",
                fw.0[k]
            );
            assert!(
                (fv.0[k] - want_v).abs() <= 1e-4 * want_v.max(1e-2),
                "warp channel {k}: {} vs {want_v}",
                fv.0[k]
            );
        }
    }
}

/// With a disk cache, a table is built once: a second scene (a new in-memory cache) loads it.
#[test]
fn tables_are_kept_on_disk_between_runs() {
    let dir = std::env::temp_dir().join(format!("woven-render-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let spec = WovenSpec {
        detail: Detail::Yarns,
        material: Material::preset("polyester-sateen").unwrap(),
        yarns_per_unit: [1.0, 1.0],
        weft_color: None,
        warp_color: None,
        u_max: 0.0,
        gap: 0.0,
        irregularity: Default::default(),
        relief: false,
        transmission: false,
    };
    let builds = std::sync::atomic::AtomicUsize::new(0);
    for _ in 0..2 {
        let mut cache = TableCache::with_disk(woven::table::cache::Cache::new(&dir));
        WovenMaterial::build(
            &spec,
            &TableGrid::Custom(tiny()),
            &mut cache,
            &|| {
                builds.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            },
            &|_, _| {},
        )
        .unwrap();
    }
    assert_eq!(builds.into_inner(), 1, "the second run rebuilt the table");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A woven cloth draped over a sphere renders (no invalid sample), covers the sphere's top and
/// hangs below its equator; its uv runs from 0 to 1 across the sheet.
#[test]
fn a_cloth_draped_over_a_sphere_renders() {
    let text = r#"
        [camera]
        origin = [0, -3, 1.2]
        target = [0, 0, 0.4]
        fov_deg = 40
        [film]
        width = 24
        height = 24
        spp = 4
        [integrator]
        max_depth = 3
        [[light]]
        type = "environment"
        radiance = [1, 1, 1]
        [[shape]]
        type = "cloth"
        drape = "sphere"
        center = [0, 0, 0.5]
        radius = 0.5
        corner = [-1, -1, 1]
        edge_u = [2, 0, 0]
        edge_v = [0, 2, 0]
        folds = 7
        amplitude = 0.04
        resolution = [60, 60]
        material = "cloth"
        [material.cloth]
        type = "woven"
        material = "silk"
        yarns_per_unit = 60
    "#;
    let desc = SceneDescription::from_str(text, "<test>", Path::new(".")).unwrap();
    let scene = Scene::build(&desc, &TableGrid::Custom(tiny()), &|_| {}, &|_, _| {}).unwrap();
    let mesh = &scene.accel.meshes()[0];
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p.z), h.max(p.z)));
    assert!((hi - 1.0).abs() < 1e-9 && lo < 0.5, "z from {lo} to {hi}");
    assert!(mesh
        .uvs
        .iter()
        .all(|uv| (0.0..=1.0).contains(&uv[0]) && (0.0..=1.0).contains(&uv[1])));
    let image = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!(image.invalid_samples, 0);
    // The cloth fills the middle of the frame.
    assert!(image.at(12, 12).0[0] > 0.0);
}

/// A path vertex builds the woven surface's BSDF once through the material's one door
/// ([`SurfaceMaterial::bsdf`]) and answers with it: bit for bit what the material's `eval`,
/// `sample` and `pdf` answer (each building it anew), on a relief (tilted floats, gaps, fibres
/// and yarns under `auto`), in any order of questions, its BSDF built over the previous
/// point's (one scratch, as a path keeps it); and the warp's share seen along the view.
#[test]
fn a_vertex_answers_as_the_material_does_bit_for_bit() {
    let mut material = Material::preset("polyester-sateen").unwrap();
    material.weave = Some(Weave::named("twill-2/1").unwrap());
    let spec = WovenSpec {
        yarns_per_unit: [8.0, 8.0],
        u_max: 0.4,
        gap: 0.15,
        relief: true,
        ..WovenSpec::new(material)
    };
    let m = build_tiny(&spec);
    let bits = |c: woven_render::Rgb| c.0.map(f64::to_bits);
    let mut rng = woven::math::rng::SplitMix(27);
    let mut drawn = 0;
    let mut scratch = BsdfScratch::default();
    for k in 0..400 {
        // Footprints from none (yarns) through fibres to a few cells (toward the macro BRDF).
        let size = [0.0, 0.002, 0.02, 0.1, 0.4][k % 5];
        let at = ShadingPoint {
            uv: [rng.uniform(), rng.uniform()],
            footprint: [[size, 0.0], [0.0, size * 0.7]],
        };
        let vertex = m.bsdf(&at, &mut scratch);
        let (wo, wi) = (rng.direction(1.45), rng.direction(1.45));
        let (uc, u) = (rng.uniform(), [rng.uniform(), rng.uniform()]);
        let ask_sample = || vertex.sample(wo, uc, u, Transport::Radiance);
        let pdf = || vertex.pdf(wi, wo, Transport::Radiance);
        // The integrator's order (eval, pdf, sample), or sampling first.
        let (f, pdf, s) = if k % 2 == 0 {
            (vertex.eval(wi, wo), pdf(), ask_sample())
        } else {
            let s = ask_sample();
            (vertex.eval(wi, wo), pdf(), s)
        };
        assert_eq!(bits(f), bits(m.eval(wi, wo, &at)), "eval at {at:?}");
        assert_eq!(pdf.to_bits(), m.pdf(wi, wo, &at).to_bits(), "pdf at {at:?}");
        let want = m.sample(wo, &at, uc, u);
        assert_eq!(s.is_some(), want.is_some(), "sample at {at:?}");
        if let (Some(s), Some(want)) = (s, want) {
            drawn += 1;
            let dir = |d: Vec3| [d.x, d.y, d.z].map(f64::to_bits);
            assert_eq!(dir(s.wi), dir(want.wi));
            assert_eq!(bits(s.f), bits(want.f));
            assert_eq!(s.pdf.to_bits(), want.pdf.to_bits());
            let alone = m.bsdf(&at, &mut BsdfScratch::default()).warp_share(wo);
            assert_eq!(vertex.warp_share(wo).to_bits(), alone.to_bits());
        }
    }
    assert!(drawn > 200, "only {drawn} draws succeeded");
}
