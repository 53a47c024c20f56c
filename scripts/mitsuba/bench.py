#!/usr/bin/env python3
"""Mitsuba 3's speed on issue 9's scene (ii) (scenes/compare/roughplastic-plane.toml) at 512x512,
64 spp, and optionally woven's on the same scene in the same run, for the ratio the issue asks for.

    python3 scripts/mitsuba/bench.py                                   # Mitsuba only
    python3 scripts/mitsuba/bench.py --woven target/release/woven      # and woven, same run

Mitsuba's time is that of the second render (the first JIT-compiles its kernels; Dr.Jit caches
them, so the second pays no compilation), from the render call until the image is evaluated.
woven's is the wall time of the second of two `woven render` runs (the first may build tables or
fill a cache). Samples are width x height x spp camera samples.
"""

from __future__ import annotations

import argparse
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes as sc

REPO = Path(__file__).resolve().parents[2]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--scene", type=Path, default=REPO / "scenes" / "compare" / "roughplastic-plane.toml"
    )
    ap.add_argument("--size", type=int, default=512, help="width = height [512]")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel [64]")
    ap.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variant [llvm_ad_rgb]")
    ap.add_argument("--woven", metavar="CMD", help="also time `CMD render` on the same scene")
    ap.add_argument(
        "--threads",
        type=int,
        help="threads for both (Dr.Jit's pool and woven's --threads); default all",
    )
    args = ap.parse_args()

    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError as e:
        print(f"bench.py: cannot import mitsuba ({e}); pip install mitsuba", file=sys.stderr)
        return 2
    from compare import pick_variant  # probes in a child process: a bad libLLVM aborts

    pick_variant(mi, args.variant)
    if args.threads:
        dr.set_thread_count(args.threads)
    scene = sc.load_scene(args.scene)
    n = args.size * args.size * args.spp
    s = mi.load_dict(sc.mitsuba_dict(scene, mi, width=args.size, height=args.size, spp=args.spp))
    times = []
    for k in range(2):
        t0 = time.perf_counter()
        img = mi.render(s, spp=args.spp, seed=k)
        dr.eval(img)
        dr.sync_thread()
        times.append(time.perf_counter() - t0)
    mean = float(np.array(img).mean())
    m_rate = n / times[1]
    print(
        f"Mitsuba {mi.__version__} {args.variant}, threads {dr.thread_count()}: "
        f"{args.scene.name} {args.size}x{args.size} {args.spp} spp; first render "
        f"{times[0]:.2f} s (with JIT), second {times[1]:.2f} s: {m_rate / 1e6:.2f} M samples/s "
        f"(mean pixel {mean:.5f})"
    )
    if args.woven:
        wt = []
        with tempfile.TemporaryDirectory() as tmp:
            for k in range(2):
                argv = shlex.split(args.woven) + [
                    "render",
                    str(args.scene),
                    "-o",
                    str(Path(tmp) / "bench.exr"),
                    "--width",
                    str(args.size),
                    "--height",
                    str(args.size),
                    "--spp",
                    str(args.spp),
                    "--seed",
                    str(k),
                ]
                if args.threads:
                    argv += ["--threads", str(args.threads)]
                t0 = time.perf_counter()
                r = subprocess.run(argv, cwd=REPO, check=False, capture_output=True, text=True)
                wt.append(time.perf_counter() - t0)
                if r.returncode != 0:
                    print(
                        f"bench.py: `{shlex.join(argv)}` failed:\n{r.stderr[-3000:]}",
                        file=sys.stderr,
                    )
                    return 1
        w_rate = n / wt[1]
        print(
            f"woven render: first {wt[0]:.2f} s, second {wt[1]:.2f} s (wall, whole command): "
            f"{w_rate / 1e6:.2f} M samples/s; woven / Mitsuba = {w_rate / m_rate:.2f}"
        )
        # woven's own figure for the render alone (after parsing and table building), the
        # counterpart of Mitsuba's, which excludes loading the scene
        own = re.search(r"in ([0-9.]+) s \(([0-9.]+) M samples/s", r.stdout + r.stderr)
        if own:
            r_rate = n / float(own.group(1))
            print(
                f"woven render, the render alone (its own report): {float(own.group(1)):.2f} s: "
                f"{r_rate / 1e6:.2f} M samples/s; woven / Mitsuba = {r_rate / m_rate:.2f} "
                "(issue 9 asks >= 0.5)"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
