//! The parameter registry: every quantity a fit can adjust, its bounds, its transform to the
//! optimizer's unconstrained space, and which are free.
//!
//! | model | parameters (free by default in bold) |
//! |---|---|
//! | `cloth` | `fiber.eta`, **`fiber.roughness`**, **`fiber.diffuse`**, **`yarn.lateral_length`**, **`yarn.slope_mean`**, **`yarn.slope_std`**, **`yarn.interreflection`**, **`yarn.interreflection_albedo`**, `yarn.twist_std` (free when the initial yarn is twisted), `yarn.u_max` (radians; free when the initial yarn's floats are tilted), `yarn.float_crest` and `yarn.float_flank` (free when they are tilted and shaped), `weave.weft_fraction` and `rotation` (free unless the yarn is isotropic), `scale` (free for relative data) |
//! | `fiber` | `fiber.eta`, **`fiber.roughness`**, **`fiber.diffuse`**, `scale` (free for relative data) |
//! | `lambert` | **`diffuse`** (`f = diffuse/π`) |
//! | `microfacet` | **`diffuse`**, **`specular`**, **`alpha`**, `eta` (`f = diffuse/π + specular·F·D·G/(4 cos θi cos θr)`) |
//! | `sheen` | **`diffuse`**, **`sheen`**, **`roughness`** (`f = diffuse/π·(1 − sheen·max(Ê(θi), Ê(θr))) + sheen·D·V/N`, [`woven::baseline::Sheen`]) |
//! | `microcylinder` | per thread (`thread1`, `thread2`): **`albedo`**, **`kd`**, **`gamma_s`**, **`gamma_v`** (radians), `eta`; **`coverage`** (`a_1 + a_2`), **`thread1.coverage_share`** (`a_1/(a_1 + a_2)`), `scale` (free for relative data); [`woven::microcylinder::Microcylinder`], [`crate::microcylinder`] |
//!
//! With colour data the albedos (`fiber.diffuse`, `yarn.interreflection_albedo`, the baselines'
//! `diffuse`, the sheen's `sheen` colour, the microcylinder threads' `albedo`) are one parameter per channel, named with `.r`, `.g`, `.b`; the geometry is shared.
//! `rotation` (radians) turns the weave in the sample's plane: the weft lies at azimuth
//! `rotation` in the measurement's frame. `scale` multiplies the whole BRDF (for data calibrated
//! only up to a factor; absent from the baselines, whose amplitudes are free anyway).
//!
//! Bounded parameters reach the optimizer through smooth bijections ([`Transform`]), so it works
//! unconstrained and every iterate is a valid material.

use crate::error::FitError;
use crate::microcylinder::Fabric;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use woven::fiber::{FiberModel, Ior};
use woven::material::{Material, Weave};

/// Which model is fitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ModelKind {
    /// The full woven material (fiber, yarn, weave; docs/spec.md §1–§2).
    Cloth,
    /// The fiber-surface BRDF alone (a flat fiber surface, docs/spec.md §1.3).
    Fiber,
    /// A Lambertian surface, `f = diffuse/π`.
    Lambert,
    /// Beckmann microfacet specular (Smith masking, dielectric Fresnel) plus Lambert.
    Microfacet,
    /// The Charlie sheen over a Lambertian base ([`woven::baseline::Sheen`]).
    Sheen,
    /// The microcylinder cloth model of Sadeghi et al. 2013
    /// ([`woven::microcylinder::Microcylinder`], guarded as it renders; [`crate::microcylinder`]).
    Microcylinder,
}

impl ModelKind {
    /// Every model, in the order reports list them (baselines first).
    pub const ALL: [ModelKind; 6] = [
        ModelKind::Lambert,
        ModelKind::Microfacet,
        ModelKind::Sheen,
        ModelKind::Fiber,
        ModelKind::Cloth,
        ModelKind::Microcylinder,
    ];

    /// The model's name (in reports and files, and what [`parse`](Self::parse) reads).
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Cloth => "cloth",
            ModelKind::Fiber => "fiber",
            ModelKind::Lambert => "lambert",
            ModelKind::Microfacet => "microfacet",
            ModelKind::Sheen => "sheen",
            ModelKind::Microcylinder => "microcylinder",
        }
    }

    /// Parses a model name.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming `model` for an unknown name.
    pub fn parse(name: &str) -> Result<Self, FitError> {
        ModelKind::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                FitError::invalid(
                    "model",
                    name,
                    "one of cloth, fiber, lambert, microfacet, sheen, microcylinder",
                )
            })
    }

    /// Whether the model is a woven material (written as a material file; a microcylinder fit
    /// is written as a microcylinder file).
    pub fn is_material(self) -> bool {
        matches!(self, ModelKind::Cloth | ModelKind::Fiber)
    }
}

impl std::fmt::Display for ModelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a parameter is (independent of its name and channel).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Refractive index `η` (the fiber's, or the microfacet baseline's).
    Eta,
    /// The fiber's `σ_h/τ`.
    Roughness,
    /// The fiber's diffuse albedo `ρ0`, or a baseline's Lambertian albedo (per channel).
    Diffuse,
    /// `L`.
    LateralLength,
    /// `μ`, radians.
    SlopeMean,
    /// `σ`, radians.
    SlopeStd,
    /// `ħ`.
    Interreflection,
    /// `ρ` (per channel).
    InterreflectionAlbedo,
    /// `σ_t`, radians.
    TwistStd,
    /// The floats' tilt `u_max`, radians (an extension beyond the paper; 0 = flat).
    UMax,
    /// The share of the fiber's body light in its glossy lobe.
    BodyGloss,
    /// The glossy body lobe's `σ_h/τ`.
    BodyRoughness,
    /// The share of each float lying flat on top (with `u_max > 0`).
    FloatCrest,
    /// The share of each float at its full tilt, at each end (with `u_max > 0`).
    FloatFlank,
    /// `γ`.
    WeftFraction,
    /// In-plane rotation of the weave, radians.
    Rotation,
    /// Overall factor on the BRDF.
    Scale,
    /// The microfacet baseline's specular weight.
    Specular,
    /// The microfacet baseline's Beckmann `α`.
    Alpha,
    /// The sheen baseline's colour (per channel), in `[0, 1]`.
    SheenColor,
    /// The sheen baseline's roughness (glTF's `sheenRoughness`; `α = roughness²`).
    SheenRoughness,
    /// A microcylinder thread's volume albedo `A` (per channel); thread 0 (`thread1`) or 1.
    VolumeAlbedo(usize),
    /// A microcylinder thread's isotropic share `k_d` of its volume lobe.
    VolumeShare,
    /// A microcylinder thread's surface lobe width `γ_s`, radians.
    SurfaceWidth,
    /// A microcylinder thread's volume lobe width `γ_v`, radians.
    VolumeWidth,
    /// The microcylinder threads' coverage `a_1 + a_2`.
    Coverage,
    /// Thread 1's share `a_1/(a_1 + a_2)` of the microcylinder's covered area.
    CoverageShare,
}

