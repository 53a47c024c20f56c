"""A ``woven render`` scene as a Mitsuba 3 scene: ``python -m woven.mitsuba SCENE.toml``.

The scene is read and checked by the renderer's library (``woven.portable_scene``: the same
parse, checks and defaults as ``woven render``), which hands over plain data: meshes with
``woven render``'s uv (rectangles and procedural cloths as triangles), each woven material's
self-contained material file and the keys that read back as its surface, and the Preetham sun
and sky as the map ``woven render`` bakes. Here that data becomes Mitsuba's dict: the camera
(``fov_deg`` across the width), a box-filtered film, ``woven_path`` (``path`` with the camera
ray's footprint, so ``detail = "auto"`` and the footprint filter work as in ``woven render``),
the plugin's ``woven`` BSDF, and the lights. An inset is a second sensor, pasted into its
rectangle with a white border as ``woven render`` draws it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import woven
from woven._inset import paste

# Mitsuba's envmap looks up a local direction d at u = atan2(d.x, -d.z) / 2π, v = acos(d.y) / π;
# woven's map has row 0 at +z and column x at φ = atan2(w.y, w.x). With the columns mirrored,
# the rotation w = (-d.z, -d.x, d.y) takes one onto the other.
_ENV_TO_WORLD = [[0, 0, -1, 0], [-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 1]]


def scene_dict(portable, mi, folder, camera=None, size=None, spp=None, seed=None):
    """The Mitsuba scene dict of ``portable`` (``woven.portable_scene``'s dict), with files it
    needs (materials, maps) written into ``folder``. ``camera`` and ``size`` (width, height)
    replace the scene's own (an inset's); ``spp`` its samples per pixel."""
    folder = Path(folder)
    width, height = size or portable["size"]
    cam = camera or portable["camera"]
    max_depth = portable["max_depth"]
    d = {
        "type": "scene",
        "integrator": {
            "type": "woven_path",
            "max_depth": -1 if max_depth is None else int(max_depth),
            "rr_depth": int(portable["rr_depth"]),
            "hide_emitters": bool(portable["hide_emitters"]),
        },
        "sensor": {
            "type": "perspective",
            "fov": float(cam["fov_deg"]),
            "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=cam["origin"], target=cam["target"], up=cam["up"]
            ),
            "sampler": {
                "type": portable["sampler"],
                "sample_count": int(spp or portable["spp"]),
                "seed": int(portable["seed"] if seed is None else seed),
            },
            "film": {
                "type": "hdrfilm",
                "width": int(width),
                "height": int(height),
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
        },
    }
    bsdfs = {name: _bsdf(name, m, folder) for name, m in portable["materials"].items()}
    for k, shape in enumerate(portable["shapes"]):
        d[f"shape-{k}"] = _shape(shape, bsdfs[shape["material"]], mi)
    for k, light in enumerate(portable["lights"]):
        for name, entry in _light(light, k, folder, mi).items():
            d[name] = entry
    return d


def _rgb(v):
    """A colour as Mitsuba's dict writes it."""
    return {"type": "rgb", "value": [float(x) for x in v]}


def _bsdf(name, m, folder):
    """A material's Mitsuba BSDF dict."""
    kind = m["type"]
    if kind == "diffuse":
        return {"type": "diffuse", "reflectance": _rgb(m["reflectance"])}
    if kind == "roughplastic":
        return {
            "type": "roughplastic",
            "distribution": m["distribution"],
            "alpha": m["alpha"],
            "int_ior": m["int_ior"],
            "ext_ior": m["ext_ior"],
            "nonlinear": m["nonlinear"],
            "diffuse_reflectance": _rgb(m["diffuse_reflectance"]),
            "specular_reflectance": _rgb(m["specular_reflectance"]),
        }
    path = folder / f"material-{_safe(name)}.toml"
    path.write_text(m["material"])
    bsdf = {"type": "woven", "material": str(path)}
    for key, value in m.get("keys", {}).items():
        if key in ("weft_color", "warp_color"):
            bsdf[key] = _rgb(value)
        elif isinstance(value, list):
            # A pair: Mitsuba's properties hold no lists; the library reads "a, b".
            bsdf[key] = ", ".join(repr(float(x)) for x in value)
        else:
            bsdf[key] = value
    return bsdf


def _safe(name):
    """A material's name as a file name's part."""
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name)[:64]


def _shape(shape, bsdf, mi):
    """A shape with its BSDF: a sphere, or a mesh built from the triangles handed over."""
    if "sphere" in shape:
        center, radius = shape["sphere"]
        return {"type": "sphere", "center": list(center), "radius": float(radius), "bsdf": bsdf}
    import drjit as dr

    positions, uvs, faces = shape["positions"], shape["uvs"], shape["indices"]
    normals = shape["normals"]
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    mesh = mi.Mesh(
        shape["key"],
        vertex_count=len(positions),
        face_count=len(faces),
        props=props,
        has_vertex_normals=normals is not None,
        has_vertex_texcoords=True,
    )
    params = mi.traverse(mesh)
    params["vertex_positions"] = dr.ravel(mi.Point3f(*np.asarray(positions, np.float32).T))
    params["vertex_texcoords"] = dr.ravel(mi.Point2f(*np.asarray(uvs, np.float32).T))
    params["faces"] = dr.ravel(mi.Vector3u(*np.asarray(faces, np.uint32).T))
    if normals is not None:
        params["vertex_normals"] = dr.ravel(mi.Normal3f(*np.asarray(normals, np.float32).T))
    params.update()
    return mesh


