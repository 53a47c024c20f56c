#!/usr/bin/env python3
"""docs/python.md's Mitsuba example: the showcase's draped fabrics, rendered by Mitsuba 3.

    python scripts/python/example_mitsuba.py -o docs/img/python-mitsuba.png

The scene is read from `woven render`'s built-in showcase (crates/woven-render/scenes/
showcase.toml), its one home: its camera, its shapes (the same draped meshes, their uv in metres
along weft and warp), and its materials (the same presets, dyes and thread counts, read by the
`woven` BSDF plugin). A preset with shaped floats (the satin charmeuse, the shot silk) is laid
with linear floats at its own tilt: the JIT variants do not trace shaped floats yet.

The threads are far below a pixel, so each cloth shows its macro BRDF (`detail = "cloth"`: the
plugin's JIT variants shade a pixel with the yarn its sample lands on, and Mitsuba's stock
`path` integrator gives no footprint to filter it by). The light is a directional sun where the
showcase's sky puts it, with a sky gradient (an environment map written here): the showcase's
sun and sky, approximately. Mitsuba's `path` integrator in `llvm_ad_rgb`; the PNG is Mitsuba's
sRGB (clipped), `--exr` writes the linear image too.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
MESHES = REPO / "crates" / "woven-render" / "scenes" / "meshes"
SHOWCASE = REPO / "crates" / "woven-render" / "scenes" / "showcase.toml"

# The sun's irradiance, chosen by eye to expose like the showcase (Mitsuba has no Preetham sky).
SUN_IRRADIANCE = [2.6, 2.4, 2.1]


def sky(path: Path, width=256, height=128):
    """A latitude-longitude sky without its sun, in Mitsuba's envmap frame (+y up): blue above,
    a pale horizon, black below it (the floor is geometry)."""
    import mitsuba as mi

    theta = (np.arange(height) + 0.5) / height * np.pi
    up = np.cos(theta)[:, None, None] * np.ones((1, width, 1))
    above_horizon = np.clip(up, 0.0, 1.0)
    zenith = np.array([0.16, 0.26, 0.55])
    horizon = np.array([0.55, 0.55, 0.55])
    above = zenith * above_horizon ** 0.5 + horizon * (1.0 - above_horizon) ** 3
    image = np.where(up > 0.0, above, 0.0)
    mi.Bitmap(image.astype(np.float32)).write(str(path))


def woven_bsdf(material: dict, tmp: Path) -> dict:
    """The plugin's `woven` BSDF for a showcase material table, as its macro BRDF. A preset whose
    floats are shaped (crest and flanks, which the JIT variants do not trace yet) is written to a
    material file with linear floats at its own `u_max_deg`."""
    import woven

    name = material["material"]
    preset = woven.Material.preset(name)
    yarn = preset.to_dict().get("yarn", {})
    if yarn.get("float_crest") or yarn.get("float_flank"):
        path = tmp / f"{name}.toml"
        path.write_text(preset.replace({"yarn.float_crest": None, "yarn.float_flank": None}).to_toml())
        name = str(path)
    bsdf = {
        "type": "woven",
        "material": name,
        "yarns_per_unit": ", ".join(str(n) for n in material["yarns_per_unit"]),
        "detail": "cloth",
    }
    for key in ("weft_color", "warp_color"):
        if key in material:
            bsdf[key] = {"type": "rgb", "value": material[key]}
    for key in ("pattern", "u_max_deg", "gap"):
        if key in material:
            bsdf[key] = material[key]
    return bsdf


def rectangle_to_world(shape: dict):
    """Mitsuba's rectangle ([-1, 1]² in x, y, normal +z) onto a showcase rectangle (a corner and
    two edges, normal along edge_u × edge_v)."""
    import mitsuba as mi

    corner, u, v = (np.array(shape[k], dtype=float) for k in ("corner", "edge_u", "edge_v"))
    n = np.cross(u, v)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = u / 2, v / 2, n / np.linalg.norm(n)
    m[:3, 3] = corner + (u + v) / 2
    return mi.ScalarTransform4f(m.tolist())


def scene_dict(env: Path, tmp: Path, width: int, height: int) -> dict:
    """The showcase (SHOWCASE) as a Mitsuba scene dict, at `width` × `height`, lit by `env` (the
    sky without its sun) and a directional sun where the showcase's sky puts it."""
    import mitsuba as mi

    showcase = tomllib.loads(SHOWCASE.read_text())
    camera, sky_light = showcase["camera"], showcase["light"][0]
    materials = showcase["material"]
    T = mi.ScalarTransform4f
    el, az = (math.radians(sky_light[k]) for k in ("sun_elevation_deg", "sun_azimuth_deg"))
    toward_sun = [math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)]
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 4},
        "sensor": {
            "type": "perspective",
            "fov": camera["fov_deg"],
            "fov_axis": "x",
            "to_world": T().look_at(origin=camera["origin"], target=camera["target"], up=camera["up"]),
            "film": {"type": "hdrfilm", "width": width, "height": height},
        },
        # The envmap's +y is turned onto the world's +z.
        "sky": {"type": "envmap", "filename": str(env), "to_world": T().rotate([1, 0, 0], 90)},
        "sun": {
            "type": "directional",
            "direction": [-c for c in toward_sun],
            "irradiance": {"type": "rgb", "value": SUN_IRRADIANCE},
        },
    }
    for k, shape in enumerate(showcase["shape"]):
        material = materials[shape["material"]]
        if material["type"] == "diffuse":
            bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": material["reflectance"]}}
        else:
            bsdf = woven_bsdf(material, tmp)
        if shape["type"] == "rectangle":
            entry = {"type": "rectangle", "to_world": rectangle_to_world(shape)}
        else:
            mesh = shape["file"].removeprefix("builtin:")
            entry = {"type": "obj", "filename": str(MESHES / f"{mesh}.obj")}
        scene[f"shape-{k}"] = {**entry, "bsdf": bsdf}
    return scene


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", default="python-mitsuba.png")
    ap.add_argument("--spp", type=int, default=128)
    ap.add_argument("--width", type=int, default=960)
    ap.add_argument("--height", type=int, default=540)
    ap.add_argument("--exr", type=Path, help="also write the linear image here")
    args = ap.parse_args()

    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    import woven.mitsuba

    # Every cloth here is traced by Dr.Jit (detail "cloth", linear tilts): symbolic mode.
    woven.mitsuba.register(symbolic=True)
    with tempfile.TemporaryDirectory() as tmp:
        env = Path(tmp) / "sky.exr"
        sky(env)
        scene = mi.load_dict(scene_dict(env, Path(tmp), args.width, args.height))
        t0 = time.time()
        img = mi.render(scene, spp=args.spp)
        pixels = np.array(img)  # evaluates the kernel
        print(f"rendered {args.width}x{args.height} at {args.spp} spp in {time.time() - t0:.1f} s")
    out = Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    mi.util.write_bitmap(str(out), pixels)
    print(f"wrote {out}")
    if args.exr:
        mi.util.write_bitmap(str(args.exr), pixels)
        print(f"wrote {args.exr}")


if __name__ == "__main__":
    main()
