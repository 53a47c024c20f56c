"""The frames the traced code turns lobes into and back: a warp yarn's 90° turn about the normal
and a tilted float's tilt (the library's crates/woven/src/surface/lobe.rs); a lobe's ``along``."""

from __future__ import annotations

# A lobe's ``along`` (JitLayout): a flat yarn, a whole tilted float.
FLAT, FLOAT = -1.0, 2.0


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
