"""``JitFloat``: a tilted float's profile and the point a ray meets on it, in Dr.Jit (the
library's crates/woven/src/yarn/float.rs)."""

from __future__ import annotations


# Bisection steps of the float's roots: 2⁻²⁴ of [0, 1], float32's resolution.
_ROOT_STEPS = 24


def _const(along, value):
    """Whether a lobe's ``along`` is the constant ``value`` (not lanes)."""
    return isinstance(along, float) and along == value


class JitFloat:
    """``FloatProfile`` (crates/woven/src/yarn/float.rs) in Dr.Jit, kept to what Dr.Jit forces
    and pinned lane for lane to the library (test_plugin_lanes_are_the_librarys): the tilt
    ``ψ(t)``, linear between the knots the library hands over (two for Irawan & Marschner's
    linear tilt, up to six for a flat crest and steep flanks), the height
    ``h(t) = rises[k] + ∫_{t_k}^t tan ψ − top`` in the piece from knot ``k``, the lit interval
    and the point a viewer's ray meets. Directions are in the yarn's frame (the axis along x).
    The library's roots (safeguarded Newton to 1e-12) are here a fixed number of bisection
    steps (float32's resolution) on the same monotone functions, every lane stepping alike."""

    def __init__(self, profile, mi):
        """``profile``: the layout's ``float`` (``{"knots", "rises", "top"}``)."""
        import drjit as dr

        self.mi, self.dr = mi, dr
        knots = [(float(t), float(p)) for t, p in profile["knots"]]
        self.u = knots[0][1]
        self.top = float(profile["top"])
        # Each piece: (t0, ψ0, t1, ψ1, its slope ψ′, the rise at t0).
        self.pieces = [
            (t0, p0, t1, p1, (p1 - p0) / (t1 - t0), float(r))
            for (t0, p0), (t1, p1), r in zip(knots, knots[1:], profile["rises"])
        ]

    def _piece(self, t):
        """(t0, ψ0, ψ′, rise) of the piece holding each lane's ``t`` (clamped to the float)."""
        dr = self.dr
        t0, p0, _, _, k, r = self.pieces[0]
        for a, pa, _, _, ka, ra in self.pieces[1:]:
            take = t >= a
            t0, p0 = dr.select(take, a, t0), dr.select(take, pa, p0)
            k, r = dr.select(take, ka, k), dr.select(take, ra, r)
        return t0, p0, k, r

    def tilt(self, t):
        t0, p0, k, _ = self._piece(t)
        return p0 + k * (t - t0)

    def height(self, t):
        """Below the crest (≤ 0), in float lengths."""
        dr = self.dr
        t0, p0, k, r = self._piece(t)
        dt = t - t0
        flat = k == 0
        bent = (dr.log(dr.cos(p0)) - dr.log(dr.cos(p0 + k * dt))) / dr.select(flat, 1.0, k)
        return r + dr.select(flat, dr.tan(p0) * dt, bent) - self.top

    def _facing_from(self, a):
        """``facing_from``: the first t past which the tilt is below ``a``."""
        dr = self.dr
        out, found = self.mi.Float(1.0), self.mi.Bool(False)
        for t0, p0, t1, p1, _, _ in self.pieces:
            take = ~found & (p1 < a)
            at = dr.select(p0 <= a, t0, t0 + (t1 - t0) * (p0 - a) / (p0 - p1))
            out, found = dr.select(take, at, out), found | take
        return out

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

    def _start(self, m):
        """(t*, full): the first facing point from +x at slope ``m > 0``, and whether the whole
        float faces (t* = 0)."""
        a = self.dr.atan(m)
        full = a >= self.u
        return self.dr.select(full, 0.0, self._facing_from(a)), full

    def _lit_plus(self, m):
        """``lit_from_plus_x``: the lit interval from +x at slope ``m > 0``."""
        dr = self.dr
        t_star, full = self._start(m)
        g = self.height(t_star) - m * t_star
        # H(t) = h(t) − m t − (g − m) decreases on [t*, 1]: the root of −H.
        t_end = self._root(lambda t: m * t + g - m - self.height(t), t_star)
        return t_star, dr.select(full, 1.0, t_end)

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
        increases on all of [t*, 1] (there tan ψ < m), so the root is bracketed by [t*, 1]
        (the library's [t*, t_e] holds the same root), sparing the lit interval's own root."""
        dr = self.dr
        along = (v.z > 0) & (v.x != 0) & dr.isfinite(v.x) & dr.isfinite(v.z)
        minus = v.x < 0
        e = dr.select(minus, 1.0 - entry, entry)
        m = dr.select(along, v.z / dr.select(along, dr.abs(v.x), 1.0), 1.0)
        lo, _ = self._start(m)

        def foot(t):
            return t - self.height(t) / m

        start = foot(lo)
        target = e - dr.floor(e - start)
        t = self._root(lambda t: foot(t) - target, lo)
        t = dr.select(minus, 1.0 - t, t)
        return dr.select(along, t, dr.clip(entry, 0.0, 1.0))
