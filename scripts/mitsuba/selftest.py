#!/usr/bin/env python3
"""Self-test of compare.py's statistics, with no woven renderer needed: a stand-in "woven" that
renders the scene with Mitsuba itself (other seeds) must pass, and stand-ins with a known defect
must fail — a 1 % brightness bias, rows flipped, a half-pixel shift. This shows the comparison can
fail, and how small a defect it catches at the default seeds and spp.

    python3 scripts/mitsuba/selftest.py            # exit 0 when every case ends as expected

It also serves as the stand-in: `selftest.py render SCENE -o OUT.exr --seed S --spp N
[--defect bias|flip-rows|shift]` writes what the woven CLI would.
"""

from __future__ import annotations

import argparse
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import scenes as sc


def stand_in(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="selftest.py render")
    ap.add_argument("scene", type=Path)
    ap.add_argument("-o", "--output", type=Path, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--spp", type=int)
    ap.add_argument("--defect", choices=["bias", "flip-rows", "shift"])
    a = ap.parse_args(argv)
    import mitsuba as mi

    mi.set_variant("scalar_rgb" if "scalar_rgb" in mi.variants() else mi.variants()[0])
    scene = sc.load_scene(a.scene)
    d = sc.mitsuba_dict(scene, mi, spp=a.spp)
    if a.defect == "shift":  # half a pixel to the right: turn the camera by fov/(2 width)
        import math

        ang = scene.fov_deg / scene.width / 2
        f = scene.target - scene.origin
        u = scene.up / np.linalg.norm(scene.up)
        r = np.cross(f / np.linalg.norm(f), u)
        r /= np.linalg.norm(r)
        t = scene.origin + f + r * np.linalg.norm(f) * math.tan(math.radians(ang))
        d["sensor"]["to_world"] = mi.ScalarTransform4f().look_at(
            origin=scene.origin.tolist(), target=t.tolist(), up=scene.up.tolist()
        )
    img = np.array(
        mi.render(mi.load_dict(d), spp=a.spp or scene.spp, seed=a.seed + 1_000_003),
        dtype=np.float32,
    )[..., :3]
    if a.defect == "bias":
        img *= 1.01
    elif a.defect == "flip-rows":
        img = img[::-1].copy()
    mi.Bitmap(img).write(str(a.output))
    return 0


def main() -> int:
    if len(sys.argv) > 1 and sys.argv[1] == "render":
        return stand_in(sys.argv[2:])
    if len(sys.argv) > 1:
        print(f"selftest.py: unknown arguments {sys.argv[1:]}", file=sys.stderr)
        return 2
    me = shlex.quote(sys.executable) + " " + shlex.quote(str(Path(__file__).resolve()))
    cases = [(None, 0), ("bias", 1), ("flip-rows", 1), ("shift", 1)]
    ok = True
    for defect, want in cases:
        # compare.py appends `render SCENE -o ...`; a defect goes in before it
        woven = f"{me} render-with {defect}" if defect else me
        argv = [
            sys.executable,
            str(HERE / "compare.py"),
            "--seeds",
            "4",
            "--no-eval-check",
            "--out",
            str(HERE.parents[1] / "target" / "mitsuba-selftest" / (defect or "none")),
            "--woven",
            woven,
            str(HERE.parents[1] / "scenes" / "compare" / "diffuse-plane.toml"),
            str(HERE.parents[1] / "scenes" / "compare" / "roughplastic-plane.toml"),
        ]
        r = subprocess.run(argv, check=False, capture_output=True, text=True)
        got = r.returncode
        lines = [ln for ln in r.stdout.splitlines() if "-> woven" in ln]
        verdict = "as expected" if got == want else "UNEXPECTED"
        print(
            f"stand-in with defect {defect or 'none'}: compare.py exit {got} "
            f"(want {want}): {verdict}"
        )
        for ln in lines:
            print("    " + ln)
        if got != want:
            ok = False
            print(r.stdout[-2000:], r.stderr[-2000:])
    print("self-test", "passed" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "render-with":
        # `selftest.py render-with DEFECT render SCENE ...` -> stand-in with --defect DEFECT
        defect = sys.argv[2]
        sys.exit(stand_in(sys.argv[4:] + ["--defect", defect]))
    sys.exit(main())
