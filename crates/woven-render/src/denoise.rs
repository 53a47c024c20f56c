//! A denoiser for one rendered frame: the edge-avoiding à-trous wavelet filter (Dammertz et al.
//! 2010), its colour weight scaled by each pixel's own noise as in SVGF (Schied et al. 2017),
//! guided by what each pixel's camera rays first met.
//!
//! Each of [`PASSES`] passes averages a pixel with 5 × 5 neighbours spaced `2^pass` pixels
//! apart (a B3-spline kernel), so the passes together reach ±62 pixels at the cost of 125 taps.
//! A neighbour counts in proportion to the kernel times five weights, each 1 for a neighbour
//! like the pixel and falling toward 0 for one unlike it:
//! - **view**: the main camera, an inset's or the inset's border never mix, and a pixel at a
//!   silhouette against the sky (some rays hit, some escaped) mixes with none;
//! - **normal**: `max(0, n·n')^64`;
//! - **distance**: `exp(−|z − z'| / (2 |∇z · Δ| + 10⁻³ z))`, with `∇z` the one-sided screen
//!   gradient of the distance (the smaller side, so that an edge does not widen it);
//! - **albedo**: `exp(−‖a − a'‖∞ / (0.05 + 2 (σₐ + σₐ')))`, with `a` the first vertex's albedo
//!   estimate and `σₐ` its standard error, so a weave's yarn colours stay apart;
//! - **yarn family**: `exp(−|w − w'| / 0.1)`, with `w` the warp's share of the BRDF where the
//!   rays met the cloth (`SurfaceMaterial::warp_share`), so resolved yarns stay apart even where
//!   the albedo estimate is too noisy to tell them;
//! - **colour**: `exp(−|L − L'| / (4 σ_L + ε))`, with `σ_L` the standard error of the pixel's
//!   luminance, blurred over 3 × 3 pixels, and carried through the passes (a weighted mean's
//!   variance is `Σ w² σ² / (Σ w)²`): a difference the noise cannot explain is kept. A frame
//!   without noise passes unchanged.
//!
//! A pixel whose rays met two surfaces (at an edge) is geometrically like none of its
//! neighbours; left alone it would keep the noise of its coverage and show the edge jagged. Such
//! a *lonely* pixel (its geometric weights to its eight neighbours summing below one half) takes
//! from its neighbours by view, albedo, yarn family and colour alone, while they take nothing
//! from it.
//!
//! The filter is biased, as every denoiser is: it trades a little blur across features the
//! guides do not see for much less noise. `[film] denoise` turns it on; the EXR and PNG then
//! hold the filtered image ([`Image::noisy`](crate::render::Image::noisy) keeps the raw one).

use crate::color::Rgb;
use crate::integrator::FirstHit;
use rayon::prelude::*;
use woven::math::special::exp_neg;
use woven::Vec3;

/// Filter passes (à-trous levels).
pub const PASSES: usize = 5;

/// The B3-spline kernel by offset 0, 1, 2.
const KERNEL: [f64; 3] = [3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];
/// Colour differences within this many of the noise's standard errors are smoothed.
const SIGMA_COLOUR: f64 = 4.0;
/// The power of the normals' cosine.
const NORMAL_POWER: i32 = 64;
/// The slack, in gradients, of the distance weight.
const SIGMA_DISTANCE: f64 = 2.0;
/// The albedo difference always tolerated.
const SIGMA_ALBEDO: f64 = 0.05;
/// The albedo difference tolerated per standard error of the two estimates.
const ALBEDO_ERRORS: f64 = 2.0;
/// Below this sum of its neighbours' guide weights a pixel is lonely ([`lonely_pixels`]).
const LONELY: f64 = 0.5;
/// The difference of warp shares tolerated.
const SIGMA_WARP: f64 = 0.1;

/// What a pixel's camera rays first met (means over its samples).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guide {
    /// Which view the pixel shows: 0 the main camera, 1 the inset, 2 the inset's border.
    pub view: u8,
    /// The mean shading normal (zero where every ray escaped).
    pub normal: Vec3,
    /// The mean distance of the rays that hit ([`FirstHit::MISS_DISTANCE`] where all escaped).
    pub distance: f64,
    /// Whether some of the pixel's rays hit a surface and some escaped: a silhouette against
    /// the sky. Such a pixel is like no other, so that no neighbour takes its colour into the
    /// sky.
    pub silhouette: bool,
    /// The mean albedo estimate ([`FirstHit::albedo`]).
    pub albedo: Rgb,
    /// The standard error of `albedo`'s luminance.
    pub albedo_error: f64,
    /// The mean warp share ([`FirstHit::warp_share`]).
    pub warp_share: f64,
}

