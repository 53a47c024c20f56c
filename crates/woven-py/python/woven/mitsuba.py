"""The woven cloth BSDF for Mitsuba 3: ``woven.mitsuba.register()``, then ``type = "woven"``.

    import mitsuba as mi, woven.mitsuba
    mi.set_variant("llvm_ad_rgb")
    woven.mitsuba.register()
    bsdf = mi.load_dict({"type": "woven", "material": "polyester-sateen",
                         "weft_color": {"type": "rgb", "value": [0.6, 0.1, 0.1]}})

Parameters (the meaning of a ``woven`` material in ``woven render`` scenes):

=================  ==========================================================================
``material``       a preset name or a material file (TOML). The table of its yarn alone is
                   taken from the table cache ``woven render`` uses, or built there (render
                   grid, dyeable; seconds per preset).
``table``          instead of ``material``: a ``.wtab`` file. It is rendered as it is (the
                   BRDF it was built for), or, with ``pattern``, as the yarn of the pattern.
``weft_fraction``  γ in place of the material's weave (its pattern too): the macro BRDF, the
                   γ-mix of the yarn as weft and, turned 90°, as warp. With ``table`` (of a yarn
                   alone), the γ-mix of that table's yarn.
``wavelength_nm``  the wavelength the material's table is built at (default 550).
``pattern``        a weave pattern (``"plain"``, ``"twill-2/1"``, ``"satin-5"``, …) replacing
                   the material's weave. With a pattern, the cell at (u·n_u, v·n_v) of the
                   shape's uv decides whether the weft (along u) or the warp (along v) is on top.
                   Without one, the material's macro BRDF: the γ-mix of weft and warp.
``yarns_per_unit`` pattern cells per unit of uv: one number or "n_u, n_v" (default 40).
``weft_color``,    dyed fiber albedos ρ0 per channel (values or textures); the interreflection
``warp_color``     albedo follows in proportion. Default: the material's own (grey).
=================  ==========================================================================

Directions: Mitsuba's ``si.wi`` points toward the viewer (woven's ``v``) and ``wo`` toward the
light (woven's ``s``). ``sample`` draws the light direction for the viewer with the table's roles
swapped (``Table.sample_direction`` with ``s = si.wi``), and ``pdf`` returns that density, so the
``paper`` normalization's missing reciprocity is handled exactly: the weight is the true
f(s = wo, v = wi) cos θo / pdf.

In JIT variants (``llvm_*``, ``cuda_*``) ``eval``, ``pdf`` and ``sample`` are Dr.Jit code: the
table's arrays (``Table.raw()``) are handed over once, and every look-up is a gather, traced into
Mitsuba's kernels (symbolic loops and calls stay on). The code repeats the library's
interpolation and sampling operation by operation (crates/woven/src/table/{eval,grid,sampler}.rs;
docs/python.md). It interpolates everywhere: tables of single-orientation yarns that the library
evaluates exactly for near-forward pairs (|wi + wo| < 0.5) give ``Table.eval_interpolated``
there. In scalar variants each call goes to the Rust library directly.
"""

from __future__ import annotations

import math

import numpy as np

import woven

__all__ = ["register", "JitTable"]

_REGISTERED = set()


def register():
    """Registers the ``woven`` BSDF with Mitsuba for the current variant (``mi.set_variant``
    first). Safe to call more than once."""
    import mitsuba as mi

    variant = mi.variant()
    if variant is None:
        raise RuntimeError("set a Mitsuba variant first (mi.set_variant)")
    if variant in _REGISTERED:
        return
    cls = _bsdf_class(mi)
    mi.register_bsdf("woven", lambda props: cls(props))
    _REGISTERED.add(variant)


