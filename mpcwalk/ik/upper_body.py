"""The upper body as a flywheel: its limits read from a robot's model (the hip strategy).

:func:`upper_body_flywheel` gives the :class:`~mpcwalk.models.flywheel.FlywheelLimits` of a
:class:`~mpcwalk.robot.robot.Robot`: the upper body is every body but the legs (the subtrees
of the hips, :attr:`Robot.hip_joints`), the flywheel's inertia the composite inertia of those
bodies about their CoM in the nominal posture (Pinocchio), its torque a share of the stance
hip's pitch and roll torque limits (the model's effort limits, else the MuJoCo actuators'
force ranges), its momentum the hip's speed limit times the inertia, and its lean the
distance from the nominal hip angles to their position limits, capped by ``max_lean``.
"""

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.joint_bounds import DEFAULT_VELOCITY_LIMIT
from mpcwalk.models.flywheel import FlywheelLimits

#: Largest lean of the upper body [rad] the flywheel may use (about 17 deg): beyond it the
#: torso's CoM moves too far for the CoM task to hold it.
MAX_LEAN = 0.3
#: Share of the hip's torque limit left to the flywheel (the rest holds the upper body up
#: and walks).
TORQUE_SHARE = 0.5


def upper_body_bodies(model: pin.Model, hips: tuple[str, str]) -> list[int]:
    """Joint indices of the bodies outside the legs (the subtrees of ``hips``)."""
    legs: set[int] = set()
    for hip in hips:
        root = int(model.getJointId(hip))
        legs.update(int(j) for j in model.subtrees[root])
    return [j for j in range(1, model.njoints) if j not in legs]


def upper_body_inertia(model: pin.Model, q: np.ndarray, bodies: list[int]) -> pin.Inertia:
    """Composite inertia of ``bodies`` at ``q``, in world axes (about the world origin's
    frame: ``lever`` is its CoM, ``inertia`` its rotational inertia about that CoM)."""
    data = model.createData()
    pin.forwardKinematics(model, data, q)
    total = pin.Inertia.Zero()
    for j in bodies:
        total += data.oMi[j].act(model.inertias[j])
    return total


def _torque_limit(robot, joint: str) -> float:
    model = robot.model
    limit = float(model.effortLimit[model.joints[model.getJointId(joint)].idx_v])
    if np.isfinite(limit) and limit > 0.0:
        return limit
    mj = robot.mj_model
    joint_id = int(mj.joint(joint).id)  # (the MuJoCo model's own lookup: no import)
    for a in range(mj.nu):
        if int(mj.actuator_trnid[a, 0]) == joint_id and mj.actuator_forcelimited[a]:
            return float(np.max(np.abs(mj.actuator_forcerange[a])))
    raise ConfigurationError(
        f"Robot '{robot.name}': joint '{joint}' has no torque limit in its model nor a "
        "force-limited actuator; give the hip's effort limit in the description, or pass "
        "flywheel_limits to the generator."
    )


def upper_body_flywheel(
    robot, *, max_lean: float = MAX_LEAN, torque_share: float = TORQUE_SHARE
) -> FlywheelLimits:
    """The flywheel limits of ``robot`` (a :class:`~mpcwalk.robot.robot.Robot`).

    Args:
        robot: The robot.
        max_lean: Cap of the lean [rad].
        torque_share: Share of the stance hip's torque limit the flywheel may use, in (0, 1].

    Raises:
        ConfigurationError: A robot without hip pitch and roll joints, or without torque
            limits on them; an option out of range.
    """
    if not (0.0 < torque_share <= 1.0 and max_lean > 0.0):
        raise ConfigurationError(
            f"torque_share must be in (0, 1] and max_lean > 0 rad, got {torque_share!r} and "
            f"{max_lean!r}."
        )
    model, q0 = robot.model, robot.q0
    inertia = upper_body_inertia(model, q0, upper_body_bodies(model, robot.hip_joints))
    rotational = inertia.inertia
    values: dict[str, tuple[float, float, float]] = {}
    for axis, role, row in (("pitch", "hip_pitch", 1), ("roll", "hip_roll", 0)):
        torque, speed, lean = np.inf, np.inf, float(max_lean)
        for side in ("left", "right"):
            joint = robot.joint_roles.joint(side, role)
            if joint is None:
                raise ConfigurationError(
                    f"Robot '{robot.name}' has no {side} {role.replace('_', ' ')} joint: the "
                    "hip strategy needs the hips' pitch and roll (name them in the preset's "
                    "[joints] table)."
                )
            j = model.joints[model.getJointId(joint)]
            torque = min(torque, _torque_limit(robot, joint))
            v_max = float(model.velocityLimit[j.idx_v])
            speed = min(
                speed, v_max if np.isfinite(v_max) and v_max > 0 else DEFAULT_VELOCITY_LIMIT
            )
            low, high = model.lowerPositionLimit[j.idx_q], model.upperPositionLimit[j.idx_q]
            lean = min(lean, float(q0[j.idx_q] - low), float(high - q0[j.idx_q]))
        I = float(rotational[row, row])
        values[axis] = (torque_share * torque, speed * I, max(lean, 0.0))
    return FlywheelLimits(
        mass=robot.total_mass,
        inertia=(float(rotational[1, 1]), float(rotational[0, 0])),
        max_torque=(values["pitch"][0], values["roll"][0]),
        max_momentum=(values["pitch"][1], values["roll"][1]),
        max_angle=(values["pitch"][2], values["roll"][2]),
    )


__all__ = ["MAX_LEAN", "TORQUE_SHARE", "upper_body_flywheel"]
