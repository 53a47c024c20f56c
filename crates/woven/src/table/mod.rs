//! Tabulated cloth BRDFs: fast evaluation and importance sampling for renderers.
//!
//! The exact model (docs/spec.md §2) nests up to four integrals; a [`Table`] stores it on a grid in
//! incidence `(θ_i, φ_i)` and warped half-vector coordinates `(t_x, t_y)` (see [`grid`]) and
//! interpolates quadrilinearly. The material's symmetries shrink the grid: every woven material is
//! invariant under the mirrors `x → −x` and `y → −y` (profiles are symmetric, twist densities even),
//! so `φ_i ∈ [0, π/2]` suffices; isotropic materials (flat fibers, `isotropic = true` yarns) need
//! `φ_i = 0` only.
//!
//! Building: single-orientation materials are evaluated exactly at every node. Twisted and
//! isotropic yarns (≈ 1 ms per exact evaluation) first tabulate the slope-averaged BRDF of fibers
//! along `x`, `F₀ = f_θ(s, v; φ_a = 0)`, then average rotated look-ups of `F₀` over fiber azimuths
//! with the twist (or uniform) weights: Eqs. (21)–(23) applied to the table, exactly linear like
//! the model.
//!
//! | option | meaning | default |
//! |---|---|---|
//! | `n_theta` | nodes in `θ_i` on `[0, theta_max]`, graded toward grazing | 30 |
//! | `theta_max_deg` | last `θ_i` node (beyond: clamped) | 87° |
//! | `n_phi` | nodes in `φ_i` on `[0, π/2]` (anisotropic materials) | 19 |
//! | `n_h` | nodes per half-vector slope axis, `t ∈ [−1, 1]` (anisotropic) | 81 ([`TableOptions::for_model`]: up to 121 for smooth fibers) |
//! | `n_h_isotropic` | the same for isotropic materials | 161 |
//! | `azimuth_nodes` | fiber azimuths per period for twisted/isotropic yarns | 180 |

pub mod format;
pub mod grid;
pub mod report;
mod sampler;

use crate::bsdf::{Bsdf, BsdfSample};
use crate::cloth::Structure;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::Model;
use grid::{slope_of_t, t_of_slope, v_of_slopes, Axis};
use sampler::Sampler;
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Grading of the `θ_i` axis (see [`Axis`]): nodes 5.3° apart at normal incidence (30 nodes to
/// 87°), 0.75° at grazing, where masking and Fresnel change fastest.
pub const THETA_GRADING: f64 = 0.75;

/// `φ_i` nodes of the intermediate single-orientation table `F₀` of twisted and isotropic yarns:
/// the azimuth average smooths its interpolation error, so it can be coarser than a final table.
pub const F0_PHI_NODES: usize = 13;

/// Which symmetry the table exploits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Symmetry {
    /// `f` depends on `φ_r − φ_i` only: one `φ_i` slice.
    Isotropic,
    /// `f` is invariant under `x → −x` and `y → −y`: `φ_i ∈ [0, π/2]`.
    Mirror,
}

/// Grid resolution and build settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableOptions {
    /// Nodes in `θ_i`.
    pub n_theta: usize,
    /// Last `θ_i` node, degrees.
    pub theta_max_deg: f64,
    /// Nodes in `φ_i` over `[0, π/2]` (ignored for isotropic materials).
    pub n_phi: usize,
    /// Nodes per half-vector axis (anisotropic materials).
    pub n_h: usize,
    /// Nodes per half-vector axis for isotropic materials (one `φ_i` slice, so finer is cheap).
    pub n_h_isotropic: usize,
    /// Fiber azimuths per period when averaging twisted or isotropic yarns.
    pub azimuth_nodes: usize,
    /// Worker threads (0: all available cores).
    pub threads: usize,
}

impl Default for TableOptions {
    fn default() -> Self {
        TableOptions {
            n_theta: 30,
            theta_max_deg: 87.0,
            n_phi: 19,
            n_h: 81,
            n_h_isotropic: 161,
            azimuth_nodes: 180,
            threads: 0,
        }
    }
}