/// Sums of [`FirstHit`]s over a pixel's samples, to make its [`Guide`].
#[derive(Clone, Copy, Debug, Default)]
pub struct GuideSums {
    samples: usize,
    hits: usize,
    normal: Vec3,
    distance: f64,
    albedo: Rgb,
    albedo_lum_sq: f64,
    warp_share: f64,
}

impl GuideSums {
    /// Adds one sample's first hit.
    pub fn add(&mut self, first: &FirstHit) {
        self.samples += 1;
        if first.distance < FirstHit::MISS_DISTANCE {
            self.hits += 1;
            self.normal = self.normal + first.normal;
            self.distance += first.distance;
        }
        self.albedo += first.albedo;
        self.warp_share += first.warp_share;
        self.albedo_lum_sq += first.albedo.luminance().powi(2);
    }

    /// The pixel's guide, in view `view`.
    pub fn guide(&self, view: u8) -> Guide {
        let n = self.samples.max(1) as f64;
        let albedo = self.albedo * (1.0 / n);
        let mean_lum = albedo.luminance();
        let var = if self.samples > 1 {
            ((self.albedo_lum_sq - n * mean_lum * mean_lum) / (n - 1.0)).max(0.0)
        } else {
            0.0
        };
        let normal = if self.normal.length() > 0.0 {
            self.normal.normalize()
        } else {
            Vec3::new(0.0, 0.0, 0.0)
        };
        Guide {
            view,
            normal,
            distance: if self.hits > 0 {
                self.distance / self.hits as f64
            } else {
                FirstHit::MISS_DISTANCE
            },
            silhouette: self.hits > 0 && self.hits < self.samples,
            albedo,
            albedo_error: (var / n).sqrt(),
            warp_share: self.warp_share / n,
        }
    }
}

/// A noisy frame and its guides, row 0 at the top.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Each pixel's estimate.
    pub colour: &'a [Rgb],
    /// The variance of each estimate's luminance (its standard error squared).
    pub variance: &'a [f64],
    /// What each pixel's rays first met.
    pub guides: &'a [Guide],
}

/// The denoised frame.
///
/// # Panics
/// If the slices are not `width × height` long (a caller's bug).
pub fn denoise(frame: &Frame) -> Vec<Rgb> {
    let (w, h) = (frame.width, frame.height);
    assert!(
        frame.colour.len() == w * h && frame.variance.len() == w * h && frame.guides.len() == w * h,
        "denoise: buffers of {w}×{h} pixels expected"
    );
    let gradient = distance_gradients(w, h, frame.guides);
    let lonely = lonely_pixels(w, h, frame.guides, &gradient);
    let mut colour = frame.colour.to_vec();
    let mut variance = frame.variance.to_vec();
    for pass in 0..PASSES {
        let blurred = blur3(w, h, &variance);
        let step = 1usize << pass;
        let level = Level {
            w,
            h,
            step,
            colour: &colour,
            variance: &variance,
            blurred: &blurred,
            guides: frame.guides,
            gradient: &gradient,
            lonely: &lonely,
        };
        let mut next_colour = vec![Rgb::BLACK; w * h];
        let mut next_variance = vec![0.0; w * h];
        next_colour
            .par_chunks_mut(w)
            .zip(next_variance.par_chunks_mut(w))
            .enumerate()
            .for_each(|(y, (row_c, row_v))| {
                for x in 0..w {
                    (row_c[x], row_v[x]) = level.filter(x, y);
                }
            });
        colour = next_colour;
        variance = next_variance;
    }
    colour
}

/// One pass's inputs.
struct Level<'a> {
    w: usize,
    h: usize,
    step: usize,
    colour: &'a [Rgb],
    variance: &'a [f64],
    blurred: &'a [f64],
    guides: &'a [Guide],
    gradient: &'a [[f64; 2]],
    lonely: &'a [bool],
}

