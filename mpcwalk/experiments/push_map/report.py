"""The push map's report: each controller's largest impulse per cell against ``paper-m``'s
in the same cell and against the LIPM's capture bounds of that cell
(:mod:`mpcwalk.experiments.capture_map.cells`: 0, 1 and 2 steps, the first landing at the
schedule's time or at the best time the swing allows, and the 1- and 2-step bounds of the
LIPM with the robot's upper body as a flywheel), the issue's goals checked on them,
the double-support cells, and the figures (:mod:`mpcwalk.experiments.push_map.plots`: polar
plots against the bounds, heat maps of the ratios).
"""

import json
from pathlib import Path
from typing import Any

from mpcwalk.experiments.push_map.cases import (
    REFERENCE,
    Cell,
    PushMapConfig,
    by_cell,
    cell_of,
    impulses,
    ratios,
)
from mpcwalk.experiments.push_map.plots import polar_figures, ratio_heatmaps
from mpcwalk.experiments.reporting import median, table

#: Share of the one-step LIPM bound every cell should reach (the issue's goal).
ONE_STEP_GOAL = 0.8
#: Ratio of the best controller's median to paper-m's (the issue's goal).
MEDIAN_GOAL = 2.0


def lipm_bounds(robot, config: PushMapConfig) -> dict[Cell, Any]:
    """The LIPM's :class:`~mpcwalk.experiments.capture_map.cells.CaptureCell` of every cell of
    ``config``'s grid, for ``robot`` (a :class:`~mpcwalk.robot.Robot`): the impulse acting
    at the middle of the push (half its duration after the phase, where the push starts)."""
    from mpcwalk.experiments.capture_map.cells import capture_map

    bounds = {}
    for speed in config.speed_shares:
        for cell in capture_map(
            robot,
            nb_directions=config.nb_directions,
            nb_phases=config.nb_phases,
            speed_share=speed,
            push_step=config.push_step,
            delay=0.5 * config.push_duration,
        ):
            bounds[cell_of({**cell.__dict__, "speed_share": speed})] = cell
    return bounds


def _shares(values: dict[Cell, float], bounds: dict[Cell, Any], which: str, n: int) -> dict:
    """Impulse / LIPM bound (``which``: fixed or adaptive, ``n`` steps) per cell where the
    LIPM recovers something."""
    out = {}
    for cell, value in values.items():
        bound = bounds.get(cell)
        if bound is not None and getattr(bound, which)[n] > 1e-9:
            out[cell] = value / getattr(bound, which)[n]
    return out


def summary_table(rows: list[dict], bounds: dict[Cell, Any] | None = None) -> str:
    """Per controller: median impulse, median ratio to paper-m, cells at or above it, and
    (with ``bounds``) the shares of the LIPM's 1- and 2-step bounds."""
    values, lines = impulses(rows), []
    for controller, pairs in ratios(rows).items():
        mine = [r for r in rows if r["controller"] == controller and not r.get("error")]
        found = [v for _, v in pairs if v is not None]
        line: dict[str, Any] = {
            "controller": controller,
            "cells": len(pairs),
            "impulse": median([r["largest_survived_Ns"] for r in mine]),
            "ratio": median(found),
            "above": f"{sum(v >= 1.0 for v in found)}/{len(found)}",
            "censored": sum(bool(r["censored"]) for r in mine),
            "walks": sum(int(r["nb_walks"]) for r in mine),
            "errors": sum(bool(r.get("error")) for r in rows if r["controller"] == controller),
        }
        if bounds:
            one = _shares(values.get(controller, {}), bounds, "fixed", 1)
            line["one"] = median(list(one.values()))
            line["worst"] = min(one.values(), default=None)
            line["below"] = f"{sum(v < ONE_STEP_GOAL for v in one.values())}/{len(one)}"
            two = _shares(values.get(controller, {}), bounds, "fixed", 2)
            line["two"] = median(list(two.values()))
            adaptive = _shares(values.get(controller, {}), bounds, "adaptive", 1)
            line["adaptive"] = median(list(adaptive.values()))
            for n, key in ((1, "fly1"), (2, "fly2")):
                flywheel = _shares(values.get(controller, {}), bounds, "flywheel", n)
                line[key] = median(list(flywheel.values()))
        lines.append(line)
    columns = [
        ("controller", "controller", 0),
        ("cells", "cells", 0),
        ("impulse", "largest impulse survived, median [N s]", 3),
        ("ratio", f"ratio to {REFERENCE} per cell, median", 2),
        ("above", f"cells at or above {REFERENCE}", 0),
    ]
    if bounds:
        columns += [
            ("one", "of the LIPM 1-step bound, median", 2),
            ("worst", "of the 1-step bound, worst cell", 2),
            ("below", f"cells under {ONE_STEP_GOAL:.0%} of the 1-step bound", 0),
            ("two", "of the 2-step bound, median", 2),
            ("adaptive", "of the 1-step bound with adapted timing, median", 2),
            ("fly1", "of the flywheel LIPM's 1-step bound, median", 2),
            ("fly2", "of the flywheel LIPM's 2-step bound, median", 2),
        ]
    columns += [
        ("censored", "cells censored at the largest push", 0),
        ("walks", "walks", 0),
        ("errors", "errors", 0),
    ]
    return table(lines, columns)


