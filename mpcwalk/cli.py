"""Command line: ``mpcwalk plan``, ``mpcwalk generators``, ``mpcwalk bench``, ``mpcwalk walk``,
``mpcwalk robots``, ``mpcwalk sweep``."""

import argparse
import os
import re
import sys
import traceback
from pathlib import Path

from mpcwalk.exceptions import ConfigurationError, MpcwalkError
from mpcwalk.walking.outputs import out_path

_DESCRIPTION = (
    "Optimization-based walking of humanoid robots: plan a walk on the LIPM (plan), list the "
    "pattern generators (generators), the named controllers (controllers) and the robots "
    "(robots), simulate a robot walking in MuJoCo (walk), run the benchmarks (bench) and the "
    "sweeps (sweep). Exit "
    "status: 0 success, 1 the simulated robot fell, 2 bad input (nothing ran), 3 the "
    "controller stopped the walk (faults beyond its bound), 4 internal error (traceback saved "
    "under --out; --debug prints it), 130 interrupted (partial results written)."
)

#: Options whose value may be a negative number ("--vx -1e-2" is read as "--vx=-1e-2").
_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Shows an option's default in its help, unless it has none (None, a flag's False) or
    the help already says it."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        if action.default is None or action.default is False or action.default == []:
            return action.help
        if "default:" in (action.help or "") or action.default is argparse.SUPPRESS:
            return action.help
        return super()._get_help_string(action)


def _use_formatter(parser: argparse.ArgumentParser) -> None:
    """Give ``parser`` and all its sub-command parsers the :class:`HelpFormatter`."""
    parser.formatter_class = HelpFormatter
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in action.choices.values():
                _use_formatter(child)


def _add_plan_parser(sub) -> None:
    p = sub.add_parser(
        "plan",
        help="plan a walk on the LIPM alone and write plots and metrics.json",
        description="Plan footsteps from a velocity command (paper M eq. 5), run a CoM/ZMP "
        "pattern generator over them on the LIPM, write a top-view plot, a CoM/ZMP-over-time "
        "plot and metrics.json into --out.",
    )
    p.add_argument(
        "--generator", default="mpc", help="pattern generator (list: mpcwalk generators)"
    )
    p.add_argument(
        "--vx",
        type=float,
        default=None,
        help="forward velocity [m/s] (default: 0.1, or the legs' reach per step when slower)",
    )
    p.add_argument("--vy", type=float, default=None, help="lateral velocity [m/s] (default: 0)")
    p.add_argument("--vyaw", type=float, default=None, help="yaw rate [rad/s] (default: 0)")
    p.add_argument(
        "--steps",
        type=int,
        default=20,
        help="number of steps that follow the command (a closing step is added)",
    )
    p.add_argument(
        "--step-duration",
        type=float,
        default=None,
        help="step duration T [s] (default: the generator's own, paper A's 12 s for the static "
        "gaits, else 0.5 s)",
    )
    p.add_argument(
        "--ds-ratio",
        type=float,
        default=None,
        help="double support ratio r_ds in [0, 1) (default: the generator's, else 0.2)",
    )
    p.add_argument("--com-height", type=float, default=0.23, help="CoM height z_c [m]")
    p.add_argument("--control-period", type=float, default=0.01, help="generator tick [s]")
    p.add_argument(
        "--solver",
        default=None,
        help="QP solver of the QP generators (osqp-direct, casadi, or a qpsolvers name; "
        "default: the generator's)",
    )
    p.add_argument("--out", type=out_path, required=True, help="output directory")
    p.add_argument("--overwrite", action="store_true", help="replace an earlier plan in --out")


