#!/usr/bin/env python3
"""Render issue 9's comparison scenes in Mitsuba 3 and compare with an analytic reference and,
when given, with `woven render`.

    python3 scripts/mitsuba/compare.py                         # Mitsuba vs analytic only
    python3 scripts/mitsuba/compare.py --woven target/release/woven
    python3 scripts/mitsuba/compare.py --woven "cargo run --release -q -p woven-cli --"
    python3 scripts/mitsuba/compare.py --woven-dir DIR         # EXRs named <scene>-s<k>.exr

The scenes are woven's scene files (scenes/compare/*.toml); each is translated to a Mitsuba dict
(scripts/mitsuba/scenes.py) so both renderers read one description. Every scene is rendered with
--seeds independent seeds at the file's spp (both renderers); the per-pixel standard error is the
spread between seeds. See docs/mitsuba.md for the statistics and the pass rule.

Exit status: 0 when every comparison passes, 1 when one fails, 2 on a usage or setup error.
"""

from __future__ import annotations

import argparse
import json
import shlex
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes as sc

REPO = Path(__file__).resolve().parents[2]
DEFAULT_SCENES = ["diffuse-plane", "roughplastic-plane", "furnace-sphere"]

# A per-pixel difference passes when |d| <= K_SIGMA * se + tol * |ref| + ABS_FLOOR.
K_SIGMA = 5.0
ABS_FLOOR = 1e-6  # float32 rounding of values ~1
PIXEL_PASS_FRACTION = 0.999
# Known systematic differences between the models (relative), by what is compared:
#  - Mitsuba vs woven on the roughplastic scene: Mitsuba's rational approximation of the Beckmann
#    Smith G1 (<= 0.35 % per G1). Not guessed: the two analytic images (exact and Mitsuba's G1)
#    measure it per scene, and its largest relative effect is added to the tolerance.
#  - everything else: 0 (pure noise) but for float32 (1e-5).
TOL_FLOAT32 = 1e-5


PROBE = """
import mitsuba as mi, numpy as np
mi.set_variant({v!r})
s = mi.load_dict({{"type": "scene", "integrator": {{"type": "path"}}, "e": {{"type": "constant"}},
                  "sensor": {{"type": "perspective",
                             "film": {{"type": "hdrfilm", "width": 2, "height": 2}}}}}})
assert np.isfinite(np.array(mi.render(s, spp=1))).all()
"""


def pick_variant(mi, wanted: str | None) -> str:
    """The first variant that renders. Probed in a child process: an LLVM that Dr.Jit cannot use
    (libLLVM 15 on Debian 12: "LLVM ERROR: Cannot select ... fmaximum") aborts the process."""
    order = [wanted] if wanted else ["llvm_ad_rgb", "scalar_rgb"]
    errors = []
    for v in order:
        if v not in mi.variants():
            errors.append(f"{v}: not in this build ({', '.join(mi.variants())})")
            continue
        r = subprocess.run(
            [sys.executable, "-c", PROBE.format(v=v)], check=False, capture_output=True, text=True
        )
        if r.returncode == 0:
            mi.set_variant(v)
            return v
        tail = r.stderr.strip().splitlines() or ["(no message)"]
        errors.append(f"{v}: a test render failed ({r.returncode}): {tail[0][:200]}")
        print(f"note: Mitsuba variant {v} does not work here: {tail[0][:200]}", file=sys.stderr)
    raise SystemExit("no Mitsuba variant works:\n  " + "\n  ".join(errors))


def render_mitsuba(
    mi, scene: sc.Scene, seeds: list[int], spp: int, out: Path, width=None, height=None
) -> np.ndarray:
    s = mi.load_dict(sc.mitsuba_dict(scene, mi, width=width, height=height, spp=spp))
    imgs = []
    for seed in seeds:
        img = np.array(mi.render(s, spp=spp, seed=seed), dtype=np.float32)
        imgs.append(img[..., :3])
        if out is not None:
            mi.Bitmap(imgs[-1]).write(str(out / f"{scene.name}-s{seed}.exr"))
    stack = np.stack(imgs).astype(np.float64)
    if out is not None:
        mi.Bitmap(stack.mean(axis=0).astype(np.float32)).write(str(out / f"{scene.name}.exr"))
    return stack


