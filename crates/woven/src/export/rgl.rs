//! Anisotropic BRDFs in RGL's `.bsdf` format (Dupuy & Jakob 2018, "An adaptive
//! parameterization for efficient material acquisition and rendering"), which Mitsuba 3's
//! `measured` plugin and pbrt-v4's `MeasuredBxDF` read natively.
//!
//! # The format
//!
//! A [tensor file](crate::tensor) with these fields (`θ`, `φ` in radians; `u`-coordinates in
//! `[0, 1]`: `u_θ = √(2θ/π)`, `u_φ = (φ + π)/2π`):
//!
//! | field | type, shape | content |
//! |---|---|---|
//! | `description` | `u8 [len]` | a text |
//! | `jacobian` | `u8 [1]` | 1: the stored values are divided by `D/(4σ)`, which the reader multiplies back |
//! | `theta_i`, `phi_i` | `f32 [n]` | the incident directions' nodes; `phi_i` spans `[−π, π]`, the full circle (pbrt-v4 refuses a folded span) |
//! | `ndf` | `f32 [n_φ, n_θ]` | `D(m)` at the half vectors `(u_θ, u_φ)` |
//! | `sigma` | `f32 [n_φ, n_θ]` | `σ(ω) = ∫ D(m)⟨ω·m⟩ dm` at the same grid |
//! | `vndf` | `f32 [φi, θi, m, m]` | per incident direction, a density over `(u_θ, u_φ)`: the warp that carries the sample square to half vectors |
//! | `luminance` | `f32 [φi, θi, n, n]` | per incident direction, the density over the sample square with which the reader draws |
//! | `rgb` or `spectra` | `f32 [φi, θi, c, n, n]` | the BRDF at the sample square's nodes, as `f·cos θo · 4σ(ωi)/D(m)` |
//! | `wavelengths` | `f32 [c]` | spectral files only: the channels' wavelengths, nm |
//!
//! A reader maps the half vector `m` of `(ωi, ωo)` through the inverse of the `vndf` warp
//! ([`Marginal2D`]) to the sample square, interpolates the stored values there (and
//! linearly between incident nodes), and multiplies by `D(m)/(4σ(ωi))`: `f·cos θo`. The
//! `incident` direction is the one a renderer holds when it looks the BRDF up: Mitsuba's
//! `si.wi` and pbrt's `wo`, toward the camera. So the file holds `f(s = ωo, v = ωi)` in woven's
//! names, `s` toward the light and `v` toward the viewer, which matters for the `paper`
//! normalization (not reciprocal).
//!
//! # How woven builds one
//!
//! - `D` is the fixed point of the power iteration that the format's authors use on
//!   retro-reflection, `D ∝ f(ω, ω) cos θ · σ[D](ω)` normalized to `∫ D cos θm dm = 1`, mixed
//!   with a tenth of the uniform `1/π`. It only factors the lobe's shape out of the stored
//!   values; a reader multiplies it back.
//! - The `vndf` warp is uniform over the half vectors whose mirror direction stays above the
//!   horizon (the note on `vndf` in the source says why not `D`'s). Every node of the sample square is mapped
//!   through it, as the reader will map it ([`Marginal2D`]), to its half vector and outgoing
//!   direction, where the BRDF is evaluated.
//! - `luminance` is `f·cos θo` (Rec. 709 luminance) over the density with which the `vndf`
//!   warp alone would draw `ωo`, so that the reader draws `ωo` in proportion to `f·cos θo`;
//!   a floor of a hundredth of its mean keeps every direction reachable.
//!
//! A spectral file lays the three channels on the spectrum: linearly between blue at 450 nm,
//! green at 540 nm and red at 610 nm, constant beyond ([`channel_weights`]); by default it holds
//! just those three wavelengths ([`default_wavelengths`]).

use crate::bsdf::Bsdf;
use crate::catalog::AnyMaterial;
use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::math::marginal::Marginal2D;
use crate::math::Vec3;
use crate::progress::Progress;
use crate::surface::{Detail, SurfacePoint, SurfaceSpec, WovenSurface};
use crate::table::cache::Tables;
use crate::table::TableOptions;
use crate::tensor::{self, Data};
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};
use std::io::Write;

