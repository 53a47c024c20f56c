//! `[inset]`: a second view over a rectangle of the film. Outside it the render is the render
//! without it, pixel for pixel; its border is white; inside it is what its camera alone sees.

use crate::render_text;

pub(crate) const SCENE: &str = r#"
[camera]
origin = [0.3, -2.0, 2.2]
target = [0.0, 0.0, 0.0]
fov_deg = 45
[film]
width = 40
height = 30
spp = 64
sampler = "independent"
seed = 5
[integrator]
max_depth = 2
[[light]]
type = "point"
position = [0.4, 0.5, 1.5]
intensity = [10, 5, 2]
[[shape]]
type = "rectangle"
corner = [-1, -1, 0]
edge_u = [2, 0, 0]
edge_v = [0, 2, 0]
material = "plane"
[[shape]]
type = "sphere"
center = [0.2, 0.1, 0.25]
radius = 0.25
material = "plane"
[material.plane]
type = "diffuse"
reflectance = [0.5, 0.8, 0.2]
"#;

/// The inset's camera and place: 18 × 18 pixels at (20, 3) with a 2-pixel border, so 14 × 14
/// inside.
pub(crate) const INSET: &str = r#"
[inset]
origin = [1.2, -1.0, 0.9]
target = [0.2, 0.1, 0.25]
fov_deg = 30
corner = [0.5, 0.1]
size = [0.45, 0.6]
border = 2
"#;

#[test]
fn an_inset_is_its_own_camera_framed_over_the_film() {
    let with = render_text(&SCENE.replace("[film]", &format!("{INSET}[film]")));
    let without = render_text(SCENE);
    // Its camera alone, on a film the inset's inner size.
    let alone = render_text(
        &SCENE
            .replace("origin = [0.3, -2.0, 2.2]", "origin = [1.2, -1.0, 0.9]")
            .replace("target = [0.0, 0.0, 0.0]", "target = [0.2, 0.1, 0.25]")
            .replace("fov_deg = 45", "fov_deg = 30")
            .replace("width = 40", "width = 14")
            .replace("height = 30", "height = 14"),
    );
    let (x0, y0, size, border) = (20, 3, 18, 2);
    let mut compared = 0;
    for y in 0..30 {
        for x in 0..40 {
            let i = y * 40 + x;
            let in_outer = (x0..x0 + size).contains(&x) && (y0..y0 + size).contains(&y);
            let in_inner = (x0 + border..x0 + size - border).contains(&x)
                && (y0 + border..y0 + size - border).contains(&y);
            if !in_outer {
                assert_eq!(with.pixels[i], without.pixels[i], "({x}, {y})");
            } else if !in_inner {
                assert_eq!(with.pixels[i], woven_render::render::INSET_BORDER);
            } else {
                let j = (y - y0 - border) * 14 + (x - x0 - border);
                for c in 0..3 {
                    let (a, b) = (with.pixels[i].0[c], alone.pixels[j].0[c]);
                    let se = with.std_error[i].0[c].hypot(alone.std_error[j].0[c]);
                    assert!(
                        (a - b).abs() <= 6.0 * se + 1e-9,
                        "({x}, {y}): {a} vs {b} ± {se}"
                    );
                }
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 14 * 14);
}