def read_exr(mi, path: Path) -> np.ndarray:
    bmp = mi.Bitmap(str(path))
    arr = np.array(bmp, dtype=np.float64)
    if arr.ndim == 2:
        arr = np.repeat(arr[..., None], 3, axis=-1)
    return arr[..., :3]


def brdf_vs_woven_eval(cmd: str, scene: sc.Scene, material: sc.Material) -> float:
    """The analytic BRDF (numpy) against `woven eval` (woven's exact model) at 256 pixels'
    directions: the largest relative difference. Shows the analytic image is woven's model."""
    wi, wo = sc.plane_pixel_directions(scene, 256)
    lines = ["theta_i,phi_i,theta_r,phi_r"]
    for a, b in zip(wi, wo):
        lines.append(
            f"{np.arccos(a[2])!r},{np.arctan2(a[1], a[0])!r},"
            f"{np.arccos(b[2])!r},{np.arctan2(b[1], b[0])!r}".replace("np.float64(", "").replace(
                ")", ""
            )
        )
    argv = shlex.split(cmd) + ["eval", "-m", str(material.source), "-i", "-"]
    r = subprocess.run(
        argv, cwd=REPO, check=False, capture_output=True, text=True, input="\n".join(lines) + "\n"
    )
    if r.returncode != 0:
        raise SystemExit(f"`{shlex.join(argv)}` failed ({r.returncode}):\n{r.stderr[-3000:]}")
    ev = np.array([float(ln.split(",")[-1]) for ln in r.stdout.strip().splitlines()[1:]])
    f = sc.brdf(material, wi, wo)[:, 0]
    return float(np.max(np.abs(f - ev) / np.maximum(np.abs(ev), 1e-300)))


def render_woven(
    cmd: str, scene: sc.Scene, seeds: list[int], spp: int, out: Path, mi
) -> np.ndarray:
    imgs = []
    for seed in seeds:
        path = out / f"{scene.name}-s{seed}.exr"
        argv = shlex.split(cmd) + [
            "render",
            str(scene.path),
            "-o",
            str(path),
            "--seed",
            str(seed),
            "--spp",
            str(spp),
        ]
        t0 = time.time()
        r = subprocess.run(argv, cwd=REPO, check=False, capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"`{shlex.join(argv)}` failed ({r.returncode}):\n{r.stderr[-3000:]}")
        print(f"  woven {scene.name} seed {seed}: {time.time() - t0:.1f} s", flush=True)
        imgs.append(read_exr(mi, path))
    return np.stack(imgs)


