#!/usr/bin/env python3
"""woven's renderer against Mitsuba 3 in speed, on the same scenes in one run.

    python3 scripts/mitsuba/bench.py                                   # Mitsuba only
    python3 scripts/mitsuba/bench.py --woven target/release/woven      # and woven, same run
    bash scripts/mitsuba/speed.sh                                      # every speed scene

Each `--scene` (default: scenes/compare/roughplastic-plane.toml, the woven plane) is rendered at
`--size` x `--size` pixels and `--spp` samples by Mitsuba in each `--variant`, and with `--woven`
by `woven render`. Mitsuba's time is that of the second render (the first JIT-compiles its
kernels; Dr.Jit caches them, so the second pays no compilation), from the render call until the
image is evaluated: the warm `mi.render`. woven's is the wall time of its whole command, the
second of two runs (the first may build tables or fill a cache), and beside it the render alone
as the command reports it. Each `--woven-only` scene (a scene file, or `showcase` for the
built-in one) is rendered by woven alone at its own size and spp, twice, the faster run kept:
scenes Mitsuba cannot read (woven's yarn-level materials). Samples are width x height x spp
camera samples. The last lines are a Markdown table of every figure.
"""

from __future__ import annotations

import argparse
import re
import shlex
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes as sc

REPO = Path(__file__).resolve().parents[2]
PLANE = REPO / "scenes" / "compare" / "roughplastic-plane.toml"


@dataclass
class Row:
    """One renderer on one scene."""

    scene: str
    renderer: str
    seconds: float
    samples: int
    alone: float | None = None  # woven: the render alone, by its own report

    @property
    def rate(self) -> float:
        return self.samples / self.seconds


def mitsuba_rows(mi, dr, scene: Path, variants: list[str], size: int, spp: int) -> list[Row]:
    """The warm `mi.render` of `scene` in each variant."""
    from compare import pick_variant  # probes in a child process: a bad libLLVM aborts

    rows = []
    for variant in variants:
        pick_variant(mi, variant)
        desc = sc.load_scene(scene)
        s = mi.load_dict(sc.mitsuba_dict(desc, mi, width=size, height=size, spp=spp))
        times = []
        for k in range(2):
            t0 = time.perf_counter()
            img = mi.render(s, spp=spp, seed=k)
            dr.eval(img)
            dr.sync_thread()
            times.append(time.perf_counter() - t0)
        row = Row(scene.stem, f"Mitsuba {variant}", times[1], size * size * spp)
        print(
            f"Mitsuba {mi.__version__} {variant}, threads {dr.thread_count()}: {scene.name} "
            f"{size}x{size} {spp} spp; first render {times[0]:.2f} s (with JIT), second "
            f"{times[1]:.2f} s: {row.rate / 1e6:.2f} M samples/s "
            f"(mean pixel {float(np.array(img).mean()):.5f})",
            flush=True,
        )
        rows.append(row)
    return rows


def woven_row(
    woven: str, scene: Path | None, size: int | None, spp: int | None, threads: int | None, best: bool
) -> Row:
    """Two `woven render` runs of `scene` (None: the built-in showcase): the second, or with
    `best` the faster."""
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(2):
            argv = shlex.split(woven) + ["render"]
            argv += [str(scene)] if scene else []
            argv += ["-o", str(Path(tmp) / "bench.exr"), "--seed", str(k)]
            if size:
                argv += ["--width", str(size), "--height", str(size)]
            if spp:
                argv += ["--spp", str(spp)]
            if threads:
                argv += ["--threads", str(threads)]
            t0 = time.perf_counter()
            r = subprocess.run(argv, cwd=REPO, check=False, capture_output=True, text=True)
            wall = time.perf_counter() - t0
            if r.returncode != 0:
                raise SystemExit(f"bench.py: `{shlex.join(argv)}` failed:\n{r.stderr[-3000:]}")
            own = re.search(
                r"\((\d+)×(\d+), (\d+) spp[^)]*\) in ([0-9.]+) s", r.stdout + r.stderr
            )
            if not own:
                raise SystemExit(f"bench.py: no timing line from `{shlex.join(argv)}`")
            w, h, n = (int(own.group(i)) for i in (1, 2, 3))
            runs.append((wall, float(own.group(4)), w * h * n))
    wall, alone, samples = min(runs) if best else runs[1]
    name = scene.stem if scene else "showcase"
    row = Row(name, "woven render", wall, samples, alone)
    print(
        f"woven render {name}: runs {runs[0][0]:.2f} and {runs[1][0]:.2f} s (wall, whole command), "
        f"kept {wall:.2f} s: {row.rate / 1e6:.3f} M samples/s; the render alone {alone:.2f} s",
        flush=True,
    )
    return row


def table(rows: list[Row]) -> str:
    """The Markdown table: each scene's rows, each Mitsuba row with woven's rate over its own."""
    out = [
        "| scene | renderer | time (s) | M samples/s | woven / this |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        woven = next((w for w in rows if w.scene == r.scene and w.renderer == "woven render"), None)
        ratio = f"{woven.rate / r.rate:.2f}" if woven and r is not woven else ""
        t = f"{r.seconds:.2f}" + (f" (render {r.alone:.2f})" if r.alone is not None else "")
        out.append(f"| {r.scene} | {r.renderer} | {t} | {r.rate / 1e6:.3f} | {ratio} |")
    return "\n".join(out)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", type=Path, action="append", help=f"[{PLANE.relative_to(REPO)}]")
    ap.add_argument("--woven-only", action="append", default=[], metavar="SCENE")
    ap.add_argument("--size", type=int, default=512, help="width = height [512]")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel [64]")
    ap.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variants, comma-separated")
    ap.add_argument("--woven", metavar="CMD", help="also time `CMD render` on the same scenes")
    ap.add_argument(
        "--threads",
        type=int,
        help="threads for both (Dr.Jit's pool and woven's --threads); default all",
    )
    args = ap.parse_args()
    scenes = args.scene or [PLANE]
    if args.woven_only and not args.woven:
        ap.error("--woven-only needs --woven")

    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError as e:
        print(f"bench.py: cannot import mitsuba ({e}); pip install mitsuba", file=sys.stderr)
        return 2
    if args.threads:
        dr.set_thread_count(args.threads)
    variants = [v.strip() for v in args.variant.split(",") if v.strip()]
    rows: list[Row] = []
    for scene in scenes:
        rows += mitsuba_rows(mi, dr, scene, variants, args.size, args.spp)
        if args.woven:
            rows.append(woven_row(args.woven, scene, args.size, args.spp, args.threads, False))
    for name in args.woven_only:
        scene = None if name == "showcase" else Path(name)
        rows.append(woven_row(args.woven, scene, None, None, args.threads, True))
    print()
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
