"""The legs of a humanoid found from its kinematics alone: feet, up, forward and left.

A description names its joints as its authors liked (``leg_left_4_joint``, ``LKneePitch``,
``left_knee_Z``); what every biped shares is its tree. :func:`find_legs` reads it, in the
description's zero configuration (the base at the origin, every joint at 0):

- **Feet.** Two *leaf chains* (chains of joints from the floating base to a joint without
  children, with at least :data:`MIN_LEG_JOINTS` joints) that leave the base by different
  branches and whose ends' midpoint lies farthest from the base: two legs, not an arm and
  a leg (half as far) nor two arms spread in a T (their midpoint is the chest). The foot link is the body the last
  joint of the chain moves.
- **Up.** From the foot to the hip (the first joint of the chain): a leg hangs straight in
  the zero configuration of the descriptions we know; the description's axis closest to
  that direction is up (a y-up description says so).
- **Forward.** The knee, the joint of the chain farthest from both its hip and its foot,
  bends towards the larger end of its range; bending it moves the foot *backward* (legs
  fold like a human's). Its horizontal opposite, snapped to the description's axes, is
  forward; both knees must agree.
- **Left.** The foot on the side of ``up x forward``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.base_orientation import AXIS_VECTORS

#: Fewest joints a chain from the base needs to count as a leg (hip pitch and roll, knee,
#: ankle pitch: no humanoid leg walks with fewer).
MIN_LEG_JOINTS = 4

#: Largest height difference of the two feet, as a share of the leg length.
LEG_MISMATCH = 0.25

#: The six axes a description's root may point forward or up along, by name (a preset's
#: ``[base]`` table names them the same way).
AXES = {name: np.array(vector) for name, vector in AXIS_VECTORS.items()}


@dataclass(frozen=True)
class Leg:
    """One leg of the description, from the base to the foot.

    Attributes:
        joints: Joint names from the hip to the ankle.
        foot: Name of the foot link (the body the last joint moves).
        knee: Name of the knee (the joint farthest from both ends of the chain).
        hip_position: Position of the first joint in the zero configuration [m].
        foot_position: Position of the foot link's origin in the zero configuration [m].
    """

    joints: tuple[str, ...]
    foot: str
    knee: str
    hip_position: np.ndarray
    foot_position: np.ndarray


@dataclass(frozen=True)
class LegSurvey:
    """What :func:`find_legs` read off the description.

    Attributes:
        left: The left leg.
        right: The right leg.
        up: Name of the description's axis pointing up (``"z"``, ``"y"``...).
        forward: Name of the description's axis pointing forward (``"x"``, ``"-x"``...).
        leg_length: Hip height above the foot origins with the legs straight [m].
    """

    left: Leg
    right: Leg
    up: str
    forward: str
    leg_length: float


def _chain(model: pin.Model, joint_id: int) -> list[int]:
    """Joints from the one after the floating base down to ``joint_id``."""
    chain = []
    while joint_id > 1:
        chain.append(joint_id)
        joint_id = model.parents[joint_id]
    return chain[::-1]


def joint_axis(model: pin.Model, data: pin.Data, joint_id: int) -> np.ndarray:
    """World axis of the revolute joint ``joint_id`` at the configuration of ``data`` (after
    forward kinematics)."""
    jacobian = pin.getJointJacobian(model, data, joint_id, pin.ReferenceFrame.LOCAL)
    angular = jacobian[3:, model.idx_vs[joint_id]]  # the joint's own axis, in its frame
    return data.oMi[joint_id].rotation @ angular


def body_of(model: pin.Model, joint_id: int) -> str:
    """Name of the body a joint moves (its first body frame)."""
    for frame in model.frames:
        if frame.parentJoint == joint_id and frame.type == pin.FrameType.BODY:
            return str(frame.name)
    return str(model.names[joint_id])


def _snap(direction: np.ndarray, what: str) -> str:
    """Name of the description axis closest to ``direction`` (refused when none is within
    30 deg: the description is not aligned with its body)."""
    direction = direction / np.linalg.norm(direction)
    name, axis = max(AXES.items(), key=lambda item: float(item[1] @ direction))
    if float(axis @ direction) < np.cos(np.radians(30.0)):
        raise ConfigurationError(
            f"The robot's {what} direction {np.round(direction, 3).tolist()} is more than 30 deg "
            "from every axis of its description's root; write a preset by hand (docs: Add a "
            "robot) with [base] forward and up."
        )
    return name


def find_legs(model: pin.Model, q: np.ndarray | None = None) -> LegSurvey:
    """The legs, up, forward and left of the robot ``model`` (a floating base first).

    Args:
        model: Pinocchio model with a free-flyer root joint.
        q: Configuration to read the legs in (default: every joint at 0).

    Raises:
        ConfigurationError: Fewer than two leaf chains of :data:`MIN_LEG_JOINTS` joints
            leaving the base by different branches, or a knee and feet that cannot tell
            forward.
    """
    q = pin.neutral(model) if q is None else q
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    pin.computeJointJacobians(model, data, q)
    children = dict.fromkeys(range(model.njoints), 0)
    for joint_id in range(2, model.njoints):
        children[model.parents[joint_id]] += 1
    leaves = [
        j
        for j in range(2, model.njoints)
        if children[j] == 0 and len(_chain(model, j)) >= MIN_LEG_JOINTS
    ]
    if len(leaves) < 2:
        raise ConfigurationError(
            f"The description has {len(leaves)} chain(s) of at least {MIN_LEG_JOINTS} joints "
            "from its base to a free end; a biped needs two legs (hip, knee, ankle each)."
        )
    # the legs: the pair of leaves on separate branches whose mean end lies farthest from
    # the base (two arms spread in a T cancel out, an arm and a leg reach half as far)
    base = data.oMi[1].translation
    pairs = [
        (a, b)
        for i, a in enumerate(leaves)
        for b in leaves[i + 1 :]
        if _chain(model, a)[0] != _chain(model, b)[0]
    ]
    if not pairs:
        raise ConfigurationError(
            "The chains of the description leave its base by one branch; a biped's legs leave "
            "the pelvis separately. Write a preset by hand (docs: Add a robot)."
        )
    first, second = max(
        pairs,
        key=lambda p: float(
            np.linalg.norm(0.5 * (data.oMi[p[0]].translation + data.oMi[p[1]].translation) - base)
        ),
    )
    legs = [_leg(model, data, leaf) for leaf in (first, second)]
    hips = [leg.hip_position for leg in legs]
    feet = [leg.foot_position for leg in legs]
    up_vector = sum(h - f for h, f in zip(hips, feet))
    up = _snap(up_vector, "up")
    up_axis = AXES[up]
    leg_length = float(np.mean([(h - f) @ up_axis for h, f in zip(hips, feet)]))
    mismatch = abs(float((feet[0] - feet[1]) @ up_axis))
    if mismatch > LEG_MISMATCH * leg_length or len(legs[0].joints) != len(legs[1].joints):
        raise ConfigurationError(
            f"The two chains taken for legs ({', '.join(legs[0].joints)} and "
            f"{', '.join(legs[1].joints)}) end {mismatch:.3f} m apart in height, or have "
            "different numbers of joints: the description does not have two legs alike. A "
            "biped needs two legs (hips, knee, ankle each)."
        )
    votes = [_forward_from_knee(model, q, leg, up_axis) for leg in legs]
    named = {_snap(v, "forward") for v in votes if v is not None}
    if len(named) != 1:
        knees = " and ".join(f"'{leg.knee}'" for leg in legs)
        why = "disagree" if len(named) > 1 else "have symmetric or unlimited ranges"
        raise ConfigurationError(
            f"The knees {knees} {why}: the robot's forward cannot be told from them (a knee "
            "bends towards the larger end of its range and moves its foot backward). Write "
            "[base] forward in a preset by hand (docs: Add a robot)."
        )
    forward_vector = next(v for v in votes if v is not None)
    forward = _snap(forward_vector, "forward")
    left_axis = np.cross(up_axis, AXES[forward])
    lateral = [float((f - 0.5 * (feet[0] + feet[1])) @ left_axis) for f in feet]
    left, right = (legs[0], legs[1]) if lateral[0] > lateral[1] else (legs[1], legs[0])
    return LegSurvey(left, right, up, forward, leg_length)


def _leg(model: pin.Model, data: pin.Data, leaf: int) -> Leg:
    """The leg ending at the joint ``leaf``."""
    chain = [j for j in _chain(model, leaf) if model.nqs[j] == 1]
    hip, foot = data.oMi[chain[0]].translation.copy(), data.oMi[chain[-1]].translation.copy()
    direction = (foot - hip) / max(float(np.linalg.norm(foot - hip)), 1e-9)
    inner = chain[1:-1] or chain
    # the knee turns about an axis across the leg, far from both of its ends
    across = [j for j in inner if abs(float(joint_axis(model, data, j) @ direction)) < 0.5]
    knee = max(
        across or inner,
        key=lambda j: min(
            float(np.linalg.norm(data.oMi[j].translation - hip)),
            float(np.linalg.norm(data.oMi[j].translation - foot)),
        ),
    )
    return Leg(
        joints=tuple(str(model.names[j]) for j in chain),
        foot=body_of(model, leaf),
        knee=str(model.names[knee]),
        hip_position=hip,
        foot_position=foot,
    )


def _forward_from_knee(
    model: pin.Model, q: np.ndarray, leg: Leg, up: np.ndarray
) -> np.ndarray | None:
    """Forward: opposite to where the foot goes when the knee bends (towards the larger end
    of its range); None when the range does not tell."""
    knee = model.getJointId(leg.knee)
    i = model.idx_qs[knee]
    low, high = model.lowerPositionLimit[i], model.upperPositionLimit[i]
    if not (np.isfinite(low) and np.isfinite(high)) or abs(abs(high) - abs(low)) < 0.1:
        return None
    bend = 0.3 if abs(high) > abs(low) else -0.3
    foot = model.getJointId(leg.joints[-1])
    q_bent = q.copy()
    q_bent[i] += bend
    ends = []
    for configuration in (q, q_bent):
        data = model.createData()
        pin.forwardKinematics(model, data, configuration)
        ends.append(data.oMi[foot].translation.copy())
    motion = ends[1] - ends[0]
    horizontal = motion - (motion @ up) * up
    if np.linalg.norm(horizontal) < 1e-6:
        return None
    return -horizontal


__all__ = ["AXES", "MIN_LEG_JOINTS", "Leg", "LegSurvey", "body_of", "find_legs", "joint_axis"]
