"""``mpcwalk bench solvers``: every QP back-end on the walking QPs, offline and in the loop
(:func:`~mpcwalk.bench.solvers.benchmark.run_solver_benchmark`), into ``results.csv.gz``,
``report.md`` and its figures; ``--report-only`` writes the report again from a finished
run.

The options change the fields of
:class:`~mpcwalk.bench.solvers.config.SolverBenchConfig` (``--quick`` starts from its small
variant); the report records the command line that reproduces the run.
"""

import argparse
import shlex
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from mpcwalk.bench.solvers.config import SolverBenchConfig


def add_parser(bsub) -> argparse.ArgumentParser:
    """Add ``solvers`` to the ``bench`` sub-commands ``bsub``."""
    p = bsub.add_parser(
        "solvers",
        help="every QP back-end on the walking QPs: offline (qpbenchmark conventions), "
        "growth with the horizon, in the loop; results.csv.gz and report.md",
    )
    p.add_argument("--quick", action="store_true", help="reduced run (a few minutes)")
    p.add_argument("--out", type=Path, required=True, help="output directory")
    p.add_argument("--backends", help="comma-separated back-ends (default: all installed)")
    p.add_argument(
        "--families",
        help="comma-separated problem families (mpc, mpc-dcm, mpc-tick, static-qp; "
        "inverse-dynamics: the QP of torque control, its own stage: alone, only it runs)",
    )
    p.add_argument("--walks", help="comma-separated walks (straight, turning, sideways)")
    p.add_argument("--levels", help="comma-separated tolerance levels (default, low, mid, high)")
    p.add_argument("--horizons", help="comma-separated horizons of the sweep [samples]")
    p.add_argument("--time-limit", type=float, default=None, help="per solve [s] (default 1)")
    p.add_argument(
        "--timing-workers",
        type=int,
        default=None,
        help="processes timing solves (default 1: no overlap between timed solves)",
    )
    p.add_argument("--no-ticks", action="store_true", help="skip the per-tick comparison")
    p.add_argument("--no-loops", action="store_true", help="skip the in-loop walks")
    p.add_argument("--no-qpbenchmark", action="store_true", help="skip the qpbenchmark run")
    p.add_argument("--no-progress", action="store_true")
    p.add_argument(
        "--report-only",
        action="store_true",
        help="rewrite report.md and the figures from DIR/results.csv.gz and extras.json",
    )
    p.set_defaults(run=run)
    return p


def _csv(text: str | None) -> tuple[str, ...] | None:
    """The values of a comma-separated option, or None when it is not given."""
    return tuple(v.strip() for v in text.split(",") if v.strip()) if text else None


def command_line(args: argparse.Namespace) -> str:
    """The command line that reproduces the run of ``args``."""
    words = ["mpcwalk", "bench", "solvers"] + (["--quick"] if args.quick else [])
    words += ["--out", str(args.out)]
    for name in (
        "backends",
        "families",
        "walks",
        "levels",
        "horizons",
        "time_limit",
        "timing_workers",
    ):
        value = getattr(args, name)
        if value is not None:
            words += [f"--{name.replace('_', '-')}", str(value)]
    for name in ("no_ticks", "no_loops", "no_qpbenchmark"):
        if getattr(args, name):
            words.append(f"--{name.replace('_', '-')}")
    return " ".join(shlex.quote(w) for w in words)


def config_from_args(args: argparse.Namespace) -> "SolverBenchConfig":
    """The :class:`~mpcwalk.bench.solvers.config.SolverBenchConfig` of ``args``: the default
    (or quick) configuration with the fields the options give."""
    from mpcwalk.bench.solvers.config import SolverBenchConfig

    config = SolverBenchConfig.quick() if args.quick else SolverBenchConfig()
    changes: dict[str, object] = {}
    for field, value in (
        ("backends", _csv(args.backends)),
        ("families", _csv(args.families)),
        ("walks", _csv(args.walks)),
        ("levels", _csv(args.levels)),
    ):
        if value:
            changes[field] = value
    if args.horizons:
        changes["sweep_horizons"] = tuple(int(v) for v in _csv(args.horizons) or ())
    if args.time_limit is not None:
        changes["time_limit"] = args.time_limit
    if args.timing_workers is not None:
        changes["timing_workers"] = args.timing_workers
    if args.no_ticks:
        changes["ticks"] = False
    return config.replace(**changes)


def run(args: argparse.Namespace) -> int:
    """``mpcwalk bench solvers``: run the benchmark of ``args`` (or rewrite its report) and
    say what it wrote."""
    from mpcwalk.bench.solvers.benchmark import rewrite_report, run_solver_benchmark

    if args.report_only:
        print(f"wrote {rewrite_report(args.out)}")
        return 0
    summary = run_solver_benchmark(
        config_from_args(args),
        args.out,
        progress=not args.no_progress,
        command=command_line(args),
        loops=not args.no_loops,
        qpbenchmark_run=not args.no_qpbenchmark,
    )
    stages = ", ".join(f"{k} {v:.0f} s" for k, v in summary["durations"].items())
    print(f"{summary['rows']} results ({stages})")
    print(f"wrote {summary['results']} and {summary['report']}")
    return 0