impl Level<'_> {
    /// Pixel `(x, y)` filtered, and its variance.
    fn filter(&self, x: usize, y: usize) -> (Rgb, f64) {
        let p = y * self.w + x;
        let (gp, lp) = (&self.guides[p], self.colour[p].luminance());
        let sigma_l = SIGMA_COLOUR * self.blurred[p].sqrt();
        let (mut sum, mut sum_var, mut sum_w) = (Rgb::BLACK, 0.0, 0.0);
        for dy in -2i64..=2 {
            let qy = y as i64 + dy * self.step as i64;
            if qy < 0 || qy >= self.h as i64 {
                continue;
            }
            for dx in -2i64..=2 {
                let qx = x as i64 + dx * self.step as i64;
                if qx < 0 || qx >= self.w as i64 {
                    continue;
                }
                let q = qy as usize * self.w + qx as usize;
                let kernel =
                    KERNEL[dx.unsigned_abs() as usize] * KERNEL[dy.unsigned_abs() as usize];
                let offset = [
                    (dx * self.step as i64) as f64,
                    (dy * self.step as i64) as f64,
                ];
                let mut weight = if q == p {
                    Weight::constant(kernel)
                } else if self.lonely[p] {
                    let gq = &self.guides[q];
                    let same_view = gp.view == gq.view && !gq.silhouette;
                    surface_weight(gp, gq).scaled(kernel * f64::from(u8::from(same_view)))
                } else {
                    guide_weight(gp, &self.guides[q], self.gradient[p], offset).scaled(kernel)
                };
                if weight.factor == 0.0 {
                    continue;
                }
                let dl = (lp - self.colour[q].luminance()).abs();
                if dl > 0.0 {
                    weight.exponent += dl / (sigma_l + 1e-300);
                }
                let wt = weight.value();
                if wt == 0.0 {
                    continue;
                }
                sum += self.colour[q] * wt;
                sum_var += wt * wt * self.variance[q];
                sum_w += wt;
            }
        }
        // The centre's own weight is its kernel's (> 0), so `sum_w > 0`.
        (sum * (1.0 / sum_w), sum_var / (sum_w * sum_w))
    }
}

/// A weight in two parts, `factor · e^{−exponent}`: the filter multiplies four weights that are
/// exponentials, and in this form their product takes one exponential, not four.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Weight {
    factor: f64,
    exponent: f64,
}

impl Weight {
    const ZERO: Weight = Weight::constant(0.0);

    const fn constant(factor: f64) -> Weight {
        Weight {
            factor,
            exponent: 0.0,
        }
    }

    /// The weight's value, in `[0, factor]`.
    #[inline]
    fn value(self) -> f64 {
        if self.factor == 0.0 {
            0.0
        } else {
            self.factor * exp_neg(self.exponent)
        }
    }

    fn scaled(self, k: f64) -> Weight {
        Weight {
            factor: self.factor * k,
            ..self
        }
    }

    fn times(self, o: Weight) -> Weight {
        Weight {
            factor: self.factor * o.factor,
            exponent: self.exponent + o.exponent,
        }
    }
}

/// How much like pixel `p` (guide `a`, distance gradient `grad`) its neighbour `offset` pixels
/// away (guide `b`) is, by view, normal, distance and albedo: in `[0, 1]`, 1 for itself.
fn guide_weight(a: &Guide, b: &Guide, grad: [f64; 2], offset: [f64; 2]) -> Weight {
    let geometric = geometric_weight(a, b, grad, offset);
    if geometric.factor == 0.0 {
        return Weight::ZERO;
    }
    geometric.times(surface_weight(a, b))
}

/// The part of [`guide_weight`] that compares where the rays landed: view, normal, distance.
fn geometric_weight(a: &Guide, b: &Guide, grad: [f64; 2], offset: [f64; 2]) -> Weight {
    if a.view != b.view || a.silhouette || b.silhouette {
        return Weight::ZERO;
    }
    let (miss_a, miss_b) = (
        a.distance >= FirstHit::MISS_DISTANCE,
        b.distance >= FirstHit::MISS_DISTANCE,
    );
    match (miss_a, miss_b) {
        (true, true) => Weight::constant(1.0),
        (false, false) => {
            let normal = a.normal.dot(b.normal).max(0.0).powi(NORMAL_POWER);
            let tolerance = SIGMA_DISTANCE
                * (grad[0] * offset[0].abs() + grad[1] * offset[1].abs())
                + 1e-3 * a.distance;
            Weight {
                factor: normal,
                exponent: (a.distance - b.distance).abs() / tolerance,
            }
        }
        _ => Weight::ZERO,
    }
}

