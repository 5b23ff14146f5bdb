"""``mpcwalk sweep ...``: the sweeps on the engine (:mod:`mpcwalk.sweep`).

- ``mpcwalk sweep robustness [--quick] --out DIR``: the robustness matrix
  (:mod:`mpcwalk.experiments.robustness_matrix`), its table and its report;
- ``mpcwalk sweep push [--quick] --out DIR``: the push map
  (:mod:`mpcwalk.experiments.push_map`), its table and its report;
- ``mpcwalk sweep scaling --out DIR``: the ``--quick`` matrix run in fresh processes with 1,
  then 2 local workers, and the speed-up.

Every sweep runs locally by default (Ray starts itself), on a cluster with ``--address
ray://HOST:PORT`` or ``RAY_ADDRESS``; ``--workers N`` bounds the walks at once. Run again on
the same folder, a sweep runs only its missing cases (``--resume``, the default); a folder
holding another configuration is refused unless ``--overwrite``.
"""

import argparse
import datetime
import json
import os
import platform
import shlex
import sys
import time
from pathlib import Path

#: File of the runs that filled a sweep's table (wall time, workers, where).
RUNS_FILE = "runs.json"


def _engine_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, required=True, help="output folder (table and report)")
    p.add_argument("--quick", action="store_true", help="the small version (the test suite's)")
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        help="walks at once (local: Ray's CPU slots; default: one per core, or the cluster's)",
    )
    p.add_argument(
        "--address",
        default=None,
        help="Ray cluster: ray://HOST:PORT (Ray client) or HOST:PORT on a node "
        "(default: RAY_ADDRESS, else a local Ray instance)",
    )
    p.add_argument(
        "--resume",
        action="store_true",
        help="run only the cases missing from the table in --out (the default when it "
        "holds this configuration)",
    )
    p.add_argument(
        "--overwrite", action="store_true", help="start afresh in a folder of another sweep"
    )
    p.add_argument(
        "--max-cases",
        type=int,
        default=None,
        metavar="N",
        help="run at most N missing cases, then stop (run again to go on)",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def add_sweep_parser(sub) -> None:
    """Add ``sweep`` and its sub-commands to the top-level parser."""
    sweep = sub.add_parser(
        "sweep",
        help="sweeps of many walks on Ray (robustness matrix, push map), locally or on a cluster",
        description="Sweeps of many walks, each a Ray task, streamed into a results table "
        "(results.csv). Local by default (Ray starts itself on this machine), on a cluster "
        "with --address ray://HOST:PORT or RAY_ADDRESS; --workers N bounds the walks at once. "
        "Run again on the same folder, a sweep runs only its missing cases; a folder holding "
        "another configuration is refused unless --overwrite.",
    )
    ssub = sweep.add_subparsers(dest="sweep_command", required=True)
    robustness = ssub.add_parser(
        "robustness",
        help="every controller on every robot in perturbed worlds: success rates, goals, report",
    )
    _engine_arguments(robustness)
    robustness.add_argument(
        "--config", type=Path, default=None, help="matrix TOML (default: the shipped one)"
    )
    robustness.set_defaults(sweep_func=_run_robustness)
    push = ssub.add_parser(
        "push", help="largest impulse survived per direction, phase and speed; ratio to paper-m"
    )
    _engine_arguments(push)
    push.add_argument("--robot", default="bioloid-like", help="robot name")
    push.add_argument(
        "--controllers",
        nargs="+",
        default=["paper-m", "mpc", "mpc-steps", "mpc-timing"],
        help="named controllers (paper-m is added: the ratios are taken against it)",
    )
    push.add_argument(
        "--with",
        dest="joined",
        type=Path,
        nargs="+",
        default=[],
        metavar="DIR",
        help="push maps of other controllers on the same robot and grid, joined to the report",
    )
    push.add_argument("--directions", type=int, default=16, help="push directions")
    push.add_argument("--phases", type=int, default=6, help="push phases per step")
    push.add_argument(
        "--speeds",
        default="0,1",
        help="forward speeds, as shares of the robot's nominal speed (comma-separated)",
    )
    push.set_defaults(sweep_func=_run_push)
    scaling = ssub.add_parser(
        "scaling", help="the --quick matrix with 1 then 2 local workers: wall times, speed-up"
    )
    scaling.add_argument("--out", type=Path, required=True, help="output folder")
    scaling.add_argument("--workers", type=int, nargs="+", default=[1, 2], help="worker counts")
    scaling.set_defaults(sweep_func=_run_scaling)


def run_sweep_command(args) -> int:
    """Run ``mpcwalk sweep ...``."""
    return args.sweep_func(args)


def _command() -> str:
    return "mpcwalk " + shlex.join(sys.argv[1:])


def record_run(out: Path, run, *, address: str | None) -> list[dict]:
    """Append this run (wall time, cases run, workers, where) to ``runs.json``; all runs."""
    from mpcwalk.sweep.cluster import where

    path = out / RUNS_FILE
    runs = json.loads(path.read_text()) if path.exists() else []
    runs.append(
        {
            "command": _command(),
            "date": datetime.datetime.now().isoformat(timespec="seconds"),
            "wall_time_s": round(run.wall_time_s, 1),
            "cases_run": run.nb_run,
            "cases_resumed": run.nb_resumed,
            "workers": run.workers,
            "where": where(address),
            "machine": f"{platform.machine()}, {os.cpu_count()} cores",
        }
    )
    path.write_text(json.dumps(runs, indent=1) + "\n")
    return runs


def read_runs(out: Path) -> list[dict]:
    """The runs recorded in ``out``'s ``runs.json`` (none when it has none)."""
    path = Path(out) / RUNS_FILE
    return json.loads(path.read_text()) if path.exists() else []


def runs_text(runs: list[dict], nb_cases: int, noun: str = "walks") -> str:
    """The runs that filled the table, in words (``noun``: what a case is)."""
    wall = sum(r["wall_time_s"] for r in runs)
    lines = [
        f"- `{r['command']}` ({r['date']}): {r['cases_run']} {noun} in "
        f"{r['wall_time_s'] / 60:.1f} min, {r['workers']} at once, {r['where']} "
        f"({r['machine']})"
        for r in runs
    ]
    return (
        f"{nb_cases} {noun}, {wall / 60:.1f} min of wall time in all:\n\n" + "\n".join(lines) + "\n"
    )


def _run_robustness(args) -> int:
    from mpcwalk.experiments.robustness_matrix import (
        DEFAULT_MATRIX,
        load_matrix_config,
        matrix_sweep,
    )
    from mpcwalk.experiments.robustness_matrix_report import write_report
    from mpcwalk.sweep import run_sweep

    config = load_matrix_config(
        args.config or DEFAULT_MATRIX, mode="quick" if args.quick else "full"
    )
    sweep = matrix_sweep(config)
    run = run_sweep(
        sweep,
        args.out,
        workers=args.workers,
        address=args.address,
        overwrite=args.overwrite,
        max_cases=args.max_cases,
        progress=not args.no_progress,
    )
    runs = record_run(args.out, run, address=args.address)
    print(f"{run.nb_run} walks run, {run.nb_resumed} already in {args.out / 'results.csv'}")
    if not run.complete:
        print(f"{len(run.rows)}/{run.nb_cases} walks done: run the same command to go on")
        return 0
    scaling = args.out / "scaling.md"
    header = _matrix_header(config, runs, len(sweep.cases))
    path = write_report(
        args.out,
        run.rows,
        header=header,
        scaling=scaling.read_text() if scaling.exists() else "",
    )
    print(f"wrote {path}")
    return 0


def _matrix_header(config, runs: list[dict], nb_cases: int) -> str:
    from mpcwalk.experiments.robustness_matrix import FACTORS

    robots = ", ".join(
        f"`{name}` ({', '.join(plan.controllers)}; {plan.nb_steps} steps at "
        f"{plan.command[0]:g} m/s)"
        for name, plan in config.robots.items()
    )
    present = {c for plan in config.robots.values() for c in plan.controllers}
    slow = (
        ", ".join(
            f"`{name}` {steps} steps"
            for name, steps in config.slow_controllers.items()
            if name in present
        )
        or "none here"
    )
    return "\n".join(
        [
            "# The robustness matrix\n",
            runs_text(runs, nb_cases),
            f"Mode {config.mode}. Robots and controllers: {robots}; the controllers with their "
            f"own timing take the same steps at it ({slow}). Worlds of each robot: the nominal "
            f"one ({len(config.nominal_seeds)} seeds), each factor alone at {config.levels} "
            f"random levels stratified over its range, and {config.combinations} random "
            f"combinations of {config.combination_size[0]} to {config.combination_size[1]} "
            f"factors; every controller of the robot walks every world, with the world's seed. "
            f"Factors ({', '.join(FACTORS)}) and ranges: `{json.dumps(dict(config.ranges))}` "
            "(`experiments/robustness/matrix.toml`). Every walk runs on the estimator, with "
            "the robot's sensor model (scaled by the noise factor) and one control period of "
            "latency unless the latency factor says otherwise. A walk succeeds when it does "
            "not fall (and runs: an error counts as a failure). Table: `results.csv` (one row "
            "per walk, its configuration and metrics); `sweep.json`: the configuration.\n",
        ]
    )


def _run_push(args) -> int:
    from mpcwalk.exceptions import ConfigurationError
    from mpcwalk.experiments.push_map import PushMapConfig, joined_push_rows, push_map_sweep
    from mpcwalk.experiments.push_report import write_push_report
    from mpcwalk.sweep import run_sweep

    # paper-m is added, unless a joined map holds it (a controller run apart)
    controllers = list(
        dict.fromkeys(args.controllers if args.joined else ["paper-m", *args.controllers])
    )
    speeds = tuple(float(v) for v in str(args.speeds).split(","))
    config = PushMapConfig(
        robot=args.robot,
        controllers=tuple(controllers),
        nb_directions=args.directions,
        nb_phases=args.phases,
        speed_shares=speeds,
    )
    if args.quick:
        config = config.quick()
    joined = joined_push_rows(config, args.joined)  # checked before anything runs
    if "paper-m" not in {*config.controllers, *(r["controller"] for r in joined)}:
        raise ConfigurationError(
            "--with: expected paper-m in this map or a joined one (the ratios are taken "
            "against it), found neither; add it to --controllers."
        )
    run = run_sweep(
        push_map_sweep(config),
        args.out,
        workers=args.workers,
        address=args.address,
        overwrite=args.overwrite,
        max_cases=args.max_cases,
        progress=not args.no_progress,
    )
    runs = record_run(args.out, run, address=args.address)
    if not run.complete:
        print(f"{len(run.rows)}/{run.nb_cases} cases done: run the same command to go on")
        return 0
    for folder in args.joined:
        runs = runs + read_runs(folder)
    rows = [*run.rows, *joined]
    text = runs_text(runs, len(rows), "cells (a bisection of walks each)")
    path = write_push_report(args.out, rows, config, text)
    print(f"wrote {path}")
    return 0


def _run_scaling(args) -> int:
    import subprocess
    import tempfile

    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    results = []
    for workers in args.workers:
        with tempfile.TemporaryDirectory() as folder:
            command = [sys.executable, "-m", "mpcwalk", "sweep", "robustness", "--quick"]
            command += ["--workers", str(workers), "--no-progress", "--out", folder]
            start = time.perf_counter()
            subprocess.run(command, check=True, capture_output=True)
            total = time.perf_counter() - start
            run = json.loads((Path(folder) / RUNS_FILE).read_text())[-1]
        results.append({"workers": workers, "process_s": total, "sweep_s": run["wall_time_s"]})
        results[-1]["walks"] = run["cases_run"]
    base = results[0]
    lines = [
        "The `--quick` matrix (a fresh local Ray instance each time: "
        f"{base['walks']} walks), run by `{_command()}`:\n",
        "| workers | wall time of the process [s] | of the sweep [s] | speed-up (sweep) |",
        "|---|---|---|---|",
    ]
    for r in results:
        lines.append(
            f"| {r['workers']} | {r['process_s']:.1f} | {r['sweep_s']:.1f} | "
            f"{base['sweep_s'] / r['sweep_s']:.2f} |"
        )
    text = "\n".join(lines) + "\n"
    (out / "scaling.json").write_text(json.dumps(results, indent=1) + "\n")
    (out / "scaling.md").write_text(text)
    print(text, end="")
    return 0


__all__ = [
    "RUNS_FILE",
    "add_sweep_parser",
    "read_runs",
    "record_run",
    "run_sweep_command",
    "runs_text",
]
