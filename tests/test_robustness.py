"""The robustness matrix: its configuration, its worlds, its cells and report on known rows,
and the quick run of the experiment."""

import csv
import dataclasses
import json

import pytest

from mpcwalk.cli import main as cli_main
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.reporting import find_results, wilson
from mpcwalk.experiments.robustness.cells import cell_rows, rate, rate_text
from mpcwalk.experiments.robustness.config import DEFAULT_MATRIX, load_matrix_config
from mpcwalk.experiments.robustness.goals import goal_checks
from mpcwalk.experiments.robustness.report import success_table, worst_cases
from mpcwalk.experiments.robustness.terrain_report import (
    skipped_text,
    terrain_command,
    terrain_goal_text,
    terrain_table,
)
from mpcwalk.experiments.robustness.terrains import (
    TERRAIN_APART,
    TERRAIN_FACTORS,
    compatible,
    far_end,
    layout_text,
)
from mpcwalk.experiments.robustness.worlds import FACTORS, plan_matrix, robot_worlds
from mpcwalk.experiments.survival import survived
from mpcwalk.sweep import read_rows
from mpcwalk.terrain import Slope, Stairs, SteppingStones, Terrain, TerrainReach


def test_the_full_matrix_and_its_quick_form():
    full, quick = load_matrix_config(), load_matrix_config(quick=True)
    robots = ["bioloid-like", "g1", "atlas-like", "talos", "romeo"]
    assert list(full.robots) == robots and full.mode == "full"
    assert full.robots["romeo"].controllers == ("paper-m", "mpc", "mpc-steps")
    assert full.robots["g1"].command == full.robots["atlas-like"].command == (0.1, 0.0, 0.0)
    assert list(quick.robots) == ["bioloid-like"] and quick.mode == "quick"
    assert quick.robots["bioloid-like"].controllers == ("paper-m-open", "mpc")
    worlds = robot_worlds(full, 0)
    singles = [w for w in worlds if w.group == "single"]
    assert len(singles) == len(FACTORS) * full.levels
    assert sum(w.group == "combination" for w in worlds) == full.combinations
    assert len({w.seed for w in worlds if w.group != "nominal"}) == len(worlds) - 2
    # the same draws every time: the configuration is the matrix
    assert robot_worlds(full, 0) == worlds
    combos = [w.factors for w in worlds if w.group == "combination"]
    assert all(compatible(f) for f in combos)
    assert any(set(f) & set(TERRAIN_FACTORS) for f in combos)  # terrain goes in combinations
    for factors in combos:
        if set(factors) & set(TERRAIN_FACTORS):
            assert not set(factors) & set(TERRAIN_APART)
    assert not compatible(["stairs", "roughness"]) and not compatible(["slope", "stones"])


def test_the_stored_tables_hold_the_cases_of_their_configurations():
    """The case id of every walk of the stored matrices is its case's id now: a new field of
    the walk specification left at its default keeps the ids, so that a run on the same
    folder finds its walks done (and a change that alters walks shows here)."""
    variants = {
        "robustness": None,
        "robustness_terrain": "terrain_only",
        "robustness_cadence": "terrain_cadence",
        "robustness_torque": "torque",
    }
    for name, variant in variants.items():
        folder = find_results(name)
        if folder is None:  # an installed package without the repository's results
            pytest.skip("no stored results beside this package")
        config = load_matrix_config(variant=variant)
        ids = {spec.case_id for spec in plan_matrix(config).cases}
        stored = {row["case_id"] for row in read_rows(folder / "results.csv")}
        assert stored == ids, name


def test_the_terrain_part_is_the_whole_matrixs_terrain_worlds():
    full = load_matrix_config()
    terrain = load_matrix_config(variant="terrain_only")
    assert terrain.factors == TERRAIN_FACTORS and terrain.mode == "full"
    assert list(terrain.robots) == ["bioloid-like", "g1"]
    assert terrain.robots["g1"].controllers == ("paper-m", "mpc", "mpc-steps")
    for index in (0, 1):
        mine = robot_worlds(terrain, index)
        assert len(mine) == len(TERRAIN_FACTORS) * terrain.levels
        assert mine == [
            w for w in robot_worlds(full, index) if w.factors in {(f,) for f in TERRAIN_FACTORS}
        ]
    with pytest.raises(ConfigurationError, match="Unknown factor"):
        robot_worlds(dataclasses.replace(terrain, factors=("lava",)), 0)
    with pytest.raises(ConfigurationError, match="holds no \\[lava\\] table"):
        load_matrix_config(variant="lava")