def best_controller(rows: list[dict]) -> str | None:
    """The QP controller (not paper-m) with the largest median impulse; of those tied, the
    one with the largest median ratio to paper-m per cell (then the first listed)."""
    medians = {
        c: median(list(v.values())) or 0.0 for c, v in impulses(rows).items() if c != REFERENCE
    }
    per_cell = ratios(rows)

    def ratio(controller: str) -> float:
        values = [r for _, r in per_cell.get(controller, []) if r is not None]
        return (median(values) or 0.0) if values else 0.0

    return max(medians, key=lambda c: (round(medians[c], 9), ratio(c))) if medians else None


def _cell_text(cell: Cell) -> str:
    return f"{cell[0]:g} deg, phase {cell[1]:.2f}, speed x{cell[2]:g}"


def goals_text(rows: list[dict], bounds: dict[Cell, Any], *, nb_worst: int = 6) -> str:
    """The goals checked: the best controller's median against twice paper-m's, every cell
    against 80 % of the 1-step LIPM bound (the worst cells), and the cells where the best
    QP controller (overall, and the best in the cell) survives less than paper-m."""
    values, best = impulses(rows), best_controller(rows)
    reference = values.get(REFERENCE, {})
    if best is None:
        return "No goals checked: the map has no QP controller.\n"
    mine = values[best]
    m_best, m_ref = median(list(mine.values())), median(list(reference.values()))
    one = _shares(mine, bounds, "fixed", 1)
    if not m_ref or m_best is None:  # paper-m walks nowhere: no ratio is taken against it
        reference = {}
    below = sorted((v, c) for c, v in one.items() if v < ONE_STEP_GOAL)
    qp = [c for c in values if c != REFERENCE]
    per_cell_best = {
        cell: max(values[c].get(cell, 0.0) for c in qp) for cell in reference if cell in mine
    }
    under_best = sorted(
        (mine[c] / r, c) for c, r in reference.items() if c in mine and r > 0 and mine[c] < r
    )
    under_any = [c for c, r in reference.items() if c in per_cell_best and per_cell_best[c] < r]
    clear = clearly_below(rows, best, REFERENCE, [c for _, c in under_best])
    if reference and m_ref and m_best is not None:
        ratio = m_best / m_ref
        verdict = "met" if ratio >= MEDIAN_GOAL else "not met"
        median_line = (
            f"- Median largest impulse {m_best:.3f} N s against {m_ref:.3f} N s for "
            f"`{REFERENCE}`: **{ratio:.2f}x** (goal {MEDIAN_GOAL:g}x: {verdict})."
        )
    else:
        median_line = (
            f"- `{REFERENCE}` survives no push in any cell (its engine falls unpushed on this "
            f"robot): no ratio is taken against it, and the goals against it do not apply. "
            f"Median largest impulse of `{best}`: {m_best or 0.0:.3f} N s."
        )
    lines = [
        f"Best QP controller (largest median; of those tied, the largest median ratio to "
        f"paper-m): `{best}`.\n",
        median_line,
        f"- Cells under {ONE_STEP_GOAL:.0%} of the LIPM's 1-step bound (schedule's timing): "
        f"**{len(below)}/{len(one)}** (goal: none; "
        f"{'met' if not below else 'not met'}); cells where the LIPM recovers nothing with "
        f"one step are left out ({len(mine) - len(one)}).",
    ]
    if reference:
        lines.append(
            f"- Cells where `{best}` survives less than `{REFERENCE}`: **{len(under_best)}/"
            f"{len(mine)}** (in {len(clear)} of them it fell under an impulse `{REFERENCE}` "
            f"survived; in the others the two bisections' brackets overlap); where every QP "
            f"controller does: **{len(under_any)}/{len(mine)}** (goal: none; "
            f"{'met' if not under_any else 'not met'}).\n"
        )
    else:
        lines[-1] += "\n"
    worst = [
        {
            "cell": _cell_text(c),
            "impulse": mine[c],
            "bound": bounds[c].fixed[1],
            "share": v,
            "ref": reference.get(c),
        }
        for v, c in sorted((v, c) for c, v in one.items())[:nb_worst]
    ]
    lines.append(f"The {len(worst)} worst cells of `{best}` against the 1-step bound:\n")
    lines.append(
        table(
            worst,
            [
                ("cell", "cell", 0),
                ("impulse", f"{best} [N s]", 3),
                ("bound", "LIPM 1-step bound [N s]", 3),
                ("share", "share", 2),
                ("ref", f"{REFERENCE} [N s]", 3),
            ],
        )
    )
    if under_best:
        lines.append(f"The cells where `{best}` survives less than `{REFERENCE}` (worst first):\n")
        lines.append(
            table(
                [
                    {"cell": _cell_text(c), "ratio": v, "mine": mine[c], "ref": reference[c]}
                    for v, c in under_best[:nb_worst]
                ],
                [
                    ("cell", "cell", 0),
                    ("ratio", f"ratio to {REFERENCE}", 2),
                    ("mine", f"{best} [N s]", 3),
                    ("ref", f"{REFERENCE} [N s]", 3),
                ],
            )
        )
    return "\n".join(lines) + "\n"


