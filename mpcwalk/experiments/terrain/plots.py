"""The terrain experiment's figures: the largest rise climbed per robot and controller (a bar
chart, :func:`rise_bars`), and the side view of one climb (:func:`pick_side_views`)."""

import shutil
from pathlib import Path
from typing import Any

from mpcwalk.experiments.terrain.cases import SIDE_VIEWS, timing_of

#: The bar chart's file.
RISE_FIGURE = "largest_rise.png"
#: The side view of the highest climb (or of the best attempt when none climbed).
SIDE_VIEW = "side_view.png"


def rise_bars(out: Path, kept: list[dict[str, Any]], goal_share: float) -> str:
    """The largest rise climbed [share of the leg length] per robot and controller (the
    stairs rows of the kept step durations and strides), the goal's share drawn; the figure's file name."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    robots = list(dict.fromkeys(r["robot"] for r in kept))
    controllers = list(dict.fromkeys(r["controller"] for r in kept))
    width = 0.8 / max(1, len(controllers))
    fig, ax = plt.subplots(figsize=(1.8 + 2.2 * len(robots), 3.4), layout="constrained")
    for j, controller in enumerate(controllers):
        values, labels = [], []
        for robot in robots:
            row = next(
                (r for r in kept if r["robot"] == robot and r["controller"] == controller), None
            )
            share = None if row is None else row.get("largest_rise_share")
            values.append(0.0 if share is None else 100.0 * float(share))
            labels.append(_bar_label(row))
        x = np.arange(len(robots)) + (j - 0.5 * (len(controllers) - 1)) * width
        bars = ax.bar(x, values, width, label=controller)
        ax.bar_label(bars, labels, fontsize=6, padding=1)
        failed = [_failed_share(robot, controller, kept) for robot in robots]
        ax.plot(x, failed, "v", ms=4, color=bars.patches[0].get_facecolor(), mec="k", mew=0.4)
    ax.plot([], [], "v", ms=4, color="w", mec="k", mew=0.4, label="smallest rise failed")
    ax.axhline(100.0 * goal_share, color="k", ls="--", lw=1.0, label="goal")
    ax.set_xticks(range(len(robots)), robots)
    ax.set_ylabel("largest rise climbed [% of leg length]")
    ax.set_ylim(0.0, 55.0)
    ax.legend(fontsize=7, ncol=3, loc="upper left")
    ax.set_title("Largest stair rise climbed (5 up, landing, 5 down)", fontsize=10)
    fig.savefig(out / RISE_FIGURE, dpi=90)
    plt.close(fig)
    return RISE_FIGURE


def _failed_share(robot: str, controller: str, kept: list[dict[str, Any]]) -> float:
    """The smallest rise failed [% of the leg] of a robot's controller (NaN: none)."""
    for row in kept:
        if row["robot"] == robot and row["controller"] == controller:
            failed, leg = row.get("smallest_failed_rise_m"), row.get("leg_length_m")
            if failed is not None and leg:
                return 100.0 * float(failed) / float(leg)
    return float("nan")


def _bar_label(row: dict[str, Any] | None) -> str:
    if row is None:
        return ""
    if row.get("refused"):
        return "refused"
    if row.get("error"):
        return "error"
    rise = row.get("largest_rise_m")
    return "-" if rise is None else f"{100.0 * float(rise):.1f} cm"


def pick_side_views(out: Path, kept: list[dict[str, Any]]) -> tuple[list[str], str]:
    """Keep, of the side views the stairs cases drew, one per robot
    (``side_view_<robot>.png``: its highest climb, else its goal walk that went farthest)
    and the best of them as :data:`SIDE_VIEW`; the drafts' folder is removed. Returns the
    files kept and what :data:`SIDE_VIEW` shows."""
    folder = out / SIDE_VIEWS
    names: list[str] = []
    best: tuple[Any, ...] | None = None
    what = ""
    for robot in dict.fromkeys(r["robot"] for r in kept):
        rows = [r for r in kept if r["robot"] == robot and _view(folder, r).exists()]
        if not rows:
            continue
        row = max(rows, key=_view_rank)
        name = f"side_view_{robot}.png"
        shutil.copyfile(_view(folder, row), out / name)
        names.append(name)
        rank = (*_view_rank(row), -len(names))
        if best is None or rank > best[0]:
            best = (rank, name, row)
    if best is not None:
        _, name, row = best
        shutil.copyfile(out / name, out / SIDE_VIEW)
        names.insert(0, SIDE_VIEW)
        what = _view_text(row)
    if folder.exists():
        shutil.rmtree(folder)
    return names, what


def _view(folder: Path, row: dict[str, Any]) -> Path:
    return folder / f"{row['robot']}_{row['controller']}_{row['variant']}.png"


def _view_rank(row: dict[str, Any]) -> tuple[float, float]:
    """A drawn climb by its share of the leg, else the goal's walk by its steps."""
    climbed = row.get("largest_rise_share") or 0.0
    done = float(row.get("steps_completed") or 0) / max(1.0, float(row.get("steps_planned") or 1))
    return (float(climbed), done)


def _view_text(row: dict[str, Any]) -> str:
    rise = row.get("drawn_rise_m")
    shown = f"{100.0 * float(rise):.1f} cm" if rise is not None else "-"
    if row.get("largest_rise_share"):
        return (
            f"{row['robot']} with `{row['controller']}` (T = {timing_of(row)} s, stride {float(row['stride_share']):g} x the run) climbing its "
            f"highest rise, {shown}"
        )
    return (
        f"no walk climbed: {row['robot']} with `{row['controller']}` (T = {timing_of(row)} s, stride {float(row['stride_share']):g} x the run) "
        f"at the goal's rise of {shown}, the attempt that went farthest"
    )


__all__ = ["RISE_FIGURE", "SIDE_VIEW", "pick_side_views", "rise_bars"]
