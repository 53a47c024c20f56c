//! The shot silk's hue against the view angle: the `silk-shot` preset with its own dyes (a green
//! weft, a red warp), as the showcase's cushion renders it from afar (the paper's cloth BRDF,
//! `detail = "cloth"`), under one distant light at 45°.
//!
//! For the light in the weft's plane (azimuth 0°) and in the warp's (90°), the viewer sweeps the
//! same plane from the back (−80°) through the normal to the mirror side (+80°). Each row gives
//! the reflected colour `f cos θi` (linear RGB), its hue (HSV, degrees: 0 red, 120 green) and
//! its luminance. The last line sums up: how far the hue travels over all these views.
//!
//! `cargo run --release -p woven-render --example shot_silk_hue`

use std::path::Path;
use woven::color::Rgb;
use woven::Vec3;
use woven_render::material::ShadingPoint;
use woven_render::scene::{Scene, SceneDescription};

const SCENE: &str = r#"
[camera]
origin = [0, -3, 1]
target = [0, 0, 0]
up = [0, 0, 1]
fov_deg = 30
[[light]]
type = "environment"
radiance = [1, 1, 1]
[[shape]]
type = "rectangle"
corner = [-1, -1, 0]
edge_u = [2, 0, 0]
edge_v = [0, 2, 0]
material = "shot"
[material.shot]
type = "woven"
material = "silk-shot"
yarns_per_unit = 5000
detail = "cloth"
"#;

fn main() {
    let desc = SceneDescription::from_str(SCENE, "shot-silk", Path::new(".")).unwrap();
    let cache = match woven::table::cache::Cache::user() {
        Ok(c) => woven_render::woven_material::TableCache::with_disk(c),
        Err(_) => Default::default(),
    };
    let scene = Scene::build_with(&desc, &Default::default(), cache, &|_| {}, &|_, _| {}).unwrap();
    let material = &scene.materials[0];
    let at = ShadingPoint::default();
    let (theta_i, mut hues) = (45f64.to_radians(), Vec::new());
    for (plane, phi) in [("weft (0°)", 0.0f64), ("warp (90°)", 90f64.to_radians())] {
        println!("light at 45° in the {plane} plane");
        println!("  view θ   R       G       B       hue°   luminance");
        let wi = Vec3::from_spherical(theta_i, phi);
        for k in -8..=8 {
            let theta_o = k as f64 * 10f64.to_radians();
            // Negative angles: the viewer on the light's side (back-scatter).
            let wo = if k < 0 {
                Vec3::from_spherical(-theta_o, phi)
            } else {
                Vec3::from_spherical(theta_o, phi + std::f64::consts::PI)
            };
            let c = material.eval(wi, wo, &at) * wi.z;
            let h = hue(c);
            hues.push(h);
            println!(
                "  {:>5}°  {:.4}  {:.4}  {:.4}  {:6.1}  {:.4}",
                k * 10,
                c.0[0],
                c.0[1],
                c.0[2],
                h,
                c.luminance()
            );
        }
    }
    let (lo, hi) = hues
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &h| (lo.min(h), hi.max(h)));
    println!(
        "hue over all views: {lo:.1}° to {hi:.1}° ({:.1}° of travel)",
        hi - lo
    );
}

/// The HSV hue of a colour, degrees in `[0, 360)`.
fn hue(c: Rgb) -> f64 {
    let [r, g, b] = c.0;
    let (max, min) = (r.max(g).max(b), r.min(g).min(b));
    if max - min <= 0.0 {
        return 0.0;
    }
    let h = if max == r {
        (g - b) / (max - min)
    } else if max == g {
        2.0 + (b - r) / (max - min)
    } else {
        4.0 + (r - g) / (max - min)
    };
    (h * 60.0).rem_euclid(360.0)
}
