"""Cartesian point-to-point trajectories (paper A's ``ctraj``).

The pose moves along the straight line between the two positions and along
the geodesic (constant axis of rotation) between the two orientations. Both
follow the same quintic time law ``r(s)`` of :func:`~mpcwalk.gait.jtraj.jtraj`
(zero velocity and acceleration at both ends), sampled at ``n`` evenly spaced
normalised times ``s``:

    p(s) = p0 + r(s) (p1 - p0)
    R(s) = R0 exp(r(s) log(R0^T R1))

``log`` and ``exp`` are those of SO(3) (rotation vectors), written here with
numpy so that the gait layer runs without Pinocchio; a ``pinocchio.SE3`` is
still accepted as a pose.

With ``precision`` (paper A: the spacing the user wants between consecutive
points, in [m]) the number of samples is chosen so that no two consecutive
positions are farther apart than ``precision``. The quintic law moves at up
to 15/8 of its mean speed, so ``n = ceil(15/8 * distance / precision) + 1``
(at least 2), where ``distance = |p1 - p0|``.
"""

import math
import sys
from dataclasses import dataclass

import numpy as np

from mpcwalk._checks import as_float, as_float_array
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.jtraj import check_nb_samples, jtraj

#: Peak of the quintic time law's derivative, ``r'(1/2) = 15/8``.
QUINTIC_PEAK_RATE = 15.0 / 8.0

#: Tolerance on ``R^T R = I`` and ``det R = 1`` for input poses.
ROTATION_TOLERANCE = 1e-6


@dataclass(frozen=True)
class CartesianTrajectory:
    """Sampled Cartesian trajectory.

    Attributes:
        poses: Homogeneous transforms, shape (n, 4, 4), positions in [m].
        s: Normalised time of each sample, shape (n,), from 0 to 1.
        path_fraction: Fraction ``r(s)`` of the way travelled at each sample,
            shape (n,), from 0 to 1 (quintic in ``s``).
    """

    poses: np.ndarray
    s: np.ndarray
    path_fraction: np.ndarray

    @property
    def positions(self) -> np.ndarray:
        """Positions, shape (n, 3), in [m]."""
        return self.poses[:, :3, 3]

    @property
    def rotations(self) -> np.ndarray:
        """Rotation matrices, shape (n, 3, 3)."""
        return self.poses[:, :3, :3]

    @property
    def nb_samples(self) -> int:
        """Number of samples ``n``."""
        return len(self.s)


def as_homogeneous(pose, name: str = "pose") -> np.ndarray:
    """A validated 4x4 homogeneous transform from an array or a pinocchio.SE3.

    Raises:
        ConfigurationError: If ``pose`` is not a rigid transform.
    """
    pinocchio = sys.modules.get("pinocchio")  # a pinocchio.SE3 implies pinocchio is loaded
    if pinocchio is not None and isinstance(pose, pinocchio.SE3):
        return np.array(pose.homogeneous, dtype=float)
    matrix = np.array(as_float_array(pose))  # a copy: the caller's array stays theirs
    if matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
        came = type(pose).__name__
        if matrix.size:
            came += f" of shape {matrix.shape}"
        raise ConfigurationError(
            f"{name} must be a pinocchio.SE3 or a finite 4x4 homogeneous transform, got {came}."
        )
    rotation = matrix[:3, :3]
    orthonormal = np.allclose(rotation.T @ rotation, np.eye(3), atol=ROTATION_TOLERANCE)
    if (
        not np.allclose(matrix[3], [0.0, 0.0, 0.0, 1.0])
        or not orthonormal
        or (np.linalg.det(rotation) < 0.0)
    ):
        raise ConfigurationError(
            f"{name} is not a rigid transform: its last row must be [0, 0, 0, 1] and "
            f"its 3x3 block a rotation (R^T R = I to {ROTATION_TOLERANCE:g}, det R = +1). "
            "Build it with pinocchio.SE3(R, p) or re-orthonormalise R."
        )
    return matrix


