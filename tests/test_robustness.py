"""The robustness matrix: its configuration, its worlds, its cells and report on known rows,
and the quick run of the experiment."""

import csv
import json

import pytest

from mpcwalk.cli import main as cli_main
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.reporting import wilson
from mpcwalk.experiments.robustness.cells import cell_rows, rate, rate_text
from mpcwalk.experiments.robustness.config import DEFAULT_MATRIX, load_matrix_config
from mpcwalk.experiments.robustness.report import worst_cases
from mpcwalk.experiments.robustness.worlds import FACTORS, robot_worlds
from mpcwalk.experiments.survival import survived
from mpcwalk.sweep import read_rows


def test_the_full_matrix_and_its_quick_form():
    full, quick = load_matrix_config(), load_matrix_config(quick=True)
    assert list(full.robots) == ["bioloid-like", "g1", "atlas-like"] and full.mode == "full"
    assert list(quick.robots) == ["bioloid-like"] and quick.mode == "quick"
    assert quick.robots["bioloid-like"].controllers == ("paper-m-open", "mpc")
    worlds = robot_worlds(full, 0)
    singles = [w for w in worlds if w.group == "single"]
    assert len(singles) == len(FACTORS) * full.levels
    assert sum(w.group == "combination" for w in worlds) == full.combinations
    assert len({w.seed for w in worlds if w.group != "nominal"}) == len(worlds) - 2
    # the same draws every time: the configuration is the matrix
    assert robot_worlds(full, 0) == worlds


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
    assert "--mass-scale 1.3" in text
    assert worst_cases([_row("mpc", "mass", "walked", **base)]) == "Every walk survived.\n"


@pytest.mark.slow
def test_the_quick_robustness_matrix(tmp_path):
    """`mpcwalk experiment run robustness --quick`: a few dozen short walks on local Ray;
    `mpc` walks the nominal world, `paper-m-open` falls under the push it cannot survive
    (beyond the LIPM's no-step bound), and the report names the reproducing command of each
    fall; run again, nothing runs."""
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
    report = (out / "report.md").read_text()
    assert "mpcwalk experiment run robustness --quick" in report
    assert "## Success rates (95 % Wilson intervals)" in report and "## Worst cases" in report
    assert "mpcwalk walk --robot bioloid-like --controller paper-m-open" in report
    assert (out / "matrix_success_bioloid-like.png").stat().st_size > 1000
    assert cli_main(command) == 0
    assert json.loads((out / "runs.json").read_text())[-1]["cases_run"] == 0
