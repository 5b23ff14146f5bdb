"""The receding-horizon core shared by the QP generators, the QP protocol's typed
prediction, the generator registry and the robot traits a generator is built from."""

from dataclasses import dataclass

import numpy as np
import pytest
from plans import velocity_schedule

from mpcwalk.exceptions import GeneratorNotFound, NoSolutionFound, NotReset
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.gait.gait_defaults import GaitDefaults
from mpcwalk.generators import generator_class, generator_names, make_generator
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.generators.receding_horizon import RecedingHorizonGenerator
from mpcwalk.generators.static_qp import StaticQPGenerator
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.program import Prediction
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.base import QPSolver, failure

LIPM_SMALL = LIPM(com_height=0.23)


class FailingTicks(QPSolver):
    """Wraps a back-end and fails on the solves whose index is in ``failing``."""

    def __init__(self, inner: QPSolver, failing: set[int]) -> None:
        self.inner, self.failing, self.calls = inner, failing, 0
        self.name = inner.name

    def reset(self) -> None:
        self.inner.reset()

    def solve(self, qp, *, shift: float = 0.0) -> QPResult:
        self.calls += 1
        if self.calls - 1 in self.failing:
            return failure(self.name, "made to fail", 0.0)
        return self.inner.solve(qp, shift=shift)


def walk_with_failures(gen: RecedingHorizonGenerator, failing: set[int], nb_ticks: int):
    schedule = velocity_schedule((0.1, 0.0, 0.0), 6)
    outs = [gen.reset(schedule)]
    gen.solver = FailingTicks(gen.solver, failing)
    for _ in range(nb_ticks):
        outs.append(gen.step())
    return outs


@pytest.mark.parametrize("kind", ["mpc", "mpc-steps"])
def test_the_core_counts_consecutive_failures_and_follows_the_last_plan(kind):
    """Both QP generators answer failed solves the same way (one core): the count of
    failures in a row grows, the output's horizon stays the last plan's, the state goes
    on along that plan (open loop, so close to what the solves would have given), and
    the count is back to 0 at the next success."""
    nominal = walk_with_failures(make_generator(kind, lipm=LIPM_SMALL), set(), 80)
    failing = {41, 42, 43, 60}
    outs = walk_with_failures(make_generator(kind, lipm=LIPM_SMALL), failing, 80)
    counts = [o.solve.consecutive_failures for o in outs[1:]]
    assert [counts[k] for k in (40, 41, 42, 43, 44, 59, 60, 61)] == [0, 1, 2, 3, 0, 0, 1, 0]
    for k in failing:
        out = outs[k + 1]
        assert not out.solve.success and out.solve.fallback and out.solve.status == "made to fail"
        assert out.horizon is outs[k].horizon or np.array_equal(
            out.horizon.com, outs[k].horizon.com
        )
    assert sum(not o.solve.success for o in outs[1:]) == len(failing)
    error = np.max([np.linalg.norm(a.com - b.com) for a, b in zip(outs, nominal)])
    assert error < 2e-5  # [m] (measured 3.9 um, 2.8 um): the previous plan stands in well


def test_past_the_bound_the_core_raises_and_coast_goes_on_with_zero_jerk():
    gen = MpcGenerator(lipm=LIPM_SMALL, max_fallback_ticks=2)
    outs = walk_with_failures(gen, set(range(30, 40)), 30)
    assert gen.tick == 30
    for failures in (1, 2):
        out = gen.step()
        assert out.solve.consecutive_failures == failures
        outs.append(out)
    with pytest.raises(NoSolutionFound, match="'daqp-direct' found no solution"):
        gen.step()
    assert gen.tick == 32  # a raising step does not move the clock
    coasted = gen.coast(solver="daqp")
    assert gen.tick == 33 and coasted.time == pytest.approx(0.33)
    assert coasted.solve.fallback and not coasted.solve.success and coasted.horizon is None
    previous = outs[-1]
    expected = CartTable(gen.lipm, gen.control_period).integrate(
        np.vstack([previous.com, previous.com_velocity, previous.com_acceleration]),
        np.zeros(2),
        gen.control_period,
    )
    np.testing.assert_array_equal(coasted.com, expected[0])
    np.testing.assert_array_equal(coasted.com_acceleration, previous.com_acceleration)
    np.testing.assert_allclose(coasted.zmp, expected[0] - expected[2] / gen.lipm.omega**2)
    again = gen.coast()  # coasting continues from the coasted reference
    np.testing.assert_allclose(again.com_velocity - coasted.com_velocity, 0.01 * expected[2])
    with pytest.raises(NotReset, match="coast"):
        MpcGenerator(lipm=LIPM_SMALL).coast()