class JitTable:
    """A woven table in Dr.Jit arrays, with its evaluation, density and sampling as Dr.Jit code
    (see the module docs). ``mi`` is the Mitsuba module with a JIT variant set."""

    def __init__(self, table: woven.Table, mi):
        import drjit as dr

        self.dr, self.mi = dr, mi
        F, U = mi.Float, mi.UInt32
        self.F, self.U = F, U
        raw = table.raw()
        self.raw = raw
        self.isotropic = raw["symmetry"] == "isotropic"
        th, ph, t = raw["theta"], raw["phi"], raw["t"]
        self.theta, self.phi, self.t = th, ph, t
        self.n_theta, self.n_phi, self.n = th["n"], ph["n"], t["n"]
        self.nc = self.n - 1
        self.half_len = self.n_theta * self.n_phi * self.n * self.n
        self.K = raw["slope_scale"]
        self.eps = raw["horizon_weight"]
        lo, hi = raw["turn_deg"]
        self.turn_lo, self.turn_hi = math.cos(math.radians(lo)), math.cos(math.radians(hi))
        self.dt_cell = (t["hi"] - t["lo"]) / self.nc
        # The grid's derived arrays, computed in float64 as the library computes them.
        nodes = np.arange(self.n_theta * self.n_phi)
        theta_nodes = _axis_nodes(th)[nodes // self.n_phi]
        phi_nodes = _axis_nodes(ph)[nodes % self.n_phi]
        dirs = woven.from_spherical(theta_nodes, phi_nodes).reshape(-1, 3)
        self.dx, self.dy, self.dz = (F(np.ascontiguousarray(dirs[:, k])) for k in range(3))
        pn = _axis_nodes(ph)
        self.phi_c, self.phi_s = F(np.cos(pn)), F(np.sin(pn))
        tn = _axis_nodes(t)
        self.slopes = F(np.tan(self.K * tn * np.abs(tn)))
        self.values = F(raw["values"])
        self.body = F(raw["body"]) if raw["body"] is not None else None
        self.own = raw["own"]
        self.per_interreflection = raw["per_interreflection"]
        self.marginal = F(raw["marginal"])
        self.conditional = F(raw["conditional"])

    # -- grid ----------------------------------------------------------------------------------

    def _locate(self, axis, x):
        """(k, w): ``Axis::locate`` (grid.rs)."""
        dr, F, U = self.dr, self.F, self.U
        n = axis["n"]
        if n == 1:
            return U(0), F(0.0)
        y = dr.clip((x - axis["lo"]) / (axis["hi"] - axis["lo"]), 0.0, 1.0)
        a = axis["grading"]
        if a == 0.0:
            u = y
        else:
            b = 1.0 + a
            u = 2.0 * y / (b + dr.sqrt(dr.maximum(b * b - 4.0 * a * y, 0.0)))
        v = u * (n - 1)
        k = dr.minimum(U(v), n - 2)
        return k, dr.clip(v - F(k), 0.0, 1.0)

    def _node(self, axis, k):
        """``Axis::node`` of index array ``k``."""
        n = axis["n"]
        if n == 1:
            return self.F(axis["lo"])
        u = self.F(k) / (n - 1)
        return axis["lo"] + (axis["hi"] - axis["lo"]) * u * (1.0 + axis["grading"] * (1.0 - u))

    def _t_of_slope(self, p):
        dr = self.dr
        return dr.copysign(dr.sqrt(dr.minimum(dr.atan(dr.abs(p)) / self.K, 1.0)), p)

    def _slope_of_t(self, t):
        return self.dr.tan(self.K * t * self.dr.abs(t))

    def _fold(self, d):
        """The fold of ``Fold::of`` for axis direction ``d``: (apply, undo) functions."""
        dr, mi = self.dr, self.mi
        if self.isotropic:
            r = dr.sqrt(d.x * d.x + d.y * d.y)
            ok = r > 0
            c = dr.select(ok, d.x / dr.select(ok, r, 1.0), 1.0)
            s = dr.select(ok, d.y / dr.select(ok, r, 1.0), 0.0)

            def apply(v):
                return mi.Vector3f(c * v.x + s * v.y, -s * v.x + c * v.y, v.z)

            def undo(v):
                return mi.Vector3f(c * v.x - s * v.y, s * v.x + c * v.y, v.z)

            return apply, undo
        fx, fy = d.x < 0, d.y < 0

        def flip(v):
            return mi.Vector3f(dr.select(fx, -v.x, v.x), dr.select(fy, -v.y, v.y), v.z)

        return flip, flip

    def _locate_axis(self, d):
        dr = self.dr
        it, wt = self._locate(self.theta, dr.acos(dr.clip(d.z, -1.0, 1.0)))
        ip, wp = self._locate(self.phi, dr.atan2(d.y, d.x))
        return it, wt, ip, wp

    # -- evaluation (eval.rs) ------------------------------------------------------------------

    def _interpolate(self, half, located, axis, other, arrays, active):
        """``Table::interpolate``: the node values of ``arrays`` around the folded pair."""
        dr, F = self.dr, self.F
        it, wt, ip, wp = located
        n = self.n
        # Query::new
        r = dr.sqrt(axis.x * axis.x + axis.y * axis.y)
        ok = r > 0
        qc = dr.select(ok, axis.x / dr.select(ok, r, 1.0), 1.0)
        qs = dr.select(ok, axis.y / dr.select(ok, r, 1.0), 0.0)
        x = dr.clip((self.turn_lo - other.z) / (self.turn_lo - self.turn_hi), 0.0, 1.0)
        turn = x * x * (3.0 - 2.0 * x)
        h = axis + other

        def locate_h(hx, hy, hz):
            return (
                self._locate(self.t, self._t_of_slope(hy / hz)),
                self._locate(self.t, self._t_of_slope(hx / hz)),
            )

        phi_nodes = [(0, 1.0 - wp), (1, wp)] if self.n_phi > 1 else [(0, F(1.0))]
        num = [F(0.0) for _ in arrays]
        den = F(0.0)
        base_half = half * self.half_len
        for b, fb in phi_nodes:
            if self.n_phi == 1:
                (iy, wy), (ix, wx) = locate_h(h.x, h.y, h.z)
            else:
                # Where the Rust code skips the turn (turn = 0) the turn below is by an angle of
                # exactly 0: sincos(0) = (0, 1) leaves h bit for bit, so one path serves both
                # (SIMD lanes would compute both paths anyway).
                cb = dr.gather(F, self.phi_c, ip + b, active)
                sb = dr.gather(F, self.phi_s, ip + b, active)
                c = cb * qc + sb * qs
                sn = sb * qc - cb * qs
                ang = turn * dr.atan2(sn, c)
                s2, c2 = dr.sincos(ang)
                full = turn >= 1.0
                c, sn = dr.select(full, c, c2), dr.select(full, sn, s2)
                (iy, wy), (ix, wx) = locate_h(c * h.x - sn * h.y, sn * h.x + c * h.y, h.z)
            py = [dr.gather(F, self.slopes, iy + k, active) for k in (0, 1)]
            px = [dr.gather(F, self.slopes, ix + k, active) for k in (0, 1)]
            for a, fa in ((0, 1.0 - wt), (1, wt)):
                node = (it + a) * self.n_phi + ip + b
                ddx = dr.gather(F, self.dx, node, active)
                ddy = dr.gather(F, self.dy, node, active)
                ddz = dr.gather(F, self.dz, node, active)
                base = base_half + (node * n + iy) * n + ix
                wa = fa * fb * ddz
                for dyy, fy in ((0, 1.0 - wy), (1, wy)):
                    for dxx, fx in ((0, 1.0 - wx), (1, wx)):
                        pxx, pyy = px[dxx], py[dyy]
                        cos_other = (
                            2.0 * (ddx * pxx + ddy * pyy + ddz) / (1.0 + pxx * pxx + pyy * pyy)
                            - ddz
                        )
                        wc = wa * fy * fx * dr.maximum(cos_other, self.eps)
                        at = base + dyy * n + dxx
                        for k, array in enumerate(arrays):
                            num[k] += wc * dr.gather(F, array, at, active)
                        den += wc
        pos = den > 0
        return [dr.select(pos, v / dr.select(pos, den, 1.0), 0.0) for v in num]

    def _eval_arrays(self, s, v, arrays, active):
        """``Table::eval_arrays`` (the interpolation alone) for ``(s, v)``."""
        dr = self.dr
        active = active & (s.z > 0) & (v.z > 0)
        light = s.z <= v.z  # Half::of
        axis = dr.select(light, s, v)
        other = dr.select(light, v, s)
        apply, _ = self._fold(axis)
        axis, other = apply(axis), apply(other)
        located = self._locate_axis(axis)
        half = dr.select(light, self.U(0), self.U(1))
        out = self._interpolate(half, located, axis, other, arrays, active)
        return [dr.select(active, x, 0.0) for x in out]

    def eval(self, s, v, active=True):
        """f(s, v), sr⁻¹: ``Table::eval_interpolated``."""
        return self.dr.maximum(self._eval_arrays(s, v, [self.values], active)[0], 0.0)

    def eval_dyed(self, s, v, diffuse, interreflection, active=True):
        """f per channel for albedos ``diffuse`` (ρ0) and ``interreflection`` (ρ), colour types:
        ``Table::eval_dyed``'s interpolation."""
        dr = self.dr
        if self.body is None:
            f = self.eval(s, v, active)
            return diffuse * 0.0 + f
        f, body = self._eval_arrays(s, v, [self.values, self.body], active)
        d0, r0 = self.own
        out = f + (diffuse - d0) * body + (interreflection - r0) * self.per_interreflection
        return dr.maximum(out, 0.0)

    # -- sampling (grid.rs, sampler.rs) --------------------------------------------------------

    def _jacobian(self, s, tx, ty):
        """``grid::jacobian``: (v, j, valid)."""
        dr, mi = self.dr, self.mi
        px, py = self._slope_of_t(tx), self._slope_of_t(ty)
        h = dr.normalize(mi.Vector3f(px, py, 1.0))
        sh = dr.dot(s, h)
        v = h * (2.0 * sh) - s
        valid = (sh > 0) & (v.z > 0)
        q = 1.0 + px * px + py * py
        dx = 2.0 * self.K * dr.abs(tx) * (1.0 + px * px)
        dy = 2.0 * self.K * dr.abs(ty) * (1.0 + py * py)
        j = 4.0 * sh / (q * dr.sqrt(q)) * dx * dy
        return v, j, valid

    def _sampling_node(self, s):
        """``Sampler::node``: the incidence node nearest folded ``s``."""
        dr, U = self.dr, self.U
        it, wt, ip, wp = self._locate_axis(s)
        dp = dr.select(wp >= 0.5, U(1), U(0)) if self.n_phi > 1 else U(0)
        dt = dr.select(wt >= 0.5, U(1), U(0))
        return (it + dt) * self.n_phi + ip + dp

    def _density(self, node, iy, ix, active):
        dr, F = self.dr, self.F
        nc = self.nc
        m = node * (nc + 1) + iy
        c = (node * nc + iy) * (nc + 1) + ix
        pm = dr.gather(F, self.marginal, m + 1, active) - dr.gather(F, self.marginal, m, active)
        pc = dr.gather(F, self.conditional, c + 1, active) - dr.gather(
            F, self.conditional, c, active
        )
        return pm * pc / (self.dt_cell * self.dt_cell)

    def pdf(self, s, v, active=True):
        """The density of drawing ``v`` for ``s`` (``Bsdf::pdf`` of a table)."""
        dr = self.dr
        active = active & (s.z > 0) & (v.z > 0)
        apply, _ = self._fold(s)
        s, v = apply(s), apply(v)
        h = s + v
        tx, ty = self._t_of_slope(h.x / h.z), self._t_of_slope(h.y / h.z)
        _, j, valid = self._jacobian(s, tx, ty)
        active = active & valid & (j > 0)
        iy, _ = self._locate(self.t, ty)
        ix, _ = self._locate(self.t, tx)
        node = self._sampling_node(s)
        p = self._density(node, iy, ix, active) / dr.select(active, j, 1.0)
        return dr.select(active, p, 0.0)

    def _invert(self, base, u, active):
        """``invert``: the CDF entry ``i`` with cdf[i] ≤ u < cdf[i+1] and the fraction within
        (``valid`` false for an empty CDF). The count of entries ≤ u, by bisection (the CDF is
        sorted)."""
        dr, F, U = self.dr, self.F, self.U
        nc = self.nc
        cdf = self.marginal if base[0] == "m" else self.conditional
        start = base[1]
        k = dr.binary_search(0, nc, lambda i: dr.gather(F, cdf, start + i, active) <= u)
        # binary_search returns nc when all of 0..nc are ≤ u: the count is then nc + 1.
        last = dr.gather(F, cdf, start + nc, active) <= u
        count = dr.select(last, U(nc + 1), k)
        valid = count > 0
        i = dr.minimum(dr.select(valid, count - 1, 0), nc - 1)
        lo = dr.gather(F, cdf, start + i, active)
        hi = dr.gather(F, cdf, start + i + 1, active)
        valid &= hi > lo
        frac = dr.clip((u - lo) / dr.select(valid, hi - lo, 1.0), 0.0, 1.0)
        return i, frac, valid

    def sample_direction(self, s, u1, u2, active=True):
        """``Table::sample_direction``: (v, pdf, valid), ``v`` drawn ∝ f(s, v) cos θv."""
        dr = self.dr
        active = active & (s.z > 0)
        apply, undo = self._fold(s)
        sf = apply(s)
        nc = self.nc
        node = self._sampling_node(sf)
        u = dr.clip(u1, 0.0, 1.0 - 2.0**-24)
        iy, fy, ok1 = self._invert(("m", node * (nc + 1)), u, active)
        u2 = dr.clip(u2, 0.0, 1.0 - 2.0**-24)
        ix, fx, ok2 = self._invert(("c", (node * nc + iy) * (nc + 1)), u2, active)
        tx = self._node(self.t, ix) + fx * self.dt_cell
        ty = self._node(self.t, iy) + fy * self.dt_cell
        v, j, valid = self._jacobian(sf, tx, ty)
        active = active & ok1 & ok2 & valid & (j > 0)
        pdf = self._density(node, iy, ix, active) / dr.select(active, j, 1.0)
        active &= (pdf > 0) & dr.isfinite(pdf)
        return undo(v), dr.select(active, pdf, 0.0), active


def _axis_nodes(axis):
    """``Axis::node`` for every node, float64."""
    n = axis["n"]
    if n == 1:
        return np.array([axis["lo"]])
    u = np.arange(n) / (n - 1)
    return axis["lo"] + (axis["hi"] - axis["lo"]) * u * (1.0 + axis["grading"] * (1.0 - u))


def _to_warp(mi, d):
    """Into a warp yarn's frame: a 90° turn about z taking y (the warp) to x."""
    return mi.Vector3f(d.y, -d.x, d.z)


def _from_warp(mi, d):
    return mi.Vector3f(-d.y, d.x, d.z)


def _yarns(value):
    """``yarns_per_unit``: a number or "n_u, n_v"."""
    if isinstance(value, str):
        parts = [float(x) for x in value.replace(",", " ").split()]
    else:
        parts = [float(value)]
    if len(parts) == 1:
        parts = parts * 2
    if len(parts) != 2 or not all(math.isfinite(p) and p > 0 for p in parts):
        raise ValueError(
            f"woven BSDF: `yarns_per_unit` = {value!r}: expected a positive number or 'n_u, n_v'"
        )
    return parts


def _bsdf_class(mi):
    """The BSDF class for the current variant."""
    import drjit as dr

    jit = dr.is_jit_v(mi.Float)

    class WovenBSDF(mi.BSDF):
        """The woven cloth BSDF (see the module ``woven.mitsuba``)."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            has = props.__contains__
            if has("table") == has("material"):
                raise ValueError("woven BSDF: give exactly one of `table` and `material`")
            wavelength = float(props["wavelength_nm"]) if has("wavelength_nm") else 550.0
            pattern = props["pattern"] if has("pattern") else None
            self.yarns = _yarns(props["yarns_per_unit"]) if has("yarns_per_unit") else [40.0, 40.0]
            if has("table"):
                table = woven.Table.load(str(props["table"]))
                material = table.material
                weave = None
                if pattern is not None:
                    weave = {"pattern": pattern}
                elif has("weft_fraction"):
                    weave = {"weft_fraction": float(props["weft_fraction"])}
                if weave is not None:
                    if material is None or material.weave is not None or material.yarn is None:
                        raise ValueError(
                            "woven BSDF: `pattern` or `weft_fraction` with `table` needs the table"
                            " of a yarn alone (a material without [weave]: Material.yarn_family())"
                        )
                    material = material.replace({"weave": weave})
                    self.layout = "pattern" if pattern is not None else "macro"
                else:
                    self.layout = "table"
            else:
                material = woven.Material.open(str(props["material"]))
                if pattern is not None:
                    material = material.replace({"weave": {"pattern": pattern}})
                elif has("weft_fraction"):
                    if material.yarn is None:
                        raise ValueError("woven BSDF: `weft_fraction` needs a material with yarns")
                    fraction = float(props["weft_fraction"])
                    material = material.replace({"weave": {"weft_fraction": fraction}})
                yarn = material.yarn_family()
                table = woven.Table.cached(yarn, wavelength, grid="render", progress=False)
                if material.yarn is None:
                    self.layout = "table"
                elif material.pattern() is not None:
                    self.layout = "pattern"
                else:
                    self.layout = "macro"
            self.material = material
            self.table = table
            self.gamma = material.weft_fraction if material is not None else 1.0
            cells = material.pattern() if self.layout == "pattern" else None
            if cells is not None:
                self.rows, self.cols = cells.shape
            own = table.raw()["own"]
            if own is None and material is not None:
                y = material.yarn
                own = (material.fiber.diffuse, y.interreflection_albedo if y is not None else 0.0)
            self.own = own
            self.colors = {}
            for key in ("weft_color", "warp_color"):
                if has(key):
                    if own is None:
                        raise ValueError(
                            f"woven BSDF: `{key}` needs a table that records its material"
                        )
                    value = props[key]
                    if isinstance(value, mi.Texture):
                        self.colors[key] = value
                    else:
                        self.colors[key] = mi.Color3f(value)
            flags = (
                mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.Anisotropic
            )
            if self.layout == "pattern" or any(
                isinstance(c, mi.Texture) for c in self.colors.values()
            ):
                flags |= mi.BSDFFlags.SpatiallyVarying
            self.m_flags = flags
            self.m_components = [flags]
            if jit:
                self.jt = JitTable(table, mi)
                if cells is not None:
                    self.cells = mi.UInt32(cells.reshape(-1).astype(np.uint32))
            else:
                self.cells_np = cells

        # -- colour ---------------------------------------------------------------------------

        def _albedos(self, key, si, active):
            """(ρ0, ρ) per channel for the weft or warp colour at ``si``, or None (own)."""
            c = self.colors.get(key)
            if c is None:
                return None
            if isinstance(c, mi.Texture):
                c = c.eval(si, active)
            d0, r0 = self.own
            rho0 = dr.clip(c, 0.0, 0.999)
            rho = dr.clip(r0 * c / d0, 0.0, 1.0) if d0 > 0 else c * 0.0 + r0
            return rho0, rho

        # -- JIT: Dr.Jit code ------------------------------------------------------------------

        def _family_eval(self, warp, s, v, si, active):
            jt = self.jt
            if warp:
                s, v = _to_warp(mi, s), _to_warp(mi, v)
            alb = self._albedos("warp_color" if warp else "weft_color", si, active)
            if alb is None:
                return mi.Color3f(jt.eval(s, v, active))
            return jt.eval_dyed(s, v, alb[0], alb[1], active)

        def _family_pdf(self, warp, wi, wo, active):
            # Drawn with the roles swapped: the table's s is the viewer wi.
            if warp:
                wi, wo = _to_warp(mi, wi), _to_warp(mi, wo)
            return self.jt.pdf(wi, wo, active)

        def _warp_on_top(self, si):
            u = si.uv.x * self.yarns[0]
            v = si.uv.y * self.yarns[1]
            # cell_index of Pattern::weft_at_uv(u / cols, v / rows).
            col = _cell(u / self.cols, self.cols)
            row = _cell(v / self.rows, self.rows)
            weft = dr.gather(mi.UInt32, self.cells, row * self.cols + col) != 0
            return ~weft & dr.isfinite(u) & dr.isfinite(v)

        def _eval_jit(self, si, wo, active):
            wi = si.wi
            s, v = wo, wi
            if self.layout == "table":
                return self._family_eval(False, s, v, si, active)
            if self.layout == "pattern":
                warp = self._warp_on_top(si)
                return dr.select(
                    warp,
                    self._family_eval(True, s, v, si, active & warp),
                    self._family_eval(False, s, v, si, active & ~warp),
                )
            g = self.gamma
            f = mi.Color3f(0.0)
            if g > 0:
                f += self._family_eval(False, s, v, si, active) * g
            if g < 1:
                f += self._family_eval(True, s, v, si, active) * (1.0 - g)
            return f

        def _pdf_jit(self, si, wo, active):
            wi = si.wi
            if self.layout == "table":
                return self._family_pdf(False, wi, wo, active)
            if self.layout == "pattern":
                warp = self._warp_on_top(si)
                return dr.select(
                    warp,
                    self._family_pdf(True, wi, wo, active & warp),
                    self._family_pdf(False, wi, wo, active & ~warp),
                )
            g = self.gamma
            p = mi.Float(0.0)
            if g > 0:
                p += g * self._family_pdf(False, wi, wo, active)
            if g < 1:
                p += (1.0 - g) * self._family_pdf(True, wi, wo, active)
            return p

        def _sample_jit(self, si, sample1, sample2, active):
            """(wo, pdf, ok): a draw and its density, the mixture's where two families mix. The
            drawn family's density is the draw's own (the cell its sampler chose), so only the
            other family's is looked up."""
            wi = si.wi
            g = self.gamma
            if self.layout == "table":
                warp = mi.Bool(False)
            elif self.layout == "pattern":
                warp = self._warp_on_top(si)
            else:
                warp = mi.Bool(sample1 >= g)
            wi_t = dr.select(warp, _to_warp(mi, wi), wi)
            d, pdf, ok = self.jt.sample_direction(wi_t, sample2.x, sample2.y, active)
            wo = dr.select(warp, _from_warp(mi, d), d)
            if self.layout == "macro" and 0 < g < 1:
                # The other family's density, in its own frame.
                wi_o = dr.select(warp, wi, _to_warp(mi, wi))
                wo_o = dr.select(warp, wo, _to_warp(mi, wo))
                other = self.jt.pdf(wi_o, wo_o, active & ok)
                pdf = dr.select(warp, (1.0 - g) * pdf + g * other, g * pdf + (1.0 - g) * other)
            return wo, pdf, ok

        # -- the BSDF interface ----------------------------------------------------------------

        def eval(self, ctx, si, wo, active=True):
            active = mi.Bool(active) & (si.wi.z > 0) & (wo.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection):
                return mi.Color3f(0.0)
            if jit:
                f = self._eval_jit(si, wo, active)
                return dr.select(active, f * wo.z, 0.0)
            if not active:
                return mi.Color3f(0.0)
            return mi.Color3f(self._rust_eval(si, wo) * wo.z)

        def pdf(self, ctx, si, wo, active=True):
            active = mi.Bool(active) & (si.wi.z > 0) & (wo.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection):
                return mi.Float(0.0)
            if jit:
                return dr.select(active, self._pdf_jit(si, wo, active), 0.0)
            if not active:
                return 0.0
            return self._rust_pdf(si, wo)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            bs = mi.BSDFSample3f()
            active = mi.Bool(active) & (si.wi.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection):
                return bs, mi.Color3f(0.0)
            if jit:
                wo, pdf, ok = self._sample_jit(si, sample1, sample2, active)
                active &= ok & (wo.z > 0)
                pdf = dr.select(active, pdf, 0.0)
            else:
                if not active:
                    return bs, mi.Color3f(0.0)
                wo = self._rust_sample(si, sample1, sample2)
                if wo is None:
                    return bs, mi.Color3f(0.0)
                pdf = self.pdf(ctx, si, wo, active)
            bs.wo = wo
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            f = self.eval(ctx, si, wo, active)
            active &= pdf > 0
            bs.pdf = dr.select(active, pdf, 0.0)
            weight = dr.select(active, f / dr.select(active, pdf, 1.0), 0.0)
            return bs, weight

        # -- scalar variants: the Rust library per call ------------------------------------------

        def _rust_family(self, warp, s, v, si):
            key = "warp_color" if warp else "weft_color"
            if warp:
                s, v = (s[1], -s[0], s[2]), (v[1], -v[0], v[2])
            alb = self._albedos(key, si, True)
            if alb is None:
                return np.full(3, float(self.table.eval(s, v)))
            albedos = [(float(alb[0][k]), float(alb[1][k])) for k in range(3)]
            return self.table.eval_dyed(s, v, albedos)[0]

        def _rust_warp(self, si):
            u = float(si.uv[0]) * self.yarns[0]
            v = float(si.uv[1]) * self.yarns[1]
            if not (math.isfinite(u) and math.isfinite(v)):
                return False
            col = int(math.floor(u / self.cols * self.cols)) % self.cols
            row = int(math.floor(v / self.rows * self.rows)) % self.rows
            return not bool(self.cells_np[row, col])

        def _rust_eval(self, si, wo):
            s = (float(wo[0]), float(wo[1]), float(wo[2]))
            v = (float(si.wi[0]), float(si.wi[1]), float(si.wi[2]))
            if self.layout == "table":
                f = self._rust_family(False, s, v, si)
            elif self.layout == "pattern":
                f = self._rust_family(self._rust_warp(si), s, v, si)
            else:
                g = self.gamma
                f = np.zeros(3)
                if g > 0:
                    f += g * self._rust_family(False, s, v, si)
                if g < 1:
                    f += (1 - g) * self._rust_family(True, s, v, si)
            return mi.Color3f(*map(float, f))

        def _rust_family_pdf(self, warp, wi, wo):
            if warp:
                wi, wo = (wi[1], -wi[0], wi[2]), (wo[1], -wo[0], wo[2])
            return float(self.table.pdf(wi, wo))

        def _rust_pdf(self, si, wo):
            wi = (float(si.wi[0]), float(si.wi[1]), float(si.wi[2]))
            wo = (float(wo[0]), float(wo[1]), float(wo[2]))
            if self.layout == "table":
                return self._rust_family_pdf(False, wi, wo)
            if self.layout == "pattern":
                return self._rust_family_pdf(self._rust_warp(si), wi, wo)
            g = self.gamma
            p = 0.0
            if g > 0:
                p += g * self._rust_family_pdf(False, wi, wo)
            if g < 1:
                p += (1 - g) * self._rust_family_pdf(True, wi, wo)
            return p

        def _rust_sample(self, si, sample1, sample2):
            wi = (float(si.wi[0]), float(si.wi[1]), float(si.wi[2]))
            if self.layout == "table":
                warp = False
            elif self.layout == "pattern":
                warp = self._rust_warp(si)
            else:
                warp = float(sample1) >= self.gamma
            if warp:
                wi = (wi[1], -wi[0], wi[2])
            d, pdf = self.table.sample_direction(wi, (float(sample2[0]), float(sample2[1])))
            if pdf[0] <= 0:
                return None
            d = d[0]
            if warp:
                d = (-d[1], d[0], d[2])
            return mi.Vector3f(*map(float, d))

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"WovenBSDF[layout={self.layout}, table={self.table!r}, gamma={self.gamma}]"

    def _cell(t, n):
        """``cell_index``: floor(t n) mod n."""
        x = dr.floor(t * n)
        x = x - n * dr.floor(x / n)
        return dr.minimum(mi.UInt32(dr.maximum(x, 0.0)), n - 1)

    return WovenBSDF


def __getattr__(name):
    if name == "WovenBSDF":
        import mitsuba as mi

        return _bsdf_class(mi)
    raise AttributeError(name)
