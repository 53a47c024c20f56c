//! Scene files: any text is parsed and checked into a scene description or refused with an
//! error; nothing panics (files named by the scene resolve against an empty folder).
#![no_main]

use libfuzzer_sys::fuzz_target;
use woven_render::scene::SceneDescription;

fuzz_target!(|data: &[u8]| {
    let base = std::env::temp_dir().join("woven-fuzz-empty");
    if let Ok(desc) = SceneDescription::from_str(&String::from_utf8_lossy(data), "<fuzz>", &base) {
        assert!(desc.film.width >= 1 && desc.film.height >= 1 && desc.film.spp >= 1);
    }
});
