//! The footprint filter: fine weaves seen from afar render as the pattern's γ-mix without the
//! sampling noise of sub-pixel cells, close-ups keep their single yarns, and a plane receding to
//! the horizon shows no moiré (docs/render.md, "Fine weaves").

use std::path::Path;
use woven::material::{Material, PatternSpec, Weave};
use woven::table::cache::Cache;
use woven::table::TableOptions;
use woven::weave::Pattern;
use woven_render::render::{render, Image, RenderOptions};
use woven_render::scene::{Scene, SceneDescription};
use woven_render::woven_material::{TableCache, TableGrid};

/// A very coarse grid (about a second per table): these tests compare the renderer with itself.
pub fn tiny_grid() -> TableGrid {
    TableGrid::Custom(TableOptions {
        n_theta: 8,
        n_phi: 5,
        n_h: 17,
        n_h_isotropic: 33,
        ..TableOptions::default()
    })
}

/// The sateen's yarn in `pattern` (a preset pattern name), or with weft fraction `gamma`.
fn cloth(pattern: Option<&str>, gamma: f64) -> String {
    let mut m = Material::preset("polyester-sateen").unwrap();
    m.weave = Some(match pattern {
        Some(p) => Weave::Pattern {
            spec: PatternSpec::Name(p.into()),
            pattern: Pattern::from_name(p).unwrap(),
        },
        None => Weave::WeftFraction(gamma),
    });
    m.to_toml_string()
}

/// Renders `text` with material files `files` written in `dir`, keeping tables in `dir`.
fn render_with(dir: &Path, text: &str, files: &[(&str, String)]) -> Image {
    for (name, body) in files {
        std::fs::write(dir.join(name), body).unwrap();
    }
    let desc = SceneDescription::from_str(text, "<test>", dir).unwrap();
    let cache = TableCache::with_disk(Cache::new(dir.join("tables")));
    let scene = Scene::build_with(&desc, &tiny_grid(), cache, &|_| {}, &|_, _| {}).unwrap();
    let image = render(&scene, &RenderOptions::default()).unwrap();
    assert_eq!(image.invalid_samples, 0);
    image
}

/// A woven square under a point light seen by a `size`² camera from `origin`, direct light only.
fn plane(origin: [f64; 3], fov: f64, size: usize, spp: usize, filter: bool, cells: f64) -> String {
    format!(
        r#"
        [camera]
        origin = {origin:?}
        target = [0, 0, 0]
        fov_deg = {fov}
        [film]
        width = {size}
        height = {size}
        spp = {spp}
        sampler = "independent"
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
        material = "cloth"
        [material.cloth]
        type = "woven"
        material = "cloth.toml"
        yarns_per_unit = {cells}
        detail = "yarns"
        "#
    )
}

/// The mean per-sample variance of channel 0 over pixels whose mean is above `floor`.
fn sample_variance(image: &Image, floor: f64) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for (p, se) in image.pixels.iter().zip(&image.std_error) {
        if p.0[0] > floor {
            sum += se.0[0] * se.0[0] * image.spp as f64;
            n += 1;
        }
    }
    sum / n.max(1) as f64
}

/// (a) Far away (about 15 cells of a 2/1 twill per pixel) the filtered image is the image of the
/// γ = 1/3 macro BRDF (the pattern's own γ), sample for sample, and the per-pixel variance the weave adds at 8 spp (over the
/// macro BRDF's own, from light and angles varying across a pixel) is a small fraction of the
/// unfiltered image's, whose samples each see one random cell.
#[test]
fn a_distant_fine_weave_renders_as_the_gamma_mix_with_less_variance() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    let far = [0.0, -2.5, 2.5];
    let n = 48;
    let twill = [("twill.toml", cloth(Some("twill-2/1"), 0.0))];
    let mixed = [("mixed.toml", cloth(None, 1.0 / 3.0))];
    let scene =
        |spp, filter, file| plane(far, 45.0, n, spp, filter, 500.0).replace("cloth.toml", file);
    let filtered = render_with(dir, &scene(8, true, "twill.toml"), &twill);
    let unfiltered = render_with(dir, &scene(8, false, "twill.toml"), &twill);
    let macro_8 = render_with(dir, &scene(8, true, "mixed.toml"), &mixed);
    let mut lit = 0;
    for i in 0..n * n {
        // A footprint of many cells is the macro BRDF itself: the same samples, the same value.
        let (a, b) = (filtered.pixels[i].0[0], macro_8.pixels[i].0[0]);
        assert!(
            (a - b).abs() <= 1e-12 * b,
            "pixel {i}: filtered {a} vs γ-mix {b}"
        );
        lit += (b > 1e-3) as usize;
    }
    assert!(lit > n * n / 4, "only {lit} lit pixels");
    let (vf, vu, vm) = (
        sample_variance(&filtered, 1e-3),
        sample_variance(&unfiltered, 1e-3),
        sample_variance(&macro_8, 1e-3),
    );
    println!(
        "per-sample variance at 8 spp: filtered {vf:.3e}, unfiltered {vu:.3e}, γ-mix material {vm:.3e}; \
         the weave's excess: filtered {:.3e}, unfiltered {:.3e}",
        vf - vm,
        vu - vm
    );
    assert!(
        vu > 3.0 * vm,
        "the weave adds too little variance to test: {vu} vs {vm}"
    );
    assert!(
        (vf - vm).abs() < 0.02 * (vu - vm),
        "filtered {vf} vs unfiltered {vu} (γ-mix {vm})"
    );
}

