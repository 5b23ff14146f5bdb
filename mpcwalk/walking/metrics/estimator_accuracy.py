"""How well the controller knew the robot during a walk: :class:`EstimatorAccuracy`.

The state the controller receives each tick is estimated from sensor readings taken a
latency earlier (:attr:`~mpcwalk.walking.log.WalkLog.estimate_time`). Its errors are measured
against the simulator's ground truth at the time of those readings, so that they are the
estimator's errors alone; what the latency itself costs shows in the walk's other metrics.
"""

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from mpcwalk.footsteps.footstep import wrap_angle
from mpcwalk.walking.log import WalkLog


@dataclass(frozen=True)
class EstimatorAccuracy:
    """Errors of the estimated state against the ground truth over a walk.

    All None when the controller read the ground truth (``state="oracle"``) or no estimate
    lies within the log.

    Attributes:
        estimator_com_error_rms_m: RMS over the ticks of the distance between the estimated
            and the true CoM (3D) [m].
        estimator_com_error_max_m: Its largest value [m].
        estimator_com_error_support_rms_m: RMS of the error of the CoM relative to the
            support (the mean of the soles in contact, or of both soles in flight) [m]: what
            the balance feedback acts on. Unlike the world-frame error it holds no odometry
            drift (a heading drift of the gyroscope's residual bias turns the estimated walk
            by a fraction of a degree, i.e. centimetres over metres of walking).
        estimator_com_velocity_error_rms_m_s: RMS of the norm of the CoM velocity error (3D)
            [m/s].
        estimator_yaw_drift_deg: Estimated minus true base yaw at the end of the walk, less
            the same difference at its start [deg] (signed: the drift over the walk).
    """

    estimator_com_error_rms_m: float | None = None
    estimator_com_error_max_m: float | None = None
    estimator_com_error_support_rms_m: float | None = None
    estimator_com_velocity_error_rms_m_s: float | None = None
    estimator_yaw_drift_deg: float | None = None

    @classmethod
    def from_log(cls, log: WalkLog, *, state_source: str = "estimator") -> "EstimatorAccuracy":
        """The errors of the walk's estimates (see the class docstring).

        Args:
            log: The walk's log (ground truth and estimates).
            state_source: Where the controller's state came from; ``"oracle"`` gives Nones.
        """
        if state_source != "estimator" or not len(log):
            return cls()
        times = log.estimate_time
        valid = (times >= log.time[0] - 1e-9) & (times <= log.time[-1] + 1e-9)
        if not np.any(valid):
            return cls()
        times = times[valid]

        def truth(series: np.ndarray) -> np.ndarray:
            return np.column_stack(
                [np.interp(times, log.time, series[:, k]) for k in range(series.shape[1])]
            )

        com_error = np.linalg.norm(log.estimated_com[valid] - truth(log.com), axis=1)
        contact = np.column_stack(
            [np.interp(times, log.time, log.contact[:, k].astype(float)) > 0.5 for k in (0, 1)]
        )
        contact[~contact.any(axis=1)] = True
        weights = contact / contact.sum(axis=1, keepdims=True)
        true_soles = np.stack([truth(log.sole_positions[:, k]) for k in (0, 1)], axis=1)
        true_support = np.einsum("nk,nkj->nj", weights, true_soles)
        estimated_support = np.einsum("nk,nkj->nj", weights, log.estimated_sole_positions[valid])
        support_error = np.linalg.norm(
            (log.estimated_com[valid] - estimated_support) - (truth(log.com) - true_support),
            axis=1,
        )
        velocity_error = np.linalg.norm(
            log.estimated_com_velocity[valid] - truth(log.com_velocity), axis=1
        )
        true_yaw = np.interp(times, log.time, np.unwrap(log.base_rpy[:, 2]))
        yaw_error = np.asarray(wrap_angle(log.estimated_base_rpy[valid, 2] - true_yaw))
        return cls(
            estimator_com_error_rms_m=float(np.sqrt(np.mean(com_error**2))),
            estimator_com_error_max_m=float(com_error.max()),
            estimator_com_error_support_rms_m=float(np.sqrt(np.mean(support_error**2))),
            estimator_com_velocity_error_rms_m_s=float(np.sqrt(np.mean(velocity_error**2))),
            estimator_yaw_drift_deg=float(np.degrees(wrap_angle(yaw_error[-1] - yaw_error[0]))),
        )

    def to_dict(self) -> dict[str, Any]:
        """The ``metrics.json`` keys."""
        return asdict(self)
