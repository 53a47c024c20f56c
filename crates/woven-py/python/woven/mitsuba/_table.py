"""``JitTable``: a woven table's look-ups, interpolation and sampling in Dr.Jit, from the arrays
``Table.raw()`` hands over (the library's crates/woven/src/table/, operation by operation)."""

from __future__ import annotations

import math

import numpy as np

import woven


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
