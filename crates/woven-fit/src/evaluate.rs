//! Evaluating a parameter set: the BRDF at every measurement, as the affine function of the
//! albedos it is (so the albedos, the scale and `ħ` get exact derivatives for free).

use crate::microcylinder::PreparedFabric;
use crate::params::{ModelKind, ParamSet, Quantity};
use rayon::prelude::*;
use std::f64::consts::FRAC_1_PI;
use std::sync::Mutex;
use woven::baseline::SheenLobe;
use woven::fiber::{beckmann_d, fresnel_dielectric, smith_lambda, Fiber, FiberParams};
use woven::{AffineBrdf, Model, Vec3};

/// The BRDF's parts at one pair of directions: `f = scale·(specular·fixed + ρ0·per_diffuse +
/// ρ·per_interreflection)` per channel ([`AffineBrdf`]; `specular` is 1 except for the
/// microfacet baseline).
///
/// The sheen baseline is bilinear in its albedos (`diffuse`, and the `sheen` colour `c` that
/// dims the base), and fills the three slots as `fixed` = the white lobe `D V / N`,
/// `per_diffuse` = `1/π`, `per_interreflection` = the base's loss per unit `c`,
/// `max(Ê(θi), Ê(θr))/π`: `f = c·fixed + diffuse·(per_diffuse − c·per_interreflection)`
/// ([`Linear::predict`]).
///
/// The microcylinder fabric fills them as `fixed` = the surface lobes, `per_diffuse` = thread
/// 1's volume lobe per unit albedo, `per_interreflection` = thread 2's, each times the held
/// energy guard's factor ([`crate::microcylinder::PreparedFabric`]).
pub type Parts = AffineBrdf;

/// One measurement as the fitter uses it: directions in the measurement's frame, values per
/// channel, weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observation {
    /// Toward the light, in the measurement's frame.
    pub s: Vec3,
    /// Toward the viewer.
    pub v: Vec3,
    /// The measured value per channel (mono data uses channel 0).
    pub value: [f64; 3],
    /// Weight in the objective.
    pub weight: f64,
}

/// A parameter set made ready to evaluate: the woven model built once (its β table and
/// quadrature set up), whatever the number of points.
pub enum Prepared {
    /// `cloth` and `fiber`: the library's model, and the weave's rotation.
    Woven {
        /// The model (albedos as in the set; [`Model::eval_affine`] frees them).
        model: Box<Model>,
        /// The weave's rotation, radians.
        rotation: f64,
    },
    /// `f = diffuse/π`.
    Lambert,
    /// Beckmann + Smith + dielectric Fresnel, plus Lambert.
    Microfacet {
        /// Beckmann `α`.
        alpha: f64,
        /// Refractive index of the Fresnel term.
        eta: f64,
    },
    /// The Charlie sheen's lobe (white) and its albedo, plus Lambert.
    Sheen {
        /// The library's lobe at the set's roughness.
        lobe: Box<SheenLobe>,
    },
    /// The microcylinder fabric, affine in its threads' albedos.
    Microcylinder(Box<PreparedFabric>),
}

impl Prepared {
    /// Prepares `set` (builds the woven model at 550 nm).
    ///
    /// # Errors
    /// When the material does not build (a parameter combination the library refuses).
    pub fn new(set: &ParamSet) -> Result<Self, woven::Error> {
        Self::with_cache(set, None)
    }

    /// [`new`](Self::new), taking the fiber's β table from `cache` when it holds one for the
    /// same roughness (building a table costs ~0.2 s, a pass over 205 points of a sateen 13 ms).
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn with_cache(set: &ParamSet, cache: Option<&FiberCache>) -> Result<Self, woven::Error> {
        Ok(match set.model {
            ModelKind::Cloth | ModelKind::Fiber => {
                let m = set.material().expect("woven models have a material");
                m.validate()?;
                let fiber = match cache {
                    Some(cache) => cache.fiber(&m.fiber)?,
                    None => Fiber::new(&m.fiber, woven::fiber::DEFAULT_WAVELENGTH_NM)?,
                };
                Prepared::Woven {
                    model: Box::new(m.build_with(fiber)?),
                    rotation: set.get(Quantity::Rotation, 0).unwrap_or(0.0),
                }
            }
            ModelKind::Lambert => Prepared::Lambert,
            ModelKind::Microfacet => Prepared::Microfacet {
                alpha: set.get(Quantity::Alpha, 0).unwrap_or(0.3),
                eta: set.get(Quantity::Eta, 0).unwrap_or(1.5),
            },
            ModelKind::Sheen => Prepared::Sheen {
                lobe: Box::new(SheenLobe::new(
                    set.get(Quantity::SheenRoughness, 0).unwrap_or(0.5),
                )?),
            },
            ModelKind::Microcylinder => {
                Prepared::Microcylinder(Box::new(PreparedFabric::new(set)?))
            }
        })
    }

