"""The torso and the servos' loads of a humanoid, found from its kinematic tree.

- **Torso.** The body where the upper body's chains meet: the deepest body that is an
  ancestor of every free end outside the legs (hands, head), above the waist joints. Without an upper body, the
  base. The walk keeps that frame upright, so it must be upright in the walking posture;
  where the body's own frame is turned (its z axis more than :data:`UPRIGHT_TOLERANCE`
  from up), the base is used instead and the preset says so.
- **Loads.** Each joint's servo is sized by the mass its subtree carries and the distance
  of that mass's CoM from the joint (:func:`joint_loads`), and checked against the torques
  of standing still on both feet (:func:`standing_torques`).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from mpcwalk.robot.survey.legs import AXES, LegSurvey, body_of

#: Largest angle between the torso frame's z axis and up [deg].
UPRIGHT_TOLERANCE = 5.0


def torso_frame(model: pin.Model, q: np.ndarray, legs: LegSurvey) -> tuple[str, str]:
    """The torso's frame name and how it was chosen (a sentence for the preset)."""
    leg_joints = {model.getJointId(n) for n in (*legs.left.joints, *legs.right.joints)}
    upper = [j for j in range(2, model.njoints) if j not in leg_joints]
    root_body = body_of(model, 1)
    if not upper:
        return root_body, "the base (no joint outside the legs)"
    parents = {model.parents[j] for j in range(2, model.njoints)}
    ends = [j for j in upper if j not in parents]  # hands, head: the upper body's leaves
    common = None
    for joint_id in ends:
        chain = _ancestors(model, joint_id)
        common = chain if common is None else [j for j in common if j in chain]
    deepest = max(common or [1], key=lambda j: len(_ancestors(model, j)))
    # the body the upper body's chains leave from: the deepest common ancestor's body
    name = body_of(model, deepest)
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    up = AXES[legs.up]
    z_axis = data.oMf[model.getFrameId(name)].rotation[:, 2]
    angle = float(np.degrees(np.arccos(np.clip(z_axis @ up, -1.0, 1.0))))
    if deepest == 1:
        return root_body, "the base, where the upper body's chains meet"
    if angle > UPRIGHT_TOLERANCE or legs.up != "z":
        return root_body, (
            f"the base: '{name}', where the upper body's chains meet, has its z axis "
            f"{angle:.0f} deg from up"
        )
    return name, "where the upper body's chains meet (waist joints below it)"


def _ancestors(model: pin.Model, joint_id: int) -> list[int]:
    """The joints above ``joint_id`` (excluded), up to the base."""
    chain = []
    joint_id = model.parents[joint_id]
    while joint_id >= 1:
        chain.append(joint_id)
        joint_id = model.parents[joint_id]
    return chain


def joint_loads(model: pin.Model, q: np.ndarray) -> dict[str, tuple[float, float]]:
    """Per joint: the mass its subtree carries [kg] and that mass's CoM distance from the
    joint's axis origin [m], at ``q``."""
    data = model.createData()
    pin.centerOfMass(model, data, q, True)  # subtree CoMs and masses
    loads = {}
    for joint_id in range(2, model.njoints):
        origin = data.oMi[joint_id].translation
        reach = float(np.linalg.norm(data.com[joint_id] - origin))
        loads[str(model.names[joint_id])] = (float(data.mass[joint_id]), reach)
    return loads


def standing_torques(
    model: pin.Model, q: np.ndarray, feet: tuple[str, str], up: str = "z"
) -> dict[str, float]:
    """Joint torques [N m] of standing still at ``q`` on both feet, the weight shared by the
    feet as the least-norm wrenches that balance the base; gravity along ``-up`` (the name
    of the description's axis that points up)."""
    model = model.copy()
    model.gravity = pin.Motion(-9.81 * AXES[up], np.zeros(3))
    data = model.createData()
    gravity = pin.computeGeneralizedGravity(model, data, q)
    pin.computeJointJacobians(model, data, q)
    pin.framesForwardKinematics(model, data, q)
    jacobians = np.vstack(
        [
            pin.getFrameJacobian(model, data, model.getFrameId(f), pin.ReferenceFrame.LOCAL)
            for f in feet
        ]
    )
    wrenches = np.linalg.lstsq(jacobians[:, :6].T, gravity[:6], rcond=None)[0]
    torques = gravity - jacobians.T @ wrenches
    return {str(model.names[j]): float(torques[model.idx_vs[j]]) for j in range(2, model.njoints)}


__all__ = ["UPRIGHT_TOLERANCE", "joint_loads", "standing_torques", "torso_frame"]
