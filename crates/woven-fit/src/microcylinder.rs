//! Fitting the microcylinder cloth model of Sadeghi et al. 2013 ([`woven::microcylinder`]):
//! its parameters, its starting fabric, its evaluation as the fitter's affine parts, its energy
//! guard, and the fitted fabric as a microcylinder file.
//!
//! **Parameters** (one row each in this module's table `SPECS`, the one home of their ranges), per thread
//! `threadN` (`thread1` along `x`, the weft; `thread2` along `y`): `albedo` (the volume albedo
//! `A`, one parameter per colour channel with colour data, as the other models' albedos: the BRDF
//! is affine in each channel's albedo, so each gets an exact derivative and the colour is not
//! tied to the start's hue), `kd`, `gamma_s`, `gamma_v` (radians) and `eta` (held unless freed,
//! as the woven fit holds the fiber's `η`); for the cloth, `coverage` (`a_1 + a_2`, the threads'
//! share of the area) and `thread1.coverage_share` (`a_1/(a_1 + a_2)`): each thread's coverage
//! is then in `[0, 1]` with `a_1 + a_2 ≤ 1` at every iterate, which two independent coverages
//! would break; `scale` for relatively calibrated data. The tangent curves are held at the
//! starting fabric's: they are the fabric's geometry.
//!
//! **Energy.** The fit's model is the one [`Microcylinder::eval_rgb`] renders: the printed model
//! times its energy guard `k(θ_i)` (docs/microcylinder.md §6), the guard that
//! [`Microcylinder::new`] measures for the fitted threads. Measuring a guard costs seconds, so a
//! fit holds one ([`Fabric::guard`]; none at the start) through its Levenberg–Marquardt runs, and
//! measures it at the result: where it changed at the data's incidences, the final run is
//! repeated with the new one ([`fit`](mod@crate::fit)). Only the guard's polar angles that bracket the
//! data's incidences are measured (the factor at `θ_i` reads those alone), so the predictions are
//! the guarded model's at every measurement.

use crate::error::FitError;
use crate::evaluate::Parts;
use crate::fit::Observations;
use crate::params::{FreeBy, Home, ModelKind, ParamSet, Quantity, Spec, Transform, SCALE};
use crate::report::{fmt, FitResult};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::fmt::Write as _;
use woven::color::Rgb;
use woven::material::Material;
use woven::microcylinder::{
    default_rule, fabric_toml, h_at, EnergyGuard, Microcylinder, Thread, GUARD_MARGIN,
    GUARD_PHI_COUNT, GUARD_THETA_DEG,
};
use woven::Vec3;

/// The starting fabric of a microcylinder fit when none is given.
pub const DEFAULT_MICROCYLINDER_INIT: &str = "microcylinder-linen-plain";

/// One degree in radians.
const DEG: f64 = PI / 180.0;

/// A microcylinder fabric as a fit holds it: its threads (the fitted values go into them, the
/// tangent curves stay) and the energy guard held during the fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Fabric {
    /// The fabric's name.
    pub name: String,
    /// Thread 1 (along `x`, the weft) and thread 2 (along `y`).
    pub threads: [Thread; 2],
    /// The energy guard held: [`EnergyGuard::none`] at the start of a fit, measured at the
    /// result (the polar angles the data needs; zeros elsewhere) after it.
    pub guard: EnergyGuard,
}

impl Fabric {
    /// A fabric from its threads, checked as [`Microcylinder::new`] checks them (without
    /// measuring its guard), with no guard held.
    ///
    /// # Errors
    /// [`FitError::Material`] naming the parameter the library refuses.
    pub fn new(name: impl Into<String>, threads: [Thread; 2]) -> Result<Fabric, FitError> {
        threads[0].validate(0)?;
        threads[1].validate(1)?;
        let covered = threads[0].coverage + threads[1].coverage;
        if covered > 1.0 + 1e-9 {
            return Err(FitError::invalid(
                "coverage",
                format!("a_1 + a_2 = {covered}"),
                "thread[0].coverage + thread[1].coverage ≤ 1",
            ));
        }
        Ok(Fabric {
            name: name.into(),
            threads,
            guard: EnergyGuard::none(),
        })
    }

