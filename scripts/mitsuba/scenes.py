"""woven scene TOML -> Mitsuba 3 scene dict, and an analytic reference in numpy.

Only the subset of the scene contract (issue 9) that the comparison scenes use is translated:
[camera], [film], [integrator], point and constant-radiance environment lights, rectangles and
spheres, `diffuse` materials, and `woven` materials whose material file is a flat rough fiber
without a diffuse part (which is exactly Mitsuba's `roughplastic`). Anything else is an error that
names the file and the key: this module never guesses.

The analytic reference (`analytic_image`) follows the camera convention woven's renderer promises
(issue 9, [film]): pixel (i, j) covers [i, i+1] x [j, j+1] of the film, column i from the left, row
j from the top; the horizontal field of view spans the film's width; right = forward x up. It
averages each pixel over a regular grid of sub-pixel rays (or takes the pixel centre only), in
float64, so it is independent of both renderers.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np


class SceneError(ValueError):
    """A scene or material file that this translator does not accept."""


def _err(path: Path, key: str, msg: str) -> SceneError:
    return SceneError(f"{path}: `{key}`: {msg}")


def _vec3(path: Path, table: dict, key: str, prefix: str) -> np.ndarray:
    v = table.get(key)
    if not (isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v)):
        raise _err(path, f"{prefix}{key}", f"expected [x, y, z] numbers, got {v!r}")
    return np.array(v, dtype=np.float64)


@dataclass
class Material:
    kind: str  # "diffuse" | "roughplastic" | "measured"
    reflectance: np.ndarray | None = None  # diffuse
    alpha: float = 0.0  # roughplastic: Beckmann alpha = 2 * roughness
    eta: float = 1.0
    source: Path | None = None  # the woven material file, for `woven eval`
    filename: str | None = None  # measured: the RGL .bsdf file


@dataclass
class Scene:
    path: Path
    origin: np.ndarray
    target: np.ndarray
    up: np.ndarray
    fov_deg: float
    width: int
    height: int
    spp: int
    seed: int
    max_depth: int
    hide_emitters: bool
    point_lights: list  # [(position, intensity)]
    env_radiance: np.ndarray | None
    rectangles: list  # [(corner, edge_u, edge_v, Material)]
    spheres: list  # [(center, radius, Material)]

    @property
    def name(self) -> str:
        return self.path.stem


def load_material_file(path: Path) -> Material:
    """A woven material file that is a flat rough fiber, diffuse 0, normalization "none"."""
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    for k in ("yarn", "weave"):
        if k in doc:
            raise _err(path, k, "has no Mitsuba equivalent (only a flat fiber surface does)")
    fiber = doc.get("fiber")
    if not isinstance(fiber, dict):
        raise _err(path, "fiber", "missing: a [fiber] table is required")
    if fiber.get("model", "rough") != "rough":
        raise _err(
            path, "fiber.model", f'{fiber.get("model")!r}: only "rough" maps to roughplastic'
        )
    if fiber.get("normalization", "paper") != "none":
        raise _err(
            path,
            "fiber.normalization",
            f'{fiber.get("normalization", "paper")!r}: only "none" is plain Torrance-Sparrow',
        )
    if float(fiber.get("diffuse", 0.0)) != 0.0:
        raise _err(
            path,
            "fiber.diffuse",
            f"{fiber['diffuse']}: woven's rho0/pi is not roughplastic's diffuse layer; use 0",
        )
    eta = fiber.get("eta")
    if not isinstance(eta, (int, float)):
        raise _err(path, "fiber.eta", f"{eta!r}: a constant refractive index is required")
    roughness = fiber.get("roughness")
    if not isinstance(roughness, (int, float)):
        raise _err(path, "fiber.roughness", f"{roughness!r}: a number is required")
    return Material("roughplastic", alpha=2.0 * float(roughness), eta=float(eta), source=path)


def load_scene(path: str | Path, measured: dict | None = None) -> Scene:
    """The scene at `path`; `measured` maps material names to RGL `.bsdf` files (`woven export
    --format rgl`) that stand for them in Mitsuba, whatever their woven keys."""
    path = Path(path)
    measured = measured or {}
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    cam, film, integ = doc.get("camera", {}), doc.get("film", {}), doc.get("integrator", {})
    materials = {}
    for name, m in doc.get("material", {}).items():
        t = m.get("type")
        if name in measured:
            materials[name] = Material("measured", filename=str(measured[name]))
        elif t == "diffuse":
            materials[name] = Material(
                "diffuse", reflectance=_vec3(path, m, "reflectance", f"material.{name}.")
            )
        elif t == "woven":
            if set(m) - {"type", "material"}:
                raise _err(path, f"material.{name}", "only `material` is translated for woven")
            materials[name] = load_material_file(path.parent / m["material"])
        else:
            raise _err(path, f"material.{name}.type", f"{t!r}: only diffuse and woven")
    points, env = [], None
    for k, light in enumerate(doc.get("light", [])):
        t = light.get("type")
        if t == "point":
            points.append(
                (
                    _vec3(path, light, "position", f"light[{k}]."),
                    _vec3(path, light, "intensity", f"light[{k}]."),
                )
            )
        elif t == "environment":
            if "file" in light:
                raise _err(path, f"light[{k}].file", "only a constant radiance is translated")
            env = _vec3(path, light, "radiance", f"light[{k}].") * float(light.get("scale", 1.0))
        else:
            raise _err(path, f"light[{k}].type", f"{t!r}: only point and environment")
    rects, spheres = [], []
    for k, s in enumerate(doc.get("shape", [])):
        t, mat = s.get("type"), s.get("material")
        if mat not in materials:
            raise _err(path, f"shape[{k}].material", f"{mat!r} is not a [material.NAME]")
        if t == "rectangle":
            rects.append(
                (
                    _vec3(path, s, "corner", f"shape[{k}]."),
                    _vec3(path, s, "edge_u", f"shape[{k}]."),
                    _vec3(path, s, "edge_v", f"shape[{k}]."),
                    materials[mat],
                )
            )
        elif t == "sphere":
            spheres.append(
                (
                    _vec3(path, s, "center", f"shape[{k}]."),
                    float(s.get("radius", 1.0)),
                    materials[mat],
                )
            )
        else:
            raise _err(path, f"shape[{k}].type", f"{t!r}: only rectangle and sphere")
    return Scene(
        path=path,
        origin=_vec3(path, cam, "origin", "camera."),
        target=_vec3(path, cam, "target", "camera."),
        up=_vec3(path, cam, "up", "camera."),
        fov_deg=float(cam["fov_deg"]),
        width=int(film["width"]),
        height=int(film["height"]),
        spp=int(film.get("spp", 64)),
        seed=int(film.get("seed", 0)),
        max_depth=int(integ.get("max_depth", 16)),
        hide_emitters=bool(integ.get("hide_emitters", False)),
        point_lights=points,
        env_radiance=env,
        rectangles=rects,
        spheres=spheres,
    )


# ----------------------------------------------------------------------------------------------
# Mitsuba 3


def mitsuba_dict(
    scene: Scene, mi, width: int | None = None, height: int | None = None, spp: int | None = None
) -> dict:
    """The Mitsuba 3 scene dict of `scene` (a variant must be set on `mi` already)."""
    T = mi.ScalarTransform4f

    def bsdf(m: Material) -> dict:
        if m.kind == "measured":
            return {"type": "measured", "filename": m.filename}
        if m.kind == "diffuse":
            return {
                "type": "diffuse",
                "reflectance": {"type": "rgb", "value": m.reflectance.tolist()},
            }
        # roughplastic without a diffuse layer is plain Torrance-Sparrow, F(eta; h.wi) D G / 4 cos
        # cos. ext_ior defaults to air (1.000277): vacuum makes eta = int_ior exactly, as in woven.
        return {
            "type": "roughplastic",
            "distribution": "beckmann",
            "alpha": m.alpha,
            "int_ior": m.eta,
            "ext_ior": 1.0,
            "nonlinear": False,
            "diffuse_reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]},
        }

    d = {
        "type": "scene",
        "integrator": {
            "type": "path",
            "max_depth": scene.max_depth,
            "hide_emitters": scene.hide_emitters,
        },
        "sensor": {
            "type": "perspective",
            "fov": scene.fov_deg,
            "fov_axis": "x",
            "to_world": T().look_at(
                origin=scene.origin.tolist(), target=scene.target.tolist(), up=scene.up.tolist()
            ),
            "sampler": {"type": "independent", "sample_count": spp or scene.spp},
            "film": {
                "type": "hdrfilm",
                "width": width or scene.width,
                "height": height or scene.height,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
                "component_format": "float32",
            },
        },
    }
    for k, (pos, inten) in enumerate(scene.point_lights):
        d[f"point{k}"] = {
            "type": "point",
            "position": pos.tolist(),
            "intensity": {"type": "rgb", "value": inten.tolist()},
        }
    if scene.env_radiance is not None:
        d["env"] = {
            "type": "constant",
            "radiance": {"type": "rgb", "value": scene.env_radiance.tolist()},
        }
    for k, (c, eu, ev, m) in enumerate(scene.rectangles):
        # Mitsuba's rectangle is [-1, 1]^2 in z = 0, normal +z; map it onto corner + s eu + t ev.
        n = np.cross(eu, ev)
        n = n / np.linalg.norm(n)
        centre = c + 0.5 * eu + 0.5 * ev
        mat = np.eye(4)
        mat[:3, 0], mat[:3, 1], mat[:3, 2], mat[:3, 3] = 0.5 * eu, 0.5 * ev, n, centre
        d[f"rect{k}"] = {"type": "rectangle", "to_world": T(mat.tolist()), "bsdf": bsdf(m)}
    for k, (c, r, m) in enumerate(scene.spheres):
        d[f"sphere{k}"] = {"type": "sphere", "center": c.tolist(), "radius": r, "bsdf": bsdf(m)}
    return d


# ----------------------------------------------------------------------------------------------
# Analytic reference (numpy, float64)


def camera_rays(
    scene: Scene,
    grid: int,
    width: int | None = None,
    height: int | None = None,
    flip_rows: bool = False,
    flip_cols: bool = False,
    shift: float = 0.0,
    fov_axis: str = "x",
):
    """Unit ray directions, shape (H, W, grid*grid, 3), for the convention of woven's [film].

    `grid` = 1 is the pixel centre; otherwise a regular grid of grid x grid sub-pixel positions.
    The flips, the sub-pixel `shift` and `fov_axis = "y"` give the *wrong* conventions, to show
    that the comparison can tell them apart.
    """
    w, h = width or scene.width, height or scene.height
    f = scene.target - scene.origin
    f /= np.linalg.norm(f)
    r = np.cross(f, scene.up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    t = math.tan(math.radians(scene.fov_deg) / 2)
    tx, ty = (t, t * h / w) if fov_axis == "x" else (t * w / h, t)
    sub = (np.arange(grid) + 0.5) / grid + shift
    x = np.arange(w)[None, :, None, None] + sub[None, None, :, None]  # film x, left to right
    y = np.arange(h)[:, None, None, None] + sub[None, None, None, :]  # film y, top to bottom
    x = np.broadcast_to(x, (h, w, grid, grid)).reshape(h, w, grid * grid)
    y = np.broadcast_to(y, (h, w, grid, grid)).reshape(h, w, grid * grid)
    if flip_cols:
        x = w - x
    if flip_rows:
        y = h - y
    sx = (2 * x / w - 1) * tx
    sy = (1 - 2 * y / h) * ty
    d = f + sx[..., None] * r + sy[..., None] * u
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def plane_pixel_directions(scene: Scene, n: int, seed: int = 0):
    """Light and view directions (local frame of the first rectangle: z = normal, x along edge_u)
    at the pixel centres of `n` random pixels that see the rectangle: (wi, wo), each (n, 3)."""
    c, eu, ev, _ = scene.rectangles[0]
    nrm = np.cross(eu, ev)
    nrm /= np.linalg.norm(nrm)
    ex = eu / np.linalg.norm(eu)
    to_local = np.stack([ex, np.cross(nrm, ex), nrm])
    d = camera_rays(scene, 1)[:, :, 0].reshape(-1, 3)
    t = ((c - scene.origin) @ nrm) / (d @ nrm)
    p = scene.origin + t[:, None] * d
    s_ = (p - c) @ eu / (eu @ eu)
    v_ = (p - c) @ ev / (ev @ ev)
    hit = np.flatnonzero((t > 0) & (s_ >= 0) & (s_ <= 1) & (v_ >= 0) & (v_ <= 1))
    pick = np.random.default_rng(seed).choice(hit, size=min(n, hit.size), replace=False)
    pos = scene.point_lights[0][0]
    wi = pos - p[pick]
    wi /= np.linalg.norm(wi, axis=-1, keepdims=True)
    return wi @ to_local.T, (-d[pick]) @ to_local.T


_erfc = np.vectorize(math.erfc, otypes=[np.float64])


def smith_g1_woven(cos_t: np.ndarray, alpha: float) -> np.ndarray:
    """docs/spec.md 1.2: S1 = (1 - erfc(a)/2) / (1 + Lambda(a)), a = cot(theta) / alpha."""
    cos_t = np.clip(cos_t, 1e-12, 1.0)
    sin_t = np.sqrt(np.maximum(0.0, 1 - cos_t**2))
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(sin_t > 0, cos_t / np.maximum(sin_t, 1e-300) / alpha, np.inf)
        big = a > 30
        af = np.where(big, 1.0, a)
        ec = _erfc(af)
        lam = 0.5 * (np.exp(-(af**2)) / (af * math.sqrt(math.pi)) - ec)
        s1 = (1 - 0.5 * ec) / (1 + lam)
    return np.where(big, 1.0, s1)


def smith_g1_mitsuba(cos_t: np.ndarray, alpha: float) -> np.ndarray:
    """Mitsuba 3's Beckmann G1: a rational approximation of 1/(1 + Lambda), 1 for a >= 1.6."""
    cos_t = np.clip(cos_t, 1e-12, 1.0)
    sin_t = np.sqrt(np.maximum(0.0, 1 - cos_t**2))
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(sin_t > 0, cos_t / np.maximum(sin_t, 1e-300) / alpha, np.inf)
        r = (3.535 * a + 2.181 * a * a) / (1 + 2.276 * a + 2.577 * a * a)
    return np.where(a >= 1.6, 1.0, r)