/// How finely a `.bsdf` file resolves a BRDF, and in which channels.
#[derive(Clone, Debug, PartialEq)]
pub struct RglOptions {
    /// Incident polar nodes, uniform from 0 to [`theta_max_deg`](Self::theta_max_deg).
    pub n_theta_i: usize,
    /// Incident azimuth nodes, uniform over `[−π, π]` (both ends: the first and last are the
    /// same direction).
    pub n_phi_i: usize,
    /// Nodes along each side of the sample square (`vndf`, `luminance` and the values).
    pub n_grid: usize,
    /// Nodes along each side of each incident direction's `vndf` grid, the warp from the
    /// sample square to half vectors.
    pub n_vndf: usize,
    /// Nodes along each side of the `ndf` and `sigma` grids.
    pub n_ndf: usize,
    /// The last incident polar node, degrees; beyond it a reader holds the last node's values.
    pub theta_max_deg: f64,
    /// RGB or spectral values.
    pub channels: Channels,
}

/// A file's channels.
#[derive(Clone, Debug, PartialEq)]
pub enum Channels {
    /// Three, red, green and blue (field `rgb`): Mitsuba 3's RGB variants.
    Rgb,
    /// One per wavelength, nm, increasing (fields `spectra`, `wavelengths`): Mitsuba 3's
    /// spectral variants and pbrt-v4.
    Spectral(Vec<f64>),
}

/// The wavelengths of a spectral file by default: 450, 540 and 610 nm, where
/// [`channel_weights`] is blue, green and red alone. Readers interpolate linearly between a
/// file's wavelengths and hold its ends beyond them, so these three give every wavelength
/// exactly the spectrum [`channel_weights`] lays out, in a file the size of an RGB one.
pub fn default_wavelengths() -> Vec<f64> {
    vec![450.0, 540.0, 610.0]
}

impl Default for RglOptions {
    fn default() -> RglOptions {
        RglOptions {
            n_theta_i: 24,
            n_phi_i: 37,
            n_grid: 48,
            n_vndf: 32,
            n_ndf: 48,
            theta_max_deg: 87.0,
            channels: Channels::Rgb,
        }
    }
}

/// The options' limits, so that a file stays below about 2 GiB.
const MAX_NODES: usize = 1024;

impl RglOptions {
    /// Checks every option against its range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the option, its value and its range.
    pub fn validate(&self) -> Result<()> {
        let count = |name: &str, n: usize, lo: usize, hi: usize| {
            if (lo..=hi).contains(&n) {
                Ok(())
            } else {
                Err(Error::invalid(name, n.to_string(), format!("{lo} to {hi}")))
            }
        };
        count("n_theta_i", self.n_theta_i, 2, 256)?;
        count("n_phi_i", self.n_phi_i, 3, 1024)?;
        count("n_grid", self.n_grid, 4, 256)?;
        count("n_vndf", self.n_vndf, 4, 256)?;
        count("n_ndf", self.n_ndf, 4, 256)?;
        if !(self.theta_max_deg > 0.0 && self.theta_max_deg < 90.0) {
            return Err(Error::invalid(
                "theta_max_deg",
                self.theta_max_deg.to_string(),
                "more than 0 and less than 90",
            ));
        }
        if let Channels::Spectral(nm) = &self.channels {
            let ok = !nm.is_empty()
                && nm.len() <= MAX_NODES
                && nm.iter().all(|l| l.is_finite() && *l > 0.0)
                && nm.windows(2).all(|p| p[0] < p[1]);
            if !ok {
                return Err(Error::invalid(
                    "wavelengths",
                    format!("{nm:?}"),
                    format!("1 to {MAX_NODES} positive, increasing wavelengths (nm)"),
                ));
            }
        }
        Ok(())
    }