impl Quantity {
    /// Whether the BRDF is affine in this quantity given the others, so that its derivative
    /// comes from one evaluation's parts (no finite difference).
    pub fn is_linear(self) -> bool {
        matches!(
            self,
            Quantity::Diffuse
                | Quantity::InterreflectionAlbedo
                | Quantity::Interreflection
                | Quantity::Scale
                | Quantity::Specular
                | Quantity::SheenColor
                | Quantity::VolumeAlbedo(_)
        )
    }
}

/// How a bounded parameter maps to the optimizer's unconstrained variable `u`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transform {
    /// `x = lo + (hi − lo)·σ(u)`, `σ` the logistic function.
    Logit,
    /// `ln x = ln lo + (ln hi − ln lo)·σ(u)`: bounded, and even in log space (`lo > 0`).
    LogLogit,
    /// `x = e^u`: positive, unbounded above.
    Log,
    /// `x = u`: unbounded (angles that wrap).
    Linear,
}

/// Keeps logistic arguments away from 0 and 1, where the transform's inverse is infinite.
const EDGE: f64 = 1e-9;

fn logistic(u: f64) -> f64 {
    1.0 / (1.0 + (-u).exp())
}

/// One parameter of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// Its name in [`ParamSet::fix`], [`ParamSet::free`] and reports (`fiber.roughness`,
    /// `fiber.diffuse.g`).
    pub name: String,
    /// What it is.
    pub quantity: Quantity,
    /// The colour channel (0, 1, 2) of a per-channel albedo; 0 otherwise.
    pub channel: usize,
    /// Its value, natural units.
    pub value: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Map to the unconstrained variable.
    pub transform: Transform,
    /// Whether the fit adjusts it.
    pub free: bool,
    /// The range the multi-start draws from (log-uniformly for logarithmic transforms).
    pub start: (f64, f64),
}

impl Param {
    /// The unconstrained variable of a natural value (clamped inside the bounds).
    pub fn to_u(&self, x: f64) -> f64 {
        match self.transform {
            Transform::Logit => {
                let t = ((x - self.lo) / (self.hi - self.lo)).clamp(EDGE, 1.0 - EDGE);
                (t / (1.0 - t)).ln()
            }
            Transform::LogLogit => {
                let (a, b) = (self.lo.ln(), self.hi.ln());
                let t = ((x.max(self.lo).ln() - a) / (b - a)).clamp(EDGE, 1.0 - EDGE);
                (t / (1.0 - t)).ln()
            }
            Transform::Log => x.max(1e-300).ln(),
            Transform::Linear => x,
        }
    }

    /// The natural value of an unconstrained variable (always within the bounds).
    pub fn from_u(&self, u: f64) -> f64 {
        match self.transform {
            Transform::Logit => {
                let t = logistic(u).clamp(EDGE, 1.0 - EDGE);
                self.lo + (self.hi - self.lo) * t
            }
            Transform::LogLogit => {
                let (a, b) = (self.lo.ln(), self.hi.ln());
                let t = logistic(u).clamp(EDGE, 1.0 - EDGE);
                (a + (b - a) * t).exp()
            }
            Transform::Log => u.clamp(-700.0, 700.0).exp(),
            Transform::Linear => u,
        }
    }

    /// `dx/du` at `u`.
    pub fn dx_du(&self, u: f64) -> f64 {
        match self.transform {
            Transform::Logit => {
                let t = logistic(u);
                (self.hi - self.lo) * t * (1.0 - t)
            }
            Transform::LogLogit => {
                let t = logistic(u);
                self.from_u(u) * (self.hi.ln() - self.lo.ln()) * t * (1.0 - t)
            }
            Transform::Log => self.from_u(u),
            Transform::Linear => 1.0,
        }
    }

    /// A point of the start range at fraction `t ∈ [0, 1)` (log-uniform for logarithmic
    /// transforms).
    pub fn start_at(&self, t: f64) -> f64 {
        let (a, b) = self.start;
        match self.transform {
            Transform::Log | Transform::LogLogit if a > 0.0 => {
                (a.ln() + (b.ln() - a.ln()) * t).exp()
            }
            _ => a + (b - a) * t,
        }
    }

    /// The name without its channel suffix.
    pub fn base_name(&self) -> &str {
        match self.name.rsplit_once('.') {
            Some((base, "r" | "g" | "b")) => base,
            _ => &self.name,
        }
    }

    /// Whether a user's name (`roughness`, `fiber.roughness`, `diffuse`, `fiber.diffuse.r`)
    /// refers to this parameter.
    pub fn matches(&self, query: &str) -> bool {
        let dotted = format!(".{query}");
        let base = self.base_name();
        self.name == query
            || self.name.ends_with(&dotted)
            || base == query
            || base.ends_with(&dotted)
    }

