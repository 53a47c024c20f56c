#!/usr/bin/env python3
"""The showcase, as it is, in Cycles and in ``woven render``: ``python -m woven.blender
showcase`` against ``woven render --no-denoise`` at the same size and samples, cloth by cloth.

    target/blender-venv/bin/python scripts/blender/showcase.py --width 320 --height 180 \
        --spp 64 --out DIR

For each cloth (the main view's pixels whose every sample's first hit is that cloth: a Cycles
render in which each shape emits its own flat colour and nothing is lit; the inset left out) the
two means of the luminance and their relative difference. Writes both images (EXR), a
side-by-side PNG and ``showcase.json``; exits 1 when a cloth's means differ by more than
``--tolerance`` (5 %).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

CLOTHS = ("satin", "linen", "shot-silk", "twill")
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def read_exr(bpy, path):
    """A linear EXR as (height, width, 3), top row first."""
    img = bpy.data.images.load(str(path))
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)


def masks(bpy, size, folder):
    """For each cloth, the main view's pixels whose every sample's first hit is that cloth."""
    import woven
    from woven.blender import _material, _scene

    portable = woven.portable_scene("showcase", width=size[0], height=size[1])
    flat = {"type": "diffuse", "reflectance": [0.0, 0.0, 0.0]}
    plain = dict(portable, materials={k: flat for k in portable["materials"]}, lights=[])
    scene = _scene.build(bpy, plain, folder)
    colours = {}
    for k, shape in enumerate(portable["shapes"]):
        obj = bpy.data.objects[f"shape-{k}"]
        colour = ((k + 1) / 16.0, 0.0, 0.0)
        colours[k] = colour[0]
        obj.data.materials[0] = _material.emitter(bpy, f"mask-{k}", colour)
    scene.cycles.max_bounces = 0
    image = _scene.render_view(bpy, scene, portable["camera"], size, 16, Path(folder) / "m.exr")
    out = {}
    for cloth in CLOTHS:
        m = np.zeros(image.shape[:2], dtype=bool)
        for k, shape in enumerate(portable["shapes"]):
            if shape["material"] == cloth:
                m |= np.abs(image[..., 0] - colours[k]) < 1e-6
        out[cloth] = m
    inset = portable["inset"]
    if inset is not None:
        (x, y), (w, h) = inset["outer"]
        for m in out.values():
            m[y:y + h, x:x + w] = False
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--tolerance", type=float, default=0.05)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--woven", default=os.environ.get("WOVEN_BIN", "target/release/woven"))
    args = ap.parse_args(argv)
    import bpy

    from woven.blender._scene import render

    args.out.mkdir(parents=True, exist_ok=True)
    size = (args.width, args.height)
    t0 = time.time()
    subprocess.run([args.woven, "render", "--no-denoise", "--width", str(size[0]), "--height",
                    str(size[1]), "--spp", str(args.spp), "-o", str(args.out / "woven.exr")],
                   check=True, capture_output=True)
    woven_s = time.time() - t0
    with tempfile.TemporaryDirectory() as folder:
        t0 = time.time()
        cycles = render("showcase", folder, samples=args.spp, size=size,
                        tell=lambda m: print(f"  {m}", file=sys.stderr, flush=True))
        cycles_s = time.time() - t0
        import woven

        woven.write_image(cycles, args.out / "cycles.exr")
        woven.write_image(cycles, args.out / "cycles.png", scene="showcase")
        w = read_exr(bpy, args.out / "woven.exr")
        cloth_masks = masks(bpy, size, folder)
    rows, ok = {}, True
    for cloth, mask in cloth_masks.items():
        a = float((w[mask] @ LUMINANCE).mean())
        b = float((cycles[mask] @ LUMINANCE).mean())
        rel = b / a - 1.0
        ok &= abs(rel) <= args.tolerance
        rows[cloth] = {"pixels": int(mask.sum()), "woven": a, "cycles": b, "rel": rel,
                       "woven_rgb": w[mask].mean(axis=0).tolist(),
                       "cycles_rgb": cycles[mask].mean(axis=0).tolist()}
        print(f"{cloth:10s} {int(mask.sum()):6d} px  woven {a:.4f}  Cycles {b:.4f}  "
              f"{100 * rel:+.1f} %")
    summary = {"size": size, "spp": args.spp, "woven_seconds": woven_s,
               "cycles_seconds": cycles_s, "cloths": rows, "ok": bool(ok)}
    (args.out / "showcase.json").write_text(json.dumps(summary, indent=1))
    print(f"woven render {woven_s:.1f} s, Cycles (with the projections) {cycles_s:.1f} s")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
