"""Every QP back-end on the walking QP: residuals, and the same answer."""

import functools
import warnings

import numpy as np
import pytest
import qpsolvers

from mpcwalk.exceptions import ConfigurationError, SolverNotFound
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.generators.static_qp import StaticQPGenerator
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp import QPResult, WalkingQP, make_solver, solver_names
from mpcwalk.qp.solvers import (
    SOLVERS,
    KktSolver,
    backend_entry,
    solver_backend,
    solver_registry,
)
from mpcwalk.qp.solvers.base import dense_residuals, dual_residual
from mpcwalk.qp.solvers.casadi_qp import available_plugins
from mpcwalk.qp.solvers.qpsolvers_backend import DEFINITE_SOLVERS
from mpcwalk.qp.solvers.registry import qpsolvers_extras
from mpcwalk.registry import format_registry


def straight_schedule(step_duration, r_ds, nb_steps=6, stride=0.05):
    """Straight walk, feet 0.08 m apart, ``stride`` [m] of torso per step."""
    left, right = Footstep(Side.LEFT, [0.0, 0.04]), Footstep(Side.RIGHT, [0.0, -0.04])
    steps = [
        Footstep(
            Side.RIGHT if k % 2 == 0 else Side.LEFT,
            [stride * (k + 1), -0.04 if k % 2 == 0 else 0.04],
        )
        for k in range(nb_steps)
    ]
    return ContactSchedule(FootstepPlan(left, right, steps, StepTiming(step_duration, r_ds)))


@functools.cache
def walking_case(kind):
    """``(parameters, schedule, t, x0)``: the state of a walk at ``t`` pushed
    sideways, so that a few support-polygon constraints are active."""
    if kind == "mpc":
        generator, schedule, t, push = (
            MpcGenerator(solver="daqp"),
            straight_schedule(0.5, 0.2),
            1.6,
            0.15,
        )
    else:
        generator, schedule, t, push = (
            StaticQPGenerator(solver="daqp"),
            straight_schedule(4.0, 0.5, stride=0.1),
            5.63,
            0.2,
        )
    out = generator.reset(schedule)
    while generator.time < t - 1e-9:
        out = generator.step()
    x0 = out.state.as_cart_table()
    x0[1, 1] += push  # [m/s]
    return generator.parameters, schedule, t, x0


def build(kind, formulation):
    params, schedule, t, x0 = walking_case(kind)
    qp = WalkingQP(LIPM(), params, formulation)
    qp.update(x0, t, schedule)
    return qp


@functools.cache
def reference(kind):
    """High-accuracy reference (quadprog, dense): predicted CoM and ZMP [m]."""
    qp = build(kind, "dense")
    result = make_solver("quadprog").solve(qp)
    assert result.success
    active = int(np.sum(qp.A @ result.x - qp.u > -1e-9))
    pred = qp.predict(qp.jerks(result.x))
    return pred.com, pred.zmp, active


#: Settings for accuracy, and tolerances (primal residual [m], dual residual,
#: duality gap, distance to the reference [m]) met by each back-end.
SETTINGS = {
    "clarabel": dict(tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10),
    "cvxopt": dict(abstol=1e-10, reltol=1e-10, feastol=1e-10),
    "osqp": dict(eps_abs=1e-9, eps_rel=0.0, polish=True, max_iter=100000),
    "piqp": dict(eps_abs=1e-10, eps_rel=0.0),
    "proxqp": dict(eps_abs=1e-9, eps_rel=0.0),
    "qpalm": dict(eps_abs=1e-10, eps_rel=0.0),
    "scs": dict(eps_abs=1e-9, eps_rel=0.0),
}
DEFAULT_TOLERANCE = (1e-8, 1e-8, 1e-7, 5e-6)
TOLERANCES = {
    # HiGHS's active-set QP stops on its own criteria; its duals are ~1e-6.
    "highs": (1e-8, 1e-5, 1e-3, 1e-3),
    # ECOS solves the QP as a cone program (through a factor of P); tighter
    # settings than its defaults make it fail on the static QP. Its duals are the
    # least accurate here (measured dual residual 7.6e-5, gap 1.6e-3 on the MPC).
    "ecos": (1e-8, 1e-5, 1e-4, 2e-5),
    "proxqp": (1e-8, 1e-8, 1e-6, 1e-6),
    "qtqp": (1e-8, 1e-8, 1e-6, 5e-6),
}
_JAX = (
    "runs in JAX float32 unless jax_enable_x64 is set process-wide (a global switch "
    "a test must not flip); in float32 it returns 'not found' on these QPs (checked, "
    "jaxopt_osqp at tol=1e-6), after a JIT compilation of ~2 s"
)
SKIP = {"qpax": f"qpax {_JAX}", "jaxopt_osqp": f"jaxopt_osqp {_JAX}"}
SKIP_SPARSE = {
    "highs": "HiGHS's QP solver ends with 'Solve error' on the sparse layout (its own KKT "
    "check finds ~1e-4 infeasibilities in the dynamics rows; checked on both QPs)",
}


