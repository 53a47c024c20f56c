//! Renderer throughput: camera samples per second on small scenes (criterion reports
//! elements/s = samples/s).
//!
//! `cargo bench -p woven-render --bench render` (`-- "showcase detail"` for the levels of detail
//! alone, `-- "tilted sateen"` for cloth at real thread counts against its yarn-level twin,
//! `-- curtains` for light through cloth against the same cloths opaque)

// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use std::path::Path;
use woven::table::cache::Cache;
use woven::table::TableOptions;
use woven_render::render::{render, RenderOptions};
use woven_render::scene::{Scene, SceneDescription, SHOWCASE_SCENE};
use woven_render::woven_material::{TableCache, TableGrid};

/// The issue's scene (ii) at 64 × 64, 16 spp: a flat woven fiber plane (Mitsuba's
/// `roughplastic` equivalent) under a point light, direct lighting; the same plane diffuse; and
/// the sateen's yarn in a fine 2/1 twill (about 30 cells a pixel), with the footprint filter
/// (the pattern's γ-mix, two look-ups a point) and without (one look-up of the cell's yarn).
/// `sampler`: the film's (the default Sobol points; the fiber plane also with independent
/// samples, for the Sobol points' cost).
fn scene(material: &str, filter: bool, sampler: &str) -> String {
    format!(
        r#"
        [camera]
        origin = [0, -2.5, 2.5]
        target = [0, 0, 0]
        up = [0, 0, 1]
        fov_deg = 45
        [film]
        width = 64
        height = 64
        spp = 16
        sampler = "{sampler}"
        [integrator]
        max_depth = 2
        footprint_filter = {filter}
        [[light]]
        type = "point"
        position = [0.4, 0.5, 1.5]
        intensity = [10, 10, 10]
        [[shape]]
        type = "rectangle"
        corner = [-1, -1, 0]
        edge_u = [2, 0, 0]
        edge_v = [0, 2, 0]
        material = "plane"
        {material}
        "#
    )
}

fn bench(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("woven-render-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("fiber.toml"),
        "[fiber]\neta = 1.6\nroughness = 0.1\ndiffuse = 0\nnormalization = \"none\"\n",
    )
    .unwrap();
    let twill = "[material.plane]\ntype = \"woven\"\nmaterial = \"polyester-sateen\"\n\
                 pattern = \"twill-2/1\"\nyarns_per_unit = 1000";
    let fiber = "[material.plane]\ntype = \"woven\"\nmaterial = \"fiber.toml\"";
    let cases = [
        (
            "diffuse plane",
            "[material.plane]\ntype = \"diffuse\"\nreflectance = [0.5, 0.5, 0.5]",
            true,
            "sobol",
        ),
        ("woven fiber plane", fiber, true, "sobol"),
        (
            "woven fiber plane, independent samples",
            fiber,
            true,
            "independent",
        ),
        ("fine twill plane, filtered", twill, true, "sobol"),
        ("fine twill plane, unfiltered", twill, false, "sobol"),
    ];
    let grid = TableGrid::Custom(TableOptions {
        n_theta: 24,
        n_h_isotropic: 81,
        ..TableOptions::default()
    });
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    for (name, material, filter, sampler) in cases {
        let text = scene(material, filter, sampler);
        let desc = SceneDescription::from_str(&text, name, Path::new(&dir)).unwrap();
        // The twill's yarn on the renderer's grid, built once (kept in the bench's folder).
        let (grid, cache) = if material == twill {
            (
                &TableGrid::Default,
                TableCache::with_disk(Cache::new(dir.join("tables"))),
            )
        } else {
            (&grid, TableCache::default())
        };
        let scene = Scene::build_with(&desc, grid, cache, &|_| {}, &|_, _| {}).unwrap();
        group.throughput(Throughput::Elements(64 * 64 * 16));
        group.bench_function(name, |b| {
            b.iter(|| render(&scene, &RenderOptions::default()).unwrap())
        });
    }
    group.finish();
    std::fs::remove_dir_all(&dir).ok();
}

