"""Kinematic tasks of the whole-body IK: CoM, frame pose (or orientation only), posture.

Every task has an error ``e(q)`` (dimension ``k``), its Jacobian ``J(q)`` (shape ``(k, nv)``)
such that ``e(q + dq) = e(q) + J dq`` to first order (``q + dq`` is Pinocchio's
``integrate``), per-coordinate weights and a feed-forward term (the rate at which the error
shrinks when the target moves and the robot stands still). Convention: local world aligned,
i.e. positions and angular quantities in world axes, Jacobians from
``pin.getFrameJacobian(..., LOCAL_WORLD_ALIGNED)``. The error of a frame orientation is
``log3(R R_target^T)``, the rotation from the target to the frame in world axes.

The tasks read the kinematics from a Pinocchio ``data`` that :func:`update_kinematics` filled
at ``q``, so that one forward pass serves all tasks. The IK then linearises each task as
``J dq = -gain e + dt feedforward``, weighted by ``weights``.
"""

import abc
from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from mpcwalk._checks import as_float_array
from mpcwalk.exceptions import ConfigurationError, FrameNotFound

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_ZERO3 = np.zeros(3)
_ZERO3.setflags(write=False)
_ZERO6 = np.zeros(6)
_ZERO6.setflags(write=False)


def update_kinematics(model: pin.Model, data: pin.Data, q: np.ndarray) -> None:
    """One forward pass that all tasks read: joint and frame placements, joint Jacobians
    (``data.J``), the CoM (``data.com[0]``) and its Jacobian (``data.Jcom``)."""
    pin.jacobianCenterOfMass(model, data, q, False)
    pin.updateFramePlacements(model, data)


def _weights(value: float | Sequence[float], size: int, name: str) -> np.ndarray:
    try:
        weights = np.broadcast_to(np.asarray(value, dtype=float), (size,)).copy()
    except (TypeError, ValueError):
        weights = np.full(size, np.nan)
    if not np.all(np.isfinite(weights)) or np.any(weights < 0.0):
        raise ConfigurationError(
            f"{name} must be a non-negative finite number or {size} of them, got {value!r}."
        )
    return weights


def finite_vector(value, size: int, name: str) -> np.ndarray:
    """``value`` as a float array of shape (size,), or a ConfigurationError naming ``name``."""
    array = as_float_array(value)
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise ConfigurationError(
            f"{name} must be an array of {size} finite numbers, got shape {np.shape(value)}: "
            f"{value!r}; pass e.g. np.zeros({size})."
        )
    return array


