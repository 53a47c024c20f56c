//! Scene-file errors name the file, the key and the line; unknown keys are errors.

use std::path::Path;
use woven_render::scene::{SceneDescription, EXAMPLE_SCENE, SHOWCASE_SCENE};
use woven_render::Error;

fn error_of(text: &str) -> (String, String, Option<usize>, String) {
    match SceneDescription::from_str(text, "scene.toml", Path::new(".")) {
        Err(Error::Scene {
            path,
            key,
            line,
            message,
        }) => (path, key, line, message),
        Err(e) => panic!("not a scene error: {e}"),
        Ok(_) => panic!("accepted:\n{text}"),
    }
}

const MINIMAL: &str = r#"
[camera]
origin = [0, -3, 1]
target = [0, 0, 0]
fov_deg = 40
"#;

#[test]
fn unknown_keys_are_rejected_with_file_key_and_line() {
    let text = format!("{MINIMAL}[film]\nwidth = 64\nwidht = 32\n");
    let (path, key, line, message) = error_of(&text);
    assert_eq!(path, "scene.toml");
    assert_eq!(key, "film.widht");
    assert_eq!(line, Some(8));
    assert!(message.contains("unknown field"), "{message}");

    let text = format!(
        "{MINIMAL}[[shape]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\ncolour = 3\n"
    );
    let (_, key, line, message) = error_of(&text);
    assert!(message.contains("colour"), "{message}");
    assert!(
        line.is_some_and(|l| (6..=11).contains(&l)),
        "{key} {line:?}"
    );

    let (_, key, _, _) = error_of(&format!("{MINIMAL}[lights]\n"));
    assert_eq!(key, "lights");
}

#[test]
fn invalid_values_name_the_key_and_line() {
    let text = format!(
        "{MINIMAL}[[shape]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = -1\nmaterial = \"m\"\n[material.m]\ntype = \"diffuse\"\nreflectance = [0.5, 0.5, 0.5]\n"
    );
    let (_, key, line, message) = error_of(&text);
    assert_eq!(key, "shape[0].radius");
    assert_eq!(line, Some(6));
    assert!(
        message.contains("-1") && message.contains("> 0"),
        "{message}"
    );

    let text = format!(
        "{MINIMAL}[[shape]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"nope\"\n"
    );
    let (_, key, _, message) = error_of(&text);
    assert_eq!(key, "shape[0].material");
    assert!(message.contains("nope"), "{message}");

    let text =
        format!("{MINIMAL}[material.m]\ntype = \"diffuse\"\nreflectance = [0.5, 1.5, 0.5]\n");
    let (_, key, line, message) = error_of(&text);
    assert_eq!(key, "material.m.reflectance");
    assert_eq!(line, Some(6));
    assert!(message.contains("[0, 1]"), "{message}");

    let text = MINIMAL.replace("fov_deg = 40", "fov_deg = 180");
    let (_, key, line, _) = error_of(&text);
    assert_eq!((key.as_str(), line), ("camera.fov_deg", Some(2)));

    let text = format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"velvet\"\n");
    let (_, key, _, message) = error_of(&text);
    assert_eq!(key, "material.m.material");
    assert!(message.contains("velvet"), "{message}");

    let text = format!(
        "{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"silk\"\npattern = \"satin-4\"\n"
    );
    let (_, key, _, _) = error_of(&text);
    assert_eq!(key, "material.m.pattern");

    // Out of range, or so large that two lights' weights would sum to infinity.
    for weight in ["0", "-2", "inf", "1e308"] {
        let text = format!(
            "{MINIMAL}[[light]]\ntype = \"point\"\nposition = [0, 0, 1]\nintensity = [1, 1, 1]\nsampling_weight = {weight}\n"
        );
        let (_, key, line, message) = error_of(&text);
        assert_eq!((key.as_str(), line), ("light[0].sampling_weight", Some(6)));
        assert!(
            message.contains(weight) && message.contains("[1e-12, 1e12]"),
            "{message}"
        );
    }

    let (_, key, line, message) = error_of("[camera]\norigin = [0, 0, 1]\nfov_deg = 4 0\n");
    assert_eq!(
        (key.as_str(), line),
        ("camera.fov_deg", Some(3)),
        "{message}"
    );
}

