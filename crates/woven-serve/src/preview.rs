//! The rendered preview: a swatch of the material on a sphere, or draped over one, path-traced
//! by `woven-render` at a small size, one sample per pixel per pass, the running mean sent after
//! every pass so the page shows it refine.
//!
//! The woven material is tabulated first on a coarse grid ([`preview_table`]: under a second
//! for a single-orientation yarn, a few seconds for twisted and isotropic ones on two cores),
//! with its progress streamed; the job stops between passes once stale.

use crate::error::{ApiError, ApiResult};
use crate::job::Emitter;
use base64::Engine;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;
use woven::material::Material;
use woven::table::TableOptions;
use woven_render::render::{render, RenderOptions};
use woven_render::scene::{MaterialDesc, Scene, SceneDescription};
use woven_render::tonemap::srgb_encode;
use woven_render::woven_material::{TableGrid, WovenSpec};
use woven_render::Rgb;

/// The preview's table grid: coarse (its errors of several per cent are below a preview's
/// noise), so that it builds while the user watches; no exact regions (a look-up everywhere).
pub fn preview_table() -> TableOptions {
    TableOptions {
        n_theta: 8,
        n_phi: 5,
        n_h: 17,
        n_h_isotropic: 33,
        azimuth_nodes: 60,
        colour: true,
        exact_regions: false,
        ..TableOptions::default()
    }
}

/// Image side limits, pixels.
pub const SIZE_RANGE: (usize, usize) = (16, 256);
/// Pass limits (one sample per pixel each).
pub const PASSES_RANGE: (usize, usize) = (1, 1024);

/// The preview's shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// A sphere covered in the cloth.
    Sphere,
    /// A square of cloth draped over a sphere.
    Drape,
}

/// One line of a preview stream.
#[derive(Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Message {
    /// The table build: nodes done of all.
    Table {
        /// Done.
        done: usize,
        /// All.
        total: usize,
    },
    /// The image after `pass` passes: sRGB bytes, row-major, RGB, base64.
    Image {
        /// Passes (= samples per pixel) so far.
        pass: usize,
        /// Width, pixels.
        width: usize,
        /// Height, pixels.
        height: usize,
        /// The pixels.
        rgb: String,
        /// Wall time since the request, milliseconds.
        ms: f64,
    },
    /// All passes done.
    Done {
        /// Wall time since the request, milliseconds.
        ms: f64,
    },
}

/// A checked preview request.
#[derive(Clone, Debug)]
pub struct Preview {
    /// The material.
    pub material: Material,
    /// The shape.
    pub shape: Shape,
    /// Image side, pixels.
    pub size: usize,
    /// Passes.
    pub passes: usize,
    /// Weft and warp dyes (linear RGB in [0, 1]); `None`: the material's own.
    pub colors: [Option<[f64; 3]>; 2],
    /// Pattern cells across the swatch.
    pub cells: f64,
}

/// Checks a dye colour.
pub fn check_color(field: &str, c: [f64; 3]) -> ApiResult<[f64; 3]> {
    if c.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)) {
        Ok(c)
    } else {
        Err(ApiError::invalid(
            field,
            format!("{c:?}"),
            "three linear RGB values in [0, 1]",
        ))
    }
}

