//! A woven surface as the standard lobes renderers carry (Blender's Cycles, OpenPBR, glTF):
//! each yarn family's BRDF projected onto Lambert + anisotropic GGX along the yarn
//! ([`projection`](crate::projection)'s [`LobeSet::Anisotropic`], fitted to the reflected
//! radiance, [`Objective::Radiance`]), its colours fitted per channel, and the surface's layout
//! baked into textures by the library ([`textures`]): which family is on top (or a hole) and
//! each yarn's dye factor. What Blender (`woven.blender`), the
//! OpenPBR and the glTF writers build is read from here, and each renderer's own
//! parametrisation of the GGX lobe ([`StandardFamily::cycles`], [`StandardFamily::gltf`]) has
//! its one home here.
//!
//! **What a family's lobes fit.** The family as the cloth shows it from a cell's distance on
//! ([`WovenSurface::family_brdf`]): its whole float, tilted, its facets lit and seen averaged
//! (or its flat yarn where floats do not tilt), in its dye, the yarn along `x` (the warp's own
//! frame is the weft's turned 90°); on a relief, scaled by the relief's ratio. The gaps and which
//! family is on top are the layout's, carried as textures. The fibre level (`detail =
//! "fibers"`, or `"auto"` close up) has no standard counterpart: the yarn's average stands for
//! it.
//!
//! **Colour.** The lobes' shapes (the roughnesses) are fitted to the luminance
//! ([`project`](crate::projection::project)); then each channel's Lambertian albedo and GGX weight
//! are the non-negative least-squares fit to that channel's BRDF with the shapes fixed, each pair
//! weighted by `cos θi cos θo` (so that the reflected radiance under even light is what matches).
//!
//! **No sheen.** The projection's sheen is a Charlie lobe; Cycles' and OpenPBR's are Zeltner et
//! al.'s, whose grazing peak differs. Fitted as Charlie and rendered as Zeltner's, a weight of
//! 0.03 made the showcase's satin 44 % brighter under the sun in Cycles than in `woven render`
//! (0.5 % without it), so the renderers' lobes are fitted without one.
//!
//! **What a family's lobes fit, measured.** Fitted to the flat yarn with the float's tilt laid
//! on as a normal map, Cycles rendered the showcase's satin 58 % brighter than `woven render`:
//! a normal map tilts the facets but cannot shadow or hide them, and the charmeuse's steep flanks
//! are mostly shadowed or hidden. Fitted to the whole float ([`WovenSurface::family_brdf`]), the
//! tilt and that masking are in the lobes.

pub mod gltf;
pub mod openpbr;
pub mod textures;

use crate::error::FitError;
use crate::projection::{project_with, BuiltLobes, LobeSet, Objective, Reference, StandardLobes};
use woven::color::Rgb;
use woven::surface::{SurfaceSpec, WovenSurface};
use woven::Vec3;

/// The version of what [`project_surface`] and the baked textures give for a surface: a cache
/// of them (`woven.blender`'s) is keyed by it, so a change of the fit or the layout here bumps it.
pub const STANDARD_VERSION: u32 = 4;

/// The smallest ratio of the two GGX roughnesses Cycles' anisotropy reaches (`aspect² =
/// 1 − 0.9 a` at `a = 1`).
pub const CYCLES_MIN_ROUGHNESS_RATIO: f64 = 0.1;

/// One yarn family on the standard lobes.
#[derive(Clone, Debug, PartialEq)]
pub struct StandardFamily {
    /// The lobes fitted to the family's luminance (their shapes; weights of the luminance).
    pub lobes: StandardLobes,
    /// The Lambertian albedo per channel.
    pub diffuse: [f64; 3],
    /// The GGX lobe's weight per channel (1: a dielectric of index
    /// [`PROJECTION_ETA`](crate::projection::PROJECTION_ETA)).
    pub specular: [f64; 3],
    /// The sheen's weight per channel: 0 (module docs, "No sheen").
    pub sheen: [f64; 3],
    /// The mixture's RMS log error against the family's luminance, best overall scale removed.
    pub rms_log: f64,
    /// The best single isotropic GGX + Lambert's, the same way.
    pub isotropic_rms_log: f64,
}

