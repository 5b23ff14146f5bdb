"""Command line of the simulated walks: ``mpcwalk walk`` and ``mpcwalk robots``.

``mpcwalk walk`` simulates one walk and writes into ``--out``: ``metrics.json``, the per-tick
log (``walk_log.npz``, or ``.csv`` with ``--log-format csv``), ``top_view.png`` (footsteps,
landed soles, CoM and measured CoP from above), ``com_cop.png`` (CoM, ZMP reference and
measured CoP over time), ``estimator.png`` (the estimated state against the ground truth,
when the controller walked on the estimator) and, with ``--video``, ``walk.mp4``.
"""

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mpcwalk.control.stabilizers import STABILIZER_NAMES
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.walking.outputs import out_path
from mpcwalk.walking.world_arguments import add_world_arguments

if TYPE_CHECKING:
    from mpcwalk.walking.result import WalkResult


def add_walk_parser(sub) -> argparse.ArgumentParser:
    """Add the ``walk`` sub-command to ``sub`` (the result of ``add_subparsers``)."""
    p = sub.add_parser(
        "walk",
        help="simulate a robot walking in MuJoCo and write metrics, log, plots (and a video)",
        description="Plan footsteps from a velocity command (paper M) or a .mdat path file "
        "(paper A), drive the robot with a pattern generator, the whole-body IK and its "
        "position servos in MuJoCo, and write metrics.json, the per-tick log, a top-view plot "
        "and a CoM/CoP-over-time plot into --out (and walk.mp4 with --video). Walking "
        "defaults (step duration, swing height, leg limits) come from the robot's preset.",
    )
    p.add_argument("--robot", default="bioloid-like", help="robot name (list: mpcwalk robots)")
    p.add_argument(
        "--controller",
        default=None,
        help="a named controller configuration (list: mpcwalk controllers), e.g. paper-m, "
        "paper-a, mpc; it sets the generator, feedback, stabilizer, arm swing and re-aiming",
    )
    p.add_argument(
        "--generator",
        default=None,
        help="pattern generator, without --controller (list: mpcwalk generators) (default: mpc)",
    )
    p.add_argument("--vx", type=float, default=None, help="forward velocity [m/s] (default: 0.1)")
    p.add_argument("--vy", type=float, default=None, help="lateral velocity [m/s] (default: 0)")
    p.add_argument("--vyaw", type=float, default=None, help="yaw rate [rad/s] (default: 0)")
    p.add_argument(
        "--path",
        type=Path,
        default=None,
        help="footstep path file (.mdat, paper A) instead of a velocity command",
    )
    p.add_argument(
        "--duration",
        type=float,
        default=None,
        help="walking time [s]: round(duration / T) steps, then a closing step (the "
        "simulation also stands still before and after: the console and metrics.json say "
        "what was planned and simulated); with --path, the path is cut after that many steps",
    )
    p.add_argument(
        "--steps",
        type=int,
        default=None,
        help="number of steps instead of --duration (a velocity command adds a closing step)",
    )
    p.add_argument(
        "--step-duration",
        type=float,
        default=None,
        help="step duration T [s] (default: the robot preset's)",
    )
    p.add_argument(
        "--ds-ratio",
        type=float,
        default=None,
        help="double support ratio r_ds (default: the robot preset's)",
    )
    p.add_argument(
        "--step-height",
        type=float,
        default=None,
        help="swing-foot height [m] (default: the robot preset's)",
    )
    p.add_argument("--control-period", type=float, default=0.01, help="controller tick [s]")
    p.add_argument(
        "--solver",
        default=None,
        help="QP solver of the QP generators (default: the generator's)",
    )
    p.add_argument(
        "--stabilizer",
        choices=STABILIZER_NAMES,
        default="none",
        help="stabilizer on the servo targets (ankle-imu: paper A's ankle strategy "
        "and IMU correction; gyro: paper M's leg offsets from the torso's roll and "
        "pitch rates, eq. 26-30)",
    )
    p.add_argument(
        "--arm-swing",
        type=float,
        default=0.0,
        metavar="S",
        help="paper M's arm swing factor s (eq. 24-25): each hand moves forward by "
        "s times the opposite foot's displacement; paper M uses 0.8, 0: arms still",
    )
    p.add_argument(
        "--reaim",
        dest="reaim",
        action="store_true",
        default=None,
        help="paper A's state machine: re-aim each step from the estimated support "
        "foot (drift does not accumulate); default: on with --path",
    )
    p.add_argument(
        "--no-reaim",
        dest="reaim",
        action="store_false",
        help="follow the planned footsteps without re-aiming",
    )
    p.add_argument(
        "--swing-profile",
        choices=("cosine", "ctraj"),
        default=None,
        help="swing foot: paper M's cosines or paper A's quintic Cartesian lift and "
        "lower (default: ctraj with --stabilizer ankle-imu, i.e. paper A's gait)",
    )
    p.add_argument(
        "--no-feedback",
        action="store_true",
        help="open loop: no estimated CoM to the generator, no DCM feedback, no balance stabilizer",
    )
    p.add_argument(
        "--push",
        action="append",
        default=[],
        metavar="T,DURATION,FX,FY,FZ",
        help="push the torso: start [s], duration [s], world force [N]; repeatable",
    )
    add_world_arguments(p)
    p.add_argument("--video", action="store_true", help="render walk.mp4 (offscreen)")
    p.add_argument(
        "--view",
        action="store_true",
        help="show the walk live in the browser (3D viewer on --view-port), in real time",
    )
    p.add_argument("--view-port", type=int, default=8080, help="port of the live viewer")
    p.add_argument(
        "--log-format", choices=("npz", "csv"), default="npz", help="format of the per-tick log"
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--out", type=out_path, required=True, help="output directory")
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="replace an earlier run in --out (refused otherwise)",
    )
    p.epilog = (
        "Exit status: 0 when the robot walked the whole schedule, 1 when it fell, 2 on bad input."
    )
    return p


