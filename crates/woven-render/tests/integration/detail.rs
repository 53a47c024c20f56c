//! Levels of detail in renders (docs/render.md, "Levels of detail"): a close-up plane at fibre
//! level shows structure inside each cell that its yarn-level render does not have, and its cells
//! average to the yarn level's; a distant plane at fibre level averages, over the image, to
//! `auto` far away (without `relief`, the paper's yarns at every level).

use crate::build_with_user_cache;
use std::path::Path;
use woven_render::render::{render, Image, RenderOptions};
use woven_render::scene::SceneDescription;

/// A plane seen straight down through a pinhole whose film covers it exactly: `cells` × `cells`
/// cells of `preset`'s yarn in its own weave, `px` pixels a cell, under a square light 40° up,
/// 6° across (sampling it is the noise).
fn top_down(preset: &str, detail: &str, cells: usize, px: usize, spp: usize) -> String {
    let size = cells * px;
    format!(
        r#"
        [camera]
        origin = [0, 0, 20]
        target = [0, 0, 0]
        up = [0, 1, 0]
        fov_deg = 5.7248977
        [film]
        width = {size}
        height = {size}
        spp = {spp}
        sampler = "independent"
        [integrator]
        max_depth = 2
        [[light]]
        type = "rectangle"
        corner = [-6.04, -4.88, 5.62]
        edge_u = [-0.55, 0.83, 0]
        edge_v = [0.531, 0.352, 0.768]
        radiance = [65, 65, 65]
        [[shape]]
        type = "rectangle"
        corner = [-1, -1, 0]
        edge_u = [2, 0, 0]
        edge_v = [0, 2, 0]
        material = "cloth"
        [material.cloth]
        type = "woven"
        material = "{preset}"
        yarns_per_unit = {cells}
        detail = "{detail}"
        "#
    )
}

fn render_scene(text: &str) -> Image {
    let desc = SceneDescription::from_str(text, "<detail>", Path::new(".")).unwrap();
    let image = render(&build_with_user_cache(&desc), &RenderOptions::default()).unwrap();
    assert_eq!(image.invalid_samples, 0);
    image
}

/// Per cell of `px` × `px` pixels (cells × cells of them): the mean of channel 0 and the variance
/// of its pixels about that mean.
fn cell_stats(image: &Image, cells: usize, px: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(cells * cells);
    for cy in 0..cells {
        for cx in 0..cells {
            let values: Vec<f64> = (0..px * px)
                .map(|k| {
                    let (x, y) = (cx * px + k % px, cy * px + k / px);
                    image.pixels[y * image.width + x].0[0]
                })
                .collect();
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
            out.push((mean, var));
        }
    }
    out
}

/// The mean and its standard error (from the spread between rows of cells, which share a weft
/// and so a drawn slope) of the per-cell differences `a − b`.
fn mean_difference(a: &[(f64, f64)], b: &[(f64, f64)], cells: usize) -> (f64, f64) {
    let rows: Vec<f64> = (0..cells)
        .map(|r| {
            (0..cells)
                .map(|c| a[r * cells + c].0 - b[r * cells + c].0)
                .sum::<f64>()
                / cells as f64
        })
        .collect();
    let mean = rows.iter().sum::<f64>() / cells as f64;
    let var = rows.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (cells - 1) as f64;
    (mean, (var / cells as f64).sqrt())
}

/// Within-cell contrast: cells 16 pixels wide, 32 spp, the belt cloth's twill (no relief). At
/// fibre level the pixels inside a cell vary (strands, lit and shadowed facets) several times
/// more than the noise of the yarn level, whose cells are flat (measured 7 times); the cells'
/// means agree with the yarn level's (measured +0.03 %).
///
/// `cargo test --release -p woven-render --test integration within_cell -- --nocapture`
#[test]
fn fibre_level_cells_show_structure_and_keep_their_mean() {
    let (cells, px, spp) = (24, 16, 32);
    let fibers = render_scene(&top_down("belt-cloth", "fibers", cells, px, spp));
    let yarns = render_scene(&top_down("belt-cloth", "yarns", cells, px, spp));
    let (f, y) = (
        cell_stats(&fibers, cells, px),
        cell_stats(&yarns, cells, px),
    );
    let within = |s: &[(f64, f64)]| (s.iter().map(|c| c.1).sum::<f64>() / s.len() as f64).sqrt();
    let noise = |image: &Image| {
        let n = image.std_error.len() as f64;
        (image.std_error.iter().map(|e| e.0[0] * e.0[0]).sum::<f64>() / n).sqrt()
    };
    let (wf, wy) = (within(&f), within(&y));
    // The fibre level's structure: its within-cell spread less its own noise.
    let structure = (wf * wf - noise(&fibers).powi(2)).max(0.0).sqrt();
    let noise = noise(&yarns);
    let mean_y = y.iter().map(|c| c.0).sum::<f64>() / y.len() as f64;
    // The cells' means are the far level's: `auto` two pixels a cell, the same cells.
    let far = cell_stats(
        &render_scene(&top_down("belt-cloth", "auto", cells, 2, 4 * spp)),
        cells,
        2,
    );
    let mean_r = far.iter().map(|c| c.0).sum::<f64>() / far.len() as f64;
    let (d, se) = mean_difference(&f, &far, cells);
    println!(
        "within-cell std: fibers {wf:.4} (structure {structure:.4}), yarns {wy:.4}; yarn-level \
         pixel noise {noise:.4}; structure / noise {:.1}; cell means: yarns \
         {mean_y:.4}, auto far {mean_r:.4}, fibers − auto {d:+.5} ± {se:.5} ({:+.2} %)",
        structure / noise,
        100.0 * d / mean_r
    );
    // The yarn level is flat inside a cell: its pixels vary by their noise and the slow change
    // of the angles across it.
    assert!(
        wy < 2.0 * noise,
        "yarn level within-cell std {wy} vs noise {noise}"
    );
    assert!(
        structure > 5.0 * noise,
        "fibre level structure {structure} vs noise {noise}"
    );
    assert!(d.abs() < 4.0 * se + 0.01 * mean_r, "{d} ± {se}");
}

/// A distant plane (two pixels a cell, 128 yarns each way): at fibre level its image mean is the
/// resolved yarn level's (`auto` there) within noise and the spread between drawn yarns.
#[test]
fn a_distant_fibre_level_plane_averages_to_the_resolved_yarn_level() {
    let (cells, px, spp) = (128, 2, 8);
    for preset in ["belt-cloth", "silk"] {
        let fibers = render_scene(&top_down(preset, "fibers", cells, px, spp));
        let yarns = render_scene(&top_down(preset, "auto", cells, px, spp));
        let (f, y) = (
            cell_stats(&fibers, cells, px),
            cell_stats(&yarns, cells, px),
        );
        let mean_y = y.iter().map(|c| c.0).sum::<f64>() / y.len() as f64;
        let (d, se) = mean_difference(&f, &y, cells);
        println!("{preset}: auto far {mean_y:.4}, fibers − auto {d:+.5} ± {se:.5}");
        assert!(mean_y > 0.01, "{preset}: the plane is lit");
        assert!(d.abs() < 4.0 * se + 0.005 * mean_y, "{preset}: {d} ± {se}");
    }
}
