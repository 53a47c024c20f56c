"""``JitIrregularity``: each yarn's dye factor along its length, in Dr.Jit (the library's
crates/woven/src/surface/irregular.rs, ``Irregularity::factor``, and
``WovenSurface::dye_factors``)."""

from __future__ import annotations

import math

# The library's hash (woven::yarn::point::hash_uniform) and knot keys (irregular.rs's
# knot_normal): constants of code the plugin translates, pinned by the golden lanes.
_HASH = (0x9E3779B97F4A7C15, 0xD1B54A32D192ED03, 0x632BE59BD9B4E019, 0xBF58476D1CE4E5B9,
         0x94D049BB133111EB)
_YARN = 0x2545F4914F6CDD1D
_FAMILY = (0x3A2F0000, 0x3A2F0001)  # the weft's, the warp's
_SECOND = 0xA5A55A5A


class JitIrregularity:
    """The weft's and the warp's dye factors ``m = exp(σ z − σ²/2)`` at each lane's uv, ``z``
    blended smoothly between standard normals hashed from the yarn, its family and the knot.
    Computed in 64 bits, as the library does: the knots' normals come from 53-bit uniforms."""

    def __init__(self, irregularity, yarns_per_unit, mi):
        """``irregularity``: the layout's (``{"spread": [σ_weft, σ_warp], "length": ℓ}``)."""
        import drjit as dr

        self.mi, self.dr = mi, dr
        self.spread = [float(s) for s in irregularity["spread"]]
        self.length = float(irregularity["length"])
        self.nu, self.nv = (float(n) for n in yarns_per_unit)

    def _uniform(self, a, b):
        """``hash_uniform(a, b)``: a uniform in [0, 1) from two 64-bit keys."""
        u = self.mi.UInt64
        z = a * u(_HASH[0]) + b * u(_HASH[1]) + u(_HASH[2])
        z = (z ^ (z >> 30)) * u(_HASH[3])
        z = (z ^ (z >> 27)) * u(_HASH[4])
        z = z ^ (z >> 31)
        return self.mi.Float64(z >> 11) * 2.0**-53

    def _normal(self, key, knot):
        """``knot_normal``: Box–Muller on two hashed uniforms."""
        dr = self.dr
        u1 = self._uniform(key, knot)
        u2 = self._uniform(key ^ self.mi.UInt64(_SECOND), knot)
        return dr.sqrt(-2.0 * dr.log(1.0 - u1)) * dr.cos(2.0 * math.pi * u2)

    def _bits(self, x):
        """A whole number's i64, read as u64 (Rust's ``as u64``: negatives wrap)."""
        return self.dr.reinterpret_array(self.mi.UInt64, self.mi.Int64(x))

    def _factor(self, index, family, along):
        """``Irregularity::factor`` of yarn ``index`` (a Float64 whole number) of ``family``
        (0 the weft, 1 the warp) at ``along`` pattern cells."""
        dr, mi = self.dr, self.mi
        sigma = self.spread[family]
        if sigma <= 0:
            return mi.Float64(1.0)
        t = along / self.length
        k = dr.floor(t)
        w = t - k
        s = w * w * (3.0 - 2.0 * w)
        key = self._bits(index) * mi.UInt64(_YARN) ^ mi.UInt64(_FAMILY[family])
        knot = self._bits(k)
        z0, z1 = self._normal(key, knot), self._normal(key, knot + 1)
        z = ((1.0 - s) * z0 + s * z1) / dr.sqrt((1.0 - s) ** 2 + s * s)
        return dr.exp(sigma * z - 0.5 * sigma * sigma)

    def varies(self, family):
        """Whether the yarns of ``family`` (0 the weft, 1 the warp) vary at all (σ > 0): where
        they do not, the library leaves their albedos as they are, uncapped."""
        return self.spread[family] > 0

    def factor(self, si, family):
        """The dye factor of ``family`` (0 the weft, 1 the warp) per lane (Float); 1 where the
        uv is not finite. The weft runs along x: its yarns are the rows, its length x."""
        dr, mi = self.dr, self.mi
        x, y = mi.Float64(si.uv.x) * self.nu, mi.Float64(si.uv.y) * self.nv
        finite = dr.isfinite(x) & dr.isfinite(y)
        x, y = dr.select(finite, x, 0.0), dr.select(finite, y, 0.0)
        index, along = (dr.floor(y), x) if family == 0 else (dr.floor(x), y)
        return mi.Float(dr.select(finite, self._factor(index, family, along), 1.0))
