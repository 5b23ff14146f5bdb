"""qpbenchmark itself on the test set :mod:`~mpcwalk.bench.solvers.peers.qpbenchmark_export`
wrote, its report and success rates; in ``mpcwalk bench solvers`` on a fresh timing actor
(:func:`~mpcwalk.sweep.timing.run_isolated`: one CPU, single-threaded, nothing beside it),
after the table of solves (``pip install mpcwalk[bench]``)."""

from collections.abc import Iterable
from pathlib import Path

from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.sweep.timing import run_isolated

#: qpsolvers back-ends left out of the reduced qpbenchmark run by default
#: (JAX-based: each solve recompiles, seconds per problem).
SLOW_QPBENCHMARK_SOLVERS = ("jaxopt_osqp", "qpax")


def run_qpbenchmark(
    test_set_dir: Path,
    *,
    settings: Iterable[str] | None = None,
    solvers: Iterable[str] | None = None,
    time_limit: float = 1.0,
    author: str = "mpcwalk bench solvers",
) -> dict:
    """Run qpbenchmark itself on an exported set and write its report.

    Args:
        test_set_dir: Directory written by
            :func:`~mpcwalk.bench.solvers.peers.qpbenchmark_export.export_test_set`.
        settings: qpbenchmark settings names to run (default: all four).
        solvers: qpsolvers names to run (default: every one qpbenchmark knows).
        time_limit: In [s].
        author: Author field of qpbenchmark's report.

    Returns:
        ``{"results": csv path, "report": md path, "success": {solver:
        {settings: %}}, "runtime": {solver: {settings: relative shgeom}}}``.
    """
    import qpbenchmark

    from mpcwalk.bench.solvers.peers.qpbenchmark_test_set import WalkingTestSet

    test_set_dir = Path(test_set_dir)
    test_set = WalkingTestSet(test_set_dir / "data", solvers=solvers, time_limit=time_limit)
    results_dir = test_set_dir / "results"
    results_dir.mkdir(parents=True, exist_ok=True)
    csv_path = results_dir / "qpbenchmark_results.csv"
    results = qpbenchmark.Results(str(csv_path), test_set)
    for name in list(settings) if settings else list(test_set.solver_settings):
        qpbenchmark.run(test_set, results, only_settings=name)
    md_path = results_dir / "mpcwalk_qpbenchmark.md"
    qpbenchmark.Report(author, results).write(str(md_path))
    tol = test_set.tolerances
    success = results.build_success_rate_df(
        {k: v.primal for k, v in tol.items()},
        {k: v.dual for k, v in tol.items()},
        {k: v.gap for k, v in tol.items()},
    )
    runtime = results.build_shgeom_df("runtime", 10.0, {k: v.runtime for k, v in tol.items()})
    return {
        "results": csv_path,
        "report": md_path,
        "success": success.to_dict(orient="index"),
        "runtime": runtime.to_dict(orient="index"),
    }


def _qpbenchmark_batch(out_dir: Path, config: SolverBenchConfig) -> dict:
    import qpsolvers

    solvers = list(config.qpbenchmark_solvers or ())
    if config.qpbenchmark_solvers is None:
        solvers = [s for s in qpsolvers.available_solvers if s not in SLOW_QPBENCHMARK_SOLVERS]
    summary = run_qpbenchmark(
        out_dir / "qpbenchmark", solvers=solvers, time_limit=config.time_limit
    )
    import qpbenchmark

    summary["solvers"] = list(solvers)
    summary["version"] = qpbenchmark.__version__
    return summary


def run_qpbenchmark_isolated(out_dir: Path, config: SolverBenchConfig) -> dict | None:
    """qpbenchmark on the exported test set, in an isolated process (None: no solver)."""
    try:
        import qpbenchmark  # noqa: F401
    except ImportError:
        return {"error": "qpbenchmark is not installed: pip install 'mpcwalk[bench]'"}
    if config.qpbenchmark_solvers == ():
        return None
    return run_isolated(_qpbenchmark_batch, out_dir, config)