def assert_result(result: QPResult, qp: WalkingQP, kind: str, tolerance):
    primal_tol, dual_tol, gap_tol, distance_tol = tolerance
    assert result.success, result.status
    assert result.primal_residual < primal_tol
    # Dual residual and gap relative to the size of their terms (the walking
    # QPs have |q| ~ 0.2-8 and x'Px up to ~400 after the cost scaling).
    Px = qp.P @ result.x
    dual_scale = max(1.0, np.max(np.abs(Px)), np.max(np.abs(qp.q)))
    assert result.dual_residual is not None and result.dual_residual < dual_tol * dual_scale
    gap_scale = max(1.0, float(result.x @ Px))
    assert result.duality_gap is not None and result.duality_gap < gap_tol * gap_scale
    com, zmp, _ = reference(kind)
    pred = qp.predict(qp.jerks(result.x))
    assert np.max(np.abs(pred.zmp - zmp)) < distance_tol
    # The last jerks are weakly determined (they act on the last ZMP samples
    # only) and the CoM diverges there: compare its first half.
    half = qp.N // 2
    assert np.max(np.abs(pred.com[:half] - com[:half])) < distance_tol


@pytest.mark.parametrize("kind", ["mpc", "static"])
def test_reference_problems_have_active_constraints(kind):
    assert reference(kind)[2] >= 1


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
@pytest.mark.parametrize("kind", ["mpc", "static"])
@pytest.mark.parametrize("solver", qpsolvers.available_solvers)
def test_qpsolvers_backend(solver, kind, formulation):
    if solver in SKIP:
        pytest.skip(SKIP[solver])
    if formulation == "sparse" and solver in DEFINITE_SOLVERS:
        pytest.skip(
            f"{solver} needs a positive definite P (at its default settings); the "
            "sparse layout's P is only semidefinite"
        )
    if formulation == "sparse" and solver in SKIP_SPARSE:
        pytest.skip(SKIP_SPARSE[solver])
    qp = build(kind, formulation)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = make_solver(solver, **SETTINGS.get(solver, {})).solve(qp)
    assert_result(result, qp, kind, TOLERANCES.get(solver, DEFAULT_TOLERANCE))


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
@pytest.mark.parametrize("kind", ["mpc", "static"])
def test_osqp_direct_matches_the_reference(kind, formulation):
    qp = build(kind, formulation)
    solver = make_solver("osqp-direct", eps_abs=1e-8, eps_rel=1e-8, max_iter=100000)
    result = solver.solve(qp)
    assert result.iterations > 0
    assert_result(result, qp, kind, (1e-7, 1e-7, 1e-6, 5e-6))
    # A second call with the same data is warm: fewer iterations, same answer.
    again = solver.solve(qp)
    assert again.iterations < result.iterations
    assert_result(again, qp, kind, (1e-7, 1e-7, 1e-6, 5e-6))


CASADI = [p for p in ("qpoases", "osqp", "qrqp", "proxqp", "daqp") if p in available_plugins()]


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
@pytest.mark.parametrize("kind", ["mpc", "static"])
@pytest.mark.parametrize("plugin", CASADI)
def test_casadi_matches_the_reference(plugin, kind, formulation):
    if plugin == "daqp" and formulation == "sparse":
        pytest.skip(
            "DAQP needs a positive definite P (at its default settings); the sparse "
            "layout's P is only semidefinite"
        )
    qp = build(kind, formulation)
    result = make_solver(f"casadi-{plugin}").solve(qp)
    if plugin in ("osqp", "proxqp"):  # first-order / proximal: 1e-8 stopping tolerance
        tolerance = (1e-6, 1e-7, 1e-6, 3e-5)  # ZMP within 0.03 mm (measured 0.012 mm)
    elif formulation == "sparse":  # active sets on a semidefinite P
        tolerance = (1e-7, 1e-8, 1e-8, 1e-6)
    else:
        tolerance = (1e-9, 1e-9, 1e-9, 1e-8)
    assert_result(result, qp, kind, tolerance)