def _run_plan(args) -> int:
    from mpcwalk._checks import checked_number
    from mpcwalk.footsteps.footstep import StepTiming
    from mpcwalk.footsteps.velocity_planner import VelocityCommand
    from mpcwalk.models.lipm import LIPM
    from mpcwalk.walking.cli import format_length
    from mpcwalk.walking.figures import plot_com_zmp, plot_top_view
    from mpcwalk.walking.inputs import MAX_STEPS
    from mpcwalk.walking.outputs import check_out_dir, write_atomic, write_json
    from mpcwalk.walking.planning import plan_walk

    if not 1 <= args.steps <= MAX_STEPS:
        raise ConfigurationError(
            f"--steps must be a number of steps in [1, {MAX_STEPS}], got {args.steps}; "
            "e.g. --steps 10 plans 10 steps and the closing step."
        )
    checked_number("--com-height", args.com_height, low=0.05, high=3.0, unit="m")
    out = check_out_dir(args.out, overwrite=args.overwrite)
    timing = None
    if args.step_duration is not None or args.ds_ratio is not None:
        timing = StepTiming(
            step_duration=0.5 if args.step_duration is None else args.step_duration,
            double_support_ratio=0.2 if args.ds_ratio is None else args.ds_ratio,
        )
    options = {} if args.solver is None else {"solver": args.solver}
    velocity = (args.vx, args.vy, args.vyaw)
    command = None
    if any(v is not None for v in velocity):
        command = VelocityCommand(*(0.0 if v is None else v for v in velocity))
    result = plan_walk(
        args.generator,
        command,
        args.steps,
        lipm=LIPM(com_height=args.com_height),
        timing=timing,
        control_period=args.control_period,
        generator_options=options,
    )
    out.mkdir(parents=True, exist_ok=True)
    traj = result.rollout
    m = result.metrics
    steps = _steps_text(m["nb_steps"], m["closing_steps"])
    c = m["command"]
    title = f"{args.generator}: v=({c['vx']:g}, {c['vy']:g}, {c['vyaw']:g}), {steps}"
    fig = plot_top_view(result.schedule, traj.times, traj.com, traj.zmp, title=title)
    write_atomic(out / "top_view.png", lambda tmp: fig.savefig(tmp, dpi=120))
    fig2 = plot_com_zmp(
        result.schedule,
        traj.times,
        traj.com,
        traj.zmp,
        zmp_reference=result.zmp_reference,
        title=title,
    )
    write_atomic(out / "com_zmp.png", lambda tmp: fig2.savefig(tmp, dpi=120))
    write_json(out / "metrics.json", m)
    print(
        f"{m['generator']}: {steps} over {m['duration_s']:.2f} s, "
        f"ZMP margin min {format_length(m['zmp_margin_min_m'])}, "
        f"CoM margin min {format_length(m['com_margin_min_m'])}, "
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


def _steps_text(nb_steps: int, closing_steps: int) -> str:
    """The steps of a plan in words, e.g. "10 steps + closing step"."""
    if not closing_steps:
        return f"{nb_steps} steps"
    return f"{nb_steps} steps + closing step"


def _run_generators(args) -> int:
    from mpcwalk.generators import generator_class, generator_names

    for name in generator_names():
        doc = (generator_class(name).__doc__ or "").strip().splitlines()
        print(f"{name:10s} {doc[0] if doc else ''}")
    return 0


def _run_controllers(args) -> int:
    from mpcwalk.walking.controllers import CONTROLLERS

    for config in CONTROLLERS.values():
        print(f"{config.name:13s} {config.summary}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The ``mpcwalk`` argument parser."""
    from mpcwalk import __version__

    parser = argparse.ArgumentParser(prog="mpcwalk", description=_DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"mpcwalk {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    _add_plan_parser(sub)
    sub.add_parser("generators", help="list the pattern generators")
    sub.add_parser(
        "controllers",
        help="list the named controller configurations (mpcwalk walk --controller NAME)",
    )
    from mpcwalk.bench.cli import add_bench_parser
    from mpcwalk.experiments.sweep_cli import add_sweep_parser
    from mpcwalk.viewer.replay import add_replay_parser
    from mpcwalk.walking.cli import add_robots_parser, add_walk_parser

    add_bench_parser(sub)
    add_walk_parser(sub)
    add_robots_parser(sub)
    add_sweep_parser(sub)
    add_replay_parser(sub)
    _use_formatter(parser)
    return parser


def _joined_negative_numbers(argv: list[str]) -> list[str]:
    """``--vx -0.05`` as ``--vx=-0.05``: argparse reads a negative number as an option."""
    out: list[str] = []
    for token in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and _NUMBER.match(token):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``mpcwalk`` command (exit codes: see the description)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = _joined_negative_numbers([token for token in argv if token != "--debug"])
    if "--video" not in argv:
        os.environ["MUJOCO_GL"] = "disable"  # only --video renders: no renderer needed
    else:
        try:
            import mujoco  # noqa: F401  (the renderer starts with it)
        except Exception as exc:
            print(
                f"mpcwalk: error: --video needs MuJoCo's renderer, which does not start "
                f"(MUJOCO_GL={os.environ.get('MUJOCO_GL', '')!r}: {type(exc).__name__}: {exc}); "
                "install its library (EGL or OSMesa) or choose another with MUJOCO_GL.",
                file=sys.stderr,
            )
            return 2
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return _dispatch(parser, args)
    except MpcwalkError as exc:
        print(f"mpcwalk: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("mpcwalk: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: one line and the traceback in a file, never a raw dump
        from mpcwalk.walking.outputs import save_traceback

        out = getattr(args, "out", None)
        saved = save_traceback(Path(out) if out else None, exc)
        where = f"; traceback saved to {saved}" if saved else ""
        print(f"mpcwalk: internal error: {type(exc).__name__}: {exc}{where}", file=sys.stderr)
        if debug:
            traceback.print_exc()
        return 4


def _dispatch(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    """Run the sub-command of ``args``."""
    if args.command == "plan":
        return _run_plan(args)
    if args.command == "generators":
        return _run_generators(args)
    if args.command == "controllers":
        return _run_controllers(args)
    if args.command == "bench":
        return args.bench_func(args)
    if args.command == "walk":
        from mpcwalk.walking.walk_command import run_walk_command

        if getattr(args, "view", False):
            from mpcwalk.robot import load_robot
            from mpcwalk.viewer.live import LiveView

            view = LiveView(load_robot(args.robot), port=args.view_port)
            print(f"the walk, live on http://127.0.0.1:{view.server.get_port()}")
            try:
                return run_walk_command(args, observer=view)
            finally:
                view.close()
        return run_walk_command(args)
    if args.command == "robots":
        from mpcwalk.walking.cli import run_robots_command

        return run_robots_command(args)
    if args.command == "replay":
        from mpcwalk.viewer.replay import run_replay_command

        return run_replay_command(args)
    if args.command == "sweep":
        from mpcwalk.experiments.sweep_cli import run_sweep_command

        return run_sweep_command(args)
    parser.error(f"unknown command {args.command!r}")
    return 2


if __name__ == "__main__":
    sys.exit(main())
