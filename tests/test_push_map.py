"""The controllers' push map: its grid against the LIPM's, its report and its goals, joined
maps, and the quick run of the experiment."""

import json
import math

import numpy as np
import pytest
from conftest import get_robot

from mpcwalk.cli import main as cli_main
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.capture_map.cells import capture_map
from mpcwalk.experiments.push_map.cases import PushMapConfig, joined_push_rows, push_map_cases
from mpcwalk.experiments.push_map.report import (
    best_controller,
    double_support_text,
    goals_text,
    lipm_bounds,
    summary_table,
)

GRID = PushMapConfig(
    controllers=("paper-m", "mpc", "fast"), nb_directions=4, nb_phases=6, speed_shares=(1.0,)
)


@pytest.fixture(scope="module")
def bounds():
    return lipm_bounds(get_robot("bioloid-like"), GRID)


def _rows(values: dict[str, dict]) -> list[dict]:
    return [
        {
            "controller": controller,
            "direction_deg": cell[0],
            "phase": cell[1],
            "speed_share": cell[2],
            "largest_survived_Ns": value,
            "smallest_fallen_Ns": 1.1 * value,
            "capture_bound_Ns": 0.5,
            "censored": False,
            "nb_walks": 5,
        }
        for controller, cells in values.items()
        for cell, value in cells.items()
    ]


def test_the_push_map_pushes_where_the_lipm_map_is_drawn():
    """Same directions and phases (the middle of each sixth of the step) as the LIPM's map,
    so that every cell has its bounds."""
    cases = push_map_cases(GRID)
    cells = capture_map(get_robot("bioloid-like"), nb_directions=4, nb_phases=6)
    assert {(c.direction_deg, c.phase) for c in cases} == {
        (c.direction_deg, c.phase) for c in cells
    }
    assert len(cases) == 3 * 4 * 6
    assert sorted({c.phase for c in cases})[0] == pytest.approx(1 / 12, abs=1e-4)


def test_report_ratios_shares_and_goals_on_known_values(bounds):
    """paper-m at 40 % of the 1-step bound everywhere, mpc at 90 %, "fast" at 100 % but
    one cell at 50 %: the best is "fast", its median is 2.5x paper-m's, one cell is under
    80 % of the bound, and paper-m beats it nowhere."""
    cells = [c for c, b in bounds.items() if b.fixed[1] > 0]
    weak = cells[0]
    values = {
        "paper-m": {c: 0.4 * bounds[c].fixed[1] for c in cells},
        "mpc": {c: 0.9 * bounds[c].fixed[1] for c in cells},
        "fast": {c: (0.5 if c == weak else 1.0) * bounds[c].fixed[1] for c in cells},
    }
    rows = _rows(values)
    assert best_controller(rows) == "fast"
    # a tie of the medians goes to the larger median ratio to paper-m per cell: "a" and "b"
    # survive the same impulses in other cells (the same median), "b" where paper-m is weak
    eight = cells[:8]
    reference = {c: 0.5 if i % 2 == 0 else 2.0 for i, c in enumerate(eight)}
    a = {c: 2.0 if i % 2 == 0 else 1.0 for i, c in enumerate(eight)}  # ratios 4 and 0.5
    b = {c: 1.0 if i % 2 == 0 else 2.0 for i, c in enumerate(eight)}  # ratios 2 and 1
    tied = _rows({"paper-m": reference, "b": b, "a": a})
    assert best_controller(tied) == "a"  # median ratio 2.25 against 1.5
    text = summary_table(rows, bounds)
    line = next(row for row in text.splitlines() if row.startswith("| fast |"))
    assert "| 2.50 |" in line and "| 1.00 |" in line  # ratio to paper-m, share of the bound
    assert f"| 1/{len(cells)} |" in line  # the cells under 80 %
    goals = goals_text(rows, bounds)
    assert "**2.50x** (goal 2x: met)" in goals
    assert f"**1/{len(cells)}** (goal: none; not met)" in goals
    assert f"{weak[0]:g} deg, phase {weak[1]:.2f}" in goals.split("worst cells")[1]
    assert "where every QP controller does: **0/" in goals
    assert "survives less than `paper-m`: **0/" in goals