def test_kkt_solver_is_exact_without_constraints():
    params, schedule, t, x0 = walking_case("mpc")
    unconstrained = params.replace(constrained=False)
    results = []
    for formulation in ("dense", "sparse"):
        qp = WalkingQP(LIPM(), unconstrained, formulation)
        qp.update(x0, t, schedule)
        result = make_solver("kkt").solve(qp)
        assert result.dual_residual < 1e-10 and result.primal_residual < 1e-10
        results.append(qp.predict(qp.jerks(result.x)).zmp)
    assert np.max(np.abs(results[0] - results[1])) < 1e-10
    with pytest.raises(ConfigurationError, match="without inequality constraints"):
        make_solver("kkt").solve(build("mpc", "dense"))


def test_unknown_solver_lists_the_available_ones():
    with pytest.raises(
        SolverNotFound,
        match="Unknown solver 'gurobo'; available: osqp-direct, kkt.*quadprog",
    ) as error:
        make_solver("gurobo")
    assert "qpsolvers[gurobo]" not in str(error.value)  # no install hint for a typo
    with pytest.raises(SolverNotFound, match="Unknown solver 'casadi-cplx'"):
        make_solver("casadi-cplx")
    assert set(qpsolvers.available_solvers) <= set(solver_names())


def test_unknown_solver_names_the_installable_ones_with_their_command():
    """One registry: a typo lists what is available and what qpsolvers can install (with
    the extra of its metadata: ``jaxopt_osqp`` comes with ``qpsolvers[jaxopt]``); a known
    solver that is not installed gets its own command."""
    missing = SOLVERS.installable()
    with pytest.raises(SolverNotFound, match=r"; installable: ") as error:
        make_solver("nosuchsolver")
    message = str(error.value)
    assert "qpsolvers[nosuchsolver]" not in message
    assert error.value.available == solver_names()
    assert error.value.installable == missing
    for name in missing:
        assert name in message
    if "jaxopt_osqp" in missing:
        assert "jaxopt_osqp (`pip install qpsolvers[jaxopt]`)" in message
    extras = qpsolvers_extras()
    assert extras.get("gurobi") == "gurobi"  # qpsolvers 4 installs Gurobi's interface
    if "gurobi" in missing:
        with pytest.raises(SolverNotFound, match=r"'gurobi' is not installed.*qpsolvers\[gurobi\]"):
            make_solver("gurobi")


def test_the_registry_takes_new_back_ends():
    missing = backend_entry(
        "fake", "a fake", lambda **settings: KktSolver(), is_available=lambda: False
    )
    registry = solver_registry([missing])
    assert registry.names() == [] and registry.installable() == {"fake": ""}
    registry = solver_registry(
        [
            backend_entry(
                "fake",
                "a fake",
                lambda **settings: KktSolver(),
                is_available=lambda: False,
                install="pip install fake",
            )
        ]
    )
    with pytest.raises(SolverNotFound, match="'fake' is not installed; install it with"):
        registry.load("fake")
    registry = solver_registry([backend_entry("fake", "a fake", lambda **s: KktSolver())])
    assert registry.names() == ["fake"]
    assert isinstance(registry.load("fake").factory(), KktSolver)
    with pytest.raises(ValueError, match="'fake' is registered already"):
        registry.register(backend_entry("fake", "again", lambda **s: KktSolver()))
    with pytest.raises(SolverNotFound, match="Unknown solver 'daqp'; available: fake"):
        registry.load("daqp")
    assert solver_backend("daqp").definite_only and solver_backend("osqp-direct").warm_start
    assert not solver_backend("osqp-direct").definite_only and not solver_backend("kkt").warm_start


def test_the_back_ends_are_listed_like_every_registry():
    """``format_registry`` lists the installed back-ends with their summary, then the known
    ones that are not installed with their install command."""
    listing = format_registry(SOLVERS)
    lines = listing.splitlines()
    assert lines[0].split(maxsplit=1) == ["osqp-direct", SOLVERS.entry("osqp-direct").summary]
    assert any(line.startswith("quadprog ") and "through qpsolvers" in line for line in lines)
    installed = [line.split()[0] for line in lines[: len(solver_names())]]
    assert installed == solver_names()
    for name, install in SOLVERS.installable().items():
        assert f"  {name}" in listing and install in listing