def _light(light, k, folder, mi):
    """A light's entries of the scene dict (a rectangle light is a shape with an emitter)."""
    kind = light["type"]
    weight = float(light["sampling_weight"])
    extra = {} if weight == 1.0 else {"sampling_weight": weight}
    if kind == "point":
        return {f"light-{k}": {"type": "point", "position": list(light["position"]),
                               "intensity": _rgb(light["intensity"]), **extra}}
    if kind == "constant":
        return {f"light-{k}": {"type": "constant", "radiance": _rgb(light["radiance"]), **extra}}
    if kind in ("map", "map_file"):
        if kind == "map":
            pixels = np.asarray(light["pixels"], dtype=np.float32)
        else:
            pixels = np.asarray(mi.Bitmap(light["path"]).convert(
                mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False
            ), dtype=np.float32) * float(light["scale"])
        path = folder / f"light-{k}.exr"
        mi.Bitmap(np.ascontiguousarray(pixels[:, ::-1, :])).write(str(path))
        return {f"light-{k}": {"type": "envmap", "filename": str(path),
                               "to_world": mi.ScalarTransform4f(_ENV_TO_WORLD), **extra}}
    if kind == "rectangle":
        return {f"light-{k}": {
            "type": "rectangle",
            "to_world": _rectangle_to_world(light, mi),
            "bsdf": {"type": "diffuse", "reflectance": _rgb([0.0, 0.0, 0.0])},
            "emitter": {"type": "area", "radiance": _rgb(light["radiance"]), **extra},
        }}
    raise ValueError(f"woven.mitsuba: a light of type {kind!r} (light[{k}]) is not translated")


def _rectangle_to_world(r, mi):
    """Mitsuba's rectangle ([-1, 1]² in x, y; normal +z) onto a corner and two edges (normal
    along edge_u × edge_v)."""
    corner, u, v = (np.asarray(r[k], dtype=float) for k in ("corner", "edge_u", "edge_v"))
    n = np.cross(u, v)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = u / 2, v / 2, n / np.linalg.norm(n)
    m[:3, 3] = corner + (u + v) / 2
    return mi.ScalarTransform4f(m.tolist())


def render(scene, mi, folder, spp=None, size=None, seed=None, progress=None):
    """Renders ``scene`` (a path, or ``"showcase"``) in the current Mitsuba variant at its own
    size, spp and seed, or ``size`` (width, height), ``spp`` and ``seed``: the linear image
    (height, width, 3), the inset pasted in with its white border, as ``woven render
    --no-denoise`` renders it (the library places the inset on the film, resized or not).
    ``progress(view, done, total)`` is told each pass's end (view "main" or "inset")."""
    width, height = size or (None, None)
    portable = woven.portable_scene(str(scene), width=width, height=height)
    tell = progress or (lambda view, done, total: None)
    image = _render_view(portable, mi, folder, spp, seed, lambda *a: tell("main", *a))
    inset = portable["inset"]
    if inset is not None:
        _, (w, h) = inset["inner"]
        close = _render_view(
            portable, mi, folder, spp, seed, lambda *a: tell("inset", *a), inset["camera"], (w, h)
        )
        paste(image, inset, close)
    return image


# The most samples one Mitsuba render takes at once: the plugin's library lanes run in Dr.Jit's
# evaluated mode, which holds every lane's state (about 0.7 kB a sample: the 960 × 540 showcase
# at 64 spp in one pass needs over 23 GB). Larger renders go in passes of whole samples per pixel,
# each with its own seed, averaged: an independent sampler's estimate of all of them.
LANE_BUDGET = 1 << 21


def _render_view(portable, mi, folder, spp, seed, tell, camera=None, size=None):
    width, height = size or portable["size"]
    total = int(spp or portable["spp"])
    seed = int(portable["seed"] if seed is None else seed)
    per_pass = max(1, min(total, LANE_BUDGET // (width * height)))
    passes = -(-total // per_pass)
    d = scene_dict(portable, mi, folder, camera=camera, size=size, spp=per_pass, seed=seed)
    scene = mi.load_dict(d)
    image, done = 0.0, 0
    for k in range(passes):
        n = min(per_pass, total - done)
        # One pass keeps the scene's own seed, so that a render within the budget is Mitsuba's
        # render of that seed; later passes take seeds of their own.
        pass_seed = seed if k == 0 else seed * 1_000_003 + k
        pixels = np.array(mi.render(scene, spp=n, seed=pass_seed), dtype=np.float64)[..., :3]
        image = image + pixels * n
        done += n
        tell(done, total)
    return image / total