/// Fibers whose half-vector lobe (the Beckmann `α = 2σ_h/τ`) is at least this wide get the default
/// `n_h` ([`TableOptions::for_model`]): roughness 0.05 and up, every preset.
pub const N_H_WIDE_LOBE: f64 = 0.1;
/// Fibers with a lobe this narrow or narrower (roughness 0.02) get [`N_H_SMOOTH`] nodes.
pub const N_H_NARROW_LOBE: f64 = 0.04;
/// `n_h` for the smoothest fibers: the most a mirror table holds under 64 MiB (30 × 19 × 121²
/// values and their sampling densities, 63 MiB).
pub const N_H_SMOOTH: usize = 121;

impl TableOptions {
    /// The default options, with the half-vector grid refined for smooth fibers: `n_h` grows
    /// linearly in `1/w` (`w` the fiber's half-vector lobe width: `α = 2σ_h/τ`, or the
    /// diffraction width `2/(kτ)` where the full model's is wider) from 81 at `w ≥ 0.1`
    /// (roughness 0.05) to 121 at `w ≤ 0.04` (roughness 0.02).
    ///
    /// The yarn ridges are as narrow as the fiber lobe, and bilinear interpolation across them
    /// needs a few nodes per lobe width: a sateen at roughness 0.02 has a 99th-percentile error
    /// of 3.9 % with 81 nodes, 3.0 % with 101 and 2.0 % with 121 (RMS 0.93, 0.64, 0.50 %), at
    /// (121/81)² ≈ 2.2× the build time. The presets (roughness ≥ 0.05) keep 81.
    pub fn for_model(model: &Model) -> TableOptions {
        let w = model.fiber().lobe_width(1.0);
        let (n0, n1) = (TableOptions::default().n_h as f64, N_H_SMOOTH as f64);
        let x =
            ((N_H_WIDE_LOBE / w - 1.0) / (N_H_WIDE_LOBE / N_H_NARROW_LOBE - 1.0)).clamp(0.0, 1.0);
        // Odd, so the axes t = 0 (the ridges) stay nodes.
        let n_h = ((n0 - 1.0 + x * (n1 - n0)) / 2.0).round() as usize * 2 + 1;
        TableOptions {
            n_h: n_h.clamp(n0 as usize, N_H_SMOOTH),
            ..TableOptions::default()
        }
    }

    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the option.
    pub fn validate(&self) -> Result<()> {
        let int = |name: &str, x: usize, lo: usize, hi: usize| {
            if (lo..=hi).contains(&x) {
                Ok(())
            } else {
                Err(Error::invalid(
                    name,
                    x,
                    format!("an integer in [{lo}, {hi}]"),
                ))
            }
        };
        int("n_theta", self.n_theta, 2, 1024)?;
        int("n_phi", self.n_phi, 2, 1024)?;
        int("n_h", self.n_h, 3, 4097)?;
        int("n_h_isotropic", self.n_h_isotropic, 3, 4097)?;
        int("azimuth_nodes", self.azimuth_nodes, 8, 100_000)?;
        crate::error::check_range("theta_max_deg", self.theta_max_deg, 1.0, 89.9)?;
        Ok(())
    }
}

/// A tabulated BRDF. `Send + Sync`; [`eval`](Table::eval), [`pdf`](Bsdf::pdf) and
/// [`sample`](Bsdf::sample) allocate nothing.
#[derive(Clone, Debug)]
pub struct Table {
    symmetry: Symmetry,
    theta: Axis,
    phi: Axis,
    t: Axis,
    values: Vec<f32>,
    /// The material (TOML) and wavelength the table was built from.
    material_toml: String,
    wavelength_nm: f64,
    sampler: Sampler,
}

/// The mirror folds that bring `s` into the table's domain, to undo on a sampled `v`.
#[derive(Clone, Copy, Debug)]
enum Fold {
    Mirror { flip_x: bool, flip_y: bool },
    Rotate { cos: f64, sin: f64 },
}

impl Fold {
    #[inline]
    fn apply(&self, d: Vec3) -> Vec3 {
        match *self {
            Fold::Mirror { flip_x, flip_y } => Vec3::new(
                if flip_x { -d.x } else { d.x },
                if flip_y { -d.y } else { d.y },
                d.z,
            ),
            // Rotation by −φ_i about z.
            Fold::Rotate { cos, sin } => {
                Vec3::new(cos * d.x + sin * d.y, -sin * d.x + cos * d.y, d.z)
            }
        }
    }

