//! The projection of a woven BRDF onto the standard lobes that renderers carry (Blender's
//! Cycles, OpenPBR, glTF): a Charlie sheen ([`SheenLobe`]: glTF's `KHR_materials_sheen` lobe,
//! normalised so that its albedo stays at most 1, where glTF's exceeds it toward grazing) laid
//! over a base of a Lambertian lobe and an anisotropic GGX whose tangent runs along the yarn
//! ([`AnisotropicGgx`]),
//!
//! ```text
//! f = w_sheen f_sheen + (1 − w_sheen max(Ê(μi), Ê(μo))) (ρ/π + w_spec f_GGX(α_along, α_across))
//! ```
//!
//! (the sheen's albedo scaling of the base, as glTF layers it), their weights and roughnesses
//! fitted to one yarn family's BRDF. Beside it, the best single isotropic GGX + Lambert: the
//! baseline the mixture must beat.
//!
//! The fit minimizes the log residuals of the luminance, `ln(p + ε) − ln(m + ε)`, at
//! [`projection_pairs`] (light and viewer up to 80°; pairs where the reference is 0 left out), by
//! Levenberg–Marquardt from several starts over unbounded coordinates (a logistic map keeps
//! each bounded parameter in its range, an exponential the specular weight positive). The
//! isotropic fit's optimum, its sheen all but off, is one of the mixture's starts, so the
//! mixture's fitted objective is never worse than the baseline's. The error reported is
//! [`rms_log_scaled`]: the RMS log error with the best overall scale removed. Where the fitted
//! sheen's weight is near 0 its roughness is whatever the start left: it changes nothing.
//!
//! What these lobes cannot carry of the woven model:
//! - **the masking's dependence on the light**: a yarn's lit-and-visible part couples the
//!   light's and the viewer's directions; a standard lobe's weight depends on neither, or (in
//!   Cycles) on the view alone;
//! - **the interreflection term**, `ρ ħ/π` with `ħ` the part of the yarn lit and seen: a
//!   Lambertian lobe is constant where it varies with both directions;
//! - **non-reciprocity**: with `normalization = "paper"` woven's `f(s, v) ≠ f(v, s)`, and every
//!   lobe here is reciprocal, so the fit takes the symmetric part of what it is given.

use crate::error::FitError;
use crate::reference::{pairs_over, rms_log_scaled, LOG_EPS};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{storage::Owned, DMatrix, DVector, Dyn};
use std::f64::consts::FRAC_1_PI;
use woven::baseline::{AnisotropicGgx, SheenLobe, MIN_GGX_ALPHA, MIN_SHEEN_ROUGHNESS};
use woven::Vec3;

/// The index of refraction of the GGX lobe's dielectric (glTF's and OpenPBR's default).
pub const PROJECTION_ETA: f64 = 1.5;

/// The light's polar angles of [`projection_pairs`], degrees.
pub const PROJECTION_THETA_I_DEG: [f64; 6] = [10.0, 25.0, 40.0, 55.0, 70.0, 80.0];
/// The viewer's polar angles of [`projection_pairs`], degrees.
pub const PROJECTION_THETA_R_DEG: [f64; 6] = [5.0, 20.0, 35.0, 50.0, 65.0, 80.0];

/// The direction pairs a projection is fitted at: the reference pairs
/// ([`hemisphere_pairs`](crate::reference::hemisphere_pairs)) with light and viewer down to 80°
/// (6 × 4 × 6 × 16 pairs plus each light's mirror direction).
pub fn projection_pairs() -> Vec<(Vec3, Vec3)> {
    pairs_over(
        &PROJECTION_THETA_I_DEG,
        &crate::reference::PHI_I_DEG,
        &PROJECTION_THETA_R_DEG,
    )
    .into_iter()
    .map(|[ti, pi, tr, pr]| (Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr)))
    .collect()
}

/// The standard lobes of a projection (module docs), the yarn along `x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StandardLobes {
    /// The Lambertian albedo `ρ`, in `[0, 1]`.
    pub diffuse: f64,
    /// The GGX lobe's weight `w_spec` (≥ 0; 1 is a dielectric coat of index [`PROJECTION_ETA`]).
    pub specular: f64,
    /// The GGX roughness `α` along the yarn and across it, each in `[MIN_GGX_ALPHA, 1]`.
    pub alpha: [f64; 2],
    /// The sheen's weight `w_sheen` (glTF's `sheenColor`, grey), in `[0, 1]`.
    pub sheen: f64,
    /// The sheen's roughness (glTF's `sheenRoughness`), in `[MIN_SHEEN_ROUGHNESS, 1]`.
    pub sheen_roughness: f64,
}