    /// The starting fabric named by `arg`: a microcylinder preset (`microcylinder-…`) or a
    /// microcylinder file (`model = "microcylinder"`), read without measuring its guard.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming `init`: for a woven preset or material file, an
    /// unknown name, or a file that is not a valid microcylinder file (the library's reason
    /// included).
    pub fn from_preset_or_path(arg: &str) -> Result<Fabric, FitError> {
        let presets = Microcylinder::preset_names().join(", ");
        let expected = |why: String| {
            FitError::invalid(
                "init",
                format!("{arg:?}"),
                format!(
                    "a microcylinder preset ({presets}) or a microcylinder file \
                     (model = \"microcylinder\"): {why}"
                ),
            )
        };
        if Microcylinder::preset_names().contains(&arg) {
            let threads = Microcylinder::preset_threads(arg)?;
            return Fabric::new(arg, threads);
        }
        if Material::preset_toml(arg).is_some() {
            return Err(expected(
                "this is a woven material preset (model cloth or fiber)".into(),
            ));
        }
        let path = std::path::Path::new(arg);
        if !(path.exists() || arg.contains('/') || arg.ends_with(".toml")) {
            return Err(expected("no such preset or file".into()));
        }
        let (name, threads) = Microcylinder::threads_from_path(path).map_err(|e| {
            let woven = Material::from_path(path).is_ok();
            expected(if woven {
                "this is a woven material file (model cloth or fiber)".into()
            } else {
                e.to_string()
            })
        })?;
        Fabric::new(name, threads)
    }

    /// The fabric as the library's model, its guard measured as for any fabric built from its
    /// threads ([`Microcylinder::new`]: seconds).
    ///
    /// # Errors
    /// As [`Microcylinder::new`].
    pub fn build(&self) -> Result<Microcylinder, FitError> {
        Ok(Microcylinder::new(self.name.clone(), self.threads.clone())?)
    }
}

/// A row for one field of thread `$k` (0 or 1): `thread_spec!(name, k, quantity, per_channel,
/// bounds, transform, start, free, |thread| read → [f64; 3], |thread, values| write)`.
macro_rules! thread_spec {
    ($name:literal, $k:literal, $quantity:expr, $per_channel:literal, $bounds:expr,
     $transform:ident, $start:expr, $free:ident, |$t:ident| $read:expr,
     |$tw:ident, $v:ident| $write:expr) => {
        Spec {
            name: $name,
            quantity: $quantity,
            per_channel: $per_channel,
            bounds: $bounds,
            transform: Transform::$transform,
            start: $start,
            home: Home::Fabric {
                read: |f| {
                    let $t = &f.threads[$k];
                    $read
                },
                write: |f, $v| {
                    let $tw = &mut f.threads[$k];
                    $write
                },
            },
            free: FreeBy::$free,
        }
    };
}

/// The narrowest lobe a fit may reach, radians (1°; the library takes 0.1°): the curve's
/// quadrature takes panels `2 γ_s` wide, so a needle lobe costs a curve hundreds of tangents
/// (linen's ±25° at 0.1°: 1500 a thread, forty times the work), and fits single samples.
/// Table II's narrowest is 2.5°.
pub const MIN_WIDTH: f64 = DEG;