    /// Whether the value sits at (within 0.1 % of the range of) a finite bound.
    pub fn at_bound(&self) -> bool {
        match self.transform {
            Transform::Logit | Transform::LogLogit => {
                let tol = 1e-3 * (self.hi - self.lo);
                self.value - self.lo < tol || self.hi - self.value < tol
            }
            Transform::Log | Transform::Linear => false,
        }
    }
}

/// The channels' suffixes.
const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// One row of a model's parameter table: everything [`ParamSet::new`] needs to make the
/// parameter, and [`ParamSet::material`] to put its value back into a material.
#[derive(Clone, Copy)]
pub(crate) struct Spec {
    /// The name in [`ParamSet::fix`], [`ParamSet::free`] and reports.
    pub(crate) name: &'static str,
    /// What it is.
    pub(crate) quantity: Quantity,
    /// One parameter per colour channel (`.r`, `.g`, `.b`) for colour data.
    pub(crate) per_channel: bool,
    /// `(lo, hi)`, natural units.
    pub(crate) bounds: (f64, f64),
    /// The map to the optimizer's variable.
    pub(crate) transform: Transform,
    /// The multi-start's range.
    pub(crate) start: (f64, f64),
    /// Where the initial value comes from and the fitted value goes.
    pub(crate) home: Home,
    /// Whether the fit adjusts it unless told otherwise.
    pub(crate) free: FreeBy,
}

/// Where a parameter's initial value comes from, and where its fitted value goes.
#[derive(Clone, Copy)]
pub(crate) enum Home {
    /// The fit's own (a baseline's parameter, `rotation`, `scale`): it starts at this value and
    /// has no place in a material file.
    Own(f64),
    /// A quantity of the initial material: `read` gives the initial value (`None` where the
    /// material has no such quantity, and so the fit has no such parameter: an isotropic yarn
    /// has no twist); `write` sets the fitted value (the channels' mean), given whether the fit
    /// adjusted it, into the fitted material.
    Material {
        read: fn(&Material) -> Option<f64>,
        write: fn(&mut Material, f64, bool),
    },
    /// A quantity of the initial microcylinder fabric: `read` gives its value per channel (a
    /// scalar in each), `write` sets the fitted values (a scalar from the first).
    Fabric {
        read: fn(&Fabric) -> [f64; 3],
        write: fn(&mut Fabric, [f64; 3]),
    },
}

/// When a parameter is free unless the caller fixes or frees it.
#[derive(Clone, Copy)]
pub(crate) enum FreeBy {
    /// Always free.
    Always,
    /// Always held.
    Never,
    /// Free for data calibrated only up to a factor.
    Relative,
    /// Free when the initial yarn is twisted (`twist_std > 0`).
    Twisted,
    /// Free unless the initial yarn is isotropic (whose BRDF turns with nothing).
    Anisotropic,
    /// Free when the initial yarn's floats are tilted (`u_max > 0`).
    Tilted,
    /// Free when the initial yarn's floats are tilted and shaped (a crest or flanks).
    Shaped,
    /// Free when the initial fiber has a glossy body (`body_gloss > 0`).
    Glossy,
}

/// The fiber's `η`: its value at the default wavelength; a fixed Cauchy index stays
/// dispersive, a fitted one becomes a constant.
const FIBER_ETA: Spec = Spec {
    name: "fiber.eta",
    quantity: Quantity::Eta,
    per_channel: false,
    bounds: (1.01, 3.0),
    transform: Transform::Logit,
    start: (1.3, 1.8),
    home: Home::Material {
        read: |m| Some(m.fiber.eta.at(woven::fiber::DEFAULT_WAVELENGTH_NM)),
        write: |m, eta, free| {
            if free || matches!(m.fiber.eta, Ior::Constant(_)) {
                m.fiber.eta = Ior::Constant(eta);
            }
        },
    },
    free: FreeBy::Never,
};

/// The fiber's `σ_h/τ` (the fitted material's fiber is the rough limit).
const FIBER_ROUGHNESS: Spec = Spec {
    name: "fiber.roughness",
    quantity: Quantity::Roughness,
    per_channel: false,
    bounds: (0.005, 2.0),
    transform: Transform::LogLogit,
    start: (0.02, 0.6),
    home: Home::Material {
        read: |m| Some(m.fiber.model.roughness()),
        write: |m, roughness, _| m.fiber.model = FiberModel::Rough { roughness },
    },
    free: FreeBy::Always,
};

/// The fiber's diffuse albedo `ρ0`.
const FIBER_DIFFUSE: Spec = Spec {
    name: "fiber.diffuse",
    quantity: Quantity::Diffuse,
    per_channel: true,
    bounds: (0.0, 0.99),
    transform: Transform::Logit,
    start: (0.01, 0.8),
    home: Home::Material {
        read: |m| Some(m.fiber.diffuse),
        write: |m, diffuse, _| m.fiber.diffuse = diffuse,
    },
    free: FreeBy::Always,
};

/// The share of the fiber's body light in its glossy lobe (an extension beyond the paper).
const FIBER_BODY_GLOSS: Spec = Spec {
    name: "fiber.body_gloss",
    quantity: Quantity::BodyGloss,
    per_channel: false,
    bounds: (0.0, 1.0),
    transform: Transform::Logit,
    start: (0.2, 0.95),
    home: Home::Material {
        read: |m| (m.fiber.body_gloss > 0.0).then_some(m.fiber.body_gloss),
        write: |m, g, _| m.fiber.body_gloss = g,
    },
    free: FreeBy::Glossy,
};

/// The roughness of the fiber's glossy body lobe.
const FIBER_BODY_ROUGHNESS: Spec = Spec {
    name: "fiber.body_roughness",
    quantity: Quantity::BodyRoughness,
    per_channel: false,
    bounds: (woven::fiber::ROUGHNESS_MIN, woven::fiber::ROUGHNESS_MAX),
    transform: Transform::LogLogit,
    start: (0.02, 0.5),
    home: Home::Material {
        read: |m| (m.fiber.body_gloss > 0.0).then_some(m.fiber.body_roughness),
        write: |m, r, _| m.fiber.body_roughness = r,
    },
    free: FreeBy::Glossy,
};

