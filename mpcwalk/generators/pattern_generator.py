"""The one protocol every CoM/ZMP pattern generator answers.

A generator is reset with a :class:`~mpcwalk.gait.ContactSchedule` (footsteps
and timing) and an initial CoM state, then stepped once per control period with
one input: the measured CoM state (closed-loop generators, preview control and
MPC, start their prediction from it; open-loop ones, the closed forms, ignore it)
and the DCM error a closed-loop controller measured (footstep-adaptive generators
use it). Every step returns a :class:`GeneratorOutput`. The generator owns its
clock: :meth:`PatternGenerator.step` and :meth:`PatternGenerator.coast` advance it.
"""

import time
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar, TypeVar

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.height_profile import height_profile
from mpcwalk.generators.robot_traits import RobotTraits
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState
from mpcwalk.models.flywheel import FlywheelState
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.deferred import deferred_item

G = TypeVar("G", bound="PatternGenerator")


@dataclass(frozen=True, init=False)
class Horizon:
    """Predicted trajectory over a generator's preview window.

    Attributes:
        times: Sample times, shape (n,), in [s].
        com: CoM positions, shape (n, 2), in [m].
        zmp: ZMP positions, shape (n, 2), in [m].

    ``com`` and ``zmp`` are given as arrays, or as ``states``: a function of no argument
    that returns them, called the first time one is read (the QP generators' horizon, made
    from their plan's :class:`~mpcwalk.qp.program.Prediction` only when asked for).
    """

    times: np.ndarray
    _states: "tuple[np.ndarray, np.ndarray] | Callable[[], tuple[np.ndarray, np.ndarray]]" = field(
        repr=False, compare=False
    )

    def __init__(
        self,
        times: np.ndarray,
        com: np.ndarray | None = None,
        zmp: np.ndarray | None = None,
        *,
        states: "Callable[[], tuple[np.ndarray, np.ndarray]] | None" = None,
        _states: Any = None,  # (replace's)
    ) -> None:
        held = states if states is not None else _states
        self.__dict__.update(times=times, _states=(com, zmp) if held is None else held)

    com = deferred_item("_states", 0, "CoM positions, shape (n, 2), in [m].")
    zmp = deferred_item("_states", 1, "ZMP positions, shape (n, 2), in [m].")


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
        flywheel: The upper body's lean and angular momentum a hip-strategy generator plans
            (:mod:`mpcwalk.models.flywheel`), None for the others; ``zmp`` is then the ZMP
            (inside the support), not the CMP the CoM accelerates from.
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
    flywheel: FlywheelState | None = None

    @property
    def state(self) -> ComState:
        """The CoM state of this output."""
        return ComState(self.com, self.com_velocity, self.com_acceleration)


