"""Optimal step timing: the CasADi program against the LIPM's closed form, its warm start,
and the generator in the loop."""

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.generators import generator_names, make_generator
from mpcwalk.generators.timing_nlp import (
    TimingNLP,
    TimingProblem,
    TimingWeights,
    nominal_offsets,
)

OMEGA = float(np.sqrt(9.81 / 0.23))
T = 0.5
STANCE = np.array([0.0, -0.04])
PLAN = np.array([[0.05, 0.04], [0.10, -0.04]])
OFFSETS = nominal_offsets(PLAN, np.array([0.10, 0.0]), OMEGA, T)
REACH = np.array([[[-0.04, 0.08], [0.08, 0.16]], [[-0.04, -0.16], [0.08, -0.08]]])


def problem(dcm, remaining=0.3, box=None):
    return TimingProblem(
        dcm=np.asarray(dcm, dtype=float),
        stance=STANCE,
        stance_yaw=0.0,
        nominal=PLAN,
        offsets=OFFSETS,
        durations=np.array([remaining, T]),
        duration_bounds=np.array([[0.05, remaining], [0.25, T]]),
        reach=REACH,
        landing_yaw=0.0,
        half_sole=np.array([0.05, 0.03]),
        box=np.array([[-np.inf, -np.inf], [np.inf, np.inf]]) if box is None else box,
    )


def on_plan_dcm(remaining=0.3):
    """The DCM now that reaches the plan's offset at the planned landing (CoP at the sole's
    centre): ``u0 + (u1 + b1 - u0) exp(-omega tau)``."""
    return STANCE + (PLAN[0] + OFFSETS[0] - STANCE) * np.exp(-OMEGA * remaining)


def test_nominal_offsets_are_the_periodic_gait_s():
    """Backwards recursion: the offset of a straight periodic gait's inner steps tends to
    ``L / (exp(omega T) - 1)`` forward (Khadiv et al.) and the last one is the final DCM."""
    steps = np.array([[0.05 * i, 0.04 * (-1) ** i] for i in range(1, 30)])
    b = nominal_offsets(steps, np.array([steps[-1, 0], 0.0]), OMEGA, T)
    assert b[0, 0] == pytest.approx(0.05 / (np.exp(OMEGA * T) - 1.0), rel=1e-6)
    # lateral: alternating, of size w / (exp(omega T) + 1) with 2 w = 0.08 the feet's gap
    assert abs(b[0, 1]) == pytest.approx(0.08 / (np.exp(OMEGA * T) + 1.0), rel=1e-6)
    np.testing.assert_allclose(b[-1], [0.0, -steps[-1, 1]])


def test_on_the_plan_the_program_keeps_the_plan():
    solution = TimingNLP(OMEGA).solve(problem(on_plan_dcm()), warm=False)
    assert solution.success
    np.testing.assert_allclose(solution.durations, [0.3, T], atol=1e-5)
    np.testing.assert_allclose(solution.landings, PLAN, atol=1e-5)
    np.testing.assert_allclose(solution.cop, STANCE, atol=1e-5)


def test_the_dcm_reaches_the_capture_offset_of_the_closed_form():
    """A 3 cm forward DCM error, offsets weighted far above the rest: the solution's DCM obeys
    the LIPM's closed form ``xi1 = p + (xi0 - p) exp(omega T1)``, ``xi2 = u1 + (xi1 - u1)
    exp(omega T2)``, and reaches the plan's offsets at both landings."""
    dcm0 = on_plan_dcm() + np.array([0.03, 0.0])
    nlp = TimingNLP(OMEGA, TimingWeights(footstep=1e-3, duration=1e-3, offset=100.0, cop=1e-3))
    s = nlp.solve(problem(dcm0), warm=False)
    assert s.success
    T1, T2 = s.durations
    xi1 = s.cop + (dcm0 - s.cop) * np.exp(OMEGA * T1)
    xi2 = s.landings[0] + (xi1 - s.landings[0]) * np.exp(OMEGA * T2)
    np.testing.assert_allclose(s.dcm, [xi1, xi2], atol=1e-9)
    np.testing.assert_allclose(xi1 - s.landings[0], OFFSETS[0], atol=2e-4)
    np.testing.assert_allclose(xi2 - s.landings[1], OFFSETS[1], atol=2e-4)
    assert s.landings[0, 0] > PLAN[0, 0] and T1 < 0.3  # further and sooner: the push's way


def test_a_push_shortens_the_step_and_the_box_holds_the_landing():
    dcm0 = on_plan_dcm() + np.array([0.05, 0.0])
    nlp = TimingNLP(OMEGA)
    free = nlp.solve(problem(dcm0), warm=False)
    assert free.success and free.durations[0] < 0.29  # lands earlier than planned
    box = np.array([PLAN[0] - 0.005, PLAN[0] + 0.005])
    boxed = nlp.solve(problem(dcm0, box=box), warm=False)
    assert boxed.success
    assert np.all(boxed.landings[0] <= box[1] + 1e-7) and np.all(boxed.landings[0] >= box[0] - 1e-7)
    assert free.landings[0, 0] > box[1, 0]  # the box is active


def test_warm_start_reduces_the_iterations():
    """Tick to tick: the next problem is the last one 10 ms later with the DCM moved a little;
    from the last solution IPOPT needs fewer iterations than from the plan, same answer."""
    nlp = TimingNLP(OMEGA)
    cold_iterations, warm_iterations = [], []
    for push in (0.0, 0.03, 0.06):
        dcm0 = on_plan_dcm() + np.array([push, 0.0])
        nlp.reset()
        nlp.solve(problem(dcm0), warm=False)
        nxt = problem(dcm0 + np.array([0.001, 0.0]), remaining=0.3)
        warm = nlp.solve(nxt)
        cold = TimingNLP(OMEGA).solve(nxt, warm=False)
        assert warm.success and cold.success
        np.testing.assert_allclose(warm.landings, cold.landings, atol=1e-4)
        warm_iterations.append(warm.iterations)
        cold_iterations.append(cold.iterations)
    assert sum(warm_iterations) < sum(cold_iterations), (warm_iterations, cold_iterations)


def test_bad_omega_is_a_named_error():
    with pytest.raises(ConfigurationError, match="omega must be a positive"):
        TimingNLP(0.0)


def test_registered_and_walks_four_steps_on_bioloid_like(record_property):
    """The generator is registered; ``mpc-timing-nlp`` walks 4 steps on bioloid-like in
    MuJoCo, every step done, no failed QP solve."""
    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.specification import WalkSpec

    assert "mpc-nlp" in generator_names()
    gen = make_generator("mpc-nlp")
    assert gen.late_adjustment and gen.timing_adaptation
    result = run_walk(
        WalkSpec.build(
            "bioloid-like", controller="mpc-timing-nlp", command=(0.1, 0.0, 0.0), nb_steps=4
        )
    )
    metrics = result.metrics
    record_property("metrics", {k: metrics[k] for k in ("fell", "steps_completed")})
    assert not metrics["fell"], metrics["fall_reason"]
    assert metrics["steps_completed"] == metrics["steps_planned"] >= 4
    assert metrics["mpc_failures"] == 0
