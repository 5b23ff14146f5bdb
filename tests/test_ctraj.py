"""Cartesian trajectories (paper A's ctraj)."""

import math

import numpy as np
import pinocchio as pin
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.ctraj import QUINTIC_PEAK_RATE, CartesianTrajectory, ctraj, exp3, log3


def pose(axis_angle, position):
    out = np.eye(4)
    out[:3, :3] = pin.exp3(np.asarray(axis_angle, dtype=float))
    out[:3, 3] = position
    return out


T0 = pose([0.1, -0.2, 0.3], [0.0, 0.1, -0.6])
T1 = pose([-0.5, 0.4, 1.2], [0.12, -0.05, -0.55])


def rotation_angle(R):
    return float(np.linalg.norm(pin.log3(R)))


def test_endpoints_are_exact_for_arrays_and_se3():
    for start, end in ((T0, T1), (pin.SE3(T0), pin.SE3(T1))):
        traj = ctraj(start, end, 9)
        assert isinstance(traj, CartesianTrajectory)
        assert traj.poses.shape == (9, 4, 4) and traj.nb_samples == 9
        np.testing.assert_array_equal(traj.poses[0], T0)
        np.testing.assert_array_equal(traj.poses[-1], T1)
        np.testing.assert_array_equal(traj.s, np.linspace(0.0, 1.0, 9))
        np.testing.assert_array_equal(traj.poses[:, 3], np.tile([0.0, 0.0, 0.0, 1.0], (9, 1)))


