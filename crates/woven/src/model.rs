//! A material prepared for evaluation at one wavelength.

use crate::cloth::{tilted_families, weave_axes, Structure};
use crate::color::Rgb;
use crate::fiber::Fiber;
use crate::gaps::{Cover, YarnSection};
use crate::material::Dye;
use crate::math::Vec3;
use crate::table::Albedos;
use crate::translucency::{
    face, forward_spread, slab_transmitted_share, Translucency, YARN_SCATTERING_DEPTH,
};
use crate::yarn::Masking;
use std::sync::{Arc, OnceLock};

/// A material ready to evaluate: the result of [`Material::build`](crate::material::Material::build).
/// `Send + Sync`; cheap to clone.
#[derive(Clone, Debug)]
pub struct Model {
    structure: Structure,
    /// The light through the cloth, when its `transmission` is on.
    through: Option<Arc<Through>>,
}

/// What a transmitting model passes and transmits (docs/model.md, "Light through the yarns").
#[derive(Debug)]
struct Through {
    /// The yarns' cross-section, for the open area.
    section: YarnSection,
    /// `τ`: the share of what enters the yarns that leaves on the far side.
    tau: f64,
    /// The forward lobe's spread ([`forward_spread`]).
    spread: f64,
    /// The cloth's back ([`Material::back`](crate::material::Material::back)), opaque: what it
    /// reflects seen from below, in its own frame.
    back: Model,
    /// `r(w)`'s table, worked out when a transmitted direction is first asked for.
    table: OnceLock<Translucency>,
}

impl Model {
    /// A model of the given structure.
    pub fn new(structure: Structure) -> Self {
        Model {
            structure,
            through: None,
        }
    }

    /// The model with light passing through it (`[weave] transmission`): between its yarns,
    /// which leave `gap` of their pitch open (the structure's own gap), and through them, a
    /// Kubelka–Munk slab of the fibre's body albedo `ρ0` ([`crate::translucency`]). `back` is
    /// the cloth seen from below, opaque ([`Material::back`](crate::material::Material::back)):
    /// its reflection there, in its own frame.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `transmission` for a
    /// flat fiber surface, which has no yarns to pass light through or between.
    pub fn transmitting(self, gap: f64, back: Model) -> crate::Result<Model> {
        if matches!(self.structure, Structure::Flat(_)) {
            return Err(crate::Error::invalid(
                "transmission",
                "true with a flat fiber surface",
                "false: a flat fiber surface (no [yarn]) has no yarns to pass light through",
            ));
        }
        let tau = slab_transmitted_share(self.fiber().params().diffuse, YARN_SCATTERING_DEPTH);
        let yarn = match &self.structure {
            Structure::Woven { yarn, .. } => Some(*yarn.params()),
            Structure::Flat(_) => None,
        };
        let spread = forward_spread(self.fiber().eta(), self.fiber().alpha(), yarn.as_ref());
        Ok(Model {
            through: Some(Arc::new(Through {
                section: YarnSection::new(gap)?,
                tau,
                spread,
                back,
                table: OnceLock::new(),
            })),
            ..self
        })
    }

    /// Whether light passes through the cloth ([`transmitting`](Self::transmitting)).
    pub fn transmits(&self) -> bool {
        self.through.is_some()
    }

    /// The BSDF (sr⁻¹, no cosine) for light from `s` seen from `v`, in the cloth's local frame
    /// (docs/spec.md §0). An opaque cloth's is its BRDF, 0 when either is below the surface. A
    /// transmitting cloth ([`transmitting`](Self::transmitting)) transmits between the sides
    /// (the diffuse part: the light straight through its gaps is the delta
    /// [`open_along`](Self::open_along)), and its back reflects as the back's cloth
    /// ([`Material::back`](crate::material::Material::back)) turned over about the weft.
    #[inline]
    pub fn eval(&self, s: Vec3, v: Vec3) -> f64 {
        if (s.z > 0.0 && v.z > 0.0) || self.through.is_none() {
            return self.structure.eval(s, v);
        }
        self.eval_beyond(s, v)
    }

