"""Gravity's tilt in the soles' world: the slope of the ground a robot stands on, from its IMU.

The loaded flat soles set the estimator's roll and pitch, so its world is the ground's. On a
ground sloping by ``theta``, gravity is tilted in that world, and the accelerometer reads it:
the tilt ``g_xy / g_z`` (``tan(theta)`` towards the uphill azimuth) is

1. averaged while the robot stands at the start (:data:`CALIBRATION`): the IMU's mean
   specific force in the world less its mean acceleration (its velocity's change over the
   window, from the legs: a robot on a slope starts to lean at once), its slope less that of
   the soles' normal where they lie flat (the attitude filter leans a little towards the
   accelerometer's vertical; a sole rolling on an edge no longer shows the ground), used
   once it spans :data:`CALIBRATION_SPAN`;
2. then low-pass filtered at every tick with the feet loaded (every phase of the gait alike,
   so that the sway averages out; slopes beyond :data:`MAX_TILT`, a push's or an impact's,
   left out), over a long time: walking, the estimated pitch leans by up to a degree;
3. zero within a deadband (an accelerometer bias of 5 mg reads as 0.3 deg; on the level floor
   with noise, latency, low friction or 1 cm bumps it read up to 1.55 deg), so that a level
   floor gives exactly zero, ramped in over :data:`RAMP` of it, and passed through three
   first-order stages of :data:`SMOOTHING_TIME_CONSTANT` (it moves the IK's CoM target, whose
   acceleration the servo feed-forward turns into torques: one stage passes a step into the
   target's velocity, two into its acceleration).

:class:`GravityTilt` holds that state; :class:`~mpcwalk.estimation.estimator.Estimator` feeds
it, puts its value in ``EstimatedState.ground_tilt`` and adds its :meth:`GravityTilt.gravity`
to the specific force to predict the base's acceleration (on a slope, gravity less only its
vertical part left ``g tan(theta)`` of acceleration in the prediction).
"""

import math

import numpy as np

from mpcwalk._checks import checked_number

CALIBRATION = (0.1, 0.5)
"""Times [s] after the start between which gravity's tilt is averaged (the robot stands on
its flat soles; before, it settles on them)."""

CALIBRATION_SPAN = 0.15
"""Span [s] of the start's average from which the tilt is used (a robot on a steep slope
starts to lean at once: waiting for the whole average made `atlas-like` fall at 4.7 deg)."""

MAX_TILT = math.tan(math.radians(20.0))
"""Largest slope of the specific force read as gravity's (beyond: a push or an impact)."""

RAMP = 0.25
"""Width of the ramp that brings the tilt in past its deadband, relative to the deadband."""

SMOOTHING_TIME_CONSTANT = 0.15
"""Time constant [s] of each of the three smoothing stages."""