/// A woven surface on the standard lobes: its two families and what lays them out.
#[derive(Clone, Debug, PartialEq)]
pub struct StandardSurface {
    /// The weft (along `u`).
    pub weft: StandardFamily,
    /// The warp (along `v`).
    pub warp: StandardFamily,
    /// Pattern cells per unit of uv, `[n_u, n_v]`.
    pub yarns_per_unit: [f64; 2],
    /// Where the surface lets light through (`transmission`): what a point on a yarn transmits
    /// through its fibres per channel, as a Lambertian translucency
    /// ([`WovenSurface::yarn_transmittance`]); its holes pass light straight through. `None`
    /// for an opaque surface, whose holes are black.
    pub translucent: Option<[f64; 3]>,
}

/// Cycles' GGX lobe (its Metallic BSDF: GGX, physical-conductor Fresnel of index 1.5 and
/// extinction 0, which is the dielectric's) for one family: Cycles stretches `α = r²` to
/// `α_x = α / a′` along the tangent and `α_y = α a′` across it, `a′ = √(1 − 0.9 a)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CyclesSpecular {
    /// `Roughness` `r`.
    pub roughness: f64,
    /// `Anisotropy` `a`, in `[0, 1]`.
    pub anisotropy: f64,
    /// `Rotation` of the tangent from the yarn, in turns: 0 (along the yarn) or 0.25 (across).
    pub rotation: f64,
    /// The roughnesses Cycles renders, `[along the yarn, across it]`: the fitted ones, unless
    /// their ratio is below [`CYCLES_MIN_ROUGHNESS_RATIO`] (then the ratio is that, about the
    /// same geometric mean).
    pub alpha: [f64; 2],
}

/// glTF's `KHR_materials_anisotropy` for one family: `α_b = roughness²` across the tangent
/// and `α_t = α_b + (1 − α_b) strength²` along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GltfSpecular {
    /// `roughnessFactor`.
    pub roughness: f64,
    /// `anisotropyStrength`, in `[0, 1]`.
    pub anisotropy_strength: f64,
    /// Whether the tangent (the rougher direction) runs along the yarn, else across it.
    pub along_yarn: bool,
}

impl StandardFamily {
    /// The family's lobes per channel at `(wi, wo)`, its yarn along `x`, sr⁻¹ without the
    /// cosine: `ρ_c/π + w_c f_GGX (+ the sheen)`, what a renderer given these parameters renders
    /// (the goniometer's judge, `scripts/blender/gonio.py`).
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming a lobe parameter out of its range.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Result<[f64; 3], FitError> {
        let [lambert, ggx, sheen] = self.lobes.build()?.unit_lobes(wi, wo);
        Ok(std::array::from_fn(|c| {
            self.diffuse[c] * lambert + self.specular[c] * ggx + self.sheen[c] * sheen
        }))
    }

    /// The GGX lobe as Cycles' node parameters ([`CyclesSpecular`]).
    pub fn cycles(&self) -> CyclesSpecular {
        let [along, across] = self.lobes.alpha;
        let (t, b, rotation) = if along >= across {
            (along, across, 0.0)
        } else {
            (across, along, 0.25)
        };
        let ratio = (b / t).max(CYCLES_MIN_ROUGHNESS_RATIO);
        let mean = (t * b).sqrt();
        let (t, b) = (mean / ratio.sqrt(), mean * ratio.sqrt());
        CyclesSpecular {
            roughness: mean.sqrt().min(1.0),
            anisotropy: ((1.0 - ratio) / 0.9).clamp(0.0, 1.0),
            rotation,
            alpha: if rotation == 0.0 { [t, b] } else { [b, t] },
        }
    }

    /// The GGX lobe as OpenPBR's parameters ([`OpenPbrSpecular`](openpbr::OpenPbrSpecular)).
    pub fn openpbr(&self) -> openpbr::OpenPbrSpecular {
        openpbr::OpenPbrSpecular::of_alpha(self.lobes.alpha)
    }

    /// The GGX lobe as glTF's parameters ([`GltfSpecular`]).
    pub fn gltf(&self) -> GltfSpecular {
        let [along, across] = self.lobes.alpha;
        let (t, b) = (along.max(across), along.min(across));
        GltfSpecular {
            roughness: b.sqrt(),
            anisotropy_strength: ((t - b) / (1.0 - b)).max(0.0).sqrt().min(1.0),
            along_yarn: along >= across,
        }
    }
}

/// Whether a surface of `spec` can be projected ([`project_surface`]): asked before its tables
/// are built, so that a refusal costs nothing.
///
/// # Errors
/// [`FitError::InvalidParameter`] naming `transmission` for a surface that lets light through:
/// the OpenPBR and glTF writers carry no transmission (they would render it opaque, its holes
/// black); Blender's Cycles does ([`StandardSurface::translucent`]).
pub fn check_spec(spec: &SurfaceSpec) -> Result<(), FitError> {
    refuse_transmission(spec.transmission)
}

