"""A ``woven render`` scene as a Blender scene rendered by Cycles.

The scene is read and checked by the renderer's library (``woven.portable_scene``, as for
``woven.mitsuba``): meshes with ``woven render``'s uv, each woven material's file and surface
keys, the Preetham sun and sky as the map ``woven render`` bakes. Here that data becomes
Blender's: meshes (uv in the cloth's units, vertex normals as custom normals), the camera
(``fov_deg`` across the width), Cycles' path tracer with as many bounces as ``max_depth``
allows, a box pixel filter, no clamping, no glossy filter, no adaptive sampling, no denoiser;
the sky as the world's equirectangular map; point lights of zero radius; rectangles as area
lights. Woven materials become node trees over their standard lobes (``_material``).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

import woven
from woven._inset import paste

from . import _material


def build(bpy, portable, folder, texels_per_cell=16, tell=None):
    """Empties Blender's scene and builds ``portable`` (``woven.portable_scene``'s dict) in it;
    files (materials, textures, maps) go into ``folder``. Returns the scene."""
    tell = tell or (lambda msg: None)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    folder = Path(folder)
    mats = {}
    for name, m in portable["materials"].items():
        mats[name] = _material_of(bpy, name, m, folder, texels_per_cell, tell)
    for k, shape in enumerate(portable["shapes"]):
        obj = _shape(bpy, shape, k)
        obj.data.materials.append(mats[shape["material"]])
        scene.collection.objects.link(obj)
    world = bpy.data.worlds.new("woven")
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes.clear()
    background = False
    for k, light in enumerate(portable["lights"]):
        background |= _light(bpy, scene, world, light, k, folder)
    if not background:
        _black_world(world)
    _settings(scene, portable)
    return scene


def _material_of(bpy, name, m, folder, texels_per_cell, tell):
    kind = m["type"]
    if kind == "diffuse":
        return _material.diffuse(bpy, name, m["reflectance"])
    if kind == "woven":
        path = folder / f"material-{_safe(name)}.toml"
        path.write_text(m["material"])
        keys = {k: v for k, v in m["keys"].items() if k != "footprint_filter"}
        tell(f"projecting `{name}` onto Cycles' lobes and baking its layout")
        surface = woven.Surface(str(path), progress=False, **keys)
        identity = m["material"] + "\n" + repr(sorted(keys.items()))
        std = _material.standard(surface, identity, folder, _safe(name), texels_per_cell)
        return _material.material(bpy, name, std)
    raise ValueError(
        f"woven.blender: material `{name}` is of type {kind!r}, which has no Cycles translation "
        "(diffuse and woven materials have)"
    )


def _safe(name):
    """A material's name as a file name's part."""
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name)[:64]


def _shape(bpy, shape, k):
    """A shape as a mesh object: triangles as handed over, or a fine uv sphere."""
    if "sphere" in shape:
        center, radius = shape["sphere"]
        mesh = bpy.data.meshes.new(f"shape-{k}")
        _sphere(mesh, center, radius)
        return bpy.data.objects.new(f"shape-{k}", mesh)
    positions = np.asarray(shape["positions"], dtype=np.float32)
    faces = np.asarray(shape["indices"], dtype=np.int32)
    uvs = np.asarray(shape["uvs"], dtype=np.float32)
    mesh = bpy.data.meshes.new(f"shape-{k}")
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.loops.add(faces.size)
    mesh.loops.foreach_set("vertex_index", faces.ravel())
    mesh.polygons.add(len(faces))
    mesh.polygons.foreach_set("loop_start", np.arange(0, faces.size, 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(faces), 3, dtype=np.int32))
    layer = mesh.uv_layers.new(name=_material.UV_MAP)
    layer.data.foreach_set("uv", uvs[faces.ravel()].ravel())
    mesh.update()
    mesh.validate()
    if shape["normals"] is not None:
        mesh.polygons.foreach_set("use_smooth", np.ones(len(faces), dtype=bool))
        mesh.normals_split_custom_set_from_vertices(
            np.asarray(shape["normals"], dtype=np.float32).tolist())
    return bpy.data.objects.new(f"shape-{k}", mesh)


def _sphere(mesh, center, radius, rings=128, segments=256):
    """A smooth uv sphere (its uv is not woven render's: a sphere's material reads none)."""
    verts, faces = [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            verts.append((center[0] + radius * math.sin(theta) * math.cos(phi),
                          center[1] + radius * math.sin(theta) * math.sin(phi),
                          center[2] + radius * math.cos(theta)))
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            faces.append((a, b, b + segments, a + segments))
    mesh.from_pydata(verts, [], faces)
    for p in mesh.polygons:
        p.use_smooth = True
    mesh.uv_layers.new(name=_material.UV_MAP)


def _light(bpy, scene, world, light, k, folder):
    """One light; True when it is the world's background."""
    kind = light["type"]
    if light["sampling_weight"] != 1.0:
        print(f"woven.blender: light[{k}]'s sampling_weight is Cycles' own to choose; ignored",
              file=sys.stderr)
    if kind == "point":
        lamp = bpy.data.lights.new(f"light-{k}", "POINT")
        # Cycles' point light of power P radiates P / (4π) W/sr in every direction.
        intensity = np.asarray(light["intensity"], dtype=float)
        power = float(intensity.max())
        lamp.energy = 4 * math.pi * power
        lamp.color = tuple(intensity / power) if power > 0 else (0.0, 0.0, 0.0)
        lamp.shadow_soft_size = 0.0
        obj = bpy.data.objects.new(f"light-{k}", lamp)
        obj.location = light["position"]
        scene.collection.objects.link(obj)
        return False
    if kind == "rectangle":
        _rectangle(bpy, scene, light, k)
        return False
    if kind == "constant":
        _background(world, color=light["radiance"])
        return True
    if kind in ("map", "map_file"):
        pixels = _map_pixels(bpy, light)
        _background(world, image=_world_image(bpy, pixels, folder / f"light-{k}.exr"))
        return True
    raise ValueError(f"woven.blender: a light of type {kind!r} (light[{k}]) is not translated")


