//! Rendering a scene into an image: tiles over all cores, per-pixel means, progress reported to
//! a callback (the library draws nothing; the CLI draws a bar).

use crate::color::Rgb;
use crate::denoise::{self, Guide, GuideSums};
use crate::integrator::{self, Aim, FirstHit};
use crate::rng::Sampler;
use crate::scene::{Scene, View};
use crate::{Error, Result};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;
use woven::progress::Progress;

/// The inset's border ([`InsetSpec`](crate::scene::InsetSpec)), linear: bright enough to show
/// white under either tone map.
pub const INSET_BORDER: Rgb = Rgb([4.0, 4.0, 4.0]);

/// Tile side, pixels: small enough to balance the cores, large enough to amortize the overhead.
pub const TILE: usize = 16;

/// How many pixels a band of tiles holds at least, rendered over all cores before the next
/// band starts: enough tiles to keep every core busy, few enough that the band's samples,
/// kept until it ends, are small beside the film (a million pixels, some 140 MB).
const BAND_PIXELS: usize = 1 << 20;

/// The film budget, bytes: the most memory a render's film may take ([`film_bytes`]), 8 GiB.
/// Over it a render is refused before anything is allocated; 8192 × 8192 fits (4096 × 4096
/// with the denoiser, whose guides and working set take four times the memory).
pub const FILM_BUDGET_BYTES: u64 = 8 << 30;

/// The memory a `width` × `height` render holds, bytes: the film's means and standard errors
/// (and the denoiser's guides, its second colour and weights when `denoise`), the band being
/// rendered, and the encoded output file.
pub fn film_bytes(width: usize, height: usize, denoise: bool) -> u64 {
    let rgb = std::mem::size_of::<Rgb>();
    // Means and errors, and the output encoded (at most 4 bytes a channel, RGBA).
    let mut per_pixel = 2 * rgb + 16;
    if denoise {
        // The guides; the denoiser's working set at its peak: the raw means, a pass's colour
        // in and out, its variance in, out, blurred and given, the distance gradients and the
        // lonely flags.
        per_pixel += std::mem::size_of::<Guide>() + 3 * rgb + 4 * 8 + 16 + 1;
    }
    let pixels = width as u64 * height as u64;
    let band = (BAND_PIXELS as u64)
        .max(width as u64 * TILE as u64)
        .min(pixels);
    pixels * per_pixel as u64 + band * std::mem::size_of::<Pixel>() as u64
}

/// Refuses a film over [`FILM_BUDGET_BYTES`], saying by how much.
///
/// # Errors
/// [`Error::OverBudget`] naming the film budget, what the film would take and the largest
/// square film within it.
pub fn check_film_budget(width: usize, height: usize, denoise: bool) -> Result<()> {
    let need = film_bytes(width, height, denoise);
    if need <= FILM_BUDGET_BYTES {
        return Ok(());
    }
    let mut side = 1usize;
    while film_bytes(side * 2, side * 2, denoise) <= FILM_BUDGET_BYTES {
        side *= 2;
    }
    Err(Error::OverBudget {
        budget: "film".into(),
        message: format!(
            "a {width} × {height} film{} takes about {:.1} GiB while it renders, {:.1}× the \
             budget of {} GiB (a square film of {side} × {side} fits)",
            if denoise { " with the denoiser" } else { "" },
            need as f64 / (1u64 << 30) as f64,
            need as f64 / FILM_BUDGET_BYTES as f64,
            FILM_BUDGET_BYTES >> 30,
        ),
    })
}

/// How to run a render.
#[derive(Clone, Debug, Default)]
pub struct RenderOptions {
    /// Worker threads; `None`: all cores (rayon's global pool).
    pub threads: Option<usize>,
}

/// A rendered image: linear RGB per pixel, row 0 at the top.
#[derive(Clone, Debug)]
pub struct Image {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// The pixel values: the plain mean of each pixel's samples (a box filter).
    pub pixels: Vec<Rgb>,
    /// The standard error of each pixel's mean (sample standard deviation / √spp). With the
    /// Sobol sampler (the default) the samples are not independent and the mean's true error is
    /// smaller than this, often several times: it is then an upper bound, not an estimate.
    pub std_error: Vec<Rgb>,
    /// Samples whose radiance came out NaN, infinite or negative; they were counted as black.
    pub invalid_samples: u64,
    /// Samples per pixel.
    pub spp: usize,
    /// Wall time of the render, seconds (the denoiser's included).
    pub seconds: f64,
    /// With `[film] denoise`, the raw means (`pixels` then holds the denoised image, and
    /// `std_error` stays the raw means' errors); `None` otherwise.
    pub noisy: Option<Vec<Rgb>>,
}

