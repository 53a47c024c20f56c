"""Drapes square cloths with a small position-based cloth simulation, offline, and writes them
as OBJ meshes for the showcase (crates/woven-render/scenes/meshes/).

The cloth is a grid of particles joined by distance constraints: stretch (each neighbour along
the weft and the warp), shear (the diagonals) and bend (every second neighbour, softer). Each
step moves the particles under gravity, then projects the constraints a number of times
(Gauss-Seidel, in batches of constraints that share no particle, so each batch is one NumPy
operation), pushes particles out of the obstacles (spheres, a round table, the floor) with
friction on contact, and derives the velocities from the positions (Müller et al. 2007's
position-based dynamics). There is no self-collision: the drops are chosen so that the cloth
does not fold onto itself.

Each mesh is written with:
- `vt`: uv in metres along the cloth's rest grid, `u` along the weft (the grid's first index)
  and `v` along the warp, so a scene's `yarns_per_unit` is yarns per metre;
- `vn`: area-weighted vertex normals;
- thickness: a back sheet offset by the cloth's thickness and a strip joining the two along the
  edges, so the cloth's edge shows as a hem rather than a razor-thin sheet.

    python3 scripts/drape/drape.py [OUT_DIR]     (needs numpy; about 2 minutes on one core)

Default OUT_DIR: crates/woven-render/scenes/meshes. The simulation is deterministic.
"""
import os
import sys

import numpy as np

GRAVITY = np.array([0.0, 0.0, -9.81])


