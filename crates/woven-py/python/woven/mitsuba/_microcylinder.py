"""The ``woven`` BSDF for a microcylinder fabric (Sadeghi et al. 2013): the library, lane by lane."""

from __future__ import annotations

from ._surface import _Lanes, _WOVEN_ONLY_KEYS


def _microcylinder_class(mi):
    """The BSDF class of a microcylinder fabric for the current variant: the library's
    ``woven.Microcylinder``, lane by lane (RGB variants only)."""
    import drjit as dr

    jit = dr.is_jit_v(mi.Float)

    class MicrocylinderBSDF(mi.BSDF):
        """A microcylinder fabric (Sadeghi et al. 2013) through the ``woven`` plugin:
        ``material = "microcylinder-..."`` or a fabric file. The library evaluates, samples and
        weighs it lane by lane (JIT variants in Dr.Jit's evaluated mode); spectral variants
        refuse it by name."""

        def __init__(self, props, fabric):
            mi.BSDF.__init__(self, props)
            name = str(props["material"])
            if not mi.is_rgb:
                raise ValueError(
                    f"woven BSDF: `material` = {name!r} is a microcylinder fabric, whose values"
                    f" are RGB: the {mi.variant()} variant is not an RGB variant; use an RGB"
                    " variant (scalar_rgb, llvm_ad_rgb, cuda_ad_rgb)"
                )
            extra = [k for k in _WOVEN_ONLY_KEYS if k in props]
            if extra:
                raise ValueError(
                    f"woven BSDF: `material` = {name!r} is a microcylinder fabric:"
                    f" {', '.join(f'`{k}`' for k in extra)} apply to woven materials only"
                )
            self.fabric = fabric
            self.why = f"`material` = {name!r} is a microcylinder fabric (no Dr.Jit port)"
            flags = (
                mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.Anisotropic
            )
            self.m_flags = flags
            self.m_components = [flags]

        # Mitsuba's si.wi is toward the viewer (woven's wo), its wo toward the light (woven's
        # wi); sample draws the light direction for the viewer: the library's radiance mode.

        def eval(self, ctx, si, wo, active=True):
            active = mi.Bool(active) & (si.wi.z > 0) & (wo.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection) or (not jit and not active):
                return mi.Color3f(0.0)
            lanes = _Lanes(mi, dr, self.why)
            f = lanes.color(self.fabric.eval(lanes.dirs(wo, active), lanes.dirs(si.wi, active)))
            return dr.select(active, f * wo.z, 0.0)

        def pdf(self, ctx, si, wo, active=True):
            active = mi.Bool(active) & (si.wi.z > 0) & (wo.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection) or (not jit and not active):
                return mi.Float(0.0)
            lanes = _Lanes(mi, dr, self.why)
            p = self.fabric.pdf(lanes.dirs(wo, active), lanes.dirs(si.wi, active), "radiance")
            return dr.select(active, lanes.floats(p), 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            bs = mi.BSDFSample3f()
            active = mi.Bool(active) & (si.wi.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection) or (not jit and not active):
                return bs, mi.Color3f(0.0)
            lanes = _Lanes(mi, dr, self.why)
            d, f, pdf = self.fabric.sample(
                lanes.dirs(si.wi, active),
                lanes.cols(sample1, 1, active, 0.5)[:, 0],
                lanes.cols(sample2, 2, active, 0.5),
                "radiance",
            )
            wo, pdf, f = lanes.vector(d), lanes.floats(pdf), lanes.color(f)
            active &= (pdf > 0) & (wo.z > 0)
            if not jit and not active:
                return bs, mi.Color3f(0.0)
            bs.wo = wo
            bs.pdf = dr.select(active, pdf, 0.0)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            weight = dr.select(active, f * (wo.z / dr.select(active, pdf, 1.0)), 0.0)
            return bs, weight

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"MicrocylinderBSDF[{self.fabric!r}]"

    return MicrocylinderBSDF