/// The factor on the whole BRDF.
pub(crate) const SCALE: Spec = Spec {
    name: "scale",
    quantity: Quantity::Scale,
    per_channel: false,
    bounds: (0.0, f64::INFINITY),
    transform: Transform::Log,
    start: (0.3, 3.0),
    home: Home::Own(1.0),
    free: FreeBy::Relative,
};

/// A row for a field of the yarn, free by default: `yarn_spec!(name, quantity, field,
/// per_channel, bounds, transform, start)`.
macro_rules! yarn_spec {
    ($name:literal, $quantity:ident, $field:ident, $per_channel:literal, $bounds:expr,
     $transform:ident, $start:expr) => {
        Spec {
            name: $name,
            quantity: Quantity::$quantity,
            per_channel: $per_channel,
            bounds: $bounds,
            transform: Transform::$transform,
            start: $start,
            home: Home::Material {
                read: |m| m.yarn.map(|y| y.$field),
                write: |m, value, _| {
                    if let Some(y) = m.yarn.as_mut() {
                        y.$field = value;
                    }
                },
            },
            free: FreeBy::Always,
        }
    };
}

/// `lambert`: `f = diffuse/π`.
const LAMBERT: &[Spec] = &[Spec {
    name: "diffuse",
    quantity: Quantity::Diffuse,
    per_channel: true,
    bounds: (0.0, f64::INFINITY),
    transform: Transform::Log,
    start: (0.02, 1.0),
    home: Home::Own(0.5),
    free: FreeBy::Always,
}];

/// `microfacet`: `f = diffuse/π + specular·F·D·G/(4 cos θi cos θr)`.
const MICROFACET: &[Spec] = &[
    Spec {
        name: "diffuse",
        quantity: Quantity::Diffuse,
        per_channel: true,
        bounds: (0.0, f64::INFINITY),
        transform: Transform::Log,
        start: (0.01, 1.0),
        home: Home::Own(0.3),
        free: FreeBy::Always,
    },
    Spec {
        name: "specular",
        quantity: Quantity::Specular,
        per_channel: false,
        bounds: (0.0, f64::INFINITY),
        transform: Transform::Log,
        start: (0.01, 3.0),
        home: Home::Own(0.3),
        free: FreeBy::Always,
    },
    Spec {
        name: "alpha",
        quantity: Quantity::Alpha,
        per_channel: false,
        bounds: (0.005, 4.0),
        transform: Transform::LogLogit,
        start: (0.02, 1.0),
        home: Home::Own(0.3),
        free: FreeBy::Always,
    },
    Spec {
        name: "eta",
        quantity: Quantity::Eta,
        per_channel: false,
        bounds: (1.01, 3.0),
        transform: Transform::Logit,
        start: (1.3, 1.8),
        home: Home::Own(1.5),
        free: FreeBy::Never,
    },
];

/// `sheen`: `f = diffuse/π·(1 − sheen·max(Ê(θi), Ê(θr))) + sheen·D·V/N`, the Charlie sheen of
/// [`woven::baseline::Sheen`]. `sheen` stays in `[0, 1]`, where the base's factor stays
/// non-negative; `roughness` in the library's `[0.1, 1]`.
const SHEEN: &[Spec] = &[
    Spec {
        name: "diffuse",
        quantity: Quantity::Diffuse,
        per_channel: true,
        bounds: (0.0, f64::INFINITY),
        transform: Transform::Log,
        start: (0.01, 1.0),
        home: Home::Own(0.3),
        free: FreeBy::Always,
    },
    Spec {
        name: "sheen",
        quantity: Quantity::SheenColor,
        per_channel: true,
        bounds: (0.0, 1.0),
        transform: Transform::Logit,
        start: (0.02, 0.98),
        home: Home::Own(0.5),
        free: FreeBy::Always,
    },
    Spec {
        name: "roughness",
        quantity: Quantity::SheenRoughness,
        per_channel: false,
        bounds: (woven::baseline::MIN_SHEEN_ROUGHNESS, 1.0),
        transform: Transform::Logit,
        start: (0.15, 0.95),
        home: Home::Own(0.5),
        free: FreeBy::Always,
    },
];

/// `fiber`: the flat fiber surface.
const FIBER: &[Spec] = &[FIBER_ETA, FIBER_ROUGHNESS, FIBER_DIFFUSE, SCALE];