impl Image {
    /// The pixel at column `x`, row `y`.
    pub fn at(&self, x: usize, y: usize) -> Rgb {
        self.pixels[y * self.width + x]
    }

    /// Camera samples per second.
    pub fn samples_per_second(&self) -> f64 {
        (self.width * self.height * self.spp) as f64 / self.seconds.max(1e-9)
    }
}

/// Renders `scene` with its film settings, reporting no progress.
///
/// # Errors
/// As [`render_with_progress`].
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<Image> {
    render_with_progress(scene, options, &|_: u64, _: u64| {})
}

/// Renders `scene` with its film settings. `progress` hears `(samples done, samples in all)` as
/// the render starts and after each finished tile, from the worker threads (calls may arrive
/// out of order: keep the largest), and is asked before each tile whether to stop. The library
/// draws nothing itself; the CLI draws a bar.
///
/// # Errors
/// [`Error::InvalidSetting`] for zero threads or when the thread pool cannot start;
/// [`Error::OverBudget`] for a film over [`FILM_BUDGET_BYTES`] ([`check_film_budget`]);
/// [`Error::Cancelled`] when `progress` asked to stop (the tiles already started finish).
pub fn render_with_progress(
    scene: &Scene,
    options: &RenderOptions,
    progress: &dyn Progress<u64>,
) -> Result<Image> {
    let film = &scene.film;
    check_film_budget(film.width, film.height, film.denoise)?;
    match options.threads {
        None => render_in_pool(scene, progress),
        Some(n) => {
            if n == 0 {
                return Err(Error::InvalidSetting {
                    name: "threads".into(),
                    value: "0".into(),
                    expected: "at least 1".into(),
                });
            }
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| Error::InvalidSetting {
                    name: "threads".into(),
                    value: n.to_string(),
                    expected: format!("a thread count the system can start ({e})"),
                })?;
            pool.install(|| render_in_pool(scene, progress))
        }
    }
}

fn render_in_pool(scene: &Scene, progress: &dyn Progress<u64>) -> Result<Image> {
    let film = &scene.film;
    let (w, h, spp) = (film.width, film.height, film.spp);
    let tiles_x = w.div_ceil(TILE);
    let tiles_y = h.div_ceil(TILE);
    let total = (w * h * spp) as u64;
    progress.update(0, total);
    let done = AtomicU64::new(0);
    let invalid = AtomicU64::new(0);
    let start = Instant::now();

    let want_guides = film.denoise;
    let mut pixels = vec![Rgb::BLACK; w * h];
    let mut std_error = vec![Rgb::BLACK; w * h];
    let mut guides = Vec::new();
    if want_guides {
        guides.resize(w * h, GuideSums::default().guide(0));
    }
    // Bands of tile rows, each rendered over all cores and written into the film before the
    // next starts: what is held besides the film is one band's pixels, not the whole image's.
    let band_rows = (BAND_PIXELS / (w * TILE)).max(1);
    for band in (0..tiles_y).step_by(band_rows) {
        let rows = band..(band + band_rows).min(tiles_y);
        let tiles: Vec<Vec<Pixel>> = (rows.start * tiles_x..rows.end * tiles_x)
            .into_par_iter()
            .map(|t| {
                if progress.cancelled() {
                    return Vec::new();
                }
                let mut out = Vec::with_capacity(TILE * TILE);
                let (tx, ty) = (t % tiles_x, t / tiles_x);
                let mut bad = 0;
                let mut scratch = integrator::Scratch::default();
                for y in ty * TILE..((ty + 1) * TILE).min(h) {
                    for x in tx * TILE..((tx + 1) * TILE).min(w) {
                        out.push(render_pixel(scene, x, y, &mut scratch, &mut bad));
                    }
                }
                invalid.fetch_add(bad, Ordering::Relaxed);
                let samples = (out.len() * spp) as u64;
                progress.update(done.fetch_add(samples, Ordering::Relaxed) + samples, total);
                out
            })
            .collect();
        if progress.cancelled() {
            return Err(Error::Cancelled);
        }
        for p in tiles.into_iter().flatten() {
            pixels[p.index] = p.mean;
            std_error[p.index] = p.se;
            if want_guides {
                guides[p.index] = p.guide;
            }
        }
    }
    let noisy = want_guides.then(|| {
        // The luminance's variance, its channels' errors taken as fully correlated.
        let variance: Vec<f64> = std_error.iter().map(|e| e.luminance().powi(2)).collect();
        let denoised = denoise::denoise(&denoise::Frame {
            width: w,
            height: h,
            colour: &pixels,
            variance: &variance,
            guides: &guides,
        });
        std::mem::replace(&mut pixels, denoised)
    });
    Ok(Image {
        width: w,
        height: h,
        pixels,
        std_error,
        invalid_samples: invalid.into_inner(),
        spp,
        seconds: start.elapsed().as_secs_f64(),
        noisy,
    })
}

