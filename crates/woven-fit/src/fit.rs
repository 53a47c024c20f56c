//! The objective and the optimizer: a quasi-random multi-start, then bounded Levenberg–Marquardt
//! (the `levenberg-marquardt` crate, a MINPACK port) in the transformed parameters.
//!
//! The residual of a measurement `m` and a prediction `p` in one channel, with weight `w`, is
//! `√w (ln(p + ε) − ln(m + ε))` ([`Residual::Log`], the default: every decade of a BRDF counts
//! alike, and a factor off is the same error at the peak and in the tail) or `√w (p − m)/(m + ε)`
//! ([`Residual::Relative`]); `ε` is 10⁻³ of the channel's median measurement, so that zeros and
//! values drowned in noise neither dominate nor break the logarithm.
//!
//! The Jacobian is exact for the parameters the BRDF is affine in (albedos, `ħ`, the scale, the
//! microfacet baseline's specular weight, the sheen baseline's colour; one evaluation gives them
//! all, [`woven::Model::eval_affine`], [`Linear::derivative`]) and a forward difference for the
//! others, all columns evaluated together over every core.
//! Everything is deterministic for a seed: the starts are a scrambled Sobol sequence and parallel
//! results are collected in order.
//!
//! A fit is never worse than its model's Lambert-like limit ([`lambert_like`]) on the
//! measurements of the final run: when the multi-start's result scores worse than that limit
//! (a start that looked best on the small screening subset can lead into a poor basin), the final
//! run is repeated from the limit and the better result kept.
//!
//! A fit the data cannot decide is refused before it runs ([`FitError::Underdetermined`]): with
//! fewer measured values than free parameters, or when the Jacobian at the initial values
//! (columns scaled to unit length) has a lower rank on the measurements than on a reference
//! geometry ([`REFERENCE_PAIRS`] direction pairs spread over the hemisphere) — some combination
//! of the parameters then changes no prediction at the measured geometries although other
//! geometries would decide it, and whatever the optimizer returned for it would be arbitrary.
//! Singular values count as zero below [`RANK_TOLERANCE`] of the largest, so only an exact
//! degeneracy is refused. A degeneracy the reference geometry shares is the model's own (with
//! relative data, `scale`, `ħ` and `ρ` only enter as `scale·(1 − ħ)` and `scale·ħ·ρ`): such a fit
//! runs, as does one that is merely ill-conditioned, and its report warns of parameters the data
//! cannot determine and of strong correlations.

use crate::data::{Dataset, Value};
use crate::error::FitError;
use crate::evaluate::{FiberCache, Linear, Observation, Parts, Prepared};
use crate::params::{ParamSet, Quantity};
use crate::report::{self, FitResult};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{storage::Owned, DMatrix, DVector, Dyn};
use rayon::prelude::*;
use std::cell::{Cell, RefCell};
use std::fmt::Write as _;
use std::sync::atomic::{AtomicBool, Ordering};

/// The residual of one measurement (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Residual {
    /// `√w (ln(p + ε) − ln(m + ε))`.
    #[default]
    Log,
    /// `√w (p − m)/(m + ε)`.
    Relative,
}

impl Residual {
    /// The residual named `name`: `"log"` or `"relative"`.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming `residual` for any other name.
    pub fn parse(name: &str) -> Result<Residual, FitError> {
        match name {
            "log" => Ok(Residual::Log),
            "relative" => Ok(Residual::Relative),
            _ => Err(FitError::invalid(
                "residual",
                format!("{name:?}"),
                "\"log\" or \"relative\"",
            )),
        }
    }
}

/// How a fit runs.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The residual.
    pub residual: Residual,
    /// Scrambles the quasi-random starts; the same seed gives the same fit.
    pub seed: u32,
    /// Quasi-random starting points screened (besides the initial values).
    pub starts: usize,
    /// The best starts refined by a short Levenberg–Marquardt run.
    pub refine: usize,
    /// Jacobians each refinement may take.
    pub refine_iterations: usize,
    /// Jacobians the final run may take.
    pub max_iterations: usize,
    /// The most measurements the screening and the refinements use (an even subset).
    pub subset: usize,
    /// The most measurements the final run uses; larger datasets are fitted on an even subset
    /// of this size, then polished on every measurement.
    pub final_subset: usize,
    /// Jacobians the polish on every measurement may take (large datasets only).
    pub polish_iterations: usize,
    /// Measurements at or above this value are dropped as saturated.
    pub saturation: Option<f64>,
}