/// A thread's five rows (`albedo`, `kd`, `gamma_s`, `gamma_v`, `eta`): the library's ranges
/// (`Thread::validate`), the widths from [`MIN_WIDTH`], `eta` held by default.
macro_rules! thread_specs {
    ($k:literal, $albedo:literal, $kd:literal, $gs:literal, $gv:literal, $eta:literal) => {
        [
            thread_spec!(
                $albedo,
                $k,
                Quantity::VolumeAlbedo($k),
                true,
                (0.0, 1.0),
                Logit,
                (0.02, 0.9),
                Always,
                |t| t.albedo.0,
                |t, v| t.albedo = Rgb(v)
            ),
            thread_spec!(
                $kd,
                $k,
                Quantity::VolumeShare,
                false,
                (0.0, 1.0),
                Logit,
                (0.02, 0.9),
                Always,
                |t| [t.kd; 3],
                |t, v| t.kd = v[0]
            ),
            thread_spec!(
                $gs,
                $k,
                Quantity::SurfaceWidth,
                false,
                (MIN_WIDTH, 60.0 * DEG),
                LogLogit,
                (1.5 * DEG, 30.0 * DEG),
                Always,
                |t| [t.gamma_s; 3],
                |t, v| t.gamma_s = v[0]
            ),
            thread_spec!(
                $gv,
                $k,
                Quantity::VolumeWidth,
                false,
                (MIN_WIDTH, 90.0 * DEG),
                LogLogit,
                (2.0 * DEG, 60.0 * DEG),
                Always,
                |t| [t.gamma_v; 3],
                |t, v| t.gamma_v = v[0]
            ),
            thread_spec!(
                $eta,
                $k,
                Quantity::Eta,
                false,
                (1.0, 3.0),
                Logit,
                (1.3, 1.8),
                Never,
                |t| [t.eta; 3],
                |t, v| t.eta = v[0]
            ),
        ]
    };
}

const THREAD1: [Spec; 5] = thread_specs!(
    0,
    "thread1.albedo",
    "thread1.kd",
    "thread1.gamma_s",
    "thread1.gamma_v",
    "thread1.eta"
);

const THREAD2: [Spec; 5] = thread_specs!(
    1,
    "thread2.albedo",
    "thread2.kd",
    "thread2.gamma_s",
    "thread2.gamma_v",
    "thread2.eta"
);

/// `a_1/(a_1 + a_2)`, ½ for a cloth of gaps alone.
fn share_of(f: &Fabric) -> f64 {
    let total = f.threads[0].coverage + f.threads[1].coverage;
    if total > 0.0 {
        f.threads[0].coverage / total
    } else {
        0.5
    }
}

/// Sets the coverages from their sum and thread 1's share.
fn set_coverages(f: &mut Fabric, total: f64, share: f64) {
    f.threads[0].coverage = total * share;
    f.threads[1].coverage = total * (1.0 - share);
}

/// `microcylinder`: the parameter table (module docs), in the order of [`ParamSet::params`].
/// `coverage` comes before `thread1.coverage_share`: each write keeps the other's value.
pub(crate) const SPECS: &[Spec] = &[
    THREAD1[0],
    THREAD1[1],
    THREAD1[2],
    THREAD1[3],
    THREAD1[4],
    THREAD2[0],
    THREAD2[1],
    THREAD2[2],
    THREAD2[3],
    THREAD2[4],
    Spec {
        name: "coverage",
        quantity: Quantity::Coverage,
        per_channel: false,
        bounds: (0.0, 1.0),
        transform: Transform::Logit,
        start: (0.4, 1.0),
        home: Home::Fabric {
            read: |f| [f.threads[0].coverage + f.threads[1].coverage; 3],
            write: |f, v| set_coverages(f, v[0], share_of(f)),
        },
        free: FreeBy::Always,
    },
    Spec {
        name: "thread1.coverage_share",
        quantity: Quantity::CoverageShare,
        per_channel: false,
        bounds: (0.0, 1.0),
        transform: Transform::Logit,
        start: (0.05, 0.95),
        home: Home::Fabric {
            read: |f| [share_of(f); 3],
            write: |f, v| {
                let total = f.threads[0].coverage + f.threads[1].coverage;
                set_coverages(f, total, v[0]);
            },
        },
        free: FreeBy::Always,
    },
    SCALE,
];