/// Film pixel `(x, y)`: its samples' mean, their standard error and its denoising guide; `bad`
/// counts the samples that came back invalid (counted as black).
fn render_pixel<'a>(
    scene: &'a Scene,
    x: usize,
    y: usize,
    scratch: &mut integrator::Scratch<'a>,
    bad: &mut u64,
) -> Pixel {
    let film = &scene.film;
    let (w, spp) = (film.width, film.spp);
    let want_guides = film.denoise;
    let pixel = (y * w + x) as u64;
    let mut sum = Rgb::BLACK;
    let mut sum_sq = Rgb::BLACK;
    let mut guide = GuideSums::default();
    let view = scene.view_at(x, y);
    // A pixel whose every ray passes by the scene's boxes meets nothing: its rays escape
    // untraced, and with no sky behind them its samples are black without being drawn (the
    // same image, bit for bit, as tracing them).
    // The camera and its film pixel; none on the inset's border.
    let seen = match view {
        View::Main => Some((&scene.camera, [x, y])),
        View::Inset(camera, at) => Some((camera, at)),
        View::Border => None,
    };
    let aim = match seen {
        Some((camera, [px, py])) if camera.pixel_misses(px, py, scene.accel.boxes()) => Aim::Clear,
        _ => Aim::Unknown,
    };
    let black = aim == Aim::Clear && scene.environment.is_none();
    for s in 0..spp {
        let Some((camera, [px, py])) = seen else {
            sum += INSET_BORDER;
            sum_sq += INSET_BORDER * INSET_BORDER;
            continue;
        };
        if black {
            if want_guides {
                guide.add(&FirstHit::MISS);
            }
            continue;
        }
        let mut sampler =
            Sampler::new(film.sampler, film.seed, pixel, film.first_sample + s as u64);
        let (dx, dy) = sampler.next2();
        let ray = camera.ray(px as f64 + dx, py as f64 + dy);
        let mut l = if want_guides {
            let (l, first) =
                integrator::radiance_and_first_hit(scene, camera, ray, aim, &mut sampler, scratch);
            guide.add(&first);
            l
        } else {
            integrator::radiance(scene, camera, ray, aim, &mut sampler, scratch)
        };
        if !l.is_valid() {
            // Guard: a NaN, infinite or negative sample counts as black.
            *bad += 1;
            l = Rgb::BLACK;
        }
        sum += l;
        sum_sq += l * l;
    }
    let n = spp as f64;
    let mean = sum / n;
    let var = if spp > 1 {
        Rgb(std::array::from_fn(|c| {
            ((sum_sq.0[c] - sum.0[c] * mean.0[c]) / (n - 1.0)).max(0.0)
        }))
    } else {
        Rgb::BLACK
    };
    let se = Rgb(var.0.map(|v| (v / n).sqrt()));
    let view = match view {
        View::Main => 0,
        View::Inset(..) => 1,
        View::Border => 2,
    };
    Pixel {
        index: y * w + x,
        mean,
        se,
        guide: guide.guide(view),
    }
}

/// One rendered pixel.
struct Pixel {
    index: usize,
    mean: Rgb,
    se: Rgb,
    guide: Guide,
}
