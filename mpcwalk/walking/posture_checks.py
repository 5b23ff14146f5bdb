"""The checks of a robot's nominal posture ``q0`` (``mpcwalk robots check``): its joints within
their limits, its soles flat on the floor, its torso frame upright and facing forward.

Each failure says what it measured, against which tolerance, and the likely fix.

Tolerances:

- :data:`SOLE_TILT_TOLERANCE_DEG` (0.5 deg): a sole tilted by it raises its far edge by
  ``L tan 0.5 deg`` = 0.87 % of its length L (0.9 mm on bioloid-like's 10 cm sole, 2.3 mm on
  atlas-like's 26 cm one): less than the 0.6 to 5.1 mm the shipped robots' bases sink into
  the contact when standing, so the servos press it flat without moving the CoP to an edge.
  Angles rounded to 4 or 5 digits (1.5708, 3.14159) are off by under 0.001 deg; to 2
  decimals (0.01 rad) by up to 0.29 deg.
- :data:`SOLE_HEIGHT_TOLERANCE` (1 mm): a sole centre this far above or below the floor
  (the loader puts the soles' middle on it) drops or lifts the robot by that much at the
  start, also less than the sink of the bases into the contact.
- :data:`TORSO_TOLERANCE_DEG` (5 deg): the walk's IK targets keep the torso frame upright and
  facing the walking direction (:meth:`~mpcwalk.ik.targets.IKTargets.from_gait`), so the
  first tick turns the torso by the frame's error in ``q0``; 5 deg of trunk lean moves the
  trunk's CoM by 9 % of its height above the hips, a frame turned the wrong way (90 deg and
  more: y forward, x up) makes the IK fold the robot.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk.robot import Robot

#: Largest tilt [deg] of a sole in the nominal posture (see the module).
SOLE_TILT_TOLERANCE_DEG = 0.5
#: Largest angle [deg] of the torso frame's z from the world's up and of its x from the
#: soles' forward direction, in the nominal posture (see the module).
TORSO_TOLERANCE_DEG = 5.0
#: Largest height [m] of a sole centre above or below the floor in the nominal posture (the
#: loader puts the soles' middle on it): the robot drops this much onto the floor at the
#: start, less than its base sinks into the contact (see the module).
SOLE_HEIGHT_TOLERANCE = 1e-3
#: Slack [rad] of the joint limits (rounding of the limits in a description).
LIMIT_SLACK = 1e-9


@dataclass(frozen=True)
class CheckResult:
    """One check: its name, whether it passed, and what was measured."""

    name: str
    passed: bool
    detail: str


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Angle [deg] between two vectors."""
    cosine = float(a @ b) / max(float(np.linalg.norm(a) * np.linalg.norm(b)), 1e-12)
    return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))


def check_joint_limits(robot: Robot) -> CheckResult:
    """Every joint of the nominal posture within its [lower, upper] limits."""
    model, problems = robot.model, []
    for name in robot.joint_names:
        index = model.idx_qs[model.getJointId(name)]
        value = float(robot.q0[index])
        lower, upper = (
            float(model.lowerPositionLimit[index]),
            float(model.upperPositionLimit[index]),
        )
        if not lower - LIMIT_SLACK <= value <= upper + LIMIT_SLACK:
            problems.append(
                f"{name} = {value:.4f} rad outside [{lower:.4f}, {upper:.4f}] "
                f"(set it to {min(max(value, lower), upper):.4f} or within)"
            )
    return CheckResult(
        "the nominal posture is within the joint limits",
        not problems,
        "; ".join(problems) + "; fix [nominal_posture] in the preset"
        if problems
        else f"{len(robot.joint_names)} joints within their limits",
    )


def _cross2(a: np.ndarray, b: np.ndarray) -> float:
    """z of the cross product of two horizontal vectors."""
    return float(a[0] * b[1] - a[1] * b[0])


