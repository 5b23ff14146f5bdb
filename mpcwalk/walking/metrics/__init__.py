"""What a walk measured: :class:`WalkMetrics` (the keys of ``metrics.json``) and the
measures it is made of.

- :mod:`~mpcwalk.walking.metrics.walk_metrics`: :func:`compute_walk_metrics` (outcome,
  steps, landings, distance, timing), the sanity warnings;
- :mod:`~mpcwalk.walking.metrics.cop_margins`: the measured CoP against the support of the
  soles that carry force (its definition);
- :mod:`~mpcwalk.walking.metrics.estimator_accuracy`: the estimated state against the
  ground truth;
- :mod:`~mpcwalk.walking.metrics.attitude`: roll, pitch, yaw rate, the planned heading and
  the yaw deviation a push causes.
"""

from mpcwalk.walking.metrics.attitude import (
    attitude_metrics,
    planned_yaw_change,
    yaw_deviation_deg,
)
from mpcwalk.walking.metrics.cop_margins import (
    cop_margins,
    loaded_soles,
    measured_support_polygon,
    measured_zmp,
)
from mpcwalk.walking.metrics.estimator_accuracy import EstimatorAccuracy
from mpcwalk.walking.metrics.walk_metrics import (
    WalkMetrics,
    compute_walk_metrics,
    landing_check_times,
    sanity_warnings,
)

__all__ = [
    "EstimatorAccuracy",
    "WalkMetrics",
    "attitude_metrics",
    "compute_walk_metrics",
    "cop_margins",
    "landing_check_times",
    "loaded_soles",
    "measured_support_polygon",
    "measured_zmp",
    "planned_yaw_change",
    "sanity_warnings",
    "yaw_deviation_deg",
]