def fallen(rows: list[dict]) -> dict[str, dict[Cell, float]]:
    """Per controller, the smallest impulse it fell under [N s] in every cell where it fell."""
    return by_cell(rows, "smallest_fallen_Ns")


def clearly_below(rows: list[dict], controller: str, other: str, cells) -> list[Cell]:
    """The cells of ``cells`` where ``controller`` fell under an impulse ``other`` survived
    (below it beyond the bisections' resolution, not only by a bracket's width)."""
    survived, fell = impulses(rows).get(other, {}), fallen(rows).get(controller, {})
    return [c for c in cells if c in fell and c in survived and fell[c] <= survived[c]]


def double_support_text(rows: list[dict], bounds: dict[Cell, Any]) -> str:
    """The footstep-adaptive controllers against ``mpc`` in the double-support cells: the
    median ratio, the cells below it, and those where it fell under an impulse ``mpc``
    survived."""
    values = impulses(rows)
    cells = [c for c, b in bounds.items() if not b.single_support]
    if "mpc" not in values or not cells:
        return ""
    lines = []
    for controller in values:
        if controller in (REFERENCE, "mpc"):
            continue
        both = [c for c in cells if c in values[controller] and c in values["mpc"]]
        pairs = [(values[controller][c], values["mpc"][c]) for c in both]
        if pairs:
            lines.append(
                {
                    "controller": controller,
                    "cells": len(pairs),
                    "ratio": median([a / b for a, b in pairs if b > 0]),
                    "above": sum(a > b for a, b in pairs),
                    "below": sum(a < b for a, b in pairs),
                    "clearly": len(clearly_below(rows, controller, "mpc", both)),
                }
            )
    return table(
        lines,
        [
            ("controller", "controller", 0),
            ("cells", "double-support cells", 0),
            ("ratio", "ratio to mpc, median", 2),
            ("above", "cells above mpc", 0),
            ("below", "cells below mpc", 0),
            ("clearly", "of which it fell under an impulse mpc survived", 0),
        ],
    )


