//! The microcylinder cloth model of Sadeghi, Bisker, De Deken & Jensen, *A Practical
//! Microcylinder Appearance Model for Cloth Rendering*, ACM TOG 32(2), article 14 (2013): cloth
//! as two kinds of thread, each a dielectric cylinder whose tangent tilts along a curve, with
//! surface and volume scattering, shadowing and masking, and a reweighting by apparent length.
//!
//! ```
//! use woven::microcylinder::Microcylinder;
//! use woven::Vec3;
//! let cloth = Microcylinder::preset("microcylinder-linen-plain")?;
//! // Light 30° off the normal in the xz plane, viewer at the mirror direction.
//! let (wi, wo) = (Vec3::from_spherical(0.52, 0.0), Vec3::from_spherical(0.52, std::f64::consts::PI));
//! let f = cloth.eval_rgb(wi, wo); // sr⁻¹, per channel, without the cosine
//! assert!(f.is_valid() && f.0[2] > f.0[0]); // a blue-green linen
//! assert!(cloth.albedo(0.52, 0.0).max() <= 1.0);
//! # Ok::<(), woven::Error>(())
//! ```
//!
//! Frames (docs/microcylinder.md §1): `z` is the cloth normal; thread 1 (the weft) runs along `x`
//! and thread 2 along `y`; `wi` points toward the light (the paper's `ω_i`) and `wo` toward the
//! viewer (`ω_r`), both away from the surface; angles in radians.
//!
//! | parameter | meaning | unit | valid range |
//! |---|---|---|---|
//! | `eta` | relative refractive index `η` | — | `[1, 3]` |
//! | `albedo` | volume albedo `A` (RGB) | — | `[0, 1]` each |
//! | `kd` | isotropic share `k_d` of the volume lobe | — | `[0, 1]` |
//! | `gamma_s`, `gamma_v` | widths of the surface and volume lobes | radians | `[0.1°, 60°]`, `[0.1°, 90°]` |
//! | `coverage` | the thread's area share `a_j` | — | `[0, 1]`, `a_1 + a_2 ≤ 1` |
//! | `tangents` | tangent offsets (radians, `[−π/2, π/2]`) and segment lengths (`≥ 0`) | — | [`TangentCurve::new`] |
//!
//! Module map: [`frame`](TangentFrame) (angles), [`scattering`] (Eqs. (3)–(5)),
//! [`masking`] (Eqs. (10)–(13)), [`TangentCurve`] (the curve and its quadrature), the shading
//! model and its normalization (Eqs. (9), (14); `cloth.rs`), the energy guard (`guard.rs`), the
//! six presets of Table II and importance sampling (`sample.rs`).

mod cloth;
mod curve;
#[cfg(feature = "serde")]
mod file;
mod frame;
mod guard;
mod masking;
mod presets;
mod sample;
mod scattering;
mod thread;

pub use cloth::{default_rule, GAUSS_NODES_PER_PANEL, PANEL_WIDTH_OVER_GAMMA_S};
pub use curve::{CurveNode, CurveRule, TangentCurve, MAX_CONTROL_POINTS};
#[cfg(feature = "serde")]
pub use file::fabric_toml;
pub use frame::{psi_difference, wrap_pi, PairAngles, TangentFrame, ThreadAngles};
pub use guard::{
    albedo_quadrature, h_at, EnergyGuard, ALBEDO_PANELS, GUARD_MARGIN, GUARD_PHI_COUNT,
    GUARD_THETA_DEG, PRESET_GUARD_MARGIN, PRESET_GUARD_PHI_COUNT,
};
pub use masking::{
    blend_correlated, correlation, masking, masking_one, reweight, reweight_one, CORRELATION_SIGMA,
};
pub use presets::{PRESET_GUARDS, PRESET_NAMES};
pub use sample::COSINE_SHARE;
pub use scattering::{gaussian, scattering, surface_lobe, volume_lobe, ScatteringParams};
pub use thread::Thread;

use crate::color::Rgb;
use crate::error::{Error, Result};
use crate::math::Vec3;
use cloth::{shading_model, PreparedThread};
use std::sync::OnceLock;

/// A microcylinder cloth: two threads, prepared to evaluate (tangent frames and quadrature
/// weights precomputed) with its energy guard tabulated.
///
/// `name` and `threads` are public to read; evaluation uses what was prepared from them at
/// construction, so a changed thread takes effect only in a cloth built anew
/// ([`Microcylinder::new`]).
#[derive(Clone, Debug)]
pub struct Microcylinder {
    /// The fabric's name (a preset's name, or a file's `name`).
    pub name: String,
    /// Thread 1 (along `x`, the weft) and thread 2 (along `y`), as given.
    pub threads: [Thread; 2],
    /// Boxed: the prepared threads are large and `Microcylinder` sits in enums of materials.
    prepared: Box<[PreparedThread; 2]>,
    gap: f64,
    guard: EnergyGuard,
}

impl Microcylinder {
    /// A cloth from its two threads (thread 1 along `x`, thread 2 along `y`), with the default
    /// curve quadrature ([`default_rule`]) and the energy guard measured (a fraction of a second:
    /// [`GUARD_THETA_DEG`] × [`GUARD_PHI_COUNT`] albedos, in parallel).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first invalid parameter (`thread[1].kd`), or
    /// `coverage` when `a_1 + a_2 > 1`.
    pub fn new(name: impl Into<String>, threads: [Thread; 2]) -> Result<Self> {
        Self::with_options(name, threads, &default_rule, true)
    }

