//! What a fit found and how sure it is: values with standard errors, warnings for what the data
//! cannot determine, residual statistics, a Markdown report and the data behind its plots.

use crate::data::Dataset;
use crate::evaluate::{Linear, Observation, Parts, Prepared};
use crate::fit::{residual, Observations, Residual};
use crate::params::{ModelKind, ParamSet, Quantity};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;
use std::fmt::Write as _;

/// A relative standard error above this marks a parameter the data does not determine.
pub const MAX_RELATIVE_ERROR: f64 = 0.5;
/// A correlation above this (in magnitude) marks two parameters the data does not tell apart.
pub const MAX_CORRELATION: f64 = 0.95;

/// One fitted parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// The parameter's name.
    pub name: String,
    /// The fitted value, natural units.
    pub value: f64,
    /// Its standard error (infinite when the data does not determine it; `NaN` at a bound).
    pub std_error: f64,
    /// Whether it ended on a bound of its range.
    pub at_bound: bool,
}

/// The result of a fit.
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The dataset's name.
    pub dataset: String,
    /// The model.
    pub model: ModelKind,
    /// Every parameter at its fitted value.
    pub params: ParamSet,
    /// The free parameters with their standard errors.
    pub estimates: Vec<Estimate>,
    /// Correlations above [`MAX_CORRELATION`] between free parameters: `(a, b, ρ)`.
    pub correlations: Vec<(String, String, f64)>,
    /// One line per parameter the data cannot determine, and other caveats.
    pub warnings: Vec<String>,
    /// The residual the fit minimized.
    pub residual: Residual,
    /// Root mean square of `ln(p + ε) − ln(m + ε)` over every measurement and channel.
    pub rms_log: f64,
    /// `√(Σ (p − m)² / Σ m²)`: the RMS error relative to the RMS value.
    pub relative_rms: f64,
    /// The measurements used (for plots), and the fit's value at each, per channel.
    pub observations: Vec<Observation>,
    /// The fitted BRDF at each observation, per channel.
    pub predicted: Vec<[f64; 3]>,
    /// Colour channels.
    pub channels: usize,
    /// Measurements dropped (negative, not finite, saturated, zero weight).
    pub dropped: usize,
    /// Evaluations of the model at single pairs of directions the fit took.
    pub evaluations: usize,
    /// How the final Levenberg–Marquardt run ended.
    pub termination: String,
}

