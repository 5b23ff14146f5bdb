"""CasADi back-end: the same walking QP through ``casadi.conic``."""

import functools
import time
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.qp.program import FixedPatternProgram, QuadraticProgram
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.solvers.base import QPSolver, fixed_pattern

#: CasADi conic plugins this back-end knows how to configure.
#: (``hpipm`` is left out: it needs the stage structure of the problem.)
PLUGINS = ("qpoases", "osqp", "qrqp", "proxqp", "highs", "daqp")
#: Plugins that need a positive definite P (not the sparse layout's).
DEFINITE_PLUGINS = frozenset({"daqp"})


@functools.lru_cache(maxsize=1)
def available_plugins() -> tuple[str, ...]:
    """Plugins of :data:`PLUGINS` that load in this CasADi installation."""
    try:
        import casadi
    except ImportError:  # pragma: no cover - casadi is a dependency
        return ()
    out = []
    for plugin in PLUGINS:
        try:
            if casadi.has_conic(plugin):
                out.append(plugin)
        except RuntimeError:  # pragma: no cover
            pass
    return tuple(out)


def _plugin_options(plugin: str, eps: float) -> dict:
    quiet: dict[str, dict[str, Any]] = {
        "qpoases": {"printLevel": "none"},
        "osqp": {
            "osqp": {
                "verbose": False,
                "eps_abs": eps,
                "eps_rel": eps,
                "polish": False,
                "max_iter": 100000,
            }
        },
        "qrqp": {"print_iter": False, "print_header": False, "print_info": False},
        "proxqp": {
            "proxqp": {"eps_abs": eps, "eps_rel": 0.0, "verbose": False, "max_iter": 100000}
        },
        "highs": {"highs": {"output_flag": False}},
        "daqp": {},
    }
    return {"error_on_fail": False, **quiet.get(plugin, {})}


class CasadiSolver(QPSolver):
    """Walking QP through ``casadi.conic(name, plugin, {"h": ..., "a": ...})``.

    The conic function is built once per QP from the fixed sparsity patterns
    of ``P`` and ``A``; every call passes the current values. The previous
    primal solution, shifted, is given as the initial guess.

    Args:
        plugin: CasADi conic plugin (``"qpoases"``, ``"osqp"``, ``"qrqp"``...).
        eps: Tolerance passed to plugins that take one.
        options: Extra options merged into the conic options.
    """

    def __init__(self, plugin: str = "qpoases", *, eps: float = 1e-8, **options) -> None:
        import casadi

        self._ca = casadi
        self.plugin = plugin
        self.name = f"casadi-{plugin}"
        self.options = {**_plugin_options(plugin, eps), **options}
        self._function: Any = None  # casadi.Function of the conic problem
        self._qp: FixedPatternProgram | None = None
        self._previous: np.ndarray | None = None
        self._h = self._a = None
        self._versions = (-1, -1)

    def reset(self) -> None:
        self._function = self._qp = self._previous = self._h = self._a = None

    def check(self, qp: QuadraticProgram) -> None:
        fixed_pattern(qp, self.name)
        if qp.formulation == "sparse" and self.plugin in DEFINITE_PLUGINS:
            raise ConfigurationError(
                f"CasADi plugin '{self.plugin}' needs a positive definite cost matrix, but "
                "the sparse formulation's P is only semidefinite; use formulation='dense'."
            )

    def _sparsity(self, pattern):
        return self._ca.Sparsity(
            pattern.shape[0], pattern.shape[1], pattern.indptr.tolist(), pattern.indices.tolist()
        )

    def solve(self, program: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        program.require_update()
        self.check(program)
        qp = fixed_pattern(program, self.name)
        ca = self._ca
        if self._function is None or self._qp is not qp:
            self._H = self._sparsity(qp.P_pattern)
            self._Asp = self._sparsity(qp.A_pattern)
            self._function = ca.conic(
                "walking_qp", self.plugin, {"h": self._H, "a": self._Asp}, self.options
            )
            self._qp, self._previous, self._h, self._a = qp, None, None, None
        start = time.perf_counter()
        # Matrix values are converted only when they changed.
        if self._versions[0] != qp.P_version or self._h is None:
            self._h = ca.DM(self._H, qp.P_data)
        if self._versions[1] != qp.A_version or self._a is None:
            self._a = ca.DM(self._Asp, qp.A_data)
        self._versions = (qp.P_version, qp.A_version)
        args = dict(h=self._h, g=qp.q, a=self._a, lba=qp.l, uba=qp.u)
        if self._previous is not None:
            args["x0"] = qp.shift_primal(self._previous, shift)
        out = self._function(**args)
        elapsed = time.perf_counter() - start
        stats = self._function.stats()
        success = bool(stats.get("success", False))
        x = np.asarray(out["x"]).ravel() if success else None
        y = np.asarray(out["lam_a"]).ravel() if success else None
        self._previous = x
        primal, dual, gap = np.inf, None, None
        if x is not None and y is not None:
            primal, dual, gap = kkt_residuals(qp.P, qp.q, qp.A, qp.l, qp.u, x, y)
        iterations = stats.get("iter_count", stats.get("iter"))
        return QPResult(
            x=x,
            y=y,
            success=success,
            status=str(stats.get("return_status", "")),
            solve_time=elapsed,
            iterations=None if iterations is None else int(iterations),
            primal_residual=primal,
            dual_residual=dual,
            duality_gap=gap,
            solver=self.name,
        )