/// The scenes the crate ships parse.
#[test]
fn example_and_showcase_scenes_parse() {
    for text in [EXAMPLE_SCENE, SHOWCASE_SCENE] {
        let desc = SceneDescription::from_str(text, "<builtin>", Path::new(".")).unwrap();
        assert!(!desc.shapes.is_empty() && !desc.lights.is_empty());
    }
}

/// The yarn options: `u_max_deg` and `gap` out of range, or on a flat fiber surface, name the
/// file, the key, the value and the range; in range they reach the material, and
/// `footprint_filter` defaults to on.
#[test]
fn yarn_tilt_gap_and_filter_keys() {
    let woven = |extra: &str| {
        format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"silk\"\n{extra}\n")
    };
    for (extra, key, needle) in [
        ("u_max_deg = 95", "material.m.u_max_deg", "[0, 80]"),
        ("u_max_deg = -1", "material.m.u_max_deg", "[0, 80]"),
        ("gap = 1.5", "material.m.gap", "[0, 0.95]"),
        ("gap = nan", "material.m.gap", "[0, 0.95]"),
    ] {
        let (path, k, line, message) = error_of(&woven(extra));
        assert_eq!(
            (path.as_str(), k.as_str(), line),
            ("scene.toml", key, Some(6))
        );
        let value = extra.split(" = ").nth(1).unwrap();
        assert!(
            message.contains(needle) && message.to_lowercase().contains(value),
            "{message}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("fiber.toml"),
        "[fiber]\neta = 1.6\nroughness = 0.1\ndiffuse = 0\nnormalization = \"none\"\n",
    )
    .unwrap();
    let text =
        format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"fiber.toml\"\ngap = 0.1\n");
    let Err(Error::Scene { key, message, .. }) =
        SceneDescription::from_str(&text, "scene.toml", dir.path())
    else {
        panic!("a gap on a flat fiber surface was accepted");
    };
    assert_eq!(key, "material.m.gap", "{message}");
    assert!(message.contains("no [yarn]"), "{message}");

    let desc = SceneDescription::from_str(
        &woven("u_max_deg = 30\ngap = 0.25"),
        "scene.toml",
        Path::new("."),
    )
    .unwrap();
    let Some(woven_render::scene::MaterialDesc::Woven(spec)) = desc.materials.get("m") else {
        panic!("no woven material");
    };
    assert!((spec.u_max - 30f64.to_radians()).abs() < 1e-15 && spec.gap == 0.25);
    assert!(desc.integrator.footprint_filter);
    let off = format!("{MINIMAL}[integrator]\nfootprint_filter = false\n");
    let desc = SceneDescription::from_str(&off, "scene.toml", Path::new(".")).unwrap();
    assert!(!desc.integrator.footprint_filter);
}

/// A woven material's keys take the library's defaults where not given (the surface
/// `SurfaceSpec::new` lays, with `DEFAULT_YARNS_PER_UNIT` cells per unit), and a bad `detail`
/// names the key, the value and the library's names.
#[test]
fn woven_keys_take_the_librarys_defaults_and_names() {
    use woven::surface::{Detail, SurfaceSpec, DEFAULT_YARNS_PER_UNIT};
    let woven = |extra: &str| {
        format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"silk\"\n{extra}\n")
    };
    let desc = SceneDescription::from_str(&woven(""), "scene.toml", Path::new(".")).unwrap();
    let Some(woven_render::scene::MaterialDesc::Woven(spec)) = desc.materials.get("m") else {
        panic!("no woven material");
    };
    let library = SurfaceSpec::new(woven::material::Material::preset("silk").unwrap());
    assert_eq!(spec.yarns_per_unit, [DEFAULT_YARNS_PER_UNIT; 2]);
    assert_eq!(spec.yarns_per_unit, library.yarns_per_unit);
    assert_eq!(
        (spec.u_max, spec.gap, spec.detail, spec.irregularity),
        (
            library.u_max,
            library.gap,
            library.detail,
            library.irregularity
        )
    );
    assert_eq!(
        (spec.weft_color, spec.warp_color),
        (library.weft_color, library.warp_color)
    );

    let (path, key, line, message) = error_of(&woven("detail = \"threads\""));
    assert_eq!(
        (path.as_str(), key.as_str(), line),
        ("scene.toml", "material.m.detail", Some(6))
    );
    assert!(message.contains("\"threads\""), "{message}");
    for name in Detail::NAMES {
        assert!(message.contains(&format!("{name:?}")), "{message}");
    }
}

