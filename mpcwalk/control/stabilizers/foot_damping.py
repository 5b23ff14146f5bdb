"""Foot force/torque damping: the ankles comply with the error of the measured sole torques.

Each foot's 6-axis force/torque sensor measures the moment ``tau`` of the ground's forces
about the sole origin, in the sole frame; the foot's desired CoP ``r`` (its share of the
desired ZMP, :mod:`~mpcwalk.control.stabilizers.zmp_distribution`) asks for
``tau_d = r x f`` with ``f`` the measured normal force (so that a foot carrying less than its
share is not asked for a torque it cannot have). The damping control of Kajita et al. 2010
(HRP-4C) and Caron et al. 2019 (HRP-4) turns the foot, relative to the leg, in the direction
of the torque error, as a damper would, with a leak back to zero:

    d theta / dt = K (tau - tau_d) / (m g) - theta / T,    |theta| <= theta_max,

``theta`` = (roll, pitch) rotation of the foot about the sole's x and y axes [rad]. Pressing
too much on the toes (``tau_y < tau_d,y``) lifts the toes, which moves the foot's CoP back
towards the heel. Normalising the torque by the robot's weight ``m g`` makes ``K`` a rate per
metre of CoP error [rad/(m s)] that means the same on a 2 kg and a 40 kg robot: with all the
weight on a foot, a 1 cm CoP error turns the foot at ``K`` x 0.01 rad/s (Caron's HRP-4
admittance of 0.01 rad/(N m s) is about 4 rad/(m s) at its 39 kg). The leak ``T`` bounds what a
steady error winds up (``K T`` x the error); a foot the plan lifts leaks faster (``T_swing``)
so that it swings and lands flat (a toe left down scuffs the floor).

The rotation is made by the two joints nearest to the sole in the kinematic tree (the ankle
pitch and roll on every shipped robot): ``dq = A^-1 theta`` with ``A`` the horizontal part of
their axes in the sole frame at the nominal posture (a joint angle ``dq`` turns the foot by
``dq`` about its axis relative to the shank).
"""

import math

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.robot import Robot
from mpcwalk.robot.sensors import ForceTorqueReading


def _check(name: str, value: float, *, positive: bool = False, allow_inf: bool = False) -> float:
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    valid = number and not math.isnan(value) and (allow_inf or math.isfinite(value))
    if valid:
        valid = value > 0.0 if positive else value >= 0.0
    if not valid:
        kind = "positive" if positive else "non-negative"
        raise ConfigurationError(f"FootDamping {name} must be a {kind} number, got {value!r}.")
    return float(value)


