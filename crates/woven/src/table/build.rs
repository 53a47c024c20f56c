//! Building a [`Table`]: exact evaluation at the nodes each half reads, and the twist average of
//! twisted and isotropic yarns applied to an intermediate table.

use super::eval::{locate_axis, Incidence, Query};
use super::grid::{h_of_slopes, v_of_slopes, Axis};
use super::{
    value_count, Half, Symmetry, Table, TableOptions, F0_PHI_NODES, HORIZON_LIFT_DEG, MAX_VALUES,
    THETA_GRADING,
};
use crate::cloth::Structure;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::progress::{Progress, Share};
use crate::Model;
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The revision of what a build computes from the same grid and material (the values, the
/// sampler's densities): part of the disk cache's key, so a change here rebuilds cached tables.
/// 2: the sampler sees the exact regions and densities of cells the horizon cuts.
pub(crate) const REVISION: u32 = 2;

impl Table {
    /// Builds the table of `model`, prepared from `material` (recorded as the table's
    /// [`Provenance`](super::Provenance), with the model's wavelength). `progress` hears
    /// `(done, total)` rows as they complete, from worker threads, and is asked between rows
    /// whether to stop.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid options or a grid larger than a table file holds;
    /// [`Error::Cancelled`] when `progress` asked to stop.
    pub fn build(
        model: &Model,
        material: &crate::material::Material,
        options: &TableOptions,
        progress: &dyn Progress,
    ) -> Result<Table> {
        options.validate()?;
        let symmetry = Symmetry::of(model);
        let count = value_count(symmetry, options);
        if count > MAX_VALUES {
            return Err(Error::invalid(
                "table grid",
                format!("{count} values"),
                format!("at most {MAX_VALUES} values (fewer nodes)"),
            ));
        }
        let (n_theta, n_phi, n_h) = super::grid_of(symmetry, options);
        let theta = Axis {
            lo: 0.0,
            hi: options.theta_max_deg.to_radians(),
            n: n_theta,
            grading: THETA_GRADING,
        };
        let phi = Axis::uniform(0.0, FRAC_PI_2, n_phi);
        let t = Axis::uniform(-1.0, 1.0, n_h);
        let pool = pool(options.threads)?;
        let wavelength_nm = model.fiber().wavelength_nm();
        let provenance = Some(super::Provenance {
            material: material.clone(),
            wavelength_nm,
        });
        let own = super::Albedos::of(material);
        // `f`, and with `colour` `∂f/∂ρ0` in the same pass (`Model::eval_affine`).
        let (values, colour) = if options.colour {
            let [values, body] =
                pool.install(|| tabulate::<2>(model, own, theta, phi, t, options, progress))?;
            (values, Some(super::Colour::new(material, body)))
        } else {
            let [values] =
                pool.install(|| tabulate::<1>(model, own, theta, phi, t, options, progress))?;
            (values, None)
        };
        // The sampler is built as the table is assembled, on the same pool.
        let table = pool.install(|| {
            Table::assemble(
                symmetry,
                theta,
                phi,
                t,
                values,
                provenance,
                wavelength_nm,
                None,
                colour,
                options.exact_regions.then_some(model),
            )
        });
        if options.crown_deg > 0.0 {
            return pool.install(|| table.crowned_until(options.crown_deg, options, progress));
        }
        Ok(table)
    }
}

/// The node values of `model` (whose albedos are `own`) on the grid `(theta, phi, t)`, on the
/// current rayon pool: `f` (`K = 1`), or `f` and `∂f/∂ρ0` (`K = 2`, [`Model::eval_affine`]).
/// [`Error::Cancelled`] when `progress` asks to stop.
fn tabulate<const K: usize>(
    model: &Model,
    own: super::Albedos,
    theta: Axis,
    phi: Axis,
    t: Axis,
    options: &TableOptions,
    progress: &dyn Progress,
) -> Result<[Vec<f32>; K]> {
    // The parts of a value: `f` first, then `∂f/∂ρ0`.
    let parts = |f: f64, per_diffuse: f64| -> [f64; K] {
        std::array::from_fn(|k| if k == 0 { f } else { per_diffuse })
    };
    let (yarn, weft_fraction, gap) = match model.structure() {
        Structure::Woven {
            yarn,
            weft_fraction,
            gap,
        } if !yarn.is_single_orientation() => (&**yarn, *weft_fraction, *gap),
        _ => {
            return fill(theta, phi, t, progress, |half, a| {
                move |o| {
                    let (s, v) = half.join(a, o);
                    if K == 1 {
                        parts(model.eval(s, v), 0.0)
                    } else {
                        let affine = model.eval_affine(s, v);
                        parts(
                            affine.at(own.diffuse, own.interreflection),
                            affine.per_diffuse,
                        )
                    }
                }
            });
        }
    };
    // Stage 1: F₀ (fibers along x), a mirror-symmetric table, exact at every node.
    let f0_phi = Axis::uniform(0.0, FRAC_PI_2, F0_PHI_NODES);
    let f0_t = Axis::uniform(-1.0, 1.0, options.n_h);
    let stage = Share {
        progress,
        index: 0,
        of: 2,
    };
    let fiber = yarn.fiber();
    let f0_values = fill(theta, f0_phi, f0_t, &stage, |half, a| {
        move |o| {
            let (s, v) = half.join(a, o);
            let p = yarn.slope_averaged_parts(s, v, 0.0, crate::yarn::Masking::Exact);
            parts(fiber.combine_parts(p), fiber.affine_in_diffuse(p).1)
        }
    })?;
    let f0 = Stage::new(theta, f0_phi, f0_t, f0_values, model);
    // Stage 2: average rotated look-ups over fiber azimuths (Eqs. (21)–(23)), with the model's
    // own orientation weights and interreflection mix.
    let n = options.azimuth_nodes;
    let weights = yarn
        .orientation()
        .midpoint_weights(n, &crate::cloth::weave_axes(weft_fraction, gap));
    let stage2 = Share {
        progress,
        index: 1,
        of: 2,
    };
    fill(theta, phi, t, &stage2, |half, a| {
        // Per fiber azimuth: the axis direction in the fiber frame, folded into F₀'s domain and
        // located once per row; each node then costs a rotation and a look-up.
        let azimuths: Vec<Azimuth> = weights
            .iter()
            .enumerate()
            .filter(|&(_, &w)| w != 0.0)
            .map(|(j, &w)| {
                let phi_a = (j as f64 + 0.5) * PI / n as f64;
                Azimuth::new(&f0.table, half, a, phi_a, w)
            })
            .collect();
        let f0 = &f0;
        move |o: Vec3| {
            let mut acc = [0.0; K];
            for z in &azimuths {
                for (sum, x) in acc.iter_mut().zip(z.eval(f0, o)) {
                    *sum += x;
                }
            }
            // Eq. (20): the interreflection term ħρ/π is part of f, not of ∂f/∂ρ0.
            std::array::from_fn(|k| {
                yarn.interreflection_mix(acc[k], if k == 0 { 1.0 } else { 0.0 })
            })
        }
    })
}

/// The intermediate table `F₀` of a build: `f` as a [`Table`] (for the grid and the look-up),
/// and with `K = 2` `∂f/∂ρ0` on the same nodes.
struct Stage<const K: usize> {
    table: Table,
    rest: Vec<Vec<f32>>,
}

impl<const K: usize> Stage<K> {
    fn new(theta: Axis, phi: Axis, t: Axis, values: [Vec<f32>; K], model: &Model) -> Stage<K> {
        let mut parts = values.into_iter();
        let table = Table::assemble(
            Symmetry::Mirror,
            theta,
            phi,
            t,
            parts.next().unwrap_or_default(),
            None,
            model.fiber().wavelength_nm(),
            Some(Vec::new()),
            None,
            None,
        );
        Stage {
            table,
            rest: parts.collect(),
        }
    }

    /// The `K` node arrays, `f` first.
    #[inline]
    fn arrays(&self) -> [&[f32]; K] {
        std::array::from_fn(|k| {
            if k == 0 {
                self.table.values()
            } else {
                self.rest[k - 1].as_slice()
            }
        })
    }
}

/// A thread pool of `threads` workers (0: rayon's default, every core).
fn pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::invalid("threads", threads, format!("a usable thread count ({e})")))
}

