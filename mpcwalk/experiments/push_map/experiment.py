"""The push maps as an experiment of the registry (``push_map``): one map per robot, each a
sweep into its own sub-folder (``results/push_map/<robot>``), and one ``report.md`` over
them."""

from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from mpcwalk.experiments.protocol import (
    Experiment,
    ExperimentRun,
    read_config,
    read_table,
    unknown_keys,
)
from mpcwalk.experiments.push_map.cases import PushMapConfig
from mpcwalk.experiments.reporting import read_runs, record_run, runs_text
from mpcwalk.sweep import Sweep, SweepRun, run_sweep


@dataclass(frozen=True)
class PushMapsConfig:
    """The maps, one per robot (:class:`~mpcwalk.experiments.push_map.cases.PushMapConfig`),
    and the mode (``"full"`` or ``"quick"``)."""

    maps: tuple[PushMapConfig, ...]
    mode: str = "full"


def load_push_maps(path: str | Path, *, quick: bool = False, table: str = "maps") -> PushMapsConfig:
    """Read the maps of the array of tables ``table`` from TOML; ``quick`` keeps the
    ``[quick]`` robots and applies the other keys of ``[quick]`` to their maps.

    Raises:
        ConfigurationError: An unknown key, or an unknown actuation.
    """
    data, small = read_config(path, quick=quick)
    names = [f.name for f in fields(PushMapConfig)]
    maps = []
    for values in data.get(table, []):
        unknown_keys(values, names, "maps")
        if quick and values["robot"] not in small.get("robots", [values["robot"]]):
            continue
        merged: dict[str, Any] = {**values, **{k: v for k, v in small.items() if k != "robots"}}
        unknown_keys(merged, names, "quick")
        merged = {k: tuple(v) if isinstance(v, list) else v for k, v in merged.items()}
        maps.append(PushMapConfig(**merged))
    return PushMapsConfig(tuple(maps), "quick" if quick else "full")


class PushMap(Experiment):
    """The largest push each controller survives, per direction, phase and speed."""

    name = "push_map"
    summary = "the largest push each controller survives per direction, phase and speed"
    package = "mpcwalk.experiments.push_map"

    def config(self, *, quick: bool = False) -> PushMapsConfig:
        return load_push_maps(self.config_file, quick=quick)

    def cases(self, config: PushMapsConfig) -> tuple[Any, ...]:
        from mpcwalk.experiments.push_map.cases import push_map_cases

        return tuple(case for one in config.maps for case in push_map_cases(one))

    def sweep(self, config: PushMapsConfig, out: str | Path | None = None) -> Sweep:
        """The first robot's map as a sweep (:meth:`run` runs one per robot)."""
        from mpcwalk.experiments.push_map.cases import push_map_sweep

        return push_map_sweep(config.maps[0])

    def run(
        self,
        out: str | Path,
        *,
        quick: bool = False,
        workers: int | None = None,
        address: str | None = None,
        progress: bool = True,
        overwrite: bool = False,
        command: str | None = None,
    ) -> ExperimentRun:
        """Each robot's map into ``out/<robot>`` (resumable), its figures and report, then
        the ``report.md`` over them."""
        from mpcwalk.experiments.push_map.cases import push_map_sweep

        config = self.config(quick=quick)
        out = Path(out)
        command = command or self.command(out, quick=quick)
        runs: list[SweepRun] = []
        for one in config.maps:
            folder = out / one.folder_name
            run = run_sweep(
                push_map_sweep(one),
                folder,
                workers=workers,
                address=address,
                overwrite=overwrite,
                progress=progress,
            )
            record_run(folder, run, command=command, address=address)
            runs.append(run)
        rows = tuple(row for run in runs for row in run.rows)
        total = SweepRun(
            rows,
            sum(r.nb_cases for r in runs),
            sum(r.nb_run for r in runs),
            sum(r.nb_resumed for r in runs),
            sum(r.wall_time_s for r in runs),
            max((r.workers for r in runs), default=1),
            all(r.complete for r in runs),
        )
        if not total.complete:
            return ExperimentRun(total, None)
        figures = tuple(self.figures(out))
        return ExperimentRun(total, self.report(out), figures)

    def figures(self, out: str | Path) -> list[str]:
        """The figures of every robot's map (paths relative to ``out``)."""
        from mpcwalk.experiments.push_map.report import write_push_figures

        names = []
        for folder in self._folders(out):
            settings, rows = read_table(folder)
            drawn = write_push_figures(folder, rows, _map_config(settings))
            names += [f"{folder.name}/{name}" for name in drawn]
        return names

    def report(self, out: str | Path) -> Path:
        """Each robot's ``report.md`` in its folder, and ``out/report.md`` with every map's
        summary table."""
        from mpcwalk.experiments.push_map.report import (
            lipm_bounds,
            summary_table,
            write_push_report,
        )
        from mpcwalk.robot import load_robot

        out = Path(out)
        parts = ["# Push maps\n"]
        for folder in self._folders(out):
            settings, rows = read_table(folder)
            config = _map_config(settings)
            runs = runs_text(read_runs(folder), len(rows), "cells (a bisection of walks each)")
            shown = sorted(p.name for p in folder.glob("push_*.png"))
            write_push_report(folder, rows, config, runs, figures=shown)
            robot = load_robot(config.robot, visual=False)
            mode = "" if config.actuation == "position" else f" ({config.actuation} control)"
            parts += [
                f"## {config.robot}{mode}\n",
                f"Every table, goal and figure: [{folder.name}/report.md]({folder.name}/report.md).\n",
                summary_table(rows, lipm_bounds(robot, config)),
            ]
        parts += self.extra_sections(out)
        path = out / "report.md"
        path.write_text("\n".join(parts))
        return path

    def extra_sections(self, out: Path) -> list[str]:
        """Sections of ``out/report.md`` after the maps' (none here)."""
        return []

    @staticmethod
    def _folders(out: str | Path) -> list[Path]:
        return sorted(p.parent for p in Path(out).glob("*/sweep.json"))


class PushMapTorque(PushMap):
    """The push maps with the robots torque-controlled beside the same maps with position
    servos, in one run (the ``[[modes]]`` maps of the config): each controller's largest
    push per cell in both modes, and their ratio."""

    name = "push_map_torque"
    summary = "the push maps in torque and in position mode, cell by cell"

    def config(self, *, quick: bool = False) -> PushMapsConfig:
        return load_push_maps(self.config_file, quick=quick, table="modes")

    def extra_sections(self, out: Path) -> list[str]:
        from mpcwalk.experiments.push_map.modes import mode_table

        maps = {}
        for folder in self._folders(out):
            settings, rows = read_table(folder)
            config = _map_config(settings)
            maps[(config.robot, config.actuation)] = rows
        return ["## Torque against position control\n", mode_table(maps)]


def _map_config(settings: dict[str, Any]) -> PushMapConfig:
    names = {f.name for f in fields(PushMapConfig)}
    values: dict[str, Any] = {
        k: tuple(v) if isinstance(v, list) else v for k, v in settings.items() if k in names
    }
    return PushMapConfig(**values)


__all__ = ["PushMap", "PushMapTorque", "PushMapsConfig", "load_push_maps"]
