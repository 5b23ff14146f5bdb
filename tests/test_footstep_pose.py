"""A footstep's full 3D pose: roll and pitch, rotation matrix, quaternion, normal, and the
support polygon of a tilted sole."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import FootGeometry, Footstep, FootstepPlan, Side
from mpcwalk.footsteps.rotations import quaternion_rpy, rpy_quaternion, tilt_in_heading
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.support_polygons import pose_key

rng = np.random.default_rng(7)
POSES = [
    (float(rng.uniform(-math.pi, math.pi)), *(float(a) for a in rng.uniform(-0.7, 0.7, 2)))
    for _ in range(40)
]


@pytest.mark.parametrize("yaw, roll, pitch", POSES[:10])
def test_rotation_matrix_is_yaw_pitch_roll_and_orthonormal(yaw, roll, pitch):
    foot = Footstep(Side.LEFT, [0.1, 0.2, 0.3], yaw, roll, pitch)
    R = foot.rotation_matrix
    expected = Rotation.from_euler("ZYX", [yaw, pitch, roll]).as_matrix()  # intrinsic Z-Y-X
    np.testing.assert_allclose(R, expected, atol=1e-15)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_array_equal(foot.normal, R[:, 2])
    assert np.linalg.norm(foot.normal) == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_array_equal(foot.transform[:3, :3], R)
    np.testing.assert_array_equal(foot.transform[:3, 3], foot.position)
    # the yaw is the heading of the sole's x axis on the horizontal plane
    assert math.atan2(R[1, 0], R[0, 0]) == pytest.approx(yaw, abs=1e-14)


def test_quaternion_and_rotation_matrix_round_trips():
    for yaw, roll, pitch in POSES:
        foot = Footstep(Side.RIGHT, [1.0, -2.0, 0.5], yaw, roll, pitch)
        x, y, z, w = Rotation.from_matrix(foot.rotation_matrix).as_quat()  # scipy: scalar last
        q = foot.quaternion
        assert abs(float(np.dot(q, [w, x, y, z]))) == pytest.approx(1.0, abs=1e-14)
        for back in (
            Footstep.from_quaternion(Side.RIGHT, foot.position, 3.0 * q),  # any norm
            Footstep.from_quaternion(Side.RIGHT, foot.position, -q),  # the same rotation
            Footstep.from_pose(Side.RIGHT, foot.position, foot.rotation_matrix),
        ):
            assert back.roll == pytest.approx(roll, abs=1e-14)
            assert back.pitch == pytest.approx(pitch, abs=1e-14)
            assert back.yaw == pytest.approx(yaw, abs=1e-14)
            np.testing.assert_array_equal(back.position, foot.position)
        assert quaternion_rpy(*rpy_quaternion(roll, pitch, yaw)) == pytest.approx(
            (roll, pitch, yaw), abs=1e-14
        )


def test_a_flat_footstep_is_exactly_its_yaw():
    foot = Footstep(Side.LEFT, [0.3, 0.1], 0.4)
    assert foot.roll == 0.0 and foot.pitch == 0.0 and foot.is_flat
    c, s = math.cos(0.4), math.sin(0.4)
    expected = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    assert foot.rotation_matrix.tobytes() == expected.tobytes()  # no negative zero
    assert tuple(foot.quaternion) == (math.cos(0.2), 0.0, 0.0, math.sin(0.2))
    assert tuple(foot.normal) == (0.0, 0.0, 1.0)
    back = Footstep.from_quaternion(Side.LEFT, foot.position, foot.quaternion)
    assert back.is_flat and back.yaw == pytest.approx(0.4, abs=1e-15)
    assert not Footstep(Side.LEFT, [0, 0], 0.4, pitch=1e-9).is_flat


def test_moved_keeps_or_takes_roll_and_pitch_and_2d_helpers_use_the_heading():
    foot = Footstep(Side.LEFT, [1.0, 2.0, 0.2], math.pi / 2, 0.1, -0.15)
    moved = foot.moved(position=[1.5, 2.0, 0.2], yaw=0.3)
    assert (moved.roll, moved.pitch, moved.yaw) == (0.1, -0.15, 0.3)
    assert foot.moved(roll=0.0, pitch=0.0).is_flat
    np.testing.assert_allclose(foot.to_local([1.0, 3.0]), [1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(foot.to_world([1.0, 0.0]), [1.0, 3.0], atol=1e-15)
    np.testing.assert_allclose(foot.rotation, [[0.0, -1.0], [1.0, 0.0]], atol=1e-16)


def test_tilt_bounds_and_bad_angles_are_named_errors():
    with pytest.raises(
        ConfigurationError, match=r"pitch must lie within \+-45 deg .*\(50\.00 deg\)"
    ):
        Footstep(Side.LEFT, [0, 0], 0.0, 0.0, math.radians(50.0))
    with pytest.raises(ConfigurationError, match=r"roll must be a finite angle"):
        Footstep(Side.LEFT, [0, 0], 0.0, float("nan"))
    with pytest.raises(ConfigurationError, match=r"roll must be a finite angle"):
        Footstep(Side.LEFT, [0, 0], 0.0, "0.1")
    Footstep(Side.LEFT, [0, 0], 0.0, math.radians(45.0), -math.radians(45.0))  # the bound
    with pytest.raises(ConfigurationError, match="must not be zero"):
        Footstep.from_quaternion(Side.LEFT, [0, 0], [0, 0, 0, 0])
    with pytest.raises(ConfigurationError, match="3x3 rotation matrix"):
        Footstep.from_pose(Side.LEFT, [0, 0], np.diag([1.0, 1.0, -1.0]))


@pytest.mark.parametrize("yaw", [0.0, 0.7, -2.5])
def test_on_ground_puts_the_sole_on_the_plane(yaw):
    ground_roll, ground_pitch = 0.12, -0.2
    normal = Rotation.from_euler("ZYX", [0.0, ground_pitch, ground_roll]).as_matrix()[:, 2]
    foot = Footstep(Side.RIGHT, [0.4, -0.1, 0.0], yaw).on_ground(0.05, ground_roll, ground_pitch)
    np.testing.assert_allclose(foot.normal, normal, atol=1e-15)
    assert foot.yaw == yaw and foot.position[2] == 0.05
    if yaw == 0.0:
        assert (foot.roll, foot.pitch) == pytest.approx((ground_roll, ground_pitch), abs=1e-15)
    assert tilt_in_heading(0.0, 0.0, yaw) == (0.0, 0.0)
    assert Footstep(Side.RIGHT, [0, 0], yaw, 0.1, 0.1).on_height_map(None).roll == 0.1


def test_schedule_polygons_are_the_horizontal_projection_of_tilted_soles():
    geometry = FootGeometry(length=0.2, width=0.1)
    left = Footstep(Side.LEFT, [0.0, 0.1, 0.0])
    right = Footstep(Side.RIGHT, [0.0, -0.1, 0.0])
    pitched = right.moved(position=[0.3, -0.1, 0.1], pitch=math.radians(30.0))
    flat_step = right.moved(position=[0.3, -0.1, 0.1])
    tilted = ContactSchedule(FootstepPlan(left, right, (pitched,)), geometry)
    flat = ContactSchedule(FootstepPlan(left, right, (flat_step,)), geometry, reuse=tilted)
    rect = tilted._rects[1][Side.RIGHT]
    extent = np.ptp(rect.vertices, axis=0)
    assert extent == pytest.approx([0.2 * math.cos(math.radians(30.0)), 0.1], abs=1e-15)
    # the flat landing at the same (x, y, yaw) is not served the tilted polygon from the cache
    np.testing.assert_allclose(np.ptp(flat._rects[1][Side.RIGHT].vertices, axis=0), [0.2, 0.1])
    assert pose_key(flat_step) != pose_key(pitched)
    final = flat.phases[-1].polygon.vertices
    assert np.ptp(final[:, 0]) == pytest.approx(0.3 + 0.2, abs=1e-15)
    assert np.ptp(tilted.phases[-1].polygon.vertices[:, 0]) < 0.3 + 0.2 - 0.01
    # the height does not change the polygon: the same key
    assert pose_key(pitched) == pose_key(pitched.moved(position=[0.3, -0.1, 0.0]))


@pytest.mark.parametrize("position", [[0.4, -0.1], (0.4, -0.1, 0.05), np.array([0.4, -0.1, 0.05])])
def test_a_footstep_moved_to_a_new_position_only_equals_one_built_anew(position):
    """Moving only the position (the footstep MPC's publications) skips the angles' checks
    but not the position's: the same fields as a footstep built anew, read-only position."""
    foot = Footstep(Side.RIGHT, [0.1, 0.2, 0.3], 0.4, 0.05, -0.1)
    moved = foot.moved(position=position)
    built = Footstep(Side.RIGHT, position, 0.4, 0.05, -0.1)
    assert moved.side is built.side and np.array_equal(moved.position, built.position)
    assert (moved.yaw, moved.roll, moved.pitch) == (built.yaw, built.roll, built.pitch)
    assert moved.quaternion.tolist() == built.quaternion.tolist()
    assert not moved.position.flags.writeable and moved.position.shape == (3,)
    assert type(moved.yaw) is float and moved.side is Side.RIGHT
    with pytest.raises(ConfigurationError, match="2 or 3 finite numbers"):
        foot.moved(position=[np.nan, 0.0])
    with pytest.raises(ConfigurationError, match="2 or 3 finite numbers"):
        foot.moved(position=[0.0, 0.0, 0.0, 1.0])