impl ParamSet {
    /// The parameters of a microcylinder fit starting at `init` (the default
    /// [`DEFAULT_MICROCYLINDER_INIT`] when `None`) for data with `channels` colour channels (1:
    /// one grey albedo per thread; 3: per channel). `relative`: `scale` is free. A start
    /// outside a parameter's range (a width below [`MIN_WIDTH`]) starts at its bound, and a
    /// free parameter on a bound (a coverage of 1, an albedo channel of 0) just inside it,
    /// where the optimizer can move it.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] for `channels` other than 1 or 3; [`FitError::Material`]
    /// if the default fabric cannot be read.
    pub fn microcylinder(
        init: Option<&Fabric>,
        channels: usize,
        relative: bool,
    ) -> Result<ParamSet, FitError> {
        let fabric = match init {
            Some(f) => f.clone(),
            None => Fabric::from_preset_or_path(DEFAULT_MICROCYLINDER_INIT)?,
        };
        let mut set = ParamSet::with_templates(
            ModelKind::Microcylinder,
            None,
            Some(fabric),
            channels,
            relative,
        )?;
        for p in set.params.iter_mut() {
            p.value = p.value.clamp(p.lo, p.hi);
            if p.free && p.at_bound() {
                let inset = 2e-3 * (p.hi - p.lo);
                p.value = p.value.clamp(p.lo + inset, p.hi - inset);
            }
        }
        Ok(set)
    }

    /// The microcylinder fabric at the set's values (its guard the one held), or `None` for the
    /// other models.
    pub fn fabric_at_values(&self) -> Option<Fabric> {
        let mut fabric = self.fabric.clone()?;
        for spec in SPECS {
            let Home::Fabric { write, .. } = spec.home else {
                continue;
            };
            let mut values = [0.0; 3];
            let mut found = false;
            for p in self.params.iter().filter(|p| p.base_name() == spec.name) {
                values[p.channel] = p.value;
                found = true;
            }
            if !found {
                continue;
            }
            if !(spec.per_channel && self.channels == 3) {
                values = [values[0]; 3];
            }
            write(&mut fabric, values);
        }
        Some(fabric)
    }
}

/// A microcylinder fabric made ready to evaluate as the fitter's affine parts: the library's
/// model (its curves' quadrature prepared) with thread 1's albedo `(0, 1, 0)` and thread 2's
/// `(0, 0, 1)`, so that one evaluation gives the surface lobes (red), and each thread's volume
/// lobe per unit albedo (green, blue, less red): the BRDF is affine in the albedos, channel by
/// channel. The held guard's factor multiplies all three.
pub struct PreparedFabric {
    unit: Microcylinder,
    guard: EnergyGuard,
}

impl PreparedFabric {
    /// Prepares the fabric at `set`'s values.
    ///
    /// # Errors
    /// When the library refuses the threads (a parameter out of its range).
    pub fn new(set: &ParamSet) -> Result<PreparedFabric, woven::Error> {
        let fabric = set.fabric_at_values().ok_or_else(|| {
            woven::Error::invalid("model", set.model.name(), "a microcylinder parameter set")
        })?;
        let mut threads = fabric.threads;
        threads[0].albedo = Rgb([0.0, 1.0, 0.0]);
        threads[1].albedo = Rgb([0.0, 0.0, 1.0]);
        let unit = Microcylinder::with_options(fabric.name, threads, &default_rule, false)?;
        Ok(PreparedFabric {
            unit,
            guard: fabric.guard,
        })
    }

    /// The parts at one pair (`s` toward the light, `v` toward the viewer, the cloth's frame):
    /// `fixed` the surface lobes, `per_diffuse` thread 1's volume lobe per unit albedo,
    /// `per_interreflection` thread 2's; each times the guard's factor.
    pub fn parts(&self, s: Vec3, v: Vec3) -> Parts {
        let f = self.unit.eval_unguarded(s, v);
        let k = self.guard.factor(s.z);
        Parts {
            fixed: k * f.0[0],
            per_diffuse: k * (f.0[1] - f.0[0]).max(0.0),
            per_interreflection: k * (f.0[2] - f.0[0]).max(0.0),
        }
    }
}

