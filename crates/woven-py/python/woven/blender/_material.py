"""A woven surface as a Cycles node tree: each yarn family's standard lobes
(``woven.standard_surface``: Lambert + anisotropic GGX along the yarn, colours per channel)
laid out on the uv by the textures the library bakes (which family is on top, each yarn's dye
factor). Nodes only, so the material renders on the CPU and on
GPUs alike (Cycles' OSL runs on the CPU only).

Each family's GGX lobe is Cycles' Metallic BSDF with a physical-conductor Fresnel of extinction
0, which is the dielectric's Fresnel exactly. Its weight is per channel: one closure per channel,
whose index of refraction is 1.5 in that channel and 1 (no reflection at all) in the others,
mixed in by its weight (added again for the part of a weight above 1). The diffuse lobe is
Lambert (Diffuse BSDF, roughness 0). A sheen, where a projection fits one, would be Cycles'
"Microfiber" (Zeltner et al. 2022); the projection fits none (``woven_fit::standard``: woven's
sheen is a Charlie lobe, whose grazing peak Zeltner's does not share).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import tempfile
from pathlib import Path


import woven

# Cycles' "Metallic BSDF" per-channel index of refraction: 1 reflects nothing.
_NO_REFLECTION = 1.0
# The UV map every mesh woven.blender builds carries (and the tangents are read from).
UV_MAP = "UVMap"


def standard(surface, identity, folder, stem, texels_per_cell=16):
    """``woven.standard_surface`` of ``surface`` (a ``woven.Surface``), its textures in
    ``folder`` as ``STEM-*.png``. ``identity`` (text naming the material and its keys wholly)
    keys a cache beside the library's tables (``$XDG_CACHE_HOME/woven/standard``, else
    ``~/.cache/woven/standard``): a projection takes seconds to a minute, a cached one none.
    A surface that lets light through (``transmission``) carries its yarns' translucency
    (``std["translucent"]``) and passes light through its holes."""
    key = hashlib.sha256(
        f"{woven.__version__}\n{woven.STANDARD_VERSION}\n{texels_per_cell}\n{identity}".encode()).hexdigest()[:32]
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    cached = Path(root) / "woven" / "standard" / key
    names = ("layout", "factors")
    try:
        std = json.loads((cached / "standard.json").read_text())
        for n in names:
            shutil.copyfile(cached / f"{n}.png", Path(folder) / f"{stem}-{n}.png")
    except (OSError, ValueError):
        std = woven.standard_surface(surface, str(folder), stem, texels_per_cell=texels_per_cell)
        _store(cached, std, names)
    std["files"] = {n: str(Path(folder) / f"{stem}-{n}.png") for n in names}
    return std


def _store(cached, std, names):
    """Keeps ``std`` and its textures in the cache folder ``cached``, whole or not at all (a
    folder renamed into place); a cache that cannot be written is skipped."""
    try:
        cached.parent.mkdir(parents=True, exist_ok=True)
        work = Path(tempfile.mkdtemp(dir=cached.parent, prefix=".tmp-"))
    except OSError:
        return
    try:
        for n in names:
            shutil.copyfile(std["files"][n], work / f"{n}.png")
        kept = {k: v for k, v in std.items() if k != "files"}
        (work / "standard.json").write_text(json.dumps(kept))
        os.replace(work, cached)
    except OSError:
        shutil.rmtree(work, ignore_errors=True)


def material(bpy, name, std):
    """A Blender material named ``name`` from ``std`` (``woven.standard_surface``'s dict with
    its ``files``): the layout's textures over the uv in the cloth's units (the mesh's uv, as
    ``woven render`` reads it), the two families' lobes, black in the holes; where the cloth
    lets light through, its yarns translucent, its holes transparent and its back face the
    weave turned over."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = Tree(bpy, mat.node_tree)
    tree.nodes.clear()
    cells, per_unit = std["cells"], std["yarns_per_unit"]
    coords = tree.node("ShaderNodeTexCoord")
    mapping = tree.node("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = (per_unit[0] / cells[0], per_unit[1] / cells[1], 1.0)
    tree.link(coords.outputs["UV"], mapping.inputs["Vector"])
    files = std["files"]
    layout = tree.split(tree.image(files["layout"], mapping, "Closest"))
    factors = tree.split(tree.image(files["factors"], mapping, "Closest"))
    geometry = tree.node("ShaderNodeNewGeometry")
    tangent = tree.node("ShaderNodeTangent", direction_type="UV_MAP", uv_map=UV_MAP)
    normal, along_u = geometry.outputs["Normal"], tangent.outputs["Tangent"]
    translucent = std.get("translucent")
    weft = _family(tree, std["weft"], factors[0], std["factor_range"], normal, along_u, 0.0,
                   translucent)
    warp = _family(tree, std["warp"], factors[1], std["factor_range"], normal, along_u, 0.25,
                   translucent)
    # The warp where it is on top, else the weft.
    families = tree.mix(layout[1], weft, warp)
    hole = None
    if translucent is not None:
        # A cloth that lets light through is two-sided: from behind, the weave turned over
        # (where the weft is on top in front, the warp shows behind: the pattern's complement;
        # Cycles turns the frame of a back face about the tangent, along the weft, as woven
        # render does), and its holes pass light straight through.
        back = tree.mix(layout[1], warp, weft)
        behind = geometry.outputs["Backfacing"]
        families = tree.mix(behind, families, back)
        hole = tree.node("ShaderNodeBsdfTransparent").outputs["BSDF"]
    cover = tree.math("ADD", layout[0], layout[1], clamp=True)
    out = tree.node("ShaderNodeOutputMaterial")
    # Where neither family is (a hole): nothing, or light straight through.
    tree.link(tree.mix(cover, hole, families), out.inputs["Surface"])
    return mat


def _family(tree, fam, factor, factor_range, normal, along_u, turn, translucent=None):
    """One family's closures, added: Lambert in its dye (times its yarn's factor), the GGX
    lobe per channel, the sheen, and where the cloth lets light through, the Lambertian
    translucency ``translucent`` (per channel) of its yarns. ``turn`` (in turns) takes the
    weft's tangent (along u) to the family's yarn."""
    scale = tree.math("MULTIPLY", factor, factor_range)
    dye = tree.node("ShaderNodeVectorMath", operation="SCALE")
    dye.inputs[0].default_value = tuple(fam["diffuse"])
    tree.link(scale, dye.inputs["Scale"])
    diffuse = tree.node("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0
    tree.link(dye.outputs["Vector"], diffuse.inputs["Color"])
    tree.link(normal, diffuse.inputs["Normal"])
    shaders = [diffuse.outputs["BSDF"]]
    cycles = fam["cycles"]
    for channel, weight in enumerate(fam["specular"]):
        ior = [_NO_REFLECTION] * 3
        ior[channel] = 1.5
        while weight > 1e-6:
            ggx = tree.node("ShaderNodeBsdfMetallic", distribution="GGX",
                            fresnel_type="PHYSICAL_CONDUCTOR")
            ggx.inputs["IOR"].default_value = ior
            ggx.inputs["Extinction"].default_value = (0.0, 0.0, 0.0)
            ggx.inputs["Roughness"].default_value = cycles["roughness"]
            ggx.inputs["Anisotropy"].default_value = cycles["anisotropy"]
            ggx.inputs["Rotation"].default_value = (cycles["rotation"] + turn) % 1.0
            tree.link(normal, ggx.inputs["Normal"])
            tree.link(along_u, ggx.inputs["Tangent"])
            shaders.append(tree.mix(min(weight, 1.0), None, ggx.outputs["BSDF"]))
            weight -= 1.0
    if max(fam["sheen"]) > 0.0:
        sheen = tree.node("ShaderNodeBsdfSheen", distribution="MICROFIBER")
        sheen.inputs["Color"].default_value = (*fam["sheen"], 1.0)
        sheen.inputs["Roughness"].default_value = fam["sheen_roughness"]
        tree.link(normal, sheen.inputs["Normal"])
        shaders.append(sheen.outputs["BSDF"])
    if translucent is not None and max(translucent) > 0.0:
        through = tree.node("ShaderNodeBsdfTranslucent")
        through.inputs["Color"].default_value = (*[float(x) for x in translucent], 1.0)
        tree.link(normal, through.inputs["Normal"])
        shaders.append(through.outputs["BSDF"])
    total = shaders[0]
    for s in shaders[1:]:
        add = tree.node("ShaderNodeAddShader")
        tree.link(total, add.inputs[0])
        tree.link(s, add.inputs[1])
        total = add.outputs["Shader"]
    return total


class Tree:
    """A node tree being built: nodes, links and the few patterns every builder here needs."""

    def __init__(self, bpy, tree):
        self.bpy, self.tree = bpy, tree
        self.nodes = tree.nodes

    def node(self, kind, **props):
        n = self.nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        return n

    def link(self, output, input_):
        self.tree.links.new(output, input_)

    def image(self, path, vector, interpolation):
        """An image texture of ``path`` (data, not colour: no transform), read at ``vector``."""
        img = self.bpy.data.images.load(str(path), check_existing=True)
        img.colorspace_settings.name = "Non-Color"
        tex = self.node("ShaderNodeTexImage", interpolation=interpolation, extension="REPEAT")
        tex.image = img
        self.link(vector.outputs["Vector"], tex.inputs["Vector"])
        return tex

    def split(self, texture):
        """A texture's R, G and B outputs."""
        sep = self.node("ShaderNodeSeparateColor")
        self.link(texture.outputs["Color"], sep.inputs["Color"])
        return [sep.outputs[c] for c in ("Red", "Green", "Blue")]

    def math(self, operation, a, b, clamp=False):
        """``a operation b``, each a socket or a number."""
        n = self.node("ShaderNodeMath", operation=operation, use_clamp=clamp)
        for k, x in enumerate((a, b)):
            if isinstance(x, (int, float)):
                n.inputs[k].default_value = float(x)
            else:
                self.link(x, n.inputs[k])
        return n.outputs["Value"]

    def mix(self, factor, a, b):
        """``(1 − factor) a + factor b`` of two shaders (None: no closure), ``factor`` a number
        or a socket."""
        n = self.node("ShaderNodeMixShader")
        if isinstance(factor, (int, float)):
            n.inputs["Factor"].default_value = float(factor)
        else:
            self.link(factor, n.inputs["Factor"])
        for k, s in ((1, a), (2, b)):
            if s is not None:
                self.link(s, n.inputs[k])
        return n.outputs["Shader"]


def diffuse(bpy, name, reflectance):
    """A Lambertian material."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = Tree(bpy, mat.node_tree)
    tree.nodes.clear()
    d = tree.node("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*[float(x) for x in reflectance], 1.0)
    d.inputs["Roughness"].default_value = 0.0
    out = tree.node("ShaderNodeOutputMaterial")
    tree.link(d.outputs["BSDF"], out.inputs["Surface"])
    return mat


def emitter(bpy, name, color):
    """A material that emits ``color`` and reflects nothing (the masks' flat colours)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = Tree(bpy, mat.node_tree)
    tree.nodes.clear()
    e = tree.node("ShaderNodeEmission")
    e.inputs["Color"].default_value = (*color, 1.0)
    e.inputs["Strength"].default_value = 1.0
    out = tree.node("ShaderNodeOutputMaterial")
    tree.link(e.outputs["Emission"], out.inputs["Surface"])
    return mat


