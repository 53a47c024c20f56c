//! Fitting to a reference model instead of a measurement: a colour BRDF sampled densely over the
//! hemisphere as a [`Dataset`], the woven model's dyes solved per yarn family, the error measure
//! presets are compared by (RMS log error of the luminance, best overall scale removed) and the
//! satin ridge ratio (docs/microcylinder.md, "Presets grounded in the microcylinder fabrics").

use crate::data::{Dataset, Sample, Value};
use rayon::prelude::*;
use std::f64::consts::PI;
use woven::bsdf::Bsdf;
use woven::color::Rgb;
use woven::material::Dye;
use woven::{AffineBrdf, Model, Vec3};

/// The polar angles of the light, degrees.
pub const THETA_I_DEG: [f64; 5] = [10.0, 25.0, 40.0, 55.0, 70.0];
/// The light's azimuths, degrees: one quadrant, both ends (the fabrics fitted are symmetric
/// under `x → −x` and `y → −y`, so one quadrant of light holds every distinct configuration).
pub const PHI_I_DEG: [f64; 4] = [0.0, 30.0, 60.0, 90.0];
/// The viewer's polar angles, degrees.
pub const THETA_R_DEG: [f64; 5] = [5.0, 20.0, 35.0, 50.0, 65.0];
/// The viewer's azimuths: every 22.5° round the whole circle.
pub const N_PHI_R: usize = 16;

/// The direction pairs of [`sample`]: `(θi, φi, θr, φr)` in radians, light in one quadrant,
/// viewer over the whole hemisphere; 5 × 4 × 5 × 16 = 1600 pairs, plus the viewer exactly at
/// the mirror direction of each light (the highlights' peaks).
pub fn hemisphere_pairs() -> Vec<[f64; 4]> {
    pairs_over(&THETA_I_DEG, &PHI_I_DEG, &THETA_R_DEG)
}

/// The pairs of [`hemisphere_pairs`] on other polar angles and light azimuths (degrees), the
/// viewer at [`N_PHI_R`] azimuths round the circle and at each light's mirror direction.
pub fn pairs_over(theta_i: &[f64], phi_i: &[f64], theta_r: &[f64]) -> Vec<[f64; 4]> {
    let mut out = Vec::new();
    for &ti in theta_i {
        for &pi in phi_i {
            let (ti, pi) = (ti.to_radians(), pi.to_radians());
            for &tr in theta_r {
                for k in 0..N_PHI_R {
                    out.push([
                        ti,
                        pi,
                        tr.to_radians(),
                        2.0 * PI * k as f64 / N_PHI_R as f64,
                    ]);
                }
            }
            out.push([ti, pi, ti, pi + PI]);
        }
    }
    out
}

/// `bsdf` at every pair of [`hemisphere_pairs`], as a colour dataset named `name` (absolute,
/// weight 1). Pairs where every channel is 0 are left out (a log residual cannot use them).
pub fn sample(bsdf: &dyn Bsdf<Value = Rgb>, name: &str) -> Dataset {
    let samples = hemisphere_pairs()
        .par_iter()
        .filter_map(|&[theta_i, phi_i, theta_r, phi_r]| {
            let f = bsdf.eval(
                Vec3::from_spherical(theta_i, phi_i),
                Vec3::from_spherical(theta_r, phi_r),
            );
            (f.max() > 0.0).then_some(Sample {
                theta_i,
                phi_i,
                theta_r,
                phi_r,
                value: Value::Rgb(f.0),
                weight: 1.0,
            })
        })
        .collect();
    Dataset {
        name: name.to_string(),
        source: format!("<{name}, sampled>").into(),
        samples,
        dropped_below_horizon: 0,
        relative: false,
    }
}