/// Builds the result from the optimum's Jacobian `jac` (in the free parameters' unconstrained
/// variables) and residuals `res`: standard errors from `s² (JᵀJ)⁻¹` in natural units, with
/// `s² = Σ r² / (m − n)`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn assemble(
    dataset: &Dataset,
    mut params: ParamSet,
    data: &Observations,
    kind: Residual,
    parts: &[Parts],
    jac: &DMatrix<f64>,
    res: &DVector<f64>,
    evaluations: usize,
    termination: String,
) -> FitResult {
    let free = params.free_indices();
    let (m, n) = (jac.nrows(), jac.ncols());
    // Parameters on a bound are held there for the error analysis (their derivative in u
    // vanishes; the error bars of the others are conditional on them).
    let inner: Vec<usize> = (0..n)
        .filter(|&j| !params.params[free[j]].at_bound())
        .collect();
    let mut jn = DMatrix::zeros(m, inner.len());
    let mut norms = vec![0.0; inner.len()];
    for (col, &j) in inner.iter().enumerate() {
        let p = &params.params[free[j]];
        let dx = p.dx_du(p.to_u(p.value));
        let mut norm = 0.0;
        for r in 0..m {
            let x = jac[(r, j)] / dx;
            jn[(r, col)] = x;
            norm += x * x;
        }
        norms[col] = norm.sqrt();
    }
    // Column-scaled pseudo-inverse: directions the data does not constrain get infinite variance.
    let k = inner.len();
    let mut cov = DMatrix::from_element(k, k, 0.0);
    if k > 0 {
        let mut a = jn.clone();
        for (col, &nrm) in norms.iter().enumerate() {
            let s = if nrm > 0.0 { 1.0 / nrm } else { 0.0 };
            a.column_mut(col).scale_mut(s);
        }
        let svd = a.svd(false, true);
        let vt = svd.v_t.expect("v requested");
        let smax = svd.singular_values.max();
        for i in 0..svd.singular_values.len() {
            let s = svd.singular_values[i];
            let w = if s > 1e-9 * smax { 1.0 / (s * s) } else { 1e30 };
            for p in 0..k {
                for q in 0..k {
                    cov[(p, q)] += w * vt[(i, p)] * vt[(i, q)];
                }
            }
        }
        for p in 0..k {
            for q in 0..k {
                let d = norms[p] * norms[q];
                cov[(p, q)] = if d > 0.0 {
                    cov[(p, q)] / d
                } else {
                    f64::INFINITY
                };
            }
        }
    }
    let dof = m.saturating_sub(n).max(1) as f64;
    let s2 = res.norm_squared() / dof;
    let mut estimates = Vec::new();
    let mut warnings = Vec::new();
    let mut se_of = vec![f64::NAN; n];
    for (col, &j) in inner.iter().enumerate() {
        se_of[j] = (s2 * cov[(col, col)]).sqrt().min(f64::INFINITY);
    }
    for j in 0..n {
        let p = &params.params[free[j]];
        let se = se_of[j];
        let at_bound = p.at_bound();
        if at_bound {
            warnings.push(format!(
                "`{}` ended on a bound of its range [{}, {}] ({}): held there for the error \
                 analysis, so it has no standard error",
                p.name,
                fmt(p.lo),
                fmt(p.hi),
                fmt(p.value)
            ));
        } else {
            // Relative to the value, or to the width of its start range near zero.
            let reference = p.value.abs().max(0.1 * (p.start.1 - p.start.0).abs());
            if se.is_nan() || se > MAX_RELATIVE_ERROR * reference {
                warnings.push(format!(
                    "`{}` = {} ± {}: the data cannot determine it",
                    p.name,
                    fmt(p.value),
                    fmt(se)
                ));
            }
        }
        estimates.push(Estimate {
            name: p.name.clone(),
            value: p.value,
            std_error: se,
            at_bound,
        });
    }
    let mut correlations = Vec::new();
    for a in 0..k {
        for b in a + 1..k {
            let rho = cov[(a, b)] / (cov[(a, a)] * cov[(b, b)]).sqrt();
            if rho.is_finite() && rho.abs() > MAX_CORRELATION {
                let (pa, pb) = (
                    &params.params[free[inner[a]]],
                    &params.params[free[inner[b]]],
                );
                warnings.push(format!(
                    "`{}` and `{}` are correlated (ρ = {:.3}): the data fixes a combination of \
                     them, not each",
                    pa.name, pb.name, rho
                ));
                correlations.push((pa.name.clone(), pb.name.clone(), rho));
            }
        }
    }
    // The canonical rotation (after the error analysis: quarter turns change no error bar).
    params.canonicalize();
    for e in &mut estimates {
        if let Some(p) = params.params.iter().find(|p| p.name == e.name) {
            e.value = p.value;
        }
    }
    let lin = Linear::of(&params);
    let predicted: Vec<[f64; 3]> = parts
        .iter()
        .map(|p| [lin.predict(p, 0), lin.predict(p, 1), lin.predict(p, 2)])
        .collect();
    let (rms_log, relative_rms) = statistics(data, &predicted);
    if data.dropped > 0 {
        warnings.push(format!(
            "{} measurements dropped (negative, not finite, saturated or of zero weight)",
            data.dropped
        ));
    }
    if dataset.dropped_below_horizon > 0 {
        warnings.push(format!(
            "{} rows with a direction at or below the horizon (θ ≥ π/2) were dropped when the \
             data was read: the fit uses reflection only (a transmitted direction, θr in \
             (π/2, π], is not fitted)",
            dataset.dropped_below_horizon
        ));
    }
    FitResult {
        dataset: dataset.name.clone(),
        model: params.model,
        params,
        estimates,
        correlations,
        warnings,
        residual: kind,
        rms_log,
        relative_rms,
        observations: data.obs.clone(),
        predicted,
        channels: data.channels,
        dropped: data.dropped,
        evaluations,
        termination,
    }
}

