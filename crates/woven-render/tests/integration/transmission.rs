//! Light straight through a gapped cloth (`transmission = true`): what passes is the open area
//! the yarns leave along the light's way (`woven::gaps::open_area`), in shadow rays and in
//! paths alike.

use crate::render_text;
use std::f64::consts::PI;
use woven::gaps::open_area;
use woven::Vec3;
use woven_render::camera::Camera;

const GAP: f64 = 0.35;

/// A 6 m square of woven cloth at height `z` in cells of 0.1 mm (a rectangle's uv spans its
/// edges), its material's other keys `keys` (TOML lines).
fn sheet(z: f64, keys: &str) -> String {
    format!(
        r#"
        [[shape]]
        type = "rectangle"
        corner = [-3, -3, {z}]
        edge_u = [6, 0, 0]
        edge_v = [0, 6, 0]
        material = "cloth"
        [material.cloth]
        type = "woven"
        yarns_per_unit = 60000
        {keys}
        "#
    )
}

/// A plain-weave linen [`sheet`] of gap [`GAP`] at height `z`, resolved as `detail` says.
fn cloth(z: f64, transmission: bool, detail: &str) -> String {
    sheet(
        z,
        &format!(
            "material = \"linen-plain\"\npattern = \"plain\"\ngap = {GAP}\n\
             transmission = {transmission}\ndetail = \"{detail}\""
        ),
    )
}