    /// As [`new`](Self::new) with a chosen quadrature of each thread's curve, and the energy
    /// guard measured or not (`guard = false`: the printed model, [`eval_rgb`](Self::eval_rgb)
    /// equal to [`eval_unguarded`](Self::eval_unguarded)).
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn with_options(
        name: impl Into<String>,
        threads: [Thread; 2],
        rule: &dyn Fn(&Thread) -> CurveRule,
        guard: bool,
    ) -> Result<Self> {
        threads[0].validate(0)?;
        threads[1].validate(1)?;
        let covered = threads[0].coverage + threads[1].coverage;
        // 1e-9: Table II's coverages are rounded to two places and sum to 1 up to rounding.
        if covered > 1.0 + 1e-9 {
            return Err(Error::invalid(
                "coverage",
                format!("a_1 + a_2 = {covered}"),
                "thread[0].coverage + thread[1].coverage ≤ 1",
            ));
        }
        let prepared = Box::new([
            PreparedThread::new(0, &threads[0], rule(&threads[0])),
            PreparedThread::new(1, &threads[1], rule(&threads[1])),
        ]);
        let mut cloth = Microcylinder {
            name: name.into(),
            threads,
            prepared,
            gap: (1.0 - covered).max(0.0),
            guard: EnergyGuard::none(),
        };
        if guard {
            cloth.guard = EnergyGuard::build(
                &|wi, wo| cloth.eval_unguarded(wi, wo),
                GUARD_PHI_COUNT,
                GUARD_MARGIN,
            );
        }
        Ok(cloth)
    }

    /// A preset of the paper's Table II by name (see [`preset_names`](Self::preset_names)); each
    /// is built once per process and cloned, its energy guard read from a table measured once
    /// on a finer grid ([`PRESET_GUARD_PHI_COUNT`] azimuths, margin [`PRESET_GUARD_MARGIN`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `material` for an unknown name.
    pub fn preset(name: &str) -> Result<Self> {
        static CACHE: [OnceLock<Microcylinder>; 6] = [const { OnceLock::new() }; 6];
        let threads = presets::preset_threads(name)?;
        let k = PRESET_NAMES.iter().position(|n| *n == name).unwrap_or(0);
        if let Some(c) = CACHE[k].get() {
            return Ok(c.clone());
        }
        // The guard measured once on a fine grid (examples/microcylinder_guard) and stored.
        let mut cloth = Microcylinder::with_options(name, threads, &default_rule, false)?;
        cloth.guard = EnergyGuard::from_table(&presets::PRESET_GUARDS[k], PRESET_GUARD_MARGIN);
        Ok(CACHE[k].get_or_init(|| cloth).clone())
    }

    /// A preset's two threads by name, to build it with other options
    /// ([`with_options`](Self::with_options)).
    ///
    /// # Errors
    /// As [`preset`](Self::preset).
    pub fn preset_threads(name: &str) -> Result<[Thread; 2]> {
        presets::preset_threads(name)
    }

    /// The six presets of the paper's Table II: linen plain, silk crêpe de Chine, polyester
    /// satin charmeuse (front and back), silk shot, velvet.
    pub fn preset_names() -> &'static [&'static str] {
        &PRESET_NAMES
    }

    /// The energy guard.
    pub fn guard(&self) -> &EnergyGuard {
        &self.guard
    }

    /// The number of tangents (quadrature nodes) of each thread's curve.
    pub fn tangent_counts(&self) -> [usize; 2] {
        [self.prepared[0].frames.len(), self.prepared[1].frames.len()]
    }

    /// The printed model's BRDF, sr⁻¹ per channel, without the energy guard (Eqs. (9), (14);
    /// docs/microcylinder.md §4). `wi` toward the light, `wo` toward the viewer, unit; 0 below
    /// the horizon.
    pub fn eval_unguarded(&self, wi: Vec3, wo: Vec3) -> Rgb {
        debug_assert!((wi.length() - 1.0).abs() < 1e-6 && (wo.length() - 1.0).abs() < 1e-6);
        shading_model(&self.prepared, self.gap, wi, wo)
    }

    /// The BRDF a renderer uses, sr⁻¹ per channel, without the cosine: the printed model times
    /// the energy guard's factor `k(θ_i)` (docs/microcylinder.md §6). `wi` toward the light, `wo`
    /// toward the viewer, unit vectors in the cloth frame; 0 below the horizon.
    pub fn eval_rgb(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::BLACK;
        }
        self.eval_unguarded(wi, wo) * self.guard.factor(wi.z)
    }

    /// The directional albedo `∫ f(ω_i, ω_o) cos θ_o dω_o` of [`eval_rgb`](Self::eval_rgb) for
    /// light at polar angle `theta_i` and azimuth `phi_i` (radians), by [`albedo_quadrature`].
    pub fn albedo(&self, theta_i: f64, phi_i: f64) -> Rgb {
        let wi = Vec3::from_spherical(theta_i, phi_i);
        albedo_quadrature(|wo| self.eval_rgb(wi, wo), ALBEDO_PANELS)
    }

    /// As [`albedo`](Self::albedo) for the printed model without the guard.
    pub fn albedo_unguarded(&self, theta_i: f64, phi_i: f64) -> Rgb {
        let wi = Vec3::from_spherical(theta_i, phi_i);
        albedo_quadrature(|wo| self.eval_unguarded(wi, wo), ALBEDO_PANELS)
    }
}