/// The indices of [`GUARD_THETA_DEG`] that the guard's factor reads for light at `cos_theta`
/// (as [`EnergyGuard::factor`] picks them: the two bracketing polar angles).
fn guard_nodes(cos_theta: f64) -> Vec<usize> {
    let theta = cos_theta.clamp(0.0, 1.0).acos().to_degrees();
    let n = GUARD_THETA_DEG.len();
    match GUARD_THETA_DEG.partition_point(|&t| t <= theta) {
        0 => vec![0],
        k if k >= n => vec![n - 1],
        k => vec![k - 1, k],
    }
}

/// Measures the energy guard of the fabric at `set`'s values at the polar angles the
/// observations' incidences need, as [`Microcylinder::new`] measures it there (the same
/// albedos, [`GUARD_PHI_COUNT`] azimuths, [`GUARD_MARGIN`]; at normal incidence one azimuth, as
/// every azimuth names the same direction), and holds it in the set. Returns whether the
/// factor changed at any observation, and the model evaluations spent; a set of another model
/// is left alone (`(false, 0)`).
pub(crate) fn update_guard(set: &mut ParamSet, data: &Observations) -> (bool, usize) {
    let Some(fabric) = set.fabric_at_values() else {
        return (false, 0);
    };
    let Ok(model) =
        Microcylinder::with_options(fabric.name.clone(), fabric.threads, &default_rule, false)
    else {
        return (false, 0);
    };
    let mut needed = vec![false; GUARD_THETA_DEG.len()];
    for o in &data.obs {
        for k in guard_nodes(o.s.z) {
            needed[k] = true;
        }
    }
    let cases: Vec<(usize, usize)> = (0..GUARD_THETA_DEG.len())
        .filter(|&k| needed[k])
        .flat_map(|k| {
            let azimuths = if GUARD_THETA_DEG[k] == 0.0 {
                1
            } else {
                GUARD_PHI_COUNT
            };
            (0..azimuths).map(move |j| (k, j))
        })
        .collect();
    let f = |wi: Vec3, wo: Vec3| model.eval_unguarded(wi, wo);
    let values: Vec<f64> = cases
        .par_iter()
        .map(|&(k, j)| h_at(&f, GUARD_THETA_DEG[k], j, GUARD_PHI_COUNT))
        .collect();
    let mut h = vec![0.0f64; GUARD_THETA_DEG.len()];
    for (&(k, _), v) in cases.iter().zip(&values) {
        h[k] = h[k].max(*v);
    }
    let guard = EnergyGuard::from_table(&h, GUARD_MARGIN);
    let old = &set.fabric.as_ref().expect("a microcylinder set").guard;
    let changed = data
        .obs
        .iter()
        .any(|o| (guard.factor(o.s.z) - old.factor(o.s.z)).abs() > 1e-9);
    if let Some(f) = set.fabric.as_mut() {
        f.guard = guard;
    }
    let panels = woven::microcylinder::ALBEDO_PANELS;
    (changed, cases.len() * panels.0 * panels.1 * 64)
}

