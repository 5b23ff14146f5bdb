"""The LIPM's push-recovery map as an experiment of the registry (``capture_map``): one case
per robot, its cells in the row."""

from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from mpcwalk.experiments.capture_map.cells import CaptureCell
from mpcwalk.experiments.protocol import (
    Experiment,
    mode_name,
    read_config,
    read_table,
    settings_of,
    unknown_keys,
)
from mpcwalk.experiments.reporting import median, read_runs, runs_text
from mpcwalk.sweep import Sweep


@dataclass(frozen=True)
class CaptureMapConfig:
    """The robots and the grid of the maps (see its ``config.toml``)."""

    robots: tuple[str, ...] = ("bioloid-like", "g1")
    nb_directions: int = 16
    nb_phases: int = 6
    mode: str = "full"


@dataclass(frozen=True)
class CaptureCase:
    """One robot's map."""

    robot: str
    nb_directions: int
    nb_phases: int

    @property
    def case_id(self) -> str:
        """The robot."""
        return self.robot

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {"case_id": self.case_id, "robot": self.robot}


def run_capture_case(case: CaptureCase) -> dict[str, Any]:
    """The cells of one robot's map (in a worker)."""
    from mpcwalk.experiments.capture_map.cells import capture_map
    from mpcwalk.walking.sweep_cases import worker_robot

    cells = capture_map(
        worker_robot(case.robot), nb_directions=case.nb_directions, nb_phases=case.nb_phases
    )
    return {"cells": [asdict(cell) for cell in cells]}


def _cells(row: dict[str, Any]) -> list[CaptureCell]:
    return [
        CaptureCell(
            c["direction_deg"],
            c["phase"],
            c["single_support"],
            tuple(c["fixed"]),
            tuple(c["adaptive"]),
            tuple(c.get("flywheel", (0.0, 0.0, 0.0))),
        )
        for c in row["cells"]
    ]


class CaptureMap(Experiment):
    """The LIPM's push-recovery map of each robot, the reference of the push maps."""

    name = "capture_map"
    summary = "the LIPM's push-recovery map of each robot with 0, 1 and 2 steps"
    package = "mpcwalk.experiments.capture_map"

    def config(self, *, quick: bool = False) -> CaptureMapConfig:
        data, small = read_config(self.config_file, quick=quick)
        keys = ("robots", "nb_directions", "nb_phases")
        unknown_keys(data, keys, "capture_map")
        unknown_keys(small, keys, "quick")
        values = {**data, **small}
        return CaptureMapConfig(
            tuple(values["robots"]),
            int(values["nb_directions"]),
            int(values["nb_phases"]),
            mode_name(quick),
        )

    def cases(self, config: CaptureMapConfig) -> tuple[CaptureCase, ...]:
        return tuple(
            CaptureCase(robot, config.nb_directions, config.nb_phases) for robot in config.robots
        )

    def sweep(self, config: CaptureMapConfig, out: str | Path | None = None) -> Sweep:
        return Sweep(
            name="capture-map",
            cases=self.cases(config),
            runner=run_capture_case,
            columns=("cells",),
            settings=settings_of(config),
        )

    def figures(self, out: str | Path) -> list[str]:
        from mpcwalk.experiments.capture_map.plots import polar_figure

        names = []
        for row in read_table(out)[1]:
            name = f"capture_map_{row['robot']}.png"
            polar_figure(row["robot"], _cells(row), Path(out) / name)
            names.append(name)
        return names

    def report(self, out: str | Path) -> Path:
        out = Path(out)
        settings, rows = read_table(out)
        lines = [
            "# The LIPM's push-recovery map",
            "",
            runs_text(read_runs(out), len(rows), "robots"),
            "The largest impulse [N s] of a 0.1 s push a linear inverted pendulum with the "
            "robot's mass, CoM height, soles, leg limits and timing recovers, with at most 0, "
            "1 and 2 steps (`mpcwalk.footsteps.capturability`, Koolen 2012), along its nominal "
            f"straight walk, {settings['nb_directions']} directions x {settings['nb_phases']} "
            "phases of the third step; first landing at the schedule's time (fixed) or at the "
            "best time the swing allows (adapted, down to a 0.15 s swing). No cross-over step: "
            "a push towards the stance leg can only be caught by the ankle or by the stance "
            "leg's own step after the swing leg's. In double support the robot stands on the "
            "hull of both soles. The walk is at the robot's nominal speed (a walk's default "
            "command), as in the push maps.",
            "",
            "| robot | steps | median over cells, fixed timing | smallest cell, fixed | "
            "median, timing adapted | smallest cell, adapted |",
            "|---|---:|---:|---:|---:|---:|",
        ]
        for row in rows:
            cells = _cells(row)
            for n in range(3):
                fixed = [c.fixed[n] for c in cells]
                adaptive = [c.adaptive[n] for c in cells]
                lines.append(
                    f"| {row['robot']} | {n} | {median(fixed):.2f} | {min(fixed):.2f} | "
                    f"{median(adaptive):.2f} | {min(adaptive):.2f} |"
                )
        names = sorted(p.name for p in out.glob("capture_map_*.png"))
        lines += [""] + [f"![{name}]({name})" for name in names]
        path = out / "report.md"
        path.write_text("\n".join(lines) + "\n")
        return path


__all__ = ["CaptureCase", "CaptureMap", "CaptureMapConfig", "run_capture_case"]
