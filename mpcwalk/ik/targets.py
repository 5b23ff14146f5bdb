"""Inputs and outputs of the whole-body IK: targets, task weights, task errors, result."""

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk._checks import as_float_array, frozen_array
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.tasks import finite_vector

_ROTATION_TOLERANCE = 1e-6


def _as_vector(value, size: int, name: str) -> np.ndarray:
    return frozen_array(finite_vector(value, size, f"IK target {name}"))


def _as_rotation(value, name: str) -> np.ndarray:
    rotation = as_float_array(value)
    if rotation.shape != (3, 3) or not np.all(np.isfinite(rotation)):
        raise ConfigurationError(
            f"IK target {name} must be a 3x3 rotation matrix, got shape {np.shape(value)}."
        )
    defect = np.abs(rotation.T @ rotation - np.eye(3)).max()
    if defect > _ROTATION_TOLERANCE or np.linalg.det(rotation) < 0.0:
        raise ConfigurationError(
            f"IK target {name} is not a rotation matrix (|R^T R - I| = {defect:.1e}, det = "
            f"{np.linalg.det(rotation):.3f}); orthonormalise it, e.g. with "
            "pinocchio.exp3(pinocchio.log3(R))."
        )
    return frozen_array(rotation)


def _as_pose(value, name: str) -> pin.SE3:
    if isinstance(value, pin.SE3):
        value = value.homogeneous
    matrix = as_float_array(value)
    if matrix.shape != (4, 4) or not np.allclose(matrix[3], [0.0, 0.0, 0.0, 1.0]):
        raise ConfigurationError(
            f"IK target {name} must be a pinocchio.SE3 or a 4x4 homogeneous transform, got "
            f"shape {np.shape(value)}."
        )
    rotation = _as_rotation(matrix[:3, :3], f"{name} rotation")
    translation = _as_vector(matrix[:3, 3], 3, f"{name} translation")
    return pin.SE3(np.array(rotation), np.array(translation))


@dataclass(frozen=True)
class IKTargets:
    """References of one IK tick, world frame.

    Give the references of the time the IK step should reach (the next tick) and no
    velocities, or the references of the current time and their velocities: the IK step then
    aims at their first-order prediction one period ahead (feed-forward).

    Attributes:
        com: CoM position, shape (3,), in [m].
        left_sole: Pose of the left sole frame (``pinocchio.SE3``; a 4x4 transform is
            converted).
        right_sole: Pose of the right sole frame.
        torso_rotation: Orientation of the torso frame, shape (3, 3) (upright: a yaw rotation).
        com_velocity: CoM velocity, shape (3,), in [m/s], or None.
        left_sole_velocity: Left sole velocity (linear [m/s], angular [rad/s], world axes),
            shape (6,), or None.
        right_sole_velocity: Right sole velocity, shape (6,), or None.
        torso_angular_velocity: Torso angular velocity, shape (3,), in [rad/s], or None.
        angular_momentum: Centroidal angular momentum the step should produce (the hip
            strategy's flywheel), world axes, shape (3,), in [kg m^2/s], or None: no
            angular-momentum task (:mod:`mpcwalk.ik.momentum_task`).

    Raises:
        ConfigurationError: A field has the wrong shape, is not finite or is not a rotation.
    """

    com: np.ndarray
    left_sole: pin.SE3
    right_sole: pin.SE3
    torso_rotation: np.ndarray
    com_velocity: np.ndarray | None = None
    left_sole_velocity: np.ndarray | None = None
    right_sole_velocity: np.ndarray | None = None
    torso_angular_velocity: np.ndarray | None = None
    angular_momentum: np.ndarray | None = None

    def __post_init__(self) -> None:
        set_field = object.__setattr__
        set_field(self, "com", _as_vector(self.com, 3, "com"))
        set_field(self, "left_sole", _as_pose(self.left_sole, "left_sole"))
        set_field(self, "right_sole", _as_pose(self.right_sole, "right_sole"))
        set_field(self, "torso_rotation", _as_rotation(self.torso_rotation, "torso_rotation"))
        for name, size in (
            ("com_velocity", 3),
            ("left_sole_velocity", 6),
            ("right_sole_velocity", 6),
            ("torso_angular_velocity", 3),
            ("angular_momentum", 3),
        ):
            value = getattr(self, name)
            if value is not None:
                set_field(self, name, _as_vector(value, size, name))

    @classmethod
    def trusted(
        cls,
        com: np.ndarray,
        left_sole: pin.SE3,
        right_sole: pin.SE3,
        torso_rotation: np.ndarray,
        com_velocity: np.ndarray | None = None,
        left_sole_velocity: np.ndarray | None = None,
        right_sole_velocity: np.ndarray | None = None,
        torso_angular_velocity: np.ndarray | None = None,
        angular_momentum: np.ndarray | None = None,
    ) -> "IKTargets":
        """Targets built without the checks of the constructor, for a caller whose values
        are valid by construction (the controller's gait references, every tick): float
        arrays of the right shapes, ``pinocchio.SE3`` soles, a rotation matrix. Validate at
        the boundary, not on the hot path; anything else goes through ``IKTargets(...)``."""
        targets = object.__new__(cls)
        set_field = object.__setattr__
        set_field(targets, "com", com)
        set_field(targets, "left_sole", left_sole)
        set_field(targets, "right_sole", right_sole)
        set_field(targets, "torso_rotation", torso_rotation)
        set_field(targets, "com_velocity", com_velocity)
        set_field(targets, "left_sole_velocity", left_sole_velocity)
        set_field(targets, "right_sole_velocity", right_sole_velocity)
        set_field(targets, "torso_angular_velocity", torso_angular_velocity)
        set_field(targets, "angular_momentum", angular_momentum)
        return targets

    @property
    def has_velocities(self) -> bool:
        """True when at least one feed-forward velocity is given."""
        return any(
            v is not None
            for v in (
                self.com_velocity,
                self.left_sole_velocity,
                self.right_sole_velocity,
                self.torso_angular_velocity,
            )
        )

    @staticmethod
    def from_configuration(robot, q: np.ndarray, torso_frame: str = "") -> "IKTargets":
        """Targets that ``q`` reaches exactly (CoM, soles and torso of ``robot`` at ``q``)."""
        left, right = robot.compute_sole_placements(q)
        torso = robot.compute_frame_placement(q, torso_frame or robot.torso_frame)
        return IKTargets(robot.compute_com(q), left, right, torso.rotation)

    @staticmethod
    def from_gait(
        com: np.ndarray,
        feet,
        torso_yaw: float,
        *,
        com_velocity: np.ndarray | None = None,
        torso_yaw_rate: float | None = None,
    ) -> "IKTargets":
        """Targets from the gait: a CoM, a :class:`~mpcwalk.gait.swing_foot.FeetState` (feet at
        their full orientation, with velocities) and the torso yaw [rad] (torso upright).

        Feed-forward velocities of the feet are set from ``feet``; the torso's when
        ``torso_yaw_rate`` [rad/s] is given.
        """
        c, s = np.cos(torso_yaw), np.sin(torso_yaw)
        torso = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

        def velocity(foot) -> np.ndarray:
            return np.concatenate([foot.linear_velocity, foot.angular_velocity])

        return IKTargets(
            com=com,
            left_sole=feet.left.transform,
            right_sole=feet.right.transform,
            torso_rotation=torso,
            com_velocity=com_velocity,
            left_sole_velocity=velocity(feet.left),
            right_sole_velocity=velocity(feet.right),
            torso_angular_velocity=None
            if torso_yaw_rate is None
            else np.array([0.0, 0.0, torso_yaw_rate]),
        )