/// `cloth`: the fiber, the yarn, the weave and its turn in the sample plane.
const CLOTH: &[Spec] = &[
    FIBER_ETA,
    FIBER_ROUGHNESS,
    FIBER_BODY_GLOSS,
    FIBER_BODY_ROUGHNESS,
    FIBER_DIFFUSE,
    yarn_spec!(
        "yarn.lateral_length",
        LateralLength,
        lateral_length,
        false,
        (0.01, 100.0),
        LogLogit,
        (0.1, 20.0)
    ),
    yarn_spec!(
        "yarn.slope_mean",
        SlopeMean,
        slope_mean,
        false,
        (0.0, FRAC_PI_2 - 1e-3),
        Logit,
        (0.0, 1.2)
    ),
    yarn_spec!(
        "yarn.slope_std",
        SlopeStd,
        slope_std,
        false,
        (0.0, PI),
        Logit,
        (0.05, 1.5)
    ),
    yarn_spec!(
        "yarn.interreflection",
        Interreflection,
        interreflection,
        false,
        (0.0, 0.999),
        Logit,
        (0.0, 0.8)
    ),
    yarn_spec!(
        "yarn.interreflection_albedo",
        InterreflectionAlbedo,
        interreflection_albedo,
        true,
        (0.0, 1.0),
        Logit,
        (0.05, 0.95)
    ),
    Spec {
        name: "yarn.twist_std",
        quantity: Quantity::TwistStd,
        per_channel: false,
        bounds: (0.0, PI),
        transform: Transform::Logit,
        start: (0.05, 1.0),
        home: Home::Material {
            // An isotropic yarn has no twist to fit.
            read: |m| m.yarn.filter(|y| !y.isotropic).map(|y| y.twist_std),
            write: |m, twist_std, _| {
                if let Some(y) = m.yarn.as_mut() {
                    y.twist_std = twist_std;
                }
            },
        },
        free: FreeBy::Twisted,
    },
    Spec {
        name: "yarn.u_max",
        quantity: Quantity::UMax,
        per_channel: false,
        bounds: (0.0, 1.3962634015954636), // 80°, the surface's MAX_U_MAX_DEG
        transform: Transform::Logit,
        start: (0.05, 0.7),
        home: Home::Material {
            // Only a material whose floats are tilted has the extension to fit.
            read: |m| m.yarn.filter(|y| y.u_max > 0.0).map(|y| y.u_max),
            write: |m, u_max, _| {
                if let Some(y) = m.yarn.as_mut() {
                    y.u_max = u_max;
                }
            },
        },
        free: FreeBy::Tilted,
    },
    Spec {
        name: "yarn.float_crest",
        quantity: Quantity::FloatCrest,
        per_channel: false,
        bounds: (0.0, woven::yarn::MAX_FLOAT_SHAPE),
        transform: Transform::Logit,
        start: (0.05, 0.6),
        home: Home::Material {
            read: |m| m.yarn.filter(|y| y.u_max > 0.0).map(|y| y.float_crest),
            write: |m, crest, _| {
                if let Some(y) = m.yarn.as_mut() {
                    y.float_crest = crest;
                }
            },
        },
        free: FreeBy::Shaped,
    },
    Spec {
        name: "yarn.float_flank",
        quantity: Quantity::FloatFlank,
        per_channel: false,
        bounds: (0.0, woven::yarn::MAX_FLOAT_SHAPE / 2.0),
        transform: Transform::Logit,
        start: (0.02, 0.3),
        home: Home::Material {
            read: |m| m.yarn.filter(|y| y.u_max > 0.0).map(|y| y.float_flank),
            // The crest is written first; the flanks yield to it (crest + 2 flank ≤ 0.9).
            write: |m, flank, _| {
                if let Some(y) = m.yarn.as_mut() {
                    y.float_flank = flank.min(0.5 * (woven::yarn::MAX_FLOAT_SHAPE - y.float_crest));
                }
            },
        },
        free: FreeBy::Shaped,
    },
    Spec {
        name: "weave.weft_fraction",
        quantity: Quantity::WeftFraction,
        per_channel: false,
        bounds: (0.0, 1.0),
        transform: Transform::Logit,
        start: (0.0, 1.0),
        home: Home::Material {
            read: |m| Some(m.weft_fraction()),
            write: |m, gamma, free| {
                // A weave pattern stays when its γ was not fitted.
                let keep = matches!(m.weave, Some(Weave::Pattern { .. }))
                    && !free
                    && (gamma - m.weft_fraction()).abs() < 1e-12;
                if !keep {
                    m.weave = Some(Weave::WeftFraction(gamma));
                }
            },
        },
        free: FreeBy::Anisotropic,
    },
    Spec {
        name: "rotation",
        quantity: Quantity::Rotation,
        per_channel: false,
        bounds: (-PI, PI),
        transform: Transform::Linear,
        start: (-FRAC_PI_4, FRAC_PI_4),
        home: Home::Own(0.0),
        free: FreeBy::Anisotropic,
    },
    SCALE,
];

/// The parameter table of `model`, in the order of [`ParamSet::params`].
fn specs(model: ModelKind) -> &'static [Spec] {
    match model {
        ModelKind::Lambert => LAMBERT,
        ModelKind::Microfacet => MICROFACET,
        ModelKind::Sheen => SHEEN,
        ModelKind::Fiber => FIBER,
        ModelKind::Cloth => CLOTH,
        ModelKind::Microcylinder => crate::microcylinder::SPECS,
    }
}

/// The initial material of `model` (`None` for the baselines), checked for what the fitter
/// needs.
fn template(model: ModelKind, init: Option<&Material>) -> Result<Option<Material>, FitError> {
    if let (ModelKind::Microcylinder, Some(m)) = (model, init) {
        return Err(FitError::invalid(
            "init",
            m.name.as_deref().unwrap_or("(a material)"),
            "a microcylinder fabric for model microcylinder (a preset microcylinder-…, or a file \
             with model = \"microcylinder\"; `ParamSet::microcylinder`), not a woven material",
        ));
    }
    if !model.is_material() {
        return match init {
            Some(m) => Err(FitError::invalid(
                "init",
                m.name.as_deref().unwrap_or("(a material)"),
                format!(
                    "no initial material for model {model}: it is not a woven material (its \
                     parameters start at their defaults, or at the values given to `fix`)"
                ),
            )),
            None => Ok(None),
        };
    }
    let m = match init {
        Some(m) => m.clone(),
        None => Material::preset(DEFAULT_CLOTH_INIT)?,
    };
    if let FiberModel::Htsg { .. } = m.fiber.model {
        return Err(FitError::invalid(
            "fiber.model",
            "\"htsg\"",
            "an initial material with model = \"rough\" (the fitter adjusts σ_h/τ)",
        ));
    }
    if model == ModelKind::Cloth && m.yarn.is_none() {
        return Err(FitError::invalid(
            "init",
            m.name.as_deref().unwrap_or("(material)"),
            "a material with a [yarn] table for model cloth (or model fiber)",
        ));
    }
    Ok(Some(m))
}