def test_the_torque_matrix_is_the_whole_matrixs_flat_worlds_torque_controlled(tmp_path):
    full = load_matrix_config()
    torque = load_matrix_config(variant="torque")
    flat = tuple(f for f in FACTORS if f not in TERRAIN_FACTORS)
    assert torque.actuation == "torque" and full.actuation == "position"
    assert torque.factors == flat and list(torque.robots) == list(full.robots)
    assert all(p.controllers == ("paper-m", "mpc", "mpc-steps") for p in torque.robots.values())
    assert torque.settings()["actuation"] == "torque"
    assert "actuation" not in full.settings()  # the position matrix keeps its fingerprint
    mine = robot_worlds(torque, 2)
    assert mine == [w for w in robot_worlds(full, 2) if set(w.factors) <= set(flat)]
    cases = plan_matrix(dataclasses.replace(torque, robots={"g1": torque.robots["g1"]})).cases
    assert {case.world.actuation for case in cases} == {"torque"}
    position = plan_matrix(dataclasses.replace(full, robots={"g1": full.robots["g1"]})).cases
    ids = {case.case_id for case in position}
    # the same walks as the position matrix's, their actuation apart
    assert {case.replace(actuation="position").case_id for case in cases} <= ids
    path = tmp_path / "matrix.toml"
    path.write_text(DEFAULT_MATRIX.read_text().replace('"torque"\nfactors', '"hydraulic"\nfactors'))
    with pytest.raises(ConfigurationError, match="actuation must be one of"):
        load_matrix_config(path, variant="torque")


def test_the_cadence_matrix_is_the_whole_matrixs_terrain_walks_at_the_terrain_cadence(tmp_path):
    full = load_matrix_config()
    cadence = load_matrix_config(variant="terrain_cadence")
    assert cadence.terrain_cadence and not full.terrain_cadence
    assert cadence.factors == TERRAIN_FACTORS and list(cadence.robots) == list(full.robots)
    assert cadence.settings()["terrain_cadence"] is True
    assert "terrain_cadence" not in full.settings()  # the matrix keeps its fingerprint
    only = {"talos": cadence.robots["talos"]}
    cases = plan_matrix(dataclasses.replace(cadence, robots=only)).cases
    assert cases and all(case.plan.terrain_cadence for case in cases)
    assert {case.controller.name for case in cases} == {"paper-m", "mpc", "mpc-steps"}
    walks = plan_matrix(dataclasses.replace(full, robots={"talos": full.robots["talos"]})).cases
    ids = {case.case_id for case in walks}
    # the same walks as the whole matrix's terrain walks, their cadence apart
    assert {case.replace(terrain_cadence=False).case_id for case in cases} <= ids
    flat = plan_matrix(dataclasses.replace(cadence, robots=only, factors=("mass",))).cases
    assert not any(case.plan.terrain_cadence for case in flat)  # nothing to lengthen there
    path = tmp_path / "matrix.toml"
    path.write_text(
        DEFAULT_MATRIX.read_text().replace("terrain_cadence = true", "terrain_cadence = 1")
    )
    with pytest.raises(ConfigurationError, match="terrain_cadence must be true or false"):
        load_matrix_config(path, variant="terrain_cadence")


