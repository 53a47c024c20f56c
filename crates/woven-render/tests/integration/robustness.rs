//! Hostile input to the renderer's readers: arbitrary bytes, and valid files mutated, never make
//! the OBJ reader, the EXR environment-map reader or the scene file's parser and checks panic;
//! each either reads its input (and what it read is sound) or returns an error.
//!
//! Executions per run (proptest cases, fixed by `CASES` below): 1000 arbitrary byte strings and
//! 1000 mutated files (one to seven bytes replaced, inserted or removed) for each of the three
//! readers, 6000 inputs in all, in a fraction of a second in release (30 000 cases each ran
//! clean in 3.4 s on 2 cores while this was written). A failure proptest finds stays here as a
//! regression test with its minimal input.

use proptest::prelude::*;
use std::io::Cursor;
use std::path::Path;
use woven::Vec3;
use woven_render::light::Environment;
use woven_render::scene::{SceneDescription, EXAMPLE_SCENE, SHOWCASE_SCENE};
use woven_render::shapes::read_obj;

#[path = "../../../woven/tests/support/mutation.rs"]
mod mutation;
use mutation::{edits, mutate};

/// Proptest cases per property.
const CASES: u32 = 1000;

/// OBJ files to mutate: uv and normals, negative (relative) indices, a polygon, groups and the
/// material lines the reader ignores.
const OBJ_SEEDS: [&str; 2] = [
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
     f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n",
    "# a comment\nmtllib cloth.mtl\no quad\ng side\nv 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\n\
     v 0.5 1.5 0\nusemtl silk\ns off\nf -5 -4 -3 -2 -1\nf 1 2 3\n",
];

/// Reads `bytes` as an OBJ mesh; a mesh read is sound (indices in range, finite positions,
/// normals and uv one per vertex or none).
fn check_obj(bytes: &[u8]) {
    if let Ok(mesh) = read_obj(
        bytes,
        "<prop>",
        1.0,
        Vec3::new(0.0, 0.0, 0.0),
        "shape[0].file",
    ) {
        let n = mesh.positions.len();
        assert!(!mesh.indices.is_empty());
        assert!(mesh.indices.iter().flatten().all(|&i| (i as usize) < n));
        assert!(mesh
            .positions
            .iter()
            .all(|p| p.x.is_finite() && p.y.is_finite() && p.z.is_finite()));
        assert!(mesh.normals.is_empty() || mesh.normals.len() == n);
        assert!(mesh.uvs.is_empty() || mesh.uvs.len() == n);
    }
}

/// Small EXR maps to mutate, written once: 4 × 2 RGB and 8 × 4 RGBA with a sun.
fn exr_seeds() -> &'static [Vec<u8>] {
    static SEEDS: std::sync::OnceLock<Vec<Vec<u8>>> = std::sync::OnceLock::new();
    SEEDS.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let (rgb, rgba) = (dir.path().join("rgb.exr"), dir.path().join("rgba.exr"));
        exr::prelude::write_rgb_file(&rgb, 4, 2, |x, y| (x as f32, y as f32, 0.5)).unwrap();
        exr::prelude::write_rgba_file(&rgba, 8, 4, |x, y| {
            let sun = if (x, y) == (3, 1) { 100.0 } else { 0.2 };
            (sun, sun, sun, 1.0)
        })
        .unwrap();
        vec![std::fs::read(rgb).unwrap(), std::fs::read(rgba).unwrap()]
    })
}

/// Reads `bytes` as an environment map; a map read gives finite, non-negative radiance and
/// finite densities.
fn check_exr(bytes: &[u8]) {
    if let Ok(env) = Environment::read_exr(Cursor::new(bytes), Path::new("<prop>"), 1.0) {
        for d in [
            Vec3::Z,
            Vec3::new(0.6, 0.0, -0.8),
            Vec3::new(0.0, -1.0, 0.0),
        ] {
            let l = env.radiance(d);
            assert!(l.0.iter().all(|c| c.is_finite() && *c >= 0.0), "{l:?}");
            assert!(env.pdf(d).is_finite() && env.pdf(d) >= 0.0);
        }
        if let Some((d, pdf)) = env.sample([0.3, 0.7]) {
            assert!(d.x.is_finite() && pdf.is_finite() && pdf > 0.0);
        }
    }
}

/// Parses and checks `bytes` as a scene file, relative paths against an empty folder.
fn check_scene(bytes: &[u8]) {
    let base = std::env::temp_dir().join("woven-render-prop-empty");
    let _ = SceneDescription::from_str(&String::from_utf8_lossy(bytes), "<prop>", &base);
}

/// A small scene with every kind of light and shape and both kinds of material.
const SMALL_SCENE: &str = "[camera]\norigin = [0, -2, 1]\ntarget = [0, 0, 0]\nfov_deg = 40\n\
    [film]\nwidth = 8\nheight = 6\nspp = 4\n[integrator]\nmax_depth = 3\n\
    [[light]]\ntype = \"point\"\nposition = [0, 0, 2]\nintensity = [1, 1, 1]\n\
    [[light]]\ntype = \"environment\"\nfile = \"sky.exr\"\nscale = 2\n\
    [[light]]\ntype = \"rectangle\"\ncorner = [0, 0, 2]\nedge_u = [1, 0, 0]\nedge_v = [0, 1, 0]\n\
    radiance = [1, 1, 1]\n\
    [material.grey]\ntype = \"diffuse\"\nreflectance = [0.5, 0.5, 0.5]\n\
    [material.silk]\ntype = \"woven\"\nmaterial = \"silk\"\npattern = \"satin-5\"\n\
    u_max_deg = 20\ngap = 0.1\n\
    [[shape]]\ntype = \"mesh\"\nfile = \"quad.obj\"\nmaterial = \"grey\"\n\
    [[shape]]\ntype = \"cloth\"\ncorner = [-1, -1, 0]\nedge_u = [2, 0, 0]\nedge_v = [0, 2, 0]\n\
    folds = 2\namplitude = 0.1\nmaterial = \"silk\"\n\
    [[shape]]\ntype = \"sphere\"\ncenter = [0, 0, 0.5]\nradius = 0.3\nmaterial = \"silk\"\n";

