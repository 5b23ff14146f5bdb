"""The sweep engine: cases as Ray tasks, rows streamed into a table, nothing lost, nothing
repeated."""

import math
import sys
from dataclasses import dataclass

import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.sweep import TIMING_COLUMNS, Sweep, read_rows, run_sweep

pytestmark = pytest.mark.slow


@dataclass(frozen=True)
class Case:
    """A case of the engine's tests: a number, its seed."""

    value: float
    seed: int = 0

    @property
    def case_id(self) -> str:
        return f"v{self.value:g}-s{self.seed}"

    def to_columns(self) -> dict:
        return {"case_id": self.case_id, "value": self.value, "seed": self.seed}


def square_root(case: Case) -> dict:
    """The runner: raises on a negative value (a case that raises)."""
    return {"root": math.sqrt(case.value), "seeded": case.value * 1000 + case.seed}


@pytest.fixture(scope="module", autouse=True)
def _pickled_by_value():
    """Ray's workers do not have the tests folder on their path: send this module's
    functions by value."""
    import ray

    ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])
    yield
    ray.cloudpickle.unregister_pickle_by_value(sys.modules[__name__])


CASES = tuple(Case(v, seed) for v in (16.0, 1.0, -4.0, 9.0, 2.0) for seed in (0, 1))


def sweep(**settings) -> Sweep:
    return Sweep("roots", CASES, square_root, ("root", "seeded"), settings=settings)


def without_timing(rows):
    return [{k: v for k, v in row.items() if k not in TIMING_COLUMNS} for row in rows]


def test_a_killed_sweep_resumes_with_only_the_missing_cases(tmp_path):
    """Stopped after 4 cases (as a kill would leave it: rows appended as they came), the
    same command runs the 6 missing ones only, and the table equals an uninterrupted run's;
    the case that raises is a row with its error, the others have no error."""
    first = run_sweep(sweep(), tmp_path / "a", workers=2, max_cases=4, progress=False)
    assert not first.complete and first.nb_run == 4 and len(first.rows) == 4
    second = run_sweep(sweep(), tmp_path / "a", workers=2, progress=False)
    assert second.complete and second.nb_resumed == 4 and second.nb_run == 6
    whole = run_sweep(sweep(), tmp_path / "b", workers=1, progress=False)
    assert whole.nb_run == 10
    assert without_timing(second.rows) == without_timing(whole.rows)
    assert without_timing(read_rows(tmp_path / "a" / "results.csv")) == without_timing(whole.rows)
    errors = {row["case_id"]: row["error"] for row in whole.rows}
    assert errors["v-4-s0"].startswith("ValueError: math domain error")
    assert all(error is None for case_id, error in errors.items() if not case_id.startswith("v-4"))
    assert [row["case_id"] for row in whole.rows] == [case.case_id for case in CASES]
    assert whole.rows[0]["root"] == 4.0 and whole.rows[1]["seeded"] == 16001.0
    # run again: nothing to do
    third = run_sweep(sweep(), tmp_path / "a", workers=2, progress=False)
    assert third.nb_run == 0 and third.nb_resumed == 10


def test_a_case_id_of_digits_stays_text(tmp_path):
    """A walk's case id is 16 hexadecimal digits: one of digits and an "e" reads as a float
    (inf), one of digits alone as an integer; the table keeps them as text."""
    path = tmp_path / "results.csv"
    path.write_text("case_id,value\n723882e344680145,1.5\n0123456789012345,2\nab12,x\n")
    rows = read_rows(path)
    assert [r["case_id"] for r in rows] == ["723882e344680145", "0123456789012345", "ab12"]
    assert [r["value"] for r in rows] == [1.5, 2, "x"]


def test_a_changed_configuration_is_refused_unless_overwritten(tmp_path):
    run_sweep(sweep(level=1), tmp_path, workers=1, max_cases=1, progress=False)
    with pytest.raises(ConfigurationError, match="another configuration.*--overwrite"):
        run_sweep(sweep(level=2), tmp_path, workers=1, progress=False)
    again = run_sweep(sweep(level=2), tmp_path, workers=1, overwrite=True, progress=False)
    assert again.complete and again.nb_resumed == 0
    with pytest.raises(ConfigurationError, match="positive integer"):
        run_sweep(sweep(), tmp_path / "c", workers=0, progress=False)


def test_walk_specifications_are_the_cases_of_a_sweep(tmp_path):
    """Two short walks as the cases of a sweep: each row holds its specification's id and
    columns (labels among them) and what the walk measured; a row gives its walk back, and
    the same sweep again runs nothing."""
    from mpcwalk.walking.specification import WalkSpec
    from mpcwalk.walking.sweep_cases import (
        CASE_COLUMNS,
        WALK_COLUMNS,
        run_walk_case,
        spec_of_row,
    )

    base = WalkSpec.build("bioloid-like", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=2)
    heavy = base.replace(mass_scale=1.1, seed=2, labels={"group": "heavy"})
    walks = Sweep("walks", (base, heavy), run_walk_case, WALK_COLUMNS)
    assert walks.table_columns()[: len(CASE_COLUMNS)] == list(CASE_COLUMNS)
    run = run_sweep(walks, tmp_path, workers=1, progress=False)
    assert run.complete and run.nb_run == 2
    rows = {row["case_id"]: row for row in run.rows}
    assert list(rows) == [base.case_id, heavy.case_id]
    for spec in (base, heavy):
        row = rows[spec.case_id]
        assert row["error"] is None and row["fell"] is False and row["steps_planned"] == 3
        assert spec_of_row(row) == spec.replace(labels=())
    assert rows[heavy.case_id]["group"] == "heavy" and rows[heavy.case_id]["mass_scale"] == 1.1
    assert rows[base.case_id]["group"] is None
    again = run_sweep(walks, tmp_path, workers=1, progress=False)
    assert again.nb_run == 0 and again.nb_resumed == 2


