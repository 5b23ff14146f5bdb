"""The figures of the robustness matrix: heat maps of success.

- per robot, success of each controller (line) under each factor alone (column), the
  nominal walks and the combinations beside them;
- over two factors at a time: for a group of controllers, the success of the combination
  walks in which both factors changed (the diagonal: those in which the factor changed);
- per factor, success against the factor's level (the single-factor walks, every
  controller of a group together).
"""

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from mpcwalk.experiments.robustness.cells import (
    GOAL_CONTROLLERS,
    REFERENCE,
    cell_rows,
    present_cells,
    rate,
    robots_and_controllers,
)
from mpcwalk.experiments.robustness.worlds import FACTORS, LEVEL_UNITS
from mpcwalk.experiments.survival import survived


def _annotated(ax, grid: np.ndarray, counts: np.ndarray):
    image = ax.imshow(grid, vmin=0.0, vmax=1.0, cmap="RdYlGn", aspect="auto")
    for (i, j), value in np.ndenumerate(grid):
        if counts[i, j]:
            ax.text(
                j,
                i,
                f"{100 * value:.0f}\n{int(round(value * counts[i, j]))}/{counts[i, j]}",
                ha="center",
                va="center",
                fontsize=6,
            )
    return image


def plot_success_heatmap(rows: Sequence[dict], robot: str, controllers: Sequence[str]):
    """Success [%] of each controller under each factor alone, nominal and combinations
    (the cells that hold a walk of the robot)."""
    import matplotlib.pyplot as plt

    mine = [r for r in rows if r["robot"] == robot]
    cells = present_cells(mine, ("nominal", *FACTORS, "combination"))
    grid = np.full((len(controllers), len(cells)), np.nan)
    counts = np.zeros(grid.shape, dtype=int)
    for i, controller in enumerate(controllers):
        for j, cell in enumerate(cells):
            k, n = rate(cell_rows(rows, robot, controller, cell))
            if n:
                grid[i, j], counts[i, j] = k / n, n
    fig, ax = plt.subplots(figsize=(1.0 + 0.75 * len(cells), 0.9 + 0.45 * len(controllers)))
    image = _annotated(ax, grid, counts)
    ax.set_xticks(range(len(cells)), cells, rotation=45, ha="right", fontsize=8)
    ax.set_yticks(range(len(controllers)), controllers, fontsize=8)
    ax.set_title(f"{robot}: walks without a fall [%] (each factor alone)", fontsize=9)
    fig.colorbar(image, ax=ax, fraction=0.03)
    fig.tight_layout()
    return fig


def plot_pair_heatmap(rows: Sequence[dict], controllers: Sequence[str], robots, title: str):
    """Success [%] of the combination walks in which both factors changed (the factors of
    the combinations)."""
    import matplotlib.pyplot as plt

    combos = [
        r
        for r in rows
        if r["group"] == "combination" and r["controller"] in controllers and r["robot"] in robots
    ]
    changed = {f for r in combos for f in str(r["factor"]).split("+")}
    factors = [f for f in FACTORS if f in changed]
    grid = np.full((len(factors), len(factors)), np.nan)
    counts = np.zeros(grid.shape, dtype=int)
    for i, a in enumerate(factors):
        for j, b in enumerate(factors):
            both = [r for r in combos if {a, b} <= set(str(r["factor"]).split("+"))]
            if both:
                k, n = rate(both)
                grid[i, j], counts[i, j] = k / n, n
    fig, ax = plt.subplots(figsize=(8.0, 6.5))
    image = _annotated(ax, grid, counts)
    ax.set_xticks(range(len(factors)), factors, rotation=45, ha="right", fontsize=8)
    ax.set_yticks(range(len(factors)), factors, fontsize=8)
    ax.set_title(title, fontsize=9)
    fig.colorbar(image, ax=ax, fraction=0.03)
    fig.tight_layout()
    return fig


def plot_levels(rows: Sequence[dict], groups: dict[str, tuple[Sequence[str], Sequence[str]]]):
    """Per factor, each single-factor walk's outcome against its level (1: walked, 0: fell),
    one marker per group of controllers (jittered), and the group's success over the level's
    lower and upper half; the factors of the single-factor walks, five a line."""
    import matplotlib.pyplot as plt

    singles = {str(r["factor"]) for r in rows if r["group"] == "single"}
    factors = [f for f in FACTORS if f in singles] or list(FACTORS)
    lines = -(-len(factors) // 5)
    fig, axes = plt.subplots(lines, 5, figsize=(15.0, 3.0 * lines), squeeze=False)
    for ax in axes.flat[len(factors) :]:
        ax.set_visible(False)
    rng = np.random.default_rng(0)
    for ax, factor in zip(axes.flat, factors):
        for (label, (controllers, robots)), marker in zip(groups.items(), "os^"):
            mine = [
                r
                for r in rows
                if r["group"] == "single"
                and r["factor"] == factor
                and r["controller"] in controllers
                and r["robot"] in robots
            ]
            if not mine:
                continue
            levels = np.array([float(r["level"]) for r in mine])
            ok = np.array([survived(r) for r in mine], dtype=float)
            jitter = 0.08 * rng.standard_normal(len(ok))
            ax.plot(levels, ok + jitter, marker, ms=3, alpha=0.5, label=label)
        ax.set_title(f"{factor}: {LEVEL_UNITS[factor]}", fontsize=8)
        ax.set_yticks([0, 1], ["fell", "walked"], fontsize=7)
        ax.tick_params(axis="x", labelsize=7)
    axes.flat[0].legend(fontsize=7)
    fig.suptitle("single-factor walks: outcome against the level", fontsize=10)
    fig.tight_layout()
    return fig


def write_figures(out: Path, rows: Sequence[dict]) -> list[str]:
    """Every figure as PNG in ``out``; returns the file names."""
    import matplotlib.pyplot as plt

    names = []

    def save(fig, name: str) -> None:
        fig.savefig(out / name, dpi=100, bbox_inches="tight")
        plt.close(fig)
        names.append(name)

    by_robot = robots_and_controllers(rows)
    for robot, controllers in by_robot.items():
        save(plot_success_heatmap(rows, robot, controllers), f"matrix_success_{robot}.png")
    all_robots = list(by_robot)
    groups: dict[str, tuple[Sequence[str], Sequence[str]]] = {
        f"QP controllers on {', '.join(all_robots)}": (GOAL_CONTROLLERS, all_robots),
        f"{REFERENCE} on {', '.join(all_robots)}": ((REFERENCE,), all_robots),
    }
    for label, (group, robots) in groups.items():
        if any(r["controller"] in group for r in rows if r["group"] == "combination"):
            slug = "qp" if group == GOAL_CONTROLLERS else REFERENCE
            title = f"combinations, {label}: walks without a fall [%] when both factors changed"
            save(plot_pair_heatmap(rows, group, robots, title), f"matrix_pairs_{slug}.png")
    everyone: dict[str, tuple[Sequence[str], Sequence[str]]] = {
        "QP controllers": (GOAL_CONTROLLERS, all_robots),
        REFERENCE: ((REFERENCE,), all_robots),
    }
    save(plot_levels(rows, everyone), "matrix_levels.png")
    return names


__all__ = ["plot_levels", "plot_pair_heatmap", "plot_success_heatmap", "write_figures"]
