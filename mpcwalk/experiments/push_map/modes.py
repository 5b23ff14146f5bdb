"""Torque against position control on the same push-map cells: for each robot mapped in both
modes and each controller of both, the median largest impulse survived in each mode, the
median of the per-cell ratio (torque over position) and the cells where torque control
survives clearly less (below 0.9 of position's)."""

from collections.abc import Mapping

from mpcwalk.experiments.push_map.cases import impulses
from mpcwalk.experiments.reporting import median, table

#: A cell counts as clearly below when its ratio is under this.
CLEARLY_BELOW = 0.9


def mode_rows(position: list[dict], torque: list[dict]) -> list[dict]:
    """One row per controller mapped in both modes (cells present in both)."""
    first, second = impulses(position), impulses(torque)
    rows = []
    for controller in [c for c in first if c in second]:
        cells = sorted(set(first[controller]) & set(second[controller]))
        ratios = [
            second[controller][cell] / first[controller][cell]
            for cell in cells
            if first[controller][cell] > 0.0
        ]
        rows.append(
            {
                "controller": controller,
                "cells": len(cells),
                "position": median(first[controller][cell] for cell in cells),
                "torque": median(second[controller][cell] for cell in cells),
                "ratio": median(ratios),
                "worst": min(ratios, default=None),
                "below": sum(ratio < CLEARLY_BELOW for ratio in ratios),
            }
        )
    return rows


def mode_table(maps: Mapping[tuple[str, str], list[dict]]) -> str:
    """Markdown: per robot mapped with position servos and torque motors, :func:`mode_rows`
    (``maps``: the rows of each ``(robot, actuation)`` map)."""
    robots = sorted({robot for robot, mode in maps if (robot, "torque") in maps})
    parts = []
    for robot in robots:
        if (robot, "position") not in maps:
            continue
        rows = mode_rows(maps[(robot, "position")], maps[(robot, "torque")])
        parts += [
            f"`{robot}`: largest impulse survived [N s], median over the cells mapped in both "
            f"modes; ratio: torque over position per cell (median, worst); below: cells under "
            f"{CLEARLY_BELOW:g} of position's.\n",
            table(
                rows,
                [
                    ("controller", "controller", 0),
                    ("cells", "cells", 0),
                    ("position", "position [N s]", 3),
                    ("torque", "torque [N s]", 3),
                    ("ratio", "torque / position (median)", 2),
                    ("worst", "worst cell", 2),
                    ("below", f"cells < {CLEARLY_BELOW:g}", 0),
                ],
            ),
        ]
    return "\n".join(parts) if parts else "No robot was mapped in both modes.\n"


__all__ = ["CLEARLY_BELOW", "mode_rows", "mode_table"]
