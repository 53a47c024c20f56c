//! Can another of Cycles' closures carry what the standard lobes miss of a silk? The showcase's
//! shot silk (its dyes, 0.2 mm cells), each family as the cloth shows it
//! (`WovenSurface::family_brdf`), against:
//! - its standard lobes (`woven_fit::standard`: Lambert + anisotropic GGX along the yarn);
//! - those lobes plus a third closure of Cycles', its weight fitted with theirs by non-negative
//!   least squares (each pair weighted `cos θi cos θo`, as `standard` fits colours): Cycles'
//!   Hair BSDF (reflection) along the yarn, or its Diffuse Toon BSDF (a diffuse lobe that fades
//!   as the light goes grazing), over a grid of their parameters;
//! - the standard lobes with weights fitted per view direction (Cycles lets a closure's weight
//!   depend on the view, not on the light).
//!
//! Printed: each fit's RMS error of the reflected radiance over the projection pairs (relative to
//! the reference's RMS), and its value at the showcase's sun pair, light (65°, −60°) → view
//! (63°, −90°), where Cycles renders the silks too bright (docs/blender.md), and at the forward
//! mirror (65°, 120°) and the normal (0°).
//!
//! ```text
//! cargo run --release -p woven-fit --example cycles_lobe_shapes
//! ```
//! (the yarn's table from the user's cache, else built: minutes on 2 cores the first time).

use nalgebra::{DMatrix, DVector};
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::Arc;
use woven::color::Rgb;
use woven::material::Material;
use woven::surface::{SurfaceSpec, WovenSurface};
use woven::table::{cache::Cache, Table, TableOptions};
use woven::Vec3;
use woven_fit::projection::{project_with, BuiltLobes, LobeSet, Objective, Reference};

fn spherical(theta_deg: f64, phi_deg: f64) -> Vec3 {
    Vec3::from_spherical(theta_deg.to_radians(), phi_deg.to_radians())
}

/// Cycles' Hair BSDF, reflection component, offset 0, its tangent along `x` (the yarn), as
/// woven's `f` (sr⁻¹ without the cosine): Cycles' closure value is a density over the light's
/// solid angle, a Cauchy lobe of width `r1` in the longitudinal half angle times
/// `cos(φ / 2r2) / 4r2` in the azimuth about the fibre, 0 beyond a quarter turn of azimuth.
fn hair(r1: f64, r2: f64, wi: Vec3, wo: Vec3) -> f64 {
    let t = Vec3::new(1.0, 0.0, 0.0);
    if wi.z <= 0.0 {
        return 0.0;
    }
    let across = |d: Vec3| (d - t * t.dot(d)).normalize();
    let (theta_r, theta_i) = (t.dot(wo).asin(), t.dot(wi).asin());
    let cos_phi = across(wi).dot(across(wo));
    if FRAC_PI_2 - theta_i.abs() < 1e-3 || cos_phi < 0.0 {
        return 0.0;
    }
    let phi = (cos_phi.min(1.0).acos() / r2).min(PI);
    let a = ((FRAC_PI_2 + theta_r) * 0.5 / r1).atan();
    let b = ((-FRAC_PI_2 + theta_r) * 0.5 / r1).atan();
    let h = (theta_i + theta_r) * 0.5;
    let density =
        (phi * 0.5).cos() * 0.25 / r2 * r1 / (2.0 * (h * h + r1 * r1) * (a - b) * theta_i.cos());
    density / wi.z
}

/// Cycles' Diffuse Toon BSDF (`size`, `smooth` in quarter turns) as woven's `f`: its closure
/// value is 1 within `size` of the normal, falling linearly to 0 over `smooth`, over
/// `2π (1 − cos(min(size + smooth, π/2)))`.
fn toon(size: f64, smooth: f64, wi: Vec3) -> f64 {
    let (full, fade) = (size * FRAC_PI_2, smooth * FRAC_PI_2);
    let reach = (full + fade).min(FRAC_PI_2);
    let angle = wi.z.clamp(-1.0, 1.0).acos();
    if wi.z <= 0.0 || angle >= reach {
        return 0.0;
    }
    let intensity = if angle < full {
        1.0
    } else {
        1.0 - (angle - full) / fade
    };
    intensity / (2.0 * PI * (1.0 - reach.cos())) / wi.z
}

/// Non-negative least squares over at most a few columns, by trying each subset: the weights
/// and the weighted squared error. `rows`: (the lobes at unit weight, the value, the weight).
fn nnls(rows: &[(Vec<f64>, f64, f64)]) -> (Vec<f64>, f64) {
    let n = rows[0].0.len();
    let cost = |w: &[f64]| -> f64 {
        rows.iter()
            .map(|(x, y, k)| k * (x.iter().zip(w).map(|(a, b)| a * b).sum::<f64>() - y).powi(2))
            .sum()
    };
    let mut best = (vec![0.0; n], cost(&vec![0.0; n]));
    for mask in 1u32..(1 << n) {
        let cols: Vec<usize> = (0..n).filter(|k| mask >> k & 1 == 1).collect();
        let mut a = DMatrix::<f64>::zeros(cols.len(), cols.len());
        let mut b = DVector::<f64>::zeros(cols.len());
        for (x, y, k) in rows {
            for (i, &ci) in cols.iter().enumerate() {
                b[i] += k * x[ci] * y;
                for (j, &cj) in cols.iter().enumerate() {
                    a[(i, j)] += k * x[ci] * x[cj];
                }
            }
        }
        let Some(s) = a.lu().solve(&b) else { continue };
        if s.iter().any(|v| *v < 0.0) {
            continue;
        }
        let mut w = vec![0.0; n];
        cols.iter().zip(s.iter()).for_each(|(&c, v)| w[c] = *v);
        let c = cost(&w);
        if c < best.1 {
            best = (w, c);
        }
    }
    best
}

