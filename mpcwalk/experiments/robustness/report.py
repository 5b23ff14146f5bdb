"""The report of the robustness matrix: success rates with Wilson intervals, the goals, the
worst cases with the command that reruns each, and the quality of the walks that succeed.

A walk *succeeds* when it ran (no error) and survived
(:func:`~mpcwalk.experiments.survival.survived`: it neither fell nor was stopped by the
controller). The tables read the rows of the
matrix's results table (:func:`mpcwalk.sweep.read_rows`); :func:`write_report` writes
``report.md`` (the figures: :mod:`mpcwalk.experiments.robustness.plots`).
"""

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from mpcwalk.experiments.reporting import median, table
from mpcwalk.experiments.robustness.cells import (
    GOAL_COMBINATION,
    GOAL_CONTROLLERS,
    GOAL_ROBOTS,
    GOAL_SINGLE,
    REFERENCE,
    cell_rows,
    rate,
    rate_text,
    robots_and_controllers,
)
from mpcwalk.experiments.robustness.worlds import FACTORS, LEVEL_UNITS
from mpcwalk.experiments.survival import survived

CELLS = ("nominal", *FACTORS, "single", "combination")


def success_table(rows: Sequence[dict], robot: str, controllers: Sequence[str]) -> str:
    """Success per factor (a line) and controller (a column), with 95 % Wilson intervals."""
    titles = {"single": "**every single factor**", "combination": "**combinations**"}
    lines = []
    for cell in CELLS:
        entry: dict[str, Any] = {"cell": titles.get(cell, cell)}
        for controller in controllers:
            entry[controller] = rate_text(*rate(cell_rows(rows, robot, controller, cell)))
        lines.append(entry)
    return table(lines, [("cell", "factor", 0)] + [(c, c, 0) for c in controllers])


def goal_checks(rows: Sequence[dict]) -> list[dict[str, Any]]:
    """The goals of the QP controllers on the goals' robots: >= 95 % over the single-factor
    walks, >= 85 % over the combinations, never below ``paper-m`` in any cell; each with
    what missed it (the factors, the cells, the case identifiers of the falls)."""
    checks = []
    for robot in GOAL_ROBOTS:
        for controller in GOAL_CONTROLLERS:
            mine = [r for r in rows if r["robot"] == robot and r["controller"] == controller]
            if not mine:
                continue
            for cell, goal in (("single", GOAL_SINGLE), ("combination", GOAL_COMBINATION)):
                walks = cell_rows(rows, robot, controller, cell)
                k, n = rate(walks)
                failed = [r for r in walks if not survived(r)]
                where = sorted({r["factor"] for r in failed})
                checks.append(
                    {
                        "robot": robot,
                        "controller": controller,
                        "goal": f">= {100 * goal:.0f} % over the "
                        + ("single-factor walks" if cell == "single" else "combinations"),
                        "value": rate_text(k, n),
                        "met": n > 0 and k / n >= goal,
                        "missed": ", ".join(where),
                        "cases": ", ".join(str(r["case_id"]) for r in failed),
                    }
                )
            if not [r for r in rows if r["robot"] == robot and r["controller"] == REFERENCE]:
                continue  # no reference to compare with
            below = []
            for cell in ("nominal", *FACTORS, "combination"):
                k, n = rate(cell_rows(rows, robot, controller, cell))
                kr, nr = rate(cell_rows(rows, robot, REFERENCE, cell))
                if n and nr and k / n < kr / nr:
                    below.append(f"{cell} ({k}/{n} < {kr}/{nr})")
            checks.append(
                {
                    "robot": robot,
                    "controller": controller,
                    "goal": f"never below {REFERENCE} in any cell",
                    "value": f"{len(below)} cell(s) below",
                    "met": not below,
                    "missed": "; ".join(below),
                    "cases": "",
                }
            )
    return checks


def goals_text(checks: Sequence[dict]) -> str:
    """The goal checks as a table."""
    if not checks:
        return "No QP controller of the goals' robots in this run.\n"
    return table(
        [{**c, "met": "met" if c["met"] else "**NOT met**"} for c in checks],
        [
            ("robot", "robot", 0),
            ("controller", "controller", 0),
            ("goal", "goal", 0),
            ("value", "measured", 0),
            ("met", "", 0),
            ("missed", "missed at (factors / cells)", 0),
            ("cases", "falls (case ids, in the worst cases below and in results.csv)", 0),
        ],
    )


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
    return "; ".join(parts) or "nominal"


def worst_cases(rows: Sequence[dict], *, limit: int = 30) -> str:
    """The walks that did not survive (fell, stopped, or could not run), the goals' first, earliest falls first, each
    with the ``mpcwalk walk`` command that reruns it."""
    from mpcwalk.walking.sweep_cases import spec_of_row

    failed = [row for row in rows if not survived(row)]
    if not failed:
        return "Every walk survived.\n"

    def key(row):
        goal = row["robot"] in GOAL_ROBOTS and row["controller"] in GOAL_CONTROLLERS
        return (not goal, row.get("fall_time_s") or 0.0)

    lines = []
    for row in sorted(failed, key=key)[:limit]:
        case = spec_of_row(row)
        if row.get("error"):
            what = row["error"]
        elif row.get("outcome") == "fell":
            what = f"fell at {row['fall_time_s']:.1f} s ({row['fall_reason']})"
        else:
            what = f"{row.get('outcome')} by the controller"
        lines.append(
            f"- `{row['case_id']}` {row['robot']}, {row['controller']}, {row['factor']}: "
            f"{world_text(row)}; {what}, {row['steps_completed']}/{row['steps_planned']} steps\n"
            f"  `{case.command_line()}`"
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


def levels_text() -> str:
    """What the level of each factor is."""
    return "; ".join(f"{factor}: {unit}" for factor, unit in LEVEL_UNITS.items())


def write_report(
    out_dir: str | Path,
    rows: Sequence[dict],
    *,
    header: str,
    scaling: str = "",
    figures: Sequence[str] = (),
) -> Path:
    """Write ``report.md`` into ``out_dir`` (showing the ``figures``, file names of
    :func:`~mpcwalk.experiments.robustness.plots.write_figures`); returns its path."""
    out = Path(out_dir)
    names = list(figures)
    parts = [header, "## Goals of the QP controllers\n", goals_text(goal_checks(rows))]
    by_robot = robots_and_controllers(rows)
    parts.append("## Success rates (95 % Wilson intervals)\n")
    for robot, controllers in by_robot.items():
        parts += [f"### {robot}\n", success_table(rows, robot, controllers)]
    parts += [
        f"Levels: {levels_text()}.\n",
        "## The walks that succeed\n",
        quality_table(rows),
        "## Worst cases\n",
        worst_cases(rows),
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
    "GOAL_ROBOTS",
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