def test_a_row_gives_back_its_walk_in_either_actuation():
    """A torque walk's row names its actuation, so the walk it gives back (and the command
    that reruns it) is the torque walk, with the same id; a row written before the column
    existed is a position walk."""
    from mpcwalk.walking.specification import WalkSpec
    from mpcwalk.walking.sweep_cases import spec_of_row

    spec = WalkSpec.build("g1", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=8)
    torque = spec.replace(actuation="torque", ground_roughness=0.0054, seed=128)
    row = torque.to_columns()
    assert row["actuation"] == "torque" and spec.to_columns()["actuation"] == "position"
    assert spec_of_row(row).case_id == torque.case_id != spec_of_row(spec.to_columns()).case_id
    assert "--actuation torque" in spec_of_row(row).command_line()
    older = {k: v for k, v in row.items() if k != "actuation"}
    assert spec_of_row(older).world.actuation == "position"


def test_a_table_of_older_columns_is_rewritten_under_the_new_ones(tmp_path):
    """A table written before the engine's ``cpu_time_s`` and ``node`` columns (the same
    configuration) is rewritten with them, its rows kept and the new cells empty; the missing cases then run
    into it, and the finished table has every column."""
    from mpcwalk.sweep.table import ResultsTable

    settings = {"runner": f"{__name__}.square_root", "columns": ["root", "seeded"]}
    columns = sweep().table_columns()
    assert columns[-1] == "node"
    ResultsTable(
        tmp_path,
        name="roots",
        settings=settings,
        case_ids=[c.case_id for c in CASES],
        columns=columns,
    )
    before = [c for c in columns if c not in ("cpu_time_s", "node")]
    old = ",".join(before) + "\nv16-s0,16.0,0,4.0,16000.0,,0.5,host:1\n"
    (tmp_path / "results.csv").write_text(old)
    run = run_sweep(sweep(), tmp_path, workers=1, progress=False)
    assert run.nb_resumed == 1 and run.nb_run == 9 and run.complete
    rows = read_rows(tmp_path / "results.csv")
    assert list(rows[0]) == columns
    assert rows[0]["worker"] == "host:1" and rows[0]["root"] == 4.0
    assert rows[0]["node"] is None and rows[0]["cpu_time_s"] is None
    assert all(isinstance(row["node"], str) and len(row["node"]) == 56 for row in rows[1:])
    assert all(0.0 <= row["cpu_time_s"] < 5.0 for row in rows[1:])


def test_a_sweep_grown_in_a_table_of_its_settings_keeps_its_rows(tmp_path):
    """A controller added to one robot's list in a table of robots: grown; a robot's other
    setting changed: another configuration."""

    def robots(controllers, steps=8):
        return {
            "robots": {
                "a": {"controllers": controllers, "steps": steps},
                "b": {"controllers": ["x"], "steps": 8},
            }
        }

    run_sweep(sweep(**robots(["x"])), tmp_path, workers=1, progress=False)
    grown = run_sweep(sweep(**robots(["x", "y"])), tmp_path, workers=1, progress=False)
    assert grown.complete and grown.nb_run == 0 and grown.nb_resumed == len(CASES)
    with pytest.raises(ConfigurationError, match="another configuration"):
        run_sweep(sweep(**robots(["x", "y"], steps=6)), tmp_path, workers=1, progress=False)


def test_a_sweep_grown_along_its_axes_keeps_the_rows_it_shares(tmp_path):
    """One more value in a list setting (a controller added to a map) with every earlier
    case kept: the folder is taken over with its rows and only the new cases run. A list that
    loses a value, or any other setting changed, is still another configuration."""
    grown = Sweep(
        "roots",
        CASES + (Case(25.0),),
        square_root,
        ("root", "seeded"),
        settings={"values": [1, 2, 3]},
    )
    run_sweep(sweep(values=[1, 2]), tmp_path, workers=1, max_cases=3, progress=False)
    first = read_rows(tmp_path / "results.csv")
    again = run_sweep(grown, tmp_path, workers=1, progress=False)
    assert again.complete and again.nb_resumed == 3 and again.nb_run == len(CASES) + 1 - 3
    assert without_timing(again.rows[:3]) == without_timing(first)
    for settings in ({"values": [1, 2]}, {"values": [1, 2, 3], "level": 1}):
        with pytest.raises(ConfigurationError, match="another configuration"):
            run_sweep(sweep(**settings), tmp_path, workers=1, progress=False)
    fewer = Sweep(
        "roots", CASES[:4], square_root, ("root", "seeded"), settings={"values": [1, 2, 3]}
    )
    with pytest.raises(ConfigurationError, match="another configuration"):
        run_sweep(fewer, tmp_path, workers=1, progress=False)
