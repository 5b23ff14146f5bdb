"""The sweep engine: each case a Ray task, the rows streamed into a results table.

:func:`run_sweep` runs a :class:`Sweep` (cases, the module-level function that runs one, the
columns it returns) on a local Ray instance or a cluster (:mod:`mpcwalk.sweep.cluster`), at
most ``workers`` cases at a time, with a tqdm progress bar. Nothing is lost and nothing is
repeated: a case that raises, times out or whose worker dies is a row with its ``error``;
rows are appended to the table as they arrive (:class:`~mpcwalk.sweep.table.ResultsTable`),
so the same command run again after a kill runs only the missing cases. The case's seed is
part of the case: the same case gives the same row (but for its wall time).

:func:`map_tasks` is the engine's plain form for work that is not a table (paper M's walks
and bisections): ``(function, args)`` tasks, results in the order of the tasks, a task's
exception raised again.
"""

import contextlib
import os
import signal
import socket
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError, MpcwalkError
from mpcwalk.sweep.cluster import check_workers, import_ray, ray_session
from mpcwalk.sweep.table import ResultsTable

#: Columns the engine adds to every row.
ENGINE_COLUMNS = ("error", "wall_time_s", "cpu_time_s", "worker", "node")

#: Columns that differ between two runs of the same case (timings and places).
TIMING_COLUMNS = (
    "wall_time_s",
    "cpu_time_s",
    "worker",
    "node",
    "real_time_factor",
    "controller_tick_us_median",
)

_POLL = 1.0  # [s] between checks of the hard time limits


class CaseTimeout(MpcwalkError, TimeoutError):
    """A case ran past its time limit."""

    def __init__(self, limit: float) -> None:
        self.limit = limit
        super().__init__(f"timeout: the case ran over its limit of {limit:g} s")


class WorkerDied(MpcwalkError, RuntimeError):
    """A worker died while it ran a task (killed, out of memory, a crash in C code)."""

    def __init__(self, detail: str) -> None:
        super().__init__(f"A sweep worker died while running a task: {detail}")