class Cloth:
    """A square grid of particles with its constraint batches."""

    def __init__(self, size, n, centre_xy, height, turn_deg=0.0, stiffness=(1.0, 0.9, 0.08)):
        """A flat `size` square of `n × n` particles at `height`, centred on `centre_xy` and
        turned `turn_deg` about the vertical."""
        self.n = n
        self.spacing = size / (n - 1)
        a = np.linspace(0.0, size, n)
        u, v = np.meshgrid(a, a, indexing="ij")
        self.rest_uv = np.stack([u, v], axis=-1).reshape(-1, 2)
        t = np.radians(turn_deg)
        du, dv = u.ravel() - size / 2, v.ravel() - size / 2
        self.x = np.zeros((n * n, 3))
        self.x[:, 0] = centre_xy[0] + np.cos(t) * du - np.sin(t) * dv
        self.x[:, 1] = centre_xy[1] + np.sin(t) * du + np.cos(t) * dv
        self.x[:, 2] = height
        self.v = np.zeros_like(self.x)
        self.batches = self._batches(stiffness)

    def _index(self, i, j):
        return i * self.n + j

    def _batches(self, stiffness):
        """Constraint batches `(a, b, rest, k)`: no particle appears twice in a batch."""
        n, h = self.n, self.spacing
        k_stretch, k_shear, k_bend = stiffness
        i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
        batches = []

        def add(di, dj, key, k):
            ok = (i + di < n) & (j + dj < n) & (j + dj >= 0)
            for parity in np.unique(key[ok]):
                sel = ok & (key == parity)
                a = self._index(i[sel], j[sel])
                b = self._index(i[sel] + di, j[sel] + dj)
                batches.append((a, b, h * np.hypot(di, dj), k))

        add(0, 1, j % 2, k_stretch)
        add(1, 0, i % 2, k_stretch)
        add(1, 1, i % 2, k_shear)
        add(1, -1, i % 2, k_shear)
        add(0, 2, (j // 2) % 2, k_bend)
        add(2, 0, (i // 2) % 2, k_bend)
        return batches

    def project(self, p):
        for a, b, rest, k in self.batches:
            d = p[b] - p[a]
            length = np.linalg.norm(d, axis=1)
            corr = (k * 0.5 * (length - rest) / np.maximum(length, 1e-12))[:, None] * d
            p[a] += corr
            p[b] -= corr


def collide(p, previous, obstacles, friction=0.6, skin=0.002):
    """Pushes particles out of the obstacles; particles in contact keep only part of their
    tangential motion this step (friction)."""
    contact = np.zeros(len(p), dtype=bool)
    for kind, params in obstacles:
        if kind == "sphere":
            centre, radius = params
            d = p - centre
            r = np.linalg.norm(d, axis=1)
            inside = r < radius + skin
            p[inside] = centre + d[inside] / r[inside, None] * (radius + skin)
            contact |= inside
        elif kind == "table":
            # A solid round table (top at `top`, down to the floor) with its rim rounded by
            # 1.5 cm, pushed out of along the gradient of its signed distance.
            dist = lambda q: _table_distance(q, *params)  # noqa: E731
            d = dist(p)
            near = d < skin
            if near.any():
                q = p[near]
                h = 1e-5
                grad = np.stack(
                    [(dist(q + h * e) - dist(q - h * e)) / (2 * h) for e in np.eye(3)], axis=1
                )
                grad /= np.maximum(np.linalg.norm(grad, axis=1, keepdims=True), 1e-12)
                p[near] = q + (skin - d[near])[:, None] * grad
            contact |= near
        elif kind == "floor":
            below = p[:, 2] < skin
            p[below, 2] = skin
            contact |= below
    moved = p[contact] - previous[contact]
    p[contact] = previous[contact] + (1.0 - friction) * moved
    return p


def _table_distance(q, centre_xy, radius, top, rim=0.015):
    """Signed distance to a solid cylinder `radius` wide from the floor to `top`, its edges
    rounded by `rim` (negative inside)."""
    r = np.linalg.norm(q[:, :2] - centre_xy, axis=1)
    half = top / 2.0
    dx = r - (radius - rim)
    dz = np.abs(q[:, 2] - half) - (half - rim)
    outside = np.hypot(np.maximum(dx, 0.0), np.maximum(dz, 0.0))
    return np.minimum(np.maximum(dx, dz), 0.0) + outside - rim


def simulate(cloth, obstacles, seconds, dt=1.0 / 300.0, iterations=30, damping=0.995):
    steps = int(seconds / dt)
    for step in range(steps):
        cloth.v = cloth.v * damping + GRAVITY * dt
        p = cloth.x + cloth.v * dt
        for _ in range(iterations):
            cloth.project(p)
        p = collide(p, cloth.x, obstacles)
        cloth.v = (p - cloth.x) / dt
        cloth.x = p
        if step % 100 == 0:
            print(f"  step {step}/{steps}", file=sys.stderr)
    return cloth


def normals(x, faces):
    fn = np.cross(x[faces[:, 1]] - x[faces[:, 0]], x[faces[:, 2]] - x[faces[:, 0]])
    vn = np.zeros_like(x)
    for k in range(3):
        np.add.at(vn, faces[:, k], fn)
    return vn / np.maximum(np.linalg.norm(vn, axis=1, keepdims=True), 1e-12)


def grid_faces(n, offset=0, flip=False):
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel() + offset
    b, c, d = a + n, a + n + 1, a + 1
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return tris[:, ::-1] if flip else tris


def boundary(n):
    """The grid's edge loop, in order."""
    loop = [(0, j) for j in range(n)] + [(i, n - 1) for i in range(1, n)]
    loop += [(n - 1, j) for j in range(n - 2, -1, -1)] + [(i, 0) for i in range(n - 2, 0, -1)]
    return np.array([i * n + j for i, j in loop])


def write_obj(path, cloth, thickness, note):
    """The front sheet, the back sheet `thickness` behind it, and the edge strip."""
    n, x = cloth.n, cloth.x
    front = grid_faces(n)
    # The front faces the side the cloth was dropped from (+z before the drop).
    if np.mean(normals(x, front)[:, 2]) < 0:
        front = front[:, ::-1]
    vn = normals(x, front)
    m = len(x)
    back = front[:, ::-1] + m
    loop = boundary(n)
    strip = []
    for k in range(len(loop)):
        a, b = loop[k], loop[(k + 1) % len(loop)]
        strip += [(a, b + m, b), (a, a + m, b + m)]
    positions = np.concatenate([x, x - thickness * vn])
    uv = np.concatenate([cloth.rest_uv, cloth.rest_uv])
    faces = np.concatenate([front, back, np.array(strip)])
    _write(path, positions, uv, np.concatenate([vn, -vn]), faces, note)


def pillow(size, thickness, n, centre, turn_deg, folds, fold_depth):
    """A cushion resting on the floor: a top sheet bulging from a seam round a `size` square,
    `thickness` through its middle, and a flatter bottom sheet (it sags onto the floor). The
    cover is cut a little larger than its stuffing, so it gathers into `folds` uneven folds
    running in from the seam, `fold_depth` deep at the seam and gone by the middle. uv is in
    metres along the surface (the arc length along each grid line from the middle)."""
    a = np.linspace(-1.0, 1.0, n)
    ua, vb = np.meshgrid(a, a, indexing="ij")
    bulge = (1.0 - ua**2) ** 0.45 * (1.0 - vb**2) ** 0.45
    # The corners pull in, as a stuffed cushion's do.
    pinch = 1.0 - 0.07 * (ua**2 * vb**2)
    # The folds: two waves round the seam (the second breaks the first's regularity), sharpened
    # toward creases, fading from the seam to nothing at 0.35 of the way out from the middle.
    angle = np.arctan2(vb, ua)
    wave = np.sin(folds * angle + 0.7 * np.sin(3.0 * angle + 1.0))
    wave += 0.5 * np.sin((folds + 5) * angle + 2.0)
    reach = np.clip((np.hypot(ua, vb) - 0.35) / 0.5, 0.0, 1.0) ** 2
    crease = fold_depth * np.sign(wave) * np.abs(wave) ** 0.7 * reach * np.sqrt(bulge)
    half = size / 2.0
    top = np.stack([half * ua * pinch, half * vb * pinch, thickness * 0.62 * bulge - crease], -1)
    bottom = np.stack([half * ua * pinch, half * vb * pinch, -thickness * 0.38 * bulge], -1)
    rot = _rotation(turn_deg, 0.0)
    lift = np.array([centre[0], centre[1], thickness * 0.38 + centre[2]])
    sheets = [x.reshape(-1, 3) @ rot.T + lift for x in (top, bottom)]
    uvs = [_arc_uv(x.reshape(n, n, 3)) for x in (top, bottom)]
    return sheets, uvs


def _arc_uv(x):
    """uv by arc length along the grid lines, from the middle line."""
    n = x.shape[0]
    du = np.linalg.norm(np.diff(x, axis=0), axis=-1)
    dv = np.linalg.norm(np.diff(x, axis=1), axis=-1)
    u = np.concatenate([np.zeros((1, n)), np.cumsum(du, axis=0)], axis=0)
    v = np.concatenate([np.zeros((n, 1)), np.cumsum(dv, axis=1)], axis=1)
    u -= u[n // 2 : n // 2 + 1, :] - u[n // 2, n // 2]
    v -= v[:, n // 2 : n // 2 + 1] - v[n // 2, n // 2]
    return np.stack([u, v], axis=-1).reshape(-1, 2) - [u.min(), v.min()]


def piping(loop_points, radius, sides=8):
    """A tube of `radius` round a closed loop of points (the cushion's seam cord), with uv in
    metres: along the cord and round it."""
    m = len(loop_points)
    verts, uv, faces = [], [], []
    along = 0.0
    for k in range(m + 1):
        p = loop_points[k % m]
        t = loop_points[(k + 1) % m] - loop_points[(k - 1) % m]
        t /= np.linalg.norm(t)
        side = np.cross(t, [0.0, 0.0, 1.0])
        side /= np.linalg.norm(side)
        up = np.cross(side, t)
        if k > 0:
            along += np.linalg.norm(p - loop_points[(k - 1) % m])
        for j in range(sides + 1):
            phi = 2 * np.pi * j / sides
            verts.append(p + radius * (np.cos(phi) * side + np.sin(phi) * up))
            uv.append((along, radius * phi))
    ring = sides + 1
    for k in range(m):
        for j in range(sides):
            a = k * ring + j
            faces += [(a, a + ring, a + ring + 1), (a, a + ring + 1, a + 1)]
    return np.array(verts), np.array(uv), np.array(faces)


def _rotation(turn_deg, tilt_deg):
    t, s = np.radians(turn_deg), np.radians(tilt_deg)
    turn = np.array([[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1]])
    tilt = np.array([[1, 0, 0], [0, np.cos(s), -np.sin(s)], [0, np.sin(s), np.cos(s)]])
    return turn @ tilt


def write_pillow(path, sheets, uvs, n, note):
    """The two sheets of a cushion, sharing their seam, and a piped cord along the seam."""
    top, bottom = sheets
    f_top = grid_faces(n)
    if np.mean(normals(top, f_top)[:, 2]) < 0:
        f_top = f_top[:, ::-1]
    f_bottom = f_top[:, ::-1] + len(top)
    seam = top[boundary(n)]
    cord, cord_uv, cord_faces = piping(seam, 0.004)
    positions = np.concatenate([top, bottom, cord])
    faces = np.concatenate([f_top, f_bottom, cord_faces + 2 * len(top)])
    vn = normals(positions, faces)
    uv = np.concatenate([uvs[0], uvs[1], cord_uv])
    _write(path, positions, uv, vn, faces, note)


def _write(path, positions, uv, vn, faces, note):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(f"# {note}\n# Written by scripts/drape/drape.py: uv in metres (u weft, v warp).\n")
        f.writelines(f"v {p[0]:.4f} {p[1]:.4f} {p[2]:.4f}\n" for p in positions)
        f.writelines(f"vt {t[0]:.4f} {t[1]:.4f}\n" for t in uv)
        f.writelines(f"vn {q[0]:.3f} {q[1]:.3f} {q[2]:.3f}\n" for q in vn)
        f.writelines(
            f"f {a + 1}/{a + 1}/{a + 1} {b + 1}/{b + 1}/{b + 1} {c + 1}/{c + 1}/{c + 1}\n"
            for a, b, c in faces
        )
    os.replace(tmp, path)


def disc_table(path, centre_xy, radius, top, leg_radius, note, segments=64):
    """A round table: a top 3 cm thick on a central leg (closed cylinders, flat-shaded)."""
    tris, verts = [], []

    def cylinder(r, z0, z1):
        base = len(verts)
        for k in range(segments):
            t = 2 * np.pi * k / segments
            x, y = centre_xy[0] + r * np.cos(t), centre_xy[1] + r * np.sin(t)
            verts.extend([(x, y, z0), (x, y, z1)])
        verts.extend([(centre_xy[0], centre_xy[1], z0), (centre_xy[0], centre_xy[1], z1)])
        c0, c1 = len(verts) - 2, len(verts) - 1
        for k in range(segments):
            a, b = base + 2 * k, base + 2 * ((k + 1) % segments)
            tris.extend([(a, b, b + 1), (a, b + 1, a + 1), (c0, b, a), (c1, a + 1, b + 1)])

    cylinder(radius, top - 0.03, top)
    cylinder(leg_radius, 0.0, top - 0.03)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(f"# {note}\n# Written by scripts/drape/drape.py.\n")
        f.writelines(f"v {x:.4f} {y:.4f} {z:.4f}\n" for x, y, z in verts)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris)
    os.replace(tmp, path)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "crates/woven-render/scenes/meshes"
    os.makedirs(out, exist_ok=True)
    # A linen tablecloth, 1.5 m square, dropped onto a round table 0.9 m across, 0.75 m high.
    print("tablecloth", file=sys.stderr)
    table = ((0.0, 0.0), 0.45, 0.75)
    cloth = simulate(
        Cloth(1.5, 75, table[0], 0.80, turn_deg=10.0),
        [("table", (np.array(table[0]), table[1], table[2])), ("floor", None)],
        seconds=2.0,
    )
    write_obj(
        os.path.join(out, "tablecloth.obj"),
        cloth,
        0.0015,
        "A 1.5 m linen tablecloth draped on a round table (radius 0.45 m, top 0.75 m) at the origin.",
    )
    # The furniture sits inside what the cloth collided with (its sharp top edge 7 mm inside the
    # rounded rim), so no edge shows through the flat triangles between the cloth's particles.
    disc_table(
        os.path.join(out, "table.obj"), table[0], table[1] - 0.012, table[2] - 0.008, 0.05, "The table."
    )
    # A satin cloth, 1.1 m square, dropped off-centre onto a round stool.
    print("satin drape", file=sys.stderr)
    stool = ((-0.88, -0.88), 0.17, 0.48)
    cloth = simulate(
        Cloth(1.1, 75, (stool[0][0] + 0.06, stool[0][1] - 0.04), 0.53, turn_deg=35.0),
        [("table", (np.array(stool[0]), stool[1], stool[2])), ("floor", None)],
        seconds=2.4,
    )
    write_obj(
        os.path.join(out, "satin-drape.obj"),
        cloth,
        0.0008,
        "A 1.1 m satin cloth dropped onto a round stool (radius 0.17 m, top 0.48 m) at (-0.88, -0.88).",
    )
    disc_table(
        os.path.join(out, "stool.obj"), stool[0], stool[1] - 0.012, stool[2] - 0.008, 0.04, "The stool."
    )
    # Two cushions on the floor, side by side. The shot silk's is turned so that the sun of the
    # showcase lies between its weft's and its warp's planes: its folds, turning either way,
    # swing between its two dyes. Taffeta is crisp and gathers into deeper folds than denim.
    n = 73
    for name, size, thick, centre, turn, folds, depth in [
        ("cushion-shot-silk", 0.45, 0.14, (0.62, -1.05, 0.0), 65.0, 9, 0.012),
        ("cushion-twill", 0.42, 0.13, (1.05, -0.62, 0.0), -12.0, 7, 0.007),
    ]:
        sheets, uvs = pillow(size, thick, n, centre, turn, folds, depth)
        write_pillow(os.path.join(out, f"{name}.obj"), sheets, uvs, n, f"A {size} m cushion.")


if __name__ == "__main__":
    main()
