"""The one protocol every CoM/ZMP pattern generator answers.

A generator is reset with a :class:`~mpcwalk.gait.ContactSchedule` (footsteps
and timing) and an initial CoM state, then stepped once per control period.
Each step may receive the measured CoM state: closed-loop generators (preview
control, MPC) start their prediction from it, open-loop ones (closed forms)
ignore it. Every step returns a :class:`GeneratorOutput`.
"""

import time
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.lipm import LIPM


def _vec2(value, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float).ravel()
    if arr.shape == (3,):
        arr = arr[:2]
    if arr.shape != (2,) or not np.all(np.isfinite(arr)):
        raise ConfigurationError(f"{name} must be 2 finite numbers (x, y), got {value!r}.")
    return arr


@dataclass(frozen=True)
class ComState:
    """Horizontal CoM state.

    Attributes:
        position: CoM ground projection, shape (2,), in [m].
        velocity: Shape (2,), in [m]/[s].
        acceleration: Shape (2,), in [m]/[s]^2, or None when unknown (a
            generator then keeps its own estimate).
    """

    position: np.ndarray
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    acceleration: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _vec2(self.position, "ComState.position"))
        object.__setattr__(self, "velocity", _vec2(self.velocity, "ComState.velocity"))
        if self.acceleration is not None:
            object.__setattr__(
                self, "acceleration", _vec2(self.acceleration, "ComState.acceleration")
            )

    def as_cart_table(self, default_acceleration=None) -> np.ndarray:
        """State matrix of shape (3, 2): rows position, velocity, acceleration."""
        acc = self.acceleration
        if acc is None:
            acc = np.zeros(2) if default_acceleration is None else default_acceleration
        return np.vstack([self.position, self.velocity, acc])


@dataclass(frozen=True)
class Horizon:
    """Predicted trajectory over a generator's preview window.

    Attributes:
        times: Sample times, shape (n,), in [s].
        com: CoM positions, shape (n, 2), in [m].
        zmp: ZMP positions, shape (n, 2), in [m].
    """

    times: np.ndarray
    com: np.ndarray
    zmp: np.ndarray


@dataclass(frozen=True)
class SolveInfo:
    """What the optimisation of one tick did (None for closed forms).

    Attributes:
        success: Whether the QP was solved.
        solver: Back-end name.
        status: Back-end status string.
        solve_time: Wall time of the solver call, in [s].
        fallback: True when the solve failed and the shifted previous plan was
            used instead.
        consecutive_failures: Failed solves in a row, including this one.
    """

    success: bool
    solver: str
    status: str = ""
    solve_time: float = 0.0
    fallback: bool = False
    consecutive_failures: int = 0


@dataclass(frozen=True)
class GeneratorOutput:
    """CoM reference at one tick.

    Attributes:
        time: Time of this reference, in [s].
        com: CoM ground projection, shape (2,), in [m].
        com_velocity: Shape (2,), in [m]/[s].
        com_acceleration: Shape (2,), in [m]/[s]^2.
        zmp: ZMP implied by the LIPM, shape (2,), in [m].
        com_height: Constant CoM height, in [m].
        horizon: Predicted trajectory, or None.
        solve: Optimisation report, or None for closed forms.
        schedule: The contact schedule the generator follows from now on, when it changed
            it this tick (footstep-adaptive generators move the future footsteps); None when
            it did not. The controller then moves its swing foot and support polygons to it.
    """

    time: float
    com: np.ndarray
    com_velocity: np.ndarray
    com_acceleration: np.ndarray
    zmp: np.ndarray
    com_height: float
    horizon: Horizon | None = None
    solve: SolveInfo | None = None
    schedule: ContactSchedule | None = None

    @property
    def state(self) -> ComState:
        """The CoM state of this output."""
        return ComState(self.com, self.com_velocity, self.com_acceleration)


class PatternGenerator(ABC):
    """Base class of CoM/ZMP pattern generators.

    Args:
        lipm: Pendulum model (CoM height, gravity).
        control_period: Time between two calls of :meth:`step`, in [s].
    """

    #: Name used on the command line and in :func:`make_generator`.
    name: ClassVar[str] = ""
    #: Share of the measured CoM error a :class:`~mpcwalk.control.controller.WalkingController` feeds
    #: back into this generator by default (its ``observer_gain``; closed forms ignore it).
    observer_gain: ClassVar[float] = 0.05

    @classmethod
    def robot_options(cls, robot) -> dict:
        """Keyword arguments of this generator taken from a robot (its preset's walking
        defaults, its leg limits); :meth:`WalkingController.for_robot
        <mpcwalk.control.controller.WalkingController.for_robot>` passes them under the caller's."""
        return {}

    def __init__(self, *, lipm: LIPM = LIPM(), control_period: float = 0.01) -> None:
        if not np.isfinite(control_period) or control_period <= 0.0:
            raise ConfigurationError(
                f"control_period must be a positive number of seconds, got {control_period!r}."
            )
        self.lipm = lipm
        self.control_period = float(control_period)
        self.schedule: ContactSchedule | None = None
        self.tick = 0

    @property
    def time(self) -> float:
        """Time of the last output, in [s]."""
        return self.tick * self.control_period

    @property
    def done(self) -> bool:
        """Whether the schedule is over."""
        return self.schedule is not None and self.time >= self.schedule.duration - 1e-9

    def reset(
        self, schedule: ContactSchedule, initial_state: ComState | None = None
    ) -> GeneratorOutput:
        """Start a walk.

        Args:
            schedule: Footsteps and timing to follow.
            initial_state: CoM state at time 0; by default at rest above the
                midpoint of the initial feet.

        Returns:
            The reference at time 0.
        """
        if initial_state is None:
            initial_state = ComState(schedule.torso_waypoints[0], np.zeros(2), np.zeros(2))
        self.schedule = schedule
        self.tick = 0
        return self._reset(schedule, initial_state)

    def observe_dcm_error(self, error: np.ndarray) -> None:
        """Told by a closed-loop controller, before :meth:`step`, the measured DCM minus the
        reference DCM [m], shape (2,), of this tick (whatever share of the CoM error it passes
        to :meth:`step`). Generators that adapt footsteps use it; others ignore it."""

    def step(self, measured: ComState | None = None) -> GeneratorOutput:
        """Advance by one control period.

        Args:
            measured: Measured CoM state at the current time (feedback); None
                runs the generator on its own prediction.

        Returns:
            The reference at the new time.
        """
        if self.schedule is None:
            raise NotReset(
                f"{type(self).__name__}.step() was called before reset(); call "
                "reset(schedule) first."
            )
        out = self._step(measured)
        self.tick += 1
        return out

    @abstractmethod
    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        """Generator-specific reset; return the output at time 0."""

    @abstractmethod
    def _step(self, measured: ComState | None) -> GeneratorOutput:
        """Generator-specific tick from :attr:`time` to ``time + control_period``."""

    def _output(self, t: float, state: np.ndarray, **kwargs) -> GeneratorOutput:
        """Output from a cart-table state of shape (3, 2)."""
        zmp = state[0] - state[2] / self.lipm.omega**2
        return GeneratorOutput(
            time=t,
            com=state[0].copy(),
            com_velocity=state[1].copy(),
            com_acceleration=state[2].copy(),
            zmp=zmp,
            com_height=self.lipm.com_height,
            **kwargs,
        )


def timed_step(generator: PatternGenerator, measured: ComState | None = None):
    """Step a generator and measure its wall time.

    Returns:
        ``(output, seconds)``.
    """
    t0 = time.perf_counter()
    out = generator.step(measured)
    return out, time.perf_counter() - t0