def _flattening(robot: Robot, side: int) -> list[tuple[str, float, float]]:
    """The change of the two joints closest to a foot that tilt it (its ankle pitch and
    roll, for most legs) that makes its sole flat: (joint, change [rad], new angle [rad])."""
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.foot_frames[side])
    chain, joint = [], model.frames[frame].parentJoint
    while joint > 1:  # up to the floating base
        chain.append(int(joint))
        joint = model.parents[joint]
    q, up = robot.q0.copy(), np.array([0.0, 0.0, 1.0])
    tilting: list[int] = []
    for _ in range(8):  # Newton's steps on the sole's tilt
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)[3:5]
        if not tilting:
            for joint in chain:  # from the foot up: the first two joints that tilt it
                tilt = jacobian[:, model.idx_vs[joint]]
                if np.linalg.norm(tilt) > 0.5 and all(
                    abs(_cross2(tilt, jacobian[:, model.idx_vs[j]])) > 0.3 for j in tilting
                ):
                    tilting.append(joint)
                if len(tilting) == 2:
                    break
            if not tilting:
                return []
        z_axis = data.oMf[frame].rotation[:, 2]
        axis = np.cross(z_axis, up)  # turning the sole about it by the angle makes it flat
        if np.linalg.norm(axis) < 1e-12:
            break
        turn = axis / np.linalg.norm(axis) * np.radians(_angle_deg(z_axis, up))
        columns = [model.idx_vs[j] for j in tilting]
        step = np.linalg.lstsq(jacobian[:, columns], turn[:2], rcond=None)[0]
        for joint, delta in zip(tilting, step):
            q[model.idx_qs[joint]] += delta
    return [
        (model.names[j], float(q[i] - robot.q0[i]), float(q[i]))
        for j, i in ((j, model.idx_qs[j]) for j in tilting)
        if abs(q[i] - robot.q0[i]) > 1e-5
    ]


def check_posture(robot: Robot) -> CheckResult:
    """Flat soles (within :data:`SOLE_TILT_TOLERANCE_DEG`) on the floor on their own side,
    the CoM at the preset's height above them."""
    problems, tilts = [], []
    placements = robot.compute_sole_placements(robot.q0)
    for i, (placement, sign, side) in enumerate(zip(placements, (1, -1), "LR")):
        if abs(placement.translation[2]) > SOLE_HEIGHT_TOLERANCE:
            problems.append(
                f"{side} sole {1000 * placement.translation[2]:.2f} mm off the floor (tolerance "
                f"{1000 * SOLE_HEIGHT_TOLERANCE:g} mm; the legs' lengths differ in the posture)"
            )
        rotation = placement.rotation
        tilt = _angle_deg(rotation[:, 2], np.array([0.0, 0.0, 1.0]))
        tilts.append(tilt)
        if tilt > SOLE_TILT_TOLERANCE_DEG:
            roll, pitch, _ = np.degrees(pin.rpy.matrixToRpy(rotation))
            fix = _flattening(robot, i)
            change = ", ".join(
                f"{name} by {delta:+.4f} rad (to {new:.4f})" for name, delta, new in fix
            )
            problems.append(
                f"{side} sole not flat: tilted {tilt:.2f} deg (roll {roll:.2f}, pitch {pitch:.2f} "
                f"deg; tolerance {SOLE_TILT_TOLERANCE_DEG:g} deg)"
                + (f"; change {change} in [nominal_posture]" if change else "")
            )
        if np.sign(placement.translation[1]) != sign:
            problems.append(f"{side} sole on the wrong side")
    com = robot.compute_com(robot.q0)
    if abs(com[2] - robot.com_height) > 0.005:
        problems.append(
            f"CoM height {com[2]:.4f} m, the preset says {robot.com_height:.4f} m (set "
            f"com_height = {com[2]:.4f})"
        )
    if abs(com[0]) > 0.25 * robot.sole_size[0]:
        problems.append(f"CoM {100 * com[0]:.1f} cm ahead of the soles' middle")
    return CheckResult(
        "the nominal posture is flat",
        not problems,
        "; ".join(problems)
        or f"soles flat (tilts {tilts[0]:.2f} and {tilts[1]:.2f} deg, tolerance "
        f"{SOLE_TILT_TOLERANCE_DEG:g} deg), CoM {com[2]:.3f} m above them",
    )