    /// [`eval`](Self::eval) of a transmitting cloth where a direction lies below it.
    #[cold]
    fn eval_beyond(&self, s: Vec3, v: Vec3) -> f64 {
        let Some(through) = &self.through else {
            return 0.0;
        };
        if s.z < 0.0 && v.z < 0.0 {
            return through.back.eval(face(s), face(v));
        }
        if s.z == 0.0 || v.z == 0.0 {
            return 0.0;
        }
        through.tau * self.translucency(through).eval(s, v).0[0]
    }

    /// [`eval_rgb`](Self::eval_rgb) of a transmitting cloth where a direction lies below it: the
    /// back reflects as its own cloth turned over, and the light through the yarns is each
    /// channel's `τ` (from its dyed `ρ0`, the families' mixed by their shares) times the undyed
    /// cloth's `r(wi) r(wo) / (π r̄)`. The dye's change of the reflection albedo `A` is not
    /// carried into `r`: exact undyed, an approximation dyed (docs/model.md).
    pub fn eval_rgb_beyond(&self, s: Vec3, v: Vec3, dye: &Dye) -> Rgb {
        let Some(through) = &self.through else {
            return Rgb::BLACK;
        };
        if s.z < 0.0 && v.z < 0.0 {
            return through.back.eval_rgb(face(s), face(v), dye);
        }
        if s.z == 0.0 || v.z == 0.0 {
            return Rgb::BLACK;
        }
        let f = self.translucency(through).eval(s, v).0[0];
        Rgb(self.dyed_tau(dye).map(|tau| tau * f))
    }

    /// `τ` per channel of the cloth dyed `dye`: each family's dyed `ρ0` as a slab's, mixed by
    /// the families' shares of the cloth.
    fn dyed_tau(&self, dye: &Dye) -> [f64; 3] {
        let own = self.own_albedos();
        let (weft, warp) = (own.dyed(dye.weft), own.dyed(dye.warp));
        let g = match &self.structure {
            Structure::Woven { weft_fraction, .. } => *weft_fraction,
            Structure::Flat(_) => 1.0,
        };
        let tau =
            |a: crate::table::Albedos| slab_transmitted_share(a.diffuse, YARN_SCATTERING_DEPTH);
        std::array::from_fn(|c| g * tau(weft[c]) + (1.0 - g) * tau(warp[c]))
    }

    /// The table of `r(w)`, worked out on first use from the exact albedo.
    fn translucency<'a>(&'a self, through: &'a Through) -> &'a Translucency {
        through.table.get_or_init(|| {
            Translucency::from_albedo(
                |_, w| [self.albedo_along(w); 3],
                |w| self.open_along(w),
                true,
                through.spread,
            )
        })
    }

    /// The share of light along `d` (either side) that passes straight between the yarns: the
    /// open area ([`open_area`](crate::gaps::open_area)); 0 for an opaque cloth.
    pub fn open_along(&self, d: Vec3) -> f64 {
        self.through
            .as_ref()
            .map_or(0.0, |t| t.section.open_along(d))
    }

    /// Where the light from `(theta_i, phi_i)` goes ([`Budget`]): what the cloth reflects (its
    /// [`albedo`](Self::albedo)), what passes straight between its yarns
    /// ([`open_along`](Self::open_along)) and what its yarns transmit, `τ (1 − O − A)`; the rest
    /// the dye absorbs. An opaque cloth passes and transmits nothing.
    pub fn budget(&self, theta_i: f64, phi_i: f64) -> Budget {
        let reflected = self.albedo(theta_i, phi_i);
        let Some(through) = &self.through else {
            return Budget {
                reflected,
                passed: 0.0,
                transmitted: 0.0,
            };
        };
        let passed = self.open_along(Vec3::from_spherical(theta_i, phi_i));
        Budget {
            reflected,
            passed,
            transmitted: through.tau * (1.0 - passed - reflected).max(0.0),
        }
    }

    /// All the light from `(theta_i, phi_i)` that reaches the far side: [`Budget::transmittance`]
    /// of [`budget`](Self::budget); 0 for an opaque cloth.
    pub fn transmittance(&self, theta_i: f64, phi_i: f64) -> f64 {
        if self.through.is_none() {
            return 0.0;
        }
        self.budget(theta_i, phi_i).transmittance()
    }

    /// The reflection albedo along `w` (upper hemisphere).
    fn albedo_along(&self, w: Vec3) -> f64 {
        self.albedo(w.z.clamp(-1.0, 1.0).acos(), w.y.atan2(w.x))
    }

