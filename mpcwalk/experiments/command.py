"""``mpcwalk experiment list`` and ``mpcwalk experiment run NAME [--quick] [--workers N]
[--address ADDR] --out DIR``: the experiments of the registry
(:data:`~mpcwalk.experiments.catalog.EXPERIMENTS`) on the command line.

``run`` checks its input before anything runs (an unknown name, a bad ``--workers``, a
folder of another experiment: exit 2 with the named error); the experiment then runs on the
sweep engine, locally (Ray starts itself) or on a cluster (``--address ray://HOST:PORT`` or
``RAY_ADDRESS``). Run again on the same folder, it runs only its missing cases.
"""

import argparse
import shlex
from pathlib import Path


def add_experiment_parser(subparsers) -> None:
    """Add ``experiment`` and its sub-commands ``list`` and ``run`` to the top-level parser."""
    experiment = subparsers.add_parser(
        "experiment",
        help="list and run the experiments (paper M, paper A, robustness, push map, ...)",
        description="The experiments of mpcwalk, each a sweep of cases on Ray streamed into a "
        "results table (results.csv) and a report (report.md). Local by default (Ray starts "
        "itself), on a cluster with --address ray://HOST:PORT or RAY_ADDRESS. Run again on "
        "the same folder, an experiment runs only its missing cases; a folder holding another "
        "configuration is refused unless --overwrite.",
    )
    sub = experiment.add_subparsers(dest="experiment_command", required=True)
    sub.add_parser("list", help="list the experiments")
    run = sub.add_parser("run", help="run an experiment into --out (table, figures, report.md)")
    run.add_argument("name", help="the experiment (list: mpcwalk experiment list)")
    run.add_argument("--out", type=Path, required=True, help="output folder")
    run.add_argument("--quick", action="store_true", help="the small variant (the test suite's)")
    run.add_argument(
        "--workers",
        type=int,
        default=None,
        help="cases at once (local: Ray's CPU slots; default: one per core, or the cluster's)",
    )
    run.add_argument(
        "--address",
        default=None,
        help="Ray cluster: ray://HOST:PORT (Ray client) or HOST:PORT on a node "
        "(default: RAY_ADDRESS, else a local Ray instance)",
    )
    run.add_argument(
        "--overwrite", action="store_true", help="start afresh in a folder of another run"
    )
    run.add_argument("--no-progress", action="store_true", help="no progress bar")


def run_experiment_command(args: argparse.Namespace) -> int:
    """Run ``mpcwalk experiment list|run``; the exit status.

    Raises:
        MpcwalkError: Bad input (an unknown experiment, a bad ``--workers``), before anything
            runs.
    """
    from mpcwalk.experiments.catalog import EXPERIMENTS
    from mpcwalk.registry import format_registry
    from mpcwalk.sweep.cluster import check_workers

    if args.experiment_command == "list":
        print(format_registry(EXPERIMENTS))
        return 0
    experiment = EXPERIMENTS.load(args.name)
    check_workers(args.workers)
    words = ["mpcwalk", "experiment", "run", args.name]
    words += ["--quick"] if args.quick else []
    words += ["--workers", str(args.workers)] if args.workers else []
    words += ["--address", args.address] if args.address else []
    command = shlex.join([*words, "--out", str(args.out)])
    run = experiment.run(
        args.out,
        quick=args.quick,
        workers=args.workers,
        address=args.address,
        progress=not args.no_progress,
        overwrite=args.overwrite,
        command=command,
    )
    sweep = run.sweep
    print(f"{sweep.nb_run} cases run, {sweep.nb_resumed} already in {args.out / 'results.csv'}")
    if run.report is None:
        print(f"{len(sweep.rows)}/{sweep.nb_cases} cases done: run the same command to go on")
        return 0
    print(f"wrote {run.report}")
    return 0


__all__ = ["add_experiment_parser", "run_experiment_command"]
