"""The registry of QP back-ends: name -> factory and flags, availability, install hint.

Names:

- ``"osqp-direct"``: OSQP set up once, then vector updates and a warm start from the
  shifted previous solution (:class:`~mpcwalk.qp.solvers.osqp_direct.OsqpSolver`);
- ``"casadi"`` (= ``"casadi-qpoases"``) and ``"casadi-<plugin>"``: CasADi's conic
  interface (:class:`~mpcwalk.qp.solvers.casadi_qp.CasadiSolver`);
- ``"daqp-direct"``: DAQP's own workspace, set up once, then vector updates and a hot
  start from the previous working set
  (:class:`~mpcwalk.qp.solvers.daqp_direct.DaqpSolver`);
- ``"quadprog-screened"``: quadprog on the rows near binding, the rows it violates added
  until none is (:class:`~mpcwalk.qp.solvers.screened.ScreenedSolver`), for dense QPs with
  many rows of which few bind (the footstep-adaptive MPC's);
- ``"kkt"``: one linear solve of the KKT system, for QPs without inequalities
  (``constrained=False``), exact up to round-off
  (:class:`~mpcwalk.qp.solvers.kkt.KktSolver`);
- any name of ``qpsolvers.available_solvers`` (``"daqp"``, ``"proxqp"``, ``"quadprog"``,
  ``"clarabel"``...): through ``qpsolvers.solve_problem``
  (:class:`~mpcwalk.qp.solvers.qpsolvers_backend.QpsolversSolver`); the ones qpsolvers
  can install (its pip extras) are known even when absent, with their install command.

:data:`SOLVERS` is a :class:`~mpcwalk.registry.Registry` like every other registry of the
project (``mpcwalk.registry.format_registry(SOLVERS)`` lists it): each name is an
:class:`~mpcwalk.registry.Entry` whose loaded value is a :class:`Backend`, the factory and
the flags of the back-end. It is filled here, from the list of :func:`default_entries`;
nothing else adds to it on import. A back-end of your own is one :func:`backend_entry`
given to ``SOLVERS.register`` by the code that uses it; a registry of its own (the solver
benchmark's, which adds CasADi's Opti layer) is :func:`solver_registry` of the entries of
:data:`SOLVERS` plus its own. The back-end modules import nothing of this one; the heavy
ones (OSQP, CasADi) are imported when their back-end is first made.
"""

import importlib.metadata
import importlib.util
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass

import qpsolvers

from mpcwalk.exceptions import ConfigurationError, SolverNotFound
from mpcwalk.qp.solvers.base import QPSolver
from mpcwalk.qp.solvers.casadi_qp import DEFINITE_PLUGINS, PLUGINS, available_plugins
from mpcwalk.qp.solvers.kkt import KktSolver
from mpcwalk.qp.solvers.qpsolvers_backend import (
    DEFINITE_SOLVERS,
    WARM_START_SOLVERS,
    QpsolversSolver,
)
from mpcwalk.registry import Entry, Registry

#: qpsolvers extras whose solver has another name.
_EXTRA_SOLVER_NAMES = {"jaxopt": "jaxopt_osqp"}


@dataclass(frozen=True)
class Backend:
    """What a back-end name stands for: how to make it and how it behaves.

    Attributes:
        factory: Builds the back-end from its keyword settings.
        warm_start: Whether it starts from the shifted previous solution.
        definite_only: Whether it needs a positive definite cost matrix (so not the sparse
            formulation's, which is only semidefinite).
    """

    factory: Callable[..., QPSolver]
    warm_start: bool = False
    definite_only: bool = False


def _always() -> bool:
    return True


def backend_entry(
    name: str,
    summary: str,
    factory: Callable[..., QPSolver],
    *,
    is_available: Callable[[], bool] = _always,
    install: str = "",
    warm_start: bool = False,
    definite_only: bool = False,
) -> Entry[Backend]:
    """One back-end of a solver registry, e.g.
    ``SOLVERS.register(backend_entry("scipy-slsqp", "SciPy's SLSQP", ScipySlsqp))``.

    Args:
        name: The name :func:`make_solver` takes.
        summary: One line for the listing.
        factory: Builds the back-end from its keyword settings.
        is_available: Whether it runs on this installation (called on demand).
        install: How to install it when it is not available (a command or a sentence).
        warm_start: Whether it starts from the shifted previous solution.
        definite_only: Whether it needs a positive definite cost matrix.
    """
    backend = Backend(factory, warm_start=warm_start, definite_only=definite_only)
    return Entry(name, summary, lambda: backend, is_available, install)


def _not_found(
    name: str, available: Sequence[str], installable: Mapping[str, str], install: str
) -> SolverNotFound:
    if install:
        return SolverNotFound(name, available, install=install)
    return SolverNotFound(name, available, installable)


def solver_registry(entries: Iterable[Entry[Backend]]) -> Registry[Backend]:
    """A registry of back-ends (unknown names raise
    :class:`~mpcwalk.exceptions.SolverNotFound`)."""
    return Registry("solver", entries, list_command="mpcwalk solvers", not_found=_not_found)