    /// The BRDF at `(s, v)` as the affine function of the material's two albedos that it is:
    /// `f = fixed + ρ0·per_diffuse + ρ·per_interreflection`, `ρ0` the fiber's diffuse albedo
    /// (`fiber.diffuse`; β carries `ζ = 1 − ρ0`, docs/spec.md §1.5) and `ρ` the interreflection
    /// albedo (`yarn.interreflection_albedo`, Eq. (20); no term for a flat fiber surface).
    /// Computed in one pass through the model's quadrature; [`AffineBrdf::at`] the material's
    /// own albedos equals [`eval`](Self::eval) to rounding, and at other albedos equals `eval` of
    /// the material with those albedos (everything else equal).
    ///
    /// For colour: evaluate once, then combine per channel with the dyed albedos.
    ///
    /// ```
    /// use woven::material::Material;
    /// use woven::Vec3;
    /// let model = Material::preset("silk")?.build(550.0)?;
    /// let (s, v) = (Vec3::from_spherical(0.5, 0.0), Vec3::from_spherical(0.6, 3.0));
    /// let parts = model.eval_affine(s, v);
    /// let (rho0, rho) = (model.fiber().params().diffuse, 0.5); // silk's own albedos
    /// assert!((parts.at(rho0, rho) - model.eval(s, v)).abs() < 1e-12 * model.eval(s, v));
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn eval_affine(&self, s: Vec3, v: Vec3) -> AffineBrdf {
        if s.z <= 0.0 || v.z <= 0.0 {
            return AffineBrdf::default();
        }
        match &self.structure {
            Structure::Flat(fiber) => {
                let (fixed, per_diffuse) =
                    fiber.affine_in_diffuse(fiber.eval_parts_with_normal(s, v, Vec3::Z));
                AffineBrdf {
                    fixed,
                    per_diffuse,
                    per_interreflection: 0.0,
                }
            }
            Structure::Woven { yarn, .. } if yarn.params().u_max > 0.0 => {
                let [weft, warp] = self.eval_affine_families(s, v);
                weft + warp
            }
            Structure::Woven {
                yarn,
                weft_fraction,
                gap,
            } => yarn.eval_mix_affine(s, v, &weave_axes(*weft_fraction, *gap), Masking::Exact),
        }
    }

    /// The BRDF per channel of this material dyed `dye` (sr⁻¹, no cosine): each yarn family's
    /// albedos dyed by its colour ([`Albedos::dyed`]), its affine parts
    /// ([`eval_affine`](Self::eval_affine)) taken at them, and the families weighted as in
    /// Eq. (23). Undyed families keep the material's own albedos, so with no dye every channel
    /// equals [`eval`](Self::eval).
    ///
    /// ```
    /// use woven::material::{Dye, Material};
    /// use woven::{color::Rgb, Vec3};
    /// let model = Material::preset("silk")?.build(550.0)?;
    /// let (s, v) = (Vec3::from_spherical(0.5, 0.0), Vec3::from_spherical(0.6, 3.0));
    /// let red = Dye { weft: Some(Rgb([0.6, 0.05, 0.05])), warp: Some(Rgb([0.6, 0.05, 0.05])) };
    /// let f = model.eval_rgb(s, v, &red);
    /// assert!(f.0[0] > f.0[1] && f.0[1] > 0.0); // the sheen stays white
    /// # Ok::<(), woven::Error>(())
    /// ```
    pub fn eval_rgb(&self, s: Vec3, v: Vec3, dye: &Dye) -> Rgb {
        if s.z <= 0.0 || v.z <= 0.0 {
            return Rgb::BLACK;
        }
        let own = self.own_albedos();
        let [weft, warp] = self.eval_affine_families(s, v);
        let channels = |parts: AffineBrdf, colour: Option<Rgb>| {
            own.dyed(colour)
                .map(|a| parts.at(a.diffuse, a.interreflection))
        };
        let (a, b) = (channels(weft, dye.weft), channels(warp, dye.warp));
        let sum = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        Rgb(sum.map(|f| f.max(0.0)))
    }

