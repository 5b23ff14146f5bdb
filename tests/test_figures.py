"""The walk's figures: a straight walk's top view uses its space, the measured CoP is drawn
per support phase, both feet have their legend, every figure has a title."""

import numpy as np
import pytest

from mpcwalk.walking.figures import (
    broken_at_phase_changes,
    plot_estimator,
    plot_walk_over_time,
    plot_walk_top_view,
)
from mpcwalk.walking.runner import run_walk


@pytest.fixture(scope="module")
def walk():
    return run_walk("bioloid-like", controller="mpc", command=(0.1, 0.0, 0.0), nb_steps=4)


def test_a_straight_walks_top_view_is_short_and_wide(walk):
    fig = plot_walk_top_view(walk.schedule, walk.log)
    width, height = fig.get_size_inches()
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert (x1 - x0) > 1.8 * (y1 - y0)  # the walk: 0.33 m long, 0.15 m wide
    assert height < 0.5 * width  # the figure follows (it was 4.8 in tall for 10 in)
    assert ax.get_title()


def test_the_cop_is_drawn_per_support_phase_and_both_landed_feet_have_a_legend(walk):
    fig = plot_walk_top_view(walk.schedule, walk.log)
    ax = fig.axes[0]
    labels = [text.get_text() for text in ax.get_legend().get_texts()]
    assert "landed left sole" in labels and "landed right sole" in labels
    single = next(line for line in ax.get_lines() if line.get_label() == "CoP, single support")
    x = np.asarray(single.get_xdata(), dtype=float)
    # the single-support trace breaks at every phase change: no segment joins two phases
    phases = walk.schedule.phase_index(walk.log.time)
    assert np.isnan(x).sum() >= np.count_nonzero(np.diff(phases))
    points = broken_at_phase_changes(walk.schedule, walk.log.time, walk.log.cop[:, :2])
    assert len(points) == len(walk.log) + np.count_nonzero(np.diff(phases))


def test_every_figure_has_a_title(walk):
    assert plot_walk_over_time(walk.schedule, walk.log).axes[0].get_title()
    estimator = plot_estimator(walk.schedule, walk.log)
    assert estimator._suptitle is not None and estimator._suptitle.get_text()
