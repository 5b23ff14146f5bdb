"""The profile of a control tick as an experiment of the registry (``performance``)."""

import platform
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpcwalk.experiments.protocol import (
    Experiment,
    mode_name,
    read_config,
    read_table,
    settings_of,
    unknown_keys,
)
from mpcwalk.experiments.reporting import read_runs, runs_text
from mpcwalk.sweep import Sweep


@dataclass(frozen=True)
class ProfiledWalk:
    """One walk to profile: robot, pattern generator, command ``(vx, vy, vyaw)``, steps."""

    robot: str
    generator: str
    command: tuple[float, float, float]
    nb_steps: int

    @property
    def case_id(self) -> str:
        """Robot, generator, command and steps."""
        return f"{self.robot}/{self.generator}/{self.command}/{self.nb_steps}"

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {
            "case_id": self.case_id,
            "robot": self.robot,
            "generator": self.generator,
            "nb_steps": self.nb_steps,
        }


@dataclass(frozen=True)
class PerformanceConfig:
    """The walks profiled."""

    walks: tuple[ProfiledWalk, ...]
    mode: str = "full"


def run_profiled_walk(case: ProfiledWalk) -> dict[str, Any]:
    """Profile one walk (in a worker): ticks, fall, loop time, microseconds per part."""
    from mpcwalk.experiments.performance.profile import profile_walk

    row = profile_walk(case.robot, case.generator, case.command, case.nb_steps)
    return {key: row[key] for key in ("ticks", "fell", "loop_s", "parts_us_per_tick")}


class Performance(Experiment):
    """Where a control tick's time goes: whole walks under ``cProfile``."""

    name = "performance"
    summary = "where a control tick's time goes: a profile of whole walks"
    package = "mpcwalk.experiments.performance"

    def config(self, *, quick: bool = False) -> PerformanceConfig:
        data, small = read_config(self.config_file, quick=quick)
        unknown_keys(data, ("walks", "nb_steps"), "performance")
        unknown_keys(small, ("walks", "nb_steps"), "quick")
        values = {**data, **small}
        walks = tuple(
            ProfiledWalk(
                robot, generator, (float(vx), float(vy), float(vyaw)), int(values["nb_steps"])
            )
            for robot, generator, (vx, vy, vyaw) in values["walks"]
        )
        return PerformanceConfig(walks, mode_name(quick))

    def cases(self, config: PerformanceConfig) -> tuple[ProfiledWalk, ...]:
        return config.walks

    def sweep(self, config: PerformanceConfig, out: str | Path | None = None) -> Sweep:
        return Sweep(
            name="performance",
            cases=self.cases(config),
            runner=run_profiled_walk,
            columns=("ticks", "fell", "loop_s", "parts_us_per_tick"),
            settings=settings_of(config),
        )

    def report(self, out: str | Path) -> Path:
        from mpcwalk.experiments.performance.profile import PARTS

        out = Path(out)
        _, rows = read_table(out)
        steps = sorted({row["nb_steps"] for row in rows})
        lines = [
            "# Where a control tick's time goes",
            "",
            runs_text(read_runs(out), len(rows)),
            f"Each walk ({', '.join(map(str, steps))} steps, default sensors and estimator) run "
            "once under `cProfile`. Microseconds per 10 ms control tick, cumulative per part "
            "(the profiler slows the Python parts more than MuJoCo and the solvers: shares are "
            "indicative; the unprofiled timings are `mpcwalk bench loop`'s).",
            f"Machine: {platform.machine()}, Python {platform.python_version()}.",
            "",
            "| part | " + " | ".join(f"{r['robot']} {r['generator']}" for r in rows) + " |",
            "|---|" + "---:|" * len(rows),
        ]
        for label, _ in PARTS:
            cells = " | ".join(f"{r['parts_us_per_tick'][label]:.0f}" for r in rows)
            lines.append(f"| {label} | {cells} |")
        path = out / "report.md"
        path.write_text("\n".join(lines) + "\n")
        return path


__all__ = ["Performance", "PerformanceConfig", "ProfiledWalk", "run_profiled_walk"]
