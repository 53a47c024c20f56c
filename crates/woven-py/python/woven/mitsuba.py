"""The woven cloth BSDF for Mitsuba 3: ``woven.mitsuba.register()``, then ``type = "woven"``.

    import mitsuba as mi, woven.mitsuba
    mi.set_variant("llvm_ad_rgb")
    woven.mitsuba.register()
    bsdf = mi.load_dict({"type": "woven", "material": "polyester-sateen", "pattern": "twill-2/1",
                         "weft_color": {"type": "rgb", "value": [0.6, 0.1, 0.1]}})

**Keys.** The plugin takes the surface keys of ``woven render``'s scenes and ``woven.Surface``
with the same names, meanings, ranges and defaults: the library owns them
(``woven.SURFACE_KEYS``; the table in docs/python.md), and a key not given here is not given to
``woven.Surface``, so the same keys give the same surface everywhere. Here in particular:
``yarns_per_unit`` is one number or a string ``"n_u, n_v"``, and ``irregularity`` one number or
``"weft, warp"``; ``weft_color`` and ``warp_color`` may be any Mitsuba texture (read at the hit);
``footprint_filter`` is a key of the material (in scenes, of the ``[integrator]``). Beside them,
``table`` (instead of ``material``) takes a ``.wtab`` file, rendered as the BRDF it was built for
or, with ``pattern`` or ``weft_fraction``, as the yarn of a weave. A ``material``'s yarn table
comes from the table cache ``woven render`` uses, or is built there (seconds per preset).

**Footprints.** ``woven render`` knows each camera ray's footprint (its ray differentials):
``detail = "auto"`` resolves fibres where a pixel spans well under a yarn, and the footprint
filter blends toward the macro BRDF where it spans cells. Mitsuba hands a BSDF the footprint as
``si.duv_dx``, ``si.duv_dy``, which its integrators compute only for BSDFs that ask for them
(this one does, whenever ``footprint_filter`` is on and the surface uses a footprint) and only
from rays that carry differentials: ``direct`` and ``aov`` do, for camera rays (scaled by
1/√spp, as Mitsuba scales them); ``path``, ``volpath`` and ``prb`` carry none. Where the partials
are zero the plugin gives the library no footprint, and the library's rule for that case holds,
as at every later vertex of ``woven render``'s paths: no filtering, and ``"auto"`` shades each
point at yarn level on the weave's relief (docs/render.md).

**Directions.** Mitsuba's ``si.wi`` points toward the viewer (woven's ``wo``) and ``wo`` toward
the light (woven's ``wi``). ``sample`` draws the light direction for the viewer (the library's
radiance transport mode), and ``pdf`` returns that density, so the ``paper`` normalization's
missing reciprocity is handled exactly: the weight is the true f(wi, wo) cos θ / pdf.

**Variants: traced, or the library lane by lane.** Scalar variants call the library's
``woven.Surface`` for each ray. JIT variants (``llvm_*``, ``cuda_*``) trace in Dr.Jit what
Dr.Jit can gather: a surface at ``detail`` "yarns" or "cloth" (and any surface without a
pattern) is the yarn table's interpolation and sampling (``JitTable``) at the lobes of each lane's
cell, float and gap (``JitLayout``, from the constants ``Surface.layout()`` hands over; the
tilted floats' geometry in ``JitFloat``; a whole tilted float is one look-up in its own table,
``Surface.float_table``), compiled into Mitsuba's kernels. What the library
computes and Dr.Jit does not trace — ``detail`` "auto" (the default) and "fibers" on a pattern
(the weave's relief, its crowned table, the fibres' draws), floats shaped by
``float_crest``/``float_flank``, ``irregularity``, and microcylinder fabrics — the library
evaluates, samples and weighs lane by lane: each call hands the lanes' arrays to ``woven.Surface``
(rayon-parallel in Rust, the GIL released) and back, so there is one implementation of those
levels. That needs Dr.Jit's evaluated (wavefront) mode, in which a call sees its lanes' values:
``register()`` switches its thread's ``SymbolicLoops``, ``SymbolicCalls`` and
``SymbolicConditionals`` off (``register(symbolic=True)`` leaves them on, for scenes whose woven
surfaces are all traced); a library surface called from a symbolic trace raises an error saying
so. On a CUDA variant the library's lanes run on the CPU, copied over and back per call.

The traced code repeats the library's operation by operation (crates/woven/src/table/,
crates/woven/src/surface/, crates/woven/src/yarn/float.rs); tests/test_mitsuba.py pins it lane
for lane to the library's values, to the horizon, for eval, pdf and sample. It interpolates
everywhere: tables of single-orientation yarns that the library evaluates exactly for
near-forward pairs (|wi + wo| < 0.5) or half vectors within 5° of the horizon (which a tilted
frame can bring about) give ``Table.eval_interpolated`` there, and flat fiber surfaces their
table, not the exact model.

``material`` may also name a microcylinder fabric (Sadeghi et al. 2013: a ``microcylinder-*``
preset, or a file with ``model = "microcylinder"``; see ``woven.Microcylinder``). RGB variants
then evaluate, sample and weigh it with the library (the keys above other than ``material`` do
not apply and are refused by name); spectral variants refuse it, its values being RGB.
"""