    /// The parts at one pair of directions in the measurement's frame.
    pub fn parts(&self, s: Vec3, v: Vec3) -> Parts {
        if s.z <= 0.0 || v.z <= 0.0 {
            return Parts::default();
        }
        match self {
            Prepared::Woven { model, rotation } => {
                // The weft lies at azimuth `rotation` in the measurement's frame: turn the
                // directions by −rotation into the cloth's.
                let (sin, cos) = rotation.sin_cos();
                let turn = |d: Vec3| Vec3::new(cos * d.x + sin * d.y, -sin * d.x + cos * d.y, d.z);
                model.eval_affine(turn(s), turn(v))
            }
            Prepared::Lambert => Parts {
                fixed: 0.0,
                per_diffuse: FRAC_1_PI,
                per_interreflection: 0.0,
            },
            Prepared::Microfacet { alpha, eta } => Parts {
                fixed: microfacet_specular(s, v, *alpha, *eta),
                per_diffuse: FRAC_1_PI,
                per_interreflection: 0.0,
            },
            Prepared::Sheen { lobe } => Parts {
                fixed: lobe.eval(s, v),
                per_diffuse: FRAC_1_PI,
                per_interreflection: lobe.base_attenuation(s.z, v.z) * FRAC_1_PI,
            },
            Prepared::Microcylinder(fabric) => fabric.parts(s, v),
        }
    }

    /// The parts at every observation, in order (over all cores; the result does not depend on
    /// the scheduling).
    pub fn parts_all(&self, obs: &[Observation]) -> Vec<Parts> {
        obs.par_iter()
            // A woven evaluation costs up to a few milliseconds: small tasks balance the cores.
            .with_max_len(4)
            .map(|o| self.parts(o.s, o.v))
            .collect()
    }
}

/// Fibers already built, by roughness, so that parameter sets differing in anything but the
/// roughness share one β table ([`Fiber::with_params`]). Holds the last [`FiberCache::CAPACITY`].
#[derive(Default)]
pub struct FiberCache {
    fibers: Mutex<Vec<Fiber>>,
}

impl FiberCache {
    /// How many fibers the cache keeps (the oldest goes first).
    pub const CAPACITY: usize = 24;

    /// A fiber of `params` at 550 nm, its β table shared with a cached fiber of the same
    /// roughness when there is one.
    ///
    /// # Errors
    /// As [`Fiber::new`].
    pub fn fiber(&self, params: &FiberParams) -> Result<Fiber, woven::Error> {
        let found = {
            let fibers = self.fibers.lock().unwrap_or_else(|e| e.into_inner());
            fibers
                .iter()
                .find(|f| {
                    f.params().model == params.model
                        && f.params().normalization == params.normalization
                })
                .cloned()
        };
        if let Some(f) = found {
            return f.with_params(params);
        }
        let f = Fiber::new(params, woven::fiber::DEFAULT_WAVELENGTH_NM)?;
        let mut fibers = self.fibers.lock().unwrap_or_else(|e| e.into_inner());
        if fibers.len() >= Self::CAPACITY {
            fibers.remove(0);
        }
        fibers.push(f.clone());
        Ok(f)
    }
}

/// The microfacet baseline's specular lobe with unit weight: `F(θd; η) D(h; α) G2 / (4 cos θi
/// cos θr)`, Beckmann `D` and the library's Smith `Λ` (height-correlated `G2 = 1/(1 + Λi + Λr)`),
/// sr⁻¹. The usual analytic fit (Cook–Torrance as in Ngan et al. 2005), and the same `D` and `Λ`
/// as the fiber model's (docs/spec.md §1.1–1.2), without its extra shadowing factor and `β`.
pub fn microfacet_specular(s: Vec3, v: Vec3, alpha: f64, eta: f64) -> f64 {
    if s.z <= 0.0 || v.z <= 0.0 {
        return 0.0;
    }
    let h = (s + v).normalize();
    let lambda = |d: Vec3| {
        let sin = (1.0 - d.z * d.z).max(0.0).sqrt();
        if sin == 0.0 {
            0.0
        } else {
            smith_lambda(d.z / (sin * alpha))
        }
    };
    let g2 = 1.0 / (1.0 + lambda(s) + lambda(v));
    fresnel_dielectric(s.dot(h), eta) * beckmann_d(h.z, alpha) * g2 / (4.0 * s.z * v.z)
}

