//! Tabulated cloth BRDFs: fast evaluation and importance sampling for renderers.
//!
//! The exact model (docs/model.md) nests up to four integrals; a [`Table`] stores it on a grid
//! and interpolates. The grid follows where cloth BRDFs change (see [`grid`]): one direction of
//! the pair, the *axis*, on polar and azimuth nodes, the other through the half vector
//! `h = (s + v)/|s + v|`, whose slopes `p = h_xy/h_z` keep the highlights in place as the axis
//! moves.
//!
//! **Two halves, the more grazing direction as the axis.** Near the horizon a BRDF changes
//! fastest with the polar angle of the more grazing direction (masking and Fresnel, roughly like
//! `√cos θ`), and at a fixed half vector, moving the axis direction moves the other direction by
//! as much. A table therefore holds two halves: the *light* half, indexed by `s` (for pairs with
//! `cos θ_i ≤ cos θ_r`), and the *view* half, indexed by `v` with `s` through the half vector
//! (pairs with `cos θ_r < cos θ_i`). Each pair is read from the half whose axis is its more
//! grazing direction, on a polar axis graded toward the horizon like `√cos θ`
//! ([`THETA_GRADING`]), so the other direction stays clear of the horizon while the grid moves
//! it. A half evaluates only the nodes its own pairs can read ([`build`](Table::build)); the
//! paper normalization's missing reciprocity costs nothing, as each half tabulates `f(s, v)`
//! itself.
//!
//! **Interpolation.** Each node holds `f`; a query averages the nodes around it with the
//! quadrilinear weights times each node's cosines `cos θ_i cos θ_r` (`Σ w c f / Σ w c`), which
//! interpolates the smooth `f cos θ_i cos θ_r` near highlights and is a convex combination of
//! node values near the horizon, never a division by a vanishing cosine. Nodes whose other
//! direction falls below the horizon hold `f` just above it and take part with a small weight
//! ([`HORIZON_WEIGHT`]).
//!
//! **Symmetries.** Every woven material is invariant under the mirrors `x → −x` and `y → −y`
//! (profiles are symmetric, twist densities even), so axis azimuths `[0, π/2]` suffice; isotropic
//! materials (flat fibers, `isotropic = true` yarns) need azimuth 0 only.
//!
//! **Building.** Single-orientation materials are evaluated exactly at every node. Twisted and
//! isotropic yarns (≈ 1 ms per exact evaluation) first tabulate the slope-averaged BRDF of fibers
//! along `x`, `F₀ = f_θ(s, v; φ_a = 0)`, then average rotated look-ups of `F₀` over fiber azimuths
//! with the twist (or uniform) weights: Eqs. (21)–(23) applied to the table, exactly linear like
//! the model.
//!
//! | option | meaning | default |
//! |---|---|---|
//! | `n_theta` | polar nodes of the axis on `[0, theta_max]`, graded toward grazing | 40 ([`TableOptions::for_model`]: 60 for isotropic materials) |
//! | `theta_max_deg` | last polar node (beyond: clamped) | 89.9° |
//! | `n_phi` | azimuth nodes of the axis on `[0, π/2]` (anisotropic materials) | 19 |
//! | `n_h` | nodes per half-vector slope axis, `t ∈ [−1, 1]` (anisotropic) | 81 ([`TableOptions::for_model`]: up to 121 for smooth fibers) |
//! | `n_h_isotropic` | the same for isotropic materials | 161 |
//! | `azimuth_nodes` | fiber azimuths per period for twisted/isotropic yarns | 180 |

mod build;
pub mod cache;
pub(crate) mod crown;
mod eval;
pub mod format;
pub mod grid;
mod options;
mod raw;
pub mod report;
mod sampler;
mod tilt;
pub use tilt::TILTED_MIN_GRID;

pub use options::{
    grid_of, value_count, TableOptions, MAX_VALUES, N_H_NARROW_LOBE, N_H_SMOOTH, N_H_WIDE_LOBE,
    N_PHI_RENDER, N_THETA_ISOTROPIC, N_THETA_RENDER,
};
pub use raw::Raw;

use crate::color::Rgb;
use crate::material::Material;
use crate::math::Vec3;
use grid::{slope_of_t, Axis};
use sampler::Sampler;

