"""The report of the robustness matrix: success rates with Wilson intervals, the goals
(:mod:`~mpcwalk.experiments.robustness.goals`), the terrain walks and the skipped worlds
(:mod:`~mpcwalk.experiments.robustness.terrain_report`), the worst cases with the command
that reruns each, and the quality of the walks that succeed.

A walk *succeeds* when it ran (no error) and survived
(:func:`~mpcwalk.experiments.survival.survived`: it neither fell nor was stopped by the
controller). The tables read the rows of the
matrix's results table (:func:`mpcwalk.sweep.read_rows`); :func:`write_report` writes
``report.md`` (the figures: :mod:`mpcwalk.experiments.robustness.plots`).
"""

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from mpcwalk.experiments.reporting import median, table
from mpcwalk.experiments.robustness.cells import (
    GOAL_CONTROLLERS,
    REFERENCE,
    cell_rows,
    present_cells,
    rate,
    rate_text,
    robots_and_controllers,
)
from mpcwalk.experiments.robustness.factors import FACTORS, LEVEL_UNITS
from mpcwalk.experiments.robustness.goals import goal_checks, goals_text
from mpcwalk.experiments.robustness.terrain_report import (
    skipped_text,
    terrain_command,
    terrain_goal_text,
    terrain_table,
    terrain_words,
    write_terrain_files,
)
from mpcwalk.experiments.survival import survived

CELLS = ("nominal", *FACTORS, "single", "terrain", "combination")
TERRAIN_NOTE = (
    "Reached it, crossed it: the walk completed the steps that put a foot beyond the "
    "terrain's first edge, both beyond its far end, at the nominal stride (the footsteps on "
    "a terrain go further). A terrain walk below reruns from this folder: its command reads "
    "its terrain from `terrains/ROBOT-SEED.toml`.\n"
)


def success_table(rows: Sequence[dict], robot: str, controllers: Sequence[str]) -> str:
    """Success per factor (a line) and controller (a column), with 95 % Wilson intervals;
    the cells that hold a walk."""
    titles = {
        "single": "**every single factor on the floor**",
        "terrain": "**every terrain factor**",
        "combination": "**combinations**",
    }
    lines = []
    for cell in present_cells(rows, CELLS):
        entry: dict[str, Any] = {"cell": titles.get(cell, cell)}
        for controller in controllers:
            entry[controller] = rate_text(*rate(cell_rows(rows, robot, controller, cell)))
        lines.append(entry)
    return table(lines, [("cell", "factor", 0)] + [(c, c, 0) for c in controllers])


def world_text(row: dict[str, Any]) -> str:
    """What a walk's world changed, in words."""
    parts = []
    if "command" in str(row["factor"]).split("+"):
        parts.append(f"v ({row['vx']:g}, {row['vy']:g}, {row['vyaw']:g})")
    for start, duration, fx, fy, _ in row.get("pushes") or []:
        impulse = math.hypot(fx, fy) * duration
        angle = math.degrees(math.atan2(fy, fx)) % 360.0
        parts.append(f"push {impulse:.2f} N s at {angle:.0f} deg, t {start:g} s")
    for key, label, nominal in (
        ("mass_scale", "mass x", 1.0),
        ("friction", "mu ", None),
        ("noise_scale", "noise x", 1.0),
        ("latency_periods", "latency ", None),
        ("servo_strength", "servo x", 1.0),
        ("ground_tilt", "tilt (deg) ", 0.0),
        ("ground_roughness", "bumps (m) ", 0.0),
    ):
        if row.get(key) not in (nominal, None):
            parts.append(f"{label}{row[key]:g}")
    if row.get("com_dx") or row.get("com_dy"):
        parts.append(f"com ({100 * row['com_dx']:.1f}, {100 * row['com_dy']:.1f}) cm")
    if row.get("layout"):
        parts.append(terrain_words(row))
    return "; ".join(parts) or "nominal"


