"""A virtual goniometer in Cycles: a material on a plane under a distant light, seen by an
orthographic camera, so that Cycles itself says what BRDF it renders.

The plane (z = 0, 2 m square, uv in metres along x and y; the camera's 2 cm view stays on it to
89°) carries the material; a sun lamp of
irradiance 1 W/m² and zero angle lights it from ``wi``; an orthographic camera looking along
``−wo`` sees only the plane. Direct light only (no bounce, nothing else in the scene), a box
filter, no clamping. Each pixel's radiance is then ``f(wi, wo) cos θi``, so
``f = mean radiance / cos θi``: Cycles' BRDF at the pair, without a re-implementation of its
closures. Directions are woven's: ``z`` the normal, ``x`` along u (the weft), ``wi`` toward the
light, ``wo`` toward the viewer.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np

from . import _material, _scene


def _look(obj, direction, distance=1.0):
    """Places ``obj`` at ``distance`` along ``direction``, its −z looking back at the origin."""
    import mathutils

    z = np.asarray(direction, dtype=float)
    z /= np.linalg.norm(z)
    up = np.array([0.0, 0.0, 1.0]) if abs(z[2]) < 0.99 else np.array([1.0, 0.0, 0.0])
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, y, z, z * distance
    obj.matrix_world = mathutils.Matrix(m.tolist())


class Goniometer:
    """A Cycles scene measuring one material (``make()`` builds it after Blender's scene is
    emptied, so it must build anew each time)."""

    def __init__(self, bpy, make, size=16, samples=64):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        self.bpy = bpy
        scene = bpy.context.scene
        mesh = bpy.data.meshes.new("plane")
        s = 1.0
        mesh.from_pydata([(-s, -s, 0), (s, -s, 0), (s, s, 0), (-s, s, 0)], [], [(0, 1, 2, 3)])
        uv = mesh.uv_layers.new(name=_material.UV_MAP)
        for k, loop in enumerate(mesh.loops):
            co = mesh.vertices[loop.vertex_index].co
            uv.data[k].uv = (co.x, co.y)
        plane = bpy.data.objects.new("plane", mesh)
        scene.collection.objects.link(plane)
        mesh.materials.append(make())
        _scene._settings(scene, {"max_depth": 2, "seed": 0, "hide_emitters": True})
        world = bpy.data.worlds.new("black")
        scene.world = world
        world.use_nodes = True
        world.node_tree.nodes.clear()
        _scene._black_world(world)
        sun = bpy.data.lights.new("sun", "SUN")
        sun.energy, sun.angle = 1.0, 0.0
        self.sun = bpy.data.objects.new("sun", sun)
        scene.collection.objects.link(self.sun)
        cam = bpy.data.cameras.new("camera")
        cam.type, cam.ortho_scale = "ORTHO", 0.02
        self.camera = bpy.data.objects.new("camera", cam)
        scene.collection.objects.link(self.camera)
        scene.camera = self.camera
        scene.render.resolution_x = scene.render.resolution_y = size
        scene.cycles.samples = samples
        self.scene = scene
        self.folder = Path(tempfile.mkdtemp(prefix="woven-gonio-"))

    def measure(self, wi, wo):
        """Cycles' BRDF per channel at ``(wi, wo)`` (unit vectors, both above the plane)."""
        wi, wo = np.asarray(wi, dtype=float), np.asarray(wo, dtype=float)
        _look(self.sun, wi)
        _look(self.camera, wo)
        path = self.folder / "g.exr"
        self.scene.render.filepath = str(path)
        self.bpy.ops.render.render(write_still=True)
        img = self.bpy.data.images.load(str(path))
        px = np.empty(len(img.pixels), dtype=np.float32)
        img.pixels.foreach_get(px)
        self.bpy.data.images.remove(img)
        return px.reshape(-1, 4)[:, :3].mean(axis=0).astype(np.float64) / wi[2]


def spherical(theta_deg, phi_deg):
    """The unit vector at polar angle θ and azimuth φ (degrees, φ from +x toward +y)."""
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])
