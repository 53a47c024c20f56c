#!/usr/bin/env python3
"""Speed of the Python package and the Mitsuba plugin (docs/python.md, "Speed").

    python scripts/python/bench.py                 # NumPy batch throughput of Table.eval
    python scripts/python/bench.py --rust          # ... and the Rust bench's, in the same run
    python scripts/python/bench.py --mitsuba       # plugin vs roughplastic render, llvm_ad_rgb

1. ``Table.eval`` on 2^20 pairs from NumPy arrays (conversion in and out included), the table
   and the pairs' distribution of ``cargo bench -p woven --bench table`` (the sateen on the
   default grid, directions within 1.4 rad of the normal), against that bench's
   ``sateen_all_cores/table_eval`` (criterion, run here with ``--rust``).
2. Mitsuba 3 ``llvm_ad_rgb`` renders of scene (ii) (scenes/compare/roughplastic-plane.toml,
   ``--size`` pixels square, 64 spp): Mitsuba's own ``roughplastic``, then the ``woven`` plugin
   with the sateen as its macro BRDF and as a tilted, gapped 2/1 twill at ``detail = "yarns"``
   (both traced, Dr.Jit's symbolic mode), and the same twill at the default ``detail = "auto"``
   (the library lane by lane, evaluated mode) beside ``roughplastic`` in evaluated mode: the
   median of ``--repeats`` renders after a warm-up (JIT compilation excluded), each against the
   first in the same run.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import woven

REPO = Path(__file__).resolve().parents[2]
BATCH = 1 << 20


def directions(rng, n, theta_max=1.4):
    """Directions uniform in solid angle within ``theta_max`` of the normal."""
    cos_t = 1 - rng.random(n) * (1 - np.cos(theta_max))
    phi = rng.random(n) * 2 * np.pi
    sin_t = np.sqrt(1 - cos_t**2)
    return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=1)


def bench_numpy():
    t0 = time.time()
    table = woven.Table.build("polyester-sateen", grid="default", progress=False)
    print(f"table (sateen, default grid {table.dims}) built in {time.time() - t0:.1f} s")
    rng = np.random.default_rng(1)
    wi, wo = directions(rng, BATCH), directions(rng, BATCH)
    table.eval(wi, wo)
    times = []
    for _ in range(7):
        t0 = time.perf_counter()
        table.eval(wi, wo)
        times.append(time.perf_counter() - t0)
    best = min(times)
    rate = BATCH / best
    print(f"numpy Table.eval, 2^20 pairs: {best * 1e3:.1f} ms = {rate / 1e6:.1f} M pairs/s (best of 7)")
    return rate


def bench_rust():
    cmd = ["cargo", "bench", "-q", "-p", "woven", "--bench", "table", "--", "sateen_all_cores/table_eval"]
    r = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{r.stderr[-2000:]}")
    m = re.search(r"thrpt:\s*\[\s*([\d.]+) (\w)elem/s\s+([\d.]+) (\w)elem/s", r.stdout)
    if not m:
        sys.exit(f"no throughput in the bench's output:\n{r.stdout[-2000:]}")
    scale = {"K": 1e3, "M": 1e6, "G": 1e9}
    rate = float(m.group(3)) * scale[m.group(4)]
    print(f"rust sateen_all_cores/table_eval: {rate / 1e6:.1f} M pairs/s (criterion median)")
    return rate


TWILL = {"type": "woven", "material": "polyester-sateen", "pattern": "twill-2/1",
         "u_max_deg": 30.0, "gap": 0.3}
CASES = [
    ("roughplastic", True, None),
    ("woven, macro BRDF", True, {"type": "woven", "material": "polyester-sateen"}),
    ("woven, twill, detail = yarns", True, dict(TWILL, detail="yarns")),
    ("roughplastic, evaluated mode", False, None),
    ("woven, twill, detail = auto (library)", False, TWILL),
]


def bench_mitsuba(size, repeats):
    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    import woven.mitsuba

    sys.path.insert(0, str(REPO / "scripts" / "mitsuba"))
    import scenes as sc

    scene = sc.load_scene(REPO / "scenes" / "compare" / "roughplastic-plane.toml")
    out = {}
    for name, symbolic, bsdf in CASES:
        # register() switches its thread to evaluated mode unless told not to.
        woven.mitsuba.register(symbolic=symbolic)
        for flag in ("SymbolicLoops", "SymbolicCalls", "SymbolicConditionals"):
            dr.set_flag(getattr(dr.JitFlag, flag), symbolic)
        d = sc.mitsuba_dict(scene, mi, width=size, height=size, spp=64)
        if bsdf is not None:
            d["rect0"]["bsdf"] = bsdf
        s = mi.load_dict(d)
        np.array(mi.render(s, spp=64))  # JIT compilation, tables
        times = []
        for k in range(repeats):
            t0 = time.perf_counter()
            np.array(mi.render(s, spp=64, seed=k + 1))
            times.append(time.perf_counter() - t0)
        out[name] = float(np.median(times))
        base = out[CASES[0][0]]
        print(f"mitsuba llvm_ad_rgb scene (ii) {size}² 64 spp, {name}: {out[name]:.3f} s"
              f" (median of {repeats}; {out[name] / base:.2f}× roughplastic)", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rust", action="store_true", help="also run the Rust bench")
    ap.add_argument("--mitsuba", action="store_true", help="the Mitsuba render benchmark only")
    ap.add_argument("--size", type=int, default=256, help="Mitsuba renders' pixels a side")
    ap.add_argument("--repeats", type=int, default=3, help="Mitsuba renders timed per case")
    args = ap.parse_args()
    print(f"{os.cpu_count()} cores")
    if args.mitsuba:
        bench_mitsuba(args.size, args.repeats)
        return
    py = bench_numpy()
    if args.rust:
        rust = bench_rust()
        print(f"numpy / rust: {py / rust:.2f}")


if __name__ == "__main__":
    main()
