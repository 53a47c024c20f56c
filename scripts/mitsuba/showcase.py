#!/usr/bin/env python3
"""The showcase (or another scene), as it is, in both renderers: `woven render --no-denoise`
and `python -m woven.mitsuba showcase` (llvm_ad_rgb, `woven_path`), at the same size, spp and
seeds, compared cloth by cloth.

    python scripts/mitsuba/showcase.py --width 320 --height 180 --spp 16 --seeds 4 --out DIR
    python scripts/mitsuba/showcase.py --scene scenes/docs/curtains.toml --width 240 --height 135

A scene other than the showcase is compared over its woven materials (`--cloths`, by default
the curtains' voile and linen), without the banding check.

For each cloth (the pixels whose first hit is that cloth in both renderers' main view, the inset
left out): the two means and their relative difference, and the 8×8-pixel block means' z-scores
(differences over the seeds' standard error): the share within 4. The satin's banding: the
power of the difference image over the satin at periods of 4–16 pixels, against the same from
two halves of woven render's own seeds (noise only). Writes both mean images (EXR) and the
masks' summary; exits 1 when a check fails (means within 1 %, 99 % of blocks within 4 standard
errors, the satin's band power within 2× noise's).
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

REPO = Path(__file__).resolve().parents[2]
CLOTHS = ("satin", "linen", "shot-silk", "twill")
CURTAINS = ("voile", "curtain-linen")


def woven_images(binary, size, spp, seeds, folder, scene="showcase"):
    """`woven render --no-denoise` of `scene` (a file, or the showcase), one linear image per
    seed, and seconds."""
    import mitsuba as mi

    out, seconds = [], 0.0
    for seed in seeds:
        path = Path(folder) / f"woven-{seed}.exr"
        t0 = time.time()
        subprocess.run(
            [binary, "render", *([] if scene == "showcase" else [str(scene)]), "--no-denoise", "--width", str(size[0]), "--height", str(size[1]),
             "--spp", str(spp), "--seed", str(seed), "-o", str(path)],
            check=True, capture_output=True,
        )
        seconds += time.time() - t0
        out.append(np.array(mi.Bitmap(str(path)), dtype=np.float64)[..., :3])
    return np.stack(out), seconds


def mitsuba_images(size, spp, seeds, folder, scene="showcase"):
    """The plugin's render of `scene` (woven.mitsuba._scene.render), one image per seed, and
    seconds."""
    import mitsuba as mi
    from woven.mitsuba._scene import render

    out, t0 = [], time.time()
    for seed in seeds:
        out.append(render(str(scene), mi, folder, spp=spp, size=size, seed=seed))
    return np.stack(out), time.time() - t0


def masks(size, folder, scene="showcase", cloths=CLOTHS):
    """For each of `cloths` (materials of `scene`), the main view's pixels whose every sample's
    first hit is that cloth (an `aov` render of the shapes' indices, 16 samples a pixel), the
    inset's rectangle left out."""
    import mitsuba as mi
    import woven
    from woven.mitsuba._scene import scene_dict

    portable = woven.portable_scene(str(scene), width=size[0], height=size[1])
    d = scene_dict(portable, mi, folder, spp=16)
    d["integrator"] = {"type": "aov", "aovs": "index:shape_index"}
    scene = mi.load_dict(d)
    img = np.array(mi.render(scene), dtype=np.float64)
    index = img[..., -1]
    ids = [s.id() for s in scene.shapes()]
    # scene_dict names the k-th shape `shape-k`.
    material_of = {f"shape-{k}": s["material"] for k, s in enumerate(portable["shapes"])}
    out = {}
    for cloth in cloths:
        # `shape_index` counts from 1 (0: no hit).
        wanted = [i + 1 for i, name in enumerate(ids) if material_of.get(name) == cloth]
        # A pixel is the cloth's where the mean index is exactly its (no edge, no other shape).
        m = np.zeros(index.shape, dtype=bool)
        for i in wanted:
            m |= np.abs(index - i) < 1e-6
        out[cloth] = m
    inset = portable["inset"]
    if inset is not None:
        (x, y), (w, h) = inset["outer"]
        for m in out.values():
            m[y:y + h, x:x + w] = False
    return out


def block_z(a, b, mask, size=8):
    """z-scores of the differences of `size`×`size` block means over the blocks wholly inside
    `mask`, from the seeds' spread (stacks (K, H, W, 3))."""
    k, h, w, _ = a.shape
    hh, ww = h // size * size, w // size * size

    def blocks(x):
        return x[:, :hh, :ww].reshape(k, hh // size, size, ww // size, size, 3).mean(axis=(2, 4))

    inside = mask[:hh, :ww].reshape(hh // size, size, ww // size, size).all(axis=(1, 3))
    ba, bb = blocks(a), blocks(b)
    se = np.sqrt(ba.var(axis=0, ddof=1) / k + bb.var(axis=0, ddof=1) / k)
    z = (bb.mean(axis=0) - ba.mean(axis=0)) / np.where(se > 0, se, np.inf)
    return z[inside]


def band_power(diff, mask, lo=4, hi=16):
    """The power of `diff` (H, W) over the bounding box of `mask` (zero outside it, mean
    removed) at spatial periods from `lo` to `hi` pixels: what banding (moiré along the folds)
    adds to a difference image."""
    ys, xs = np.nonzero(mask)
    box = (slice(ys.min(), ys.max() + 1), slice(xs.min(), xs.max() + 1))
    m = mask[box]
    d = np.where(m, diff[box] - diff[box][m].mean(), 0.0)
    p = np.abs(np.fft.fft2(d)) ** 2
    fy = np.fft.fftfreq(d.shape[0])[:, None]
    fx = np.fft.fftfreq(d.shape[1])[None, :]
    f = np.hypot(fy, fx)
    band = (f >= 1.0 / hi) & (f <= 1.0 / lo)
    return float(p[band].sum() / max(m.sum(), 1))


def compare(w, m, cloth_masks, banding="satin"):
    """Per cloth: means, relative difference, the share of 8×8 blocks within 4 s.e.; and the
    band power of the cloth named `banding` (None: no such check) against noise's."""
    rows, ok = {}, True
    for cloth, mask in cloth_masks.items():
        a, b = w.mean(axis=0)[mask].mean(), m.mean(axis=0)[mask].mean()
        z = block_z(w, m, mask)
        within = float(np.mean(np.abs(z) <= 4)) if z.size else float("nan")
        # The means' standard error from the seeds' spread.
        sa, sb = (x[:, mask].mean(axis=(1, 2)) for x in (w, m))
        se = np.sqrt(sa.var(ddof=1) / len(sa) + sb.var(ddof=1) / len(sb))
        rows[cloth] = {"pixels": int(mask.sum()), "woven": a, "mitsuba": b,
                       "rel": b / a - 1.0, "z": (b - a) / se if se > 0 else 0.0,
                       "blocks": int(z.size), "within4": within}
        ok &= abs(b / a - 1.0) <= 0.01 and (not z.size or within >= 0.99)
    if banding is None:
        return rows, {}, ok
    satin = cloth_masks[banding]
    lum = np.array([0.2126, 0.7152, 0.0722])
    diff = (m.mean(axis=0) - w.mean(axis=0)) @ lum
    k = len(w) // 2
    noise = (w[:k].mean(axis=0) - w[k:].mean(axis=0)) @ lum
    # Two halves' difference has the noise of one half's mean twice over: scale to the
    # difference of the two full means (each K seeds): (1/K + 1/K) against (2/K' + 2/K'), K' = K/2.
    noise_power = band_power(noise, satin) * (2 / len(w)) / (4 / len(w))
    bands = {"satin_band_power": band_power(diff, satin), "noise_band_power": noise_power}
    ok &= bands["satin_band_power"] <= 2.0 * noise_power
    return rows, bands, ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--out", type=Path, help="write the mean images and the figures here")
    ap.add_argument("--scene", default="showcase", help="a scene file (default: the showcase)")
    ap.add_argument("--cloths", help="the materials compared, comma-separated (default: the"
                    " showcase's four cloths, or the curtains' two for another scene)")
    args = ap.parse_args()
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    import woven.mitsuba

    woven.mitsuba.register()
    binary = os.environ.get("WOVEN_BIN") or str(REPO / "target" / "release" / "woven")
    size, seeds = (args.width, args.height), list(range(args.seeds))
    showcase = args.scene == "showcase"
    cloths = tuple(args.cloths.split(",")) if args.cloths else (CLOTHS if showcase else CURTAINS)
    with tempfile.TemporaryDirectory() as folder:
        w, tw = woven_images(binary, size, args.spp, seeds, folder, args.scene)
        m, tm = mitsuba_images(size, args.spp, seeds, folder, args.scene)
        cloth_masks = masks(size, folder, args.scene, cloths)
    rows, bands, ok = compare(w, m, cloth_masks, "satin" if showcase else None)
    print(f"{args.scene} {size[0]}x{size[1]}, {args.spp} spp x {len(seeds)} seeds: woven render"
          f" {tw:.1f} s, Mitsuba llvm_ad_rgb + plugin {tm:.1f} s ({tm / tw:.1f}x)")
    print(f"{'cloth':<10} {'pixels':>7} {'woven':>9} {'mitsuba':>9} {'rel':>8} {'z':>6}"
          f" {'blocks':>7} {'<=4 se':>7}")
    for cloth, r in rows.items():
        print(f"{cloth:<10} {r['pixels']:>7} {r['woven']:>9.5f} {r['mitsuba']:>9.5f}"
              f" {100 * r['rel']:>+7.2f}% {r['z']:>+6.1f} {r['blocks']:>7}"
              f" {100 * r['within4']:>6.1f}%")
    if bands:
        print(f"satin, power at 4-16 px periods: difference {bands['satin_band_power']:.3g},"
              f" noise {bands['noise_band_power']:.3g}")
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        mi.Bitmap(w.mean(axis=0).astype("float32")).write(str(args.out / "woven.exr"))
        mi.Bitmap(m.mean(axis=0).astype("float32")).write(str(args.out / "mitsuba.exr"))
        figures = {"rows": rows, "bands": bands, "seconds": {"woven": tw, "mitsuba": tm}}
        (args.out / "showcase.json").write_text(json.dumps(figures, indent=1))
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
