"""Shared fixtures: the repository's paths, the `woven` command-line binary, small tables."""

import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

import woven

REPO = pathlib.Path(__file__).resolve().parents[3]
VECTORS = REPO / "crates" / "woven" / "tests" / "data" / "vectors"

# With CI set, a skipped test (no Mitsuba, no libLLVM for its LLVM variant, no `woven` binary)
# fails the run: scripts/ci_no_skips.py.
sys.path.insert(0, str(REPO / "scripts"))
from ci_no_skips import pytest_sessionfinish, pytest_terminal_summary  # noqa: E402, F401


def _find_cli():
    """The `woven` binary: $WOVEN_BIN, else the release build in the cargo target folder."""
    env = os.environ.get("WOVEN_BIN")
    if env:
        return env
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    path = target / "release" / "woven"
    if path.exists():
        return str(path)
    return shutil.which("woven")


@pytest.fixture(scope="session")
def cli():
    """Runs the `woven` binary with arguments; returns its standard output."""
    binary = _find_cli()
    if binary is None:
        pytest.skip("no `woven` binary: cargo build --release -p woven-cli, or set WOVEN_BIN")

    def run(*args, **kw):
        done = subprocess.run([binary, *map(str, args)], capture_output=True, text=True, **kw)
        assert done.returncode == 0, f"woven {' '.join(map(str, args))}: {done.stderr}"
        return done.stdout

    return run


# A coarse grid: a table in about a second, every code path of the full one.
SMALL = dict(n_theta=8, n_phi=4, n_h=21, n_h_isotropic=31, azimuth_nodes=24)


@pytest.fixture(scope="session")
def sateen():
    return woven.Material.preset("polyester-sateen")


@pytest.fixture(scope="session")
def sateen_table(sateen):
    return woven.Table.build(sateen, progress=False, colour=True, **SMALL)


@pytest.fixture(scope="session")
def flat():
    return woven.Material.from_toml(
        'name = "flat"\n[fiber]\neta = 1.5\nroughness = 0.3\ndiffuse = 0.1\n'
    )


@pytest.fixture(scope="session")
def flat_table(flat):
    return woven.Table.build(flat, progress=False, **SMALL)


def random_dirs(rng, n, upper=True):
    """`n` directions uniform on the upper hemisphere (or the sphere)."""
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    if upper:
        d[:, 2] = np.abs(d[:, 2])
    return d
