"""woven's RGL `.bsdf` export read by Mitsuba 3's own `measured` plugin, against `woven eval`.

    python scripts/mitsuba/rgl_check.py [--presets P ...] [--variants V ...] [--pairs N]
                                        [--woven target/release/woven] [--keep DIR]
                                        [--export-args "--n-grid 64 ..."]

For each preset it writes the file with `woven export --format rgl` (RGB, and spectral when a
spectral variant is asked for), draws N random pairs of directions up to 80° from the normal,
and compares Mitsuba's `BSDF.eval` (f·cos θ of the light's direction) with `woven eval --rgb`'s
f times the same cosine:
  - RGB variants: each channel;
  - spectral variants: at 450, 540, 610 and 700 nm, where the file's spectrum is woven's blue,
    green, red and red channel (docs/export.md).
With --render PRESET ..., it also renders a plane of each at cloth level under a point light and
under a constant environment, in Mitsuba 3 with the file and in `woven render` with
`detail = "cloth"`, and prints the two means (they must agree within 1 %).
It prints, per preset and variant, the median and 99th-percentile relative error of f·cos over
pairs and channels whose reference is above 1 % of the preset's mean (where a relative error
means something), the file's size and its build time, and exits 1 when a median exceeds
--median-limit (2 %) or a 99th percentile --p99-limit (10 %).

Mitsuba's `si.wi` (toward the camera) is the file's incident direction: woven's viewer `v`.
"""

import argparse
import csv
import io
import os
import shlex
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

PRESETS = [
    "polyester-sateen", "belt-cloth", "silk", "filament-satin", "satin-charmeuse",
    "silk-crepe-de-chine", "linen-plain", "silk-shot",
    "microcylinder-linen-plain", "microcylinder-silk-crepe-de-chine",
    "microcylinder-satin-charmeuse", "microcylinder-satin-charmeuse-back",
    "microcylinder-silk-shot", "microcylinder-velvet",
]
MEDIAN_LIMIT, P99_LIMIT = 0.02, 0.10
# Wavelengths where a spectral file holds woven's blue, green and red channels exactly (red is
# held beyond 610 nm); Mitsuba's spectral variants trace four wavelengths at once.
SPECTRAL_CHANNELS = {450.0: 2, 540.0: 1, 610.0: 0, 700.0: 0}


def directions(rng, n, theta_max_deg=80.0):
    """n directions uniform over the cap up to theta_max_deg: (theta, phi) arrays."""
    cos_min = np.cos(np.radians(theta_max_deg))
    cos_t = 1.0 - rng.random(n) * (1.0 - cos_min)
    return np.arccos(cos_t), rng.uniform(-np.pi, np.pi, n)


def to_vec(theta, phi):
    s = np.sin(theta)
    return np.stack([s * np.cos(phi), s * np.sin(phi), np.cos(theta)], axis=1)


def woven_eval(woven, preset, light, view):
    """woven's f in RGB, shape (n, 3): light = s (theta_i, phi_i), view = v (theta_r, phi_r)."""
    rows = io.StringIO()
    rows.write("theta_i,phi_i,theta_r,phi_r\n")
    for a, b, c, d in zip(*light, *view):
        rows.write(f"{float(a)!r},{float(b)!r},{float(c)!r},{float(d)!r}\n")
    out = subprocess.run(
        [woven, "eval", "--rgb", "-m", preset, "-i", "-"],
        input=rows.getvalue(), capture_output=True, text=True, check=True,
    ).stdout
    table = list(csv.DictReader(io.StringIO(out)))
    return np.array([[float(r["brdf_r"]), float(r["brdf_g"]), float(r["brdf_b"])] for r in table])


def export(woven, preset, path, spectral, extra=()):
    args = [woven, "export", "--format", "rgl", "-m", preset, "-o", path, *extra]
    if spectral:
        args.append("--spectral")
    start = time.perf_counter()
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start, os.path.getsize(path)


def mitsuba_eval(variant, path, light, view, wavelengths=None):
    """Mitsuba's measured BSDF: f·cos θ(light), shape (n, channels)."""
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    bsdf = mi.load_dict({"type": "measured", "filename": path})
    ctx = mi.BSDFContext()
    wi, wo = to_vec(*view), to_vec(*light)
    n = len(wi)
    scalar = variant.startswith("scalar")
    out = []
    if scalar:
        for k in range(n):
            si = dr.zeros(mi.SurfaceInteraction3f)
            si.wi = mi.Vector3f(*wi[k])
            if wavelengths is not None:
                si.wavelengths = mi.UnpolarizedSpectrum(*wavelengths)
            v = bsdf.eval(ctx, si, mi.Vector3f(*wo[k]))
            out.append([v[c] for c in range(len(v))] if wavelengths is None else
                       [v[c] for c in range(len(wavelengths))])
        return np.array(out)
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(*[wi[:, c] for c in range(3)])
    if wavelengths is not None:
        si.wavelengths = mi.UnpolarizedSpectrum(*[np.full(n, w) for w in wavelengths])
    v = bsdf.eval(ctx, si, mi.Vector3f(*[wo[:, c] for c in range(3)]))
    return np.stack([np.array(v[c]) for c in range(dr.size_v(v))], axis=1)


