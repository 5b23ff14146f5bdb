"""What ``mpcwalk bench solvers`` runs: the configuration of the solver benchmark."""

import dataclasses
from dataclasses import dataclass

from mpcwalk.bench.solvers.problems.families import WALKS, families
from mpcwalk.bench.solvers.solves.cases import STARTS
from mpcwalk.bench.solvers.tolerances import LEVEL_NAMES
from mpcwalk.exceptions import ConfigurationError

#: The family of the inverse-dynamics QP of torque control: its own stage
#: (:mod:`mpcwalk.bench.solvers.dynamics`), the other families are the MPCs'.
DYNAMICS_FAMILY = "inverse-dynamics"


@dataclass(frozen=True)
class SolverBenchConfig:
    """Problem set, back-ends and run options.

    Attributes:
        families: Problem families of the main set (each at its own horizon), and
            :data:`DYNAMICS_FAMILY` for the inverse-dynamics stage (alone: only that stage
            runs).
        walks: Walks sampled.
        nb_steps: Steps of each walk.
        nb_nominal: Snapshots per walk at the walk's own states.
        nb_pushed: Snapshots per walk with a velocity push.
        push_speed: Velocity of a push, in [m/s].
        warmup_ticks: Ticks solved before a warm-started problem.
        control_period: Tick of the walks, in [s].
        sweep_family: Family of the horizon sweep.
        sweep_walk: Walk of the horizon sweep.
        sweep_horizons: Horizons of the sweep (same 1.6 s duration).
        sweep_nb_nominal: Nominal snapshots of the sweep (the first ones of the main set).
        sweep_nb_pushed: Pushed snapshots of the sweep.
        sweep_levels: Tolerance levels of the sweep.
        sweep_starts: Starts of the sweep.
        levels: Tolerance levels of the main set.
        formulations: ``"dense"`` and/or ``"sparse"``.
        starts: ``"cold"`` and/or ``"warm"``.
        backends: Back-ends (None: every installed one).
        time_limit: Time limit of one solve, in [s].
        opti_max_horizon: Largest horizon given to CasADi's Opti (its one-off
            symbolic set-up takes seconds beyond that).
        timing_workers: Processes that time solves (1: never two at once).
        prep_workers: Processes for the untimed work (walks, checks, export).
        loop_backends_max_time: A back-end enters the in-loop runs when its
            median solve of the loop's QP stayed under this, in [s].
        loop_nb_steps: Steps of each in-loop walk.
        loop_pushes: Velocity pushes during each in-loop walk.
        loop_push_speed: In [m/s].
        mujoco_robot: Robot of the MuJoCo in-loop walks (None: LIPM loops only).
        ticks: Also time every generator per tick with the qpmpc peer (ticks.py).
        qpbenchmark_solvers: qpsolvers names of the reduced qpbenchmark run
            (None: all but the JAX-based ones; empty: no run).
        export_max_horizon: Largest horizon exported to the qpbenchmark set.
        seed: Seed of the push directions.
        dynamics_robots: Robots of the torque-mode walks the inverse-dynamics problems are
            taken along.
        dynamics_vx: Forward velocity of those walks, in [m/s].
        dynamics_nb_steps: Steps of those walks.
        dynamics_nb_per_phase: Problems per walk in each phase (double support, single
            support, touch-down ramp).
        dynamics_nb_pushed: Problems per walk in single support with a velocity push on
            the base.
        dynamics_push_speed: Velocity of that push, in [m/s].
        dynamics_loop_robot: Robot of the in-loop torque walks (None: none).
        dynamics_loop_nb_steps: Steps of each in-loop torque walk.
        dynamics_loop_min_success: A back-end walks in the loop when its cold solves at
            the default level succeeded on at least this share of the loop robot's problems.
    """

    families: tuple[str, ...] = ("mpc", "mpc-dcm", "mpc-tick", "static-qp", DYNAMICS_FAMILY)
    walks: tuple[str, ...] = ("straight", "turning", "sideways")
    nb_steps: int = 20
    nb_nominal: int = 4
    nb_pushed: int = 2
    push_speed: float = 0.1  # [m/s]
    warmup_ticks: int = 3
    control_period: float = 0.01  # [s]
    sweep_family: str = "mpc"
    sweep_walk: str = "turning"
    sweep_horizons: tuple[int, ...] = (16, 32, 64, 128, 160, 320)
    sweep_nb_nominal: int = 2
    sweep_nb_pushed: int = 1
    sweep_levels: tuple[str, ...] = ("default", "mid")
    sweep_starts: tuple[str, ...] = STARTS
    levels: tuple[str, ...] = LEVEL_NAMES
    formulations: tuple[str, ...] = ("dense", "sparse")
    starts: tuple[str, ...] = STARTS
    backends: tuple[str, ...] | None = None
    time_limit: float = 1.0  # [s]
    opti_max_horizon: int = 64
    timing_workers: int = 1
    prep_workers: int = 2
    loop_backends_max_time: float = 0.01  # [s]
    loop_nb_steps: int = 20
    loop_pushes: int = 3
    loop_push_speed: float = 0.15  # [m/s]
    mujoco_robot: str | None = "bioloid-like"
    ticks: bool = True
    qpbenchmark_solvers: tuple[str, ...] | None = None
    export_max_horizon: int = 64
    seed: int = 0
    dynamics_robots: tuple[str, ...] = ("bioloid-like", "g1")
    dynamics_vx: float = 0.1  # [m/s]
    dynamics_nb_steps: int = 20
    dynamics_nb_per_phase: int = 4
    dynamics_nb_pushed: int = 3
    dynamics_push_speed: float = 0.1  # [m/s]
    dynamics_loop_robot: str | None = "bioloid-like"
    dynamics_loop_nb_steps: int = 20
    dynamics_loop_min_success: float = 0.95

    def __post_init__(self) -> None:
        known = [*families(), DYNAMICS_FAMILY]
        for name in self.families + (self.sweep_family,):
            if name not in known:
                raise ConfigurationError(
                    f"Unknown problem family {name!r}; the families are {', '.join(known)}."
                )
        for name in self.walks + (self.sweep_walk,):
            if name not in WALKS:
                raise ConfigurationError(
                    f"Unknown walk {name!r}; the walks are {', '.join(WALKS)}."
                )
        for name in self.levels + self.sweep_levels:
            if name not in LEVEL_NAMES:
                raise ConfigurationError(
                    f"Unknown tolerance level {name!r}; the levels are {', '.join(LEVEL_NAMES)}."
                )
        for name in self.starts + self.sweep_starts:
            if name not in STARTS:
                raise ConfigurationError(f"Unknown start {name!r}; use {' or '.join(STARTS)}.")
        if min(self.sweep_horizons, default=1) < 1:
            raise ConfigurationError(
                f"Horizons are numbers of samples >= 1, got {self.sweep_horizons}."
            )

    @staticmethod
    def quick() -> "SolverBenchConfig":
        """A reduced run of a few minutes on 2 cores."""
        return SolverBenchConfig(
            walks=("turning",),
            nb_nominal=1,
            nb_pushed=1,
            sweep_horizons=(16, 32, 64, 160, 320),
            sweep_nb_nominal=1,
            sweep_nb_pushed=0,
            sweep_levels=("default",),
            sweep_starts=("cold",),
            opti_max_horizon=32,
            export_max_horizon=32,
            loop_nb_steps=8,
            loop_backends_max_time=2e-3,
            loop_pushes=2,
            dynamics_nb_steps=8,
            dynamics_nb_per_phase=2,
            dynamics_nb_pushed=1,
            dynamics_loop_nb_steps=8,
        )

    @property
    def mpc_families(self) -> tuple[str, ...]:
        """The families of :attr:`families` that are MPC QPs (all but
        :data:`DYNAMICS_FAMILY`)."""
        return tuple(f for f in self.families if f != DYNAMICS_FAMILY)

    @property
    def dynamics(self) -> bool:
        """Whether the inverse-dynamics stage runs."""
        return DYNAMICS_FAMILY in self.families

    def replace(self, **changes) -> "SolverBenchConfig":
        """Copy with some fields changed."""
        return dataclasses.replace(self, **changes)
