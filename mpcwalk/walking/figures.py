"""Figures of walks (matplotlib, no screen): top view and CoM/ZMP over time of a planned
walk, and the same of a simulated walk with its measured CoM and CoP."""

import numpy as np

from mpcwalk.footsteps.footstep import Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.support_polygon import foot_rectangle
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import landing_check_times

_SIDES = (Side.LEFT, Side.RIGHT)


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
    new_figure = ax is None
    if ax is None:
        fig, ax = plt.subplots(figsize=(10.0, 4.0), layout="constrained")
    else:
        fig = ax.figure
    colors = {Side.LEFT: "tab:blue", Side.RIGHT: "tab:red"}
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
    ax.set_title(title or "Footsteps, CoM and ZMP seen from above [m]")
    if new_figure:
        fit_figure_to_data(ax)
    return fig


def fit_figure_to_data(ax, *, width: float = 10.0, plot_width: float = 6.9) -> None:
    """Size the figure so that the equal-aspect axes fill it: a straight walk's long thin
    strip gets a short wide figure, a turning walk a taller one (``plot_width`` [in]: what
    the axes get of ``width`` beside the legend)."""
    ax.autoscale_view()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    height = plot_width * (y1 - y0) / max(x1 - x0, 1e-9) + 1.4  # title, labels
    ax.figure.set_size_inches(width, float(np.clip(height, 2.8, 11.0)))


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
    axes[0].set_title(title or "CoM and ZMP over time [m]")
    fig.tight_layout()
    return fig


def _label_as_measured(ax) -> None:
    """The planning plots draw a planned ZMP and CoM; here they are the measured CoP and CoM."""
    for line in ax.get_lines():
        if line.get_label() == "ZMP":
            line.set_label("CoP, single support")
            line.set_color("tab:red")
            line.set_linewidth(0.6)
        elif line.get_label() == "CoM":
            line.set_label("CoM (measured)")


def broken_at_phase_changes(
    schedule: ContactSchedule, times, points, *, single_support: bool | None = None
) -> np.ndarray:
    """``points`` (n, 2) with a NaN row inserted wherever the support phase changes, so that
    a measured CoP is drawn support phase by support phase (no line jumping between the
    feet when the weight moves); ``single_support`` True (False) also blanks the points of
    the double (single) support phases."""
    points = np.array(points, dtype=float)
    phases = schedule.phase_index(np.asarray(times, dtype=float))
    if single_support is not None:
        single = np.array([schedule.phases[i].single_support for i in phases])
        points[single != single_support] = np.nan
    cuts = np.flatnonzero(np.diff(phases) != 0) + 1
    return np.insert(points, cuts, np.nan, axis=0)


def plot_walk_top_view(schedule: ContactSchedule, log: WalkLog, *, title: str = ""):
    """Planned footsteps, landed soles, measured CoM and CoP seen from above (paper M
    Fig. 1a, paper A Fig. 5); the CoP drawn per support phase."""
    from matplotlib.patches import Polygon

    cop = broken_at_phase_changes(schedule, log.time, log.cop[:, :2], single_support=True)
    fig = plot_top_view(
        schedule,
        log.time,
        log.com[:, :2],
        cop,
        title=title or "Footsteps, CoM and CoP of the walk seen from above [m]",
    )
    ax = fig.axes[0]
    _label_as_measured(ax)
    shifting = broken_at_phase_changes(schedule, log.time, log.cop[:, :2], single_support=False)
    ax.plot(
        shifting[:, 0],
        shifting[:, 1],
        ":",
        color="tab:red",
        lw=0.6,
        alpha=0.6,
        label="CoP, double support",
    )
    ax.plot(
        log.com_reference[:, 0],
        log.com_reference[:, 1],
        "--",
        color="0.5",
        lw=1.0,
        label="CoM reference",
    )
    checks = landing_check_times(schedule)
    labelled: set[int] = set()
    for k, t in enumerate(checks):
        if t > log.time[-1] + 1e-9:
            break
        i = min(int(np.searchsorted(log.time, t - 1e-9)), len(log) - 1)
        j = _SIDES.index(schedule.plan.steps[k].side)
        rect = foot_rectangle(
            log.sole_positions[i, j, :2],
            float(log.sole_yaws[i, j]),
            schedule.foot.length,
            schedule.foot.width,
        )
        ax.add_patch(
            Polygon(
                rect.vertices,
                closed=True,
                fill=True,
                alpha=0.15,
                color="tab:blue" if j == 0 else "tab:red",
                lw=0,
                label=None if j in labelled else f"landed {_SIDES[j].value} sole",
            )
        )
        labelled.add(j)
    place_legend_below(ax)
    fit_figure_to_data(ax)
    return fig


def plot_walk_over_time(schedule: ContactSchedule, log: WalkLog, *, title: str = ""):
    """CoM (measured and reference), ZMP reference and measured CoP over time, per axis."""
    fig = plot_com_zmp(
        schedule,
        log.time,
        log.com[:, :2],
        log.cop[:, :2],
        zmp_reference=log.zmp_reference,
        title=title or "CoM and CoP of the walk over time [m]",
    )
    for axis, ax in enumerate(fig.axes):
        _label_as_measured(ax)
        ax.plot(
            log.time, log.com_reference[:, axis], "--", color="0.4", lw=1.0, label="CoM reference"
        )
    fig.axes[0].legend(loc="best", fontsize=8)
    return fig


def plot_estimator(schedule: ContactSchedule, log: WalkLog, *, title: str = ""):
    """The state the controller received against the ground truth, over time: CoM x and y
    (true and estimated, each estimate at the time of the readings it came from), the CoM
    error [mm] and the base yaw error [deg]."""
    plt = _pyplot()
    fig, axes = plt.subplots(4, 1, figsize=(10, 9), sharex=True, layout="constrained")
    times = log.estimate_time
    for axis, ax in enumerate(axes[:2]):
        ax.plot(log.time, log.com[:, axis], color="k", lw=1.2, label="CoM (true)")
        ax.plot(times, log.estimated_com[:, axis], "--", color="tab:orange", lw=1.0)
        ax.lines[-1].set_label("CoM (estimated)")
        ax.set_ylabel(f"CoM {'xy'[axis]} [m]")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="best", fontsize=8)
    truth = np.column_stack([np.interp(times, log.time, log.com[:, k]) for k in range(3)])
    error = 1e3 * np.linalg.norm(log.estimated_com - truth, axis=1)
    axes[2].plot(times, error, color="tab:red", lw=0.8)
    axes[2].set_ylabel("CoM error [mm]")
    axes[2].grid(alpha=0.3)
    true_yaw = np.interp(times, log.time, np.unwrap(log.base_rpy[:, 2]))
    yaw_error = np.angle(np.exp(1j * (log.estimated_base_rpy[:, 2] - true_yaw)))
    axes[3].plot(times, np.degrees(yaw_error), color="tab:purple", lw=0.8)
    axes[3].set_ylabel("yaw error [deg]")
    axes[3].set_xlabel("time [s]")
    axes[3].grid(alpha=0.3)
    for ax in axes:
        for phase_start in (schedule.walk_start, schedule.walk_end):
            ax.axvline(phase_start, color="0.7", lw=0.6, ls=":")
    fig.suptitle(title or "Estimated state against the simulator's ground truth")
    return fig
