"""``mpcwalk plan``: a walk planned on the LIPM alone (no robot, no simulator): footsteps
from a velocity command, a pattern generator over them, plots and ``metrics.json``."""

import argparse
import sys

from mpcwalk.cli.console import format_length, out_path
from mpcwalk.exceptions import ConfigurationError


def add_parser(sub) -> argparse.ArgumentParser:
    """Add ``plan`` to ``sub`` (the result of ``add_subparsers``)."""
    p = sub.add_parser(
        "plan",
        help="plan a walk on the LIPM alone and write plots and metrics.json",
        description="Plan footsteps from a velocity command (paper M eq. 5), run a CoM/ZMP "
        "pattern generator over them on the LIPM, write a top-view plot, a CoM/ZMP-over-time "
        "plot and metrics.json into --out (with --mdat, the footsteps as footsteps.mdat too).",
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
    p.add_argument(
        "--mdat",
        action="store_true",
        help="also write the planned footsteps as footsteps.mdat in --out (paper A's path "
        "format: one stance per line, both feet's position and quaternion; --path of "
        "mpcwalk walk reads it back)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace an earlier plan in --out")
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    """Run ``mpcwalk plan``."""
    from mpcwalk._checks import checked_number
    from mpcwalk.footsteps.footstep import StepTiming
    from mpcwalk.footsteps.velocity_planner import VelocityCommand
    from mpcwalk.models.lipm import LIPM
    from mpcwalk.walking.figures import plot_com_zmp, plot_top_view
    from mpcwalk.walking.lipm_plan import plan_walk
    from mpcwalk.walking.outputs import check_out_dir, write_atomic, write_json
    from mpcwalk.walking.specification.plan import MAX_STEPS

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
    written = [out / "top_view.png", out / "com_zmp.png", out / "metrics.json"]
    if args.mdat:
        from mpcwalk.footsteps.mdat import write_mdat

        header = f"mpcwalk plan: {title}; step duration {result.schedule.step_duration:g} s"
        write_atomic(
            out / "footsteps.mdat", lambda tmp: write_mdat(tmp, result.schedule.plan, header=header)
        )
        written.append(out / "footsteps.mdat")
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
    print("wrote " + ", ".join(str(path) for path in written))
    return 0


def _steps_text(nb_steps: int, closing_steps: int) -> str:
    """The steps of a plan in words, e.g. "10 steps + closing step"."""
    if not closing_steps:
        return f"{nb_steps} steps"
    return f"{nb_steps} steps + closing step"
