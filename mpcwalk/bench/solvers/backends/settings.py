"""Settings of the solver benchmark's QP back-ends per tolerance level.

Back-end names are those of the benchmark's registry
(:mod:`mpcwalk.bench.solvers.backends.registry`): ``"osqp-direct"`` (OSQP through its own
API, vector-only updates, warm start from the shifted previous solution),
``"casadi-<plugin>"`` (CasADi's conic interface), every name of
``qpsolvers.available_solvers``, and ``"casadi-opti"`` (CasADi's Opti modelling
layer, see :mod:`mpcwalk.bench.solvers.backends.opti`). At the ``default`` level each back-end keeps
the settings a user gets without asking (for ``osqp-direct`` and the CasADi
plugins: those of :mod:`mpcwalk.qp`); at the other levels it is asked for
the level's absolute tolerance and no relative one, as qpbenchmark does.
Every back-end also gets the level's time limit where it takes one.
"""

from mpcwalk.bench.solvers.tolerances import ToleranceLevel

#: Settings of a qpsolvers back-end asked for an absolute tolerance ``eps``.
_QPSOLVERS_EPS = {
    "clarabel": lambda e: {"tol_feas": e, "tol_gap_abs": e, "tol_gap_rel": 0.0},
    "cvxopt": lambda e: {"feastol": e},
    "daqp": lambda e: {"primal_tol": e, "dual_tol": e},
    "ecos": lambda e: {"feastol": e},
    "highs": lambda e: {"primal_feasibility_tolerance": e, "dual_feasibility_tolerance": e},
    "jaxopt_osqp": lambda e: {"tol": e},
    "osqp": lambda e: {"eps_abs": e, "eps_rel": 0.0},
    "piqp": lambda e: {
        "eps_abs": e,
        "eps_rel": 0.0,
        "eps_duality_gap_abs": e,
        "eps_duality_gap_rel": 0.0,
        "check_duality_gap": True,
    },
    "proxqp": lambda e: {
        "eps_abs": e,
        "eps_rel": 0.0,
        "eps_duality_gap_abs": e,
        "eps_duality_gap_rel": 0.0,
        "check_duality_gap": True,
    },
    "pyqpmad": lambda e: {"tolerance": e},
    "qpalm": lambda e: {"eps_abs": e, "eps_rel": 0.0},
    "qpax": lambda e: {"solver_tol": e},
    "qtqp": lambda e: {"tol_feas": e, "tol_gap_abs": e, "tol_gap_rel": 0.0},
    "scs": lambda e: {"eps_abs": e, "eps_rel": 0.0},
    "sip": lambda e: {"eps_abs": e, "eps_rel": 0.0},
}
#: Name of the time-limit setting of the qpsolvers back-ends that have one.
_QPSOLVERS_TIME_LIMIT = {
    "clarabel": "time_limit",
    "daqp": "time_limit",
    "highs": "time_limit",
    "osqp": "time_limit",
    "qpalm": "time_limit",
    "scs": "time_limit_secs",
    "sip": "time_limit",
}
_QPSOLVERS_QUIET = {"qtqp": {"verbose": False}}


def backend_settings(backend: str, level: ToleranceLevel) -> dict:
    """Keyword settings of the back-end ``backend`` at ``level`` (:func:`make_backend`)."""
    eps, limit = level.eps, level.runtime
    if backend == "osqp-direct":
        settings: dict = {"time_limit": limit}
        if eps is not None:
            settings.update(eps_abs=eps, eps_rel=0.0)
        return settings
    if backend == "daqp-direct":  # DAQP's workspace: the settings of qpsolvers' daqp
        settings = {"time_limit": limit}
        if eps is not None:
            settings.update(primal_tol=eps, dual_tol=eps)
        return settings
    if backend.startswith("casadi-"):
        return _casadi_settings(backend[len("casadi-") :], eps, limit)
    settings = dict(_QPSOLVERS_QUIET.get(backend, {}))
    if eps is not None and backend in _QPSOLVERS_EPS:
        settings.update(_QPSOLVERS_EPS[backend](eps))
    if backend in _QPSOLVERS_TIME_LIMIT:
        settings[_QPSOLVERS_TIME_LIMIT[backend]] = limit
    return settings


def _casadi_settings(plugin: str, eps: float | None, limit: float) -> dict:
    """Options of :class:`~mpcwalk.qp.CasadiSolver` (nested plugin dictionaries
    replace the defaults of :mod:`mpcwalk.qp.solvers.casadi_qp` as a whole)."""
    if plugin == "osqp":
        # CasADi's OSQP plugin (OSQP 0.6) knows no time limit.
        inner: dict[str, float | bool] = {"verbose": False, "polish": False, "max_iter": 100000}
        inner.update(
            {"eps_abs": 1e-8, "eps_rel": 1e-8} if eps is None else {"eps_abs": eps, "eps_rel": 0.0}
        )
        return {"osqp": inner}
    if plugin == "highs":
        # No time limit: HiGHS counts it over the life of the solver object, so a
        # controller calling it every tick would hit it after the first second.
        highs: dict[str, float | bool] = {"output_flag": False}
        if eps is not None:
            highs.update(primal_feasibility_tolerance=eps, dual_feasibility_tolerance=eps)
        return {"highs": highs}
    if eps is None:
        return {}
    if plugin == "proxqp":  # CasADi's ProxQP plugin has no duality-gap check
        return {"eps": eps}
    if plugin == "qrqp":
        return {"constr_viol_tol": eps, "dual_inf_tol": eps}
    if plugin == "daqp":
        return {"daqp": {"primal_tol": eps, "dual_tol": eps}}
    return {}  # qpOASES (conic and Opti): exact active set, no tolerance; its CPUtime
    # option did not bound the solves measured here, so none is set


def settings_table(levels: dict[str, ToleranceLevel], backends: list[str]) -> str:
    """Markdown table of the settings each back-end gets at each level."""
    names = list(levels)
    lines = ["| back-end | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for backend in backends:
        cells = []
        for name in names:
            settings = backend_settings(backend, levels[name])
            text = ", ".join(f"{k}={v}" for k, v in sorted(_flatten(settings).items()))
            cells.append(f"`{text}`" if text else "")
        lines.append(f"| {backend} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _flatten(settings: dict, prefix: str = "") -> dict:
    out = {}
    for key, value in settings.items():
        if isinstance(value, dict):
            out.update(_flatten(value, f"{prefix}{key}."))
        elif key not in ("verbose", "output_flag"):
            out[f"{prefix}{key}"] = value
    return out