/// Grading of the polar axis (see [`Axis`]): `θ = θ_max (1 − (1 − u)²)` for nodes uniform in `u`,
/// so the spacing shrinks linearly to 0 at `θ_max` — nodes uniform in `√(θ_max − θ)`, which is
/// how a BRDF changes next to the horizon (≈ `√cos θ`). 40 nodes to 89.9°: 4.6° apart at normal
/// incidence, 1.5° at 80°, 0.7° at 88°, 0.06° at the end.
pub const THETA_GRADING: f64 = 1.0;

/// Azimuth nodes of the intermediate single-orientation table `F₀` of twisted and isotropic
/// yarns: the azimuth average smooths its interpolation error, so it can be coarser than a final
/// table.
pub const F0_PHI_NODES: usize = 13;

/// The floor `ε` of a node's `cos θ` (of the direction derived through the half vector) in the
/// interpolation weights: nodes whose derived direction lies below (or within 0.06° of) the
/// horizon take part with this small weight only, holding `f` just above the horizon, so a query
/// next to the horizon reads the nodes above it.
pub const HORIZON_WEIGHT: f64 = 1e-3;

/// How far above the horizon a node whose derived direction lies below it is evaluated, degrees.
pub const HORIZON_LIFT_DEG: f64 = 0.1;

/// Which symmetry the table exploits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Symmetry {
    /// `f` depends on `φ_r − φ_i` only: one axis azimuth.
    Isotropic,
    /// `f` is invariant under `x → −x` and `y → −y`: axis azimuths `[0, π/2]`.
    Mirror,
}

/// The two halves of a table (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Half {
    /// Indexed by the light direction `s`: pairs with `cos θ_i ≤ cos θ_r`.
    Light,
    /// Indexed by the viewer direction `v`: pairs with `cos θ_r < cos θ_i`.
    View,
}

impl Half {
    /// The half that answers for the pair `(s, v)`: the one whose axis is the more grazing.
    #[inline]
    pub fn of(s: Vec3, v: Vec3) -> Half {
        if s.z <= v.z {
            Half::Light
        } else {
            Half::View
        }
    }

    /// `(axis, other)` of the pair `(s, v)` in this half.
    #[inline]
    pub fn split(self, s: Vec3, v: Vec3) -> (Vec3, Vec3) {
        match self {
            Half::Light => (s, v),
            Half::View => (v, s),
        }
    }

    /// `(s, v)` from `(axis, other)`.
    #[inline]
    pub fn join(self, axis: Vec3, other: Vec3) -> (Vec3, Vec3) {
        self.split(axis, other)
    }

    /// Index of the half in [`Table::values`].
    #[inline]
    fn index(self) -> usize {
        match self {
            Half::Light => 0,
            Half::View => 1,
        }
    }
}

/// A tabulated BRDF. `Send + Sync`; [`eval`](Table::eval), [`pdf`](crate::bsdf::Bsdf::pdf) and
/// [`sample`](crate::bsdf::Bsdf::sample) allocate nothing.
#[derive(Clone, Debug)]
pub struct Table {
    symmetry: Symmetry,
    theta: Axis,
    phi: Axis,
    t: Axis,
    /// `f` at every node of both halves; see [`Table::values`].
    values: Vec<f32>,
    /// The axis direction of each `(iθ, iφ)` node, index `iθ·n_φ + iφ`.
    axis_dirs: Vec<Vec3>,
    /// The slope `p` of each half-vector node.
    slopes: Vec<f64>,
    /// `(cos φ, sin φ)` of each azimuth node.
    phi_cs: Vec<(f64, f64)>,
    /// What the table was built from (`None` for an intermediate table of the build).
    provenance: Option<Provenance>,
    wavelength_nm: f64,
    sampler: Sampler,
    /// The parts for other albedos ([`Table::eval_dyed`]), when built with them.
    colour: Option<Colour>,
    /// The crown's half-angle the yarn was averaged over, degrees ([`Table::crowned`]); 0: none.
    crown_deg: f64,
    /// The exact model, for the near-forward pairs of single-orientation yarns
    /// ([`FORWARD_EXACT`]).
    exact: Option<Exact>,
}

