"""Paper A's comparison on the sweep engine: each (path, controller) walk a case
(:class:`PathWalk`), its row streamed into ``results.csv`` (resumable); the table
(``table.md``, ``table.json``), the top views (paper A Fig. 5 and 7) and the per-step
placement errors (Fig. 8)."""

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpcwalk.experiments.paper_a.config import DEFAULT_SPECS, PATHS_DIR, PaperAConfig
from mpcwalk.experiments.paper_a.table import PAPER_A_ROW, format_table, plot_placement_errors
from mpcwalk.experiments.paper_a.walks import (
    TimedController,
    placement_errors,
    table_row,
    walk_path,
)
from mpcwalk.experiments.protocol import read_table, settings_of
from mpcwalk.sweep import Sweep, run_sweep


@dataclass(frozen=True)
class PathWalk:
    """One controller on one path: the case of the sweep. ``figure``: where its top view is
    drawn (a PNG file; None: none); ``terrain``: the ground the path crosses (the terrain
    file beside the path, ``<name>.toml``; None: the floor)."""

    spec: TimedController
    path_name: str
    path: str
    robot: str = "atlas-like"
    nb_steps: int | None = None
    figure: str | None = None
    terrain: str | None = None

    @property
    def case_id(self) -> str:
        """The path and the controller's label."""
        return f"{self.path_name}/{self.spec.label}"

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {"case_id": self.case_id, "label": self.spec.label, "path": self.path_name}


#: What :func:`run_path_walk` returns: a row of the table and the per-step errors.
ROW_COLUMNS = (
    "row",
    "position_errors_cm",
    "yaw_errors_deg",
)


def run_path_walk(case: PathWalk) -> dict[str, Any]:
    """Walk one case (in a worker): its row of the table, its per-step errors, and its top
    view drawn to ``case.figure``."""
    result = walk_path(
        case.spec, case.path, nb_steps=case.nb_steps, robot=case.robot, terrain=case.terrain
    )
    if case.figure and len(result.log):
        import matplotlib.pyplot as plt

        from mpcwalk.walking.figures import plot_walk_top_view

        title = f"{case.path_name}: {case.spec.label}"
        fig = plot_walk_top_view(result.schedule, result.log, title=title)
        fig.savefig(case.figure, dpi=100, bbox_inches="tight")
        plt.close(fig)
    positions, yaws = placement_errors(result)
    return {
        "row": table_row(case.spec, case.path_name, result),
        "position_errors_cm": [float(v) for v in positions],
        "yaw_errors_deg": [float(v) for v in yaws],
    }


def top_view_name(spec: TimedController, path_name: str) -> str:
    """The file name of a walk's top view."""
    return f"top_{path_name}_{spec.generator}_{spec.step_duration:g}s.png"


def paper_a_sweep(
    config: PaperAConfig, out: str | Path | None = None, *, path_dir=PATHS_DIR
) -> Sweep:
    """The walks of ``config`` as a sweep (their top views drawn into ``out``, if given); a
    path with a terrain file beside it (``<name>.toml``) is walked on that terrain."""
    cases = []
    for name in config.paths:
        ground = Path(path_dir) / f"{name}.toml"
        terrain = str(ground) if ground.is_file() else None
        for spec in config.specs:
            slow = spec.step_duration >= 3.0 and config.slow_nb_steps
            steps = config.slow_nb_steps if slow else config.nb_steps
            figure = None if out is None else str(Path(out) / top_view_name(spec, name))
            path = str(Path(path_dir) / f"{name}.mdat")
            cases.append(PathWalk(spec, name, path, config.robot, steps, figure, terrain))
    return Sweep(
        name="paper-a",
        cases=tuple(cases),
        runner=run_path_walk,
        columns=ROW_COLUMNS,
        settings=settings_of(config),
    )


def write_figures(out: str | Path) -> list[str]:
    """The placement errors of each path's walks (``placement_errors_<path>.png``)."""
    import matplotlib.pyplot as plt

    out = Path(out)
    _, rows = read_table(out)
    names = []
    for path in dict.fromkeys(row["path"] for row in rows):
        entries = [
            (row["label"], row["position_errors_cm"], row["yaw_errors_deg"])
            for row in rows
            if row["path"] == path and not row.get("error")
        ]
        fig = plot_placement_errors(entries, title=f"{path}: foot placement errors")
        name = f"placement_errors_{path}.png"
        fig.savefig(out / name, dpi=100, bbox_inches="tight")
        plt.close(fig)
        names.append(name)
    return names


def write_table(out: str | Path) -> list[dict]:
    """``table.md`` and ``table.json`` from the rows in ``out``; the table's rows."""
    out = Path(out)
    settings, rows = read_table(out)
    table = [row["row"] for row in rows if row.get("row")]
    (out / "table.md").write_text(format_table(table))
    payload = {"paper_a": PAPER_A_ROW, "rows": table, **settings}
    (out / "table.json").write_text(json.dumps(payload, indent=2) + "\n")
    return table


def run_paper_a(
    out_dir,
    *,
    specs: Sequence[TimedController] = DEFAULT_SPECS,
    experiments: Sequence[str] = ("straight", "turning", "ramp"),
    nb_steps: int | None = None,
    slow_nb_steps: int | None = None,
    path_dir=PATHS_DIR,
    plots: bool = True,
    workers: int | None = None,
    progress: bool = False,
) -> list[dict]:
    """Run every controller on every path (on the sweep engine) and write the table and the
    figures into ``out_dir``.

    Args:
        out_dir: Output directory (created).
        specs: Controllers.
        experiments: Path names (``<path_dir>/<name>.mdat``).
        nb_steps: Steps kept from each path (None: all).
        slow_nb_steps: Steps kept for controllers with T >= 3 s (None: as ``nb_steps``).
        path_dir: Directory of the ``.mdat`` files.
        plots: Write the figures.
        workers: Walks at once (None: one per core).
        progress: Show a progress bar.

    Returns:
        The table rows.
    """
    config = PaperAConfig(tuple(specs), tuple(experiments), "atlas-like", nb_steps, slow_nb_steps)
    out = Path(out_dir)
    sweep = paper_a_sweep(config, out if plots else None, path_dir=path_dir)
    run_sweep(sweep, out, workers=workers, progress=progress)
    if plots:
        write_figures(out)
    return write_table(out)


__all__ = [
    "PathWalk",
    "paper_a_sweep",
    "run_paper_a",
    "run_path_walk",
    "top_view_name",
    "write_figures",
    "write_table",
]
