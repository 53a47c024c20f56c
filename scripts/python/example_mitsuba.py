#!/usr/bin/env python3
"""docs/python.md's Mitsuba example: a cloth-covered sphere on a cloth floor under a sky.

    python scripts/python/example_mitsuba.py -o docs/img/python-mitsuba.png

The sphere wears the belt cloth woven as its own 2/1 twill (dyed: a dark red weft, a cream
warp), 160 × 80 yarns per unit of uv (square cells on the sphere); the floor is the silk preset, dyed blue, as its macro BRDF (the
γ-mix, `weft_fraction`). The light is an environment map written here (a sky gradient and a small bright sun,
latitude-longitude EXR) plus nothing else. Mitsuba's default path integrator, llvm_ad_rgb.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np


def sky(path: Path, width=512, height=256):
    """A latitude-longitude sky: blue above, a warm horizon, a sun at 35° elevation."""
    import mitsuba as mi

    v = (np.arange(height) + 0.5) / height  # 0 at the top (Mitsuba's envmap: +y up)
    u = (np.arange(width) + 0.5) / width
    theta = v * np.pi
    phi = u * 2 * np.pi
    up = np.broadcast_to(np.cos(theta)[:, None, None], (height, width, 1))
    zenith = np.array([0.35, 0.55, 1.0])
    horizon = np.array([0.6, 0.5, 0.4])
    ground = np.array([0.25, 0.22, 0.2])
    above = zenith * (0.4 + 0.6 * up) + horizon * (1 - up) ** 4
    base = np.where(up > 0, above, ground)
    # The sun: direction (elevation 35°, azimuth 120°), a 3° disc.
    el, az = np.radians(35.0), np.radians(120.0)
    sun = np.array([np.cos(el) * np.cos(az), np.sin(el), np.cos(el) * np.sin(az)])
    d = np.stack(
        [np.sin(theta)[:, None] * np.cos(phi)[None, :], np.broadcast_to(np.cos(theta)[:, None], (height, width)),
         np.sin(theta)[:, None] * np.sin(phi)[None, :]],
        axis=-1,
    )
    base[(d @ sun) > np.cos(np.radians(3.0))] = [400.0, 380.0, 330.0]
    mi.Bitmap(base.astype(np.float32)).write(str(path))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", default="python-mitsuba.png")
    ap.add_argument("--spp", type=int, default=128)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=400)
    args = ap.parse_args()

    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    import woven.mitsuba

    woven.mitsuba.register()
    T = mi.ScalarTransform4f
    with tempfile.TemporaryDirectory() as tmp:
        env = Path(tmp) / "sky.exr"
        sky(env)
        scene = mi.load_dict(
            {
                "type": "scene",
                "integrator": {"type": "path", "max_depth": 6},
                "sensor": {
                    "type": "perspective",
                    "fov": 35,
                    "to_world": T().look_at(origin=[0, 1.2, 4.2], target=[0, 0.55, 0], up=[0, 1, 0]),
                    "film": {"type": "hdrfilm", "width": args.width, "height": args.height},
                },
                "sky": {"type": "envmap", "filename": str(env)},
                "ball": {
                    "type": "sphere",
                    # The sphere's poles on the vertical: latitude rows of yarn.
                    "to_world": T().translate([0, 0.7, 0]).rotate([1, 0, 0], -90).scale(0.7),
                    "bsdf": {
                        "type": "woven",
                        "material": "belt-cloth",
                        "yarns_per_unit": "160, 80",
                        "weft_color": {"type": "rgb", "value": [0.45, 0.04, 0.05]},
                        "warp_color": {"type": "rgb", "value": [0.8, 0.72, 0.55]},
                    },
                },
                "floor": {
                    "type": "rectangle",
                    "to_world": T().rotate([1, 0, 0], -90).scale(200),
                    "bsdf": {
                        "type": "woven",
                        "material": "silk",
                        "weft_fraction": 0.5,
                        "weft_color": {"type": "rgb", "value": [0.1, 0.2, 0.5]},
                        "warp_color": {"type": "rgb", "value": [0.1, 0.2, 0.5]},
                    },
                },
            }
        )
        t0 = time.time()
        img = mi.render(scene, spp=args.spp)
        pixels = np.array(img)  # evaluates the kernel
        print(f"rendered {args.width}x{args.height} at {args.spp} spp in {time.time() - t0:.1f} s")
        mi.util.write_bitmap(args.output, pixels)
        print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