/// One fiber azimuth `φ_a` of the twist average for a fixed axis direction: the rotation into the
/// frame whose x is the fiber axis, the mirror fold of the rotated axis direction, and its
/// located position in the `F₀` table.
struct Azimuth {
    weight: f64,
    half: Half,
    cos: f64,
    sin: f64,
    flip_x: bool,
    flip_y: bool,
    axis: Vec3,
    located: Incidence,
}

impl Azimuth {
    fn new(f0: &Table, half: Half, axis: Vec3, phi_a: f64, weight: f64) -> Azimuth {
        let (sin, cos) = phi_a.sin_cos();
        let r = Vec3::new(
            cos * axis.x + sin * axis.y,
            -sin * axis.x + cos * axis.y,
            axis.z,
        );
        let (flip_x, flip_y) = (r.x < 0.0, r.y < 0.0);
        let axis = Vec3::new(r.x.abs(), r.y.abs(), r.z);
        Azimuth {
            weight,
            half,
            cos,
            sin,
            flip_x,
            flip_y,
            axis,
            located: locate_axis(&f0.theta, &f0.phi, axis),
        }
    }

    /// `w · F₀` in the fiber frame for the other direction `o`: what `w · f0.eval` of the rotated
    /// pair gives, reading the located axis when the pair belongs to this half.
    #[inline]
    fn eval<const K: usize>(&self, f0: &Stage<K>, o: Vec3) -> [f64; K] {
        if self.axis.z <= 0.0 || o.z <= 0.0 {
            return [0.0; K];
        }
        let x = self.cos * o.x + self.sin * o.y;
        let y = -self.sin * o.x + self.cos * o.y;
        let o = Vec3::new(
            if self.flip_x { -x } else { x },
            if self.flip_y { -y } else { y },
            o.z,
        );
        let (s, v) = self.half.join(self.axis, o);
        let arrays = f0.arrays();
        let f = if Half::of(s, v) == self.half {
            f0.table
                .interpolate(self.half, self.located, Query::new(self.axis, o), arrays)
        } else {
            f0.table.eval_arrays(s, v, arrays)
        };
        // `f` is never negative; `∂f/∂ρ0` may be (the sheen's loss to `ζ = 1 − ρ0`).
        let mut f = f.map(|x| self.weight * x);
        f[0] = f[0].max(0.0);
        f
    }
}