from __future__ import annotations

import math

import numpy as np

import woven

__all__ = ["register", "JitTable", "JitLayout", "JitFloat"]

_REGISTERED = set()


def register(symbolic=False):
    """Registers the ``woven`` BSDF with Mitsuba for the current variant (``mi.set_variant``
    first). Safe to call more than once.

    In a JIT variant it also switches Dr.Jit, in the calling thread, to evaluated loops, calls
    and conditionals, which the surfaces the library evaluates lane by lane need (``detail``
    "auto", the default, and "fibers" on a pattern; shaped floats; ``irregularity``): call it
    in the thread that renders. ``symbolic=True`` leaves Dr.Jit's modes alone, for scenes whose
    woven surfaces are all traced (``detail`` "yarns" or "cloth"): a surface that needs the
    library then raises an error naming this when it is called."""
    import drjit as dr
    import mitsuba as mi

    variant = mi.variant()
    if variant is None:
        raise RuntimeError("set a Mitsuba variant first (mi.set_variant)")
    if dr.is_jit_v(mi.Float) and not symbolic:
        _evaluated_mode(dr)
    if variant in _REGISTERED:
        return
    cls = _bsdf_class(mi)
    fabric_cls = _microcylinder_class(mi)
    mi.register_bsdf("woven", lambda props: _make(props, cls, fabric_cls))
    _REGISTERED.add(variant)


def _make(props, woven_cls, fabric_cls):
    """The BSDF a ``woven`` plugin's properties describe: a microcylinder fabric when
    ``material`` names one, otherwise the woven cloth."""
    if "material" in props and "table" not in props:
        try:
            opened = woven.open_material(str(props["material"]))
        except ValueError as e:
            raise ValueError(f"woven BSDF: {e}") from None
        if isinstance(opened, woven.Microcylinder):
            return fabric_cls(props, opened)
    return woven_cls(props)


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
        self.crown = F(raw["crown"]) if raw.get("crown") is not None else None
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
        d0, r0 = self.own
        if self.crown is None:
            f, body = self._eval_arrays(s, v, [self.values, self.body], active)
            per = self.per_interreflection
        else:
            f, body, g = self._eval_arrays(s, v, [self.values, self.body, self.crown], active)
            per = self.per_interreflection * g
        out = f + (diffuse - d0) * body + (interreflection - r0) * per
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


def _turn(mi, dr, d, warp):
    """Into a warp yarn's frame where ``warp`` (a bool or a Bool per lane): the library's 90°
    turn about z taking y (the warp) to x (woven::surface)."""
    if warp is False:
        return d
    t = mi.Vector3f(d.y, -d.x, d.z)
    if warp is True:
        return t
    return mi.Vector3f(dr.select(warp, t.x, d.x), dr.select(warp, t.y, d.y), d.z)


def _unturn(mi, dr, d, warp):
    """Back from ``_turn``."""
    if warp is False:
        return d
    t = mi.Vector3f(-d.y, d.x, d.z)
    if warp is True:
        return t
    return mi.Vector3f(dr.select(warp, t.x, d.x), dr.select(warp, t.y, d.y), d.z)


