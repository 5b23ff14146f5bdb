"""The footstep-adaptive MPC's per-tick shortcuts give what the direct computation gives."""

import dataclasses
import functools
import warnings

import numpy as np
import pytest
import qpsolvers
from plans import tail_moved, velocity_schedule

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.footstep_qp import FootstepQP
from mpcwalk.qp.footstep_supports import FootstepSlots
from mpcwalk.qp.solvers import make_solver
from mpcwalk.qp.solvers.quadprog_dense import solve_dense_quadprog

LIPM_SMALL = LIPM(com_height=0.23)


@functools.cache
def straight(nb_steps=6):
    return velocity_schedule((0.1, 0.0, np.deg2rad(10.0)), nb_steps)


def walked(ticks: int, **options) -> FootstepMpcGenerator:
    """A generator reset on the straight walk and stepped ``ticks`` times (open loop)."""
    gen = FootstepMpcGenerator(lipm=LIPM_SMALL, **options)
    gen.reset(straight())
    for _ in range(ticks):
        gen.step()
    return gen


@pytest.mark.parametrize("ticks", [1, 37, 122])
def test_direct_quadprog_is_the_qpsolvers_call(ticks):
    qp = walked(ticks).qp
    assert qp is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        reference = qpsolvers.solve_problem(qp.problem(), "quadprog")
    direct = solve_dense_quadprog(*qp.dense_arrays())
    np.testing.assert_array_equal(direct.x, reference.x)
    np.testing.assert_array_equal(direct.y, reference.z)
    assert direct.primal_residual == reference.primal_residual()
    # (the product over the binding rows only: the same sum to rounding)
    assert direct.dual_residual == pytest.approx(reference.dual_residual(), rel=1e-9, abs=1e-15)
    assert direct.duality_gap == reference.duality_gap()
    assert direct.iterations == reference.extras["iterations"][0]
    # the back-end takes the direct path, with the same answer
    through_backend = make_solver("quadprog").solve(qp)
    np.testing.assert_array_equal(through_backend.x, reference.x)


def test_direct_quadprog_reports_an_infeasible_qp():
    P, q = np.eye(2), np.zeros(2)
    G = np.array([[1.0, 0.0], [-1.0, 0.0]])
    h = np.array([-1.0, -1.0])  # x <= -1 and x >= 1
    result = solve_dense_quadprog(P, q, G, h)
    assert not result.success and result.x is None and result.status == "not found"
    result = solve_dense_quadprog(-P, q, G, -h)
    assert not result.success and "positive definite" in result.status


def assert_same_fields(a, b):
    for field in dataclasses.fields(a):
        x, y = getattr(a, field.name), getattr(b, field.name)
        if x is None or y is None:
            assert x is None and y is None, field.name
        else:
            np.testing.assert_array_equal(x, y, err_msg=field.name)


def pushed_ticks(gen: FootstepMpcGenerator, ticks: int, push_tick: int = 120):
    """Step ``gen`` in closed loop on its own outputs, its CoM velocity kicked sideways at
    ``push_tick`` (the next landings move: schedules are published); yield before each
    step."""
    out = gen.reset(straight())
    for tick in range(ticks):
        yield tick
        measured = out.state
        if tick == push_tick:
            measured = ComState(out.com, out.com_velocity + [0.0, 0.15], out.com_acceleration)
        out = gen.step(measured)


@pytest.mark.parametrize("absolute", [True, False])
def test_the_kept_supports_and_reach_are_the_ones_computed_anew(absolute):
    reference = "absolute" if absolute else "relative"
    gen = FootstepMpcGenerator(lipm=LIPM_SMALL, footstep_reference=reference)
    checked = 0
    for _ in pushed_ticks(gen, 260):
        slots, qp = gen._slots, gen.qp
        if qp is None or slots is None or qp.x0 is None:
            continue
        t = gen.time
        times = qp.sample_times_at(t)
        steps_k, variable = slots.free_steps(t, times[-1], gen.freeze_before_landing)
        velocity = slots.nominal_schedule.reference_velocity(times)
        np.testing.assert_array_equal(slots.reference_velocity(times), velocity)
        points = qp.constraint_times(t)
        P = qp.parameters.constraint_points
        kept = slots.supports(points, variable, qp.nf, fresh=P)
        assert_same_fields(kept, slots.supports(points, variable, qp.nf))
        offset = np.array([0.003, -0.002])
        options = {"absolute": absolute, "offset": offset}
        steps = slots.step_variables(steps_k, variable, qp.nf, **options)
        slots._reach_rows = None  # computed anew
        assert_same_fields(steps, slots.step_variables(steps_k, variable, qp.nf, **options))
        # the QP's rows from the kept reach arrays, and from writeable copies (not kept)
        arrays = {f.name: getattr(steps, f.name) for f in dataclasses.fields(steps)}
        copies = dataclasses.replace(
            steps, **{name: np.copy(a) for name, a in arrays.items() if a is not None}
        )
        x0 = qp.x0
        kept_rows = qp._constraints(x0, kept, steps)
        kept_rows = qp._constraints(x0, kept, steps)  # the second time from the QP's cache
        for (G, h), (G_new, h_new) in zip(kept_rows, qp._constraints(x0, kept, copies)):
            np.testing.assert_array_equal(G, G_new)
            np.testing.assert_array_equal(h, h_new)
        checked += 1
    assert gen.nb_publications > 0 and checked > 250