def test_double_support_cells_compare_the_adaptive_controllers_with_mpc(bounds):
    """The LIPM's impulse acts at the middle of the 0.1 s push: a push starting 42 ms into
    a 0.5 s step (r_ds = 0.2: 50 ms of double support) acts in single support; one starting
    42 ms before its end acts in the next double support."""
    double = [c for c, b in bounds.items() if not b.single_support]
    assert {c[1] for c in double} == {0.9167} and len(double) == 4
    rows = _rows(
        {
            "mpc": dict.fromkeys(double, 0.6),
            "fast": {c: (0.5 if i == 0 else 0.62) for i, c in enumerate(double)},
        }
    )
    text = double_support_text(rows, bounds)
    line = next(row for row in text.splitlines() if row.startswith("| fast |"))
    # 4 cells, median ratio 0.62 / 0.6, 3 above mpc, one below, where it fell at 0.55 N s
    # (1.1 x 0.5) under mpc's 0.6 survived
    assert line.split("|")[2:7] == [" 4 ", f" {0.62 / 0.6:.2f} ", " 3 ", " 1 ", " 1 "]


def test_the_torque_maps_pair_each_robots_cells_in_both_modes():
    from mpcwalk.experiments.push_map.experiment import PushMapTorque
    from mpcwalk.experiments.push_map.modes import mode_rows, mode_table

    maps = PushMapTorque().config().maps
    pairs = {(m.robot, m.actuation): m for m in maps}
    assert set(pairs) == {(r, a) for r in ("bioloid-like", "g1") for a in ("position", "torque")}
    for robot in ("bioloid-like", "g1"):
        position, torque = pairs[(robot, "position")], pairs[(robot, "torque")]
        assert {c.case_id for c in push_map_cases(position)} == {
            c.case_id for c in push_map_cases(torque)
        }
        assert torque.folder_name == f"{robot}-torque" and position.folder_name == robot
    assert "actuation" not in GRID.settings()  # the maps run before keep their fingerprint
    with pytest.raises(ConfigurationError, match="actuation must be one of"):
        PushMapConfig(actuation="hydraulic")
    cells = {(0.0, 0.25, 1.0): 0.4, (90.0, 0.25, 1.0): 0.2, (180.0, 0.25, 1.0): 0.5}
    position = _rows({"mpc": cells, "paper-m": cells})
    torque = _rows(
        {
            "mpc": {cell: 1.2 * v for cell, v in cells.items()},
            "paper-m": {**cells, (0.0, 0.25, 1.0): 0.2},
        }
    )
    rows = {row["controller"]: row for row in mode_rows(position, torque)}
    assert rows["mpc"]["ratio"] == pytest.approx(1.2) and rows["mpc"]["below"] == 0
    assert rows["paper-m"]["worst"] == pytest.approx(0.5) and rows["paper-m"]["below"] == 1
    assert rows["paper-m"]["torque"] == pytest.approx(0.2)  # median of 0.2, 0.2, 0.5
    text = mode_table({("g1", "position"): position, ("g1", "torque"): torque})
    assert "`g1`" in text and "1.20" in text
    assert mode_table({("g1", "position"): position}) == "No robot was mapped in both modes.\n"


def test_joined_maps_must_share_the_robot_and_the_grid(tmp_path):
    folder = tmp_path / "other"
    with pytest.raises(ConfigurationError, match="expected the folder of a push map"):
        joined_push_rows(GRID, [folder])
    folder.mkdir()
    other = PushMapConfig(controllers=("mpc-timing",), nb_directions=8, speed_shares=(1.0,))
    (folder / "sweep.json").write_text(
        json.dumps({"settings": other.settings(), "cases": ["a", "b"]})
    )
    (folder / "results.csv").write_text("case_id,controller\na,mpc-timing\n")
    with pytest.raises(ConfigurationError, match="nb_directions is 8 there, 4 here"):
        joined_push_rows(GRID, [folder])
    same = PushMapConfig(controllers=("mpc",), nb_directions=4, speed_shares=(1.0,))
    (folder / "sweep.json").write_text(
        json.dumps({"settings": same.settings(), "cases": ["a", "b"]})
    )
    with pytest.raises(ConfigurationError, match="expected a finished push map"):
        joined_push_rows(GRID, [folder])
    (folder / "results.csv").write_text("case_id,controller\na,mpc\nb,mpc\n")
    with pytest.raises(ConfigurationError, match="mpc run here too"):
        joined_push_rows(GRID, [folder])
    mine = PushMapConfig(controllers=("paper-m",), nb_directions=4, speed_shares=(1.0,))
    assert [r["controller"] for r in joined_push_rows(mine, [folder])] == ["mpc", "mpc"]


