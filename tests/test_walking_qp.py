"""Walking MPC QP construction: condensed vs sparse, cheap updates, inputs."""

import numpy as np
import pytest
from plans import velocity_schedule as arc_schedule
from test_height_profile import climbing_schedule

from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.footsteps.footstep import StepTiming
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp import MpcParameters, WalkingQP, make_solver
from mpcwalk.qp.schedule_tables import ScheduleTables

RICH = MpcParameters(  # every term and every constraint group
    velocity_weight=0.1,
    com_weight=0.1,
    com_weight_single_support_only=True,
    zmp_margin=0.002,
    com_margin=0.0,
    terminal_dcm=True,
)
X0 = np.array([[0.0, 0.0], [0.05, 0.1], [0.0, 0.0]])  # pushed sideways
ACCURATE = {"quadprog": {}, "clarabel": dict(tol_gap_abs=1e-11, tol_gap_rel=1e-11, tol_feas=1e-11)}


def walking_state(schedule, t, push=(0.0, 0.05), params=MpcParameters()):
    """CoM state at ``t`` of an MPC walk on ``schedule`` plus a velocity push
    [m/s]: a state the QP meets in practice, with active constraints."""
    generator = MpcGenerator(solver="daqp", parameters=params)
    out = generator.reset(schedule)
    while generator.time < t - 1e-9:
        out = generator.step()
    state = out.state.as_cart_table()
    state[1] += push
    return state


def solve_pair(params, x0, t, schedule, control_period=None):
    """Dense (quadprog) and sparse (clarabel) solutions: CoM and ZMP [m]."""
    out = []
    for formulation, solver in (("dense", "quadprog"), ("sparse", "clarabel")):
        qp = WalkingQP(LIPM(), params, formulation, control_period=control_period)
        qp.update(x0, t, schedule)
        result = make_solver(solver, **ACCURATE[solver]).solve(qp)
        assert result.success, (formulation, result.status)
        out.append((qp, result, qp.predict(qp.jerks(result.x))))
    return out


@pytest.mark.parametrize("phase", [0.3, 1.02, 1.27, 2.46])
@pytest.mark.parametrize("params", [MpcParameters(), RICH], ids=["default", "rich"])
def test_dense_and_sparse_formulations_agree(params, phase):
    # CoM constraints need a slow (static) gait: T = 2 s there.
    step_duration = 0.5 if params.com_margin is None else 2.0
    t = phase * step_duration / 0.5
    schedule = arc_schedule(
        (0.1 * 0.5 / step_duration, 0.0, np.deg2rad(20.0)),
        step_duration=step_duration,
        r_ds=0.2 if step_duration == 0.5 else 0.5,
    )
    x0 = walking_state(schedule, t, params=params)
    (_qd, _rd, pd), (qs, rs, ps) = solve_pair(params, x0, t, schedule, control_period=0.01)
    assert np.max(np.abs(pd.zmp - ps.zmp)) < 1e-7  # [m]
    assert np.max(np.abs(pd.com - ps.com)) < 1e-7  # [m]
    # Same constraints: the sparse states satisfy the dynamics.
    assert rs.primal_residual < 1e-8
    states = rs.x[2 * qs.N :].reshape(2, qs.N, 3)
    assert np.max(np.abs(states[:, :, 0].T - ps.com)) < 1e-8


def test_an_active_constraint_is_met_with_equality():
    schedule = arc_schedule((0.1, 0.0, 0.0))
    x0 = walking_state(schedule, 1.2, push=(0.0, 0.2))  # ZMP pressed on an edge
    (qd, rd, pd), (_qs, _rs, ps) = solve_pair(MpcParameters(), x0, 1.2, schedule)
    slack = qd.u - qd.A @ rd.x
    assert np.min(slack) < 1e-9 and np.min(slack) > -1e-9
    margins = support_margins(schedule, pd.times, pd.zmp)
    assert margins.min() > -1e-9
    assert np.max(np.abs(pd.zmp - ps.zmp)) < 1e-7


