"""Metrics of planned and executed walks."""

import numpy as np

from mpcwalk.gait.contact_schedule import ContactSchedule


def support_margins(schedule: ContactSchedule, times, points) -> np.ndarray:
    """Signed distance of points to the support polygon of their time.

    Args:
        schedule: Contact schedule giving the polygon at each time.
        times: Shape (n,), in [s].
        points: Shape (n, 2), in [m].

    Returns:
        Shape (n,), in [m], positive inside the support polygon.
    """
    times = np.asarray(times, dtype=float)
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    idx = schedule.phase_index(times)
    margins = np.empty(len(times))
    for i in np.unique(idx):
        sel = idx == i
        margins[sel] = schedule.phases[i].polygon.signed_distance(points[sel])
    return margins