def _forward(robot: Robot) -> np.ndarray:
    """The soles' forward direction in the nominal posture: their mean horizontal x axis."""
    heading = sum(p.rotation[:, 0] for p in robot.compute_sole_placements(robot.q0))
    heading = np.array([heading[0], heading[1], 0.0])
    norm = float(np.linalg.norm(heading))
    return heading / norm if norm > 1e-9 else np.array([1.0, 0.0, 0.0])


def _torso_errors(rotation: np.ndarray, forward: np.ndarray) -> tuple[float, float]:
    """Angles [deg] of a frame's z from the world's up and of its x from ``forward``."""
    tilt = _angle_deg(rotation[:, 2], np.array([0.0, 0.0, 1.0]))
    return tilt, _angle_deg(rotation[:, 0], forward)


def upright_frames(robot: Robot, tolerance_deg: float = TORSO_TOLERANCE_DEG) -> list[str]:
    """The frames of the torso's rigid body and of the bodies between it and the base (the
    base's first) that are upright and face forward in the nominal posture."""
    model, data = robot.model, robot.model.createData()
    pin.framesForwardKinematics(model, data, robot.q0)
    joints, joint = [], model.frames[model.getFrameId(robot.torso_frame)].parentJoint
    while joint > 0:
        joints.append(int(joint))
        joint = model.parents[joint]
    forward, found = _forward(robot), []
    kinds = (pin.FrameType.BODY, pin.FrameType.OP_FRAME)
    for joint in reversed(joints):
        for i, frame in enumerate(model.frames):
            if frame.parentJoint != joint or frame.type not in kinds:
                continue
            if max(_torso_errors(data.oMf[i].rotation, forward)) <= tolerance_deg:
                found.append(frame.name)
    return found


def check_torso(robot: Robot) -> CheckResult:
    """The torso frame upright (z up) and facing the soles' forward direction (x forward)
    within :data:`TORSO_TOLERANCE_DEG` in the nominal posture."""
    rotation = robot.compute_frame_placement(robot.q0, robot.torso_frame).rotation
    tilt, turn = _torso_errors(rotation, _forward(robot))
    passed = tilt <= TORSO_TOLERANCE_DEG and turn <= TORSO_TOLERANCE_DEG
    measured = (
        f"torso frame '{robot.torso_frame}': z axis {tilt:.1f} deg from up, x axis {turn:.1f} "
        f"deg from the soles' forward (tolerance {TORSO_TOLERANCE_DEG:g} deg)"
    )
    if passed:
        return CheckResult("the torso frame is upright", True, measured)
    x, z = (", ".join(f"{round(v, 2) + 0.0:.2f}" for v in rotation[:, k]) for k in (0, 2))
    candidates = [name for name in upright_frames(robot) if name != robot.torso_frame]
    fix = (
        f"set torso_frame to an upright frame of the trunk: {', '.join(candidates[:6])}"
        if candidates
        else "the trunk has no upright frame: add one to the description (a link on a fixed "
        "joint whose rpy undoes this rotation) and name it in torso_frame"
    )
    return CheckResult(
        "the torso frame is upright", False, f"{measured}; its x axis ({x}), z axis ({z}); {fix}"
    )


__all__ = [
    "SOLE_TILT_TOLERANCE_DEG",
    "TORSO_TOLERANCE_DEG",
    "CheckResult",
    "check_joint_limits",
    "check_posture",
    "check_torso",
    "upright_frames",
]