    #[inline]
    fn undo(&self, d: Vec3) -> Vec3 {
        match *self {
            Fold::Mirror { .. } => self.apply(d),
            Fold::Rotate { cos, sin } => {
                Vec3::new(cos * d.x - sin * d.y, sin * d.x + cos * d.y, d.z)
            }
        }
    }
}

impl Table {
    /// Builds the table of `model` (prepared at `wavelength_nm` from `material_toml`, which is
    /// stored in the file for provenance). `progress(done, total)` is called as rows complete,
    /// from worker threads.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid options.
    pub fn build(
        model: &Model,
        material_toml: &str,
        options: &TableOptions,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Table> {
        options.validate()?;
        let symmetry = symmetry_of(model);
        let theta = Axis {
            lo: 0.0,
            hi: options.theta_max_deg.to_radians(),
            n: options.n_theta,
            grading: THETA_GRADING,
        };
        let phi = Axis::uniform(
            0.0,
            FRAC_PI_2,
            if symmetry == Symmetry::Isotropic {
                1
            } else {
                options.n_phi
            },
        );
        let t = Axis::uniform(
            -1.0,
            1.0,
            if symmetry == Symmetry::Isotropic {
                options.n_h_isotropic
            } else {
                options.n_h
            },
        );
        let f0_t = Axis::uniform(-1.0, 1.0, options.n_h);
        let structure = model.structure();
        let values = match structure {
            Structure::Woven {
                yarn,
                weft_fraction,
            } if !yarn.is_single_orientation() => {
                // Stage 1: F₀ (fibers along x), a mirror-symmetric table, exact at every node.
                let f0_phi = Axis::uniform(0.0, FRAC_PI_2, F0_PHI_NODES);
                let stage = |done: usize, total: usize| progress(done, 2 * total);
                let f0_values = fill(theta, f0_phi, f0_t, options.threads, &stage, |s| {
                    move |v| yarn.slope_averaged(s, v, 0.0)
                });
                let f0 = Table::assemble(
                    Symmetry::Mirror,
                    theta,
                    f0_phi,
                    f0_t,
                    f0_values,
                    String::new(),
                    0.0,
                    Some(Vec::new()),
                );
                // Stage 2: average rotated look-ups over fiber azimuths (Eqs. (21)–(23)).
                let p = yarn.params();
                let n = options.azimuth_nodes;
                let weights = azimuth_weights(n, p.isotropic, p.twist_std, *weft_fraction);
                let (hbar, rho) = (p.interreflection, p.interreflection_albedo);
                let rows = theta.n * phi.n;
                let stage2 = |done: usize, _total: usize| progress(rows + done, 2 * rows);
                fill(theta, phi, t, options.threads, &stage2, |s| {
                    // Per fiber azimuth, light in the fiber frame, folded into F₀'s domain and
                    // located once per row; each v then costs a rotation and a look-up.
                    let azimuths: Vec<Azimuth> = weights
                        .iter()
                        .enumerate()
                        .filter(|&(_, &w)| w != 0.0)
                        .map(|(j, &w)| {
                            let phi_a = (j as f64 + 0.5) * PI / n as f64;
                            Azimuth::new(&f0, s, phi_a, w)
                        })
                        .collect();
                    let f0 = &f0;
                    move |v: Vec3| {
                        let acc: f64 = azimuths.iter().map(|a| a.eval(f0, v)).sum();
                        (1.0 - hbar) * acc + hbar * rho * FRAC_1_PI
                    }
                })
            }
            _ => fill(theta, phi, t, options.threads, progress, |s| {
                move |v| model.eval(s, v)
            }),
        };
        Ok(Table::assemble(
            symmetry,
            theta,
            phi,
            t,
            values,
            material_toml.to_string(),
            model.fiber().wavelength_nm(),
            None,
        ))
    }

    fn assemble(
        symmetry: Symmetry,
        theta: Axis,
        phi: Axis,
        t: Axis,
        values: Vec<f32>,
        material_toml: String,
        wavelength_nm: f64,
        cell_pdf: Option<Vec<f32>>,
    ) -> Table {
        let mut table = Table {
            symmetry,
            theta,
            phi,
            t,
            values,
            material_toml,
            wavelength_nm,
            sampler: Sampler::default(),
        };
        table.sampler = match cell_pdf {
            Some(c) => Sampler::from_cell_pdf(&table, c),
            None => Sampler::build(&table),
        };
        table
    }

    /// The symmetry the table uses.
    pub fn symmetry(&self) -> Symmetry {
        self.symmetry
    }

    /// The material the table was built from, as TOML.
    pub fn material_toml(&self) -> &str {
        &self.material_toml
    }

    /// The wavelength the table was built at, nm.
    pub fn wavelength_nm(&self) -> f64 {
        self.wavelength_nm
    }

    /// `(n_theta, n_phi, n_h)`.
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.theta.n, self.phi.n, self.t.n)
    }

    /// The stored values `f cos θ_i cos θ_r` (`f32`, sr⁻¹), index `((iθ·n_φ + iφ)·n_h + i_y)·n_h + i_x`.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    #[inline]
    fn index(&self, it: usize, ip: usize, iy: usize, ix: usize) -> usize {
        ((it * self.phi.n + ip) * self.t.n + iy) * self.t.n + ix
    }

    /// The fold that brings `s` into the table's domain.
    #[inline]
    fn fold_for(&self, s: Vec3) -> Fold {
        match self.symmetry {
            Symmetry::Mirror => Fold::Mirror {
                flip_x: s.x < 0.0,
                flip_y: s.y < 0.0,
            },
            Symmetry::Isotropic => {
                let r = (s.x * s.x + s.y * s.y).sqrt();
                if r > 0.0 {
                    Fold::Rotate {
                        cos: s.x / r,
                        sin: s.y / r,
                    }
                } else {
                    Fold::Rotate { cos: 1.0, sin: 0.0 }
                }
            }
        }
    }

    /// The BRDF (sr⁻¹) by quadrilinear interpolation; 0 below the horizon.
    #[inline]
    pub fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let fold = self.fold_for(s);
        self.eval_folded(fold.apply(s), fold.apply(v))
    }

    /// [`eval`](Self::eval) for `s` already in the domain (`s_x, s_y ≥ 0`; `s_y = 0` if isotropic).
    #[inline]
    fn eval_folded(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let (s, v) = match self.symmetry {
            Symmetry::Mirror => (
                Vec3::new(s.x.abs(), s.y.abs(), s.z),
                Vec3::new(
                    if s.x < 0.0 { -v.x } else { v.x },
                    if s.y < 0.0 { -v.y } else { v.y },
                    v.z,
                ),
            ),
            Symmetry::Isotropic => (s, v),
        };
        let (incidence, y, x) = locate_query(&self.theta, &self.phi, &self.t, s, v);
        self.eval_at(incidence, y, x, s.z, v.z)
    }

    /// Quadrilinear interpolation at located coordinates: `(iθ, wθ, iφ, wφ)`, `(i_y, w_y)`,
    /// `(i_x, w_x)`; divides the stored `f cos θ_i cos θ_r` by the cosines.
    #[inline]
    fn eval_at(
        &self,
        (it, wt, ip, wp): Incidence,
        (iy, wy): (usize, f64),
        (ix, wx): (usize, f64),
        cos_i: f64,
        cos_r: f64,
    ) -> f64 {
        let dp = usize::from(self.phi.n > 1);
        let n = self.t.n;
        let mut acc = 0.0;
        for (a, fa) in [(0, 1.0 - wt), (1, wt)] {
            for (b, fb) in [(0, 1.0 - wp), (dp, wp)] {
                let base = self.index(it + a, ip + b, iy, ix);
                let v00 = self.values[base] as f64;
                let v01 = self.values[base + 1] as f64;
                let v10 = self.values[base + n] as f64;
                let v11 = self.values[base + n + 1] as f64;
                let bil =
                    (1.0 - wy) * ((1.0 - wx) * v00 + wx * v01) + wy * ((1.0 - wx) * v10 + wx * v11);
                acc += fa * fb * bil;
            }
        }
        // The table stores f cos θ_i cos θ_r (continued linearly below the horizon).
        (acc / (cos_i * cos_r)).max(0.0)
    }
}