/// `(RMS log error, relative RMS)` of predictions against the data (see [`FitResult`]).
pub fn statistics(data: &Observations, predicted: &[[f64; 3]]) -> (f64, f64) {
    let (mut sum_log, mut count, mut sum_err, mut sum_val) = (0.0, 0usize, 0.0, 0.0);
    for (o, p) in data.obs.iter().zip(predicted) {
        for c in 0..data.channels {
            let r = residual(Residual::Log, o.value[c], p[c], data.eps[c], 1.0);
            sum_log += r * r;
            count += 1;
            sum_err += (p[c] - o.value[c]).powi(2);
            sum_val += o.value[c].powi(2);
        }
    }
    (
        (sum_log / count.max(1) as f64).sqrt(),
        (sum_err / sum_val.max(1e-300)).sqrt(),
    )
}

/// A number for a report: 4 significant digits.
pub fn fmt(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "—".into()
        } else {
            "∞".into()
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-3..1e5).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    }
}

impl FitResult {
    /// The fitted material (for `cloth` and `fiber`; see [`ParamSet::material`]).
    pub fn material(&self) -> Option<woven::material::Material> {
        self.params.material()
    }

    /// The fitted material as a TOML material file, with a header recording the fit (and the
    /// rotation, scale and per-channel albedos, which a material file has no key for); for
    /// `microcylinder`, the fitted fabric as a microcylinder file (`model = "microcylinder"`).
    /// `None` for the baselines.
    pub fn material_toml(&self) -> Option<String> {
        if self.model == ModelKind::Microcylinder {
            return crate::microcylinder::fabric_toml_of(self);
        }
        let mut m = self.material()?;
        if m.name.is_none()
            || m.name
                .as_deref()
                .is_some_and(|n| woven::material::Material::preset_toml(n).is_some())
        {
            m.name = Some(format!("fit-{}", self.dataset));
        }
        let mut head = format!(
            "# Fitted by `woven fit` to `{}` (model {}): RMS log error {:.4}, relative RMS {:.4}.\n",
            self.dataset, self.model, self.rms_log, self.relative_rms
        );
        for q in [Quantity::Rotation, Quantity::Scale] {
            if let Some(p) = self.params.params.iter().find(|p| p.quantity == q) {
                let _ = writeln!(
                    head,
                    "# {} = {} (not part of a material file)",
                    p.name,
                    fmt(p.value)
                );
            }
        }
        if self.channels == 3 {
            for q in [Quantity::Diffuse, Quantity::InterreflectionAlbedo] {
                let v = self.params.channels_of(q);
                if self.params.get(q, 0).is_some() {
                    let _ = writeln!(
                        head,
                        "# {q:?} per channel (r, g, b) = ({}, {}, {}); the file holds their mean",
                        fmt(v[0]),
                        fmt(v[1]),
                        fmt(v[2])
                    );
                }
            }
        }
        Some(format!("{head}\n{}", m.to_toml_string()))
    }

    /// The parameters as a TOML table (the baselines, which have no material file).
    pub fn params_toml(&self) -> String {
        let mut out = format!(
            "# Fitted by `woven fit` to `{}` (model {}): RMS log error {:.4}, relative RMS {:.4}.\nmodel = \"{}\"\n",
            self.dataset, self.model, self.rms_log, self.relative_rms, self.model
        );
        for p in &self.params.params {
            let _ = writeln!(out, "\"{}\" = {}", p.name, p.value);
        }
        out
    }

