//! A woven surface's BSDF at one point ([`PointBsdf`]): the point's lobes, its dyes (varied
//! along the yarns by an [`Irregularity`](super::Irregularity)), and the [`Bsdf`] that mixes the lobes.

use super::{Entry, Layout, LobeMix, SurfacePoint, WovenSurface};
use crate::bsdf::{known_and_drawn, pair_of, Bsdf, BsdfSample, LobeFlags, Transport};
use crate::color::Rgb;
use crate::table::Albedos;
use crate::Vec3;
use std::borrow::Cow;

impl WovenSurface {
    /// The surface's BSDF at `at`.
    #[inline]
    pub fn at(&self, at: &SurfacePoint) -> PointBsdf<'_> {
        // A blank point made this surface's at `at` by the one routine that also rebuilds a
        // renderer's slot (`at_into`).
        let mut point = PointBsdf {
            surface: self,
            entry: None,
            mix: LobeMix::default(),
            seen: std::sync::OnceLock::new(),
            weft: self.dyes.weft,
            warp: self.dyes.warp,
            factors: [1.0, 1.0],
            glow: None,
        };
        point.reset(self, at);
        point
    }

    /// The surface's BSDF at `at`, built into `slot`: over the BSDF a previous point left there
    /// (of any surface that outlives it), field by field, or anew into an empty slot. A path
    /// tracer keeps one slot a path: a point's BSDF is over a kilobyte, and building it anew
    /// and moving it into place was a tenth of a plane's render time.
    #[inline]
    pub fn at_into<'a>(&'a self, at: &SurfacePoint, slot: &mut Option<PointBsdf<'a>>) {
        match slot {
            Some(point) => point.reset(self, at),
            None => *slot = Some(self.at(at)),
        }
    }

    /// The irregularity that varies this surface's yarns, one by one along their length: an
    /// active one on a pattern (only there are yarns laid out one by one), else `None`.
    pub fn varying_dyes(&self) -> Option<&super::Irregularity> {
        (self.dyes.irregularity.is_active() && matches!(self.layout, Layout::Pattern { .. }))
            .then_some(&self.dyes.irregularity)
    }

    /// The weft's and the warp's dye factors at `at` ([`Irregularity::factor`](super::Irregularity::factor) of the yarns
    /// through the point); 1 and 1 without irregularity.
    pub fn dye_factors(&self, at: &SurfacePoint) -> [f64; 2] {
        let Some(irregularity) = self.varying_dyes() else {
            return [1.0, 1.0];
        };
        let x = at.uv[0] * self.yarns_per_unit[0];
        let y = at.uv[1] * self.yarns_per_unit[1];
        if !(x.is_finite() && y.is_finite()) {
            return [1.0, 1.0];
        }
        // The weft runs along x: its yarns are the rows, its length x; the warp the other way.
        [
            irregularity.factor(y.floor() as i64, false, x),
            irregularity.factor(x.floor() as i64, true, y),
        ]
    }
}

/// `albedos` with the body scaled by `factor` (an [`Irregularity`](super::Irregularity)'s), each kept in its range
/// (`ρ0 ≤` [`Albedos::MAX_DYED_DIFFUSE`], `ρ ≤ 1`, as [`Albedos::dyed`] keeps them).
fn scaled(albedos: [Albedos; 3], factor: f64) -> [Albedos; 3] {
    if factor == 1.0 {
        return albedos;
    }
    albedos.map(|a| Albedos {
        diffuse: (a.diffuse * factor).min(Albedos::MAX_DYED_DIFFUSE),
        interreflection: (a.interreflection * factor).min(1.0),
    })
}

/// `τ` per channel for these dyes (the body albedos `ρ0`), the weft's share `g` of the weave
/// ([`translucent`](super::translucent)).
pub(super) fn tau(g: f64, weft: &[Albedos; 3], warp: &[Albedos; 3]) -> [f64; 3] {
    use super::translucent::{slab_transmitted_share, YARN_SCATTERING_DEPTH};
    let share = |a: &Albedos| slab_transmitted_share(a.diffuse, YARN_SCATTERING_DEPTH);
    std::array::from_fn(|c| g * share(&weft[c]) + (1.0 - g) * share(&warp[c]))
}