def _tilt_into(mi, d, s, c):
    """Into the frame of a yarn tilted by (sin, cos) of its tilt: x turned toward +z."""
    return mi.Vector3f(c * d.x + s * d.z, d.y, c * d.z - s * d.x)


def _tilt_from(mi, d, s, c):
    return mi.Vector3f(c * d.x - s * d.z, d.y, s * d.x + c * d.z)


def _pair(value, name):
    """A key that takes one number or two ("n_u, n_v"; "weft, warp")."""
    if isinstance(value, str):
        parts = [float(x) for x in value.replace(",", " ").split()]
    else:
        parts = [float(value)]
    if len(parts) == 1:
        parts = parts * 2
    if len(parts) != 2 or not all(math.isfinite(p) for p in parts):
        raise ValueError(f"woven BSDF: `{name}` = {value!r}: expected a number or two ('a, b')")
    return parts


def _surface(props, mi):
    """The ``woven.Surface`` a plugin's properties describe, its textured colours, and whether
    it dyes its yarns unevenly. A key not given takes the library's default
    (``woven.SURFACE_KEYS``), as scenes and ``woven.Surface`` do."""
    has = props.__contains__
    if has("table") == has("material"):
        raise ValueError("woven BSDF: give exactly one of `table` and `material`")
    kwargs = {}
    for key, read in _READERS.items():
        if has(key):
            kwargs[key] = read(props[key])
    irregular = any(x != 0 for x in kwargs.get("irregularity", (0.0, 0.0)))
    textures = {}
    for key in ("weft_color", "warp_color"):
        if has(key):
            value = props[key]
            if isinstance(value, mi.Texture):
                textures[key] = value
            else:
                kwargs[key] = [float(x) for x in mi.ScalarColor3f(value)]
    try:
        if has("table"):
            table = woven.Table.load(str(props["table"]))
            surface = woven.Surface(table=table, **kwargs)
        else:
            surface = woven.Surface(
                woven.Material.open(str(props["material"])), progress=False, **kwargs
            )
    except ValueError as e:
        raise ValueError(f"woven BSDF: {e}") from None
    if textures and surface.table.raw()["own"] is None:
        raise ValueError("woven BSDF: a textured colour needs a table that records its material")
    return surface, textures, irregular


# Mitsuba's BSDFFlags::NeedsDifferentials (include/mitsuba/render/bsdf.h), not in its Python
# enum: ``si.bsdf(ray)`` then computes the uv partials from a ray's differentials.
_NEEDS_DIFFERENTIALS = 0x20000

# The surface keys (the library's table: woven.SURFACE_KEYS), and how the plugin reads each
# from Mitsuba's properties into woven.Surface's arguments; ``material`` and ``footprint_filter``
# the plugin reads itself, colours may be textures (_surface).
_KEYS = {k["name"]: k for k in woven.SURFACE_KEYS}
_READERS = {
    "pattern": str,
    "weft_fraction": float,
    "yarns_per_unit": lambda v: _pair(v, "yarns_per_unit"),
    "u_max_deg": float,
    "gap": float,
    "detail": str,
    "irregularity": lambda v: _pair(v, "irregularity"),
    "irregularity_length": float,
    "wavelength_nm": float,
}
_OWN_KEYS = ("material", "footprint_filter", "weft_color", "warp_color")
if set(_READERS) | set(_OWN_KEYS) != set(_KEYS):
    raise ImportError(
        "woven.mitsuba: the plugin does not read every surface key of the library, or reads"
        f" one it does not have: {sorted(set(_KEYS) ^ (set(_READERS) | set(_OWN_KEYS)))}"
    )

# The plugin's default for ``footprint_filter`` (scenes: the ``[integrator]`` key's).
_FILTER_DEFAULT = _KEYS["footprint_filter"]["default"] == "true"


def _boolean(props, key, default):
    """A boolean property: True or False (XML's ``<boolean>``), ``default`` when absent. Anything
    else is refused, naming the key: the string "false" is not false."""
    if key not in props:
        return default
    value = props[key]
    if isinstance(value, bool):
        return value
    raise ValueError(
        f"woven: `{key}` = {value!r}: expected a boolean (True or False; <boolean> in XML)"
    )

