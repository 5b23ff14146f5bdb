"""The robustness matrix's cells and their success rates: the goals' robots and
controllers, which rows make a cell, rates with their Wilson intervals.
Shared by the report (:mod:`mpcwalk.experiments.robustness.report`) and its figures
(:mod:`mpcwalk.experiments.robustness.plots`)."""

from collections.abc import Iterable, Sequence

from mpcwalk.experiments.reporting import wilson
from mpcwalk.experiments.survival import survived

#: The QP controllers of the goals, on the robots of the goals.
GOAL_CONTROLLERS = ("preview", "mpc", "mpc-steps")
GOAL_ROBOTS = ("bioloid-like", "g1")
#: Success rates the goals ask for: over the single-factor walks, over the combinations.
GOAL_SINGLE, GOAL_COMBINATION = 0.95, 0.85
REFERENCE = "paper-m"


def cell_rows(rows: Iterable[dict], robot: str, controller: str, cell: str) -> list[dict]:
    """The rows of one cell: ``cell`` is a factor (its single-factor walks), ``"nominal"``,
    ``"single"`` (every single-factor walk) or ``"combination"``."""
    out = []
    for row in rows:
        if row["robot"] != robot or row["controller"] != controller:
            continue
        group = row["group"]
        if cell in ("single", "combination", "nominal"):
            keep = group == cell
        else:
            keep = group == "single" and row["factor"] == cell
        if keep:
            out.append(row)
    return out


def rate(rows: Sequence[dict]) -> tuple[int, int]:
    """(successes, walks)."""
    return sum(survived(row) for row in rows), len(rows)


def rate_text(successes: int, n: int) -> str:
    """``k/n, p % [low, high]``."""
    if n == 0:
        return "-"
    low, high = wilson(successes, n)
    return f"{successes}/{n}, {100 * successes / n:.0f} % [{100 * low:.0f}, {100 * high:.0f}]"


def robots_and_controllers(rows: Sequence[dict]) -> dict[str, list[str]]:
    """Robot -> its controllers, in the order of the table."""
    out: dict[str, list[str]] = {}
    for row in rows:
        names = out.setdefault(row["robot"], [])
        if row["controller"] not in names:
            names.append(row["controller"])
    return out


__all__ = [
    "GOAL_COMBINATION",
    "GOAL_CONTROLLERS",
    "GOAL_ROBOTS",
    "GOAL_SINGLE",
    "REFERENCE",
    "cell_rows",
    "rate",
    "rate_text",
    "robots_and_controllers",
]