def local_se(se: np.ndarray) -> np.ndarray:
    """A steadier per-pixel standard error: the larger of the pixel's own and the rms over its 3x3
    neighbourhood. With a few seeds the pixel's own estimate has few degrees of freedom (a heavy
    t tail); the noise level varies smoothly in these scenes, so the neighbourhood adds ~9x the
    degrees of freedom, and the max keeps the jumps at silhouettes (never smaller than its own)."""
    v = np.pad(se**2, ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = se.shape[:2]
    box = sum(v[i : i + h, j : j + w] for i in range(3) for j in range(3)) / 9.0
    return np.maximum(se, np.sqrt(box))


def stats(a: np.ndarray, b: np.ndarray, tol: float, mask: np.ndarray | None = None) -> dict:
    """a: reference stack (K, H, W, 3) or exact image (H, W, 3); b: stack (K', H, W, 3).
    `mask` (H, W): only these pixels count in the per-pixel figures."""

    def mean_se(x):
        if x.ndim == 3:
            return x, np.zeros_like(x), np.full(1, x.mean()), 0.0
        k = x.shape[0]
        per_seed = x.reshape(k, -1).mean(axis=1)
        return (
            x.mean(axis=0),
            x.std(axis=0, ddof=1) / np.sqrt(k),
            per_seed,
            per_seed.std(ddof=1) / np.sqrt(k),
        )

    ma, sa, ga, gsa = mean_se(a)
    mb, sb, gb, gsb = mean_se(b)
    if ma.shape != mb.shape:
        raise SystemExit(f"image sizes differ: {ma.shape} vs {mb.shape}")
    d = mb - ma
    se = local_se(np.sqrt(sa**2 + sb**2))
    allowed = K_SIGMA * se + tol * np.abs(ma) + ABS_FLOOR
    ok = np.abs(d) <= allowed
    if mask is not None:
        ok = ok[mask]
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(se > 0, d / se, 0.0)
    noisy = se > 0
    gmean_a, gmean_b = ga.mean(), gb.mean()
    gse = float(np.hypot(gsa, gsb))
    gdiff = gmean_b - gmean_a
    lit = np.abs(ma) > 1e-3 * np.abs(ma).max()
    if mask is not None:
        lit &= mask[..., None]
        noisy &= mask[..., None]
    if mask is not None:  # the image means are not comparable then: judge pixels only
        gdiff, gse = float((d * mask[..., None]).sum() / (3 * mask.sum())), float("inf")
    glob_ok = abs(gdiff) <= K_SIGMA * gse + tol * abs(gmean_a) + ABS_FLOOR
    frac = float(ok.mean())
    return {
        "mean_ref": float(gmean_a),
        "mean_test": float(gmean_b),
        "mean_rel_diff": float(gdiff / gmean_a) if gmean_a else float("nan"),
        "mean_diff_z": float(gdiff / gse) if gse > 0 else float("nan"),
        "pixel_rel_diff_mean_abs": float(np.mean(np.abs(d[lit]) / np.abs(ma[lit]))),
        "pixel_rel_diff_max_abs": float(np.max(np.abs(d[lit]) / np.abs(ma[lit]))),
        "rms_z": float(np.sqrt(np.mean(z[noisy] ** 2))) if noisy.any() else 0.0,
        "max_abs_z": float(np.max(np.abs(z[noisy]))) if noisy.any() else 0.0,
        "pixels_within": frac,
        "tol_rel": tol,
        "pass": bool(frac >= PIXEL_PASS_FRACTION and glob_ok),
    }


def row(label: str, s: dict) -> str:
    return (
        f"{label:<54} {s['mean_ref']:>9.5f} {s['mean_test']:>9.5f} "
        f"{100 * s['mean_rel_diff']:>+8.3f}% {s['mean_diff_z']:>+7.1f} "
        f"{100 * s['pixel_rel_diff_mean_abs']:>7.3f}% {s['rms_z']:>6.2f} {s['max_abs_z']:>6.1f} "
        f"{100 * s['pixels_within']:>7.2f}% {'PASS' if s['pass'] else 'FAIL'}"
    )


HEADER = (
    f"{'comparison (ref -> test)':<54} {'ref mean':>9} {'test mean':>9} {'rel diff':>9} "
    f"{'z':>7} {'|px rel|':>8} {'rms z':>6} {'max|z|':>6} {'within':>8} result"
)


def main() -> int:
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "scenes",
        nargs="*",
        help=f"scene files (default: scenes/compare/{{{','.join(DEFAULT_SCENES)}}}.toml)",
    )
    ap.add_argument("--variant", help="Mitsuba variant (default: llvm_ad_rgb, else scalar_rgb)")
    ap.add_argument("--seeds", type=int, default=8, help="independent renders per scene [8]")
    ap.add_argument("--spp", type=int, help="samples per pixel per render (default: the file's)")
    ap.add_argument(
        "--grid",
        type=int,
        default=8,
        help="analytic sub-pixel grid per axis (1 = pixel centres) [8]",
    )
    ap.add_argument(
        "--out",
        type=Path,
        default=REPO / "woven-out" / "mitsuba",
        help="output folder for EXRs and results.json [woven-out/mitsuba]",
    )
    g = ap.add_mutually_exclusive_group()
    g.add_argument(
        "--woven", metavar="CMD", help="the woven binary or command, e.g. target/release/woven"
    )
    g.add_argument(
        "--woven-dir",
        type=Path,
        metavar="DIR",
        help="compare woven EXRs already rendered, DIR/<scene>-s<seed>.exr",
    )
    ap.add_argument(
        "--woven-tol",
        type=float,
        default=0.0,
        help="extra relative tolerance for woven's comparisons, e.g. the stated error of the "
        "BRDF table a render evaluates [0]",
    )
    ap.add_argument(
        "--no-eval-check",
        action="store_true",
        help="skip checking the analytic BRDF against `woven eval` (for a stand-in without eval)",
    )
    args = ap.parse_args()
    if args.seeds < 2:
        ap.error("--seeds must be at least 2 (the error estimate needs a spread)")

    try:
        import mitsuba as mi
    except ImportError as e:
        print(f"compare.py: cannot import mitsuba ({e}); pip install mitsuba", file=sys.stderr)
        return 2
    variant = pick_variant(mi, args.variant)
    print(f"Mitsuba {mi.__version__}, variant {variant}")

    paths = [Path(p) for p in args.scenes] or [
        REPO / "scenes" / "compare" / f"{n}.toml" for n in DEFAULT_SCENES
    ]
    (args.out / "mitsuba").mkdir(parents=True, exist_ok=True)
    wdir = args.out / "woven"
    if args.woven:
        wdir.mkdir(parents=True, exist_ok=True)

    results, lines = {}, []
    for path in paths:
        try:
            scene = sc.load_scene(path)
        except (sc.SceneError, OSError, KeyError) as e:
            print(f"compare.py: {e}", file=sys.stderr)
            return 2
        spp = args.spp or scene.spp
        seeds = [scene.seed + k for k in range(args.seeds)]
        t0 = time.time()
        m = render_mitsuba(mi, scene, seeds, spp, args.out / "mitsuba")
        print(
            f"{scene.name}: Mitsuba {len(seeds)} x {scene.width}x{scene.height} x {spp} spp "
            f"in {time.time() - t0:.1f} s; mean pixel {m.mean():.6f}",
            flush=True,
        )
        r = results[scene.name] = {"mitsuba_mean": float(m.mean()), "spp": spp, "seeds": len(seeds)}
        # Analytic reference (the exact image, float64). For roughplastic two: one with woven's
        # exact Smith G1 (what woven must match) and one with Mitsuba's approximation.
        tol_rough = TOL_FLOAT32
        has_rough = any(mt.kind == "roughplastic" for *_, mt in scene.rectangles + scene.spheres)
        exact = sc.analytic_image(scene, grid=args.grid, g1="woven")
        r["analytic_mean"] = float(exact.mean())
        if has_rough:
            approx = sc.analytic_image(scene, grid=args.grid, g1="mitsuba")
            r["analytic_mitsuba_g1_mean"] = float(approx.mean())
            lit = exact > 1e-3 * exact.max()
            ratio = approx[lit] / exact[lit]
            r["smith_approx_ratio_range"] = [float(ratio.min()), float(ratio.max())]
            tol_rough = TOL_FLOAT32 + float(np.max(np.abs(ratio - 1)))
            r["tol_rel"] = tol_rough
            s = stats(approx, m, TOL_FLOAT32)
            lines.append(row(f"{scene.name}: analytic(Mitsuba G1) -> Mitsuba", s))
            r["analytic_mitsuba_g1_vs_mitsuba"] = s
            s = stats(exact, m, tol_rough)
            lines.append(row(f"{scene.name}: analytic(exact G1) -> Mitsuba", s))
            r["analytic_vs_mitsuba"] = s
        else:
            s = stats(exact, m, TOL_FLOAT32)
            lines.append(row(f"{scene.name}: analytic -> Mitsuba", s))
            r["analytic_vs_mitsuba"] = s
        # woven
        w = None
        if args.woven and has_rough and not args.no_eval_check:
            mat = next(mt for *_, mt in scene.rectangles if mt.kind == "roughplastic")
            err = brdf_vs_woven_eval(args.woven, scene, mat)
            r["analytic_brdf_vs_woven_eval_max_rel"] = err
            print(f"{scene.name}: analytic BRDF vs `woven eval` at 256 pixels: max rel {err:.1e}")
            if err > 1e-9:
                raise SystemExit(f"the analytic BRDF is not woven's model (max rel {err:.1e})")
        if args.woven:
            w = render_woven(args.woven, scene, seeds, spp, wdir, mi)
        elif args.woven_dir:
            w = np.stack([read_exr(mi, args.woven_dir / f"{scene.name}-s{k}.exr") for k in seeds])
        if w is not None:
            tol = (tol_rough if has_rough else TOL_FLOAT32) + args.woven_tol
            s = stats(m, w, tol)
            lines.append(row(f"{scene.name}: Mitsuba -> woven", s))
            r["mitsuba_vs_woven"] = s
            s = stats(exact, w, TOL_FLOAT32 + args.woven_tol)
            lines.append(row(f"{scene.name}: analytic -> woven", s))
            r["analytic_vs_woven"] = s

    # Conventions: the diffuse plane against deliberately wrong analytic conventions. Only the
    # right one may pass. A non-square film tells a horizontal fov from a vertical one.
    conv = {}
    diffuse = next((p for p in paths if p.stem == "diffuse-plane"), None)
    if diffuse is not None:
        scene = sc.load_scene(diffuse)
        w_, h_ = 128, 80
        m = render_mitsuba(
            mi, scene, [1000 + k for k in range(args.seeds)], scene.spp, None, width=w_, height=h_
        )
        variants = {
            "right (row 0 top, fov horizontal, centres)": {},
            "rows flipped (row 0 at the bottom)": {"flip_rows": True},
            "columns flipped (mirror image)": {"flip_cols": True},
            "half-pixel shift (corners, not centres)": {"shift": 0.5},
            "fov vertical": {"fov_axis": "y"},
        }
        for label, kw in variants.items():
            img = sc.analytic_image(scene, grid=args.grid, width=w_, height=h_, **kw)
            s = stats(img, m, TOL_FLOAT32)
            lines.append(row(f"conv {w_}x{h_}: {label}", s))
            conv[label] = s
        # point light units: W/sr (radiance I cos / r^2), not watts (I / 4 pi)
        img = sc.analytic_image(scene, grid=args.grid, width=w_, height=h_) / (4 * np.pi)
        s = stats(img, m, TOL_FLOAT32)
        lines.append(row(f"conv {w_}x{h_}: intensity read as power (W)", s))
        conv["intensity read as power (W)"] = s
        results["conventions"] = conv
        # the centre ray alone (grid 1), as rho/pi I cos / r^2 is usually stated: it differs from
        # the pixel mean by the curvature of the image within a pixel, and at the plane's edges
        # by partial coverage; shown on the pixels the plane covers whole.
        img = sc.analytic_image(scene, grid=1, width=w_, height=h_)
        full = sc.analytic_image(scene, grid=args.grid, width=w_, height=h_, coverage=True) == 1
        s = stats(img, m, TOL_FLOAT32, mask=full)
        lines.append(row(f"conv {w_}x{h_}: pixel-centre rays, covered px", s))
        conv["pixel-centre rays only"] = s

    print()
    print(HEADER)
    print("-" * len(HEADER))
    for ln in lines:
        print(ln)
    print()
    print(
        f"z: difference of the image means over its standard error; within: pixels with "
        f"|d| <= {K_SIGMA:g} se + tol*|ref| (pass needs >= {100 * PIXEL_PASS_FRACTION:g} % "
        f"and |mean d| <= {K_SIGMA:g} se + tol*mean); tol = {TOL_FLOAT32:g} (float32), "
        "plus the largest effect of Mitsuba's approximate Smith G1 where the exact one is compared "
        "with it (measured on the scene's analytic images)"
    )
    results["variant"] = variant
    results["mitsuba_version"] = mi.__version__
    (args.out / "results.json").write_text(json.dumps(results, indent=2) + "\n")
    print(f"results: {args.out / 'results.json'}; EXRs under {args.out}")

    must_pass = [
        v
        for name, r in results.items()
        if isinstance(r, dict) and name != "conventions"
        for k, v in r.items()
        if isinstance(v, dict) and "pass" in v
    ]
    if conv:
        must_pass.append(conv["right (row 0 top, fov horizontal, centres)"])
        wrong = [
            v
            for k, v in conv.items()
            if k not in ("right (row 0 top, fov horizontal, centres)", "pixel-centre rays only")
        ]
        if any(v["pass"] for v in wrong):
            print("a WRONG convention passed: the convention check cannot tell them apart")
            return 1
    return 0 if all(s["pass"] for s in must_pass) else 1


if __name__ == "__main__":
    sys.exit(main())
