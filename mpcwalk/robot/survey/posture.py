"""A walking posture solved from the kinematics: knees bent, soles flat, CoM above them.

The walking pattern generators keep the CoM at a constant height with the knees bent (a
straight knee is a singularity of the leg's inverse kinematics), so a preset needs a
*nominal posture*. :func:`solve_posture` finds it by Gauss-Newton on the base's position
and the leg joints (the base keeps its orientation: the torso stays upright):

- each foot keeps its pose of the zero configuration, so the soles stay flat and at the
  stance the description was drawn with;
- the hips drop to :data:`HIP_HEIGHT_RATIO` of their straight-leg height (the knees bend
  by about 36 deg on a leg of two equal segments);
- the CoM lies above the middle of the two sole centres.

Fifteen equations (6 per foot, 2 for the CoM, 1 for the height) for the base's three
coordinates and the legs' joints: square for two 6-joint legs, least squares otherwise.
Joints outside their limits are reported (:attr:`Posture.outside_limits`), never clipped
silently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.survey.legs import AXES, LegSurvey

#: Hip height of the walking posture, as a share of the straight leg's.
HIP_HEIGHT_RATIO = 0.95

#: Tolerance of the solve: foot pose [m, rad] and CoM [m].
TOLERANCE = 1e-9


@dataclass(frozen=True)
class Posture:
    """The solved walking posture.

    Attributes:
        q: Full configuration (base first) [m, rad].
        angles: Joint angles by joint name [rad]: every leg joint, and the other joints
            that are not at 0 (from ``q_start``).
        com_height: CoM above the soles [m].
        residual: Largest remaining error of the solve [m or rad].
        outside_limits: ``(joint, angle, lower, upper)`` of each joint of ``angles`` outside
            its limits.
    """

    q: np.ndarray
    angles: dict[str, float]
    com_height: float
    residual: float
    outside_limits: tuple[tuple[str, float, float, float], ...]


def solve_posture(
    model: pin.Model,
    legs: LegSurvey,
    sole_centres: tuple[np.ndarray, np.ndarray],
    *,
    hip_height_ratio: float = HIP_HEIGHT_RATIO,
    q_start: np.ndarray | None = None,
    iterations: int = 100,
) -> Posture:
    """The walking posture of the robot ``model`` whose legs :func:`find_legs` found.

    Args:
        model: Pinocchio model with a free-flyer root.
        legs: The survey of its legs (axes of the description).
        sole_centres: Centre of each sole (left, right) in its foot link's frame [m].
        hip_height_ratio: Hip height as a share of the straight leg's.
        q_start: Configuration to start from (default: every joint at 0, the knees bent a
            little towards their larger range); a joint outside its limits starts at the
            nearer one.
        iterations: Most Gauss-Newton iterations.

    Raises:
        ConfigurationError: The solve does not converge (the legs cannot reach the posture).
    """
    data = model.createData()
    up, forward = AXES[legs.up], AXES[legs.forward]
    lateral = np.cross(up, forward)
    leg_joints = [model.getJointId(n) for n in (*legs.left.joints, *legs.right.joints)]
    v_columns = np.array([0, 1, 2] + [model.idx_vs[j] for j in leg_joints])
    q = pin.neutral(model) if q_start is None else q_start.copy()
    for joint_id in range(2, model.njoints):  # a joint whose 0 is out of range: its bound
        i = model.idx_qs[joint_id]
        low, high = model.lowerPositionLimit[i], model.upperPositionLimit[i]
        if model.nqs[joint_id] == 1 and np.isfinite(low) and np.isfinite(high) and low <= high:
            q[i] = min(max(q[i], low), high)
    if q_start is None:
        for leg in (legs.left, legs.right):
            knee = model.getJointId(leg.knee)
            i = model.idx_qs[knee]
            larger = (
                model.upperPositionLimit[i]
                if abs(model.upperPositionLimit[i]) > abs(model.lowerPositionLimit[i])
                else model.lowerPositionLimit[i]
            )
            q[i] = 0.3 * float(np.sign(larger))
    feet = [model.getFrameId(leg.foot) for leg in (legs.left, legs.right)]
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    targets = [data.oMf[f].copy() for f in feet]
    soles = [t.act(np.asarray(c, dtype=float)) for t, c in zip(targets, sole_centres)]
    middle = 0.5 * (soles[0] + soles[1])
    base_height = float(legs.left.hip_position @ up) * hip_height_ratio + float(middle @ up) * (
        1.0 - hip_height_ratio
    )
    residual = np.inf
    for _ in range(iterations):
        pin.framesForwardKinematics(model, data, q)
        pin.computeJointJacobians(model, data, q)
        com = pin.centerOfMass(model, data, q)
        com_jacobian = pin.jacobianCenterOfMass(model, data, q)
        errors, rows = [], []
        for frame, target in zip(feet, targets):
            error = pin.log6(data.oMf[frame].actInv(target)).vector
            jacobian = pin.getFrameJacobian(model, data, frame, pin.ReferenceFrame.LOCAL)
            errors.append(error)
            rows.append(jacobian)
        hip = data.oMi[model.getJointId(legs.left.joints[0])].translation
        errors.append(
            np.array(
                [
                    float((middle - com) @ forward),
                    float((middle - com) @ lateral),
                    base_height - float(hip @ up),
                ]
            )
        )
        hip_jacobian = pin.getJointJacobian(
            model, data, model.getJointId(legs.left.joints[0]), pin.LOCAL_WORLD_ALIGNED
        )[:3]
        rows.append(np.vstack([forward @ com_jacobian, lateral @ com_jacobian, up @ hip_jacobian]))
        error_vector = np.concatenate(errors)
        residual = float(np.max(np.abs(error_vector)))
        if residual < TOLERANCE:
            break
        jacobian = np.vstack(rows)[:, v_columns]
        step = np.linalg.lstsq(jacobian, error_vector, rcond=None)[0]
        velocity = np.zeros(model.nv)
        velocity[v_columns] = step
        q = pin.integrate(model, q, velocity)
    if residual > 1e-6:
        raise ConfigurationError(
            f"The walking posture does not converge (error {residual:.2e} after {iterations} "
            "iterations): the legs cannot bend to flat soles with the CoM above them. Write "
            "[nominal_posture] by hand (docs: Add a robot)."
        )
    pin.framesForwardKinematics(model, data, q)
    com = pin.centerOfMass(model, data, q)
    sole_height = float(
        np.mean([data.oMf[f].act(np.asarray(c)) @ up for f, c in zip(feet, sole_centres)])
    )
    angles, outside = {}, []
    for joint_id in range(2, model.njoints):
        name = str(model.names[joint_id])
        i = model.idx_qs[joint_id]
        angle = round(float(np.arctan2(np.sin(q[i]), np.cos(q[i]))), 6) + 0.0
        if joint_id not in leg_joints and angle == 0.0:
            continue  # the joints outside the legs stay where q_start had them (0)
        angles[name] = angle
        low, high = float(model.lowerPositionLimit[i]), float(model.upperPositionLimit[i])
        if angle < low - 1e-6 or angle > high + 1e-6:
            outside.append((name, angle, low, high))
    return Posture(
        q=q,
        angles=angles,
        com_height=float(com @ up) - sole_height,
        residual=residual,
        outside_limits=tuple(outside),
    )


__all__ = ["HIP_HEIGHT_RATIO", "Posture", "solve_posture"]