/// The example scene (`woven render --example`) states each woven key's numeric default and
/// range in its comments as the library's table of surface keys has them.
#[test]
fn the_example_scene_states_the_librarys_surface_defaults_and_ranges() {
    use woven::surface::SURFACE_KEYS;
    // The example's first woven material, where every key is shown.
    let all: Vec<&str> = EXAMPLE_SCENE.lines().collect();
    let start = (0..all.len())
        .find(|&i| all[i].starts_with("[material.") && all[i + 1] == "type = \"woven\"")
        .expect("a woven material in the example");
    let end = (start + 1..all.len())
        .find(|&i| all[i].starts_with('['))
        .unwrap_or(all.len());
    let lines = &all[start..end];
    let mut checked = 0;
    for key in SURFACE_KEYS {
        let Some(at) = lines.iter().position(|l| {
            let l = l.trim_start_matches('#').trim_start();
            l.starts_with(&format!("{} = ", key.name)) && l.contains('#')
        }) else {
            continue;
        };
        // The key's comment, and the comment lines that continue it (`#   …   # …`).
        let mut comment = lines[at].to_string();
        for l in &lines[at + 1..] {
            let rest = l.strip_prefix('#').unwrap_or("");
            if !(rest.starts_with("     ") && rest.trim_start().starts_with('#')) {
                break;
            }
            comment += l;
        }
        if let Ok(d) = key.default().parse::<f64>() {
            assert!(
                comment.contains(&format!("default {d}")),
                "{}: {comment}",
                key.name
            );
        }
        let valid = key.valid();
        if let Some(start) = valid.find('[') {
            let interval = &valid[start..=start + valid[start..].find(']').unwrap()];
            assert!(
                comment.contains(interval),
                "{}: {interval} in {comment}",
                key.name
            );
        }
        if key.name == "detail" {
            for name in woven::surface::Detail::NAMES {
                assert!(comment.contains(&format!("{name:?}")), "{comment}");
            }
        }
        checked += 1;
    }
    assert!(checked >= 6, "{checked} keys found in the example");
}

/// `irregularity` and `irregularity_length`: out of range, or without a pattern, they name the
/// key and the range; in range (one number or one per family) they reach the material.
#[test]
fn irregularity_keys() {
    let woven = |extra: &str| {
        format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"silk\"\n{extra}\n")
    };
    for (extra, key, needle) in [
        ("irregularity = 1.5", "material.m.irregularity", "[0, 1]"),
        (
            "irregularity = [0.2, -1]",
            "material.m.irregularity",
            "[0, 1]",
        ),
        (
            "irregularity = 0.2\nirregularity_length = 0.5",
            "material.m.irregularity_length",
            "[1, 1e6]",
        ),
    ] {
        let (_, k, _, message) = error_of(&woven(extra));
        assert_eq!(k, key, "{message}");
        assert!(message.contains(needle), "{message}");
    }
    // The sateen preset is a weft fraction, no pattern: no yarns to vary one by one.
    let sateen = format!(
        "{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"polyester-sateen\"\nirregularity = 0.2\n"
    );
    let (_, k, _, message) = error_of(&sateen);
    assert_eq!(k, "material.m.irregularity", "{message}");
    assert!(message.contains("pattern"), "{message}");

    let desc = SceneDescription::from_str(
        &woven("irregularity = [0.1, 0.4]\nirregularity_length = 60"),
        "scene.toml",
        Path::new("."),
    )
    .unwrap();
    let Some(woven_render::scene::MaterialDesc::Woven(spec)) = desc.materials.get("m") else {
        panic!("no woven material");
    };
    assert_eq!(spec.irregularity.spread, [0.1, 0.4]);
    assert_eq!(spec.irregularity.length, 60.0);
}

