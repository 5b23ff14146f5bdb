"""The checks of a robot's body (``mpcwalk robots check``): the inertias repaired for MuJoCo,
the soles on the feet's shapes, the servos strong enough to hold the nominal posture.

Tolerances:

- :data:`SOLE_OVERHANG_TOLERANCE` (5 mm): how far a corner of the preset's sole may lie
  outside the lowest face of the foot's shapes (:func:`~mpcwalk.robot.footprint.
  sole_from_geometry`). A sole larger than the foot lets the controllers put the CoP where
  the real foot has no ground under it; 5 mm is the sink of the shipped robots' bases into
  the contact when standing (0.6 to 5.1 mm), the foot's own compliance, and Talos' rounded
  sole edges (its sole reaches 4.5 mm past the flat face of its mesh at the toe).
- :data:`TORQUE_SHARE_LIMIT` (80 %): a servo holding the standing posture with more than
  80 % of its torque limit has too little left to walk (the swing leg, the stance's sway).
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import MpcwalkError
from mpcwalk.robot import Robot
from mpcwalk.robot.footprint import SoleFootprint, foot_footprints
from mpcwalk.robot.survey.upper_body import standing_torques as survey_standing_torques
from mpcwalk.robot.urdf_repair import inertia_repairs
from mpcwalk.walking.posture_checks import CheckResult

#: Largest distance [m] of a sole corner outside the foot's footprint (see the module).
SOLE_OVERHANG_TOLERANCE = 0.005
#: Largest share of a servo's torque limit that holding the nominal posture may take.
TORQUE_SHARE_LIMIT = 0.8


def check_inertias(robot: Robot) -> CheckResult:
    """Which links of a URDF the loader repaired for MuJoCo (:mod:`mpcwalk.robot.urdf_repair`);
    it never fails: what could not be repaired fails to load."""
    if robot.preset.format != "urdf":
        return CheckResult("the inertias", True, "MJCF: loaded as written")
    _, repairs = inertia_repairs(robot.description_path.read_text())
    if not repairs:
        return CheckResult("the inertias", True, "none repaired: MuJoCo takes them as written")
    by_reason = defaultdict(list)
    for repair in repairs:
        by_reason[repair.reason].append(repair.link)
    listed = "; ".join(f"{reason}: {', '.join(links)}" for reason, links in by_reason.items())
    return CheckResult(
        "the inertias",
        True,
        f"{len(repairs)} links repaired in the text both engines load (MuJoCo refuses them as "
        f"written; give them real inertias in the description): {listed}",
    )


def _overhang(
    footprint: SoleFootprint,
    centre: np.ndarray,
    size: tuple[float, float],
    axes: np.ndarray | None = None,
) -> float:
    """Largest distance [m] of a corner of the sole (``centre`` in the foot frame, ``size``
    along the sole's ``axes``) outside ``footprint`` (measured along the same axes), 0
    inside."""
    turn = np.eye(3) if axes is None else axes
    centre = turn.T @ np.asarray(centre, dtype=float)
    middle = turn.T @ np.asarray(footprint.offset, dtype=float)
    x_min, x_max = middle[0] - footprint.size[0] / 2, middle[0] + footprint.size[0] / 2
    y_min, y_max = middle[1] - footprint.size[1] / 2, middle[1] + footprint.size[1] / 2
    half = np.array(size) / 2
    return float(
        max(
            x_min - (centre[0] - half[0]),
            centre[0] + half[0] - x_max,
            y_min - (centre[1] - half[1]),
            centre[1] + half[1] - y_max,
            0.0,
        )
    )


def check_soles_on_feet(robot: Robot) -> CheckResult:
    """Each sole rectangle of the preset within :data:`SOLE_OVERHANG_TOLERANCE` of its foot's
    footprint (the lowest face of its collision or visual shapes, the closer of the two)."""
    name = "the soles lie on the feet"
    preset = robot.preset
    centre = np.array(preset.sole_offset if preset.format == "urdf" else (0.0, 0.0, 0.0))
    axes = pin.rpy.rpyToMatrix(np.array(preset.sole_rpy, dtype=float))
    try:
        footprints = foot_footprints(robot.description_path, preset.foot_frames, axes=axes)
    except MpcwalkError as error:
        return CheckResult(name, True, f"not measured: {error}")
    problems, measured = [], []
    for foot, side in zip(preset.foot_frames, "LR"):
        if not footprints[foot]:
            measured.append(f"{side} foot: no shape MuJoCo reads, not measured")
            continue
        best = min(
            footprints[foot].values(), key=lambda fp: _overhang(fp, centre, preset.sole_size, axes)
        )
        overhang = _overhang(best, centre, preset.sole_size, axes)
        if overhang > SOLE_OVERHANG_TOLERANCE:
            (x, y, z), (length, width) = best.offset, best.size
            problems.append(
                f"{side} sole {preset.sole_size[0]:.3f} x {preset.sole_size[1]:.3f} m at "
                f"({centre[0]:.3f}, {centre[1]:.3f}) m reaches {1000 * overhang:.1f} mm outside "
                f"the foot's footprint {best} (tolerance "
                f"{1000 * SOLE_OVERHANG_TOLERANCE:g} mm): set [feet] "
                + (
                    f"sole_offset = [{x:.3f}, {y:.3f}, {z:.3f}], "
                    if preset.format == "urdf"
                    else ""
                )
                + f"sole_size = [{length:.3f}, {width:.3f}]"
                + ("" if preset.format == "urdf" else " and centre the sole sites on it")
            )
        else:
            where = f"{1000 * overhang:.1f} mm past" if overhang > 0 else "inside"
            measured.append(f"{side} sole {where} the footprint {best}")
    detail = "; ".join(problems) or (
        "; ".join(measured) + f" (tolerance {1000 * SOLE_OVERHANG_TOLERANCE:g} mm)"
    )
    return CheckResult(name, not problems, detail)


def standing_torques(robot: Robot) -> np.ndarray:
    """Joint torques [N m] that hold the nominal posture standing still on both feet, in
    ``robot.joint_names`` order (:func:`~mpcwalk.robot.survey.upper_body.standing_torques`
    at the sole frames: gravity's less the smallest sole wrenches that carry the base)."""
    torques = survey_standing_torques(robot.model, robot.q0, robot.foot_frames)
    return np.array([torques[name] for name in robot.joint_names])


def check_servo_torques(robot: Robot) -> CheckResult:
    """Each servo holds the standing posture with at most :data:`TORQUE_SHARE_LIMIT` of its
    torque limit."""
    torques = np.abs(standing_torques(robot))
    limits = robot.servo_gains.torque_limit
    shares = np.where(np.isfinite(limits) & (limits > 0), torques / limits, 0.0)
    stiffness = robot.servo_gains.stiffness

    def describe(i: int) -> str:
        sag = np.degrees(torques[i] / stiffness[i]) if np.isfinite(stiffness[i]) else 0.0
        return (
            f"{robot.joint_names[i]} {torques[i]:.1f} N m, {100 * shares[i]:.0f} % of its "
            f"{limits[i]:.1f} N m limit (its servo sags {sag:.2f} deg)"
        )

    over = [i for i in np.argsort(-shares) if shares[i] > TORQUE_SHARE_LIMIT]
    if not over:
        worst = int(np.argmax(shares))
        return CheckResult(
            "the servos hold the posture",
            True,
            f"largest share: {describe(worst)}; limit {100 * TORQUE_SHARE_LIMIT:.0f} %",
        )
    where = (
        "the force_limit of the preset's [[actuators]]"
        if robot.preset.format == "urdf"
        else "the actuators' forcerange in the MJCF file"
    )
    return CheckResult(
        "the servos hold the posture",
        False,
        f"standing takes more than {100 * TORQUE_SHARE_LIMIT:.0f} % of the torque limit: "
        + "; ".join(describe(i) for i in over)
        + f"; raise {where} (and kp where the servo sags), or choose a posture that loads these "
        "joints less: the robot cannot hold this one",
    )


__all__ = [
    "SOLE_OVERHANG_TOLERANCE",
    "TORQUE_SHARE_LIMIT",
    "check_inertias",
    "check_servo_torques",
    "check_soles_on_feet",
    "standing_torques",
]