/// The parameters of one fit: the model, every parameter (free and fixed) and, for the woven
/// models, the material everything not fitted comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSet {
    /// The model.
    pub model: ModelKind,
    /// Every parameter, in a fixed order.
    pub params: Vec<Param>,
    /// Colour channels of the data (1 or 3).
    pub channels: usize,
    /// For `cloth` and `fiber`: the initial material (its fiber model, normalization, yarn kind
    /// and weave pattern are kept).
    pub template: Option<Material>,
    /// For `microcylinder`: the initial fabric (its tangent curves are kept) and the energy
    /// guard held during a fit ([`crate::microcylinder`]).
    pub fabric: Option<Fabric>,
}

/// The initial material of a `cloth` or `fiber` fit when none is given: the twisted belt cloth.
pub const DEFAULT_CLOTH_INIT: &str = "belt-cloth";

impl ParamSet {
    /// The parameters of `model` for data with `channels` colour channels (1 or 3), starting at
    /// `init` (`cloth` and `fiber`: a material; `None` takes the belt-cloth preset; the baselines
    /// take no material; `microcylinder` takes none either and starts at its default fabric:
    /// [`ParamSet::microcylinder`] takes another). `relative`: the data is calibrated only up to a factor, so `scale` is
    /// free. The model's table of parameter specs gives every parameter.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] for `channels` other than 1 or 3, for a material the fitter
    /// cannot use (an `htsg` fiber, a flat surface for `cloth`), or for `init` given to a baseline.
    pub fn new(
        model: ModelKind,
        init: Option<&Material>,
        channels: usize,
        relative: bool,
    ) -> Result<Self, FitError> {
        if model == ModelKind::Microcylinder && init.is_none() {
            return ParamSet::microcylinder(None, channels, relative);
        }
        let template = template(model, init)?;
        ParamSet::with_templates(model, template, None, channels, relative)
    }

    /// [`new`](Self::new) from its initial material or fabric (checked by the caller).
    pub(crate) fn with_templates(
        model: ModelKind,
        template: Option<Material>,
        fabric: Option<Fabric>,
        channels: usize,
        relative: bool,
    ) -> Result<Self, FitError> {
        if channels != 1 && channels != 3 {
            return Err(FitError::invalid(
                "channels",
                channels,
                "1 (single-channel data) or 3 (RGB)",
            ));
        }
        let yarn = template.as_ref().and_then(|m| m.yarn);
        let mut params = Vec::new();
        for spec in specs(model) {
            // A fabric's value per channel; one value (the channels' mean) for mono data.
            let per_channel = match (spec.home, fabric.as_ref()) {
                (Home::Fabric { read, .. }, Some(f)) => Some(read(f)),
                (Home::Fabric { .. }, None) => continue,
                _ => None,
            };
            let value = match spec.home {
                Home::Own(value) => value,
                Home::Fabric { .. } => match per_channel {
                    Some(v) if spec.per_channel => (v[0] + v[1] + v[2]) / 3.0,
                    Some(v) => v[0],
                    None => continue,
                },
                Home::Material { read, .. } => match template.as_ref().and_then(read) {
                    Some(value) => value,
                    // The material has no such quantity (an isotropic yarn has no twist).
                    None => continue,
                },
            };
            let free = match spec.free {
                FreeBy::Always => true,
                FreeBy::Never => false,
                FreeBy::Relative => relative,
                FreeBy::Twisted => yarn.is_some_and(|y| y.twist_std > 0.0),
                FreeBy::Anisotropic => yarn.is_some_and(|y| !y.isotropic),
                FreeBy::Tilted => yarn.is_some_and(|y| y.u_max > 0.0),
                FreeBy::Glossy => template.as_ref().is_some_and(|m| m.fiber.body_gloss > 0.0),
                FreeBy::Shaped => yarn
                    .is_some_and(|y| y.u_max > 0.0 && (y.float_crest > 0.0 || y.float_flank > 0.0)),
            };
            let param = Param {
                name: spec.name.to_string(),
                quantity: spec.quantity,
                channel: 0,
                value,
                lo: spec.bounds.0,
                hi: spec.bounds.1,
                transform: spec.transform,
                free,
                start: spec.start,
            };
            if spec.per_channel && channels == 3 {
                for (channel, suffix) in CHANNELS.iter().enumerate() {
                    params.push(Param {
                        name: format!("{}.{suffix}", spec.name),
                        channel,
                        value: per_channel.map_or(value, |v| v[channel]),
                        ..param.clone()
                    });
                }
            } else {
                params.push(param);
            }
        }
        Ok(ParamSet {
            model,
            params,
            channels,
            template,
            fabric,
        })
    }

    /// The parameters' names, comma-separated (for messages).
    pub fn names(&self) -> String {
        let mut names: Vec<&str> = Vec::new();
        for p in &self.params {
            if !names.contains(&p.base_name()) {
                names.push(p.base_name());
            }
        }
        names.join(", ")
    }

    fn matching(&self, name: &str) -> Result<Vec<usize>, FitError> {
        let hits: Vec<usize> = (0..self.params.len())
            .filter(|&i| self.params[i].matches(name))
            .collect();
        if hits.is_empty() {
            return Err(FitError::UnknownParameter {
                name: name.to_string(),
                model: self.model.name().to_string(),
                known: self.names(),
            });
        }
        let first = self.params[hits[0]].base_name();
        if hits.iter().any(|&i| self.params[i].base_name() != first) {
            return Err(FitError::invalid(
                name,
                "(ambiguous)",
                format!("one of the full names: {}", self.names()),
            ));
        }
        Ok(hits)
    }

    /// Sets the parameter (every channel of a per-channel one) and holds it.
    ///
    /// # Errors
    /// [`FitError::UnknownParameter`], or [`FitError::InvalidParameter`] for a value outside
    /// the parameter's range.
    pub fn fix(&mut self, name: &str, value: f64) -> Result<(), FitError> {
        for i in self.matching(name)? {
            let p = &mut self.params[i];
            // A log-scaled parameter (a scale, a roughness) never reaches its lower bound.
            let open = p.transform == Transform::Log;
            if !value.is_finite() || value < p.lo || (open && value <= p.lo) || value > p.hi {
                let lo = if open { "(" } else { "[" };
                return Err(FitError::invalid(
                    &p.name,
                    value,
                    format!("a finite value in {lo}{}, {}]", p.lo, p.hi),
                ));
            }
            p.value = value;
            p.free = false;
        }
        Ok(())
    }

