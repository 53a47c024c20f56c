#!/usr/bin/env python3
"""The virtual goniometer in Cycles against ``woven eval``: one preset's weft, its projection
built as a Cycles material (``woven.blender``), measured by Cycles in the plane of incidence
(``woven.blender.gonio``) beside the exact model (``woven.Surface.eval`` of the family as the
cloth shows it) and the fitted lobes (``woven.standard_eval``: what the parameters mean). Prints
the table and the ridge: where each curve peaks and how high.

    target/blender-venv/bin/python scripts/blender/gonio.py [PRESET] [--theta-i 40] \
        [--across] [--out gonio.json]
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("preset", nargs="?", default="polyester-sateen")
    ap.add_argument("--theta-i", type=float, default=40.0)
    ap.add_argument("--across", action="store_true",
                    help="the plane of incidence across the yarn (default: along it)")
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--out", type=Path)
    args = ap.parse_args(argv)
    import bpy
    import woven
    from woven.blender import _material
    from woven.blender.gonio import Goniometer, spherical

    folder = Path(tempfile.mkdtemp(prefix="woven-gonio-"))
    surface = woven.Surface(args.preset, progress=False, weft_fraction=1.0, detail="yarns")
    std = _material.standard(surface, f"gonio {args.preset} weft_fraction=1", folder, "g")
    g = Goniometer(bpy, lambda: _material.material(bpy, "g", std), samples=args.samples)
    phi = 90.0 if args.across else 0.0
    wi = spherical(args.theta_i, phi)
    rows = []
    for theta_r in range(-80, 81, 5):
        wo = spherical(abs(theta_r), phi + (180.0 if theta_r < 0 else 0.0))
        if abs(theta_r) < 1e-9:
            wo = np.array([0.0, 0.0, 1.0])
        cycles = float(g.measure(wi, wo) @ LUMINANCE)
        exact = float(np.asarray(surface.eval([[0.01, 0.01]], wi, wo)).ravel() @ LUMINANCE)
        lobes = float(np.asarray(woven.standard_eval(std["weft"], wi, wo)).ravel() @ LUMINANCE)
        rows.append({"theta_r": theta_r, "woven": exact, "lobes": lobes, "cycles": cycles})
        print(f"θr {theta_r:+4d}°  woven {exact:.4f}  lobes {lobes:.4f}  Cycles {cycles:.4f}")
    ridge = {k: max(rows, key=lambda r: r[k]) for k in ("woven", "lobes", "cycles")}
    for k, r in ridge.items():
        print(f"ridge of {k}: θr {r['theta_r']:+d}°, {r[k]:.4f} sr⁻¹")
    worst = max(abs(r["cycles"] / r["lobes"] - 1.0) for r in rows if r["lobes"] > 0)
    print(f"Cycles against the lobes it was given: worst {100 * worst:.1f} %")
    if args.out:
        args.out.write_text(json.dumps({"preset": args.preset, "theta_i": args.theta_i,
                                        "across": args.across, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