/// The part of [`guide_weight`] that compares what the rays met: albedo and yarn family.
fn surface_weight(a: &Guide, b: &Guide) -> Weight {
    let da = (0..3).fold(0.0f64, |m, c| m.max((a.albedo.0[c] - b.albedo.0[c]).abs()));
    Weight {
        factor: 1.0,
        exponent: da / (SIGMA_ALBEDO + ALBEDO_ERRORS * (a.albedo_error + b.albedo_error))
            + (a.warp_share - b.warp_share).abs() / SIGMA_WARP,
    }
}

/// The pixels geometrically like none of their eight neighbours (their geometric weights summing
/// below one half): those whose rays met two surfaces, at an edge. Their mean is the edge's
/// anti-aliased value but carries its coverage noise, so they take from their neighbours by
/// colour and surface alone (the neighbours, unlike them, take nothing from them).
fn lonely_pixels(w: usize, h: usize, guides: &[Guide], gradient: &[[f64; 2]]) -> Vec<bool> {
    (0..w * h)
        .into_par_iter()
        .map(|p| {
            let (x, y) = ((p % w) as i64, (p / w) as i64);
            let g = &guides[p];
            if g.silhouette {
                return false;
            }
            let mut sum = 0.0;
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (qx, qy) = (x + dx, y + dy);
                    if (dx, dy) == (0, 0) || qx < 0 || qy < 0 || qx >= w as i64 || qy >= h as i64 {
                        continue;
                    }
                    let q = qy as usize * w + qx as usize;
                    let offset = [dx as f64, dy as f64];
                    sum += geometric_weight(g, &guides[q], gradient[p], offset).value();
                }
            }
            sum < LONELY
        })
        .collect()
}

/// Each pixel's screen gradient of the distance, `[|∂z/∂x|, |∂z/∂y|]`: per axis the smaller of
/// the one-sided differences toward neighbours that hit in the same view (0 where none does).
fn distance_gradients(w: usize, h: usize, guides: &[Guide]) -> Vec<[f64; 2]> {
    let diff = |p: usize, q: usize| {
        let (a, b) = (&guides[p], &guides[q]);
        (a.view == b.view
            && a.distance < FirstHit::MISS_DISTANCE
            && b.distance < FirstHit::MISS_DISTANCE)
            .then(|| (a.distance - b.distance).abs())
    };
    let smaller = |u: Option<f64>, v: Option<f64>| match (u, v) {
        (Some(u), Some(v)) => u.min(v),
        (Some(u), None) | (None, Some(u)) => u,
        (None, None) => 0.0,
    };
    (0..w * h)
        .map(|p| {
            let (x, y) = (p % w, p / w);
            let gx = smaller(
                (x > 0).then(|| diff(p, p - 1)).flatten(),
                (x + 1 < w).then(|| diff(p, p + 1)).flatten(),
            );
            let gy = smaller(
                (y > 0).then(|| diff(p, p - w)).flatten(),
                (y + 1 < h).then(|| diff(p, p + w)).flatten(),
            );
            [gx, gy]
        })
        .collect()
}

