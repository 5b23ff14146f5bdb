"""The terrain part of the robustness matrix's report: the terrain walks per factor (how
many walked, reached and crossed the terrain, how they landed and swung), the worlds skipped
because their terrain does not fit the robot, and the terrain files that rerun a walk.

A terrain walk's row holds its terrain in its ``layout`` column
(:data:`~mpcwalk.experiments.robustness.terrains.LAYOUT_LABEL`).
"""

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from mpcwalk.experiments.reporting import median, table
from mpcwalk.experiments.robustness.cells import (
    GOAL_TERRAIN,
    TERRAIN_CONTROLLER,
    cell_rows,
    rate,
    rate_text,
    robots_and_controllers,
)
from mpcwalk.experiments.robustness.terrains import (
    LAYOUT_LABEL,
    MILESTONES_LABEL,
    TERRAIN_FACTORS,
    describe,
    terrain_of_text,
)
from mpcwalk.terrain import terrain_to_toml

#: Folder of the terrain files of the walks that did not survive, in the results folder.
TERRAIN_DIR = "terrains"


def terrain_words(row: Mapping[str, Any]) -> str:
    """The terrain of a row, in words."""
    return describe(terrain_of_text(row[LAYOUT_LABEL]))


def terrain_command(
    row: Mapping[str, Any], terrain_file: str | None = None, terrain_cadence: bool = False
) -> str:
    """The ``mpcwalk walk`` command that walks a row again alone; on a terrain, reading it
    from ``terrain_file`` (a path in the results folder; None: ``terrain.toml``), at the
    terrain cadence with ``terrain_cadence``."""
    from mpcwalk.walking.sweep_cases import spec_of_row

    spec = spec_of_row(dict(row))
    if not row.get(LAYOUT_LABEL):
        return spec.command_line()
    terrain = terrain_of_text(row[LAYOUT_LABEL])
    spec = spec.replace(terrain=terrain, terrain_cadence=terrain_cadence)
    line = spec.command_line()
    return line if terrain_file is None else line.replace("terrain.toml", terrain_file, 1)


def write_terrain_files(out: str | Path, rows: Sequence[Mapping[str, Any]]) -> dict[str, str]:
    """The terrain file of each terrain walk of ``rows`` in ``out/terrains`` (one per robot
    and world seed); case id -> its path in ``out``."""
    files = {}
    for row in rows:
        if not row.get(LAYOUT_LABEL):
            continue
        name = f"{TERRAIN_DIR}/{row['robot']}-{row['seed']}.toml"
        path = Path(out) / name
        if not path.exists():
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(terrain_to_toml(terrain_of_text(row[LAYOUT_LABEL])))
        files[str(row["case_id"])] = name
    return files


def _min(values) -> float | None:
    present = [v for v in values if v is not None]
    return min(present) if present else None


def terrain_table(rows: Sequence[dict[str, Any]]) -> str:
    """The single-factor terrain walks per robot, controller and terrain factor: the walks
    that walked, that reached the terrain and that crossed it (completed the steps that put
    a foot beyond its first edge, both beyond its far end: the ``terrain_steps`` label), and
    the terrain metrics; empty without a terrain walk."""
    lines = []
    for robot, controllers in robots_and_controllers(rows).items():
        for controller in controllers:
            for factor in TERRAIN_FACTORS:
                mine = [
                    r
                    for r in rows
                    if r["robot"] == robot
                    and r["controller"] == controller
                    and r["group"] == "single"
                    and r["factor"] == factor
                ]
                if not mine:
                    continue
                done = [(int(r.get("steps_completed") or 0), r[MILESTONES_LABEL]) for r in mine]
                reached = sum(steps >= approach for steps, (approach, _) in done)
                crossed = sum(steps >= cross for steps, (_, cross) in done)
                lines.append(
                    {
                        "robot": robot,
                        "controller": controller,
                        "factor": factor,
                        "walked": rate_text(*rate(mine)),
                        "reached": f"{reached}/{len(mine)}",
                        "crossed": f"{crossed}/{len(mine)}",
                        "landing": median(r.get("landing_error_3d_cm_mean") for r in mine),
                        "margin": _min(r.get("tread_margin_cm_min") for r in mine),
                        "clearance": _min(r.get("swing_clearance_cm_min") for r in mine),
                        "stubs": sum(int(r.get("toe_stubs") or 0) for r in mine),
                        "height": median(r.get("com_height_error_cm_rms") for r in mine),
                    }
                )
    if not lines:
        return ""
    return table(
        lines,
        [
            ("robot", "robot", 0),
            ("controller", "controller", 0),
            ("factor", "terrain", 0),
            ("walked", "walked", 0),
            ("reached", "reached it", 0),
            ("crossed", "crossed it", 0),
            ("landing", "landing error 3D, median of the walks' means [cm]", 2),
            ("margin", "tread margin, min [cm]", 2),
            ("clearance", "swing clearance, min [cm]", 2),
            ("stubs", "toe stubs", 0),
            ("height", "CoM height error RMS, median [cm]", 2),
        ],
    )


def terrain_goal_text(rows: Sequence[dict[str, Any]]) -> str:
    """The share of the terrain single-factor walks ``mpc`` walked, per robot, against its
    goal (>= 90 %); empty without such walks."""
    lines = []
    for robot in robots_and_controllers(rows):
        k, n = rate(cell_rows(rows, robot, TERRAIN_CONTROLLER, "terrain"))
        if n:
            met = "met" if k / n >= GOAL_TERRAIN else "**not met**"
            lines.append(
                f"- {robot}: `{TERRAIN_CONTROLLER}` walked {k}/{n} ({100 * k / n:.0f} %) of the "
                f"terrain single-factor walks; the goal (>= {100 * GOAL_TERRAIN:.0f} %) is {met}."
            )
    return "\n".join(lines) + "\n" if lines else ""


def skipped_text(skipped: Sequence[Mapping[str, Any]]) -> str:
    """The worlds skipped because their terrain does not fit the robot, with the reason."""
    if not skipped:
        return "No world was skipped: every drawn terrain fits its robot.\n"
    lines = [
        f"- {s['robot']}, {s['factor']}"
        + ("" if s.get("level") is None else f" at {s['level']:g}")
        + f" (seed {s['seed']}): {s['reason']}"
        for s in skipped
    ]
    return (
        f"{len(skipped)} world(s) skipped, their terrain does not fit the robot (no walk):\n\n"
        + "\n".join(lines)
        + "\n"
    )


__all__ = [
    "TERRAIN_DIR",
    "skipped_text",
    "terrain_command",
    "terrain_goal_text",
    "terrain_table",
    "terrain_words",
    "write_terrain_files",
]