    /// The number of channels.
    pub fn n_channels(&self) -> usize {
        match &self.channels {
            Channels::Rgb => 3,
            Channels::Spectral(nm) => nm.len(),
        }
    }

    /// The size of the file these options write, bytes.
    pub fn file_len(&self, description: &str) -> u64 {
        let slices = (self.n_phi_i * self.n_theta_i) as u64;
        let grid = (self.n_grid * self.n_grid) as u64;
        let floats = (self.n_theta_i + self.n_phi_i) as u64
            + 2 * (self.n_ndf * self.n_ndf) as u64
            + slices * (self.n_vndf * self.n_vndf) as u64
            + slices * grid * (1 + self.n_channels() as u64)
            + matches!(self.channels, Channels::Spectral(_)) as u64 * self.n_channels() as u64;
        // The header and alignment: at most 100 bytes a field.
        4 * floats + description.len() as u64 + 1 + 1000
    }

    fn theta_i(&self) -> Vec<f64> {
        let last = self.theta_max_deg.to_radians();
        (0..self.n_theta_i)
            .map(|k| last * k as f64 / (self.n_theta_i - 1) as f64)
            .collect()
    }

    fn phi_i(&self) -> Vec<f64> {
        (0..self.n_phi_i)
            .map(|k| -PI + 2.0 * PI * k as f64 / (self.n_phi_i - 1) as f64)
            .collect()
    }
}