def write_push_figures(out_dir: str | Path, rows, config: PushMapConfig, *, robot=None) -> list:
    """Write ``lipm_bounds.json``, the polar plots and the heat maps into ``out_dir``; returns
    the figures' file names. ``robot``: the robot of ``config`` (loaded by name when None)
    for the LIPM's bounds."""
    if robot is None:
        from mpcwalk.robot import load_robot

        robot = load_robot(config.robot, visual=False)
    out = Path(out_dir)
    rows = list(rows)
    bounds = lipm_bounds(robot, config)
    (out / "lipm_bounds.json").write_text(
        json.dumps(
            [{"speed_share": c[2], **b.__dict__} for c, b in sorted(bounds.items())], indent=0
        )
        + "\n"
    )
    return polar_figures(out, rows, bounds, config) + ratio_heatmaps(out, rows, config)


def write_push_report(
    out_dir: str | Path, rows, config: PushMapConfig, runs: str, *, robot=None, figures=None
) -> Path:
    """Write ``report.md`` into ``out_dir`` (and, when ``figures`` is None, the figures of
    :func:`write_push_figures` first; else ``figures`` are the file names to show); returns
    the report's path. ``robot``: the robot of ``config`` (loaded by name when None) for the
    LIPM's bounds."""
    if robot is None:
        from mpcwalk.robot import load_robot

        robot = load_robot(config.robot, visual=False)
    out = Path(out_dir)
    rows = list(rows)
    if figures is None:
        figures = write_push_figures(out, rows, config, robot=robot)
    bounds = lipm_bounds(robot, config)
    double = double_support_text(rows, bounds)
    text = [
        f"# Push map: {config.robot}"
        + ("" if config.actuation == "position" else f" ({config.actuation} control)")
        + "\n",
        runs,
        f"Grid: {config.nb_directions} directions, {config.nb_phases} phases per step (at the "
        "middle of each share, as the LIPM's map), speeds "
        f"{', '.join(f'x{s:g}' for s in config.speed_shares)} of the robot's nominal speed; "
        f"a {config.push_duration:g} s push on the torso in step {config.push_step} of "
        f"{config.nb_steps}; per cell, the largest impulse survived by bracketing and "
        f"bisection (from {config.initial_share:g} up to {config.max_share:g} times the "
        "LIPM's no-step capture bound in that direction). The LIPM's bounds "
        "(`lipm_bounds.json`) are those of the robot's soles, leg limits and timing in the "
        "same cell (`mpcwalk.experiments.capture_map.cells`), the impulse acting at the middle of "
        "the push (a push starting in the last sixth of double support acts mostly in single "
        "support: the cell is drawn as the support where it acts). Settings: "
        f"`{json.dumps(config.settings())}`.\n",
        summary_table(rows, bounds),
        "## Goals\n",
        goals_text(rows, bounds),
    ]
    if double:
        text += ["## Double support\n", double]
    text.append("\n".join(f"![{n}]({n})" for n in figures) + "\n")
    path = out / "report.md"
    path.write_text("\n".join(text))
    return path


__all__ = [
    "MEDIAN_GOAL",
    "ONE_STEP_GOAL",
    "best_controller",
    "clearly_below",
    "double_support_text",
    "fallen",
    "goals_text",
    "lipm_bounds",
    "summary_table",
    "write_push_figures",
    "write_push_report",
]