impl Symmetry {
    /// The symmetry of a model's BRDF, which its table uses: isotropic for flat fibers and
    /// `isotropic = true` yarns, mirror for every other woven material.
    pub fn of(model: &Model) -> Symmetry {
        match model.structure() {
            Structure::Flat(_) => Symmetry::Isotropic,
            Structure::Woven { yarn, .. } if yarn.params().isotropic => Symmetry::Isotropic,
            Structure::Woven { .. } => Symmetry::Mirror,
        }
    }
}

/// The other direction of a node whose derived direction lies below the horizon: lifted
/// [`HORIZON_LIFT_DEG`] above it in the same azimuth (the BRDF is continuous up to the horizon: the
/// Smith term cancels `1/cos θ`); where the half vector faces away from the axis, the reflection
/// `2 (a·h) h − a` still gives an azimuth to lift. `None` only straight below.
fn lifted(a: Vec3, px: f64, py: f64) -> Option<Vec3> {
    let h = h_of_slopes(px, py);
    let o = h * (2.0 * a.dot(h)) - a;
    let min_z = HORIZON_LIFT_DEG.to_radians().sin();
    let r_xy = (o.x * o.x + o.y * o.y).sqrt();
    if r_xy <= 0.0 {
        return None;
    }
    let c = (1.0 - min_z * min_z).sqrt() / r_xy;
    Some(Vec3::new(o.x * c, o.y * c, min_z))
}

