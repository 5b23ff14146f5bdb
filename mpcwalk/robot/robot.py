"""Robot: one description in Pinocchio and in MuJoCo, with its walking traits.

Conventions: world z up, x forward. Sole frames are named ``left_sole`` and ``right_sole``
in both engines (a Pinocchio frame, a MuJoCo site), at the sole centre, z up when the foot is
flat. Pinocchio's free-flyer configuration stores the base quaternion as (x, y, z, w) and the
base linear velocity in the base frame; MuJoCo's free joint stores (w, x, y, z) and the linear
velocity in the world frame: use :meth:`Robot.q_to_qpos` and friends to convert.

This module reads the MuJoCo model's data but calls nothing of MuJoCo: the IK and the
controller use a :class:`Robot` without loading the simulator
(:mod:`mpcwalk.robot.loading` builds it).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError, FrameNotFound
from mpcwalk.footsteps import Footstep, LegLimits, Side
from mpcwalk.gait.gait_defaults import GaitDefaults
from mpcwalk.robot.joint_roles import JointRoles
from mpcwalk.robot.preset import RobotPreset

if TYPE_CHECKING:
    import mujoco

_XYZW = np.array([1, 2, 3, 0])  # MuJoCo's quaternion (w, x, y, z) -> Pinocchio's (x, y, z, w)


@dataclass(frozen=True)
class ServoGains:
    """Position servo of each joint (``robot.joint_names`` order), read from MuJoCo at load.

    Attributes:
        stiffness: Servo stiffness kp [N m/rad], shape (nb_joints,); inf where the joint has
            no position actuator.
        damping: Servo velocity gain plus passive joint damping [N m s/rad], shape
            (nb_joints,).
        torque_limit: Servo torque limit [N m], shape (nb_joints,); inf where unlimited.
    """

    stiffness: np.ndarray
    damping: np.ndarray
    torque_limit: np.ndarray


@dataclass(frozen=True, eq=False)
class Robot:
    """One robot in Pinocchio (free-flyer model) and in MuJoCo (scene with floor).

    Attributes:
        name: Robot name.
        preset: The preset it was built from.
        description_path: Description file (MJCF or URDF) both models come from.
        model: Pinocchio model; configuration q = (base position [m], base quaternion x, y, z,
            w, joint angles [rad]) in Pinocchio's joint order.
        data: Pinocchio data of ``model`` (shared scratch space).
        mj_model: MuJoCo model: the robot, its floor, actuators and sensors.
        q0: Nominal walking posture, soles flat on z = 0, feet midpoint at x = y = 0.
        foot_frames: Left and right sole frame names (Pinocchio frames and MuJoCo sites).
        sole_size: Sole length and width [m].
        com_height: CoM height above the soles in the nominal posture [m] (from the preset).
        torso_frame: Frame to keep upright while walking.
        joint_names: Actuated joints in Pinocchio's order.
        gait: Walking defaults of the preset's ``[gait]`` table.
        leg_limits: Leg limits of the footstep planners: the ``[gait]`` values, the half
            stance width of ``q0`` where the table has none, the :class:`LegLimits` defaults
            for the rest.
        servo_gains: Position servo stiffness, damping and torque limit of each joint.
        joint_roles: The joint of each role (hip roll, knee, shoulder pitch...) on each side:
            found from the kinematics at ``q0``, the preset's ``[joints]`` table over them
            (:mod:`mpcwalk.robot.joint_roles`).

    The legs' traits are found from the kinematic tree, the same way for every robot:
    :attr:`hip_joints` (the first joint of each leg from the base) and :attr:`leg_length`
    (the hips' height above the soles in ``q0``).
    """

    name: str
    preset: RobotPreset
    description_path: Path
    model: pin.Model
    data: pin.Data
    mj_model: mujoco.MjModel
    q0: np.ndarray
    foot_frames: tuple[str, str]
    sole_size: tuple[float, float]
    com_height: float
    torso_frame: str
    joint_names: tuple[str, ...]
    gait: GaitDefaults
    leg_limits: LegLimits
    servo_gains: ServoGains
    joint_roles: JointRoles
    _q_index: np.ndarray = field(repr=False)
    _v_index: np.ndarray = field(repr=False)
    _qpos_index: np.ndarray = field(repr=False)
    _dof_index: np.ndarray = field(repr=False)
    _ctrl_qpos_index: np.ndarray = field(repr=False)

    @property
    def total_mass(self) -> float:
        """Total mass [kg]."""
        return float(pin.computeTotalMass(self.model))

    @functools.cached_property
    def lateral_cop_reach(self) -> float:
        """How far sideways from a sole's centre the CoP can go with the whole weight on that
        foot [m]: half the sole's width, or less where the ankle roll motors cannot hold the
        weight there (their torque limit over ``m g``, the weaker of the two ankles)."""
        reach = 0.5 * float(self.sole_size[1])
        weight = self.total_mass * float(np.linalg.norm(self.model.gravity.linear))
        for side in ("left", "right"):
            joint = self.joint_roles.joint(side, "ankle_roll")
            if joint is not None and weight > 0.0:
                limit = float(self.servo_gains.torque_limit[self.joint_names.index(joint)])
                reach = min(reach, limit / weight)
        return reach

    @functools.cached_property
    def hip_joints(self) -> tuple[str, str]:
        """The hip of each leg (left, right): the joint of each sole's chain closest to the
        base that the other sole's chain does not hold (where the legs branch).

        Raises:
            ConfigurationError: A sole whose chain holds no joint of its own.
        """
        chains = []
        for frame in self.foot_frames:
            joint, chain = self.model.frames[self.frame_id(frame)].parentJoint, []
            while joint > 0:
                chain.append(int(joint))
                joint = self.model.parents[joint]
            chains.append(chain[::-1])  # from the base down to the sole
        hips = []
        for own, other in ((chains[0], chains[1]), (chains[1], chains[0])):
            first = next((joint for joint in own if joint not in other), None)
            if first is None:
                raise ConfigurationError(
                    f"Robot '{self.name}': the sole frames {self.foot_frames} share their whole "
                    "joint chain, so no leg joint tells the hips; each foot frame must end a "
                    "leg of its own."
                )
            hips.append(str(self.model.names[first]))
        return hips[0], hips[1]

    @functools.cached_property
    def leg_length(self) -> float:
        """The hips' height above the soles in the nominal posture ``q0`` [m] (the mean of
        both legs; the hip: :attr:`hip_joints`)."""
        pin.framesForwardKinematics(self.model, self.data, self.q0)
        heights = []
        for hip, sole in zip(self.hip_joints, self.foot_frames):
            hip_z = self.data.oMi[self.model.getJointId(hip)].translation[2]
            heights.append(float(hip_z - self.data.oMf[self.frame_id(sole)].translation[2]))
        return 0.5 * (heights[0] + heights[1])

    def frame_id(self, frame: str) -> int:
        """Pinocchio frame index of ``frame``; raises :class:`FrameNotFound`."""
        if not self.model.existFrame(frame):
            raise FrameNotFound(frame, [f.name for f in self.model.frames], self.name)
        return int(self.model.getFrameId(frame))

    def compute_frame_placement(self, q: np.ndarray, frame: str) -> pin.SE3:
        """World placement of ``frame`` at configuration ``q`` (Pinocchio)."""
        frame_id = self.frame_id(frame)
        pin.forwardKinematics(self.model, self.data, q)
        return pin.updateFramePlacement(self.model, self.data, frame_id).copy()

    def compute_sole_placements(self, q: np.ndarray) -> tuple[pin.SE3, pin.SE3]:
        """World placements of the left and right soles at ``q``."""
        left, right = self.foot_frames
        return self.compute_frame_placement(q, left), self.compute_frame_placement(q, right)

    def compute_com(self, q: np.ndarray) -> np.ndarray:
        """Whole-body CoM position [m], shape (3,), at ``q``."""
        return pin.centerOfMass(self.model, self.data, q).copy()

    def initial_feet(self, q: np.ndarray | None = None) -> tuple[Footstep, Footstep]:
        """Left and right footsteps of the soles at ``q`` (default ``q0``): the stance a
        walk starts from."""
        soles = self.compute_sole_placements(self.q0 if q is None else q)
        feet = []
        for side, sole in zip((Side.LEFT, Side.RIGHT), soles):
            yaw = math.atan2(sole.rotation[1, 0], sole.rotation[0, 0])
            feet.append(Footstep(side, sole.translation.copy(), yaw))
        return feet[0], feet[1]

    def q_to_qpos(self, q: np.ndarray) -> np.ndarray:
        """Pinocchio configuration -> MuJoCo ``qpos``."""
        qpos = np.zeros(self.mj_model.nq)
        qpos[0:3] = q[0:3]
        qpos[3:7] = (q[6], q[3], q[4], q[5])
        qpos[self._qpos_index] = q[self._q_index]
        return qpos

    def qpos_to_q(self, qpos: np.ndarray) -> np.ndarray:
        """MuJoCo ``qpos`` -> Pinocchio configuration (base quaternion normalized)."""
        q = np.zeros(self.model.nq)
        q[0:3] = qpos[0:3]
        quat = np.asarray(qpos[3:7], dtype=float)
        q[3:7] = quat[_XYZW] / math.sqrt(quat.dot(quat))  # what np.linalg.norm computes
        q[self._q_index] = qpos[self._qpos_index]
        return q

    def v_to_qvel(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Pinocchio velocity at ``q`` -> MuJoCo ``qvel`` (base linear velocity to world)."""
        qvel = np.zeros(self.mj_model.nv)
        rotation = pin.Quaternion(np.asarray(q[3:7], dtype=float)).normalized().matrix()
        qvel[0:3] = rotation @ v[0:3]
        qvel[3:6] = v[3:6]
        qvel[self._dof_index] = v[self._v_index]
        return qvel

    def qvel_to_v(self, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
        """MuJoCo ``qvel`` at ``qpos`` -> Pinocchio velocity (base linear velocity to local)."""
        v = np.zeros(self.model.nv)
        quat = np.asarray(qpos[3:7], dtype=float)
        w, x, y, z = quat / math.sqrt(quat.dot(quat))
        rotation = pin.Quaternion(w, x, y, z).matrix()
        v[0:3] = rotation.T @ qvel[0:3]
        v[3:6] = qvel[3:6]
        v[self._v_index] = qvel[self._dof_index]
        return v

    @property
    def joint_dofs(self) -> np.ndarray:
        """MuJoCo degree of freedom of each joint of :attr:`joint_names`: ``qvel[joint_dofs]``
        (or ``qfrc_actuator[joint_dofs]``) lists them in Pinocchio's joint order (a copy)."""
        return self._dof_index.copy()

    def q_to_ctrl(self, q: np.ndarray) -> np.ndarray:
        """Position-actuator targets (MuJoCo ``ctrl``, actuator order) holding posture ``q``."""
        return self.q_to_qpos(q)[self._ctrl_qpos_index]
