//! The BRDF over the whole view hemisphere, on a grid of the orthographic (azimuthal) projection.
//!
//! A view direction `v = (sin θr cos φr, sin θr sin φr, cos θr)` maps to the point
//! `(x, y) = (sin θr cos φr, sin θr sin φr)` of the unit disc: the hemisphere seen from above,
//! the weft (`x`) to the right and the warp (`y`) up. The BRDF is evaluated on an `n × n` grid of
//! cell centres over `[−1, 1]²` and read back anywhere in the disc by bilinear interpolation, so
//! that a slow material can be drawn at any image size from a coarse grid.
//!
//! `woven plot hemisphere` and the explorer (`woven serve`) draw this map; both compute it here.

use crate::bsdf::Bsdf;
use crate::Vec3;
use rayon::prelude::*;

/// The largest `sin θr` evaluated (θr = 89.9°): the BRDF is 0 at the horizon itself, while its
/// limit there is not; grid nodes on or outside the rim take the value just inside it.
pub const RIM: f64 = 0.999_998_476_913_287_7;

/// The BRDF on a square grid over the projected hemisphere.
#[derive(Clone, Debug)]
pub struct Grid {
    /// Nodes per side.
    pub n: usize,
    /// `f(s, v)` in sr⁻¹, row-major, row 0 at the top (`y` near +1), column 0 at the left
    /// (`x` near −1); NaN at nodes too far outside the disc to be needed.
    pub values: Vec<f64>,
}

/// The coordinate (`x`, or `−y` for rows) of node or pixel `k` of `n` across `[−1, 1]`: cell
/// centres.
pub fn centre(k: usize, n: usize) -> f64 {
    -1.0 + (2 * k + 1) as f64 / n as f64
}

/// The view direction at disc point `(x, y)`, pulled in to [`RIM`] when on or beyond the rim.
pub fn view_direction(x: f64, y: f64) -> Vec3 {
    let r = x.hypot(y);
    let (x, y) = if r > RIM {
        (x * RIM / r, y * RIM / r)
    } else {
        (x, y)
    };
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

/// Which hemisphere of view directions a grid covers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Side {
    /// Above the cloth: what it reflects.
    #[default]
    Above,
    /// Below the cloth, seen from above through it (disc point `(x, y)` is the direction
    /// `(x, y, −√(1 − x² − y²))`): what a cloth that lets light through transmits.
    Below,
}

impl Side {
    /// The view direction at disc point `(x, y)` on this side ([`view_direction`], mirrored
    /// below the cloth's plane for [`Side::Below`]).
    pub fn view(self, x: f64, y: f64) -> Vec3 {
        let v = view_direction(x, y);
        match self {
            Side::Above => v,
            Side::Below => Vec3::new(v.x, v.y, -v.z),
        }
    }
}

/// Whether node `(row, col)` of an `n`-grid can take part in interpolating a point of the disc:
/// it lies within one grid diagonal of the unit circle.
fn needed(row: usize, col: usize, n: usize) -> bool {
    let (x, y) = (centre(col, n), -centre(row, n));
    x.hypot(y) <= 1.0 + 2.0 * std::f64::consts::SQRT_2 / n as f64
}

/// The number of nodes [`evaluate`] computes on an `n`-grid (for a progress bar's length).
pub fn nodes_needed(n: usize) -> u64 {
    (0..n)
        .map(|row| (0..n).filter(|&col| needed(row, col, n)).count() as u64)
        .sum()
}

/// Evaluates `model` (any single-valued BSDF: a woven [`Model`](crate::Model), a table, a
/// colour BSDF's [`Luminance`](crate::catalog::Luminance)) for light from `s` at the nodes of
/// an `n × n` grid of view directions on `side`, rows in parallel;
/// `progress` is called with the number of nodes each finished row computed (from any thread).
///
/// # Panics
/// If `n < 2`.
pub fn evaluate<B: Bsdf<Value = f64> + ?Sized>(
    model: &B,
    s: Vec3,
    n: usize,
    side: Side,
    progress: impl Fn(u64) + Sync,
) -> Grid {
    assert!(n >= 2, "a grid needs at least 2 nodes per side");
    let mut values = vec![f64::NAN; n * n];
    values.par_chunks_mut(n).enumerate().for_each(|(row, out)| {
        progress(evaluate_row(model, s, n, row, side, out));
    });
    Grid { n, values }
}

/// Evaluates row `row` of an `n × n` grid into `out` (length `n`; nodes that are not needed
/// are left as they are) and returns the number of nodes computed: the unit of work of
/// [`evaluate`], for callers that schedule rows themselves (to stop between rows, say).
///
/// # Panics
/// If `out.len() != n` or `row >= n`.
pub fn evaluate_row<B: Bsdf<Value = f64> + ?Sized>(
    model: &B,
    s: Vec3,
    n: usize,
    row: usize,
    side: Side,
    out: &mut [f64],
) -> u64 {
    assert!(out.len() == n && row < n, "row {row} of an {n}-grid");
    let y = -centre(row, n);
    let mut done = 0;
    for (col, value) in out.iter_mut().enumerate() {
        if needed(row, col, n) {
            *value = model.eval(s, side.view(centre(col, n), y));
            done += 1;
        }
    }
    done
}

