"""The checks a robot preset must pass before it walks (``mpcwalk robots check PRESET``).

1. **It loads**: the description is found, the frames and joints the preset names exist,
   its keys are known (``load_robot`` raises a named error otherwise); the links of a URDF
   whose inertias MuJoCo refuses are listed (repaired by :mod:`mpcwalk.robot.urdf_repair`).
2. **The engines agree**: for random configurations, Pinocchio's and MuJoCo's sole poses and
   CoM match (both load the same description).
3. **The nominal posture**: its joints within their limits, both soles flat on the floor on
   their own side, the CoM at the preset's height above the middle of the soles, the torso
   frame upright and facing forward (:mod:`mpcwalk.walking.posture_checks`).
4. **The body**: the soles on the feet's shapes, the servos strong enough to hold the
   posture (:mod:`mpcwalk.walking.body_checks`).
5. **It stands**: one second in MuJoCo under its servos, carrying its weight on its feet.
6. **It walks**: a short walk with the linear MPC on the robot's own walking defaults does
   not fall.

Checks 1 to 4 all run (each failure says its number and its likely fix); 5 and 6 run when
they passed.
"""

from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from mpcwalk.exceptions import MpcwalkError, RobotNotFound
from mpcwalk.robot import Robot, load_robot
from mpcwalk.sim import make_mj_data
from mpcwalk.walking.body_checks import (
    TORQUE_SHARE_LIMIT,
    check_inertias,
    check_servo_torques,
    check_soles_on_feet,
)
from mpcwalk.walking.posture_checks import (
    CheckResult,
    check_joint_limits,
    check_posture,
    check_torso,
)

#: Largest disagreement accepted between the two engines [m].
ENGINE_TOLERANCE = 1e-6


def _random_configuration(robot: Robot, rng: np.random.Generator) -> np.ndarray:
    q = np.empty(robot.model.nq)
    q[0:3] = rng.uniform(-1.0, 1.0, 3)
    quaternion = rng.normal(size=4)
    q[3:7] = quaternion / np.linalg.norm(quaternion)
    lower = np.clip(robot.model.lowerPositionLimit[7:], -np.pi, np.pi)
    upper = np.clip(robot.model.upperPositionLimit[7:], -np.pi, np.pi)
    q[7:] = rng.uniform(lower, upper)
    return q


def check_engines(robot: Robot, *, samples: int = 5, seed: int = 0) -> CheckResult:
    """Pinocchio and MuJoCo agree on the soles and the CoM at random configurations."""
    rng, data, worst = np.random.default_rng(seed), mujoco.MjData(robot.mj_model), 0.0
    root = int(robot.mj_model.jnt_bodyid[0])
    for _ in range(samples):
        q = _random_configuration(robot, rng)
        data.qpos[:] = robot.q_to_qpos(q)
        mujoco.mj_forward(robot.mj_model, data)
        for frame in robot.foot_frames:
            site = robot.mj_model.site(frame).id
            placement = robot.compute_frame_placement(q, frame)
            worst = max(worst, float(np.abs(placement.translation - data.site_xpos[site]).max()))
        worst = max(worst, float(np.abs(robot.compute_com(q) - data.subtree_com[root]).max()))
    return CheckResult(
        "the engines agree",
        worst < ENGINE_TOLERANCE,
        f"largest sole or CoM difference {worst:.1e} m over {samples} random configurations",
    )