#: Shortest control period [s] (MuJoCo's physics steps are 1 to 2 ms; below this a walk is
#: millions of ticks).
MIN_CONTROL_PERIOD = 1e-3
#: Longest control period [s]: a tenth of a 0.5 s step.
MAX_CONTROL_PERIOD = 0.05


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
    #: Whether the generator reads the schedule at every tick, so that the controller may turn
    #: the footsteps still to come (:class:`~mpcwalk.control.heading_hold.HeadingHold`).
    follows_new_footsteps: ClassVar[bool] = False
    #: ``(step duration [s], double support ratio)`` this generator walks with when the caller
    #: gives none, or None: the robot preset's (the dynamic gaits walk at any robot's timing).
    default_timing: ClassVar[tuple[float, float] | None] = None
    #: Whether every single support holds the CoM above the support foot (paper A's static
    #: gait): the swing leg then lands a step ahead of a CoM still above the other foot, on a
    #: nearly straight knee at long steps, and the controller builder damps the whole-body IK
    #: for it (:data:`~mpcwalk.walking.controller_builder.STATIC_IK_DAMPING`).
    holds_com_over_support: ClassVar[bool] = False

    @classmethod
    def check_timing(cls, schedule: ContactSchedule, lipm: LIPM) -> None:
        """Refuse, before any walk, a schedule whose timing this generator cannot realise
        (raises ConfigurationError saying the fastest feasible timing); accepts any here."""

    @classmethod
    def robot_options(cls, robot: RobotTraits) -> dict[str, Any]:
        """Keyword arguments of this generator taken from a robot's traits (its walking
        defaults, the ``[gait]`` table of its preset, its leg limits...); none by default.
        :meth:`for_robot` passes them under the caller's options."""
        return {}

    @classmethod
    def for_robot(cls: type[G], robot: RobotTraits, **options: Any) -> G:
        """Generator on the robot's LIPM (its CoM height) with its :meth:`robot_options`;
        ``options`` override them (e.g. ``control_period=0.01``)."""
        defaults = cls.robot_options(robot)
        return cls(**{"lipm": LIPM(com_height=robot.com_height), **defaults, **options})

    def __init__(self, *, lipm: LIPM = LIPM(), control_period: float = 0.01) -> None:
        control_period = checked_number(
            "control_period",
            control_period,
            low=MIN_CONTROL_PERIOD,
            high=MAX_CONTROL_PERIOD,
            unit="s",
            fix="e.g. control_period=0.01",
        )
        if not isinstance(lipm, LIPM):
            raise ConfigurationError(
                f"lipm must be a LIPM, got {type(lipm).__name__} {lipm!r}; e.g. "
                "lipm=LIPM(com_height=0.23)."
            )
        self.lipm = lipm
        self.control_period = float(control_period)
        self.schedule: ContactSchedule | None = None
        self.tick = 0
        self.time_offset = 0.0
        """Schedule time gained by landings brought forward (step-timing adaptation), [s]."""
        self._dcm_error = np.zeros(2)
        self._last_output: GeneratorOutput | None = None

    @property
    def time(self) -> float:
        """Time of the last output on the schedule's clock, in [s] (the ticks' time, ahead by
        :attr:`time_offset` when a generator brought landings forward)."""
        return self.tick * self.control_period + self.time_offset

    @property
    def current_schedule(self) -> ContactSchedule:
        """The schedule being followed (:attr:`schedule`).

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        if self.schedule is None:
            raise NotReset(
                f"{type(self).__name__} has no schedule yet; call reset(schedule) first."
            )
        return self.schedule

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
        self.time_offset = 0.0
        self._dcm_error = np.zeros(2)
        self._last_output = self._reset(schedule, initial_state)
        return self._last_output

    @property
    def dcm_error(self) -> np.ndarray:
        """DCM error given to the current :meth:`step`, shape (2,), in [m]."""
        return self._dcm_error

    def step(
        self, measured: ComState | None = None, *, dcm_error: np.ndarray | None = None
    ) -> GeneratorOutput:
        """Advance by one control period.

        Args:
            measured: Measured CoM state at the current time (feedback); None
                runs the generator on its own prediction.
            dcm_error: Measured DCM minus the reference DCM of this tick, shape (2,), in
                [m] (whatever share of the CoM error ``measured`` carries); None: zero.
                Generators that adapt footsteps use it; others ignore it.

        Returns:
            The reference at the new time.

        Raises:
            NotReset: :meth:`reset` was not called.
            NoSolutionFound: An optimising generator failed more often in a row than its
                fallback allows; :meth:`coast` then continues the reference.
        """
        if self.schedule is None:
            raise NotReset(
                f"{type(self).__name__}.step() was called before reset(); call "
                "reset(schedule) first."
            )
        self._dcm_error = np.zeros(2) if dcm_error is None else _dcm_error(dcm_error)
        out = self._step(measured)
        self.tick += 1
        self._last_output = out
        return out

    def coast(self, *, solver: str = "") -> GeneratorOutput:
        """Advance by one control period without the generator: the last reference goes on
        with zero jerk (what a caller that must not stop does after :meth:`step` raised
        NoSolutionFound). The generator's own state is left as it was, so that its next
        :meth:`step` starts from there (or from the measured state).

        Args:
            solver: Back-end name for the output's :class:`SolveInfo` (``fallback`` True).

        Returns:
            The reference at the new time.

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        previous = self._last_output
        if previous is None:
            raise NotReset(
                f"{type(self).__name__}.coast() was called before reset(); call "
                "reset(schedule) first."
            )
        state = np.vstack([previous.com, previous.com_velocity, previous.com_acceleration])
        model = CartTable(self.lipm, self.control_period)
        state = model.integrate(state, np.zeros(2), self.control_period)
        self.tick += 1
        info = SolveInfo(False, solver, "coast", fallback=True)
        self._last_output = self._output(self.time, state, solve=info)
        return self._last_output

    @abstractmethod
    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        """Generator-specific reset; return the output at time 0."""

    @abstractmethod
    def _step(self, measured: ComState | None) -> GeneratorOutput:
        """Generator-specific tick from :attr:`time` to ``time + control_period``."""

    def _output(self, t: float, state: np.ndarray, **kwargs) -> GeneratorOutput:
        """Output from a cart-table state of shape (3, 2); off level footsteps, the ZMP of
        the time-varying LIPM on the schedule's height profile."""
        eta = 1.0 / self.lipm.omega**2
        if self.schedule is not None:
            profile = height_profile(self.schedule, self.lipm.com_height)
            if not profile.is_level:
                eta = float(profile.eta(t, self.lipm.gravity)[0])
        zmp = state[0] - eta * state[2]
        return GeneratorOutput(
            time=t,
            com=state[0].copy(),
            com_velocity=state[1].copy(),
            com_acceleration=state[2].copy(),
            zmp=zmp,
            com_height=self.lipm.com_height,
            **kwargs,
        )


def _dcm_error(value) -> np.ndarray:
    error = np.asarray(value, dtype=float)
    if error.shape != (2,) or not np.isfinite(error).all():
        raise ConfigurationError(
            f"dcm_error must be 2 finite numbers (x, y) in metres, got {value!r}."
        )
    return error


def timed_step(
    generator: PatternGenerator, measured: ComState | None = None
) -> tuple[GeneratorOutput, float]:
    """Step a generator and measure its wall time.

    Returns:
        ``(output, seconds)``.
    """
    t0 = time.perf_counter()
    out = generator.step(measured)
    return out, time.perf_counter() - t0
