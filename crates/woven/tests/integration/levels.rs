//! One macro BRDF per material: with `relief` off (the default) every level of detail averages
//! to the paper's BRDF, which `woven eval` is — fibres to yarns, yarns to the cloth's γ-mix,
//! `"auto"` at every footprint — under one point light and in a white furnace.
//!
//! `cargo test --release -p woven --test integration levels -- --nocapture`

use crate::common::Rng;
use std::sync::Arc;
use woven::bsdf::{Bsdf, Transport};
use woven::color::Rgb;
use woven::material::{Material, Weave};
use woven::surface::{Detail, SurfacePoint, SurfaceSpec, WovenSurface};
use woven::table::Table;
use woven::Vec3;

/// Cells each side of the patch the means are taken over (many yarns: their drawn slopes
/// average out).
const CELLS: f64 = 64.0;

/// The polyester sateen in a 5-harness satin at one cell a unit (`relief` off), at `detail`,
/// dyed `dye` (`None`: its own albedos).
fn sateen(detail: Detail, dye: Option<Rgb>, table: &Arc<Table>) -> WovenSurface {
    let mut material = Material::preset("polyester-sateen").unwrap();
    material.weave = Some(Weave::named("satin-5").unwrap());
    let spec = SurfaceSpec {
        yarns_per_unit: [1.0, 1.0],
        detail,
        weft_color: dye,
        warp_color: dye,
        ..SurfaceSpec::new(material)
    };
    assert!(!spec.relief, "the relief is off by default");
    WovenSurface::new(&spec, Arc::clone(table)).unwrap()
}

/// A point of the patch, stratified in `y`, golden-ratio in `x`, with a footprint of `cells`
/// cells a pixel.
fn point(k: usize, n: usize, cells: f64) -> SurfacePoint {
    SurfacePoint {
        uv: [
            woven::yarn::point::golden_uniform(k as i64, 21) * CELLS,
            (k as f64 + 0.5) / n as f64 * CELLS,
        ],
        footprint: [[cells, 0.0], [0.0, cells]],
    }
}

/// The levels compared: a name, the detail and the footprint in cells a pixel (0: none known).
const LEVELS: [(&str, Detail, f64); 6] = [
    ("fibers", Detail::Fibers, 0.0),
    ("yarns", Detail::Yarns, 0.0),
    ("cloth", Detail::Cloth, 0.0),
    ("auto, 5 px a cell", Detail::Auto, 0.2),
    ("auto, 1.3 px a cell", Detail::Auto, 0.77),
    ("auto, far", Detail::Auto, 1e6),
];

/// Under one point light 42° off the normal, seen from straight above (the close-up),
/// the patch's mean BRDF is the same at every level, within 1 %, and `woven eval` (the exact
/// model, no table) is the far level's within the table's accuracy (2 %).
#[test]
fn every_level_has_the_papers_mean_under_a_point_light() {
    let table = crate::relief::table("polyester-sateen");
    let (s, v) = (
        Vec3::from_spherical(42f64.to_radians(), 0.6),
        Vec3::new(0.0, 0.0, 1.0),
    );
    let n = 40_000;
    let cloth = sateen(Detail::Cloth, None, &table);
    let far = cloth.at(&point(0, 1, 0.0)).eval(s, v).0[1];
    let mut report = Vec::new();
    for (name, detail, cells) in LEVELS {
        let surface = sateen(detail, None, &table);
        let mean = (0..n)
            .map(|k| surface.at(&point(k, n, cells)).eval(s, v).0[1])
            .sum::<f64>()
            / n as f64;
        report.push(format!(
            "{name} {mean:.5} ({:+.2} %)",
            100.0 * (mean / far - 1.0)
        ));
        assert!(
            (mean - far).abs() <= 0.01 * far,
            "{name}: mean {mean} vs the cloth's {far}"
        );
    }
    let mut material = Material::preset("polyester-sateen").unwrap();
    material.weave = Some(Weave::named("satin-5").unwrap());
    let exact = material.build(550.0).unwrap().eval(s, v);
    report.push(format!(
        "woven eval {exact:.5} ({:+.2} %)",
        100.0 * (far / exact - 1.0)
    ));
    println!("point light: {}", report.join(", "));
    assert!(
        (far - exact).abs() <= 0.02 * exact,
        "the cloth level {far} vs woven eval {exact}"
    );
}

/// In a white furnace (white-dyed yarns, seen 45° off the normal) the patch's albedo, estimated
/// from the BSDF's own draws, is the same at every level, within 1 % and four standard errors.
#[test]
fn every_level_has_the_papers_albedo_in_a_white_furnace() {
    let table = crate::relief::table("polyester-sateen");
    let white = Some(Rgb([0.999; 3]));
    let v = Vec3::from_spherical(45f64.to_radians(), 1.1);
    let n = 40_000;
    let mut rng = Rng(5);
    let mut means = Vec::new();
    for (name, detail, cells) in LEVELS {
        let surface = sateen(detail, white, &table);
        let (mut sum, mut sq) = (0.0, 0.0);
        for k in 0..n {
            let bsdf = surface.at(&point(k, n, cells));
            let u = [rng.uniform(), rng.uniform()];
            let w = bsdf
                .sample(v, rng.uniform(), u, Transport::Radiance)
                .map_or(0.0, |d| d.f.0[1] * d.wi.z / d.pdf);
            sum += w;
            sq += w * w;
        }
        let mean = sum / n as f64;
        let se = ((sq / n as f64 - mean * mean) / n as f64).sqrt();
        means.push((name, mean, se));
    }
    let (_, far, far_se) = means[2];
    println!(
        "white furnace: {}",
        means
            .iter()
            .map(|(name, m, se)| format!("{name} {m:.4} ± {se:.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for &(name, mean, se) in &means {
        assert!(mean <= 1.0 + 4.0 * se, "{name}: albedo {mean} ± {se}");
        assert!(
            (mean - far).abs() <= 0.01 * far + 4.0 * se.hypot(far_se),
            "{name}: albedo {mean} ± {se} vs the cloth's {far} ± {far_se}"
        );
    }
}