/// The refusal of [`check_spec`] (and of the OpenPBR and glTF writers).
pub(crate) fn refuse_transmission(transmits: bool) -> Result<(), FitError> {
    if !transmits {
        return Ok(());
    }
    Err(FitError::InvalidParameter {
        name: "transmission".into(),
        value: "true".into(),
        expected: "false: the OpenPBR and glTF materials woven writes do not pass light \
                   between or through the yarns yet (woven render, the Mitsuba plugin and \
                   woven.blender do); with transmission = false they carry the cloth's \
                   reflection, its holes black"
            .into(),
    })
}

/// `surface`'s two families on the standard lobes (module docs).
///
/// # Errors
/// [`FitError`] when a family's BRDF is 0 everywhere (nothing to fit).
pub fn project_surface(surface: &WovenSurface) -> Result<StandardSurface, FitError> {
    let weft = project_family(surface, false)?;
    // Families dyed alike are one projection.
    let warp = if surface.albedos(true) == surface.albedos(false) {
        weft.clone()
    } else {
        project_family(surface, true)?
    };
    Ok(StandardSurface {
        weft,
        warp,
        yarns_per_unit: surface.yarns_per_unit(),
        translucent: surface.yarn_transmittance().map(|t| t.0),
    })
}

/// One family: the shapes from its luminance, then its colours.
fn project_family(surface: &WovenSurface, warp: bool) -> Result<StandardFamily, FitError> {
    let rgb = |wi: Vec3, wo: Vec3| surface.family_brdf(warp, wi, wo).0;
    let reference = Reference::sample(|wi, wo| Rgb(rgb(wi, wo)).luminance());
    let fabric = project_with(&reference, LobeSet::Anisotropic, Objective::Radiance)?;
    let built = fabric.lobes.build()?;
    let values: Vec<[f64; 3]> = reference.pairs.iter().map(|&(i, o)| rgb(i, o)).collect();
    let (mut diffuse, mut specular) = ([0.0; 3], [0.0; 3]);
    for c in 0..3 {
        let [d, s] = channel_weights(&built, &reference.pairs, |k| values[k][c]);
        (diffuse[c], specular[c]) = (d, s);
    }
    Ok(StandardFamily {
        lobes: fabric.lobes,
        diffuse,
        specular,
        sheen: [fabric.lobes.sheen; 3],
        rms_log: fabric.rms_log,
        isotropic_rms_log: fabric.baseline.as_ref().map_or(f64::NAN, |b| b.rms_log),
    })
}