/// (b) Close up (a cell spans about seven pixels) the filter changes nothing: the image is bit
/// for bit the unfiltered one, and single cells show (neighbouring cells differ).
#[test]
fn a_close_up_is_unchanged_by_the_filter() {
    let dir = tempfile::tempdir().unwrap();
    let near = [0.05, -0.25, 0.3];
    let twill = [("cloth.toml", cloth(Some("twill-2/1"), 0.0))];
    let a = render_with(dir.path(), &plane(near, 30.0, 32, 4, true, 20.0), &twill);
    let b = render_with(dir.path(), &plane(near, 30.0, 32, 4, false, 20.0), &twill);
    assert_eq!(a.pixels, b.pixels, "the filter changed a close-up");
    // The weave is visible: pixel values spread over more than a factor of 1.5.
    let v: Vec<f64> = a.pixels.iter().map(|p| p.0[0]).collect();
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    assert!(lo > 0.0 && hi > 1.5 * lo, "no cells visible: {lo}..{hi}");
}

/// (c) The anti-moiré demonstration (docs/render.md, "Fine weaves"): a sateen-5 plane of 5 cm
/// cells receding from 1 m to the horizon, a light to the side, 160 × 90 pixels. Against the
/// γ-mix image (the far field's alias-free look), where the footprint spans ≥ 2 cells: the
/// pixel RMS and the low-frequency (8 × 8-block mean) RMS of the unfiltered image at 64 spp,
/// of the unfiltered image converged (512 spp: the box filter's own aliasing) and of the
/// filtered image at 64 spp; where it spans < 0.5 cells, the filtered image against the
/// converged unfiltered one in standard errors. `WOVEN_MOIRE_OUT=dir` also writes the PNGs.
///
/// `cargo test --release -p woven-render --test integration moire -- --ignored --nocapture`
#[test]
#[ignore = "a demonstration with figures (~6 s on 2 cores); CI runs it"]
fn moire_demo_on_a_plane_receding_to_the_horizon() {
    use woven::Vec3;
    use woven_render::camera::Camera;
    use woven_render::geometry::Primitive;
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    let (w, h) = (160, 90);
    let scene = |file: &str, spp: usize, filter: bool| {
        format!(
            r#"
            [camera]
            origin = [0, 0, 0.3]
            target = [0, 3, 0]
            fov_deg = 40
            [film]
            width = {w}
            height = {h}
            spp = {spp}
            sampler = "independent"
            [integrator]
            max_depth = 2
            footprint_filter = {filter}
            [[light]]
            type = "point"
            position = [15, 12, 5]
            intensity = [1000, 1000, 1000]
            [[shape]]
            type = "rectangle"
            corner = [-60, -1, 0]
            edge_u = [120, 0, 0]
            edge_v = [0, 120, 0]
            material = "cloth"
            [material.cloth]
            type = "woven"
            material = "{file}"
            yarns_per_unit = 2400
            detail = "yarns"
            "#
        )
    };
    let sateen = cloth(Some("sateen-5"), 0.0);
    let gamma = Pattern::from_name("sateen-5").unwrap().weft_fraction();
    let files = [("sateen.toml", sateen), ("mixed.toml", cloth(None, gamma))];
    let unfiltered = render_with(dir, &scene("sateen.toml", 64, false), &files);
    let filtered = render_with(dir, &scene("sateen.toml", 64, true), &files);
    let converged = render_with(dir, &scene("sateen.toml", 512, false), &files);
    let mixed = render_with(dir, &scene("mixed.toml", 128, false), &files);
    if let Ok(out) = std::env::var("WOVEN_MOIRE_OUT") {
        // Top to bottom, each at twice the size: unfiltered at 64 spp, filtered at 64 spp,
        // unfiltered at 512 spp; 4-pixel white rules between.
        let (sw, sh, rule) = (2 * w, 2 * h, 4);
        let height = 3 * sh + 2 * rule;
        let mut pixels = vec![woven_render::Rgb::grey(1.0); sw * height];
        for (k, img) in [&unfiltered, &filtered, &converged].into_iter().enumerate() {
            for y in 0..sh {
                for x in 0..sw {
                    pixels[(k * (sh + rule) + y) * sw + x] = img.at(x / 2, y / 2) * 8.0;
                }
            }
        }
        let strip = Image {
            width: sw,
            height,
            std_error: vec![woven_render::Rgb::BLACK; sw * height],
            pixels,
            ..unfiltered.clone()
        };
        woven_render::output::write_png(
            &strip,
            &Path::new(&out).join("moire.png"),
            &woven_render::tonemap::Display::default(),
        )
        .unwrap();
    }

    // Each pixel's footprint in cells (at its centre), as the material measures it.
    let camera = Camera::new(
        Vec3::new(0.0, 0.0, 0.3),
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::Z,
        40.0,
        w,
        h,
    );
    let plane = Primitive::Rectangle {
        corner: Vec3::new(-60.0, -1.0, 0.0),
        edge_u: Vec3::new(120.0, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 120.0, 0.0),
    };
    let cells: Vec<f64> = (0..w * h)
        .map(|i| {
            let ray = camera.ray((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
            match plane.intersect(&ray, 0.0, f64::INFINITY, &[], 0) {
                None => f64::NAN,
                Some(hit) => {
                    let [a, b] = camera.footprint().uv(&ray, &hit);
                    2400.0 * (a[0].abs() + b[0].abs()).max(a[1].abs() + b[1].abs())
                }
            }
        })
        .collect();
    let far: Vec<usize> = (0..w * h).filter(|&i| cells[i] >= 2.0).collect();
    let near: Vec<usize> = (0..w * h).filter(|&i| cells[i] < 0.5).collect();
    let mean_m = far.iter().map(|&i| mixed.pixels[i].0[0]).sum::<f64>() / far.len() as f64;
    let rms = |img: &Image| {
        (far.iter()
            .map(|&i| (img.pixels[i].0[0] - mixed.pixels[i].0[0]).powi(2))
            .sum::<f64>()
            / far.len() as f64)
            .sqrt()
            / mean_m
    };
    // 8 × 8 blocks wholly in the far region: the RMS of their mean differences.
    let low = |img: &Image| {
        let (mut sum, mut n) = (0.0, 0);
        for by in 0..h / 8 {
            for bx in 0..w / 8 {
                let idx: Vec<usize> = (0..64)
                    .map(|k| (by * 8 + k / 8) * w + bx * 8 + k % 8)
                    .collect();
                if idx.iter().all(|&i| cells[i] >= 2.0) {
                    let d = idx
                        .iter()
                        .map(|&i| img.pixels[i].0[0] - mixed.pixels[i].0[0])
                        .sum::<f64>()
                        / 64.0;
                    sum += d * d;
                    n += 1;
                }
            }
        }
        ((sum / n.max(1) as f64).sqrt() / mean_m, n)
    };
    let se = |img: &Image, set: &[usize]| {
        set.iter().map(|&i| img.std_error[i].0[0]).sum::<f64>() / set.len() as f64 / mean_m
    };
    println!(
        "pixels: {} far (≥ 2 cells), {} near (< 0.5 cells), {} between; footprints {:.2}..{:.0} cells",
        far.len(),
        near.len(),
        cells.iter().filter(|c| c.is_finite()).count() - far.len() - near.len(),
        cells.iter().cloned().filter(|c| c.is_finite()).fold(f64::INFINITY, f64::min),
        cells.iter().cloned().filter(|c| c.is_finite()).fold(0.0, f64::max),
    );
    println!("far region, relative to the γ-mix image's mean {mean_m:.4}:");
    for (name, img) in [
        ("unfiltered, 64 spp", &unfiltered),
        ("unfiltered, 512 spp", &converged),
        ("filtered, 64 spp", &filtered),
    ] {
        let (l, blocks) = low(img);
        println!(
            "  {name:22} pixel RMS {:.4}  8x8-block RMS {:.4} ({blocks} blocks)  mean standard error {:.4}",
            rms(img),
            l,
            se(img, &far)
        );
    }
    // Against the converged unfiltered image, in standard errors: near, the filter keeps the
    // cells; between, it blends them toward the γ-mix.
    let z_rms = |img: &Image, set: &[usize]| {
        let sum: f64 = set
            .iter()
            .map(|&i| {
                let d = img.pixels[i].0[0] - converged.pixels[i].0[0];
                let s2 = img.std_error[i].0[0].powi(2) + converged.std_error[i].0[0].powi(2);
                if s2 > 0.0 {
                    d * d / s2
                } else {
                    0.0
                }
            })
            .sum();
        (sum / set.len().max(1) as f64).sqrt()
    };
    let between: Vec<usize> = (0..w * h)
        .filter(|&i| (0.5..2.0).contains(&cells[i]))
        .collect();
    for (name, set) in [("near", &near), ("between", &between)] {
        println!(
            "{name} region ({} pixels), against the unfiltered 512-spp image: RMS z of the filtered 64-spp image {:.2}, of the unfiltered one {:.2}",
            set.len(),
            z_rms(&filtered, set),
            z_rms(&unfiltered, set),
        );
    }
    let z2 = z_rms(&filtered, &near).powi(2);
    let (l_filtered, _) = low(&filtered);
    let (l_unfiltered, _) = low(&unfiltered);
    assert!(l_filtered < 0.5 * l_unfiltered);
    assert!(rms(&filtered) < 0.5 * rms(&unfiltered));
    assert!(near.is_empty() || z2.sqrt() < 1.5);
}
