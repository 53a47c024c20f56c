//! EXR environment maps: any bytes give a map with finite, non-negative radiance and finite
//! densities, or an error; a header declaring more pixels than the bytes can hold allocates
//! nothing (libFuzzer's `-rss_limit_mb` catches one that does).
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::io::Cursor;
use std::path::Path;
use woven::Vec3;
use woven_render::light::Environment;

fuzz_target!(|data: &[u8]| {
    if let Ok(env) = Environment::read_exr(Cursor::new(data), Path::new("<fuzz>"), 1.0) {
        for d in [Vec3::Z, Vec3::new(0.6, 0.0, -0.8), Vec3::new(0.0, -1.0, 0.0)] {
            let l = env.radiance(d);
            assert!(l.0.iter().all(|c| c.is_finite() && *c >= 0.0));
            assert!(env.pdf(d).is_finite() && env.pdf(d) >= 0.0);
        }
        if let Some((d, pdf)) = env.sample([0.3, 0.7]) {
            assert!(d.x.is_finite() && pdf.is_finite() && pdf > 0.0);
        }
    }
});
