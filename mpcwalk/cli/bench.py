"""``mpcwalk bench ticks|ik|loop|solvers``: the benchmarks (generator ticks, whole-body IK,
walk loop, QP solvers).

``ticks``, ``ik`` and ``loop`` print their report and write it to ``--out`` as ``NAME.md``
with the results as ``NAME.json``; ``solvers`` is :mod:`~mpcwalk.cli.bench_solvers`. The
benchmarks themselves are the library's (:mod:`mpcwalk.bench`).
"""

import argparse
from dataclasses import asdict
from pathlib import Path
from typing import Any


def add_parser(sub) -> argparse.ArgumentParser:
    """Add ``bench`` and its sub-commands to ``sub``."""
    from mpcwalk.cli import bench_solvers

    bench = sub.add_parser(
        "bench", help="benchmarks: generator ticks, whole-body IK, walk loop, QP solvers"
    )
    bsub = bench.add_subparsers(dest="bench_command", required=True)
    _add_ticks(bsub)
    _add_ik(bsub)
    _add_loop(bsub)
    bench_solvers.add_parser(bsub)
    return bench


def _add_ticks(bsub) -> None:
    """Add ``bench ticks`` to the ``bench`` sub-commands ``bsub``."""
    from mpcwalk.bench.ticks import DEFAULT_QPSOLVERS

    ticks = bsub.add_parser(
        "ticks",
        help="per-tick time of every generator and MPC back-end on one walk, with the qpmpc peer",
    )
    ticks.add_argument(
        "--steps", type=int, default=20, help="steps of the walk (a closing step is added)"
    )
    ticks.add_argument("--vx", type=float, default=0.1, help="forward velocity [m/s]")
    ticks.add_argument("--vy", type=float, default=0.0, help="lateral velocity [m/s]")
    ticks.add_argument("--vyaw", type=float, default=0.35, help="yaw rate [rad/s]")
    ticks.add_argument("--control-period", type=float, default=0.01, help="generator tick [s]")
    ticks.add_argument(
        "--solvers",
        default=None,
        help="comma-separated qpsolvers back-ends for the MPC (default: "
        f"{','.join(DEFAULT_QPSOLVERS)})",
    )
    ticks.add_argument(
        "--repeats",
        type=int,
        default=3,
        help="walks per case: the medians over them of each walk's median and p99",
    )
    ticks.add_argument("--no-peer", action="store_true", help="skip the qpmpc peer")
    ticks.add_argument("--no-progress", action="store_true", help="no progress bar")
    ticks.add_argument(
        "--out",
        type=Path,
        default=Path("results/ticks"),
        help="output directory (ticks.md, ticks.json)",
    )
    ticks.set_defaults(run=run_ticks)


def _add_ik(bsub) -> None:
    """Add ``bench ik`` to the ``bench`` sub-commands ``bsub``."""
    from mpcwalk.bench.ik import DEFAULT_PINK_SOLVERS, DEFAULT_ROBOTS

    parser = bsub.add_parser(
        "ik", help="per-tick time of the whole-body IK, ours beside pink, same tasks and motion"
    )
    parser.add_argument(
        "--robots", default=",".join(DEFAULT_ROBOTS), help="comma-separated robot names"
    )
    parser.add_argument("--duration", type=float, default=2.0, help="motion length [s]")
    parser.add_argument("--control-period", type=float, default=0.01, help="IK tick [s]")
    parser.add_argument(
        "--pink-solvers",
        default=",".join(DEFAULT_PINK_SOLVERS),
        help="comma-separated qpsolvers back-ends for pink",
    )
    parser.add_argument("--no-pink", action="store_true", help="skip the pink peer")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--out", type=Path, default=Path("results/ik"), help="output directory (ik.md, ik.json)"
    )
    parser.set_defaults(run=run_ik)


def _add_loop(bsub) -> None:
    """Add ``bench loop`` to the ``bench`` sub-commands ``bsub``."""
    loop = bsub.add_parser(
        "loop", help="whole-loop timing of MuJoCo walks per robot, with the IK beside pink"
    )
    loop.add_argument("--no-progress", action="store_true", help="no progress bar")
    loop.add_argument(
        "--out",
        type=Path,
        default=Path("results/loop"),
        help="output directory (loop.md, loop.json)",
    )
    loop.set_defaults(run=run_loop)


def _names(text: str) -> list[str]:
    """The names of a comma-separated option (empty ones left out)."""
    return [name for name in text.split(",") if name]


def _write(out: Path, name: str, text: str, payload: Any) -> int:
    """Print the report ``text``, write it and ``payload`` into ``out``, say where."""
    from mpcwalk.bench.output import write_bench_output

    print(text)
    markdown, data = write_bench_output(out, name, text, payload)
    print(f"\nwrote {markdown} and {data}")
    return 0


def run_ticks(args: argparse.Namespace) -> int:
    """``mpcwalk bench ticks``: time every generator on one walk; ``ticks.md`` and
    ``ticks.json``."""
    from mpcwalk.bench.ticks import run_tick_benchmark, tick_report
    from mpcwalk.footsteps.velocity_planner import VelocityCommand

    command = VelocityCommand(args.vx, args.vy, args.vyaw)
    results = run_tick_benchmark(
        nb_steps=args.steps,
        command=command,
        control_period=args.control_period,
        solvers=args.solvers.split(",") if args.solvers else None,
        include_peer=not args.no_peer,
        progress=not args.no_progress,
        repeats=args.repeats,
    )
    text = tick_report(
        results,
        nb_steps=args.steps,
        command=command,
        control_period=args.control_period,
        command_line=f"mpcwalk bench ticks --out {args.out}",
    )
    return _write(args.out, "ticks", text, [asdict(r) for r in results])


def run_ik(args: argparse.Namespace) -> int:
    """``mpcwalk bench ik``: time the whole-body IK beside pink; ``ik.md`` and ``ik.json``."""
    from mpcwalk.bench.ik import ik_report, run_ik_benchmark

    results = run_ik_benchmark(
        _names(args.robots),
        duration=args.duration,
        control_period=args.control_period,
        pink_solvers=() if args.no_pink else tuple(_names(args.pink_solvers)),
        progress=not args.no_progress,
    )
    text = ik_report(
        results,
        duration=args.duration,
        control_period=args.control_period,
        command_line=f"mpcwalk bench ik --out {args.out}",
    )
    return _write(args.out, "ik", text, [asdict(r) for r in results])


def run_loop(args: argparse.Namespace) -> int:
    """``mpcwalk bench loop``: time the walks of every robot in MuJoCo, and the IK beside
    pink on the same robots; ``loop.md`` and ``loop.json``."""
    from mpcwalk.bench.ik import run_ik_benchmark
    from mpcwalk.bench.loop import DEFAULT_WALKS, loop_payload, loop_report, run_loop_benchmark

    cases = run_loop_benchmark(progress=not args.no_progress)
    robots = sorted({c.robot for c in cases}, key=[w[0] for w in DEFAULT_WALKS].index)
    ik = run_ik_benchmark(robots, progress=not args.no_progress)
    text = loop_report(cases, ik, command_line=f"mpcwalk bench loop --out {args.out}")
    return _write(args.out, "loop", text, loop_payload(cases, ik))
