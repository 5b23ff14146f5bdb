"""Walking QPs sampled from real walks: the problems of the solver benchmark.

A *family* is one QP controller of mpcwalk (its QP structure and weights):
paper M's reformulation (``mpc``: ZMP MPC tracking the polygonal ZMP
reference), two ZMP-MPC variants and paper A's quasi-static QP
(``static-qp``). For each family and each walk (20-step straight, turning
and sideways plans of the velocity planner) the family's generator walks
the plan once on the LIPM (open loop, its default solver): this gives the
CoM state at every control tick. A *problem* is the family's QP at one tick
of that walk (the QP the controller faces at that tick), at a given horizon;
*pushed* problems add a velocity kick to that state, as a push would. The
ticks that precede a problem carry the states used to warm the solvers up
along the walk before the timed solve.

The footstep-adaptive MPC does not exist yet: :func:`footstep_adaptive_family`
is the hook where it enters the benchmark.
"""

import functools
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import FootGeometry, StepTiming
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.velocity_planner import VelocityCommand, VelocityPlanner
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.walking_qp import WalkingQP

#: Walks: name -> velocity command at paper M's timing (0.5 s steps).
WALKS: dict[str, VelocityCommand] = {
    "straight": VelocityCommand(0.1, 0.0, 0.0),
    "turning": VelocityCommand(0.1, 0.0, 0.35),
    "sideways": VelocityCommand(0.0, 0.05, 0.0),
}
#: Step timings: paper M's, and the slow one a static gait needs.
TIMINGS: dict[str, StepTiming] = {
    "paper M": StepTiming(step_duration=0.5, double_support_ratio=0.2),
    "slow": StepTiming(step_duration=2.0, double_support_ratio=0.5),
}


@dataclass(frozen=True)
class ProblemFamily:
    """The QP of one controller.

    Attributes:
        name: Family name (results column ``family``).
        description: One line for the report.
        generator: Registered generator that walks the reference walks.
        parameters: The generator's MPC parameters (its own horizon).
        timing: Key of :data:`TIMINGS`.
        constrain_next_tick: The generator's ``constrain_next_tick``.
        track_walking_velocity: The generator's velocity term tracks the walking
            velocity of each step (its ``track_walking_velocity``) rather than zero.
    """

    name: str
    description: str
    generator: str
    parameters: MpcParameters
    timing: str = "paper M"
    constrain_next_tick: bool = False
    track_walking_velocity: bool = False

    def parameters_for(self, horizon: int) -> MpcParameters:
        """Same horizon duration and weights, ``horizon`` samples."""
        duration = self.parameters.duration
        return self.parameters.replace(
            horizon=int(horizon), sampling_period=duration / int(horizon)
        )

    def generator_options(self) -> dict:
        """Keyword arguments of the generator for the reference walk."""
        return {"parameters": self.parameters, "constrain_next_tick": self.constrain_next_tick}

    def update_qp(self, qp, state: np.ndarray, t: float, schedule: ContactSchedule) -> None:
        """Update ``qp`` at a tick as the family's generator does (same references)."""
        velocity = None
        if self.track_walking_velocity and qp.parameters.velocity_weight:
            velocity = schedule.reference_velocity(t + qp.sample_offsets)
        qp.update(state, t, schedule, velocity_reference=velocity)

    def build_qp(self, horizon: int, formulation: str, control_period: float):
        """The family's QP object at ``horizon`` samples (a :class:`WalkingQP`;
        a family with another QP class overrides this)."""
        params = self.parameters_for(horizon)
        tick = None
        if self.constrain_next_tick and not np.isclose(control_period, params.sampling_period):
            tick = control_period
        return WalkingQP(LIPM(), params, formulation, control_period=tick)


def _builtin_families() -> list[ProblemFamily]:
    from mpcwalk.generators.mpc import MpcGenerator
    from mpcwalk.generators.static_qp import StaticQPGenerator

    mpc = MpcGenerator.default_parameters
    track = bool(getattr(MpcGenerator, "track_walking_velocity", False))
    static_track = bool(getattr(StaticQPGenerator, "track_walking_velocity", False))
    return [
        ProblemFamily(
            "mpc",
            "paper M reformulation: ZMP MPC tracking paper M's polygonal ZMP "
            "reference (and weakly the walking velocity), ZMP of every sample in its "
            "support polygon",
            "mpc",
            mpc,
            track_walking_velocity=track,
        ),
        ProblemFamily(
            "mpc-dcm",
            "ZMP MPC variant: same, plus the terminal DCM in the last "
            "support polygon (capturable plans)",
            "mpc",
            mpc.replace(terminal_dcm=True),
            track_walking_velocity=track,
        ),
        ProblemFamily(
            "mpc-tick",
            "ZMP MPC variant: same as mpc, plus the ZMP at the next control tick in its polygon",
            "mpc",
            mpc,
            constrain_next_tick=True,
            track_walking_velocity=track,
        ),
        ProblemFamily(
            "static-qp",
            "paper A's quasi-static gait as a QP: CoM projection and ZMP "
            "in the support polygon, CoM pulled over the support foot",
            "static-qp",
            StaticQPGenerator.default_parameters,
            timing="slow",
            track_walking_velocity=static_track,
        ),
    ]