/// A located incidence: `(iθ, wθ, iφ, wφ)`, each node index with the weight of the next node.
pub(crate) type Incidence = (usize, f64, usize, f64);

/// A located coordinate on one axis: `(k, w)`.
type AxisPos = (usize, f64);

/// The cell of a folded query: `(iθ, wθ, iφ, wφ)`, `(i_y, w_y)`, `(i_x, w_x)`.
#[inline]
fn locate_query(
    theta: &Axis,
    phi: &Axis,
    t: &Axis,
    s: Vec3,
    v: Vec3,
) -> (Incidence, AxisPos, AxisPos) {
    let (y, x) = locate_half_vector(t, s, v);
    (locate_incidence(theta, phi, s), y, x)
}

/// The located incidence of a folded light direction `s`.
#[inline]
pub(crate) fn locate_incidence(theta: &Axis, phi: &Axis, s: Vec3) -> Incidence {
    let (it, wt) = theta.locate(s.z.clamp(-1.0, 1.0).acos());
    let (ip, wp) = phi.locate(s.y.atan2(s.x));
    (it, wt, ip, wp)
}

/// The located half-vector slopes `(t_y, t_x)` of `(s, v)`.
#[inline]
fn locate_half_vector(t: &Axis, s: Vec3, v: Vec3) -> (AxisPos, AxisPos) {
    let h = s + v;
    (
        t.locate(t_of_slope(h.y / h.z)),
        t.locate(t_of_slope(h.x / h.z)),
    )
}