SCENE = """
[camera]
origin = [0.0, -2.5, 2.5]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov_deg = 45.0

[film]
width = 64
height = 64
spp = {spp}
sampler = "independent"
seed = 0

[integrator]
max_depth = 2
hide_emitters = true

{light}

[[shape]]
type = "rectangle"
corner = [-1.0, -1.0, 0.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 2.0, 0.0]
material = "cloth"

[material.cloth]
{material}
"""

LIGHTS = {
    "point light": '[[light]]\ntype = "point"\nposition = [0.4, 0.5, 1.5]\nintensity = [10.0, 10.0, 10.0]',
    "environment": '[[light]]\ntype = "environment"\nradiance = [1.0, 1.0, 1.0]',
}


def render_both(woven, preset, bsdf_path, folder, spp=256, variant="llvm_ad_rgb"):
    """Means of a cloth-level plane in woven render and in Mitsuba with the file, per light."""
    import mitsuba as mi
    import scenes as sc

    mi.set_variant(variant)
    out = {}
    for light, text in LIGHTS.items():
        scene_path = os.path.join(folder, f"{preset}-{light.replace(' ', '-')}.toml")
        with open(scene_path, "w") as f:
            material = (f'type = "microcylinder"\nmaterial = "{preset}"'
                        if preset.startswith("microcylinder-") else
                        f'type = "woven"\nmaterial = "{preset}"\ndetail = "cloth"')
            f.write(SCENE.format(spp=spp, light=text, material=material))
        exr = scene_path[:-5] + ".exr"
        subprocess.run([woven, "render", scene_path, "-o", exr, "--spp", str(spp)],
                       check=True, capture_output=True)
        ours = np.array(mi.Bitmap(exr), dtype=np.float64)[..., :3]
        scene = sc.load_scene(scene_path, measured={"cloth": bsdf_path})
        theirs = np.array(mi.render(mi.load_dict(sc.mitsuba_dict(scene, mi)), spp=spp), dtype=np.float64)[..., :3]
        out[light] = (ours.mean(), theirs.mean())
    return out


def errors(got, want):
    """Relative errors of got against want over entries above 1 % of want's mean."""
    keep = want > 0.01 * want.mean()
    return np.abs(got[keep] - want[keep]) / want[keep]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--presets", nargs="*", default=PRESETS)
    ap.add_argument("--variants", nargs="+", default=["scalar_rgb", "scalar_spectral", "llvm_ad_rgb"])
    ap.add_argument("--pairs", type=int, default=10_000)
    ap.add_argument("--woven", default=os.environ.get("WOVEN_BIN", "target/release/woven"))
    ap.add_argument("--median-limit", type=float, default=MEDIAN_LIMIT)
    ap.add_argument("--p99-limit", type=float, default=P99_LIMIT)
    ap.add_argument("--export-args", default="", metavar="ARGS",
                    help="more arguments to `woven export`, e.g. \"--n-grid 64 --n-phi-i 73\"")
    ap.add_argument("--keep", help="write the .bsdf files here (default: a temporary folder)")
    ap.add_argument("--render", nargs="*", default=[], metavar="PRESET",
                    help="also render these presets' planes in both renderers (RGB file)")
    args = ap.parse_args()

    extra = shlex.split(args.export_args)
    rng = np.random.default_rng(20261205)
    failed = False
    folder = args.keep or tempfile.mkdtemp(prefix="woven-rgl-")
    os.makedirs(folder, exist_ok=True)
    print(f"{'preset':20} {'variant':16} {'median':>7} {'p99':>7} {'size':>9} {'build':>7}")
    for preset in args.presets:
        light, view = directions(rng, args.pairs), directions(rng, args.pairs)
        ref = woven_eval(args.woven, preset, light, view) * np.cos(light[0])[:, None]
        files = {}
        for variant in args.variants:
            spectral = "spectral" in variant
            if spectral not in files:
                path = os.path.join(folder, f"{preset}{'-spectral' if spectral else ''}.bsdf")
                files[spectral] = (path, *export(args.woven, preset, path, spectral, extra))
            path, seconds, size = files[spectral]
            if spectral:
                nms = list(SPECTRAL_CHANNELS)
                got = mitsuba_eval(variant, path, light, view, nms)
                want = ref[:, [SPECTRAL_CHANNELS[w] for w in nms]]
            else:
                got = mitsuba_eval(variant, path, light, view)
                want = ref
            e = errors(got, want)
            median, p99 = np.median(e), np.percentile(e, 99)
            bad = median > args.median_limit or p99 > args.p99_limit
            failed |= bad
            print(f"{preset:20} {variant:16} {100 * median:6.2f}% {100 * p99:6.2f}% "
                  f"{size / 1e6:7.1f}MB {seconds:6.1f}s{'  FAIL' if bad else ''}", flush=True)
    for preset in args.render:
        path = os.path.join(folder, f"{preset}.bsdf")
        if not os.path.exists(path):
            export(args.woven, preset, path, False, extra)
        for light, (ours, theirs) in render_both(args.woven, preset, path, folder).items():
            diff = theirs / ours - 1.0
            bad = abs(diff) > 0.01
            failed |= bad
            print(f"{preset:20} {light:12} woven render {ours:.5f}, Mitsuba measured {theirs:.5f}: "
                  f"{100 * diff:+.2f}%{'  FAIL' if bad else ''}", flush=True)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
