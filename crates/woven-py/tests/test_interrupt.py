"""Long calls stop for Ctrl-C: a call in a child process gets SIGINT half a second in and raises
KeyboardInterrupt promptly, on all cores (the GIL released) and on the calling thread alike:
the batches, and the libraries' long computations (table builds, fits, renders, sweeps,
exports), which leave nothing half made behind."""

import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import REPO

CHILD = r"""
import os
import sys
import numpy as np
import woven

repo, out = sys.argv[2], sys.argv[3]
scene = os.path.join(out, "plane.toml")
with open(scene, "w") as f:
    f.write('''
[camera]
origin = [0, 0, 1]
target = [0, 0, 0]
up = [0, 1, 0]
fov_deg = 10
[[light]]
type = "point"
position = [0, 0, 1]
intensity = [1, 1, 1]
[[shape]]
type = "rectangle"
corner = [-1, -1, 0]
edge_u = [2, 0, 0]
edge_v = [0, 2, 0]
material = "sateen"
[material.sateen]
type = "woven"
material = "polyester-sateen"
''')

slow = woven.Material.preset("belt-cloth").build()    # about a millisecond a pair
sateen = woven.Material.preset("polyester-sateen").build()
belt = woven.Material.preset("belt-cloth")
up = np.array([0.0, 0.6, 0.8])
calls = {
    "parallel": lambda: slow.eval(np.broadcast_to(up, (10**6, 3)), up),
    "serial": lambda: slow.eval(np.broadcast_to(up, (woven.PARALLEL_MIN - 1, 3)), up),
    "albedo": lambda: sateen.albedo(np.full(10**4, 0.5)),
    # Each of these takes a minute or more uninterrupted on two cores.
    "table_build": lambda: woven.Table.build(belt, progress=False),
    "table_cached": lambda: woven.Table.cached(belt, grid="model", progress=False),
    "surface": lambda: woven.Surface(belt),
    "fit": lambda: woven.fit(repo + "/data/curet/abrdf.dat#curet-44-linen", init="belt-cloth",
                             starts=2000),
    "render": lambda: woven.render(scene, os.path.join(out, "image.exr"), width=512,
                                   height=512, spp=4096),
    "gonio": lambda: woven.gonio(slow, tilt_deg=np.linspace(-40, 40, 10**5)),
    "export_merl": lambda: woven.export_merl(woven.Material.preset("silk").build(),
                                             os.path.join(out, "silk.binary")),
}
print("ready", flush=True)
try:
    calls[sys.argv[1]]()
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""

LONG = ["table_build", "table_cached", "surface", "fit", "render", "gonio", "export_merl"]


@pytest.mark.parametrize("call", ["parallel", "serial", "albedo", *LONG])
def test_ctrl_c_interrupts_a_long_call(call, tmp_path):
    cache = tmp_path / "cache"  # empty: tables are built, not read
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, call, str(REPO), str(tmp_path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "XDG_CACHE_HOME": str(cache)},
    )
    try:
        assert child.stdout.readline().strip() == "ready", child.stderr.read()
        time.sleep(0.5)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, err = child.communicate(timeout=5)
        waited = time.monotonic() - sent
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    assert out.strip() == "interrupted", f"stdout {out!r}, stderr {err!r}"
    assert waited < 2.0, f"KeyboardInterrupt came {waited:.2f} s after SIGINT"
    # Nothing half made: no image or MERL file, no table in the cache, no temporary file.
    left = sorted(p.name for p in tmp_path.rglob("*") if p.is_file() and p.name != "plane.toml")
    assert left == [], f"left behind: {left}"