/// The reciprocal part of `bsdf` at every pair of [`hemisphere_pairs`]: per channel, the
/// geometric mean `√(f(ω_i, ω_r) f(ω_r, ω_i))`, the reciprocal BRDF nearest to `bsdf` in log
/// terms. The microcylinder model is not reciprocal (docs/microcylinder.md §4); a physical
/// (reciprocal) model is fairly compared with it here. Pairs where either way is 0 in every
/// channel are left out.
pub fn sample_reciprocal(bsdf: &dyn Bsdf<Value = Rgb>, name: &str) -> Dataset {
    let mut data = sample(bsdf, name);
    data.samples = data
        .samples
        .into_par_iter()
        .filter_map(|mut s| {
            let (wi, wo) = directions(&s);
            let back = bsdf.eval(wo, wi);
            let there = channels(&s);
            let mean: [f64; 3] = std::array::from_fn(|c| (there[c] * back.0[c]).sqrt());
            s.value = Value::Rgb(mean);
            (mean.iter().any(|&v| v > 0.0)).then_some(s)
        })
        .collect();
    data.source = format!("<{name}, reciprocal part, sampled>").into();
    data
}

/// How far `bsdf` is from reciprocal over [`hemisphere_pairs`]: the RMS, mean removed, of half
/// the log ratio `ln f(ω_i, ω_r) − ln f(ω_r, ω_i)` of the luminance. No reciprocal model can
/// follow that antisymmetric part, so a reciprocal fit to [`sample`] cannot reach an
/// [`rms_log_scaled`] error below about this (0 for a reciprocal `bsdf`).
pub fn reciprocity_floor(bsdf: &dyn Bsdf<Value = Rgb>) -> f64 {
    let halves: Vec<f64> = hemisphere_pairs()
        .par_iter()
        .filter_map(|&[theta_i, phi_i, theta_r, phi_r]| {
            let (a, b) = (
                Vec3::from_spherical(theta_i, phi_i),
                Vec3::from_spherical(theta_r, phi_r),
            );
            let (there, back) = (bsdf.eval(a, b).luminance(), bsdf.eval(b, a).luminance());
            (there > 0.0 && back > 0.0).then(|| 0.5 * (there / back).ln())
        })
        .collect();
    // Half the log ratio is the log residual of the reciprocal part against the model.
    let ones = vec![1.0; halves.len()];
    let ratios: Vec<f64> = halves.iter().map(|h| h.exp()).collect();
    rms_log_scaled(&ratios, &ones)
}

/// The directions of a sample.
fn directions(s: &Sample) -> (Vec3, Vec3) {
    (
        Vec3::from_spherical(s.theta_i, s.phi_i),
        Vec3::from_spherical(s.theta_r, s.phi_r),
    )
}

/// The value of a sample per channel (a mono value in every channel).
fn channels(s: &Sample) -> [f64; 3] {
    match s.value {
        Value::Mono(v) => [v; 3],
        Value::Rgb(c) => c,
    }
}

/// The dyes of the weft and the warp that best fit `data` (log residuals, per channel) for the
/// woven `model`, its geometry held: in each channel the model is each family's affine parts
/// ([`Model::eval_affine_families`]) taken at that family's albedos dyed by the colour's
/// channel ([`Albedos::dyed`](woven::table::Albedos::dyed): piecewise linear in it), solved by
/// coordinate descent within `[0, 0.999]`. A flat surface gets one colour (the weft's).
pub fn fit_dyes(model: &Model, data: &Dataset) -> Dye {
    let own = model.own_albedos();
    let rows: Vec<([AffineBrdf; 2], [f64; 3])> = data
        .samples
        .par_iter()
        .map(|s| {
            let (wi, wo) = directions(s);
            (model.eval_affine_families(wi, wo), channels(s))
        })
        .collect();
    let flat = rows.iter().all(|(p, _)| p[1] == AffineBrdf::default());
    let predict = |parts: &[AffineBrdf; 2], x: [f64; 2]| -> f64 {
        let dyed = |k: usize| own.dyed(Some(Rgb::grey(x[k])))[0];
        let (a, b) = (dyed(0), dyed(1));
        parts[0].at(a.diffuse, a.interreflection) + parts[1].at(b.diffuse, b.interreflection)
    };
    let mut dye = [[0.0f64; 3]; 2];
    for c in 0..3 {
        // A faint pull toward equal dyes: where the two families reflect alike (a plain weave of
        // like threads), the data cannot tell their colours apart, and the same colour is the
        // answer; where they differ (shot silk) the data outweighs it.
        let pull = (EQUAL_DYE_PULL * rows.len() as f64).sqrt();
        let cost = |x: [f64; 2]| -> (f64, Vec<f64>) {
            let mut r: Vec<f64> = rows
                .iter()
                .map(|(p, y)| (predict(p, x).max(0.0) + LOG_EPS).ln() - (y[c] + LOG_EPS).ln())
                .collect();
            if !flat {
                r.push(pull * (x[0] - x[1]));
            }
            (r.iter().map(|r| r * r).sum(), r)
        };
        let n = if flat { 1 } else { 2 };
        // Coordinate descent steps over the kinks; Gauss–Newton runs down the valley that two
        // families of similar shape make (their dyes trade against each other).
        let mut x = [0.3, if flat { 0.0 } else { 0.3 }];
        for _ in 0..3 {
            x = coordinate_descent(cost, n, x, 3);
            x = gauss_newton_box(cost, n, x);
        }
        dye[0][c] = x[0];
        dye[1][c] = x[1];
    }
    Dye {
        weft: Some(Rgb(dye[0])),
        warp: (!flat).then_some(Rgb(dye[1])),
    }
}