def check_standing(robot: Robot, duration: float = 1.0) -> CheckResult:
    """The robot stands ``duration`` seconds in MuJoCo under its servos, none of them past
    :data:`~mpcwalk.walking.body_checks.TORQUE_SHARE_LIMIT` of its force limit in the last
    half of it."""
    data = make_mj_data(robot)
    height = float(data.qpos[2])
    model = robot.mj_model
    limited = model.actuator_forcelimited.astype(bool)
    limits = np.where(limited, np.abs(model.actuator_forcerange).max(axis=1), 0.0)
    peak = np.zeros(model.nu)
    while data.time < duration:
        mujoco.mj_step(model, data)
        if data.time > 0.5 * duration:
            peak = np.maximum(peak, np.abs(data.actuator_force))
    shares = np.where(limits > 0, peak / np.where(limits > 0, limits, 1.0), 0.0)
    sink = abs(float(data.qpos[2]) - height)
    tilt = np.degrees(2.0 * np.arccos(min(1.0, abs(float(data.qpos[3])))))
    load = data.sensor("left_foot_touch").data[0] + data.sensor("right_foot_touch").data[0]
    share = float(load) / (robot.total_mass * 9.81)
    saturated = [
        f"{model.actuator(i).name} {peak[i]:.1f} N m = {100 * shares[i]:.0f} % of {limits[i]:.1f}"
        for i in np.argsort(-shares)
        if shares[i] > TORQUE_SHARE_LIMIT
    ]
    passed = sink < 0.05 * height and tilt < 5.0 and abs(share - 1.0) < 0.05 and not saturated
    if saturated:
        servos = (
            f"servos past {100 * TORQUE_SHARE_LIMIT:.0f} % of their force limit: "
            + ", ".join(saturated)
            + " (raise the force limit in the preset's [[actuators]] or the MJCF file)"
        )
    elif model.nu:
        worst = int(np.argmax(shares))
        servos = (
            f"largest servo torque {peak[worst]:.1f} N m, {100 * shares[worst]:.0f} % of its "
            f"limit ({model.actuator(worst).name})"
        )
    else:
        servos = "no servo"
    return CheckResult(
        "it stands under its servos",
        passed,
        f"after {duration:g} s: base {1000 * sink:.1f} mm lower, tilted {tilt:.1f} deg, "
        f"feet carry {100 * share:.0f} % of its weight; {servos}",
    )


def check_walk(robot: Robot, nb_steps: int = 4) -> CheckResult:
    """A short walk with the linear MPC on the robot's walking defaults."""
    from mpcwalk.walking.runner import run_walk

    speed = 0.5 * robot.leg_limits.max_step_forward / robot.gait.step_duration
    result = run_walk(robot, controller="mpc", command=(speed, 0.0, 0.0), nb_steps=nb_steps)
    m = result.metrics
    return CheckResult(
        "it walks",
        not m.fell,
        f"{nb_steps} steps at {speed:.2f} m/s with mpc: "
        + (f"fell at {m.fall_time_s:.1f} s ({m.fall_reason})" if m.fell else "no fall")
        + (
            f", landings within {m.foot_position_error_cm_max:.1f} cm"
            if m.foot_position_error_cm_max is not None
            else ""
        ),
    )


def check_robot(name_or_preset: str | Path, *, walk: bool = True) -> list[CheckResult]:
    """Every check of a robot (a shipped name or the path of a preset file): the checks of
    the loaded robot all run; standing and walking only when they passed (a robot that does
    not load is one failed check).

    Raises:
        RobotNotFound: No such robot or preset file, or its description is not found: there
            is nothing to check (exit code 2 on the command line).
    """
    try:
        robot = load_robot(name_or_preset, visual=False)
    except RobotNotFound:
        raise
    except MpcwalkError as error:
        return [CheckResult("it loads", False, str(error))]
    results = [
        CheckResult(
            "it loads",
            True,
            f"{robot.name}: {len(robot.joint_names)} joints, {robot.total_mass:.1f} kg",
        )
    ]
    static: list[Callable[[Robot], CheckResult]] = [
        check_inertias,
        check_engines,
        check_joint_limits,
        check_posture,
        check_torso,
        check_soles_on_feet,
        check_servo_torques,
    ]
    results += [check(robot) for check in static]
    dynamic: list[Callable[[Robot], CheckResult]] = [check_standing]
    if walk:
        dynamic.append(check_walk)
    for check in dynamic:
        if not all(r.passed for r in results):
            break
        results.append(check(robot))
    return results


__all__ = [
    "CheckResult",
    "check_engines",
    "check_inertias",
    "check_joint_limits",
    "check_posture",
    "check_robot",
    "check_servo_torques",
    "check_soles_on_feet",
    "check_standing",
    "check_torso",
]