def assert_same_schedule(fast: ContactSchedule, full: ContactSchedule) -> None:
    for name in (
        "torso_waypoints",
        "support_positions",
        "phase_centers",
        "zmp_breakpoints",
        "zmp_breakpoint_values",
        "_phase_starts",
        "_phase_single",
    ):
        np.testing.assert_array_equal(getattr(fast, name), getattr(full, name), err_msg=name)
    # the polygons of shapes reused along the chain: to 1e-12 m (the shapes' key)
    for a, b in zip(fast.phase_halfplanes, full.phase_halfplanes):
        np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-12)
    assert fast._phase_start_list == full._phase_start_list
    assert len(fast.phases) == len(full.phases)
    for mine, theirs in zip(fast.phases, full.phases):
        assert (mine.start, mine.end, mine.step_index) == (
            theirs.start,
            theirs.end,
            theirs.step_index,
        )
        assert mine.feet == theirs.feet
        np.testing.assert_allclose(mine.polygon.vertices, theirs.polygon.vertices, atol=1e-12)


@pytest.mark.parametrize("first", [0, 1, 4, 9])
def test_a_publication_is_the_schedule_built_anew(first):
    """Steps from ``first`` on moved by one offset (the tail of a publication), again and
    again: each schedule built from the last one is the one built from its plan alone."""
    schedule = velocity_schedule((0.1, 0.0, np.deg2rad(20.0)), 12)
    rng = np.random.default_rng(first)
    for _ in range(4):
        schedule = tail_moved(schedule, first, rng.normal(0.0, 2e-3, 2))
        assert_same_schedule(schedule, ContactSchedule(schedule.plan, schedule.foot))
    # fewer steps: nothing of the phase times is taken
    shorter = schedule.with_steps(schedule.plan.steps[:8])
    assert_same_schedule(shorter, ContactSchedule(shorter.plan, shorter.foot))


def test_the_cost_factor_of_a_varying_height_is_its_own():
    """A prediction kept for a level tick lends nothing made from its rows (the cost factor,
    the weighted rows) to a tick of a varying CoM height."""
    gen = walked(23)
    slots, qp = gen._slots, gen.qp
    assert slots is not None and qp is not None
    t = gen.time
    times = qp.sample_times_at(t)
    steps_k, variable = slots.free_steps(t, times[-1], gen.freeze_before_landing)
    points = qp.constraint_times(t)
    supports = slots.supports(points, variable, qp.nf)
    steps = slots.step_variables(steps_k, variable, qp.nf, absolute=True, offset=np.zeros(2))
    velocity = slots.reference_velocity(times)
    qp.update(gen._state, t, velocity, supports, steps)
    qp.cost_factor()  # kept in the level prediction
    eta = (0.02 + 0.001 * np.arange(len(times)), 0.02 + 0.0005 * np.arange(len(points)))
    qp.update(gen._state, t, velocity, supports, steps, eta)
    # (to round-off: the kept prediction is of a first interval within 1 ns of this one)
    fresh = FootstepQP(qp.lipm, qp.parameters, qp.nf)  # never updated at the level
    fresh.update(gen._state, t, velocity, supports, steps, eta)
    for mine, theirs in zip(qp.dense_arrays(), fresh.dense_arrays()):
        np.testing.assert_allclose(mine, theirs, rtol=1e-9, atol=1e-12 * np.abs(theirs).max())
    order, inverse = qp.cost_factor()
    factor = np.linalg.inv(inverse)
    P = qp.P[np.ix_(order, order)]
    np.testing.assert_allclose(factor.T @ factor, P, atol=1e-9 * np.abs(P).max())


def test_the_first_points_of_the_next_ticks_are_computed_with_the_interval(monkeypatch):
    """The first constraint points the generator gives for the next ticks of a sampling
    interval are, to the bit, those the ticks find: no tick computes its own."""
    sizes = []
    compute = FootstepSlots._supports

    def counted(self, times, variable, nf):
        sizes.append(len(times))
        return compute(self, times, variable, nf)

    monkeypatch.setattr(FootstepSlots, "_supports", counted)
    gen = walked(300)
    points = gen.qp.parameters.constraint_points if gen.qp is not None else 0
    assert len(sizes) < 300 / 3 and points not in sizes


@pytest.mark.parametrize("capturability", [False, True])
def test_the_rows_written_in_place_are_the_blocks_of_the_tick(capturability):
    """``update`` writes the ZMP rows into its ``G`` and copies the reach, box and band
    rows (and the terminal DCM rows) after them: the rows of every tick of a pushed walk
    are those blocks, stacked in that order."""
    gen = FootstepMpcGenerator(lipm=LIPM_SMALL, capturability=capturability)
    seen = []
    sizes = set()
    for _ in pushed_ticks(gen, 200):
        qp = gen.qp
        if qp is not None and not seen:
            update = qp.update

            def recorded(x0, t, velocity, supports, steps, eta=None, update=update):
                seen.append((np.array(x0, dtype=float), supports, steps))
                update(x0, t, velocity, supports, steps, eta)

            qp.update = recorded
        if seen and qp.x0 is not None:
            x0, supports, steps = seen[-1]
            blocks = qp._constraints(x0, supports, steps)
            if capturability and qp.terminal_rows:
                blocks.append(qp._terminal_dcm_rows(x0, supports))
            np.testing.assert_array_equal(qp.G, np.vstack([G for G, _ in blocks]))
            np.testing.assert_array_equal(qp.h, np.concatenate([h for _, h in blocks]))
            sizes.add(len(qp.h))
    assert len(seen) > 150 and len(sizes) > 1  # rows of every tick, of varying counts
