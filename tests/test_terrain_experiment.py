"""The terrain experiment (`mpcwalk experiment run terrain`): its configuration, its
terrains sized per robot, a refused terrain recorded (not crashed), and the quick run."""

import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.terrain.cases import TerrainCase, run_terrain_case, terrain_cases
from mpcwalk.experiments.terrain.config import load_terrain_config
from mpcwalk.experiments.terrain.report import walk_table
from mpcwalk.experiments.terrain.walks import stair_run, stairs_terrain, walk_spec
from mpcwalk.terrain import TerrainReach, check_terrain
from mpcwalk.walking.walk_setup import check_walk_terrain


def test_the_configuration_and_its_quick_variant(tmp_path):
    full = load_terrain_config()
    assert [p.robot for p in full.robots] == ["bioloid-like", "g1", "atlas-like"]
    assert all(
        set(p.controllers) == {"mpc", "mpc-steps", "paper-a", "paper-m"} for p in full.robots
    )
    # paper A keeps its own timing, the others walk at each step duration; every stride
    cases = terrain_cases(full)
    assert full.stride_shares == (0.5, 0.25)
    assert len(cases) == 3 * (3 * 2 + 1) * 2 * 4
    assert {c.timing for c in cases if c.controller == "paper-a"} == {"own"}
    assert len({c.case_id for c in cases}) == len(cases)
    quick = load_terrain_config(quick=True)
    assert [(p.robot, p.controllers, len(p.step_durations)) for p in quick.robots] == [
        ("g1", ("mpc",), 1)
    ]
    assert quick.bisection_iterations == 2 and quick.mode == "quick"
    assert quick.stride_shares == (1.0,)
    bad = tmp_path / "config.toml"
    bad.write_text('climb_cm = 5.0\n[[robots]]\nrobot = "g1"\ncontrollers = ["mpc"]\n')
    with pytest.raises(ConfigurationError, match="climb_cm"):
        load_terrain_config(bad)


@pytest.mark.parametrize("name", ["bioloid-like", "g1", "atlas-like"])
def test_the_stairs_fit_each_robot_at_the_goal_rise(name):
    robot = get_robot(name)
    config = load_terrain_config()
    reach = TerrainReach.for_leg(*robot.sole_size, robot.leg_length)
    assert reach.min_tread <= stair_run(robot, config) <= 1.5 * robot.sole_size[0] + 1e-12
    terrain = stairs_terrain(robot, config, 0.25 * robot.leg_length)
    check_terrain(terrain, reach, name)
    check_walk_terrain(robot, terrain)  # the initial stance on level ground
    # the steps leave the stairs behind
    spec = walk_spec(robot, "mpc", terrain, config, robot.gait.step_duration)
    assert spec.plan.nb_steps > 2 * config.nb_stairs


def test_a_refused_terrain_is_a_row_not_a_crash():
    """bioloid-like's stride does not cross gaps of 40 % of its leg: the row says why."""
    config = load_terrain_config()
    row = run_terrain_case(TerrainCase(config, "bioloid-like", "mpc", "stones", 0.5))
    assert row["refused"].startswith("TerrainError: The terrain does not fit bioloid-like")
    assert "gap" in row["refused"] and row["climbed"] is False and row["nb_walks"] == 0
    shown = walk_table([{**row, "robot": "bioloid-like", "controller": "mpc", "timing": 0.5}])
    assert "refused (TerrainError: The terrain does not fit bioloid-like" in shown


@pytest.mark.slow
def test_the_quick_terrain_experiment(tmp_path):
    """`mpcwalk experiment run terrain --quick`: g1 with mpc, a 2-walk bisection on the
    stairs and the slope; the report, its tables and figures."""
    from mpcwalk.cli import main as cli_main
    from mpcwalk.sweep import read_rows

    out = tmp_path / "terrain"
    command = ["experiment", "run", "terrain", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    rows = {row["terrain"]: row for row in read_rows(out / "results.csv")}
    assert set(rows) == {"stairs", "slope"}
    assert rows["stairs"]["case_id"] == "g1/mpc/stairs/T1-stride1"
    stairs, slope = rows["stairs"], rows["slope"]
    assert not stairs["error"] and not slope["error"]
    assert (stairs["robot"], stairs["controller"]) == ("g1", "mpc")
    leg = get_robot("g1").leg_length
    assert 1 <= stairs["nb_walks"] <= 2 and len(stairs["trials"]) == stairs["nb_walks"]
    assert stairs["trials"][0][0] == pytest.approx(0.25 * leg, abs=1e-4)  # the goal first
    assert 0.0 <= stairs["largest_rise_m"] < 0.5 * leg
    assert stairs["steps_planned"] > 10 and slope["outcome"] in ("walked", "fell", "stopped")
    report = (out / "report.md").read_text()
    assert "mpcwalk experiment run terrain --quick" in report
    for part in ("## Largest rise climbed", "## At the goal's rise", "## Slopes", "## Goals"):
        assert part in report
    assert "18.5 cm" in report  # the peers' figure, stated as theirs
    assert "| g1 | mpc | 1 | 1.00 |" in report
    assert (out / "largest_rise.png").stat().st_size > 1000
    assert (out / "side_view.png").stat().st_size > 1000
    assert not (out / "side_views").exists()


def test_paper_a_walks_at_its_own_timing_with_a_command_within_reach():
    robot = get_robot("atlas-like")
    config = load_terrain_config()
    terrain = stairs_terrain(robot, config, 0.05)
    spec = walk_spec(robot, "paper-a", terrain, config, robot.gait.step_duration)
    assert spec.plan.step_duration is None  # the static gait's 12 s
    assert spec.plan.command[0] * 12.0 <= robot.gait.max_step_forward
