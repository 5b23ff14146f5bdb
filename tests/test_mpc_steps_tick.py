"""The footstep-adaptive MPC's per-tick shortcuts give what the direct computation gives."""

import functools
import warnings

import numpy as np
import pytest
import qpsolvers
from plans import velocity_schedule

from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.models.lipm import LIPM
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
    assert direct.dual_residual == reference.dual_residual()
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