def worst_cases(
    rows: Sequence[dict],
    *,
    limit: int = 30,
    terrain_files: Mapping[str, str] | None = None,
    terrain_cadence: bool = False,
) -> str:
    """The walks that did not survive (fell, stopped, or could not run), the goals' first,
    earliest falls first, each with the ``mpcwalk walk`` command that reruns it (a terrain
    walk's with its terrain file, ``terrain_files``: case id -> path in the folder; and at
    the terrain cadence when the matrix walked its terrains so, ``terrain_cadence``)."""
    failed = [row for row in rows if not survived(row)]
    if not failed:
        return "Every walk survived.\n"

    def key(row):
        return (row["controller"] not in GOAL_CONTROLLERS, row.get("fall_time_s") or 0.0)

    files = terrain_files or {}
    lines = []
    for row in sorted(failed, key=key)[:limit]:
        steps = f", {row['steps_completed']}/{row['steps_planned']} steps"
        if row.get("error"):
            what, steps = f"could not run: {row['error']}", ""
        elif row.get("outcome") == "fell":
            what = f"fell at {row['fall_time_s']:.1f} s ({row['fall_reason']})"
        else:
            what = f"{row.get('outcome')} by the controller"
        lines.append(
            f"- `{row['case_id']}` {row['robot']}, {row['controller']}, {row['factor']}: "
            f"{world_text(row)}; {what}{steps}\n"
            f"  `{terrain_command(row, files.get(str(row['case_id'])), terrain_cadence)}`"
        )
    more = len(failed) - len(lines)
    tail = f"\n\n({more} more in `results.csv`.)" if more > 0 else ""
    return (
        f"{len(failed)} walks fell, were stopped or could not run.\n\n"
        + "\n".join(lines)
        + tail
        + "\n"
    )


def quality_table(rows: Sequence[dict]) -> str:
    """Median foot placement error and CoP margin of the walks that succeed."""
    lines = []
    for robot, controllers in robots_and_controllers(rows).items():
        for controller in controllers:
            ok = [
                r
                for r in rows
                if r["robot"] == robot and r["controller"] == controller and survived(r)
            ]
            margin = median(r["cop_margin_p05_m"] for r in ok)
            lines.append(
                {
                    "robot": robot,
                    "controller": controller,
                    "n": len(ok),
                    "foot": median(r["foot_position_error_cm_mean"] for r in ok),
                    "step": median(r["foot_step_error_cm_max"] for r in ok),
                    "margin": None if margin is None else 1e3 * margin,
                }
            )
    return table(
        lines,
        [
            ("robot", "robot", 0),
            ("controller", "controller", 0),
            ("n", "walks that succeed", 0),
            ("foot", "foot placement error, mean of a walk [cm]", 2),
            ("step", "step error, max of a walk [cm]", 2),
            ("margin", "CoP margin, 5th percentile of a walk [mm]", 1),
        ],
    )


def levels_text(rows: Sequence[dict] = ()) -> str:
    """What the level of each factor is (of the factors of ``rows``; none: every factor)."""
    present = {str(r["factor"]) for r in rows}
    return "; ".join(
        f"{factor}: {unit}"
        for factor, unit in LEVEL_UNITS.items()
        if not present or factor in present
    )


def write_report(
    out_dir: str | Path,
    rows: Sequence[dict],
    *,
    header: str,
    scaling: str = "",
    figures: Sequence[str] = (),
    skipped: Sequence[Mapping[str, Any]] = (),
    terrain_cadence: bool = False,
) -> Path:
    """Write ``report.md`` into ``out_dir`` (showing the ``figures``, file names of
    :func:`~mpcwalk.experiments.robustness.plots.write_figures`; the worlds ``skipped``
    for their terrain; the terrain files of the terrain walks that did not survive, in
    ``terrains/``; their commands at the terrain cadence with ``terrain_cadence``);
    returns its path."""
    out = Path(out_dir)
    names = list(figures)
    parts = [header, "## Goals of the QP controllers\n", goals_text(goal_checks(rows))]
    by_robot = robots_and_controllers(rows)
    parts.append("## Success rates (95 % Wilson intervals)\n")
    for robot, controllers in by_robot.items():
        parts += [f"### {robot}\n", success_table(rows, robot, controllers)]
    parts += [f"Levels: {levels_text(rows)}.\n"]
    terrain = terrain_table(rows)
    if terrain or skipped:
        parts += ["## On terrain\n", terrain_goal_text(rows), terrain]
        parts += [skipped_text(skipped), TERRAIN_NOTE]
    files = write_terrain_files(out, [r for r in rows if not survived(r)])
    parts += [
        "## The walks that succeed\n",
        quality_table(rows),
        "## Worst cases\n",
        worst_cases(rows, terrain_files=files, terrain_cadence=terrain_cadence),
    ]
    if names:
        parts += ["## Figures\n", "\n".join(f"![{n}]({n})" for n in names) + "\n"]
    if scaling:
        parts += ["## Scaling of the engine\n", scaling]
    path = out / "report.md"
    path.write_text("\n".join(parts))
    return path


__all__ = [
    "GOAL_CONTROLLERS",
    "REFERENCE",
    "cell_rows",
    "goal_checks",
    "quality_table",
    "rate",
    "robots_and_controllers",
    "success_table",
    "worst_cases",
    "write_report",
]