/// One fiber azimuth `φ_a` of the twist average for a fixed light direction: the rotation into
/// the frame whose x is the fiber axis, the mirror fold of the rotated light, and its located
/// incidence in the `F₀` table.
struct Azimuth {
    weight: f64,
    cos: f64,
    sin: f64,
    flip_x: bool,
    flip_y: bool,
    s: Vec3,
    incidence: Incidence,
}

impl Azimuth {
    fn new(f0: &Table, s: Vec3, phi_a: f64, weight: f64) -> Azimuth {
        let (sin, cos) = phi_a.sin_cos();
        let r = Vec3::new(cos * s.x + sin * s.y, -sin * s.x + cos * s.y, s.z);
        let (flip_x, flip_y) = (r.x < 0.0, r.y < 0.0);
        let s = Vec3::new(r.x.abs(), r.y.abs(), r.z);
        Azimuth {
            weight,
            cos,
            sin,
            flip_x,
            flip_y,
            s,
            incidence: locate_incidence(&f0.theta, &f0.phi, s),
        }
    }

    /// `w · F₀(s, v)` in the fiber frame: what `w · f0.eval_folded(rotate(s), rotate(v))` gives.
    #[inline]
    fn eval(&self, f0: &Table, v: Vec3) -> f64 {
        if self.s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let x = self.cos * v.x + self.sin * v.y;
        let y = -self.sin * v.x + self.cos * v.y;
        let v = Vec3::new(
            if self.flip_x { -x } else { x },
            if self.flip_y { -y } else { y },
            v.z,
        );
        let (ty, tx) = locate_half_vector(&f0.t, self.s, v);
        self.weight * f0.eval_at(self.incidence, ty, tx, self.s.z, v.z)
    }
}

/// The symmetry of a model's BRDF.
fn symmetry_of(model: &Model) -> Symmetry {
    match model.structure() {
        Structure::Flat(_) => Symmetry::Isotropic,
        Structure::Woven { yarn, .. } if yarn.params().isotropic => Symmetry::Isotropic,
        Structure::Woven { .. } => Symmetry::Mirror,
    }
}

/// Quadrature weights of the fiber azimuths `φ_j = (j + ½)π/n` over one period, for the weave mix
/// of twisted (Eq. (21)) or isotropic (Eq. (22)) yarns: normalized per yarn so each sums to its
/// weight `γ` or `1 − γ` (isotropic: uniform, summing to 1).
fn azimuth_weights(n: usize, isotropic: bool, twist_std: f64, gamma: f64) -> Vec<f64> {
    if isotropic {
        return vec![1.0 / n as f64; n];
    }
    let density = |centre: f64| -> Vec<f64> {
        let w: Vec<f64> = (0..n)
            .map(|j| {
                let phi = (j as f64 + 0.5) * PI / n as f64;
                // δ reduced to [−π/2, π/2): the twist window is one period.
                let d = (phi - centre + FRAC_PI_2).rem_euclid(PI) - FRAC_PI_2;
                (-d * d / (2.0 * twist_std * twist_std)).exp()
            })
            .collect();
        let sum: f64 = w.iter().sum();
        w.into_iter().map(|x| x / sum).collect()
    };
    let weft = density(0.0);
    let warp = density(FRAC_PI_2);
    weft.iter()
        .zip(&warp)
        .map(|(a, b)| gamma * a + (1.0 - gamma) * b)
        .collect()
}

