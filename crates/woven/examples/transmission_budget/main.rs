//! Where the light goes when a cloth lets it through (`transmission`, docs/model.md, "Light
//! through the yarns"): for every woven preset laid as its own weave with gaps of 0.2, white
//! (its fibres absorbing nothing) and dyed a mid grey (0.4), light at θi 0°, 30°, 60° and 80°
//! (φi 0.3): the reflected share `R`, the transmitted share `T` through the yarns and the share
//! `O` passed straight between them, and their sum. `R + T` is the mean of `f |cos θ| / pdf` over
//! 128² stratified draws of the cloth level's own sampling (exact in expectation, however
//! peaked the reflection); `T`, a smooth lobe, is integrated over 128² stratified cosine
//! directions on the far side, and `R` is the difference. White fibres give `R + T + O = 1`
//! within the albedo table's error; a dye absorbs the rest.
//!
//! ```text
//! cargo run --release -p woven --example transmission_budget [PRESET…]
//! ```
//! (small tables: a minute or two on 2 cores.)

use std::f64::consts::PI;
use std::sync::Arc;
use woven::bsdf::{Bsdf, Transport};
use woven::color::Rgb;
use woven::material::{Material, Weave};
use woven::math::sampling::cosine_hemisphere;
use woven::surface::{SurfacePoint, SurfaceSpec, WovenSurface};
use woven::table::{Table, TableOptions};
use woven::Vec3;

const THETAS_DEG: [f64; 4] = [0.0, 30.0, 60.0, 80.0];
const N: usize = 128;

/// `R`, `T` (channel means) and `O` for light from `w` at the cloth level.
fn budget(surface: &WovenSurface, w: Vec3) -> [f64; 3] {
    let far = SurfacePoint {
        uv: [0.0; 2],
        footprint: [[1e6, 0.0], [0.0, 1e6]],
    };
    let bsdf = surface.at(&far);
    let mean = |f: Rgb| (f.0[0] + f.0[1] + f.0[2]) / 3.0 / (N * N) as f64;
    let (mut both, mut t) = (0.0, 0.0);
    // The lobe's choice independent of the direction's stratum.
    let mut lobe = woven::math::rng::SplitMix(7);
    for a in 0..N {
        for b in 0..N {
            let u = [(a as f64 + 0.5) / N as f64, (b as f64 + 0.5) / N as f64];
            let uc = lobe.uniform();
            if let Some(s) = bsdf.sample(w, uc, u, Transport::Importance) {
                both += mean(s.f * (s.wo.z.abs() / s.pdf));
            }
            let d = cosine_hemisphere(u[0], u[1]);
            t += mean(bsdf.eval(w, Vec3::new(d.x, d.y, -d.z)) * PI);
        }
    }
    [both - t, t, surface.open_along(w)]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = if args.is_empty() {
        Material::all_preset_names()
            .iter()
            .map(|s| s.to_string())
            .collect()
    } else {
        args
    };
    println!("| preset | dye | θi | R | T | O | R + T + O |");
    println!("|---|---|---|---|---|---|---|");
    for name in &names {
        let mut material = Material::preset(name)?;
        if material.yarn.is_none() {
            continue;
        }
        if !matches!(material.weave, Some(Weave::Pattern { .. })) {
            material.weave = Some(Weave::named("plain")?);
        }
        let yarn = material.yarn_family();
        let options = TableOptions {
            n_theta: 12,
            n_phi: 7,
            n_h: 31,
            colour: true,
            ..TableOptions::default()
        };
        let table = Arc::new(Table::build(
            &yarn.build(550.0)?,
            &yarn,
            &options,
            &|_, _| {},
        )?);
        for dye in [1.0, 0.4] {
            let spec = SurfaceSpec {
                yarns_per_unit: [10.0, 10.0],
                gap: 0.2,
                transmission: true,
                weft_color: Some(Rgb([dye; 3])),
                warp_color: Some(Rgb([dye; 3])),
                ..SurfaceSpec::new(material.clone())
            };
            let surface = WovenSurface::new(&spec, Arc::clone(&table))?;
            for theta in THETAS_DEG {
                let w = Vec3::from_spherical(theta.to_radians(), 0.3);
                let [r, t, o] = budget(&surface, w);
                println!(
                    "| {name} | {dye} | {theta}° | {r:.3} | {t:.3} | {o:.3} | {:.3} |",
                    r + t + o
                );
            }
        }
    }
    Ok(())
}
