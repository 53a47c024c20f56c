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
    assert_eq!(key, "widht");
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

    for weight in ["0", "-2", "inf"] {
        let text = format!(
            "{MINIMAL}[[light]]\ntype = \"point\"\nposition = [0, 0, 1]\nintensity = [1, 1, 1]\nsampling_weight = {weight}\n"
        );
        let (_, key, line, message) = error_of(&text);
        assert_eq!((key.as_str(), line), ("light[0].sampling_weight", Some(6)));
        assert!(
            message.contains(weight) && message.contains("> 0"),
            "{message}"
        );
    }

    let (_, key, line, message) = error_of("[camera]\norigin = [0, 0, 1]\nfov_deg = 4 0\n");
    assert_eq!((key.as_str(), line), ("fov_deg", Some(3)), "{message}");
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