@contextlib.contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Raise :class:`CaseTimeout` in the block after ``seconds`` (None: no limit; only in a
    process's main thread, where the workers run their tasks)."""
    if not seconds or threading.current_thread() is not threading.main_thread():
        yield
        return

    def expire(signum, frame):
        raise CaseTimeout(seconds)

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


def node_id() -> str | None:
    """The id of the Ray node this process runs on (hexadecimal), None outside Ray."""
    ray = sys.modules.get("ray")
    if ray is None or not ray.is_initialized():
        return None
    return str(ray.get_runtime_context().get_node_id())


def run_case(runner: Callable[[Any], dict], case: Any, timeout: float | None) -> dict[str, Any]:
    """Run one case (in a worker): the runner's columns, ``error`` (None, or the exception
    in one line), ``wall_time_s``, ``cpu_time_s`` (the worker process's processor time
    during the case: below the wall time when other work shares the core), ``worker``
    (host:pid) and ``node`` (the Ray node's id: the machine of a cluster, or one of the
    nodes of a cluster on one machine)."""
    start, cpu = time.perf_counter(), time.process_time()
    try:
        with time_limit(timeout):
            values, error = dict(runner(case)), None
    except Exception as exc:  # a case that raises is a row with its error
        values, error = {}, " ".join(f"{type(exc).__name__}: {exc}".split())[:500]
    return {
        **values,
        "error": error,
        "wall_time_s": time.perf_counter() - start,
        "cpu_time_s": time.process_time() - cpu,
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "node": node_id(),
    }


@dataclass(frozen=True)
class Sweep:
    """What a sweep runs.

    Attributes:
        name: Name (in the table's manifest).
        cases: The cases: objects with ``case_id`` and ``to_columns()`` (e.g.
            :class:`~mpcwalk.walking.specification.WalkSpec`), picklable.
        runner: Module-level function running one case, returning ``columns``.
        columns: The runner's columns.
        settings: What else defines the sweep (JSON-ready; part of its fingerprint).
        timeout: Time limit of one case [s] (None: none).
    """

    name: str
    cases: tuple[Any, ...]
    runner: Callable[[Any], dict]
    columns: tuple[str, ...]
    settings: dict[str, Any] = field(default_factory=dict)
    timeout: float | None = None

    def table_columns(self) -> list[str]:
        """The columns of its table: the cases', the runner's, the engine's."""
        names: dict[str, None] = {}
        for case in self.cases:
            names.update(dict.fromkeys(case.to_columns()))
        return list(names) + [c for c in self.columns if c not in names] + list(ENGINE_COLUMNS)


@dataclass(frozen=True)
class SweepRun:
    """What :func:`run_sweep` did.

    Attributes:
        rows: The rows of the table (every case's, in case order, when ``complete``).
        nb_cases: Cases of the sweep.
        nb_run: Cases run by this call.
        nb_resumed: Cases whose rows an earlier run had written.
        wall_time_s: Wall time of this call [s].
        workers: Cases run at once.
        complete: Every case has its row.
    """

    rows: tuple[dict[str, Any], ...]
    nb_cases: int
    nb_run: int
    nb_resumed: int
    wall_time_s: float
    workers: int
    complete: bool

    @property
    def nb_errors(self) -> int:
        """Rows with an error."""
        return sum(bool(row.get("error")) for row in self.rows)


def run_sweep(
    sweep: Sweep,
    out_dir: str | Path,
    *,
    workers: int | None = None,
    address: str | None = None,
    overwrite: bool = False,
    max_cases: int | None = None,
    progress: bool = True,
) -> SweepRun:
    """Run the cases of ``sweep`` that have no row yet in ``out_dir``'s table.

    Args:
        sweep: The sweep.
        out_dir: Folder of the results table (``results.csv``, ``sweep.json``).
        workers: Cases at once (local: also the CPU slots of the Ray instance it starts;
            None: one per core, or the cluster's CPUs).
        address: Ray cluster (None: ``RAY_ADDRESS``, else local).
        overwrite: Start afresh in a folder holding another configuration.
        max_cases: Run at most this many missing cases, then stop (None: all).
        progress: Show a tqdm progress bar.

    Raises:
        ConfigurationError: The folder holds another configuration (without ``overwrite``),
            duplicated cases, or a bad ``workers``.
    """
    from tqdm import tqdm

    check_workers(workers)
    ids = [case.case_id for case in sweep.cases]
    if len(set(ids)) != len(ids):
        raise ConfigurationError(f"Sweep '{sweep.name}' holds the same case more than once.")
    runner_name = f"{sweep.runner.__module__}.{sweep.runner.__qualname__}"
    table = ResultsTable(
        out_dir,
        name=sweep.name,
        settings={**sweep.settings, "runner": runner_name, "columns": list(sweep.columns)},
        case_ids=ids,
        columns=sweep.table_columns(),
        overwrite=overwrite,
    )
    done = table.done()
    todo = [case for case in sweep.cases if case.case_id not in done]
    if max_cases is not None:
        todo = todo[: max(0, max_cases)]
    start = time.perf_counter()
    bar = tqdm(total=len(ids), initial=len(done), desc=sweep.name, disable=not progress)
    slots = workers or 1
    try:
        if todo:
            with ray_session(address=address, workers=workers) as slots:
                for case, result in _stream(sweep, todo, slots):
                    table.append({**case.to_columns(), **result})
                    bar.update(1)
    finally:
        bar.close()
    complete = len(table.done()) == len(ids)
    rows = table.finish() if complete else table.rows()
    return SweepRun(
        rows=tuple(rows),
        nb_cases=len(ids),
        nb_run=len(todo),
        nb_resumed=len(done),
        wall_time_s=time.perf_counter() - start,
        workers=slots,
        complete=complete,
    )


def _stream(sweep: Sweep, cases: Sequence[Any], slots: int) -> Iterator[tuple[Any, dict]]:
    """(case, result) as the cases finish, at most ``slots`` at once."""
    ray = import_ray()
    task = ray.remote(num_cpus=1, max_retries=0)(run_case)
    hard = None if sweep.timeout is None else 2.0 * sweep.timeout + 60.0
    pending = list(reversed(cases))
    running: dict[Any, tuple[Any, float]] = {}
    while pending or running:
        while pending and len(running) < slots:
            case = pending.pop()
            running[task.remote(sweep.runner, case, sweep.timeout)] = (case, time.monotonic())
        ready, _ = ray.wait(list(running), num_returns=1, timeout=_POLL)
        for ref in ready:
            case, started = running.pop(ref)
            try:
                result = ray.get(ref)
            except Exception as exc:  # the worker died: the case is a row with the error
                result = _error_row(f"worker died: {type(exc).__name__}", started)
            yield case, result
        if hard is not None:
            for ref, (case, started) in list(running.items()):
                if time.monotonic() - started > hard:
                    ray.cancel(ref, force=True)
                    del running[ref]
                    yield case, _error_row(f"timeout: killed after {hard:g} s", started)


def _error_row(error: str, started: float) -> dict[str, Any]:
    return {"error": error, "wall_time_s": time.monotonic() - started, "worker": None, "node": None}


Task = tuple[Callable[..., Any], tuple]
"""A task of :func:`map_tasks`: a module-level function and its positional arguments."""


def _call(function: Callable[..., Any], args: tuple) -> Any:
    return function(*args)


def map_tasks(
    tasks: Sequence[Task],
    *,
    workers: int | None = None,
    address: str | None = None,
    progress: bool = True,
    description: str = "tasks",
) -> list[Any]:
    """Run ``(function, args)`` tasks as Ray tasks; the results in the order of ``tasks``.

    Args:
        tasks: Functions (importable: module level) and their picklable arguments.
        workers: Tasks at once (local: the CPU slots; None: one per core).
        address: Ray cluster (None: ``RAY_ADDRESS``, else local).
        progress: Show a tqdm progress bar.
        description: Label of the bar.

    Raises:
        ConfigurationError: ``workers`` is not a positive integer.
        WorkerDied: A worker died while it ran a task.
        Exception: A task's own exception.
    """
    from tqdm import tqdm

    check_workers(workers)
    results: list[Any] = [None] * len(tasks)
    if not tasks:
        return results
    bar = tqdm(total=len(tasks), desc=description, disable=not progress)
    try:
        with ray_session(address=address, workers=workers) as slots:
            ray = import_ray()
            remote = ray.remote(num_cpus=1, max_retries=0)(_call)
            pending = list(reversed(range(len(tasks))))
            running: dict[Any, int] = {}
            while pending or running:
                while pending and len(running) < slots:
                    i = pending.pop()
                    running[remote.remote(*tasks[i])] = i
                ready, _ = ray.wait(list(running), num_returns=1)
                for ref in ready:
                    i = running.pop(ref)
                    try:
                        results[i] = ray.get(ref)
                    except ray.exceptions.RayTaskError as error:
                        raise error.as_instanceof_cause() from None
                    except ray.exceptions.RayError as error:
                        raise WorkerDied(f"{type(error).__name__}") from error
                    bar.update(1)
    finally:
        bar.close()
    return results


__all__ = [
    "ENGINE_COLUMNS",
    "TIMING_COLUMNS",
    "CaseTimeout",
    "Sweep",
    "SweepRun",
    "Task",
    "WorkerDied",
    "map_tasks",
    "node_id",
    "run_case",
    "run_sweep",
    "time_limit",
]