/// A woven surface's BSDF at one point: its mixture of lobes.
#[derive(Clone, Debug)]
pub struct PointBsdf<'a> {
    surface: &'a WovenSurface,
    /// On a relief, where the viewer's ray enters it: the lobes it meets depend on the view.
    entry: Option<Entry>,
    /// The lobes that do not depend on the view.
    mix: LobeMix,
    /// The first view's lobes on a relief ([`mix_seen_from`](Self::mix_seen_from)).
    seen: std::sync::OnceLock<(Vec3, LobeMix)>,
    weft: [Albedos; 3],
    warp: [Albedos; 3],
    /// The weft's and the warp's dye factors here ([`WovenSurface::dye_factors`]).
    factors: [f64; 2],
    /// The light through the yarns here, where the surface transmits.
    glow: Option<Glow>,
}

/// What a point transmits through its yarns ([`translucent`](super::translucent)).
#[derive(Clone, Copy, Debug)]
struct Glow {
    /// `τ` per channel: the Kubelka–Munk share of the point's dyes, the families mixed by their
    /// shares of the weave.
    tau: [f64; 3],
    /// The point's share of the cloth's `f_t`: 1 at the cloth level; at the yarn level
    /// `1 / (1 − gap²)` on a yarn and 0 in a hole; blended by the footprint between.
    weight: f64,
    /// Where the point lies for the light through it (what it passes straight through).
    through: super::pass::Through,
}

impl<'a> PointBsdf<'a> {
    /// The lobes mixed here.
    pub fn mix(&self) -> LobeMix {
        self.mix_seen_from(Vec3::new(0.0, 0.0, 1.0)).into_owned()
    }