def _by_hand(args) -> dict:
    """The parts given by hand (all of them without --controller; with it, none may be)."""
    if args.controller is None:
        return {
            "feedback": not args.no_feedback,
            "stabilizer": _stabilizer(args),
            "controller_options": {"swing_profile": _swing_profile(args)},
            "arm_swing": args.arm_swing,
        }
    given = [
        option
        for option, value in (
            ("--generator", args.generator),
            ("--no-feedback", args.no_feedback or None),
            ("--stabilizer", None if args.stabilizer == "none" else args.stabilizer),
            ("--arm-swing", args.arm_swing or None),
            ("--reaim/--no-reaim", args.reaim),
            ("--swing-profile", args.swing_profile),
        )
        if value is not None
    ]
    if given:
        raise ConfigurationError(
            f"--controller {args.controller} sets its own parts; drop {', '.join(given)}, or "
            "compose the controller by hand with --generator and those options."
        )
    return {}


def _swing_profile(args) -> str:
    """``--swing-profile``, by default paper A's with paper A's stabilizer."""
    if getattr(args, "swing_profile", None):
        return args.swing_profile
    return "ctraj" if getattr(args, "stabilizer", "none") == "ankle-imu" else "cosine"


def _stabilizer(args):
    """The stabilizer of ``--stabilizer`` and ``--reaim`` (None: neither); re-aiming is on
    by default for path files."""
    from mpcwalk.control.stabilizers import StabilizerChain, make_stabilizer

    parts = []
    reaim = getattr(args, "reaim", None)
    if reaim is None:
        reaim = getattr(args, "path", None) is not None
    if reaim:
        from mpcwalk.control.stabilizers.paper_a import PaperAStateMachine

        parts.append(PaperAStateMachine())
    stabilizer = make_stabilizer(getattr(args, "stabilizer", "none"))
    if stabilizer is not None:
        parts.append(stabilizer)
    return StabilizerChain(parts) if parts else None


def format_length(value: float | None) -> str:
    """A length [m] in millimetres with three significant digits (4e-6 m: "0.004 mm")."""
    if value is None:
        return "n/a"
    digits = np.format_float_positional(
        1e3 * value, precision=3, unique=False, fractional=False, trim="-"
    )
    return f"{digits} mm"


def _format(value: float | None, unit: str = "") -> str:
    return "n/a" if value is None else f"{value:.2f}{unit}"


def summary(result: "WalkResult") -> str:
    """Two lines telling what was planned and simulated, and how the walk went."""
    m, config = result.metrics, result.config
    state = f"FELL at {m.fall_time_s:.2f} s ({m.fall_reason})" if m.fell else "no fall"
    if m.outcome in ("stopped", "interrupted"):
        state = f"{m.outcome.upper()} at {m.time_simulated_s:.2f} s"
    steps = f"{m.steps_planned} steps"
    if m.closing_steps:
        steps = f"{m.steps_planned - m.closing_steps} steps + {m.closing_steps} closing step"
    standing = m.time_planned_s - m.walking_time_planned_s
    asked = "" if config.duration_s is None else f" for --duration {config.duration_s:g} s"
    return (
        f"{result.robot} {result.generator}: planned {steps}{asked}, "
        f"{m.time_planned_s:.2f} s ({m.walking_time_planned_s:.2f} s walking, "
        f"{standing:.2f} s standing before and after); simulated {m.time_simulated_s:.2f} s\n"
        f"{state}; {m.steps_completed}/{m.steps_planned} steps completed, "
        f"{m.distance_m:.3f} m (planned {m.distance_planned_m:.3f} m), yaw "
        f"{m.yaw_change_deg:.1f} deg, foot error {_format(m.foot_position_error_cm_mean, ' cm')} "
        f"mean, CoP margin min {format_length(m.cop_margin_min_m)}, real time "
        f"x{_format(m.real_time_factor)}\n{_sensing(result)}"
    )


