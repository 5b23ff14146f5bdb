"""The side view of a walk on a terrain (matplotlib, no screen): heights along the robot's
initial heading (the world's x axis).

:func:`plot_walk_side_view` draws the terrain's profile under the walk
(:meth:`Terrain.profile <mpcwalk.terrain.Terrain.profile>`, filled down to its floor), the
measured CoM height, each sole's height over x, the planned footsteps (at their planned
heights) and the landings as measured: ``side_view.png`` among a walk's figures when it has a
terrain (:func:`~mpcwalk.walking.outputs.write_walk_outputs`).
"""

import numpy as np

from mpcwalk.footsteps.footstep import Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.terrain import Terrain
from mpcwalk.walking.figures import fit_figure_to_data, place_legend_below
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import landing_check_times

#: Ground drawn before the walk's first and after its last point [m].
MARGIN = 0.3
#: Distance [m] between the points of the terrain's profile.
PROFILE_STEP = 0.002

_COLORS = {Side.LEFT: "tab:blue", Side.RIGHT: "tab:red"}


def walk_extent(schedule: ContactSchedule, log: WalkLog) -> tuple[float, float]:
    """The x range [m] of a walk: its planned footsteps and its measured CoM and soles,
    with :data:`MARGIN` each side."""
    plan = schedule.plan
    xs = [foot.position[0] for foot in (plan.initial_left, plan.initial_right, *plan.steps)]
    measured = np.concatenate([log.com[:, 0], log.sole_positions[:, :, 0].ravel()])
    measured = measured[np.isfinite(measured)]
    low = min(min(xs), float(measured.min()) if len(measured) else min(xs))
    high = max(max(xs), float(measured.max()) if len(measured) else max(xs))
    return low - MARGIN, high + MARGIN


def plot_walk_side_view(
    schedule: ContactSchedule, log: WalkLog, terrain: Terrain, *, title: str = ""
):
    """The walk seen from its side along the heading: the terrain's profile (at y = 0), the
    measured CoM height, the soles' heights over x, the planned footsteps and the landings.

    Args:
        schedule: The footsteps and phases of the walk.
        log: Its log.
        terrain: The terrain it walked on.
        title: Figure title.

    Returns:
        The matplotlib figure.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10.0, 4.0), layout="constrained")
    low, high = walk_extent(schedule, log)
    x = np.arange(low, high + PROFILE_STEP, PROFILE_STEP)
    ground = terrain.profile(x)
    bottom = min(terrain.floor, float(ground.min())) - 0.05
    ax.fill_between(x, bottom, ground, color="0.8", lw=0, label="terrain (y = 0)")
    ax.plot(x, ground, color="0.35", lw=1.0)
    ax.plot(log.com[:, 0], log.com[:, 2], color="k", lw=1.5, label="CoM (measured)")
    for j, side in enumerate((Side.LEFT, Side.RIGHT)):
        sole = log.sole_positions[:, j]
        ax.plot(sole[:, 0], sole[:, 2], color=_COLORS[side], lw=0.8, label=f"{side.value} sole")
    plan = schedule.plan
    for k, step in enumerate(plan.steps):
        ax.plot(
            step.position[0],
            step.position[2],
            "v",
            ms=5,
            mfc="none",
            color=_COLORS[step.side],
            label="planned footstep" if k == 0 else None,
        )
    labelled = False
    for k, t in enumerate(landing_check_times(schedule)):
        if not len(log) or t > log.time[-1] + 1e-9:
            break
        i = min(int(np.searchsorted(log.time, t - 1e-9)), len(log) - 1)
        j = 0 if plan.steps[k].side == Side.LEFT else 1
        landed = log.sole_positions[i, j]
        ax.plot(
            landed[0],
            landed[2],
            "o",
            ms=4,
            color=_COLORS[plan.steps[k].side],
            label=None if labelled else "landed sole",
        )
        labelled = True
    ax.set_xlim(low, high)
    top = max(float(np.nanmax(log.com[:, 2])) if len(log) else 0.0, float(ground.max()))
    ax.set_ylim(bottom, top + 0.1)
    ax.set_aspect("equal", adjustable="box")  # the stairs as they are
    ax.set_xlabel("x along the initial heading [m]")
    ax.set_ylabel("height [m]")
    ax.grid(True, alpha=0.3)
    place_legend_below(ax)
    ax.set_title(title or "The walk seen from its side: terrain, CoM and soles [m]")
    fit_figure_to_data(ax)
    return fig


__all__ = ["MARGIN", "plot_walk_side_view", "walk_extent"]