    /// [`eval_affine`](Self::eval_affine) split by yarn family: the weft's share (weight `γ`)
    /// and the warp's (`1 − γ`), which sum to it. A flat fiber surface is all weft.
    pub fn eval_affine_families(&self, s: Vec3, v: Vec3) -> [AffineBrdf; 2] {
        if s.z <= 0.0 || v.z <= 0.0 {
            return [AffineBrdf::default(); 2];
        }
        match &self.structure {
            Structure::Flat(_) => [self.eval_affine(s, v), AffineBrdf::default()],
            Structure::Woven {
                yarn,
                weft_fraction,
                gap,
            } if yarn.params().u_max > 0.0 => {
                let cover = Cover::new(*weft_fraction, *gap);
                let mut families = tilted_families(yarn, cover.top, s, v, |y, a, b, w| {
                    y.eval_mix_affine(a, b, &[(0.0, w)], Masking::Exact)
                });
                if *gap > 0.0 {
                    // The share below the crossing family's gaps lies flat.
                    let axes = [0.0, std::f64::consts::FRAC_PI_2]
                        .into_iter()
                        .zip(cover.below);
                    for (family, (phi, w)) in families.iter_mut().zip(axes) {
                        *family += yarn.eval_mix_affine(s, v, &[(phi, w)], Masking::Exact);
                    }
                }
                families
            }
            Structure::Woven {
                yarn,
                weft_fraction,
                gap,
            } => weave_axes(*weft_fraction, *gap)
                .map(|axis| yarn.eval_mix_affine(s, v, &[axis], Masking::Exact)),
        }
    }

    /// The albedos the material was built with: the fiber's `ρ0` and the yarn's `ρ` (0 for a
    /// flat fiber surface).
    pub fn own_albedos(&self) -> Albedos {
        Albedos {
            diffuse: self.fiber().params().diffuse,
            interreflection: match &self.structure {
                Structure::Flat(_) => 0.0,
                Structure::Woven { yarn, .. } => yarn.params().interreflection_albedo,
            },
        }
    }

    /// The structure (flat fiber surface or woven yarns).
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// The fiber surface of this material.
    pub fn fiber(&self) -> &Fiber {
        self.structure.fiber()
    }

    /// Directional albedo `∫ f cos θ_r dω_r` (plus the full model's specular spike) for light from
    /// polar angle `theta_i` and azimuth `phi_i` (radians).
    pub fn albedo(&self, theta_i: f64, phi_i: f64) -> f64 {
        match &self.structure {
            Structure::Flat(fiber) => fiber.albedo(theta_i.cos()),
            Structure::Woven { .. } => crate::albedo::hemisphere_albedo(self, theta_i, phi_i),
        }
    }
}

/// Where the light arriving from one direction goes ([`Model::budget`]), as shares of it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Budget {
    /// Reflected: the directional albedo `A`.
    pub reflected: f64,
    /// Passed straight between the yarns: the open area `O`.
    pub passed: f64,
    /// Transmitted diffusely through the yarns: `τ (1 − O − A)`.
    pub transmitted: f64,
}

impl Budget {
    /// All that reaches the far side: passed and transmitted.
    pub fn transmittance(&self) -> f64 {
        self.passed + self.transmitted
    }
}

/// A BRDF value as an affine function of the material's albedos (see [`Model::eval_affine`]):
/// `f(ρ0, ρ) = fixed + ρ0·per_diffuse + ρ·per_interreflection`, sr⁻¹.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AffineBrdf {
    /// The value at `ρ0 = ρ = 0`: the Fresnel sheen (with β at `ζ = 1`), scaled by `1 − ħ`.
    pub fixed: f64,
    /// The change per unit of the fiber's diffuse albedo `ρ0` (negative where the sheen's loss
    /// to `ζ = 1 − ρ0` outweighs the Lambertian gain).
    pub per_diffuse: f64,
    /// The change per unit of the interreflection albedo `ρ`: `ħ/π` times the yarn weights.
    pub per_interreflection: f64,
}

impl std::ops::Add for AffineBrdf {
    type Output = AffineBrdf;
    fn add(self, o: AffineBrdf) -> AffineBrdf {
        AffineBrdf {
            fixed: self.fixed + o.fixed,
            per_diffuse: self.per_diffuse + o.per_diffuse,
            per_interreflection: self.per_interreflection + o.per_interreflection,
        }
    }
}

impl std::ops::AddAssign for AffineBrdf {
    fn add_assign(&mut self, o: AffineBrdf) {
        *self = *self + o;
    }
}

