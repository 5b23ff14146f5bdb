"""One registry of QP back-ends: name -> factory, availability, install hint.

Names:

- ``"osqp-direct"``: OSQP set up once, then vector updates and a warm start from the
  shifted previous solution (:class:`~mpcwalk.qp.solvers.osqp_direct.OsqpSolver`);
- ``"casadi"`` (= ``"casadi-qpoases"``) and ``"casadi-<plugin>"``: CasADi's conic
  interface (:class:`~mpcwalk.qp.solvers.casadi_qp.CasadiSolver`);
- ``"daqp-direct"``: DAQP's own workspace, set up once, then vector updates and a hot
  start from the previous working set
  (:class:`~mpcwalk.qp.solvers.daqp_direct.DaqpSolver`);
- ``"kkt"``: one linear solve of the KKT system, for QPs without inequalities
  (``constrained=False``), exact up to round-off
  (:class:`~mpcwalk.qp.solvers.kkt.KktSolver`);
- any name of ``qpsolvers.available_solvers`` (``"daqp"``, ``"proxqp"``, ``"quadprog"``,
  ``"clarabel"``...): through ``qpsolvers.solve_problem``
  (:class:`~mpcwalk.qp.solvers.qpsolvers_backend.QpsolversSolver`); the ones qpsolvers
  can install (its pip extras) are known even when absent, with their install command.

A new back-end is one :class:`SolverEntry` given to :meth:`SolverRegistry.register` of
:data:`SOLVERS` (the solver benchmark registers CasADi's Opti layer that way). The
back-end modules import nothing of this one; the heavy ones (OSQP, CasADi) are imported
when their back-end is first made.
"""

import importlib.metadata
import importlib.util
import re
from collections.abc import Callable
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

#: qpsolvers extras whose solver has another name.
_EXTRA_SOLVER_NAMES = {"jaxopt": "jaxopt_osqp"}


@dataclass(frozen=True)
class SolverEntry:
    """One back-end of the registry.

    Attributes:
        name: The name :func:`make_solver` takes.
        factory: Builds the back-end from its keyword settings.
        is_available: Whether it runs on this installation (called on demand).
        install: How to install it when it is not available (a command or a sentence).
        warm_start: Whether it starts from the shifted previous solution.
        definite_only: Whether it needs a positive definite cost matrix (so not the sparse
            formulation's, which is only semidefinite).
    """

    name: str
    factory: Callable[..., QPSolver]
    is_available: Callable[[], bool]
    install: str
    warm_start: bool = False
    definite_only: bool = False


class SolverRegistry:
    """Back-ends by name, in the order they were registered."""

    def __init__(self) -> None:
        self._entries: dict[str, SolverEntry] = {}

    def register(self, entry: SolverEntry) -> None:
        """Add ``entry`` (or replace the entry of the same name)."""
        self._entries[entry.name] = entry

    def get(self, name: str) -> SolverEntry | None:
        """Entry called ``name``, installed or not; None when unknown."""
        return self._entries.get(name)

    def names(self) -> list[str]:
        """Names of the back-ends available on this installation."""
        return [name for name, entry in self._entries.items() if entry.is_available()]

    def installable(self) -> dict[str, str]:
        """Known back-ends that are not installed -> how to install them."""
        return {n: e.install for n, e in self._entries.items() if not e.is_available()}

    def make(self, name: str, **settings) -> QPSolver:
        """Back-end called ``name``, built with ``settings``.

        Raises:
            SolverNotFound: Unknown name (the message lists the available and the
                installable back-ends), or a known back-end that is not installed (the
                message says how to install it).
        """
        entry = self._entries.get(name)
        if entry is None:
            raise SolverNotFound(name, self.names(), self.installable())
        if not entry.is_available():
            raise SolverNotFound(name, self.names(), install=entry.install)
        return entry.factory(**settings)


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


def _casadi_entry(name: str, plugin: str) -> SolverEntry:
    def make(**settings) -> QPSolver:
        from mpcwalk.qp.solvers.casadi_qp import CasadiSolver

        return CasadiSolver(plugin, **settings)

    if importlib.util.find_spec("casadi") is None:
        install = "pip install casadi"
    else:
        install = f"a CasADi build with the '{plugin}' conic plugin"
    return SolverEntry(
        name,
        make,
        lambda: plugin in available_plugins(),
        install,
        warm_start=True,
        definite_only=plugin in DEFINITE_PLUGINS,
    )


def _qpsolvers_entry(name: str, extra: str | None) -> SolverEntry:
    install = f"pip install qpsolvers[{extra}]" if extra else "see the qpsolvers documentation"
    return SolverEntry(
        name,
        lambda **settings: QpsolversSolver(name, **settings),
        lambda: name in qpsolvers.available_solvers,
        install,
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


def _default_registry() -> SolverRegistry:
    registry = SolverRegistry()
    osqp_missing = importlib.util.find_spec("osqp") is None
    registry.register(
        SolverEntry(
            "osqp-direct",
            _make_osqp,
            lambda: not osqp_missing,
            "pip install osqp",
            warm_start=True,
        )
    )
    registry.register(SolverEntry("kkt", _make_kkt, lambda: True, ""))
    daqp_missing = importlib.util.find_spec("daqp") is None
    registry.register(
        SolverEntry(
            "daqp-direct",
            _make_daqp,
            lambda: not daqp_missing,
            "pip install daqp",
            warm_start=True,
            definite_only=True,
        )
    )
    registry.register(_casadi_entry("casadi", "qpoases"))
    for plugin in PLUGINS:
        registry.register(_casadi_entry(f"casadi-{plugin}", plugin))
    extras = qpsolvers_extras()
    for name in [
        *qpsolvers.available_solvers,
        *sorted(set(extras) - set(qpsolvers.available_solvers)),
    ]:
        registry.register(_qpsolvers_entry(name, extras.get(name)))
    return registry


#: The registry of every back-end (see the module docstring).
SOLVERS = _default_registry()


def solver_names() -> list[str]:
    """Names accepted by :func:`make_solver` on this installation."""
    return SOLVERS.names()


def make_solver(name: str, **settings) -> QPSolver:
    """Back-end called ``name`` (see the module docstring), built with ``settings``.

    Raises:
        SolverNotFound: Unknown or uninstalled back-end; the message lists the available
            ones and how to install the missing ones.
    """
    return SOLVERS.make(name, **settings)
