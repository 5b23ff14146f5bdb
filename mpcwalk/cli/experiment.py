"""``mpcwalk experiment list``, ``mpcwalk experiment run NAME [--quick] [--workers N]
[--address ADDR] --out DIR`` and ``mpcwalk experiment scaling NAME [--quick] --out DIR``
(the sweep engine's throughput on its cases): the experiments of the registry
(:data:`~mpcwalk.experiments.catalog.EXPERIMENTS`) on the command line.

``run`` checks its input before anything runs (an unknown name, a bad ``--workers``, a
folder of another experiment: exit 2 with the named error); the experiment then runs on the
sweep engine, locally (Ray starts itself) or on a cluster (``--address ray://HOST:PORT`` or
``RAY_ADDRESS``). Run again on the same folder, it runs only its missing cases.
"""

import argparse
import shlex
from pathlib import Path


def add_parser(sub) -> argparse.ArgumentParser:
    """Add ``experiment`` and its sub-commands ``list`` and ``run`` to ``sub``."""
    experiment = sub.add_parser(
        "experiment",
        help="list and run the experiments (paper M, paper A, robustness, push map, ...)",
        description="The experiments of mpcwalk, each a sweep of cases on Ray streamed into a "
        "results table (results.csv) and a report (report.md). Local by default (Ray starts "
        "itself), on a cluster with --address ray://HOST:PORT or RAY_ADDRESS. Run again on "
        "the same folder, an experiment runs only its missing cases; a folder holding another "
        "configuration is refused unless --overwrite.",
    )
    esub = experiment.add_subparsers(dest="experiment_command", required=True)
    listing = esub.add_parser("list", help="list the experiments")
    listing.set_defaults(run=run_list)
    run = esub.add_parser("run", help="run an experiment into --out (table, figures, report.md)")
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
    run.set_defaults(run=run_experiment)
    scaling = esub.add_parser(
        "scaling",
        help="the sweep engine's throughput on an experiment's cases: 1 and 2 workers, on a "
        "local Ray instance and a local cluster (scaling.md, scaling.json)",
        description="Run the experiment's cases (into temporary folders) with each number of "
        "workers, on a fresh local Ray instance and on a fresh Ray cluster of one node per "
        "worker started on this machine; write walks per minute and per core, the speed-up "
        "and Ray's start into --out (scaling.md, scaling.json).",
    )
    scaling.add_argument("name", help="the experiment (list: mpcwalk experiment list)")
    scaling.add_argument("--out", type=Path, required=True, help="output folder")
    scaling.add_argument("--quick", action="store_true", help="the small variant's cases")
    scaling.add_argument(
        "--workers", type=int, nargs="+", default=[1, 2], help="numbers of workers"
    )
    scaling.add_argument(
        "--places",
        nargs="+",
        default=["local", "cluster"],
        choices=["local", "cluster"],
        help="where: a local Ray instance (local), a local cluster (cluster)",
    )
    scaling.add_argument("--repeats", type=int, default=1, help="runs of each (the median)")
    scaling.set_defaults(run=run_scaling)
    return experiment


def run_list(args: argparse.Namespace) -> int:
    """``mpcwalk experiment list``: the experiments, one a line."""
    from mpcwalk.experiments.catalog import EXPERIMENTS
    from mpcwalk.registry import format_registry

    print(format_registry(EXPERIMENTS))
    return 0


def command_line(args: argparse.Namespace) -> str:
    """The command line that runs the experiment of ``args`` again (its report prints it)."""
    words = ["mpcwalk", "experiment", "run", args.name]
    words += ["--quick"] if args.quick else []
    words += ["--workers", str(args.workers)] if args.workers else []
    words += ["--address", args.address] if args.address else []
    return shlex.join([*words, "--out", str(args.out)])


def run_experiment(args: argparse.Namespace) -> int:
    """``mpcwalk experiment run NAME``: run the experiment (its missing cases), then its
    report when every case is done.

    Raises:
        MpcwalkError: Bad input (an unknown experiment, a bad ``--workers``), before anything
            runs.
    """
    from mpcwalk.experiments.catalog import EXPERIMENTS
    from mpcwalk.sweep.cluster import check_workers

    experiment = EXPERIMENTS.load(args.name)
    check_workers(args.workers)
    run = experiment.run(
        args.out,
        quick=args.quick,
        workers=args.workers,
        address=args.address,
        progress=not args.no_progress,
        overwrite=args.overwrite,
        command=command_line(args),
    )
    sweep = run.sweep
    print(f"{sweep.nb_run} cases run, {sweep.nb_resumed} already in {args.out / 'results.csv'}")
    if run.report is None:
        print(f"{len(sweep.rows)}/{sweep.nb_cases} cases done: run the same command to go on")
        return 0
    print(f"wrote {run.report}")
    return 0


def run_scaling(args: argparse.Namespace) -> int:
    """``mpcwalk experiment scaling NAME``: the sweep engine's throughput on the
    experiment's cases (:mod:`mpcwalk.experiments.scaling`).

    Raises:
        MpcwalkError: Bad input (an unknown experiment or place, a bad number of workers or
            repeats, ``RAY_ADDRESS`` set), before anything runs.
    """
    import os

    from mpcwalk.experiments.catalog import EXPERIMENTS
    from mpcwalk.experiments.scaling import machine_words, measure_throughput, write_scaling
    from mpcwalk.sweep.cluster import check_workers

    experiment = EXPERIMENTS.load(args.name)
    for count in (*args.workers, args.repeats):
        check_workers(count)
    config = experiment.config(quick=args.quick)
    experiment.check(config)
    sweep = experiment.sweep(config)
    words = ["mpcwalk", "experiment", "scaling", args.name] + (["--quick"] if args.quick else [])
    words += ["--workers", *map(str, args.workers), "--places", *args.places]
    words += ["--repeats", str(args.repeats), "--out", str(args.out)]
    before = os.getloadavg()
    runs = measure_throughput(sweep, workers=args.workers, places=args.places, repeats=args.repeats)
    path = write_scaling(
        args.out,
        runs,
        command=shlex.join(words),
        what=f"the {len(sweep.cases)} cases of `{args.name}`{' --quick' if args.quick else ''}",
        machine=machine_words(before, os.getloadavg()),
    )
    print(path.read_text(), end="")
    return 0
