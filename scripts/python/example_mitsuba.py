#!/usr/bin/env python3
"""docs/python.md's Mitsuba example: the showcase's draped fabrics, rendered by Mitsuba 3.

    python scripts/python/example_mitsuba.py -o docs/img/python-mitsuba.png

The scene is `woven render`'s built-in showcase (crates/woven-render/scenes/showcase.toml),
rebuilt for Mitsuba: the same draped meshes (their uv in metres along weft and warp), the same
presets, dyes and thread counts, read by the `woven` BSDF plugin (the satin's and the shot
silk's floats tilt linearly: the JIT variants do not trace shaped floats yet):

- a satin charmeuse (0.125 mm threads, wine red) thrown over a stool;
- a linen tablecloth (0.5 mm threads, oatmeal) on a round table;
- two cushions: shot silk (0.2 mm threads, its own green weft on an orange-red warp) and a
  denim 3/1 twill (an indigo warp over a white weft, tilted floats and gaps).

The threads are far below a pixel, so each cloth shows its macro BRDF (`detail = "cloth"`: the
plugin's JIT variants shade a pixel with the yarn its sample lands on, and Mitsuba's stock
`path` integrator gives no footprint to filter it by). The light is a directional sun 25° up on
the camera's right with a sky gradient (an environment map written here): the showcase's sun
and sky, approximately. Mitsuba's `path` integrator in `llvm_ad_rgb`; the PNG is Mitsuba's sRGB
(clipped), `--exr` writes the linear image too.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
MESHES = REPO / "crates" / "woven-render" / "scenes" / "meshes"

# The sun: 25° above the horizon, at azimuth −60° from +x (z up): low, on the camera's right.
SUN_ELEVATION_DEG = 25.0
SUN_AZIMUTH_DEG = -60.0


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


def woven(material: str, yarns: str, **keys) -> dict:
    """A `woven` BSDF of `material` at `yarns` per metre, as its macro BRDF."""
    bsdf = {"type": "woven", "material": material, "yarns_per_unit": yarns, "detail": "cloth"}
    for key, value in keys.items():
        bsdf[key] = {"type": "rgb", "value": value} if key.endswith("_color") else value
    return bsdf


def linear_floats(preset: str, tmp: Path) -> str:
    """A material file of `preset` whose floats tilt linearly (its `u_max_deg`, without the
    crest and flanks of its shaped floats, which the JIT variants do not trace yet)."""
    import woven

    material = woven.Material.preset(preset)
    material = material.replace({"yarn.float_crest": None, "yarn.float_flank": None})
    path = tmp / f"{preset}.toml"
    path.write_text(material.to_toml())
    return str(path)


def scene_dict(env: Path, tmp: Path, width: int, height: int) -> dict:
    import mitsuba as mi

    T = mi.ScalarTransform4f
    diffuse = lambda rgb: {"type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}}
    mesh = lambda name, bsdf: {"type": "obj", "filename": str(MESHES / f"{name}.obj"), "bsdf": bsdf}
    rectangle = lambda to_world, bsdf: {"type": "rectangle", "to_world": to_world, "bsdf": bsdf}
    el, az = math.radians(SUN_ELEVATION_DEG), math.radians(SUN_AZIMUTH_DEG)
    toward_sun = [math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)]
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 4},
        "sensor": {
            "type": "perspective",
            "fov": 45,
            "fov_axis": "x",
            "to_world": T().look_at(origin=[0, -4.0, 1.2], target=[0.05, -0.55, 0.36], up=[0, 0, 1]),
            "film": {"type": "hdrfilm", "width": width, "height": height},
        },
        # The envmap's +y is turned onto the world's +z.
        "sky": {"type": "envmap", "filename": str(env), "to_world": T().rotate([1, 0, 0], 90)},
        "sun": {
            "type": "directional",
            "direction": [-c for c in toward_sun],
            "irradiance": {"type": "rgb", "value": [2.6, 2.4, 2.1]},
        },
        # The floor, the back wall and its skirting board (rectangles span [-1, 1]² in x, y).
        "floor": rectangle(T().scale([40, 40, 1]), diffuse([0.3, 0.22, 0.15])),
        "wall": rectangle(
            T().translate([0, 1.6, 1.5]).rotate([1, 0, 0], 90).scale([6, 1.5, 1]),
            diffuse([0.62, 0.6, 0.56]),
        ),
        "skirting": rectangle(
            T().translate([0, 1.585, 0.045]).rotate([1, 0, 0], 90).scale([6, 0.045, 1]),
            diffuse([0.75, 0.74, 0.7]),
        ),
        "table": mesh("table", diffuse([0.25, 0.15, 0.08])),
        "stool": mesh("stool", diffuse([0.25, 0.15, 0.08])),
        "tablecloth": mesh(
            "tablecloth",
            woven("linen-plain", "2000", weft_color=[0.62, 0.58, 0.5], warp_color=[0.6, 0.56, 0.48]),
        ),
        "satin": mesh(
            "satin-drape",
            woven(
                linear_floats("satin-charmeuse", tmp),
                "8000",
                weft_color=[0.3, 0.02, 0.05],
                warp_color=[0.3, 0.02, 0.05],
            ),
        ),
        "shot-silk": mesh("cushion-shot-silk", woven(linear_floats("silk-shot", tmp), "5000")),
        "twill": mesh(
            "cushion-twill",
            woven(
                "belt-cloth",
                "2500, 2000",
                pattern="twill-3/1",
                weft_color=[0.5, 0.48, 0.44],
                warp_color=[0.025, 0.045, 0.11],
                u_max_deg=25.0,
                gap=0.08,
            ),
        ),
    }


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

    woven.mitsuba.register()
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
