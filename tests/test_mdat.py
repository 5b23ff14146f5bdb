"""Paper A's footstep path files (.mdat) and plans built from them."""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mpcwalk.exceptions import ConfigurationError, FootstepFileError
from mpcwalk.footsteps.footstep import Footstep, Side, wrap_angle
from mpcwalk.footsteps.mdat import (
    MDAT_FIELDS,
    PathWaypoint,
    parse_mdat,
    path_targets,
    plan_from_path,
    quaternion_to_yaw,
    read_mdat,
    write_mdat,
    yaw_to_quaternion,
)
from mpcwalk.footsteps.reachability import ATLAS_REACHABILITY

PAPER_A = Path(__file__).resolve().parent.parent / "mpcwalk" / "experiments" / "paper_a" / "paths"
GOOD_LINE = "0 0.12 0 1 0 0 0 0 -0.12 0 1 0 0 0"


def waypoint(xl, yl, yawl, xr, yr, yawr):
    return PathWaypoint(
        Footstep(Side.LEFT, [xl, yl, 0.0], yawl), Footstep(Side.RIGHT, [xr, yr, 0.0], yawr)
    )


def test_parse_comments_blank_lines_commas_and_quaternions():
    q = yaw_to_quaternion(-math.pi / 2)
    text = (
        f"# a path\n\n{GOOD_LINE}   # initial stance\n"
        f"0.1, 0.12, 0.0, {q[0]!r}, 0, 0, {q[3]!r}, 0, -0.12, 0, 1, 0, 0, 0\n"
    )
    waypoints = parse_mdat(text)
    assert [w.line for w in waypoints] == [3, 4]
    np.testing.assert_array_equal(waypoints[1].left.position, [0.1, 0.12, 0.0])
    assert waypoints[1].left.yaw == pytest.approx(-math.pi / 2, abs=1e-15)
    assert waypoints[1].right.yaw == 0.0


def test_quaternion_to_yaw_matches_scipy():
    rng = np.random.default_rng(0)
    for _ in range(50):
        yaw, roll, pitch = rng.uniform(-math.pi, math.pi), *rng.uniform(-0.05, 0.05, 2)
        rotation = Rotation.from_euler("ZYX", [yaw, pitch, roll])
        x, y, z, w = rotation.as_quat()  # scipy: scalar last
        expected = rotation.as_euler("ZYX")[0]
        assert float(wrap_angle(quaternion_to_yaw(w, x, y, z) - expected)) == pytest.approx(
            0.0, abs=1e-12
        )


def test_write_read_round_trip_is_exact(tmp_path):
    rng = np.random.default_rng(1)
    waypoints = [
        PathWaypoint(
            Footstep(Side.LEFT, rng.uniform(-5, 5, 3), rng.uniform(-math.pi, math.pi)),
            Footstep(Side.RIGHT, rng.uniform(-5, 5, 3), rng.uniform(-math.pi, math.pi)),
        )
        for _ in range(30)
    ]
    path = tmp_path / "random.mdat"
    write_mdat(path, waypoints, header="random waypoints\nsecond line")
    assert path.read_text().startswith("# random waypoints\n# second line\n# xlf ylf")
    for source in (path, str(path), path.read_text()):
        back = read_mdat(source)
        assert len(back) == len(waypoints)
        for a, b in zip(waypoints, back):
            for side in Side:
                np.testing.assert_allclose(
                    b.foot(side).position, a.foot(side).position, rtol=0, atol=1e-12
                )
                assert float(wrap_angle(b.foot(side).yaw - a.foot(side).yaw)) == pytest.approx(
                    0.0, abs=1e-12
                )


@pytest.mark.parametrize(
    "line, field, pattern",
    [
        (
            GOOD_LINE.rsplit(" ", 1)[0],
            "qzrf",
            r"expected 14 numbers \(xlf ylf zlf .* qzrf\), got 13",
        ),
        (GOOD_LINE + " 0", None, r"expected 14 numbers .*, got 15"),
        (
            GOOD_LINE.replace(" 1 0 0 0", " one 0 0 0", 2).replace("one", "1", 1),
            "qwrf",
            r"'one' is not a number",
        ),
        (GOOD_LINE.replace("0.12", "nan", 1), "ylf", r"'nan' is not a finite number"),
        (GOOD_LINE.replace("-0.12", "-inf"), "yrf", r"'-inf' is not a finite number"),
        (
            GOOD_LINE.replace(" 1 0 0 0", " 1.2 0 0 0", 1),
            "qwlf",
            r"norm 1\.2, but a unit quaternion is expected",
        ),
    ],
)
def test_malformed_lines_name_file_line_and_field(line, field, pattern):
    text = f"# header\n{GOOD_LINE}\n{line}\n"
    with pytest.raises(FootstepFileError, match=pattern) as info:
        parse_mdat(text, source="walk.mdat")
    assert info.value.line == 3 and info.value.field == field and info.value.path == "walk.mdat"
    assert str(info.value).startswith("walk.mdat:3")