/// The prediction per channel from parts and the set's linear parameters.
#[derive(Clone, Copy, Debug)]
pub struct Linear {
    /// `ρ0` (or the baselines' diffuse albedo) per channel.
    pub diffuse: [f64; 3],
    /// `ρ` per channel.
    pub interreflection_albedo: [f64; 3],
    /// The microfacet baseline's specular weight (1 otherwise).
    pub specular: f64,
    /// The sheen baseline's colour per channel (`None` for the other models, whose parts are
    /// read the affine way; [`Parts`] for the sheen's).
    pub sheen: Option<[f64; 3]>,
    /// The overall factor.
    pub scale: f64,
}

impl Linear {
    /// The linear parameters of `set` (a microcylinder's threads' albedos in the places of
    /// `diffuse` and `interreflection_albedo`, as its [`Parts`] are laid out).
    pub fn of(set: &ParamSet) -> Self {
        let (first, second) = match set.model {
            ModelKind::Microcylinder => (Quantity::VolumeAlbedo(0), Quantity::VolumeAlbedo(1)),
            _ => (Quantity::Diffuse, Quantity::InterreflectionAlbedo),
        };
        Linear {
            diffuse: set.channels_of(first),
            interreflection_albedo: set.channels_of(second),
            specular: set.get(Quantity::Specular, 0).unwrap_or(1.0),
            sheen: (set.model == ModelKind::Sheen).then(|| set.channels_of(Quantity::SheenColor)),
            scale: set.get(Quantity::Scale, 0).unwrap_or(1.0),
        }
    }

    /// The BRDF in channel `c`.
    #[inline]
    pub fn predict(&self, p: &Parts, c: usize) -> f64 {
        match self.sheen {
            None => {
                self.scale
                    * (self.specular * p.fixed
                        + self.diffuse[c] * p.per_diffuse
                        + self.interreflection_albedo[c] * p.per_interreflection)
            }
            Some(sheen) => {
                self.scale
                    * (sheen[c] * p.fixed
                        + self.diffuse[c] * (p.per_diffuse - sheen[c] * p.per_interreflection))
            }
        }
    }