    /// Parses and applies `name=value` text with [`fix`](Self::fix).
    ///
    /// # Errors
    /// As [`fix`](Self::fix), and for text that is not `name=number`.
    pub fn fix_arg(&mut self, arg: &str) -> Result<(), FitError> {
        let Some((name, value)) = arg.split_once('=') else {
            return Err(FitError::invalid(
                "fix",
                arg,
                "name=value, e.g. fiber.roughness=0.1",
            ));
        };
        let v: f64 = value
            .trim()
            .parse()
            .map_err(|_| FitError::invalid(name.trim(), value, "a number"))?;
        self.fix(name.trim(), v)
    }

    /// Lets the fit adjust the parameter (every channel). A value sitting on a bound (a twist of
    /// 0, say) moves to the middle of its start range, where it can move.
    ///
    /// # Errors
    /// [`FitError::UnknownParameter`].
    pub fn free(&mut self, name: &str) -> Result<(), FitError> {
        for i in self.matching(name)? {
            let p = &mut self.params[i];
            p.free = true;
            if p.at_bound() {
                p.value = p.start_at(0.5);
            }
        }
        Ok(())
    }

    /// Indices of the free parameters.
    pub fn free_indices(&self) -> Vec<usize> {
        (0..self.params.len())
            .filter(|&i| self.params[i].free)
            .collect()
    }

    /// The value of `q` in `channel` (a per-channel quantity with one channel answers channel 0);
    /// `None` if the model has no such parameter.
    pub fn get(&self, q: Quantity, channel: usize) -> Option<f64> {
        let mut found = None;
        for p in &self.params {
            if p.quantity == q {
                if p.channel == channel {
                    return Some(p.value);
                }
                found.get_or_insert(p.value);
            }
        }
        found
    }