def test_footstep_qp_predicts_a_typed_prediction_of_the_exact_states():
    """FootstepQP.predict answers as WalkingQP.predict: a Prediction whose states are the
    cart-table integration of the jerks over the sample intervals (the first is shorter:
    the samples sit on a fixed grid)."""
    gen = FootstepMpcGenerator(lipm=LIPM_SMALL)
    gen.reset(velocity_schedule((0.1, 0.0, 0.0), 6))
    for _ in range(13):
        gen.step()
    qp = gen.qp
    jerks = np.random.default_rng(3).normal(0.0, 1.0, (qp.N, 2))
    prediction = qp.predict(jerks)
    assert isinstance(prediction, Prediction)
    for array in (prediction.com, prediction.com_velocity, prediction.zmp):
        assert array.shape == (qp.N, 2)
    np.testing.assert_array_equal(prediction.times, qp.sample_times)
    state, t = qp.x0, qp.time
    for i, sample in enumerate(prediction.times):
        state = CartTable.transition(sample - t)[0] @ state + np.outer(
            CartTable.transition(sample - t)[1], jerks[i]
        )
        t = sample
        np.testing.assert_allclose(prediction.com[i], state[0], atol=1e-12)
        np.testing.assert_allclose(prediction.com_velocity[i], state[1], atol=1e-12)
        np.testing.assert_allclose(prediction.com_acceleration[i], state[2], atol=1e-12)
    omega2 = LIPM_SMALL.omega**2
    np.testing.assert_allclose(
        prediction.zmp, prediction.com - prediction.com_acceleration / omega2, atol=1e-12
    )
    out = gen.step()
    np.testing.assert_array_equal(out.horizon.com, gen._plan.prediction.com)


@dataclass(frozen=True)
class Traits:
    """What a generator reads of a robot (a test double of ``Robot``)."""

    com_height: float
    gait: GaitDefaults
    leg_limits: LegLimits
    lateral_cop_reach: float = 0.05


def test_generators_are_built_from_robot_traits_without_a_robot():
    limits = LegLimits(max_step_forward=0.1, half_stance_width=0.06, y_sep=0.05)
    traits = Traits(
        0.5,
        GaitDefaults(mpc_sampling_period=0.1, mpc_horizon=20, mpc_jerk_weight=1e-5),
        limits,
    )
    mpc = MpcGenerator.for_robot(traits, control_period=0.02)
    assert mpc.lipm.com_height == 0.5 and mpc.control_period == 0.02
    assert (mpc.parameters.sampling_period, mpc.parameters.horizon) == (0.1, 20)
    assert mpc.parameters.jerk_weight == 1e-5
    steps = FootstepMpcGenerator.for_robot(traits, horizon=24)
    assert steps.parameters.horizon == 24  # the caller's options come last
    assert steps.parameters.jerk_weight == FootstepMpcGenerator.default_parameters.jerk_weight
    assert steps.reachability == limits.rectangle()
    static = StaticQPGenerator.for_robot(traits)
    assert static.parameters == StaticQPGenerator.default_parameters
    unset = MpcGenerator.robot_options(Traits(0.5, GaitDefaults(), limits))
    assert unset == {}


def test_the_registry_names_every_generator():
    assert generator_names() == [
        *("analytic", "static", "preview", "mpc", "static-qp", "mpc-steps", "mpc-nlp", "mpc-hip")
    ]
    for name in generator_names():
        assert generator_class(name).name == name
    with pytest.raises(GeneratorNotFound, match="Unknown pattern generator 'zmp'.*mpc-steps"):
        generator_class("zmp")


def test_hot_started_daqp_plans_as_the_cold_qpsolvers_path():
    """The default back-end (DAQP's own workspace: the Hessian factorised once, vectors
    rewritten, the working set of the last tick kept) gives, tick after tick and through
    the changes of support polygons, the plans of DAQP called anew through qpsolvers."""
    schedule = velocity_schedule((0.1, 0.0, 0.2), 6)
    hot = make_generator("mpc", lipm=LIPM_SMALL)
    cold = make_generator("mpc", lipm=LIPM_SMALL, solver="daqp")
    assert hot.solver.name == "daqp-direct"
    hot.reset(schedule)
    cold.reset(schedule)
    for _ in range(300):
        a, b = hot.step(), cold.step()
        assert a.solve.success and b.solve.success
        np.testing.assert_allclose(a.com, b.com, atol=1e-9)
        np.testing.assert_allclose(a.horizon.zmp, b.horizon.zmp, atol=1e-6)