# The keys of the woven cloth that a microcylinder fabric has no use for.
_WOVEN_ONLY_KEYS = tuple(name for name in _KEYS if name != "material")


def _library_route(lay, irregular):
    """Why a JIT variant evaluates a surface with the library lane by lane rather than in
    Dr.Jit (None: it traces it): what the library computes and Dr.Jit does not trace — the
    weave's relief and fibres (``detail`` "auto" and "fibers"), shaped floats, uneven dyeing."""
    if lay["kind"] != "pattern":
        return None
    if lay["detail"] in ("fibers", "auto"):
        return f"`detail` = {lay['detail']!r} resolves the weave's relief and its fibres"
    if lay["u_max"] > 0 and tuple(lay.get("float_shape", (0.0, 0.0))) != (0.0, 0.0):
        return "floats shaped by `float_crest` and `float_flank`"
    if irregular:
        return "`irregularity` dyes each yarn unevenly along its length"
    return None


_EVALUATED_FLAGS = ("SymbolicLoops", "SymbolicCalls", "SymbolicConditionals")


def _evaluated_mode(dr):
    """Switches Dr.Jit, in the calling thread (its flags are per thread), to evaluated
    (wavefront) loops, calls and conditionals, so that the library can answer each lane of a
    BSDF call."""
    for f in _EVALUATED_FLAGS:
        dr.set_flag(getattr(dr.JitFlag, f), False)


class _Lanes:
    """Mitsuba values as the library's arrays (rows) and back: a JIT variant's lanes, or a
    scalar variant's one value as one row."""

    def __init__(self, mi, dr, why):
        self.mi, self.dr = mi, dr
        self.jit = dr.is_jit_v(mi.Float)
        if self.jit and dr.flag(dr.JitFlag.SymbolicScope):
            raise RuntimeError(
                f"woven BSDF: {why}, which the library evaluates lane by lane: that needs"
                " Dr.Jit's evaluated mode, but this call is traced symbolically. Call"
                " woven.mitsuba.register() in the thread that renders (it sets"
                " dr.JitFlag.SymbolicLoops, SymbolicCalls and SymbolicConditionals to False"
                " there), or give the surface detail = 'yarns' or 'cloth' (traced by Dr.Jit)"
            )

    def cols(self, x, k, active, fill):
        """``x`` (k components) as (N, k) float64, ``fill`` where a lane is inactive or not
        finite."""
        comps = [x] if k == 1 else [x[i] for i in range(k)]
        arrs = [np.atleast_1d(np.asarray(c, dtype=np.float64)) for c in comps]
        ok = np.atleast_1d(np.asarray(active, dtype=bool))
        n = max([len(a) for a in arrs] + [len(ok)])
        out = np.stack([np.broadcast_to(a, (n,)) for a in arrs], axis=1)
        keep = np.broadcast_to(ok, (n,))[:, None] & np.isfinite(out)
        return np.where(keep, out, fill)

    def dirs(self, x, active):
        """Unit vectors (N, 3): Mitsuba's as they are where their length is within
        ``woven.UNIT_TOLERANCE`` of 1, as the library takes them (float32 rounding is), normalised
        again in float64 where it is not; straight up where a lane is inactive, or a component or
        the length is not finite or 0."""
        d = self.cols(x, 3, active, np.nan)
        length = np.linalg.norm(d, axis=1, keepdims=True)
        ok = np.isfinite(length) & (length > 0)
        off = ok & (np.abs(length - 1.0) > woven.UNIT_TOLERANCE)
        d = np.where(off, d / np.where(off, length, 1.0), d)
        return np.where(ok, d, np.array([0.0, 0.0, 1.0]))

    def _float(self, column):
        if not self.jit:
            return float(column[0])
        return self.mi.Float(np.ascontiguousarray(column, dtype=np.float32))

    def floats(self, a):
        return self._float(np.asarray(a).reshape(-1))

    def color(self, a):
        return self.mi.Color3f(*(self._float(a[:, c]) for c in range(3)))

    def vector(self, a):
        return self.mi.Vector3f(*(self._float(a[:, c]) for c in range(3)))