    /// The report in Markdown: the fitted values with their standard errors, the warnings and
    /// the residual statistics.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "# Fit of `{}` to `{}`\n", self.model, self.dataset);
        let _ = writeln!(
            s,
            "{} measurements × {} channel(s) ({} dropped); {} residuals; {} model evaluations; \
             final run: {}.\n",
            self.observations.len(),
            self.channels,
            self.dropped,
            match self.residual {
                Residual::Log => "log",
                Residual::Relative => "relative",
            },
            self.evaluations,
            self.termination
        );
        let _ = writeln!(s, "| statistic | value |\n|---|---|");
        let _ = writeln!(s, "| RMS log error | {:.4} |", self.rms_log);
        let _ = writeln!(
            s,
            "| relative RMS (RMS error / RMS value) | {:.4} |\n",
            self.relative_rms
        );
        let _ = writeln!(
            s,
            "| parameter | value | standard error | |\n|---|---|---|---|"
        );
        for p in &self.params.params {
            let (se, note) = match self.estimates.iter().find(|e| e.name == p.name) {
                Some(e) if e.at_bound => ("—".to_string(), "free, on a bound"),
                Some(e) => (fmt(e.std_error), "free"),
                None => (String::new(), "fixed"),
            };
            let _ = writeln!(s, "| `{}` | {} | {} | {} |", p.name, fmt(p.value), se, note);
        }
        if let Some(p) = self
            .params
            .params
            .iter()
            .find(|p| p.quantity == Quantity::Rotation)
        {
            let _ = writeln!(
                s,
                "\nThe weave's rotation is {:.1}° (the weft's azimuth in the data's frame).",
                p.value * 180.0 / PI
            );
        }
        if !self.warnings.is_empty() {
            let _ = writeln!(s, "\n## Warnings\n");
            for w in &self.warnings {
                let _ = writeln!(s, "- {w}");
            }
        }
        s
    }

    /// The fitted BRDF per channel at `(θi, φi, θr, φr)` (radians, the data's frame).
    pub fn predict(&self, theta_i: f64, phi_i: f64, theta_r: f64, phi_r: f64) -> [f64; 3] {
        self.predict_many(&[(theta_i, phi_i, theta_r, phi_r)])[0]
    }

    /// [`predict`](Self::predict) for many direction pairs (over all cores).
    pub fn predict_many(&self, dirs: &[(f64, f64, f64, f64)]) -> Vec<[f64; 3]> {
        let Ok(prepared) = Prepared::new(&self.params) else {
            return vec![[0.0; 3]; dirs.len()];
        };
        let lin = Linear::of(&self.params);
        let obs: Vec<Observation> = dirs
            .iter()
            .map(|&(ti, pi, tr, pr)| Observation {
                s: woven::Vec3::from_spherical(ti, pi),
                v: woven::Vec3::from_spherical(tr, pr),
                value: [0.0; 3],
                weight: 1.0,
            })
            .collect();
        prepared
            .parts_all(&obs)
            .iter()
            .map(|p| [lin.predict(p, 0), lin.predict(p, 1), lin.predict(p, 2)])
            .collect()
    }
}

/// Measurements in one plane of incidence at one incidence: a curve to plot.
#[derive(Clone, Debug, PartialEq)]
pub struct InPlaneCurve {
    /// Polar angle of the light, radians.
    pub theta_i: f64,
    /// Azimuth of the plane (the light's), radians.
    pub phi_i: f64,
    /// `(signed θr, index into the observations)`: θr > 0 on the specular side (`φr = φi + π`),
    /// < 0 on the light's side.
    pub points: Vec<(f64, usize)>,
}