def test_the_terrain_worlds_are_built_to_the_robots_size():
    """Rise and gap a share of the leg length, treads and stones 1.5 sole lengths, a pit 0.2
    leg lengths deep, the initial stance on level ground (none skipped)."""
    from conftest import get_robot

    config = load_matrix_config(variant="terrain_only")
    plan = plan_matrix(config)
    cases = [c for c in plan.cases if c.controller.name == "mpc"]
    assert len(cases) == 2 * len(TERRAIN_FACTORS) * config.levels and not plan.skipped
    for case in cases:
        robot = get_robot(case.robot)
        leg, (sole, width) = robot.leg_length, robot.sole_size
        factor, level, terrain = case.label("factor"), case.label("level"), case.world.terrain
        assert case.label("layout") == layout_text(terrain)
        approach, cross = case.label("terrain_steps")
        assert 0 < approach < cross == case.plan.nb_steps - config.terrain.exit_steps
        first, *rest = terrain.features
        assert first.start == 0.5
        if factor == "stairs":
            up, down = first, rest[0]
            assert 0.03 <= level <= 0.12
            assert up.rise == pytest.approx(level * leg, abs=1e-4) == -down.rise
            assert up.run == down.run == pytest.approx(1.5 * sole, abs=1e-4)
            assert up.run >= TerrainReach.for_leg(sole, width, leg).min_tread
            assert isinstance(up, Stairs) and up.count == down.count == 3
        elif factor == "slope":
            assert isinstance(first, Slope) and 2.0 <= level <= 10.0
            assert first.angle == level == -rest[0].angle
            assert first.length == pytest.approx(2.0 * leg, abs=1e-4)
        else:
            assert isinstance(first, SteppingStones) and 0.05 <= level <= 0.2
            assert first.gap == pytest.approx(level * leg, abs=1e-4)
            assert first.length == pytest.approx(1.5 * sole, abs=1e-4)
            assert first.depth == pytest.approx(0.2 * leg, abs=1e-4)
    small = [c for c in cases if c.robot == "bioloid-like" and c.label("factor") == "stairs"]
    big = [c for c in cases if c.robot == "g1" and c.label("factor") == "stairs"]
    assert small[0].world.terrain.features[0].run < big[0].world.terrain.features[0].run


@pytest.mark.slow
def test_the_terrain_walks_take_the_steps_that_cross_their_terrain():
    """The footsteps of each terrain walk of the terrain part, as the walk plans them, carry
    both soles beyond the terrain's far end by the steps its label says cross it (a terrain
    on which the planner finds no place for a landing is a walk that cannot run, left out
    here)."""
    from conftest import get_robot

    from mpcwalk.exceptions import InfeasibleStep
    from mpcwalk.walking.walk_setup import set_up_walk

    config = load_matrix_config(variant="terrain_only")
    cases = [c for c in plan_matrix(config).cases if c.controller.name == "mpc"]
    crossed = 0
    for case in cases:
        try:
            steps = set_up_walk(case, get_robot(case.robot)).plan.steps
        except InfeasibleStep:
            continue
        beyond = far_end(case.world.terrain) + 0.5 * get_robot(case.robot).sole_size[0]
        cross = case.label("terrain_steps")[1]  # the steps that cross, at the nominal stride
        assert min(step.position[0] for step in steps[cross - 2 : cross]) > beyond, case
        crossed += 1
    assert crossed >= len(cases) - 3


def test_a_terrain_that_does_not_fit_the_robot_is_skipped_with_its_reason(tmp_path):
    path = tmp_path / "matrix.toml"
    text = DEFAULT_MATRIX.read_text().replace("stone_gap = [0.05, 0.2]", "stone_gap = [0.5, 0.6]")
    path.write_text(text)
    config = load_matrix_config(path, variant="terrain_only")
    plan = plan_matrix(config)
    assert not any(c.label("factor") == "stones" for c in plan.cases)
    assert len(plan.cases) == 2 * 2 * config.levels * 3  # stairs and slope: 2 robots, 3 each
    assert [(s["robot"], s["factor"]) for s in plan.skipped] == [
        ("bioloid-like", "stones")
    ] * config.levels + [("g1", "stones")] * config.levels
    assert "The terrain does not fit bioloid-like: a gap of" in plan.skipped[0]["reason"]
    text = skipped_text(plan.skipped)
    assert text.startswith("6 world(s) skipped") and "g1, stones at 0.5" in text