class JitLayout:
    """The layout of a ``woven.Surface`` in Dr.Jit: the lobes mixed at each lane's point. The
    Python twin of ``WovenSurface::lobes`` (crates/woven/src/surface.rs), tested lane for lane
    against it (tests/test_mitsuba.py); every constant (pattern cells, floats, the macro
    BRDF's lobes, the filter's range, the dyed albedos) comes from ``Surface.layout()``.

    A lobe is ``(warp, along, weight)``, ``along`` as ``Surface.lobes`` reports the library's
    ``Tilt``: −1 flat, the entry fraction in [0, 1] for a point of a tilted float, 2 for a whole
    float (a constant, or lanes). ``float`` is the floats' profile (``JitFloat``), None without
    a tilt."""

    def __init__(self, surface, mi, footprint_filter=True):
        import drjit as dr

        self.mi, self.dr = mi, dr
        self.filter = footprint_filter
        lay = surface.layout()
        self.kind = lay["kind"]
        if lay["detail"] == "cloth" and self.kind == "pattern":
            self.kind = "macro"  # every point the macro BRDF
        self.nu, self.nv = lay["yarns_per_unit"]
        self.u_max, self.gap = lay["u_max"], lay["gap"]
        if self.u_max > 0 and tuple(lay.get("float_shape", (0.0, 0.0))) != (0.0, 0.0):
            crest, flank = lay["float_shape"]
            raise ValueError(
                f"woven BSDF: floats shaped by float_crest = {crest} and float_flank = {flank}"
                " are not traced by the JIT variants yet (their floats tilt linearly); use a"
                " scalar variant, or u_max_deg = 0"
            )
        self.float = JitFloat(self.u_max, mi) if self.u_max > 0 else None
        self.filter_lo, self.filter_hi = lay["filter_cells"]
        self.macro = [(bool(w), FLOAT if f else FLAT, float(g)) for w, f, g in lay["macro"]]
        self.albedos = lay["albedos"]
        if self.kind == "pattern":
            cells = np.asarray(lay["cells"])
            self.rows, self.cols = cells.shape
            self.cells = mi.UInt32(cells.reshape(-1).astype(np.uint32))
            floats = np.asarray(lay["floats"])
            self.tilted = floats.size > 0
            if self.tilted:
                self.before = mi.Float(floats[..., 0].reshape(-1).astype(np.float64))
                self.length = mi.Float(floats[..., 1].reshape(-1).astype(np.float64))

    def macro_weight(self, si):
        """``WovenSurface::macro_weight``: the footprint filter's weight of the macro BRDF."""
        dr = self.dr
        a, b = si.duv_dx, si.duv_dy
        cells = dr.maximum(
            self.nu * (dr.abs(a.x) + dr.abs(b.x)), self.nv * (dr.abs(a.y) + dr.abs(b.y))
        )
        x = dr.clip((cells - self.filter_lo) / (self.filter_hi - self.filter_lo), 0.0, 1.0)
        return dr.select(cells > self.filter_lo, x * x * (3.0 - 2.0 * x), 0.0)

    def _cell(self, t, n):
        """``Pattern::cell_at``'s wrap: floor(t) mod n, in range."""
        dr, mi = self.dr, self.mi
        x = dr.floor(t)
        x = x - n * dr.floor(x / n)
        return dr.minimum(mi.UInt32(dr.maximum(x, 0.0)), n - 1)

    def cell_lobe(self, si):
        """``WovenSurface::push_cell`` at weight 1: (warp, along, weight) per lane, ``along``
        the entry fraction ``(before + along) / len`` on a tilted float, else −1 (flat)."""
        dr, mi = self.dr, self.mi
        x, y = si.uv.x * self.nu, si.uv.y * self.nv
        finite = dr.isfinite(x) & dr.isfinite(y)
        row, col = self._cell(y, self.rows), self._cell(x, self.cols)
        index = row * self.cols + col
        weft = (dr.gather(mi.UInt32, self.cells, index) != 0) | ~finite
        if self.gap == 0 and self.u_max == 0:
            return ~weft, FLAT, mi.Float(1.0)
        cx, cy = x - dr.floor(x), y - dr.floor(y)
        half = 0.5 * (1.0 - self.gap)
        covers_warp = dr.abs(cx - 0.5) < half  # the warp spans x
        covers_weft = dr.abs(cy - 0.5) < half
        covers_top = dr.select(weft, covers_weft, covers_warp)
        covers_below = dr.select(weft, covers_warp, covers_weft)
        along = FLAT
        if self.tilted:
            before = dr.gather(mi.Float, self.before, index)
            length = dr.gather(mi.Float, self.length, index)
            ok = length > 0
            entry = (before + dr.select(weft, cx, cy)) / dr.select(ok, length, 1.0)
            along = dr.select(ok & covers_top & finite, entry, FLAT)
        warp = dr.select(covers_top, ~weft, weft)
        weight = dr.select(covers_top | covers_below, 1.0, 0.0)
        # A non-finite uv shades as the weft, flat.
        return dr.select(finite, warp, False), along, dr.select(finite, weight, 1.0)

    def lobes(self, si):
        """The lobes at each lane: a list of (warp, along, weight), warp and along constants or
        lanes; ``WovenSurface::lobes`` (the Rust mix merges equal lobes; the sum is the same)."""
        mi = self.mi
        if self.kind != "pattern":
            return [(w, t, mi.Float(g)) for w, t, g in self.macro]
        if not self.filter:
            return [self.cell_lobe(si)]
        w = self.macro_weight(si)
        warp, along, weight = self.cell_lobe(si)
        out = [(warp, along, weight * (1.0 - w))]
        out += [(mw, mt, w * mg) for mw, mt, mg in self.macro]
        return out