/// The in-plane curves of a set of observations: groups of at least `min_points` measurements
/// with the viewer in the light's plane of incidence (within 1°) at one incidence (within 0.5°).
pub fn in_plane_curves(obs: &[Observation], min_points: usize) -> Vec<InPlaneCurve> {
    let tol = 1f64.to_radians();
    let mut curves: Vec<InPlaneCurve> = Vec::new();
    for (k, o) in obs.iter().enumerate() {
        let (ti, pi) = o.s.to_spherical();
        let (tr, pr) = o.v.to_spherical();
        let dphi = (pr - pi).rem_euclid(2.0 * PI);
        let signed = if tr < tol || (dphi - PI).abs() < tol {
            tr
        } else if dphi < tol || 2.0 * PI - dphi < tol {
            -tr
        } else {
            continue;
        };
        let same = |c: &InPlaneCurve| {
            (c.theta_i - ti).abs() < 0.5 * tol
                && (ti < tol || ((c.phi_i - pi + PI).rem_euclid(2.0 * PI) - PI).abs() < tol)
        };
        match curves.iter_mut().find(|c| same(c)) {
            Some(c) => c.points.push((signed, k)),
            None => curves.push(InPlaneCurve {
                theta_i: ti,
                phi_i: pi,
                points: vec![(signed, k)],
            }),
        }
    }
    curves.retain(|c| c.points.len() >= min_points);
    for c in &mut curves {
        c.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    curves
}

/// A model's `(RMS log error, relative RMS)` on a dataset, or why its fit could not run.
pub type Outcome = Result<(f64, f64), String>;

/// One row of a comparison: a dataset and each model's errors.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The dataset.
    pub dataset: String,
    /// Measurements used.
    pub points: usize,
    /// `(model, RMS log error, relative RMS)`, or the error message of a fit that could not run.
    pub fits: Vec<(String, Outcome)>,
}

/// The comparison as a Markdown table: one row per dataset, the RMS log error (and the relative
/// RMS) of each model; the best RMS log error of a row in bold.
pub fn comparison_table(rows: &[Comparison]) -> String {
    let mut models: Vec<String> = Vec::new();
    for r in rows {
        for (m, _) in &r.fits {
            if !models.contains(m) {
                models.push(m.clone());
            }
        }
    }
    let mut s = String::from("| dataset | points |");
    for m in &models {
        let _ = write!(s, " {m} |");
    }
    s.push_str("\n|---|---|");
    for _ in &models {
        s.push_str("---|");
    }
    s.push('\n');
    for r in rows {
        let best = r
            .fits
            .iter()
            .filter_map(|(_, f)| f.as_ref().ok().map(|x| x.0))
            .fold(f64::INFINITY, f64::min);
        let _ = write!(s, "| {} | {} |", r.dataset, r.points);
        for m in &models {
            match r.fits.iter().find(|(n, _)| n == m) {
                Some((_, Ok((log, rel)))) => {
                    let cell = format!("{log:.3} ({rel:.3})");
                    if *log == best {
                        let _ = write!(s, " **{cell}** |");
                    } else {
                        let _ = write!(s, " {cell} |");
                    }
                }
                Some((_, Err(e))) => {
                    let _ = write!(s, " failed: {e} |");
                }
                None => s.push_str(" — |"),
            }
        }
        s.push('\n');
    }
    s.push_str(
        "\nEach cell: RMS log error (relative RMS); the best RMS log error of a row in bold.\n",
    );
    s
}

/// The published SGD and ABC fits' errors on a MERL dataset (`data/published/`), measured as a
/// fit's are (the same measurements, `ε` and statistics): `[("sgd", …), ("abc", …)]`, or nothing
/// when no published fit has the dataset's name.
pub fn published_errors(dataset: &Dataset) -> Vec<(String, Outcome)> {
    let Ok((sgd, abc)) = crate::data::published::for_material(&dataset.name) else {
        return Vec::new();
    };
    let data = match Observations::new(dataset, None) {
        Ok(d) => d,
        Err(e) => {
            return vec![
                ("sgd".into(), Err(e.to_string())),
                ("abc".into(), Err(e.to_string())),
            ]
        }
    };
    let errors = |eval: &dyn Fn(woven::Vec3, woven::Vec3) -> [f64; 3]| {
        let predicted: Vec<[f64; 3]> = data.obs.iter().map(|o| eval(o.s, o.v)).collect();
        let mut p = predicted;
        if data.channels == 1 {
            // A grey dataset against a colour fit: the channels' mean.
            for x in &mut p {
                x[0] = (x[0] + x[1] + x[2]) / 3.0;
            }
        }
        Ok(statistics(&data, &p))
    };
    vec![
        ("sgd".into(), errors(&|s, v| sgd.eval(s, v))),
        ("abc".into(), errors(&|s, v| abc.eval(s, v))),
    ]
}
