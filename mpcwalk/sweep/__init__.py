"""Sweeps: many walks (or other cases) run as Ray tasks into a results table.

A sweep is a list of cases (:class:`WalkCase`: a walk's whole configuration) and the
function that runs one; :func:`run_sweep` runs each case as a Ray task, on a local Ray
instance started on first use or on a cluster (``address="ray://HOST:PORT"`` or
``RAY_ADDRESS``), and streams one row per case into ``results.csv`` as they finish: a case
that raises or times out is a row with its error, and a sweep run again on the same folder
runs only the cases without a row. :func:`map_tasks` runs plain ``(function, args)`` tasks the
same way (results in order). :mod:`mpcwalk.sweep.timing` keeps the benchmarks' timed work one
case at a time on one CPU.
"""

from mpcwalk.sweep.case import CASE_COLUMNS, WalkCase
from mpcwalk.sweep.cluster import SweepDependencyMissing, ensure_ray, shutdown
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
from mpcwalk.sweep.walks import WALK_COLUMNS, run_walk_case, worker_robot

__all__ = [
    "CASE_COLUMNS",
    "TIMING_COLUMNS",
    "WALK_COLUMNS",
    "CaseTimeout",
    "ResultsTable",
    "Sweep",
    "SweepDependencyMissing",
    "SweepRun",
    "Task",
    "WalkCase",
    "WorkerDied",
    "ensure_ray",
    "map_tasks",
    "read_rows",
    "run_sweep",
    "run_walk_case",
    "shutdown",
    "worker_robot",
]