/// The fitted fabric as a microcylinder file (`woven eval --material FILE` reads it), with a
/// header recording the fit and the scale, which the file has no key for; `None` for the other
/// models.
pub(crate) fn fabric_toml_of(result: &FitResult) -> Option<String> {
    let fabric = result.params.fabric_at_values()?;
    let mut name = fabric.name.clone();
    if Microcylinder::preset_names().contains(&name.as_str()) {
        name = format!("fit-{}", result.dataset);
    }
    let mut head = format!(
        "# Fitted by `woven fit` to `{}` (model {}): RMS log error {:.4}, relative RMS {:.4}.\n\
         # The threads' tangent curves are the starting fabric's `{}`; the energy guard is\n\
         # measured when the file is read, as for any microcylinder file.\n",
        result.dataset, result.model, result.rms_log, result.relative_rms, fabric.name
    );
    if let Some(p) = result
        .params
        .params
        .iter()
        .find(|p| p.quantity == Quantity::Scale)
    {
        let _ = writeln!(
            head,
            "# {} = {} (not part of a microcylinder file)",
            p.name,
            fmt(p.value)
        );
    }
    Some(format!("{head}\n{}", fabric_toml(&name, &fabric.threads)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_round_trip_through_the_fabric() {
        let shot = Fabric::from_preset_or_path("microcylinder-silk-shot").unwrap();
        let set = ParamSet::microcylinder(Some(&shot), 3, false).unwrap();
        let names: Vec<&str> = set.params.iter().map(|p| p.name.as_str()).collect();
        assert!(
            names.contains(&"thread1.albedo.g")
                && names.contains(&"thread2.gamma_v")
                && names.contains(&"thread1.coverage_share"),
            "{names:?}"
        );
        assert!(set.params.iter().any(|p| p.name == "scale" && !p.free));
        let eta = set.params.iter().find(|p| p.name == "thread1.eta").unwrap();
        assert!(!eta.free && eta.value == 1.345);
        // Free parameters on a bound start just inside it (the warp's green albedo is 0, the
        // coverages sum to 1).
        let fabric = set.fabric_at_values().unwrap();
        let (a1, a2) = (fabric.threads[0].coverage, fabric.threads[1].coverage);
        assert!(a1 + a2 < 1.0 && a1 + a2 > 0.99 && (a1 / (a1 + a2) - 0.86).abs() < 1e-9);
        assert!(fabric.threads[1].albedo.0[1] > 0.0);
        assert_eq!(fabric.threads[0].tangents, shot.threads[0].tangents);
        // Mono data: one grey albedo per thread.
        let mono = ParamSet::microcylinder(Some(&shot), 1, true).unwrap();
        let f = mono.fabric_at_values().unwrap();
        assert_eq!(f.threads[0].albedo.0[0], f.threads[0].albedo.0[2]);
        assert!(mono.params.iter().any(|p| p.name == "scale" && p.free));
    }

    #[test]
    fn parts_are_the_unguarded_model_channel_by_channel() {
        let set = ParamSet::microcylinder(None, 3, false).unwrap();
        let fabric = set.fabric_at_values().unwrap();
        let model =
            Microcylinder::with_options("x", fabric.threads.clone(), &default_rule, false).unwrap();
        let prepared = PreparedFabric::new(&set).unwrap();
        let lin = crate::evaluate::Linear::of(&set);
        for (s, v) in [
            (
                Vec3::from_spherical(0.4, 0.3),
                Vec3::from_spherical(0.5, 3.0),
            ),
            (
                Vec3::from_spherical(1.1, 1.7),
                Vec3::from_spherical(0.2, 0.1),
            ),
        ] {
            let f = model.eval_unguarded(s, v);
            let parts = prepared.parts(s, v);
            for c in 0..3 {
                let p = lin.predict(&parts, c);
                assert!((p - f.0[c]).abs() <= 1e-12 * f.0[c], "{p} vs {}", f.0[c]);
            }
        }
    }

    #[test]
    fn guard_nodes_bracket_as_the_factor_reads() {
        let at = |deg: f64| guard_nodes(deg.to_radians().cos());
        assert_eq!(at(0.0), vec![0, 1]);
        assert_eq!(at(25.0), vec![0, 1]);
        assert_eq!(at(69.0), vec![2, 3]);
        assert_eq!(at(71.0), vec![3, 4]);
        assert_eq!(at(90.0), vec![12]);
    }

    #[test]
    fn inits_of_the_wrong_kind_are_named() {
        for (arg, says) in [
            ("belt-cloth", "woven material preset"),
            ("no-such-fabric", "no such preset or file"),
            ("/no/such/file.toml", "microcylinder preset"),
        ] {
            let e = Fabric::from_preset_or_path(arg).unwrap_err().to_string();
            assert!(
                e.contains("init") && e.contains(arg) && e.contains(says),
                "{arg}: {e}"
            );
            assert!(e.contains("microcylinder-linen-plain"), "{e}");
        }
    }
}
