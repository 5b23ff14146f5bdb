"""The terrain: its features laid along the heading, its queries, its file and its fit."""

import math

import numpy as np
import pytest

from mpcwalk.exceptions import TerrainError
from mpcwalk.terrain import (
    Platform,
    RoughPatch,
    Slope,
    Stairs,
    SteppingStones,
    Terrain,
    TerrainReach,
    check_terrain,
    read_terrain,
    sole_tilt,
    terrain_to_toml,
)

ISSUE_FILE = """
[[stairs]]
start = 0.6     # [m] to the first riser
rise = 0.15     # [m] per step; negative goes down
run = 0.30      # [m] tread depth
count = 5
[[stairs]]
start = 2.4
rise = -0.15
run = 0.30
count = 5
[[slope]]
start = 4.5
length = 1.5
angle = 10.0    # [deg] up; negative down
"""


@pytest.fixture
def issue_terrain(tmp_path):
    path = tmp_path / "terrain.toml"
    path.write_text(ISSUE_FILE)
    return read_terrain(path)


def test_the_issue_file_gives_stairs_up_a_landing_stairs_down_and_a_ramp(issue_terrain):
    t = issue_terrain
    # up: 5 risers 0.30 m apart from 0.6 m, 0.15 m each
    assert t.height(0.55) == 0.0
    for k in range(5):
        assert t.height(0.6 + k * 0.3 + 0.15) == pytest.approx(0.15 * (k + 1))
    assert t.height(2.3) == pytest.approx(0.75)  # the landing
    for k in range(5):
        assert t.height(2.4 + k * 0.3 + 0.15) == pytest.approx(0.75 - 0.15 * (k + 1))
    assert t.height(4.4) == pytest.approx(0.0)
    top = 1.5 * math.tan(math.radians(10.0))
    assert t.height(5.25) == pytest.approx(0.5 * top)
    assert t.height(6.5) == pytest.approx(top)
    assert t.level_after == pytest.approx(top)
    np.testing.assert_allclose(
        t.normal(5.0, 0.0), [-math.sin(math.radians(10)), 0, math.cos(math.radians(10))]
    )
    assert t.floor == 0.0


def test_a_terrain_file_round_trips(issue_terrain, tmp_path):
    path = tmp_path / "again.toml"
    path.write_text(terrain_to_toml(issue_terrain))
    assert read_terrain(path) == issue_terrain


def test_sole_support_on_a_tread_and_over_its_edge(issue_terrain):
    on = issue_terrain.sole_support((0.75, 0.1), 0.0, 0.2, 0.1)
    assert on.height == pytest.approx(0.15)
    assert on.margin == pytest.approx(0.05)  # 0.15 m tread half minus 0.10 m sole half
    over = issue_terrain.sole_support((0.63, 0.1), 0.0, 0.2, 0.1)
    assert over.height == pytest.approx(0.15)  # resting on the higher tread's nose
    assert over.margin == pytest.approx(-0.07)


def test_a_sole_on_a_ramp_takes_its_pitch_and_keeps_its_yaw(issue_terrain):
    support = issue_terrain.sole_support((5.0, 0.0), 0.0, 0.2, 0.1)
    assert support.pitch == pytest.approx(-math.radians(10.0))
    assert support.roll == pytest.approx(0.0)
    roll, pitch = sole_tilt(issue_terrain.normal(5.0, 0.0), 0.5)
    c, s = math.cos(0.5), math.sin(0.5)
    Rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    Ry = np.array(
        [[math.cos(pitch), 0, math.sin(pitch)], [0, 1, 0], [-math.sin(pitch), 0, math.cos(pitch)]]
    )
    Rx = np.array(
        [[1, 0, 0], [0, math.cos(roll), -math.sin(roll)], [0, math.sin(roll), math.cos(roll)]]
    )
    R = Rz @ Ry @ Rx
    np.testing.assert_allclose(R[:, 2], issue_terrain.normal(5.0, 0.0), atol=1e-12)
    assert math.atan2(R[1, 0], R[0, 0]) == pytest.approx(0.5)


def test_stones_stand_over_a_pit_that_lowers_the_floor():
    t = Terrain([SteppingStones(start=0.5, count=3, length=0.2, gap=0.1, depth=0.3)])
    assert t.height(0.6, 0.0) == 0.0  # a stone
    assert t.height(0.75, 0.0) == pytest.approx(-0.3)  # a gap
    assert t.height(0.6, 1.0) == pytest.approx(-0.3)  # beside the stones
    assert t.floor == pytest.approx(-0.3)
    assert t.height(2.0, 0.0) == 0.0  # the level goes on after them
    # every top above the floor is a box, the start's ground among them
    assert len(t.boxes()) == len([s for s in t.surfaces if s.top > t.floor])


def test_rough_blocks_are_known_and_the_same_for_the_same_seed():
    a = Terrain([RoughPatch(start=0.3, length=0.5, width=0.4, block=0.1, height=0.02, seed=3)])
    b = Terrain([RoughPatch(start=0.3, length=0.5, width=0.4, block=0.1, height=0.02, seed=3)])
    xs = np.linspace(0.3, 0.8, 23)
    np.testing.assert_array_equal(a.profile(xs), b.profile(xs))
    heights = a.profile(xs)
    assert heights.max() <= 0.02 and heights.max() > 0.0


