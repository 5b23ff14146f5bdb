"""The experiments as a family: one registry, one protocol, one command, one survival
criterion; the quick runs of the faults and performance experiments (the others are in
their own test files)."""

import json
from types import SimpleNamespace

import pytest

from mpcwalk.cli import main as cli_main
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.catalog import EXPERIMENTS
from mpcwalk.experiments.protocol import Experiment, read_config
from mpcwalk.experiments.reporting import median, runs_text, table
from mpcwalk.experiments.survival import survived

NAMES = [
    "paper_m",
    "paper_a",
    "robustness",
    "robustness_terrain",
    "robustness_cadence",
    "robustness_torque",
    "push_map",
    "push_map_torque",
    "capture_map",
    "terrain",
    "faults",
    "performance",
]


def test_the_registry_lists_every_experiment_with_its_shipped_configuration(capsys):
    assert list(EXPERIMENTS) == NAMES
    assert cli_main(["experiment", "list"]) == 0
    listed = [line.split()[0] for line in capsys.readouterr().out.splitlines() if line]
    assert listed == NAMES
    for name, summary, available, _ in EXPERIMENTS.rows():
        experiment = EXPERIMENTS.load(name)
        assert isinstance(experiment, Experiment) and available
        assert experiment.name == name and experiment.summary == summary
        assert experiment.config_file.is_file()
        full, quick = experiment.config(), experiment.config(quick=True)
        assert full.mode == "full" and quick.mode == "quick"
        assert 0 < len(experiment.cases(quick)) <= len(experiment.cases(full))


@pytest.mark.parametrize(
    "argv, message",
    [
        (["experiment", "run", "teleport", "--out", "{out}"], "Unknown experiment 'teleport'"),
        (["experiment", "run", "capture_map", "--workers", "0", "--out", "{out}"], "positive"),
        (["experiment", "scaling", "teleport", "--out", "{out}"], "Unknown experiment 'teleport'"),
        (["experiment", "scaling", "robustness", "--repeats", "0", "--out", "{out}"], "positive"),
    ],
)
def test_bad_input_is_exit_2_with_a_named_error_and_nothing_written(
    tmp_path, capsys, argv, message
):
    out = tmp_path / "out"
    assert cli_main([a.replace("{out}", str(out)) for a in argv]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_a_walk_survives_when_it_neither_fell_nor_was_stopped():
    assert survived({"outcome": "walked", "error": None})
    for outcome in ("fell", "stopped", "interrupted"):
        assert not survived({"outcome": outcome, "fell": False})
    assert not survived({"outcome": "walked", "error": "InfeasibleCommand: too fast"})
    assert survived(SimpleNamespace(metrics=SimpleNamespace(outcome="walked")))
    assert not survived(SimpleNamespace(metrics=SimpleNamespace(outcome="stopped")))
    with pytest.raises(ConfigurationError, match="Expected a row with the walk's 'outcome'"):
        survived({"fell": False})


def test_the_report_helpers_on_known_values():
    assert median([3.0, None, 1.0, 2.0, 10.0]) == 2.5 and median([None]) is None
    text = table(
        [{"a": 1.234, "b": None, "c": True}], [("a", "A", 1), ("b", "B", 0), ("c", "C", 0)]
    )
    assert text == "| A | B | C |\n|---|---|---|\n| 1.2 | - | yes |\n"
    runs = [
        {"command": "mpcwalk experiment run x --out y", "date": "d", "wall_time_s": 90.0,
         "cases_run": 3, "workers": 2, "where": "local Ray instance", "machine": "m"},
    ]  # fmt: skip
    assert runs_text(runs, 3).startswith("3 walks, 1.5 min of wall time in all:")


def test_a_configuration_without_its_file_or_with_bad_toml_is_a_named_error(tmp_path):
    with pytest.raises(ConfigurationError, match="found none"):
        read_config(tmp_path / "none.toml", quick=False)
    (tmp_path / "bad.toml").write_text("robots = [\n")
    with pytest.raises(ConfigurationError, match="Expected TOML"):
        read_config(tmp_path / "bad.toml", quick=True)


@pytest.mark.slow
def test_the_quick_faults_experiment(tmp_path):
    """One case of the outputs' test file, run by pytest in a worker, counted as outputs."""
    out = tmp_path / "faults"
    command = ["experiment", "run", "faults", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    report = (out / "report.md").read_text()
    assert "| outputs | 1 | 1 |" in report
    assert "`tests/test_outputs.py` selected by `-k 'atomic_write'`" in report
    assert "mpcwalk experiment run faults --quick" in report


@pytest.mark.slow
def test_the_quick_performance_experiment(tmp_path):
    """One short walk under cProfile: its ticks, and the parts of a tick within the loop."""
    from mpcwalk.experiments.performance.profile import PARTS
    from mpcwalk.sweep import read_rows

    out = tmp_path / "performance"
    command = ["experiment", "run", "performance", "--quick", "--out", str(out), "--no-progress"]
    assert cli_main(command) == 0
    (row,) = read_rows(out / "results.csv")
    parts = row["parts_us_per_tick"]
    assert row["ticks"] > 100 and not row["fell"] and row["loop_s"] > 0.0
    assert set(parts) == {label for label, _ in PARTS}
    assert (
        0.0 < parts["estimator"] < parts["loop"] and 0.0 < parts["controller tick"] < parts["loop"]
    )
    report = (out / "report.md").read_text()
    assert "| bioloid-like mpc |" in report and "| estimator |" in report
    assert json.loads((out / "runs.json").read_text())[0]["cases_run"] == 1