/// A cloth draped over a sphere: `drape = "sphere"` needs `center` and `radius`; they are errors
/// on a folded cloth, as is an unknown drape.
#[test]
fn draped_cloth_keys() {
    let cloth = |extra: &str| {
        format!(
            "{MINIMAL}[[shape]]\ntype = \"cloth\"\ncorner = [-1, -1, 1]\nedge_u = [2, 0, 0]\nedge_v = [0, 2, 0]\nmaterial = \"m\"\n{extra}\n[material.m]\ntype = \"diffuse\"\nreflectance = [0.5, 0.5, 0.5]\n"
        )
    };
    for (extra, key, needle) in [
        (
            "drape = \"sphere\"\nradius = 0.5",
            "shape[0].center",
            "missing",
        ),
        (
            "drape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0",
            "shape[0].radius",
            "> 0",
        ),
        ("drape = \"table\"", "shape[0].drape", "table"),
        ("radius = 0.5", "shape[0].radius", "drape = \"sphere\""),
    ] {
        let (_, k, line, message) = error_of(&cloth(extra));
        assert_eq!((k.as_str(), line), (key, Some(6)), "{message}");
        assert!(message.contains(needle), "{message}");
    }
    let desc = SceneDescription::from_str(
        &cloth("drape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0.5\nfolds = 8"),
        "scene.toml",
        Path::new("."),
    )
    .unwrap();
    assert!(matches!(
        desc.shapes[0].0,
        woven_render::scene::ShapeDesc::Drape(d) if d.radius == 0.5 && d.folds == 8.0
    ));
}

/// `type = "sky"`: its keys reach the description with [`SkyParams`]' defaults; a value out of
/// range names the file, the key, the value and the range; a sky is the scene's one environment.
#[test]
fn sky_light_keys() {
    use woven_render::scene::LightDesc;
    use woven_render::sky::SkyParams;
    let sky = |extra: &str| format!("{MINIMAL}[[light]]\ntype = \"sky\"\n{extra}\n");
    let desc = SceneDescription::from_str(&sky(""), "scene.toml", Path::new(".")).unwrap();
    assert!(
        matches!(desc.lights[..], [LightDesc::Sky { params }] if params == SkyParams::default()),
        "{:?}",
        desc.lights
    );
    let text = sky(
        "sun_elevation_deg = 20\nsun_azimuth_deg = -30\nturbidity = 6\nscale = 0.5\nsun = false",
    );
    let desc = SceneDescription::from_str(&text, "scene.toml", Path::new(".")).unwrap();
    let expected = SkyParams {
        sun_elevation_deg: 20.0,
        sun_azimuth_deg: -30.0,
        turbidity: 6.0,
        scale: 0.5,
        sun: false,
    };
    assert!(
        matches!(desc.lights[..], [LightDesc::Sky { params }] if params == expected),
        "{:?}",
        desc.lights
    );

    for (extra, key, value, range) in [
        ("turbidity = 12", "light[0].turbidity", "12", "[2, 10]"),
        ("turbidity = 1", "light[0].turbidity", "1", "[2, 10]"),
        (
            "sun_elevation_deg = -10",
            "light[0].sun_elevation_deg",
            "-10",
            "[0, 90]",
        ),
        (
            "sun_elevation_deg = 95",
            "light[0].sun_elevation_deg",
            "95",
            "[0, 90]",
        ),
        (
            "sun_azimuth_deg = nan",
            "light[0].sun_azimuth_deg",
            "NaN",
            "finite",
        ),
        ("scale = -1", "light[0].scale", "-1", ">= 0"),
    ] {
        let (path, k, line, message) = error_of(&sky(extra));
        assert_eq!(
            (path.as_str(), k.as_str(), line),
            ("scene.toml", key, Some(6)),
            "{message}"
        );
        assert!(
            message.contains(value) && message.contains(range),
            "{message}"
        );
    }
    let (_, key, _, message) = error_of(&sky("sun = 1"));
    assert!(
        key.contains("sun") || message.contains("bool"),
        "{key}: {message}"
    );
    let (_, key, _, message) = error_of(&sky("colour = 1"));
    assert!(message.contains("colour"), "{key}: {message}");

    let text = format!(
        "{}[[light]]\ntype = \"environment\"\nradiance = [1, 1, 1]\n",
        sky("")
    );
    let (_, key, _, message) = error_of(&text);
    assert_eq!(key, "light[1]");
    assert!(message.contains("at most one"), "{message}");
}