/// Pairs with `|s + v|` below this (the angle between `s` and `−v` under 29°, so both
/// directions within 15° of the horizon) are evaluated by the exact model in tables of
/// single-orientation yarns. There the half vector is ill-conditioned — a degree of either
/// direction swings it across the grid — while the fibers' specular cone passes through the
/// forward direction and, along a yarn, closes onto a ring about a degree wide: no grid holds
/// that ridge. The pairs are grazing and backlit, 1.4 % of uniform pairs (a renderer meets them
/// on backlit silhouettes); each costs an exact evaluation (~25 µs for the sateen), which doubles
/// the mean cost of uniform random look-ups on the sateen. Twisted and isotropic yarns spread
/// the ridge over their fiber azimuths and their exact evaluation is slow: their tables
/// interpolate there too, as do flat fibers, whose tables meet their targets.
pub const FORWARD_EXACT: f64 = 0.5;

/// Pairs whose half vector `s + v` lies within 5° of the horizon (`h_z < sin 5° |h|`; both
/// directions then within 10° of it) are evaluated by the exact model in tables of
/// single-orientation yarns, like the near-forward pairs ([`FORWARD_EXACT`]) and for the same
/// reason: the half-vector grid's slopes run to its edge there, so its cells hold directions far
/// apart, and the table was off by up to 400× the exact value — within 0.7 % of the peak of
/// `f cos θ_i cos θ_r`, but with sampling weights up to 80× their median for the smooth sateen
/// at `θ_i` 89.5° (3° left 24× at 3.1°). They are 0.8 % of uniform pairs (2.1 % with the
/// near-forward ones), fewer of a renderer's, which meets them on silhouettes.
pub const GRAZING_HALF_EXACT: f64 = 0.087_155_742_747_658_17;

/// The exact model a table keeps for near-forward pairs ([`FORWARD_EXACT`]).
#[derive(Clone, Debug)]
pub(crate) struct Exact {
    model: std::sync::Arc<crate::Model>,
}

impl Exact {
    /// The exact part of a table of `model`: single-orientation yarns only.
    fn of(model: &crate::Model) -> Option<Exact> {
        match model.structure() {
            crate::cloth::Structure::Woven { yarn, .. } if yarn.is_single_orientation() => {
                Some(Exact {
                    model: std::sync::Arc::new(model.clone()),
                })
            }
            _ => None,
        }
    }
}

/// The albedos a BRDF is affine in: the fiber's diffuse albedo `ρ0` (`[fiber] diffuse`) and the
/// yarn's interreflection albedo `ρ` (`[yarn] interreflection_albedo`; 0 for a flat fiber). They
/// are the dyed body of the fibers; the Fresnel sheen stays white.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Albedos {
    /// `ρ0`, in `[0, 1)`.
    pub diffuse: f64,
    /// `ρ`, in `[0, 1]`.
    pub interreflection: f64,
}

impl Albedos {
    /// The largest dyed body albedo `ρ0` (a dye of 1 is kept just below it: the fiber BRDF's
    /// body term is defined for `ρ0 < 1`). The one home of the cap the dye rule
    /// ([`dyed`](Self::dyed)), irregular dyeing and the Mitsuba plugin's traced dyes apply.
    pub const MAX_DYED_DIFFUSE: f64 = 0.999;

    /// The material's own albedos.
    pub fn of(material: &Material) -> Albedos {
        Albedos {
            diffuse: material.fiber.diffuse,
            interreflection: material
                .yarn
                .as_ref()
                .map_or(0.0, |y| y.interreflection_albedo),
        }
    }

    /// The albedos per channel of these (a material's own) dyed `colour`: the colour replaces
    /// `ρ0` (kept below 1), and `ρ` scales with it (`ρ·c/ρ0`, at most 1; unchanged when `ρ0` is
    /// 0). No colour: these, in every channel. A channel that is not a number (a NaN texel)
    /// counts as 0, black, as the renderer counts a NaN sample. The one rule every dyed surface
    /// follows ([`dye_rule`](Self::dye_rule) states it as constants).
    pub fn dyed(self, colour: Option<Rgb>) -> [Albedos; 3] {
        let Some(c) = colour else {
            return [self; 3];
        };
        let rule = self.dye_rule();
        c.0.map(|c| rule.apply(c))
    }

