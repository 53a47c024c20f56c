"""``python -m woven.blender SCENE.toml -o OUT.exr``: a ``woven render`` scene rendered by
Blender's Cycles (``showcase`` for the built-in one), each woven material as its families'
standard lobes laid out by the library's textures (``woven.blender``). Runs where ``bpy`` imports
(``pip install bpy==5.0.1`` on CPython 3.11). The output is written as ``woven render`` writes
its own (``woven.write_image``): the linear image (EXR), or sRGB through the scene's display
(PNG), to a temporary file renamed into place."""

from __future__ import annotations

import argparse
import importlib
import sys
import tempfile
import time
from pathlib import Path


def _positive(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value}: expected at least 1")
    return value


def _texels(text):
    value = int(text)
    if not 1 <= value <= 64:
        raise argparse.ArgumentTypeError(f"{value}: expected an integer in [1, 64]")
    return value


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="python -m woven.blender", description=__doc__.split("\n\n")[0].replace("``", "")
    )
    ap.add_argument("scene", help="a woven render scene file (TOML), or 'showcase'")
    ap.add_argument("-o", "--output", required=True, type=Path, help="OUT.exr (linear) or OUT.png")
    ap.add_argument("--spp", "--samples", dest="samples", type=_positive,
                    help="samples per pixel (the scene's by default; --spp as woven render and"
                    " python -m woven.mitsuba spell it)")
    ap.add_argument("--width", type=_positive, help="film width (the scene's by default)")
    ap.add_argument("--height", type=_positive, help="film height (the scene's by default)")
    ap.add_argument("--seed", type=int, help="Cycles' seed (the scene's by default)")
    ap.add_argument("--texels-per-cell", type=_texels, default=16,
                    help="texels along each pattern cell's side in the layout's textures (16)")
    args = ap.parse_args(argv)
    if args.output.suffix.lower() not in (".exr", ".png"):
        ap.error(f"-o {args.output}: expected a file ending in .exr or .png")
    if (args.width is None) != (args.height is None):
        ap.error("give --width and --height together (the inset keeps its place in fractions)")
    if args.scene != "showcase" and not Path(args.scene).is_file():
        ap.error(f"{args.scene}: no such scene file (or give 'showcase')")
    try:
        importlib.import_module("bpy")
    except ImportError as e:
        print(f"error: woven.blender needs Blender's Python module (pip install bpy==5.0.1 on "
              f"CPython 3.11): {e}", file=sys.stderr)
        return 1
    import woven

    from ._scene import render

    size = (args.width, args.height) if args.width else None
    t0 = time.time()

    def tell(msg):
        print(f"  {msg} ({time.time() - t0:.0f} s)", file=sys.stderr, flush=True)

    with tempfile.TemporaryDirectory() as folder:
        try:
            image = render(args.scene, folder, samples=args.samples, size=size, seed=args.seed,
                           texels_per_cell=args.texels_per_cell, tell=tell)
        except (ValueError, OSError) as e:
            print(f"error: {e}", file=sys.stderr)
            return 1
    seconds = time.time() - t0
    out = args.output
    out.parent.mkdir(parents=True, exist_ok=True)
    try:
        woven.write_image(image, out, scene=args.scene)
    except (ValueError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    h, w = image.shape[:2]
    print(f"rendered {args.scene} at {w}x{h} in {seconds:.1f} s (Cycles, CPU); wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