    /// The lobes mixed here for a viewer toward `view` (or, drawing for a known light, toward
    /// it): on a relief, the yarn that the ray toward `view` meets first. Borrowed where it can
    /// be: a mix is over half a kilobyte, and eval, sample and pdf each ask for it.
    #[inline]
    pub fn mix_seen_from(&self, view: Vec3) -> Cow<'_, LobeMix> {
        let Some(e) = &self.entry else {
            return Cow::Borrowed(&self.mix);
        };
        // A renderer asks for the same view several times at a vertex (eval, sample, pdf): the
        // first view's march is kept.
        let (seen, mix) = self
            .seen
            .get_or_init(|| (view, self.surface.with_relief(self.mix, e, view)));
        if *seen == view {
            Cow::Borrowed(mix)
        } else {
            Cow::Owned(self.surface.with_relief(self.mix, e, view))
        }
    }

    /// This BSDF made `surface`'s at `at`, in place: every field set anew (what
    /// [`WovenSurface::at`] and [`WovenSurface::at_into`] build with).
    #[inline]
    fn reset(&mut self, surface: &'a WovenSurface, at: &SurfacePoint) {
        let factors = surface.dye_factors(at);
        self.surface = surface;
        self.seen = std::sync::OnceLock::new();
        self.weft = scaled(surface.dyes.weft, factors[0]);
        self.warp = scaled(surface.dyes.warp, factors[1]);
        self.factors = factors;
        self.mix.clear();
        self.entry = surface.split_into(at, &mut self.mix);
        self.glow = self.glow_at(at);
    }

    /// The point's [`Glow`], where the surface transmits (and has yarns).
    fn glow_at(&self, at: &SurfacePoint) -> Option<Glow> {
        let s = self.surface;
        if !s.transmits() || matches!(s.layout, Layout::Flat { .. }) {
            return None;
        }
        let t = s.through(at);
        let yarn = if t.hole {
            0.0
        } else {
            1.0 / (1.0 - s.gap * s.gap)
        };
        Some(Glow {
            tau: tau(s.weft_fraction(), &self.weft, &self.warp),
            weight: t.cloth + (1.0 - t.cloth) * yarn,
            through: t,
        })
    }

    /// `f_t(wi, wo)` here, `wi` and `wo` on opposite sides (0 where nothing is transmitted).
    fn eval_transmission(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let Some(glow) = &self.glow else {
            return Rgb::BLACK;
        };
        let f = self.surface.translucency().eval(wi, wo);
        Rgb(std::array::from_fn(|c| glow.tau[c] * glow.weight * f.0[c]))
    }

    /// The probability that [`sample`](Bsdf::sample) draws through the cloth for `known`: the
    /// luminance of what is transmitted from it against what is reflected (held in
    /// `[0.05, 0.95]`), 0 where nothing is.
    fn transmission_choice(&self, known: Vec3) -> f64 {
        let Some(glow) = &self.glow else {
            return 0.0;
        };
        let r = self.surface.translucency().transmitted(known);
        let t = Rgb(std::array::from_fn(|c| glow.tau[c] * glow.weight * r.0[c])).luminance();
        if t <= 0.0 {
            return 0.0;
        }
        let reflected = (1.0 - self.surface.open_along(known) - r.luminance()).max(0.0);
        (t / (t + reflected)).clamp(0.05, 0.95)
    }

    /// The same point with other dyes where given (a textured colour, read at the point), each
    /// channel clamped to `[0, 1]`, and varied along the yarns as the surface's are.
    pub fn dyed(mut self, weft_color: Option<Rgb>, warp_color: Option<Rgb>) -> Self {
        if weft_color.is_some() {
            self.weft = scaled(self.surface.dyes.own.dyed(weft_color), self.factors[0]);
        }
        if warp_color.is_some() {
            self.warp = scaled(self.surface.dyes.own.dyed(warp_color), self.factors[1]);
        }
        if let Some(glow) = self.glow {
            self.glow = Some(Glow {
                tau: tau(self.surface.weft_fraction(), &self.weft, &self.warp),
                ..glow
            });
        }
        self
    }

    fn pdf_mix(&self, mix: &LobeMix, known: Vec3, drawn: Vec3) -> f64 {
        let mut p = 0.0;
        for l in mix.lobes() {
            p += l.weight * self.surface.lobe_pdf(l, known, drawn);
        }
        let total = mix.total();
        if total == 1.0 || total == 0.0 {
            p
        } else {
            p / total
        }
    }
}

impl Bsdf for PointBsdf<'_> {
    type Value = Rgb;

    fn lobes(&self) -> LobeFlags {
        let flags = LobeFlags::REFLECTION | LobeFlags::GLOSSY | LobeFlags::DIFFUSE;
        let flags = flags | LobeFlags::ANISOTROPIC;
        let flags = if self.glow.is_some() {
            flags | LobeFlags::TRANSMISSION
        } else {
            flags
        };
        if self.surface.uses_footprint() {
            flags | LobeFlags::SPATIALLY_VARYING
        } else {
            flags
        }
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z * wo.z < 0.0 {
            return self.eval_transmission(wi, wo);
        }
        self.eval_reflection(wi, wo)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        if known.z <= 0.0 {
            return 0.0;
        }
        let q = self.transmission_choice(known);
        if drawn.z < 0.0 {
            if q > 0.0 {
                q * self.surface.translucency().pdf(known, drawn)
            } else {
                0.0
            }
        } else {
            (1.0 - q) * self.pdf_reflection(wi, wo, mode)
        }
    }

    fn sample(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Rgb>> {
        if known.z <= 0.0 {
            return None;
        }
        let q = self.transmission_choice(known);
        if uc < q {
            // Through the yarns: the forward lobe or a cosine lobe on the far side.
            let table = self.surface.translucency();
            let drawn = table.sample(known, uc / q, u)?;
            let pdf = q * table.pdf(known, drawn);
            let (wi, wo) = pair_of(known, drawn, mode);
            return (pdf > 0.0).then(|| BsdfSample {
                wi,
                wo,
                f: self.eval_transmission(wi, wo),
                pdf,
                lobe: LobeFlags::TRANSMISSION | LobeFlags::DIFFUSE,
            });
        }
        let uc = if q > 0.0 { (uc - q) / (1.0 - q) } else { uc };
        let mut s = self.sample_reflection(known, uc.clamp(0.0, 1.0), u, mode)?;
        s.pdf *= 1.0 - q;
        Some(s)
    }

    /// The share passed straight through here ([`WovenSurface::pass_through`]), from where the
    /// point lies as its reset found it.
    fn pass_through(&self, d: Vec3) -> f64 {
        self.glow
            .as_ref()
            .map_or(0.0, |g| self.surface.passed(g.through, d))
    }

    /// The warp lobes' share of the weights the view meets (on a relief, the yarn the ray
    /// toward `wo` meets first); 0 over a hole.
    fn warp_share(&self, wo: Vec3) -> f64 {
        let mix = self.mix_seen_from(wo);
        let total = mix.total();
        if total > 0.0 {
            let warp: f64 = mix
                .lobes()
                .iter()
                .filter(|l| l.warp)
                .map(|l| l.weight)
                .sum();
            warp / total
        } else {
            0.0
        }
    }
}