impl FitOptions {
    /// Checks the options [`fit`] cannot run with: a `saturation` that is not finite and
    /// positive, and a `subset` or `final_subset` of no measurements.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming the option, its value and its range.
    pub fn check(&self) -> Result<(), FitError> {
        if let Some(s) = self.saturation.filter(|s| !s.is_finite() || *s <= 0.0) {
            return Err(FitError::invalid(
                "saturation",
                s,
                "a finite value > 0 (1/sr)",
            ));
        }
        for (name, value) in [("subset", self.subset), ("final_subset", self.final_subset)] {
            if value == 0 {
                return Err(FitError::invalid(name, 0, "at least 1 measurement"));
            }
        }
        // The budgets: every start is a parameter set kept until the starts are ranked, every
        // iteration a run of the model over the measurements.
        for (name, value, max) in [
            ("starts", self.starts, MAX_STARTS),
            ("refine", self.refine, MAX_STARTS),
            ("refine_iterations", self.refine_iterations, MAX_ITERATIONS),
            ("max_iterations", self.max_iterations, MAX_ITERATIONS),
            ("polish_iterations", self.polish_iterations, MAX_ITERATIONS),
        ] {
            if value > max {
                return Err(FitError::invalid(
                    name,
                    value,
                    format!(
                        "at most {max} (the fit's budget; {value} is {:.0}x it)",
                        value as f64 / max as f64
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The most multi-start points a fit draws ([`FitOptions::starts`], and the refined
/// [`FitOptions::refine`]): each is a parameter set held until they are ranked, and 10⁵ take
/// hours on the default subset.
pub const MAX_STARTS: usize = 100_000;

/// The most iterations of a run ([`FitOptions::max_iterations`], `refine_iterations`,
/// `polish_iterations`).
pub const MAX_ITERATIONS: usize = 100_000;

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            residual: Residual::Log,
            seed: 1,
            starts: 32,
            refine: 2,
            refine_iterations: 4,
            max_iterations: 25,
            subset: 64,
            final_subset: 768,
            polish_iterations: 1,
            saturation: None,
        }
    }
}

/// The measurements a fit uses, with what was left out.
#[derive(Clone, Debug)]
pub struct Observations {
    /// The measurements kept.
    pub obs: Vec<Observation>,
    /// 1 or 3.
    pub channels: usize,
    /// The floor `ε` of each channel (see the module docs).
    pub eps: [f64; 3],
    /// Measurements dropped: negative or not finite values, zero weights, saturated values.
    pub dropped: usize,
}

impl Observations {
    /// The measurements of `dataset` the fit can use.
    ///
    /// # Errors
    /// [`FitError::Data`] for a dataset with no usable measurement or with both mono and colour
    /// values.
    pub fn new(dataset: &Dataset, saturation: Option<f64>) -> Result<Self, FitError> {
        let err = |message: String| FitError::Data {
            name: dataset.name.clone(),
            message,
        };
        let rgb = dataset
            .samples
            .iter()
            .filter(|s| matches!(s.value, Value::Rgb(_)))
            .count();
        if rgb != 0 && rgb != dataset.samples.len() {
            return Err(err(format!(
                "{rgb} of {} measurements are colour and the rest mono: one kind per dataset",
                dataset.samples.len()
            )));
        }
        let channels = if rgb > 0 { 3 } else { 1 };
        let mut obs = Vec::with_capacity(dataset.samples.len());
        let mut dropped = 0;
        for s in &dataset.samples {
            let value = match s.value {
                Value::Mono(x) => [x, 0.0, 0.0],
                Value::Rgb(v) => v,
            };
            let ok = value[..channels]
                .iter()
                .all(|&x| x.is_finite() && x >= 0.0 && saturation.is_none_or(|cap| x < cap))
                && s.weight.is_finite()
                && s.weight > 0.0
                && s.theta_i < std::f64::consts::FRAC_PI_2
                && s.theta_r < std::f64::consts::FRAC_PI_2;
            if !ok {
                dropped += 1;
                continue;
            }
            obs.push(Observation {
                s: woven::Vec3::from_spherical(s.theta_i, s.phi_i),
                v: woven::Vec3::from_spherical(s.theta_r, s.phi_r),
                value,
                weight: s.weight,
            });
        }
        if obs.is_empty() {
            return Err(err(format!(
                "no usable measurement ({} dropped: negative, not finite, saturated or of zero weight)",
                dropped
            )));
        }
        if obs
            .iter()
            .all(|o| o.value[..channels].iter().all(|&x| x == 0.0))
        {
            return Err(err(format!(
                "all {} usable measurements are 0: nothing to fit (a model scaled to 0 fits any \
                 such data exactly)",
                obs.len()
            )));
        }
        let mut eps = [1e-12; 3];
        for (c, e) in eps.iter_mut().enumerate().take(channels) {
            let mut v: Vec<f64> = obs
                .iter()
                .map(|o| o.value[c])
                .filter(|&x| x > 0.0)
                .collect();
            if !v.is_empty() {
                v.sort_by(f64::total_cmp);
                *e = 1e-3 * v[v.len() / 2];
            }
        }
        Ok(Observations {
            obs,
            channels,
            eps,
            dropped,
        })
    }

    /// An even subset of at most `n` measurements (all of them when there are no more).
    pub fn subset(&self, n: usize) -> Observations {
        if self.obs.len() <= n {
            return self.clone();
        }
        let step = self.obs.len() as f64 / n as f64;
        let obs = (0..n)
            .map(|k| self.obs[((k as f64 + 0.5) * step) as usize])
            .collect();
        Observations {
            obs,
            ..self.clone()
        }
    }

    /// Number of residuals.
    pub fn len(&self) -> usize {
        self.obs.len() * self.channels
    }

    /// Whether there is nothing to fit.
    pub fn is_empty(&self) -> bool {
        self.obs.is_empty()
    }

    /// The residuals of predictions from `parts` under the linear parameters `lin`.
    pub fn residuals(&self, kind: Residual, parts: &[Parts], lin: &Linear) -> Vec<f64> {
        let mut r = Vec::with_capacity(self.len());
        for (o, p) in self.obs.iter().zip(parts) {
            for c in 0..self.channels {
                r.push(residual(
                    kind,
                    o.value[c],
                    lin.predict(p, c),
                    self.eps[c],
                    o.weight.sqrt(),
                ));
            }
        }
        r
    }
}

/// One residual (module docs).
#[inline]
pub fn residual(kind: Residual, measured: f64, predicted: f64, eps: f64, sqrt_w: f64) -> f64 {
    match kind {
        Residual::Log => sqrt_w * ((predicted.max(0.0) + eps).ln() - (measured + eps).ln()),
        Residual::Relative => sqrt_w * (predicted - measured) / (measured + eps),
    }
}

/// `∂residual/∂prediction`.
#[inline]
fn dresidual(kind: Residual, measured: f64, predicted: f64, eps: f64, sqrt_w: f64) -> f64 {
    match kind {
        Residual::Log => sqrt_w / (predicted.max(0.0) + eps),
        Residual::Relative => sqrt_w / (measured + eps),
    }
}

/// The forward-difference step in the unconstrained variables (the model's quadrature is
/// accurate to ~1e-6 relative, so the difference quotient keeps ~3 digits).
const FD_STEP: f64 = 1e-3;

/// The roughness levels the multi-start draws from (evenly in log over the start range).
const ROUGHNESS_LEVELS: f64 = 6.0;

/// A sum of squares that is not a number counts as infinitely bad.
fn cost_of(r: &[f64]) -> f64 {
    let c = 0.5 * r.iter().map(|x| x * x).sum::<f64>();
    if c.is_finite() {
        c
    } else {
        f64::INFINITY
    }
}

/// The least-squares problem in the free parameters' unconstrained variables.
struct Problem<'a> {
    set: ParamSet,
    free: Vec<usize>,
    data: &'a Observations,
    kind: Residual,
    u: DVector<f64>,
    parts: Vec<Parts>,
    res: Option<DVector<f64>>,
    jacobians: Cell<usize>,
    max_jacobians: usize,
    /// The lowest cost seen and its variables.
    best: RefCell<(f64, Vec<f64>)>,
    evaluations: Cell<usize>,
    progress: &'a (dyn Fn() + Sync),
    cache: &'a FiberCache,
    stop: &'a Stop<'a>,
}

impl<'a> Problem<'a> {
    fn new(
        set: ParamSet,
        data: &'a Observations,
        kind: Residual,
        max_jacobians: usize,
        progress: &'a (dyn Fn() + Sync),
        cache: &'a FiberCache,
        stop: &'a Stop<'a>,
    ) -> Self {
        let free = set.free_indices();
        let u = DVector::from_vec(set.free_u());
        let mut p = Problem {
            set,
            free,
            data,
            kind,
            u: u.clone(),
            parts: Vec::new(),
            res: None,
            jacobians: Cell::new(0),
            max_jacobians,
            best: RefCell::new((f64::INFINITY, u.as_slice().to_vec())),
            evaluations: Cell::new(0),
            progress,
            cache,
            stop,
        };
        p.set_params(&u);
        p
    }

    /// Parts at every observation for the set moved to `u`, or `None` if it does not build.
    fn parts_at(&self, u: &[f64]) -> Option<(ParamSet, Vec<Parts>)> {
        let mut set = self.set.clone();
        set.set_free_u(u);
        let prepared = Prepared::with_cache(&set, Some(self.cache)).ok()?;
        self.evaluations
            .set(self.evaluations.get() + self.data.obs.len());
        Some((set.clone(), prepared.parts_all(&self.data.obs)))
    }

    /// The Jacobian at the current point (see the module docs).
    fn jacobian_here(&self) -> DMatrix<f64> {
        let data = self.data;
        let (m, n) = (data.len(), self.free.len());
        let mut jac = DMatrix::zeros(m, n);
        let lin = Linear::of(&self.set);
        let res = self.res.as_ref().expect("residuals at the current point");
        // Analytic columns: the BRDF is affine in these given the parts.
        let hbar = self.set.get(Quantity::Interreflection, 0).unwrap_or(0.0);
        let mut fd_cols = Vec::new();
        for (j, &i) in self.free.iter().enumerate() {
            let p = &self.set.params[i];
            if !p.quantity.is_linear() {
                fd_cols.push(j);
                continue;
            }
            let dx = p.dx_du(self.u[j]);
            for (k, (o, parts)) in data.obs.iter().zip(&self.parts).enumerate() {
                for c in 0..data.channels {
                    let pred = lin.predict(parts, c);
                    let dpred = lin.derivative(p.quantity, p.channel, parts, c, hbar);
                    let d = dresidual(self.kind, o.value[c], pred, data.eps[c], o.weight.sqrt());
                    jac[(k * data.channels + c, j)] = d * dpred * dx;
                }
            }
        }
        // Forward differences for the rest, every column at once.
        let (u0, set0, cache, stop) = (self.u.as_slice(), &self.set, self.cache, self.stop);
        let stepped: Vec<Option<Vec<Parts>>> = fd_cols
            .par_iter()
            .map(|&j| {
                if stop.now() {
                    return None; // the fit ends with FitError::Cancelled: the column is unused
                }
                let mut u = u0.to_vec();
                u[j] += FD_STEP;
                let mut set = set0.clone();
                set.set_free_u(&u);
                let prepared = Prepared::with_cache(&set, Some(cache)).ok()?;
                Some(prepared.parts_all(&data.obs))
            })
            .collect();
        self.evaluations
            .set(self.evaluations.get() + fd_cols.len() * data.obs.len());
        for (&j, parts) in fd_cols.iter().zip(stepped) {
            let Some(parts) = parts else {
                continue; // a step the library refuses: a zero column (that direction is frozen)
            };
            let r = data.residuals(self.kind, &parts, &lin);
            for (row, rv) in r.iter().enumerate() {
                let d = (rv - res[row]) / FD_STEP;
                jac[(row, j)] = if d.is_finite() { d } else { 0.0 };
            }
        }
        jac
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, u: &DVector<f64>) {
        self.u = u.clone();
        if self.stop.now() {
            // No residuals end the run; the fit then ends with FitError::Cancelled.
            self.set.set_free_u(u.as_slice());
            self.res = None;
            return;
        }
        match self.parts_at(u.as_slice()) {
            Some((set, parts)) => {
                let r = self.data.residuals(self.kind, &parts, &Linear::of(&set));
                self.set = set;
                self.parts = parts;
                let cost = cost_of(&r);
                self.res = Some(DVector::from_vec(r));
                let mut best = self.best.borrow_mut();
                if cost < best.0 {
                    *best = (cost, u.as_slice().to_vec());
                }
            }
            None => {
                self.set.set_free_u(u.as_slice());
                self.res = None;
            }
        }
    }

    fn params(&self) -> DVector<f64> {
        self.u.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        // A point the library refuses, or predictions that are not numbers, stop the step.
        self.res.clone().filter(|r| r.iter().all(|x| x.is_finite()))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        if self.jacobians.get() >= self.max_jacobians || self.stop.now() {
            // The iteration budget is spent (or the fit cancelled): keep the best point.
            return None;
        }
        self.jacobians.set(self.jacobians.get() + 1);
        (self.progress)();
        self.res.as_ref()?;
        Some(self.jacobian_here())
    }
}

/// Runs Levenberg–Marquardt from `set` on `data` for at most `max_jacobians` iterations; returns
/// the best point found, its cost, the model evaluations (at single points) spent and how the
/// run ended.
fn levenberg_marquardt(
    set: ParamSet,
    data: &Observations,
    kind: Residual,
    max_jacobians: usize,
    progress: &(dyn Fn() + Sync),
    cache: &FiberCache,
    stop: &Stop,
) -> (ParamSet, f64, usize, String) {
    let problem = Problem::new(set, data, kind, max_jacobians, progress, cache, stop);
    let (problem, report) = LevenbergMarquardt::new()
        .with_ftol(1e-4)
        .with_xtol(1e-4)
        .with_patience(100)
        .minimize(problem);
    let (cost, u) = problem.best.borrow().clone();
    let mut set = problem.set.clone();
    set.set_free_u(&u);
    let termination = match report.termination {
        levenberg_marquardt::TerminationReason::User("jacobian") => {
            "iteration limit reached".to_string()
        }
        t if t.was_successful() => "converged".to_string(),
        t => format!("stopped: {t:?}"),
    };
    (set, cost, problem.evaluations.get(), termination)
}

/// Where a singular value of the column-scaled Jacobian counts as zero, relative to the largest:
/// far above rounding (~1e-15, the size an exact degeneracy leaves), far below the finite
/// differences' noise (~1e-3 relative), so that only an exact degeneracy counts.
pub const RANK_TOLERANCE: f64 = 1e-8;

/// The direction pairs of the reference geometry the data's rank is compared with: light and
/// viewer uniform in solid angle up to [`REFERENCE_THETA_MAX_DEG`], from a fixed seed.
pub const REFERENCE_PAIRS: usize = 64;

/// The largest polar angle of the reference geometry, degrees.
pub const REFERENCE_THETA_MAX_DEG: f64 = 80.0;

/// The rank of `jac` with its columns scaled to unit length (a zero column stays zero), and how
/// much each column takes part in its null directions (the sum of its squared components over
/// them: 0 for a column the data determines, 1 for one it says nothing of).
fn rank_of(jac: &DMatrix<f64>) -> (usize, Vec<f64>) {
    let (m, n) = jac.shape();
    // At least n rows, so that the SVD gives n singular values and a full V: the missing rows of
    // a short matrix are zeros.
    let mut a = DMatrix::zeros(m.max(n), n);
    a.rows_mut(0, m).copy_from(jac);
    for mut col in a.column_iter_mut() {
        let norm = col.norm();
        if norm > 0.0 && norm.is_finite() {
            col /= norm;
        } else {
            col.fill(0.0);
        }
    }
    let svd = a.svd(false, true);
    let vt = svd.v_t.expect("v requested");
    let smax = svd.singular_values.max();
    let mut null_weight = vec![0.0; n];
    let mut rank = 0;
    for (i, &s) in svd.singular_values.iter().enumerate() {
        if smax > 0.0 && s > RANK_TOLERANCE * smax {
            rank += 1;
        } else {
            for (j, w) in null_weight.iter_mut().enumerate() {
                *w += vt[(i, j)] * vt[(i, j)];
            }
        }
    }
    (rank, null_weight)
}

/// Observations at the reference geometry ([`REFERENCE_PAIRS`]) with `data`'s channels and
/// floors; their values (the data's first) only scale the Jacobian's rows, which leaves its rank.
fn reference_geometry(data: &Observations) -> Observations {
    let mut rng = woven::math::rng::SplitMix(0x5eed);
    let theta_max = REFERENCE_THETA_MAX_DEG.to_radians();
    let obs = (0..REFERENCE_PAIRS)
        .map(|_| Observation {
            s: rng.direction(theta_max),
            v: rng.direction(theta_max),
            value: data.obs[0].value,
            weight: 1.0,
        })
        .collect();
    Observations {
        obs,
        dropped: 0,
        ..data.clone()
    }
}

/// Refuses a fit the data cannot decide (module docs): fewer measured values than free
/// parameters, or a Jacobian at `set`'s initial values of lower rank on the data (its screening
/// subset, confirmed on the final run's measurements) than on the reference geometry. A rank
/// the reference geometry shares is the model's own degeneracy at this point (a combination
/// only the parameters' bounds decide), which the report's warnings describe; predictions that
/// are not numbers at the initial values are left to the fit.
fn check_determined(
    dataset: &Dataset,
    set: &ParamSet,
    data: &Observations,
    options: &FitOptions,
    cache: &FiberCache,
    stop: &Stop,
) -> Result<(), FitError> {
    let free = set.free_indices();
    if free.is_empty() {
        return Ok(());
    }
    let rank_on = |obs: &Observations| -> Option<(usize, Vec<f64>)> {
        let noop = || {};
        let problem = Problem::new(set.clone(), obs, options.residual, 1, &noop, cache, stop);
        if !problem.res.as_ref()?.iter().all(|r| r.is_finite()) {
            return None;
        }
        Some(rank_of(&problem.jacobian_here()))
    };
    let screen = data.subset(options.subset.max(free.len()));
    let Some(mut found) = rank_on(&screen) else {
        return Ok(());
    };
    if found.0 == free.len() {
        return Ok(());
    }
    let Some(reference) = rank_on(&reference_geometry(data)) else {
        return Ok(());
    };
    let work = data.subset(options.final_subset.max(1));
    if found.0 < reference.0 && work.obs.len() > screen.obs.len() {
        match rank_on(&work) {
            Some(f) => found = f,
            None => return Ok(()),
        }
    }
    let (rank, null_weight) = found;
    let short = data.len() < free.len();
    if rank >= reference.0 && !short {
        return Ok(());
    }
    // The parameters the data leaves undetermined beyond what the model itself does.
    let mut involved: Vec<usize> = (0..free.len())
        .filter(|&j| null_weight[j] - reference.1[j] > 0.1)
        .collect();
    involved.sort_by(|&a, &b| {
        let excess = |j: usize| null_weight[j] - reference.1[j];
        excess(b).total_cmp(&excess(a))
    });
    let undetermined: Vec<String> = involved
        .iter()
        .map(|&j| set.params[free[j]].name.clone())
        .collect();
    let detail = if short {
        format!(
            "fewer values than free parameters, so some combinations of {} change no prediction",
            undetermined.join(", ")
        )
    } else {
        format!(
            "the measurements' geometry leaves {} combination(s) of {} that change no \
             prediction, which other geometries decide (rank {} there)",
            reference.0 - rank,
            undetermined.join(", "),
            reference.0
        )
    };
    Err(FitError::Underdetermined {
        name: dataset.name.clone(),
        measurements: data.obs.len(),
        channels: data.channels,
        values: data.len(),
        free: free.len(),
        rank,
        reference_rank: reference.0,
        undetermined,
        detail,
    })
}

/// What a fit reports `(done, total)` steps to (screened starts plus iterations), and asks
/// between units of its work whether to stop ([`fit`]).
pub type ProgressFn<'a> = &'a dyn woven::progress::Progress;

/// A progress's cancellation, latched: once it has answered `true` the fit stops at each later
/// check too, and ends with [`FitError::Cancelled`] (never a partial result).
struct Stop<'a> {
    ask: ProgressFn<'a>,
    seen: AtomicBool,
}

impl<'a> Stop<'a> {
    fn new(ask: ProgressFn<'a>) -> Self {
        Stop {
            ask,
            seen: AtomicBool::new(false),
        }
    }

    /// Whether to stop now.
    fn now(&self) -> bool {
        if self.seen.load(Ordering::Relaxed) {
            return true;
        }
        let stop = self.ask.cancelled();
        if stop {
            self.seen.store(true, Ordering::Relaxed);
        }
        stop
    }

    /// [`FitError::Cancelled`] if the fit was asked to stop at this or any earlier check.
    fn check(&self) -> Result<(), FitError> {
        if self.now() {
            Err(FitError::Cancelled)
        } else {
            Ok(())
        }
    }
}

/// Fits the parameter set `set` (its free parameters) to `dataset`.
///
/// The stages: the initial values and `options.starts` quasi-random points of the free
/// parameters' start ranges are scored on a subset of the data; the best `options.refine` are
/// refined by short Levenberg–Marquardt runs on the subset; the best of those by a full run on
/// every measurement (a dataset larger than `options.final_subset` on an even subset of that
/// size, then polished on every measurement). If the full run's result is worse than the
/// Lambert-like limit ([`lambert_like`]) on its measurements, the full run is repeated from the
/// limit and the better result kept. With a free `scale`, each start takes the scale that
/// matches the data's median level. The result carries standard errors and warnings
/// ([`FitResult`]).
///
/// # Errors
/// [`FitError::Data`] for a dataset with nothing to fit or whose channels do not match `set`;
/// [`FitError::Material`] if the initial parameters do not build;
/// [`FitError::Underdetermined`] if the data cannot determine the free parameters (fewer
/// measured values than free parameters, or a Jacobian at the initial values of lower rank on
/// the measurements than on a reference geometry: module docs);
/// [`FitError::Cancelled`] once `progress` has asked to stop.
///
/// # Stopping
/// `progress` is asked whether to stop ([`Progress::cancelled`](woven::progress::Progress))
/// between units of work: before each start is scored, before each evaluation of the model over
/// the measurements (a step of Levenberg–Marquardt, a column of a finite-difference Jacobian)
/// and between the stages. A fit told to stop ends within one such unit (a few evaluations of
/// the model at each measurement of the run). `woven serve` stops the fits whose client has
/// gone with it, Python those a Ctrl-C interrupts.
pub fn fit(
    dataset: &Dataset,
    set: &ParamSet,
    options: &FitOptions,
    progress: ProgressFn<'_>,
) -> Result<FitResult, FitError> {
    let stop = Stop::new(progress);
    options.check()?;
    let data = Observations::new(dataset, options.saturation)?;
    if data.channels != set.channels {
        return Err(FitError::Data {
            name: dataset.name.clone(),
            message: format!(
                "the data has {} channel(s), the parameters were set up for {}",
                data.channels, set.channels
            ),
        });
    }
    let cache = FiberCache::default();
    stop.check()?;
    Prepared::with_cache(set, Some(&cache))?;
    // A cancelled check may have seen zero columns: its verdict only counts if it ran through.
    let determined = check_determined(dataset, set, &data, options, &cache, &stop);
    stop.check()?;
    determined?;
    let subset = data.subset(options.subset.max(1));
    let total = options.starts
        + 1
        + options.refine * options.refine_iterations
        + options.max_iterations
        + options.polish_iterations;
    let done = std::sync::atomic::AtomicUsize::new(0);
    let tick = || {
        let d = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        progress.update(d.min(total), total);
    };

    // Stage 1: score the initial values and the quasi-random starts on the subset.
    let scored = screen(set, &subset, options, &cache, &tick, &stop);
    stop.check()?;
    let mut evaluations = scored.len() * subset.obs.len();

    // Stage 2: refine the best starts on the subset.
    let (start, evals) = refine(scored, &subset, options, &tick, &cache, &stop)?;
    evaluations += evals;

    // Stage 3: the final run (on an even subset of a large dataset, then polished on all of it).
    let work = data.subset(options.final_subset.max(1));
    let (mut fitted, cost, evals, mut termination) = levenberg_marquardt(
        start,
        &work,
        options.residual,
        options.max_iterations,
        &tick,
        &cache,
        &stop,
    );
    stop.check()?;
    evaluations += evals;

    // The guard (module docs): a result worse than the Lambert-like limit is a poor basin; the
    // final run is repeated from the limit, and the better result kept.
    let mut limit = lambert_like(set, &work, options.residual);
    let limit_cost = score(&mut limit, &work, options.residual, &cache);
    evaluations += work.obs.len();
    if limit_cost < cost {
        let (again, again_cost, evals, t) = levenberg_marquardt(
            limit,
            &work,
            options.residual,
            options.max_iterations,
            &tick,
            &cache,
            &stop,
        );
        stop.check()?;
        evaluations += evals;
        if again_cost < cost {
            fitted = again;
            termination = format!(
                "{t} (restarted from the Lambert-like limit: the multi-start's result was worse \
                 than it)"
            );
        }
    }
    if work.obs.len() < data.obs.len() {
        let (polished, _, evals, t) = levenberg_marquardt(
            fitted,
            &data,
            options.residual,
            options.polish_iterations,
            &tick,
            &cache,
            &stop,
        );
        stop.check()?;
        fitted = polished;
        evaluations += evals;
        termination = format!(
            "{termination} on {} points; polish on all: {t}",
            work.obs.len()
        );
    }
    // The microcylinder's energy guard, measured at the result (crate::microcylinder).
    let (guarded, evals, t) = settle_guard(fitted, &work, &data, options, &tick, &cache, &stop);
    stop.check()?;
    fitted = guarded;
    evaluations += evals;
    termination.push_str(&t);
    progress.update(total, total);

    // The Jacobian at the optimum for the standard errors.
    let noop = || {};
    let problem = Problem::new(
        fitted.clone(),
        &data,
        options.residual,
        1,
        &noop,
        &cache,
        &stop,
    );
    // Cancelled before the residuals were evaluated, the problem has none to differentiate.
    stop.check()?;
    let jac = problem.jacobian_here();
    stop.check()?;
    let res = problem
        .res
        .clone()
        .unwrap_or_else(|| DVector::zeros(data.len()));
    evaluations += problem.evaluations.get();
    fitted = problem.set.clone();
    let parts = problem.parts.clone();
    let result = report::assemble(
        dataset,
        fitted,
        &data,
        options.residual,
        &parts,
        &jac,
        &res,
        evaluations,
        termination,
    );
    check_result(dataset, &result)?;
    Ok(result)
}

/// Stage 2 of [`fit`]: the best `options.refine` of the `scored` starts refined by short runs on
/// `subset`; the best result and the model evaluations spent.
fn refine(
    scored: Vec<(f64, ParamSet)>,
    subset: &Observations,
    options: &FitOptions,
    tick: &(dyn Fn() + Sync),
    cache: &FiberCache,
    stop: &Stop,
) -> Result<(ParamSet, usize), FitError> {
    let mut evaluations = 0;
    let mut best: Option<(f64, ParamSet)> = None;
    for (_, start) in scored.into_iter().take(options.refine.max(1)) {
        let (set, cost, evals, _) = levenberg_marquardt(
            start,
            subset,
            options.residual,
            options.refine_iterations,
            tick,
            cache,
            stop,
        );
        stop.check()?;
        evaluations += evals;
        if best.as_ref().is_none_or(|b| cost < b.0) {
            best = Some((cost, set));
        }
    }
    let (_, start) = best.expect("at least one start");
    Ok((start, evaluations))
}

/// [`FitError::Data`] for a fit whose error is not finite or whose model is 0 everywhere.
fn check_result(dataset: &Dataset, result: &FitResult) -> Result<(), FitError> {
    if !(result.relative_rms.is_finite() && result.rms_log.is_finite()) {
        return Err(FitError::Data {
            name: dataset.name.clone(),
            message: format!(
                "the fit's error is not finite (relative RMS {}, log RMS {}): values too large \
                 for the model to reach in floating point, or parameters held where the model \
                 overflows",
                result.relative_rms, result.rms_log
            ),
        });
    }
    if result.predicted.iter().all(|p| p.iter().all(|&x| x == 0.0)) {
        return Err(FitError::Data {
            name: dataset.name.clone(),
            message: "the fitted model is 0 at every measurement (a parameter held at a value \
                      that blanks it?)"
                .into(),
        });
    }
    Ok(())
}

/// Stage 1 of [`fit`]: the initial values and `options.starts` quasi-random points of the free
/// parameters' start ranges, scored on `subset` (over every core) and sorted, the best first.
/// Once `stop` says so, the remaining starts are left unscored (at an infinite cost).
fn screen(
    set: &ParamSet,
    subset: &Observations,
    options: &FitOptions,
    cache: &FiberCache,
    tick: &(dyn Fn() + Sync),
    stop: &Stop,
) -> Vec<(f64, ParamSet)> {
    let free = set.free_indices();
    let mut candidates = vec![set.clone()];
    for i in 0..options.starts {
        let mut c = set.clone();
        for (d, &pi) in free.iter().enumerate() {
            let p = &mut c.params[pi];
            if p.quantity == Quantity::Scale {
                continue; // matched to the data when scored
            }
            let mut t = sobol_burley::sample(i as u32, d as u32, options.seed) as f64;
            if p.quantity == Quantity::Roughness {
                // A few roughness levels only: each needs its own β table (~0.2 s to build).
                t = ((t * ROUGHNESS_LEVELS).floor() + 0.5) / ROUGHNESS_LEVELS;
            }
            p.value = p.start_at(t);
        }
        candidates.push(c);
    }
    let mut scored: Vec<(f64, ParamSet)> = candidates
        .into_par_iter()
        .map(|mut c| {
            if stop.now() {
                return (f64::INFINITY, c);
            }
            let cost = score(&mut c, subset, options.residual, cache);
            tick();
            (cost, c)
        })
        .collect();
    // A stable sort: equal costs keep the candidates' order, so the result is deterministic.
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    scored
}

/// Runs of the microcylinder's energy guard ([`crate::microcylinder`]) before the final run is
/// repeated with a guard measured anew at its result.
pub const GUARD_ROUNDS: usize = 2;

/// The microcylinder's energy guard, held through the runs (none at the start), measured at the
/// result `set` at the incidences of `all`; while it changed, the final run on `work` is repeated
/// with it and the guard measured at that run's result (at most [`GUARD_ROUNDS`] times). Of the
/// results, each holding its own guard, the one of least cost on `work` is kept. Returns it, the
/// model evaluations spent and what happened (empty when nothing did); other models pass through.
fn settle_guard(
    mut set: ParamSet,
    work: &Observations,
    all: &Observations,
    options: &FitOptions,
    tick: &(dyn Fn() + Sync),
    cache: &FiberCache,
    stop: &Stop,
) -> (ParamSet, usize, String) {
    let (mut evaluations, mut note) = (0, String::new());
    let mut best: Option<(f64, ParamSet, usize)> = None;
    let mut results = 0;
    for round in 0..=GUARD_ROUNDS {
        let (changed, evals) = crate::microcylinder::update_guard(&mut set, all);
        evaluations += evals;
        if round == 0 && !changed {
            return (set, evaluations, note);
        }
        let cost = Prepared::with_cache(&set, Some(cache)).map_or(f64::INFINITY, |p| {
            cost_of(&work.residuals(options.residual, &p.parts_all(&work.obs), &Linear::of(&set)))
        });
        evaluations += work.obs.len();
        results += 1;
        if best.as_ref().is_none_or(|b| cost < b.0) {
            best = Some((cost, set.clone(), round));
        }
        if !changed || round == GUARD_ROUNDS || stop.now() {
            break;
        }
        let (again, _, evals, t) = levenberg_marquardt(
            set,
            work,
            options.residual,
            options.max_iterations,
            tick,
            cache,
            stop,
        );
        evaluations += evals;
        set = again;
        let _ = write!(note, "; again with the energy guard of its result: {t}");
    }
    let (_, set, round) = best.expect("one round at least");
    let _ = write!(
        note,
        "; kept result {} of {}, each scored with its own energy guard",
        round + 1,
        results
    );
    (set, evaluations, note)
}

/// The cost of `set` on `data` (infinite if it does not build), a free `scale` first matched to
/// the data's level ([`match_scale`]).
fn score(set: &mut ParamSet, data: &Observations, kind: Residual, cache: &FiberCache) -> f64 {
    let Ok(prepared) = Prepared::with_cache(set, Some(cache)) else {
        return f64::INFINITY;
    };
    let parts = prepared.parts_all(&data.obs);
    if set
        .params
        .iter()
        .any(|p| p.free && p.quantity == Quantity::Scale)
    {
        match_scale(set, data, &parts);
    }
    cost_of(&data.residuals(kind, &parts, &Linear::of(set)))
}

/// The `ħ` of the Lambert-like limit: high enough that the yarn's body (specular and diffuse)
/// weighs 1 %, low enough that the optimizer can still move it (the logistic transform is flat
/// at the bound 0.999).
pub const LAMBERT_LIKE_INTERREFLECTION: f64 = 0.99;

/// The Lambert-like limit of `set` for `data`: every free albedo (`diffuse`,
/// `interreflection_albedo`, per channel) at the Lambert fit's albedo of its channel (the
/// optimum of the residual `kind` for `f = ρ/π`, in closed form), a free `ħ` at
/// [`LAMBERT_LIKE_INTERREFLECTION`] (the cloth's BRDF tends to `ρ/π` as `ħ → 1`), a free
/// roughness (the fiber's, the microfacet's `α`, the sheen's) at the top of its start range (a
/// broad lobe), a free specular weight or sheen colour at the bottom of its; the other parameters
/// keep their values. Its error is the Lambert fit's for `lambert`, and close to it for `cloth`
/// (1 % of the yarn's body is left), `microfacet` and `sheen`; the `fiber` model, which has no
/// `ħ`, keeps its specular lobe. The microcylinder's limit is a start, not a limit: its threads'
/// albedos at that albedo, their lobes at their broadest start and `k_d` at the top of its start
/// range (its surface lobes stay). A free `scale` is matched to the data when the limit is
/// scored.
pub fn lambert_like(set: &ParamSet, data: &Observations, kind: Residual) -> ParamSet {
    let mut albedo = [0.0; 3];
    for (c, a) in albedo.iter_mut().enumerate().take(data.channels) {
        let eps = data.eps[c];
        let (mut num, mut den) = (0.0, 0.0);
        for o in &data.obs {
            let m = o.value[c];
            match kind {
                // Σ w (ln(ρ/π + ε) − ln(m + ε))² is least at the weighted mean of ln(m + ε).
                Residual::Log => {
                    num += o.weight * (m + eps).ln();
                    den += o.weight;
                }
                // Σ w ((ρ/π − m)/(m + ε))² is least at Σ w m/(m + ε)² / Σ w/(m + ε)².
                Residual::Relative => {
                    let k = o.weight / ((m + eps) * (m + eps));
                    num += k * m;
                    den += k;
                }
            }
        }
        let level = match kind {
            Residual::Log => (num / den).exp() - eps,
            Residual::Relative => num / den,
        };
        *a = std::f64::consts::PI * level;
    }
    let mut out = set.clone();
    for p in out.params.iter_mut().filter(|p| p.free) {
        match p.quantity {
            Quantity::Diffuse | Quantity::InterreflectionAlbedo | Quantity::VolumeAlbedo(_) => {
                // Inside the bounds, where the transform can move it.
                let (lo, hi) = if p.hi.is_finite() {
                    let margin = 1e-3 * (p.hi - p.lo);
                    (p.lo + margin, p.hi - margin)
                } else {
                    (p.lo.max(1e-9), f64::MAX)
                };
                let a = albedo[p.channel];
                p.value = if a.is_finite() { a.clamp(lo, hi) } else { lo };
            }
            Quantity::Interreflection => {
                p.value = LAMBERT_LIKE_INTERREFLECTION.clamp(p.lo, p.hi);
            }
            Quantity::Roughness
            | Quantity::Alpha
            | Quantity::SheenRoughness
            | Quantity::SurfaceWidth
            | Quantity::VolumeWidth
            | Quantity::VolumeShare => p.value = p.start.1,
            Quantity::Specular | Quantity::SheenColor => p.value = p.start.0,
            _ => {}
        }
    }
    out
}

/// Sets a free `scale` so the predictions match the data's median level (the median of
/// `ln m − ln p` over the measurements).
fn match_scale(set: &mut ParamSet, data: &Observations, parts: &[Parts]) {
    let Some(i) = set
        .params
        .iter()
        .position(|p| p.quantity == Quantity::Scale)
    else {
        return;
    };
    set.params[i].value = 1.0;
    let lin = Linear::of(set);
    let mut logs: Vec<f64> = Vec::new();
    for (o, p) in data.obs.iter().zip(parts) {
        for c in 0..data.channels {
            let (m, q) = (o.value[c], lin.predict(p, c));
            if m > 0.0 && q > 0.0 {
                logs.push(m.ln() - q.ln());
            }
        }
    }
    if logs.is_empty() {
        return;
    }
    logs.sort_by(f64::total_cmp);
    let p = &mut set.params[i];
    p.value = logs[logs.len() / 2].exp().clamp(1e-12, 1e12);
}