# A lobe's ``along`` (JitLayout): a flat yarn, a whole tilted float.
FLAT, FLOAT = -1.0, 2.0

# Bisection steps of the float's roots: 2⁻²⁴ of [0, 1], float32's resolution.
_ROOT_STEPS = 24


def _const(along, value):
    """Whether a lobe's ``along`` is the constant ``value`` (not lanes)."""
    return isinstance(along, float) and along == value


class JitFloat:
    """``FloatProfile`` (crates/woven/src/yarn/float.rs) in Dr.Jit, kept to what Dr.Jit forces
    and pinned lane for lane to the library (test_jit_layout_is_the_librarys): the tilt
    ``ψ(t) = u_max (1 − 2t)``, the height ``h(t) = ln cos ψ / (2 u_max)``, the lit interval and
    the point a viewer's ray meets. Directions are in the yarn's frame (the axis along x). The
    library's roots (safeguarded Newton to 1e-12) are here a fixed number of bisection steps
    (float32's resolution) on the same monotone functions, every lane stepping alike."""

    def __init__(self, u_max, mi):
        import drjit as dr

        self.u, self.mi, self.dr = float(u_max), mi, dr

    def tilt(self, t):
        return self.u * (1.0 - 2.0 * t)

    def height(self, t):
        return self.dr.log(self.dr.cos(self.tilt(t))) / (2.0 * self.u)

    def _root(self, f, lo):
        """The root of increasing ``f`` on [lo, 1] (f(lo) ≤ 0 ≤ f(1)), by bisection: a symbolic
        loop, so that its steps are compiled once (unrolled, they made kernels that LLVM took
        half a minute to compile)."""
        dr = self.dr

        def step(lo, hi, i):
            mid = 0.5 * (lo + hi)
            below = f(mid) < 0
            return dr.select(below, mid, lo), dr.select(below, hi, mid), i + 1

        lo, hi, _ = dr.while_loop(
            state=(lo, dr.maximum(lo, 1.0), self.mi.UInt32(0)),
            cond=lambda lo, hi, i: i < _ROOT_STEPS,
            body=step,
        )
        return 0.5 * (lo + hi)

    def _lit_plus(self, m):
        """``lit_from_plus_x``: the lit interval from +x at slope ``m > 0``."""
        dr = self.dr
        a = dr.atan(m)
        t_star = 0.5 * (1.0 - a / self.u)
        g = self.height(t_star) - m * t_star
        # H(t) = h(t) − m t − (g − m) decreases on [t*, 1]: the root of −H.
        t_end = self._root(lambda t: m * t + g - m - self.height(t), t_star)
        full = a >= self.u
        return dr.select(full, 0.0, t_star), dr.select(full, 1.0, t_end)

    def lit(self, d):
        """``FloatProfile::lit``: (t0, t1, ok), ok false at or below the horizon."""
        dr = self.dr
        ok = d.z > 0
        along = d.x != 0
        lo, hi = self._lit_plus(dr.select(along, d.z / dr.select(along, dr.abs(d.x), 1.0), 1.0))
        minus = d.x < 0
        lo, hi = dr.select(minus, 1.0 - hi, lo), dr.select(minus, 1.0 - lo, hi)
        return dr.select(along, lo, 0.0), dr.select(along, hi, 1.0), ok

    def seen_at(self, entry, v):
        """``FloatProfile::seen_at``: the fraction along the float of the point that the ray
        toward ``v`` entering the crests' plane at ``entry`` meets. The foot ``t − h(t)/m``
        increases on all of [t*, 1], so the root is bracketed by [t*, 1] (the library's
        [t*, t_e] holds the same root), sparing the lit interval's own root."""
        dr = self.dr
        along = (v.z > 0) & (v.x != 0) & dr.isfinite(v.x) & dr.isfinite(v.z)
        minus = v.x < 0
        e = dr.select(minus, 1.0 - entry, entry)
        m = dr.select(along, v.z / dr.select(along, dr.abs(v.x), 1.0), 1.0)
        a = dr.atan(m)
        lo = dr.select(a >= self.u, 0.0, 0.5 * (1.0 - a / self.u))

        def foot(t):
            return t - self.height(t) / m

        start = foot(lo)
        target = e - dr.floor(e - start)
        t = self._root(lambda t: foot(t) - target, lo)
        t = dr.select(minus, 1.0 - t, t)
        return dr.select(along, t, dr.clip(entry, 0.0, 1.0))


