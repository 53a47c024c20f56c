"""The ``woven`` BSDF class for a variant: traced in Dr.Jit where the library's route says so
(``Surface.route``), else the library lane by lane."""

from __future__ import annotations

import numpy as np

from ._float import _const
from ._frames import FLAT, FLOAT, _tilt_from, _tilt_into, _turn, _unturn
from ._layout import JitLayout
from ._surface import _Lanes, _NEEDS_DIFFERENTIALS, _surface
from ._table import JitTable


# A face's directions as the library takes them: the front's as they are, the back's turned
# half a turn about the weft, (x, y, z) → (x, −y, −z) (an involution: it turns them back too).
_AS_IS = np.array([1.0, 1.0, 1.0])
_TURNED = np.array([1.0, -1.0, -1.0])


def _bsdf_class(mi):
    """The BSDF class for the current variant."""
    import drjit as dr

    jit = dr.is_jit_v(mi.Float)

    class WovenBSDF(mi.BSDF):
        """The woven cloth BSDF (see the module ``woven.mitsuba``)."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            if not mi.is_rgb:
                raise ValueError(
                    f"woven BSDF: the {mi.variant()} variant is not an RGB variant, and the"
                    " woven cloth's values are RGB; use an RGB variant (scalar_rgb, llvm_ad_rgb,"
                    " cuda_ad_rgb), or for a spectral one `woven export --format rgl --spectral`"
                    " and Mitsuba's `measured` BSDF"
                )
            self.surface, self.textures = _surface(props, mi)
            self.filter = self.surface.footprint_filter
            self.table = self.surface.table
            self.material = self.surface.material
            # A cloth that lets light through (the library answers it: Surface.route): two-sided,
            # its back face seen from behind, light through the yarns a diffuse transmission and
            # light straight between them Mitsuba's null component.
            self.transmits = self.surface.transmits
            self.back = self.surface.back
            extra = 0
            if self.surface.uses_footprint or self.textures:
                extra |= int(mi.BSDFFlags.SpatiallyVarying)
            lay = self.surface.layout()
            if self.filter and (self.surface.uses_footprint or lay["detail"] == "auto"):
                # Integrators that can (``direct``, ``aov``, ``woven_path``) then compute
                # si.duv_dx, si.duv_dy (BSDFFlags::NeedsDifferentials, which Mitsuba's Python
                # enum leaves out).
                extra |= _NEEDS_DIFFERENTIALS
            reflection = (
                mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.Anisotropic
            )
            if self.transmits:
                sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
                components = [
                    reflection | mi.BSDFFlags.BackSide,
                    mi.BSDFFlags.DiffuseTransmission | sides,
                    mi.BSDFFlags.Null | sides,
                ]
            else:
                components = [reflection]
            self.m_components = [int(c) | extra for c in components]
            flags = 0
            for c in self.m_components:
                flags |= c
            self.m_flags = flags
            # The library's dye rule as constants, for colours read per lane (textures).
            self.dye_rule = lay["dye_rule"]
            # Where the library answers each lane (every variant's scalar calls, and in JIT
            # variants the levels Dr.Jit does not trace: see the module's docs).
            # The library decides which surfaces a JIT variant traces (Surface.route).
            self.library = not jit or self.surface.route is not None
            self.why = self.surface.route if jit else None
            if jit and not self.library:
                self.jt = JitTable(self.table, mi)
                self.layout = JitLayout(self.surface, mi, self.filter)
                # A whole tilted float's table (Table::tilted): one look-up.
                tilted = self.layout.float is not None
                self.jt_float = JitTable(self.surface.float_table, mi) if tilted else None

        # -- colour ---------------------------------------------------------------------------

        def _dye(self, key, si, active):
            """(ρ0, ρ) per channel for the weft or the warp at ``si``: a textured colour read
            there, dyed by the library's rule (``Albedos::dye_rule``, its constants from the
            layout), else the layout's albedos."""
            c = self.textures.get(key)
            if c is None:
                a = self.layout.albedos["warp" if key == "warp_color" else "weft"]
                return mi.Color3f(*(x[0] for x in a)), mi.Color3f(*(x[1] for x in a))
            # A NaN texel is black, the library's dye rule (Albedos::dyed); left NaN it made
            # NaN samples, which the film's filter spread over neighbouring pixels.
            # In [0, 1], as the library path takes it (an HDR texture saturates).
            c = c.eval(si, active)
            c = dr.clip(dr.select(dr.isnan(c), 0.0, c), 0.0, 1.0)
            cap, slope, offset = self.dye_rule
            return dr.minimum(c, cap), dr.clip(slope * c + offset, 0.0, 1.0)

        def _varied(self, albedos, si, family):
            """``albedos`` scaled by the irregularity's factor of ``family`` (0 the weft, 1 the
            warp) at ``si``, each kept in its range (the library's ``scaled``: ρ0 ≤ the dye
            rule's cap, ρ ≤ 1)."""
            irregular = self.layout.irregular
            if irregular is None or not irregular.varies(family):
                return albedos
            m = irregular.factor(si, family)
            return dr.minimum(albedos[0] * m, self.dye_rule[0]), dr.minimum(albedos[1] * m, 1.0)

        def _albedos(self, warp, si, active):
            weft = self._varied(self._dye("weft_color", si, active), si, 0)
            if warp is False:
                return weft
            warp_a = self._varied(self._dye("warp_color", si, active), si, 1)
            if warp is True:
                return warp_a
            return (dr.select(warp, warp_a[0], weft[0]), dr.select(warp, warp_a[1], weft[1]))

        # -- JIT: one lobe in Dr.Jit (WovenSurface::lobe_eval, lobe_pdf, lobe_sample) ----------

        def _lobe_eval(self, lobe, s, v, si, active):
            """One lobe's f per channel for light from ``s`` seen from ``v``: flat, a point of a
            tilted float (the facet the viewer's ray meets, if lit: f′ cos θ′i / cos θi) or a
            whole float (its own table's look-up)."""
            warp, along, _ = lobe
            a, b = _turn(mi, dr, s, warp), _turn(mi, dr, v, warp)
            rho0, rho = self._albedos(warp, si, active)
            fl = self.layout.float
            if _const(along, FLAT) or fl is None:
                return self.jt.eval_dyed(a, b, rho0, rho, active)
            if _const(along, FLOAT):
                return self.jt_float.eval_dyed(a, b, rho0, rho, active)
            # Lanes: an entry fraction, or flat (ψ = 0: the same look-up, bit for bit).
            flat = along < 0
            t = fl.seen_at(dr.select(flat, 0.0, along), b)
            lo, hi, ok = fl.lit(a)
            lit = flat | (ok & (t >= lo) & (t <= hi))
            sn, cs = dr.sincos(dr.select(flat, 0.0, fl.tilt(t)))
            ta, tb = _tilt_into(mi, a, sn, cs), _tilt_into(mi, b, sn, cs)
            ok = active & lit & (ta.z > 0) & (tb.z > 0)
            f = self.jt.eval_dyed(ta, tb, rho0, rho, ok)
            return dr.select(ok, f * (ta.z / dr.select(ok, a.z, 1.0)), 0.0)

        def _tilted_pdf(self, k, d, sn, cs, active):
            k, d = _tilt_into(mi, k, sn, cs), _tilt_into(mi, d, sn, cs)
            active = active & (k.z > 0) & (d.z > 0)
            return dr.select(active, self.jt.pdf(k, d, active), 0.0)

        def _lobe_pdf(self, lobe, known, drawn, active):
            """One lobe's density: a point of a float in the tilt of the facet ``known``'s ray
            meets, a whole float its own table's."""
            warp, along, _ = lobe
            k, d = _turn(mi, dr, known, warp), _turn(mi, dr, drawn, warp)
            fl = self.layout.float
            if _const(along, FLAT) or fl is None:
                return dr.select(active, self.jt.pdf(k, d, active), 0.0)
            if _const(along, FLOAT):
                return dr.select(active, self.jt_float.pdf(k, d, active), 0.0)
            flat = along < 0
            t = fl.seen_at(dr.select(flat, 0.0, along), k)
            sn, cs = dr.sincos(dr.select(flat, 0.0, fl.tilt(t)))
            return self._tilted_pdf(k, d, sn, cs, active)

        def _eval_jit(self, si, wo, active):
            s, v = wo, si.wi  # Mitsuba's wo is toward the light: woven's wi (s)
            f = mi.Color3f(0.0)
            for lobe in self.layout.lobes(si):
                f += self._lobe_eval(lobe, s, v, si, active & (lobe[2] > 0)) * lobe[2]
            return f

        def _pdf_mix(self, lobes, known, drawn, active):
            p, total = mi.Float(0.0), mi.Float(0.0)
            for lobe in lobes:
                p += lobe[2] * self._lobe_pdf(lobe, known, drawn, active & (lobe[2] > 0))
                total += lobe[2]
            return dr.select(total > 0, p / dr.select(total > 0, total, 1.0), 0.0)

        def _pdf_jit(self, si, wo, active):
            # Drawn for a camera path: the viewer si.wi is known, the light direction drawn.
            return self._pdf_mix(self.layout.lobes(si), si.wi, wo, active)

        def _sample_jit(self, si, sample1, sample2, active):
            """(wo, pdf, ok): a lobe picked with ``sample1`` in proportion to its weight, a
            direction drawn from it with ``sample2`` (``WovenSurface::lobe_sample``: a point of
            a float in the tilt its facet seen from ``si.wi`` has, a whole float from its own
            table), the mixture's density."""
            lobes = self.layout.lobes(si)
            total = mi.Float(0.0)
            for lobe in lobes:
                total += lobe[2]
            x = sample1 * total
            # The picked lobe's warp and along, per lane (the first whose cumulative weight
            # exceeds x; the last where rounding leaves none).
            warp, along = mi.Bool(False), mi.Float(FLAT)
            found, before = mi.Bool(False), mi.Float(0.0)
            for i, (lw, lt, lg) in enumerate(lobes):
                take = ~found & ((x < before + lg) | (i == len(lobes) - 1)) & (lg > 0)
                warp = dr.select(take, lw, warp)
                along = dr.select(take, lt, along)
                found |= take
                before += lg
            active = active & found
            known = _turn(mi, dr, si.wi, warp)
            u0 = sample2.x
            fl = self.layout.float
            # Lanes on a point of a tilted float draw in the tilt of the facet their ray meets.
            points = fl is not None and any(not isinstance(lt, float) for _, lt, _ in lobes)
            if points:
                plain = (along < 0) | (along > 1.5)
                t = fl.seen_at(dr.select(plain, 0.0, along), known)
                sn, cs = dr.sincos(dr.select(plain, 0.0, fl.tilt(t)))
                known = _tilt_into(mi, known, sn, cs)
            active &= known.z > 0
            d, pdf, ok = self.jt.sample_direction(known, u0, sample2.y, active)
            if fl is not None and any(not isinstance(lt, float) or lt == FLOAT for _, lt, _ in lobes):
                # Lanes on a whole float draw from its own table.
                whole = along > 1.5
                dw, pw, okw = self.jt_float.sample_direction(known, u0, sample2.y, active & whole)
                d, pdf, ok = dr.select(whole, dw, d), dr.select(whole, pw, pdf), dr.select(whole, okw, ok)
            if points:
                d = _tilt_from(mi, d, sn, cs)
            wo = _unturn(mi, dr, d, warp)
            ok &= active & (wo.z > 0)
            if len(lobes) > 1:
                pdf = self._pdf_mix(lobes, si.wi, wo, ok)
            return wo, pdf, ok

        # -- the BSDF interface ----------------------------------------------------------------

        def _enabled(self, ctx):
            """Whether ``ctx`` enables any of the components."""
            if not self.transmits:
                return ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
            return any(ctx.is_enabled(mi.BSDFFlags(c & 0x7FF), i)
                       for i, c in enumerate(self.m_components))

        def _sides(self, ctx, si, wo, active):
            """The lanes a call answers: ``si.wi`` and ``wo`` above (an opaque cloth), or, where
            light passes through, on any side whose component ``ctx`` enables (reflection where
            they share a side, transmission where they do not)."""
            active = mi.Bool(active)
            if not self.transmits:
                return active & (si.wi.z > 0) & (wo.z > 0)
            reflect = mi.Bool(ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 0))
            through = mi.Bool(ctx.is_enabled(mi.BSDFFlags.DiffuseTransmission, 1))
            same = si.wi.z * wo.z > 0
            return active & (si.wi.z != 0) & (wo.z != 0) & dr.select(same, reflect, through)

        def eval(self, ctx, si, wo, active=True):
            active = self._sides(ctx, si, wo, active)
            if not self._enabled(ctx) or (not jit and not active):
                return mi.Color3f(0.0)
            if self.library:
                f = self._lib_eval(si, wo, active)
            else:
                f = self._eval_jit(si, wo, active)
            return dr.select(active, f * dr.abs(wo.z), 0.0)

        def pdf(self, ctx, si, wo, active=True):
            active = self._sides(ctx, si, wo, active)
            if not self._enabled(ctx) or (not jit and not active):
                return mi.Float(0.0)
            if self.library:
                p = self._lib_pdf(si, wo, active)
            else:
                p = self._pdf_jit(si, wo, active)
            return dr.select(active, p, 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def eval_null_transmission(self, si, active=True):
            """The share of the light along ``si.wi`` that passes straight between the yarns
            (0 where the cloth does not let light through): what ``woven_path``'s and
            ``volpath``'s shadow rays carry through the cloth."""
            if not self.transmits:
                return mi.Spectrum(0.0)
            return mi.Spectrum(dr.select(mi.Bool(active), self._lib_passed(si, active), 0.0))

        def sample(self, ctx, si, sample1, sample2, active=True):
            bs = mi.BSDFSample3f()
            active = mi.Bool(active) & ((si.wi.z != 0) if self.transmits else (si.wi.z > 0))
            if not self._enabled(ctx) or (not jit and not active):
                return bs, mi.Color3f(0.0)
            # Straight through with the share that passes (Mitsuba's null component: the
            # direction on, the throughput unchanged), the rest drawn from the other lobes.
            passed = mi.Float(0.0)
            if self.transmits and ctx.is_enabled(mi.BSDFFlags.Null, 2):
                passed = dr.select(active, self._lib_passed(si, active), 0.0)
            null = mi.Bool(active & (sample1 < passed))
            drawn = mi.Bool(active & ~null)
            sample1 = dr.clip((sample1 - passed) / dr.select(passed < 1, 1 - passed, 1), 0, 1)
            if not jit and null:
                return self._passed_sample(bs, si, passed)
            if self.library:
                # The library's draw carries its f: no second call to evaluate it.
                wo, pdf, f = self._lib_sample(si, sample1, sample2, drawn)
                f = f * dr.abs(wo.z)
            else:
                wo, pdf, ok = self._sample_jit(si, sample1, sample2, drawn)
                drawn &= ok
                f = self.eval(ctx, si, wo, drawn)
            drawn = mi.Bool(drawn & self._sides(ctx, si, wo, drawn) & (pdf > 0))
            if not jit and not drawn:
                return bs, mi.Color3f(0.0)
            pdf = pdf * (1 - passed)
            same = wo.z * si.wi.z > 0
            bs.wo = dr.select(null, -si.wi, wo)
            bs.eta = 1.0
            bs.pdf = dr.select(null, passed, dr.select(drawn, pdf, 0.0))
            # The component drawn, in m_components' order, and its type.
            bs.sampled_component = mi.UInt32(dr.select(null, 2, dr.select(same, 0, 1)))
            reflected, through = +mi.BSDFFlags.GlossyReflection, +mi.BSDFFlags.DiffuseTransmission
            bs.sampled_type = mi.UInt32(
                dr.select(null, +mi.BSDFFlags.Null, dr.select(same, reflected, through)))
            weight = dr.select(drawn, f / dr.select(drawn, pdf, 1.0), 0.0)
            return bs, dr.select(null, 1.0, weight)

        def _passed_sample(self, bs, si, passed):
            """A scalar variant's draw straight through the gaps."""
            bs.wo, bs.eta, bs.pdf = -si.wi, 1.0, passed
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.Null)
            bs.sampled_component = mi.UInt32(2)
            return bs, mi.Color3f(1.0)

        # -- the library's woven.Surface, lanes as arrays (scalar variants: one lane) ----------

        @property
        def _lib(self):
            return _Lanes(mi, dr, self.why)

        def _lib_points(self, si, active):
            """uv (N, 2) and the footprint (N, 4) as the library takes them (zero where the
            filter is off or the integrator left the partials unset: no footprint known)."""
            lanes = self._lib
            uv = lanes.cols(si.uv, 2, active, 0.0)
            if not self.filter:
                return uv, np.zeros((len(uv), 4))
            a, b = lanes.cols(si.duv_dx, 2, active, 0.0), lanes.cols(si.duv_dy, 2, active, 0.0)
            fp = np.concatenate([a, b], axis=1)
            return uv, np.where(np.isfinite(fp), fp, 0.0)

        def _lib_args(self, si, wo, active):
            uv, fp = self._lib_points(si, active)
            lanes = self._lib
            # Mitsuba's wo is toward the light (woven's wi), si.wi toward the viewer.
            return uv, lanes.dirs(wo, active), lanes.dirs(si.wi, active), fp

        def _faces(self, v):
            """The face that answers each lane, as [(surface, rows, turn)]: the front where the
            viewer ``v`` (N, 3) is above it, and where the cloth lets light through, the back
            where it is below, its directions turned over about the weft (``turn``: y and z
            reversed, as ``woven render`` turns the frame of a hit from behind)."""
            if not self.transmits:
                return [(self.surface, np.ones(len(v), dtype=bool), _AS_IS)]
            below = v[:, 2] < 0
            return [(self.surface, ~below, _AS_IS), (self.back or self.surface, below, _TURNED)]

        def _lib_dyes(self, si, active):
            lanes = self._lib
            # The library takes dyes in [0, 1]: a texture outside (HDR, scaled) saturates, and
            # a NaN texel is black (the library's dye rule).
            return {k: np.clip(np.nan_to_num(lanes.cols(t.eval(si, active), 3, active, 0.0),
                                             nan=0.0), 0.0, 1.0)
                    for k, t in self.textures.items()}

        def _lib_eval(self, si, wo, active):
            uv, s, v, fp = self._lib_args(si, wo, active)
            dyes = self._lib_dyes(si, active)
            f = np.zeros((len(uv), 3))
            for surface, rows, turn in self._faces(v):
                if rows.any():
                    f[rows] = surface.eval(uv[rows], s[rows] * turn, v[rows] * turn, fp[rows],
                                           **{k: c[rows] for k, c in dyes.items()})
            return self._lib.color(f)

        def _lib_pdf(self, si, wo, active):
            uv, s, v, fp = self._lib_args(si, wo, active)
            p = np.zeros(len(uv))
            for surface, rows, turn in self._faces(v):
                if rows.any():
                    p[rows] = surface.pdf(uv[rows], s[rows] * turn, v[rows] * turn, fp[rows])
            if self.transmits:
                p *= 1.0 - self._lib_passes(uv, v, fp)
            return self._lib.floats(p)

        def _lib_passes(self, uv, v, fp):
            """The share (N,) passed straight through along the viewer's ``v`` at each lane."""
            out = np.zeros(len(uv))
            for surface, rows, turn in self._faces(v):
                if rows.any():
                    out[rows] = surface.pass_through(uv[rows], v[rows] * turn, fp[rows])
            return np.minimum(out, 1.0)

        def _lib_passed(self, si, active):
            uv, fp = self._lib_points(si, active)
            return self._lib.floats(self._lib_passes(uv, self._lib.dirs(si.wi, active), fp))

        def _lib_sample(self, si, sample1, sample2, active):
            lanes = self._lib
            uv, fp = self._lib_points(si, active)
            v = lanes.dirs(si.wi, active)
            uc, u = lanes.cols(sample1, 1, active, 0.5)[:, 0], lanes.cols(sample2, 2, active, 0.5)
            dyes = self._lib_dyes(si, active)
            d, f, pdf = np.zeros((len(uv), 3)), np.zeros((len(uv), 3)), np.zeros(len(uv))
            for surface, rows, turn in self._faces(v):
                if rows.any():
                    dr_, f[rows], pdf[rows] = surface.sample(
                        uv[rows], v[rows] * turn, uc[rows], u[rows], fp[rows],
                        **{k: c[rows] for k, c in dyes.items()})
                    d[rows] = dr_ * turn
            return lanes.vector(d), lanes.floats(pdf), lanes.color(f)

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"WovenBSDF[{self.surface!r}, table={self.table!r}]"

    return WovenBSDF
