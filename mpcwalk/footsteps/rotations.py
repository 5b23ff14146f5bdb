"""Rotations of a footstep's sole: yaw-pitch-roll angles, matrices and quaternions.

A sole's orientation is ``R = Rz(yaw) Ry(pitch) Rx(roll)`` (Z-Y-X intrinsic angles): the
heading first, then the pitch about the turned y axis (toes down for a positive pitch), then
the roll about the sole's own x axis. The yaw is the heading of the sole's x axis projected
on the horizontal plane, so every planar helper of a footstep keeps its meaning on a tilted
sole. Quaternions are ``(w, x, y, z)``, scalar first, as in paper A's path files.

A flat orientation (roll and pitch exactly 0) takes exact yaw-only formulas: a flat
footstep's matrix and quaternion hold no rounded product and no negative zero.
"""

import math

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.terrain.surface import sole_tilt

#: Largest roll or pitch of a footstep, in [rad] (45 deg): steeper is a wall, not a foothold.
MAX_FOOTSTEP_TILT = math.radians(45.0)


def yaw_matrix(yaw: float) -> np.ndarray:
    """Rotation of ``yaw`` [rad] about the world z axis, shape (3, 3)."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)``, shape (3, 3); angles in [rad]."""
    if roll == 0.0 and pitch == 0.0:
        return yaw_matrix(yaw)
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_rpy(rotation) -> tuple[float, float, float]:
    """``(roll, pitch, yaw)`` [rad] of a rotation matrix (3, 3), inverse of :func:`rpy_matrix`
    for ``|pitch| < pi/2``."""
    R = np.asarray(rotation, dtype=float)
    roll = math.atan2(R[2, 1], R[2, 2]) + 0.0  # + 0.0: no negative zero
    pitch = math.atan2(-R[2, 0], math.hypot(R[2, 1], R[2, 2])) + 0.0
    yaw = math.atan2(R[1, 0], R[0, 0])
    return roll, pitch, yaw


def rpy_quaternion(roll: float, pitch: float, yaw: float) -> tuple[float, float, float, float]:
    """Unit quaternion ``(w, x, y, z)`` of ``Rz(yaw) Ry(pitch) Rx(roll)``; angles in [rad]."""
    cy, sy = math.cos(0.5 * yaw), math.sin(0.5 * yaw)
    if roll == 0.0 and pitch == 0.0:
        return (cy, 0.0, 0.0, sy)
    cr, sr = math.cos(0.5 * roll), math.sin(0.5 * roll)
    cp, sp = math.cos(0.5 * pitch), math.sin(0.5 * pitch)
    return (
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    )


def quaternion_rpy(w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    """``(roll, pitch, yaw)`` [rad] of a unit quaternion ``(w, x, y, z)`` (normalise it
    first); inverse of :func:`rpy_quaternion` for ``|pitch| < pi/2``. A quaternion about the
    vertical alone (``x = y = 0``) gives a roll and a pitch of exactly 0."""
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    if x == 0.0 and y == 0.0:
        return 0.0, 0.0, yaw
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y)) + 0.0
    sin_pitch = 2.0 * (w * y - z * x)
    pitch = math.atan2(sin_pitch, math.sqrt(max(0.0, 1.0 - sin_pitch * sin_pitch))) + 0.0
    return roll, pitch, yaw


def unit_quaternion(quaternion) -> np.ndarray:
    """``quaternion`` (w, x, y, z) divided by its norm, shape (4,).

    Raises:
        ConfigurationError: Not 4 finite numbers, or a zero quaternion.
    """
    q = np.asarray(quaternion, dtype=float).ravel()
    if q.shape != (4,) or not np.all(np.isfinite(q)):
        raise ConfigurationError(
            f"A quaternion must be 4 finite numbers (w, x, y, z), got {quaternion!r}."
        )
    norm = float(np.linalg.norm(q))
    if norm < 1e-9:
        raise ConfigurationError(
            f"A quaternion must not be zero (norm {norm:g}); the identity is (1, 0, 0, 0)."
        )
    return q / norm


def tilt_in_heading(roll: float, pitch: float, yaw: float) -> tuple[float, float]:
    """Roll and pitch [rad] that put a sole of heading ``yaw`` on a plane of world roll and
    pitch ``(roll, pitch)`` [rad] (the plane's normal is ``Ry(pitch) Rx(roll) e_z``).

    A sole of yaw 0 takes the plane's angles; a turned sole the same plane's tilt about its
    own axes, so that its z axis is the plane's normal (the terrain's
    :func:`~mpcwalk.terrain.surface.sole_tilt` of that normal)."""
    if roll == 0.0 and pitch == 0.0:
        return 0.0, 0.0
    foot_roll, foot_pitch = sole_tilt(rpy_matrix(roll, pitch, 0.0)[:, 2], yaw)
    return foot_roll + 0.0, foot_pitch + 0.0
