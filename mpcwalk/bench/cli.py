"""``mpcwalk bench ...`` sub-commands."""

from dataclasses import asdict
from pathlib import Path


def _run_ticks(args) -> int:
    from mpcwalk.bench.output import machine_description, write_bench_output
    from mpcwalk.bench.ticks import format_table, run_tick_benchmark
    from mpcwalk.footsteps.velocity_planner import VelocityCommand

    results = run_tick_benchmark(
        nb_steps=args.steps,
        command=VelocityCommand(args.vx, args.vy, args.vyaw),
        control_period=args.control_period,
        solvers=args.solvers.split(",") if args.solvers else None,
        include_peer=not args.no_peer,
        progress=not args.no_progress,
    )
    from mpcwalk.generators.mpc import MpcGenerator

    table = format_table(results)
    params = MpcGenerator.default_parameters
    header = (
        f"Per-tick time of each pattern generator, {args.steps}-step walk at "
        f"v=({args.vx}, {args.vy}, {args.vyaw}), control period {args.control_period} s, "
        f"MPC (and qpmpc peer) horizon {params.horizon} samples at {params.sampling_period} s; "
        f"static gaits on slow timing (T = 2 s, r_ds = 0.5, same step lengths). "
        f"Machine: {machine_description()}.\n"
        f"Command: `mpcwalk bench ticks --out {args.out}`\n"
    )
    write_bench_output(
        args.out, "ticks", header + "\n" + table + "\n", [asdict(r) for r in results]
    )
    return 0


def add_bench_parser(sub) -> None:
    """Add ``bench`` and its sub-commands to the top-level parser."""
    from mpcwalk.bench.ticks import DEFAULT_QPSOLVERS

    bench = sub.add_parser(
        "bench", help="benchmarks: generator ticks, whole-body IK, walk loop, QP solvers"
    )
    bsub = bench.add_subparsers(dest="bench_command", required=True)
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
    ticks.add_argument("--no-peer", action="store_true", help="skip the qpmpc peer")
    ticks.add_argument("--no-progress", action="store_true", help="no progress bar")
    ticks.add_argument(
        "--out",
        type=Path,
        default=Path("results/ticks"),
        help="output directory (ticks.md, ticks.json)",
    )
    ticks.set_defaults(bench_func=_run_ticks)
    from mpcwalk.bench.ik import add_ik_bench_parser

    add_ik_bench_parser(bsub)
    from mpcwalk.bench.loop import add_loop_bench_parser

    add_loop_bench_parser(bsub)
    from mpcwalk.bench.solvers.cli import add_solver_bench_parser

    add_solver_bench_parser(bsub)