/// The weight, per sample, of the squared difference between the weft's and the warp's dye in
/// [`fit_dyes`]'s objective.
const EQUAL_DYE_PULL: f64 = 1e-7;

/// The floor added to values before taking logs (sr⁻¹): a reference's zeros are fitted as small
/// values (here and in [`projection`](crate::projection)).
pub(crate) const LOG_EPS: f64 = 1e-6;

/// Minimizes `cost(x)` (its value and residuals) over the first `n` of two variables in
/// `[0, 0.999]`, by coordinate descent: each variable in turn on a grid of 25 values, then by
/// golden-section search in the best cell, round after round until it moves less than 10⁻⁹. Robust to the kink where the dyed
/// interreflection albedo reaches 1, where a derivative-based step stalls.
fn coordinate_descent(
    cost: impl Fn([f64; 2]) -> (f64, Vec<f64>),
    n: usize,
    mut x: [f64; 2],
    rounds: usize,
) -> [f64; 2] {
    const HI: f64 = 0.999;
    const GRID: usize = 24;
    for _round in 0..rounds {
        let before = x;
        for k in 0..n {
            let at = |v: f64| {
                let mut y = x;
                y[k] = v;
                cost(y).0
            };
            let step = HI / GRID as f64;
            let best = (0..=GRID)
                .map(|i| (at(i as f64 * step), i))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map_or(0, |(_, i)| i);
            let (mut lo, mut hi) = (
                (best as f64 - 1.0).max(0.0) * step,
                ((best + 1) as f64 * step).min(HI),
            );
            let g = 0.5 * (5f64.sqrt() - 1.0);
            for _ in 0..40 {
                let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
                if at(a) < at(b) {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            x[k] = 0.5 * (lo + hi);
        }
        if (x[0] - before[0]).abs().max((x[1] - before[1]).abs()) < 1e-9 {
            break;
        }
    }
    x
}

/// Lowers `cost(x)` (its value and residuals) over the first `n` of two variables in
/// `[0, 0.999]` from `x`: Gauss–Newton with a forward-difference Jacobian, a small damping and a
/// halving line search, projected onto the box.
fn gauss_newton_box(
    cost: impl Fn([f64; 2]) -> (f64, Vec<f64>),
    n: usize,
    mut x: [f64; 2],
) -> [f64; 2] {
    const H: f64 = 1e-7;
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
    let (mut current, mut r) = cost(x);
    for _ in 0..100 {
        let jac: Vec<Vec<f64>> = (0..n)
            .map(|k| {
                let mut xh = x;
                xh[k] = if x[k] + H <= 0.999 {
                    x[k] + H
                } else {
                    x[k] - H
                };
                let (_, rh) = cost(xh);
                rh.iter()
                    .zip(&r)
                    .map(|(a, b)| (a - b) / (xh[k] - x[k]))
                    .collect()
            })
            .collect();
        let step = if n == 1 {
            let d = dot(&jac[0], &jac[0]);
            if d <= 0.0 {
                break;
            }
            [dot(&jac[0], &r) / d, 0.0]
        } else {
            let (a, b, c) = (
                dot(&jac[0], &jac[0]),
                dot(&jac[0], &jac[1]),
                dot(&jac[1], &jac[1]),
            );
            let (g0, g1) = (dot(&jac[0], &r), dot(&jac[1], &r));
            let lambda = 1e-9 * (a + c);
            let det = (a + lambda) * (c + lambda) - b * b;
            if det.abs() <= 1e-300 || det.is_nan() {
                break;
            }
            [
                ((c + lambda) * g0 - b * g1) / det,
                ((a + lambda) * g1 - b * g0) / det,
            ]
        };
        let mut t = 1.0;
        let mut improved = false;
        for _ in 0..30 {
            let trial = [
                (x[0] - t * step[0]).clamp(0.0, 0.999),
                (x[1] - t * step[1]).clamp(0.0, 0.999),
            ];
            let (c, rt) = cost(trial);
            if c < current {
                (x, current, r, improved) = (trial, c, rt, true);
                break;
            }
            t *= 0.5;
        }
        if !improved {
            break;
        }
    }
    x
}

/// The RMS of `ln p − ln m` over luminances, with the best overall scale removed (the mean log
/// ratio subtracted): how well a model's shape matches a reference's, whatever its brightness.
/// Pairs where either is 0 are skipped.
pub fn rms_log_scaled(predicted: &[f64], measured: &[f64]) -> f64 {
    let logs: Vec<f64> = predicted
        .iter()
        .zip(measured)
        .filter(|(p, m)| **p > 0.0 && **m > 0.0)
        .map(|(p, m)| (p / m).ln())
        .collect();
    if logs.is_empty() {
        return f64::NAN;
    }
    let mean = logs.iter().sum::<f64>() / logs.len() as f64;
    (logs.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / logs.len() as f64).sqrt()
}

/// The luminance of each sample of `data`.
pub fn luminances(data: &Dataset) -> Vec<f64> {
    data.samples
        .iter()
        .map(|s| Rgb(channels(s)).luminance())
        .collect()
}

/// A colour BRDF's luminance at each sample of `data`.
pub fn predict_luminances(bsdf: &dyn Bsdf<Value = Rgb>, data: &Dataset) -> Vec<f64> {
    data.samples
        .par_iter()
        .map(|s| {
            let (wi, wo) = directions(s);
            bsdf.eval(wi, wo).luminance()
        })
        .collect()
}

/// The ridge ratio of a sheen along floats that run along `x` (`floats_along_x`) or `y`: the
/// light at θi = 30° in the plane across the floats, the viewer at its mirror direction, over
/// the same viewer tilted 30° along the floats (turned on a great circle out of the plane of
/// incidence, toward the floats' direction). A satin's long floats make it large (≈ 2.9 for the
/// microcylinder charmeuse); a matte cloth has ≈ 1.
pub fn ridge_ratio(f: impl Fn(Vec3, Vec3) -> f64, floats_along_x: bool) -> f64 {
    let t = 30f64.to_radians();
    // In the frame (along, across, z): light in the (across, z) plane.
    let frame = |along: f64, across: f64, z: f64| {
        if floats_along_x {
            Vec3::new(along, across, z)
        } else {
            Vec3::new(across, along, z)
        }
    };
    let (s, c) = t.sin_cos();
    let wi = frame(0.0, s, c);
    let mirror = frame(0.0, -s, c);
    let off = frame(s, -s * c, c * c);
    f(wi, mirror) / f(wi, off)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_has_every_pair_once_and_above_the_horizon() {
        let pairs = hemisphere_pairs();
        assert_eq!(pairs.len(), 5 * 4 * (5 * 16 + 1));
        assert!(pairs.iter().all(|p| p[0] < 1.5 && p[2] < 1.5));
    }

    #[test]
    fn the_scaled_log_error_ignores_a_constant_factor() {
        let m = [0.1, 0.2, 0.5, 1.0];
        let p: Vec<f64> = m.iter().map(|v| 3.0 * v).collect();
        assert!(rms_log_scaled(&p, &m) < 1e-12);
        let q = [0.1, 0.2, 0.5, 2.0];
        assert!(rms_log_scaled(&q, &m) > 0.2);
    }

    /// A material dyed with known colours, sampled, gives back those colours.
    #[test]
    fn dyes_are_recovered_from_a_dyed_material() {
        // Belt cloth: twisted yarns in a twill, so the two families reflect differently (an
        // isotropic yarn's families are the same BRDF, and their dyes only count as a sum).
        let mut m = woven::material::Material::preset("belt-cloth").unwrap();
        m.dye = Dye {
            weft: Some(Rgb([0.7, 0.2, 0.05])),
            warp: Some(Rgb([0.1, 0.4, 0.6])),
        };
        let bsdf = woven::catalog::AnyMaterial::Woven(m.clone())
            .build_rgb(550.0)
            .unwrap();
        let mut data = sample(&*bsdf, "belt-cloth");
        data.samples.truncate(200);
        let got = fit_dyes(&m.build(550.0).unwrap(), &data);
        for (g, w) in [(got.weft, m.dye.weft), (got.warp, m.dye.warp)] {
            for (a, b) in g.unwrap().0.iter().zip(w.unwrap().0) {
                assert!((a - b).abs() < 1e-2, "{got:?} vs {:?}", m.dye);
            }
        }
    }

    #[test]
    fn an_isotropic_brdf_has_a_ridge_ratio_of_one() {
        let lambert = |_: Vec3, _: Vec3| 0.3;
        assert!((ridge_ratio(lambert, true) - 1.0).abs() < 1e-12);
    }

    /// A test BRDF `(cos θi / cos θr)^k · (1 + (ω_i·ω_r)²)` in colour: its reciprocal part is
    /// the symmetric factor, and its antisymmetric half log ratio is `k (ln cos θi − ln cos θr)`.
    struct Skewed(f64);

    impl Bsdf for Skewed {
        type Value = Rgb;
        fn lobes(&self) -> woven::bsdf::LobeFlags {
            woven::bsdf::LobeFlags::REFLECTION
        }
        fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
            let f = (wi.z / wo.z).powf(self.0) * (1.0 + wi.dot(wo).powi(2));
            Rgb([f, 0.5 * f, 0.25 * f])
        }
        fn pdf(&self, _: Vec3, _: Vec3, _: woven::bsdf::Transport) -> f64 {
            0.0
        }
        fn sample(
            &self,
            _: Vec3,
            _: f64,
            _: [f64; 2],
            _: woven::bsdf::Transport,
        ) -> Option<woven::bsdf::BsdfSample<Rgb>> {
            None
        }
    }

    #[test]
    fn the_reciprocity_floor_is_the_antisymmetric_part() {
        assert!(reciprocity_floor(&Skewed(0.0)) < 1e-12);
        let k = 0.7;
        let halves: Vec<f64> = hemisphere_pairs()
            .iter()
            .map(|p| k * (p[0].cos().ln() - p[2].cos().ln()))
            .collect();
        let mean = halves.iter().sum::<f64>() / halves.len() as f64;
        let want =
            (halves.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / halves.len() as f64).sqrt();
        let got = reciprocity_floor(&Skewed(k));
        assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    }

    #[test]
    fn the_reciprocal_part_is_the_symmetric_factor() {
        let data = sample_reciprocal(&Skewed(0.7), "skewed");
        assert_eq!(data.samples.len(), hemisphere_pairs().len());
        for s in &data.samples {
            let (wi, wo) = directions(s);
            let want = Skewed(0.0).eval(wi, wo).0;
            for (a, b) in channels(s).iter().zip(want) {
                assert!((a - b).abs() < 1e-12 * b, "{a} vs {b}");
            }
        }
        // A reciprocal BRDF is its own reciprocal part.
        let same = sample_reciprocal(&Skewed(0.0), "symmetric");
        let plain = sample(&Skewed(0.0), "symmetric");
        for (a, b) in same.samples.iter().zip(&plain.samples) {
            assert!((channels(a)[0] - channels(b)[0]).abs() < 1e-12);
        }
    }
}