def _sensing(result: "WalkResult") -> str:
    """One line on what the controller read and how well it knew the robot."""
    m, config = result.metrics, result.config
    sensors = "ideal sensors" if config.ideal_sensors else f"noise x{config.noise_scale:g}"
    text = f"state: {config.state_source} ({sensors}, latency {1e3 * config.latency_s:g} ms)"
    changed = {
        key: value
        for key, value in config.perturbation.items()
        if value not in (None, 1.0, [0.0, 0.0], (0.0, 0.0))
    }
    if changed:
        text += "; world: " + ", ".join(f"{key} {value}" for key, value in changed.items())
    if m.estimator_com_error_rms_m is not None:
        text += (
            f"; estimator CoM error RMS {format_length(m.estimator_com_error_rms_m)}, "
            f"max {format_length(m.estimator_com_error_max_m)} (relative to the support "
            f"{format_length(m.estimator_com_error_support_rms_m)}), yaw drift "
            f"{_format(m.estimator_yaw_drift_deg, ' deg')}"
        )
    return text


def add_robots_parser(sub) -> argparse.ArgumentParser:
    """Add the ``robots`` sub-command to ``sub`` (``mpcwalk robots`` lists them,
    ``mpcwalk robots check NAME|PRESET`` runs the checks a preset must pass)."""
    p = sub.add_parser(
        "robots",
        help="list the robots that load on this machine; 'robots check PRESET' checks one",
        description="List the robots whose description is installed, with their size and "
        "walking defaults. 'mpcwalk robots check NAME|PRESET.toml' runs the checks a preset "
        "must pass: it loads, Pinocchio and MuJoCo agree, the nominal posture is flat and "
        "stands under the servos, a short walk with mpc does not fall (exit code 1 when one "
        "fails).",
    )
    p.add_argument("action", nargs="?", choices=["check"], help="check one robot")
    p.add_argument("robot", nargs="?", help="robot name or path of a preset file (.toml)")
    p.add_argument("--no-walk", action="store_true", help="skip the short walk")
    return p


def run_robots_check(args) -> int:
    """Run ``mpcwalk robots check ROBOT``: one line per check; 1 when one fails."""
    from mpcwalk.walking.robot_check import check_robot

    if not args.robot:
        raise ConfigurationError(
            "mpcwalk robots check needs a robot: a name (mpcwalk robots) or the path of a "
            "preset file, e.g. mpcwalk robots check my_robot/my_biped.toml."
        )
    results = check_robot(args.robot, walk=not args.no_walk)
    for result in results:
        print(f"{'ok  ' if result.passed else 'FAIL'} {result.name}: {result.detail}")
    return 0 if all(r.passed for r in results) else 1


def run_robots_command(args) -> int:
    """Run ``mpcwalk robots``: one line per robot that loads.

    Raises:
        ConfigurationError: No robot is installed (exit code 2 in ``main``).
    """
    from mpcwalk.robot.loading import PRESETS_DIR, load_robot, robot_names

    if getattr(args, "action", None) == "check":
        return run_robots_check(args)
    names = robot_names()
    if not names:
        raise ConfigurationError(
            f"No robot found: searched {PRESETS_DIR} for presets (*.toml) whose description "
            "is installed (MJCF files in the robots folder, URDF models of the "
            "example-robot-data package). Reinstall mpcwalk with its robot files."
        )
    for name in names:
        robot = load_robot(name, visual=False)
        period = robot.gait.step_duration
        print(
            f"{name:14s} {len(robot.joint_names):2d} joints, {robot.total_mass:6.1f} kg, CoM "
            f"height {robot.com_height:.3f} m, soles {robot.sole_size[0]:.2f} x "
            f"{robot.sole_size[1]:.2f} m, step duration "
            f"{period:g} s  "
            f"[{robot.description_path.name}]"
        )
    return 0