def test_definite_solvers_refuse_the_sparse_layout():
    with pytest.raises(ConfigurationError, match="quadprog.*formulation='dense'"):
        make_solver("quadprog").check(build("mpc", "sparse"))


@pytest.mark.parametrize("kind", ["mpc", "static"])
def test_daqp_direct_matches_the_reference_and_hot_starts(kind):
    qp = build(kind, "dense")
    solver = make_solver("daqp-direct")
    result = solver.solve(qp)
    assert result.solver == "daqp-direct" and result.iterations > 0
    assert_result(result, qp, kind, TOLERANCES.get("daqp", DEFAULT_TOLERANCE))
    # The same vectors again: the working set of the last solve is already optimal.
    again = solver.solve(qp)
    assert again.iterations < result.iterations
    np.testing.assert_allclose(again.x, result.x, atol=1e-9)
    with pytest.raises(ConfigurationError, match="formulation='dense'"):
        solver.check(build(kind, "sparse"))
    with pytest.raises(ConfigurationError, match="does not take the settings bogus"):
        make_solver("daqp-direct", bogus=1)


def test_daqp_direct_whitens_per_block_of_the_cost():
    from mpcwalk.qp.solvers.daqp_direct import _Whitening

    rng = np.random.default_rng(3)
    blocks = []
    for n in (5, 7):
        R = np.triu(rng.normal(size=(n, n))) + 3.0 * np.eye(n)
        blocks.append(R.T @ R)
    P = np.zeros((12, 12))
    P[:5, :5], P[5:, 5:] = blocks
    whitening = _Whitening(P)
    assert [(b.start, b.stop) for b, _ in whitening.blocks] == [(0, 5), (5, 12)]
    assert whitening.axis is None  # two blocks, not the same one twice
    np.testing.assert_allclose(whitening.factor.T @ whitening.factor, P, atol=1e-12)
    W = whitening.inverse
    np.testing.assert_allclose(W.T @ P @ W, np.eye(12), atol=1e-12)
    assert np.all(np.tril(W, -1) == 0.0)  # R^-1 is upper triangular
    G = rng.normal(size=(300, 12))  # more rows than one product takes
    np.testing.assert_allclose(whitening.rows(G), G @ W, atol=1e-12)
    twice = np.kron(np.eye(2), blocks[1])
    axis = _Whitening(twice).axis
    assert axis is not None and np.allclose(axis.T @ blocks[1] @ axis, np.eye(7), atol=1e-12)
    coupled = P.copy()
    coupled[0, 11] = coupled[11, 0] = 0.1
    assert len(_Whitening(coupled).blocks) == 1
    with pytest.raises(np.linalg.LinAlgError):
        _Whitening(-P)


def test_daqp_direct_keeps_its_workspace_when_the_cost_changes():
    """The static gait's QP: its CoM weight moves along the horizon, so ``P`` changes at
    sample instants and comes back to earlier values; every solve matches quadprog's on the
    same QP, and each distinct ``P`` is factorised once."""
    schedule = straight_schedule(4.0, 0.5, stride=0.1)
    generator = StaticQPGenerator(solver="daqp-direct")
    generator.reset(schedule)
    reference_solver = make_solver("quadprog")
    versions = set()
    for tick in range(1200):  # three steps
        generator.step()
        qp = generator.qp
        versions.add(qp.P_version)
        if tick % 7 == 0:
            expected = reference_solver.solve(qp)
            assert generator.last_result.success and expected.success
            np.testing.assert_allclose(generator.last_result.x, expected.x, atol=1e-7)
    factorised = len(generator.solver._whitenings._by_matrix)
    assert len(versions) > 2 * factorised > 0  # the costs recur, factorised once each