def test_highest_along_sees_the_nose_of_a_step(issue_terrain):
    heights = issue_terrain.highest_along((0.45, 0.05), (0.75, 0.05), 0.03)
    assert heights[0] == 0.0 and heights.max() == pytest.approx(0.15)


def test_a_box_top_is_the_surface(issue_terrain):
    ramp = next(s for s in issue_terrain.surfaces if s.kind == "ramp")
    box = ramp.box(issue_terrain.floor)
    # the middle of the box's top face lies on the ramp
    R = np.array(
        [
            [math.cos(box.pitch), 0, math.sin(box.pitch)],
            [0, 1, 0],
            [-math.sin(box.pitch), 0, math.cos(box.pitch)],
        ]
    )
    top = np.array(box.center) + R @ np.array([0.0, 0.0, box.half_size[2]])
    assert top[2] == pytest.approx(issue_terrain.height(top[0], top[1]))


@pytest.mark.parametrize(
    "table, message",
    [
        ("[[stairs]]\nstart = 0.6\nrise = 0.0\n", "must not be 0"),
        ("[[stairz]]\nstart = 0.6\n", "unknown table [[stairz]]"),
        ("[[stairs]]\nstart = 0.6\nriser = 0.1\n", "unknown field(s) riser"),
        ("[[slope]]\nlength = 1.0\n", "needs 'start'"),
        ("[[slope]]\nstart = 0.5\nangle = 45.0\n", "Slope.angle"),
        ("[[stairs]]\nstart = 0.6\n[[slope]]\nstart = 1.0\n", "overlap"),
        ("[[stairs\n", "not valid TOML"),
    ],
)
def test_a_bad_terrain_file_is_named(tmp_path, table, message):
    path = tmp_path / "bad.toml"
    path.write_text(table)
    with pytest.raises(TerrainError, match=__import__("re").escape(message)):
        read_terrain(path)


def test_a_terrain_that_does_not_fit_is_refused_with_its_limit():
    reach = TerrainReach(sole_length=0.1, sole_width=0.06, leg_length=0.2, max_stride=0.16)
    check_terrain(Terrain([Stairs(0.5, rise=0.1, run=0.15, count=3)]), reach)
    with pytest.raises(TerrainError, match=r"beyond the 10\.0 cm its legs reach"):
        check_terrain(Terrain([Stairs(0.5, rise=0.12, run=0.15, count=3)]), reach)
    with pytest.raises(TerrainError, match=r"shorter than its sole with margins .* 12\.0 cm"):
        check_terrain(Terrain([Stairs(0.5, rise=0.05, run=0.11, count=3)]), reach)
    with pytest.raises(TerrainError, match="steeper than the 20 deg"):
        check_terrain(Terrain([Slope(0.5, length=1.0, angle=25.0)]), reach)
    with pytest.raises(TerrainError, match="needs a stride of"):
        check_terrain(Terrain([SteppingStones(0.5, count=3, length=0.15, gap=0.1)]), reach)
    check_terrain(Terrain([Platform(0.5, length=0.3, height=0.05)]), reach)


def test_a_sole_straddles_a_gentle_ramp_s_foot_and_brow():
    """Over a 4 deg ramp's foot (a hollow) the sole rests on both tops, on the chord from
    its heel to its toe; over its brow (a crest) on the top under its centre. Its margin
    counts the two tops as one; a kink beyond ``max_kink`` is not straddled."""
    terrain = Terrain([Slope(0.5, 1.0, 4.0)])
    kink, rise = math.radians(5.0), math.tan(math.radians(4.0))
    floor, ramp, top = 0, 1, 2
    assert terrain.joined(floor, ramp, kink) and terrain.joined(ramp, top, kink)
    assert not terrain.joined(floor, ramp, math.radians(3.0))
    assert not terrain.joined(floor, top, kink)  # not end to end
    on_ramp = terrain.sole_support((1.0, 0.0), 0.0, 0.2, 0.1)
    hollow = terrain.sole_support((0.5, 0.0), 0.0, 0.2, 0.1, max_kink=kink)
    # heel at 0.4 on the floor, toe at 0.6 on the ramp 0.1 tan(4 deg) up: the chord
    assert hollow.height == pytest.approx(0.5 * 0.1 * rise, abs=1e-12)
    chord = math.atan(0.1 * rise / 0.2)
    assert hollow.pitch == pytest.approx(chord * on_ramp.pitch / math.radians(4.0), abs=1e-12)
    assert hollow.margin > 0.04  # the two tops as one: 0.05 m to the sides
    assert terrain.sole_support((0.5, 0.0), 0.0, 0.2, 0.1).margin < 0.0
    height = 1.0 * rise
    before = terrain.sole_support((1.45, 0.0), 0.0, 0.2, 0.1, max_kink=kink)
    assert before.height == pytest.approx(height - 0.05 * rise, abs=1e-12)
    assert before.pitch == pytest.approx(on_ramp.pitch, abs=1e-12)  # on the ramp
    after = terrain.sole_support((1.55, 0.0), 0.0, 0.2, 0.1, max_kink=kink)
    assert after.height == pytest.approx(height, abs=1e-12) and after.pitch == 0.0  # on the top
    steep = Terrain([Slope(0.5, 1.0, 8.0)])
    assert steep.sole_support((0.5, 0.0), 0.0, 0.2, 0.1, max_kink=kink).margin < 0.0