impl PointBsdf<'_> {
    /// The reflection alone: the paper's BRDF at this point (0 unless both directions are
    /// above).
    pub(super) fn eval_reflection(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::BLACK;
        }
        if let Layout::Flat { model } = &self.surface.layout {
            let affine = model.eval_affine(wi, wo);
            return Rgb(self
                .weft
                .map(|a| affine.at(a.diffuse, a.interreflection).max(0.0)));
        }
        let mut f = Rgb::BLACK;
        // Both families' relief ratios in one read, when a resolved macro lobe needs them.
        let mut ratios = None;
        for l in self.mix_seen_from(wo).lobes() {
            let albedos = if l.warp { &self.warp } else { &self.weft };
            let ratio = l.resolved.then(|| {
                ratios.get_or_insert_with(|| self.surface.relief_ratios(wi, wo))
                    [usize::from(l.warp)]
            });
            f += self.surface.lobe_eval(l, albedos, wi, wo, ratio) * l.weight;
        }
        f
    }

    /// The density of [`sample_reflection`](Self::sample_reflection)'s draws.
    fn pdf_reflection(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let (known, drawn) = known_and_drawn(wi, wo, mode);
        self.pdf_mix(&self.mix_seen_from(known), known, drawn)
    }

    /// A draw of the reflection alone (the lobes' mixture), its density the mixture's.
    pub(super) fn sample_reflection(
        &self,
        known: Vec3,
        uc: f64,
        u: [f64; 2],
        mode: Transport,
    ) -> Option<BsdfSample<Rgb>> {
        if known.z <= 0.0 {
            return None;
        }
        // A lobe with probability ∝ its weight; the density is the mixture's.
        let mix = self.mix_seen_from(known);
        let lobes = mix.lobes();
        let last = lobes.len().checked_sub(1)?;
        let x = uc * mix.total();
        let mut before = 0.0;
        let mut pick = 0;
        while pick < last && x >= before + lobes[pick].weight {
            before += lobes[pick].weight;
            pick += 1;
        }
        let (drawn, pdf) = self.surface.lobe_sample(&lobes[pick], known, u)?;
        // A mixture's density is the mean of its lobes'.
        let pdf = if lobes.len() == 1 {
            pdf
        } else {
            self.pdf_mix(&mix, known, drawn)
        };
        let (wi, wo) = pair_of(known, drawn, mode);
        (pdf > 0.0 && pdf.is_finite()).then(|| BsdfSample {
            wi,
            wo,
            f: self.eval_reflection(wi, wo),
            pdf,
            lobe: LobeFlags::REFLECTION | LobeFlags::GLOSSY,
        })
    }
}
