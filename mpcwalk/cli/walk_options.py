"""The options of ``mpcwalk walk`` and the walk specification they make.

Every option that describes the walk is a field of the
:class:`~mpcwalk.walking.specification.WalkSpec` (or a few of them: ``--vx`` is a component of
``command``); its default is the specification's. An option not given is absent from the
parsed arguments, so that with ``--spec FILE`` the options given change those fields of the
file's walk and nothing else (:func:`spec_from_args`). Input checking happens here, at the
boundary: every bad value is a named error before anything runs.
"""

import argparse
from pathlib import Path
from typing import Any

from mpcwalk.cli.world_options import add_world_options, world_fields
from mpcwalk.exceptions import ConfigurationError

S = argparse.SUPPRESS

#: The default robot of ``mpcwalk walk``.
DEFAULT_ROBOT = "bioloid-like"


def add_walk_options(p: argparse.ArgumentParser) -> None:
    """The options of a walk (controller, plan, world, disturbances, run)."""
    p.add_argument(
        "--spec",
        type=Path,
        default=None,
        metavar="FILE",
        help="walk the "
        "specification FILE (a spec.toml a walk wrote); the options given beside it "
        "change those fields",
    )
    p.add_argument(
        "--robot",
        default=S,
        help=f"robot name (list: mpcwalk robots) or preset file (default: {DEFAULT_ROBOT})",
    )
    c = p.add_argument_group(
        "controller",
        "A named controller, or its parts; parts given beside a named controller change it.",
    )
    c.add_argument(
        "--controller",
        default=S,
        help="named controller (list: mpcwalk "
        "controllers), e.g. paper-m, paper-a, mpc (default: mpc)",
    )
    c.add_argument("--generator", default=S, help="pattern generator (list: mpcwalk generators)")
    c.add_argument(
        "--solver",
        default=S,
        help="QP solver of the QP generators (list: mpcwalk solvers; default: the generator's)",
    )
    c.add_argument(
        "--dynamics-solver",
        default=S,
        metavar="NAME",
        help="QP solver of the inverse dynamics of a torque walk (--actuation torque; a name "
        "of mpcwalk solvers that takes equalities and inequalities; default: daqp-direct)",
    )
    c.add_argument(
        "--torque-loop",
        dest="torque_loop",
        action="store_true",
        default=S,
        help="divide a torque walk's torques by each motor's gain as its joint torque sensor "
        "measures it (--actuation torque; off by default)",
    )
    c.add_argument(
        "--stabilizer",
        default=S,
        metavar="NAME",
        help="stabilizer on the servo "
        "targets (list: mpcwalk stabilizers; ankle-imu: paper A's ankle strategy and "
        "IMU correction; gyro: paper M's eq. 26-30; none)",
    )
    c.add_argument(
        "--reaim",
        dest="reaim",
        action="store_true",
        default=S,
        help="paper A's "
        "state machine: re-aim each step from the estimated support foot (default: "
        "on with --path when the controller is composed by hand)",
    )
    c.add_argument(
        "--no-reaim",
        dest="reaim",
        action="store_false",
        default=S,
        help="follow the planned footsteps without re-aiming",
    )
    c.add_argument(
        "--hold-position",
        dest="hold_position",
        action="store_true",
        default=S,
        help="hold the footholds' positions in the world, not only their heading: each "
        "landing from the support foot where the robot measures it (generators that follow "
        "new footsteps: mpc, preview, static-qp)",
    )
    c.add_argument(
        "--arm-swing",
        type=float,
        default=S,
        metavar="S",
        help="paper M's arm swing factor s (eq. 24-25); paper M uses 0.8, 0: arms still",
    )
    c.add_argument(
        "--swing-profile",
        choices=("cosine", "ctraj"),
        default=S,
        help="swing foot: "
        "paper M's cosines or paper A's quintic Cartesian lift (default: ctraj with "
        "--stabilizer ankle-imu)",
    )
    c.add_argument(
        "--no-feedback",
        dest="feedback",
        action="store_false",
        default=S,
        help="open loop: no estimated CoM to the generator, no DCM feedback, no balance stabilizer",
    )
    plan = p.add_argument_group("plan")
    plan.add_argument("--vx", type=float, default=S, help="forward velocity [m/s] (default: 0.1)")
    plan.add_argument("--vy", type=float, default=S, help="lateral velocity [m/s] (default: 0)")
    plan.add_argument("--vyaw", type=float, default=S, help="yaw rate [rad/s] (default: 0)")
    plan.add_argument(
        "--path",
        type=Path,
        default=S,
        help="footstep path file (.mdat, paper A) instead of a velocity command",
    )
    plan.add_argument(
        "--duration",
        type=float,
        default=S,
        help="walking time [s]: "
        "round(duration / T) steps, then a closing step (the simulation also "
        "stands still 1 s before and after); with --path, the path is cut after "
        "that many steps",
    )
    plan.add_argument(
        "--steps",
        dest="nb_steps",
        type=int,
        default=S,
        help="number of steps instead of --duration (a velocity command adds a closing step)",
    )
    plan.add_argument(
        "--step-duration",
        type=float,
        default=S,
        help="step duration T [s] (default: the generator's own, else the robot preset's)",
    )
    plan.add_argument(
        "--terrain-cadence",
        dest="terrain_cadence",
        action="store_true",
        default=S,
        help="on a terrain (--terrain), lengthen every step so that none advances faster "
        "than 75 %% of the flat legs' top speed, the command divided alike (the same "
        "footsteps, slower); stairs and stones otherwise make the walk climb several times "
        "faster than commanded",
    )
    plan.add_argument(
        "--ds-ratio",
        dest="double_support_ratio",
        type=float,
        default=S,
        help="double support ratio r_ds (default: the robot preset's)",
    )
    plan.add_argument(
        "--step-height",
        type=float,
        default=S,
        help="swing-foot height [m] (default: the robot preset's)",
    )
    plan.add_argument(
        "--control-period", type=float, default=S, help="controller tick [s] (default: 0.01)"
    )
    add_world_options(p)
    p.add_argument(
        "--push",
        dest="pushes",
        action="append",
        default=S,
        metavar="T,DURATION,FX,FY,FZ",
        help="push the torso: start [s], duration [s], world force [N]; repeatable",
    )


