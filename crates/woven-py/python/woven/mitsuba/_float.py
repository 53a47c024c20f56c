"""``JitFloat``: a tilted float's profile and the point a ray meets on it, in Dr.Jit (the
library's crates/woven/src/yarn/float.rs)."""

from __future__ import annotations


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