    /// The dye rule of these (a material's own) albedos as constants: what
    /// [`dyed`](Self::dyed) does to one channel, for a front end that dyes per lane (the
    /// Mitsuba plugin's textured colours) and applies it without knowing why.
    pub fn dye_rule(self) -> DyeRule {
        let (slope, offset) = if self.diffuse > 0.0 {
            (self.interreflection / self.diffuse, 0.0)
        } else {
            (0.0, self.interreflection)
        };
        DyeRule {
            cap: Albedos::MAX_DYED_DIFFUSE,
            slope,
            offset,
        }
    }
}

/// How a dye `c` (one channel) sets the albedos ([`Albedos::dye_rule`]): `c` read as 0 where it
/// is not a number and clamped to `[0, 1]`, then `ρ0 = min(c, cap)` and
/// `ρ = clamp(slope·c + offset, 0, 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DyeRule {
    /// The largest `ρ0` ([`Albedos::MAX_DYED_DIFFUSE`]).
    pub cap: f64,
    /// `ρ/ρ0` of the material's own albedos (0 when its `ρ0` is 0).
    pub slope: f64,
    /// The material's own `ρ` when its `ρ0` is 0, else 0.
    pub offset: f64,
}

impl DyeRule {
    /// The albedos of one channel dyed `c`.
    pub fn apply(self, c: f64) -> Albedos {
        let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
        Albedos {
            diffuse: c.min(self.cap),
            interreflection: (self.slope * c + self.offset).clamp(0.0, 1.0),
        }
    }
}

/// What [`Table::eval_dyed`] adds to a table: `∂f/∂ρ0` at every node, and `∂f/∂ρ = ħ/π`.
#[derive(Clone, Debug)]
pub(crate) struct Colour {
    /// `∂f/∂ρ0` at every node, laid out as [`Table::values`].
    pub(crate) body: Vec<f32>,
    /// `∂f/∂ρ`: the interreflection term `ħρ/π` of Eq. (20), averaged with weights summing to 1.
    pub(crate) per_interreflection: f64,
    /// The albedos `values` were built with.
    pub(crate) own: Albedos,
    /// A crowned table's ([`Table::crowned`]): what `∂f/∂ρ` is multiplied by at every node, the
    /// crown's average of 1; `None`: 1.
    pub(crate) crown: Option<Vec<f32>>,
}

impl Colour {
    /// The colour parts of a table of `material` with node derivatives `body`.
    pub(crate) fn new(material: &Material, body: Vec<f32>) -> Colour {
        Colour {
            body,
            per_interreflection: material
                .yarn
                .as_ref()
                .map_or(0.0, |y| y.interreflection * std::f64::consts::FRAC_1_PI),
            own: Albedos::of(material),
            crown: None,
        }
    }
}

/// What a table was built from: the material and the wavelength. Written into `.wtab` files, so
/// a table can be traced and rebuilt; the material is kept self-contained (a WIF pattern as its
/// matrix, [`Material::to_self_contained_toml_string`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Provenance {
    /// The material.
    pub material: Material,
    /// The wavelength, nm.
    pub wavelength_nm: f64,
}

impl Table {
    /// A table from its grid and values, keeping `exact` for the pairs no grid holds
    /// ([`FORWARD_EXACT`], [`GRAZING_HALF_EXACT`]) when it is a single-orientation yarn's; the sampler is rebuilt from the
    /// values (the exact ones where the table answers with them), or from stored per-cell
    /// densities.
    #[allow(clippy::too_many_arguments)]
    fn assemble(
        symmetry: Symmetry,
        theta: Axis,
        phi: Axis,
        t: Axis,
        values: Vec<f32>,
        provenance: Option<Provenance>,
        wavelength_nm: f64,
        cell_pdf: Option<Vec<f32>>,
        colour: Option<Colour>,
        exact: Option<&crate::Model>,
    ) -> Table {
        let axis_dirs = (0..theta.n * phi.n)
            .map(|r| Vec3::from_spherical(theta.node(r / phi.n), phi.node(r % phi.n)))
            .collect();
        let slopes = (0..t.n).map(|k| slope_of_t(t.node(k))).collect();
        let phi_cs = (0..phi.n)
            .map(|k| {
                let (s, c) = phi.node(k).sin_cos();
                (c, s)
            })
            .collect();
        let mut table = Table {
            phi_cs,
            symmetry,
            theta,
            phi,
            t,
            values,
            axis_dirs,
            slopes,
            provenance,
            wavelength_nm,
            sampler: Sampler::default(),
            colour,
            crown_deg: 0.0,
            exact: exact.and_then(Exact::of),
        };
        table.sampler = match cell_pdf {
            Some(c) => Sampler::from_cell_pdf(&table, c),
            None => Sampler::build(&table),
        };
        table
    }