/// `values` blurred by a 3 × 3 Gaussian (weights 1-2-1), edges clamped.
fn blur3(w: usize, h: usize, values: &[f64]) -> Vec<f64> {
    const K: [f64; 3] = [0.25, 0.5, 0.25];
    (0..w * h)
        .map(|p| {
            let (x, y) = ((p % w) as i64, (p / w) as i64);
            let mut sum = 0.0;
            for (j, ky) in K.iter().enumerate() {
                for (i, kx) in K.iter().enumerate() {
                    let qx = (x + i as i64 - 1).clamp(0, w as i64 - 1) as usize;
                    let qy = (y + j as i64 - 1).clamp(0, h as i64 - 1) as usize;
                    sum += kx * ky * values[qy * w + qx];
                }
            }
            sum
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic stream of standard normal deviates (Box–Muller over a hash).
    fn normals(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        let mut uniform = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        move || (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos()
    }

    const W: usize = 64;

    /// A weight kept as `factor · e^{−exponent}` multiplies as the product of its values: the
    /// filter's one exponential for four is the same weight, to rounding.
    #[test]
    fn weights_multiply_in_exponent_form() {
        let mut next = normals(3);
        for _ in 0..1000 {
            let w = |next: &mut dyn FnMut() -> f64| Weight {
                factor: next().abs(),
                exponent: next().abs() * 5.0,
            };
            let (a, b) = (w(&mut next), w(&mut next));
            let (product, separate) = (a.times(b).value(), a.value() * b.value());
            assert!(
                (product - separate).abs() <= 1e-14 * separate,
                "{product} vs {separate}"
            );
            assert_eq!(a.scaled(0.0).value(), 0.0);
        }
        assert_eq!(Weight::ZERO.value(), 0.0);
        assert_eq!(Weight::constant(0.25).value(), 0.25);
    }

    fn plane(distance: f64, normal: Vec3, albedo: f64) -> Guide {
        Guide {
            view: 0,
            normal,
            distance,
            albedo: Rgb::grey(albedo),
            albedo_error: 0.0,
            silhouette: false,
            warp_share: 0.0,
        }
    }

    /// `truth` per pixel plus Gaussian noise of standard error `sigma`, and its variance.
    fn noisy(truth: &[Rgb], sigma: f64, seed: u64) -> (Vec<Rgb>, Vec<f64>) {
        let mut z = normals(seed);
        let colour = truth
            .iter()
            .map(|t| Rgb(t.0.map(|c| c + sigma * z())))
            .collect();
        (colour, vec![sigma * sigma; truth.len()])
    }

    /// The denoised `W × W` frame.
    fn run(colour: &[Rgb], variance: &[f64], guides: &[Guide]) -> Vec<Rgb> {
        denoise(&Frame {
            width: W,
            height: W,
            colour,
            variance,
            guides,
        })
    }

    fn rms(a: &[Rgb], b: &[Rgb]) -> f64 {
        let sum: f64 = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x.luminance() - y.luminance()).powi(2))
            .sum();
        (sum / a.len() as f64).sqrt()
    }

    #[test]
    fn a_noisy_plane_is_smoothed_without_moving_its_mean() {
        let truth = vec![Rgb::grey(0.5); W * W];
        let guides = vec![plane(3.0, Vec3::Z, 0.5); W * W];
        let (colour, variance) = noisy(&truth, 0.05, 1);
        let out = run(&colour, &variance, &guides);
        let (before, after) = (rms(&colour, &truth), rms(&out, &truth));
        assert!(after < before / 8.0, "rms {before:.4} → {after:.4}");
        let mean = out.iter().map(|c| c.luminance()).sum::<f64>() / out.len() as f64;
        assert!((mean - 0.5).abs() < 0.002, "mean {mean}");
    }

    #[test]
    fn an_edge_between_surfaces_stays_sharp() {
        // Left half faces the camera at 0.45, right half is tilted at 0.55: a difference the
        // colour weight alone would smooth (5 standard errors). A pixel next to the edge keeps
        // its side's value.
        let tilted = Vec3::new(0.6, 0.0, 0.8);
        let side = |x: usize| x >= W / 2;
        let truth: Vec<Rgb> = (0..W * W)
            .map(|p| Rgb::grey(if side(p % W) { 0.55 } else { 0.45 }))
            .collect();
        let guides: Vec<Guide> = (0..W * W)
            .map(|p| {
                if side(p % W) {
                    plane(3.0, tilted, 0.5)
                } else {
                    plane(3.0, Vec3::Z, 0.5)
                }
            })
            .collect();
        let (colour, variance) = noisy(&truth, 0.02, 2);
        let out = run(&colour, &variance, &guides);
        for y in 0..W {
            for x in [W / 2 - 1, W / 2] {
                let p = y * W + x;
                let err = (out[p].luminance() - truth[p].luminance()).abs();
                assert!(
                    err < 0.02,
                    "pixel ({x}, {y}): {} for {}",
                    out[p].luminance(),
                    truth[p].luminance()
                );
            }
        }
    }

    #[test]
    fn a_weave_seen_in_the_albedo_or_the_warp_share_keeps_its_pattern() {
        // A checkerboard of dark and light yarns one pixel each, on one flat surface: only the
        // albedo tells them apart, or only the warp share (the albedo estimates then alike and
        // too noisy to tell).
        let light = |p: usize| (p % W + p / W) % 2 == 0;
        let truth: Vec<Rgb> = (0..W * W)
            .map(|p| Rgb::grey(if light(p) { 0.7 } else { 0.1 }))
            .collect();
        let by_albedo: Vec<Guide> = (0..W * W)
            .map(|p| plane(3.0, Vec3::Z, if light(p) { 0.9 } else { 0.15 }))
            .collect();
        let by_share: Vec<Guide> = (0..W * W)
            .map(|p| Guide {
                albedo_error: 0.3,
                warp_share: if light(p) { 1.0 } else { 0.0 },
                ..plane(3.0, Vec3::Z, 0.5)
            })
            .collect();
        let (colour, variance) = noisy(&truth, 0.05, 3);
        for guides in [by_albedo, by_share] {
            let out = run(&colour, &variance, &guides);
            let (before, after) = (rms(&colour, &truth), rms(&out, &truth));
            assert!(after < before / 3.0, "rms {before:.4} → {after:.4}");
        }
    }

    #[test]
    fn pixels_on_an_edge_are_smoothed_without_bleeding() {
        // Two surfaces (0.45 and 0.55) meet at column W/2, whose pixels saw both in shares that
        // vary along it: each one's normal and distance are its own mix of the two, so it is
        // like none of its neighbours (lonely). Its noise is still averaged, by colour, while
        // the surfaces beside it take nothing from it.
        let tilted = Vec3::new(0.8, 0.0, 0.6);
        let edge = W / 2;
        let share = |y: usize| 0.2 + 0.6 * ((y * 37) % W) as f64 / W as f64;
        let truth: Vec<Rgb> = (0..W * W)
            .map(|p| Rgb::grey([0.45, 0.5, 0.55][((p % W).cmp(&edge) as i8 + 1) as usize]))
            .collect();
        let guides: Vec<Guide> = (0..W * W)
            .map(|p| match (p % W).cmp(&edge) {
                std::cmp::Ordering::Less => plane(3.0, Vec3::Z, 0.5),
                std::cmp::Ordering::Equal => {
                    let t = share(p / W);
                    plane(3.0 + t, (Vec3::Z * (1.0 - t) + tilted * t).normalize(), 0.5)
                }
                std::cmp::Ordering::Greater => plane(4.0, tilted, 0.5),
            })
            .collect();
        let (colour, variance) = noisy(&truth, 0.05, 5);
        let out = run(&colour, &variance, &guides);
        let column =
            |img: &[Rgb], x: usize| -> Vec<Rgb> { (0..W).map(|y| img[y * W + x]).collect() };
        let (before, after) = (
            rms(&column(&colour, edge), &column(&truth, edge)),
            rms(&column(&out, edge), &column(&truth, edge)),
        );
        assert!(after < before / 2.0, "edge rms {before:.4} → {after:.4}");
        for x in [edge - 1, edge + 1] {
            let err = rms(&column(&out, x), &column(&truth, x));
            assert!(err < 0.01, "column {x}: rms {err:.4}");
        }
    }

    #[test]
    fn a_noiseless_frame_and_other_views_keep_their_values() {
        // An exact gradient (no variance) stays as it is; so does a border column, whatever
        // its neighbours.
        let truth: Vec<Rgb> = (0..W * W)
            .map(|p| Rgb::grey((p % W) as f64 / W as f64))
            .collect();
        let mut guides = vec![plane(3.0, Vec3::Z, 0.5); W * W];
        let mut colour = truth.clone();
        let border = 10;
        for y in 0..W {
            guides[y * W + border].view = 2;
            colour[y * W + border] = Rgb::grey(4.0);
        }
        let variance = vec![0.0; W * W];
        let out = run(&colour, &variance, &guides);
        for (p, (o, c)) in out.iter().zip(&colour).enumerate() {
            assert!(
                (o.luminance() - c.luminance()).abs() < 1e-12,
                "pixel {p}: {o:?} for {c:?}"
            );
        }
    }

    #[test]
    fn guides_average_their_samples() {
        let mut sums = GuideSums::default();
        let hit = FirstHit {
            warp_share: 0.0,
            normal: Vec3::Z,
            distance: 2.0,
            albedo: Rgb::grey(0.4),
        };
        sums.add(&hit);
        sums.add(&FirstHit {
            distance: 4.0,
            albedo: Rgb::grey(0.6),
            ..hit
        });
        sums.add(&FirstHit::MISS);
        let g = sums.guide(1);
        assert_eq!((g.view, g.distance, g.silhouette), (1, 3.0, true));
        assert!((g.normal.z - 1.0).abs() < 1e-12);
        assert!((g.albedo.luminance() - 1.0 / 3.0).abs() < 1e-12);
        assert!(g.albedo_error > 0.0);
        // All escaped: a miss, not a silhouette.
        let mut sums = GuideSums::default();
        sums.add(&FirstHit::MISS);
        sums.add(&FirstHit::MISS);
        let g = sums.guide(0);
        assert_eq!((g.distance, g.silhouette), (FirstHit::MISS_DISTANCE, false));
    }
}