def test_a_malformed_matrix_is_a_named_error(tmp_path):
    path = tmp_path / "matrix.toml"
    path.write_text(DEFAULT_MATRIX.read_text().replace("[factors]", "[factor]"))
    with pytest.raises(ConfigurationError, match="Malformed matrix file"):
        load_matrix_config(path)


def _row(controller, factor, outcome, **extra):
    return {
        "case_id": f"{controller}-{factor}",
        "robot": "bioloid-like",
        "controller": controller,
        "group": "single" if factor != "nominal" else "nominal",
        "factor": factor,
        "outcome": outcome,
        "fell": outcome == "fell",
        "fall_time_s": 2.5 if outcome == "fell" else None,
        "fall_reason": "base tilt" if outcome == "fell" else "",
        "error": None,
        **extra,
    }


def test_a_stopped_walk_is_no_success_and_the_rates_carry_wilson_intervals():
    rows = [
        _row("mpc", "mass", "walked"),
        _row("mpc", "mass", "stopped"),
        _row("mpc", "mass", "fell"),
        _row("mpc", "nominal", "walked"),
        {**_row("mpc", "noise", "walked"), "error": "InfeasibleCommand: no"},
    ]
    assert [survived(r) for r in rows] == [True, False, False, True, False]
    assert rate(cell_rows(rows, "bioloid-like", "mpc", "mass")) == (1, 3)
    assert rate(cell_rows(rows, "bioloid-like", "mpc", "single")) == (1, 4)
    low, high = wilson(1, 3)
    assert rate_text(1, 3) == f"1/3, 33 % [{100 * low:.0f}, {100 * high:.0f}]"
    assert 0.0 < low < 1 / 3 < high < 1.0


def test_the_terrain_cells_and_the_terrain_goal_of_mpc():
    stairs = layout_text(Terrain([Stairs(0.5, 0.02, 0.15, 3), Stairs(1.1, -0.02, 0.15, 3)]))
    base = {"layout": stairs, "terrain_steps": [10, 20], "steps_completed": 25, "toe_stubs": 0}
    rows = [
        _row("mpc", "stairs", "walked", **base),
        _row("mpc", "stairs", "fell", **{**base, "steps_completed": 12}),
        _row("mpc", "mass", "walked"),
        _row("paper-m", "stairs", "walked", **base),
    ]
    assert rate(cell_rows(rows, "bioloid-like", "mpc", "terrain")) == (1, 2)
    assert rate(cell_rows(rows, "bioloid-like", "mpc", "single")) == (1, 1)
    [goal] = [c for c in goal_checks(rows) if "terrain" in c["goal"]]
    assert goal["goal"] == ">= 90 % over the terrain single-factor walks" and not goal["met"]
    assert goal["value"].startswith("1/2, 50 %") and goal["missed"] == "stairs"
    table = success_table(rows, "bioloid-like", ["mpc", "paper-m"])
    assert "**every terrain factor**" in table and "| slope |" not in table
    assert terrain_goal_text(rows) == (
        "- bioloid-like: `mpc` walked 1/2 (50 %) of the terrain single-factor walks; the goal "
        "(>= 90 %) is **not met**.\n"
    )
    text = terrain_table(rows)
    assert "| bioloid-like | mpc | stairs | 1/2, 50 %" in text and "| 2/2 | 1/2 |" in text
    # the command that walks a terrain row again, at the terrain cadence when asked
    assert "--terrain terrain.toml" in terrain_command(rows[0])
    assert "--terrain-cadence" not in terrain_command(rows[0])
    assert "--terrain-cadence" in terrain_command(rows[0], "terrains/a.toml", True)
    assert "--terrain-cadence" not in terrain_command(rows[2], None, True)  # on the floor
    fallen = [{**rows[1], "steps_planned": 25}]
    assert "--terrain-cadence" in worst_cases(fallen, terrain_cadence=True)