    /// `∂f/∂x` in channel `c` for a parameter the BRDF is affine in ([`Quantity::is_linear`]):
    /// `quantity` in colour channel `channel` (0 for shared ones); 0 for the others. `hbar` is
    /// the set's `ħ` (0 where it has none).
    pub fn derivative(
        &self,
        quantity: Quantity,
        channel: usize,
        p: &Parts,
        c: usize,
        hbar: f64,
    ) -> f64 {
        if let Some(sheen) = self.sheen {
            return match quantity {
                Quantity::Diffuse if channel == c => {
                    self.scale * (p.per_diffuse - sheen[c] * p.per_interreflection)
                }
                Quantity::SheenColor if channel == c => {
                    self.scale * (p.fixed - self.diffuse[c] * p.per_interreflection)
                }
                Quantity::Scale => self.predict(p, c) / self.scale,
                _ => 0.0,
            };
        }
        match quantity {
            Quantity::Diffuse | Quantity::VolumeAlbedo(0) if channel == c => {
                self.scale * p.per_diffuse
            }
            Quantity::InterreflectionAlbedo | Quantity::VolumeAlbedo(1) if channel == c => {
                self.scale * p.per_interreflection
            }
            Quantity::Specular => self.scale * p.fixed,
            Quantity::Scale => self.predict(p, c) / self.scale,
            Quantity::Interreflection => {
                // fixed and per_diffuse carry (1 − ħ); per_interreflection is ħ/π.
                let body = self.specular * p.fixed + self.diffuse[c] * p.per_diffuse;
                self.scale
                    * (-body / (1.0 - hbar)
                        + self.interreflection_albedo[c] * p.per_interreflection / hbar.max(1e-300))
            }
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use woven::material::Material;

    #[test]
    fn woven_parts_are_the_library_model_turned() {
        let set = ParamSet::new(ModelKind::Cloth, None, 1, false).unwrap();
        let material = set.material().unwrap();
        let model = material.build(550.0).unwrap();
        let prepared = Prepared::new(&set).unwrap();
        let (s, v) = (
            Vec3::from_spherical(0.5, 0.3),
            Vec3::from_spherical(0.7, 2.5),
        );
        let f = Linear::of(&set).predict(&prepared.parts(s, v), 0);
        assert!(
            (f - model.eval(s, v)).abs() <= 1e-12 * f,
            "{f} vs {}",
            model.eval(s, v)
        );
        // Rotating the weave by ψ is evaluating the unrotated cloth at azimuths − ψ.
        let mut turned = set.clone();
        turned.fix("rotation", 0.4).unwrap();
        let p = Prepared::new(&turned).unwrap();
        let (s2, v2) = (
            Vec3::from_spherical(0.5, 0.7),
            Vec3::from_spherical(0.7, 2.9),
        );
        let g = Linear::of(&turned).predict(&p.parts(s2, v2), 0);
        assert!((g - f).abs() <= 1e-9 * f, "{g} vs {f}");
        let _ = Material::preset("silk").unwrap();
    }

    #[test]
    fn sheen_parts_are_the_library_sheen_and_their_derivatives_exact() {
        use woven::baseline::{Sheen, SheenParams};
        use woven::bsdf::Bsdf;
        use woven::color::Rgb;
        let mut set = ParamSet::new(ModelKind::Sheen, None, 3, false).unwrap();
        for (name, value) in [
            ("diffuse.r", 0.6),
            ("diffuse.g", 0.3),
            ("diffuse.b", 0.1),
            ("sheen.r", 0.2),
            ("sheen.g", 0.5),
            ("sheen.b", 0.9),
            ("roughness", 0.35),
        ] {
            set.fix(name, value).unwrap();
        }
        let sheen = Sheen::new(&SheenParams {
            diffuse: Rgb([0.6, 0.3, 0.1]),
            sheen_color: Rgb([0.2, 0.5, 0.9]),
            roughness: 0.35,
        })
        .unwrap();
        let prepared = Prepared::new(&set).unwrap();
        let lin = Linear::of(&set);
        for (s, v) in [
            (
                Vec3::from_spherical(0.3, 0.0),
                Vec3::from_spherical(1.4, 2.0),
            ),
            (
                Vec3::from_spherical(1.5, 0.5),
                Vec3::from_spherical(1.3, 3.5),
            ),
        ] {
            let parts = prepared.parts(s, v);
            let f = sheen.eval(s, v);
            for c in 0..3 {
                let p = lin.predict(&parts, c);
                assert!((p - f.0[c]).abs() <= 1e-14 * f.0[c], "{p} vs {}", f.0[c]);
                // The analytic derivatives against central differences of the prediction.
                for (q, name) in [
                    (Quantity::Diffuse, "diffuse"),
                    (Quantity::SheenColor, "sheen"),
                ] {
                    let h = 1e-6;
                    let mut up = set.clone();
                    let mut down = set.clone();
                    let full = format!("{name}.{}", ["r", "g", "b"][c]);
                    let x = set.get(q, c).unwrap();
                    up.fix(&full, x + h).unwrap();
                    down.fix(&full, x - h).unwrap();
                    let fd = (Linear::of(&up).predict(&parts, c)
                        - Linear::of(&down).predict(&parts, c))
                        / (2.0 * h);
                    let d = lin.derivative(q, c, &parts, c, 0.0);
                    assert!(
                        (d - fd).abs() <= 1e-7 * fd.abs().max(1e-3),
                        "{name}: {d} vs {fd}"
                    );
                    // Another channel's parameter does not move this channel.
                    assert_eq!(lin.derivative(q, (c + 1) % 3, &parts, c, 0.0), 0.0);
                }
            }
        }
    }

    #[test]
    fn microfacet_is_reciprocal_and_its_lobe_integrates_below_one() {
        let (s, v) = (
            Vec3::from_spherical(0.5, 0.3),
            Vec3::from_spherical(0.9, 2.5),
        );
        let a = microfacet_specular(s, v, 0.3, 1.5);
        let b = microfacet_specular(v, s, 0.3, 1.5);
        assert!(a > 0.0 && (a - b).abs() < 1e-14 * a);
        // Albedo of the lobe at θi = 30° (F ≤ 1 and masking: below 1, and well above F(0) = 0.04).
        let s = Vec3::from_spherical(0.5, 0.0);
        let n = 400;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let theta = (i as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
                let phi = (j as f64 + 0.5) / n as f64 * 2.0 * std::f64::consts::PI;
                let v = Vec3::from_spherical(theta, phi);
                sum += microfacet_specular(s, v, 0.3, 1.5) * v.z * theta.sin();
            }
        }
        let albedo = sum
            * (std::f64::consts::FRAC_PI_2 / n as f64)
            * (2.0 * std::f64::consts::PI / n as f64);
        assert!(albedo > 0.03 && albedo < 0.07, "{albedo}");
    }
}