/// [`StandardLobes`] made ready to evaluate.
#[derive(Clone, Debug)]
pub struct BuiltLobes {
    lobes: StandardLobes,
    ggx: AnisotropicGgx,
    sheen: SheenLobe,
}

impl StandardLobes {
    /// The lobes made ready to evaluate.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming a parameter out of its range.
    pub fn build(&self) -> Result<BuiltLobes, FitError> {
        let check = |name: &str, x: f64, lo: f64, hi: f64| {
            if x.is_finite() && (lo..=hi).contains(&x) {
                Ok(())
            } else {
                Err(FitError::invalid(
                    name,
                    x,
                    format!("a value in [{lo}, {hi}]"),
                ))
            }
        };
        check("diffuse", self.diffuse, 0.0, 1.0)?;
        check("specular", self.specular, 0.0, f64::MAX)?;
        check("sheen", self.sheen, 0.0, 1.0)?;
        let lib = |e: woven::Error| FitError::invalid("lobes", self.describe(), e.to_string());
        Ok(BuiltLobes {
            lobes: *self,
            ggx: AnisotropicGgx::new(self.alpha[0], self.alpha[1], PROJECTION_ETA).map_err(lib)?,
            sheen: SheenLobe::new(self.sheen_roughness).map_err(lib)?,
        })
    }

    /// The parameters as one line.
    pub fn describe(&self) -> String {
        format!(
            "ρ {:.4}, w_spec {:.4}, α along {:.4}, α across {:.4}, w_sheen {:.4}, sheen roughness {:.4}",
            self.diffuse,
            self.specular,
            self.alpha[0],
            self.alpha[1],
            self.sheen,
            self.sheen_roughness
        )
    }
}

impl BuiltLobes {
    /// The lobes' parameters.
    pub fn lobes(&self) -> &StandardLobes {
        &self.lobes
    }

    /// `f(wi, wo)` (module docs), sr⁻¹ without the cosine; 0 below the horizon.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let [lambert, ggx, sheen] = self.unit_lobes(wi, wo);
        let l = &self.lobes;
        l.sheen * sheen + l.diffuse * lambert + l.specular * ggx
    }

    /// Each lobe at unit weight, as `f` adds them: the Lambertian and the GGX lobes under the
    /// sheen's albedo scaling, and the sheen; 0 below the horizon. `f` is
    /// `ρ · [0] + w_spec · [1] + w_sheen · [2]`: linear in the weights, so each colour channel's
    /// weights follow from the same lobes by least squares.
    #[inline]
    pub fn unit_lobes(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        let over = 1.0 - self.lobes.sheen * self.sheen.base_attenuation(wi.z, wo.z);
        [
            over * FRAC_1_PI,
            over * self.ggx.eval(wi, wo),
            self.sheen.eval(wi, wo),
        ]
    }
}

/// Which lobes a projection fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LobeSet {
    /// The sheen over a Lambertian lobe and an anisotropic GGX along the yarn: six parameters.
    Fabric,
    /// One isotropic GGX + Lambert (no sheen): three parameters, the baseline.
    IsotropicGgx,
    /// Lambert + the anisotropic GGX along the yarn, no sheen: four parameters. What the
    /// renderers' materials are fitted with ([`standard`](crate::standard)): their sheens
    /// (Cycles' and OpenPBR's are Zeltner et al.'s) are not this Charlie lobe.
    Anisotropic,
}

