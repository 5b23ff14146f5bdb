"""The checks a robot preset must pass before it walks (``mpcwalk robots check PRESET``).

1. **It loads**: the description is found, the frames and joints the preset names exist,
   its keys are known (``load_robot`` raises a named error otherwise).
2. **The engines agree**: for random configurations, Pinocchio's and MuJoCo's sole poses and
   CoM match (both load the same description).
3. **The nominal posture stands**: both soles flat on the floor on their own side, the CoM at
   the preset's height above the middle of the soles, and the robot standing one second in
   MuJoCo under its servos, carrying its weight on its feet.
4. **It walks**: a short walk with the linear MPC on the robot's own walking defaults does
   not fall.
"""

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from mpcwalk.exceptions import MpcwalkError
from mpcwalk.robot import Robot, load_robot
from mpcwalk.sim import make_mj_data

#: Largest disagreement accepted between the two engines [m].
ENGINE_TOLERANCE = 1e-6


@dataclass(frozen=True)
class CheckResult:
    """One check: its name, whether it passed, and what was measured."""

    name: str
    passed: bool
    detail: str


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


def check_posture(robot: Robot) -> CheckResult:
    """Flat soles on their sides, the CoM at the preset's height above them."""
    problems = []
    for placement, sign, side in zip(robot.compute_sole_placements(robot.q0), (1, -1), "LR"):
        if abs(placement.translation[2]) > 1e-6:
            problems.append(f"{side} sole {1000 * placement.translation[2]:.1f} mm off the floor")
        if not np.allclose(placement.rotation, np.eye(3), atol=1e-6):
            problems.append(f"{side} sole not flat")
        if np.sign(placement.translation[1]) != sign:
            problems.append(f"{side} sole on the wrong side")
    com = robot.compute_com(robot.q0)
    if abs(com[2] - robot.com_height) > 0.005:
        problems.append(f"CoM height {com[2]:.4f} m, the preset says {robot.com_height:.4f} m")
    if abs(com[0]) > 0.25 * robot.sole_size[0]:
        problems.append(f"CoM {100 * com[0]:.1f} cm ahead of the soles' middle")
    return CheckResult(
        "the nominal posture is flat",
        not problems,
        "; ".join(problems) or f"soles flat, CoM {com[2]:.3f} m above them",
    )


def check_standing(robot: Robot, duration: float = 1.0) -> CheckResult:
    """The robot stands ``duration`` seconds in MuJoCo under its servos."""
    data = make_mj_data(robot)
    height = float(data.qpos[2])
    while data.time < duration:
        mujoco.mj_step(robot.mj_model, data)
    sink = abs(float(data.qpos[2]) - height)
    tilt = np.degrees(2.0 * np.arccos(min(1.0, abs(float(data.qpos[3])))))
    load = data.sensor("left_foot_touch").data[0] + data.sensor("right_foot_touch").data[0]
    share = float(load) / (robot.total_mass * 9.81)
    passed = sink < 0.05 * height and tilt < 5.0 and abs(share - 1.0) < 0.05
    return CheckResult(
        "it stands under its servos",
        passed,
        f"after {duration:g} s: base {1000 * sink:.1f} mm lower, tilted {tilt:.1f} deg, "
        f"feet carry {100 * share:.0f} % of its weight",
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
    """Every check of a robot (a shipped name or the path of a preset file); the first
    failing one stops the list (a robot that does not load is one failed check)."""
    try:
        robot = load_robot(name_or_preset, visual=False)
    except MpcwalkError as error:
        return [CheckResult("it loads", False, str(error))]
    results = [
        CheckResult(
            "it loads",
            True,
            f"{robot.name}: {len(robot.joint_names)} joints, {robot.total_mass:.1f} kg",
        )
    ]
    checks: list[Callable[[Robot], CheckResult]] = [check_engines, check_posture, check_standing]
    if walk:
        checks.append(check_walk)
    for check in checks:
        results.append(check(robot))
        if not results[-1].passed:
            break
    return results


__all__ = ["CheckResult", "check_engines", "check_posture", "check_robot", "check_standing"]