impl Grid {
    /// The node value at `(row, col)`.
    fn at(&self, row: usize, col: usize) -> f64 {
        self.values[row * self.n + col]
    }

    /// The BRDF at disc point `(x, y)` by bilinear interpolation between the four nearest nodes
    /// (clamped at the grid's edge).
    pub fn sample(&self, x: f64, y: f64) -> f64 {
        let n = self.n;
        // Continuous node indices: node k sits at k + ½ cells from the edge.
        let fx = ((x + 1.0) * 0.5 * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
        let fy = ((1.0 - y) * 0.5 * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
        let (c0, r0) = (fx.floor() as usize, fy.floor() as usize);
        let (c1, r1) = ((c0 + 1).min(n - 1), (r0 + 1).min(n - 1));
        let (tx, ty) = (fx - c0 as f64, fy - r0 as f64);
        let top = self.at(r0, c0) * (1.0 - tx) + self.at(r0, c1) * tx;
        let bottom = self.at(r1, c0) * (1.0 - tx) + self.at(r1, c1) * tx;
        top * (1.0 - ty) + bottom * ty
    }

    /// The largest node value inside the disc (0 when there is none).
    pub fn max_in_disc(&self) -> f64 {
        let n = self.n;
        (0..n * n)
            .filter(|&k| centre(k % n, n).hypot(centre(k / n, n)) <= 1.0)
            .map(|k| self.values[k])
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max)
    }

    /// The image of the disc at `diameter` pixels: row-major, `None` outside the disc.
    pub fn upsample(&self, diameter: usize) -> Vec<Option<f64>> {
        let mut pixels = vec![None; diameter * diameter];
        pixels
            .par_chunks_mut(diameter)
            .enumerate()
            .for_each(|(row, out)| {
                let y = -centre(row, diameter);
                for (col, pixel) in out.iter_mut().enumerate() {
                    let x = centre(col, diameter);
                    if x.hypot(y) <= 1.0 {
                        *pixel = Some(self.sample(x, y));
                    }
                }
            });
        pixels
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fiber::FiberParams;
    use crate::material::Material;
    use crate::Model;

    fn model() -> Model {
        Material::flat(FiberParams::rough(1.5, 0.2, 0.1))
            .build(550.0)
            .unwrap()
    }

    #[test]
    fn a_grid_as_fine_as_the_image_is_exact() {
        let m = model();
        let s = Vec3::from_spherical(0.6, 0.3);
        let n = 24;
        let grid = evaluate(&m, s, n, Side::Above, |_| {});
        let image = grid.upsample(n);
        for row in 0..n {
            for col in 0..n {
                let (x, y) = (centre(col, n), -centre(row, n));
                match image[row * n + col] {
                    Some(f) => {
                        assert!(x.hypot(y) <= 1.0);
                        // Exact up to the rounding of the node coordinates.
                        let want = m.eval(s, view_direction(x, y));
                        assert!(
                            (f - want).abs() <= 1e-12 * want,
                            "({x}, {y}): {f} vs {want}"
                        );
                    }
                    None => assert!(x.hypot(y) > 1.0),
                }
            }
        }
        // Every pixel of a finer image reads finite values: the nodes it needs were computed.
        assert!(grid
            .upsample(97)
            .iter()
            .flatten()
            .all(|f| f.is_finite() && *f >= 0.0));
    }

    #[test]
    fn bilinear_reads_between_nodes_and_the_mapping_is_orthographic() {
        let grid = Grid {
            n: 2,
            values: vec![1.0, 2.0, 3.0, 4.0],
        };
        // Nodes at x, y = ±½; row 0 is the top (y = +½).
        assert_eq!(grid.sample(-0.5, 0.5), 1.0);
        assert_eq!(grid.sample(0.5, -0.5), 4.0);
        assert_eq!(grid.sample(0.0, 0.0), 2.5);
        assert_eq!(grid.sample(-0.9, 0.9), 1.0);
        let v = view_direction(0.5, 0.0);
        assert!((v.to_spherical().0 - 30f64.to_radians()).abs() < 1e-12);
        let rim = view_direction(0.0, 2.0);
        assert!(rim.z > 0.0 && (rim.length() - 1.0).abs() < 1e-12 && rim.y > 0.999);
        assert_eq!(nodes_needed(2), 4);
    }

    #[test]
    fn the_mirror_direction_is_the_brightest_of_a_smooth_surface() {
        let m = Material::flat(FiberParams::rough(1.5, 0.05, 0.0))
            .build(550.0)
            .unwrap();
        let s = Vec3::from_spherical(40f64.to_radians(), 0.0);
        let n = 64;
        let grid = evaluate(&m, s, n, Side::Above, |_| {});
        let best = (0..n * n)
            .filter(|&k| grid.values[k].is_finite())
            .max_by(|&a, &b| grid.values[a].total_cmp(&grid.values[b]))
            .unwrap();
        let (x, y) = (centre(best % n, n), -centre(best / n, n));
        // Mirror direction: φ = π, sin 40° ≈ 0.643 from the centre (the off-specular peak sits a
        // little further out).
        assert!(
            y.abs() < 0.05 && x < -0.6 && x > -0.75,
            "peak at ({x}, {y})"
        );
        assert!(grid.max_in_disc() == grid.values[best]);
    }
}
