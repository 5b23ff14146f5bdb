"""The back-ends of the solver benchmark: the project's QP back-ends plus CasADi's Opti layer.

:func:`benchmark_registry` is a registry of its own, made from the entries of
:data:`mpcwalk.qp.solvers.registry.SOLVERS` and one more, ``"casadi-opti"`` (CasADi's Opti
modelling layer, :mod:`mpcwalk.bench.solvers.backends.opti`), which only the benchmark
solves with: the project's registry is read, never changed, so the names a walk or a
generator accepts do not depend on whether the benchmark was imported. Each back-end is
made with the settings of a tolerance level (:mod:`mpcwalk.bench.solvers.backends.settings`).
"""

import qpsolvers

from mpcwalk.bench.solvers.backends.settings import backend_settings
from mpcwalk.bench.solvers.tolerances import ToleranceLevel
from mpcwalk.qp.solvers.base import QPSolver
from mpcwalk.qp.solvers.casadi_qp import available_plugins
from mpcwalk.qp.solvers.registry import SOLVERS, Backend, backend_entry, solver_registry
from mpcwalk.registry import Entry, Registry

#: CasADi's modelling layer, benchmarked beside the conic plugins.
OPTI_BACKEND = "casadi-opti"
#: Back-ends known to take over a second per walking QP whatever the problem
#: (JAX-based: qpsolvers builds and compiles a new solver at every call).
#: Like qpbenchmark's known timeouts, they are only sampled: default
#: settings, cold start, one problem per family.
KNOWN_SLOW_BACKENDS = frozenset({"jaxopt_osqp", "qpax"})


def _make_opti(**settings) -> QPSolver:
    from mpcwalk.bench.solvers.backends.opti import OptiSolver

    return OptiSolver(**settings)


def opti_entry() -> Entry[Backend]:
    """The entry of :data:`OPTI_BACKEND`."""
    return backend_entry(
        OPTI_BACKEND,
        "CasADi's Opti modelling layer on qpOASES (solver benchmark only)",
        _make_opti,
        is_available=lambda: "qpoases" in available_plugins(),
        install="a CasADi build with the 'qpoases' conic plugin",
        warm_start=True,
    )


def benchmark_registry() -> Registry[Backend]:
    """The back-ends the benchmark knows: every entry of
    :data:`~mpcwalk.qp.solvers.registry.SOLVERS` at the time of the call, then
    :func:`opti_entry`."""
    return solver_registry([*(SOLVERS.entry(name) for name in SOLVERS), opti_entry()])


def benchmark_backends(include_opti: bool = True) -> list[str]:
    """Every back-end installed here, direct paths first.

    Args:
        include_opti: Add :data:`OPTI_BACKEND` (when CasADi has the qpOASES plugin).
    """
    plugins = available_plugins()
    names = ["osqp-direct"] + [f"casadi-{p}" for p in plugins]
    if include_opti and "qpoases" in plugins:
        names.append(OPTI_BACKEND)
    return names + sorted(qpsolvers.available_solvers)


def _backend(name: str) -> Backend | None:
    registry = benchmark_registry()
    return registry.entry(name).load() if name in registry else None


def is_applicable(backend: str, formulation: str) -> bool:
    """Whether ``backend`` can take the ``formulation``'s problems at all.

    Back-ends that need a positive definite cost matrix (DAQP, quadprog,
    ECOS...) cannot take the sparse formulation, whose ``P`` is only
    semidefinite. Such pairs are left out of the benchmark, not counted as
    failures.
    """
    found = _backend(backend)
    return formulation != "sparse" or found is None or not found.definite_only


def supports_warm_start(backend: str) -> bool:
    """Whether the back-end takes an initial guess (the shifted previous solution)."""
    found = _backend(backend)
    return found is not None and found.warm_start


def make_backend(backend: str, level: ToleranceLevel) -> QPSolver:
    """A fresh back-end object of :func:`benchmark_registry`, configured for ``level``.

    Raises:
        SolverNotFound: Unknown or uninstalled back-end.
    """
    return benchmark_registry().load(backend).factory(**backend_settings(backend, level))