/// The weights of red, green and blue in a spectral file's channel at `nm`: linear between blue
/// at 450 nm, green at 540 nm and red at 610 nm, constant beyond. They sum to 1, so a grey
/// BRDF is the same at every wavelength.
pub fn channel_weights(nm: f64) -> [f64; 3] {
    const BLUE: f64 = 450.0;
    const GREEN: f64 = 540.0;
    const RED: f64 = 610.0;
    if nm <= BLUE {
        [0.0, 0.0, 1.0]
    } else if nm <= GREEN {
        let t = (nm - BLUE) / (GREEN - BLUE);
        [0.0, t, 1.0 - t]
    } else if nm <= RED {
        let t = (nm - GREEN) / (RED - GREEN);
        [t, 1.0 - t, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// `u_θ` of a polar angle.
fn theta_to_u(theta: f64) -> f64 {
    (theta / FRAC_PI_2).max(0.0).sqrt()
}

/// `u_φ` of an azimuth in `[−π, π]`.
fn phi_to_u(phi: f64) -> f64 {
    (phi + PI) / (2.0 * PI)
}

/// The direction at `(u_θ, u_φ)`.
fn direction(u: [f64; 2]) -> Vec3 {
    Vec3::from_spherical(u[0] * u[0] * FRAC_PI_2, (2.0 * u[1] - 1.0) * PI)
}

/// `dω/du` at `u`: `2π² u_θ sin θ`.
fn jacobian(u: [f64; 2]) -> f64 {
    2.0 * PI * PI * u[0] * (u[0] * u[0] * FRAC_PI_2).sin()
}

/// A square grid of values over `(u_θ, u_φ)` (`x` = `u_θ` fastest), read as the readers read
/// `ndf` and `sigma`: bilinearly, clamped to the square.
#[derive(Clone, Debug)]
struct UGrid {
    n: usize,
    values: Vec<f64>,
}

impl UGrid {
    fn node(&self, k: usize) -> [f64; 2] {
        let step = 1.0 / (self.n - 1) as f64;
        [(k % self.n) as f64 * step, (k / self.n) as f64 * step]
    }

    fn eval(&self, u: [f64; 2]) -> f64 {
        let scale = (self.n - 1) as f64;
        let g = u.map(|v| v.clamp(0.0, 1.0) * scale);
        let [x, y] = g.map(|v| (v as usize).min(self.n - 2));
        let (fx, fy) = (g[0] - x as f64, g[1] - y as f64);
        let at = |i: usize, j: usize| self.values[j * self.n + i];
        let lo = at(x, y) + (at(x + 1, y) - at(x, y)) * fx;
        let hi = at(x, y + 1) + (at(x + 1, y + 1) - at(x, y + 1)) * fx;
        lo + (hi - lo) * fy
    }
}

/// The share of the uniform NDF mixed into `D`.
const UNIFORM_SHARE: f64 = 0.1;

/// Power iterations on retro-reflection.
const ITERATIONS: usize = 8;

/// `D` and `σ` on an `n × n` grid from the retro-reflection `retro(ω) = f(ω, ω) cos θ`.
fn ndf_and_sigma(n: usize, retro: &(dyn Fn(Vec3) -> f64 + Sync)) -> (UGrid, UGrid) {
    let grid = UGrid {
        n,
        values: vec![0.0; n * n],
    };
    let dirs: Vec<Vec3> = (0..n * n).map(|k| direction(grid.node(k))).collect();
    let weights: Vec<f64> = (0..n * n)
        .map(|k| {
            let (x, y) = (k % n, k / n);
            let edge = |i: usize| if i == 0 || i == n - 1 { 0.5 } else { 1.0 };
            edge(x) * edge(y) * jacobian(grid.node(k)) / ((n - 1) * (n - 1)) as f64
        })
        .collect();
    let retro: Vec<f64> = dirs.par_iter().map(|&d| retro(d).max(0.0)).collect();
    let sigma_of = |d: &[f64]| -> Vec<f64> {
        dirs.par_iter()
            .map(|w| {
                dirs.iter()
                    .zip(weights.iter().zip(d))
                    .map(|(m, (wt, dm))| wt * dm * w.dot(*m).max(0.0))
                    .sum()
            })
            .collect()
    };
    let normalized = |mut d: Vec<f64>| {
        let mass: f64 = d
            .iter()
            .zip(&weights)
            .zip(&dirs)
            .map(|((v, w), m)| v * w * m.z)
            .sum();
        if mass > 0.0 && mass.is_finite() {
            d.iter_mut().for_each(|v| *v /= mass);
            Some(d)
        } else {
            None
        }
    };
    let uniform = vec![1.0 / PI; n * n];
    let mut d = normalized(uniform.clone()).unwrap_or(uniform);
    for _ in 0..ITERATIONS {
        let sigma = sigma_of(&d);
        let next = retro.iter().zip(&sigma).map(|(r, s)| r * s).collect();
        match normalized(next) {
            Some(next) => d = next,
            None => break,
        }
    }
    let floor = UNIFORM_SHARE / PI;
    let d: Vec<f64> = d
        .iter()
        .map(|v| (1.0 - UNIFORM_SHARE) * v + floor)
        .collect();
    let sigma = sigma_of(&d);
    (UGrid { n, values: d }, UGrid { n, values: sigma })
}

/// One incident node's arrays: the `vndf`, `luminance` and per-channel values (`[c][n·n]`).
struct Slice {
    vndf: Vec<f64>,
    luminance: Vec<f64>,
    values: Vec<Rgb>,
}

/// The `vndf` warp's density at incident direction `wi` over an `nv × nv` grid of `(u_θ, u_φ)`:
/// uniform over the half vectors whose mirror direction stays above the horizon, 0 beyond. The
/// sample square is then the `(u_θ, u_φ)` square cut to where the BRDF lives, whose map is
/// finest about the normal, where a grazing pair's sharp forward lobe lies.
///
/// (A warp that follows `D⟨ωi·m⟩`, as for measured materials, or the lobe `f·cos θo` itself, or
/// a mix of either with this one, crowds the nodes into the lobe and leaves its steep flanks to
/// a few: on the polyester sateen a `D` warp gave a 99th-percentile error of 40–57 % where this
/// gives 8 %, and on the filament satin mixes of 30 % and 60 % of the lobe gave 17 % and 26 %
/// where this gives 13 % (3000 pairs).)
fn vndf(wi: Vec3, nv: usize) -> Vec<f64> {
    let step = 1.0 / (nv - 1) as f64;
    (0..nv * nv)
        .map(|k| {
            let m = direction([(k % nv) as f64 * step, (k / nv) as f64 * step]);
            let d = wi.dot(m);
            let above = d > 0.0 && (m * (2.0 * d) - wi).z > 0.0;
            f64::from(u8::from(above))
        })
        .collect()
}

/// The arrays of incident direction `wi` (toward the viewer).
fn slice(
    wi: Vec3,
    n: usize,
    nv: usize,
    ndf: &UGrid,
    sigma: &UGrid,
    brdf: &(dyn Fn(Vec3, Vec3) -> Rgb + Sync),
) -> Slice {
    let step = 1.0 / (n - 1) as f64;
    let node = |k: usize| [(k % n) as f64 * step, (k / n) as f64 * step];
    let vndf = vndf(wi, nv);
    let warp = Marginal2D::new(nv, nv, vndf.clone(), vec![], true);
    let (theta_i, phi_i) = wi.to_spherical();
    let sigma_i = sigma.eval([theta_to_u(theta_i), phi_to_u(phi_i)]);
    let mut luminance = Vec::with_capacity(n * n);
    let mut values = Vec::with_capacity(n * n);
    for k in 0..n * n {
        let (u, density) = warp.sample(node(k), &[]);
        let m = direction(u);
        let d = wi.dot(m);
        let wo = m * (2.0 * d) - wi;
        if d <= 0.0 || wo.z <= 0.0 || density <= 0.0 {
            luminance.push(0.0);
            values.push(Rgb::BLACK);
            continue;
        }
        let fcos = brdf(wo, wi).0.map(|c| c.max(0.0) * wo.z);
        let scale = 4.0 * sigma_i / ndf.eval(u);
        values.push(Rgb(fcos.map(|c| c * scale)));
        // ωo's density when the warp alone draws: `density / (dω/du · 4⟨ωi·m⟩)`.
        let drawn = density / (jacobian(u).max(1e-6) * 4.0 * d);
        luminance.push(Rgb(fcos).luminance() / drawn);
    }
    let mean = luminance.iter().sum::<f64>() / (n * n) as f64;
    let floor = if mean > 0.0 { 0.01 * mean } else { 1.0 };
    luminance.iter_mut().for_each(|l| *l = l.max(floor));
    Slice {
        vndf,
        luminance,
        values,
    }
}

/// What a `.bsdf` file of a material holds: its cloth-level BRDF in colour, `f(s, v)`.
///
/// A woven material is read as a renderer shades it at cloth level ([`Detail::Cloth`]): the
/// weave's families mixed by their shares, each dyed, from its yarn's table on the accurate grid
/// ([`TableOptions::for_model`], dyeable, without exact regions: from `tables`, built and kept
/// when missing; `on_build` and `progress` as [`Tables::table`] has them). That table is within
/// 2.4 % of the exact model at the 99th percentile on the polyester sateen, where a render
/// table ([`TableOptions::for_render`]) is within 8 %. A microcylinder fabric is its exact
/// model.
///
/// # Errors
/// An invalid material, or a table that cannot be built.
pub fn material_brdf(
    material: &AnyMaterial,
    wavelength_nm: f64,
    tables: &mut Tables,
    on_build: &dyn Fn(Option<&std::path::Path>),
    progress: &dyn Progress,
) -> Result<ClothBrdf> {
    let material = match material {
        AnyMaterial::Woven(m) => m,
        AnyMaterial::Microcylinder(_) => {
            let exact = material.build_rgb(wavelength_nm)?;
            return Ok(Box::new(move |s, v| exact.eval(s, v)));
        }
    };
    let spec = SurfaceSpec {
        detail: Detail::Cloth,
        ..SurfaceSpec::new(material.clone())
    };
    let yarn = spec.table_material();
    let options = TableOptions {
        colour: true,
        exact_regions: false,
        ..TableOptions::for_model(&yarn.build(wavelength_nm)?)
    };
    let table = tables.table(&yarn, wavelength_nm, &options, on_build, progress)?;
    let surface = WovenSurface::new(&spec, table)?;
    Ok(Box::new(move |s, v| {
        surface.at(&SurfacePoint::default()).eval(s, v)
    }))
}

/// A cloth-level BRDF in colour, `f(s, v)` ([`material_brdf`]).
pub type ClothBrdf = Box<dyn Fn(Vec3, Vec3) -> Rgb + Send + Sync>;

/// A BRDF laid out as an RGL `.bsdf` file's fields.
#[derive(Clone, Debug)]
pub struct RglFile {
    fields: Vec<Data>,
}

impl RglFile {
    /// Builds the file of `brdf` (`f(s, v)`, sr⁻¹, no cosine, in colour; `s` toward the light,
    /// `v` toward the viewer; evaluated in parallel). `description` is stored as the file's
    /// text; `progress` hears `(done, total)` incident nodes and is asked between them whether to
    /// stop.
    ///
    /// # Errors
    /// Invalid `options` ([`RglOptions::validate`]); [`Error::Cancelled`]
    /// when `progress` asked to stop.
    pub fn build(
        brdf: &(dyn Fn(Vec3, Vec3) -> Rgb + Sync),
        description: &str,
        options: &RglOptions,
        progress: &dyn Progress,
    ) -> Result<RglFile> {
        options.validate()?;
        let retro = |w: Vec3| brdf(w, w).luminance() * w.z;
        let (ndf, sigma) = ndf_and_sigma(options.n_ndf, &retro);
        let (theta_i, phi_i) = (options.theta_i(), options.phi_i());
        let total = theta_i.len() * phi_i.len();
        let done = std::sync::atomic::AtomicUsize::new(0);
        let slices: Option<Vec<Slice>> = (0..total)
            .into_par_iter()
            .map(|k| {
                if progress.cancelled() {
                    return None;
                }
                let (p, t) = (k / theta_i.len(), k % theta_i.len());
                let wi = Vec3::from_spherical(theta_i[t], phi_i[p]);
                let s = slice(wi, options.n_grid, options.n_vndf, &ndf, &sigma, brdf);
                let d = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress.update(d, total);
                Some(s)
            })
            .collect();
        let slices = slices.ok_or(crate::Error::Cancelled)?;
        Ok(RglFile {
            fields: fields(
                description,
                options,
                &theta_i,
                &phi_i,
                &ndf,
                &sigma,
                &slices,
            ),
        })
    }

    /// The file's size, bytes.
    pub fn len(&self) -> u64 {
        tensor::file_len(&self.fields)
    }

    /// Whether the file is empty (never: it always has its fields).
    pub fn is_empty(&self) -> bool {
        self.fields.is_empty()
    }

    /// The fields, in the file's order.
    pub fn fields(&self) -> &[Data] {
        &self.fields
    }

    /// Writes the file.
    ///
    /// # Errors
    /// The writer's.
    pub fn write(&self, out: impl Write) -> std::io::Result<()> {
        tensor::write(out, &self.fields)
    }
}

/// Every field of the file.
fn fields(
    description: &str,
    options: &RglOptions,
    theta_i: &[f64],
    phi_i: &[f64],
    ndf: &UGrid,
    sigma: &UGrid,
    slices: &[Slice],
) -> Vec<Data> {
    let f32s = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<f32>>();
    let (np, nt, n, nd) = (phi_i.len(), theta_i.len(), options.n_grid, options.n_ndf);
    let nv = options.n_vndf;
    let all = |part: &dyn Fn(&Slice) -> &[f64]| {
        slices
            .iter()
            .flat_map(|s| part(s).iter().map(|&x| x as f32))
            .collect::<Vec<f32>>()
    };
    let mut fields = vec![
        Data::bytes("description", description.as_bytes()),
        Data::bytes("jacobian", &[1]),
        Data::f32("theta_i", &[nt], &f32s(theta_i)),
        Data::f32("phi_i", &[np], &f32s(phi_i)),
        Data::f32("ndf", &[nd, nd], &f32s(&ndf.values)),
        Data::f32("sigma", &[nd, nd], &f32s(&sigma.values)),
        Data::f32("vndf", &[np, nt, nv, nv], &all(&|s| &s.vndf)),
        Data::f32("luminance", &[np, nt, n, n], &all(&|s| &s.luminance)),
    ];
    let per_channel = |weights: &dyn Fn(usize) -> [f64; 3], c: usize| -> Vec<f32> {
        slices
            .iter()
            .flat_map(|s| {
                (0..c).flat_map(move |ch| {
                    let w = weights(ch);
                    s.values
                        .iter()
                        .map(move |v| (w[0] * v.0[0] + w[1] * v.0[1] + w[2] * v.0[2]) as f32)
                })
            })
            .collect()
    };
    match &options.channels {
        Channels::Rgb => {
            let unit = |ch: usize| {
                let mut w = [0.0; 3];
                w[ch] = 1.0;
                w
            };
            fields.push(Data::f32("rgb", &[np, nt, 3, n, n], &per_channel(&unit, 3)));
        }
        Channels::Spectral(nm) => {
            let c = nm.len();
            fields.push(Data::f32("wavelengths", &[c], &f32s(nm)));
            let weights = |ch: usize| channel_weights(nm[ch]);
            fields.push(Data::f32(
                "spectra",
                &[np, nt, c, n, n],
                &per_channel(&weights, c),
            ));
        }
    }
    fields
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::SplitMix;

    /// What a reader computes at an incident node: `f·cos θo`.
    fn read_back(
        file_ndf: &UGrid,
        file_sigma: &UGrid,
        s: &Slice,
        [n, nv]: [usize; 2],
        wi: Vec3,
        wo: Vec3,
    ) -> Rgb {
        let m = (wi + wo).normalize();
        let (tm, pm) = m.to_spherical();
        let um = [theta_to_u(tm), phi_to_u(pm)];
        let warp = Marginal2D::new(nv, nv, s.vndf.clone(), vec![], true);
        let sample = warp.invert(um, &[]);
        let (ti, pi) = wi.to_spherical();
        let scale = file_ndf.eval(um) / (4.0 * file_sigma.eval([theta_to_u(ti), phi_to_u(pi)]));
        let channel = |c: usize| {
            let grid = UGrid {
                n,
                values: s.values.iter().map(|v| v.0[c]).collect(),
            };
            grid.eval(sample) * scale
        };
        Rgb([channel(0), channel(1), channel(2)])
    }

    /// A smooth, coloured, anisotropic BRDF: a Lambertian term and a broad lobe about the
    /// mirror direction, stretched along x.
    fn brdf(s: Vec3, v: Vec3) -> Rgb {
        let h = (s + v).normalize();
        let lobe = (-(h.x * h.x / 0.2 + h.y * h.y / 0.05)).exp();
        Rgb([
            0.2 / PI + lobe,
            0.1 / PI + 0.5 * lobe,
            0.05 / PI + 0.2 * lobe,
        ])
    }

    #[test]
    fn a_reader_gets_the_brdf_back_at_an_incident_node() {
        let (ndf, sigma) = ndf_and_sigma(32, &|w| brdf(w, w).luminance() * w.z);
        let mut rng = SplitMix(3);
        let n = 48;
        let mut errors = Vec::new();
        for wi in [
            Vec3::from_spherical(0.4, 0.7),
            Vec3::from_spherical(1.1, -2.0),
        ] {
            let s = slice(wi, n, 32, &ndf, &sigma, &brdf);
            for _ in 0..400 {
                let wo = rng.direction(80f64.to_radians());
                let got = read_back(&ndf, &sigma, &s, [n, 32], wi, wo);
                let want = brdf(wo, wi).0.map(|c| c * wo.z);
                for c in 0..3 {
                    errors.push((got.0[c] - want[c]).abs() / want[c]);
                }
            }
        }
        errors.sort_by(f64::total_cmp);
        let median = errors[errors.len() / 2];
        let p99 = errors[errors.len() * 99 / 100];
        assert!(median < 0.01 && p99 < 0.06, "median {median}, p99 {p99}");
    }

    #[test]
    fn the_ndf_is_normalized_and_positive_and_a_lambertian_stays_near_uniform() {
        let (ndf, sigma) = ndf_and_sigma(24, &|w| w.z / PI);
        assert!(ndf.values.iter().all(|&d| d > 0.0));
        assert!(sigma.values.iter().all(|&s| s >= 0.0));
        // σ(z) = ∫ D cos θm dm = 1 by the normalization.
        assert!(
            (sigma.eval([0.0, 0.5]) - 1.0).abs() < 0.02,
            "{}",
            sigma.eval([0.0, 0.5])
        );
    }

    #[test]
    fn luminance_follows_f_cos_and_spectral_weights_sum_to_one() {
        for nm in [300.0, 450.0, 500.0, 540.0, 580.0, 610.0, 900.0] {
            let w = channel_weights(nm);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12 && w.iter().all(|&x| x >= 0.0));
        }
        let (ndf, sigma) = ndf_and_sigma(16, &|w| brdf(w, w).luminance() * w.z);
        let s = slice(Vec3::from_spherical(0.6, 0.2), 16, 24, &ndf, &sigma, &brdf);
        assert!(s.luminance.iter().all(|&l| l > 0.0 && l.is_finite()));
    }

    #[test]
    fn options_out_of_range_are_named() {
        let bad = RglOptions {
            n_grid: 2,
            ..RglOptions::default()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("n_grid"));
        let bad = RglOptions {
            theta_max_deg: 90.0,
            ..RglOptions::default()
        };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("theta_max_deg"));
        let bad = RglOptions {
            channels: Channels::Spectral(vec![500.0, 400.0]),
            ..RglOptions::default()
        };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("wavelengths"));
    }

    /// A build whose progress asks to stop returns `Error::Cancelled`, after no more incident
    /// nodes than it was let compute (and one more a worker).
    #[test]
    fn a_build_told_to_stop_is_cancelled() {
        use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};
        let options = RglOptions {
            n_theta_i: 3,
            n_phi_i: 5,
            n_grid: 6,
            n_vndf: 10,
            n_ndf: 8,
            ..RglOptions::default()
        };
        for nodes in [0, 4] {
            let (done, asked) = (AtomicUsize::new(0), AtomicUsize::new(0));
            let stop_after = crate::progress::Hooks {
                update: |_: usize, _: usize| {
                    done.fetch_add(1, SeqCst);
                },
                cancelled: || asked.fetch_add(1, SeqCst) >= nodes,
            };
            let got = RglFile::build(&brdf, "test", &options, &stop_after);
            assert!(matches!(got, Err(Error::Cancelled)), "{nodes} nodes");
            assert!(done.load(SeqCst) <= nodes + rayon::current_num_threads());
        }
    }

    #[test]
    fn the_file_has_the_fields_and_shapes_readers_check() {
        let options = RglOptions {
            n_theta_i: 3,
            n_phi_i: 5,
            n_grid: 6,
            n_vndf: 10,
            n_ndf: 8,
            channels: Channels::Spectral(vec![400.0, 500.0, 600.0, 700.0]),
            ..RglOptions::default()
        };
        let file = RglFile::build(&brdf, "test", &options, &|_, _| {}).unwrap();
        let shape = |name: &str| {
            file.fields()
                .iter()
                .find(|f| f.name == name)
                .unwrap_or_else(|| panic!("no field {name}"))
                .shape
                .clone()
        };
        assert_eq!(shape("spectra"), [5, 3, 4, 6, 6]);
        assert_eq!(shape("vndf"), [5, 3, 10, 10]);
        assert_eq!(shape("luminance"), [5, 3, 6, 6]);
        assert_eq!(shape("ndf"), [8, 8]);
        assert_eq!(shape("jacobian"), [1]);
        let mut bytes = Vec::new();
        file.write(&mut bytes).unwrap();
        assert_eq!(bytes.len() as u64, file.len());
        assert!(file.len() <= options.file_len("test"));
    }
}