    /// The per-channel values of a quantity (`[x; 3]` for a shared one), or zeros.
    pub fn channels_of(&self, q: Quantity) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            *o = self.get(q, c).unwrap_or(0.0);
        }
        out
    }

    /// The fitted material (`cloth` and `fiber`), its albedos the mean over the channels (the
    /// material file holds one value each). `rotation` and `scale` have no place in a material
    /// file: [`crate::FitResult`] reports them. `None` for the baselines.
    pub fn material(&self) -> Option<Material> {
        let mut m = self.template.clone()?;
        if self.model == ModelKind::Fiber {
            m.yarn = None;
            m.weave = None;
        }
        for spec in specs(self.model) {
            let Home::Material { write, .. } = spec.home else {
                continue;
            };
            let mut params = self.params.iter().filter(|p| p.quantity == spec.quantity);
            let Some(first) = params.next() else {
                continue; // a quantity the material does not have
            };
            let value = if spec.per_channel {
                let v = self.channels_of(spec.quantity);
                (v[0] + v[1] + v[2]) / 3.0
            } else {
                first.value
            };
            write(&mut m, value, first.free);
        }
        Some(m)
    }

    /// The unconstrained variables of the free parameters.
    pub fn free_u(&self) -> Vec<f64> {
        self.free_indices()
            .into_iter()
            .map(|i| self.params[i].to_u(self.params[i].value))
            .collect()
    }

    /// Sets the free parameters from their unconstrained variables (in [`free_indices`] order).
    ///
    /// [`free_indices`]: Self::free_indices
    pub fn set_free_u(&mut self, u: &[f64]) {
        for (k, i) in self.free_indices().into_iter().enumerate() {
            let p = &mut self.params[i];
            p.value = p.from_u(u[k]);
        }
    }

    /// Puts the result in its canonical form: the rotation in `[−π/4, π/4)`, trading quarter
    /// turns for `γ ↔ 1 − γ` (the weft turned by 90° is the warp), when both are parameters.
    pub fn canonicalize(&mut self) {
        let Some(ir) = self
            .params
            .iter()
            .position(|p| p.quantity == Quantity::Rotation)
        else {
            return;
        };
        let gi = self
            .params
            .iter()
            .position(|p| p.quantity == Quantity::WeftFraction);
        let mut rot = self.params[ir].value;
        // f is π-periodic in the rotation (a yarn axis has no sense).
        rot = (rot + FRAC_PI_2).rem_euclid(PI) - FRAC_PI_2;
        if let Some(gi) = gi {
            if !(-FRAC_PI_4..FRAC_PI_4).contains(&rot) {
                rot -= FRAC_PI_2 * rot.signum();
                let g = &mut self.params[gi];
                g.value = 1.0 - g.value;
            }
        }
        self.params[ir].value = rot;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transforms_round_trip_and_stay_in_bounds() {
        let set = ParamSet::new(ModelKind::Cloth, None, 3, true).unwrap();
        for p in &set.params {
            for &x in &[p.start.0, p.start_at(0.37), p.start.1] {
                let back = p.from_u(p.to_u(x));
                assert!(
                    (back - x).abs() <= 1e-6 * (1.0 + x.abs()),
                    "{}: {x} → {back}",
                    p.name
                );
                // dx/du by a central difference.
                let u = p.to_u(x);
                let fd = (p.from_u(u + 1e-6) - p.from_u(u - 1e-6)) / 2e-6;
                assert!(
                    (fd - p.dx_du(u)).abs() <= 1e-5 * (1.0 + fd.abs()),
                    "{}: {fd} vs {}",
                    p.name,
                    p.dx_du(u)
                );
            }
            for u in [-1e3, -30.0, 0.0, 30.0, 1e3] {
                if p.transform == Transform::Linear {
                    continue; // the rotation wraps; it has no bounds to keep
                }
                let x = p.from_u(u);
                assert!(
                    x >= p.lo && x <= p.hi && x.is_finite(),
                    "{} at u {u}: {x}",
                    p.name
                );
            }
        }
    }

    #[test]
    fn defaults_follow_the_yarn_and_the_data() {
        let belt = ParamSet::new(ModelKind::Cloth, None, 1, false).unwrap();
        let free: Vec<&str> = belt
            .free_indices()
            .iter()
            .map(|&i| belt.params[i].name.as_str())
            .collect();
        assert!(
            free.contains(&"yarn.twist_std") && free.contains(&"rotation"),
            "{free:?}"
        );
        assert!(
            !free.contains(&"scale") && !free.contains(&"fiber.eta"),
            "{free:?}"
        );
        let silk = Material::preset("silk").unwrap();
        let iso = ParamSet::new(ModelKind::Cloth, Some(&silk), 3, true).unwrap();
        assert!(iso.params.iter().all(|p| p.quantity != Quantity::TwistStd));
        let free: Vec<&str> = iso
            .free_indices()
            .iter()
            .map(|&i| iso.params[i].name.as_str())
            .collect();
        assert!(
            !free.contains(&"rotation")
                && free.contains(&"scale")
                && free.contains(&"fiber.diffuse.b"),
            "{free:?}"
        );
    }

    #[test]
    fn fix_and_free_by_short_and_full_names() {
        let mut set = ParamSet::new(ModelKind::Cloth, None, 3, false).unwrap();
        set.fix_arg("roughness=0.3").unwrap();
        assert_eq!(set.get(Quantity::Roughness, 0), Some(0.3));
        set.fix("fiber.diffuse", 0.2).unwrap();
        assert_eq!(set.channels_of(Quantity::Diffuse), [0.2; 3]);
        set.free("diffuse.g").unwrap();
        let d: Vec<bool> = set
            .params
            .iter()
            .filter(|p| p.quantity == Quantity::Diffuse)
            .map(|p| p.free)
            .collect();
        assert_eq!(d, [false, true, false]);
        // Errors name the parameter, the value and the range.
        let e = set.fix_arg("roughness=7").unwrap_err().to_string();
        assert!(
            e.contains("fiber.roughness") && e.contains('7') && e.contains("[0.005, 2]"),
            "{e}"
        );
        let e = set.fix_arg("nonsense=1").unwrap_err().to_string();
        assert!(
            e.contains("nonsense") && e.contains("yarn.slope_std"),
            "{e}"
        );
        assert!(set.fix_arg("roughness").is_err() && set.fix_arg("roughness=abc").is_err());
        // A twist of 0 freed moves off its bound.
        let mut sateen = ParamSet::new(
            ModelKind::Cloth,
            Some(&Material::preset("polyester-sateen").unwrap()),
            1,
            false,
        )
        .unwrap();
        sateen.free("twist_std").unwrap();
        assert!(sateen.get(Quantity::TwistStd, 0).unwrap() > 0.1);
    }

    #[test]
    fn the_material_carries_the_values_and_builds() {
        let mut set = ParamSet::new(ModelKind::Cloth, None, 3, false).unwrap();
        set.fix("yarn.slope_std", 0.7).unwrap();
        set.fix("fiber.diffuse.r", 0.3).unwrap();
        let m = set.material().unwrap();
        assert_eq!(m.yarn.unwrap().slope_std, 0.7);
        assert!((m.fiber.diffuse - (0.3 + 0.1 + 0.1) / 3.0).abs() < 1e-12);
        m.build(550.0).unwrap();
        // The file reads back as the same material.
        let back = Material::from_toml_str(&m.to_toml_string(), "fitted.toml").unwrap();
        assert_eq!(back, m);
        assert!(ParamSet::new(ModelKind::Lambert, Some(&m), 1, false).is_err());
    }

    #[test]
    fn new_refuses_what_it_cannot_use_without_panicking() {
        let preset = |name| Some(Material::preset(name).unwrap());
        let mut htsg = Material::preset("silk").unwrap();
        htsg.fiber.model = FiberModel::Htsg {
            sigma_h_um: 0.1,
            tau_um: 1.0,
        };
        let flat = Material::flat(woven::fiber::FiberParams::rough(1.5, 0.1, 0.1));
        let inits = [
            None,
            preset("belt-cloth"),
            preset("silk"),
            preset("polyester-sateen"),
            Some(flat),
            Some(htsg),
        ];
        for model in ModelKind::ALL {
            for channels in 0..6 {
                for (k, init) in inits.iter().enumerate() {
                    let usable = match init {
                        None => true,
                        Some(m) => {
                            model.is_material()
                                && !matches!(m.fiber.model, FiberModel::Htsg { .. })
                                && (model == ModelKind::Fiber || m.yarn.is_some())
                        }
                    };
                    let want = usable && (channels == 1 || channels == 3);
                    match ParamSet::new(model, init.as_ref(), channels, k % 2 == 0) {
                        Ok(set) => {
                            assert!(want, "{model}, {channels} channels, init {k}: accepted");
                            assert_eq!(set.material().is_some(), model.is_material());
                            for p in &set.params {
                                assert!(p.value.is_finite() && p.lo <= p.value && p.value <= p.hi);
                            }
                        }
                        Err(e) => {
                            let e = e.to_string();
                            assert!(!want, "{model}, {channels} channels, init {k}: {e}");
                            // The library names its own parameters, never a command-line flag.
                            assert!(!e.contains("--"), "{e}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn canonical_rotation_trades_quarter_turns_for_the_weft_fraction() {
        let mut set = ParamSet::new(ModelKind::Cloth, None, 1, false).unwrap();
        set.fix("rotation", 2.0).unwrap();
        set.fix("weft_fraction", 0.3).unwrap();
        set.canonicalize();
        let rot = set.get(Quantity::Rotation, 0).unwrap();
        assert!((rot - (2.0 - FRAC_PI_2)).abs() < 1e-12, "{rot}");
        assert!((set.get(Quantity::WeftFraction, 0).unwrap() - 0.7).abs() < 1e-12);
    }
}