/// The scene around the swatch, in `woven render`'s format; the cloth's material is replaced
/// by the page's.
fn scene_text(p: &Preview) -> String {
    let common = format!(
        "[film]\nwidth = {s}\nheight = {s}\nspp = 1\nseed = 0\n\
         [integrator]\nmax_depth = 3\n\
         [[light]]\ntype = \"point\"\nposition = [2.5, -3.0, 4.0]\nintensity = [60.0, 60.0, 60.0]\n\
         [[light]]\ntype = \"environment\"\nradiance = [0.35, 0.37, 0.4]\n\
         [material.cloth]\ntype = \"woven\"\nmaterial = \"silk\"\n\
         [material.floor]\ntype = \"diffuse\"\nreflectance = [0.3, 0.3, 0.3]\n",
        s = p.size
    );
    let shapes = match p.shape {
        Shape::Sphere => "[camera]\norigin = [0.0, -3.6, 1.6]\ntarget = [0.0, 0.0, 0.0]\n\
             up = [0.0, 0.0, 1.0]\nfov_deg = 34.0\n\
             [[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n\
             material = \"cloth\"\n"
            .to_string(),
        Shape::Drape => "[camera]\norigin = [0.0, -3.0, 2.2]\ntarget = [0.0, 0.0, 0.45]\n\
             up = [0.0, 0.0, 1.0]\nfov_deg = 44.0\n\
             [[shape]]\ntype = \"cloth\"\ndrape = \"sphere\"\ncenter = [0.0, 0.0, 0.6]\n\
             radius = 0.6\ncorner = [-1.1, -1.1, 1.2]\nedge_u = [2.2, 0.0, 0.0]\n\
             edge_v = [0.0, 2.2, 0.0]\nfolds = 9\namplitude = 0.05\nresolution = [90, 90]\n\
             material = \"cloth\"\n\
             [[shape]]\ntype = \"rectangle\"\ncorner = [-3.0, -3.0, 0.0]\nedge_u = [6.0, 0.0, 0.0]\n\
             edge_v = [0.0, 6.0, 0.0]\nmaterial = \"floor\"\n"
            .to_string(),
    };
    format!("{shapes}{common}")
}

/// Builds the preview's scene: the material tabulated on [`preview_table`].
fn build_scene(p: &Preview, out: &Emitter) -> ApiResult<Scene> {
    let mut desc = SceneDescription::from_str(&scene_text(p), "<preview>", Path::new("."))?;
    // Cells per unit of uv: the sphere's u runs once around, its v from pole to pole.
    let yarns_per_unit = match p.shape {
        Shape::Sphere => [p.cells * 2.0, p.cells],
        Shape::Drape => [p.cells, p.cells],
    };
    let mut spec = WovenSpec::new(p.material.clone());
    spec.yarns_per_unit = yarns_per_unit;
    spec.weft_color = p.colors[0].map(Rgb);
    spec.warp_color = p.colors[1].map(Rgb);
    desc.materials
        .insert("cloth".into(), MaterialDesc::Woven(Box::new(spec)));
    let progress = |done: usize, total: usize| {
        out.send(&Message::Table { done, total });
    };
    Ok(Scene::build(
        &desc,
        &TableGrid::Custom(preview_table()),
        &|_| {},
        &progress,
    )?)
}

/// Renders the preview pass by pass, sending the running mean after each; returns early once
/// stale. Errors before the first pass (the scene cannot be built) are sent as an `error` line.
pub fn run(p: &Preview, out: &Emitter) {
    let start = Instant::now();
    let mut scene = match build_scene(p, out) {
        Ok(s) => s,
        Err(e) => {
            out.send(&e.body());
            return;
        }
    };
    let (w, h) = (scene.film.width, scene.film.height);
    let mut sum = vec![Rgb::BLACK; w * h];
    for pass in 1..=p.passes {
        if out.cancelled() {
            return;
        }
        // One sequence of samples over the passes (stratified together with Sobol points).
        scene.film.first_sample = (pass - 1) as u64;
        let image = match render(&scene, &RenderOptions::default()) {
            Ok(i) => i,
            Err(e) => {
                out.send(&ApiError::from(e).body());
                return;
            }
        };
        for (acc, px) in sum.iter_mut().zip(&image.pixels) {
            *acc += *px;
        }
        let mut bytes = Vec::with_capacity(w * h * 3);
        for px in &sum {
            for c in px.0 {
                let linear = (c / pass as f64).clamp(0.0, 1.0);
                bytes.push((srgb_encode(linear) * 255.0).round() as u8);
            }
        }
        let sent = out.send(&Message::Image {
            pass,
            width: w,
            height: h,
            rgb: base64::engine::general_purpose::STANDARD.encode(&bytes),
            ms: start.elapsed().as_secs_f64() * 1e3,
        });
        if !sent {
            return;
        }
    }
    out.send(&Message::Done {
        ms: start.elapsed().as_secs_f64() * 1e3,
    });
}
