"""woven in Blender: woven materials as Cycles node trees, and ``woven render`` scenes rendered
by Cycles (``python -m woven.blender SCENE.toml -o OUT.exr``).

Cycles cannot host a BSDF of its own making: its closures are a fixed list. So a woven material
reaches Cycles as its projection onto the lobes Cycles has (``woven.standard_surface``, from the
library): for each yarn family a Lambertian lobe and an anisotropic GGX along the yarn, fitted
to the family as the cloth shows it; and its layout on the uv, baked by the library into
textures — which family is on top (and the holes between gapped yarns) and each yarn's dye
factor (``irregularity``). Nothing of the layout is
rewritten here: the rules are the library's, read as images. The float's tilt is in each
family's lobes (fitted to its whole float, with the masking between its facets, which a normal
map could not carry: docs/blender.md).

What the standard lobes cannot carry, and so this material does not: the masking's dependence on
the light (a yarn's lit-and-seen part), the interreflection term's shape, the paper
normalisation's non-reciprocity, woven's sheen, and the fibre level (``detail = "fibers"``, or ``"auto"``
close up): the yarn's average stands for the fibres. docs/blender.md measures what that costs.

    import bpy, woven, woven.blender
    mat = woven.blender.material("polyester-sateen", pattern="twill-2/1",
                                 weft_color=(0.6, 0.1, 0.1), yarns_per_unit=4000)
    bpy.context.object.data.materials.append(mat)

As an add-on (Blender's Preferences → Add-ons → Install from disk, with the ``woven`` package
importable by Blender's Python): Object → "Add woven material" asks for a preset or a material
file and the surface keys.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

bl_info = {
    "name": "woven cloth",
    "author": "the woven developers",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "Object > Add woven material",
    "description": "Woven cloth materials (Yang & Ikeuchi's model) as Cycles node trees",
    "category": "Material",
}

__all__ = ["material", "register", "unregister"]


def material(source, name=None, folder=None, texels_per_cell=16, **keys):
    """A Blender material of the woven material ``source`` (a preset name or a material file, as
    ``woven.Surface`` takes it) with the surface keys ``keys`` (those of ``woven.SURFACE_KEYS``;
    a WIF draft is ``pattern={"wif": "draft.wif"}``): its families' standard lobes laid out by its textures, which are
    written into ``folder`` (a new temporary folder by default; Blender reads them from
    there). Raises ValueError naming a key out of range."""
    import bpy
    import woven

    from . import _material

    folder = Path(folder or tempfile.mkdtemp(prefix="woven-blender-"))
    name = name or str(source)
    surface = woven.Surface(str(source), progress=False, **keys)
    stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in name)[:64]
    identity = _contents(source) + repr(sorted(keys.items()))
    pattern = keys.get("pattern")
    if isinstance(pattern, dict) and "wif" in pattern:
        identity += _contents(pattern["wif"])
    std = _material.standard(surface, identity, folder, stem, texels_per_cell)
    return _material.material(bpy, name, std)


def _contents(source):
    """A material's or draft's text where ``source`` names a file, else its name: what keys the
    projection's cache (a file edited is a new material)."""
    path = Path(str(source))
    try:
        return path.read_text(errors="replace") if path.is_file() else str(source)
    except OSError:
        return str(source)


def register():
    """Registers the add-on's operator (Object → "Add woven material")."""
    from . import _addon

    _addon.register()


def unregister():
    from . import _addon

    _addon.unregister()