/// A diffuse floor lit by a point light through a gapped cloth above it, seen by a camera
/// between the two: each pixel is the floor's analytic radiance times the open area along the
/// way to the light. With transmission off the cloth is opaque and the floor black.
#[test]
fn light_through_a_gapped_cloth_reaches_the_floor_by_its_open_area() {
    let (w, h) = (12, 8);
    let (origin, light, intensity, rho) = (
        Vec3::new(0.0, -0.3, 0.45),
        Vec3::new(0.3, 0.2, 1.6),
        4.0,
        0.5,
    );
    let scene = |transmission: bool| {
        format!(
            r#"
            [camera]
            origin = [{}, {}, {}]
            target = [0, 0.1, 0]
            up = [0, 0, 1]
            fov_deg = 50
            [film]
            width = {w}
            height = {h}
            spp = 256
            seed = 5
            [integrator]
            max_depth = 2
            [[light]]
            type = "point"
            position = [{}, {}, {}]
            intensity = [{intensity}, {intensity}, {intensity}]
            [[shape]]
            type = "rectangle"
            corner = [-2, -2, 0]
            edge_u = [4, 0, 0]
            edge_v = [0, 4, 0]
            material = "floor"
            [material.floor]
            type = "diffuse"
            reflectance = [{rho}, {rho}, {rho}]
            {}
            "#,
            origin.x,
            origin.y,
            origin.z,
            light.x,
            light.y,
            light.z,
            cloth(0.5, transmission, "auto")
        )
    };
    let image = render_text(&scene(true));
    let camera = Camera::new(
        origin,
        Vec3::new(0.0, 0.1, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        50.0,
        w,
        h,
    );
    let n = 16;
    let (mut got_sum, mut want_sum, mut checked) = (0.0, 0.0, 0);
    for y in 0..h {
        for x in 0..w {
            let mut want = 0.0;
            for a in 0..n {
                for b in 0..n {
                    let ray = camera.ray(
                        x as f64 + (a as f64 + 0.5) / n as f64,
                        y as f64 + (b as f64 + 0.5) / n as f64,
                    );
                    let p = ray.o + ray.d * (-ray.o.z / ray.d.z);
                    let d = light - p;
                    let r2 = d.dot(d);
                    let to_light = d * (1.0 / r2.sqrt());
                    let open = open_area(GAP, to_light).unwrap();
                    want += rho / PI * intensity * to_light.z / r2 * open / (n * n) as f64;
                }
            }
            let got = image.at(x, y).0[1];
            let se = image.std_error[y * w + x].0[1];
            assert!(
                (got - want).abs() <= 5.0 * se + 1e-3 * want,
                "pixel ({x}, {y}): rendered {got} vs {want} (standard error {se})"
            );
            (got_sum, want_sum, checked) = (got_sum + got, want_sum + want, checked + 1);
        }
    }
    assert!(want_sum > 0.0 && checked == w * h);
    // Over the whole image the stochastic passes average out closely.
    assert!(
        (got_sum / want_sum - 1.0).abs() < 0.02,
        "{got_sum} {want_sum}"
    );
    let opaque = render_text(&scene(false));
    assert!(opaque.pixels.iter().all(|p| p.0 == [0.0; 3]));
}

/// A camera looking down through a gapped cloth at nothing but an even sky (emitters only,
/// `max_depth = 1`): each pixel is the open area along its rays, from far away (the cloth
/// level) and cell by cell (the yarn level, where the holes pass it; each pixel spans cells).
#[test]
fn the_sky_shows_through_a_gapped_cloth_by_its_open_area() {
    for (height, fov, detail) in [(8.0, 30.0, "auto"), (0.02, 60.0, "yarns")] {
        let (w, h) = (10, 10);
        let origin = Vec3::new(0.0, -0.4 * height, height);
        let text = format!(
            r#"
            [camera]
            origin = [{}, {}, {}]
            target = [0, 0, 0]
            up = [0, 1, 0]
            fov_deg = {fov}
            [film]
            width = {w}
            height = {h}
            spp = 256
            seed = 2
            [integrator]
            max_depth = 1
            [[light]]
            type = "environment"
            radiance = [1, 1, 1]
            {}
            "#,
            origin.x,
            origin.y,
            origin.z,
            cloth(0.0, true, detail)
        );
        let image = render_text(&text);
        let camera = Camera::new(
            origin,
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            fov,
            w,
            h,
        );
        let (mut got, mut want) = (0.0, 0.0);
        for y in 0..h {
            for x in 0..w {
                let ray = camera.ray(x as f64 + 0.5, y as f64 + 0.5);
                want += open_area(GAP, -ray.d).unwrap();
                got += image.at(x, y).0[0];
            }
        }
        assert!(
            (got / want - 1.0).abs() < 0.03,
            "camera at {height}: rendered {got} vs open area {want}"
        );
    }
}

/// A white furnace through a two-sided sheet: a white linen (its fibres absorb nothing) with
/// gaps, transmission on, hanging in an even sky of radiance 1. What it reflects, passes and
/// transmits through its yarns adds to what arrives, so every pixel is 1 (within the albedo
/// table's 2 % and the noise); dyed, the yarns absorb, and no pixel exceeds 1.
#[test]
fn a_white_transmitting_sheet_vanishes_in_a_furnace() {
    for (dye, low, high) in [(1.0, 0.975, 1.01), (0.4, 0.3, 1.0)] {
        let text = format!(
            r#"
            [camera]
            origin = [0.4, -2.0, 1.5]
            target = [0, 0, 0]
            up = [0, 0, 1]
            fov_deg = 20
            [film]
            width = 8
            height = 8
            spp = 1024
            seed = 9
            [integrator]
            max_depth = 8
            [[light]]
            type = "environment"
            radiance = [1, 1, 1]
            {}
            "#,
            sheet(
                0.0,
                &format!(
                    "material = \"linen-plain\"\npattern = \"plain\"\ngap = 0.3\n\
                     weft_color = [{dye}, {dye}, {dye}]\nwarp_color = [{dye}, {dye}, {dye}]\n\
                     transmission = true"
                ),
            )
        );
        let image = render_text(&text);
        let mean = image.pixels.iter().map(|p| p.0[1]).sum::<f64>() / image.pixels.len() as f64;
        let brightest = image.pixels.iter().map(|p| p.0[1]).fold(0.0, f64::max);
        println!("dye {dye}: mean {mean:.4}, brightest pixel {brightest:.4}");
        for (p, se) in image.pixels.iter().zip(&image.std_error) {
            assert!(
                p.0[1] <= high + 4.0 * se.0[1],
                "dye {dye}: a pixel of {} (standard error {})",
                p.0[1],
                se.0[1]
            );
        }
        assert!(
            mean >= low && mean <= high,
            "dye {dye}: the sheet's mean {mean}"
        );
    }
}

/// A cloth that lets light through, met from behind, is shaded as its back: the pattern's
/// complement (a weft-faced satin's back is warp-faced), turned over about the weft. The back of
/// a satin `P`, seen from below, renders as the front of `1 − P` seen from above in the scene
/// turned by π about the weft (`x`): the same image, pixel for pixel within the noise.
#[test]
fn a_cloth_met_from_behind_shows_its_back() {
    let satin: Vec<Vec<u8>> = (0..5)
        .map(|r| (0..5).map(|c| u8::from(c != (2 * r) % 5)).collect())
        .collect();
    let back: Vec<Vec<u8>> = satin
        .iter()
        .map(|row| row.iter().map(|c| 1 - c).collect())
        .collect();
    // `side` 1: the camera above, looking down, the light low from +x; −1: the scene turned
    // over (below). Lit across the weft, a warp-faced satin shows its warp's sheen toward the
    // camera and a weft-faced one hardly any.
    let render = |pattern: &[Vec<u8>], side: f64| {
        let text = format!(
            r#"
            [camera]
            origin = [0, 0, {}]
            target = [0, 0, 0]
            up = [0, {}, 0]
            fov_deg = 40
            [film]
            width = 8
            height = 8
            spp = 256
            seed = 4
            [integrator]
            max_depth = 2
            [[light]]
            type = "point"
            position = [2, 0, {}]
            intensity = [10, 10, 10]
            {}
            "#,
            2.0 * side,
            side,
            side,
            sheet(
                0.0,
                &format!(
                    "material = \"filament-satin\"\npattern = {pattern:?}\ngap = 0.1\n\
                     transmission = true"
                ),
            ),
        );
        let image = render_text(&text);
        (0..8 * 8)
            .map(|i| image.at(i % 8, i / 8).luminance())
            .collect::<Vec<f64>>()
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    // The satin's back from below, the complement's front from above.
    let (below, above) = (render(&satin, -1.0), render(&back, 1.0));
    let front = render(&satin, 1.0);
    let (b, a, f) = (mean(&below), mean(&above), mean(&front));
    assert!(
        (b / a - 1.0).abs() < 0.03,
        "back from below {b}, its front from above {a}"
    );
    // The two faces differ: the test would see the front shown from behind. The warp's sheen
    // is a band across the middle of the image (the viewers on its specular cone).
    let peak = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    let (pa, pf) = (peak(&above), peak(&front));
    println!("means: below {b}, above {a}, front {f}; peaks: above {pa}, front {pf}");
    assert!(pa > 1.5 * pf, "the back's peak {pa}, the front's {pf}");
}