@pytest.mark.slow
def test_the_quick_push_map_and_a_map_joined_to_it(tmp_path):
    """`mpcwalk experiment run push_map --quick`: paper-m and mpc in one cell of
    bioloid-like's map, in its sub-folder, with the LIPM's bounds of the cell; a map of
    paper-m-open (which falls unpushed) run apart on the same grid joins its report."""
    from mpcwalk.experiments.push_map.cases import push_map_sweep
    from mpcwalk.experiments.push_map.experiment import PushMap
    from mpcwalk.experiments.push_map.report import write_push_report
    from mpcwalk.sweep import read_rows, run_sweep

    out = tmp_path / "push_map"
    command = ["experiment", "run", "push_map", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    folder = out / "bioloid-like"
    rows = read_rows(folder / "results.csv")
    assert sorted(r["controller"] for r in rows) == ["mpc", "paper-m"]
    for row in rows:
        assert not row["error"] and 0.0 < row["largest_survived_Ns"] <= 3 * row["capture_bound_Ns"]
        assert row["nb_walks"] == len(row["trials"]) >= 2
    (bound,) = json.loads((folder / "lipm_bounds.json").read_text())
    assert bound["direction_deg"] == 0.0 and bound["phase"] == 0.5 and bound["single_support"]
    assert math.isfinite(bound["fixed"][1]) and bound["fixed"][1] > 0.0
    assert (folder / "push_polar_speed1.png").stat().st_size > 1000
    report = (out / "report.md").read_text()
    assert "## bioloid-like" in report and "| paper-m |" in report and "| mpc |" in report
    assert "mpcwalk experiment run push_map --quick" in (folder / "report.md").read_text()
    # another controller on the same grid, run apart, joined to the report
    (config,) = PushMap().config(quick=True).maps
    from dataclasses import replace

    apart = replace(config, controllers=("paper-m-open",))
    run_sweep(push_map_sweep(apart), tmp_path / "apart", workers=1, progress=False)
    joined = joined_push_rows(config, [tmp_path / "apart"])
    assert [r["controller"] for r in joined] == ["paper-m-open"]
    path = write_push_report(tmp_path / "apart", [*rows, *joined], config, "")
    assert "| paper-m-open |" in path.read_text()
    # a joined folder of another grid is refused
    with pytest.raises(ConfigurationError, match="expected a push map on the same robot and grid"):
        joined_push_rows(replace(config, nb_directions=2), [tmp_path / "apart"])


def test_every_cell_has_the_flywheel_bounds_beside_the_lipms(bounds):
    """The upper body as a flywheel (bioloid-like's limits) widens every bound a little, and
    the report gives each controller's share of them."""
    for cell in bounds.values():
        for n in (1, 2):
            assert cell.flywheel[n] >= cell.fixed[n]
    grown = [b.flywheel[1] / b.fixed[1] for b in bounds.values() if b.fixed[1] > 0]
    assert 1.0 < float(np.median(grown)) < 1.2
    cells = [c for c, b in bounds.items() if b.flywheel[1] > 0]
    rows = _rows({"mpc": {c: bounds[c].flywheel[1] for c in cells}})
    text = summary_table(rows, bounds)
    assert "of the flywheel LIPM's 1-step bound, median" in text
    line = next(row for row in text.splitlines() if row.startswith("| mpc |"))
    assert "| 1.00 |" in line