impl std::ops::Mul<f64> for AffineBrdf {
    type Output = AffineBrdf;
    fn mul(self, k: f64) -> AffineBrdf {
        AffineBrdf {
            fixed: self.fixed * k,
            per_diffuse: self.per_diffuse * k,
            per_interreflection: self.per_interreflection * k,
        }
    }
}

impl AffineBrdf {
    /// The BRDF at diffuse albedo `diffuse` (`ρ0`) and interreflection albedo
    /// `interreflection_albedo` (`ρ`).
    #[inline]
    pub fn at(&self, diffuse: f64, interreflection_albedo: f64) -> f64 {
        self.fixed + diffuse * self.per_diffuse + interreflection_albedo * self.per_interreflection
    }
}

#[cfg(test)]
mod tests {
    use crate::material::Material;
    use crate::math::rng::SplitMix;
    use crate::yarn::YarnParams;
    use std::f64::consts::FRAC_PI_2;

    /// The materials the affine split is checked on: the presets (aligned, twisted, isotropic
    /// yarns), a narrow-slope yarn, a flat paper-normalized fiber and a flat unnormalized one.
    fn materials() -> Vec<Material> {
        let mut out: Vec<Material> = Material::preset_names()
            .iter()
            .map(|n| Material::preset(n).unwrap())
            .collect();
        let mut narrow = Material::preset("belt-cloth").unwrap();
        narrow.yarn = Some(YarnParams {
            slope_std: 0.02,
            twist_std: 0.01,
            ..narrow.yarn.unwrap()
        });
        out.push(narrow);
        // Floats tilted along their length (the `[yarn] u_max_deg` extension).
        let mut tilted = Material::preset("filament-satin").unwrap();
        tilted.yarn.as_mut().unwrap().u_max = 0.4;
        out.push(tilted);
        let silk = Material::preset("silk").unwrap();
        out.push(Material::flat(silk.fiber));
        out.push(Material::flat(
            silk.fiber
                .with_normalization(crate::fiber::Normalization::None),
        ));
        out
    }

    /// `f = fixed + ρ0·per_diffuse + ρ·per_interreflection`: at the material's own albedos it
    /// is `eval`, and at other albedos it is `eval` of the material rebuilt with them (every
    /// other parameter equal), to rounding, for random directions.
    #[test]
    fn eval_affine_is_eval_at_every_pair_of_albedos() {
        let mut rng = SplitMix(11);
        for material in materials() {
            let model = material.build(550.0).unwrap();
            let others: Vec<((f64, f64), crate::Model)> = [(0.0, 0.0), (0.9, 1.0), (0.999, 0.05)]
                .into_iter()
                .map(|(rho0, rho)| {
                    let mut m = material.clone();
                    m.fiber.diffuse = rho0;
                    if let Some(y) = &mut m.yarn {
                        y.interreflection_albedo = rho;
                    }
                    ((rho0, rho), m.build(550.0).unwrap())
                })
                .collect();
            let own_rho = material.yarn.map_or(0.0, |y| y.interreflection_albedo);
            for _ in 0..8 {
                let (s, v) = (rng.direction(FRAC_PI_2), rng.direction(FRAC_PI_2));
                let parts = model.eval_affine(s, v);
                let f = model.eval(s, v);
                let got = parts.at(material.fiber.diffuse, own_rho);
                assert!(
                    (got - f).abs() <= 1e-12 * f.abs(),
                    "{:?} s {s:?} v {v:?}: affine {got} vs eval {f}",
                    material.name
                );
                for ((rho0, rho), other) in &others {
                    let want = other.eval(s, v);
                    let got = parts.at(*rho0, *rho);
                    assert!(
                        (got - want).abs() <= 1e-12 * want.abs() + 1e-300,
                        "{:?} at ρ0 {rho0} ρ {rho}, s {s:?} v {v:?}: affine {got} vs eval {want}",
                        material.name
                    );
                }
            }
        }
        // Below the surface: all parts 0.
        let model = Material::preset("silk").unwrap().build(550.0).unwrap();
        let below = crate::Vec3::new(0.0, 0.6, -0.8);
        assert_eq!(
            model.eval_affine(below, crate::Vec3::Z),
            super::AffineBrdf::default()
        );
    }
}
