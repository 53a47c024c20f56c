"""woven.batch: fits and tables of many items on any executor (docs/batch.md).

The first test is the batch layer's contract: a 2-worker dask LocalCluster with processes fits three small
datasets and builds two small tables; the results equal the serial run's bit for bit, an item
given a corrupt file fails alone, and a rerun after deleting one result recomputes only that one.
The rest are cheap: the serial and thread-pool executors, progress, errors, the bindings.
"""

import concurrent.futures
import json
import os

import numpy as np
import pytest

import woven
from woven import batch

from conftest import REPO, SMALL

CURET = REPO / "data" / "curet" / "abrdf.dat"
DATASETS = [f"{CURET}#curet-01-felt", f"{CURET}#curet-44-linen", f"{CURET}#curet-46-cotton"]
# A cloth fit in seconds: yarns of one orientation (the sateen's; belt-cloth's twisted yarns
# cost ten times more), few starts, short runs, small subsets.
TINY = dict(init="polyester-sateen", starts=2, refine=1, max_iterations=3, subset=32,
            final_subset=64, seed=3)
TABLES = ["polyester-sateen", "silk"]
GRID = dict(SMALL, n_theta=6, n_phi=3, n_h=15, n_h_isotropic=21, azimuth_nodes=12)

# A 4×4 diffuse square under a point light: a render in milliseconds.
SCENE = """
[camera]
origin = [0, 0, 1]
target = [0, 0, 0]
up = [0, 1, 0]
fov_deg = 10
[film]
width = 4
height = 4
spp = 4
[[light]]
type = "point"
position = [0, 0, 1]
intensity = [1, 1, 1]
[[shape]]
type = "rectangle"
corner = [-1, -1, 0]
edge_u = [2, 0, 0]
edge_v = [0, 2, 0]
material = "grey"
[material.grey]
type = "diffuse"
reflectance = [0.5, 0.5, 0.5]
"""


def fit_key(o):
    """What must be equal bit for bit between two runs of a fit."""
    return (o.dataset, o.ok, o.rms_log, o.relative_rms, o.material_toml, o.parameters)


@pytest.fixture(scope="module")
def corrupt(tmp_path_factory):
    path = tmp_path_factory.mktemp("data") / "corrupt.csv"
    path.write_text("theta_i,phi_i,theta_r,phi_r,value\n0.1,0,0.2,3.1,0.3\n0.2,0,oops,3.1,0.2\n")
    return str(path)


@pytest.fixture(scope="module")
def serial(corrupt, tmp_path_factory):
    """The serial run: three fits and a corrupt file, two tables."""
    fits = batch.fit_many(DATASETS + [corrupt], progress=False, **TINY)
    tables = batch.tabulate_many(
        TABLES, tmp_path_factory.mktemp("serial-tables"), progress=False, **GRID
    )
    return fits, tables


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        yield client