impl LobeSet {
    /// `"fabric"` or `"isotropic-ggx"`.
    pub fn name(self) -> &'static str {
        match self {
            LobeSet::Fabric => "fabric",
            LobeSet::IsotropicGgx => "isotropic-ggx",
            LobeSet::Anisotropic => "anisotropic",
        }
    }

    fn len(self) -> usize {
        match self {
            LobeSet::Fabric => 6,
            LobeSet::IsotropicGgx => 3,
            LobeSet::Anisotropic => 4,
        }
    }

    /// The lobes at unbounded coordinates `u` (module docs).
    fn lobes(self, u: &[f64]) -> StandardLobes {
        let alpha = |x: f64| MIN_GGX_ALPHA + (1.0 - MIN_GGX_ALPHA) * logistic(x);
        let (diffuse, specular) = (logistic(u[0]), u[1].exp());
        match self {
            LobeSet::Fabric => StandardLobes {
                diffuse,
                specular,
                alpha: [alpha(u[2]), alpha(u[3])],
                sheen: logistic(u[4]),
                sheen_roughness: MIN_SHEEN_ROUGHNESS + (1.0 - MIN_SHEEN_ROUGHNESS) * logistic(u[5]),
            },
            LobeSet::IsotropicGgx => StandardLobes {
                diffuse,
                specular,
                alpha: [alpha(u[2]); 2],
                sheen: 0.0,
                sheen_roughness: 1.0,
            },
            LobeSet::Anisotropic => StandardLobes {
                diffuse,
                specular,
                alpha: [alpha(u[2]), alpha(u[3])],
                sheen: 0.0,
                sheen_roughness: 1.0,
            },
        }
    }

    /// The coordinates of `lobes` (the inverse of [`lobes`](Self::lobes), within its range).
    fn coordinates(self, l: &StandardLobes) -> Vec<f64> {
        let a = |x: f64| logit((x - MIN_GGX_ALPHA) / (1.0 - MIN_GGX_ALPHA));
        let mut u = vec![logit(l.diffuse), l.specular.max(1e-12).ln(), a(l.alpha[0])];
        if self != LobeSet::IsotropicGgx {
            u.push(a(l.alpha[1]));
        }
        if self == LobeSet::Fabric {
            u.push(logit(l.sheen));
            u.push(logit(
                (l.sheen_roughness - MIN_SHEEN_ROUGHNESS) / (1.0 - MIN_SHEEN_ROUGHNESS),
            ));
        }
        u
    }
}

/// What a projection's residuals compare.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Objective {
    /// `ln(p + ε) − ln(m + ε)` at every pair: the shape everywhere, dim pairs as much as the
    /// highlight (the error the projection's table reports).
    Log,
    /// `(p − m) √(cos θi cos θo)`, over the reference's RMS so weighted: the reflected radiance
    /// under even light, where the highlights weigh as much as they add to a render's mean. What
    /// a renderer's material is fitted with ([`standard`](crate::standard)).
    Radiance,
}

fn logistic(x: f64) -> f64 {
    1.0 / (1.0 + (-x).exp())
}

/// The logistic's inverse, `p` kept off 0 and 1.
fn logit(p: f64) -> f64 {
    let p = p.clamp(1e-9, 1.0 - 1e-9);
    (p / (1.0 - p)).ln()
}

/// A fitted projection.
#[derive(Clone, Debug)]
pub struct Projection {
    /// The lobes fitted.
    pub set: LobeSet,
    /// Their parameters.
    pub lobes: StandardLobes,
    /// The RMS log error of the luminance against the reference, best overall scale removed.
    pub rms_log: f64,
    /// For [`LobeSet::Fabric`], the isotropic baseline fitted on the way (one of its starts);
    /// `None` for the baseline itself.
    pub baseline: Option<Box<Projection>>,
}

/// The reference's luminance at each pair: what a projection is fitted to.
#[derive(Clone, Debug)]
pub struct Reference {
    /// `(wi, wo)`, `wi` toward the light.
    pub pairs: Vec<(Vec3, Vec3)>,
    /// The luminance of `f(wi, wo)`, sr⁻¹, each finite and ≥ 0.
    pub values: Vec<f64>,
}

impl Reference {
    /// `f` at [`projection_pairs`].
    pub fn sample(f: impl Fn(Vec3, Vec3) -> f64 + Sync) -> Reference {
        use rayon::prelude::*;
        let pairs = projection_pairs();
        let values = pairs.par_iter().map(|&(wi, wo)| f(wi, wo)).collect();
        Reference { pairs, values }
    }
}

/// The lobes of `set` that best fit `reference` (module docs) where it is not 0. For
/// [`LobeSet::Fabric`] the isotropic baseline is fitted first and its optimum is one of the
/// starts.
///
/// # Errors
/// [`FitError::Data`] when `reference` has no pairs, its lengths differ, or a value is not a
/// finite number ≥ 0, or every value is 0.
pub fn project(reference: &Reference, set: LobeSet) -> Result<Projection, FitError> {
    project_with(reference, set, Objective::Log)
}

