"""``woven-batch``: fits, tables and renders of many items on a dask cluster (docs/batch.md).

::

    woven-batch fit --data 'data/**/*.csv' data/curet/abrdf.dat --models cloth,microfacet -o results/
    woven-batch fit --data 'data/curet/abrdf.dat#linen' --scheduler tcp://host:8786 -o results/
    woven-batch tabulate --materials silk belt-cloth my.toml -o tables/
    woven-batch render --scenes scenes/*.toml -o renders/ --spp 64

Without ``--scheduler`` it starts a dask ``LocalCluster`` on this machine (``--workers``
processes of ``--threads-per-worker`` task slots). The work is ``woven.batch``'s: a rerun with the
same ``-o`` reuses what is done.
"""

from __future__ import annotations

import argparse
import glob
import os
import pathlib
import sys
import time
from typing import List, Optional

MODELS = ("cloth", "fiber", "lambert", "microfacet", "sheen", "microcylinder")


def _expand_data(patterns: List[str]) -> List[str]:
    """Each --data value as datasets: `FILE#N` as given; a glob (`**` recursive) as the files it
    matches, each file of several materials (CUReT) as one dataset per material. Files that are
    not measurement files are left out with a note on stderr."""
    import woven

    out: List[str] = []
    for pattern in patterns:
        if "#" in pattern:
            out.append(pattern)
            continue
        files = sorted(glob.glob(pattern, recursive=True)) or [pattern]
        for path in files:
            if os.path.isdir(path):
                continue
            try:
                out.extend(woven.datasets(path))
            except (OSError, ValueError) as e:
                if len(files) == 1:
                    raise SystemExit(f"woven-batch: --data {pattern!r}: {e}")
                print(f"woven-batch: leaving out {path}: {e}", file=sys.stderr)
    if not out:
        raise SystemExit(f"woven-batch: --data {' '.join(patterns)}: no datasets found")
    return out


def _models(text: str) -> List[str]:
    models = [m.strip() for m in text.split(",") if m.strip()]
    for m in models:
        if m not in MODELS:
            raise argparse.ArgumentTypeError(
                f"--models: {m!r} is not a model: expected any of {', '.join(MODELS)}"
            )
    if not models:
        raise argparse.ArgumentTypeError("--models: expected at least one model")
    return models


def _positive(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a whole number >= 1")
    return n


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="woven-batch",
        description="Fit, tabulate or render many items on a dask cluster (docs/batch.md).",
    )
    sub = p.add_subparsers(dest="command", required=True)
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("-o", "--output", required=True, help="the results' folder")
    common.add_argument("--scheduler", help="a dask scheduler's address (default: a LocalCluster)")
    common.add_argument("--workers", type=_positive, default=None,
                        help="LocalCluster worker processes (default: the cores)")
    common.add_argument("--threads-per-worker", type=_positive, default=1,
                        help="LocalCluster task slots per worker (default 1)")
    common.add_argument("--quiet", action="store_true", help="no progress line")

    fit = sub.add_parser("fit", parents=[common], help="fit every model to every dataset",
                         description="Fit every model of --models to every dataset; writes the "
                         "comparison table `woven fit --compare` writes (comparison.md) and each "
                         "fitted material (NAME.MODEL.toml).")
    fit.add_argument("--data", nargs="+", required=True, metavar="DATA",
                     help="files, globs ('data/**/*.csv') or FILE#N")
    fit.add_argument("--models", type=_models, default=["lambert", "microfacet", "cloth"],
                     help="comma-separated (default lambert,microfacet,cloth)")
    fit.add_argument("--seed", type=int, default=1, help="scrambles the starts (default 1)")
    fit.add_argument("--starts", type=int, help="quasi-random starts screened (woven fit's)")
    fit.add_argument("--max-iterations", type=int,
                     help="Levenberg-Marquardt iterations of the final run (woven fit's)")
    fit.add_argument("--fix", action="append", default=[], metavar="NAME=VALUE",
                     help="hold a parameter at a value (repeatable; every model must have it)")
    fit.add_argument("--free", default="", metavar="NAMES",
                     help="let parameters vary (comma-separated; every model must have them)")

    tab = sub.add_parser("tabulate", parents=[common], help="build a table of every material")
    tab.add_argument("--materials", nargs="+", required=True, metavar="MATERIAL")
    tab.add_argument("--grid", choices=("model", "render", "default"), default="model")
    tab.add_argument("--wavelength-nm", type=float, default=550.0)
    for name in ("n-theta", "n-phi", "n-h", "n-h-isotropic", "azimuth-nodes"):
        tab.add_argument(f"--{name}", type=_positive)

    ren = sub.add_parser("render", parents=[common], help="render every scene file")
    ren.add_argument("--scenes", nargs="+", required=True, metavar="SCENE")
    ren.add_argument("--format", choices=("exr", "png"), default="exr")
    for name in ("spp", "width", "height"):
        ren.add_argument(f"--{name}", type=_positive)
    return p