class GravityTilt:
    """Gravity's tilt in the soles' world, from the IMU and the soles.

    Args:
        time_constant: Time constant [s] of the low-pass after the start's average.
        deadband_deg: Tilt [deg] read as a level floor (ramped in up to 1.25 times it; 0:
            none).

    Raises:
        ConfigurationError: A time constant that is not positive, a deadband outside
            [0, 20] deg.
    """

    def __init__(self, *, time_constant: float = 20.0, deadband_deg: float = 2.0) -> None:
        self.time_constant = checked_number(
            "tilt_time_constant", time_constant, low=0.0, low_inclusive=False, unit="s"
        )
        self.deadband = math.tan(
            math.radians(
                checked_number("tilt_deadband_deg", deadband_deg, low=0.0, high=20.0, unit="deg")
            )
        )
        self.reset()

    def reset(self) -> None:
        """Forget everything: the start's average begins again."""
        self._tilt = np.zeros(2)  # low-passed
        self._stages = [np.zeros(2) for _ in range(3)]  # past the deadband, smoothed
        self._time = 0.0  # [s] since the start
        self._calibration: dict | None = None  # the start's sums
        self._ready = False  # the start's average spans CALIBRATION_SPAN

    @property
    def raw(self) -> np.ndarray:
        """The tilt before the deadband and the smoothing, shape (2,)."""
        return self._tilt.copy()

    @property
    def value(self) -> np.ndarray | None:
        """The tilt, shape (2,); None while it is level (exactly)."""
        tilt = self._stages[-1]
        if not (tilt[0] or tilt[1]):
            return None
        return tilt.copy()

    def gravity(self, norm: float) -> np.ndarray:
        """Gravity of norm ``norm`` [m/s^2] in the world as it reads so far, shape (3,):
        ``g_z (t, 1)`` with the tilt ``t`` (:attr:`value`) and ``g_z = -norm / sqrt(1 +
        |t|^2)``; exactly ``(0, 0, -norm)`` while the ground reads level."""
        tilt = self._stages[-1]
        if not (tilt[0] or tilt[1]):
            return np.array((0.0, 0.0, -norm))
        vertical = -norm / math.sqrt(1.0 + float(tilt[0]) ** 2 + float(tilt[1]) ** 2)
        return np.array((vertical * float(tilt[0]), vertical * float(tilt[1]), vertical))

    def update(
        self,
        specific_force: np.ndarray,
        velocity: np.ndarray,
        normals: np.ndarray,
        flat: np.ndarray,
        load: float,
        trusted: bool,
        dt: float,
    ) -> None:
        """One tick.

        Args:
            specific_force: The IMU's specific force, world frame, shape (3,) [m/s^2].
            velocity: The IMU's velocity from the legs, world frame, shape (3,) [m/s].
            normals: The soles' normals (z axes), world frame, shape (2, 3).
            flat: Each foot's trust as flat on the ground (load times its CoP's distance
                from the edges), shape (2,).
            load: The feet's load, share of the weight.
            trusted: Whether the accelerometer reads gravity now (its norm near g).
            dt: Time since the last tick [s].
        """
        self._time += dt
        if self._time >= CALIBRATION[0] and specific_force[2] > 0.0:
            if self._time < CALIBRATION[1]:
                self._average(specific_force, velocity, normals, flat)
            elif load >= 0.3 and trusted:
                tilt = specific_force[:2] / specific_force[2]
                if float(tilt @ tilt) <= MAX_TILT**2:  # else a push, an impact
                    self._tilt += min(dt / self.time_constant, 1.0) * (tilt - self._tilt)
        self._smooth(dt)

    def _average(
        self, force: np.ndarray, velocity: np.ndarray, normals: np.ndarray, flat: np.ndarray
    ) -> None:
        """The start's average (see the module)."""
        calibration = self._calibration
        if calibration is None:
            self._calibration = calibration = {
                "start": self._time,
                "velocity": velocity.copy(),
                "force": np.zeros(3),
                "normal": np.zeros(3),
                "n": 0,
                "flat": 0.0,
            }
        calibration["force"] += force
        calibration["n"] += 1
        total = float(flat.sum())
        if total > 0.3:
            calibration["normal"] += flat @ normals
            calibration["flat"] += total
        span = self._time - calibration["start"]
        if span > 0.0 and calibration["flat"] > 0.0:
            mean = calibration["force"] / calibration["n"]
            mean -= (velocity - calibration["velocity"]) / span
            normal = calibration["normal"] / calibration["flat"]
            tilt = mean[:2] / mean[2] - normal[:2] / normal[2]
            if float(tilt @ tilt) <= MAX_TILT**2:
                self._tilt = tilt
                self._ready = self._ready or span >= CALIBRATION_SPAN

    def _smooth(self, dt: float) -> None:
        """The tilt past its deadband through the three smoothing stages."""
        tilt = self._tilt
        norm = math.hypot(float(tilt[0]), float(tilt[1]))
        dead = self.deadband
        target = np.zeros(2)
        if norm > dead and self._ready:
            target = tilt * (min((norm - dead) / (RAMP * dead), 1.0) if dead > 0.0 else 1.0)
        elif max(float(np.abs(stage).max()) for stage in self._stages) < 1e-5:
            for stage in self._stages:  # level: exactly (a decay never reaches zero)
                stage[:] = 0.0
            return
        share = min(dt / SMOOTHING_TIME_CONSTANT, 1.0)
        for stage in self._stages:
            stage += share * (target - stage)
            target = stage


__all__ = ["CALIBRATION", "GravityTilt"]