/// The shot silk of `crates/woven-render/scenes/showcase.toml`.
fn shot_silk() -> Result<WovenSurface, Box<dyn std::error::Error>> {
    let spec = SurfaceSpec {
        yarns_per_unit: [5000.0, 5000.0],
        weft_color: Some(Rgb([0.02, 0.42, 0.12])),
        warp_color: Some(Rgb([0.6, 0.04, 0.06])),
        ..SurfaceSpec::new(Material::preset("silk-shot")?)
    };
    let yarn = spec.table_material();
    let options = TableOptions {
        colour: true,
        ..TableOptions::default()
    };
    let build = || Table::build(&yarn.build(550.0)?, &yarn, &options, &|_, _| {});
    let table = Cache::user()?.load_or_build(&yarn, 550.0, &options, build, &|_| {})?;
    Ok(WovenSurface::new(&spec, Arc::new(table))?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let surface = shot_silk()?;
    let sun = spherical(65.0, -60.0);
    let views = [
        spherical(63.0, -90.0),
        spherical(65.0, 120.0),
        spherical(0.0, 0.0),
    ];
    println!("| family | lobes | relative RMS | sun pair | forward mirror | normal |");
    println!("|---|---|---|---|---|---|");
    for (family, warp) in [("weft", false), ("warp", true)] {
        let f = |wi: Vec3, wo: Vec3| Rgb(surface.family_brdf(warp, wi, wo).0).luminance();
        let reference = Reference::sample(f);
        let lobes = project_with(&reference, LobeSet::Anisotropic, Objective::Radiance)?;
        let built = lobes.lobes.build()?;
        let data: Vec<(Vec3, Vec3, f64)> = reference
            .pairs
            .iter()
            .map(|&(i, o)| (i, o, f(i, o)))
            .collect();
        let total: f64 = data.iter().map(|(i, o, y)| i.z * o.z * y * y).sum();
        let woven: Vec<String> = views.iter().map(|&v| format!("{:.4}", f(sun, v))).collect();
        println!("| {family} | woven | 0 | {} |", woven.join(" | "));
        let row = |name: String, third: &dyn Fn(Vec3, Vec3) -> f64| {
            let unit = |i: Vec3, o: Vec3| {
                let [lambert, ggx, _] = built.unit_lobes(i, o);
                vec![lambert, ggx, third(i, o)]
            };
            let rows: Vec<_> = data
                .iter()
                .map(|&(i, o, y)| (unit(i, o), y, i.z * o.z))
                .collect();
            let (w, cost) = nnls(&rows);
            let at = |v: Vec3| unit(sun, v).iter().zip(&w).map(|(a, b)| a * b).sum::<f64>();
            let cells: Vec<String> = views.iter().map(|&v| format!("{:.4}", at(v))).collect();
            println!(
                "| {family} | {name}, weights {:.3?} | {:.3} | {} |",
                w,
                (cost / total).sqrt(),
                cells.join(" | ")
            );
        };
        row("Lambert + GGX".into(), &|_, _| 0.0);
        for (r1, r2) in [(0.05, 0.3), (0.1, 1.0), (0.2, 0.6), (0.4, 1.0)] {
            row(format!("+ Hair ({r1}, {r2})"), &|i, o| hair(r1, r2, i, o));
        }
        for (size, smooth) in [(0.1, 0.5), (0.35, 0.5), (0.5, 0.5), (0.2, 1.0)] {
            row(format!("+ Diffuse Toon ({size}, {smooth})"), &|i, _| {
                toon(size, smooth, i)
            });
        }
        per_view(&built, &f, sun, &views, family);
    }
    Ok(())
}

/// The standard lobes with their two weights fitted at each view alone, over lights to 80°.
fn per_view(
    built: &BuiltLobes,
    f: &dyn Fn(Vec3, Vec3) -> f64,
    sun: Vec3,
    views: &[Vec3],
    family: &str,
) {
    let cells: Vec<String> = views
        .iter()
        .map(|&v| {
            let mut rows = vec![];
            for k in 0..8 {
                for j in 0..24 {
                    let l = spherical(10.0 + 10.0 * k as f64, 15.0 * j as f64);
                    let [lambert, ggx, _] = built.unit_lobes(l, v);
                    rows.push((vec![lambert, ggx], f(l, v), l.z));
                }
            }
            let (w, _) = nnls(&rows);
            let [lambert, ggx, _] = built.unit_lobes(sun, v);
            format!("{:.4}", w[0] * lambert + w[1] * ggx)
        })
        .collect();
    println!(
        "| {family} | Lambert + GGX, weights per view | — | {} |",
        cells.join(" | ")
    );
}