/// One channel's Lambertian albedo (at most 1) and GGX weight, both ≥ 0: the least-squares fit
/// of `value(k)` less the grey sheen at `pairs[k]`, weighted by `cos θi cos θo`.
fn channel_weights(
    lobes: &BuiltLobes,
    pairs: &[(Vec3, Vec3)],
    value: impl Fn(usize) -> f64,
) -> [f64; 2] {
    // The normal equations of the weighted fit: [a b; b c] x = [p; q].
    let (mut a, mut b, mut c, mut p, mut q) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k, &(wi, wo)) in pairs.iter().enumerate() {
        let [lambert, ggx, sheen] = lobes.unit_lobes(wi, wo);
        let w = wi.z * wo.z;
        let y = value(k) - lobes.lobes().sheen * sheen;
        (a, b, c) = (
            a + w * lambert * lambert,
            b + w * lambert * ggx,
            c + w * ggx * ggx,
        );
        (p, q) = (p + w * lambert * y, q + w * ggx * y);
    }
    let alone = |num: f64, den: f64| if den > 0.0 { (num / den).max(0.0) } else { 0.0 };
    let det = a * c - b * b;
    let both = (det > 0.0).then(|| [(p * c - q * b) / det, (q * a - p * b) / det]);
    let [d, s] = match both {
        Some([d, s]) if d >= 0.0 && s >= 0.0 && d <= 1.0 => [d, s],
        _ => {
            // The best fit on the boundary: the albedo at 0 or at 1, or the GGX off.
            let candidates = [
                [0.0, alone(q, c)],
                [1.0, alone(q - b, c)],
                [alone(p, a).min(1.0), 0.0],
            ];
            let cost =
                |[d, s]: [f64; 2]| a * d * d + 2.0 * b * d * s + c * s * s - 2.0 * (p * d + q * s);
            candidates
                .into_iter()
                .min_by(|x, y| cost(*x).total_cmp(&cost(*y)))
                .unwrap_or([0.0, 0.0])
        }
    };
    [d, s]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::projection_pairs;

    fn lobes(alpha: [f64; 2]) -> StandardLobes {
        StandardLobes {
            diffuse: 0.3,
            specular: 1.0,
            alpha,
            sheen: 0.0,
            sheen_roughness: 1.0,
        }
    }

    #[test]
    fn each_channel_s_weights_are_recovered_from_its_own_brdf() {
        let built = lobes([0.08, 0.4]).build().unwrap();
        let pairs = projection_pairs();
        let (diffuse, specular) = ([0.5, 0.1, 0.0], [0.7, 1.6, 0.9]);
        for c in 0..3 {
            let value = |k: usize| {
                let [lambert, ggx, _] = built.unit_lobes(pairs[k].0, pairs[k].1);
                diffuse[c] * lambert + specular[c] * ggx
            };
            let [d, s] = channel_weights(&built, &pairs, value);
            assert!(
                (d - diffuse[c]).abs() < 1e-9 && (s - specular[c]).abs() < 1e-9,
                "{c}"
            );
        }
        // A channel whose best fit would need a negative albedo takes 0 and refits the GGX.
        let [d, s] = channel_weights(&built, &pairs, |k| {
            let [lambert, ggx, _] = built.unit_lobes(pairs[k].0, pairs[k].1);
            0.8 * ggx - 0.05 * lambert
        });
        assert_eq!(d, 0.0);
        assert!(s > 0.7 && s < 0.8, "{s}");
    }

    #[test]
    fn a_radiance_projection_recovers_the_anisotropic_lobes_it_was_made_of() {
        let truth = lobes([0.12, 0.45]).build().unwrap();
        let reference = Reference::sample(|wi, wo| truth.eval(wi, wo));
        let p = project_with(&reference, LobeSet::Anisotropic, Objective::Radiance).unwrap();
        assert!(p.rms_log < 1e-3, "{}", p.rms_log);
        for (got, want) in p.lobes.alpha.iter().zip([0.12, 0.45]) {
            assert!((got - want).abs() < 2e-3, "{:?}", p.lobes);
        }
        assert_eq!(p.lobes.sheen, 0.0);
        assert!(p.baseline.unwrap().rms_log > 10.0 * p.rms_log);
    }

    #[test]
    fn the_renderers_parameters_give_back_the_fitted_roughnesses() {
        let family = |alpha: [f64; 2]| StandardFamily {
            lobes: lobes(alpha),
            diffuse: [0.2; 3],
            specular: [1.0; 3],
            sheen: [0.0; 3],
            rms_log: 0.0,
            isotropic_rms_log: 0.0,
        };
        // Cycles: α_x = r² / √(1 − 0.9 a) along its tangent, α_y = r² √(1 − 0.9 a).
        for alpha in [[0.3, 0.1], [0.05, 0.4], [0.2, 0.2]] {
            let c = family(alpha).cycles();
            let aspect = (1.0 - 0.9 * c.anisotropy).sqrt();
            let (x, y) = (c.roughness.powi(2) / aspect, c.roughness.powi(2) * aspect);
            let along_yarn = if c.rotation == 0.0 { [x, y] } else { [y, x] };
            for k in 0..2 {
                assert!((along_yarn[k] - alpha[k]).abs() < 1e-12, "{alpha:?} {c:?}");
                assert!((c.alpha[k] - alpha[k]).abs() < 1e-12);
            }
            // glTF: α_b = r², α_t = α_b + (1 − α_b) s² along the rougher direction.
            let g = family(alpha).gltf();
            let b = g.roughness.powi(2);
            let t = b + (1.0 - b) * g.anisotropy_strength.powi(2);
            let (hi, lo) = (alpha[0].max(alpha[1]), alpha[0].min(alpha[1]));
            assert!((t - hi).abs() < 1e-12 && (b - lo).abs() < 1e-12);
            assert_eq!(g.along_yarn, alpha[0] >= alpha[1]);
        }
        // Beyond Cycles' reach (a ratio under 0.1) it keeps the geometric mean at ratio 0.1.
        let c = family([0.5, 0.01]).cycles();
        assert!((c.alpha[1] / c.alpha[0] - CYCLES_MIN_ROUGHNESS_RATIO).abs() < 1e-12);
        assert!((c.alpha[0] * c.alpha[1] - 0.005).abs() < 1e-12);
        assert_eq!(c.anisotropy, 1.0);
    }
}