def _rectangle(bpy, scene, r, k):
    """An area light on the rectangle, emitting on the side of edge_u × edge_v (Blender's area
    light emits along its local −z: x along edge_u, y against edge_v)."""
    corner, u, v = (np.asarray(r[key], dtype=float) for key in ("corner", "edge_u", "edge_v"))
    lu, lv = np.linalg.norm(u), np.linalg.norm(v)
    x, y = u / lu, -v / lv
    z = np.cross(x, y)
    lamp = bpy.data.lights.new(f"light-{k}", "AREA")
    lamp.shape = "RECTANGLE"
    lamp.size, lamp.size_y = float(lu), float(lv)
    radiance = np.asarray(r["radiance"], dtype=float)
    peak = float(radiance.max())
    # A Lambertian emitter of radiance L over area A radiates π L A watts.
    lamp.energy = math.pi * peak * lu * lv
    lamp.color = tuple(radiance / peak) if peak > 0 else (0.0, 0.0, 0.0)
    obj = bpy.data.objects.new(f"light-{k}", lamp)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, y, z, corner + (u + v) / 2
    obj.matrix_world = _matrix(m)
    scene.collection.objects.link(obj)


def _matrix(m):
    import mathutils

    return mathutils.Matrix([list(row) for row in m])


def _map_pixels(bpy, light):
    """An environment map's pixels (rows from the zenith, woven's layout), scale applied."""
    if light["type"] == "map":
        return np.asarray(light["pixels"], dtype=np.float32)
    img = bpy.data.images.load(str(light["path"]))
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    # Blender's rows run from the bottom.
    return px.reshape(h, w, 4)[::-1, :, :3] * float(light["scale"])