def fresnel_dielectric(cos_i: np.ndarray, eta: float) -> np.ndarray:
    """Unpolarized reflectance (rs^2 + rp^2)/2 from the outside of a dielectric of index eta."""
    cos_i = np.clip(cos_i, 0.0, 1.0)
    sin_t2 = (1 - cos_i**2) / eta**2
    cos_t = np.sqrt(np.maximum(0.0, 1 - sin_t2))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (rs**2 + rp**2)


def brdf(m: Material, wi: np.ndarray, wo: np.ndarray, g1: str = "woven") -> np.ndarray:
    """f(wi, wo) without the cosine, (..., 3) RGB, local frame z = normal; wi toward the light."""
    ci, co = wi[..., 2], wo[..., 2]
    ok = (ci > 0) & (co > 0)
    if m.kind == "diffuse":
        return np.where(ok[..., None], m.reflectance / math.pi, 0.0)
    hv = wi + wo
    hv = hv / np.linalg.norm(hv, axis=-1, keepdims=True)
    ch = np.clip(hv[..., 2], 1e-12, 1.0)
    tan2 = (1 - ch**2) / ch**2
    d = np.exp(-tan2 / m.alpha**2) / (math.pi * m.alpha**2 * ch**4)
    fr = fresnel_dielectric(np.sum(wi * hv, axis=-1), m.eta)
    g1f = smith_g1_woven if g1 == "woven" else smith_g1_mitsuba
    g = g1f(ci, m.alpha) * g1f(co, m.alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(ok, fr * d * g / (4 * ci * co), 0.0)
    return np.repeat(f[..., None], 3, axis=-1)


def analytic_image(
    scene: Scene, grid: int = 8, g1: str = "woven", coverage: bool = False, **ray_kw
) -> np.ndarray:
    """Pixel means (H, W, 3) of direct lighting: point lights on rectangles, and for a constant
    environment the furnace identity (a diffuse convex shape under uniform radiance L reflects
    rho * L; rays that miss see L unless emitters are hidden)."""
    dirs = camera_rays(scene, grid, **ray_kw)
    o = scene.origin
    t_best = np.full(dirs.shape[:-1], np.inf)
    out = np.zeros(dirs.shape[:-1] + (3,))
    hit_any = np.zeros(dirs.shape[:-1], dtype=bool)
    for c, eu, ev, m in scene.rectangles:
        n = np.cross(eu, ev)
        n /= np.linalg.norm(n)
        denom = dirs @ n
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((c - o) @ n) / denom
        p = o + t[..., None] * dirs
        rel = p - c
        s = rel @ eu / (eu @ eu)
        v = rel @ ev / (ev @ ev)
        hit = (t > 0) & (s >= 0) & (s <= 1) & (v >= 0) & (v <= 1) & (t < t_best)
        # one-sided: black from behind
        front = denom < 0
        radiance = np.zeros_like(out)
        # local frame: z = n, x = eu direction
        ex = eu / np.linalg.norm(eu)
        ey = np.cross(n, ex)
        to_local = np.stack([ex, ey, n])
        wo = (-dirs) @ to_local.T
        for pos, inten in scene.point_lights:
            dl = pos - p
            r2 = np.sum(dl * dl, axis=-1)
            wi = (dl / np.sqrt(r2)[..., None]) @ to_local.T
            f = brdf(m, wi, wo, g1)
            radiance += f * (np.clip(wi[..., 2], 0, None) / r2)[..., None] * inten
        if scene.env_radiance is not None:
            if m.kind != "diffuse":
                raise SceneError(f"{scene.path}: no analytic environment term for {m.kind}")
            radiance += m.reflectance * scene.env_radiance  # a plane sees only the sky
        radiance = np.where(front[..., None], radiance, 0.0)
        out = np.where(hit[..., None], radiance, out)
        t_best = np.where(hit, t, t_best)
        hit_any |= hit
    for c, rad, m in scene.spheres:
        oc = o - c
        b = dirs @ oc
        disc = b * b - (oc @ oc - rad * rad)
        t = -b - np.sqrt(np.maximum(disc, 0))
        hit = (disc > 0) & (t > 0) & (t < t_best)
        if scene.point_lights:
            raise SceneError(f"{scene.path}: no analytic point-light term for spheres")
        if m.kind != "diffuse" or scene.env_radiance is None:
            raise SceneError(
                f"{scene.path}: the sphere's analytic value needs a diffuse "
                "material and a constant environment"
            )
        out = np.where(hit[..., None], m.reflectance * scene.env_radiance, out)
        t_best = np.where(hit, t, t_best)
        hit_any |= hit
    if scene.env_radiance is not None and not scene.hide_emitters:
        out = np.where(hit_any[..., None], out, scene.env_radiance)
    if coverage:  # the fraction of each pixel's rays that hit a shape
        return hit_any.mean(axis=2)
    return out.mean(axis=2)