def test_tilted_foot_is_read_and_a_steep_one_refused():
    c, s = math.cos(math.radians(5.0)), math.sin(math.radians(5.0))  # 10 deg about x
    line = GOOD_LINE.replace(" 1 0 0 0", f" {c!r} {s!r} 0 0", 1)
    left, right = parse_mdat(line)[0].left, parse_mdat(line)[0].right
    assert left.roll == pytest.approx(math.radians(10.0), abs=1e-12) and left.pitch == 0.0
    assert right.is_flat and right.yaw == 0.0 and not left.is_flat
    c, s = math.cos(math.radians(25.0)), math.sin(math.radians(25.0))  # 50 deg about y
    steep = GOOD_LINE.replace(" 1 0 0 0", f" {c!r} 0 {s!r} 0", 1)
    with pytest.raises(
        FootstepFileError, match=r"pitch of 50\.00 deg, beyond the \+-45 deg"
    ) as info:
        parse_mdat(steep)
    assert info.value.field == "qylf" and info.value.line == 1


def test_empty_and_missing_files(tmp_path):
    empty = tmp_path / "empty.mdat"
    empty.write_text("# nothing here\n\n")
    with pytest.raises(FootstepFileError, match=r"empty\.mdat: no waypoint found"):
        read_mdat(empty)
    with pytest.raises(FootstepFileError, match=r"missing\.mdat: cannot read"):
        read_mdat(str(tmp_path / "missing.mdat"))
    assert MDAT_FIELDS[10] == "qwrf"


def test_path_targets_alternate_and_skip_unchanged_waypoints():
    waypoints = [
        waypoint(0, 0.12, 0, 0, -0.12, 0),
        waypoint(0, 0.12, 0, 0, -0.12, 0),  # unchanged: skipped
        waypoint(0, 0.12, 0, 0.2, -0.12, 0),  # right moves
        waypoint(0.4, 0.12, 0, 0.2, -0.12, 0),  # left moves
        waypoint(0.4, 0.12, 0, 0.6, -0.12, 0),  # right
        waypoint(0.8, 0.12, 0, 0.8, -0.12, 0),  # both: left first (right moved last)
        waypoint(0.8, 0.12, 0, 1.0, -0.12, 0),  # right again: left steps in place first
    ]
    targets = path_targets(waypoints)
    sides = [t.footstep.side for t in targets]
    assert sides == [
        Side.RIGHT,
        Side.LEFT,
        Side.RIGHT,
        Side.LEFT,
        Side.RIGHT,
        Side.LEFT,
        Side.RIGHT,
    ]
    assert [t.waypoint_index for t in targets] == [2, 3, 4, 5, 5, 6, 6]
    np.testing.assert_allclose(targets[5].footstep.xy, [0.8, 0.12])  # in place
    with_in_place = path_targets(waypoints, steps_in_place=True)
    assert (
        len(with_in_place) == 8 and with_in_place[0].footstep.side is Side.LEFT
    )  # keeps alternation
    forced = path_targets(waypoints, first_swing="left")
    assert forced[0].footstep.side is Side.LEFT and forced[1].footstep.side is Side.RIGHT


def test_both_feet_moving_first_follow_the_turn():
    turn_right = [waypoint(0, 0.12, 0, 0, -0.12, 0), waypoint(0, 0.12, -0.3, 0, -0.12, -0.3)]
    assert path_targets(turn_right)[0].footstep.side is Side.RIGHT
    step_left = [waypoint(0, 0.12, 0, 0, -0.12, 0), waypoint(0, 0.32, 0, 0, 0.08, 0)]
    assert path_targets(step_left)[0].footstep.side is Side.LEFT


def shipped_plan(name, **options):
    waypoints = read_mdat(PAPER_A / f"{name}.mdat")
    targets = path_targets(waypoints, **options)
    plan = plan_from_path(waypoints, rectangle=ATLAS_REACHABILITY, **options)
    return waypoints, targets, plan


