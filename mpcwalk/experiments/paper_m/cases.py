"""Paper M's long cases on the sweep engine: the push sweep's cells and the speed searches.

Each cell of the push sweep (a controller pushed in one direction at one phase:
:class:`PushCell`) and each speed search (a controller at one step duration:
:class:`SpeedSearch`) is a case of one :class:`~mpcwalk.sweep.Sweep`
(:func:`paper_m_sweep`), run by :func:`run_paper_m_case`: its row streams into
``results.csv``, and a run stopped half-way runs only the missing cases when given again.
:func:`cell_results` and :func:`speed_results` read the rows back.
"""

import json
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

from mpcwalk.experiments.paper_m.config import PaperMConfig, SpeedConfig
from mpcwalk.experiments.paper_m.push_grid import CaseResult, PushSweepConfig, SweepCase
from mpcwalk.experiments.paper_m.walks import push_case_task, speed_task
from mpcwalk.experiments.protocol import settings_of
from mpcwalk.sweep import Sweep
from mpcwalk.walking.specification import ControllerSpec

#: What :func:`run_paper_m_case` returns (push cells: the bisection; speed searches: theirs).
CASE_COLUMNS = (
    "largest_survived_Ns",
    "smallest_fallen_Ns",
    "trials",
    "bound_m_s",
    "fastest_m_s",
    "fastest_measured_m_s",
    "smallest_fallen_m_s",
    "limited_by",
)


@dataclass(frozen=True)
class PushCell:
    """One cell of the push sweep: a controller (name, specification) pushed in one
    direction [deg] at one phase."""

    robot: str
    controller: str
    controller_spec: ControllerSpec = field(compare=False)
    grid: PushSweepConfig
    direction_deg: float
    phase: str

    @property
    def case_id(self) -> str:
        """The part, the controller and the cell."""
        return f"push/{self.controller}/{self.direction_deg:g}/{self.phase}"

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {
            "case_id": self.case_id,
            "part": "push",
            "controller": self.controller,
            "direction_deg": self.direction_deg,
            "phase": self.phase,
            "step_duration_s": None,
        }


@dataclass(frozen=True)
class SpeedSearch:
    """The fastest forward command a controller survives at one step duration [s]."""

    robot: str
    controller: str
    controller_spec: ControllerSpec = field(compare=False)
    speed: SpeedConfig
    step_duration: float

    @property
    def case_id(self) -> str:
        """The part, the controller and the step duration."""
        return f"speed/{self.controller}/{self.step_duration:g}"

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {
            "case_id": self.case_id,
            "part": "speed",
            "controller": self.controller,
            "direction_deg": None,
            "phase": None,
            "step_duration_s": self.step_duration,
        }


def run_paper_m_case(case: PushCell | SpeedSearch) -> dict[str, Any]:
    """Run one case (in a worker): its :data:`CASE_COLUMNS`."""
    values: dict[str, Any] = dict.fromkeys(CASE_COLUMNS)
    if isinstance(case, PushCell):
        cell = SweepCase(case.controller, case.direction_deg, case.phase)
        found = push_case_task(case.robot, case.controller_spec, case.grid, cell)
        record = found.to_dict()
        values.update({key: record[key] for key in ("largest_survived_Ns", "smallest_fallen_Ns")})
        values["trials"] = record["trials"]
        return values
    search = speed_task(case.robot, case.controller_spec, case.speed, case.step_duration)
    values.update({key: search[key] for key in CASE_COLUMNS if key in search})
    return values


def paper_m_cases(
    config: PaperMConfig, controllers: Mapping[str, ControllerSpec]
) -> tuple[PushCell | SpeedSearch, ...]:
    """The push cells, then the speed searches, of the ``controllers`` (name ->
    specification)."""
    cases: list[PushCell | SpeedSearch] = []
    grid, speed = config.push_sweep, config.speed
    if "push" in config.parts:
        for name, spec in controllers.items():
            for direction in grid.directions_deg:
                for phase in grid.phases:
                    cases.append(PushCell(config.robot, name, spec, grid, direction, phase))
    if "speed" in config.parts:
        for name, spec in controllers.items():
            for T in speed.step_durations:
                cases.append(SpeedSearch(config.robot, name, spec, speed, T))
    return tuple(cases)


def paper_m_sweep(config: PaperMConfig, controllers: Mapping[str, ControllerSpec]) -> Sweep:
    """The push cells and speed searches as a sweep of the engine."""
    settings = settings_of(config)
    settings["controllers"] = {
        name: json.loads(json.dumps(asdict(spec), default=str))
        for name, spec in controllers.items()
    }
    return Sweep(
        name="paper-m",
        cases=paper_m_cases(config, controllers),
        runner=run_paper_m_case,
        columns=CASE_COLUMNS,
        settings=settings,
        timeout=3600.0,
    )


def cell_results(rows: Sequence[Mapping[str, Any]]) -> list[CaseResult]:
    """The push cells of the table's rows, as :class:`CaseResult` (the wall time of the
    engine's row)."""
    return [
        CaseResult(
            SweepCase(row["controller"], float(row["direction_deg"]), row["phase"]),
            float(row["largest_survived_Ns"]),
            None if row["smallest_fallen_Ns"] is None else float(row["smallest_fallen_Ns"]),
            tuple((float(value), bool(ok)) for value, ok in row["trials"]),
            float(row["wall_time_s"]),
        )
        for row in rows
        if row["part"] == "push"
    ]


def speed_results(rows: Sequence[Mapping[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    """Controller -> its speed searches, from the table's rows."""
    out: dict[str, list[dict[str, Any]]] = {}
    keys = ("bound_m_s", "fastest_m_s", "fastest_measured_m_s", "smallest_fallen_m_s")
    for row in rows:
        if row["part"] == "speed":
            out.setdefault(row["controller"], []).append(
                {
                    "step_duration_s": row["step_duration_s"],
                    **{key: row[key] for key in keys},
                    "limited_by": row["limited_by"],
                    "trials": row["trials"],
                    "wall_time_s": row["wall_time_s"],
                }
            )
    return out


__all__ = [
    "CASE_COLUMNS",
    "PushCell",
    "SpeedSearch",
    "cell_results",
    "paper_m_cases",
    "paper_m_sweep",
    "run_paper_m_case",
    "speed_results",
]
