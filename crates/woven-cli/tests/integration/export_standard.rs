//! `woven export --format openpbr|gltf` end to end: a woven surface read from the surface keys'
//! flags, tabulated (a draft table in a cache of the test's own), projected and written with
//! its textures; what is refused names the flag. (The documents' contents are tested in
//! woven-fit's `exports.rs`.)

use assert_cmd::Command;
use predicates::prelude::*;
use std::path::Path;

fn woven(cache: &Path) -> Command {
    let mut c = Command::cargo_bin("woven").unwrap();
    c.env("XDG_CACHE_HOME", cache);
    c
}

#[test]
fn export_openpbr_and_gltf_write_a_woven_surface_and_refuse_bad_flags_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let surface = [
        "-m",
        "polyester-sateen",
        "--pattern",
        "satin-5",
        "--gap",
        "0.1",
        "--yarns-per-unit",
        "500,400",
        "--draft-tables",
        "--texels-per-cell",
        "4",
    ];

    // OpenPBR, the weft dyed apart: both families projected, each error printed.
    let mtlx = out.join("sateen.mtlx");
    let run = woven(&cache)
        .args(["export", "--format", "openpbr"])
        .args(surface)
        .args(["--weft-color", "0.8,0.2,0.1", "-o"])
        .arg(&mtlx)
        .arg("--also-output")
        .arg(out.join("dyed.gltf"))
        .assert()
        .success()
        .stderr(predicate::str::contains(
            "tabulating `polyester-sateen`'s yarn",
        ))
        .stderr(predicate::str::contains("projecting"));
    let stdout = String::from_utf8(run.get_output().stdout.clone()).unwrap();
    assert!(
        stdout.contains("one tile of 5×5 pattern cells at 500×400"),
        "{stdout}"
    );
    for family in ["weft", "warp"] {
        assert!(
            stdout.contains(&format!("  {family}: RMS log error"))
                && stdout.contains("isotropic GGX + Lambert"),
            "{stdout}"
        );
    }
    // The glTF of the same projection beside it.
    assert!(stdout.contains("dyed.gltf (glTF 2.0"), "{stdout}");
    let text = std::fs::read_to_string(&mtlx).unwrap();
    assert!(text.contains("<materialx version=\"1.39\""));
    assert_eq!(text.matches("<open_pbr_surface ").count(), 3);
    for texture in ["layout", "factors"] {
        let name = format!("sateen-{texture}.png");
        assert!(text.contains(&name) && out.join(&name).is_file(), "{name}");
    }
    assert!(!out.join("sateen-normal.png").exists());

    // glTF, the same surface undyed (one family projected: the table is the cache's now).
    let gltf = out.join("sateen.gltf");
    woven(&cache)
        .args(["export", "--format", "gltf"])
        .args(surface)
        .args(["--swatch-m", "0.03", "-o"])
        .arg(&gltf)
        .assert()
        .success()
        .stderr(predicate::str::contains("tabulating").not())
        .stdout(predicate::str::contains("a 3 cm swatch"))
        .stdout(predicate::str::contains("KHR_materials_anisotropy"));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&gltf).unwrap()).unwrap();
    assert_eq!(doc["extensionsUsed"].as_array().unwrap().len(), 4);
    for image in doc["images"].as_array().unwrap() {
        assert!(out.join(image["uri"].as_str().unwrap()).is_file());
    }
    assert!(out.join("sateen.bin").is_file());
    let written = std::fs::read_dir(&out).unwrap().count();
    // The .mtlx and the layout's two textures; each .gltf, its .bin and five textures.
    assert_eq!(written, 3 + 2 * 7);

    // Refusals, each naming the flag, leaving nothing new.
    let refused = out.join("refused.mtlx");
    for (format, extra, says) in [
        (
            "openpbr",
            vec!["--texels-per-cell", "0"],
            "--texels-per-cell",
        ),
        ("openpbr", vec!["--gap", "2"], "--gap"),
        // These formats carry no transmission: a cloth that lets light through is refused.
        (
            "openpbr",
            vec!["--gap", "0.3", "--transmission", "true"],
            "--transmission",
        ),
        (
            "openpbr",
            vec!["--yarns-per-unit", "-3"],
            "--yarns-per-unit",
        ),
        ("openpbr", vec!["--weft-color", "2,0,0"], "--weft-color"),
        ("openpbr", vec!["--pattern", "no-such-weave"], "--pattern"),
        ("gltf", vec!["--swatch-m", "0"], "--swatch-m"),
        ("openpbr", vec!["--wavelength-nm", "600"], "--wavelength-nm"),
        ("merl", vec!["--pattern", "plain"], "--pattern"),
        (
            "openpbr",
            vec!["--also-output", "x.png"],
            ".mtlx (openpbr) or .gltf",
        ),
        (
            "openpbr",
            vec!["--also-output", "x.mtlx"],
            "the other format",
        ),
    ] {
        woven(&cache)
            .args([
                "export",
                "--format",
                format,
                "-m",
                "polyester-sateen",
                "--draft-tables",
            ])
            .args(extra)
            .arg("-o")
            .arg(&refused)
            .assert()
            .code(1)
            .stderr(predicate::str::contains(says));
    }
    woven(&cache)
        .args([
            "export",
            "--format",
            "gltf",
            "-m",
            "microcylinder-velvet",
            "-o",
        ])
        .arg(&refused)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("microcylinder fabric"));
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), written);
}