#: Options that are fields of the specification under the same name.
_FIELDS = (
    "generator", "arm_swing", "swing_profile", "feedback", "path", "duration", "nb_steps",
    "step_duration", "double_support_ratio", "step_height", "control_period", "noise_scale",
    "terrain_cadence",
    "latency", "ideal", "state", "mass_scale", "friction", "servo_strength", "friction_cone",
    "impratio", "ground_tilt", "ground_tilt_direction", "ground_roughness", "seed", "actuation",
)  # fmt: skip


def spec_from_args(args: argparse.Namespace, *, out: Path) -> Any:
    """The walk specification of ``mpcwalk walk``'s arguments (see the module docstring).

    Raises:
        MpcwalkError: A bad option, a bad specification file, or options that contradict
            each other.
    """
    from mpcwalk.sim import parse_push
    from mpcwalk.walking.specification import WalkSpec, read_spec

    given = vars(args)
    base_file = args.spec
    if base_file is not None:
        spec = read_spec(base_file)
    else:
        spec = WalkSpec.build(DEFAULT_ROBOT)
    fields: dict[str, Any] = {k: given[k] for k in _FIELDS if k in given}
    if "robot" in given:
        fields["robot"] = given["robot"]
    if "controller" in given:
        fields["controller"] = given["controller"]
    velocity = [given.get(k) for k in ("vx", "vy", "vyaw")]
    if any(v is not None for v in velocity):
        if "path" in given:
            raise ConfigurationError(
                "Give either a velocity command (--vx, --vy, --vyaw) or --path FILE.mdat, not both."
            )
        fields["command"] = tuple(0.0 if v is None else v for v in velocity)
        fields.setdefault("path", None)
    elif "path" in given:
        fields["command"] = None
    if "nb_steps" in given and "duration" in given:
        raise ConfigurationError("Give either --duration or --steps, not both.")
    if "nb_steps" in given:
        fields["duration"] = None
    if "duration" in given:
        fields["nb_steps"] = None
    fields.update(world_fields(given))
    if "pushes" in given:
        fields["pushes"] = tuple(parse_push(text) for text in given["pushes"])
        fields["yaw_reference"] = True
    spec = spec.replace(**fields)
    if "solver" in given:
        solver = {"solver": given["solver"]}
        spec = spec.replace(generator_options={**spec.controller.generator_options, **solver})
    if "dynamics_solver" in given:
        dynamics = {"dynamics_solver": given["dynamics_solver"]}
        spec = spec.replace(controller_options={**spec.controller.controller_options, **dynamics})
    if "torque_loop" in given:
        loop = {"torque_loop": bool(given["torque_loop"])}
        spec = spec.replace(controller_options={**spec.controller.controller_options, **loop})
    if "hold_position" in given:
        hold = {"hold_position": bool(given["hold_position"])}
        spec = spec.replace(controller_options={**spec.controller.controller_options, **hold})
    spec = _stabilizers(spec, given, by_hand=base_file is None and "controller" not in given)
    if (
        base_file is None
        and spec.plan.path is None
        and spec.plan.nb_steps is None
        and (spec.plan.duration is None)
    ):
        raise ConfigurationError(
            "A walk from a velocity command needs --duration S (walking time) or --steps N."
        )
    return spec.replace(
        progress=not given.get("no_progress", False),
        video=str(out / "walk.mp4") if given.get("video") else None,
    )


def _stabilizers(spec: Any, given: dict[str, Any], *, by_hand: bool) -> Any:
    """``--stabilizer`` and ``--reaim`` as the controller's stabilizers; composed by hand,
    a path file re-aims by default and paper A's ankle strategy swings with ctraj."""
    if "stabilizer" not in given and "reaim" not in given and not by_hand:
        return spec
    names = list(spec.controller.stabilizers)
    reaim = given.get("reaim")
    if reaim is None and by_hand:
        reaim = spec.plan.path is not None
    if reaim is not None:
        names = [n for n in names if n != "reaim"] + (["reaim"] if reaim else [])
        names.sort(key=lambda n: n != "reaim")  # re-aiming moves the targets first
    if "stabilizer" in given:
        names = [n for n in names if n == "reaim"]
        if given["stabilizer"] != "none":
            names.append(given["stabilizer"])
    changes: dict[str, Any] = {"stabilizers": tuple(names)}
    if by_hand and "swing_profile" not in given and "ankle-imu" in names:
        changes["swing_profile"] = "ctraj"
    if tuple(names) == spec.controller.stabilizers and len(changes) == 1:
        return spec
    return spec.replace(**changes)


__all__ = ["DEFAULT_ROBOT", "add_walk_options", "spec_from_args"]
