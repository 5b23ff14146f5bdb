"""The robustness matrix's cells and their success rates: the goals' controllers (on every
robot of the table), which rows make a cell (a factor, the nominal walks, every factor on
the floor, every terrain factor, the combinations), rates with their Wilson intervals.
Shared by the report (:mod:`mpcwalk.experiments.robustness.report`) and its figures
(:mod:`mpcwalk.experiments.robustness.plots`)."""

from collections.abc import Iterable, Sequence

from mpcwalk.experiments.reporting import wilson
from mpcwalk.experiments.robustness.terrains import TERRAIN_FACTORS
from mpcwalk.experiments.survival import survived

#: The QP controllers of the goals; the goals hold on every robot of the table.
GOAL_CONTROLLERS = ("preview", "mpc", "mpc-steps")
#: Success rates the goals ask for: over the single-factor walks on the floor, over the
#: combinations.
GOAL_SINGLE, GOAL_COMBINATION = 0.95, 0.85
#: The terrain goal: this share of the terrain factors' single-factor walks walked by
#: :data:`TERRAIN_CONTROLLER`.
GOAL_TERRAIN, TERRAIN_CONTROLLER = 0.90, "mpc"
REFERENCE = "paper-m"


def cell_rows(rows: Iterable[dict], robot: str, controller: str, cell: str) -> list[dict]:
    """The rows of one cell: ``cell`` is a factor (its single-factor walks), ``"nominal"``,
    ``"single"`` (every single-factor walk on the floor: of a factor that is no terrain),
    ``"terrain"`` (every single-factor walk of a terrain factor) or ``"combination"``."""
    out = []
    for row in rows:
        if row["robot"] != robot or row["controller"] != controller:
            continue
        group, terrain = row["group"], row["factor"] in TERRAIN_FACTORS
        if cell in ("combination", "nominal"):
            keep = group == cell
        elif cell in ("single", "terrain"):
            keep = group == "single" and terrain == (cell == "terrain")
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


def present_cells(rows: Sequence[dict], cells: Sequence[str]) -> list[str]:
    """The ``cells`` (in their order) that hold a walk of ``rows``, any robot or controller."""
    pairs = {(r["robot"], r["controller"]) for r in rows}
    return [c for c in cells if any(cell_rows(rows, *pair, c) for pair in pairs)]


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
    "GOAL_SINGLE",
    "GOAL_TERRAIN",
    "REFERENCE",
    "TERRAIN_CONTROLLER",
    "cell_rows",
    "present_cells",
    "rate",
    "rate_text",
    "robots_and_controllers",
]
