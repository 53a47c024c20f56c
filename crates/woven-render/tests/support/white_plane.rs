//! The white furnace's scene and its figures, shared by the furnace test
//! (`tests/integration/furnace.rs`) and the `furnace_table` example.

/// The white furnace of a woven plane: a white-dyed plain weave of `preset` (laid as a relief
/// where `relief`), `cells` cells
/// across (16: 4 a unit of length, the close-up of the furnace table in docs/render.md), 4 × 4 units, seen from `(0, −1, 1)` at 30° in a
/// uniform sky of radiance 1 (hidden), one bounce, `px` × `px` pixels at `spp` independent
/// samples.
pub fn white_plane(
    preset: &str,
    (detail, relief, u_max_deg, gap): (&str, bool, f64, f64),
    cells: usize,
    px: usize,
    spp: usize,
) -> String {
    format!(
        r#"
        [camera]
        origin = [0, -1, 1]
        target = [0, 0, 0]
        up = [0, 0, 1]
        fov_deg = 30
        [film]
        width = {px}
        height = {px}
        spp = {spp}
        sampler = "independent"
        [integrator]
        max_depth = 2
        hide_emitters = true
        [[light]]
        type = "environment"
        radiance = [1, 1, 1]
        [[shape]]
        type = "rectangle"
        corner = [-2, -2, 0]
        edge_u = [4, 0, 0]
        edge_v = [0, 4, 0]
        material = "cloth"
        [material.cloth]
        type = "woven"
        material = "{preset}"
        pattern = "plain"
        yarns_per_unit = {cells}
        weft_color = [0.999, 0.999, 0.999]
        warp_color = [0.999, 0.999, 0.999]
        u_max_deg = {u_max_deg}
        gap = {gap}
        detail = "{detail}"
        relief = {relief}
        "#
    )
}

/// The brightest pixel (its largest channel), the share of pixels above 1.05, the image mean,
/// the largest excess over 1 in the pixel's own standard errors, and the standard error of the
/// image mean (from the pixels' own), of a white plane's furnace.
pub fn furnace_figures(image: &woven_render::render::Image) -> (f64, f64, f64, f64, f64) {
    let values: Vec<f64> = image.pixels.iter().map(|p| p.max()).collect();
    let n = values.len() as f64;
    let brightest = values.iter().copied().fold(0.0, f64::max);
    let above = values.iter().filter(|v| **v > 1.05).count() as f64 / n;
    let mean = image.pixels.iter().map(|p| p.0[1]).sum::<f64>() / n;
    let excess = image
        .pixels
        .iter()
        .zip(&image.std_error)
        .map(|(p, se)| (p.max() - 1.0) / se.max().max(1e-9))
        .fold(f64::NEG_INFINITY, f64::max);
    let mean_se = image
        .std_error
        .iter()
        .map(|se| se.0[1].powi(2))
        .sum::<f64>()
        .sqrt()
        / n;
    (brightest, above, mean, excess, mean_se)
}