/// A value for a node whose `v` lies below the horizon, so that interpolation next to it is not
/// dragged toward 0: `f` at `v` lifted just above the horizon, times `cos θ_i` and the *signed*
/// `cos θ_r` of the unlifted `v`. The stored `f cos θ_i cos θ_r` then continues linearly through
/// the horizon (the BRDF is continuous up to it: the Smith term cancels `1/cos θ_r`), so cells that
/// straddle it interpolate correctly on their valid side; `eval` returns 0 below it regardless.
fn extrapolated(s: Vec3, px: f64, py: f64, f: &impl Fn(Vec3) -> f64) -> f64 {
    let h = grid::h_of_slopes(px, py);
    let sh = s.dot(h);
    if sh <= 0.0 {
        return 0.0;
    }
    let v = h * (2.0 * sh) - s;
    // 0.1° above the horizon, same azimuth.
    let min_z = 0.1f64.to_radians().sin();
    let r_xy = (v.x * v.x + v.y * v.y).sqrt();
    if r_xy <= 0.0 {
        return 0.0;
    }
    let c = (1.0 - min_z * min_z).sqrt() / r_xy;
    let lifted = Vec3::new(v.x * c, v.y * c, min_z);
    f(lifted) * s.z * v.z
}

/// Which half-vector nodes of incidence row `(it, ip)` some valid query interpolates, row-major
/// `(i_y, i_x)`.
///
/// A query `(s, v)` with `v` above the horizon reads the nodes around its cell: incidence nodes
/// `it, it + 1` and `ip, ip + 1` around `s`, half-vector nodes around its slopes `p`. For light from
/// `s`, `v` is above the horizon exactly when `|p − a|² < 1 + |a|²` with `a = (s_x, s_y)/s_z`
/// (a disk of radius `sec θ_i` about `a = tan θ_i (cos φ_i, sin φ_i)`; from
/// `v_z = 2 (s·h) h_z − s_z > 0`). A node is reachable when that disk meets the slope rectangle of
/// the cells around it for some `s` in the incidence cells around it (sampled 17 × 17, each disk
/// widened by how far it moves to the next sample). The rest — more than a third of a
/// table, below the horizon whatever the light — need no exact evaluation.
fn reachable_nodes(theta: Axis, phi: Axis, t: Axis, it: usize, ip: usize) -> Vec<bool> {
    let n = t.n;
    // Incidence range whose queries read node (it, ip); beyond the last θ node queries clamp to it.
    let th_lo = theta.node(it.saturating_sub(1));
    let th_hi = if it + 1 < theta.n {
        theta.node(it + 1)
    } else {
        FRAC_PI_2
    };
    let (ph_lo, ph_hi) = if phi.n == 1 {
        (phi.lo, phi.lo)
    } else {
        (
            phi.node(ip.saturating_sub(1)),
            phi.node((ip + 1).min(phi.n - 1)),
        )
    };
    const SAMPLES: usize = 17;
    let disk = |a: usize, b: usize| {
        // Stop short of the horizon, where the disk is unbounded.
        let th =
            (th_lo + (th_hi - th_lo) * a as f64 / (SAMPLES - 1) as f64).min(89.9f64.to_radians());
        let ph = ph_lo + (ph_hi - ph_lo) * b as f64 / (SAMPLES - 1) as f64;
        let r = th.tan();
        (r * ph.cos(), r * ph.sin(), (1.0 + r * r).sqrt())
    };
    let mut disks = Vec::with_capacity(SAMPLES * SAMPLES);
    for a in 0..SAMPLES {
        for b in 0..SAMPLES {
            // Every incidence is within half a step in θ and in φ of a sample; over such a
            // step the disk moves and grows by at most half its change to the neighbouring
            // samples (tan θ is convex): widen it by that, so the sampled union covers them all.
            let (x, y, r) = disk(a, b);
            let change = |(x2, y2, r2): (f64, f64, f64)| (x2 - x).hypot(y2 - y) + (r2 - r).abs();
            let along_theta =
                change(disk((a + 1).min(SAMPLES - 1), b)).max(change(disk(a.saturating_sub(1), b)));
            let along_phi =
                change(disk(a, (b + 1).min(SAMPLES - 1))).max(change(disk(a, b.saturating_sub(1))));
            let pad = 0.5 * (along_theta + along_phi);
            disks.push((x, y, (r + pad) * (r + pad)));
        }
    }
    let slope = |k: isize| slope_of_t(t.node(k.clamp(0, n as isize - 1) as usize));
    let gap = |x: f64, lo: f64, hi: f64| (lo - x).max(x - hi).max(0.0);
    let mut out = vec![false; n * n];
    for iy in 0..n {
        let (y_lo, y_hi) = (slope(iy as isize - 1), slope(iy as isize + 1));
        for ix in 0..n {
            let (x_lo, x_hi) = (slope(ix as isize - 1), slope(ix as isize + 1));
            out[iy * n + ix] = disks.iter().any(|&(ax, ay, r2)| {
                let (dx, dy) = (gap(ax, x_lo, x_hi), gap(ay, y_lo, y_hi));
                dx * dx + dy * dy < r2
            });
        }
    }
    out
}