    /// A table on the mirror grid `(θ, φ, t)` derived from this one by averaging its look-ups
    /// (crowned, [`crowned_with`](Self::crowned_with); tilted, [`tilted`](Self::tilted)): this
    /// table's provenance and wavelength, no exact regions, sampled by its own values.
    fn derived(
        &self,
        (theta, phi, t): (Axis, Axis, Axis),
        values: Vec<f32>,
        colour: Option<Colour>,
        crown_deg: f64,
    ) -> Table {
        let mut table = Table::assemble(
            Symmetry::Mirror,
            theta,
            phi,
            t,
            values,
            self.provenance.clone(),
            self.wavelength_nm,
            None,
            colour,
            None,
        );
        table.crown_deg = crown_deg;
        table
    }

    /// The symmetry the table uses.
    pub fn symmetry(&self) -> Symmetry {
        self.symmetry
    }

    /// What the table was built from.
    pub fn provenance(&self) -> Option<&Provenance> {
        self.provenance.as_ref()
    }

    /// The material the table was built from.
    pub fn material(&self) -> Option<&Material> {
        self.provenance.as_ref().map(|p| &p.material)
    }

    /// The wavelength the table was built at, nm.
    pub fn wavelength_nm(&self) -> f64 {
        self.wavelength_nm
    }

    /// `(n_theta, n_phi, n_h)` of each half.
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.theta.n, self.phi.n, self.t.n)
    }

    /// The last polar node, degrees.
    pub fn theta_max_deg(&self) -> f64 {
        self.theta.hi.to_degrees()
    }

    /// The stored values: the BRDF `f` (`f32`, sr⁻¹) at every node, the light half then the view
    /// half, index `(((half·n_θ + iθ)·n_φ + iφ)·n_h + i_y)·n_h + i_x`. A node whose derived
    /// direction lies below the horizon holds `f` with that direction lifted [`HORIZON_LIFT_DEG`]
    /// above it in the same azimuth; a node no pair of its half reads holds 0.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Whether the table was built with the parts [`eval_dyed`](Self::eval_dyed) needs
    /// ([`TableOptions::colour`]).
    pub fn is_dyeable(&self) -> bool {
        self.colour.is_some()
    }

    /// `∂f/∂ρ0` at every node, laid out as [`values`](Self::values), when
    /// [`is_dyeable`](Self::is_dyeable).
    pub fn body_values(&self) -> Option<&[f32]> {
        self.colour.as_ref().map(|c| c.body.as_slice())
    }

    /// The crown's half-angle, degrees, that the table's yarn is averaged over
    /// ([`TableOptions::crown_deg`]); 0 for a yarn as the paper has it.
    pub fn crown_deg(&self) -> f64 {
        self.crown_deg
    }

    /// A crowned table's `∂f/∂ρ` factor at every node ([`Table::crowned`]), when it is dyeable.
    pub(crate) fn crown_values(&self) -> Option<&[f32]> {
        self.colour.as_ref().and_then(|c| c.crown.as_deref())
    }

    /// The exact model for `(s, v)` when the pair is near forward scattering or its half vector
    /// near the horizon, in a table that keeps one ([`FORWARD_EXACT`], [`GRAZING_HALF_EXACT`]).
    #[inline]
    pub(crate) fn exact_at(&self, s: Vec3, v: Vec3) -> Option<&crate::Model> {
        let exact = self.exact.as_ref()?;
        let h = s + v;
        let hh = h.dot(h);
        (hh < FORWARD_EXACT * FORWARD_EXACT
            || h.z * h.z < GRAZING_HALF_EXACT * GRAZING_HALF_EXACT * hh)
            .then_some(&*exact.model)
    }

    /// Values in one half.
    #[inline]
    fn half_len(&self) -> usize {
        self.theta.n * self.phi.n * self.t.n * self.t.n
    }

    #[inline]
    fn index(&self, half: Half, it: usize, ip: usize, iy: usize, ix: usize) -> usize {
        half.index() * self.half_len() + ((it * self.phi.n + ip) * self.t.n + iy) * self.t.n + ix
    }
}
