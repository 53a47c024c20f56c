"""Scaling of woven.batch.fit_many over dask workers (docs/batch.md).

    target/mitsuba-venv/bin/python scripts/python/batch_scaling.py [--workers 1,2] [--starts N]
        [--max-iterations N] [--model cloth]

Fits every CUReT textile of data/curet (11 datasets) with each worker count in turn, in one run:
a LocalCluster of that many processes with one task slot each (so each worker's rayon pool gets
cores/workers threads). Prints the wall time of each, the ratio to the first, that the outcomes
agree bit for bit, and what a projection to many workers needs: each task's compute time, the
scheduler's overhead per task (no-op tasks through the same executor) and the bytes each task
moves (its pickled arguments and result).
"""

import argparse
import os
import pathlib
import pickle
import statistics
import time

import woven
from woven import batch

REPO = pathlib.Path(__file__).resolve().parents[2]
TEXTILES = ["01-felt", "02-polyester", "03-terrycloth", "07-velvet", "18-rug_a", "19-rug_b",
            "22-lambswool", "29-polyester_zoomed", "42-corduroy", "44-linen", "46-cotton"]


def _noop(x):
    return x


def overhead(executor, n=200):
    """Seconds per task of `n` no-op tasks through `executor` (submit to result)."""
    start = time.perf_counter()
    futures = [executor.submit(_noop, i) for i in range(n)]
    for f in futures:
        f.result()
    return (time.perf_counter() - start) / n


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--workers", default="1,2")
    p.add_argument("--model", default="cloth")
    p.add_argument("--starts", type=int)
    p.add_argument("--max-iterations", type=int)
    args = p.parse_args()
    from dask.distributed import Client, LocalCluster

    data = str(REPO / "data" / "curet" / "abrdf.dat")
    datasets = [f"{data}#curet-{t}" for t in TEXTILES]
    options = {}
    if args.starts is not None:
        options["starts"] = args.starts
    if args.max_iterations is not None:
        options["max_iterations"] = args.max_iterations
    print(f"{len(datasets)} CUReT textiles, model {args.model}, options {options or 'default'}, "
          f"{os.cpu_count()} cores, woven {woven.__version__}")
    runs = {}
    for n in [int(w) for w in args.workers.split(",")]:
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            executor = client.get_executor()
            client.run(lambda: None)  # workers up before the clock starts
            start = time.perf_counter()
            outcomes = batch.fit_many(datasets, args.model, executor, progress=False, **options)
            wall = time.perf_counter() - start
            per_task = overhead(executor)
        runs[n] = (wall, outcomes, per_task)
        failed = [o.dataset for o in outcomes if not o.ok]
        print(f"{n} worker(s) x {outcomes[0].threads} thread(s): {wall:.1f} s wall, "
              f"fits {sum(o.seconds for o in outcomes):.1f} s summed "
              f"(min {min(o.seconds for o in outcomes):.1f}, median "
              f"{statistics.median(o.seconds for o in outcomes):.1f}, max "
              f"{max(o.seconds for o in outcomes):.1f}), overhead {per_task * 1e3:.2f} ms/task"
              + (f", FAILED {failed}" if failed else ""))
    first = min(runs)
    key = lambda o: (o.rms_log, o.material_toml)  # noqa: E731
    for n, (wall, outcomes, _) in runs.items():
        same = [key(o) for o in outcomes] == [key(o) for o in runs[first][1]]
        print(f"{n} worker(s): {runs[first][0] / wall:.2f}x the {first}-worker speed; outcomes "
              f"{'equal' if same else 'DIFFER'} bit for bit")
    outcomes = runs[first][1]
    sent = [len(pickle.dumps((d, args.model, options, {"slots": {"127.0.0.1": 2}})))
            for d in datasets]
    back = [len(pickle.dumps(o.to_dict())) for o in outcomes]
    print(f"data per task: {max(sent)} bytes sent (arguments), {statistics.median(back):.0f} "
          f"bytes back (median result, max {max(back)}); the dataset file is read by the worker "
          f"({os.path.getsize(data)} bytes, all 61 samples)")


if __name__ == "__main__":
    main()