def _world_image(bpy, pixels, path):
    """woven's map (row 0 at +z, column x at φ = 2π (x + ½) / W from +x toward +y) as
    Blender's equirectangular image, written to ``path`` (EXR) and loaded: Blender's column j
    looks toward φ = π − 2π (j + ½) / W, so it is woven's column W/2 − 1 − j (mod W); its top
    row is the zenith, as woven's."""
    h, w, _ = pixels.shape
    cols = (w // 2 - 1 - np.arange(w)) % w
    woven.write_image(np.ascontiguousarray(pixels[:, cols, :], dtype=np.float64), path)
    img = bpy.data.images.load(str(path))
    img.colorspace_settings.name = "Linear Rec.709"
    return img


def _background(world, color=None, image=None):
    nodes, links = world.node_tree.nodes, world.node_tree.links
    bg = nodes.new("ShaderNodeBackground")
    bg.inputs["Strength"].default_value = 1.0
    if image is not None:
        env = nodes.new("ShaderNodeTexEnvironment")
        env.image = image
        env.interpolation = "Linear"
        links.new(env.outputs["Color"], bg.inputs["Color"])
    else:
        bg.inputs["Color"].default_value = (*[float(c) for c in color], 1.0)
    out = nodes.new("ShaderNodeOutputWorld")
    links.new(bg.outputs["Background"], out.inputs["Surface"])


def _black_world(world):
    _background(world, color=(0.0, 0.0, 0.0))


def _settings(scene, portable):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    # Mitsuba's max_depth counts the camera ray's segment and the direct light's: Cycles'
    # bounces are what follows the first hit's direct light.
    depth = portable["max_depth"]
    bounces = 1024 if depth is None else max(int(depth) - 2, 0)
    for key in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                "transparent_max_bounces"):
        setattr(c, key, bounces)
    c.min_light_bounces = 0
    c.seed = int(portable["seed"])
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    if portable["hide_emitters"] and scene.world is not None:
        scene.world.cycles_visibility.camera = False


def camera(bpy, scene, cam, size):
    """Points the scene's camera as ``cam`` (woven's: origin, target, up, fov_deg across the
    width) at ``size`` (width, height)."""
    origin, target, up = (np.asarray(cam[k], dtype=float) for k in ("origin", "target", "up"))
    f = target - origin
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "HORIZONTAL"
    data.angle = math.radians(float(cam["fov_deg"]))
    data.clip_start, data.clip_end = 1e-3, 1e5
    obj = scene.camera
    if obj is None:
        obj = bpy.data.objects.new("camera", data)
        scene.collection.objects.link(obj)
        scene.camera = obj
    else:
        obj.data = data
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = r, u, -f, origin
    obj.matrix_world = _matrix(m)
    scene.render.resolution_x, scene.render.resolution_y = int(size[0]), int(size[1])
    scene.render.resolution_percentage = 100


def render_view(bpy, scene, cam, size, samples, path):
    """Renders ``scene`` through ``cam`` at ``size`` with ``samples`` a pixel into ``path``
    (EXR) and returns the linear image (height, width, 3), top row first."""
    camera(bpy, scene, cam, size)
    scene.cycles.samples = int(samples)
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(path))
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)


def render(scene_path, folder, samples=None, size=None, seed=None, texels_per_cell=16,
           tell=None):
    """Renders ``scene_path`` (a path, or ``"showcase"``) in Cycles at its own size and spp or
    ``size`` (width, height) and ``samples``: the linear image (height, width, 3), the inset
    pasted in with its white border as ``woven render`` draws it."""
    import bpy

    tell = tell or (lambda msg: None)
    width, height = size or (None, None)
    portable = woven.portable_scene(str(scene_path), width=width, height=height)
    scene = build(bpy, portable, folder, texels_per_cell, tell)
    if seed is not None:
        scene.cycles.seed = int(seed)
    spp = int(samples or portable["spp"])
    tell(f"rendering the main view, {portable['size'][0]}x{portable['size'][1]}, {spp} spp")
    image = render_view(bpy, scene, portable["camera"], portable["size"], spp,
                        Path(folder) / "main.exr")
    inset = portable["inset"]
    if inset is not None:
        _, (w, h) = inset["inner"]
        tell(f"rendering the inset, {w}x{h}, {spp} spp")
        close = render_view(bpy, scene, inset["camera"], (w, h), spp, Path(folder) / "inset.exr")
        paste(image, inset, close)
    return image