/// Which half-vector nodes of row `(it, ip)` some pair of its half reads, row-major `(i_y, i_x)`.
///
/// A half answers for the pairs whose axis direction is the more grazing, `θ_o ≤ θ_a`. A pair
/// reads the nodes around it: axis nodes within one polar step `Δθ` and one azimuth step `Δφ`
/// (an angle of at most `Δθ + Δφ sin θ`), half-vector nodes within one cell (`δh`, the sum of the
/// slope-angle steps of both axes). At a fixed half vector the other direction is the axis
/// reflected about it, so it moves by as much as the axis, and by at most `2δh` as the half
/// vector moves. A node is therefore read only if its own other direction has
/// `θ_o ≤ θ_a + 2Δθ + Δφ sin θ_a + 2δh`; the rest of the row is never read and is not evaluated
/// (below-horizon other directions count as `θ_o = 90°`).
fn needed_nodes(theta: Axis, phi: Axis, t: Axis, it: usize, ip: usize) -> Vec<bool> {
    let n = t.n;
    let th = theta.node(it);
    let prev = if it > 0 { th - theta.node(it - 1) } else { 0.0 };
    let next = if it + 1 < theta.n {
        theta.node(it + 1) - th
    } else {
        FRAC_PI_2 - th
    };
    let d_theta = prev.max(next);
    let d_phi = if phi.n > 1 {
        phi.node(1) - phi.node(0)
    } else {
        0.0
    };
    let a = Vec3::from_spherical(th, phi.node(ip));
    let angle = |k: usize| super::grid::slope_of_t(t.node(k)).atan();
    let step: Vec<f64> = (0..n)
        .map(|k| {
            let lo = if k > 0 { angle(k) - angle(k - 1) } else { 0.0 };
            let hi = if k + 1 < n {
                angle(k + 1) - angle(k)
            } else {
                0.0
            };
            lo.abs().max(hi.abs())
        })
        .collect();
    // A little slack for rounding and the sampler's corner reads.
    let base = th + 2.0 * d_theta + d_phi * th.sin() + 1e-3;
    let mut out = vec![false; n * n];
    for iy in 0..n {
        let py = super::grid::slope_of_t(t.node(iy));
        for ix in 0..n {
            let px = super::grid::slope_of_t(t.node(ix));
            let theta_o = match v_of_slopes(a, px, py) {
                Some((o, _)) => o.z.clamp(-1.0, 1.0).acos(),
                None => FRAC_PI_2,
            };
            out[iy * n + ix] = theta_o <= base + 2.0 * (step[ix] + step[iy]);
        }
    }
    out
}

/// Evaluates both halves at every node they read, rows of `(half, θ, φ)` spread over the current
/// rayon pool: `row(half, a)` prepares the evaluation for axis direction `a` and returns
/// `o ↦ f(s, v)` with `(s, v) = half.join(a, o)`. `progress` hears rows and is asked before each
/// whether to stop: [`Error::Cancelled`] then.
pub(super) fn fill<const K: usize, R: Fn(Vec3) -> [f64; K]>(
    theta: Axis,
    phi: Axis,
    t: Axis,
    progress: &dyn Progress,
    row: impl Fn(Half, Vec3) -> R + Sync,
) -> Result<[Vec<f32>; K]> {
    let rows_per_half = theta.n * phi.n;
    let rows = 2 * rows_per_half;
    let row_len = t.n * t.n;
    // Row-major, each row holding its K parts one after the other.
    let mut values = vec![0f32; K * rows * row_len];
    let done = AtomicUsize::new(0);
    values
        .par_chunks_mut(K * row_len)
        .enumerate()
        .with_max_len(1)
        .for_each(|(r, out)| {
            if progress.cancelled() {
                return;
            }
            let half = if r < rows_per_half {
                Half::Light
            } else {
                Half::View
            };
            let rr = r % rows_per_half;
            let (it, ip) = (rr / phi.n, rr % phi.n);
            let a = Vec3::from_spherical(theta.node(it), phi.node(ip));
            let needed = needed_nodes(theta, phi, t, it, ip);
            let f = row(half, a);
            for iy in 0..t.n {
                let py = super::grid::slope_of_t(t.node(iy));
                for ix in 0..t.n {
                    if !needed[iy * t.n + ix] {
                        continue;
                    }
                    let px = super::grid::slope_of_t(t.node(ix));
                    let o = match v_of_slopes(a, px, py) {
                        Some((o, _)) => Some(o),
                        None => lifted(a, px, py),
                    };
                    let parts = o.map_or([0.0; K], &f);
                    for (k, x) in parts.into_iter().enumerate() {
                        out[k * row_len + iy * t.n + ix] = x as f32;
                    }
                }
            }
            progress.update(done.fetch_add(1, Ordering::Relaxed) + 1, rows);
        });
    if progress.cancelled() {
        return Err(Error::Cancelled);
    }
    Ok(std::array::from_fn(|k| {
        values
            .chunks_exact(K * row_len)
            .flat_map(|row| &row[k * row_len..(k + 1) * row_len])
            .copied()
            .collect()
    }))
}

