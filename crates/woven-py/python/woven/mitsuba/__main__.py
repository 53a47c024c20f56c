"""``python -m woven.mitsuba SCENE.toml -o OUT.exr``: a ``woven render`` scene rendered by
Mitsuba 3 with the woven plugin (``showcase`` for the built-in one). The scene is translated by
``woven.mitsuba._scene`` (the library reads and checks it); the output is written as ``woven
render`` writes its own (``woven.write_image``): the linear image (EXR), or sRGB through the
scene's display (PNG), to a temporary file renamed into place."""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path


def _positive(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value}: expected at least 1")
    return value


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="python -m woven.mitsuba", description=__doc__.split("\n\n")[0].replace("``", "")
    )
    ap.add_argument("scene", help="a woven render scene file (TOML), or 'showcase'")
    ap.add_argument("-o", "--output", required=True, type=Path, help="OUT.exr (linear) or OUT.png")
    ap.add_argument("--spp", type=_positive, help="samples per pixel (the scene's by default)")
    ap.add_argument("--width", type=_positive, help="film width (the scene's by default)")
    ap.add_argument("--height", type=_positive, help="film height (the scene's by default)")
    ap.add_argument("--seed", type=int, help="the sampler's seed (the scene's by default)")
    ap.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variant (llvm_ad_rgb)")
    args = ap.parse_args(argv)
    if args.output.suffix.lower() not in (".exr", ".png"):
        ap.error(f"-o {args.output}: expected a file ending in .exr or .png")
    if (args.width is None) != (args.height is None):
        ap.error("give --width and --height together (the inset keeps its place in fractions)")
    if args.scene != "showcase" and not Path(args.scene).is_file():
        ap.error(f"{args.scene}: no such scene file (or give 'showcase')")

    import mitsuba as mi

    if args.variant not in mi.variants():
        ap.error(f"--variant {args.variant}: not in this Mitsuba build ({', '.join(mi.variants())})")
    mi.set_variant(args.variant)
    import woven.mitsuba
    from ._scene import render

    woven.mitsuba.register()
    size = (args.width, args.height) if args.width else None
    t0 = time.time()

    def progress(view, done, total):
        print(f"\r  {view}: {done}/{total} spp", end="\n" if done == total else "",
              file=sys.stderr, flush=True)

    with tempfile.TemporaryDirectory() as folder:
        try:
            image = render(args.scene, mi, folder, spp=args.spp, size=size, seed=args.seed,
                           progress=progress)
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
    print(f"rendered {args.scene} at {w}x{h} in {seconds:.1f} s ({args.variant}); wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
