"""A walk on a terrain: its specification holds the terrain inline, ``mpcwalk walk --terrain``
reads a terrain file and refuses a bad one or one the robot cannot walk before anything runs,
and a walk on a terrain writes its terrain and its side view."""

import json
import sys

import pytest

from mpcwalk.cli import main
from mpcwalk.cli.world_options import read_terrain_option, shipped_terrains
from mpcwalk.exceptions import ConfigurationError, SpecFileError, TerrainError
from mpcwalk.terrain import Platform, Slope, Stairs, Terrain, read_terrain
from mpcwalk.walking.specification import WalkSpec, WorldSpec, read_spec, spec_to_toml, write_spec

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

ISSUE_TERRAIN = Terrain(
    [
        Stairs(0.6, rise=0.15, run=0.30, count=5),
        Stairs(2.4, rise=-0.15, run=0.30, count=5),
        Slope(4.5, length=1.5, angle=10.0),
    ]
)

#: Two low steps the small humanoid's legs reach (0.04 m rises, 0.25 m treads).
LOW_STAIRS = """
[[stairs]]
start = 0.3
rise = 0.04
run = 0.25
count = 2
"""


def walk(tmp_path, capsys, *argv: str) -> tuple[int, str]:
    """Exit code and standard error of ``mpcwalk walk ARGV --out tmp_path/out``."""
    code = main(["walk", *argv, "--no-progress", "--out", str(tmp_path / "out")])
    return code, capsys.readouterr().err


def test_the_shipped_example_is_the_issues_terrain():
    assert "stairs_and_slope" in shipped_terrains()
    assert read_terrain_option("stairs_and_slope") == ISSUE_TERRAIN


def test_a_spec_with_a_terrain_goes_through_its_file_unchanged(tmp_path):
    spec = WalkSpec.build("g1", command=(0.1, 0.0, 0.0), nb_steps=4, terrain=ISSUE_TERRAIN)
    text = spec_to_toml(spec)
    assert "[world.terrain]" in text and "[[world.terrain.stairs]]" in text
    assert tomllib.loads(text)["world"]["terrain"]["slope"] == [
        {"start": 4.5, "length": 1.5, "angle": 10.0}
    ]
    again = read_spec(write_spec(spec, tmp_path / "spec.toml"))
    assert again == spec and again.world.terrain == ISSUE_TERRAIN
    assert again.case_id == spec.case_id
    assert WalkSpec.from_dict(json.loads(json.dumps(spec.to_dict()))) == spec


def test_a_walk_on_the_floor_keeps_its_spec_file_and_its_id():
    flat = WalkSpec.build("bioloid-like", command=(0.1, 0.0, 0.0), nb_steps=4)
    assert flat.world.terrain is None
    assert flat.replace(terrain=Terrain()) == flat  # a terrain without features: the floor
    lines = [line for line in spec_to_toml(flat).splitlines() if "terrain =" in line]
    assert lines == [f"# terrain = (unset)  # {lines[0].split('# ', 2)[2]}"]
    assert flat.replace(terrain=ISSUE_TERRAIN).case_id != flat.case_id


@pytest.mark.parametrize(
    "value, error, message",
    [
        ({"stairs": [{"start": 0.6, "rise": 0.0}]}, TerrainError, "Stairs.rise must not be 0"),
        ({"ramp": [{"start": 1.0}]}, TerrainError, "[world.terrain]: unknown table [[ramp]]"),
        ("stairs.toml", ConfigurationError, "terrain must be a Terrain"),
    ],
)
def test_the_world_refuses_what_is_no_terrain(value, error, message):
    with pytest.raises(error) as info:
        WorldSpec(terrain=value)
    assert message in str(info.value)


def test_a_terrain_on_bumps_is_refused():
    with pytest.raises(ConfigurationError, match="lay a \\[\\[rough\\]\\] patch"):
        WorldSpec(terrain=ISSUE_TERRAIN, ground_roughness=0.01)


def test_a_rise_beyond_the_small_humanoids_legs_exits_2_before_anything_runs(tmp_path, capsys):
    code, err = walk(tmp_path, capsys, "--terrain", "stairs_and_slope", "--steps", "2")
    assert code == 2
    assert "The terrain does not fit bioloid-like: a stair rise of 15.0 cm" in err
    assert "beyond the 10.7 cm its legs reach" in err and "at most 0.107 m" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "text, message",
    [
        (None, "Cannot read the terrain file"),
        ("[[stairs]\nstart = 1", "is not valid TOML"),
        ("[[ramp]]\nstart = 1.0\n", "unknown table [[ramp]]"),
        ("[[stairs]]\nrise = 0.1\n", "needs 'start'"),
        ("[[platform]]\nstart = 1.0\nheight = 5.0\n", "Platform.height must be"),
        ("[[platform]]\nstart = 0.0\nheight = 0.02\n", "initial stance on the level ground"),
    ],
    ids=["missing", "not-toml", "unknown-table", "no-start", "out-of-range", "under-the-feet"],
)
def test_a_bad_terrain_file_exits_2_with_the_reason(tmp_path, capsys, text, message):
    path = tmp_path / "terrain.toml"
    if text is not None:
        path.write_text(text)
    code, err = walk(tmp_path, capsys, "--terrain", str(path), "--steps", "2")
    assert code == 2 and err.startswith("mpcwalk: error: ") and message in err, err
    assert not (tmp_path / "out" / "metrics.json").exists()