/// A diffuse plane (ρ = 0.5) under a sky, seen from above, has radiance `ρ/π · E`, `E` the
/// horizontal irradiance of the sky's map (sun included) summed pixel by pixel: the scene builds
/// the map the library makes, in the environment's layout, and importance samples its sun.
#[test]
fn sky_lights_a_diffuse_plane_as_its_map_says() {
    use std::f64::consts::PI;
    use woven_render::sky::{sky_image, SkyParams, SKY_MAP_HEIGHT, SKY_MAP_WIDTH};
    let text = r#"
        [camera]
        origin = [0, 0, 1]
        target = [0, 0, 0]
        up = [0, 1, 0]
        fov_deg = 20
        [film]
        width = 4
        height = 4
        spp = 256
        [integrator]
        max_depth = 2
        [[light]]
        type = "sky"
        sun_elevation_deg = 50
        sun_azimuth_deg = 120
        turbidity = 3
        scale = 0.03
        [[shape]]
        type = "rectangle"
        corner = [-2, -2, 0]
        edge_u = [4, 0, 0]
        edge_v = [0, 4, 0]
        material = "grey"
        [material.grey]
        type = "diffuse"
        reflectance = [0.5, 0.5, 0.5]
    "#;
    let image = crate::render_text(text);
    let params = SkyParams {
        sun_elevation_deg: 50.0,
        sun_azimuth_deg: 120.0,
        turbidity: 3.0,
        scale: 0.03,
        sun: true,
    };
    let map = sky_image(&params, SKY_MAP_WIDTH, SKY_MAP_HEIGHT).unwrap();
    let (w, h) = (map.width, map.height);
    let mut irradiance = [0.0; 3];
    for y in 0..h {
        let (t0, t1) = (y as f64 * PI / h as f64, (y + 1) as f64 * PI / h as f64);
        // ∫ cos θ dω over a pixel of the row (below the horizon the map is black).
        let weight = 0.5 * (t1.sin().powi(2) - t0.sin().powi(2)) * 2.0 * PI / w as f64;
        for p in &map.pixels[y * w..(y + 1) * w] {
            for c in 0..3 {
                irradiance[c] += p.0[c] * weight;
            }
        }
    }
    let n = image.pixels.len() as f64;
    for c in 0..3 {
        let expected = 0.5 / PI * irradiance[c];
        let mean = image.pixels.iter().map(|p| p.0[c]).sum::<f64>() / n;
        let se = image
            .std_error
            .iter()
            .map(|s| s.0[c].powi(2))
            .sum::<f64>()
            .sqrt()
            / n;
        assert!(
            (mean - expected).abs() < 4.0 * se + 1e-3 * expected,
            "channel {c}: {mean} ± {se} vs ρ/π E = {expected}"
        );
    }
}

/// `[film] exposure` and `tonemap`: defaults, values reaching the film, errors naming the key.
#[test]
fn film_display_keys() {
    use woven_render::tonemap::{Display, ToneMap};
    let parse = |extra: &str| {
        SceneDescription::from_str(
            &format!("{MINIMAL}[film]\nwidth = 8\n{extra}"),
            "scene.toml",
            Path::new("."),
        )
    };
    assert_eq!(parse("").unwrap().film.display, Display::default());
    assert_eq!(Display::default().tonemap, ToneMap::Filmic);
    let film = parse("exposure = -1.5\ntonemap = \"clamp\"\n")
        .unwrap()
        .film;
    assert_eq!(film.display.exposure, -1.5);
    assert_eq!(film.display.tonemap, ToneMap::Clamp);

    let (_, key, line, message) = error_of(&format!("{MINIMAL}[film]\nwidth = 8\nexposure = 40\n"));
    assert_eq!((key.as_str(), line), ("film.exposure", Some(6)));
    assert!(
        message.contains("40") && message.contains("[-20, 20]"),
        "{message}"
    );
    let (_, key, _, message) = error_of(&format!("{MINIMAL}[film]\ntonemap = \"aces\"\n"));
    assert!(key.contains("tonemap"), "{key}");
    assert!(
        message.contains("filmic") && message.contains("clamp"),
        "{message}"
    );

    // Denoising: off unless asked for.
    assert!(!parse("").unwrap().film.denoise);
    assert!(parse("denoise = true\n").unwrap().film.denoise);
    let (_, key, _, _) = error_of(&format!("{MINIMAL}[film]\ndenoise = \"yes\"\n"));
    assert!(key.contains("denoise"), "{key}");
}

