"""Figures of paper M's experiments: attitude over time, push recovery (polar, heat map)."""

import math
from collections.abc import Mapping, Sequence
from typing import Any, cast

import numpy as np

from mpcwalk.experiments.paper_m.push_grid import CaseResult, PushSweepConfig
from mpcwalk.footsteps.capturability import capture_impulse_bound
from mpcwalk.walking.log import WalkLog

_RPY = ("roll", "pitch", "yaw")


def plot_attitude(
    entries: Sequence[tuple[str, WalkLog]],
    *,
    title: str = "",
    pushes: Sequence = (),
    yaw_rate: float | None = None,
    walk_start: float = 1.0,
    walk_end: float | None = None,
):
    """IMU roll, pitch and yaw [deg] over time of several walks (paper M Fig. 1b and 2).

    Args:
        entries: ``(label, WalkLog)`` pairs; a label starting with ``"_"`` draws a thin grey
            reference line without a legend entry.
        title: Figure title.
        pushes: :class:`~mpcwalk.sim.ExternalForce` windows to shade.
        yaw_rate: Commanded yaw rate [rad/s]: draws the commanded yaw from ``walk_start`` to
            ``walk_end``.
        walk_start: Start of walking [s].
        walk_end: End of walking [s] (default: end of the longest log).
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(8, 6.5), sharex=True)
    for label, log in entries:
        if not len(log):
            continue
        rpy = np.degrees(np.column_stack([log.base_rpy[:, :2], np.unwrap(log.base_rpy[:, 2])]))
        rpy -= rpy[0]
        style = (
            dict(color="0.6", lw=0.8, label=None)
            if label.startswith("_")
            else dict(lw=1.1, label=label)
        )
        for axis, ax in enumerate(axes):
            ax.plot(log.time, rpy[:, axis], **style)
    if yaw_rate is not None:
        end = (
            walk_end
            if walk_end is not None
            else max((float(log.time[-1]) for _, log in entries if len(log)), default=walk_start)
        )
        commanded = axes[2].plot(
            [0.0, walk_start, end],
            [0.0, 0.0, math.degrees(yaw_rate) * (end - walk_start)],
            "k:",
            lw=1.0,
            label="commanded",
        )
    for push in pushes:
        for ax in axes:
            ax.axvspan(push.start, push.end, color="tab:orange", alpha=0.25, lw=0)
    for axis, ax in enumerate(axes):
        ax.set_ylabel(f"{_RPY[axis]} [deg]")
        ax.grid(True, lw=0.3)
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title(title)
    axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    if yaw_rate is not None:
        axes[2].legend(handles=commanded, loc="upper left", fontsize=8, frameon=False)
    fig.tight_layout()
    return fig


def plot_push_polar(
    summary: Mapping[str, Mapping],
    config: PushSweepConfig,
    *,
    mass: float,
    com_height: float,
    sole_size: tuple[float, float] = (0.10, 0.06),
    step_reach: tuple[float, float, float] = (0.08, 0.04, 0.04),
    step_time: float = 0.25,
    title: str = "",
):
    """Largest impulse survived [N s] against the push direction (median over the phases),
    one line per controller, with the LIPM's capturability bounds (no step; one step landing
    ``step_time`` after the push) as references."""
    import matplotlib.pyplot as plt
    from matplotlib.projections.polar import PolarAxes

    fig = plt.figure(figsize=(7, 6))
    ax = cast(PolarAxes, fig.add_subplot(projection="polar"))
    fine = np.linspace(0.0, 2.0 * math.pi, 361)
    common: dict[str, Any] = dict(
        mass=mass,
        com_height=com_height,
        half_length=0.5 * sole_size[0],
        half_width=0.5 * sole_size[1],
    )
    ax.plot(
        fine,
        [capture_impulse_bound(a, **common) for a in fine],
        "k--",
        lw=1.0,
        label="LIPM bound, no step",
    )
    ax.plot(
        fine,
        [
            capture_impulse_bound(a, step_reach=step_reach, step_time=step_time, **common)
            for a in fine
        ],
        "k:",
        lw=1.0,
        label=f"LIPM bound, one step after {step_time:g} s",
    )
    for name, row in summary.items():
        directions = sorted(float(d) for d in row["per_direction_Ns"])
        if not directions:
            continue
        values = [row["per_direction_Ns"][f"{d:g}"] for d in directions]
        angles = np.radians(directions + [directions[0]])
        ax.plot(angles, values + [values[0]], "o-", ms=3, lw=1.2, label=name)
    ax.set_theta_zero_location("E")
    ax.set_title(
        title or "largest impulse survived [N s] (0 deg: forward, 90 deg: left)", fontsize=10
    )
    ax.legend(loc="upper left", bbox_to_anchor=(1.05, 1.0), fontsize=8, frameon=False)
    fig.tight_layout()
    return fig


def plot_push_heatmap(results: Sequence[CaseResult], config: PushSweepConfig, *, title: str = ""):
    """Largest impulse survived [N s] per controller (rows) and (direction, phase) (columns)."""
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(r.case.controller for r in results))
    columns = [(d, p) for d in config.directions_deg for p in config.phases]
    grid = np.full((len(names), len(columns)), np.nan)
    for r in results:
        key = (r.case.direction_deg, r.case.phase)
        if key in columns:
            grid[names.index(r.case.controller), columns.index(key)] = r.largest_survived
    fig, ax = plt.subplots(figsize=(max(6.0, 0.45 * len(columns) + 2.5), 1.0 + 0.5 * len(names)))
    image = ax.imshow(grid, aspect="auto", cmap="viridis", vmin=0.0)
    for i in range(len(names)):
        for j in range(len(columns)):
            if np.isfinite(grid[i, j]):
                ax.text(
                    j,
                    i,
                    f"{grid[i, j]:.2f}",
                    ha="center",
                    va="center",
                    fontsize=6,
                    color="w" if grid[i, j] < 0.6 * np.nanmax(grid) else "k",
                )
    ax.set_yticks(range(len(names)), names)
    ax.set_xticks(range(len(columns)), [f"{d:g} {p}" for d, p in columns], rotation=90, fontsize=7)
    ax.set_title(title or "largest impulse survived [N s] (direction [deg], phase)", fontsize=10)
    fig.colorbar(image, ax=ax, label="[N s]", fraction=0.03)
    fig.tight_layout()
    return fig


def write_figures(
    out, results: Mapping, walks: Mapping, cases: Sequence[CaseResult], config
) -> list:
    """Every figure of :func:`mpcwalk.experiments.paper_m.run.run_paper_m` as PNG in ``out``; returns
    the file names."""
    import matplotlib.pyplot as plt

    from mpcwalk.walking.figures import plot_walk_top_view
    from mpcwalk.walking.sweep_cases import worker_robot

    names = []

    def save(fig, name: str) -> None:
        fig.savefig(out / name, dpi=100, bbox_inches="tight")
        plt.close(fig)
        names.append(name)

    def slug(name: str) -> str:
        return name.replace("+", "_").replace(" ", "_")

    turning = walks.get("turning", {})
    for name, result in turning.items():
        if len(result.log):
            save(
                plot_walk_top_view(result.schedule, result.log, title=f"turning walk: {name}"),
                f"turning_top_{slug(name)}.png",
            )
    if turning:
        schedule = next(iter(turning.values())).schedule
        save(
            plot_attitude(
                [(n, r.log) for n, r in turning.items()],
                title="turning walk: IMU attitude",
                yaw_rate=config.turning.command[2],
                walk_start=schedule.walk_start,
                walk_end=schedule.walk_end,
            ),
            "turning_attitude.png",
        )
    pushes = config.disturbance.external_forces()
    for name, runs in walks.get("disturbance", {}).items():
        entries = [("_no pushes", runs["off"][1].log), ("no stabilizer", runs["off"][0].log)]
        if runs["on"] is not None:
            entries.append((f"{config.disturbance.stabilizer} stabilizer", runs["on"][0].log))
        save(
            plot_attitude(entries, title=f"F1 + F2: {name} (grey: without pushes)", pushes=pushes),
            f"disturbance_{slug(name)}.png",
        )
    summary = results.get("push_sweep", {}).get("summary", {})
    if summary:
        robot = worker_robot(config.robot)
        limits = robot.leg_limits
        step_time = 0.5 * robot.gait.step_duration
        save(
            plot_push_polar(
                summary,
                config.push_sweep,
                mass=robot.total_mass,
                com_height=robot.com_height,
                sole_size=tuple(robot.sole_size),
                step_reach=(
                    limits.max_step_forward,
                    limits.max_step_backward,
                    limits.max_step_lateral,
                ),
                step_time=step_time,
            ),
            "push_polar.png",
        )
        save(plot_push_heatmap(cases, config.push_sweep), "push_heatmap.png")
    return names