def test_prediction_is_exact_integration():
    qp = WalkingQP(LIPM(), MpcParameters(horizon=10), "dense")
    qp.update(X0, 0.0, arc_schedule((0.1, 0.0, 0.0)))
    jerks = np.random.default_rng(1).normal(size=(10, 2))
    pred = qp.predict(jerks)
    model = CartTable(LIPM(), 0.1)
    state = X0.copy()
    for i in range(10):
        state = model.integrate(state, jerks[i], 0.1)
        assert np.allclose(pred.com[i], state[0], atol=1e-13)
        assert np.allclose(pred.com_velocity[i], state[1], atol=1e-13)
        assert np.allclose(pred.com_acceleration[i], state[2], atol=1e-13)
        assert np.allclose(pred.zmp[i], model.zmp(state), atol=1e-13)


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
def test_matrices_keep_their_pattern_and_change_only_with_polygons(formulation):
    schedule = arc_schedule((0.1, 0.0, 0.0))
    qp = WalkingQP(LIPM(), RICH, formulation, control_period=0.01)
    pattern = (qp.A.indptr.copy(), qp.A.indices.copy())
    P_pattern = (qp.P_upper.indptr.copy(), qp.P_upper.indices.copy())
    versions, qs = [], []
    for tick in range(150):
        qp.update(X0, 0.01 * tick, schedule)
        versions.append((qp.A_version, qp.P_version))
        qs.append(qp.q.copy())
        assert np.array_equal(qp.A.indptr, pattern[0]) and np.array_equal(qp.A.indices, pattern[1])
        assert np.array_equal(qp.P_upper.indptr, P_pattern[0])
        assert np.array_equal(qp.P_upper.indices, P_pattern[1])
    A_rewrites = versions[-1][0]
    # The matrix is rewritten when the polygon sequence changes, not every tick.
    assert 5 <= A_rewrites < 75
    assert versions[-1][1] >= 2  # CoM weights follow single support
    assert len({q.tobytes() for q in qs}) > 100  # q moves every tick


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
def test_the_bounds_and_dense_rows_built_per_sequence_are_the_direct_ones(formulation):
    """What an update keeps per support sequence (bounds affine in the state, the dense
    rows) equals what the layout gives for the tick's own state, with every constraint
    group on."""
    schedule = arc_schedule((0.1, 0.0, 0.0))
    qp = WalkingQP(LIPM(), RICH, formulation, control_period=0.01)
    rng = np.random.default_rng(5)
    for tick in range(0, 150, 7):
        x0 = X0 + rng.normal(scale=0.05, size=(3, 2))
        qp.update(x0, 0.01 * tick, schedule)
        lower, upper = qp.layout.bounds(x0, qp.supports)
        np.testing.assert_allclose(qp.l, lower, rtol=0.0, atol=1e-12)
        np.testing.assert_allclose(qp.u, upper, rtol=0.0, atol=1e-12)
        dense = qp.problem(dense=True)
        np.testing.assert_array_equal(dense.G, qp.A.toarray()[qp.m_eq :])
        if formulation == "dense":
            np.testing.assert_array_equal(qp.dense_arrays()[2], qp.A.toarray())


@pytest.mark.parametrize("ground", ["flat", "stairs"])
def test_a_qp_that_lived_through_the_walk_equals_a_fresh_one(ground):
    """What an update keeps from earlier ticks (the cost matrices per CoM-weight pattern,
    the polygons' rows per sequence, the bounds' map of the state, dropped when the CoM
    height's rows change on stairs) gives the QP a fresh one builds at the same tick."""
    if ground == "flat":
        schedule = arc_schedule((0.025, 0.0, 0.0), step_duration=2.0, r_ds=0.5)
    else:
        schedule = climbing_schedule(rise=0.03, timing=StepTiming(2.0, 0.5, 0.6, 0.8))
    lived = WalkingQP(LIPM(), RICH, "dense", control_period=0.01)
    versions = set()
    for tick in range(0, 900, 3):
        lived.update(X0, 0.01 * tick, schedule)
        versions.add(lived.P_version)
        if tick % 21 == 0:
            fresh = WalkingQP(LIPM(), RICH, "dense", control_period=0.01)
            fresh.update(X0, 0.01 * tick, schedule)
            np.testing.assert_array_equal(lived.P_data, fresh.P_data)
            np.testing.assert_array_equal(lived.A_data, fresh.A_data)
            np.testing.assert_array_equal(lived.dense_arrays()[2], fresh.dense_arrays()[2])
            np.testing.assert_array_equal(lived.u, fresh.u)
            np.testing.assert_array_equal(lived.q, fresh.q)
    assert len(versions) > 10  # the CoM weights moved along the horizon