def footstep_adaptive_family() -> ProblemFamily | None:
    """Hook for the footstep-adaptive MPC (Herdt et al. 2010), which mpcwalk
    does not have yet: returns None, so the benchmark leaves it out and says so.

    To add it, return a :class:`ProblemFamily` whose ``generator`` is the
    registered adaptive generator and, since its QP has the footstep
    positions as extra variables, override ``build_qp`` to return its QP
    object (and ``update_qp`` if it updates it differently). That object must
    offer what the benchmark uses of :class:`WalkingQP`: ``P``, ``q``, ``A``,
    ``l``, ``u``, ``n``, ``m``, ``problem()``, ``shift_primal`` and
    ``shift_dual``.
    """
    return None


#: Families announced but not available yet: name -> reason (for the report).
PENDING_FAMILIES = {
    "mpc-adaptive": "footstep-adaptive MPC: not implemented in mpcwalk yet "
    "(hook: mpcwalk.bench.solvers.problems.families.footstep_adaptive_family)",
}


def families() -> dict[str, ProblemFamily]:
    """Available families by name (the adaptive one once its hook returns it)."""
    out = {f.name: f for f in _builtin_families()}
    adaptive = footstep_adaptive_family()
    if adaptive is not None:
        out[adaptive.name] = adaptive
    return out


def get_family(name: str) -> ProblemFamily:
    """Family called ``name``.

    Raises:
        ConfigurationError: Unknown family (the message lists the known ones).
    """
    known = families()
    if name not in known:
        pending = f" ({PENDING_FAMILIES[name]})" if name in PENDING_FAMILIES else ""
        raise ConfigurationError(
            f"Unknown problem family {name!r}{pending}; the families are {', '.join(known)}."
        )
    return known[name]


@functools.lru_cache(maxsize=64)
def walk_schedule(timing: str, walk: str, nb_steps: int) -> ContactSchedule:
    """Contact schedule of ``walk`` at ``timing``; slow timing keeps the step
    lengths by scaling the command with the step duration."""
    if walk not in WALKS:
        raise ConfigurationError(f"Unknown walk {walk!r}; the walks are {', '.join(WALKS)}.")
    step_timing = TIMINGS[timing]
    scale = TIMINGS["paper M"].step_duration / step_timing.step_duration
    c = WALKS[walk]
    command = VelocityCommand(c.vx * scale, c.vy * scale, c.vyaw * scale)
    plan = VelocityPlanner(LegLimits(), step_timing).plan(command, nb_steps)
    return ContactSchedule(plan, FootGeometry())


@dataclass(frozen=True)
class WalkingProblem:
    """One QP of the benchmark (without its formulation).

    Attributes:
        name: Unique name, e.g. ``"mpc-turning-n32-k345-push"``.
        family: Family name.
        walk: Walk name.
        nb_steps: Steps of the walk.
        horizon: Samples N.
        sampling_period: In [s].
        control_period: Time between ticks, in [s].
        tick: Control tick of the walk.
        time: Time of the tick, in [s].
        state: Cart-table state at the tick, shape (3, 2) (position [m],
            velocity [m/s], acceleration [m/s^2]; columns x, y).
        pushed: Whether ``state`` carries a push.
        warmup_times: Times of the preceding ticks, shape (W,), in [s].
        warmup_states: Their (nominal) states, shape (W, 3, 2).
    """

    name: str
    family: str
    walk: str
    nb_steps: int
    horizon: int
    sampling_period: float
    control_period: float
    tick: int
    time: float
    state: np.ndarray
    pushed: bool
    warmup_times: np.ndarray
    warmup_states: np.ndarray

    @property
    def qp_key(self) -> tuple[str, str, int, int]:
        """QPs with the same key share structure (cache key, without formulation)."""
        return (self.family, self.walk, self.nb_steps, self.horizon)

    def schedule(self) -> ContactSchedule:
        """The walk's contact schedule."""
        return walk_schedule(get_family(self.family).timing, self.walk, self.nb_steps)
