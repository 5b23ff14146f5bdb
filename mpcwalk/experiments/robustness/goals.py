"""The goals of the robustness matrix's QP controllers on every robot, checked on its
rows (:func:`goal_checks`) and as a table of the report (:func:`goals_text`): >= 95 % of the
single-factor walks on the floor, >= 85 % of the combinations, never below ``paper-m`` in
any cell, and ``mpc`` >= 90 % of the terrain single-factor walks.
"""

from collections.abc import Sequence
from typing import Any

from mpcwalk.experiments.reporting import table
from mpcwalk.experiments.robustness.cells import (
    GOAL_COMBINATION,
    GOAL_CONTROLLERS,
    GOAL_SINGLE,
    GOAL_TERRAIN,
    REFERENCE,
    TERRAIN_CONTROLLER,
    cell_rows,
    rate,
    rate_text,
    robots_and_controllers,
)
from mpcwalk.experiments.robustness.factors import FACTORS
from mpcwalk.experiments.survival import survived

#: The goals: (cell, share asked for, what it is over).
GOALS = (
    ("single", GOAL_SINGLE, "single-factor walks on the floor"),
    ("combination", GOAL_COMBINATION, "combinations"),
    ("terrain", GOAL_TERRAIN, "terrain single-factor walks"),
)


def goal_checks(rows: Sequence[dict]) -> list[dict[str, Any]]:
    """The goals of the QP controllers on every robot of the table (in its order): >= 95 %
    over the single-factor walks on the floor, >= 85 % over the combinations, never below
    ``paper-m`` in any cell, and ``mpc`` >= 90 % over the terrain single-factor walks; each
    with what missed it (the factors, the cells, the case identifiers of the falls). A goal
    without walks in the table is left out."""
    checks = []
    for robot in robots_and_controllers(rows):
        for controller in GOAL_CONTROLLERS:
            mine = [r for r in rows if r["robot"] == robot and r["controller"] == controller]
            if not mine:
                continue
            for cell, goal, over in GOALS:
                if cell == "terrain" and controller != TERRAIN_CONTROLLER:
                    continue
                walks = cell_rows(rows, robot, controller, cell)
                k, n = rate(walks)
                if n == 0:
                    continue
                failed = [r for r in walks if not survived(r)]
                where = sorted({r["factor"] for r in failed})
                checks.append(
                    {
                        "robot": robot,
                        "controller": controller,
                        "goal": f">= {100 * goal:.0f} % over the {over}",
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
        return "No QP controller of the goals in this run.\n"
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


__all__ = ["GOALS", "goal_checks", "goals_text"]
