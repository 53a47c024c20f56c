"""Many fits, tables or renders at once, on any ``concurrent.futures.Executor``.

::

    import woven.batch
    outcomes = woven.batch.fit_many(["data/curet/abrdf.dat#linen", "data/merl/beige-fabric.grid.csv"],
                                    model="cloth", output="results/")
    for o in outcomes:
        print(o.dataset, o.ok, o.rms_log if o.ok else o.error)

    from dask.distributed import Client, LocalCluster          # pip install "woven[dask]"
    client = Client(LocalCluster(n_workers=2, threads_per_worker=1))
    outcomes = woven.batch.fit_many(datasets, executor=client.get_executor())

``fit_many``, ``tabulate_many`` and ``render_many`` take a list of items (datasets, materials,
scene files) and return one outcome per item, in input order. ``executor`` is any
``concurrent.futures.Executor`` (a ``ThreadPoolExecutor``, a dask client's ``get_executor()``),
a ``dask.distributed.Client``, or a scheduler address (``"tcp://host:8786"``, needs dask); None
runs the items one after another in this process. What the batch layer guarantees:

- Tasks carry plain data (strings, numbers, dicts), never live objects, so any executor that
  pickles its tasks can run them; the results come back as plain data too.
- Each worker caps rayon's threads (fits, table builds, renders) to its share of its machine's
  cores: ``threads`` per task, else the share the executor implies (a dask worker: its host's
  cores (its CPU affinity: a SLURM allocation's, not the node's) divided among the task slots
  on that host; a process pool: the cores over its workers;
  in-process pools: all cores, as the pool is shared). Each outcome records the size the worker
  ran with (``threads``).
- Results are those of the serial run bit for bit: every fit is deterministic for its seed, and
  tables and renders do not depend on the number of threads.
- One bad item fails alone: its outcome has ``ok=False`` and ``error`` (the library's message),
  and the others run.
- With ``output`` (a folder), each finished item is written there at once, atomically (a
  temporary file renamed into place): a fit as ``NAME.MODEL.json`` (the outcome) and
  ``NAME.MODEL.toml`` (the fitted material, as ``woven fit -o`` writes it), a table as
  ``NAME.wtab`` and ``NAME.wtab.json``, a render as ``NAME.exr`` (or ``.png``) and
  ``NAME.render.json``. A rerun reuses every item whose record exists and was made with the same
  options (its outcome has ``reused=True``) and computes only the rest, so an interrupted batch
  loses nothing. Failures are not recorded: a rerun tries them again. Tables and renders are
  written by the worker, so on a cluster ``output`` must be a folder every worker sees.
- Progress: items done, failed and remaining and an estimate of the time left, on
  ``sys.stderr`` (``progress=None`` or True: one line updated in place on a terminal, a line per
  item otherwise), nothing (False), or a callable that receives a ``Progress`` after each item.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import hashlib
import json
import os
import pathlib
import re
import sys
import tempfile
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

__all__ = [
    "FitOutcome",
    "TableOutcome",
    "RenderOutcome",
    "Progress",
    "fit_many",
    "tabulate_many",
    "render_many",
    "make_executor",
]

# The keyword options `woven.fit` takes (the rest of fit_many's **options is an error).
FIT_OPTIONS = (
    "init",
    "fix",
    "free",
    "seed",
    "starts",
    "refine",
    "max_iterations",
    "subset",
    "final_subset",
    "residual",
    "saturation",
)
# The keyword options `woven.Table.build` takes besides the material (threads and progress are
# the batch layer's).
TABLE_OPTIONS = (
    "wavelength_nm",
    "grid",
    "n_theta",
    "theta_max_deg",
    "n_phi",
    "n_h",
    "n_h_isotropic",
    "azimuth_nodes",
    "colour",
    "exact_regions",
)
# The keyword options `woven.render` takes besides the scene, the output and threads.
RENDER_OPTIONS = ("spp", "width", "height", "seed", "cache")
# Bumped when a record's layout changes, so older records are recomputed, never misread.
RECORD_VERSION = 1

# Each model's median seconds per fit on one core, in the bundled corpus's run (docs/fitting.md,
# "The whole corpus"; lambert and microfacet under 0.2 s): the order in which fit batches submit
# their items, dearest first.
FIT_COST = {"cloth": 303.6, "microcylinder": 7.9, "fiber": 6.9, "sheen": 0.3}


class _Record:
    """Outcomes read like the dict they are stored as: ``o.ok`` or ``o["ok"]``."""

    def __getitem__(self, key: str) -> Any:
        if key not in self.keys():
            raise KeyError(key)
        return getattr(self, key)

    def keys(self) -> List[str]:
        return [f.name for f in dataclasses.fields(self)]

    def to_dict(self) -> Dict[str, Any]:
        return {k: getattr(self, k) for k in self.keys()}


@dataclasses.dataclass
class FitOutcome(_Record):
    """One dataset's fit: ``dataset`` as given, ``ok``, ``error`` (the message when not ok),
    ``rms_log`` and ``relative_rms`` (the fit's errors), ``material_toml`` (what ``woven fit -o``
    writes), ``name`` (the dataset's own name), ``points`` (measurements), ``parameters``
    (name → fitted value), ``seconds`` (the fit's wall time), ``threads`` (the worker's rayon
    threads) and ``reused`` (read back from ``output`` rather than computed)."""

    dataset: str
    model: str
    ok: bool
    error: Optional[str] = None
    rms_log: Optional[float] = None
    relative_rms: Optional[float] = None
    material_toml: Optional[str] = None
    name: Optional[str] = None
    points: Optional[int] = None
    parameters: Optional[Dict[str, float]] = None
    seconds: float = 0.0
    threads: Optional[int] = None
    reused: bool = False


@dataclasses.dataclass
class TableOutcome(_Record):
    """One material's table: ``material`` as given, ``ok``, ``error``, ``path`` (the ``.wtab``
    written, with ``output``), ``sha256`` (of the table file's bytes), ``dims``, ``seconds``,
    ``threads`` and ``reused``."""

    material: str
    ok: bool
    error: Optional[str] = None
    path: Optional[str] = None
    sha256: Optional[str] = None
    dims: Optional[List[int]] = None
    seconds: float = 0.0
    threads: Optional[int] = None
    reused: bool = False


@dataclasses.dataclass
class RenderOutcome(_Record):
    """One scene's render: ``scene`` as given, ``ok``, ``error``, ``path`` (the image written,
    with ``output``), ``sha256`` (of the linear float64 pixels), ``width``, ``height``, ``spp``,
    ``seconds``, ``threads``, ``reused``, and ``pixels`` (the linear RGB image, (height, width,
    3), without ``output`` only)."""

    scene: str
    ok: bool
    error: Optional[str] = None
    path: Optional[str] = None
    sha256: Optional[str] = None
    width: Optional[int] = None
    height: Optional[int] = None
    spp: Optional[int] = None
    seconds: float = 0.0
    threads: Optional[int] = None
    reused: bool = False
    pixels: Any = None


@dataclasses.dataclass
class Progress:
    """Where a batch stands: items ``done`` (finished well, reused ones included), ``failed``,
    ``remaining``, ``total``, ``elapsed`` seconds and ``eta`` (seconds left, from the mean time
    of the items computed so far; None before the first)."""

    done: int
    failed: int
    remaining: int
    total: int
    elapsed: float
    eta: Optional[float]

    def line(self) -> str:
        """The progress as one line: ``done 3, failed 1, remaining 7 of 11; 1m20s left``."""
        eta = "estimating" if self.eta is None else f"{_duration(self.eta)} left"
        return (
            f"done {self.done}, failed {self.failed}, remaining {self.remaining} of "
            f"{self.total}; {_duration(self.elapsed)} elapsed, {eta}"
        )


def _duration(seconds: float) -> str:
    seconds = max(0, int(round(seconds)))
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"


# ---------------------------------------------------------------------------------------------
# Executors and the threads each worker may use


def make_executor(executor: Any) -> Optional[concurrent.futures.Executor]:
    """The executor ``executor`` names: None (serial), an Executor as it is, a
    ``dask.distributed.Client`` (its ``get_executor()``), or a scheduler address string (a new
    client of it). Raises TypeError for anything else, ImportError naming the extra when dask
    is needed and missing."""
    if executor is None or isinstance(executor, concurrent.futures.Executor):
        return executor
    if isinstance(executor, str):
        try:
            from dask.distributed import Client
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError(
                f"`executor` = {executor!r} is a scheduler address, which needs dask: "
                'pip install "woven[dask]"'
            ) from e
        return Client(executor).get_executor()
    if hasattr(executor, "get_executor") and hasattr(executor, "scheduler_info"):
        return executor.get_executor()
    raise TypeError(
        f"`executor` = {executor!r}: expected None (serial), a concurrent.futures.Executor, a "
        "dask.distributed.Client or a scheduler address such as 'tcp://host:8786'"
    )


def _cores() -> int:
    """The cores this process may run on: its CPU affinity (what a SLURM or cgroup allocation
    grants), else the machine's count."""
    try:
        return len(os.sched_getaffinity(0)) or 1
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _thread_plan(executor: Optional[concurrent.futures.Executor], threads: Optional[int]) -> Dict:
    """What each task needs to size its worker's pool: plain data, resolved in the worker.

    ``{"threads": n}`` fixes it; ``{"slots": {host: task slots}}`` (dask) lets each worker take
    its host's cores in proportion to its own slots; ``{}`` leaves the pool alone (serial runs
    and in-process pools, which share this process's pool)."""
    if threads is not None:
        if not isinstance(threads, int) or threads < 1:
            raise ValueError(f"`threads` = {threads!r}: expected a whole number of threads >= 1")
        return {"threads": threads}
    if executor is None or isinstance(executor, concurrent.futures.ThreadPoolExecutor):
        return {}
    if isinstance(executor, concurrent.futures.ProcessPoolExecutor):
        workers = getattr(executor, "_max_workers", None) or _cores()
        return {"threads": max(1, _cores() // workers)}
    client = getattr(executor, "_client", None)
    if client is not None and hasattr(client, "scheduler_info"):
        slots: Dict[str, int] = {}
        for w in client.scheduler_info().get("workers", {}).values():
            host = w.get("host", "")
            slots[host] = slots.get(host, 0) + int(w.get("nthreads", 1))
        return {"slots": slots}
    return {}


def _cap_threads(plan: Dict) -> Optional[int]:
    """In the worker: caps rayon's pools to this worker's share (RAYON_NUM_THREADS for the pools
    built per call, `woven.set_threads` for the global one) and returns the global pool's size."""
    import woven

    n = plan.get("threads")
    if n is None and "slots" in plan:
        try:
            from distributed import get_worker

            worker = get_worker()
            host = worker.address.split("://")[-1].rsplit(":", 1)[0]
            mine = int(worker.state.nthreads)
            here = int(plan["slots"].get(host, mine))
            n = max(1, _cores() * mine // max(here, 1))
        except (ImportError, ValueError, AttributeError):
            n = None
    if n is None:
        return woven.threads()
    os.environ["RAYON_NUM_THREADS"] = str(n)
    return woven.set_threads(n)


# ---------------------------------------------------------------------------------------------
# Records on disk


def _slug(item: str) -> str:
    """A file name for an item: its readable tail and a hash of the whole (no collisions)."""
    tail = os.path.basename(item.replace("#", "_")) or "item"
    tail = re.sub(r"[^A-Za-z0-9._-]+", "_", tail)[:60]
    digest = hashlib.sha256(item.encode()).hexdigest()[:8]
    return f"{tail}-{digest}"


def _write_atomically(path: pathlib.Path, data: Union[str, bytes]) -> None:
    """Writes `data` to a temporary file beside `path`, then renames it into place."""
    raw = data.encode() if isinstance(data, str) else data
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _read_record(path: pathlib.Path, key: Dict) -> Optional[Dict]:
    """The record at `path` if it was made for `key` (same item and options), else None."""
    try:
        record = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(record, dict) or record.get("key") != key:
        return None
    return record.get("outcome")


def _output_dir(output: Union[None, str, os.PathLike]) -> Optional[pathlib.Path]:
    if output is None:
        return None
    path = pathlib.Path(output)
    if path.exists() and not path.is_dir():
        raise ValueError(f"`output` = {str(output)!r}: expected a folder, found a file")
    path.mkdir(parents=True, exist_ok=True)
    return path


def _check_options(options: Dict, allowed: Sequence[str], function: str) -> None:
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise TypeError(
            f"{function}: unknown option(s) {', '.join(unknown)}; expected any of "
            f"{', '.join(allowed)}"
        )


def _check_items(items: Any, name: str) -> List[str]:
    if isinstance(items, (str, bytes, os.PathLike)):
        raise TypeError(f"`{name}` = {items!r}: expected a list of them, not one")
    out = []
    for item in items:
        if not isinstance(item, (str, os.PathLike)):
            raise TypeError(f"`{name}`: {item!r} is not a path or name (str)")
        out.append(os.fspath(item))
    return out


def _error_message(e: BaseException) -> str:
    text = str(e) or type(e).__name__
    return text if isinstance(e, (ValueError, OSError)) else f"{type(e).__name__}: {text}"


# ---------------------------------------------------------------------------------------------
# The tasks: module-level functions of plain data, run in the workers


def _fit_task(dataset: str, model: str, options: Dict, plan: Dict) -> Dict:
    """Fits one dataset in a worker; never raises (a failure is an outcome)."""
    start = time.perf_counter()
    out: Dict[str, Any] = {"dataset": dataset, "model": model}
    try:
        out["threads"] = _cap_threads(plan)
        import woven

        result = woven.fit(dataset, model, **options)
        out.update(
            ok=True,
            rms_log=result["rms_log"],
            relative_rms=result["relative_rms"],
            material_toml=result["material_toml"],
            name=result["dataset"],
            points=result["points"],
            parameters=dict(result["parameters"]),
        )
    except Exception as e:  # one bad item never stops the batch
        out.update(ok=False, error=_error_message(e))
    out["seconds"] = time.perf_counter() - start
    return out


def _sha256_file(path: Union[str, os.PathLike]) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _table_task(material: str, options: Dict, path: str, plan: Dict) -> Dict:
    """Builds one material's table in a worker and saves it (atomically) to `path`."""
    start = time.perf_counter()
    out: Dict[str, Any] = {"material": material}
    try:
        threads = _cap_threads(plan)
        out["threads"] = threads
        import woven

        table = woven.Table.build(
            material, progress=False, threads=threads if plan else 0, **options
        )
        table.save(path)
        out.update(ok=True, path=path, sha256=_sha256_file(path), dims=list(table.dims))
    except Exception as e:
        out.update(ok=False, error=_error_message(e))
    out["seconds"] = time.perf_counter() - start
    return out


def _render_task(scene: str, options: Dict, path: Optional[str], plan: Dict) -> Dict:
    """Renders one scene in a worker, writing the image (atomically) to `path` when given."""
    start = time.perf_counter()
    out: Dict[str, Any] = {"scene": scene}
    try:
        out["threads"] = _cap_threads(plan)
        import woven

        image = woven.render(scene, path, **options)
        pixels = image["pixels"]
        out.update(
            ok=True,
            path=path,
            sha256=hashlib.sha256(pixels.tobytes()).hexdigest(),
            width=image["width"],
            height=image["height"],
            spp=image["spp"],
        )
        if path is None:
            out["pixels"] = pixels
    except Exception as e:
        out.update(ok=False, error=_error_message(e))
    out["seconds"] = time.perf_counter() - start
    return out


# ---------------------------------------------------------------------------------------------
# The driver


class _Reporter:
    """Counts outcomes and shows the progress (stderr, a callable, or nothing)."""

    def __init__(self, progress: Any, total: int, what: str):
        if progress is None or progress is True:
            self.sink: Optional[Callable[[Progress], None]] = self._stderr
        elif callable(progress):
            self.sink = progress
        elif progress is False:
            self.sink = None
        else:
            raise TypeError(
                f"`progress` = {progress!r}: expected None or True (a line on stderr), False "
                "(nothing) or a callable taking a woven.batch.Progress"
            )
        self.total, self.what = total, what
        self.done = self.failed = self.computed = 0
        self.start = time.perf_counter()

    def _stderr(self, p: Progress) -> None:
        # On a terminal one line updated in place; in a log, a line per item.
        if getattr(sys.stderr, "isatty", lambda: False)():
            end = "\n" if p.remaining == 0 else ""
            sys.stderr.write(f"\r{self.what}: {p.line()}\x1b[K{end}")
        else:
            sys.stderr.write(f"{self.what}: {p.line()}\n")
        sys.stderr.flush()

    def count(self, ok: bool, reused: bool) -> None:
        if ok:
            self.done += 1
        else:
            self.failed += 1
        if not reused:
            self.computed += 1
        if self.sink is None:
            return
        elapsed = time.perf_counter() - self.start
        remaining = self.total - self.done - self.failed
        # The rate of the items computed in this run (reused ones cost nothing).
        eta = elapsed / self.computed * remaining if self.computed else None
        if remaining == 0:
            eta = 0.0
        self.sink(Progress(self.done, self.failed, remaining, self.total, elapsed, eta))


@dataclasses.dataclass
class _Job:
    index: int
    function: Callable[..., Dict]
    args: tuple


def _drive(
    jobs: List[_Job],
    executor: Optional[concurrent.futures.Executor],
    finish: Callable[[int, Dict], None],
) -> None:
    """Runs `jobs` serially (no executor) or on `executor`, calling `finish(index, result)` as
    each completes; a task that dies (a lost worker) becomes a failed result."""
    if executor is None:
        for job in jobs:
            finish(job.index, job.function(*job.args))
        return
    futures = {executor.submit(job.function, *job.args): job for job in jobs}
    try:
        for future in concurrent.futures.as_completed(futures):
            job = futures[future]
            try:
                result = future.result()
            except Exception as e:
                result = {"ok": False, "error": f"the task failed: {_error_message(e)}"}
            finish(job.index, result)
    except BaseException:
        for future in futures:
            future.cancel()
        raise


@dataclasses.dataclass
class _Batch:
    """One batch's rules per item (by index), which `_run` applies: where the item's record
    lives (None: nothing kept), the key it was made for, whether a stored record still stands,
    the task that computes it (given the thread plan), the outcome a result or record becomes,
    and what is written before the record (a fitted material)."""

    what: str
    count: int
    record: Callable[[int], Optional[pathlib.Path]]
    key: Callable[[int], Dict]
    task: Callable[[int, Dict], _Job]
    outcome: Callable[[int, Dict], Any]
    stands: Callable[[int, Dict], bool] = lambda index, stored: True
    before_record: Callable[[int, Any], None] = lambda index, outcome: None
    # A rough cost: the dearest items are submitted first, so a many-worker run's last wave is
    # not one long item started late (the outcomes keep the input order).
    cost: Callable[[int], float] = lambda index: 0.0


def _run(batch: _Batch, executor: Optional[concurrent.futures.Executor], progress: Any,
         threads: Optional[int]) -> List[Any]:
    """Reuses every item whose record stands, computes the rest on `executor`, writes each new
    success's record atomically as it arrives, and returns the outcomes in input order."""
    plan = _thread_plan(executor, threads)
    outcomes: List[Any] = [None] * batch.count
    reporter = _Reporter(progress, batch.count, batch.what)
    jobs = []
    for index in range(batch.count):
        path = batch.record(index)
        stored = None if path is None else _read_record(path, batch.key(index))
        if stored is not None and batch.stands(index, stored):
            outcomes[index] = batch.outcome(index, {**stored, "reused": True})
            reporter.count(True, True)
        else:
            jobs.append(batch.task(index, plan))

    jobs.sort(key=lambda job: -batch.cost(job.index))  # stable: ties keep the input order

    def finish(index: int, result: Dict) -> None:
        outcome = batch.outcome(index, result)
        path = batch.record(index)
        if outcome.ok and path is not None:
            batch.before_record(index, outcome)
            record = {"key": batch.key(index), "outcome": outcome.to_dict()}
            _write_atomically(path, json.dumps(record, indent=1))
        outcomes[index] = outcome
        reporter.count(outcome.ok, False)

    _drive(jobs, executor, finish)
    return outcomes


def _json_options(options: Dict) -> Dict:
    """The options as JSON values (tuples become lists), so a record's key compares equal."""
    return json.loads(json.dumps(options, sort_keys=True))


def fit_many(
    datasets: Sequence[Union[str, os.PathLike]],
    model: str = "cloth",
    executor: Any = None,
    *,
    output: Union[None, str, os.PathLike] = None,
    progress: Any = None,
    threads: Optional[int] = None,
    **options: Any,
) -> List[FitOutcome]:
    """Fits `model` to each of `datasets`; one ``FitOutcome`` per dataset, in input order.

    A dataset is anything ``woven fit --data`` takes: a measurement file's path, or ``FILE#N`` /
    ``FILE#NAME`` for one sample of a file of several (``woven.datasets(path)`` lists them).
    `options` are ``woven.fit``'s (``init``, ``fix``, ``free``, ``seed``, ``starts``, ``refine``,
    ``max_iterations``, ``subset``, ``final_subset``, ``residual``, ``saturation``), the same
    for every dataset. `executor`, `output`, `progress` and `threads`: the module's docs.
    Raises TypeError for an unknown option or a bad argument; a dataset that fails is an
    outcome with ``ok=False``, never an exception.
    """
    _check_options(options, FIT_OPTIONS, "fit_many")
    if not isinstance(model, str):
        raise TypeError(f"`model` = {model!r}: expected a model name such as 'cloth'")
    items = _check_items(datasets, "datasets")
    return _fit_pairs([(item, model) for item in items], executor, output, progress, threads,
                      options, f"fit_many ({model})")


def _fit_pairs(
    pairs: List[tuple],
    executor: Any,
    output: Union[None, str, os.PathLike],
    progress: Any,
    threads: Optional[int],
    options: Dict,
    what: str,
) -> List[FitOutcome]:
    """`fit_many` over `(dataset, model)` pairs, all submitted at once (`woven-batch fit`)."""
    out_dir = _output_dir(output)
    opts = _json_options(options)

    def record(index: int) -> Optional[pathlib.Path]:
        item, model = pairs[index]
        return None if out_dir is None else out_dir / f"{_slug(item)}.{model}.json"

    def key(index: int) -> Dict:
        item, model = pairs[index]
        return {"version": RECORD_VERSION, "kind": "fit", "item": item, "model": model,
                "options": opts}

    def task(index: int, plan: Dict) -> _Job:
        item, model = pairs[index]
        return _Job(index, _fit_task, (item, model, options, plan))

    def outcome(index: int, data: Dict) -> FitOutcome:
        item, model = pairs[index]
        return FitOutcome(**{"dataset": item, "model": model, **data})

    def material(index: int, fitted: FitOutcome) -> None:
        path = record(index)
        assert path is not None
        _write_atomically(path.with_suffix(".toml"), fitted.material_toml or "")

    def cost(index: int) -> float:
        return FIT_COST.get(pairs[index][1], 0.0)

    batch = _Batch(what, len(pairs), record, key, task, outcome, before_record=material,
                   cost=cost)
    return _run(batch, make_executor(executor), progress, threads)


def tabulate_many(
    materials: Sequence[Union[str, os.PathLike]],
    output: Union[str, os.PathLike],
    executor: Any = None,
    *,
    progress: Any = None,
    threads: Optional[int] = None,
    **options: Any,
) -> List[TableOutcome]:
    """Tabulates each of `materials` (preset names or material files) into the folder `output`,
    as ``woven.Table.build`` does; one ``TableOutcome`` per material, in input order.

    `options` are ``Table.build``'s (``wavelength_nm``, ``grid``, ``n_theta``,
    ``theta_max_deg``, ``n_phi``, ``n_h``, ``n_h_isotropic``, ``azimuth_nodes``, ``colour``,
    ``exact_regions``). Each table is written by its worker as ``NAME.wtab``: on a cluster,
    `output` must be a folder every worker sees. Raises TypeError for an unknown option,
    ValueError for a missing `output`.
    """
    _check_options(options, TABLE_OPTIONS, "tabulate_many")
    if output is None:
        raise ValueError(
            "`output` = None: tabulate_many writes each table as a .wtab file: give a folder"
        )
    items = _check_items(materials, "materials")
    out_dir = _output_dir(output)
    assert out_dir is not None
    opts = _json_options(options)

    def table(index: int) -> pathlib.Path:
        return out_dir / f"{_slug(items[index])}.wtab"

    def record(index: int) -> pathlib.Path:
        return table(index).with_name(table(index).name + ".json")

    def key(index: int) -> Dict:
        return {"version": RECORD_VERSION, "kind": "table", "item": items[index], "options": opts}

    def stands(index: int, stored: Dict) -> bool:
        path = table(index)
        return path.exists() and _sha256_file(path) == stored.get("sha256")

    def task(index: int, plan: Dict) -> _Job:
        return _Job(index, _table_task, (items[index], options, str(table(index)), plan))

    def outcome(index: int, data: Dict) -> TableOutcome:
        return TableOutcome(**{"material": items[index], **data})

    batch = _Batch("tabulate_many", len(items), record, key, task, outcome, stands)
    return _run(batch, make_executor(executor), progress, threads)


def render_many(
    scenes: Sequence[Union[str, os.PathLike]],
    output: Union[None, str, os.PathLike] = None,
    executor: Any = None,
    *,
    format: str = "exr",
    progress: Any = None,
    threads: Optional[int] = None,
    **options: Any,
) -> List[RenderOutcome]:
    """Renders each scene file of `scenes`, as ``woven.render`` does; one ``RenderOutcome`` per
    scene, in input order.

    With `output`, each image is written by its worker as ``NAME.exr`` (or ``.png``,
    `format`): on a cluster a folder every worker sees; without it the outcomes carry the
    pixels. `options` are ``woven.render``'s (``spp``, ``width``, ``height``, ``seed``,
    ``cache``). Raises TypeError for an unknown option, ValueError for a bad `format`.
    """
    _check_options(options, RENDER_OPTIONS, "render_many")
    if format not in ("exr", "png"):
        raise ValueError(f"`format` = {format!r}: expected 'exr' or 'png'")
    items = _check_items(scenes, "scenes")
    out_dir = _output_dir(output)
    opts = _json_options(options)

    def image(index: int) -> Optional[pathlib.Path]:
        return None if out_dir is None else out_dir / f"{_slug(items[index])}.{format}"

    def record(index: int) -> Optional[pathlib.Path]:
        return None if out_dir is None else out_dir / f"{_slug(items[index])}.render.json"

    def key(index: int) -> Dict:
        return {"version": RECORD_VERSION, "kind": "render", "item": items[index],
                "format": format, "options": opts}

    def stands(index: int, stored: Dict) -> bool:
        path = image(index)
        return path is not None and path.exists()

    def task(index: int, plan: Dict) -> _Job:
        target = image(index)
        return _Job(index, _render_task,
                    (items[index], options, None if target is None else str(target), plan))

    def outcome(index: int, data: Dict) -> RenderOutcome:
        return RenderOutcome(**{"scene": items[index], **data})

    batch = _Batch("render_many", len(items), record, key, task, outcome, stands)
    return _run(batch, make_executor(executor), progress, threads)