def log3(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector (axis times angle in [0, pi], in [rad]) of a rotation matrix (3, 3),
    through its unit quaternion (Shepperd's method: accurate at every angle, pi included)."""
    R = np.asarray(rotation, dtype=float)
    trace = np.trace(R)
    k = int(np.argmax([R[0, 0], R[1, 1], R[2, 2], trace]))
    if k == 3:
        w = 0.5 * math.sqrt(1.0 + trace)
        xyz = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (4.0 * w)
    else:
        i, j, m = k, (k + 1) % 3, (k + 2) % 3
        xyz = np.zeros(3)
        xyz[i] = 0.5 * math.sqrt(1.0 + 2.0 * R[i, i] - trace)
        w = (R[m, j] - R[j, m]) / (4.0 * xyz[i])
        xyz[j] = (R[j, i] + R[i, j]) / (4.0 * xyz[i])
        xyz[m] = (R[m, i] + R[i, m]) / (4.0 * xyz[i])
    if w < 0.0:  # the same rotation, the angle in [0, pi]
        w, xyz = -w, -xyz
    angle = 2.0 * math.atan2(float(np.linalg.norm(xyz)), w)
    if angle > 1e-3:
        scale = angle / math.sin(0.5 * angle)
    else:  # series of angle / sin(angle / 2)
        scale = 2.0 + angle**2 / 12.0 + 7.0 * angle**4 / 2880.0
    return scale * xyz


def exp3(rotation_vectors: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of rotation vectors (..., 3) [rad] (Rodrigues)."""
    w = np.asarray(rotation_vectors, dtype=float)
    angle = np.linalg.norm(w, axis=-1)[..., None, None]
    K = np.zeros(w.shape + (3,))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = w[..., 2], -w[..., 1], w[..., 0]
    small = angle < 1e-4
    safe = np.where(small, 1.0, angle)
    a = np.where(small, 1.0 - angle**2 / 6.0, np.sin(safe) / safe)  # sin(x) / x
    b = np.where(small, 0.5 - angle**2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    return np.eye(3) + a * K + b * (K @ K)


def ctraj(T0, T1, n: int | None = None, *, precision: float | None = None) -> CartesianTrajectory:
    """Cartesian trajectory from pose ``T0`` to pose ``T1``.

    Give exactly one of ``n`` and ``precision``.

    Args:
        T0: Start pose, 4x4 homogeneous transform or pinocchio.SE3.
        T1: End pose, same types.
        n: Number of samples, including both ends (>= 2).
        precision: Largest distance between consecutive positions, in [m];
            the number of samples follows from it (see the module docstring).

    Returns:
        The sampled trajectory; its first and last poses equal ``T0`` and
        ``T1`` exactly.

    Raises:
        ConfigurationError: If a pose is not a rigid transform, if both or
            neither of ``n`` and ``precision`` are given, or if ``precision``
            is not a positive number.
    """
    start = as_homogeneous(T0, "T0")
    end = as_homogeneous(T1, "T1")
    if (n is None) == (precision is None):
        raise ConfigurationError(
            "ctraj needs exactly one of n (number of samples) and precision "
            f"(spacing in metres), got n={n!r} and precision={precision!r}."
        )
    translation = end[:3, 3] - start[:3, 3]
    if precision is not None:
        precision = as_float(precision)
        if not np.isfinite(precision) or precision <= 0.0:
            raise ConfigurationError(
                f"precision must be a positive distance in metres, got {precision!r}."
            )
        distance = float(np.linalg.norm(translation))
        n = max(2, math.ceil(QUINTIC_PEAK_RATE * distance / precision) + 1)
    n = check_nb_samples(n)
    timing = jtraj(0.0, 1.0, n)
    fraction = np.array(timing.q[:, 0])
    rotation0 = start[:3, :3]
    axis_angle = log3(rotation0.T @ end[:3, :3])
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, :3] = rotation0 @ exp3(fraction[:, None] * axis_angle)
    poses[:, :3, 3] = start[:3, 3] + fraction[:, None] * translation
    poses[0], poses[-1] = start, end
    s = np.array(timing.s)
    for array in (poses, s, fraction):
        array.setflags(write=False)
    return CartesianTrajectory(poses=poses, s=s, path_fraction=fraction)


def ctraj_swing(
    phi: float, phi_b: float, phi_e: float, step_duration: float
) -> tuple[float, float, float, float]:
    """Paper A's lift-then-lower swing profile at the step phase ``phi`` (single support
    from ``phi_b`` to ``phi_e`` of a step of ``step_duration`` [s]): the fraction of the
    step ``h`` and of the height ``v`` with their time derivatives [1/s], each half on the
    quintic law of :func:`ctraj` (the foot lifted to an apex, then lowered)."""
    span = (phi_e - phi_b) * step_duration  # single support [s]
    s = min(max((phi - phi_b) / (phi_e - phi_b), 0.0), 1.0)
    half = 2.0 * s if s < 0.5 else 2.0 * s - 1.0
    r = half**3 * (10.0 - 15.0 * half + 6.0 * half**2)
    dr = 30.0 * half**2 * (1.0 - half) ** 2 * (2.0 / span)  # d r / d t
    if s < 0.5:  # lift: pose -> apex
        return 0.5 * r, 0.5 * dr, r, dr
    return 0.5 + 0.5 * r, 0.5 * dr, 1.0 - r, -dr  # lower: apex -> landing
