"""The inverse-dynamics problem set: snapshots of the whole-body inverse dynamics' QP taken
along real torque-mode walks in MuJoCo.

A walk (``mpcwalk.walking.runner.run_walk``, ``actuation = "torque"``, named controller
``mpc``) runs with its inverse dynamics swapped, before the walk starts, for a
:class:`RecordingInverseDynamics` of the same settings (same back-end, same delay-capped
gains): it solves every tick exactly as the controller's own would and keeps the tick's
estimated state, references and result. :func:`sample_dynamics_problems` then picks ticks
in double support, in single support and in the load ramp after a touch-down (and a few in
single support with a velocity push on the base), and builds the QP of each again from the
kept state and references (:meth:`~mpcwalk.ik.inverse_dynamics.InverseDynamicsQP.build`,
deterministic), with the QPs of the ticks before it for warm starts. A snapshot holds the
QP's matrices in the form ``l <= A x <= u`` (equalities first) and what turns a solution
into joint torques (mass matrix, nonlinear effects, sole Jacobians).
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.ik.dynamics_program import DynamicsProgram
from mpcwalk.ik.dynamics_targets import DynamicsResult, DynamicsTargets
from mpcwalk.ik.inverse_dynamics import InverseDynamicsQP

#: Kinds of ticks of the problem set, by the sole loads of the tick.
PHASES = ("double", "single", "touch-down")


class RecordingInverseDynamics(InverseDynamicsQP):
    """:class:`~mpcwalk.ik.inverse_dynamics.InverseDynamicsQP` that keeps every tick it
    solves: :attr:`results` always, :attr:`states` (estimated ``q``, ``v`` and the
    references) when ``keep_states``.

    Args:
        robot: The robot.
        keep_states: Keep each tick's state and references (the problem set), not only its
            result (the in-loop runs).
        settings: Keyword arguments of :class:`InverseDynamicsQP`.
    """

    def __init__(self, robot, *, keep_states: bool = True, **settings) -> None:
        super().__init__(robot, **settings)
        self.settings = dict(settings)
        """The keyword arguments it was built with."""
        self.keep_states = keep_states
        self.states: list[tuple[np.ndarray, np.ndarray, DynamicsTargets]] = []
        self.results: list[DynamicsResult] = []

    def solve(self, q: np.ndarray, v: np.ndarray, targets: DynamicsTargets) -> DynamicsResult:
        result = super().solve(q, v, targets)
        if self.keep_states:
            self.states.append((np.array(q, dtype=float), np.array(v, dtype=float), targets))
        self.results.append(result)
        return result


def record_dynamics(controller, *, keep_states: bool = True) -> RecordingInverseDynamics:
    """Swap the inverse dynamics of a torque ``controller``
    (:class:`~mpcwalk.control.torque_controller.TorqueController`, not yet reset) for a
    recording one of the same back-end and gains; returns it.

    Raises:
        ValueError: ``controller`` has no inverse dynamics (a position-servo walk).
    """
    current = getattr(controller, "inverse_dynamics", None)
    if current is None:
        raise ValueError("The walk's controller has no inverse dynamics: walk in torque mode.")
    recorder = RecordingInverseDynamics(
        controller.robot,
        keep_states=keep_states,
        solver=current.solver_name,
        state_delay=controller.state_delay,
    )
    if not np.array_equal(recorder.posture_frequencies, current.posture_frequencies):
        raise ValueError("The recording inverse dynamics would not have the walk's gains.")
    controller.inverse_dynamics = recorder
    return recorder


@dataclass(frozen=True)
class DynamicsQPValues:
    """The values of one tick's QP, ``min 1/2 x'Px + q'x  s.t.  l <= A x <= u``.

    Attributes:
        P: Cost matrix, shape (n, n).
        q: Cost vector, shape (n,).
        A: Constraint rows, the ``m_eq`` equalities first, shape (m, n).
        l: Lower bounds, shape (m,) (``-inf`` on the inequality rows).
        u: Upper bounds, shape (m,).
        m_eq: Equality rows.
        contacts: Whether the left and the right sole carry a wrench.
    """

    P: np.ndarray
    q: np.ndarray
    A: np.ndarray
    l: np.ndarray
    u: np.ndarray
    m_eq: int
    contacts: tuple[bool, bool]

    @classmethod
    def of(cls, program: DynamicsProgram, contacts: tuple[bool, bool]) -> "DynamicsQPValues":
        """A copy of the values of ``program`` as last updated."""
        P, q, A, lower, upper = program.dense_rows()
        return cls(P.copy(), q.copy(), A.copy(), lower.copy(), upper.copy(), program.m_eq, contacts)

    def load(self, program: DynamicsProgram) -> None:
        """Write these values into ``program`` (of the same size; the cost is copied: the
        program keeps it, and arrays sent between processes are read-only)."""
        m_eq = self.m_eq
        program.update(
            np.array(self.P),
            np.array(self.q),
            self.A[:m_eq],
            self.l[:m_eq],
            self.A[m_eq:],
            self.u[m_eq:],
        )

    def cost(self, x: np.ndarray) -> float:
        """``1/2 x'Px + q'x``."""
        return float(0.5 * x @ self.P @ x + self.q @ x)


@dataclass(frozen=True)
class DynamicsProblem:
    """One inverse-dynamics QP of the problem set.

    Attributes:
        name: ``robot/tick`` (``+push`` for a pushed one).
        robot: Robot name.
        tick: Control tick of the walk.
        time: Its time [s].
        phase: One of :data:`PHASES`.
        pushed: The base velocity was pushed by ``push`` before the QP was built.
        qp: The QP.
        warmup: The QPs of the ticks before it, oldest first (warm starts solve them first).
        mass_matrix: ``M(q)``, shape (nv, nv).
        nonlinear: ``h(q, v)``, shape (nv,).
        jacobians: ``(k, J)`` of each sole in contact: its wrench is ``x[nv + 6k : nv + 6k
            + 6]`` and ``J`` its Jacobian (sole frame), shape (6, nv).
        torque_limit: Joint torque limits [N m], shape (nv - 6,).
        live_torques: Torques [N m] the walk's own solve gave at this tick, shape (nv - 6,)
            (None for a pushed problem).
        push: Velocity added to the base [m/s], shape (3,) (zero when not pushed).
    """

    name: str
    robot: str
    tick: int
    time: float
    phase: str
    pushed: bool
    qp: DynamicsQPValues
    warmup: tuple[DynamicsQPValues, ...]
    mass_matrix: np.ndarray
    nonlinear: np.ndarray
    jacobians: tuple[tuple[int, np.ndarray], ...]
    torque_limit: np.ndarray
    live_torques: np.ndarray | None
    push: np.ndarray

    @property
    def n(self) -> int:
        """Variables."""
        return len(self.qp.q)

    @property
    def m(self) -> int:
        """Constraint rows."""
        return len(self.qp.l)

    def generalized_forces(self, x: np.ndarray) -> np.ndarray:
        """``M a + h - sum_i J_i^T f_i`` of a solution ``x`` [N, N m], shape (nv,): the
        base's six rows are zero when ``x`` keeps the floating-base equations, the others are
        the joint torques."""
        nv = len(self.nonlinear)
        forces = self.mass_matrix @ x[:nv] + self.nonlinear
        for k, J in self.jacobians:
            forces -= J.T @ x[nv + 6 * k : nv + 6 * k + 6]
        return forces

    def torques(self, x: np.ndarray) -> np.ndarray:
        """Joint torques [N m] of a solution ``x``, clipped to the limits as the controller
        does."""
        return np.clip(self.generalized_forces(x)[6:], -self.torque_limit, self.torque_limit)


def classify_ticks(weights: np.ndarray) -> list[str]:
    """The phase of each tick from the sole loads ``weights`` (shape (n, 2)): a load
    strictly between 0 and 1 that rose since the tick before is a touch-down ramp; both
    soles fully loaded double support; one sole unloaded single support; anything else
    (a lift-off ramp) ``"other"``."""
    phases = []
    for i, (left, right) in enumerate(weights):
        before = weights[i - 1] if i else weights[i]
        ramp = [0.0 < w < 1.0 for w in (left, right)]
        rising = any(r and w > b for r, w, b in zip(ramp, (left, right), before))
        if rising:
            phases.append("touch-down")
        elif left == 1.0 and right == 1.0:
            phases.append("double")
        elif (left == 0.0) != (right == 0.0) and not any(ramp):
            phases.append("single")
        else:
            phases.append("other")
    return phases


def pick_ticks(phases: list[str], phase: str, count: int, first: int) -> list[int]:
    """``count`` ticks of ``phase`` spread evenly over the walk, none before ``first`` nor in
    its last tenth."""
    candidates = [i for i, p in enumerate(phases) if p == phase and first <= i < 0.9 * len(phases)]
    if not candidates or count <= 0:
        return []
    positions = np.linspace(0, len(candidates) - 1, count + 2)[1:-1]
    return sorted({candidates[int(round(p))] for p in positions})


def sample_dynamics_problems(
    recorder: RecordingInverseDynamics,
    robot_name: str,
    *,
    control_period: float,
    nb_per_phase: int,
    nb_pushed: int,
    push_speed: float,
    warmup_ticks: int,
    seed: int = 0,
) -> list[DynamicsProblem]:
    """The problems of one recorded walk (see the module docstring): ``nb_per_phase``
    ticks of each phase of :data:`PHASES`, and ``nb_pushed`` single-support ticks (others)
    with the base velocity pushed by ``push_speed`` [m/s] in a horizontal direction drawn
    with ``seed``; each with the QPs of its ``warmup_ticks`` ticks before."""
    states, results = recorder.states, recorder.results
    weights = np.array([targets.contact_weights for _, _, targets in states], dtype=float)
    phases = classify_ticks(weights)
    first = max(warmup_ticks, 1)
    chosen = [
        (t, phase, False)
        for phase in PHASES
        for t in pick_ticks(phases, phase, nb_per_phase, first)
    ]
    taken = {t for t, _, _ in chosen}
    spare = pick_ticks(phases, "single", nb_per_phase + nb_pushed + 1, first)
    spare = [t for t in spare if t not in taken]
    chosen += [(t, "single", True) for t in spare[:nb_pushed]]
    rng = np.random.default_rng(seed)
    builder = InverseDynamicsQP(recorder.robot, **recorder.settings)
    problems = []
    for tick, phase, pushed in chosen:
        warmup = []
        for j in range(tick - warmup_ticks, tick):
            program, contacts, *_ = builder.build(*states[j])
            warmup.append(DynamicsQPValues.of(program, contacts))
        q, v, targets = states[tick]
        push = np.zeros(3)
        if pushed:
            angle = rng.uniform(0.0, 2.0 * math.pi)
            push = push_speed * np.array([math.cos(angle), math.sin(angle), 0.0])
            v = v.copy()
            v[:3] += push
        program, contacts, M, h, jacobians = builder.build(q, v, targets)
        problems.append(
            DynamicsProblem(
                name=f"{robot_name}/{tick}" + ("+push" if pushed else ""),
                robot=robot_name,
                tick=tick,
                time=(tick + 1) * control_period,
                phase=phase,
                pushed=pushed,
                qp=DynamicsQPValues.of(program, contacts),
                warmup=tuple(warmup),
                mass_matrix=M.copy(),
                nonlinear=h.copy(),
                jacobians=tuple((k, J.copy()) for _, k, J in jacobians),
                torque_limit=recorder.torque_limit.copy(),
                live_torques=None if pushed else results[tick].torques.copy(),
                push=push,
            )
        )
    return problems


@dataclass(frozen=True)
class CapturedWalk:
    """A torque-mode walk and the inverse dynamics of each of its ticks.

    Attributes:
        robot: Robot name.
        recorder: The walk's (recording) inverse dynamics.
        control_period: Tick [s].
        fell: Whether the robot fell.
        steps: Steps completed over steps planned, e.g. ``"21/21"``.
    """

    robot: str
    recorder: RecordingInverseDynamics
    control_period: float
    fell: bool
    steps: str


def recorded_torque_walk(
    robot: str,
    *,
    nb_steps: int,
    vx: float,
    control_period: float = 0.01,
    dynamics_solver: str | None = None,
    keep_states: bool = True,
):
    """Walk ``robot`` in torque mode (named controller ``mpc``, ``nb_steps`` steps at
    ``vx`` [m/s] straight ahead, the default sensors; the inverse dynamics on
    ``dynamics_solver``, None: the default) with a recording inverse dynamics.

    Returns:
        The :class:`~mpcwalk.walking.result.WalkResult` and the
        :class:`RecordingInverseDynamics`.
    """
    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.specification import WalkSpec

    options = {} if dynamics_solver is None else {"dynamics_solver": dynamics_solver}
    spec = WalkSpec.build(
        robot,
        controller="mpc",
        command=(vx, 0.0, 0.0),
        nb_steps=nb_steps,
        control_period=control_period,
        actuation="torque",
        **({"controller_options": options} if options else {}),
    )
    recorders: list[RecordingInverseDynamics] = []
    result = run_walk(
        spec, on_controller=lambda c: recorders.append(record_dynamics(c, keep_states=keep_states))
    )
    return result, recorders[0]


def capture_walk(
    robot: str, *, nb_steps: int, vx: float, control_period: float = 0.01
) -> CapturedWalk:
    """Walk ``robot`` in torque mode (:func:`recorded_torque_walk`, the default back-end)
    and record its inverse dynamics."""
    result, recorder = recorded_torque_walk(
        robot, nb_steps=nb_steps, vx=vx, control_period=control_period
    )
    metrics = result.metrics
    return CapturedWalk(
        robot,
        recorder,
        control_period,
        bool(metrics.fell),
        f"{metrics.steps_completed}/{metrics.steps_planned}",
    )