/// Evaluates the BRDF at every reachable node, rows of `(θ_i, φ_i)` spread over threads:
/// `row(s)` prepares the evaluation for light from `s` and returns `v ↦ f(s, v)`.
fn fill<R: Fn(Vec3) -> f64>(
    theta: Axis,
    phi: Axis,
    t: Axis,
    threads: usize,
    progress: &(dyn Fn(usize, usize) + Sync),
    row: impl Fn(Vec3) -> R + Sync,
) -> Vec<f32> {
    let rows = theta.n * phi.n;
    let row_len = t.n * t.n;
    let mut values = vec![0f32; rows * row_len];
    let threads = if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    };
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    // Rows are handed out one at a time; each thread writes only the rows it took.
    let chunks: Vec<std::sync::Mutex<&mut [f32]>> = values
        .chunks_mut(row_len)
        .map(std::sync::Mutex::new)
        .collect();
    std::thread::scope(|scope| {
        for _ in 0..threads.min(rows) {
            scope.spawn(|| loop {
                let r = next.fetch_add(1, Ordering::Relaxed);
                if r >= rows {
                    break;
                }
                let (it, ip) = (r / phi.n, r % phi.n);
                let s = Vec3::from_spherical(theta.node(it), phi.node(ip));
                let needed = reachable_nodes(theta, phi, t, it, ip);
                let f = row(s);
                let mut row = chunks[r].lock().expect("row lock poisoned");
                for iy in 0..t.n {
                    let py = slope_of_t(t.node(iy));
                    for ix in 0..t.n {
                        if !needed[iy * t.n + ix] {
                            // No valid query interpolates this node: leave it 0.
                            continue;
                        }
                        let px = slope_of_t(t.node(ix));
                        // Stored: f cos θ_i cos θ_r, which varies far more slowly with θ_i at fixed h
                        // than f (whose 1/(cos θ_i cos θ_r) dominates near the highlight).
                        row[iy * t.n + ix] = match v_of_slopes(s, px, py) {
                            Some((v, _)) => f(v) * s.z * v.z,
                            None => extrapolated(s, px, py, &f),
                        } as f32;
                    }
                }
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, rows);
            });
        }
    });
    drop(chunks);
    values
}

