"""Constraint screening (``quadprog-screened``): quadprog on the rows near binding, rows
added until none is violated, the whole QP's optimum; and the footstep QPs' cost factors."""

import numpy as np
import pytest
import quadprog
from plans import kicked_walk

from mpcwalk import ContactSchedule, VelocityCommand, VelocityPlanner
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.dynamics_program import check_dynamics_solver
from mpcwalk.qp.solvers import make_solver
from mpcwalk.qp.solvers.screened import FIRST_ROWS, ScreenedSolver


class _DenseQP:
    """A dense QP with inequality rows, as the walking QPs answer it."""

    formulation = "dense"
    fixed_pattern = False
    m_eq = 0

    def __init__(self, P, q, G, h):
        self.P, self.q, self.G, self.h = P, q, G, h
        self.m = len(h)

    def require_update(self):
        pass

    def dense_arrays(self):
        return self.P, self.q, self.G, self.h

    def shift_primal(self, x, samples):
        return np.asarray(x)


def _random_qp(seed, n=12, m=150):
    """A strictly convex QP whose origin is feasible; with ``q`` large, several rows bind."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    P = A @ A.T + n * np.eye(n)
    q = rng.normal(size=n) * 10.0
    G = rng.normal(size=(m, n))
    h = rng.uniform(0.5, 2.0, size=m)  # x = 0 is feasible: the optimum binds a few rows
    return _DenseQP(P, q, G, h)


@pytest.mark.parametrize("seed", range(5))
def test_the_optimum_is_quadprogs_on_every_row(seed):
    qp = _random_qp(seed)
    x_full, *_ = quadprog.solve_qp(qp.P, -qp.q, -qp.G.T, -qp.h, 0)
    solver = ScreenedSolver()
    result = solver.solve(qp)
    assert result.success and result.solver == "quadprog-screened"
    np.testing.assert_allclose(result.x, x_full, atol=1e-9)
    assert 1 <= solver.rounds <= qp.m
    slack = qp.h - qp.G @ result.x
    assert slack.min() > -1e-9  # every row holds, the ones never solved with too
    # multipliers on every row: zero off the binding ones, and the KKT conditions hold
    assert result.y.shape == (qp.m,) and np.all(result.y >= -1e-12)
    assert np.all(result.y[slack > 1e-6] == 0.0) and np.any(result.y > 1e-6)
    assert result.dual_residual < 1e-8 and result.primal_residual < 1e-9
    # the next solve starts from this optimum's nearest rows: one round suffices when they
    # hold every binding row
    result_again = solver.solve(qp)
    np.testing.assert_allclose(result_again.x, x_full, atol=1e-9)
    assert solver.rounds == 1 or np.sum(result.y > 0.0) > FIRST_ROWS


def test_inconsistent_rows_fail_and_the_next_solve_starts_afresh():
    qp = _random_qp(0, n=3, m=4)
    qp.G = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    qp.h = np.array([-1.0, -1.0, 1.0, 1.0])  # x0 <= -1 and x0 >= 1
    solver = ScreenedSolver()
    result = solver.solve(qp)
    assert not result.success and "inconsistent" in result.status and result.x is None
    assert solver._previous is None


def test_what_it_refuses_is_named():
    with pytest.raises(ConfigurationError, match="first_rows"):
        ScreenedSolver(first_rows=-1)
    with pytest.raises(ConfigurationError, match="quadprog-screened.*first_rows"):
        make_solver("quadprog-screened", first_rows=1.5)
    qp = _random_qp(1)
    qp.formulation = "sparse"
    with pytest.raises(ConfigurationError, match="dense QPs"):
        ScreenedSolver().solve(qp)
    # the inverse dynamics' QP has equality rows: not among its back-ends
    with pytest.raises(ConfigurationError, match="equality and inequality"):
        check_dynamics_solver("quadprog-screened")


def _walk(name, solver, kick=(0.35, 0.0), at=1.4):
    plan = VelocityPlanner().plan(VelocityCommand(vx=0.1, vy=0.0, vyaw=0.2), nb_steps=6)
    options = {} if solver is None else {"solver": solver}
    return kicked_walk(name, ContactSchedule(plan), kick, at, **options)


@pytest.mark.parametrize("name, kick", [("mpc-steps", (0.2, 0.1)), ("mpc-hip", (0.35, 0.0))])
def test_the_footstep_mpcs_plan_as_with_quadprog_on_every_row(name, kick):
    """The screened back-end gives quadprog's plans (the footstep-adaptive MPCs' default),
    pushed (the footsteps move, the flywheel leans) as undisturbed."""
    generator, screened = _walk(name, "quadprog-screened", kick)
    assert generator.solver_name == "quadprog-screened"
    _, full = _walk(name, None, kick)
    for a, b in zip(screened, full):
        np.testing.assert_allclose(a.com, b.com, atol=1e-9)
        np.testing.assert_allclose(a.zmp, b.zmp, atol=1e-9)
    assert all(o.solve.success for o in screened[1:])
    if name == "mpc-hip":  # the push is held by the flywheel's torque
        assert max(abs(o.flywheel.torque[0]) for o in screened) > 0.1
    assert generator.nb_publications > 0


@pytest.mark.parametrize("name", ["mpc-steps", "mpc-hip"])
def test_the_cost_factor_is_the_cost_matrix_s(name):
    """``cost_factor()``: ``R^-1`` upper triangular with ``R^T R = P[order][:, order]``, the
    blocks factorised once per first interval."""
    generator, _ = _walk(name, "quadprog-screened", kick=(0.0, 0.0))
    qp = generator.qp
    order, inverse = qp.cost_factor()
    assert sorted(order) == list(range(qp.n))
    assert np.allclose(np.tril(inverse, -1), 0.0)
    R = np.linalg.inv(inverse)
    np.testing.assert_allclose(R.T @ R, qp.P[np.ix_(order, order)], atol=1e-10)
