"""Paper A's path files with all 14 numbers: heights and tilted feet read and written back,
flat files read exactly as before."""

import hashlib
import math
from pathlib import Path

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side
from mpcwalk.footsteps.mdat import (
    PathWaypoint,
    parse_mdat,
    plan_from_path,
    quaternion_to_yaw,
    read_mdat,
    write_mdat,
)

PAPER_A = Path(__file__).resolve().parent.parent / "mpcwalk" / "experiments" / "paper_a" / "paths"


def _tilted_waypoints(count: int, seed: int = 3) -> list[PathWaypoint]:
    rng = np.random.default_rng(seed)

    def foot(side):
        yaw = rng.uniform(-math.pi, math.pi)
        roll, pitch = rng.uniform(-0.7, 0.7, 2)
        return Footstep(side, rng.uniform(-5, 5, 3), yaw, roll, pitch)

    return [PathWaypoint(foot(Side.LEFT), foot(Side.RIGHT)) for _ in range(count)]


def test_tilted_feet_and_heights_round_trip(tmp_path):
    waypoints = _tilted_waypoints(30)
    path = tmp_path / "stairs.mdat"
    write_mdat(path, waypoints)
    numbers = [line.split() for line in path.read_text().splitlines() if not line.startswith("#")]
    assert len(numbers) == 30 and all(len(row) == 14 for row in numbers)
    back = read_mdat(path)
    for a, b in zip(waypoints, back):
        for side in Side:
            fa, fb = a.foot(side), b.foot(side)
            np.testing.assert_array_equal(fb.position, fa.position)  # heights too, exactly
            assert (fb.roll, fb.pitch, fb.yaw) == pytest.approx(
                (fa.roll, fa.pitch, fa.yaw), abs=1e-9
            )
            np.testing.assert_allclose(fb.rotation_matrix, fa.rotation_matrix, atol=1e-9)


def test_a_quaternion_slightly_off_the_unit_norm_is_normalised():
    foot = Footstep(Side.LEFT, [0.2, 0.1, 0.15], 0.3, 0.1, -0.2)
    q = 1.0005 * foot.quaternion  # within the 1e-3 tolerance on the norm
    values = [*foot.position, *q, 0.2, -0.1, 0.0, 1.0, 0.0, 0.0, 0.0]
    read = parse_mdat(" ".join(repr(float(v)) for v in values))[0].left
    assert (read.roll, read.pitch, read.yaw) == pytest.approx((0.1, -0.2, 0.3), abs=1e-12)
    assert read.position[2] == 0.15


def test_a_plan_or_its_stances_are_written_and_walked_again(tmp_path):
    left = Footstep(Side.LEFT, [0.0, 0.12, 0.0])
    right = Footstep(Side.RIGHT, [0.0, -0.12, 0.0])
    tread = dict(pitch=math.radians(-10.0), roll=math.radians(3.0))
    steps = (
        right.moved(position=[0.2, -0.12, 0.05], **tread),
        left.moved(position=[0.4, 0.12, 0.1], **tread),
        right.moved(position=[0.4, -0.12, 0.1], **tread),
    )
    plan = FootstepPlan(left, right, steps)
    for source in (plan, plan.stances()):
        path = tmp_path / "plan.mdat"
        write_mdat(path, source)
        waypoints = read_mdat(path)
        assert len(waypoints) == plan.nb_steps + 1
        again = plan_from_path(waypoints)
        assert again.nb_steps == plan.nb_steps
        for a, b in zip(plan.steps, again.steps):
            assert a.side is b.side
            np.testing.assert_array_equal(b.position, a.position)
            assert (b.roll, b.pitch, b.yaw) == pytest.approx((a.roll, a.pitch, a.yaw), abs=1e-12)
    with pytest.raises(ConfigurationError, match=r"pass plan\.stances\(\) for a plan"):
        write_mdat(tmp_path / "bad.mdat", [left, right])


def test_a_pose_change_of_the_tilt_alone_is_a_step():
    flat = PathWaypoint(Footstep(Side.LEFT, [0, 0.12, 0]), Footstep(Side.RIGHT, [0, -0.12, 0]))
    tilted = PathWaypoint(flat.left, flat.right.moved(pitch=0.1))
    plan = plan_from_path([flat, tilted])
    assert plan.nb_steps == 1 and plan.steps[0].pitch == 0.1


#: The plans of the shipped flat files, as the yaw-only reader gave them (positions and yaws
#: to 1e-9, sha256 prefix).
FLAT_PLAN_DIGESTS = {"straight": "2515e9574bddc23d", "turning": "656b49a6fdf54682"}


@pytest.mark.parametrize("name", sorted(FLAT_PLAN_DIGESTS))
def test_flat_files_give_exactly_the_plans_of_the_yaw_only_reader(name):
    path = PAPER_A / f"{name}.mdat"
    plan = plan_from_path(read_mdat(path))
    feet = [plan.initial_left, plan.initial_right, *plan.steps]
    assert all(foot.roll == 0.0 and foot.pitch == 0.0 and foot.is_flat for foot in feet)
    text = "\n".join(
        f"{f.side.value} " + " ".join(f"{float(v):.9f}" for v in (*f.position, f.yaw)) for f in feet
    ).replace("-0.000000000", "0.000000000")
    assert hashlib.sha256(text.encode()).hexdigest()[:16] == FLAT_PLAN_DIGESTS[name]
    # and bit for bit what footsteps built from the yaw alone give
    yaw_only = []
    for line in path.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            v = [float(t) for t in line.split()]
            feet_of_line = []
            for offset, side in ((0, Side.LEFT), (7, Side.RIGHT)):
                q = np.array(v[offset + 3 : offset + 7])
                yaw = quaternion_to_yaw(*(q / np.linalg.norm(q)))
                feet_of_line.append(Footstep(side, v[offset : offset + 3], yaw))
            yaw_only.append(PathWaypoint(*feet_of_line))
    expected = plan_from_path(yaw_only)
    for a, b in zip([expected.initial_left, expected.initial_right, *expected.steps], feet):
        assert a.position.tobytes() == b.position.tobytes() and a.yaw == b.yaw


def test_the_plan_command_writes_its_footsteps_as_mdat(tmp_path, capsys):
    from mpcwalk.cli.main import main

    out = tmp_path / "plan"
    assert main(["plan", "--steps", "3", "--vyaw", "0.2", "--mdat", "--out", str(out)]) == 0
    assert "footsteps.mdat" in capsys.readouterr().out
    waypoints = read_mdat(out / "footsteps.mdat")
    assert (out / "footsteps.mdat").read_text().startswith("# mpcwalk plan: mpc")
    assert len(waypoints) == 3 + 1 + 1  # the initial stance, 3 steps and the closing one
    assert len({round(w.left.yaw, 12) for w in waypoints}) > 1  # turning: the yaws are kept