def test_a_spec_file_with_a_terrain_the_robot_cannot_walk_exits_2(tmp_path, capsys):
    spec = WalkSpec.build("bioloid-like", command=(0.1, 0.0, 0.0), nb_steps=2)
    path = write_spec(spec.replace(terrain=ISSUE_TERRAIN), tmp_path / "spec.toml")
    code, err = walk(tmp_path, capsys, "--spec", str(path))
    assert code == 2 and "its legs reach" in err
    broken = tmp_path / "broken.toml"
    broken.write_text(path.read_text().replace("count = 5", "count = 0", 1))
    with pytest.raises(SpecFileError, match="Stairs.count must be an integer"):
        read_spec(broken)


def test_a_walk_on_a_terrain_writes_its_terrain_and_side_view_and_walks_again(tmp_path, capsys):
    terrain_file = tmp_path / "low.toml"
    terrain_file.write_text(LOW_STAIRS)
    code, _ = walk(tmp_path, capsys, "--terrain", str(terrain_file), "--steps", "2")
    out = tmp_path / "out"
    assert code in (0, 1)  # two steps only: the robot stands before the stairs or on them
    assert (out / "side_view.png").stat().st_size > 10_000
    assert read_terrain(out / "terrain.toml") == read_terrain(terrain_file)
    spec = read_spec(out / "spec.toml")
    assert spec.world.terrain == Terrain([Stairs(0.3, rise=0.04, run=0.25, count=2)])
    assert "--terrain terrain.toml" in spec.command_line()
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["config"]["robot"] == "bioloid-like"


def test_a_platform_the_robot_reaches_is_accepted_and_one_under_its_soles_is_not():
    from conftest import get_robot

    from mpcwalk.walking.walk_setup import check_walk_terrain

    robot = get_robot("bioloid-like")
    check_walk_terrain(robot, Terrain([Platform(0.2, length=0.3, height=0.1)]))
    check_walk_terrain(robot, None)
    with pytest.raises(TerrainError, match="start the first feature at 0.07 m or beyond"):
        check_walk_terrain(robot, Terrain([Platform(0.03, length=0.3, height=0.02)]))


def test_the_small_humanoid_walks_up_and_down_stairs_on_its_sensors():
    """Closed loop on the estimator: two steps up and two down of 3 cm (14 % of the leg),
    treads 1.5 soles long; every landing on its tread, at most one light scuff of a sole
    corner mid-swing (measured: one, under 1 cm), the CoM on its height profile."""
    from mpcwalk.walking.runner import run_walk

    stairs = Terrain(
        [Stairs(0.2, rise=0.03, run=0.15, count=2), Stairs(0.5, rise=-0.03, run=0.15, count=2)]
    )
    spec = WalkSpec.build(
        "bioloid-like",
        controller="mpc",
        command=(0.05, 0.0, 0.0),
        nb_steps=16,
        step_duration=0.8,
        terrain=stairs,
        progress=False,
    )
    result = run_walk(spec)
    m = result.metrics
    assert not m.fell and m.outcome == "walked"
    assert m.steps_completed == m.steps_planned
    heights = {round(float(step.position[2]), 6) for step in result.schedule.plan.steps}
    assert heights == {0.0, 0.03, 0.06}  # up two treads, down again
    assert m.landing_height_error_cm_max < 1.0  # every sole landed on its tread
    assert m.toe_stubs <= 1 and m.swing_clearance_cm_min > -1.0
    assert m.com_height_error_cm_rms < 1.0
    final = result.log.sole_positions[-1]
    assert final[:, 0].min() > 0.65 and abs(final[:, 2]).max() < 0.005  # past the stairs


def test_g1_keeps_its_strides_up_an_even_ramp():
    """Up a 3 deg ramp, on the ground truth: each landing within 8 mm of its stride from the
    support foot on average (measured 4.9 mm). With the shaped swing (rise, travel, lower)
    the same walk's landings were 13.9 mm off their strides."""
    from mpcwalk.walking.runner import run_walk

    spec = WalkSpec.build(
        "g1",
        controller="mpc",
        command=(0.1, 0.0, 0.0),
        nb_steps=16,
        terrain=Terrain([Slope(0.2, length=2.0, angle=3.0)]),
        ideal=True,
        progress=False,
    )
    result = run_walk(spec)
    m = result.metrics
    assert m.outcome == "walked" and m.steps_completed == m.steps_planned
    heights = [float(step.position[2]) for step in result.schedule.plan.steps]
    assert heights[-1] > 0.03  # up the ramp
    assert m.foot_step_error_cm_mean < 0.8