/// `[inset]` and built-in meshes: values reach the description; errors name the key, the value
/// and what was expected.
#[test]
fn inset_and_builtin_mesh_keys() {
    let inset = "[inset]\norigin = [1, 1, 1]\ntarget = [0, 0, 0]\nfov_deg = 20\ncorner = [0.6, 0.1]\nsize = [0.3, 0.4]\n";
    let desc =
        SceneDescription::from_str(&format!("{MINIMAL}{inset}"), "s.toml", Path::new(".")).unwrap();
    let i = desc.inset.unwrap();
    assert_eq!((i.corner, i.size, i.border), ([0.6, 0.1], [0.3, 0.4], 3));
    let r = i.pixels([100, 50]);
    assert_eq!(r.outer, ([60, 5], [30, 20]));
    assert_eq!(r.inner, ([63, 8], [24, 14]));
    // Too small for its border: the border narrows, the inside keeps a pixel.
    let tiny = i.pixels([4, 4]);
    assert!(tiny.inner.1.iter().all(|&s| s >= 1), "{tiny:?}");
    assert_eq!(tiny.inner, tiny.outer);

    let (_, key, _, message) = error_of(&format!(
        "{MINIMAL}{}",
        inset.replace("[0.3, 0.4]", "[0.5, 0.4]")
    ));
    assert_eq!(key, "inset.size");
    assert!(
        message.contains("0.5") && message.contains("inside the film"),
        "{message}"
    );
    let (_, key, _, message) = error_of(&format!(
        "{MINIMAL}{}",
        inset.replace("[0.6, 0.1]", "[1.2, 0.1]")
    ));
    assert_eq!(key, "inset.corner");
    assert!(
        message.contains("1.2") && message.contains("[0, 1)"),
        "{message}"
    );
    let (_, key, _, _) = error_of(&format!("{MINIMAL}{}", inset.replace("20", "0")));
    assert_eq!(key, "inset.fov_deg");

    let mesh = |file: &str| {
        format!(
            "{MINIMAL}[[shape]]\ntype = \"mesh\"\nfile = \"{file}\"\nmaterial = \"m\"\n[material.m]\ntype = \"diffuse\"\nreflectance = [0.5, 0.5, 0.5]\n"
        )
    };
    let desc = SceneDescription::from_str(&mesh("builtin:tablecloth"), "s.toml", Path::new("."));
    assert!(desc.is_ok());
    let (_, key, _, message) = error_of(&mesh("builtin:sofa"));
    assert_eq!(key, "shape[0].file");
    assert!(
        message.contains("sofa") && message.contains("builtin:tablecloth"),
        "{message}"
    );
}

