"""The robustness experiment: its cases, its tables, and a quick run of its script."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.robustness import (
    DEFAULT_CONFIG,
    RobustnessCase,
    RobustnessResults,
    build_cases,
    estimator_tasks,
    load_config,
    robustness_tasks,
)
from mpcwalk.experiments.robustness_report import (
    case_tables,
    estimator_summary,
    falls_table,
    format_readme,
)

ROOT = Path(__file__).resolve().parent.parent


def test_the_full_table_has_the_cases_of_the_issue():
    config = load_config()
    names = [case.name for case in config.cases]
    singles = [
        "nominal",
        "mass x0.7",
        "mass x1.3",
        "com +1 cm x",
        "com -1 cm x",
        "com +1 cm y",
        "com -1 cm y",
        "friction 0.4",
        "latency 2",
        "noise x2",
    ]
    # mass x1.3 with each of the others that changes something else (7 combinations)
    combined = [f"mass x1.3 + {name}" for name in singles[3:]]
    assert names == singles + combined
    assert set(config.robots) == {"bioloid-like", "g1"}
    assert [walk.name for walk in config.robots["g1"]] == ["forward", "turning"]
    assert all(walk.nb_steps == 20 for walks in config.robots.values() for walk in walks)
    assert set(config.generators) == {
        "analytic",
        "preview",
        "mpc",
        "mpc-steps",
        "static",
        "static-qp",
    }
    by_name = {case.name: case for case in config.cases}
    assert by_name["mass x1.3 + latency 2"].walk_arguments(0.01) == {
        "mass_scale": 1.3,
        "latency": 0.02,
    }
    assert by_name["mass x1.3 + com -1 cm y"].walk_arguments(0.01) == {
        "mass_scale": 1.3,
        "com_offset": (0.0, -0.01),
    }
    assert set(config.estimator_walks) == {"bioloid-like", "g1", "atlas-like"}
    assert config.estimator_seeds == (0, 1, 2, 3, 4)
    estimator = estimator_tasks(config, "out")
    assert len(estimator) == 15  # 3 robots, 5 seeds; a figure for the first seed only
    assert [args[4] for _, args in estimator[:2]] == ["out/estimator_bioloid-like.png", None]
    tasks = robustness_tasks(config)
    assert len(tasks) == 2 * 2 * 17 * 6  # robots, walks, cases, generators
    # the static gaits take the same steps 4 times slower, half of each in double support
    static = next(args for _, args in tasks if args[1] == "static")
    assert static[2].command == (0.025, 0.0, 0.0)
    assert static[2].walk_arguments(get_robot("bioloid-like")) == {
        "command": (0.025, 0.0, 0.0),
        "nb_steps": 20,
        "step_duration": 2.0,
        "double_support_ratio": 0.5,
    }


def test_quick_mode_is_a_handful_of_walks():
    config = load_config(mode="quick")
    assert [case.name for case in config.cases] == [
        "nominal",
        "mass x1.3",
        "mass x1.3 + com +1 cm x",
    ]
    assert list(config.robots) == ["bioloid-like"] and config.generators == ("mpc",)
    assert not config.estimator_walks


def test_combinations_skip_the_same_quantity_and_unknown_bases_are_errors():
    heavy = RobustnessCase("heavy", {"mass_scale": 1.3})
    cases = build_cases(
        [RobustnessCase("nominal"), heavy, RobustnessCase("light", {"mass_scale": 0.7})],
        "heavy",
    )
    assert [case.name for case in cases] == ["nominal", "heavy", "light"]
    with pytest.raises(ConfigurationError, match="combine_with = 'nope' is not a case"):
        build_cases([heavy], "nope")
    with pytest.raises(ConfigurationError, match="mode must be 'full' or 'quick'"):
        load_config(DEFAULT_CONFIG, mode="fast")


def _row(case, generator, fell):
    return {
        "robot": "bioloid-like",
        "walk": "forward",
        "command": [0.1, 0.0, 0.0],
        "case": case,
        "generator": generator,
        "fell": fell,
        "fall_time_s": 4.25 if fell else None,
        "fall_reason": "base tilt 46.0 deg above 45 deg" if fell else "",
        "steps_completed": 5 if fell else 21,
        "steps_planned": 21,
        "foot_position_error_cm_max": 1.234,
        "cop_margin_p05_m": 0.0042,
    }


def test_tables_show_every_walk_and_list_the_falls():
    rows = [_row("nominal", "mpc", False), _row("mass x1.3", "mpc", True)]
    text = case_tables(rows, ["mpc", "analytic"])
    assert "| nominal | 21/21, 1.2 cm, +4.2 mm |  |" in text
    assert "| mass x1.3 | **fell** 4.2 s (5/21) |  |" in text
    falls = falls_table(rows)
    assert "mass x1.3" in falls and "nominal" not in falls and "base tilt" in falls
    assert falls_table(rows[:1]) == "No walk falls.\n"
    # a walk the library refused: listed with its error, no metrics
    refused = {**_row("friction 0.4", "mpc", False), "fell": None, "error": "InfeasibleCommand"}
    assert "| friction 0.4 | **error** |" in case_tables([refused], ["mpc"])
    assert "InfeasibleCommand" in falls_table([refused])
    results = RobustnessResults(tuple(rows), (), 90.0, 2)
    readme = format_readme(load_config(mode="quick"), results, command="run.py --quick")
    assert "`run.py --quick` (quick mode; 2 walks in 1.5 min" in readme
    assert "| mpc | 1/2 |" in readme


def test_estimator_summary_counts_the_seeds_meeting_the_goal():
    rows = [
        {"robot": "bioloid-like", "estimator_com_error_rms_m": value}
        for value in (0.004, 0.006, 0.003)
    ] + [{"robot": "g1", "estimator_com_error_rms_m": 0.009}]
    text = estimator_summary(rows)
    assert "| bioloid-like | 4.0 | 3.0 to 6.0 | 2/3 (< 5 mm) |" in text
    assert "| g1 | 9.0 | 9.0 to 9.0 | 1/1 (< 10 mm) |" in text


@pytest.mark.slow
def test_quick_run_of_the_script(tmp_path):
    out = tmp_path / "robustness"
    completed = subprocess.run(
        [
            sys.executable,
            str(ROOT / "experiments" / "robustness" / "run.py"),
            "--quick",
            "--workers",
            "2",
            "--no-progress",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert completed.returncode == 0, completed.stderr
    data = json.loads((out / "results.json").read_text())
    assert data["mode"] == "quick" and len(data["rows"]) == 3
    for row in data["rows"]:
        # a heavier torso, and a heavier torso with its CoM 1 cm forward: the robot walks
        assert not row["fell"], row
        assert row["steps_completed"] == row["steps_planned"] == 5
        assert row["config"]["state_source"] == "estimator"
    assert data["rows"][2]["config"]["model_mismatch"]["com_offset"] == [0.01, 0.0]
    readme = (out / "README.md").read_text()
    assert "No walk falls." in readme and "#### bioloid-like, forward" in readme