def _bsdf_class(mi):
    """The BSDF class for the current variant."""
    import drjit as dr

    jit = dr.is_jit_v(mi.Float)

    class WovenBSDF(mi.BSDF):
        """The woven cloth BSDF (see the module ``woven.mitsuba``)."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.surface, self.textures, self.irregular = _surface(props, mi)
            self.filter = _boolean(props, "footprint_filter", _FILTER_DEFAULT)
            self.table = self.surface.table
            self.material = self.surface.material
            self.own = self.table.raw()["own"]
            flags = (
                mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.Anisotropic
            )
            if self.surface.uses_footprint or self.textures:
                flags |= mi.BSDFFlags.SpatiallyVarying
            self.m_flags = flags
            self.m_components = [flags]
            lay = self.surface.layout()
            # Where the library answers each lane (every variant's scalar calls, and in JIT
            # variants the levels Dr.Jit does not trace: see the module's docs).
            self.library = not jit or _library_route(lay, self.irregular) is not None
            if self.filter and (self.surface.uses_footprint or lay["detail"] == "auto"):
                # Integrators that can (``direct``, ``aov``) then compute si.duv_dx, si.duv_dy.
                # (BSDFFlags::NeedsDifferentials, which Mitsuba's Python enum leaves out.)
                self.m_flags = int(flags) | _NEEDS_DIFFERENTIALS
                self.m_components = [int(flags) | _NEEDS_DIFFERENTIALS]
            self.why = _library_route(lay, self.irregular) if jit else None
            if jit and not self.library:
                self.jt = JitTable(self.table, mi)
                self.layout = JitLayout(self.surface, mi, self.filter)
                # A whole tilted float's table (Table::tilted): one look-up.
                tilted = self.layout.float is not None
                self.jt_float = JitTable(self.surface.float_table, mi) if tilted else None

        # -- colour ---------------------------------------------------------------------------

        def _dye(self, key, si, active):
            """(ρ0, ρ) per channel for the weft or the warp at ``si``: a textured colour read
            there (the library's dye rule, woven::surface), else the layout's albedos."""
            c = self.textures.get(key)
            if c is None:
                a = self.layout.albedos["warp" if key == "warp_color" else "weft"]
                return mi.Color3f(*(x[0] for x in a)), mi.Color3f(*(x[1] for x in a))
            # A NaN texel is black, the library's dye rule (Albedos::dyed); left NaN it made
            # NaN samples, which the film's filter spread over neighbouring pixels.
            # In [0, 1], as the library path takes it (an HDR texture saturates).
            c = c.eval(si, active)
            c = dr.clip(dr.select(dr.isnan(c), 0.0, c), 0.0, 1.0)
            d0, r0 = self.own
            rho0 = dr.clip(c, 0.0, 0.999)
            rho = dr.clip(r0 * c / d0, 0.0, 1.0) if d0 > 0 else c * 0.0 + r0
            return rho0, rho

        def _albedos(self, warp, si, active):
            weft = self._dye("weft_color", si, active)
            if warp is False:
                return weft
            warp_a = self._dye("warp_color", si, active)
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

        def eval(self, ctx, si, wo, active=True):
            active = mi.Bool(active) & (si.wi.z > 0) & (wo.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection) or (not jit and not active):
                return mi.Color3f(0.0)
            if self.library:
                f = self._lib_eval(si, wo, active)
            else:
                f = self._eval_jit(si, wo, active)
            return dr.select(active, f * wo.z, 0.0)

        def pdf(self, ctx, si, wo, active=True):
            active = mi.Bool(active) & (si.wi.z > 0) & (wo.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection) or (not jit and not active):
                return mi.Float(0.0)
            if self.library:
                p = self._lib.floats(self.surface.pdf(*self._lib_args(si, wo, active)))
            else:
                p = self._pdf_jit(si, wo, active)
            return dr.select(active, p, 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            bs = mi.BSDFSample3f()
            active = mi.Bool(active) & (si.wi.z > 0)
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection) or (not jit and not active):
                return bs, mi.Color3f(0.0)
            if self.library:
                # The library's draw carries its f: no second call to evaluate it.
                wo, pdf, f = self._lib_sample(si, sample1, sample2, active)
            else:
                wo, pdf, ok = self._sample_jit(si, sample1, sample2, active)
                active &= ok
            active &= wo.z > 0
            if not jit and not (active and pdf > 0):
                return bs, mi.Color3f(0.0)
            pdf = dr.select(active, pdf, 0.0)
            bs.wo = wo
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            if self.library:
                f = dr.select(active, f * wo.z, 0.0)
            else:
                f = self.eval(ctx, si, wo, active)
            active &= pdf > 0
            bs.pdf = dr.select(active, pdf, 0.0)
            weight = dr.select(active, f / dr.select(active, pdf, 1.0), 0.0)
            return bs, weight

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

        def _lib_dyes(self, si, active):
            lanes = self._lib
            # The library takes dyes in [0, 1]: a texture outside (HDR, scaled) saturates, and
            # a NaN texel is black (the library's dye rule).
            return {k: np.clip(np.nan_to_num(lanes.cols(t.eval(si, active), 3, active, 0.0),
                                             nan=0.0), 0.0, 1.0)
                    for k, t in self.textures.items()}

        def _lib_eval(self, si, wo, active):
            f = self.surface.eval(*self._lib_args(si, wo, active), **self._lib_dyes(si, active))
            return self._lib.color(f)

        def _lib_sample(self, si, sample1, sample2, active):
            lanes = self._lib
            uv, fp = self._lib_points(si, active)
            d, f, pdf = self.surface.sample(
                uv,
                lanes.dirs(si.wi, active),
                lanes.cols(sample1, 1, active, 0.5)[:, 0],
                lanes.cols(sample2, 2, active, 0.5),
                fp,
                **self._lib_dyes(si, active),
            )
            return lanes.vector(d), lanes.floats(pdf), lanes.color(f)

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"WovenBSDF[{self.surface!r}, table={self.table!r}]"

    return WovenBSDF




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


def __getattr__(name):
    if name == "WovenBSDF":
        import mitsuba as mi

        return _bsdf_class(mi)
    if name == "MicrocylinderBSDF":
        import mitsuba as mi

        return _microcylinder_class(mi)
    raise AttributeError(name)