def test_the_dual_residual_over_the_binding_rows_is_the_whole_product():
    """``dual_residual`` skips the rows whose multiplier is zero: the same norm as the full
    ``gradient + G^T z`` (to rounding), with a few binding rows, with all and with none."""
    rng = np.random.default_rng(3)
    G, gradient = rng.normal(size=(40, 7)), rng.normal(size=7)
    for binding in ([], [4, 31], list(range(40))):
        z = np.zeros(40)
        z[binding] = rng.uniform(0.1, 2.0, size=len(binding))
        full = np.max(np.abs(gradient + G.T @ z))
        assert dual_residual(gradient, G, z) == pytest.approx(full, rel=1e-14, abs=1e-15)
    # and inside the residuals of a solved QP: the KKT conditions of x = argmin
    P, q = np.eye(2), np.array([-2.0, 0.0])  # min |x - (2, 0)|^2 / 2, x0 <= 1
    G, h, x, z = (
        np.array([[1.0, 0.0], [0.0, 1.0]]),
        np.array([1.0, 5.0]),
        np.array([1.0, 0.0]),
        np.array([1.0, 0.0]),
    )
    assert dense_residuals(P, q, G, h, x, z) == (0.0, 0.0, 0.0)
    primal, dual, _ = dense_residuals(P, q, G, h, x, np.array([0.0, 0.0]))
    assert primal == 0.0 and dual == pytest.approx(1.0)  # the binding row's force missing


@pytest.mark.parametrize(
    "generator, solver",
    [
        ("mpc", "daqp-direct"),
        ("mpc", "daqp"),
        ("mpc", "casadi"),
        ("mpc-steps", "quadprog"),
        ("mpc-steps", "quadprog-screened"),
        ("mpc-steps", "daqp-direct"),
        ("static-qp", "daqp-direct"),
    ],
)
def test_residuals_and_horizons_read_after_the_walk_are_those_of_their_tick(generator, solver):
    """A result computes its residuals, and an output its horizon, when they are first
    read, from the arrays of their tick: read after the walk (and every later update of
    the QP), they equal those of an identical walk that read them at once; the residuals
    are those of a solution."""
    from mpcwalk.footsteps import FootGeometry, LegLimits, VelocityPlanner
    from mpcwalk.generators import make_generator

    timing = StepTiming(2.0, 0.5) if generator == "static-qp" else StepTiming()
    plan = VelocityPlanner(LegLimits(), timing).plan((0.03, 0.0, 0.1), 4)
    schedule = ContactSchedule(plan, FootGeometry())
    walks = [make_generator(generator, solver=solver) for _ in range(2)]
    for walk in walks:
        walk.reset(schedule)
    kept, at_once = [], []
    for tick in range(120):
        outputs = [walk.step() for walk in walks]
        results = [walk.last_result for walk in walks]
        assert results[0] is not None and results[1] is not None and results[0].success
        read, horizon = results[1], outputs[1].horizon
        assert horizon is not None
        at_once.append(
            (read.primal_residual, read.dual_residual, read.duality_gap, horizon.com, horizon.zmp)
        )
        if tick % 7 == 0:
            kept.append((tick, results[0], outputs[0].horizon))
    for tick, result, horizon in kept:
        residuals = (result.primal_residual, result.dual_residual, result.duality_gap)
        assert residuals == at_once[tick][:3]
        assert residuals[0] < 1e-6 and residuals[1] is not None and residuals[1] < 1e-6
        np.testing.assert_array_equal(horizon.com, at_once[tick][3])
        np.testing.assert_array_equal(horizon.zmp, at_once[tick][4])


def test_a_result_replaced_keeps_its_residuals():
    """``dataclasses.replace`` of a result (a new status) keeps its residuals, given as
    numbers or computed when read; the function runs once."""
    import dataclasses

    calls = []

    def residuals():
        calls.append(1)
        return 1e-9, 2e-9, 3e-9

    lazy = QPResult(
        np.zeros(2), np.zeros(1), True, "found", 0.1, 4, solver="s", residuals=residuals
    )
    changed = dataclasses.replace(lazy, status="found (retried)")
    assert changed.status == "found (retried)" and changed.solver == "s"
    assert (changed.primal_residual, changed.dual_residual, changed.duality_gap) == (
        1e-9,
        2e-9,
        3e-9,
    )
    assert lazy.duality_gap == 3e-9 and changed.primal_residual == 1e-9
    assert len(calls) == 2  # once per result, when first read
    given = QPResult(None, None, False, "not found", 0.0, None, np.inf, None, None, "q")
    again = dataclasses.replace(given, status="not found (twice)")
    assert again.primal_residual == np.inf and again.dual_residual is None