class Task(abc.ABC):
    """A kinematic task: error, Jacobian, weights, feed-forward.

    Attributes:
        name: Task name (used in the IK's reports).
        dimension: Number of task coordinates ``k``.
        weights: Weight of each coordinate, shape (k,), in [cost] per task unit.
    """

    name: str
    dimension: int
    weights: np.ndarray

    @abc.abstractmethod
    def compute_error(self, model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
        """Task error ``e(q)``, shape (k,), at the configuration of ``data``."""

    @abc.abstractmethod
    def compute_jacobian(self, model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
        """Task Jacobian ``de/dq``, shape (k, nv), at the configuration of ``data``."""

    def compute_feedforward(self, model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
        """Rate [task unit/s] at which the error decreases when the target moves with its
        velocity and the robot stands still; zero for a still target."""
        return np.zeros(self.dimension)

    def compute_linearization(
        self, model: pin.Model, data: pin.Data, q: np.ndarray, feedforward: bool = True
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """Error, Jacobian and (if ``feedforward``) feed-forward in one call (what the IK
        uses; tasks override it to share intermediate results)."""
        return (
            self.compute_error(model, data, q),
            self.compute_jacobian(model, data, q),
            self.compute_feedforward(model, data, q) if feedforward else None,
        )


class ComTask(Task):
    """Whole-body centre of mass at a 3D target (world frame).

    Args:
        weight: Weight [cost/m], a float or one per axis.
    """

    def __init__(self, weight: float | Sequence[float] = 1.0) -> None:
        self.name = "com"
        self.dimension = 3
        self.weights = _weights(weight, 3, "ComTask weight")
        self.target = np.zeros(3)
        self.target_velocity = np.zeros(3)

    def set_target(self, com: np.ndarray, velocity: np.ndarray | None = None) -> None:
        """Target CoM position [m] and, optionally, its velocity [m/s], world frame."""
        self.target = finite_vector(com, 3, "CoM target")
        self.target_velocity = (
            np.zeros(3) if velocity is None else finite_vector(velocity, 3, "CoM target velocity")
        )

    def set_checked_target(self, com: np.ndarray, velocity: np.ndarray | None) -> None:
        """:meth:`set_target` for values already checked (an :class:`IKTargets`'): finite
        float arrays of shape (3,)."""
        self.target = com
        self.target_velocity = _ZERO3 if velocity is None else velocity

    def compute_error(self, model, data, q) -> np.ndarray:
        """``c(q) - c_target`` [m]."""
        return data.com[0] - self.target

    def compute_jacobian(self, model, data, q) -> np.ndarray:
        """CoM Jacobian, shape (3, nv)."""
        return data.Jcom.copy()

    def compute_feedforward(self, model, data, q) -> np.ndarray:
        """Target CoM velocity [m/s]."""
        return self.target_velocity

    def compute_linearization(self, model, data, q, feedforward=True):
        """Error, Jacobian (a view of ``data.Jcom``, valid until the next update) and
        feed-forward."""
        return data.com[0] - self.target, data.Jcom, self.target_velocity if feedforward else None


class FrameTask(Task):
    """Pose of a frame at an SE3 target, or its orientation only.

    The error stacks the position error ``p - p_target`` [m] (unless the task is
    orientation-only) and the orientation error ``log3(R R_target^T)`` [rad], both in world
    axes.

    Args:
        model: Pinocchio model holding the frame.
        frame: Frame name.
        position_weight: Weight [cost/m], a float or one per world axis; ``None`` makes an
            orientation-only task (dimension 3).
        orientation_weight: Weight [cost/rad], a float or one per world axis.
        name: Task name (default: the frame name).

    Raises:
        FrameNotFound: The model has no frame ``frame``.
    """

    def __init__(
        self,
        model: pin.Model,
        frame: str,
        *,
        position_weight: float | Sequence[float] | None = 1.0,
        orientation_weight: float | Sequence[float] = 1.0,
        name: str = "",
    ) -> None:
        if not isinstance(frame, str) or not model.existFrame(frame):
            raise FrameNotFound(str(frame), [f.name for f in model.frames], model.name)
        self.frame = frame
        self.frame_id = int(model.getFrameId(frame))
        self.name = name or frame
        self.orientation_only = position_weight is None
        orientation = _weights(orientation_weight, 3, f"FrameTask({frame}) orientation_weight")
        if position_weight is None:
            self.weights = orientation
        else:
            position = _weights(position_weight, 3, f"FrameTask({frame}) position_weight")
            self.weights = np.concatenate([position, orientation])
        self.dimension = len(self.weights)
        self.target = pin.SE3.Identity()
        self._target_rotation_t = np.eye(3)
        self.target_velocity = np.zeros(6)

    def set_target(self, pose: pin.SE3 | np.ndarray, velocity: np.ndarray | None = None) -> None:
        """Target pose in the world and, optionally, its velocity (linear [m/s], angular
        [rad/s], world axes, shape (6,)). Orientation-only tasks ignore the position."""
        if not isinstance(pose, pin.SE3):
            matrix = np.asarray(pose, dtype=float)
            if matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
                raise ConfigurationError(
                    f"FrameTask({self.frame}) target must be a pinocchio.SE3 or a 4x4 transform, "
                    f"got shape {matrix.shape}."
                )
            pose = pin.SE3(matrix)
        self.target = pose
        self._target_rotation_t = pose.rotation.T.copy()
        self.target_velocity = (
            np.zeros(6) if velocity is None else finite_vector(velocity, 6, "frame target velocity")
        )

    def set_checked_target(self, pose: pin.SE3, velocity: np.ndarray | None) -> None:
        """:meth:`set_target` for values already checked (an :class:`IKTargets`'): an SE3
        and a finite float array of shape (6,) or None."""
        self.target = pose
        self._target_rotation_t = pose.rotation.T.copy()
        self.target_velocity = _ZERO6 if velocity is None else velocity

    def _rotation_error(self, data: pin.Data) -> np.ndarray:
        return data.oMf[self.frame_id].rotation @ self._target_rotation_t

    def compute_error(self, model, data, q) -> np.ndarray:
        """Position error [m] (unless orientation-only) then ``log3(R R_target^T)`` [rad]."""
        rotation_error = pin.log3(self._rotation_error(data))
        if self.orientation_only:
            return rotation_error
        position_error = data.oMf[self.frame_id].translation - self.target.translation
        return np.concatenate([position_error, rotation_error])

    def compute_jacobian(self, model, data, q) -> np.ndarray:
        """``[J_linear; Jlog3(E) E^T J_angular]`` with ``E = R R_target^T``, world axes."""
        jacobian = pin.getFrameJacobian(model, data, self.frame_id, _LWA)
        rotation_error = self._rotation_error(data)
        angular = pin.Jlog3(rotation_error) @ rotation_error.T @ jacobian[3:]
        if self.orientation_only:
            return angular
        jacobian[3:] = angular
        return jacobian

    def compute_feedforward(self, model, data, q) -> np.ndarray:
        """Target linear velocity [m/s] and ``Jlog3(E)`` times its angular velocity."""
        angular = pin.Jlog3(self._rotation_error(data)) @ self.target_velocity[3:]
        if self.orientation_only:
            return angular
        return np.concatenate([self.target_velocity[:3], angular])

    def compute_linearization(self, model, data, q, feedforward=True):
        """Error, Jacobian and feed-forward sharing one ``log3`` and one ``Jlog3``."""
        placement = data.oMf[self.frame_id]
        rotation_error = placement.rotation @ self._target_rotation_t
        jlog = pin.Jlog3(rotation_error)
        jacobian = pin.getFrameJacobian(model, data, self.frame_id, _LWA)
        angular = jlog @ rotation_error.T @ jacobian[3:]
        angular_error = pin.log3(rotation_error)
        angular_feedforward = jlog @ self.target_velocity[3:] if feedforward else None
        if self.orientation_only:
            return angular_error, angular, angular_feedforward
        jacobian[3:] = angular
        error = np.concatenate([placement.translation - self.target.translation, angular_error])
        if feedforward:
            return error, jacobian, np.concatenate([self.target_velocity[:3], angular_feedforward])
        return error, jacobian, None


class PostureTask(Task):
    """Joint angles towards a reference posture (the floating base is free).

    Args:
        model: Pinocchio model with a free-flyer root.
        weight: Weight [cost/rad], a float or one per actuated joint.
        reference: Reference configuration, shape (nq,) (default: Pinocchio's neutral).
    """

    def __init__(
        self,
        model: pin.Model,
        weight: float | Sequence[float] = 1e-2,
        reference: np.ndarray | None = None,
    ) -> None:
        self.name = "posture"
        self.root_nv = int(model.joints[1].nv) if model.njoints > 1 else 0
        self.dimension = model.nv - self.root_nv
        self.weights = _weights(weight, self.dimension, "PostureTask weight")
        self.reference = pin.neutral(model)
        if reference is not None:
            self.set_target(model, reference)

    def set_target(self, model: pin.Model, reference: np.ndarray) -> None:
        """Reference configuration, shape (nq,)."""
        self.reference = finite_vector(reference, model.nq, "posture reference").copy()

    def compute_error(self, model, data, q) -> np.ndarray:
        """Joint displacement from the reference [rad]."""
        return pin.difference(model, self.reference, q)[self.root_nv :]

    def compute_jacobian(self, model, data, q) -> np.ndarray:
        """``[0 I]``, shape (nv - 6, nv)."""
        return np.eye(model.nv)[self.root_nv :]
