"""The inset as ``woven render`` draws it, for the renderers ``woven`` drives elsewhere
(``woven.mitsuba``, ``woven.blender``)."""

from __future__ import annotations


def paste(image, inset, close):
    """Pastes ``close`` (the inset's own render) into ``image`` (height, width, 3) at
    ``inset["inner"]``, inside a white border filling ``inset["outer"]`` (``woven.portable_scene``'s
    inset; its linear colour ``inset["border"]``, `woven render`'s), in place; returns ``image``."""
    (x0, y0), (w, h) = inset["inner"]
    (ox, oy), (ow, oh) = inset["outer"]
    image[oy:oy + oh, ox:ox + ow] = inset["border"]
    image[y0:y0 + h, x0:x0 + w] = close
    return image
