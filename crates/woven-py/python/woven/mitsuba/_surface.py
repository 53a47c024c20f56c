"""The ``woven.Surface`` a plugin's properties describe (the library reads every key), and the
lanes through which the library answers a JIT variant's calls (Dr.Jit's evaluated mode)."""

from __future__ import annotations

import numpy as np

import woven


def _surface(props, mi):
    """The ``woven.Surface`` a plugin's properties describe, and its textured colours. The
    plugin reads no key itself: it hands every surface key given (``woven.SURFACE_KEYS``) to
    ``woven.Surface``, whose one reader in the library (``SurfaceSpec::from_keys``) takes,
    defaults and checks them as scenes do; a colour may also be a texture, read at each hit."""
    has = props.__contains__
    if has("table") == has("material"):
        raise ValueError("woven BSDF: give exactly one of `table` and `material`")
    keys, textures = {}, {}
    for name in _KEYS:
        if name == "material" or not has(name):
            continue
        value = props[name]
        if isinstance(value, mi.Texture):
            if name not in ("weft_color", "warp_color"):
                raise ValueError(f"woven BSDF: `{name}` takes no texture")
            textures[name] = value
        elif name in ("weft_color", "warp_color"):
            keys[name] = [float(x) for x in mi.ScalarColor3f(value)]
        else:
            keys[name] = value
    try:
        if has("table"):
            table = woven.Table.load(str(props["table"]))
            surface = woven.Surface(table=table, **keys)
        else:
            surface = woven.Surface(str(props["material"]), progress=False, **keys)
    except (ValueError, TypeError) as e:
        raise ValueError(f"woven BSDF: {e}") from None
    if textures and surface.table.raw()["own"] is None:
        raise ValueError("woven BSDF: a textured colour needs a table that records its material")
    return surface, textures


# Mitsuba's BSDFFlags::NeedsDifferentials (include/mitsuba/render/bsdf.h), not in its Python
# enum: ``si.bsdf(ray)`` then computes the uv partials from a ray's differentials.
_NEEDS_DIFFERENTIALS = 0x20000

# The surface keys (the library's table: woven.SURFACE_KEYS), which the plugin hands on.
_KEYS = {k["name"]: k for k in woven.SURFACE_KEYS}

# The keys of the woven cloth that a microcylinder fabric has no use for.
_WOVEN_ONLY_KEYS = tuple(name for name in _KEYS if name != "material")


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