@dataclass(frozen=True)
class IKWeights:
    """Task weights of the whole-body IK (pink's "costs": a 1 cm CoM error with weight 10
    costs as much as a 0.1 rad torso error with weight 1).

    Attributes:
        com: CoM position [cost/m].
        sole_position: Position of each sole [cost/m].
        sole_orientation: Orientation of each sole [cost/rad].
        torso_orientation: Torso orientation [cost/rad].
        posture: Joint angles towards the reference posture [cost/rad].
        angular_momentum: Centroidal angular momentum, as the upper body's equivalent
            rotation [cost/rad] (only when a target gives one).
    """

    com: float = 10.0
    sole_position: float = 10.0
    sole_orientation: float = 10.0
    torso_orientation: float = 1.0
    posture: float = 1e-2
    angular_momentum: float = 1.0


@dataclass(frozen=True)
class TaskErrors:
    """Norms of the task errors at one configuration.

    Attributes:
        com: CoM position error, in [m].
        left_sole_position: Left sole position error, in [m].
        left_sole_orientation: Left sole orientation error (rotation angle), in [rad].
        right_sole_position: Right sole position error, in [m].
        right_sole_orientation: Right sole orientation error, in [rad].
        torso_orientation: Torso orientation error, in [rad].
        posture: Distance of the joint angles to the posture reference, in [rad].
    """

    com: float
    left_sole_position: float
    left_sole_orientation: float
    right_sole_position: float
    right_sole_orientation: float
    torso_orientation: float
    posture: float

    @property
    def position_max(self) -> float:
        """Largest of the CoM and sole position errors, in [m]."""
        return max(self.com, self.left_sole_position, self.right_sole_position)

    @property
    def orientation_max(self) -> float:
        """Largest of the sole and torso orientation errors, in [rad]."""
        return max(self.left_sole_orientation, self.right_sole_orientation, self.torso_orientation)


@dataclass(frozen=True)
class IKResult:
    """Result of one IK step (:meth:`WholeBodyIK.solve`) or of a whole solve
    (:meth:`WholeBodyIK.solve_pose`).

    Attributes:
        q_next: Configuration after the step(s), shape (nq,).
        v: Velocity of the step, ``difference(q, q_next) / dt``, shape (nv,), in [m/s, rad/s]
            (base linear velocity in the base frame, as Pinocchio).
        task_errors: Errors at the input configuration for :meth:`~WholeBodyIK.solve` (what
            the step corrects), at ``q_next`` for :meth:`~WholeBodyIK.solve_pose`.
        solve_time: Wall time of the call, in [s].
        success: False when the QP failed and a fallback was used, or when ``solve_pose``
            did not reach its tolerance.
        status: ``"unconstrained"`` (damped least squares within the bounds), ``"qp"``,
            ``"fallback"`` (QP failed: least squares clipped to the bounds), ``"kept"`` (no
            finite step: q kept), ``"converged"`` / ``"max_iterations"`` (``solve_pose``).
        iterations: Number of steps taken.
        qp_solves: Number of steps that needed the QP.
    """

    q_next: np.ndarray
    v: np.ndarray
    task_errors: TaskErrors
    solve_time: float
    success: bool
    status: str
    iterations: int = 1
    qp_solves: int = 0