/// [`project`] with residuals of `objective`; the error reported is still the RMS log error
/// ([`rms_log_scaled`]), so the two objectives' fits compare on one scale.
///
/// # Errors
/// As [`project`].
pub fn project_with(
    reference: &Reference,
    set: LobeSet,
    objective: Objective,
) -> Result<Projection, FitError> {
    check_reference(reference)?;
    // A pair the reference gives 0 (a masked one) is left out, as rms_log_scaled leaves it:
    // no lobe here reaches 0, and its log residual would outweigh the rest.
    let (pairs, values): (Vec<_>, Vec<_>) = reference
        .pairs
        .iter()
        .zip(&reference.values)
        .filter(|(_, v)| **v > 0.0)
        .unzip();
    let reference = &Reference { pairs, values };
    let logs: Vec<f64> = reference
        .values
        .iter()
        .map(|m| (m + LOG_EPS).ln())
        .collect();
    debug_assert!(
        !logs.is_empty(),
        "check_reference refuses an all-zero reference"
    );
    let mut starts = vec![];
    let mut baseline = None;
    let base = StandardLobes {
        diffuse: 0.3,
        specular: 1.0,
        alpha: [0.3; 2],
        sheen: 0.3,
        sheen_roughness: 0.5,
    };
    match set {
        LobeSet::IsotropicGgx => {
            for a in [0.05, 0.15, 0.4, 0.8] {
                starts.push(StandardLobes {
                    alpha: [a; 2],
                    ..base
                });
            }
        }
        LobeSet::Fabric | LobeSet::Anisotropic => {
            let iso = project_with(reference, LobeSet::IsotropicGgx, objective)?;
            starts.push(StandardLobes {
                sheen: if set == LobeSet::Fabric { 1e-6 } else { 0.0 },
                ..iso.lobes
            });
            baseline = Some(Box::new(iso));
            // The sheen's roughness is a coordinate of the Fabric set alone.
            let sheens: &[f64] = if set == LobeSet::Fabric {
                &[0.3, 0.8]
            } else {
                &[0.3]
            };
            for (along, across) in [(0.05, 0.3), (0.3, 0.05), (0.1, 0.1), (0.4, 0.6)] {
                for &sheen_roughness in sheens {
                    starts.push(StandardLobes {
                        alpha: [along, across],
                        sheen_roughness,
                        ..base
                    });
                }
            }
        }
    }
    let mut best: Option<(f64, Vec<f64>)> = None;
    for start in &starts {
        let problem = Problem::new(reference, &logs, set, objective, set.coordinates(start));
        let (problem, _) = LevenbergMarquardt::new()
            .with_ftol(1e-10)
            .with_xtol(1e-10)
            .with_patience(200)
            .minimize(problem);
        if let Some((cost, u)) = problem.best {
            if best.as_ref().is_none_or(|b| cost < b.0) {
                best = Some((cost, u));
            }
        }
    }
    let (_, u) = best.ok_or_else(|| FitError::Data {
        name: "reference".into(),
        message: "no start of the projection could be evaluated".into(),
    })?;
    let lobes = set.lobes(&u);
    let built = lobes.build()?;
    let predicted: Vec<f64> = reference
        .pairs
        .iter()
        .map(|&(wi, wo)| built.eval(wi, wo))
        .collect();
    Ok(Projection {
        set,
        lobes,
        rms_log: rms_log_scaled(&predicted, &reference.values),
        baseline,
    })
}

fn check_reference(reference: &Reference) -> Result<(), FitError> {
    let bad = |message: String| {
        Err(FitError::Data {
            name: "reference".into(),
            message,
        })
    };
    let (n, m) = (reference.pairs.len(), reference.values.len());
    if n == 0 || n != m {
        return bad(format!(
            "{n} direction pairs and {m} values: expected as many of each, at least one"
        ));
    }
    if let Some(v) = reference
        .values
        .iter()
        .find(|v| !(v.is_finite() && **v >= 0.0))
    {
        return bad(format!("a value {v}: expected finite numbers ≥ 0"));
    }
    if reference.values.iter().all(|v| *v == 0.0) {
        return bad("every value is 0: nothing to project".into());
    }
    Ok(())
}

/// The least-squares problem of one start: residuals of its [`Objective`], the Jacobian by
/// forward differences; the best point seen is kept.
struct Problem<'a> {
    reference: &'a Reference,
    logs: &'a [f64],
    set: LobeSet,
    objective: Objective,
    /// [`Objective::Radiance`]'s weight of each pair, `√(cos θi cos θo)` over the weighted
    /// reference's RMS.
    weights: Vec<f64>,
    u: DVector<f64>,
    res: Option<DVector<f64>>,
    best: Option<(f64, Vec<f64>)>,
}