/// The user's table cache (in memory only when it has none).
fn user_cache() -> TableCache {
    match Cache::user() {
        Ok(c) => TableCache::with_disk(c),
        Err(_) => TableCache::default(),
    }
}

/// Renders `desc` on the renderer's default tables (from the user's table cache) as bench `name`
/// of `group`, its throughput in camera samples.
fn bench_scene(group: &mut BenchmarkGroup<WallTime>, name: &str, desc: &SceneDescription) {
    let scene =
        Scene::build_with(desc, &TableGrid::Default, user_cache(), &|_| {}, &|_, _| {}).unwrap();
    let samples = desc.film.width * desc.film.height * desc.film.spp;
    group.throughput(Throughput::Elements(samples as u64));
    group.bench_function(name, |b| {
        b.iter(|| render(&scene, &RenderOptions::default()).unwrap())
    });
}

/// The built-in showcase at its own 960 × 540, one sample a pixel, on the renderer's default
/// tables (from the user's table cache, built there on the first run): as it is (`detail =
/// "auto"`), and with every woven material at `"fibers"` and at `"yarns"` — the cost per sample
/// of resolving yarns in space (the denoiser off: samples alone).
fn detail(c: &mut Criterion) {
    let mut group = c.benchmark_group("showcase detail");
    group.sample_size(10);
    for level in ["auto", "fibers", "yarns"] {
        let text = SHOWCASE_SCENE.replace(
            "type = \"woven\"",
            &format!("type = \"woven\"\ndetail = \"{level}\""),
        );
        let mut desc = SceneDescription::from_str(&text, "showcase", Path::new(".")).unwrap();
        desc.film.spp = 1;
        desc.film.denoise = false;
        bench_scene(&mut group, level, &desc);
    }
    group.finish();
}

/// The tilted sateen plane at real thread counts (0.2 mm yarns: cloth level everywhere, the
/// tilted yarns' macro BRDF) and its yarn-level twin with cells 100 times larger
/// (scenes/speed/tilted-sateen*.toml, which `scripts/mitsuba/speed.sh` renders at full size) at
/// 160 × 120, one sample a pixel, on the renderer's default tables (from the user's table cache):
/// what a tilted cloth costs a sample.
fn tilted(c: &mut Criterion) {
    let mut group = c.benchmark_group("tilted sateen");
    group.sample_size(10);
    let scenes = [
        (
            "cloth level",
            include_str!("../../../scenes/speed/tilted-sateen.toml"),
        ),
        (
            "yarn level",
            include_str!("../../../scenes/speed/tilted-sateen-yarns.toml"),
        ),
    ];
    for (name, text) in scenes {
        let mut desc = SceneDescription::from_str(text, name, Path::new(".")).unwrap();
        (desc.film.width, desc.film.height, desc.film.spp) = (160, 120, 1);
        bench_scene(&mut group, name, &desc);
    }
    group.finish();
}

/// The curtains before a sunlit window (scenes/docs/curtains.toml) at 240 × 135, four samples a
/// pixel, as they are (both curtains passing light between their yarns) and with `transmission`
/// off (the same cloths opaque): what light through cloth costs a sample.
fn transmission(c: &mut Criterion) {
    let mut group = c.benchmark_group("curtains");
    group.sample_size(10);
    let text = include_str!("../../../scenes/docs/curtains.toml");
    for (name, text) in [
        ("transmitting", text.to_string()),
        (
            "opaque",
            text.replace("transmission = true", "transmission = false"),
        ),
    ] {
        let mut desc = SceneDescription::from_str(&text, name, Path::new(".")).unwrap();
        (desc.film.width, desc.film.height, desc.film.spp) = (240, 135, 4);
        desc.film.denoise = false;
        desc.inset = None;
        bench_scene(&mut group, name, &desc);
    }
    group.finish();
}

criterion_group!(benches, bench, detail, tilted, transmission);
criterion_main!(benches);
