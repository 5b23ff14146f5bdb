"""Sweeps: many walks (or other cases) run as Ray tasks into a results table.

A sweep is a list of cases (anything with a ``case_id`` and its ``to_columns()``: a walk's
:class:`~mpcwalk.walking.specification.WalkSpec`, whose runner is
:func:`~mpcwalk.walking.sweep_cases.run_walk_case`) and the function that runs one; :func:`run_sweep` runs each case as a Ray task, on a local Ray
instance started on first use or on a cluster (``address="ray://HOST:PORT"`` or
``RAY_ADDRESS``; :func:`local_cluster` starts one of several nodes on this machine), and
streams one row per case into ``results.csv`` as they finish: a case
that raises or times out is a row with its error, and a sweep run again on the same folder
runs only the cases without a row. :func:`map_tasks` runs plain ``(function, args)`` tasks the
same way (results in order). The engine knows nothing of walks: it sits below them. :mod:`mpcwalk.sweep.timing` keeps the benchmarks' timed work one
case at a time on one CPU.
"""

from mpcwalk.sweep.cluster import SweepDependencyMissing, ensure_ray, local_cluster, shutdown
from mpcwalk.sweep.engine import (
    TIMING_COLUMNS,
    CaseTimeout,
    Sweep,
    SweepRun,
    Task,
    WorkerDied,
    map_tasks,
    run_sweep,
)
from mpcwalk.sweep.table import ResultsTable, read_rows

__all__ = [
    "TIMING_COLUMNS",
    "CaseTimeout",
    "ResultsTable",
    "Sweep",
    "SweepDependencyMissing",
    "SweepRun",
    "Task",
    "WorkerDied",
    "ensure_ray",
    "local_cluster",
    "map_tasks",
    "read_rows",
    "run_sweep",
    "shutdown",
]