impl Bsdf for Table {
    #[inline]
    fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        Table::eval(self, s, v)
    }

    #[inline]
    fn pdf(&self, s: Vec3, v: Vec3) -> f64 {
        if s.z <= 0.0 || v.z <= 0.0 {
            return 0.0;
        }
        let fold = self.fold_for(s);
        self.sampler.pdf(self, fold.apply(s), fold.apply(v))
    }

    #[inline]
    fn sample(&self, s: Vec3, u1: f64, u2: f64) -> Option<BsdfSample> {
        if s.z <= 0.0 {
            return None;
        }
        let fold = self.fold_for(s);
        let sf = fold.apply(s);
        let (vf, pdf, f) = self.sampler.sample(self, sf, u1, u2)?;
        let v = fold.undo(vf);
        Some(BsdfSample {
            v,
            f,
            pdf,
            weight: f * v.z / pdf,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::report::SplitMix;

    #[test]
    fn smooth_fibers_get_finer_half_vector_grids() {
        let n_h = |roughness: f64| {
            let m = crate::material::Material::from_toml_str(
                &format!("[fiber]\neta = 1.5\nroughness = {roughness}\ndiffuse = 0.1\n"),
                "test",
            )
            .unwrap();
            TableOptions::for_model(&m.build(550.0).unwrap()).n_h
        };
        assert_eq!(n_h(0.3), 81);
        assert_eq!(n_h(0.05), 81);
        assert_eq!(n_h(0.02), N_H_SMOOTH);
        assert_eq!(n_h(0.005), N_H_SMOOTH);
        let mid = n_h(0.03);
        assert!(mid > 81 && mid < N_H_SMOOTH && mid % 2 == 1, "{mid}");
        let mut prev = 0;
        for k in 0..=12 {
            let n = n_h(0.01 + 0.005 * (k * k) as f64);
            assert!(n % 2 == 1, "n_h {n} is even");
            assert!(prev == 0 || n <= prev, "n_h not decreasing with roughness");
            prev = n;
        }
        // Everything else is the default.
        let m = crate::material::Material::preset("silk").unwrap();
        let o = TableOptions::for_model(&m.build(550.0).unwrap());
        assert_eq!(o, TableOptions::default());
    }

    /// Every node a valid query interpolates is one `fill` evaluates: random folded queries,
    /// grazing ones over-represented, on coarse and fine grids of both symmetries.
    #[test]
    fn queries_read_only_reachable_nodes() {
        let mut rng = SplitMix(5);
        for (n_theta, n_phi, n_t) in [(30, 19, 81), (6, 4, 17), (30, 1, 161), (12, 13, 41)] {
            let theta = Axis {
                lo: 0.0,
                hi: 87f64.to_radians(),
                n: n_theta,
                grading: THETA_GRADING,
            };
            let phi = Axis::uniform(0.0, FRAC_PI_2, n_phi);
            let t = Axis::uniform(-1.0, 1.0, n_t);
            let rows: Vec<Vec<bool>> = (0..n_theta * n_phi)
                .map(|r| reachable_nodes(theta, phi, t, r / n_phi, r % n_phi))
                .collect();
            let reachable = rows.iter().flatten().filter(|&&b| b).count();
            let total = rows.len() * n_t * n_t;
            assert!(
                reachable < total,
                "mask prunes nothing ({n_theta}, {n_phi}, {n_t})"
            );
            for k in 0..200_000 {
                // Half the draws within 10° of the horizon.
                let lim = if k % 2 == 0 { 1.0 } else { 0.17 };
                let pick = |rng: &mut SplitMix| {
                    let z = lim * rng.uniform().max(1e-9);
                    let ph = if n_phi == 1 && k % 3 == 0 {
                        0.0
                    } else {
                        FRAC_PI_2 * rng.uniform()
                    };
                    let r = (1.0 - z * z).sqrt();
                    (r, ph, z)
                };
                let (r, ph, z) = pick(&mut rng);
                let ph = if n_phi == 1 { 0.0 } else { ph };
                let s = Vec3::new(r * ph.cos(), r * ph.sin(), z);
                let (r2, _, z2) = pick(&mut rng);
                let pv = 2.0 * std::f64::consts::PI * rng.uniform();
                let v = Vec3::new(r2 * pv.cos(), r2 * pv.sin(), z2);
                let ((it, wt, ip, wp), (iy, wy), (ix, wx)) = locate_query(&theta, &phi, &t, s, v);
                let dp = usize::from(n_phi > 1);
                // Nodes read with weight 0 (clamped beyond the last θ node) do not count.
                for (a, fa) in [(it, 1.0 - wt), (it + 1, wt)] {
                    for (b, fb) in [(ip, 1.0 - wp), (ip + dp, wp)] {
                        for (y, fy) in [(iy, 1.0 - wy), (iy + 1, wy)] {
                            for (x, fx) in [(ix, 1.0 - wx), (ix + 1, wx)] {
                                assert!(
                                    fa * fb * fy * fx == 0.0 || rows[a * n_phi + b][y * n_t + x],
                                    "grid ({n_theta}, {n_phi}, {n_t}): s {s:?} v {v:?} reads \
                                     unevaluated node ({a}, {b}, {y}, {x})"
                                );
                            }
                        }
                    }
                }
            }
            println!(
                "grid ({n_theta}, {n_phi}, {n_t}): {:.1} % of nodes reachable",
                100.0 * reachable as f64 / total as f64
            );
        }
    }
}