impl<'a> Problem<'a> {
    fn new(
        reference: &'a Reference,
        logs: &'a [f64],
        set: LobeSet,
        objective: Objective,
        u: Vec<f64>,
    ) -> Self {
        let mut weights: Vec<f64> = reference
            .pairs
            .iter()
            .map(|(wi, wo)| (wi.z * wo.z).sqrt())
            .collect();
        let rms = (weights
            .iter()
            .zip(&reference.values)
            .map(|(w, m)| (w * m).powi(2))
            .sum::<f64>()
            / weights.len() as f64)
            .sqrt();
        weights.iter_mut().for_each(|w| *w /= rms);
        let mut p = Problem {
            reference,
            logs,
            set,
            objective,
            weights,
            u: DVector::from_vec(vec![0.0; set.len()]),
            res: None,
            best: None,
        };
        p.set_params(&DVector::from_vec(u));
        p
    }

    fn residuals_at(&self, u: &[f64]) -> Option<DVector<f64>> {
        let built = self.set.lobes(u).build().ok()?;
        let r: Vec<f64> = self
            .reference
            .pairs
            .iter()
            .enumerate()
            .map(|(k, &(wi, wo))| {
                let p = built.eval(wi, wo);
                match self.objective {
                    Objective::Log => (p + LOG_EPS).ln() - self.logs[k],
                    Objective::Radiance => (p - self.reference.values[k]) * self.weights[k],
                }
            })
            .collect();
        r.iter()
            .all(|x| x.is_finite())
            .then(|| DVector::from_vec(r))
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, u: &DVector<f64>) {
        self.u = u.clone();
        self.res = self.residuals_at(u.as_slice());
        if let Some(r) = &self.res {
            let cost = r.norm_squared();
            if self.best.as_ref().is_none_or(|b| cost < b.0) {
                self.best = Some((cost, u.as_slice().to_vec()));
            }
        }
    }

    fn params(&self) -> DVector<f64> {
        self.u.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.res.clone()
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let r = self.res.as_ref()?;
        let mut jac = DMatrix::zeros(r.len(), self.u.len());
        for k in 0..self.u.len() {
            let mut u = self.u.as_slice().to_vec();
            let h = 1e-6 * (1.0 + u[k].abs());
            u[k] += h;
            let rh = self.residuals_at(&u)?;
            jac.set_column(k, &((rh - r) / h));
        }
        Some(jac)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_projection_recovers_the_lobes_it_was_made_of() {
        let truth = StandardLobes {
            diffuse: 0.25,
            specular: 0.8,
            alpha: [0.12, 0.45],
            sheen: 0.6,
            sheen_roughness: 0.4,
        };
        let built = truth.build().unwrap();
        let reference = Reference::sample(|wi, wo| built.eval(wi, wo));
        let fit = project(&reference, LobeSet::Fabric).unwrap();
        assert!(
            fit.rms_log < 1e-4,
            "{}: {}",
            fit.lobes.describe(),
            fit.rms_log
        );
        let l = fit.lobes;
        for (got, want) in [
            (l.diffuse, truth.diffuse),
            (l.specular, truth.specular),
            (l.alpha[0], truth.alpha[0]),
            (l.alpha[1], truth.alpha[1]),
            (l.sheen, truth.sheen),
            (l.sheen_roughness, truth.sheen_roughness),
        ] {
            assert!(
                (got - want).abs() < 1e-3 * want.max(0.1),
                "{}",
                l.describe()
            );
        }
        // One isotropic GGX cannot make an anisotropic highlight and a sheen.
        let iso = project(&reference, LobeSet::IsotropicGgx).unwrap();
        assert!(
            iso.rms_log > 100.0 * fit.rms_log.max(1e-6),
            "{}",
            iso.rms_log
        );
    }

    #[test]
    fn a_bad_reference_is_refused() {
        let pairs = projection_pairs();
        for (values, needle) in [
            (vec![], "direction pairs"),
            (vec![f64::NAN; pairs.len()], "finite"),
            (vec![0.0; pairs.len()], "every value is 0"),
        ] {
            let reference = Reference {
                pairs: pairs.clone(),
                values,
            };
            let err = project(&reference, LobeSet::Fabric)
                .unwrap_err()
                .to_string();
            assert!(err.contains(needle), "{err}");
        }
        let bad = StandardLobes {
            diffuse: 1.5,
            specular: 1.0,
            alpha: [0.2; 2],
            sheen: 0.0,
            sheen_roughness: 0.5,
        };
        assert!(bad.build().unwrap_err().to_string().contains("diffuse"));
    }
}