def test_rotations_stay_in_so3_and_positions_on_the_segment():
    traj = ctraj(T0, T1, 41)
    for R in traj.rotations:
        np.testing.assert_allclose(R.T @ R, np.eye(3), rtol=0.0, atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
    direction = T1[:3, 3] - T0[:3, 3]
    offsets = traj.positions - T0[:3, 3]
    np.testing.assert_allclose(np.cross(offsets, direction), 0.0, atol=1e-15)
    np.testing.assert_allclose(offsets, traj.path_fraction[:, None] * direction, atol=1e-15)
    assert np.all(np.diff(traj.path_fraction) > 0.0)


def test_midpoint_rotation_is_half_way_on_the_geodesic():
    traj = ctraj(T0, T1, 21)
    assert traj.path_fraction[10] == pytest.approx(0.5, abs=1e-15)
    R0, Rmid, R1 = traj.rotations[0], traj.rotations[10], traj.rotations[-1]
    total, half = pin.log3(R0.T @ R1), pin.log3(R0.T @ Rmid)
    np.testing.assert_allclose(half, 0.5 * total, atol=1e-12)  # same axis, half the angle
    assert rotation_angle(R0.T @ Rmid) == pytest.approx(0.5 * rotation_angle(R0.T @ R1), abs=1e-12)
    assert rotation_angle(Rmid.T @ R1) == pytest.approx(0.5 * rotation_angle(R0.T @ R1), abs=1e-12)
    # Quintic timing: the rotation angle grows as 10 r^3 - 15 r^4 + 6 r^5.
    s = traj.s
    law = 10 * s**3 - 15 * s**4 + 6 * s**5
    angles = [rotation_angle(R0.T @ R) for R in traj.rotations]
    np.testing.assert_allclose(angles, law * rotation_angle(R0.T @ R1), atol=1e-12)


@pytest.mark.parametrize(
    "start, end",
    [
        (T0, T1),
        (pose([0.0, 0.0, 3.0], [0.0, 0.0, 0.0]), pose([0.0, 0.0, -3.0], [0.1, 0.0, 0.0])),
        (pose([0.3, -2.0, 1.0], [1.0, 2.0, 3.0]), pose([-1.0, 2.5, 0.2], [0.0, 0.0, 0.0])),
    ],
)
def test_same_poses_as_pinocchio_interpolation(start, end):
    """The SO(3) log/exp of the gait layer (no Pinocchio there) give Pinocchio's geodesic:
    ``R0 exp3(r log3(R0^T R1))`` and the straight line, sample by sample."""
    traj = ctraj(start, end, 17)
    R0, axis_angle = start[:3, :3], pin.log3(start[:3, :3].T @ end[:3, :3])
    for T, r in zip(traj.poses, traj.path_fraction):
        np.testing.assert_allclose(T[:3, :3], R0 @ pin.exp3(r * axis_angle), atol=1e-12)
        position = start[:3, 3] + r * (end[:3, 3] - start[:3, 3])
        np.testing.assert_allclose(T[:3, 3], position, atol=1e-15)


def test_so3_log_and_exp_agree_with_pinocchio():
    """The numpy SO(3) maps of ctraj against Pinocchio's, at every angle up to pi and near
    zero (series)."""
    rng = np.random.default_rng(7)
    vectors = list(rng.normal(0.0, 1.0, (200, 3)))
    vectors += [np.array([0.0, 0.0, np.pi]), np.array([1e-7, 0.0, -2e-8]), np.zeros(3)]
    for w in vectors:
        angle = float(np.linalg.norm(w))
        if angle > np.pi:
            w = w * (np.pi - 1e-3) / angle
        R = pin.exp3(w)
        np.testing.assert_allclose(exp3(w), R, atol=1e-15)
        if abs(np.linalg.norm(w) - np.pi) > 1e-9:  # at pi, w and -w are the same rotation
            np.testing.assert_allclose(log3(R), pin.log3(R), atol=1e-10)
    np.testing.assert_allclose(
        exp3(np.array([[0.0, 0.0, 0.5], [0.2, 0.0, 0.0]]))[1],
        pin.exp3(np.array([0.2, 0.0, 0.0])),
        atol=1e-15,
    )
    np.testing.assert_allclose(np.abs(log3(pin.exp3(np.array([0.0, 0.0, np.pi])))), [0, 0, np.pi])


def test_large_rotation_takes_the_short_way():
    start = pose([0.0, 0.0, 3.0], [0.0, 0.0, 0.0])
    end = pose([0.0, 0.0, -3.0], [0.0, 0.0, 0.0])  # 0.283 rad away through pi
    traj = ctraj(start, end, 3)
    yaw_mid = math.atan2(traj.rotations[1][1, 0], traj.rotations[1][0, 0])
    assert abs(yaw_mid) == pytest.approx(np.pi, abs=1e-12)


@pytest.mark.parametrize("precision", [0.05, 0.01, 0.003])
def test_precision_bounds_consecutive_spacing(precision):
    distance = float(np.linalg.norm(T1[:3, 3] - T0[:3, 3]))
    traj = ctraj(T0, T1, precision=precision)
    assert traj.nb_samples == math.ceil(QUINTIC_PEAK_RATE * distance / precision) + 1
    spacing = np.linalg.norm(np.diff(traj.positions, axis=0), axis=1)
    assert spacing.max() <= precision * (1.0 + 1e-12)
    assert spacing.sum() == pytest.approx(distance, rel=1e-12)
    # One sample fewer would break the bound at the middle of the motion.
    coarser = ctraj(T0, T1, traj.nb_samples - 1) if traj.nb_samples > 2 else None
    if coarser is not None:
        assert np.linalg.norm(np.diff(coarser.positions, axis=0), axis=1).max() > 0.9 * precision


def test_pure_rotation_with_precision_has_two_samples():
    end = pose([0.0, 0.0, 0.5], T0[:3, 3])
    end[:3, :3] = T0[:3, :3] @ end[:3, :3]
    traj = ctraj(T0, end, precision=0.01)
    assert traj.nb_samples == 2
    np.testing.assert_array_equal(traj.poses[-1], end)


def test_results_are_read_only():
    traj = ctraj(T0, T1, 3)
    with pytest.raises(ValueError):
        traj.poses[0, 0, 0] = 2.0


def _bad_poses():
    reflection = np.diag([1.0, 1.0, -1.0, 1.0])
    sheared = np.eye(4)
    sheared[0, 1] = 0.1
    last_row = np.eye(4)
    last_row[3, 0] = 1.0
    return [np.eye(3), reflection, sheared, last_row, np.full((4, 4), np.nan), "identity"]


@pytest.mark.parametrize("bad", _bad_poses())
def test_non_se3_input_raises(bad):
    with pytest.raises(ConfigurationError, match="T1"):
        ctraj(T0, bad, 5)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({}, "exactly one of n"),
        ({"n": 5, "precision": 0.01}, "exactly one of n"),
        ({"precision": 0.0}, "positive distance"),
        ({"precision": -0.01}, "positive distance"),
        ({"precision": float("nan")}, "positive distance"),
        ({"n": 1}, "integer >= 2"),
    ],
)
def test_bad_sampling_raises(kwargs, message):
    with pytest.raises(ConfigurationError, match=message):
        ctraj(T0, T1, **kwargs)