def test_dask_cluster_matches_serial_and_reruns_only_what_is_missing(
    serial, cluster, corrupt, tmp_path
):
    fits, tables = serial
    executor = cluster.get_executor()
    out = tmp_path / "results"
    got = batch.fit_many(DATASETS + [corrupt], executor=executor, output=out, progress=False, **TINY)
    got_tables = batch.tabulate_many(TABLES, out, executor, progress=False, **GRID)

    # In input order, bit for bit the serial run's; the corrupt file fails alone.
    assert [o.dataset for o in got] == DATASETS + [corrupt]
    assert [fit_key(o) for o in got] == [fit_key(o) for o in fits]
    assert [o.ok for o in got] == [True, True, True, False]
    assert "corrupt.csv" in got[3].error and "oops" in got[3].error, got[3].error
    assert [(t.material, t.sha256, t.dims) for t in got_tables] == [
        (t.material, t.sha256, t.dims) for t in tables
    ]
    assert all(t.ok for t in got_tables)
    # Each worker ran with its share of the cores: 2 workers of one slot each.
    share = max(1, batch._cores() // 2)
    assert {o.threads for o in got[:3]} == {share}, [o.threads for o in got]

    # Written per item: a fit's record and material, a table and its record.
    records = sorted(p.name for p in out.iterdir())
    assert len([r for r in records if r.endswith(".cloth.json")]) == 3, records
    assert len([r for r in records if r.endswith(".cloth.toml")]) == 3, records
    assert len([r for r in records if r.endswith(".wtab")]) == 2, records
    assert not [r for r in records if r.endswith(".tmp")], records

    # A rerun after deleting one result recomputes that one only.
    linen = next(p for p in out.iterdir() if "curet-44-linen" in p.name and p.suffix == ".json")
    linen.unlink()
    (out / next(r for r in records if r.startswith("silk") and r.endswith(".wtab"))).unlink()
    again = batch.fit_many(DATASETS + [corrupt], executor=executor, output=out, progress=False,
                           **TINY)
    again_tables = batch.tabulate_many(TABLES, out, executor, progress=False, **GRID)
    assert [o.reused for o in again] == [True, False, True, False]
    assert [fit_key(o) for o in again] == [fit_key(o) for o in fits]
    assert [t.reused for t in again_tables] == [True, False]
    assert [t.sha256 for t in again_tables] == [t.sha256 for t in tables]


def test_woven_batch_command_writes_the_comparison_and_materials(cluster, tmp_path, cli):
    from woven import _batch_cli

    out = tmp_path / "cmd"
    address = cluster.scheduler.address
    args = ["fit", "--data", DATASETS[0], DATASETS[1], "--models", "lambert,sheen",
            "--scheduler", address, "-o", str(out), "--quiet", "--seed", "3"]
    assert _batch_cli.main(args) == 0
    table = (out / "comparison.md").read_text()
    assert table.startswith("| dataset | points | lambert | sheen |"), table
    assert "curet-01-felt" in table and "curet-44-linen" in table
    assert len(list(out.glob("*.lambert.toml"))) == len(list(out.glob("*.sheen.toml"))) == 2
    # The same table `woven fit --compare` prints for the same fits.
    want = cli("fit", "--compare", DATASETS[0], DATASETS[1], "--models", "lambert,sheen",
               "--seed", "3")
    assert table == want


def test_serial_and_thread_pool_agree():
    # The sheen baseline: a fit in a fraction of a second.
    fits = batch.fit_many(DATASETS, "sheen", progress=False)
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        got = batch.fit_many(DATASETS, "sheen", executor=pool, progress=False)
    assert [fit_key(o) for o in got] == [fit_key(o) for o in fits]
    assert all(o.ok for o in got) and got[0].material_toml.count('model = "sheen"') == 1


class _Recorder(concurrent.futures.Executor):
    """Records what is submitted, in order, and runs nothing (each task fails at once)."""

    def __init__(self):
        self.submitted = []

    def submit(self, fn, *args, **kwargs):
        self.submitted.append(args[:2])
        future = concurrent.futures.Future()
        future.set_exception(RuntimeError("not run"))
        return future


def test_the_dearest_fits_are_submitted_first():
    pairs = [(d, m) for d in DATASETS[:2] for m in ("lambert", "cloth", "sheen", "microcylinder")]
    recorder = _Recorder()
    outcomes = batch._fit_pairs(pairs, recorder, None, False, None, {}, "test")
    models = [m for _, m in recorder.submitted]
    assert models == ["cloth"] * 2 + ["microcylinder"] * 2 + ["sheen"] * 2 + ["lambert"] * 2
    # Within a model the input order stands, and the outcomes keep the input order.
    assert [d for d, m in recorder.submitted if m == "cloth"] == DATASETS[:2]
    assert [(o.dataset, o.model) for o in outcomes] == pairs
    assert all(not o.ok and "not run" in o.error for o in outcomes)


def test_outcomes_follow_the_contract(serial):
    fits, _ = serial
    o = fits[1]
    assert o.ok and o.error is None and o["ok"] is True
    assert o.dataset == DATASETS[1] and o.name == "curet-44-linen" and o.points == 205
    assert 0 < o.rms_log < 2
    assert "Fitted by `woven fit`" in o.material_toml
    woven.Material.from_toml(o.material_toml)  # a usable material file
    bad = fits[3]
    assert not bad.ok and bad.rms_log is None and bad.material_toml is None and bad.error


def test_fit_matches_the_command_line(tmp_path, cli):
    result = woven.fit(DATASETS[1], "sheen", seed=3, starts=4)
    out = tmp_path / "linen.toml"
    cli("fit", "--data", DATASETS[1], "--model", "sheen", "--seed", "3", "--starts", "4", "-o", out)
    assert result["material_toml"] == out.read_text()
    assert result["points"] == 205 and result["dataset"] == "curet-44-linen"


def test_progress_counts_done_failed_and_remaining(corrupt):
    seen = []
    batch.fit_many([corrupt, DATASETS[0]], model="lambert", progress=seen.append)
    assert [(p.done, p.failed, p.remaining, p.total) for p in seen] == [(0, 1, 1, 2), (1, 1, 0, 2)]
    assert seen[-1].eta == 0.0 and "remaining 0 of 2" in seen[-1].line()


def test_bad_arguments_name_the_parameter():
    with pytest.raises(TypeError, match="unknown option.*stars"):
        batch.fit_many(DATASETS, stars=3)
    with pytest.raises(TypeError, match="`datasets`"):
        batch.fit_many(DATASETS[0])
    with pytest.raises(ValueError, match="`threads` = 0"):
        batch.fit_many(DATASETS, threads=0)
    with pytest.raises(ValueError, match="`output` = None"):
        batch.tabulate_many(TABLES, None)
    with pytest.raises(ValueError, match="cloht"):
        woven.fit(DATASETS[0], "cloht")
    with pytest.raises(ValueError, match='`residual` = "square"'):
        woven.fit(DATASETS[0], residual="square")
    with pytest.raises(OSError, match="no-such-file"):
        woven.fit("no-such-file.csv")
    with pytest.raises(ValueError, match="`threads` = 0"):
        woven.set_threads(0)
    out = batch.fit_many(DATASETS[:1], model="cloht", progress=False)
    assert not out[0].ok and "cloht" in out[0].error


def test_datasets_lists_a_file_of_several():
    names = woven.datasets(str(CURET))
    assert f"{CURET}#curet-44-linen" in names and len(names) > 11


def test_render_many_writes_images_and_reuses_them(tmp_path):
    scene = tmp_path / "square.toml"
    scene.write_text(SCENE)
    direct = woven.render(scene)
    centre = direct["pixels"][2, 2, 0]
    assert abs(centre - 0.5 / np.pi) < 2e-3, centre
    out = tmp_path / "renders"
    first = batch.render_many([scene, tmp_path / "missing.toml"], out, progress=False)
    assert first[0].ok and not first[1].ok and "missing.toml" in first[1].error
    assert (out / os.path.basename(first[0].path)).exists()
    again = batch.render_many([scene], out, progress=False)
    assert again[0].reused and again[0].sha256 == first[0].sha256
    bare = batch.render_many([scene], progress=False)
    assert np.array_equal(bare[0].pixels, direct["pixels"])
    record = json.loads((out / (os.path.basename(first[0].path)[:-4] + ".render.json")).read_text())
    assert record["outcome"]["sha256"] == first[0].sha256