@pytest.mark.parametrize(
    "name, nb_steps, final_yaw", [("straight", 16, 0.0), ("turning", 11, 0.0), ("ramp", 16, 0.0)]
)
def test_shipped_paths_give_valid_unclamped_plans(name, nb_steps, final_yaw):
    from mpcwalk.gait.contact_schedule import ContactSchedule

    waypoints, targets, plan = shipped_plan(name)
    assert plan.nb_steps == nb_steps == len(targets)  # no step clamped, none inserted
    for step, target in zip(plan.steps, targets):
        assert step is target.footstep
    final = plan.stance(plan.nb_steps)
    for side in Side:
        np.testing.assert_allclose(
            final[side].position, waypoints[-1].foot(side).position, atol=1e-12
        )
        assert final[side].yaw == pytest.approx(final_yaw, abs=1e-12)
    assert ContactSchedule(plan).duration == pytest.approx(2.0 + 0.5 * nb_steps)
    # paper A: the first two steps are in place
    _, targets, plan = shipped_plan(name, steps_in_place=True)
    assert plan.nb_steps == nb_steps + 2
    for k in range(2):
        start = waypoints[0].foot(plan.steps[k].side)
        np.testing.assert_allclose(plan.steps[k].position, start.position, atol=1e-15)


def test_shipped_path_geometry():
    straight = read_mdat(PAPER_A / "straight.mdat")
    np.testing.assert_allclose(straight[0].left.xy - straight[0].right.xy, [0.0, 0.24])
    assert straight[-1].left.xy[0] == pytest.approx(3.0) and straight[-1].right.xy[
        0
    ] == pytest.approx(3.0)
    assert all(w.left.yaw == 0.0 and w.right.yaw == 0.0 for w in straight)
    turning = read_mdat(PAPER_A / "turning.mdat")
    np.testing.assert_allclose(
        0.5 * (turning[0].left.xy + turning[0].right.xy), [0.0, 0.0], atol=1e-12
    )
    assert turning[0].left.yaw == pytest.approx(-math.pi / 2, abs=1e-12)
    yaws = [w.left.yaw for w in turning]
    assert len(set(np.round(yaws, 9))) > 5  # orientation changes along the arc


def test_generator_reproduces_the_shipped_files(tmp_path, monkeypatch):
    from mpcwalk.experiments.paper_a import make_paths as module

    monkeypatch.setattr(module, "HERE", tmp_path)
    module.main()
    for name in ("straight", "turning", "ramp"):
        assert (tmp_path / f"{name}.mdat").read_text() == (PAPER_A / f"{name}.mdat").read_text()
    assert (tmp_path / "ramp.toml").read_text() == (PAPER_A / "ramp.toml").read_text()


def test_the_3d_path_rests_every_sole_on_its_ramp():
    """ramp.mdat is the straight path in 3D: every sole at the height of the ground under
    its centre in ramp.toml (to the file's micrometre) and pitched as that ground, heights
    and tilted quaternions in the file; up 7 cm and down again."""
    from mpcwalk.experiments.paper_a.make_paths import ATLAS_LEG, ATLAS_SOLE
    from mpcwalk.robot import load_robot
    from mpcwalk.terrain import TerrainReach, read_terrain

    terrain = read_terrain(PAPER_A / "ramp.toml")
    ramp, straight = read_mdat(PAPER_A / "ramp.mdat"), read_mdat(PAPER_A / "straight.mdat")
    assert len(ramp) == len(straight)
    reach = TerrainReach.for_leg(*ATLAS_SOLE, ATLAS_LEG)
    heights, pitches = [], []
    for waypoint in ramp:
        for side in Side:
            foot = waypoint.foot(side)
            support = terrain.sole_support(
                foot.xy, foot.yaw, *ATLAS_SOLE, samples=11, max_kink=reach.max_kink
            )
            assert foot.position[2] == pytest.approx(support.height, abs=1e-6)
            assert foot.pitch == pytest.approx(support.pitch, abs=1e-12)
            heights.append(foot.position[2])
            pitches.append(foot.pitch)
    assert max(heights) == pytest.approx(0.8 * math.tan(math.radians(5.0)), abs=1e-6)
    assert min(pitches) < -0.08 and max(pitches) > 0.08  # toes up, then toes down
    assert ramp[-1].left.position[2] == 0.0 == ramp[-1].right.position[2]
    robot = load_robot("atlas-like")  # the soles and the leg the path was placed for
    assert robot.sole_size == pytest.approx(ATLAS_SOLE)
    assert robot.leg_length == pytest.approx(ATLAS_LEG, abs=1e-3)


def test_bad_inputs():
    with pytest.raises(ConfigurationError, match="at least one waypoint"):
        path_targets([])
    with pytest.raises(ConfigurationError, match="file path or the file's text"):
        read_mdat(42)