/// [`fill`] for work nothing stops: a table derived on first use (tilted).
pub(super) fn fill_uncancelled<const K: usize, R: Fn(Vec3) -> [f64; K]>(
    theta: Axis,
    phi: Axis,
    t: Axis,
    row: impl Fn(Half, Vec3) -> R + Sync,
) -> [Vec<f32>; K] {
    match fill(theta, phi, t, crate::progress::NONE, row) {
        Ok(values) => values,
        Err(_) => unreachable!("a progress that never asks to stop"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::report::SplitMix;

    /// A constant BRDF tabulates to itself at every pair, grazing ones included, on grids of both
    /// symmetries: interpolation only ever reads nodes that [`needed_nodes`] had evaluated (an
    /// unevaluated node holds 0 and would pull the value below 1).
    #[test]
    fn queries_read_only_evaluated_nodes() {
        let mut rng = SplitMix(5);
        for (n_theta, n_phi, n_t, symmetry) in [
            (30, 19, 81, Symmetry::Mirror),
            (8, 4, 17, Symmetry::Mirror),
            (30, 1, 161, Symmetry::Isotropic),
            (12, 13, 41, Symmetry::Mirror),
        ] {
            let theta = Axis {
                lo: 0.0,
                hi: 89.9f64.to_radians(),
                n: n_theta,
                grading: THETA_GRADING,
            };
            let phi = Axis::uniform(0.0, FRAC_PI_2, n_phi);
            let t = Axis::uniform(-1.0, 1.0, n_t);
            let [values] = fill_uncancelled(theta, phi, t, |_, _| |_| [1.0]);
            let evaluated = values.iter().filter(|&&v| v == 1.0).count();
            assert!(
                evaluated < values.len(),
                "nothing pruned ({n_theta}, {n_phi}, {n_t})"
            );
            let table = Table::assemble(
                symmetry,
                theta,
                phi,
                t,
                values,
                None,
                550.0,
                Some(Vec::new()),
                None,
                None,
            );
            for k in 0..100_000 {
                // Half the draws within 10° of the horizon, a quarter within 1°.
                let lim = [1.0, 0.17, 1.0, 0.017][k % 4];
                let mut pick = || {
                    let z = lim * rng.uniform().max(1e-9);
                    let ph = 2.0 * std::f64::consts::PI * rng.uniform();
                    let r = (1.0 - z * z).sqrt();
                    Vec3::new(r * ph.cos(), r * ph.sin(), z)
                };
                let (s, v) = (pick(), pick());
                let f = table.eval(s, v);
                assert!(
                    (f - 1.0).abs() < 1e-9,
                    "grid ({n_theta}, {n_phi}, {n_t}): s {s:?} v {v:?} gives {f}"
                );
            }
            println!(
                "grid ({n_theta}, {n_phi}, {n_t}): {:.1} % of nodes evaluated",
                100.0 * evaluated as f64 / table.values.len() as f64
            );
        }
    }
}