class FootDamping:
    """Ankle pitch and roll offsets from the error of each foot's measured sole torque.

    Args:
        gain: ``K``, foot rotation rate per metre of weight-normalised CoP error
            [rad/(m s)].
        time_constant: ``T``, leak time constant [s] (inf: no leak).
        max_offset: Bound of the foot rotation about each axis [rad].
        swing_time_constant: ``T_swing``, leak time constant [s] of a lifted foot.
        min_force: Feet whose measured normal force is below this share of the robot's
            weight are not damped (lifted, or just touching), only leaked.

    Raises:
        ConfigurationError: A parameter out of range; on :meth:`calibrate`, a robot whose
            two joints nearest to a sole are not two revolute actuated joints turning the
            foot about two horizontal axes.
    """

    def __init__(
        self,
        *,
        gain: float,
        time_constant: float,
        max_offset: float,
        min_force: float = 0.05,
        swing_time_constant: float = 0.05,
    ) -> None:
        self.gain = _check("gain", gain)
        self.time_constant = _check("time_constant", time_constant, positive=True, allow_inf=True)
        self.max_offset = _check("max_offset", max_offset)
        self.min_force = _check("min_force", min_force)
        self.swing_time_constant = _check("swing_time_constant", swing_time_constant, positive=True)
        self.joint_indices = np.zeros((2, 2), dtype=int)
        """Indices in ``robot.joint_names`` of the two ankle joints of each foot (left, right)."""
        self.inverse_axes = np.zeros((2, 2, 2))
        """Per foot, ``A^-1``: joint angles per foot rotation (roll, pitch in the sole frame)."""
        self.rotation = np.zeros((2, 2))
        """Foot rotations ``theta`` (roll, pitch) [rad] of the left and right feet."""
        self.weight = 0.0

    def reset(self) -> None:
        """Feet back flat (a new walk)."""
        self.rotation = np.zeros((2, 2))

    def calibrate(self, robot: Robot) -> None:
        """Find the two ankle joints of each foot of ``robot`` and their axes in the sole frame
        at ``robot.q0``; forget the rotations."""
        model, data = robot.model, robot.model.createData()
        pin.computeJointJacobians(model, data, robot.q0)
        pin.updateFramePlacements(model, data)
        names = list(robot.joint_names)
        for index, frame in enumerate(robot.foot_frames):
            frame_id = robot.frame_id(frame)
            sole = data.oMf[frame_id].rotation
            last = int(model.frames[frame_id].parentJoint)
            joints = (int(model.parents[last]), last)
            axes, found = [], []
            for joint in joints:
                name = model.names[joint]
                if model.joints[joint].nv != 1 or name not in names:
                    raise ConfigurationError(
                        f"Foot damping turns the foot with the two joints nearest to its sole; "
                        f"on robot '{robot.name}' joint '{name}' above '{frame}' is not a "
                        "revolute actuated joint."
                    )
                column = model.joints[joint].idx_v
                jacobian = pin.getJointJacobian(model, data, joint, pin.LOCAL_WORLD_ALIGNED)
                axes.append(sole.T @ jacobian[3:6, column])
                found.append(names.index(name))
            matrix = np.array(axes).T[:2]  # columns: the joints' (x, y) axes in the sole frame
            if abs(np.linalg.det(matrix)) < 0.5:
                raise ConfigurationError(
                    f"Foot damping needs two ankle joints turning '{frame}' about its x and y "
                    f"axes; on robot '{robot.name}' joints {[names[i] for i in found]} do not "
                    f"(axes {np.round(matrix, 2).tolist()} in the sole frame)."
                )
            self.joint_indices[index] = found
            self.inverse_axes[index] = np.linalg.inv(matrix)
        self.weight = robot.total_mass * float(-robot.model.gravity.linear[2])
        self.reset()

    def update(
        self,
        wrenches: tuple[ForceTorqueReading, ForceTorqueReading],
        desired_cops: np.ndarray,
        in_contact: tuple[bool, bool],
        dt: float,
        lifted: tuple[bool, bool] = (False, False),
    ) -> np.ndarray:
        """Advance the foot rotations by one tick.

        Args:
            wrenches: Left and right force/torque readings (sole frames, about the sole
                origins).
            desired_cops: Desired CoP of each foot in its sole frame, shape (2, 2), in [m].
            in_contact: Whether each foot is in contact (estimated).
            dt: Duration of the tick [s].
            lifted: Whether the plan lifts each foot (its rotation leaks with
                ``swing_time_constant``).

        Returns:
            The foot rotations (roll, pitch) [rad], shape (2, 2).
        """
        decays = (math.exp(-dt / self.time_constant), math.exp(-dt / self.swing_time_constant))
        rate, bound = dt * self.gain / self.weight, self.max_offset
        for index, (wrench, contact) in enumerate(zip(wrenches, in_contact)):
            decay = decays[1] if lifted[index] else decays[0]  # 1 without leak
            roll, pitch = decay * self.rotation[index, 0], decay * self.rotation[index, 1]
            force = float(wrench.force[2])
            if contact and force > self.min_force * self.weight:
                x, y = float(desired_cops[index][0]), float(desired_cops[index][1])
                # torque error about the sole's x and y axes; desired r x f = (y f, -x f)
                roll += rate * (float(wrench.torque[0]) - y * force)
                pitch += rate * (float(wrench.torque[1]) + x * force)
            self.rotation[index, 0] = min(bound, max(-bound, roll))
            self.rotation[index, 1] = min(bound, max(-bound, pitch))
        return self.rotation

    def joint_offsets(self) -> np.ndarray:
        """Ankle joint offsets [rad] of the current foot rotations, shape (2, 2): per foot,
        those of the joints :attr:`joint_indices`."""
        return (self.inverse_axes @ self.rotation[:, :, None])[:, :, 0]
