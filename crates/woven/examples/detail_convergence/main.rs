//! How the fibre level converges to the yarn's BRDF (docs/render.md, "Levels of detail"): for
//! each preset, the area mean of `detail = "fibers"` over the first N yarns of a weft-only
//! surface (64 points across each) against the exact yarn BRDF, at three direction pairs.
//!
//! `cargo run --release -p woven --example detail_convergence`

use std::sync::Arc;
use woven::bsdf::Bsdf;
use woven::material::{Material, PatternSpec, Weave};
use woven::surface::{Detail, SurfacePoint, SurfaceSpec, WovenSurface};
use woven::table::{Table, TableOptions};
use woven::weave::Pattern;
use woven::Vec3;

fn main() -> Result<(), woven::Error> {
    let pairs = [
        (20.0, 10.0, 35.0, 200.0),
        (60.0, 90.0, 50.0, 260.0),
        (75.0, 30.0, 40.0, 150.0),
    ];
    let counts = [16, 256, 4096];
    println!("| preset | θi, φi → θr, φr | exact f | N = 16 | N = 256 | N = 4096 |");
    println!("|---|---|---|---|---|---|");
    for name in Material::preset_names() {
        let mut material = Material::preset(name)?;
        material.weave = Some(Weave::Pattern {
            spec: PatternSpec::Matrix(vec![vec![1]]),
            pattern: Pattern::from_matrix(vec![vec![1]])?,
        });
        // One pick per unit of v: pick `y` is the row v in [y, y + 1).
        let spec = SurfaceSpec {
            yarns_per_unit: [1.0, 1.0],
            detail: Detail::Fibers,
            ..SurfaceSpec::new(material)
        };
        let yarn = spec.table_material();
        let exact = yarn.build(550.0)?;
        // The table is not read at fibre level; a tiny one serves.
        let options = TableOptions {
            n_theta: 3,
            n_phi: 2,
            n_h: 5,
            colour: true,
            ..TableOptions::default()
        };
        let table = Table::build(&exact, &yarn, &options, &|_, _| {})?;
        let surface = WovenSurface::new(&spec, Arc::new(table))?;
        for (ti, pi, tr, pr) in pairs {
            let s = Vec3::from_spherical(f64::to_radians(ti), f64::to_radians(pi));
            let v = Vec3::from_spherical(f64::to_radians(tr), f64::to_radians(pr));
            let want = exact.eval(s, v);
            let mut sum = 0.0;
            let mut cells = Vec::new();
            for y in 0..counts[counts.len() - 1] {
                for k in 0..64 {
                    let at = SurfacePoint {
                        uv: [0.5, y as f64 + (k as f64 + 0.5) / 64.0],
                        footprint: [[0.0; 2]; 2],
                    };
                    sum += surface.at(&at).eval(s, v).0[0] / 64.0;
                }
                if counts.contains(&(y + 1)) {
                    let mean = sum / (y + 1) as f64;
                    cells.push(format!("{:+.2} %", 100.0 * (mean / want - 1.0)));
                }
            }
            println!(
                "| {name} | {ti}°, {pi}° → {tr}°, {pr}° | {want:.4} | {} |",
                cells.join(" | ")
            );
        }
    }
    Ok(())
}