/// The unmutated seeds are read: the mutations start from inputs that reach every stage.
#[test]
fn the_seeds_are_read() {
    for text in OBJ_SEEDS {
        read_obj(
            text.as_bytes(),
            "<seed>",
            1.0,
            Vec3::new(0.0, 0.0, 0.0),
            "k",
        )
        .unwrap();
    }
    for bytes in exr_seeds() {
        Environment::read_exr(Cursor::new(bytes), Path::new("<seed>"), 1.0).unwrap();
    }
    let base = std::env::temp_dir();
    for text in [EXAMPLE_SCENE, SHOWCASE_SCENE, SMALL_SCENE] {
        SceneDescription::from_str(text, "<seed>", &base).unwrap();
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: CASES, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_are_an_obj_mesh_or_an_error(
        bytes in proptest::collection::vec(any::<u8>(), 0..400),
    ) {
        check_obj(&bytes);
    }

    #[test]
    fn mutated_obj_meshes_are_read_or_refused(seed in 0usize..2, edits in edits()) {
        check_obj(&mutate(OBJ_SEEDS[seed].as_bytes(), &edits));
    }

    /// Arbitrary bytes after the EXR magic number and version (without them every input stops
    /// at the first four bytes).
    #[test]
    fn arbitrary_bytes_are_an_environment_map_or_an_error(
        bytes in proptest::collection::vec(any::<u8>(), 0..600),
        magic in any::<bool>(),
    ) {
        let mut input = if magic { vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0] } else { Vec::new() };
        input.extend_from_slice(&bytes);
        check_exr(&input);
    }

    #[test]
    fn mutated_environment_maps_are_read_or_refused(seed in 0usize..2, edits in edits()) {
        check_exr(&mutate(&exr_seeds()[seed], &edits));
    }

    #[test]
    fn arbitrary_bytes_are_a_scene_or_an_error(
        bytes in proptest::collection::vec(any::<u8>(), 0..400),
    ) {
        check_scene(&bytes);
    }

    #[test]
    fn mutated_scenes_are_checked_or_refused(seed in 0usize..3, edits in edits()) {
        let text = [EXAMPLE_SCENE, SHOWCASE_SCENE, SMALL_SCENE][seed];
        check_scene(&mutate(text.as_bytes(), &edits));
    }
}

/// A small EXR whose header is rewritten to declare `width` × `height` pixels (its data and
/// display windows), the rest of the file left as it was: a few hundred bytes that claim
/// gigabytes.
fn exr_claiming(width: i32, height: i32) -> Vec<u8> {
    let mut bytes = exr_seeds()[0].clone();
    for name in [&b"dataWindow\0box2i\0"[..], &b"displayWindow\0box2i\0"[..]] {
        let at = bytes
            .windows(name.len())
            .position(|w| w == name)
            .expect("the seed's header has its windows")
            + name.len()
            + 4; // the attribute's size
        for (k, v) in [0, 0, width - 1, height - 1].into_iter().enumerate() {
            bytes[at + 4 * k..at + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

/// A file far too small for the pixels its header declares is refused from the header and
/// the file's length, before the pixels are allocated: 16384 × 8192 pixels (3 GiB once read)
/// in a few hundred bytes.
#[test]
fn an_exr_declaring_more_than_it_holds_is_refused_before_allocating() {
    let bytes = exr_claiming(16384, 8192);
    assert!(bytes.len() < 1000, "{} bytes", bytes.len());
    let Err(e) = Environment::read_exr(Cursor::new(&bytes), Path::new("big.exr"), 1.0) else {
        panic!(
            "a {}-byte file declaring 16384 × 8192 pixels was read",
            bytes.len()
        );
    };
    let message = e.to_string();
    assert!(
        message.contains("declares 16384 × 8192 pixels") && message.contains("the file has"),
        "{message}"
    );
    // The same header over a file long enough to hold its pixels compressed is not refused
    // for its size (it fails later, on its missing chunks, without the check's message).
    let mut padded = exr_claiming(64, 32);
    padded.resize(padded.len() + 64 * 32 * 8, 0);
    if let Err(e) = Environment::read_exr(Cursor::new(&padded), Path::new("pad.exr"), 1.0) {
        assert!(!e.to_string().contains("the file has"), "{e}");
    }
}

/// Inputs the cargo-fuzz targets (fuzz/) found crashing, kept as regression tests: each is read
/// or refused without a panic.
#[test]
fn fuzz_crashes_are_refused() {
    // A channel subsampled by 0: the declared-size check divided by it.
    let bytes = include_bytes!("../data/fuzz/exr-zero-sampling.exr");
    check_exr(bytes);
    // A 4 × 2 image in tiles of 33 554 496 × 64 pixels: the reader allocated a tile (25 GB),
    // past libFuzzer's memory limit. Refused from the header.
    let bytes = include_bytes!("../data/fuzz/exr-huge-tile.exr");
    let Err(e) = Environment::read_exr(Cursor::new(bytes), Path::new("tile.exr"), 1.0) else {
        panic!("a tile larger than the file could hold was read");
    };
    let e = e.to_string();
    assert!(e.contains("tiles of 33554496 × 64 pixels"), "{e}");
}
