"""Fault containment in the control tick: every value that crosses into the controller is
checked once, at that boundary, and a bad one is replaced, counted and bounded.

- **Measurements** (the estimated state the controller receives): a non-finite CoM, CoM
  velocity, sole pose or attitude is a sensor fault; the controller uses the last good
  estimate instead.
- **Generator**: a failed solve, a back-end that raises or returns garbage, is a failed solve
  (checked in :mod:`mpcwalk.generators.receding_horizon`); the generator follows its last plan,
  then coasts (:meth:`~mpcwalk.generators.pattern_generator.PatternGenerator.coast`).
- **IK output**: a non-finite configuration is an IK failure; the reference holds.
- **Joint targets** (after the feed-forward and the stabilizers): non-finite targets are
  replaced by the last good ones: NaN never reaches the actuators.

Each tick with any of these is a fallback tick. After ``max_fault_ticks`` fallback ticks in
a row the controller stops the walk (:class:`~mpcwalk.exceptions.ControllerStopped`, with
the reason): a controlled stop, not a crash; the walk's log and metrics are still written.
"""

from dataclasses import dataclass, field, replace

import numpy as np

from mpcwalk._checks import all_finite
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError, ControllerStopped, NoSolutionFound
from mpcwalk.generators.pattern_generator import GeneratorOutput, PatternGenerator
from mpcwalk.ik.targets import IKResult, IKTargets
from mpcwalk.ik.whole_body_ik import WholeBodyIK
from mpcwalk.models.com_state import ComState

#: Fallback ticks in a row after which the walk stops (0.25 s at a 10 ms tick).
DEFAULT_MAX_FAULT_TICKS = 25


def estimate_is_finite(state: EstimatedState | ComState | None) -> bool:
    """Whether the values the controller reads from ``state`` are all finite."""
    if not isinstance(state, (EstimatedState, ComState)):
        return True  # None, or a wrong type the controller names
    if isinstance(state, ComState):
        return bool(np.all(np.isfinite(state.as_cart_table(np.zeros(2)))))
    values = (
        state.com,
        state.com_velocity,
        state.sole_positions,
        state.sole_rotations,
        state.q,
        state.v,
        state.sensors.imu.gyro,
        state.sensors.imu.accelerometer,
    )
    return all_finite(values, (state.roll, state.pitch, state.yaw))


def step_generator(
    generator: PatternGenerator, measured: ComState | None, dcm_error: np.ndarray
) -> tuple[GeneratorOutput, bool]:
    """Generator step that never raises NoSolutionFound: ``(output, failed)``. After its own
    fallback ticks the generator coasts on its last reference with zero jerk for this tick
    (and moves its own clock)."""
    try:
        output = generator.step(measured, dcm_error=dcm_error)
    except NoSolutionFound as error:
        return generator.coast(solver=error.solver), True
    return output, output.solve is not None and not output.solve.success


def ik_step(
    ik: WholeBodyIK, q: np.ndarray, targets: IKTargets, dt: float, held: IKResult
) -> IKResult:
    """One IK step; targets the IK refuses (not finite) give ``held`` with a non-finite
    configuration, which :meth:`FaultMonitor.ik` counts and replaces."""
    try:
        return ik.solve(q, targets, dt)
    except ConfigurationError:
        return replace(held, q_next=np.full_like(q, np.nan), status="refused targets")


@dataclass
class FaultMonitor:
    """Counts the faults of a walk and stops it after too many fallback ticks in a row.

    Attributes:
        max_fault_ticks: Fallback ticks in a row tolerated (then ControllerStopped).
        sensor_faults: Ticks whose estimate was not finite (the last good one was used).
        ik_failures: Ticks whose IK output was not finite (the reference held).
        target_faults: Ticks whose joint targets were not finite (the last good ones held).
        generator_failures: Ticks whose generator solve failed.
        fallback_ticks: Ticks with any of these.
    """

    max_fault_ticks: int = DEFAULT_MAX_FAULT_TICKS
    sensor_faults: int = 0
    ik_failures: int = 0
    target_faults: int = 0
    generator_failures: int = 0
    fallback_ticks: int = 0
    _in_a_row: int = 0
    _tick_faults: list[str] = field(default_factory=list)
    _last_estimate: EstimatedState | ComState | None = None

    def __post_init__(self) -> None:
        value = self.max_fault_ticks
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise ConfigurationError(
                f"max_fault_ticks must be a non-negative integer, got {value!r}."
            )

    def measurement(
        self, state: EstimatedState | ComState | None
    ) -> EstimatedState | ComState | None:
        """``state`` if finite, else the last good estimate (a sensor fault)."""
        if estimate_is_finite(state):
            self._last_estimate = state
            return state
        self.sensor_faults += 1
        self._tick_faults.append("non-finite estimate")
        return self._last_estimate

    def note_sensor_fault(self) -> None:
        """A reading that was bad or did not arrive (the caller kept the last estimate)."""
        self.sensor_faults += 1
        self._tick_faults.append("bad or missing sensor readings")

    def generator(self, failed: bool) -> None:
        """Record this tick's generator outcome."""
        if failed:
            self.generator_failures += 1
            self._tick_faults.append("failed solve")

    def ik(self, q_next: np.ndarray, q_hold: np.ndarray) -> np.ndarray:
        """``q_next`` if finite, else ``q_hold`` (an IK failure)."""
        if all_finite((q_next,)):
            return q_next
        self.ik_failures += 1
        self._tick_faults.append("non-finite IK output")
        return q_hold.copy()

    def joint_targets(self, targets: np.ndarray, hold: np.ndarray) -> np.ndarray:
        """``targets`` if finite, else ``hold`` (the last good targets)."""
        if all_finite((targets,)):
            return targets
        self.target_faults += 1
        self._tick_faults.append("non-finite joint targets")
        return hold.copy()

    def end_tick(self, time: float) -> None:
        """Close the tick; raise ControllerStopped after too many fallback ticks in a row."""
        faults, self._tick_faults = self._tick_faults, []
        if not faults:
            self._in_a_row = 0
            return
        self.fallback_ticks += 1
        self._in_a_row += 1
        if self._in_a_row > self.max_fault_ticks:
            raise ControllerStopped(
                f"{self._in_a_row} fallback ticks in a row up to t = {time:.3f} s (last: "
                f"{', '.join(sorted(set(faults)))}); the bound is {self.max_fault_ticks}"
            )