def test_the_goals_hold_on_every_robot_of_the_table():
    """Every robot of the table gets its goal rows (in the table's order), not only the
    small humanoid: a robot whose combinations fall shows the goal as not met."""
    talos = [
        {**_row("mpc", "mass", "walked"), "robot": "talos"},
        {**_row("mpc", "mass+slope", "fell"), "robot": "talos", "group": "combination"},
        {**_row("paper-m", "mass", "walked"), "robot": "talos"},
    ]
    rows = [_row("mpc", "mass", "walked"), *talos]
    checks = goal_checks(rows)
    assert list(dict.fromkeys(c["robot"] for c in checks)) == ["bioloid-like", "talos"]
    [combined] = [c for c in checks if c["robot"] == "talos" and "combinations" in c["goal"]]
    assert not combined["met"] and combined["value"].startswith("0/1")
    assert combined["cases"] == "mpc-mass+slope"
    [single] = [c for c in checks if c["robot"] == "talos" and "single-factor" in c["goal"]]
    assert single["met"] and single["value"].startswith("1/1")


def test_the_worst_cases_name_stopped_and_fallen_walks_with_their_command():
    base = {
        "vx": 0.1, "vy": 0.0, "vyaw": 0.0, "nb_steps": 4, "pushes": [], "mass_scale": 1.3,
        "com_dx": 0.0, "com_dy": 0.0, "friction": None, "noise_scale": 1.0,
        "latency_periods": None, "servo_strength": 1.0, "ground_tilt": 0.0,
        "ground_tilt_direction": 0.0, "ground_roughness": 0.0, "seed": 3,
        "control_period": 0.01, "level": 1.3, "steps_completed": 2, "steps_planned": 5,
    }  # fmt: skip
    rows = [_row("mpc", "mass", "stopped", **base), _row("mpc", "mass", "fell", **base)]
    text = worst_cases(rows)
    assert text.startswith("2 walks fell, were stopped or could not run.")
    assert "stopped by the controller" in text and "fell at 2.5 s (base tilt)" in text
    assert "mpcwalk walk --robot bioloid-like --controller mpc" in text
    assert "--mass-scale 1.3" in text and "--actuation" not in text
    assert worst_cases([_row("mpc", "mass", "walked", **base)]) == "Every walk survived.\n"
    torque = worst_cases([_row("mpc", "mass", "fell", **base, actuation="torque")])
    assert "--mass-scale 1.3 --actuation torque --seed 3" in torque


@pytest.mark.slow
def test_the_quick_robustness_matrix(tmp_path):
    """`mpcwalk experiment run robustness --quick`: a few dozen short walks on local Ray;
    `mpc` walks the nominal world, `paper-m-open` falls under the push it cannot survive
    (beyond the LIPM's no-step bound), `mpc` walks onto each terrain, and the report names
    the reproducing command of each fall; run again, nothing runs."""
    out = tmp_path / "robustness"
    command = ["experiment", "run", "robustness", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    with open(out / "results.csv", newline="") as stream:
        header = next(csv.reader(stream))
    rows = read_rows(out / "results.csv")
    for column in ("case_id", "robot", "controller", "group", "factor", "fell", "outcome"):
        assert column in header
    assert len(rows) == json.loads((out / "sweep.json").read_text())["nb_cases"] >= 20
    assert not any(row["error"] for row in rows)

    def outcome(controller, factor):
        return [
            r["outcome"] for r in rows if r["controller"] == controller and r["factor"] == factor
        ]

    assert outcome("mpc", "nominal") == ["walked"]
    assert outcome("paper-m-open", "push") == ["fell"]
    for factor in TERRAIN_FACTORS:  # each terrain walked on, well past its first edge
        [row] = [r for r in rows if r["controller"] == "mpc" and r["factor"] == factor]
        assert row["layout"] and not row["error"] and row["distance_m"] > 0.15
    report = (out / "report.md").read_text()
    assert "## On terrain" in report and ">= 90 % over the terrain single-factor walks" in report
    assert "mpcwalk experiment run robustness --quick" in report
    assert "## Success rates (95 % Wilson intervals)" in report and "## Worst cases" in report
    assert "mpcwalk walk --robot bioloid-like --controller paper-m-open" in report
    assert (out / "matrix_success_bioloid-like.png").stat().st_size > 1000
    assert cli_main(command) == 0
    assert json.loads((out / "runs.json").read_text())[-1]["cases_run"] == 0