def batch_cores() -> int:
    """This machine's usable cores (woven.batch's count: the CPU affinity)."""
    from woven import batch

    return batch._cores()


def _client(args: argparse.Namespace):
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise SystemExit('woven-batch: needs dask: pip install "woven[dask]"')
    if args.scheduler:
        return Client(args.scheduler), None
    cluster = LocalCluster(
        n_workers=args.workers or batch_cores(),
        threads_per_worker=args.threads_per_worker,
        processes=True,
    )
    return Client(cluster), cluster


def _fit(args: argparse.Namespace, executor, progress) -> int:
    import woven
    from woven import batch

    datasets = _expand_data(args.data)
    options = {"seed": args.seed, "fix": args.fix,
               "free": [f for f in args.free.split(",") if f.strip()]}
    if args.starts is not None:
        options["starts"] = args.starts
    if args.max_iterations is not None:
        options["max_iterations"] = args.max_iterations
    pairs = [(d, m) for d in datasets for m in args.models]
    start = time.perf_counter()
    outcomes = batch._fit_pairs(pairs, executor, args.output, progress, None, options,
                                "woven-batch fit")
    wall = time.perf_counter() - start
    rows, unreadable = [], []
    for i, d in enumerate(datasets):
        mine = outcomes[i * len(args.models):(i + 1) * len(args.models)]
        cells = [(o.model, o.rms_log, o.relative_rms) if o.ok else (o.model, o.error or "")
                 for o in mine]
        try:
            woven.comparison_table([(d, cells)])  # reads the dataset: a corrupt file fails here
            rows.append((d, cells))
        except (OSError, ValueError) as e:
            unreadable.append(f"{d}: {e}")
    table = woven.comparison_table(rows) if rows else ""
    failed = [o for o in outcomes if not o.ok]
    for o in failed:
        print(f"failed: {o.dataset} / {o.model}: {o.error}", file=sys.stderr)
    for line in unreadable:
        print(f"unreadable: {line}", file=sys.stderr)
    out = pathlib.Path(args.output)
    batch._write_atomically(out / "comparison.md", table)
    print(table, end="")
    print(f"{len(outcomes) - len(failed)} fits, {len(failed)} failed, in {wall:.1f} s; "
          f"{out / 'comparison.md'} and the fitted materials (*.toml) in {out}/", file=sys.stderr)
    return 1 if failed else 0


def _tabulate(args: argparse.Namespace, executor, progress) -> int:
    from woven import batch

    options = {"grid": args.grid, "wavelength_nm": args.wavelength_nm}
    for name in ("n_theta", "n_phi", "n_h", "n_h_isotropic", "azimuth_nodes"):
        if getattr(args, name) is not None:
            options[name] = getattr(args, name)
    outcomes = batch.tabulate_many(args.materials, args.output, executor, progress=progress,
                                   **options)
    for o in outcomes:
        print(f"{o.material}: {o.path} ({o.seconds:.1f} s)" if o.ok
              else f"{o.material}: failed: {o.error}")
    return 0 if all(o.ok for o in outcomes) else 1


def _render(args: argparse.Namespace, executor, progress) -> int:
    from woven import batch

    options = {k: getattr(args, k) for k in ("spp", "width", "height")
               if getattr(args, k) is not None}
    outcomes = batch.render_many(args.scenes, args.output, executor, format=args.format,
                                 progress=progress, **options)
    for o in outcomes:
        print(f"{o.scene}: {o.path} ({o.seconds:.1f} s)" if o.ok
              else f"{o.scene}: failed: {o.error}")
    return 0 if all(o.ok for o in outcomes) else 1


def main(argv: Optional[List[str]] = None) -> int:
    """The console script's entry point; returns the exit status (1 when an item failed)."""
    args = _parser().parse_args(argv)
    progress = False if args.quiet else None
    client, cluster = _client(args)
    try:
        run = {"fit": _fit, "tabulate": _tabulate, "render": _render}[args.command]
        return run(args, client.get_executor(), progress)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


if __name__ == "__main__":
    sys.exit(main())
