"""``JitLayout``: the lobes mixed at each lane's point, from the constants ``Surface.layout()``
hands over (the library's crates/woven/src/surface/layout.rs)."""

from __future__ import annotations

import numpy as np

from ._float import JitFloat
from ._frames import FLAT, FLOAT
from ._irregular import JitIrregularity

# The version of the library's JitLayout (woven::surface::JIT_LAYOUT_VERSION) this code traces:
# written here, not read, so a library that changed the layout is refused, not misread.
LAYOUT_VERSION = 2


class JitLayout:
    """The layout of a ``woven.Surface`` in Dr.Jit: the lobes mixed at each lane's point. The
    Python twin of ``WovenSurface::lobes`` (crates/woven/src/surface.rs), tested lane for lane
    against it (tests/test_mitsuba.py); every constant (pattern cells, floats, the macro
    BRDF's lobes, the filter's range, the dyed albedos) comes from ``Surface.layout()``.

    A lobe is ``(warp, along, weight)``, ``along`` as ``Surface.lobes`` reports the library's
    ``Tilt``: −1 flat, the entry fraction in [0, 1] for a point of a tilted float, 2 for a whole
    float (a constant, or lanes). ``float`` is the floats' profile (``JitFloat``), None without
    a tilt; ``irregular`` the yarns' dye factors (``JitIrregularity``), None where every yarn
    is dyed evenly."""

    def __init__(self, surface, mi, footprint_filter=True):
        import drjit as dr

        self.mi, self.dr = mi, dr
        self.filter = footprint_filter
        lay = surface.layout()
        if lay.get("version") != LAYOUT_VERSION:
            raise ValueError(
                f"woven BSDF: the library hands over a surface layout of version"
                f" {lay.get('version')}, and this plugin traces version {LAYOUT_VERSION}:"
                " install the plugin and the library from the same woven build"
            )
        self.kind = lay["kind"]  # a pattern at "cloth" is already "macro"
        self.nu, self.nv = lay["yarns_per_unit"]
        self.u_max, self.gap = lay["u_max"], lay["gap"]
        self.float = None if lay["float"] is None else JitFloat(lay["float"], mi)
        irregular = lay["irregularity"]
        self.irregular = None if irregular is None else JitIrregularity(
            irregular, lay["yarns_per_unit"], mi
        )
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
