"""Figures of planned walks: top view and CoM/ZMP over time (matplotlib, no screen)."""

import numpy as np

from mpcwalk.footsteps.footstep import Side
from mpcwalk.gait.contact_schedule import ContactSchedule


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_top_view(schedule: ContactSchedule, times, com, zmp, *, title: str = "", ax=None):
    """Footsteps, CoM and ZMP seen from above (paper M Fig. 1a style).

    Args:
        schedule: Contact schedule (footsteps and sole size).
        times: Shape (n,), in [s] (unused but kept for symmetry).
        com: CoM ground projection, shape (n, 2), in [m].
        zmp: ZMP, shape (n, 2), in [m].
        title: Figure title.
        ax: Existing axes, or None for a new figure.

    Returns:
        The matplotlib figure.
    """
    plt = _pyplot()
    from matplotlib.patches import Polygon

    plan = schedule.plan
    feet = [plan.initial_left, plan.initial_right, *plan.steps]
    if ax is None:
        xy = np.array([f.xy for f in feet])
        margin = schedule.foot.length
        width = np.ptp(xy[:, 0]) + 2 * margin
        height = np.ptp(xy[:, 1]) + 2 * margin
        # Size the figure to the walk's aspect (a straight walk is long and thin).
        fig_width = 10.0
        fig_height = float(np.clip(7.5 * height / width, 2.0, 8.0)) + 1.2
        fig, ax = plt.subplots(figsize=(fig_width, fig_height), layout="constrained")
    else:
        fig = ax.figure
    colors = {Side.LEFT: "tab:blue", Side.RIGHT: "tab:red"}
    from mpcwalk.models.support_polygon import foot_rectangle

    for i, foot in enumerate(feet):
        rect = foot_rectangle(foot.xy, foot.yaw, schedule.foot.length, schedule.foot.width)
        ax.add_patch(
            Polygon(
                rect.vertices,
                closed=True,
                fill=False,
                lw=1.0,
                ec=colors[foot.side],
                alpha=0.8,
                label=f"{foot.side.value} foot" if i < 2 else None,
            )
        )
    ax.plot(np.asarray(zmp)[:, 0], np.asarray(zmp)[:, 1], color="tab:green", lw=1.0, label="ZMP")
    ax.plot(np.asarray(com)[:, 0], np.asarray(com)[:, 1], color="k", lw=1.5, label="CoM")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    place_legend_below(ax)
    if title:
        ax.set_title(title)
    return fig


def place_legend_below(ax) -> None:
    """Legend beside the axes (right), so that it never hides the walk."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)


def plot_com_zmp(
    schedule: ContactSchedule,
    times,
    com,
    zmp,
    *,
    zmp_reference: np.ndarray | None = None,
    title: str = "",
):
    """CoM and ZMP over time, per axis, with single-support phases shaded.

    Returns:
        The matplotlib figure.
    """
    plt = _pyplot()
    times = np.asarray(times)
    fig, axes = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    for ph in schedule.phases:
        if ph.single_support:
            for ax in axes:
                ax.axvspan(ph.start, ph.end, color="0.9", lw=0)
    for axis, ax in enumerate(axes):
        if zmp_reference is not None:
            ax.plot(
                times,
                zmp_reference[:, axis],
                "--",
                color="tab:olive",
                lw=1.0,
                label="ZMP reference",
            )
        ax.plot(times, np.asarray(zmp)[:, axis], color="tab:green", lw=1.0, label="ZMP")
        ax.plot(times, np.asarray(com)[:, axis], color="k", lw=1.5, label="CoM")
        ax.set_ylabel(f"{'xy'[axis]} [m]")
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="best", fontsize=8)
    axes[-1].set_xlabel("time [s] (grey: single support)")
    if title:
        axes[0].set_title(title)
    fig.tight_layout()
    return fig