/// Type errors name the dotted key, under its table (the third `[[shape]]` is `shape[2]`), not
/// the table; a wrong shape of `yarns_per_unit` or `pattern` says what is expected of it.
#[test]
fn type_errors_name_the_key_and_what_it_takes() {
    let (_, key, line, message) = error_of(&format!("{MINIMAL}[film]\nwidth = \"wide\"\n"));
    assert_eq!((key.as_str(), line), ("film.width", Some(7)), "{message}");
    assert!(
        message.contains("invalid type: string \"wide\""),
        "{message}"
    );
    let sphere = "[[shape]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n";
    let text = format!(
        "{MINIMAL}{sphere}{sphere}[[shape]] # the third\ntype = \"sphere\"\nradius = \"big\"\n"
    );
    // A shape's values are read by its `type`, from a copy of the table without places: the
    // line is its header's.
    let (_, key, line, message) = error_of(&text);
    assert_eq!(
        (key.as_str(), line),
        ("shape[2].radius", Some(16)),
        "{message}"
    );
    assert!(message.contains("\"big\""), "{message}");
    let woven = |extra: &str| {
        format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"silk\"\n{extra}\n")
    };
    for (extra, key, expected) in [
        (
            "yarns_per_unit = [40.0]",
            "material.m.yarns_per_unit",
            "a number > 0 for both, or a pair (n_u, n_v)",
        ),
        (
            "yarns_per_unit = [1, 2, 3]",
            "material.m.yarns_per_unit",
            "a number > 0 for both, or a pair (n_u, n_v)",
        ),
        (
            "yarns_per_unit = \"many\"",
            "material.m.yarns_per_unit",
            "a number > 0 for both, or a pair (n_u, n_v)",
        ),
        (
            "pattern = 3",
            "material.m.pattern",
            "a name (\"plain\", \"twill-2/1\", \"satin-5\", \"sateen-5\"), a 0/1 matrix of rows",
        ),
        ("pattern = [[1, 2]]", "material.m.pattern[0][1]", "0 or 1"),
        ("colour = [1, 0, 0]", "material.m.colour", "unknown field"),
        (
            "pattern = { wiff = \"a.wif\" }",
            "material.m.pattern.wiff",
            "(an unknown field)",
        ),
    ] {
        let (_, k, _, message) = error_of(&woven(extra));
        assert_eq!(k, key, "{extra}: {message}");
        assert!(message.contains(expected), "{extra}: {message}");
        assert!(!message.contains("untagged"), "{extra}: {message}");
    }
    // The forms each takes still read.
    for extra in [
        "yarns_per_unit = 40",
        "yarns_per_unit = [40, 60.5]",
        "pattern = \"twill-2/1\"",
        "pattern = [[1, 0], [0, 1]]",
    ] {
        SceneDescription::from_str(&woven(extra), "scene.toml", Path::new("."))
            .unwrap_or_else(|e| panic!("{extra}: {e}"));
    }
}

/// A woven material that is neither a preset nor a file that exists, and does not look like a
/// path, is taken for a mistyped preset: the message lists the presets.
#[test]
fn a_mistyped_preset_lists_the_presets() {
    let text = format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"polyester-satin\"\n");
    let (_, key, _, message) = error_of(&text);
    assert_eq!(key, "material.m.material");
    assert!(
        message.contains("polyester-satin") && message.contains("polyester-sateen, "),
        "{message}"
    );
    // A path still says the file is missing.
    let text = format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"cloth/mine.toml\"\n");
    let (_, _, _, message) = error_of(&text);
    assert!(message.contains("No such file"), "{message}");
}

/// A woven material's keys are the library's (`SurfaceSpec::from_keys`): `weft_fraction` lays
/// the macro BRDF as in `woven.Surface`; an unknown key is refused with the library's list; the
/// two keys the scene takes elsewhere or not at all are refused by name, saying where they go.
#[test]
fn woven_keys_are_the_librarys_and_the_scene_refuses_two_by_name() {
    let woven = |extra: &str| {
        format!("{MINIMAL}[material.m]\ntype = \"woven\"\nmaterial = \"silk\"\n{extra}\n")
    };
    let desc =
        SceneDescription::from_str(&woven("weft_fraction = 0.25"), "scene.toml", Path::new("."))
            .unwrap();
    let Some(woven_render::scene::MaterialDesc::Woven(spec)) = desc.materials.get("m") else {
        panic!("no woven material");
    };
    assert_eq!(
        spec.material.weave,
        Some(woven::material::Weave::WeftFraction(0.25))
    );
    let (_, key, line, message) = error_of(&woven("colour = 3"));
    assert_eq!((key.as_str(), line), ("material.m.colour", Some(6)));
    assert!(message.contains("`weft_fraction`"), "{message}");
    for (extra, needle) in [
        ("footprint_filter = false", "[integrator]"),
        ("wavelength_nm = 450", "550"),
    ] {
        let (_, key, _, message) = error_of(&woven(extra));
        let name = extra.split(' ').next().unwrap();
        assert_eq!(key, format!("material.m.{name}"), "{message}");
        assert!(message.contains(needle), "{message}");
    }
    let (_, key, _, message) = error_of(&woven("pattern = \"plain\"\nweft_fraction = 0.5"));
    assert_eq!(key, "material.m.weft_fraction", "{message}");
}
