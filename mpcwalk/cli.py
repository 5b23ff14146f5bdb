"""Command line: ``mpcwalk plan``, ``mpcwalk generators``, ``mpcwalk bench``, ``mpcwalk walk``,
``mpcwalk robots``."""

import argparse
import json
import sys
from pathlib import Path

from mpcwalk.exceptions import MpcwalkError


def _add_plan_parser(sub) -> None:
    p = sub.add_parser(
        "plan",
        help="plan a walk on the LIPM alone and write plots and metrics.json",
        description="Plan footsteps from a velocity command (paper M eq. 5), run a CoM/ZMP "
        "pattern generator over them on the LIPM, write a top-view plot, a CoM/ZMP-over-time "
        "plot and metrics.json into --out.",
    )
    p.add_argument(
        "--generator", default="mpc", help="pattern generator (see `mpcwalk generators`)"
    )
    p.add_argument("--vx", type=float, default=0.1, help="forward velocity [m/s]")
    p.add_argument("--vy", type=float, default=0.0, help="lateral velocity [m/s]")
    p.add_argument("--vyaw", type=float, default=0.0, help="yaw rate [rad/s]")
    p.add_argument("--steps", type=int, default=20, help="number of steps")
    p.add_argument("--step-duration", type=float, default=0.5, help="step duration T [s]")
    p.add_argument(
        "--ds-ratio", type=float, default=0.2, help="double support ratio r_ds in [0, 1)"
    )
    p.add_argument("--com-height", type=float, default=0.23, help="CoM height z_c [m]")
    p.add_argument("--control-period", type=float, default=0.01, help="generator tick [s]")
    p.add_argument(
        "--solver",
        default=None,
        help="QP solver of the QP generators (osqp-direct, casadi, or a qpsolvers name)",
    )
    p.add_argument("--out", type=Path, required=True, help="output directory")


def _run_plan(args) -> int:
    from mpcwalk.footsteps.footstep import StepTiming
    from mpcwalk.footsteps.velocity_planner import VelocityCommand
    from mpcwalk.models.lipm import LIPM
    from mpcwalk.walking.plan_figures import plot_com_zmp, plot_top_view
    from mpcwalk.walking.planning import plan_walk

    timing = StepTiming(step_duration=args.step_duration, double_support_ratio=args.ds_ratio)
    options = {} if args.solver is None else {"solver": args.solver}
    result = plan_walk(
        args.generator,
        VelocityCommand(args.vx, args.vy, args.vyaw),
        args.steps,
        lipm=LIPM(com_height=args.com_height),
        timing=timing,
        control_period=args.control_period,
        generator_options=options,
    )
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    traj = result.rollout
    title = f"{args.generator}: v=({args.vx}, {args.vy}, {args.vyaw}), {args.steps} steps"
    fig = plot_top_view(result.schedule, traj.times, traj.com, traj.zmp, title=title)
    fig.savefig(out / "top_view.png", dpi=120)
    fig = plot_com_zmp(
        result.schedule,
        traj.times,
        traj.com,
        traj.zmp,
        zmp_reference=result.zmp_reference,
        title=title,
    )
    fig.savefig(out / "com_zmp.png", dpi=120)
    (out / "metrics.json").write_text(json.dumps(result.metrics, indent=2) + "\n")
    m = result.metrics
    print(
        f"{m['generator']}: {m['nb_steps']} steps over {m['duration_s']:.2f} s, "
        f"ZMP margin min {m['zmp_margin_min_m'] * 100:.2f} cm, "
        f"CoM margin min {m['com_margin_min_m'] * 100:.2f} cm, "
        f"tick median {m['tick_us_median']:.1f} us"
    )
    if m["zmp_margin_min_m"] < 0.0:
        print(
            "warning: the planned ZMP leaves the support polygon (negative margin): this "
            "generator cannot realise the command at this timing",
            file=sys.stderr,
        )
    print(f"wrote {out / 'top_view.png'}, {out / 'com_zmp.png'}, {out / 'metrics.json'}")
    return 0


def _run_generators(args) -> int:
    from mpcwalk.generators import generator_class, generator_names

    for name in generator_names():
        doc = (generator_class(name).__doc__ or "").strip().splitlines()
        print(f"{name:10s} {doc[0] if doc else ''}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The ``mpcwalk`` argument parser."""
    parser = argparse.ArgumentParser(prog="mpcwalk", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    _add_plan_parser(sub)
    sub.add_parser("generators", help="list the pattern generators")
    from mpcwalk.bench.cli import add_bench_parser
    from mpcwalk.walking.cli import add_robots_parser, add_walk_parser

    add_bench_parser(sub)
    add_walk_parser(sub)
    add_robots_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``mpcwalk`` command."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        if args.command == "plan":
            return _run_plan(args)
        if args.command == "generators":
            return _run_generators(args)
        if args.command == "bench":
            return args.bench_func(args)
        if args.command == "walk":
            from mpcwalk.walking.cli import run_walk_command

            return run_walk_command(args)
        if args.command == "robots":
            from mpcwalk.walking.cli import run_robots_command

            return run_robots_command(args)
    except MpcwalkError as exc:
        print(f"mpcwalk: error: {exc}", file=sys.stderr)
        return 2
    parser.error(f"unknown command {args.command!r}")
    return 2


if __name__ == "__main__":
    sys.exit(main())