def test_the_whitened_rows_are_the_rows_times_the_factor_of_each_axis():
    schedule = arc_schedule((0.1, 0.0, 0.3))
    qp = WalkingQP(LIPM(), RICH, "dense", control_period=0.01)
    transform = np.triu(np.random.default_rng(2).normal(size=(qp.N, qp.N)))
    both = np.kron(np.eye(2), transform)
    for tick in (0, 37, 81):
        qp.update(X0, 0.01 * tick, schedule)
        G = qp.dense_arrays()[2]
        np.testing.assert_allclose(qp.whitened_inequalities(transform), G @ both, atol=1e-12)
    sparse = WalkingQP(LIPM(), RICH, "sparse", control_period=0.01)
    sparse.update(X0, 0.0, schedule)
    with pytest.raises(ConfigurationError, match="condensed layout"):
        sparse.whitened_inequalities(transform)


def test_polygon_sequence_key_merges_phases_with_the_same_polygon():
    schedule = arc_schedule((0.1, 0.0, 0.0))
    tables = ScheduleTables.from_schedule(schedule)
    # Double support closing step k and opening step k + 1 share the stance.
    for i, phase in enumerate(schedule.phases[1:-1], start=1):
        following = schedule.phases[i + 1]
        if not phase.single_support and not following.single_support:
            assert tables.polygon_id[i] == tables.polygon_id[i + 1]


@pytest.mark.parametrize("r_ds", [0.0, 0.2, 0.5])
def test_interpolated_zmp_reference_matches_the_schedule(r_ds):
    schedule = arc_schedule((0.1, 0.05, 0.3), nb_steps=5, r_ds=r_ds)
    tables = ScheduleTables.from_schedule(schedule)
    times = np.random.default_rng(0).uniform(-0.5, schedule.duration + 1.0, 5000)
    times = np.concatenate([times, [ph.start for ph in schedule.phases]])
    assert np.max(np.abs(tables.zmp_reference(times) - schedule.zmp_reference(times))) < 1e-12


def test_com_polygon_switches_to_the_foot_one_sample_before_single_support():
    schedule = arc_schedule((0.1, 0.0, 0.0), step_duration=4.0, r_ds=0.5)
    qp = WalkingQP(LIPM(), MpcParameters(com_margin=0.01, zmp_weight=0.0), "dense")
    ss_start = schedule.walk_start + schedule.t_b
    qp.update(X0, ss_start - 0.55, schedule)  # samples at ss_start - 0.45 + 0.1 i
    foot = schedule.phase(ss_start + 0.01).polygon
    for i, time in enumerate(qp.sample_times):
        expected = foot if time > ss_start - 0.1 else schedule.phase(time).polygon
        k = len(expected.b)
        assert np.allclose(qp.supports.com_A[i, :k], expected.A)
        assert np.allclose(qp.supports.com_b[i, :k], expected.b)
        assert np.allclose(qp.supports.zmp_b[i, :k], schedule.phase(time).polygon.b)


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
def test_shifted_warm_start_moves_samples(formulation):
    qp = WalkingQP(LIPM(), MpcParameters(horizon=4), formulation)
    x = np.arange(qp.n, dtype=float)
    shifted = qp.shift_primal(x, 1.0)
    assert np.array_equal(shifted[:8], [1, 2, 3, 3, 5, 6, 7, 7])
    half = qp.shift_primal(x, 0.5)
    assert np.allclose(half[:4], [0.5, 1.5, 2.5, 3.0])


def test_bad_inputs_raise_named_errors():
    with pytest.raises(ConfigurationError, match="formulation must be one of dense, sparse"):
        WalkingQP(LIPM(), MpcParameters(), "condensed")
    qp = WalkingQP(LIPM(), MpcParameters(), "dense")
    with pytest.raises(NotReset, match="update"):
        qp.problem()
    with pytest.raises(ConfigurationError, match=r"shape \(3, 2\)"):
        qp.update(np.zeros(3), 0.0, arc_schedule((0.1, 0.0, 0.0)))
    with pytest.raises(ConfigurationError, match=r"zmp_reference must have shape \(16, 2\)"):
        qp.update(X0, 0.0, arc_schedule((0.1, 0.0, 0.0)), zmp_reference=np.zeros((3, 2)))
    with pytest.raises(ConfigurationError, match="horizon is a number of samples"):
        MpcParameters(horizon=1.6)
    with pytest.raises(ConfigurationError, match="jerk_weight must be positive"):
        MpcParameters(jerk_weight=0.0)
    with pytest.raises(ConfigurationError, match="Unknown MPC parameter.*horizon_duration"):
        MpcParameters().replace(horizon_duration=1.6)
    assert MpcParameters.with_duration(1.6, 0.005).horizon == 320