def _make_osqp(**settings) -> QPSolver:
    from mpcwalk.qp.solvers.osqp_direct import OsqpSolver

    return OsqpSolver(**settings)


def _make_daqp(**settings) -> QPSolver:
    from mpcwalk.qp.solvers.daqp_direct import DaqpSolver

    return DaqpSolver(**settings)


def _make_kkt(**settings) -> QPSolver:
    if settings:
        raise ConfigurationError(
            f"Solver 'kkt' takes no settings, got {', '.join(sorted(settings))}."
        )
    return KktSolver()


def _make_screened(**settings) -> QPSolver:
    from mpcwalk.qp.solvers.screened import ScreenedSolver

    return ScreenedSolver(**settings)


def _casadi_entry(name: str, plugin: str, summary: str = "") -> Entry[Backend]:
    def make(**settings) -> QPSolver:
        from mpcwalk.qp.solvers.casadi_qp import CasadiSolver

        return CasadiSolver(plugin, **settings)

    if importlib.util.find_spec("casadi") is None:
        install = "pip install casadi"
    else:
        install = f"a CasADi build with the '{plugin}' conic plugin"
    return backend_entry(
        name,
        summary or f"CasADi's conic interface, plugin {plugin}",
        make,
        is_available=lambda: plugin in available_plugins(),
        install=install,
        warm_start=True,
        definite_only=plugin in DEFINITE_PLUGINS,
    )


def _qpsolvers_entry(name: str, extra: str | None) -> Entry[Backend]:
    install = f"pip install qpsolvers[{extra}]" if extra else "see the qpsolvers documentation"
    return backend_entry(
        name,
        f"{name} through qpsolvers",
        lambda **settings: QpsolversSolver(name, **settings),
        is_available=lambda: name in qpsolvers.available_solvers,
        install=install,
        warm_start=name in WARM_START_SOLVERS,
        definite_only=name in DEFINITE_SOLVERS,
    )


def qpsolvers_extras() -> dict[str, str]:
    """qpsolvers solver name -> the pip extra of qpsolvers that installs it (read from the
    installed qpsolvers' metadata, so the hint is the one its version offers)."""
    try:
        requirements = importlib.metadata.requires("qpsolvers") or []
    except importlib.metadata.PackageNotFoundError:  # pragma: no cover - a dependency
        return {}
    extras = {}
    for requirement in requirements:
        package, _, marker = requirement.partition(";")
        match = re.search(r"extra\s*==\s*['\"]([^'\"]+)['\"]", marker)
        if match is None or package.strip().startswith("qpsolvers"):
            continue  # not an extra, or a group of other extras
        extras[_EXTRA_SOLVER_NAMES.get(match[1], match[1])] = match[1]
    return extras


def default_entries() -> list[Entry[Backend]]:
    """The back-ends of :data:`SOLVERS`, in the order they are listed."""
    osqp_missing = importlib.util.find_spec("osqp") is None
    daqp_missing = importlib.util.find_spec("daqp") is None
    quadprog_missing = importlib.util.find_spec("quadprog") is None
    entries = [
        backend_entry(
            "osqp-direct",
            "OSQP set up once, vector updates, warm start from the shifted solution",
            _make_osqp,
            is_available=lambda: not osqp_missing,
            install="pip install osqp",
            warm_start=True,
        ),
        backend_entry("kkt", "one linear solve of the KKT system (no inequalities)", _make_kkt),
        backend_entry(
            "daqp-direct",
            "DAQP's own workspace, vector updates, hot start from the last working set",
            _make_daqp,
            is_available=lambda: not daqp_missing,
            install="pip install daqp",
            warm_start=True,
            definite_only=True,
        ),
        backend_entry(
            "quadprog-screened",
            "quadprog on the rows near binding, rows added until none is violated (dense QPs)",
            _make_screened,
            is_available=lambda: not quadprog_missing,
            install="pip install quadprog",
            warm_start=True,
            definite_only=True,
        ),
        _casadi_entry("casadi", "qpoases", "CasADi's conic interface, plugin qpoases (default)"),
    ]
    entries += [_casadi_entry(f"casadi-{plugin}", plugin) for plugin in PLUGINS]
    extras = qpsolvers_extras()
    names = [*qpsolvers.available_solvers, *sorted(set(extras) - set(qpsolvers.available_solvers))]
    entries += [_qpsolvers_entry(name, extras.get(name)) for name in names]
    return entries


#: The registry of every back-end (see the module docstring).
SOLVERS: Registry[Backend] = solver_registry(default_entries())


def solver_names() -> list[str]:
    """Names accepted by :func:`make_solver` on this installation."""
    return SOLVERS.names()


def solver_backend(name: str) -> Backend:
    """The factory and the flags of the back-end ``name`` of :data:`SOLVERS`, installed or
    not.

    Raises:
        SolverNotFound: Unknown name.
    """
    return SOLVERS.entry(name).load()


def make_solver(name: str, **settings) -> QPSolver:
    """Back-end called ``name`` (see the module docstring), built with ``settings``.

    Raises:
        SolverNotFound: Unknown or uninstalled back-end; the message lists the available
            ones and how to install the missing ones.
    """
    return SOLVERS.load(name).factory(**settings)
